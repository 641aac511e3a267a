"""Which samples the joint identification analyses (:mod:`fricdamp.signals.identify`).

The time base (near-uniform stamps rebuilt, :func:`fricdamp.signals.records.uniform_time`),
the excitation frequency (:func:`estimate_frequency`), the start-up transient
(:func:`steady_start`) and the window of whole periods (:func:`whole_periods`).
"""

from __future__ import annotations

import logging

import numpy as np

from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.signals.energy import steady_cycle
from fricdamp.signals.records import uniform_time

log = logging.getLogger(__name__)

#: FFT lengths whose prime factors are all below this are fast (pocketfft); a record whose
#: length has a large prime factor (9973 Hz sampling) is ~5x slower to transform
_FFT_PRIME_LIMIT = 100

#: start-up transient: relative change of a period's fundamental that counts as transient
TRANSIENT_TOLERANCE = 0.01
#: ... or this many times the median scatter of the steady periods' fundamentals
TRANSIENT_NOISE_FACTOR = 5.0


def estimate_frequency(x, dt: float, *, f_min: float = 0.0) -> float:
    """Frequency [Hz] of the strongest spectral line of a sampled signal.

    Hann window, largest bin above ``f_min``, then a parabola through the logarithms of the
    magnitudes of that bin and its neighbours (accurate to a few thousandths of a bin for a
    clean line: for N periods in the record, a relative error of about 1e-3 / N).

    Parameters
    ----------
    x : array_like, shape (n,)
        Signal, n >= 16.
    dt : float
        Sampling interval [s].
    f_min : float, optional
        Lines below this frequency [Hz] are ignored (e.g. a suspension mode); default 0.

    Returns
    -------
    float
        Frequency [Hz].
    """
    x = as_finite_array("x", x, ndim=1)
    if x.size < 16:
        raise ModelError(f"estimating a frequency needs at least 16 samples, got {x.size}")
    dt = float(check_positive("dt", dt, unit="s"))
    n = x.size
    spec = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(n)))
    freq = np.fft.rfftfreq(n, dt)
    spec[freq < max(f_min, 1e-300)] = 0.0
    k = int(np.argmax(spec))
    if spec[k] <= 0.0:
        raise ModelError("the signal has no spectral line (it is constant or zero)")
    if 0 < k < spec.size - 1 and spec[k - 1] > 0 and spec[k + 1] > 0:
        a, b, c = np.log(spec[k - 1]), np.log(spec[k]), np.log(spec[k + 1])
        den = a - 2.0 * b + c
        delta = 0.5 * (a - c) / den if den < 0 else 0.0
    else:
        delta = 0.0
    return float((k + delta) / (n * dt))


def check_time(t) -> tuple[np.ndarray, float, bool]:
    """Uniform time base of a record: ``(t, dt, snapped)`` (see :func:`uniform_time`)."""
    t = as_finite_array("time", t, ndim=1)
    if t.size < 16:
        raise ModelError(f"the record needs at least 16 samples, got {t.size}")
    t, dt, snapped = uniform_time(t)
    if snapped:
        log.info("time stamps rebuilt on a uniform grid of %.9g Hz (rounded stamps)", 1 / dt)
    return t, dt, snapped


def _largest_prime_factor(m: int) -> int:
    m = int(m)
    largest, p = 1, 2
    while p * p <= m:
        while m % p == 0:
            largest, m = p, m // p
        p += 1
    return max(largest, m)


def whole_periods(t, x, dt, frequency, periods):
    """The last whole periods of the record: ``(t, x, n_periods, resampled, dt)``.

    Raw samples whenever a whole number of periods spans a whole number of samples (to 1e-6
    of a sample) whose prime factors are small (a fast FFT length): every period asked when
    a period is a whole number of samples, otherwise the largest such number of periods not
    below 3/4 of those asked (10240 Hz at 30 Hz: 3 periods are 1024 samples). Otherwise the
    periods are resampled by a cubic spline (:func:`steady_cycle`, error O(h^4)) on a fast
    FFT length of at least ``ceil(samples per period)`` points per period.
    """
    from scipy.fft import next_fast_len

    per = 1.0 / (frequency * dt)  # samples per period
    if per < 8:
        raise ModelError(f"{per:.3g} samples per period of {frequency:g} Hz: at least 8 are "
                         "needed (sample faster)")
    # n raw samples hold n / per whole periods (half-open window); interpolation needs the
    # closing sample: (n - 1) / per
    avail_raw = int(np.floor(t.size / per + 1e-9))
    avail_int = int(np.floor((t.size - 1) / per + 1e-9))
    if avail_raw < 1:
        raise ModelError(f"the record ({(t.size - 1) * dt:.4g} s) is shorter than one period "
                         f"of {frequency:g} Hz")
    if periods is None:
        periods = avail_raw
    if int(periods) != periods or periods < 1:
        raise ModelError(f"periods must be an integer >= 1, got {periods!r}")
    periods = int(periods)
    if periods > avail_raw:
        raise ModelError(f"periods = {periods} whole periods of {frequency:g} Hz asked for, "
                         f"the record holds {avail_raw}")
    candidates = range(periods, int(np.ceil(0.75 * periods)) - 1, -1)
    for n_per in candidates:
        m = n_per * per
        if abs(m - round(m)) <= 1e-6 and _largest_prime_factor(round(m)) < _FFT_PRIME_LIMIT:
            m = int(round(m))
            return t[-m:].copy(), x[-m:].copy(), n_per, False, dt
    periods = min(periods, avail_int)
    if periods < 1:  # pragma: no cover - needs a record of exactly one period
        raise ModelError("the record is too short to be resampled on one whole period")
    periods = next((n for n in range(periods, int(np.ceil(0.75 * periods)) - 1, -1)
                    if _largest_prime_factor(n) < _FFT_PRIME_LIMIT), periods)
    spc = int(next_fast_len(int(np.ceil(per - 1e-9)), real=True))
    tw, xw = steady_cycle(t, x, 1.0 / frequency, n_cycles=periods, samples_per_cycle=spc,
                          interpolation="cubic")
    return tw, xw, periods, True, 1.0 / (frequency * spc)


