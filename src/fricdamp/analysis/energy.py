"""Hysteresis loops and energy: loop area (dissipated energy per cycle), energy balance."""

from __future__ import annotations

import numpy as np

from fricdamp.errors import ModelError


def loop_area(u, f) -> float:
    """Work ``∮ f du`` [J] done on a contact around a loop (dissipated energy per cycle).

    Trapezoidal rule on the samples, closing the loop from the last sample back to the first.
    Positive for a dissipative (clockwise in the u-f plane... i.e. f lagging u) loop.

    Parameters
    ----------
    u : array_like, shape (n,)
        Displacement [m] (or rotation [rad]) over one cycle.
    f : array_like, shape (n,)
        Force [N] (or moment [N m]) resisting it.
    """
    u = np.asarray(u, dtype=float).ravel()
    f = np.asarray(f, dtype=float).ravel()
    if u.shape != f.shape or u.size < 3:
        raise ModelError(f"u and f must be 1-D arrays of equal length >= 3, got {u.shape}, "
                         f"{f.shape}")
    du = np.diff(np.append(u, u[0]))
    fm = 0.5 * (f + np.append(f[1:], f[0]))
    return float(np.sum(fm * du))
