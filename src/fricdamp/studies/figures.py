"""Figures of a sweep Dataset: a line over one parameter, heat maps over two or more.

matplotlib is imported only when a figure is drawn.
"""

from __future__ import annotations

import logging
import math

import numpy as np

log = logging.getLogger(__name__)

__all__ = ["plot_sweep", "plot_variable", "plotted_variables"]


def plotted_variables(ds, *, max_figures: int = 40) -> list[str]:
    """Results worth a figure: every variable but ``failed`` that varies over the grid."""
    names = []
    for name in ds.data_vars:
        if name == "failed":
            continue
        vals = np.asarray(ds[name].values, float)
        finite = vals[np.isfinite(vals)]
        if finite.size and (np.ptp(finite) > 0 or finite.size < vals.size):
            names.append(str(name))
    return names[:max_figures]


def plot_variable(ds, name: str):
    """Figure of one result: a line over 1 parameter, heat maps over 2 or more.

    With more than two parameters, one heat map over the first two is drawn for each
    combination of the others (at most 9 panels). Failed points are marked in red, the
    minimum with a star.

    Returns
    -------
    matplotlib.figure.Figure or None
        None when more than 9 panels would be needed.
    """
    import matplotlib.pyplot as plt

    dims = [str(d) for d in ds[name].dims]
    var = ds[name]
    failed = np.asarray(ds["failed"].transpose(*dims).values, bool)
    if len(dims) == 1:
        fig, ax = plt.subplots(figsize=(6, 4))
        x = ds[dims[0]].values
        ax.plot(x, var.values, "o-")
        for xf in x[failed]:  # failed points: red vertical lines
            ax.axvline(xf, color="r", alpha=0.3, lw=1)
        ax.set_xlabel(dims[0])
        ax.set_ylabel(name)
        ax.ticklabel_format(style="sci", scilimits=(-3, 4))
        ax.grid(True, alpha=0.3)
    else:
        rest = dims[2:]
        combos = list(np.ndindex(*[ds.sizes[d] for d in rest])) if rest else [()]
        if len(combos) > 9:
            log.info("no figure of %s: %d panels would be needed", name, len(combos))
            return None
        ncol = min(3, len(combos))
        nrow = math.ceil(len(combos) / ncol)
        fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 4.2 * nrow), squeeze=False)
        vals_all = np.asarray(var.values, float)
        finite = vals_all[np.isfinite(vals_all)]
        vmin, vmax = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
        x, y = ds[dims[1]].values, ds[dims[0]].values
        for ax, combo in zip(axes.flat, combos, strict=False):
            sel = (slice(None), slice(None), *combo)
            z = vals_all[sel]
            mesh = ax.pcolormesh(x, y, z, shading="nearest", vmin=vmin, vmax=vmax,
                                 cmap="viridis")
            fz = failed[sel]
            if fz.any():
                yy, xx = np.nonzero(fz)
                ax.plot(x[xx], y[yy], "rx", ms=8, label="failed")
            if np.isfinite(z).any():
                iy, ix = np.unravel_index(np.nanargmin(z), z.shape)
                ax.plot(x[ix], y[iy], "w*", ms=12, mec="k", label="minimum")
            ax.set_xlabel(dims[1])
            ax.set_ylabel(dims[0])
            ax.ticklabel_format(style="sci", scilimits=(-3, 4))
            ax.legend(loc="best", fontsize=8, framealpha=0.6)
            if rest:
                ax.set_title(", ".join(f"{d}={ds[d].values[i]:g}"
                                       for d, i in zip(rest, combo, strict=True)), fontsize=9)
            fig.colorbar(mesh, ax=ax, label=name)
        for ax in list(axes.flat)[len(combos):]:
            ax.set_visible(False)
    fig.suptitle(f"{name}\nover {' x '.join(dims)}", fontsize=10)
    fig.tight_layout()
    return fig


def plot_sweep(ds, *, max_figures: int = 40) -> list:
    """Figures of a sweep: one per result that varies (:func:`plotted_variables`).

    Returns
    -------
    list of (filename, title, matplotlib.figure.Figure)
    """
    figs = []
    for name in plotted_variables(ds, max_figures=max_figures):
        fig = plot_variable(ds, name)
        if fig is not None:
            figs.append((f"sweep_{name}.png", f"{name} over {' x '.join(ds[name].dims)}", fig))
    return figs

