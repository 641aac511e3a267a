"""Figures of the blade_pair case (paper 001): Campbell diagram, mode shapes, steady states
with HB beside the equivalent linearisation. Imported only when figures are drawn (plotting
is never imported with fricdamp)."""

from __future__ import annotations

import numpy as np


def _f_label(f) -> str:
    from fricdamp.models.blade_pair.case import _f_label as label

    return label(f)


def _campbell_axes(ax, camp: dict, fmax: float) -> None:
    """Branches (dots), excitation lines k rpm / 60 and their crossings up to ``fmax``."""
    rpm = np.asarray(camp["rpm"])
    F = np.array(camp["frequency_hz"], dtype=float)
    for i, row in enumerate(F):
        ax.plot(rpm, row, ".", ms=2.5, color="tab:blue",
                label=r"Im($\lambda$)/2$\pi$" if i == 0 else None)
    for k in camp["excitation_orders"]:
        line = k * rpm / 60.0
        ax.plot(rpm, line, "k--", lw=0.8)
        j = min(max(int(np.searchsorted(line, fmax)) - 1, 0), rpm.size - 1)
        ax.annotate(rf"{k}$\Omega$", (rpm[j], line[j]), fontsize=8,
                    textcoords="offset points", xytext=(-16, 4))
        for rs in camp["crossing_speeds"][f"k{k}"].values():
            ax.plot(rs, k * np.asarray(rs) / 60.0, "o", mfc="none", color="tab:red", ms=5)
    ax.set_ylim(0, fmax)
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_xlabel("spin speed [rpm]")
    ax.set_ylabel(r"Im($\lambda$)/2$\pi$ [Hz]")


def campbell_figures(camp: dict, modes: dict | None, spec) -> list:
    from fricdamp import plot

    rpm = np.asarray(camp["rpm"])
    F = np.array(camp["frequency_hz"], dtype=float)
    Z = np.array(camp["damping_ratio"], dtype=float)
    what = (f"with the friction damping of the k = {camp['k']} steady state, f = "
            f"{camp['friction_coefficient']:g}" if camp["friction"] else "without friction")
    fig, axes = plot.new_figure(1, 2, width=12.0, height=4.6,
                                title=f"Campbell diagram (001 Figs 3-4), {what}")
    fmax = float(np.nanmax(F)) * 1.05 if np.isfinite(F).any() else 1.0
    _campbell_axes(axes[0, 0], camp, fmax)
    axes[0, 0].set_title(f"{F.shape[0]} lowest complex pairs", fontsize="small")
    zoom = 1.3 * max(camp["excitation_orders"]) * rpm[-1] / 60.0
    _campbell_axes(axes[0, 1], camp, min(zoom, fmax))
    axes[0, 1].set_title("excitation range; circles: k Omega meets a branch (resonance)",
                         fontsize="small")
    figs = [("campbell.png", f"Campbell diagram {what}: imaginary parts of the eigenvalues "
             "vs spin speed with the excitation lines k Omega (001 Figs 3-4); right: the "
             "range of the excitation lines", fig)]
    fig, axes = plot.new_figure(width=7.5, height=4.2, title="Damping ratios of the lowest "
                                                             "Campbell branches")
    az = axes[0, 0]
    for i in range(min(6, Z.shape[0])):
        az.semilogy(rpm, np.where(Z[i] > 0, Z[i], np.nan), ".-", ms=3, lw=0.8,
                    label=f"branch {i + 1}")
    az.set_xlabel("spin speed [rpm]")
    az.set_ylabel(r"damping ratio $-\mathrm{Re}\,\lambda/|\lambda|$ [-]")
    az.set_title(f"{what}; branches sorted by frequency at each speed", fontsize="small")
    az.legend(fontsize="small", ncols=2)
    figs.append(("campbell_damping.png", f"Damping ratios -Re(lambda)/|lambda| of the six "
                 f"lowest Campbell branches {what}", fig))
    if modes is not None:
        r = np.asarray(modes["blade_nodes_m"])
        n = len(modes["frequency_hz"])
        fig, axes = plot.new_figure(1, n, width=3.6 * n + 0.6, height=4.0,
                                    title=f"Complex mode shapes at {modes['rpm']:g} rpm "
                                          "(001 Fig. 5): tangential deflection w")
        for j, ax in enumerate(axes[0]):
            for b, style in (("blade1", "-"), ("blade2", "--")):
                w = np.array(modes[b][j])[:, 1]                       # (node, [re, im])
                ax.plot(w[:, 0], r, "tab:blue", ls=style, marker="o", ms=3,
                        label=f"{b} Re")
                ax.plot(w[:, 1], r, "tab:red", ls=style, marker="s", ms=3,
                        label=f"{b} Im")
            ax.set_title(f"{modes['frequency_hz'][j]:.1f} Hz, zeta = "
                         f"{modes['damping_ratio'][j]:.3g}", fontsize="small")
            ax.set_xlabel("w (largest translation = 1) [-]")
            ax.locator_params(axis="x", nbins=4)
        axes[0, 0].set_ylabel("radius [m]")
        axes[0, 0].legend(fontsize="x-small")
        figs.append(("mode_shapes.png", f"Complex mode shapes at {modes['rpm']:g} rpm: real "
                     "and imaginary parts of the tangential deflection of both blades "
                     "(001 Fig. 5)", fig))
    return figs


