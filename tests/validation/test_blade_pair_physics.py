"""Paper 001, two rotating blades with a wedge: physics checks of the assembled model and
its analyses (models/blade_pair.py, models/blade_pair_analyses.py).

References
----------
* 001 (6): static equilibrium of the wedge (force balance, derived again in the model).
* Energy conservation per cycle: work of the nozzle load = material + contact + friction
  dissipation (an identity of the converged linear steady state).
* Coulomb's work: the equivalent dampers dissipate f N x orbit perimeter + 4 M_0 phi.
* Limits: f = 0 (plain linear response) and f -> infinity (contacts locked).
* Independent engine: multi-harmonic balance with 2D Jenkins contacts (solvers/hb.py).
* 001 section 4: the first resonance with 30 Omega near 390 rpm (the blade was chosen for
  it), orbits shrinking with f (Fig. 12), more real eigenvalues with friction (section 4.1).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

from fricdamp.contact.equivalent import ellipse_perimeter
from fricdamp.models.blade_pair.model import build_blade_pair, rpm_to_rad_s
from fricdamp.models.blade_pair.studies import (
    campbell_diagram,
    complex_modes,
    harmonic_balance_cross_check,
    orbits,
    solve_steady_states,
    steady_state_sweep,
)

RPM = np.linspace(150.0, 2400.0, 40)


@pytest.fixture(autouse=True)
def _one_blas_thread():
    with threadpool_limits(limits=1):
        yield


@pytest.fixture(scope="module")
def model():
    return build_blade_pair()


def test_elastic_wedge_reproduces_the_normal_loads_of_001_6(model):
    """With the contact points on the normals through D (no moment) and the shrouds held,
    the linear static problem K_C q_D = m_D r_D Omega^2 x gives spring forces k zeta equal
    to 001 (6) (1e-9; the wedge's free axial translation is left out by least squares)."""
    p = model.params
    lam = 0.004
    pts = ((lam * np.sin(p.delta_a), -lam * np.cos(p.delta_a)),
           (lam * np.sin(p.delta_b), lam * np.cos(p.delta_b)))
    m = build_blade_pair(p.with_(contact_points=pts))
    d = m.damper_slice
    w = rpm_to_rad_s(1200.0)
    F = np.zeros(6)
    F[0] = p.damper_mass * p.damper_radius * w**2
    qD = np.linalg.lstsq(m.K_C[d, d], F, rcond=None)[0]
    q = np.zeros(m.n_dof)
    q[d] = qD
    zeta = m.contact_projection[:, 0, :] @ q
    N_elastic = np.array(p.contact_stiffness) * zeta
    assert N_elastic == pytest.approx(m.normal_loads(w), rel=1e-9)


@pytest.fixture(scope="module")
def sweep30(model):
    return solve_steady_states(model, 30, RPM, [0.05, 0.1, 0.3])


def test_steady_states_converge_and_balance_energy(sweep30):
    """Every speed converges; W_in = W_visc + W_friction per cycle to 1e-8 (stuck contacts
    carry damping ~1e6 N s/m, so the linear solves lose a few digits)."""
    for _, res, _ in sweep30:
        assert res.success
        assert res.energy_balance_error.max() < 1e-8
        assert np.all(res.external_work > 0)


def test_friction_dissipation_is_coulombs_work(sweep30, model):
    """Per contact: pi w s^H C s = f N x perimeter + 4 f N rho phi at the converged orbit
    (Coulomb rule, p = 1) wherever no floor is active (semi-axes and rotation above twice
    their floors: below them the damping is held at its floor value). The damping was built
    from the previous iterate, so the two agree to the fixed-point tolerances: 1e-8
    relative and the absolute floor (1 nm of slip, 1 nm / rho of rotation), i.e. to
    f N (2 pi + 4) x 1 nm in energy (plus 1e-6 relative)."""
    speeds = rpm_to_rad_s(RPM)
    N = model.normal_loads(speeds)
    checked = 0
    for f, res, damp in sweep30:
        s = res.contact_response
        e = damp.orbits(s)
        phi = np.abs(s[:, [2, 5]])
        coulomb = f * N * (ellipse_perimeter(e.major, e.minor) + 4 * model.torque_arms * phi)
        W = res.equivalent_dissipation
        got = np.column_stack([W[:, 0] + W[:, 1], W[:, 2] + W[:, 3]])
        free = ((e.minor > 2 * damp.min_amplitude) & (e.minor > 2e-6 * e.major)
                & (phi > 2 * damp.min_rotation))
        tol = 1e-6 * coulomb + f * N * (2 * np.pi + 4) * damp.min_amplitude
        assert np.all(np.abs(got - coulomb)[free] <= tol[free])
        checked += int(free.sum())
    assert checked >= 10


def test_without_friction_the_response_is_the_linear_one(model):
    """f = 0: no equivalent damping, the response is Z^-1 F (1e-12)."""
    (_, res, _), = solve_steady_states(model, 20, [700.0, 1300.0], [0.0])
    w = rpm_to_rad_s(np.array([700.0, 1300.0]))
    for i in range(2):
        Z = model.stiffness(w[i]) - (20 * w[i]) ** 2 * model.M + 1j * 20 * w[i] * (
            model.damping(w[i]))
        q = np.linalg.solve(Z, model.load(20))
        assert np.abs(res.response[i] - q).max() < 1e-12 * np.abs(q).max()


def test_very_high_friction_locks_the_contacts(model):
    """f -> infinity: the slip vanishes and the blades respond like the structure with its
    friction coordinates locked (a stiff spring 1e14 N/m on them): tip amplitudes agree to
    1e-3 (both only approximate the constraint)."""
    rpm = np.array([400.0, 900.0, 1600.0])
    (_, res, damp), = solve_steady_states(model, 15, rpm, [1e3])
    assert damp.stuck(res.contact_response).all()
    P = model.friction_projection
    Klock = P.T @ np.diag([1e14, 1e14, 1e14 * 3e-5] * 2) @ P
    it = model.dof_index("blade1", model.tip_node, "w")
    for i, w in enumerate(rpm_to_rad_s(rpm)):
        wk = 15 * w
        Z = (model.stiffness(w) + Klock - wk**2 * model.M + 1j * wk * model.damping(w))
        q = np.linalg.solve(Z, model.load(15))
        assert abs(res.response[i, it]) == pytest.approx(abs(q[it]), rel=1e-3)


def test_orbits_shrink_with_the_friction_coefficient(sweep30):
    """001 Fig. 12: the orbits reduce in size as f grows (largest major semi-axis over the
    speeds, both contacts, strictly decreasing for f = 0.05, 0.1, 0.3)."""
    big = [damp.orbits(res.contact_response).major.max(axis=0) for _, res, damp in sweep30]
    assert np.all(np.diff(np.array(big), axis=0) < 0)


def test_first_resonance_with_30_omega_near_390_rpm(model):
    """001 section 4.2: the first resonance peak for k = 30 at n = 390 rpm (the blade section
    was chosen for it, so this checks the whole chain model -> sweep): the dissipated energy
    peaks within 360-420 rpm for f = 0.05."""
    rpm = np.linspace(300.0, 480.0, 37)
    out = steady_state_sweep(model, 30, rpm, [0.05])[0]
    W = np.array(out["dissipated_energy_J"])
    assert 360.0 <= rpm[np.argmax(W)] <= 420.0
    assert out["converged"] and out["energy_balance_error"] < 1e-8
    assert len(out["semi_axes_A_m"]) == rpm.size and len(out["semi_axes_A_m"][0]) == 2


def test_campbell_without_friction_matches_independent_modal_solvers(model):
    """No friction: (i) the Campbell frequencies equal the complex modes of the same system from
    solvers/modal.py (generalised first-order pencil, an independent implementation), 1e-6
    (the Campbell path takes the eigenvalues of the state matrix built with M^-1, a non-
    normal matrix: for the close pair at 494.7 / 496.3 Hz (0.3 % apart) the two paths differ
    by up to 1.3e-7 with the LAPACK of the current numpy/scipy wheels, 1e-9 with older ones;
    far below the 1e-3 the Campbell crossings need); (ii) at 200 rpm, where the gyroscopic
    coupling is negligible, the undamped frequencies of (K(Omega), M) to 1e-4 (light damping
    shifts them by ~zeta^2/2); at 1800 rpm the gyroscopic terms split the close in-
    phase/out-of-phase pair by up to 0.1 %; (iii) the eigenvalues number 2 n = 156."""
    from fricdamp.solvers.modal import modes

    rpm = [200.0, 1800.0]
    c = campbell_diagram(model, rpm, friction=False, n_modes=6)
    F = np.array(c["frequency_hz"], float)
    for i, w in enumerate(rpm_to_rad_s(np.array(rpm))):
        ref = modes(model.system(w), 8, kind="damped", sigma=150.0, method="dense")
        f_ref = np.sort(ref.frequencies[ref.frequencies > 1.0])[:6]
        assert F[:, i] == pytest.approx(f_ref, rel=1e-6)
        lam = sla.eigh(model.stiffness(w), model.M, eigvals_only=True)
        f_und = np.sqrt(lam[lam > 1.0]) / (2 * np.pi)
        assert F[:, i] == pytest.approx(f_und[:6], rel=1e-4 if i == 0 else 1e-3)
        assert 2 * c["complex_pairs"][i] + c["real_eigenvalues"][i] == 156


def test_friction_damping_turns_modes_over_damped(model):
    """001 section 4.1: with the equivalent damping, complex pairs vanish and real
    (over-damped) eigenvalues appear -- more real eigenvalues than without friction where
    the contacts stick (1500 rpm, k = 30, f = 0.1)."""
    free = campbell_diagram(model, [1500.0], friction=False)
    fric = campbell_diagram(model, [1500.0], friction=True, friction_coefficient=0.1)
    assert fric["real_eigenvalues"][0] > free["real_eigenvalues"][0]
    assert 2 * fric["complex_pairs"][0] + fric["real_eigenvalues"][0] == 156
    lit = campbell_diagram(model, [1500.0], damping_source="linear")
    assert 2 * lit["complex_pairs"][0] + lit["real_eigenvalues"][0] == 156


@pytest.mark.parametrize("source", ["linear", "converged"])
def test_complex_modes_solve_the_quadratic_eigenproblem(model, source):
    """001 Fig. 5 modes at 2000 rpm: (lambda^2 M + lambda D + K) phi = 0 with the friction
    damping of 001 section 4.1 (from the response without friction damping, the default) or
    of the converged steady state (relative residual 1e-9); shapes normalised on the
    translations (the largest translational DOF is 1, every rotation may be larger)."""
    from fricdamp.models.blade_pair.studies import _condensed, equivalent_damping_matrix

    modes = complex_modes(model, 2000.0, n_modes=3, damping_source=source)
    w = rpm_to_rad_s(2000.0)
    if source == "converged":
        (_, res, _), = solve_steady_states(model, 30, [2000.0], [0.1])
        Be = equivalent_damping_matrix(model, res)[0]
    else:
        cs = _condensed(model, 30, np.array([w]))
        C = model.friction_damping([w], 0.1).matrix(cs.contact_free, cs.omega, np.arange(1))
        P = model.friction_projection
        Be = P.T @ C[0] @ P
    D = model.damping(w) + Be
    K = model.stiffness(w)
    X = np.array(modes["shapes"])
    trans = np.array([n.split(".")[-1][0] in "uvw" for n in model.dof_names])
    for j, (re, im) in enumerate(modes["eigenvalues"]):
        lam = re + 1j * im
        phi = X[:, j, 0] + 1j * X[:, j, 1]
        r = (lam**2 * model.M + lam * D + K) @ phi
        assert np.linalg.norm(r) < 1e-9 * np.linalg.norm(K) * np.linalg.norm(phi)
        assert np.abs(phi[trans]).max() == pytest.approx(1.0, rel=1e-12)
        assert model.dof_names.index(modes["normalised_on"][j]) == np.argmax(
            np.abs(phi) * trans)
    assert np.all(np.diff(modes["frequency_hz"]) > 0)
    assert len(modes["blade1"]) == 3 and len(modes["blade1"][0]) == 6


def test_orbit_output_closes_on_its_semi_axes(model):
    """The orbit curves (Figs 12-14) reach the semi-axes they report."""
    o = orbits(model, 20, [500.0], [0.05], n_points=181)[0]
    for c in ("A", "B"):
        x = np.array(o[c][0]["xi_m"])
        y = np.array(o[c][0]["eta_m"])
        a, b = o[c][0]["semi_axes_m"]
        r = np.hypot(x, y)
        assert r.max() == pytest.approx(a, rel=1e-6)
        assert r.min() == pytest.approx(b, rel=1e-3, abs=1e-3 * a)


def test_equivalent_linearisation_agrees_with_harmonic_balance_in_gross_slip(model):
    """Cross-check with an independent engine (HB-AFT, 5 harmonics, 2D Jenkins contacts with
    k_t = 1e8 N/m). In gross slip (k = 30, f = 0.05 at 300 and 389 rpm: orbits of 20-500 um,
    stick displacement f N / k_t ~ 10 nm) the orbits and the dissipated energy agree to 2 %
    (the describing function drops the higher harmonics of the friction force). Where the
    equivalent model sticks (1000 rpm) HB shows only elastic micro-slip (< 50 nm) and no
    dissipation."""
    x = harmonic_balance_cross_check(model, 30, [300.0, 389.0, 1000.0], 0.05)
    assert all(x["hb_success"])
    eq, hb = x["eqlin"], x["hb"]
    for i in (0, 1):
        for key in ("semi_axes_A_m", "semi_axes_B_m"):
            assert hb[key][i][0] == pytest.approx(eq[key][i][0], rel=0.02)
        assert hb["dissipated_energy_J"][i] == pytest.approx(eq["dissipated_energy_J"][i],
                                                             rel=0.02)
    assert hb["semi_axes_A_m"][2][0] < 5e-8 and hb["semi_axes_B_m"][2][0] < 5e-8
    assert eq["semi_axes_A_m"][2][0] < 5e-9
    assert abs(hb["dissipated_energy_J"][2]) < 1e-12
