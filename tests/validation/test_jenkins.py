"""Jenkins element against its closed form (den Hartog 1931; Iwan 1966; REFERENCES.md).

W = 4 F_s (A - F_s/k_t) for A > F_s/k_t, W = 0 below. The numerical loop is traced at 4000
samples per cycle and integrated by the trapezoidal rule; the force is piecewise linear in u
with kinks at the reversal points (sampled exactly at theta = 0, pi), so the only error is the
corner where slip starts, of order (2 pi / 4000)^2 relative: tolerance 1e-5.
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.signals.energy import loop_area


def _steady_loop(law, amplitude, n=4000):
    theta = np.linspace(0.0, 4 * np.pi, 2 * n + 1)
    u = amplitude * np.cos(theta)
    f = law.drive(u)
    return u[n:], f[n:]  # second cycle: steady


@pytest.mark.parametrize("amplitude", [1.5e-3, 2e-3, 5e-3, 0.05])
def test_energy_per_cycle_closed_form(amplitude):
    kt, fs = 1000.0, 1.0  # F_s / k_t = 1e-3 m
    u, f = _steady_loop(Jenkins(kt, fs), amplitude)
    W = loop_area(u, f)
    W_exact = 4 * fs * (amplitude - fs / kt)
    assert W == pytest.approx(W_exact, rel=1e-5)


def test_below_slip_limit_no_dissipation():
    u, f = _steady_loop(Jenkins(1000.0, 1.0), 0.9e-3)
    assert abs(loop_area(u, f)) < 1e-12
    np.testing.assert_allclose(f, 1000.0 * u, atol=1e-12)


def test_maximum_dissipation_at_half_stuck_force():
    """At fixed A, W is largest at F_s = k_t A / 2 with W_max = k_t A^2 (REFERENCES.md)."""
    kt, A = 1000.0, 2e-3
    fs_grid = np.linspace(0.05, 1.95, 39)
    W = [loop_area(*_steady_loop(Jenkins(kt, fs), A, n=1000)) for fs in fs_grid]
    assert fs_grid[int(np.argmax(W))] == pytest.approx(kt * A / 2, abs=0.026)
    assert max(W) == pytest.approx(kt * A**2, rel=1e-3)


def test_vectorised_contacts_match_single():
    kt = np.array([1e3, 2e3, 5e3])
    fs = np.array([1.0, 0.5, 2.0])
    theta = np.linspace(0, 4 * np.pi, 801)
    u = np.outer(np.cos(theta), [2e-3, 1e-3, 3e-3])
    f = Jenkins(kt, fs).drive(u)
    for j in range(3):
        np.testing.assert_allclose(f[:, j], Jenkins(kt[j], fs[j]).drive(u[:, j]), rtol=0,
                                   atol=1e-14)
