"""Paper 001: two rotating shrouded blades with a wedge friction element -- the figures.

Runs the whole study of paper 001 on the 78-DOF model (models/blade_pair.py, parameters
documented in BladePairParameters) and draws the paper's figures:

* ``campbell_k30.png``  -- Figs 3: imaginary parts of the eigenvalues with the equivalent
  damping of the k = 30 steady state (f = 0.1), excitation lines 15, 20, 30 Omega;
* ``campbell_k20_k15.png`` -- Fig. 4: the first six branches for k = 20 and k = 15;
* ``mode_shapes.png``   -- Fig. 5: first three complex modes at 2000 rpm;
* ``semi_axes.png``     -- Figs 6-7: semi-axes of the orbits of A and B vs rpm, k = 30;
* ``inclination.png``   -- Fig. 8: inclination of the major axes, k = 30;
* ``energy.png``        -- Figs 9-11: friction energy per period vs rpm, k = 30, 20, 15,
  four friction coefficients;
* ``orbits.png``        -- Figs 12-14: orbits of A and B at chosen speeds;
* ``hb_cross_check.png`` -- equivalent linearisation vs multi-harmonic stick-slip HB with
  2D Jenkins contacts, continued in speed (models/blade_pair_hb.py): where they agree (gross
  slip) and where not (near the stick threshold).

The Campbell diagrams follow 001 section 4.1 (B_e from the response without friction
damping), the default of :func:`~fricdamp.models.blade_pair.studies.campbell_diagram`.

Run: ``python examples/001_blade_pair.py [out_dir]``. ``main(out_dir)`` returns the
summary (the ``summary.json`` contract of the blade_pair case plus the file names).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ORDERS = (15, 20, 30)
FRICTION = (0.05, 0.1, 0.2, 0.3)


def _campbell_axes(ax, camp, n, orders, fmax=None):
    rpm = np.array(camp["rpm"])
    F = np.array(camp["frequency_hz"], dtype=float)[:n]
    for row in F:
        ax.plot(rpm, row, "b.", ms=2)
    for k in orders:
        ax.plot(rpm, k * rpm / 60.0, "k--", lw=0.8)
        ax.annotate(f"{k}$\\Omega$", (rpm[-1], k * rpm[-1] / 60.0), fontsize=7)
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("Im($\\lambda$)/2$\\pi$ [Hz]")
    ax.set_ylim(0, fmax if fmax else np.nanmax(F) * 1.05)


def main(out_dir="out/001_blade_pair", *, n_campbell: int = 100, n_sweep: int = 200,
         cross_check: bool = True) -> dict:
    """Compute the 001 study and write the figures and ``summary.json`` into ``out_dir``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from fricdamp.models.blade_pair.hb import compare_with_hb, hb_speed_sweep
    from fricdamp.models.blade_pair.model import build_blade_pair
    from fricdamp.models.blade_pair.studies import (
        campbell_diagram,
        orbits,
        run_blade_pair_case,
        steady_state_sweep,
    )

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    model = build_blade_pair()
    summary = run_blade_pair_case(model.params, n_campbell=n_campbell, n_sweep=n_sweep,
                                  orders=ORDERS, friction_coefficients=FRICTION,
                                  orbit_rpm=[400.0, 1000.0, 1600.0])
    files = []

    def save(fig, name):
        fig.tight_layout()
        fig.savefig(out / name, dpi=110)
        plt.close(fig)
        files.append(name)

    # Figs 3-4: Campbell diagrams with the equivalent damping of each order
    camp = summary["campbell"]
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
    _campbell_axes(axs[0], camp, 15, ORDERS)
    axs[0].set_title(f"k = 30, f = 0.1: first 15 ({camp['complex_pairs'][-1]} complex pairs, "
                     f"{camp['real_eigenvalues'][-1]} real at {camp['rpm'][-1]:.0f} rpm)",
                     fontsize=8)
    _campbell_axes(axs[1], camp, 6, ORDERS, fmax=1400)
    axs[1].set_title("first six (zoom)", fontsize=9)
    save(fig, "campbell_k30.png")
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, k in zip(axs, (20, 15), strict=True):
        c = campbell_diagram(model, np.linspace(100, 2500, n_campbell), order=k,
                             friction_coefficient=0.1, n_modes=6)
        _campbell_axes(ax, c, 6, ORDERS, fmax=1400)
        ax.set_title(f"k = {k}, f = 0.1", fontsize=9)
    save(fig, "campbell_k20_k15.png")

    # Fig. 5: complex mode shapes at 2000 rpm (tangential deflection of both blades)
    cm = summary["complex_modes"]
    r = np.array(cm["blade_nodes_m"])
    fig, axs = plt.subplots(1, 3, figsize=(11, 3.6))
    for j, ax in enumerate(axs):
        for b, style in (("blade1", "-"), ("blade2", "--")):
            w = np.array(cm[b][j])[:, 1]                    # (node, [re, im]) of w
            ax.plot(w[:, 0], r, "b" + style, label=f"{b} Re")
            ax.plot(w[:, 1], r, "r" + style, label=f"{b} Im")
        ax.set_title(f"{cm['frequency_hz'][j]:.1f} Hz, zeta = {cm['damping_ratio'][j]:.3f}",
                     fontsize=9)
        ax.set_xlabel("tangential deflection [-]")
    axs[0].set_ylabel("radius [m]")
    axs[0].legend(fontsize=6)
    save(fig, "mode_shapes.png")

    # Figs 6-8: semi-axes and inclinations vs rpm for k = 30
    ss = [s for s in summary["steady_state"] if s["k"] == 30]
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    for s in ss:
        rpm = np.array(s["rpm"])
        for ax, key in zip(axs, ("semi_axes_A_m", "semi_axes_B_m"), strict=True):
            ab = np.array(s[key])
            line, = ax.semilogy(rpm, ab[:, 0], label=f"a, f = {s['friction_coefficient']}")
            ax.semilogy(rpm, np.maximum(ab[:, 1], 1e-12), ":", color=line.get_color())
    for ax, name in zip(axs, "AB", strict=True):
        ax.set_title(f"contact {name}, k = 30 (solid a, dotted b)", fontsize=9)
        ax.set_xlabel("speed [rpm]")
        ax.set_ylabel("semi-axis [m]")
    axs[0].legend(fontsize=7)
    save(fig, "semi_axes.png")
    fig, ax = plt.subplots(figsize=(6, 4))
    for s in ss:
        ax.plot(s["rpm"], s["inclination_A_rad"], label=f"A, f = {s['friction_coefficient']}")
        ax.plot(s["rpm"], s["inclination_B_rad"], "--", label=f"B, f = "
                f"{s['friction_coefficient']}")
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("inclination of the major axis [rad]")
    ax.legend(fontsize=6, ncol=2)
    save(fig, "inclination.png")

    # Figs 9-11: dissipated energy per period
    fig, axs = plt.subplots(1, 3, figsize=(13, 4))
    for ax, k in zip(axs, (30, 20, 15), strict=True):
        for s in summary["steady_state"]:
            if s["k"] == k:
                ax.semilogy(s["rpm"], np.maximum(s["dissipated_energy_J"], 1e-12),
                            label=f"f = {s['friction_coefficient']}")
        ax.set_title(f"k = {k}", fontsize=9)
        ax.set_xlabel("speed [rpm]")
    axs[0].set_ylabel("friction energy per period [J]")
    axs[0].legend(fontsize=7)
    save(fig, "energy.png")

    # Figs 12-14: orbits at chosen speeds
    orb = {k: orbits(model, k, [400.0, 1000.0, 1600.0], FRICTION) for k in ORDERS}
    fig, axs = plt.subplots(2, 3, figsize=(12, 7))
    for col, k in enumerate((30, 20, 15)):
        for row, name in enumerate("AB"):
            ax = axs[row, col]
            for o in orb[k]:
                e = o[name][0]                              # 400 rpm
                ax.plot(np.array(e["xi_m"]) * 1e6, np.array(e["eta_m"]) * 1e6,
                        label=f"f = {o['friction_coefficient']}")
            ax.set_title(f"{name}, k = {k}, 400 rpm", fontsize=9)
            ax.set_xlabel("xi [um]")
            ax.set_ylabel("eta [um]")
            ax.axis("equal")
    axs[0, 0].legend(fontsize=7)
    save(fig, "orbits.png")

    # cross-check against multi-harmonic balance with 2D Jenkins contacts
    if cross_check:
        rpm_x = np.linspace(250.0, 700.0, 19)
        eq = steady_state_sweep(model, 30, rpm_x, [0.1])[0]
        hb = hb_speed_sweep(model, 30, rpm_x, 0.1)
        cmp_ = compare_with_hb(rpm_x, eq["dissipated_energy_J"], eq["tip_amplitude_m"],
                               hb.dissipated_energy, hb.tip_amplitude.max(axis=1), hb.success)
        summary["hb_cross_check"] = {"rpm": rpm_x.tolist(), **cmp_}
        curves = {"eqlin": (np.array(eq["semi_axes_B_m"])[:, 0],
                            np.asarray(eq["dissipated_energy_J"])),
                  "hb": (hb.semi_axes[:, 1, 0], hb.dissipated_energy)}
        fig, axs = plt.subplots(1, 2, figsize=(11, 4))
        for meth, style in (("eqlin", "o-"), ("hb", "s--")):
            a, W = curves[meth]
            axs[0].semilogy(rpm_x, np.where(a > 0, a, np.nan), style, label=meth)
            axs[1].semilogy(rpm_x, np.where(W > 0, W, np.nan), style, label=meth)
        axs[0].set_ylabel("major semi-axis at B [m]")
        axs[1].set_ylabel("friction energy per period [J]")
        for ax in axs:
            ax.set_xlabel("speed [rpm]")
            ax.legend()
        axs[0].set_title("k = 30, f = 0.1: agree in gross slip, not near the stick threshold",
                         fontsize=8)
        save(fig, "hb_cross_check.png")

    summary["files"] = files
    (out / "summary.json").write_text(json.dumps(summary, indent=1, default=float))
    return summary


if __name__ == "__main__":
    s = main(sys.argv[1] if len(sys.argv) > 1 else "out/001_blade_pair")
    print(f"n_dof {s['n_dof']}, {s['eqlin_iterations']} eqlin iterations, energy balance "
          f"error {s['energy_balance_error']:.1e}, {s['runtime_s']:.1f} s; figures: "
          f"{', '.join(s['files'])}")