def _floats(values) -> np.ndarray:
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def _positive(values) -> np.ndarray:
    """Values for a log axis: zero (a stuck contact, no slip) and NaN are not drawn."""
    a = np.asarray(values, dtype=float)
    return np.where(a > 0, a, np.nan)


def sweep_figures(entries: list, orb: dict, o_rpm: list, spec) -> list:
    from fricdamp import plot

    orders = list(spec.orders)

    # Figs 6-7: semi-axes vs rpm, one row per order, contacts A and B side by side
    fig, axes = plot.new_figure(len(orders), 2, width=11.5, height=3.4, sharex=True,
                                title="Semi-axes of the slip ellipses vs spin speed "
                                      "(001 Figs 6-7): solid major, dotted minor")
    for row, k in enumerate(orders):
        for col, c in enumerate("AB"):
            ax = axes[row, col]
            for e in (e for e in entries if e["k"] == k):
                ab = np.array(e[f"semi_axes_{c}_m"])
                line, = ax.semilogy(e["rpm"], _positive(ab[:, 0]), lw=1,
                                    label=f"f = {_f_label(e['friction_coefficient'])}")
                ax.semilogy(e["rpm"], _positive(ab[:, 1]), ":", lw=1,
                            color=line.get_color())
            ax.set_title(f"contact {c}, k = {k}", fontsize="small")
            ax.set_ylabel("semi-axis [m]")
        axes[row, 0].legend(fontsize="x-small", ncols=2)
    for ax in axes[-1]:
        ax.set_xlabel("spin speed [rpm]")
    figs = [("semi_axes.png", "Major (solid) and minor (dotted) semi-axes of the elliptical "
             "slip orbits of A and B vs spin speed, per order and friction coefficient "
             "(001 Figs 6-7; a stuck contact has no slip and is not drawn)", fig)]

    # Fig. 8: inclinations
    fig, axes = plot.new_figure(1, len(orders), width=4.0 * len(orders) + 0.5, height=3.8,
                                title="Inclination of the major axes (001 Fig. 8)")
    for ax, k in zip(axes[0], orders, strict=True):
        for e in (e for e in entries if e["k"] == k):
            line, = ax.plot(e["rpm"], e["inclination_A_rad"], lw=1,
                            label=f"A, f = {_f_label(e['friction_coefficient'])}")
            ax.plot(e["rpm"], e["inclination_B_rad"], "--", lw=1, color=line.get_color())
        ax.set_title(f"k = {k} (solid A, dashed B)", fontsize="small")
        ax.set_xlabel("spin speed [rpm]")
        ax.set_ylim(0, np.pi)
    axes[0, 0].set_ylabel(r"inclination from $\xi$ [rad]")
    axes[0, 0].legend(fontsize="x-small")
    figs.append(("inclination.png", "Inclination of the major axis of the slip ellipses to "
                 "the xi axis of each contact plane (001 Fig. 8)", fig))

    # Figs 9-11: dissipated energy vs rpm
    fig, axes = plot.new_figure(1, len(orders), width=4.0 * len(orders) + 0.5, height=3.8,
                                title="Energy dissipated by friction per period T_k "
                                      "(001 Figs 9-11)")
    hb_on = any(e.get("hb") for e in entries)
    for ax, k in zip(axes[0], orders, strict=True):
        for e in (e for e in entries if e["k"] == k):
            r = np.asarray(e["rpm"])
            W = np.asarray(e["dissipated_energy_J"], float)
            line, = ax.semilogy(r, _positive(W), lw=1,
                                label=f"f = {_f_label(e['friction_coefficient'])}")
            if e.get("hb"):
                ax.semilogy(r, _positive(_floats(e["hb"]["dissipated_energy_J"])), "--",
                            lw=1, color=line.get_color())
                bad = np.asarray(e["disagreement"], bool)
                ax.plot(r[bad], np.where(W[bad] > 0, W[bad], np.nan), "x", ms=3,
                        color=line.get_color())
        ax.set_title(f"k = {k}" + (" (solid eqlin, dashed HB, x: > "
                                   f"{spec.disagreement_threshold:.0%} apart)" if hb_on
                                   else ""), fontsize="small")
        ax.set_xlabel("spin speed [rpm]")
    axes[0, 0].set_ylabel("friction energy per period [J]")
    axes[0, 0].legend(fontsize="x-small")
    figs.append(("dissipated_energy.png", "Energy dissipated by friction at A and B per "
                 "excitation period vs spin speed, one curve per friction coefficient "
                 "(001 Figs 9-11): equivalent linearisation (solid) and multi-harmonic "
                 "stick-slip HB (dashed); x marks speeds where they differ by more than the "
                 "threshold; zero (stuck) is not drawn", fig))

    # tip amplitude, eqlin and HB
    fig, axes = plot.new_figure(1, len(orders), width=4.0 * len(orders) + 0.5, height=3.8,
                                title="Tangential tip (shroud) amplitude, larger of the two "
                                      "blades")
    for ax, k in zip(axes[0], orders, strict=True):
        for e in (e for e in entries if e["k"] == k):
            line, = ax.semilogy(e["rpm"], _positive(e["tip_amplitude_m"]), lw=1,
                                label=f"f = {_f_label(e['friction_coefficient'])}")
            if e.get("hb"):
                ax.semilogy(e["rpm"], _positive(_floats(e["hb"]["tip_amplitude_m"])), "--",
                            lw=1, color=line.get_color())
        ax.set_title(f"k = {k}" + (" (solid eqlin, dashed HB)" if hb_on else ""),
                     fontsize="small")
        ax.set_xlabel("spin speed [rpm]")
    axes[0, 0].set_ylabel("tip amplitude [m]")
    axes[0, 0].legend(fontsize="x-small")
    figs.append(("tip_amplitude.png", "Tangential amplitude of the tip (shroud) node, the "
                 "larger of the two blades, vs spin speed: equivalent linearisation (solid, "
                 "harmonic amplitude) and multi-harmonic HB (dashed, largest excursion from "
                 "the mean over the period)", fig))

    # Figs 12-14: orbits
    for k in orders if orb else []:
        n = len(o_rpm)
        fig, axes = plot.new_figure(2, n, width=3.6 * n + 0.6, height=3.3,
                                    title=f"Slip orbits for k = {k} (001 Figs 12-14)")
        for col, r in enumerate(o_rpm):
            for row, c in enumerate("AB"):
                ax = axes[row, col]
                big = [o[c][col]["semi_axes_m"][0] for o in orb[k]]
                fac, unit = plot.si_scale(big, "m")
                for o in orb[k]:
                    e = o[c][col]
                    ax.plot(np.array(e["xi_m"]) / fac, np.array(e["eta_m"]) / fac, lw=1,
                            label=f"f = {_f_label(o['friction_coefficient'])}")
                ax.set_title(f"{c}, {r:.0f} rpm", fontsize="small")
                ax.set_xlabel(rf"$\xi$ [{unit}]")
                ax.set_ylabel(rf"$\eta$ [{unit}]")
                ax.set_aspect("equal", adjustable="datalim")
                ax.locator_params(nbins=5)
        axes[0, 0].legend(fontsize="x-small")
        figs.append((f"orbits_k{k}.png", f"Elliptical slip orbits of the contact points A "
                     f"and B in their contact planes for k = {k} at "
                     f"{', '.join(f'{r:.0f}' for r in o_rpm)} rpm, one curve per friction "
                     "coefficient (001 Figs 12-14; a stuck contact's orbit is a dot)", fig))
    return figs
