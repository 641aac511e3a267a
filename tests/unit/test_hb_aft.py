"""AFT building blocks: harmonic basis, cycle work, periodic contact response and its Jacobian.

References: the real Fourier series identities (exact for trigonometric polynomials of degree
< N sampled at N points); the Jenkins first-harmonic closed form (REFERENCES.md, "Jenkins
element": a1, b1 and W = 4 F_s (A - F_s/k_t)).
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.contact.base import ContactLaw, LawStep
from fricdamp.errors import ModelError
from fricdamp.solvers.aft import HarmonicBasis, aft, cycle_work
from fricdamp.structure import ContactElement


class _PythonJenkins(ContactLaw):
    """Jenkins through the generic protocol only (no specialised periodic_response)."""

    def __init__(self, kt, fs):
        self._j = Jenkins(kt, fs)
        self.n_contacts = self._j.n_contacts

    def initial_state(self):
        return self._j.initial_state()

    def step(self, state, u, v=None) -> LawStep:
        return self._j.step(state, u, v)

    def stored_energy(self, state, u):
        return self._j.stored_energy(state, u)


def _random_coeffs(rng, n, H, scale):
    x = rng.normal(size=(n, 2 * H + 1)) * scale
    x[:, 3:] *= 0.3   # decaying higher harmonics, like a real response
    return x


def test_basis_round_trip_and_derivative():
    """analysis o synthesis = identity; derivative matches d/dtau of the series (exact)."""
    b = HarmonicBasis.create(5, 32)
    np.testing.assert_allclose(b.analysis @ b.synthesis, np.eye(11), atol=1e-14)
    c = np.random.default_rng(0).normal(size=11)
    np.testing.assert_allclose(b.derivative @ c, b.synthesis @ (b.d_dtau @ c), atol=1e-13)
    # derivative by central differences on a fine grid
    fine = b.to_time(c, 4096)
    dfd = (np.roll(fine, -1) - np.roll(fine, 1)) / (2 * 2 * np.pi / 4096)
    np.testing.assert_allclose(dfd[::128], b.derivative @ c, atol=2e-5 * np.abs(c).sum() * 25)


@pytest.mark.parametrize("H, N", [(0, 16), (3, 6), (2.5, 16), (3, 6.5)])
def test_basis_rejects_bad_sizes(H, N):
    with pytest.raises(ModelError, match="harmonics|samples"):
        HarmonicBasis.create(H, N)


def test_default_samples():
    assert HarmonicBasis.create(7).samples == 128
    assert HarmonicBasis.create(1).samples == 16


def test_cycle_work_equals_trapezoid_on_samples():
    """W = pi sum k (A_k b_k - B_k a_k) equals the sampled loop integral oint f dx."""
    rng = np.random.default_rng(1)
    b = HarmonicBasis.create(4, 64)
    x = rng.normal(size=9)
    f_samples = rng.normal(size=64)          # any periodic samples (aliasing included)
    F = b.analysis @ f_samples
    xdot = b.derivative @ x
    W_trap = np.sum(f_samples * xdot) * 2 * np.pi / 64
    assert cycle_work(x, F) == pytest.approx(W_trap, rel=1e-12)


@pytest.mark.parametrize("A", [0.5e-3, 1.5e-3, 4e-3, 0.02])
def test_jenkins_first_harmonic_closed_form(A):
    """AFT of u = A cos tau: a1, b1 and the loop area against REFERENCES.md.

    The force is piecewise linear in tau with one kink per half period at the stick-to-slip
    transition; the DFT of N samples integrates it with error O((2 pi / N)^2) relative: with
    N = 2048, tolerance 2e-5 of k_t A.
    """
    kt, fs = 1000.0, 1.0
    b = HarmonicBasis.create(3, 2048)
    c = ContactElement(Jenkins(kt, fs), [[1.0]])
    U = np.zeros((1, 7))
    U[0, 1] = A
    res = aft([c], U, 1.0, b, jacobian=False)
    if A <= fs / kt:
        a1, b1, W = kt * A, 0.0, 0.0
    else:
        th = np.arccos(1 - 2 * fs / (kt * A))
        a1 = kt * A / np.pi * (th - 0.5 * np.sin(2 * th))
        b1 = -4 * fs / np.pi * (1 - fs / (kt * A))
        W = 4 * fs * (A - fs / kt)
    # f = a1 cos(theta) + b1 sin(theta): b1 < 0, the force lags the displacement
    assert res.force[0, 1] == pytest.approx(a1, abs=2e-5 * kt * A)
    assert res.force[0, 2] == pytest.approx(b1, abs=2e-5 * kt * A)
    assert cycle_work(U, res.force)[0] == pytest.approx(W, abs=2e-4 * kt * A**2)
    assert cycle_work(U, res.force)[0] >= -1e-15     # never generates energy


def test_jenkins_exact_sensitivity_matches_generic_finite_differences():
    """The compiled anchor sensitivity agrees with forward differences of the generic march."""
    rng = np.random.default_rng(3)
    b = HarmonicBasis.create(4, 64)
    kt = np.array([1e3, 1e3, 2e3, 1e3, 1e3])
    fs = np.array([1.0, 1.0, 0.5, 0.0, 50.0])   # slip, slip, slip, frictionless, stuck
    x = _random_coeffs(rng, 5, 4, 1e-3)
    x[1, 0] = 8e-3                              # large static offset: slips only at first
    u = (b.synthesis @ x.T)[:, :, None]
    law = Jenkins(kt, fs)
    exact = law.periodic_response(u, basis=b.synthesis)
    generic = ContactLaw.periodic_response(law, u, basis=b.synthesis)
    assert exact.converged and generic.converged
    np.testing.assert_allclose(exact.force, generic.force, atol=1e-14)
    np.testing.assert_allclose(exact.state, generic.state, atol=1e-15)
    scale = np.abs(exact.jacobian).max()
    np.testing.assert_allclose(exact.jacobian, generic.jacobian, atol=1e-6 * scale)
    assert exact.periods <= 3


def test_generic_law_in_aft_matches_specialised():
    """A law with only step() goes through the generic path with the same forces/Jacobian."""
    rng = np.random.default_rng(4)
    b = HarmonicBasis.create(3, 64)
    x = _random_coeffs(rng, 3, 3, 2e-3)
    spec = ContactElement(Jenkins([1e3, 2e3, 5e2], [1.0, 0.7, 0.2]), np.eye(3))
    gen = ContactElement(_PythonJenkins([1e3, 2e3, 5e2], [1.0, 0.7, 0.2]), np.eye(3))
    r1 = aft([spec], x, 2.0, b)
    r2 = aft([gen], x, 2.0, b)
    np.testing.assert_allclose(r1.force, r2.force, atol=1e-13)
    np.testing.assert_allclose(r1.jacobian[0], r2.jacobian[0], atol=1e-6 * 2e3)


def test_aft_jacobian_is_derivative_of_force_harmonics():
    """Central differences of the harmonic force w.r.t. each coefficient (away from kinks)."""
    rng = np.random.default_rng(5)
    b = HarmonicBasis.create(3, 128)
    x = _random_coeffs(rng, 2, 3, 3e-3)
    c = ContactElement(Jenkins([1e3, 3e3], [1.0, 2.0]), np.eye(2))
    J = aft([c], x, 1.0, b).jacobian[0]
    h = 1e-10
    for cc in range(2):
        for j in range(7):
            e = np.zeros_like(x)
            e[cc, j] = h
            fd = (aft([c], x + e, 1.0, b, jacobian=False).force[cc]
                  - aft([c], x - e, 1.0, b, jacobian=False).force[cc]) / (2 * h)
            np.testing.assert_allclose(J[cc][:, j], fd, atol=1e-4 * 3e3)


def test_periodic_response_reports_non_periodic_law():
    """A law whose state never repeats (a ratchet) is flagged converged=False."""

    class Ratchet(ContactLaw):
        n_contacts = 1

        def initial_state(self):
            return np.zeros((1, 1))

        def step(self, state, u, v=None):
            s = state + 1.0
            return LawStep(np.asarray(u).reshape(1, 1) + s, np.ones((1, 1, 1)), None, s)

        def stored_energy(self, state, u):
            return np.zeros(1)

    r = Ratchet().periodic_response(np.zeros((8, 1, 1)), max_periods=4)
    assert not r.converged and r.periods == 4
