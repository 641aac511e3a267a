"""Paper 003 (Pesek et al.): bladed wheel with tie-boss friction contacts.

Makes the paper's tables and figures from the tuned beam model of the 30-blade wheel
(:mod:`fricdamp.models.tieboss_wheel.model`):

* ``table1.png`` -- open-contact eigenfrequencies by nodal diameter against Table 1;
* ``campbell.png`` -- Campbell diagram 60-450 rpm with the lines of p = 8 pulses and the
  critical speeds of Table 2 (003 (1));
* ``decay_2ND.png``, ``decay_6ND.png`` -- the free attenuation of the paper's strategy
  (modal forces at the tie-bosses, static solution with contacts, release): displacements
  of the contact nodes of contacts A and B with the envelope (Figs 13-14);
* ``trajectories_2ND.png``, ``trajectories_6ND.png`` -- one period of the contact nodes'
  motion and of the relative motion in the contact plane (Figs 15-16);
* ``contact_states_2ND.png``, ``contact_states_6ND.png`` -- open / stick / slip of the 30
  contacts over time (Figs 17-18);
* ``envelopes.png`` -- the envelopes of both modes and the amplitude-dependent damping
  ratio (Fig. 19).

Run it::

    python examples/003_tieboss_wheel.py [OUT_DIR]

It writes ``summary.json`` (the ``summary.json`` contract of ``tieboss_wheel.toml``: ``modal``,
``decay``, ``critical_speeds_rpm``, ``reduction``, plus ``long_decay`` and ``figures``) and the
figures into OUT_DIR (default ``fricdamp-out/003_tieboss_wheel``); ``main(out_dir)`` returns
the summary. With ``compare_full=True`` (default) the 2ND decay is also run on the
full-order wheel with the general solver (~20-40 s).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from fricdamp.iofiles import save_figure, write_json
from fricdamp.models.tieboss_wheel.model import (
    TABLE1_EXPERIMENT_HZ,
    TABLE1_FEM_HZ,
    TiebossWheelParameters,
    build_sector,
    build_wheel,
)
from fricdamp.models.tieboss_wheel.studies import (
    TABLE2_ORDERS,
    campbell_by_nd,
    critical_speeds_by_nd,
    free_decay,
    modal_by_nd,
    reduction_comparison,
)

N_MODES = 10            # fixed-interface modes per sector
DT = 1e-5               # time step [s] (converged: 5e-6 s changes the ratios by < 0.1 %)
STATE_COLORS = ("#d9d9d9", "#1f77b4", "#d62728")   # open, stick, slip


def _plot_table1(modal, ax):
    nd = np.asarray(modal["nd"])
    f = np.asarray(modal["frequency_hz"])
    ax.plot(nd, f, "k.-", label="model (cyclic symmetry)")
    for k, (n, pair) in enumerate(TABLE1_FEM_HZ.items()):
        ax.plot([n] * len(pair), pair, "s", mfc="none", color="C0",
                label="003 Table 1, FEM" if k == 0 else None)
    for k, (n, pair) in enumerate(TABLE1_EXPERIMENT_HZ.items()):
        vals = [v for v in pair if v is not None]
        ax.plot([n] * len(vals), vals, "^", mfc="none", color="C1",
                label="003 Table 1, experiment" if k == 0 else None)
    ax.set_xlabel("nodal diameter")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title("open-contact eigenfrequencies by ND (003 Table 1)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")


def _plot_decay(run, ax_a, ax_b):
    """Figs 13-14: contact nodes of contacts A (B29|B0) and B (B0|B1), x y z components."""
    t = run.t
    for ax, keys, title in ((ax_a, ("B29.right", "B0.left"), "contact A"),
                            (ax_b, ("B0.right", "B1.left"), "contact B")):
        for key, ls in zip(keys, ("-", "--"), strict=True):
            for c, comp in enumerate("xyz"):
                ax.plot(t, 1e3 * run.nodes[key][:, c], ls, lw=0.8, color=f"C{c}",
                        label=f"{key} {comp}")
        ax.set_title(f"{run.nd}ND, {title}")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("displacement [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
    if run.decay is not None:
        env = run.decay.envelope
        ax_b.plot(env.time, 1e3 * env.amplitude, "r.-", lw=0.8, label="envelope (probe)")
        ax_b.plot(env.time, -1e3 * env.amplitude, "g.-", lw=0.8)


def _last_period(run):
    f = run.decay.mean_frequency_hz if run.decay is not None else 45.0
    return run.t >= run.t[-1] - 1.0 / f


def _plot_trajectories(run, fig):
    """Figs 15-16: one period of the contact nodes' motion and of their relative motion."""
    sel = _last_period(run)
    ax = fig.add_subplot(1, 3, 1, projection="3d")
    for key, c in (("B0.right", "C0"), ("B1.left", "C1"), ("B29.right", "C2"),
                   ("B0.left", "C3")):
        x = 1e3 * run.nodes[key][sel]
        ax.plot(x[:, 0], x[:, 1], x[:, 2], color=c, lw=1, label=key)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.legend(fontsize=6)
    ax.set_title(f"{run.nd}ND: contact nodes, one period")
    ax2 = fig.add_subplot(1, 3, 2)
    for c, name in ((0, "contact B (0)"), (run.contact_displacement.shape[1] - 1,
                                          "contact A (29)")):
        u = 1e6 * run.contact_displacement[sel, c]
        ax2.plot(u[:, 1], u[:, 2], lw=1, label=name)
    ax2.set_xlabel("relative t1 (radial) [um]")
    ax2.set_ylabel("relative t2 (in plane) [um]")
    ax2.set_title("relative motion in the contact plane")
    ax2.axis("equal")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize="small")
    ax3 = fig.add_subplot(1, 3, 3)
    ax3.plot(run.t[sel], 1e6 * run.contact_displacement[sel, 0, 0], label="u_n [um]")
    ax3.plot(run.t[sel], run.contact_force[sel, 0, 0], label="N [N]")
    ax3.plot(run.t[sel], np.hypot(run.contact_force[sel, 0, 1], run.contact_force[sel, 0, 2]),
             label="|f_t| [N]")
    ax3.axhline(-1e6 * run.meta["offset_m"], color="0.5", lw=0.8, ls=":", label="opening")
    ax3.set_xlabel("time [s]")
    ax3.set_title("contact B: approach and forces")
    ax3.grid(alpha=0.3)
    ax3.legend(fontsize="small")


