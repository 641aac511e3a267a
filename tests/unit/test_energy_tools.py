"""Steady cycles, hysteresis loops and dissipated energy; FFT integration; CSV import.

References
----------
- Jenkins element at u = A cos(w t): W = 4 F_s (A - F_s / k_t) (REFERENCES.md).
- Dashpot loop f = c u': W = pi c w A^2.
- FFT integration of a sum of sines holding whole periods in the record: exact to round-off.
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.errors import ModelError
from fricdamp.signals.energy import (
    dissipated_energy_per_cycle,
    hysteresis_loop,
    loop_area,
    peak_strain_energy,
    steady_cycle,
)
from fricdamp.signals.records import fft_integrate, read_signals_csv

# ---------------------------------------------------------------------------------------------
# steady cycles and loops
# ---------------------------------------------------------------------------------------------


def test_steady_cycle_aligned_grid_returns_the_samples():
    dt, period = 1e-3, 0.05  # 50 samples per period
    t = dt * np.arange(1001)
    x = np.sin(2 * np.pi * t / period) + np.exp(-20 * t)
    tc, xc = steady_cycle(t, x, period, n_cycles=2)
    assert tc.size == 100
    np.testing.assert_array_equal(xc, x[-100:])
    np.testing.assert_array_equal(tc, t[-100:])


@pytest.mark.parametrize(("interpolation", "tol"), [("linear", 2e-4), ("cubic", 2e-7)])
def test_steady_cycle_resampled(interpolation, tol):
    """dt does not divide the period: resampling error (h w)^2 / 8 = 1.5e-4 for linear,
    O((h w)^4) (~1e-7) for the cubic spline, h w = 2 pi / 180."""
    period = 0.1
    t = np.arange(0.0, 1.0, period / 180.3)
    x = np.column_stack((np.sin(2 * np.pi * t / period), np.cos(2 * np.pi * t / period)))
    tc, xc = steady_cycle(t, x, period, interpolation=interpolation)
    assert xc.shape == (tc.size, 2)
    assert tc[-1] < t[-1] and tc[0] == pytest.approx(t[-1] - period)
    np.testing.assert_allclose(np.diff(tc), period / tc.size, rtol=1e-9)
    np.testing.assert_allclose(xc[:, 0], np.sin(2 * np.pi * tc / period), atol=tol)


def test_jenkins_energy_per_cycle_with_unaligned_sampling():
    """Drive a Jenkins element through a transient into u = A cos(w t) sampled with a step that
    does not divide the period; the resampled steady loop gives 4 F_s (A - F_s/k_t).

    Linear resampling of the piecewise-linear loop errs only at its corners (two reversal
    points and two slip onsets per cycle), O(h^2) relative: 1e-4 at ~1000 samples per cycle.
    """
    kt, fs, A, f0 = 1000.0, 1.0, 3e-3, 7.0
    w = 2 * np.pi * f0
    t = np.arange(0.0, 5 / f0, 1 / (f0 * 997.3))
    u = A * np.cos(w * t) * (1 - np.exp(-t * 5 * f0))  # grows into the steady state
    f = Jenkins(kt, fs).drive(u)
    energy = dissipated_energy_per_cycle(t, u, f, 1 / f0)
    assert energy == pytest.approx(4 * fs * (A - fs / kt), rel=1e-4)
    ul, fl = hysteresis_loop(t, u, f, 1 / f0, n_cycles=2)
    assert ul.shape == fl.shape and ul.size == 2 * 998
    assert np.max(np.abs(fl)) == pytest.approx(fs, rel=1e-9)


def test_dissipated_energy_vectorised_over_contacts():
    """Two dashpots c = 2, 5 at u = A cos(w t) on an aligned grid: the trapezoidal loop area is
    exactly pi c w A^2 sin(h)/h with h = 2 pi / 400."""
    f0, A = 5.0, 1e-2
    w = 2 * np.pi * f0
    t = np.arange(0.0, 1.0, 1 / (400 * f0))
    u = A * np.cos(w * t)
    c = np.array([2.0, 5.0])
    u2 = np.column_stack((u, u))
    f2 = c * np.column_stack((-A * w * np.sin(w * t),) * 2)
    h = 2 * np.pi / 400
    np.testing.assert_allclose(dissipated_energy_per_cycle(t, u2, f2, 1 / f0, n_cycles=3),
                               np.pi * c * w * A**2 * np.sin(h) / h, rtol=1e-12)


def test_peak_strain_energy_methods_on_a_linear_spring():
    theta = 2 * np.pi * np.arange(64) / 64
    u = 2e-3 * np.cos(theta)
    f = 500.0 * u
    assert peak_strain_energy(u, f) == pytest.approx(0.5 * 500.0 * 4e-6, rel=1e-12)
    assert peak_strain_energy(u, f, method="peak") == pytest.approx(0.5 * 500.0 * 4e-6,
                                                                    rel=1e-12)
    assert loop_area(u, f) == pytest.approx(0.0, abs=1e-18)


def test_energy_errors():
    t = np.linspace(0.0, 1.0, 101)
    with pytest.raises(ModelError, match="shorter"):
        steady_cycle(t, np.sin(t), 2.0)
    with pytest.raises(ModelError, match="strictly increasing"):
        steady_cycle(t[::-1], np.sin(t), 0.1)
    with pytest.raises(ModelError, match="period"):
        steady_cycle(t, np.sin(t), -0.1)
    with pytest.raises(ModelError, match="n_cycles"):
        steady_cycle(t, np.sin(t), 0.1, n_cycles=0)
    with pytest.raises(ModelError, match="same shape"):
        hysteresis_loop(t, np.sin(t), np.sin(t)[:50], 0.1)
    with pytest.raises(ModelError, match="secant stiffness"):
        th = 2 * np.pi * np.arange(100) / 100
        peak_strain_energy(np.cos(th), -np.cos(th))


# ---------------------------------------------------------------------------------------------
# FFT integration
# ---------------------------------------------------------------------------------------------

FREQS = np.array([3.0, 17.0, 30.0, 41.0])  # Hz, whole periods in 2 s
AMPS = np.array([1e-3, 2e-4, 5e-4, 1e-5])
PHASES = np.array([0.1, 1.3, -0.7, 2.2])


def _sines(t, deriv):
    w = 2 * np.pi * FREQS
    arg = np.outer(t, w) + PHASES
    # d^n/dt^n sin = w^n sin(arg + n pi/2)
    return np.sum(AMPS * w**deriv * np.sin(arg + deriv * np.pi / 2), axis=1)


@pytest.mark.parametrize("n", [2000, 2001])  # even (Nyquist bin) and odd lengths
def test_fft_integrate_sum_of_sines(n):
    """Acceleration -> velocity -> displacement to 1e-8 of the displacement amplitude
    (round-off is ~1e-15: the record holds whole periods of every component)."""
    dt = 2.0 / n
    t = dt * np.arange(n)
    acc = _sines(t, 2)
    disp = fft_integrate(acc, dt, order=2)
    vel = fft_integrate(acc, dt, order=1)
    np.testing.assert_allclose(disp, _sines(t, 0), rtol=0, atol=1e-8 * AMPS.max())
    np.testing.assert_allclose(vel, _sines(t, 1), rtol=0,
                               atol=1e-8 * np.max(AMPS * 2 * np.pi * FREQS))
    np.testing.assert_allclose(fft_integrate(vel, dt), disp, rtol=0, atol=1e-8 * AMPS.max())


def test_fft_integrate_high_pass_and_offset():
    """A sensor offset and a 0.5 Hz drift are removed by f_low = 2 Hz; the 3-41 Hz content
    survives unchanged (to 1e-8)."""
    n, dt = 4000, 5e-4
    t = dt * np.arange(n)
    acc = _sines(t, 2) + 0.3 + 0.05 * np.sin(2 * np.pi * 0.5 * t)
    disp = fft_integrate(acc, dt, order=2, f_low=2.0)
    np.testing.assert_allclose(disp, _sines(t, 0), rtol=0, atol=1e-8 * AMPS.max())
    assert abs(np.mean(disp)) < 1e-15


def test_fft_integrate_multichannel_axis():
    n, dt = 1000, 2e-3
    t = dt * np.arange(n)
    acc = np.stack((_sines(t, 2), 2 * _sines(t, 2)))  # (2, n): time on axis 1
    disp = fft_integrate(acc, dt, order=2, axis=1)
    np.testing.assert_allclose(disp[1], 2 * disp[0], rtol=1e-12, atol=1e-20)
    np.testing.assert_allclose(disp[0], _sines(t, 0), atol=1e-8 * AMPS.max())


def test_fft_integrate_errors():
    x = np.ones(16)
    with pytest.raises(ModelError, match="order"):
        fft_integrate(x, 0.01, order=3)
    with pytest.raises(ModelError, match="dt"):
        fft_integrate(x, 0.0)
    with pytest.raises(ModelError, match="f_low"):
        fft_integrate(x, 0.01, f_low=60.0)
    with pytest.raises(ModelError, match="finite"):
        fft_integrate(np.array([1.0, np.inf, 0.0, 1.0]), 0.01)


# ---------------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------------

def test_csv_comma_with_units_in_header(tmp_path):
    p = tmp_path / "a.csv"
    t = np.arange(5) * 1e-3
    acc = np.sin(t * 100) * 9.81
    lines = ["# accelerometers, rig 002", "Time [s],acc_A [m/s^2],force (N)"]
    lines += [f"{ti:.6e},{ai:.12e},{2 * ai:.12e}" for ti, ai in zip(t, acc, strict=True)]
    p.write_text("\n".join(lines) + "\n")
    sig = read_signals_csv(p)
    assert set(sig) == {"time", "acc_A", "force"}
    np.testing.assert_allclose(sig["time"], t)
    np.testing.assert_allclose(sig["acc_A"], acc, rtol=1e-12)
    assert sig.units == {"time": "s", "acc_A": "m/s^2", "force": "N"}
    assert sig.time_column == "Time"


def test_csv_semicolon_decimal_comma_units_row_ms(tmp_path):
    """Typical European lab export: ';' delimiter, decimal comma, units row, time in ms,
    trailing delimiter on every line."""
    p = tmp_path / "b.csv"
    p.write_text("Zeit;theta1;M\nms;rad;N m\n0,0;1,5e-3;-0,25;\n0,5;2,5E-03;0,75;\n"
                 "1,0;-1,0e-3;1,25;\n", encoding="utf-8")
    sig = read_signals_csv(p)
    np.testing.assert_allclose(sig["time"], [0.0, 5e-4, 1e-3])
    np.testing.assert_allclose(sig["theta1"], [1.5e-3, 2.5e-3, -1e-3])
    np.testing.assert_allclose(sig["M"], [-0.25, 0.75, 1.25])
    assert sig.units["theta1"] == "rad" and sig.units["M"] == "N m"
    assert sig.time_column == "Zeit"


def test_csv_tab_and_explicit_time_column(tmp_path):
    p = tmp_path / "c.txt"
    p.write_text("x\tsample_time\n1.0\t0.0\n2.0\t0.1\n3.0\t0.2\n")
    sig = read_signals_csv(p, time_column="sample_time")
    np.testing.assert_allclose(sig["time"], [0.0, 0.1, 0.2])
    np.testing.assert_allclose(sig["x"], [1.0, 2.0, 3.0])
    sig2 = read_signals_csv(p, time_column=1)
    np.testing.assert_allclose(sig2["time"], sig["time"])


def test_csv_errors_name_file_column_and_line(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("time,acc\n0.0,1.0\n0.1,oops\n0.2,3.0\n")
    with pytest.raises(ModelError, match=r"bad\.csv.*line 3.*column 'acc'.*'oops'"):
        read_signals_csv(p)
    p.write_text("time,acc\n0.0,1.0\n0.0,2.0\n")
    with pytest.raises(ModelError, match=r"bad\.csv.*'time'.*strictly increasing.*line 3"):
        read_signals_csv(p)
    p.write_text("time,acc\n0.0,1.0\n0.1,2.0,5.0\n")
    with pytest.raises(ModelError, match=r"line 3: 3 fields, expected 2"):
        read_signals_csv(p)
    p.write_text("time [h],acc\n0.0,1.0\n0.1,2.0\n")
    with pytest.raises(ModelError, match="unit 'h'"):
        read_signals_csv(p)
    assert read_signals_csv(p, time_scale=3600.0)["time"][1] == pytest.approx(360.0)
    with pytest.raises(ModelError, match="no column named 'tau'"):
        read_signals_csv(p, time_column="tau", time_scale=1.0)
    with pytest.raises(ModelError, match="does not exist"):
        read_signals_csv(tmp_path / "missing.csv")
