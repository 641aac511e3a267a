"""Hysteresis loops and energy: loop area, steady cycles, dissipated and strain energy.

Sign convention (as in :mod:`fricdamp.contact.base`): ``u`` is the displacement (or
rotation) imposed on an element and ``f`` the force (or moment) with which the element
*resists* it, so that ``f = k u + c u'`` for a spring and dashpot. With this convention the
work ``∮ f du`` done on the element over a cycle is the energy it dissipates, positive for
a passive element.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from fricdamp.errors import ModelError, as_finite_array

__all__ = [
    "dissipated_energy_per_cycle",
    "hysteresis_loop",
    "loop_area",
    "peak_strain_energy",
    "steady_cycle",
]


def loop_area(u, f) -> float:
    """Work ``∮ f du`` [J] done on an element around a closed loop (energy dissipated).

    Trapezoidal rule on the samples, closing the loop from the last sample back to the
    first (so pass one period *without* repeating the first sample at the end; a repeated
    sample adds a zero-length segment and is harmless). The elastic part of a loop cancels
    exactly; for a harmonic loop sampled at N equally spaced phases the dissipated part comes
    out multiplied by ``sin(h) / h``, h = 2 pi / N (relative error h^2 / 6, 5e-7 at N = 3600).

    The result is positive when ``f`` lags ``u`` (the loop is run clockwise in the (u, f)
    plane with u to the right and f up), i.e. for a dissipative element.

    Parameters
    ----------
    u : array_like, shape (n,)
        Displacement [m] (or rotation [rad]) over one cycle (or several: the result is then
        their sum).
    f : array_like, shape (n,)
        Force [N] (or moment [N m]) with which the element resists u.

    Returns
    -------
    float
        ``∮ f du`` [J]; ``pi c w A^2`` for a dashpot c at ``u = A cos(w t)``.

    Raises
    ------
    ModelError
        If u and f are not 1-D arrays of equal length >= 3, or hold NaN or inf.
    """
    u = as_finite_array("u", u).ravel()
    f = as_finite_array("f", f).ravel()
    if u.shape != f.shape or u.size < 3:
        raise ModelError(f"u and f must be 1-D arrays of equal length >= 3, got {u.shape}, "
                         f"{f.shape}")
    du = np.diff(np.append(u, u[0]))
    fm = 0.5 * (f + np.append(f[1:], f[0]))
    return float(np.sum(fm * du))


def _check_time(t) -> np.ndarray:
    t = as_finite_array("t", t, ndim=1)
    if t.size < 3:
        raise ModelError(f"t needs at least 3 samples, got {t.size}")
    dt = np.diff(t)
    if np.any(dt <= 0):
        i = int(np.flatnonzero(dt <= 0)[0])
        raise ModelError(f"t must be strictly increasing; t[{i}] = {t[i]!r} >= "
                         f"t[{i + 1}] = {t[i + 1]!r}")
    return t


def steady_cycle(t, x, period: float, *, n_cycles: int = 1,
                 samples_per_cycle: int | None = None,
                 interpolation: Literal["linear", "cubic"] = "linear"
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The last ``n_cycles`` full periods of a sampled signal (the steady state, if any).

    When ``t`` is uniform and the period is an integer number of samples (to 1e-6 of a
    sample), the last ``n_cycles * period / dt`` samples are returned unchanged. Otherwise the
    window ``[t_end - n_cycles * period, t_end)`` is resampled on ``samples_per_cycle`` equally
    spaced points per period: linear interpolation by default (it never overshoots at the
    corners of friction forces; error O(h^2)), or a cubic spline for smooth (measured,
    band-limited) signals (error O(h^4)).

    The returned window is half-open: the sample at ``t_end`` (equal to the first one for a
    periodic signal) is not repeated, which is what :func:`loop_area` expects.

    Parameters
    ----------
    t : array_like, shape (n_t,)
        Sample times [s], strictly increasing.
    x : array_like, shape (n_t, ...)
        Signal(s) sampled at t (time on the first axis).
    period : float
        Period T [s], > 0.
    n_cycles : int, optional
        Number of periods to return, >= 1; default 1.
    samples_per_cycle : int, optional
        Points per period when resampling (>= 8); default ``ceil(T / median(dt))``.
    interpolation : {"linear", "cubic"}, optional
        Resampling interpolant; default "linear".

    Returns
    -------
    t_cycle : ndarray, shape (m,)
        Times of the window [s], m = n_cycles * samples per cycle.
    x_cycle : ndarray, shape (m, ...)
        The signal over the window.

    Raises
    ------
    ModelError
        If the record is shorter than ``n_cycles`` periods, or on bad input.
    """
    t = _check_time(t)
    x = as_finite_array("x", x)
    if x.ndim == 0 or x.shape[0] != t.size:
        raise ModelError(f"x must have len(t) = {t.size} samples on its first axis, got shape "
                         f"{x.shape}")
    period = float(as_finite_array("period", period))
    if period <= 0:
        raise ModelError(f"period must be > 0 s, got {period!r}")
    if int(n_cycles) != n_cycles or n_cycles < 1:
        raise ModelError(f"n_cycles must be an integer >= 1, got {n_cycles!r}")
    n_cycles = int(n_cycles)
    if interpolation not in ("linear", "cubic"):
        raise ModelError(f"interpolation must be 'linear' or 'cubic', got {interpolation!r}")
    span = n_cycles * period
    if t[-1] - t[0] < span * (1.0 - 1e-12):
        raise ModelError(f"the record lasts {t[-1] - t[0]:.6g} s, shorter than n_cycles = "
                         f"{n_cycles} period(s) of {period:.6g} s")
    dt = np.diff(t)
    dt_med = float(np.median(dt))
    uniform = np.max(np.abs(dt - dt_med)) <= 1e-9 * dt_med
    per_samples = period / dt_med
    if (uniform and samples_per_cycle is None
            and abs(per_samples - round(per_samples)) <= 1e-6 and round(per_samples) >= 3):
        m = n_cycles * int(round(per_samples))
        return t[-m:].copy(), x[-m:].copy()
    if samples_per_cycle is None:
        samples_per_cycle = int(np.ceil(per_samples - 1e-9))
    if int(samples_per_cycle) != samples_per_cycle or samples_per_cycle < 8:
        raise ModelError(f"samples_per_cycle must be an integer >= 8, got {samples_per_cycle!r}"
                         f" (the signal has about {per_samples:.3g} samples per period)")
    m = n_cycles * int(samples_per_cycle)
    tg = t[-1] - span + (span / m) * np.arange(m)
    tg[0] = max(tg[0], t[0])  # guard against round-off below t[0]
    if interpolation == "cubic":
        from scipy.interpolate import CubicSpline

        xg = CubicSpline(t, x, axis=0)(tg)
    else:
        from scipy.interpolate import interp1d

        xg = interp1d(t, x, axis=0, assume_sorted=True)(tg)
    return tg, np.asarray(xg, dtype=float)


