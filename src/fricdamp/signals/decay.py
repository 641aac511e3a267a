"""Damping identification from a free decay ``x(t)``: peaks, envelopes, log decrement.

Two envelope estimators feed one identification:

- **peaks** (:func:`envelope_peaks`): one extremum per half cycle (or per cycle), located by
  a local polynomial through the samples around the largest sample of each lobe (lobes are
  the runs between zero crossings of ``x - center``), so the time and value are sub-sample
  accurate for uniform and non-uniform sampling.
- **hilbert** (:func:`envelope_hilbert`): modulus and unwrapped phase of the analytic signal
  (``scipy.signal.hilbert``) on a uniform grid, with tapered and trimmed ends.

Amplitude-dependent damping ratio
---------------------------------
Between two successive envelope points ``A_i`` and ``A_{i+1}``, ``c_i`` cycles apart (1 for
consecutive positive peaks, 1/2 for alternating positive/negative peaks), the per-cycle
logarithmic decrement is ``delta_i = ln(A_i / A_{i+1}) / c_i`` and

    zeta_i = delta_i / sqrt(4 pi^2 + delta_i^2),

attributed to the mean amplitude ``(A_i + A_{i+1}) / 2`` and the mean time. For a viscous
decay this is exact (the peaks of ``exp(-zeta w_n t) cos(w_d t)`` are exactly one damped
period apart and their ratio is ``exp(delta)``, whatever the sampling phase). For a Coulomb
decay the amplitude drops by ``dA = 4 F_f / k`` per cycle; with ``x = dA c_i / (2 A)``,
``ln(A_i / A_{i+1}) = 2 artanh(x)`` and

    zeta_i = zeta_eq(A) [1 + x^2 (1/3 - 1 / (2 pi^2 c_i^2)) + O(x^4)],
    zeta_eq(A) = dA / (2 pi A) = 2 F_f / (pi k A),

so the model-free estimate reduces to the Coulomb equivalent ratio at small decrements, with
a relative bias 0.131 x^2 for alternating peaks (c_i = 1/2) and 0.283 x^2 for one peak per
cycle: below 1e-3 while the drop between the two peaks stays under 17 % (resp. 12 %) of the
amplitude (tests/unit/test_decay.py checks this law).

The Hilbert branch averages ``ln|z|`` over each full cycle of the unwrapped phase and uses
the difference of two successive averages as ``delta_i`` (same formula, ``c_i = 1``).

Which model
-----------
:func:`decay_damping` also fits an exponential envelope ``a0 exp(-sigma t)`` (viscous) and a
linear one ``a0 - s t`` (Coulomb) to the envelope, both by least squares on the amplitude
itself, and with ``kind="auto"`` picks the one with the smaller rms residual. When the
amplitude drops only a little over the record both fit almost equally well: look at the
residuals (``DecayResult.viscous.residual``, ``.coulomb.residual``).

References
----------
REFERENCES.md ("Coulomb oscillator", "Damping ratios"); paper 003 (damping ratios of the
2ND and 6ND modes from the logarithmic decrement of the free-attenuation envelopes).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from fricdamp.errors import ModelError, as_finite_array
from fricdamp.results import ResultMixin
from fricdamp.signals.damping import zeta_from_log_decrement

__all__ = [
    "CoulombFit",
    "DecayResult",
    "Envelope",
    "Peaks",
    "ViscousFit",
    "coulomb_envelope_fit",
    "decay_damping",
    "envelope_hilbert",
    "envelope_peaks",
    "find_peaks",
    "log_decrement",
    "second_mode",
    "viscous_envelope_fit",
]


# ---------------------------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------------------------

def _check_signal(t, x, *, min_size: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Validate a sampled signal: finite 1-D arrays, equal length, strictly increasing t."""
    t = as_finite_array("t", t)
    x = as_finite_array("x", x)
    if t.ndim != 1 or x.ndim != 1:
        raise ModelError(f"t and x must be 1-D arrays, got shapes {t.shape} and {x.shape}")
    if t.shape != x.shape:
        raise ModelError(f"t and x must have the same length, got {t.size} and {x.size}")
    if t.size < min_size:
        raise ModelError(f"the signal needs at least {min_size} samples, got {t.size}")
    dt = np.diff(t)
    if np.any(dt <= 0.0):
        i = int(np.flatnonzero(dt <= 0.0)[0])
        raise ModelError(f"t must be strictly increasing; t[{i}] = {t[i]!r} >= "
                         f"t[{i + 1}] = {t[i + 1]!r}")
    return t, x


# ---------------------------------------------------------------------------------------------
# peaks
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Peaks:
    """Extrema of a signal, sorted by time.

    Attributes
    ----------
    time : ndarray, shape (n,)
        Interpolated peak times [s].
    value : ndarray, shape (n,)
        Interpolated peak values [unit of x].
    sign : ndarray of int, shape (n,)
        +1 for a maximum (positive peak), -1 for a minimum (negative peak).
    center : float
        Reference level the lobes were taken about [unit of x].
    """

    time: np.ndarray
    value: np.ndarray
    sign: np.ndarray
    center: float = 0.0

    @property
    def amplitude(self) -> np.ndarray:
        """Peak amplitudes ``|value - center|``, shape (n,)."""
        return np.abs(self.value - self.center)

    @property
    def cycles_between(self) -> np.ndarray:
        """Cycles between consecutive peaks, shape (n - 1,): 1/2 if signs alternate, else 1."""
        return np.where(self.sign[1:] != self.sign[:-1], 0.5, 1.0)

    def __len__(self) -> int:
        return int(self.time.size)


