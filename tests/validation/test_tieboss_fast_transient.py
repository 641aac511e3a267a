"""The compiled Contact3D transient (fricdamp.solvers.fast_transient) against the general
solver, energy conservation, and the static contact solver.

References: :func:`fricdamp.solvers.timestep.simulate` integrates the same discrete
equations (Newmark/HHT with Newton condensed on the contacts), so histories must agree to
the Newton tolerance: the residual test ``max|g| <= 1e-10 max|u|`` leaves ~1e-10 relative
per step, which a 1000-step run with friction switching amplifies to < 1e-7 of the
amplitude (measured 1e-9 to 1e-8). Newmark conserves the energy of the linear part exactly,
so the energy residual measures only the contact integration (break-away drops and
opening/closing within a step): bounded by 1e-3 of the energy scale here (measured 2e-4).
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import build_sector, build_wheel
from fricdamp.models.tieboss_wheel.studies import initial_deformation
from fricdamp.solvers.fast_transient import integrate_contact3d, solve_static
from fricdamp.solvers.timestep import simulate
from fricdamp.structure.system import ContactElement, HarmonicLoad, MechanicalSystem


@pytest.fixture(scope="module")
def wheel():
    return build_wheel(build_sector(rotation=False), n_modes=0)    # 450 DOFs, 30 contacts


@pytest.fixture(scope="module")
def start(wheel):
    return initial_deformation(wheel, 6, 5e-4)


@pytest.mark.parametrize("chord", [True, False])
def test_fast_path_equals_simulate_on_the_wheel(wheel, start, chord):
    """1000 Newmark steps of the 6ND free decay of the CB wheel with 30 kinetic mu(v)
    contacts, from the static initial deformation (virgin contacts loaded in one step in
    both solvers): displacements, contact forces and energies agree."""
    t_end, dt = 0.01, 1e-5
    ref = simulate(wheel.system, t_end, dt, q0=start.q0, progress=False)
    out = np.arange(0, wheel.n_dof, 7)
    res = integrate_contact3d(wheel.system, t_end, dt, q0=start.q0, output_dofs=out,
                              chord=chord)
    amp = np.abs(ref.q[:, out]).max()
    np.testing.assert_allclose(res.q, ref.q[:, out], rtol=0, atol=1e-7 * amp)
    fscale = np.abs(ref.contact_force[0]).max()
    np.testing.assert_allclose(res.contact_force, ref.contact_force[0], rtol=0,
                               atol=1e-6 * fscale)
    for key in ("kinetic", "strain", "contact_dissipation", "viscous_dissipation"):
        np.testing.assert_allclose(res.energy[key], ref.energy[key], rtol=1e-6,
                                   atol=1e-9 * ref.energy["strain"].max())
    # every regime occurred: open, stick and slip
    assert set(np.unique(res.contact_status).tolist()) == {0, 1, 2}
    assert res.energy["contact_dissipation"][-1] > 0


def test_given_static_states_equal_the_virgin_convention(wheel, start):
    """The paper's start (the static solution's contact states) equals simulate's convention
    (virgin states loaded to q0 in one step) because the static solution is one step from
    the virgin state: both runs are identical."""
    a = integrate_contact3d(wheel.system, 2e-3, 1e-5, q0=start.q0, states0=start.states0)
    b = integrate_contact3d(wheel.system, 2e-3, 1e-5, q0=start.q0)
    np.testing.assert_allclose(a.q, b.q, rtol=0, atol=1e-12 * np.abs(b.q).max())
    np.testing.assert_array_equal(a.contact_status, b.contact_status)


def test_energy_balance_and_hht(wheel, start):
    """Newmark: the energy residual is small against a friction dissipation that is not.
    HHT-alpha (alpha = -0.05) only damps unresolved modes: with 2000 steps per period of
    the 6ND mode the probe history equals Newmark's within 1e-3 of the amplitude."""
    probe = wheel.group_dofs("probe", 0)
    nm = integrate_contact3d(wheel.system, 0.02, 1e-5, q0=start.q0, output_dofs=probe)
    assert nm.energy_balance_error < 1e-3
    assert nm.energy["contact_dissipation"][-1] > 0.05 * nm.energy["strain"][0]
    hht = integrate_contact3d(wheel.system, 0.02, 1e-5, q0=start.q0, output_dofs=probe,
                              method="hht", alpha=-0.05)
    assert hht.method.startswith("hht") and hht.energy_balance_error < 1e-3
    np.testing.assert_allclose(hht.q, nm.q, rtol=0, atol=1e-3 * np.abs(nm.q).max())


