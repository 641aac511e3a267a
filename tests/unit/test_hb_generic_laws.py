"""Harmonic balance with contact laws that have no specialised AFT method.

These laws go through the generic ``ContactLaw.periodic_response`` (march until periodic,
forward-difference sensitivities). References:

- Contact3D with the normal motion frozen by a static load and one tangential direction
  moving is a Jenkins element with slip force ``mu N`` (N = the static normal force): the
  HB solutions agree to the Newton tolerance (1e-9 relative).
- Cattaneo-Mindlin under ``delta = A cos tau``: energy per cycle
  ``W = (9 mu^2 N^2 C / (10 a)) [1 - (1 - q)^(5/3) - (5q/6)(1 + (1 - q)^(2/3))]`` with
  ``q = T*/(mu N)`` (REFERENCES.md); the AFT work equals it to 1e-8 (the Masing branches are
  exact functions of the samples; T* is read from the samples at the reversal tau = 0).
- Velocity-dependent Coulomb friction (paper 003 mu(v)): analytic-by-differences Jacobian
  and dR/dOmega against central differences of the residual.
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.solvers import hb
from fricdamp.solvers.aft import HarmonicBasis, aft, cycle_work
from fricdamp.solvers.hb import frequency_response, harmonic_balance
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem

element3d = pytest.importorskip("fricdamp.contact.element3d")
mindlin = pytest.importorskip("fricdamp.contact.mindlin")
coulomb = pytest.importorskip("fricdamp.contact.coulomb")

M3, K3, D3 = np.eye(3), np.eye(3), 0.02 * np.eye(3)


def test_contact3d_reduces_to_jenkins():
    law = element3d.Contact3D(50.0, 1.0, 0.03)
    sys3 = MechanicalSystem(M=M3, K=K3, D=D3, contacts=(ContactElement(law, np.eye(3)),),
                            static_load=[1.0, 0.0, 0.0],
                            loads=(HarmonicLoad([0.0, 0.05, 0.0], omega=1.0),))
    n_static = 1.0 * 50.0 / 51.0      # k_n u_n with (K + k_n) u_n = 1
    sys1 = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
                            contacts=(ContactElement(Jenkins(1.0, 0.03 * n_static), [[1.0]]),),
                            loads=(HarmonicLoad([0.05], omega=1.0),))
    for w in (0.8, 1.2, 1.5):
        a = harmonic_balance(sys3, w, harmonics=5, samples=64)
        b = harmonic_balance(sys1, w, harmonics=5, samples=64)
        assert a.success and b.success
        np.testing.assert_allclose(a.coefficients[1], b.coefficients[0],
                                   atol=1e-9 * np.abs(b.coefficients).max())
        assert a.dissipated_energy[0] == pytest.approx(b.dissipated_energy[0], rel=1e-8)


def test_contact3d_variable_normal_load_frequency_response():
    """Normal forcing modulates mu N; 2D tangential orbit: the curve completes and every
    point balances energy (the contact stays closed: normal amplitude << static indent)."""
    law = element3d.Contact3D(50.0, 1.0, 0.03)
    sysm = MechanicalSystem(M=M3, K=K3, D=D3, contacts=(ContactElement(law, np.eye(3)),),
                            static_load=[1.0, 0.0, 0.0],
                            loads=(HarmonicLoad([0.2, 0.05, 0.02j], omega=1.0),))
    fr = frequency_response(sysm, 0.6, 2.0, harmonics=5, samples=64)
    assert fr.success, fr.message
    assert np.all(fr.energy_balance_error < 1e-3)
    assert fr.dissipated_energy.max() > 1e-3
    assert fr.amplitude[:, 0].max() < 1.0 / 51.0       # never opens


@pytest.mark.parametrize("A", [1e-7, 2e-7, 3e-7])
def test_mindlin_energy_per_cycle(A):
    mu, N, a, C = 0.5, 10.0, 1e-4, 4e-11
    law = mindlin.CattaneoMindlin(mu=mu, normal_load=N, contact_radius=a, compliance=C)
    b = HarmonicBasis.create(1, 4096)
    U = np.array([[0.0, A, 0.0]])
    res = aft([ContactElement(law, [[1.0]])], U, 1.0, b, jacobian=False)
    q = res.f_time[0, 0] / (mu * N)       # tau = 0 is the reversal at +A
    W = 9 * mu**2 * N**2 * C / (10 * a) * (1 - (1 - q) ** (5 / 3)
                                          - 5 * q / 6 * (1 + (1 - q) ** (2 / 3)))
    assert cycle_work(U, res.force)[0] == pytest.approx(W, rel=1e-8)
    assert res.converged


def test_velocity_dependent_coulomb_jacobian():
    law = coulomb.Coulomb(1.0, 1.0, 0.06, 0.04, decay=4.0)
    assert law.velocity_dependent
    M = np.diag([1.0, 2.0])
    K = np.array([[3.0, -1.0], [-1.0, 2.0]])
    sysm = MechanicalSystem(M=M, K=K, D=0.01 * K,
                            contacts=(ContactElement(law, [[1.0, 0.0]]),),
                            loads=(HarmonicLoad([0.1, 0.0], omega=1.0),))
    s = hb._Setup(sysm, 3, 64)
    for form in (hb._Full(s), hb._Condensed(s, "modal")):
        x = np.random.default_rng(0).normal(size=form.N) * 0.2
        r, J, dr, _, _ = form.evaluate(x, 1.1)
        h = 1e-7
        Jfd = np.empty_like(J)
        for j in range(form.N):
            e = np.zeros(form.N)
            e[j] = h
            Jfd[:, j] = (form.evaluate(x + e, 1.1, jacobian=False)[0]
                         - form.evaluate(x - e, 1.1, jacobian=False)[0]) / (2 * h)
        drfd = (form.evaluate(x, 1.1 + h, jacobian=False)[0]
                - form.evaluate(x, 1.1 - h, jacobian=False)[0]) / (2 * h)
        np.testing.assert_allclose(J, Jfd, atol=1e-6 * np.abs(J).max())
        np.testing.assert_allclose(dr, drfd, atol=1e-6 * np.abs(dr).max())


def test_mixed_contact_elements():
    """Two elements (2 Jenkins contacts, 1 Contact3D): per-contact energies add up to the
    energy balance, full and condensed formulations agree."""
    n = 5
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0] += 1.0
    sysm = MechanicalSystem(
        M=np.eye(n), K=K, D=0.02 * K + 0.01 * np.eye(n),
        contacts=(ContactElement(Jenkins([0.5, 0.8], [0.02, 0.03]),
                                 np.eye(n)[[1, 4]], name="j"),
                  ContactElement(element3d.Contact3D(20.0, 0.6, 0.1),
                                 np.eye(n)[[2, 3, 0]], name="c3")),
        static_load=[0.0, 0.0, 0.5, 0.0, 0.0],
        loads=(HarmonicLoad([0.1, 0.0, 0.0, 0.3, 0.2j], omega=1.0),))
    a = harmonic_balance(sysm, 0.7, harmonics=3, samples=64, method="full")
    b = harmonic_balance(sysm, 0.7, harmonics=3, samples=64, method="condensed")
    assert a.success and b.success
    assert a.contact_names == ("j[0]", "j[1]", "c3")
    assert a.dissipated_energy.shape == (3,)
    assert a.dissipated_energy[0] < 1e-15 < a.dissipated_energy[1]    # stuck / slipping
    assert a.dissipated_energy[2] > 1e-3
    assert a.energy_balance_error < 1e-6
    np.testing.assert_allclose(a.coefficients, b.coefficients,
                               atol=1e-8 * np.abs(a.coefficients).max())