def _plot_states(run, fig):
    """Figs 17-18: contact states of the 30 tie-boss pairs over time."""
    from matplotlib.colors import ListedColormap

    ax = fig.add_subplot(1, 1, 1)
    st = run.contact_status
    ax.imshow(st.T, aspect="auto", interpolation="nearest", origin="lower",
              cmap=ListedColormap(STATE_COLORS), vmin=0, vmax=2,
              extent=(run.t[0], run.t[-1], -0.5, st.shape[1] - 0.5))
    frac = [np.mean(st == k) for k in range(3)]
    for k, name in enumerate(("open (near contact)", "stick", "slip")):
        ax.plot([], [], "s", color=STATE_COLORS[k], label=f"{name}: {100 * frac[k]:.0f} %")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("contact (blade pair)")
    ax.set_title(f"{run.nd}ND: contact states")
    ax.legend(fontsize="small", loc="upper right")


def main(out_dir="fricdamp-out/003_tieboss_wheel", *, params: TiebossWheelParameters | None = None,
         compare_full: bool = True, long_decay_s: float = 0.3) -> dict:
    """Make the figures and the summary; return the summary (also written as JSON)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    p = TiebossWheelParameters() if params is None else params
    sector = build_sector(p)
    modal = modal_by_nd(sector, n_modes=2)
    camp = campbell_by_nd(sector, rpm=np.linspace(60.0, 450.0, 40))
    crit = critical_speeds_by_nd(sector, orders=TABLE2_ORDERS + ((2, 15),))
    wheel = build_wheel(sector, n_modes=N_MODES)
    runs, long_runs, decay = {}, {}, []
    for nd in (2, 6):
        runs[nd] = free_decay(wheel, nd, amplitude_m=5e-4, duration_s=0.1, dt=DT)
        long_runs[nd] = free_decay(wheel, nd, amplitude_m=5e-4, duration_s=long_decay_s,
                                   dt=2 * DT, save_every=1)
        entry = runs[nd].summary()
        entry["damping_ratio_modal_forcing"] = free_decay(
            wheel, nd, amplitude_m=5e-4, duration_s=0.1, dt=DT, forcing="modal").damping_ratio
        decay.append(entry)
    if compare_full:
        reduction = reduction_comparison(p, nd=2, n_modes=N_MODES, duration_s=0.1, dt=DT)
    else:
        reduction = {"full_dof": p.n_blades * sector.cyclic.n_independent,
                     "reduced_dof": wheel.n_dof, "n_modes": N_MODES,
                     "damping_ratio_difference": None}
    summary = {
        "modal": {k: modal[k] for k in ("nd", "frequency_hz", "table1", "max_table1_error")},
        "decay": decay,
        "critical_speeds_rpm": crit,
        "reduction": reduction,
        "long_decay": [{"nd": nd, "duration_s": long_decay_s,
                        "damping_ratio": r.damping_ratio,
                        "envelope_time_s": r.decay.envelope.time.tolist(),
                        "envelope_m": r.decay.envelope.amplitude.tolist(),
                        "amplitude_m": r.summary().get("amplitude_m"),
                        "amplitude_damping_ratio": r.summary().get("amplitude_damping_ratio")}
                       for nd, r in long_runs.items()],
        "paper": {"damping_ratio": {"2": 0.012, "6": 0.022},
                  "critical_speeds_rpm": {"o=1 (2ND)": 334, "o=3 (6ND)": 123}},
        "parameters": p.to_dict(),
    }

    figs = []
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    _plot_table1(modal, ax)
    figs.append(("table1.png", fig))

    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    camp.plot(orders=(1, 2, 3), pulses=8, ax=ax)
    for c in crit:
        if c["rpm"] is not None:
            ax.plot(c["rpm"], c["frequency_hz"], "ro", ms=5)
            ax.annotate(f"{c['rpm']:.0f} rpm ({c['nd']}ND, o={c['order']})",
                        (c["rpm"], c["frequency_hz"]), fontsize=7, xytext=(4, -10),
                        textcoords="offset points")
    figs.append(("campbell.png", fig))

    for nd, run in runs.items():
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
        _plot_decay(run, a1, a2)
        figs.append((f"decay_{nd}ND.png", fig))
        fig = plt.figure(figsize=(14, 4.4))
        _plot_trajectories(run, fig)
        figs.append((f"trajectories_{nd}ND.png", fig))
        fig = plt.figure(figsize=(8, 4.4))
        _plot_states(run, fig)
        figs.append((f"contact_states_{nd}ND.png", fig))

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for nd, r in long_runs.items():
        env = r.decay.envelope
        a1.plot(env.time, 1e3 * env.amplitude, ".-", label=f"{nd}ND (zeta over 0.1 s: "
                f"{100 * runs[nd].damping_ratio:.2f} %)")
        amp = r.amplitude_decay if r.amplitude_decay is not None else r.decay
        a2.plot(1e3 * amp.amplitude, 100 * amp.damping_ratio, "o-", ms=3, label=f"{nd}ND")
    a1.set_xlabel("time [s]")
    a1.set_ylabel("envelope of the probe [mm]")
    a1.set_title("free attenuation envelopes (003 Fig. 19)")
    a1.legend(fontsize="small")
    a1.grid(alpha=0.3)
    for nd, z in ((2, 1.2), (6, 2.2)):
        a2.axhline(z, ls=":", color="C0" if nd == 2 else "C1", lw=0.8)
        a2.annotate(f"paper {nd}ND", (0.05, z), fontsize=7)
    a2.set_xlabel("amplitude [mm]")
    a2.set_ylabel("damping ratio [%]")
    a2.set_title("amplitude-dependent damping ratio")
    a2.legend(fontsize="small")
    a2.grid(alpha=0.3)
    figs.append(("envelopes.png", fig))

    for name, fig in figs:
        fig.tight_layout()
        save_figure(fig, out / name)
        plt.close(fig)
    summary["figures"] = [name for name, _ in figs]
    summary["runtime_s"] = time.perf_counter() - t0
    write_json(out / "summary.json", summary)
    return summary


if __name__ == "__main__":
    s = main(*(sys.argv[1:2]))
    print(f"Table 1: largest error {100 * s['modal']['max_table1_error']:.2f} %")
    for c in s["critical_speeds_rpm"]:
        print(f"o = {c['order']} ({c['nd']}ND): {c['rpm']:.1f} rpm at {c['frequency_hz']:.2f} Hz"
              + (f"  (paper {c['paper_rpm']} rpm)" if "paper_rpm" in c else ""))
    for d in s["decay"]:
        print(f"{d['nd']}ND: zeta = {100 * d['damping_ratio']:.2f} % (paper "
              f"{'1.2' if d['nd'] == 2 else '2.2'} %), pure-mode start "
              f"{100 * d['damping_ratio_modal_forcing']:.2f} %, from "
              f"{1e3 * d['initial_amplitude_m']:.2f} mm, {d['runtime_s']:.2f} s")
    r = s["reduction"]
    if r.get("damping_ratio_difference") is not None:
        print(f"reduced {r['reduced_dof']} DOF vs full {r['full_dof']} DOF: damping difference "
              f"{100 * r['damping_ratio_difference']:.2f} %, speed ratio {r['speed_ratio']:.1f}x")
    print(f"figures: {', '.join(s['figures'])}  ({s['runtime_s']:.1f} s)")
