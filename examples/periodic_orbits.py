"""Periodic orbits of friction oscillators by three methods (docs/periodic_orbits.md).

For den Hartog's oscillator ``x'' + x + 0.3 sgn(x') = cos(w t)`` and a 2-DOF chain (m = 1, 1
kg, k = 1, 1 N/m from ground, dashpots 0.02 N s/m, 1 N on DOF 1, a Coulomb contact
mu N = 0.4 N from DOF 2 to ground) it computes the steady amplitude against the excitation
frequency by

* shooting through exact stick-slip (:func:`fricdamp.solvers.shooting.continue_orbits`),
  with the Floquet multipliers (stable points filled, unstable open);
* harmonic balance (Jenkins contacts at k_t = 1e4 N/m for den Hartog, 1e3 N/m for the
  chain, whose arclength continuation stalls in the stick-slip range at stiffer contacts;
  H = 15, :func:`fricdamp.solvers.hb.frequency_response`);
* long event-driven integration from rest (300 periods) at a few frequencies;

and for den Hartog the closed form (non-stop range). Run
``python examples/periodic_orbits.py [out.png]``; :func:`compute` returns the numbers so that a
test can import them.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from fricdamp.contact import Jenkins
from fricdamp.solvers.event import CoulombSystem, simulate_events
from fricdamp.solvers.hb import frequency_response
from fricdamp.solvers.shooting import continue_orbits
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem, chain

K_T = {"den_hartog": 1e4, "two_dof": 1e3}  # Jenkins stiffness of the HB models [N/m]
DAMPERS = [0.02, 0.02]  # chain dashpots [N s/m]


def den_hartog(w, beta=0.3):
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], w),))
    return CoulombSystem(s, [1.0], beta, 1.0)


def den_hartog_hb(beta=0.3):
    return MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], 1.0),),
                            contacts=(ContactElement(Jenkins(K_T["den_hartog"], beta),
                                                     [[1.0]]),))


def two_dof(w, fs=0.4):
    base = chain([1.0, 1.0], [1.0, 1.0], dampers=DAMPERS)
    return CoulombSystem(base.with_loads(HarmonicLoad([1.0, 0.0], w)), [[0.0, 1.0]], fs, 1.0)


def two_dof_hb(fs=0.4):
    return chain([1.0, 1.0], [1.0, 1.0], dampers=DAMPERS,
                 loads=(HarmonicLoad([1.0, 0.0], 1.0),),
                 contacts=(ContactElement(Jenkins(K_T["two_dof"], fs), [[0.0, 1.0]]),))


def den_hartog_closed(w, beta=0.3):
    V = 1 / (1 - w**2)
    U = np.tan(np.pi / (2 * w)) / w
    return np.sqrt(V**2 - beta**2 * U**2)


def long_run(cs, w, periods=300):
    T = 2 * np.pi / w
    res = simulate_events(cs, (0.0, periods * T), np.zeros(2 * cs.n_dof),
                          t_eval=np.linspace((periods - 1) * T, periods * T, 4001))
    last = res.t >= (periods - 1) * T
    return 0.5 * np.ptp(res.q[last], axis=0)


def compute(quick: bool = False) -> dict:
    """Amplitudes of both models by the three methods (and den Hartog's closed form)."""
    n = 13 if quick else 41
    out = {}
    for name, build, build_hb, (lo, hi), (hb_lo, hb_hi), dof in (
            ("den_hartog", den_hartog, den_hartog_hb, (0.55, 0.9), (0.55, 0.9), 0),
            ("two_dof", two_dof, two_dof_hb, (0.4, 1.9), (0.6, 1.85), 1)):
        om = np.linspace(lo, hi, n)
        br = continue_orbits(build, om)
        hb = frequency_response(build_hb(), hb_lo, hb_hi, harmonics=15)
        om_long = om[::4 if quick else 5]
        out[name] = dict(
            dof=dof, omega=om, shooting=br.amplitude[:, dof], stable=br.stable,
            max_multiplier=np.array([np.abs(o.multipliers).max() for o in br.orbits]),
            hb_omega=hb.omega, hb=hb.amplitude[:, dof], long_omega=om_long,
            long=np.array([long_run(build(w), w)[dof] for w in om_long]))
    w = out["den_hartog"]["omega"]
    out["den_hartog"]["closed"] = den_hartog_closed(w)
    return out


def plot(data: dict, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    titles = {"den_hartog": "den Hartog: x'' + x + 0.3 sgn x' = cos wt",
              "two_dof": "2-DOF chain, Coulomb contact (0.4 N) on DOF 2"}
    for ax, (name, d) in zip(axes, data.items(), strict=True):
        if "closed" in d:
            ax.plot(d["omega"], d["closed"], "k-", lw=2.5, alpha=0.3,
                    label="closed form (den Hartog)")
        st = d["stable"]
        ax.plot(d["omega"], d["shooting"], "C0-", lw=1)
        ax.plot(d["omega"][st], d["shooting"][st], "C0o", ms=4,
                label="shooting (filled: stable)")
        ax.plot(d["omega"][~st], d["shooting"][~st], "C0o", mfc="none", ms=4)
        ax.plot(d["hb_omega"], d["hb"], "C1--", lw=1.2,
                label=f"harmonic balance, Jenkins k_t={K_T[name]:g} N/m, H=15")
        ax.plot(d["long_omega"], d["long"], "C3s", mfc="none", ms=8,
                label="event-driven, 300 periods")
        ax.set_xlabel("excitation frequency w [rad/s]")
        ax.set_ylabel(f"amplitude of q{d['dof'] + 1} [m]")
        ax.set_title(titles[name], fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    path = Path(argv[0]) if argv else Path(__file__).resolve().parents[1] / "docs" / \
        "periodic_orbits.png"
    data = compute(quick="--quick" in argv)
    plot(data, path)
    for name, d in data.items():
        inside = (d["long_omega"] >= d["hb_omega"].min()) & (d["long_omega"]
                                                             <= d["hb_omega"].max())
        order = np.argsort(d["hb_omega"])
        hb_at = np.interp(d["long_omega"], d["hb_omega"][order], d["hb"][order])[inside]
        sh_at = np.interp(d["long_omega"], d["omega"], d["shooting"])
        print(f"{name}: max |long - shooting| / shooting = "
              f"{np.max(np.abs(d['long'] - sh_at) / sh_at):.2e}, max |HB - shooting| / "
              f"shooting = {np.max(np.abs(hb_at - sh_at[inside]) / sh_at[inside]):.2e}, max |mu| = "
              f"{d['max_multiplier'].max():.4f}")
    print(f"figure: {path}")
    return data


if __name__ == "__main__":
    main()