def hysteresis_loop(t, u, f, period: float, *, n_cycles: int = 1, **kwargs
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Displacement and force over the last ``n_cycles`` periods: the steady hysteresis loop.

    Parameters
    ----------
    t : array_like, shape (n_t,)
        Times [s], strictly increasing.
    u : array_like, shape (n_t,) or (n_t, n_c)
        Displacement [m] (or rotation [rad]) imposed on the element(s).
    f : array_like, same shape as u
        Force [N] (or moment [N m]) resisting u.
    period : float
        Period of the steady state [s].
    n_cycles : int, optional
        Periods to return; default 1.
    **kwargs
        ``samples_per_cycle``, ``interpolation``: see :func:`steady_cycle`.

    Returns
    -------
    u_loop, f_loop : ndarray, shape (m,) or (m, n_c)
        The loop, one period per ``m / n_cycles`` samples, not closed (first sample not
        repeated).
    """
    u = as_finite_array("u", u)
    f = as_finite_array("f", f)
    if u.shape != f.shape:
        raise ModelError(f"u and f must have the same shape, got {u.shape} and {f.shape}")
    _, uf = steady_cycle(t, np.stack((u, f), axis=-1), period, n_cycles=n_cycles, **kwargs)
    return uf[..., 0], uf[..., 1]


def dissipated_energy_per_cycle(t, u, f, period: float, *, n_cycles: int = 1, **kwargs):
    """Energy dissipated per cycle [J]: area of the steady loop, averaged over ``n_cycles``.

    Parameters
    ----------
    t, u, f, period, n_cycles, **kwargs
        As in :func:`hysteresis_loop`; u and f of shape (n_t,) or (n_t, n_c).

    Returns
    -------
    float or ndarray, shape (n_c,)
        ``∮ f du`` over the last ``n_cycles`` periods divided by ``n_cycles`` [J].
    """
    ul, fl = hysteresis_loop(t, u, f, period, n_cycles=n_cycles, **kwargs)
    if ul.ndim == 1:
        return loop_area(ul, fl) / n_cycles
    return np.array([loop_area(ul[:, j], fl[:, j]) for j in range(ul.shape[1])]) / n_cycles


def _extreme(u: np.ndarray, f: np.ndarray, sign: int) -> tuple[float, float]:
    """Sub-sample extreme of ``sign * u`` (parabola in the sample index), f interpolated."""
    n = u.size
    i = int(np.argmax(sign * u))
    im, ip = (i - 1) % n, (i + 1) % n  # the loop is periodic
    y0, y1, y2 = sign * u[im], sign * u[i], sign * u[ip]
    den = y0 - 2.0 * y1 + y2
    s = 0.5 * (y0 - y2) / den if den < 0 else 0.0
    s = min(max(s, -0.5), 0.5)
    u_ext = sign * (y1 - 0.25 * (y0 - y2) * s)
    # f at the tip by the quadratic through the same three samples
    f_ext = f[i] + 0.5 * s * (f[ip] - f[im]) + 0.5 * s * s * (f[ip] - 2.0 * f[i] + f[im])
    return u_ext, f_ext


def peak_strain_energy(u, f, *, method: Literal["secant", "peak"] = "secant") -> float:
    """Peak strain energy E_s [J] of one cycle of a loop, for the energy damping ratios.

    - ``"secant"`` (default): ``E_s = k_sec A^2 / 2`` with the amplitude ``A = (u_max -
      u_min) / 2`` and the secant stiffness ``k_sec = (f(u_max) - f(u_min)) / (u_max -
      u_min)`` through the loop tips. At the tips the velocity vanishes, so for the viscous
      ellipse ``f = k u + c u'`` this is exactly ``k A^2 / 2`` -- the E_s of
      :func:`fricdamp.signals.damping.energy_damping_ratio` and ``loss_factor``.
    - ``"peak"``: ``E_s = u_max f_max / 2`` with the largest |u| and |f| of the cycle (which
      need not occur together); paper 002's "supplied energy" 002 (27) is 8 times this.

    The extremes are located to sub-sample accuracy by a parabola through the largest
    sample and its neighbours (the loop is treated as periodic), and f is interpolated there
    by the quadratic through the same three samples.

    Parameters
    ----------
    u : array_like, shape (n,)
        Displacement [m] (or rotation [rad]) over one cycle, n >= 3.
    f : array_like, shape (n,)
        Force [N] (or moment [N m]) resisting u.
    method : {"secant", "peak"}, optional
        Definition; default "secant".

    Returns
    -------
    float
        E_s [J], > 0 for a loop with a positive secant stiffness.

    Raises
    ------
    ModelError
        On bad input, or when the secant stiffness is not positive (no elastic restoring
        force: the strain energy is undefined, use another normalisation).
    """
    u = as_finite_array("u", u, ndim=1)
    f = as_finite_array("f", f, ndim=1)
    if u.shape != f.shape or u.size < 3:
        raise ModelError(f"u and f must be 1-D arrays of equal length >= 3, got {u.shape}, "
                         f"{f.shape}")
    if method == "peak":
        ua, _ = _extreme(np.abs(u), f, 1)
        fa, _ = _extreme(np.abs(f), u, 1)
        return 0.5 * ua * fa
    if method != "secant":
        raise ModelError(f"method must be 'secant' or 'peak', got {method!r}")
    u_hi, f_hi = _extreme(u, f, 1)
    u_lo, f_lo = _extreme(u, f, -1)
    if u_hi <= u_lo:
        raise ModelError("u does not vary over the cycle: no strain energy")
    k_sec = (f_hi - f_lo) / (u_hi - u_lo)
    if k_sec <= 0:
        raise ModelError(f"the secant stiffness of the loop is {k_sec:.4g} <= 0: the peak "
                         "strain energy is undefined (pure friction loop?); normalise by "
                         "another energy")
    amp = 0.5 * (u_hi - u_lo)
    return 0.5 * k_sec * amp * amp
