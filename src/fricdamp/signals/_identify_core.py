"""Numerical core of the joint identification (:mod:`fricdamp.signals.identify`).

Kinematics 002 (B.1)-(B.10) and torque 002 (8) on plain arrays (so the sensor positions can
be arrays of Monte Carlo draws), and the processing of one window of whole periods:
drift removal, harmonic or high-pass filter, FFT/IFFT integration (002 Fig. 7), torque,
loop. Every function here broadcasts over trailing axes: a window is ``(n, 3)`` for one
record or ``(n, 3, m)`` for ``m`` perturbed copies of it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fricdamp.signals.records import fft_integrate


def kinematics_linear(ga, gb, gc, d1, d2, d3, d4, d5):
    """``theta1''``, ``theta2''``, ``x1''`` from 002 (B.3), (B.6), (B.10) (linear)."""
    th1 = (ga - gb) / (d1 - d2)  # 002 (B.6)
    x1 = 0.5 * (ga + gb - (d1 + d2) * th1)  # 002 (B.6)
    th2 = (gc - (x1 + d3 * th1)) / (d4 + d5)  # 002 (B.3), (B.10)
    return th1, th2, x1


def kinematics_exact(ga, gb, gc, t1, t2, w1, d1, d2, d3, d4, d5, gravity):
    """The exact beam-fixed kinematics solved for the accelerations, given the rotations.

    ``gravity`` is the g [m/s^2] the sensors read (0 for sensors that do not sense it).
    """
    ga = ga - gravity * np.sin(t1)
    gb = gb - gravity * np.sin(t1)
    gc = gc - gravity * np.sin(t2)
    th1 = (ga - gb) / (d1 - d2)
    x1 = 0.5 * (ga + gb - (d1 + d2) * th1) / np.cos(t1)
    rel = t1 - t2
    o_t = x1 * np.cos(t2) + d3 * (th1 * np.cos(rel) - w1 * w1 * np.sin(rel))
    th2 = (gc - o_t) / (d4 + d5)
    return th1, th2, x1


def torque_002(t1, t2, w1, a1, a2, ax, m2, i2, gravity, d3, d5):
    """Joint torque, paper 002 (8) [N m] (see :func:`fricdamp.signals.identify.joint_torque`)."""
    rel = t1 - t2
    return ((i2 + m2 * d5 * d5) * a2 + m2 * d5 * ax * np.cos(t2)  # 002 (8)
            + m2 * d3 * d5 * (a1 * np.cos(rel) - w1 * w1 * np.sin(rel))
            + m2 * gravity * d5 * np.sin(t2))


def harmonic_mask(n: int, n_periods: int, n_harmonics: int | None) -> np.ndarray:
    """rfft bins of the harmonics 1..n_harmonics of a record of n_periods periods."""
    bins = np.arange(n // 2 + 1)
    keep = (bins % n_periods == 0) & (bins > 0)
    if n % 2 == 0:
        keep[-1] = False  # Nyquist: no phase information
    if n_harmonics is not None:
        keep &= bins <= n_harmonics * n_periods
    return keep


def remove_drift(x, n_periods):
    """Subtract the linear drift estimated from the means of the first and last periods.

    The per-period means of a periodic signal are all equal, so the estimate is exactly zero
    for it (unlike a least-squares line, which correlates with the oscillation) and exactly
    the slope of a linear drift (sensor offset creeping, integration constant).
    """
    n = x.shape[0]
    if n_periods < 2:
        return x
    m = n // n_periods
    slope = (x[n - m:].mean(axis=0) - x[:m].mean(axis=0)) / (n - m)  # per sample
    ramp = (np.arange(n) - 0.5 * (n - 1)).reshape((n,) + (1,) * (x.ndim - 1))
    return x - slope * ramp


def spectral(x, dt, n_periods, mode, n_harmonics, f_low, n_velocity=None):
    """Filter and integrate accelerations ``x`` (n, k) column by column.

    Returns the filtered accelerations (n, k), the first integrals of the first
    ``n_velocity`` columns (n, n_velocity) (default all), the second integrals (n, k), and
    the fraction of the signals' RMS (without the mean, all columns together) that the
    filter removed (drift included).
    """
    from scipy import fft as sfft

    n = x.shape[0]
    x0 = x - x.mean(axis=0)
    total = float(np.sum(x0 * x0))
    x = remove_drift(x, n_periods)
    spec = sfft.rfft(x, axis=0)
    freq = sfft.rfftfreq(n, dt)
    if mode == "harmonic":
        keep = harmonic_mask(n, n_periods, n_harmonics)
    else:
        keep = freq >= max(f_low, 1e-300)
        if n % 2 == 0:
            keep[-1] = False
    spec[~keep] = 0.0
    kept = sfft.irfft(spec, n=n, axis=0)
    residual = float(np.sqrt(np.sum((x0 - kept) ** 2) / total)) if total > 0 else 0.0
    nv = x.shape[1] if n_velocity is None else int(n_velocity)
    if mode == "harmonic":
        iw = np.zeros(freq.size, dtype=complex)
        iw[keep] = 1.0 / (2j * np.pi * freq[keep])
        spec *= iw[:, None]
        vel = sfft.irfft(spec[:, :nv], n=n, axis=0)
        spec *= iw[:, None]
        dis = sfft.irfft(spec, n=n, axis=0)
        return kept, vel, dis, residual
    vel = fft_integrate(x[:, :nv], dt, 1, f_low=f_low)
    dis = fft_integrate(x, dt, 2, f_low=f_low)
    return x - x.mean(axis=0), vel, dis, residual


@dataclass(frozen=True)
class WindowLoop:
    """Processed window: states, loop and energy, each with trailing batch axes ``...``.

    ``theta1``, ``theta2``, ``x1``, ``rotation``, ``torque``: (n, ...); ``theta1_dot``:
    (n, ...); ``acc``: (n, 3, ...) filtered (theta1'', theta2'', x1''); ``energy``: (...)
    loop area per period [J]; ``residual``: float, the filter's removed fraction.
    """

    theta1: np.ndarray
    theta2: np.ndarray
    x1: np.ndarray
    theta1_dot: np.ndarray
    acc: np.ndarray
    rotation: np.ndarray
    torque: np.ndarray
    energy: np.ndarray
    residual: float


def process_window(G, dt, n_periods, geometry, *, positions=None, kinematics="paper",
                   gravity_sensing=False, filter="harmonic", n_harmonics=None, f_low=None,
                   iterations=3) -> WindowLoop:
    """Run the pipeline on a window ``G`` (n, 3, ...) of whole periods of A, B, C [m/s^2].

    ``positions`` (d1, d2, d4) override the geometry's sensor positions (arrays broadcast
    against the trailing axes of ``G``); everything else comes from ``geometry``.
    """
    G = np.asarray(G, dtype=float)
    n = G.shape[0]
    batch = G.shape[2:]
    d1, d2, d4 = ((geometry.sensor_a, geometry.sensor_b, geometry.sensor_c)
                  if positions is None else positions)
    d3, d5 = geometry.joint_arm1, geometry.joint_arm2
    f_low = 0.0 if f_low is None else f_low
    ga, gb, gc = G[:, 0], G[:, 1], G[:, 2]
    acc = np.stack(kinematics_linear(ga, gb, gc, d1, d2, d3, d4, d5), axis=1)

    n_batch = int(np.prod(batch, dtype=int))

    def integrate(a):  # columns (theta1'' x batch, theta2'' x batch, x1'' x batch)
        kept, vel, dis, res = spectral(a.reshape(n, -1), dt, n_periods, filter, n_harmonics,
                                       f_low, n_velocity=n_batch)  # only theta1' is needed
        shape = (n, 3) + batch
        return kept.reshape(shape), vel.reshape((n,) + batch), dis.reshape(shape), res

    a, w1, d, residual = integrate(acc)
    if kinematics == "exact":
        g = geometry.gravity if gravity_sensing else 0.0
        for _ in range(int(iterations)):
            acc = np.stack(kinematics_exact(ga, gb, gc, d[:, 0], d[:, 1], w1, d1, d2, d3,
                                            d4, d5, g), axis=1)
            a, w1, d, residual = integrate(acc)
    t1, t2, x1 = d[:, 0], d[:, 1], d[:, 2]
    tq = torque_002(t1, t2, w1, a[:, 0], a[:, 1], a[:, 2], geometry.beam2_mass,
                    geometry.beam2_inertia, geometry.gravity, d3, d5)
    rot = t1 - t2
    # loop area: trapezoids closed from the last sample to the first (one whole window)
    inc = 0.5 * (tq + np.roll(tq, -1, axis=0)) * (np.roll(rot, -1, axis=0) - rot)
    energy = np.sum(inc, axis=0) / n_periods
    return WindowLoop(t1, t2, x1, w1, a, rot, tq, energy, residual)


def first_harmonic(x, n_periods: int):
    """Amplitude of the fundamental of a window of whole periods along axis 0."""
    n = x.shape[0]
    return 2.0 * np.abs(np.fft.rfft(x, axis=0)[n_periods]) / n
