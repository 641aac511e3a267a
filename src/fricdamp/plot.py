"""Matplotlib figures of the command line and the report.

Import this module only when drawing: it imports matplotlib (``import fricdamp`` does not).
Figures are built with :class:`matplotlib.figure.Figure` directly, not with pyplot, so no GUI
backend and no global figure state are involved; save them with
:func:`fricdamp.iofiles.save_figure`.

Axes are labelled with the quantity and its unit; SI values are rescaled to a readable prefix
(``displacement [µm]`` rather than ``1e-5`` offsets).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

__all__ = [
    "cycle_energy",
    "damping_vs_amplitude",
    "dof_label",
    "format_si",
    "energy_partition",
    "hysteresis_loops",
    "loop_energy_vs_amplitude",
    "new_figure",
    "si_scale",
    "stability_line",
    "time_histories",
]

#: What the beam builders' DOF names mean (``"w8"``: z-displacement of node 8).
_DOF_KINDS = {"u": "x-displacement", "v": "y-displacement", "w": "z-displacement",
              "phi": "rotation about x", "theta": "rotation about y", "psi": "rotation about z"}


def dof_label(name: str) -> str:
    """A DOF name for axis labels: a beam DOF ``"w8"`` becomes ``"w8 (z-displacement of
    node 8)"``; other names are returned unchanged."""
    m = re.fullmatch(r"(u|v|w|phi|theta|psi)(\d+)", str(name))
    return f"{name} ({_DOF_KINDS[m[1]]} of node {m[2]})" if m else str(name)


_PREFIXES = ((1e-9, "n"), (1e-6, "µ"), (1e-3, "m"), (1.0, ""), (1e3, "k"), (1e6, "M"))


def si_scale(values, unit: str) -> tuple[float, str]:
    """Factor and unit label that bring ``max |values|`` into [1, 1000).

    Examples
    --------
    >>> si_scale([2e-5, -3e-5], "m")
    (1e-06, 'µm')
    >>> si_scale([0.0], "N")
    (1.0, 'N')
    """
    arr = np.asarray(values, dtype=float)
    arr = arr[np.isfinite(arr)]
    peak = float(np.max(np.abs(arr))) if arr.size else 0.0
    if peak == 0.0:
        return 1.0, unit
    factor, prefix = _PREFIXES[0]
    for f, p in _PREFIXES:
        if peak >= f * 0.9999:
            factor, prefix = f, p
    return factor, prefix + unit


def format_si(value: float, unit: str, digits: int = 3) -> str:
    """``format_si(2e-5, "m")`` -> ``"20 µm"``."""
    fac, lab = si_scale([value], unit)
    return f"{value / fac:.{digits}g} {lab}"


def new_figure(nrows: int = 1, ncols: int = 1, *, width: float = 7.5, height: float = 3.6,
               sharex: bool = False, title: str | None = None):
    """A Figure with a grid of axes (always a 2-D array) and constrained layout."""
    fig = Figure(figsize=(width, height * nrows if nrows > 1 else height), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False, sharex=sharex)
    if title:
        fig.suptitle(title, fontsize="medium")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    return fig, axes


def time_histories(t, q, names: Sequence[str], *, title: str = "",
                   quantity: str = "displacement", unit: str = "m",
                   max_lines: int = 8) -> Figure:
    """Time history of each DOF: ``q`` (n_t, n_dof) [unit] against ``t`` (n_t,) [s]."""
    q = np.asarray(q, dtype=float)
    fac, lab = si_scale(q, unit)
    fig, axes = new_figure(title=title)
    ax = axes[0, 0]
    for i in range(min(q.shape[1], max_lines)):
        ax.plot(t, q[:, i] / fac, lw=0.8, label=names[i])
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"{quantity} [{lab}]")
    ax.legend(loc="upper right", fontsize="small", ncols=min(4, q.shape[1]))
    ax.set_xlim(t[0], t[-1])
    return fig


