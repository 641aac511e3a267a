"""Four-parameter Iwan law (fricdamp.contact.iwan): Segalman's closed forms, the protocol,
and use by the solvers.

References: Segalman (2005), J. Appl. Mech. 72, 752-760: ``K_T = int rho``, ``F_S = int rho
phi`` and the micro-slip dissipation ``E_d = 4 R A^(3+chi) / ((chi+2)(chi+3))`` for a
symmetric cycle of amplitude ``A <= phi_max``; den Hartog's ``4 F (A - F/k)`` per Jenkins
element.
"""

import numpy as np
import pytest

from fricdamp.contact import Iwan, Jenkins
from fricdamp.contact.base import ContactLaw
from fricdamp.errors import ModelError
from fricdamp.signals.energy import loop_area
from fricdamp.solvers.hb import harmonic_balance
from fricdamp.solvers.timestep import simulate
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem


@pytest.mark.parametrize("chi, beta", [(-0.8, 0.0), (-0.5, 0.3), (-0.2, 2.0), (0.0, 0.5)])
def test_stiffness_slip_force_and_density(chi, beta):
    law = Iwan(2e6, 15.0, chi, beta)
    assert law.element_stiffness.sum() == pytest.approx(2e6, rel=1e-12)
    assert law.element_slip_force.sum() == pytest.approx(15.0, rel=1e-12)
    pm, R, S = law.phi_max[0], law.density_coefficient[0], law.dirac_stiffness[0]
    # Segalman's definitions: K_T = R pm^(chi+1)/(chi+1) + S, F_S = R pm^(chi+2)/(chi+2) + S pm
    assert R * pm ** (chi + 1) / (chi + 1) + S == pytest.approx(2e6, rel=1e-12)
    assert R * pm ** (chi + 2) / (chi + 2) + S * pm == pytest.approx(15.0, rel=1e-12)
    assert S == pytest.approx(beta * R * pm ** (chi + 1) / (chi + 1), rel=1e-12, abs=1e-9)


@pytest.mark.parametrize("chi", [-0.8, -0.5, -0.2, 0.0])
def test_microslip_energy_power_law(chi):
    """E_d ~ A^(3 + chi): the least-squares exponent over 30 min_ratio phi_max .. phi_max
    (2.5 decades) is 3 + chi to 1e-4, and E_d is within 0.6 % of the closed form (the
    discrete law is piecewise linear between its 100 elements' slip displacements)."""
    law = Iwan(1e6, 10.0, chi, 0.3)
    pm = law.phi_max[0]
    A = pm * np.geomspace(30 * law.min_ratio, 1.0, 200)
    e = law.discrete_energy(A)[:, 0]
    exponent = np.polyfit(np.log(A), np.log(e), 1)[0]
    assert exponent == pytest.approx(3 + chi, abs=1e-4)
    closed = 4 * law.density_coefficient[0] * A ** (chi + 3) / ((chi + 2) * (chi + 3))
    np.testing.assert_allclose(law.continuum_energy(A)[:, 0], closed, rtol=1e-12)
    np.testing.assert_allclose(e, closed, rtol=6e-3)


@pytest.mark.parametrize("amp_ratio", [0.01, 0.3, 1.0, 5.0])
def test_marched_loop_area_is_the_closed_form(amp_ratio):
    """The law marched through a symmetric cycle (after a first loading) encloses the
    den Hartog sum of its elements: trapezoidal rule, 4000 samples, tolerance 1e-5; in gross
    slip it tends to 4 F_S (A - F_S/K_T')."""
    law = Iwan(1e6, 10.0, -0.5, 0.3)
    A = amp_ratio * law.phi_max[0]
    n = 4000
    cyc = A * np.cos(2 * np.pi * np.arange(n) / n)
    u = np.concatenate((A * np.sin(np.linspace(0, np.pi / 2, 300)), cyc, cyc))
    f = law.drive(u)
    assert loop_area(u[-n:], f[-n:]) == pytest.approx(law.discrete_energy(A)[0], rel=1e-5)
    assert law.discrete_energy(A)[0] == pytest.approx(law.continuum_energy(A)[0], rel=6e-3)
    if amp_ratio > 1:
        assert np.max(np.abs(f[-n:])) == pytest.approx(10.0, rel=1e-9)  # macro-slip


def test_step_march_tangent_and_energy_balance():
    law = Iwan([1e6, 3e5], [10.0, 2.0], [-0.5, -0.7], [0.3, 0.0], n_elements=40)
    rng = np.random.default_rng(1)
    u = np.cumsum(rng.normal(scale=4e-6, size=(100, 2, 1)), axis=0)
    f_march, w_march = law.march(u)
    st = law.initial_state()
    for i in range(u.shape[0]):
        r = law.step(st, u[i])
        np.testing.assert_allclose(r.force, f_march[i], rtol=1e-12, atol=1e-12)
        # tangent = finite difference from the same state, inside the step's regime
        h = 1e-13
        fd = (law.step(st, u[i] + h).force - law.step(st, u[i] - h).force) / (2 * h)
        np.testing.assert_allclose(r.stiffness[:, :, 0], fd, rtol=1e-4, atol=1.0)
        st = r.state
    np.testing.assert_allclose(st, w_march, atol=1e-18)