def _lobe_state(x: np.ndarray, threshold: float) -> np.ndarray:
    """+1/-1 on each sample for the lobe it belongs to (Schmitt trigger), 0 before the first."""
    raw = np.where(x > threshold, 1, np.where(x < -threshold, -1, 0))
    idx = np.where(raw != 0, np.arange(raw.size), 0)
    np.maximum.accumulate(idx, out=idx)
    return raw[idx]  # leading zeros stay 0 (idx = 0 there and raw[0] = 0)


def _closed_lobe_extrema(x: np.ndarray, state: np.ndarray, sign: int) -> np.ndarray:
    """Index of the largest ``sign * x`` sample in every lobe of ``sign`` closed on both ends."""
    if state.size == 0:
        return np.zeros(0, dtype=int)
    starts = np.concatenate(([0], np.flatnonzero(np.diff(state) != 0) + 1))
    ends = np.concatenate((starts[1:], [state.size]))
    run_sign = state[starts]
    n_run = starts.size
    # a lobe is closed when an opposite-sign run precedes and follows it
    prev_ok = np.zeros(n_run, bool)
    next_ok = np.zeros(n_run, bool)
    prev_ok[1:] = run_sign[:-1] == -run_sign[1:]
    next_ok[:-1] = run_sign[1:] == -run_sign[:-1]
    keep = (run_sign == sign) & prev_ok & next_ok
    if not np.any(keep):
        return np.zeros(0, dtype=int)
    run_id = np.repeat(np.arange(n_run), ends - starts)
    order = np.lexsort((sign * x, run_id))  # by run, then by value ascending
    last_of_run = order[ends - 1]  # index with the largest sign*x of each run
    return last_of_run[keep]