def damping_vs_amplitude(amplitude, damping_ratio, frequency_hz, *, title: str = "",
                         unit: str = "m", log_amplitude: bool | None = None) -> Figure:
    """Damping ratio [%] and frequency [Hz] against amplitude, one point per decay cycle
    (or per amplitude of a nonlinear mode).

    ``log_amplitude``: a logarithmic amplitude axis; by default when the (positive)
    amplitudes span more than a decade, so that micro-slip at small amplitude shows.
    """
    amplitude = np.asarray(amplitude, float)
    fac, lab = si_scale(amplitude, unit)
    fig, axes = new_figure(1, 2, width=9.0, height=3.6, title=title)
    ax1, ax2 = axes[0]
    if log_amplitude is None:
        pos = amplitude[np.isfinite(amplitude)]
        log_amplitude = bool(pos.size > 1 and np.all(pos > 0) and pos.max() > 10 * pos.min())
    if log_amplitude:
        ax1.set_xscale("log")
        ax2.set_xscale("log")
    ax1.plot(amplitude / fac, 100 * np.asarray(damping_ratio), "o-", ms=3, lw=1)
    ax1.set_xlabel(f"amplitude [{lab}]")
    ax1.set_ylabel("damping ratio [%]")
    ax2.plot(amplitude / fac, frequency_hz, "o-", ms=3, lw=1, color="C1")
    ax2.set_xlabel(f"amplitude [{lab}]")
    ax2.set_ylabel("frequency [Hz]")
    ax2.ticklabel_format(axis="y", useOffset=False)
    return fig


def energy_partition(t, energy: Mapping[str, np.ndarray], *, title: str = "") -> Figure:
    """Mechanical energy, dissipated energies and the balance against time.

    ``energy`` holds the time integrator's terms (``kinetic``, ``strain``,
    ``contact_stored``, ``viscous_dissipation``, ``contact_dissipation``, ``input_work``),
    each (n_t,) [J]. The lower panel shows the balance residual
    ``input work - (change of mechanical energy + dissipation)``.
    """
    e = {k: np.asarray(v, float) for k, v in energy.items()}
    mech = e["kinetic"] + e["strain"] + e["contact_stored"]
    visc = e["viscous_dissipation"] - e["viscous_dissipation"][0]
    cont = e["contact_dissipation"] - e["contact_dissipation"][0]
    w_in = e["input_work"] - e["input_work"][0]
    resid = w_in - (mech - mech[0]) - visc - cont
    fac, lab = si_scale(np.concatenate([mech, visc, cont, w_in]), "J")
    fig, axes = new_figure(2, 1, height=2.6, sharex=True, title=title)
    ax, axr = axes[:, 0]
    ax.plot(t, mech / fac, lw=0.8, label="kinetic + strain + contact stored")
    ax.plot(t, cont / fac, lw=1.2, label="dissipated by contacts")
    ax.plot(t, visc / fac, lw=1.2, label="dissipated by dashpots")
    if np.any(w_in):
        ax.plot(t, w_in / fac, lw=1.2, label="work of the external force")
    ax.plot(t, (mech + visc + cont - w_in) / fac, "k--", lw=1, label="total (constant)")
    ax.set_ylabel(f"energy [{lab}]")
    ax.legend(loc="best", fontsize="small")
    rfac, rlab = si_scale(resid, "J")
    axr.plot(t, resid / rfac, lw=0.8, color="C3")
    axr.set_ylabel(f"balance residual [{rlab}]")
    axr.set_xlabel("time [s]")
    axr.set_xlim(t[0], t[-1])
    return fig


def hysteresis_loops(loops: Sequence[tuple[str, np.ndarray, np.ndarray]], *, title: str = "",
                     group: Sequence[str] | None = None, u_unit: str = "m",
                     f_unit: str = "N", max_panels: int = 6) -> Figure:
    """Force against relative displacement, one curve per ``(label, u, f)``.

    Curves with the same ``group`` entry share a panel (default: one panel per curve, at
    most ``max_panels`` panels).
    """
    group = list(group) if group is not None else [lab for lab, _, _ in loops]
    panels = list(dict.fromkeys(group))[:max_panels]
    ncols = min(len(panels), 3)
    nrows = int(np.ceil(len(panels) / ncols))
    fig, axes = new_figure(nrows, ncols, width=4.0 * ncols if ncols > 1 else 6.0,
                           height=3.4, title=title)
    all_u = np.concatenate([np.ravel(u) for _, u, _ in loops])
    all_f = np.concatenate([np.ravel(f) for _, _, f in loops])
    ufac, ulab = si_scale(all_u, u_unit)
    ffac, flab = si_scale(all_f, f_unit)
    for p, name in enumerate(panels):
        ax = axes.flat[p]
        members = [(lab, u, f) for (lab, u, f), g in zip(loops, group, strict=True) if g == name]
        for lab, u, f in members:
            ax.plot(np.asarray(u) / ufac, np.asarray(f) / ffac, lw=1,
                    label=lab if len(members) > 1 else None)
        ax.set_title(name, fontsize="small")
        ax.set_xlabel(f"relative displacement [{ulab}]")
        ax.set_ylabel(f"contact force [{flab}]")
        if len(members) > 1:
            ax.legend(fontsize="x-small", loc="center left", bbox_to_anchor=(1.01, 0.5))
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    return fig


