"""Paper 000 (Pfeiffer & Hajek 1992): stick-slip motion of turbine blade dampers.

Makes the paper's figures for the planar blade-damper model into a folder:

* ``fig08_phase_plot.png``   -- phase plot of blade 2 (q4, q4') in forced stick-slip
  (000 Fig. 8): the run and the closed periodic orbit it approaches (shooting, with its
  period multiple and stability), with the time history and the contact configurations;
* ``fig09_pulloff_gamma.png`` -- pull-off amplitude vs block angle gamma (000 Fig. 9);
* ``fig10_pulloff_FZ.png``    -- pull-off amplitude vs centrifugal force F_Z (000 Fig. 10);
* ``fig11_pulloff_frequency.png`` -- pull-off amplitude vs excitation frequency for
  F_Z = 60/100/140 N and gamma = 60/50/40 degrees, with the stuck eigenfrequencies
  (000 Fig. 11);
* ``fig12_design.png``        -- resonant blade amplitude q4 over damper mass and gamma
  (000 Fig. 12).

Run ``python examples/000_blade_damper.py [out_dir] [--quick]``. The full design grid
(4 masses x 4 angles x 2 parabolas, steady states by shooting, lift-off boundary bisected per
mass) takes about an hour of CPU: about a minute per design near the friction-damped
resonance, where responses switch 28 times per period and some beat. :func:`main` returns the
results as plain Python data so that a test can import it (``quick=True`` keeps the
event-driven parts short: a coarse design grid and a short time response).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper.orbits import steady_orbit
from fricdamp.models.blade_damper.studies import (
    CONFIGURATIONS,
    confirm_pulloff,
    default_design_band,
    design_study,
    pulloff_curve,
    pulloff_curves,
    sliding_eigenfrequencies,
    stuck_eigenfrequencies,
    time_response,
)

#: Excitation amplitude of the design study [N] (the paper does not give it).
DESIGN_FE = 8.0


def _fig_pulloff(curves, out: Path) -> list[str]:
    import matplotlib.pyplot as plt

    paths = []
    # Fig. 11: F_e,limit vs frequency, one panel per gamma
    gammas = sorted({c["gamma_deg"] for c in curves}, reverse=True)
    fig, axes = plt.subplots(1, len(gammas), figsize=(4.2 * len(gammas), 3.6), sharey=True)
    for ax, g in zip(np.atleast_1d(axes), gammas, strict=True):
        for c in (c for c in curves if c["gamma_deg"] == g):
            ax.semilogy(c["frequency_hz"], c["F_e_limit_N"], lw=1.2,
                        label=f"F_Z = {c['F_Z_N']:g} N")
        for f0 in c["stuck_eigenfrequencies_hz"]:
            ax.axvline(f0, color="0.6", ls=":", lw=1)
        ax.set_title(f"gamma = {g:g} deg")
        ax.set_xlabel("excitation frequency f_e [Hz]")
        ax.grid(alpha=0.3, which="both")
    np.atleast_1d(axes)[0].set_ylabel("pull-off amplitude F_e,limit [N]")
    np.atleast_1d(axes)[0].legend(fontsize="small")
    fig.suptitle("000 Fig. 11: pull-off amplitude (dotted: stuck 3-DOF eigenfrequencies)")
    fig.tight_layout()
    p = out / "fig11_pulloff_frequency.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    paths.append(str(p))
    return paths


def _fig_pulloff_trends(base, out: Path, f_ref: float) -> tuple[list[str], dict]:
    import matplotlib.pyplot as plt

    gam = np.linspace(35.0, 80.0, 46)
    fz = np.linspace(40.0, 160.0, 25)
    by_gamma = {F: [float(pulloff_curve(base.with_(gamma_deg=g, centrifugal_force=F),
                                        [f_ref]).F_e_limit_N[0]) for g in gam]
                for F in (60.0, 100.0, 140.0)}
    by_fz = {g: [float(pulloff_curve(base.with_(gamma_deg=g, centrifugal_force=F),
                                     [f_ref]).F_e_limit_N[0]) for F in fz]
             for g in (40.0, 50.0, 60.0)}

    def trend_figure(x, curves, label, xlabel, title, name):
        fig, ax = plt.subplots(figsize=(5, 3.6))
        for key, v in curves.items():
            ax.plot(x, v, label=label(key))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"F_e,limit at {f_ref:g} Hz [N]")
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
        fig.tight_layout()
        p = out / name
        fig.savefig(p, dpi=120)
        plt.close(fig)
        return str(p)

    paths = [
        trend_figure(gam, by_gamma, lambda F: f"F_Z = {F:g} N", "block angle gamma [deg]",
                     "000 Fig. 9: pull-off amplitude falls with gamma", "fig09_pulloff_gamma.png"),
        trend_figure(fz, by_fz, lambda g: f"gamma = {g:g} deg", "centrifugal force F_Z [N]",
                     "000 Fig. 10: pull-off amplitude rises with F_Z", "fig10_pulloff_FZ.png"),
    ]
    data = {"frequency_hz": f_ref, "gamma_deg": gam.tolist(),
            "by_gamma": {str(k): v for k, v in by_gamma.items()}, "F_Z_N": fz.tolist(),
            "by_F_Z": {str(k): v for k, v in by_fz.items()}}
    return paths, data


def _fig_phase(tr, out: Path, last_periods: float, orbit=None) -> str:
    import matplotlib.pyplot as plt

    r = tr.result
    t, x, v = tr.phase_plot(3, last_periods=last_periods)
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    axes[0].plot(x * 1e3, v, lw=0.7, color="0.6", label=f"run, last {last_periods:g} periods")
    if orbit is not None and orbit.orbit is not None:
        o = orbit.orbit
        axes[0].plot(o.q[:, 3] * 1e3, o.qd[:, 3], lw=1.5, color="C3",
                     label=f"periodic orbit ({orbit.period_multiple} T, "
                           f"{'stable' if orbit.stable else 'unstable'})")
    axes[0].legend(fontsize="small")
    axes[0].set_xlabel("q4 [mm]")
    axes[0].set_ylabel("q4' [m/s]")
    axes[0].set_title("000 Fig. 8: phase plot of blade 2")
    axes[1].plot(r.t, r.q[:, 3] * 1e3, lw=0.8, label="q4 (blade 2)")
    axes[1].plot(r.t, r.q[:, 1] * 1e3, lw=0.8, label="q2 (blade 1)")
    axes[1].set_xlabel("t [s]")
    axes[1].set_ylabel("displacement [mm]")
    axes[1].legend(fontsize="small")
    axes[2].step(r.t, tr.configuration, where="post", lw=0.8)
    axes[2].set_yticks(range(4), CONFIGURATIONS)
    axes[2].set_xlabel("t [s]")
    axes[2].set_title("contact configuration (K1/K2)")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    p = out / "fig08_phase_plot.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    return str(p)


def _fig_design(design: dict, out: Path) -> str:
    import matplotlib.pyplot as plt

    m = np.array(design["damper_mass_kg"]) * 1e3
    g = np.array(design["gamma_deg"])
    fig, axes = plt.subplots(1, len(design["parabolas"]), figsize=(5.2 * len(
        design["parabolas"]), 3.8), squeeze=False)
    for ax, par in zip(axes[0], design["parabolas"], strict=True):
        A = np.array(par["blade_amplitude_m"]) * 1e3
        ok = np.array(par["valid"], dtype=bool)
        for j, gj in enumerate(g):
            line, = ax.plot(m, np.where(ok[:, j], A[:, j], np.nan), "o-", lw=1.2, ms=3,
                            label=f"gamma = {gj:g} deg")
            bad = ~ok[:, j]
            ax.plot(m[bad], A[bad, j], "x", color=line.get_color(), ms=7)
        ax.set_xscale("log")
        ax.set_xticks(m, [f"{v:g}" for v in m])
        ax.minorticks_off()
        ax.set_xlabel("damper mass m_D [g]")
        ax.set_ylabel("resonant blade amplitude q4 [mm]")
        ax.set_title(f"000 Fig. 12: p1 = {par['p1_per_m']:g} 1/m, p2 = "
                     f"{par['p2_m'] * 1e3:g} mm")
        ax.grid(alpha=0.3, which="both")
    opt = design["optimum"]
    axes[0][0].plot(opt["damper_mass_kg"] * 1e3, opt["blade_amplitude_m"] * 1e3, "k*", ms=12,
                    label="optimum")
    axes[0][0].legend(fontsize="small", title="x: normal force < 0 (invalid)",
                      title_fontsize="small")
    fig.tight_layout()
    p = out / "fig12_design.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    return str(p)


def main(out_dir="000_blade_damper_out", *, quick: bool = False) -> dict:
    """Compute the paper-000 results and write the figures into ``out_dir``.

    Returns
    -------
    dict
        ``pulloff`` (9 curves, results contract), ``design`` (results contract),
        ``eigenfrequencies`` (stuck, sliding [Hz]), ``pulloff_checks`` (event-driven
        confirmations), ``time_response`` (summary of the Fig. 8 run), ``trends`` (Figs 9-10
        data), ``figures`` (paths), ``runtime_s``.
    """
    t0 = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    base = BladeDamperParameters()
    sysb = BladeDamperSystem(base)
    freq = np.linspace(10.0, 250.0, 961)
    curves = pulloff_curves(base, frequency_hz=freq)
    figures = _fig_pulloff(curves, out)
    trend_paths, trends = _fig_pulloff_trends(base, out, 30.0)
    figures += trend_paths
    fs = stuck_eigenfrequencies(sysb)
    checks = []
    for f in ([float(fs[1])] if quick else [30.0, float(fs[0]), float(fs[1]), float(fs[2])]):
        c = confirm_pulloff(base, f, margin=0.02, periods=1.5)
        checks.append({"frequency_hz": c.frequency_hz, "F_e_limit_N": c.F_e_limit_N,
                       "slipped_below": c.slipped[0], "slipped_above": c.slipped[1],
                       "confirmed": c.confirmed})
    # Fig. 8: forced stick-slip between the blade resonances
    pp = base.with_(excitation_amplitude=8.0, excitation_frequency=58.0)
    periods = 6.0 if quick else 40.0
    tr = time_response(pp, periods, samples_per_period=200, rtol=1e-8)
    r = tr.result
    # the closed orbit the run approaches, by shooting from its end state
    so = steady_orbit(pp, y0=np.concatenate([r.q[-1], r.qd[-1]]), t_start=float(r.t[-1]))
    figures.append(_fig_phase(tr, out, 3.0, so))
    tresp = {"periods": periods, "excitation_frequency_hz": 58.0, "excitation_amplitude_N": 8.0,
             "time_in_configuration_s": tr.time_in_configuration,
             "n_events": int(r.n_events), "energy_balance_error": r.energy_balance_error,
             "q4_amplitude_m": 0.5 * float(np.ptp(tr.phase_plot(3, 3.0)[1])),
             "errors": list(tr.errors), "orbit": so.summary()}
    # Fig. 12: design study (F_Z = m_D a_c, a_c = 1e5 m/s^2)
    if quick:
        ds = design_study(base.with_(excitation_amplitude=DESIGN_FE), (2e-3, 4e-3), (50.0,),
                          frequency_hz=[45.0, 47.0])
    else:
        ds = design_study(base.with_(excitation_amplitude=DESIGN_FE),
                          (0.5e-3, 1e-3, 2e-3, 4e-3), (40.0, 55.0, 65.0, 80.0),
                          parabolas=[(base.p1, base.p2), (-150.0, base.p2)],
                          frequency_hz=default_design_band(base, 6))
    design = ds.to_dict()
    figures.append(_fig_design(design, out))
    return {
        "pulloff": curves,
        "design": design,
        "eigenfrequencies": {"stuck_hz": fs.tolist(),
                             "sliding_hz": sliding_eigenfrequencies(sysb).tolist()},
        "pulloff_checks": checks,
        "time_response": tresp,
        "trends": trends,
        "figures": figures,
        "runtime_s": time.perf_counter() - t0,
    }


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    res = main(args[0] if args else "000_blade_damper_out", quick="--quick" in sys.argv)
    print(f"figures: {res['figures']}")
    print(f"stuck eigenfrequencies [Hz]: {np.round(res['eigenfrequencies']['stuck_hz'], 2)}")
    print(f"design optimum: {res['design']['optimum']}")
    print(f"runtime {res['runtime_s']:.1f} s")
