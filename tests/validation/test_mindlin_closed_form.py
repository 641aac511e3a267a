"""Cattaneo–Mindlin contact against its closed forms (Mindlin & Deresiewicz 1953; Johnson,
Contact Mechanics (1985) §7.3, eqs (7.43)–(7.59); REFERENCES.md).

The law is driven by ``delta = delta* cos(theta)`` with ``delta*`` from the inverted loading
curve, ``delta* = delta_s [1 - (1 - q)^(2/3)]`` for ``T* = q mu N``; the second cycle is
integrated by the trapezoidal rule (``fricdamp.signals.energy.loop_area``). With the
turning points sampled exactly (theta = 0, pi) and smooth branches in between, the rule's
error is ``-(d theta)^2 / 6`` relative for every q (measured: 6.6e-6, 1.6e-6, 4.1e-7 at 1000,
2000, 4000 samples per cycle, a clean second-order sequence); with 4000 samples we allow
1e-6 relative, plus 1e-12 of the largest loop for the closed form's own cancellation at
small q (its bracket is a difference of O(1) terms equal to 5 q^3 / 162).
"""

import numpy as np
import pytest

from fricdamp.contact.mindlin import (
    CattaneoMindlin,
    effective_modulus,
    hertz_radius,
    shear_modulus,
    tangential_compliance,
)
from fricdamp.signals.energy import loop_area

# steel ball R = 5 mm on a steel flat, N = 50 N, mu = 0.3
E, NU, R, NLOAD, MU = 210e9, 0.3, 5e-3, 50.0, 0.3
G = E / (2 * (1 + NU))
C = 2 * (2 - NU) / G                      # REFERENCES.md / Johnson (7.42) compliance
E_STAR = 1 / (2 * (1 - NU**2) / E)
A = (3 * NLOAD * R / (4 * E_STAR)) ** (1 / 3)
DS = 3 * MU * NLOAD * C / (16 * A)
N_CYCLE = 4000


def law():
    return CattaneoMindlin.from_materials(MU, NLOAD, R, E, NU)


def w_closed(q):
    """Energy per cycle, REFERENCES.md (Johnson 7.59 with the compliance C)."""
    return 9 * MU**2 * NLOAD**2 * C / (10 * A) * (
        1 - (1 - q) ** (5 / 3) - 5 * q / 6 * (1 + (1 - q) ** (2 / 3)))


def amplitude(q):
    """Invert the loading curve T = mu N [1 - (1 - delta/delta_s)^(3/2)] at T = q mu N."""
    return DS * (1 - (1 - q) ** (2 / 3))


def steady_loop(amp, n=N_CYCLE):
    theta = np.linspace(0.0, 4 * np.pi, 2 * n + 1)
    u = amp * np.cos(theta)
    f = law().drive(u)
    return u[n:-1], f[n:-1]


def test_factories_reproduce_reference_constants():
    cm = law()
    assert cm.contact_radius[0] == pytest.approx(A, rel=1e-14)
    assert cm.compliance[0] == pytest.approx(C, rel=1e-14)
    assert cm.slip_displacement[0] == pytest.approx(DS, rel=1e-14)
    assert effective_modulus(E, NU, E, NU) == pytest.approx(E_STAR, rel=1e-14)
    assert tangential_compliance(shear_modulus(E, NU), NU, G, NU) == pytest.approx(C, rel=1e-14)
    assert hertz_radius(NLOAD, R, E_STAR) == pytest.approx(A, rel=1e-14)


@pytest.mark.parametrize("q", [0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.95])
def test_energy_per_cycle_closed_form(q):
    u, f = steady_loop(amplitude(q))
    W = loop_area(u, f)
    assert W == pytest.approx(w_closed(q), rel=1e-6, abs=1e-12 * w_closed(1.0))
    assert f.max() == pytest.approx(q * MU * NLOAD, rel=1e-12)  # the loop tip is T*