def cycle_energy(period, input_work, dissipated, *, title: str = "") -> Figure:
    """Input work and dissipated energy per excitation period against the period number."""
    fac, lab = si_scale(np.concatenate([np.ravel(input_work), np.ravel(dissipated)]), "J")
    fig, axes = new_figure(title=title)
    ax = axes[0, 0]
    ax.plot(period, np.asarray(input_work) / fac, "o-", ms=3, lw=1, label="work of the force")
    ax.plot(period, np.asarray(dissipated) / fac, "s--", ms=3, lw=1,
            label="dissipated (contacts + dashpots)")
    ax.set_xlabel("excitation period [-]")
    ax.set_ylabel(f"energy per period [{lab}]")
    ax.legend(loc="best", fontsize="small")
    return fig


def loop_energy_vs_amplitude(amplitude, energies: Mapping[str, np.ndarray],
                             closed_forms: Mapping[str, tuple | None] | None = None, *,
                             title: str = "", unit: str = "m") -> Figure:
    """Energy per cycle against amplitude (log-log): markers numerical, lines closed form.

    ``energies`` maps a contact label to its loop energies (n_amplitudes,) [J];
    ``closed_forms`` maps a label to ``(amplitudes, energies)`` of the closed form (any grid)
    or None.
    """
    amplitude = np.asarray(amplitude, float)
    closed_forms = closed_forms or {}
    fac, lab = si_scale(amplitude, unit)
    vals = np.concatenate([np.ravel(w) for w in energies.values()])
    efac, elab = si_scale(vals, "J")
    fig, axes = new_figure(title=title)
    ax = axes[0, 0]
    floor = 1e-6 * max(float(np.max(vals)), 0.0)  # loops of stuck contacts: round-off only
    for i, (name, W) in enumerate(energies.items()):
        W = np.asarray(W, float)
        pos = W > floor
        ax.plot(amplitude[pos] / fac, W[pos] / efac, "o", ms=4, color=f"C{i % 10}",
                label=f"{name}: loop area")
        curve = closed_forms.get(name)
        if curve is not None:
            a_c, w_c = (np.asarray(x, float) for x in curve)
            ok = w_c > floor
            ax.plot(a_c[ok] / fac, w_c[ok] / efac, "-", lw=1, color=f"C{i % 10}",
                    label=f"{name}: closed form")
    if np.any(vals > floor):
        ax.set_xscale("log")
        ax.set_yscale("log")
        top = float(np.max(vals)) / efac
        ax.set_ylim(top * 1e-3, top * 2)
    ax.set_xlabel(f"displacement amplitude [{lab}]")
    ax.set_ylabel(f"energy per cycle [{elab}]")
    ax.legend(loc="best", fontsize="small")
    return fig


def stability_line(ax, x, y, stable, **kwargs):
    """Plot a branch ``y(x)``: solid where stable, dashed where unstable, in one colour.

    A segment between two points is solid only if both are stable. ``kwargs`` go to
    ``ax.plot`` (``label`` to the first stable and first unstable piece only: "stable" /
    "unstable" suffixes are added when the branch has both). Returns the list of lines.
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.asarray(stable, bool)
    if x.size < 2:
        return ax.plot(x, y, **kwargs)
    seg = ok[:-1] & ok[1:]
    label = kwargs.pop("label", None)
    color = kwargs.pop("color", kwargs.pop("c", None))
    kwargs.pop("linestyle", None)
    kwargs.pop("ls", None)
    lines, start, seen = [], 0, set()
    both = bool(seg.any() and (~seg).any())
    for i in range(1, seg.size + 1):
        if i == seg.size or seg[i] != seg[start]:
            st = bool(seg[start])
            lab = None
            if label is not None and st not in seen:
                lab = f"{label} ({'stable' if st else 'unstable'})" if both else label
                seen.add(st)
            (ln,) = ax.plot(x[start:i + 1], y[start:i + 1], linestyle="-" if st else "--",
                            color=color, label=lab, **kwargs)
            color = ln.get_color()
            lines.append(ln)
            start = i
    return lines