def test_work_is_stored_plus_dissipated():
    """Along a fine random path: the trapezoidal work equals the stored energy plus the
    law's own dissipation (friction force x slider travel) to 3e-3 (the trapezoidal rule
    across the slip onsets of the elements)."""
    law = Iwan([1e6, 3e5], [10.0, 2.0], [-0.5, -0.7], [0.3, 0.0], n_elements=40)
    rng = np.random.default_rng(2)
    u = np.cumsum(rng.normal(scale=3e-8, size=(20000, 2)), axis=0)
    u = 2e-5 * np.sin(np.linspace(0, 9, u.shape[0]))[:, None] + u
    st = law.initial_state()
    dissipated = np.zeros(2)
    forces = np.empty_like(u)
    for i in range(u.shape[0]):
        r = law.step(st, u[i])
        dissipated += law.dissipation(st, r.state, r.force)
        forces[i] = r.force[:, 0]
        st = r.state
    du = np.diff(np.vstack((np.zeros((1, 2)), u)), axis=0)
    fm = 0.5 * (forces + np.vstack((np.zeros((1, 2)), forces[:-1])))
    work = np.sum(fm * du, axis=0)
    np.testing.assert_allclose(work, law.stored_energy(st, u[-1]) + dissipated, rtol=3e-3)
    assert np.all(dissipated > 0.1 * work)


def test_periodic_response_and_exact_jacobian():
    """The exact sensitivity (Jenkins anchors summed over the elements) equals the generic
    finite-difference one of ContactLaw.periodic_response (1e-5)."""
    law = Iwan([1e6, 2e6], [10.0, 5.0], [-0.5, -0.3], [0.3, 1.0], n_elements=30)
    nt = 64
    tau = 2 * np.pi * np.arange(nt) / nt
    basis = np.column_stack([np.ones(nt), np.cos(tau), np.sin(tau), np.cos(2 * tau),
                             np.sin(2 * tau)])
    x = np.array([[0.0, 8e-6, 3e-6, 1e-6, 0.0], [0.0, 2e-6, 0.0, 0.0, 5e-7]])
    u = (basis @ x.T)[:, :, None]
    exact = law.periodic_response(u, basis=basis)
    generic = ContactLaw.periodic_response(law, u, basis=basis)
    assert exact.converged and generic.converged
    np.testing.assert_allclose(exact.force, generic.force, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(exact.jacobian, generic.jacobian, rtol=1e-5,
                               atol=1e-5 * np.abs(exact.jacobian).max())


def _oscillator(law):
    return MechanicalSystem(M=[[1.0]], K=[[4e5]], D=[[200.0]],
                            contacts=(ContactElement(law, [[1.0]]),),
                            loads=(HarmonicLoad([3.0], omega=1.0),))


def test_harmonic_balance_equals_parallel_jenkins_and_time_integration():
    """Every solver takes the law: harmonic balance with Iwan equals harmonic balance with
    its elements as separate Jenkins contacts (1e-8), and a Newmark time integration
    reaches the same steady amplitude (1 %)."""
    law = Iwan(1e6, 2.0, -0.5, 0.3, n_elements=20)
    jen = Jenkins(law.element_stiffness[0, :-1], law.element_slip_force[0, :-1])
    dirac = Jenkins(law.element_stiffness[0, -1], law.element_slip_force[0, -1])
    w = 1.15 * np.sqrt(1.4e6)
    par = MechanicalSystem(M=[[1.0]], K=[[4e5]], D=[[200.0]],
                           contacts=(ContactElement(jen, np.ones((20, 1))),
                                     ContactElement(dirac, [[1.0]])),
                           loads=(HarmonicLoad([3.0], omega=1.0),))
    a = harmonic_balance(_oscillator(law), w, harmonics=7, samples=128)
    b = harmonic_balance(par, w, harmonics=7, samples=128)
    assert a.success and b.success
    np.testing.assert_allclose(a.coefficients, b.coefficients,
                               atol=1e-8 * np.abs(b.coefficients).max())
    assert a.dissipated_energy[0] > 0
    period = 2 * np.pi / w
    sys_t = MechanicalSystem(M=[[1.0]], K=[[4e5]], D=[[200.0]],
                             contacts=(ContactElement(law, [[1.0]]),),
                             loads=(HarmonicLoad([3.0], omega=w),))
    res = simulate(sys_t, 40 * period, period / 100, progress=False)
    q = res.q[0, -500:] if res.q.shape[0] == 1 else res.q[-500:, 0]
    amp_t = 0.5 * np.ptp(q)
    amp_hb = np.max(np.abs(np.fft.irfft(np.r_[0, a.coefficients[0, 1::2] - 1j
                                              * a.coefficients[0, 2::2]], 512) * 256))
    assert amp_t == pytest.approx(amp_hb, rel=0.01)


@pytest.mark.parametrize("kwargs, word", [
    ({"stiffness": -1.0}, "stiffness"),
    ({"slip_force": 0.0}, "slip_force"),
    ({"chi": -1.0}, "chi"),
    ({"chi": 1.5}, "chi"),
    ({"beta": -0.1}, "beta"),
    ({"n_elements": 1}, "n_elements"),
    ({"min_ratio": 1.0}, "min_ratio"),
    ({"stiffness": [1.0, 2.0], "slip_force": [1.0, 2.0, 3.0]}, "inconsistent"),
])
def test_bad_parameters_are_named(kwargs, word):
    args = dict(stiffness=1e6, slip_force=1.0, chi=-0.5, beta=0.1)
    args.update(kwargs)
    with pytest.raises(ModelError, match=word):
        Iwan(**args)