@pytest.mark.parametrize("q", [0.005, 0.01, 0.02, 0.05])
def test_small_amplitude_cubic_law(q):
    """W ~ C T*^3 / (36 a mu N) (micro-slip signature). The exact ratio is
    1 + 2q/3 + 7q^2/15 + O(q^3) (series of the closed form); we check the traced loop
    against the first two terms within q^2 (the third term is 0.47 q^2; the sampling
    error 4e-7 is below q^2 for q >= 0.005)."""
    tstar = q * MU * NLOAD
    u, f = steady_loop(amplitude(q))
    ratio = loop_area(u, f) / (C * tstar**3 / (36 * A * MU * NLOAD))
    assert abs(ratio - (1 + 2 * q / 3)) < q**2


def test_unloading_branch_shape():
    """Points of the traced unloading branch satisfy delta(T) of REFERENCES.md:
    delta = delta_s [2 (1 - (T* - T)/(2 mu N))^(2/3) - (1 - q)^(2/3) - 1]."""
    q = 0.8
    u, f = steady_loop(amplitude(q), n=2000)
    down = slice(1, 1000)  # theta in (0, pi): unloading from +T*
    d_expect = DS * (2 * (1 - (q * MU * NLOAD - f[down]) / (2 * MU * NLOAD)) ** (2 / 3)
                     - (1 - q) ** (2 / 3) - 1)
    np.testing.assert_allclose(u[down], d_expect, rtol=0, atol=1e-11 * DS)


def test_initial_tangential_stiffness_finite_difference():
    """dT/d delta at 0 = 8 a / C (Mindlin 1949; Johnson 7.44). One-sided FD from the virgin
    state: T(h)/h = (8a/C)(1 - h/(4 delta_s) + ...), so h = 1e-8 delta_s gives 3e-9."""
    cm = law()
    h = 1e-8 * DS
    t_h = cm.step(cm.initial_state(), [h]).force[0, 0]
    assert t_h / h == pytest.approx(8 * A / C, rel=1e-8)
    assert cm.step(cm.initial_state(), [0.0]).stiffness[0, 0, 0] == pytest.approx(8 * A / C,
                                                                                  rel=1e-14)


@pytest.mark.parametrize("ratio", [1.2, 2.0, 10.0])
def test_gross_slip_limit(ratio):
    """Beyond delta_s every cycle reaches |T| = mu N. Each reversal follows the Masing
    branch for 2 delta_s, area deficit 2 * 2 mu N * 2 delta_s * int_0^1 (1-y)^3/2 dy:
    W = 4 mu N (delta* - 0.8 delta_s), continuous with W(q = 1) = 0.8 mu N delta_s."""
    amp = ratio * DS
    u, f = steady_loop(amp)
    assert f.max() == pytest.approx(MU * NLOAD, rel=1e-14)
    assert f.min() == pytest.approx(-MU * NLOAD, rel=1e-14)
    W = loop_area(u, f)
    assert W == pytest.approx(4 * MU * NLOAD * (amp - 0.8 * DS), rel=1e-6)
    assert 4 * MU * NLOAD * (DS - 0.8 * DS) == pytest.approx(w_closed(1.0), rel=1e-14)


def test_energy_balance_dissipation_equals_loop_area():
    """Dissipation = work - stored-energy change over the second cycle equals the closed
    form (the stored energy is a state function: its change over a closed cycle is 0)."""
    q = 0.6
    amp = amplitude(q)
    cm = law()
    theta = np.linspace(0.0, 4 * np.pi, 2 * N_CYCLE + 1)
    u = amp * np.cos(theta)
    f, st1 = cm.march(u[:N_CYCLE + 1, None, None])
    e1 = cm.stored_energy(st1, [u[N_CYCLE]])[0]
    f2, st2 = cm.march(u[N_CYCLE:, None, None], state=st1)
    e2 = cm.stored_energy(st2, [u[-1]])[0]
    uu, ff = u[N_CYCLE:], f2[:, 0, 0]
    work = np.sum(0.5 * (ff[1:] + ff[:-1]) * np.diff(uu))
    assert e2 == pytest.approx(e1, rel=1e-13)
    assert work - (e2 - e1) == pytest.approx(w_closed(q), rel=1e-6)