def _local_vertex(t: np.ndarray, x: np.ndarray, idx: np.ndarray, half: int
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Vertex of the polynomial of degree 2*half through samples idx-half..idx+half.

    Local coordinate ``s = (t - t[idx]) / h`` with ``h = (t[idx+1] - t[idx-1]) / 2``; the
    parabola's vertex starts Newton's iteration on p'(s) = 0 (degree 4), kept in [-1, 1].
    """
    offs = np.arange(-half, half + 1)
    cols = idx[:, None] + offs[None, :]
    h = 0.5 * (t[idx + 1] - t[idx - 1])
    s = (t[cols] - t[idx][:, None]) / h[:, None]
    y = x[cols]
    deg = 2 * half
    vander = s[:, :, None] ** np.arange(deg + 1)[None, None, :]
    coef = np.linalg.solve(vander, y[:, :, None])[:, :, 0]  # (n, deg+1), ascending powers
    # parabola vertex through the 3 central samples (start value)
    s3 = s[:, half - 1: half + 2]
    y3 = y[:, half - 1: half + 2]
    v3 = s3[:, :, None] ** np.arange(3)[None, None, :]
    c3 = np.linalg.solve(v3, y3[:, :, None])[:, :, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        sv = np.where(c3[:, 2] != 0.0, -c3[:, 1] / (2.0 * c3[:, 2]), 0.0)
    sv = np.clip(sv, -1.0, 1.0)
    if deg > 2:
        powers = np.arange(deg + 1)
        d1 = coef[:, 1:] * powers[1:]
        d2 = d1[:, 1:] * powers[1:-1]
        for _ in range(8):
            p1 = np.sum(d1 * sv[:, None] ** powers[None, :-1], axis=1)
            p2 = np.sum(d2 * sv[:, None] ** powers[None, :-2], axis=1)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.where(p2 != 0.0, p1 / p2, 0.0)
            sv = np.clip(sv - step, -1.0, 1.0)
        val = np.sum(coef * sv[:, None] ** np.arange(deg + 1)[None, :], axis=1)
    else:
        val = c3[:, 0] + c3[:, 1] * sv + c3[:, 2] * sv * sv
    return t[idx] + sv * h, val


def find_peaks(t, x, *, negative: bool = False, center: float = 0.0, threshold: float = 0.0,
               interpolation: Literal["quartic", "parabolic"] = "quartic") -> Peaks:
    """Positive (and optionally negative) peaks of ``x(t)`` with sub-sample interpolation.

    The signal is split into lobes by the crossings of ``x - center`` (a Schmitt trigger of
    half-width ``threshold`` keeps noise near the crossings from splitting lobes). In every
    lobe closed by a crossing on both sides, the largest sample is refined by the vertex of
    the interpolating polynomial through its neighbours: degree 2 through 3 samples
    (``"parabolic"``; for a cosine whose nearest sample is b from the peak, h apart, both in
    w t units, the value is low by b^2 h^2 / 8 <= h^4 / 32) or degree 4 through 5 samples
    (``"quartic"``, default: about h^2 more accurate; the parabola is used at the ends of
    the record). Both work on non-uniform sampling. Lobes cut by the start or end of the record,
    and the rest position at the end of a stick-slip decay, give no peak.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times [s], strictly increasing (uniform or not).
    x : array_like, shape (n,)
        Signal [any unit], finite.
    negative : bool, optional
        Also return the minima (``sign = -1``); default False (maxima only).
    center : float, optional
        Level the lobes are taken about (the equilibrium) [unit of x]; default 0.
    threshold : float, optional
        Half-width of the crossing hysteresis [unit of x], >= 0; set it to a few noise
        standard deviations for measured signals. Default 0.
    interpolation : {"quartic", "parabolic"}, optional
        Local interpolant; default "quartic".

    Returns
    -------
    Peaks
        ``time``, ``value``, ``sign`` (n,), sorted by time.

    Raises
    ------
    ModelError
        Non-finite input, t not strictly increasing, fewer than 5 samples, bad options.
    """
    t, x = _check_signal(t, x)
    center = float(as_finite_array("center", center))
    threshold = float(as_finite_array("threshold", threshold))
    if threshold < 0.0:
        raise ModelError(f"threshold must be >= 0, got {threshold!r}")
    if interpolation not in ("quartic", "parabolic"):
        raise ModelError(f"interpolation must be 'quartic' or 'parabolic', got "
                         f"{interpolation!r}")
    y = x - center
    state = _lobe_state(y, threshold)
    signs = (1, -1) if negative else (1,)
    times, values, sgn = [], [], []
    n = t.size
    for sg in signs:
        idx = _closed_lobe_extrema(y, state, sg)
        idx = idx[(idx > 0) & (idx < n - 1)]
        if idx.size == 0:
            continue
        tp = np.empty(idx.size)
        vp = np.empty(idx.size)
        wide = (idx >= 2) & (idx <= n - 3) if interpolation == "quartic" else np.zeros(
            idx.size, bool)
        for mask, half in ((wide, 2), (~wide, 1)):
            if np.any(mask):
                tp[mask], vp[mask] = _local_vertex(t, sg * y, idx[mask], half)
        times.append(tp)
        values.append(sg * vp + center)
        sgn.append(np.full(idx.size, sg, dtype=int))
    if not times:
        return Peaks(np.zeros(0), np.zeros(0), np.zeros(0, dtype=int), center)
    tp = np.concatenate(times)
    order = np.argsort(tp, kind="stable")
    return Peaks(tp[order], np.concatenate(values)[order], np.concatenate(sgn)[order], center)


# ---------------------------------------------------------------------------------------------
# envelopes
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Envelope:
    """Amplitude envelope of an oscillating signal.

    Attributes
    ----------
    time : ndarray, shape (m,)
        Times [s].
    amplitude : ndarray, shape (m,)
        Envelope [unit of x], > 0.
    cycle : ndarray, shape (m,)
        Oscillation cycles elapsed since the first point [-] (0, 1/2, 1, ... for peaks;
        unwrapped phase / 2 pi for the Hilbert envelope).
    method : str
        ``"peaks"`` or ``"hilbert"``.
    """

    time: np.ndarray
    amplitude: np.ndarray
    cycle: np.ndarray
    method: str


def envelope_peaks(t, x, *, negative: bool = True, center: float = 0.0,
                   threshold: float = 0.0, interpolation: str = "quartic") -> Envelope:
    """Envelope through the interpolated extrema ``|x_peak - center|`` (see :func:`find_peaks`).

    Parameters
    ----------
    t, x : array_like, shape (n,)
        Times [s] (strictly increasing) and signal [any unit].
    negative : bool, optional
        Use minima as well as maxima (two points per cycle); default True. Use False when the
        oscillation is not symmetric about ``center``.
    center, threshold, interpolation
        As in :func:`find_peaks`.

    Returns
    -------
    Envelope
        One point per peak; ``cycle`` counts 1/2 between alternating peaks, 1 otherwise.
    """
    pk = find_peaks(t, x, negative=negative, center=center, threshold=threshold,
                    interpolation=interpolation)
    cyc = np.concatenate(([0.0], np.cumsum(pk.cycles_between))) if len(pk) else np.zeros(0)
    return Envelope(pk.time, pk.amplitude, cyc, "peaks")


def _uniform(t: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return (t, x) on a uniform grid (cubic spline resampling when t is not uniform)."""
    dt = np.diff(t)
    dt_med = float(np.median(dt))
    if np.max(np.abs(dt - dt_med)) <= 1e-9 * dt_med:
        return t, x
    from scipy.interpolate import CubicSpline

    n = int(np.floor((t[-1] - t[0]) / dt_med)) + 1
    tu = t[0] + dt_med * np.arange(n)
    return tu, CubicSpline(t, x)(tu)


def envelope_hilbert(t, x, *, center: float = 0.0, trim_cycles: float = 3.0) -> Envelope:
    """Envelope ``|z|`` and phase of the analytic signal ``z = hilbert(x - center)``.

    The record is first cut to the span between its first and last crossing of ``center``
    (which drops the rest position at the end of a stick-slip decay) and resampled on a
    uniform grid by a cubic spline if the sampling is not uniform. The FFT-based transform
    treats the record as periodic, so the jump between its ends would spoil the envelope
    everywhere; the signal is therefore multiplied by a raised-cosine (Tukey) taper over
    ``trim_cycles`` periods at each end and those tapered parts are discarded. In the kept
    interior the analytic signal of ``A exp(-sigma t) cos(w t)`` is ``A exp((-sigma + i w) t)``
    up to a residual leakage error that decays away from the ends (for zeta = 0.01 and 3
    tapered cycles: ~2e-3 relative just inside the kept part, ~1e-4 in the middle of a
    30-cycle record); it oscillates at w and averages out over whole cycles and in fits.

    Parameters
    ----------
    t, x : array_like, shape (n,)
        Times [s] (strictly increasing) and signal [any unit].
    center : float, optional
        Equilibrium level removed before the transform [unit of x]; default 0.
    trim_cycles : float, optional
        Tapered and discarded length at each end, in periods of the signal, > 0; default 3.

    Returns
    -------
    Envelope
        Interior samples; ``cycle`` is the unwrapped phase / 2 pi from the first kept sample.

    Raises
    ------
    ModelError
        Bad input, or a record too short to keep anything after trimming.
    """
    from scipy.signal import hilbert

    t, x = _check_signal(t, x)
    center = float(as_finite_array("center", center))
    trim_cycles = float(as_finite_array("trim_cycles", trim_cycles))
    if trim_cycles <= 0.0:
        raise ModelError(f"trim_cycles must be > 0, got {trim_cycles!r}")
    y = x - center
    cross = np.flatnonzero(np.signbit(y[1:]) != np.signbit(y[:-1]))
    if cross.size < 3:
        raise ModelError(f"x crosses center = {center} only {cross.size} times: not an "
                         "oscillation, or the record is too short for a Hilbert envelope")
    i0, i1 = cross[0], cross[-1] + 2
    t, y = _uniform(t[i0:i1], y[i0:i1])
    n = t.size
    period = 2.0 * (t[-1] - t[0]) / max(cross.size - 1, 1)  # two crossings per period
    m = int(np.ceil(trim_cycles * period / (t[1] - t[0])))
    if n - 2 * m < 8:
        raise ModelError(f"record of {t[-1] - t[0]:.4g} s (about {(t[-1] - t[0]) / period:.1f} "
                         f"cycles) is too short to trim {trim_cycles} cycles at each end; "
                         "lower trim_cycles or use method='peaks'")
    w = np.ones(n)
    ramp = 0.5 * (1.0 - np.cos(np.pi * np.arange(m) / m))
    w[:m] = ramp
    w[n - m:] = ramp[::-1]
    z = hilbert(y * w)[m: n - m]
    amp = np.abs(z)
    phase = np.unwrap(np.angle(z))
    return Envelope(t[m: n - m], amp, (phase - phase[0]) / (2.0 * np.pi), "hilbert")


# ---------------------------------------------------------------------------------------------
# decrements and envelope fits
# ---------------------------------------------------------------------------------------------

def log_decrement(peaks, *, cycles_between=None) -> tuple[np.ndarray, np.ndarray]:
    """Logarithmic decrement per cycle between successive peaks, and the viscous ratio.

    ``delta_i = ln(A_i / A_{i+1}) / c_i`` with ``c_i`` the cycles between the two peaks, and
    ``zeta_i = delta_i / sqrt(4 pi^2 + delta_i^2)`` (exact for a linear viscous decay; for a
    Coulomb decay see the module docstring and :func:`coulomb_envelope_fit`).

    Parameters
    ----------
    peaks : Peaks or array_like, shape (n,)
        A :class:`Peaks` (its amplitudes and ``cycles_between`` are used) or successive peak
        amplitudes (> 0) one cycle apart unless ``cycles_between`` says otherwise.
    cycles_between : float or array_like, shape (n - 1,), optional
        Cycles between consecutive amplitudes (0.5 for alternating positive/negative peaks).

    Returns
    -------
    delta : ndarray, shape (n - 1,)
        Logarithmic decrement per cycle [-].
    zeta : ndarray, shape (n - 1,)
        Viscous damping ratio [-].

    Raises
    ------
    ModelError
        Fewer than 2 peaks, non-positive or non-finite amplitudes.
    """
    if isinstance(peaks, Peaks):
        amp = peaks.amplitude
        cyc = peaks.cycles_between if cycles_between is None else cycles_between
    else:
        amp = as_finite_array("peaks", peaks, ndim=1)
        cyc = 1.0 if cycles_between is None else cycles_between
    if amp.size < 2:
        raise ModelError(f"log_decrement needs at least 2 peaks, got {amp.size}")
    if np.any(amp <= 0.0):
        raise ModelError("peak amplitudes must be > 0 (peaks measured from the equilibrium)")
    cyc = np.broadcast_to(as_finite_array("cycles_between", cyc), (amp.size - 1,))
    if np.any(cyc <= 0.0):
        raise ModelError(f"cycles_between must be > 0, got {cycles_between!r}")
    delta = np.log(amp[:-1] / amp[1:]) / cyc
    return delta, np.asarray(zeta_from_log_decrement(delta), dtype=float).reshape(delta.shape)


def _fit_inputs(t, a, period, cycles_between) -> tuple[np.ndarray, np.ndarray, float]:
    t = as_finite_array("t_peaks", t, ndim=1)
    a = as_finite_array("a_peaks", a, ndim=1)
    if t.shape != a.shape:
        raise ModelError(f"t_peaks and a_peaks must have the same length, got {t.size}, "
                         f"{a.size}")
    if t.size < 3:
        raise ModelError(f"an envelope fit needs at least 3 points, got {t.size}: record a "
                         "longer decay or lower the threshold")
    if np.any(np.diff(t) <= 0):
        raise ModelError("t_peaks must be strictly increasing")
    if np.any(a <= 0):
        raise ModelError("a_peaks must be > 0 (amplitudes measured from the equilibrium)")
    if period is None:
        c = 1.0 if cycles_between is None else float(cycles_between)
        if c <= 0:
            raise ModelError(f"cycles_between must be > 0, got {cycles_between!r}")
        period = float(np.mean(np.diff(t))) / c
    period = float(as_finite_array("period", period))
    if period <= 0:
        raise ModelError(f"period must be > 0 s, got {period!r}")
    return t, a, period


@dataclass(frozen=True)
class CoulombFit:
    """Linear envelope ``a(t) = a0 - slope t`` of a Coulomb (dry-friction) free decay.

    Attributes
    ----------
    slope : float
        Amplitude lost per second, s [unit of x / s] (> 0 for a decay).
    intercept : float
        a0, envelope at t = 0 [unit of x].
    period : float
        Oscillation period T [s].
    decrement_per_cycle : float
        dA = s T, amplitude lost per cycle [unit of x]; ``4 F_f / k`` for a Coulomb
        oscillator.
    residual : float
        Rms residual of the fit divided by the rms amplitude [-].
    """

    slope: float
    intercept: float
    period: float
    decrement_per_cycle: float
    residual: float

    @property
    def slip_displacement(self) -> float:
        """``F_f / k = dA / 4`` [unit of x]: friction force over stiffness, identified."""
        return self.decrement_per_cycle / 4.0

    def equivalent_ratio(self, amplitude):
        """Equivalent ratio ``zeta_eq(A) = dA / (2 pi A)`` [-] at amplitude(s) A (> 0)."""
        a = as_finite_array("amplitude", amplitude)
        if np.any(a <= 0):
            raise ModelError(f"amplitude must be > 0, got {amplitude!r}")
        return self.decrement_per_cycle / (2.0 * np.pi * a)


def coulomb_envelope_fit(t_peaks, a_peaks, *, period=None, cycles_between=None) -> CoulombFit:
    """Fit a linear envelope ``a0 - s t`` (least squares) to a dry-friction free decay.

    A Coulomb oscillator's peaks fall by ``dA = 4 F_f / k`` per cycle at an unchanged period
    ``2 pi / w_n``; its amplitude-dependent equivalent damping ratio is ``zeta_eq(A) =
    dA / (2 pi A) = 2 F_f / (pi k A)`` (:meth:`CoulombFit.equivalent_ratio`).

    Parameters
    ----------
    t_peaks : array_like, shape (n,)
        Times of the envelope points [s], strictly increasing, n >= 3.
    a_peaks : array_like, shape (n,)
        Envelope amplitudes [unit of x], > 0.
    period : float, optional
        Oscillation period [s]; default: mean spacing of ``t_peaks`` / ``cycles_between``.
    cycles_between : float, optional
        Cycles between consecutive points when ``period`` is not given (0.5 for alternating
        positive/negative peaks); default 1.

    Returns
    -------
    CoulombFit
    """
    t, a, period = _fit_inputs(t_peaks, a_peaks, period, cycles_between)
    p = np.polyfit(t, a, 1)
    res = a - np.polyval(p, t)
    rel = float(np.sqrt(np.mean(res**2)) / np.sqrt(np.mean(a**2)))
    slope = -float(p[0])
    return CoulombFit(slope, float(p[1]), period, slope * period, rel)


@dataclass(frozen=True)
class ViscousFit:
    """Exponential envelope ``a(t) = a0 exp(-sigma t)`` of a linear viscous free decay.

    Attributes
    ----------
    decay_rate : float
        sigma = zeta w_n [1/s].
    intercept : float
        a0, envelope at t = 0 [unit of x].
    period : float
        Damped period T_d [s].
    log_decrement : float
        delta = sigma T_d [-].
    damping_ratio : float
        zeta = delta / sqrt(4 pi^2 + delta^2) [-].
    residual : float
        Rms residual of the fit (on the amplitude, not its log) over the rms amplitude [-].
    """

    decay_rate: float
    intercept: float
    period: float
    log_decrement: float
    damping_ratio: float
    residual: float


def viscous_envelope_fit(t_peaks, a_peaks, *, period=None, cycles_between=None) -> ViscousFit:
    """Fit ``a0 exp(-sigma t)`` to an envelope by least squares on the amplitude.

    Started from the straight-line fit of ``ln a``, refined by Gauss-Newton on the amplitude
    residual, so that its residual is comparable with :func:`coulomb_envelope_fit`'s.

    Parameters
    ----------
    t_peaks, a_peaks, period, cycles_between
        As in :func:`coulomb_envelope_fit`.

    Returns
    -------
    ViscousFit
    """
    t, a, period = _fit_inputs(t_peaks, a_peaks, period, cycles_between)
    t0 = t[0]
    tau = t - t0
    slope, lna0 = np.polyfit(tau, np.log(a), 1)
    sigma, a0 = -float(slope), float(np.exp(lna0))

    def cost_of(a0_: float, sigma_: float) -> float:
        r_ = a - a0_ * np.exp(-sigma_ * tau)
        return float(r_ @ r_)

    cost = cost_of(a0, sigma)
    for _ in range(30):  # Gauss-Newton with step halving on (a0, sigma)
        e = np.exp(-sigma * tau)
        jac = np.column_stack((e, -a0 * tau * e))  # d(model)/d(a0, sigma)
        step, *_ = np.linalg.lstsq(jac, a - a0 * e, rcond=None)
        lam = 1.0
        while lam > 1e-6:
            a0_new, sigma_new = a0 + lam * step[0], sigma + lam * step[1]
            if a0_new > 0.0:
                new_cost = cost_of(a0_new, sigma_new)
                if new_cost <= cost:
                    break
            lam *= 0.5
        else:
            break
        small = abs(lam * step[1]) * tau[-1] <= 1e-13 and abs(lam * step[0]) <= 1e-13 * a0
        a0, sigma, cost = a0_new, sigma_new, new_cost
        if small:
            break
    rel = float(np.sqrt(cost / a.size) / np.sqrt(np.mean(a**2)))
    delta = sigma * period
    return ViscousFit(sigma, a0 * np.exp(sigma * t0), period, delta,
                      float(zeta_from_log_decrement(delta)), rel)


# ---------------------------------------------------------------------------------------------
# the identification
# ---------------------------------------------------------------------------------------------

def _array_list(value) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    return value


#: Second spectral peak (relative to the dominant one) above which a decay counts as carrying
#: two modes -- together with an envelope that grows somewhere (beating).
SECOND_MODE_RATIO = 0.1
#: Relative growth of the interval amplitude that counts as the envelope growing.
ENVELOPE_GROWTH = 5e-3


def second_mode(t, x, *, center: float = 0.0) -> tuple[float, float, float]:
    """Largest spectral peak of ``x(t)`` away from the dominant frequency and its harmonics.

    The signal (about ``center``, mean removed, Hann window, zero-padded to 4x) is
    transformed; local maxima of the magnitude closer than ``max(3 / T, 0.1 f1)`` to the
    dominant frequency ``f1``, to one of its harmonics ``k f1`` (a friction decay's
    stick-slip corners make odd harmonics) or to 0 are ignored.

    Returns
    -------
    ratio : float
        That peak's magnitude over the dominant one's [-] (0 when there is none).
    f1, f2 : float
        The dominant frequency and that of the second peak [Hz] (NaN when none).
    """
    t_arr, x_arr = _check_signal(t, x)
    tu, xu = _uniform(t_arr, x_arr)
    y = xu - center
    y = y - y.mean()
    n = y.size
    if n < 8:
        return 0.0, float("nan"), float("nan")
    dt = float(tu[1] - tu[0])
    nfft = 1 << int(np.ceil(np.log2(4 * n)))
    mag = np.abs(np.fft.rfft(y * np.hanning(n), nfft))
    f = np.fft.rfftfreq(nfft, dt)
    if mag.size < 3 or not np.any(mag[1:] > 0):
        return 0.0, float("nan"), float("nan")
    k1 = 1 + int(np.argmax(mag[1:]))
    f1 = float(f[k1])
    guard = max(3.0 / (n * dt), 0.1 * f1)
    peak = np.zeros(mag.size, bool)
    peak[1:-1] = (mag[1:-1] > mag[:-2]) & (mag[1:-1] >= mag[2:])
    harmonic = np.rint(f / f1) if f1 > 0 else np.zeros_like(f)
    near = (np.abs(f - harmonic * f1) < guard) | (f < guard)
    cand = np.flatnonzero(peak & ~near)
    if cand.size == 0:
        return 0.0, f1, float("nan")
    j = cand[np.argmax(mag[cand])]
    return float(mag[j] / mag[k1]), f1, float(f[j])


@dataclass(frozen=True, repr=False)
class DecayResult(ResultMixin):
    """Damping identified from a free decay.

    Attributes
    ----------
    time : ndarray, shape (n,)
        Mid-time of each interval (peak pair, or Hilbert cycle) [s].
    amplitude : ndarray, shape (n,)
        Mean amplitude of each interval [unit of x].
    damping_ratio : ndarray, shape (n,)
        Model-free amplitude-dependent ratio ``zeta_i`` (module docstring) [-].
    frequency_hz : ndarray, shape (n,)
        Instantaneous frequency from the peak spacing (or phase rate) [Hz].
    mean_damping_ratio : float
        Ratio from the record-average decrement ``ln(A_first / A_last) / cycles`` [-] (for
        the Hilbert envelope, A are the cycle means of ln|z|), the number paper 003 reports
        for its free attenuations.
    mean_frequency_hz : float
        Cycles counted over the time they take [Hz].
    model : str
        ``"viscous"`` or ``"coulomb"``: the envelope model chosen (``kind``) or fitted best.
    model_damping_ratio : ndarray, shape (n,)
        The chosen model's ratio at ``amplitude``: constant zeta (viscous) or
        ``dA / (2 pi A)`` (Coulomb) [-].
    viscous, coulomb : ViscousFit, CoulombFit
        Both envelope fits.
    envelope : Envelope
        The envelope the fits used.
    method : str
        ``"peaks"`` or ``"hilbert"``.
    second_mode_ratio : float
        Largest spectral peak away from the dominant frequency and its harmonics, relative
        to the dominant one (:func:`second_mode`) [-].
    second_mode_hz : float
        Its frequency [Hz] (NaN when none).
    envelope_growth : float
        Largest relative growth of the interval amplitude from one interval to the next
        [-]: 0 for a single decaying mode (its energy, hence its amplitude, only falls).
    verdict : fricdamp.verdict.Verdict
        ``unreliable`` when the signal carries two modes (``second_mode_ratio`` above
        :data:`SECOND_MODE_RATIO` and an envelope that grows by more than
        :data:`ENVELOPE_GROWTH`: beating): a decrement then mixes both modes' damping.
    """

    time: np.ndarray
    amplitude: np.ndarray
    damping_ratio: np.ndarray
    frequency_hz: np.ndarray
    mean_damping_ratio: float
    mean_frequency_hz: float
    model: str
    model_damping_ratio: np.ndarray
    viscous: ViscousFit
    coulomb: CoulombFit
    envelope: Envelope = field(repr=False)
    method: str = "peaks"
    second_mode_ratio: float = 0.0
    second_mode_hz: float = float("nan")
    envelope_growth: float = 0.0

    @property
    def multi_mode(self) -> bool:
        """The signal carries two modes (see ``verdict``)."""
        return bool(self.second_mode_ratio > SECOND_MODE_RATIO
                    and self.envelope_growth > ENVELOPE_GROWTH)

    def _judge(self):
        from fricdamp.results import status_verdict

        est = {"second_mode_ratio": float(self.second_mode_ratio),
               "envelope_growth": float(self.envelope_growth),
               "viscous_fit_residual": float(self.viscous.residual),
               "coulomb_fit_residual": float(self.coulomb.residual)}
        reasons = ()
        if self.multi_mode:
            reasons = (_multi_mode_message(self),)
        return status_verdict(True, "", est, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` over the decay intervals (time, amplitude, damping ratios,
        frequency [Hz]) with the record means and both fits as attributes."""
        import xarray as xr

        return xr.Dataset(
            {"amplitude": (("interval",), self.amplitude, {"units": "unit of x"}),
             "damping_ratio": (("interval",), self.damping_ratio, {"units": "1"}),
             "model_damping_ratio": (("interval",), self.model_damping_ratio,
                                     {"units": "1"}),
             "frequency": (("interval",), self.frequency_hz, {"units": "Hz"})},
            coords={"time": ("interval", self.time, {"units": "s"})},
            attrs={"mean_damping_ratio": self.mean_damping_ratio,
                   "mean_frequency_hz": self.mean_frequency_hz, "model": self.model,
                   "method": self.method,
                   "viscous_damping_ratio": self.viscous.damping_ratio,
                   "coulomb_decrement_per_cycle": self.coulomb.decrement_per_cycle,
                   "second_mode_ratio": self.second_mode_ratio,
                   "envelope_growth": self.envelope_growth})

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (lists and floats) of every field, fits and envelope nested."""
        out: dict[str, Any] = {}
        for name in ("time", "amplitude", "damping_ratio", "frequency_hz",
                     "mean_damping_ratio", "mean_frequency_hz", "model",
                     "model_damping_ratio", "method"):
            out[name] = _array_list(getattr(self, name))
        for name in ("viscous", "coulomb"):
            fit = getattr(self, name)
            out[name] = {k: _array_list(v) for k, v in fit.__dict__.items()}
        out["coulomb"]["slip_displacement"] = self.coulomb.slip_displacement
        out["envelope"] = {k: _array_list(v) for k, v in self.envelope.__dict__.items()}
        return out

    def plot(self, ax=None):
        """Plot the damping ratio [%] against the amplitude: the intervals (points), the
        record mean ``mean_damping_ratio`` (dashed, the number printed and reported) and
        the chosen model's fit (line; its value in the legend).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Axes to draw on; a new figure is made when omitted.

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(layout="constrained")
        order = np.argsort(self.amplitude)
        ax.plot(self.amplitude, 100 * self.damping_ratio, "o", ms=3,
                label=f"per interval ({self.method})")
        ax.axhline(100 * self.mean_damping_ratio, color="k", ls="--", lw=1,
                   label=f"record mean ζ = {100 * self.mean_damping_ratio:.3g} %")
        if self.model == "viscous":
            fit_label = f"viscous fit ζ = {100 * self.viscous.damping_ratio:.3g} %"
        else:
            fit_label = "Coulomb fit ζ = ΔA / (2π A)"
        ax.plot(self.amplitude[order], 100 * self.model_damping_ratio[order], "-",
                label=fit_label)
        ax.set_xlabel("amplitude")
        ax.set_ylabel("damping ratio ζ [%]")
        if self.multi_mode:
            ax.set_title("unreliable: the signal carries two modes", fontsize="small",
                         color="C3")
        ax.legend(fontsize="small")
        return ax


def _multi_mode_message(res: DecayResult) -> str:
    return (f"the signal carries two modes (a second spectral peak at "
            f"{res.second_mode_hz:.4g} Hz, {100 * res.second_mode_ratio:.0f} % of the one at "
            f"{res.mean_frequency_hz:.4g} Hz, and an envelope that grows by "
            f"{100 * res.envelope_growth:.1f} %): the decrement mixes their damping; "
            "band-pass filter the signal around one mode or excite one mode only")


def _hilbert_cycles(env: Envelope) -> tuple[np.ndarray, ...]:
    """Per pair of successive full phase cycles: decrement, amplitude, time and frequency.

    ``ln|z|`` is averaged over each full cycle of the phase, which removes the residual
    ripple at the oscillation frequency (the leakage of the Hilbert transform) to first
    order; the difference of two successive averages is the logarithmic decrement of that
    cycle, as between two peaks.
    """
    k = np.floor(env.cycle + 1e-12).astype(int)
    n_full = int(np.floor(env.cycle[-1] + 1e-12))
    full = (k >= 0) & (k < n_full)
    k, t, la, ph = k[full], env.time[full], np.log(env.amplitude[full]), env.cycle[full]
    if n_full < 2:
        raise ModelError("the Hilbert envelope spans fewer than 2 full cycles after trimming: "
                         "record a longer decay or use method='peaks'")
    cnt = np.bincount(k, minlength=n_full).astype(float)
    if np.any(cnt < 4):
        raise ModelError("fewer than 4 samples per cycle: the signal is undersampled for a "
                         "Hilbert envelope")
    tm = np.bincount(k, t, minlength=n_full) / cnt
    lm = np.bincount(k, la, minlength=n_full) / cnt
    delta = lm[:-1] - lm[1:]
    # frequency: least-squares slope of the phase over the two cycles of each pair
    tc = t - t.mean()
    sums = [np.bincount(k, v, minlength=n_full) for v in (tc, tc * tc, ph, tc * ph)]
    s1, s2, sp, stp = (v[:-1] + v[1:] for v in sums)
    nn = cnt[:-1] + cnt[1:]
    freq = (nn * stp - s1 * sp) / (nn * s2 - s1 * s1)
    zeta = np.asarray(zeta_from_log_decrement(delta), dtype=float).reshape(delta.shape)
    amp = 0.5 * (np.exp(lm[:-1]) + np.exp(lm[1:]))
    return 0.5 * (tm[:-1] + tm[1:]), amp, zeta, freq, delta


def decay_damping(t, x, *, method: Literal["peaks", "hilbert"] = "peaks",
                  kind: Literal["auto", "viscous", "coulomb"] = "auto", center: float = 0.0,
                  negative_peaks: bool = True, threshold: float = 0.0,
                  trim_cycles: float = 3.0) -> DecayResult:
    """Identify the damping of a free decay ``x(t)``: amplitude-dependent ratio and model.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times [s], strictly increasing (uniform or not).
    x : array_like, shape (n,)
        Free-decay signal [any unit] oscillating about ``center``.
    method : {"peaks", "hilbert"}, optional
        Envelope estimator (module docstring); default "peaks".
    kind : {"auto", "viscous", "coulomb"}, optional
        Envelope model: exponential (viscous), linear (Coulomb), or the better fit (smaller
        rms residual on the amplitude); default "auto".
    center : float, optional
        Equilibrium level [unit of x]; default 0.
    negative_peaks : bool, optional
        ``method="peaks"``: use minima too (two envelope points per cycle); default True.
    threshold : float, optional
        ``method="peaks"``: crossing hysteresis for noisy signals [unit of x]; default 0.
    trim_cycles : float, optional
        ``method="hilbert"``: tapered and discarded cycles at each end; default 3.

    Returns
    -------
    DecayResult

    Raises
    ------
    ModelError
        Non-finite input, t not strictly increasing, too few peaks (fewer than 3 envelope
        points), an unknown ``method`` or ``kind``.

    Warns
    -----
    UserWarning
        The signal carries two modes (a second spectral peak and a growing envelope, see
        :class:`DecayResult`): the result's verdict is then ``unreliable``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 2.0, 4001)
    >>> wn, zeta = 2 * np.pi * 10.0, 0.01
    >>> x = np.exp(-zeta * wn * t) * np.cos(wn * np.sqrt(1 - zeta**2) * t)
    >>> res = decay_damping(t, x)
    >>> res.model, round(res.mean_damping_ratio, 6)
    ('viscous', 0.01)
    """
    if method not in ("peaks", "hilbert"):
        raise ModelError(f"method must be 'peaks' or 'hilbert', got {method!r}")
    if kind not in ("auto", "viscous", "coulomb"):
        raise ModelError(f"kind must be 'auto', 'viscous' or 'coulomb', got {kind!r}")
    if method == "peaks":
        t_arr, _ = _check_signal(t, x)
        env = envelope_peaks(t, x, negative=negative_peaks, center=center,
                             threshold=threshold)
        if env.time.size < 3:
            raise ModelError(
                f"found {env.time.size} peaks in {t_arr[-1] - t_arr[0]:.4g} s of signal; at "
                "least 3 are needed (is x a decaying oscillation about center = "
                f"{center}? record a longer decay, or lower threshold = {threshold})")
        a, tt, cyc = env.amplitude, env.time, np.diff(env.cycle)
        delta = np.log(a[:-1] / a[1:]) / cyc
        zeta = np.asarray(zeta_from_log_decrement(delta), dtype=float).reshape(delta.shape)
        amp = 0.5 * (a[:-1] + a[1:])
        tmid = 0.5 * (tt[:-1] + tt[1:])
        freq = cyc / np.diff(tt)
        total_cycles = float(env.cycle[-1] - env.cycle[0])
        delta_mean = float(np.log(a[0] / a[-1]) / total_cycles)
        f_mean = total_cycles / float(tt[-1] - tt[0])
    else:
        env = envelope_hilbert(t, x, center=center, trim_cycles=trim_cycles)
        tmid, amp, zeta, freq, delta = _hilbert_cycles(env)
        total_cycles = float(env.cycle[-1] - env.cycle[0])
        f_mean = total_cycles / float(env.time[-1] - env.time[0])
        delta_mean = float(np.mean(delta))  # = (first - last cycle-mean ln A) / cycles
    period = 1.0 / f_mean
    vfit = viscous_envelope_fit(env.time, env.amplitude, period=period)
    cfit = coulomb_envelope_fit(env.time, env.amplitude, period=period)
    model = kind if kind != "auto" else ("coulomb" if cfit.residual < vfit.residual
                                         else "viscous")
    if model == "viscous":
        model_zeta = np.full(amp.shape, vfit.damping_ratio)
    else:
        model_zeta = cfit.decrement_per_cycle / (2.0 * np.pi * amp)
    ratio, _, f2 = second_mode(t, x, center=center)
    growth = float(np.max(amp[1:] / amp[:-1] - 1.0, initial=0.0)) if amp.size > 1 else 0.0
    res = DecayResult(time=tmid, amplitude=amp, damping_ratio=zeta, frequency_hz=freq,
                      mean_damping_ratio=float(zeta_from_log_decrement(delta_mean)),
                      mean_frequency_hz=float(f_mean), model=model,
                      model_damping_ratio=model_zeta, viscous=vfit, coulomb=cfit,
                      envelope=env, method=method, second_mode_ratio=ratio,
                      second_mode_hz=f2, envelope_growth=max(growth, 0.0))
    if res.multi_mode:
        warnings.warn(_multi_mode_message(res), UserWarning, stacklevel=2)
    return res