def period_fundamentals(x, dt, frequency) -> np.ndarray:
    """Complex amplitude of the fundamental of each whole period of the record.

    ``c_p = (2/T) int_{pT}^{(p+1)T} x(t) e^{-i w t} dt`` (trapezoidal cumulative integral,
    period ends interpolated between samples so periods need not be whole numbers of
    samples), for every column of ``x`` (n, k). Returns shape (n_periods, k).
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    per = 1.0 / (frequency * dt)
    n_per = int(np.floor((n - 1) / per + 1e-9))
    z = x * np.exp(-2j * np.pi * frequency * dt * np.arange(n))[:, None]
    cum = np.concatenate((np.zeros((1, x.shape[1]), complex),
                          np.cumsum(0.5 * (z[1:] + z[:-1]), axis=0)), axis=0)
    ends = np.arange(n_per + 1) * per
    i0 = np.minimum(np.floor(ends).astype(int), n - 2)
    frac = (ends - i0)[:, None]
    at = cum[i0] + frac * (cum[i0 + 1] - cum[i0])
    return 2.0 * np.diff(at, axis=0) / per


def refine_frequency(x, dt, frequency, *, passes: int = 2) -> float:
    """Refine an excitation frequency [Hz] from the phase drift of the periods' fundamentals.

    At a frequency off by ``df`` the phase of each period's fundamental
    (:func:`period_fundamentals` of the signal ``x`` (n,)) advances by ``2 pi df / f`` per
    period; the least-squares slope of the unwrapped phases gives ``df``. Needs at least 4
    periods (else returns ``frequency``); a spectral-peak estimate (:func:`estimate_frequency`)
    within a fraction of a bin is refined to ~1e-7 on a steady record.
    """
    f = float(frequency)
    x = np.asarray(x, dtype=float).reshape(-1, 1)
    for _ in range(int(passes)):
        c = period_fundamentals(x, dt, f)[:, 0]
        if c.size < 4 or not np.all(np.abs(c) > 0):
            return f
        phase = np.unwrap(np.angle(c))
        p = np.arange(c.size, dtype=float)
        slope = float(np.polyfit(p, phase, 1)[0])
        f_new = f * (1.0 + slope / (2.0 * np.pi))
        if not np.isfinite(f_new) or abs(f_new - f) > 0.1 * f:
            return f
        f = f_new
    return f


def steady_start(acc, dt, frequency, *, tolerance: float = TRANSIENT_TOLERANCE,
                 noise_factor: float = TRANSIENT_NOISE_FACTOR) -> tuple[int, bool]:
    """Whole periods of start-up transient at the beginning of a record.

    The documented rule (docs/identify.md): the fundamental of every period is computed for
    each column of ``acc`` (the angular and linear accelerations and the joint's relative
    angular acceleration); the steady value of each is the median over the second half of
    the record. A period is *transient* when its fundamental differs from the steady value
    by more than ``tolerance`` of it or more than ``noise_factor`` times the median
    difference of the second half's periods (the noise). The steady state starts after the
    last transient period of the first half; the second half is never cut.

    Returns
    -------
    skip : int
        Leading whole periods to drop.
    settled : bool
        False when the two quarters of the second half themselves differ (the record may
        not reach a steady state).
    """
    c = period_fundamentals(acc, dt, frequency)
    n_per = c.shape[0]
    if n_per < 4:
        return 0, True
    half = n_per // 2
    tail = c[half:]
    ref = np.median(tail.real, axis=0) + 1j * np.median(tail.imag, axis=0)
    dev = np.abs(c - ref)
    scatter = np.median(dev[half:], axis=0)
    limit = np.maximum(tolerance * np.abs(ref), noise_factor * scatter)
    bad = np.any(dev[:half] > limit, axis=1)
    skip = int(np.flatnonzero(bad)[-1]) + 1 if np.any(bad) else 0
    q = max(1, (n_per - half) // 2)
    third, fourth = c[half:half + q], c[n_per - q:]
    m3 = np.median(third.real, axis=0) + 1j * np.median(third.imag, axis=0)
    m4 = np.median(fourth.real, axis=0) + 1j * np.median(fourth.imag, axis=0)
    settled = bool(np.all(np.abs(m4 - m3) <= limit))
    return skip, settled
