"""Figures of paper 003's case-file analyses (Table 1, the Campbell diagram, the free
attenuations of Figs 13-19, the reduction comparison).

A helper of :mod:`fricdamp.models.tieboss_wheel.case`: each ``run_*`` there returns a
``figures()`` callable that calls one of these. matplotlib is imported inside the functions
only; the leading underscore keeps :mod:`fricdamp.runner`'s auto-import away.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from fricdamp.models.tieboss_wheel._case_spec import PAPER_DAMPING_RATIO

if TYPE_CHECKING:
    from fricdamp.models.tieboss_wheel.case import CampbellByNDAnalysis, TiebossWheelCaseModel

#: Open / stick / slip colours of the contact-state figures.
STATE_COLORS = ("#d9d9d9", "#1f77b4", "#d62728")


def _last_period(run) -> np.ndarray:
    f = run.decay.mean_frequency_hz if run.decay is not None else 45.0
    return run.t >= run.t[-1] - 1.0 / f


def _modal_figures(summary: dict) -> list:
    from fricdamp import plot
    from fricdamp.models.tieboss_wheel.model import TABLE1_EXPERIMENT_HZ, TABLE1_FEM_HZ

    nd = np.asarray(summary["nd"])
    F = np.asarray(summary["families_hz"])
    table = "table1" in summary
    fig, axes = plot.new_figure(1, 2 if table else 1, width=11.5 if table else 6.5,
                                height=4.2, title="Open-contact eigenfrequencies by nodal "
                                                  "diameter (003 Table 1)")
    ax = axes[0, 0]
    ax.plot(nd, F[:, 0], "k.-", label="model, first family (cyclic symmetry)")
    if table:
        for k, (n, pair) in enumerate(TABLE1_FEM_HZ.items()):
            ax.plot([n] * len(pair), pair, "s", mfc="none", color="C0",
                    label="003 Table 1, FEM" if k == 0 else None)
        for k, (n, pair) in enumerate(TABLE1_EXPERIMENT_HZ.items()):
            vals = [v for v in pair if v is not None]
            ax.plot([n] * len(vals), vals, "^", mfc="none", color="C1",
                    label="003 Table 1, experiment" if k == 0 else None)
    ax.set_xlabel("nodal diameter")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize="small", loc="lower right")
    if table:
        ax2 = axes[0, 1]
        rows = summary["table1"]
        x = [r["nd"] for r in rows]
        err = [100 * r["relative_error"] for r in rows]
        ax2.bar([str(v) for v in x], err, color="C0")
        for lim in (-1.0, 1.0):
            ax2.axhline(lim, color="0.4", ls="--", lw=0.8)
        ax2.axhline(0.0, color="k", lw=0.6)
        ax2.set_xlabel("nodal diameter")
        ax2.set_ylabel("model / paper FEM pair mean - 1 [%]")
        ax2.set_title("error to Table 1 (dashed: 1 %)", fontsize="small")
        ax2.set_ylim(-1.5, 1.5)
    return [("table1.png", "Open-contact eigenfrequencies by nodal diameter: the model's first "
             "family against 003 Table 1 (FEM pairs and experiment), and the relative error "
             "to the FEM pair means", fig)]


def _campbell_figures(camp, crit: list, spec: CampbellByNDAnalysis) -> list:
    import matplotlib

    from fricdamp import plot

    fig, axes = plot.new_figure(width=8.0, height=5.0, title=f"Campbell diagram by nodal "
                                f"diameter, p = {spec.pulses} pulses (003 Fig. 6, (1))")
    ax = axes[0, 0]
    cmap = matplotlib.colormaps["viridis"]
    nd_max = max(int(camp.nd.max()), 1)
    for k, nd in enumerate(camp.nd):
        ax.plot(camp.rpm, camp.frequency_hz[:, k], color=cmap(nd / nd_max), lw=1.1,
                label=f"{nd}ND" if nd in (0, 2, 6, nd_max) else None)
    fmin, fmax = float(camp.frequency_hz.min()), float(camp.frequency_hz.max())
    lo, hi = 0.9 * fmin, 1.05 * fmax
    orders = sorted(set(spec.orders) | {c["order"] for c in crit})
    for o in orders:
        f = spec.pulses * o * camp.rpm / 60.0
        ax.plot(camp.rpm, f, "k--", lw=0.8)
        inside = np.flatnonzero((f > lo) & (f < hi))
        if inside.size:
            i = inside[inside.size // 2]
            ax.annotate(f"o = {o}", (camp.rpm[i], f[i]), fontsize=8, xytext=(4, -2),
                        textcoords="offset points")
    labels = {"model": "critical speed 003 (1)", "paper": "003 Table 2 (measured)"}
    for c in crit:
        if c["rpm"] is not None:
            ax.plot(c["rpm"], c["frequency_hz"], "o", color="tab:red", ms=6,
                    label=labels.pop("model", None))
            ax.annotate(f"{c['rpm']:.0f} rpm ({c['nd']}ND, o = {c['order']})",
                        (c["rpm"], c["frequency_hz"]), fontsize=7, xytext=(5, -11),
                        textcoords="offset points")
        if "paper_rpm" in c:
            ax.plot(c["paper_rpm"], c["paper_frequency_hz"], "x", color="k", ms=7,
                    label=labels.pop("paper", None))
    ax.set_xlim(camp.rpm[0], camp.rpm[-1])
    ax.set_ylim(lo, hi)
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize="small", loc="lower right")
    return [("campbell.png", f"Campbell diagram: first-family frequencies by nodal diameter vs "
             f"speed (contacts open), the engine-order lines p o n / 60 of p = {spec.pulses} "
             "pulses and the critical speeds s = 60 f / (p o) (003 (1)) against Table 2", fig)]


def _decay_figures(runs: list, obj: TiebossWheelCaseModel) -> list:
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.ticker import ScalarFormatter

    from fricdamp import plot

    N = obj.n_blades
    A = (f"B{N - 1}.right", "B0.left")
    B = ("B0.right", "B1.left")
    figs = []
    for run in runs:
        # Figs 13-14: the contact nodes of contacts A and B, with the probe's envelope
        fig, axes = plot.new_figure(1, 2, width=12.0, height=4.2, title=f"{run.nd}ND: free "
                                    "attenuation of the contact nodes (003 Figs 13-14)")
        for ax, keys, name in ((axes[0, 0], A, "contact A"), (axes[0, 1], B, "contact B")):
            for key, ls in zip(keys, ("-", "--"), strict=True):
                for c, comp in enumerate("xyz"):
                    ax.plot(run.t, 1e3 * run.nodes[key][:, c], ls, lw=0.7, color=f"C{c}",
                            label=f"{key} {comp}")
            ax.set_title(f"{name} ({keys[0]} | {keys[1]})", fontsize="small")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("displacement from rest [mm]")
        if run.decay is not None:
            env = run.decay.envelope
            axes[0, 1].plot(env.time, 1e3 * env.amplitude, "k.", ms=4,
                            label="envelope (B0.right along the flexural direction)")
        for ax in axes[0]:
            ax.legend(fontsize=6, ncols=2, loc="upper right")
        figs.append((f"decay_{run.nd}ND.png", f"{run.nd}ND: displacements (x, y, z in blade "
                     "0's frame) of the contact nodes of contacts A and B during the free "
                     "attenuation, with the envelope of the probe (003 Figs 13-14)", fig))

        # Figs 15-16: one period of the contact nodes' trajectories, relative motion, forces
        sel = _last_period(run)
        fig = Figure(figsize=(14.0, 4.4), layout="constrained")
        fig.suptitle(f"{run.nd}ND: contact-node trajectories over the last period "
                     "(003 Figs 15-16)", fontsize="medium")
        ax = fig.add_subplot(1, 3, 1, projection="3d")
        for key, c in zip(B + A, ("C0", "C1", "C2", "C3"), strict=True):
            x = 1e3 * run.nodes[key][sel]
            ax.plot(x[:, 0], x[:, 1], x[:, 2], color=c, lw=1, label=key)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")
        ax.legend(fontsize=6)
        ax2 = fig.add_subplot(1, 3, 2)
        for ci, name in ((0, "contact B (0)"), (N - 1, f"contact A ({N - 1})")):
            u = 1e6 * run.contact_displacement[sel, ci]
            ax2.plot(u[:, 1], u[:, 2], lw=1, label=name)
        ax2.set_xlabel("relative t1 (radial) [µm]")
        ax2.set_ylabel("relative t2 (in the plane) [µm]")
        ax2.set_title("relative motion in the contact plane", fontsize="small")
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize="small")
        ax3 = fig.add_subplot(1, 3, 3)
        t = run.t[sel]
        ax3.plot(t, 1e6 * run.contact_displacement[sel, 0, 0], label="approach u_n [µm]")
        ax3.plot(t, run.contact_force[sel, 0, 0], label="normal force N [N]")
        ax3.plot(t, np.hypot(run.contact_force[sel, 0, 1], run.contact_force[sel, 0, 2]),
                 label="|f_t| [N]")
        ax3.axhline(-1e6 * run.meta["offset_m"], color="0.5", lw=0.8, ls=":",
                    label="opening (u_n = -g0)")
        ax3.set_xlabel("time [s]")
        ax3.set_title("contact B: approach and forces", fontsize="small")
        ax3.grid(alpha=0.3)
        ax3.legend(fontsize="small")
        figs.append((f"trajectories_{run.nd}ND.png", f"{run.nd}ND: trajectories of the contact "
                     "nodes of contacts A and B over the last period, their relative motion in "
                     "the contact plane, and contact B's normal approach and forces "
                     "(003 Figs 15-16)", fig))

        # Figs 17-18: open / stick / slip of every contact over time
        if run.contact_status is not None:
            st = run.contact_status
            fig, axes = plot.new_figure(width=9.0, height=4.4, title=f"{run.nd}ND: contact "
                                        "states (003 Figs 17-18)")
            ax = axes[0, 0]
            ax.grid(False)
            ax.imshow(st.T, aspect="auto", interpolation="nearest", origin="lower",
                      cmap=ListedColormap(STATE_COLORS), vmin=0, vmax=2,
                      extent=(run.t[0], run.t[-1], -0.5, st.shape[1] - 0.5))
            for k, name in enumerate(("open (near contact)", "stick", "slip")):
                ax.plot([], [], "s", color=STATE_COLORS[k],
                        label=f"{name}: {100 * np.mean(st == k):.0f} %")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("contact (blade j | j + 1)")
            ax.legend(fontsize="small", loc="upper right")
            figs.append((f"contact_states_{run.nd}ND.png", f"{run.nd}ND: state of each of the "
                         f"{N} tie-boss contacts over time: open, stick or slip "
                         "(003 Figs 17-18)", fig))

    # Fig. 19: envelopes with the log-decrement fit, amplitude-dependent ratio
    fig, axes = plot.new_figure(1, 2, width=12.0, height=4.4, title="Free-attenuation "
                                "envelopes and damping (003 Fig. 19)")
    a1, a2 = axes[0]
    for i, run in enumerate(runs):
        if run.decay is None:
            continue
        col = f"C{i % 10}"
        dec = run.decay
        env = dec.envelope
        a1.semilogy(env.time, 1e3 * env.amplitude, "o", ms=3.5, color=col,
                    label=f"{run.nd}ND envelope (probe)")
        delta = 2 * np.pi * run.damping_ratio / math.sqrt(1.0 - run.damping_ratio ** 2)
        tl = np.linspace(env.time[0], env.time[-1], 100)
        a1.semilogy(tl, 1e3 * env.amplitude[0] * np.exp(
            -delta * dec.mean_frequency_hz * (tl - env.time[0])), "-", lw=1, color=col,
            label=rf"log decrement: $\zeta$ = {100 * run.damping_ratio:.2f} %")
        cf = dec.coulomb
        a1.semilogy(tl, 1e3 * np.maximum(cf.intercept - cf.slope * tl, 1e-12), ":", lw=1,
                    color=col, label="linear (Coulomb) fit")
        a2.plot(1e3 * dec.amplitude, 100 * dec.damping_ratio, "o", ms=3, color=col,
                alpha=0.6, label=f"{run.nd}ND, successive peaks")
        hil = run.amplitude_decay
        if hil is not None and hil.amplitude.size >= 2:
            a2.plot(1e3 * hil.amplitude, 100 * hil.damping_ratio, "s-", ms=4, color=col,
                    label=f"{run.nd}ND, Hilbert cycles")
        a2.axhline(100 * run.damping_ratio, ls=":", lw=1, color=col,
                   label=f"{run.nd}ND, record average")
        if run.nd in PAPER_DAMPING_RATIO and obj.n_blades == 30:
            a2.axhline(100 * PAPER_DAMPING_RATIO[run.nd], ls="--", lw=0.8, color=col,
                       label=f"paper {run.nd}ND (log decrement)")
    a1.yaxis.set_minor_formatter(ScalarFormatter())
    a1.set_xlabel("time [s]")
    a1.set_ylabel("envelope of the probe [mm]")
    a2.set_xlabel("amplitude [mm]")
    a2.set_ylabel("damping ratio [%]")
    a2.set_title("amplitude-dependent ratio (alternate peak pairs differ by the drift of "
                 "the friction-locked rest position)", fontsize="x-small")
    if any(run.decay is not None for run in runs):
        a1.legend(fontsize="x-small")
        a2.legend(fontsize="x-small")
    else:
        a1.text(0.5, 0.5, "too few envelope peaks: lengthen duration_s", ha="center",
                transform=a1.transAxes)
    figs.append(("envelopes.png", "Envelopes of the free attenuations (peaks of the probe) "
                 "with the record-average log-decrement fit and the linear (Coulomb) fit, and "
                 "the amplitude-dependent damping ratio against the paper's values "
                 "(003 Fig. 19)", fig))
    return figs


def _reduction_figures(rf, rr, r: dict) -> list:
    from fricdamp import plot

    n = min(rf.t.size, rr.t.size)
    fig, axes = plot.new_figure(2, 1, width=9.0, height=2.8, sharex=True,
                                title=f"{r['nd']}ND free attenuation: full order "
                                      f"({r['full_dof']} DOFs) vs Craig-Bampton "
                                      f"({r['reduced_dof']} DOFs)")
    t = rf.t[:n]
    a1, a2 = axes[:, 0]
    a1.plot(t, 1e3 * rf.signal[:n], lw=1.2, label=f"full: zeta = "
            f"{100 * r['damping_ratio_full']:.3f} %")
    a1.plot(t, 1e3 * rr.signal[:n], "--", lw=1, label=f"reduced: zeta = "
            f"{100 * r['damping_ratio_reduced']:.3f} %")
    a1.set_ylabel("probe [mm]")
    a1.legend(fontsize="small", loc="upper right")
    d = rr.signal[:n] - rf.signal[:n]
    fac, unit = plot.si_scale(d, "m")
    a2.plot(t, d / fac, lw=0.8, color="C3")
    a2.set_ylabel(f"reduced - full [{unit}]")
    a2.set_xlabel("time [s]")
    return [("reduction.png", "Probe displacement of the free attenuation on the full-order "
             "wheel (general solver) and on the Craig-Bampton wheel (compiled path), and "
             "their difference", fig)]


# ------------------------------------------------------------------------------ issue 17
def _orders_figures(emap: list, forces, content, obj, branch) -> list:
    """Interference (ZZENF) diagram and the rig's force pattern decomposition."""
    from fricdamp import plot

    N = obj.n_blades
    nds = np.arange(N // 2 + 1)
    fig, axes = plot.new_figure(1, 2, width=12.0, height=4.6,
                                title="Electromagnet excitation: engine orders and nodal "
                                      "diameters (interference diagram)")
    ax = axes[0, 0]
    speeds = sorted({e.get("measured_rpm") or 0.0 for e in emap} - {0.0}) or [300.0]
    for k, rpm in enumerate(speeds):
        f = [branch(int(n), rpm) for n in nds]
        ax.plot(nds, f, ".-", color=f"C{k}", label=f"first family at {rpm:g} rpm")
    for e in emap:
        rpm = e.get("measured_rpm")
        if rpm is None:
            continue
        fe = e["harmonic"] * rpm / 60.0
        ax.axhline(fe, color="0.5", ls=":", lw=0.8)
        ax.plot(e["excited_nds"], [fe] * len(e["excited_nds"]), "o", mfc="none", color="k",
                ms=5, label="excited NDs (synchronous pulses)" if e is emap[0] else None)
        ax.plot([e["stationary_rule_nd"]], [fe], "x", color="tab:red", ms=8,
                label="stationary rule ND = +-p o mod N" if e is emap[0] else None)
        if e["nd"] is not None:
            ax.plot([e["nd"]], [fe], "*", color="tab:green", ms=12,
                    label="resonating ND (nearest crossing)" if e is emap[0] else None)
        ax.annotate(f"o = {e['order']}: {e['harmonic']} x {rpm:g}/60 Hz", (0, fe),
                    fontsize=7, xytext=(2, 3), textcoords="offset points")
    ax.set_xlabel("nodal diameter")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize="x-small", loc="lower right")
    ax2 = axes[0, 1]
    n_show = max(e["harmonic"] for e in emap) + 4
    C = content[:n_show + 1]
    folded = np.stack([np.maximum(C[:, k], C[:, (N - k) % N]) for k in nds], axis=1)
    im = ax2.imshow(folded.T, origin="lower", aspect="auto", cmap="magma_r",
                    extent=(-0.5, n_show + 0.5, -0.5, N // 2 + 0.5))
    fig.colorbar(im, ax=ax2, label="|c(n, k)| per unit pull [N]")
    ax2.set_xlabel("revolution harmonic n")
    ax2.set_ylabel("nodal diameter k")
    ax2.set_title("2D DFT of the blade forces over one revolution", fontsize="small")
    return [("engine_orders.png", "Interference diagram: first-family frequencies by ND at "
             "the measured critical speeds, the pulse frequencies p o n / 60, the NDs the "
             "rotor-synchronous pulses excite (all even NDs), the stationary-pattern alias "
             "and the resonating ND; right: the pattern's content by revolution harmonic and "
             "ND", fig)]


def _forced_figures(entries: list) -> list:
    from fricdamp import plot

    fig, axes = plot.new_figure(1, len(entries), width=5.5 * len(entries), height=4.2,
                                title="Forced response around the critical speeds (cyclic "
                                      "harmonic balance, one sector)")
    for ax, e in zip(axes[0], entries, strict=True):
        ax.plot(e["rpm"], 1e3 * np.asarray(e["amplitude_m"]), "k.-", ms=3)
        ax.axvline(e["peak_rpm"], color="tab:red", ls="--", lw=0.8,
                   label=f"peak {e['peak_rpm']:.1f} rpm")
        ax.set_xlabel("speed [rpm]")
        ax.set_ylabel("contact-node amplitude [mm]")
        ax.set_title(f"{e['nd']}ND, o = {e['order']} ({e['force_N']:g} N per blade)",
                     fontsize="small")
        ax.legend(fontsize="small")
    return [("forced_response.png", "Forced response of the travelling wave around each "
             "critical speed: amplitude of blade 0's contact node along the flexural "
             "direction vs speed, excitation p o times the rotation frequency", fig)]


def _damping_amplitude_figures(entries: list) -> list:
    from fricdamp import plot

    fig, axes = plot.new_figure(width=7.5, height=4.6, title="Damping ratio vs amplitude "
                                "(resonance energies, cyclic HB)")
    ax = axes[0, 0]
    for k, e in enumerate(entries):
        col = f"C{k}"
        ax.plot(1e3 * np.asarray(e["amplitude_m"]), 100 * np.asarray(e["damping_ratio"]),
                "o-", color=col, label=f"{e['nd']}ND model")
        rel = e.get("release_decay")
        if rel and rel["amplitude_m"]:
            ax.plot(1e3 * np.asarray(rel["amplitude_m"]), 100 * np.asarray(rel["damping_ratio"]),
                    "-", color=col, lw=3, alpha=0.4,
                    label=f"{e['nd']}ND release at {rel['rpm']:.0f} rpm, free decay (Hilbert)")
        if "paper_fem_damping_ratio" in e:
            ax.plot([0.0, 1e3 * e["paper_fem_max_amplitude_m"]],
                    [100 * e["paper_fem_damping_ratio"]] * 2, "--", color=col, lw=1.5,
                    label=f"{e['nd']}ND 003 FEM log decrement (up to 0.5 mm)")
            for a in e["paper_test_amplitudes_m"]:
                ax.axvline(1e3 * a, color=col, ls=":", lw=0.8)
    ax.set_xlabel("contact-node amplitude [mm] (dotted: 003 Table 2 test amplitudes)")
    ax.set_ylabel("damping ratio [%]")
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ax.legend(fontsize="small")
    return [("damping_vs_amplitude.png", "Damping ratio of the resonant state vs amplitude "
             "for each ND, with 003's FEM damping ratios and the amplitudes of its rotary "
             "tests (Table 2)", fig)]