def _toy(mu=0.3, offset=1e-4, damping=True, law=None):
    M = np.diag([1.0, 2.0, 1.5])
    K = np.array([[3e4, -1e4, 0.0], [-1e4, 2e4, -5e3], [0.0, -5e3, 1e4]])
    D = 1e-4 * K if damping else None
    P = np.array([[1.0, 0.0, -1.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    law = law or Contact3D(1e5, 5e4, mu, offset=offset)
    return MechanicalSystem(M=M, K=K, D=D, contacts=(ContactElement(law, P),))


def test_static_solution_is_in_equilibrium_and_stuck_case_is_linear():
    """solve_static: K q + P^T f(P q) = F to 1e-9; with a high mu the contact sticks and
    the result is the linear solution with the stuck tangent diag(k_n, k_t, k_t) and the
    offset load -P^T k_n g0 e_n (closed form of the linear problem)."""
    F = np.array([5.0, -3.0, 2.0])
    for mu in (0.05, 10.0):
        s = _toy(mu)
        r = solve_static(s, F)
        P = s.contacts[0].projection
        resid = s.K @ r.q + P.T @ r.contact_force[0].ravel() - F
        assert np.abs(resid).max() < 1e-9 * np.abs(F).max()
    Kc = np.diag([1e5, 5e4, 5e4])
    q_lin = np.linalg.solve(s.K + P.T @ Kc @ P, F - P.T @ np.array([1e5 * 1e-4, 0, 0]))
    np.testing.assert_allclose(r.q, q_lin, rtol=1e-10)
    # increments (quasi-static path, states committed): still in equilibrium, and the
    # stuck case does not depend on the path
    s = _toy(0.05)
    r10 = solve_static(s, F, increments=10)
    P = s.contacts[0].projection
    assert np.abs(s.K @ r10.q + P.T @ r10.contact_force[0].ravel() - F).max() < 1e-9 * 5
    np.testing.assert_allclose(solve_static(_toy(10.0), F, increments=7).q, q_lin,
                               rtol=1e-10)


def test_fast_path_on_a_toy_equals_simulate_with_sparse_matrices():
    """Three DOFs, one contact that opens, sticks and slips under a free decay."""
    s = _toy(0.3)
    s = MechanicalSystem(M=sp.csr_matrix(s.M), K=sp.csr_matrix(s.K), D=sp.csr_matrix(s.D),
                         contacts=s.contacts)
    q0 = np.array([2e-3, 1e-3, -1e-3])
    ref = simulate(s, 0.3, 2e-4, q0=q0, progress=False)
    res = integrate_contact3d(s, 0.3, 2e-4, q0=q0)
    np.testing.assert_allclose(res.q, ref.q, rtol=0, atol=1e-8 * np.abs(q0).max())
    np.testing.assert_allclose(res.q_final, ref.q[-1], rtol=0, atol=1e-8 * np.abs(q0).max())
    np.testing.assert_allclose(res.v_final, ref.v[-1], rtol=0, atol=1e-6 * np.abs(ref.v).max())
    # restarting from the final state continues the same history
    half = integrate_contact3d(s, 0.15, 2e-4, q0=q0)
    rest = integrate_contact3d(s, 0.3, 2e-4, t0=half.t[-1], q0=half.q_final, v0=half.v_final,
                               states0=half.states_final)
    np.testing.assert_allclose(rest.q[-1], res.q[-1], rtol=0, atol=1e-3 * np.abs(q0).max())
    assert set(np.unique(res.contact_status).tolist()) == {0, 1, 2}


def test_errors_are_named():
    s = _toy()
    with pytest.raises(ModelError, match="Contact3D"):
        integrate_contact3d(s.with_contacts(ContactElement(Jenkins(1e4, 1.0),
                                                           np.array([[1.0, 0, 0]]))), 0.1, 1e-3)
    nonprop = MechanicalSystem(M=s.M, K=s.K, D=np.diag([1.0, 0.0, 0.0]), contacts=s.contacts)
    with pytest.raises(ModelError, match="diagonal"):
        integrate_contact3d(nonprop, 0.1, 1e-3)
    with pytest.raises(ModelError, match="time-dependent"):
        integrate_contact3d(s.with_loads(HarmonicLoad(np.ones(3), 10.0)), 0.1, 1e-3)
    with pytest.raises(ModelError, match="dt"):
        integrate_contact3d(s, 0.1, -1e-3)
    with pytest.raises(ModelError, match="output_dofs"):
        integrate_contact3d(s, 0.1, 1e-3, output_dofs=[5])
    with pytest.raises(ModelError, match="increments"):
        solve_static(s, increments=0)


def test_simulate_strategies_are_one_scheme():
    """``simulate(strategy="modal")`` is the compiled modal strategy of the same Newmark
    step: on the toy (a contact that opens, sticks and slips) displacements, velocities,
    accelerations, contact forces and energies equal the direct strategy's to the Newton
    tolerance (1e-10 per step, amplified by the friction switches to < 1e-8 of the
    amplitude, measured ~1e-11); ``"auto"`` takes the modal strategy for Contact3D with
    Rayleigh damping and the direct one otherwise."""
    s = _toy(0.3)
    q0 = np.array([2e-3, 1e-3, -1e-3])
    ref = simulate(s, 0.2, 2e-4, q0=q0, progress=False)
    mod = simulate(s, 0.2, 2e-4, q0=q0, strategy="modal")
    assert mod.meta["strategy"] == "modal" and "strategy" not in ref.meta
    amp = np.abs(q0).max()
    np.testing.assert_allclose(mod.t, ref.t, rtol=0, atol=1e-15)
    np.testing.assert_allclose(mod.q, ref.q, rtol=0, atol=1e-8 * amp)
    np.testing.assert_allclose(mod.v, ref.v, rtol=0, atol=1e-8 * np.abs(ref.v).max())
    np.testing.assert_allclose(mod.a, ref.a, rtol=0, atol=1e-7 * np.abs(ref.a).max())
    np.testing.assert_allclose(mod.contact_force[0], ref.contact_force[0], rtol=0,
                               atol=1e-7 * np.abs(ref.contact_force[0]).max())
    for key in ("kinetic", "strain", "contact_dissipation", "input_work"):
        np.testing.assert_allclose(mod.energy[key], ref.energy[key], rtol=0,
                                   atol=1e-8 * ref.energy["strain"].max())
    assert set(np.unique(mod.meta["contact_status"]).tolist()) == {0, 1, 2}
    assert simulate(s, 0.01, 2e-4, q0=q0, strategy="auto").meta["strategy"] == "modal"
    jen = s.with_contacts(ContactElement(Jenkins(1e4, 1.0), np.array([[1.0, 0, 0]])))
    assert "strategy" not in simulate(jen, 0.01, 2e-4, q0=q0, strategy="auto").meta
    with pytest.raises(ModelError, match="strategy must be one of"):
        simulate(s, 0.01, 2e-4, strategy="fast")
