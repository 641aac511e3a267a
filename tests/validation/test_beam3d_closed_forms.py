"""3D Rayleigh beam elements (structure/beam3d.py) against closed forms, 001 (2).

Each test names its reference and its tolerance. Frequencies of the quadratic problem
``M q'' + (D + Omega G) q' + K(Omega) q = 0`` are taken from the state-space eigenvalues.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation
from threadpoolctl import threadpool_limits

from fricdamp.structure.beam3d import BeamSection, beam_model, line_mesh
from fricdamp.structure.beam3d_rotation import rigid_body_terms, skew


@pytest.fixture(autouse=True)
def _one_blas_thread():
    """Small dense eigenproblems: BLAS threads on a shared 2-core machine only contend."""
    with threadpool_limits(limits=1):
        yield


BETA_L = (1.8751040687, 4.6940911330, 7.8547574382)   # 1 + cos cosh = 0
STEEL = dict(E_Pa=2.1e11, rho_kg_m3=7850.0, nu=0.3)


def _dense(A):
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A)


def damped_frequencies(system) -> np.ndarray:
    """Sorted positive imaginary parts [rad/s] of the eigenvalues of the quadratic problem."""
    M, D, K = _dense(system.M), _dense(system.D), _dense(system.K)
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    lam = np.linalg.eigvals(A)
    return np.sort(lam.imag[lam.imag > 0])


PLANE = {"u": (0,), "v": (1, 5), "w": (2, 4), "phi": (3,)}   # DOF codes of each motion


def energy_fraction(model, M, vec, motion: str) -> float:
    """Share of the kinetic energy of mode ``vec`` carried by the DOFs of ``motion``."""
    sel = np.isin(model.free_dofs % 6, PLANE[motion])
    Mv = M @ vec
    return float(vec[sel] @ Mv[sel] / (vec @ Mv))


def modes_in_direction(model, motion: str, n: int, K=None) -> np.ndarray:
    """The n lowest undamped frequencies [rad/s] of modes that are mostly ``motion``.

    ``motion``: "u" (axial along x), "v" / "w" (bending with v or w), "phi" (twist); a mode
    is counted when those DOFs carry more than 90 % of its kinetic energy.
    """
    M = model.M.toarray()
    lam, vec = sl.eigh(model.K.toarray() if K is None else K, M)
    out = [np.sqrt(lam[k]) for k in np.argsort(lam)
           if energy_fraction(model, M, vec[:, k], motion) > 0.9]
    return np.array(out[:n])


def cantilever_mode(beta_l: float):
    """Exact clamped-free mode shape phi(x) and phi'(x) on [0, 1] (int phi^2 = 1)."""
    s = (np.cosh(beta_l) + np.cos(beta_l)) / (np.sinh(beta_l) + np.sin(beta_l))

    def phi(x):
        b = beta_l * x
        return np.cosh(b) - np.cos(b) - s * (np.sinh(b) - np.sin(b))

    def dphi(x):
        b = beta_l * x
        return beta_l * (np.sinh(b) + np.sin(b) - s * (np.cosh(b) - np.cos(b)))

    return phi, dphi


def southwell_reference(hub_ratio: float) -> float:
    """d(omega^2)/d(Omega^2) at Omega = 0 of the first flap mode, exact Rayleigh quotient.

    First-order perturbation of a self-adjoint problem: the eigenvalue derivative is the
    Rayleigh quotient of the perturbation at the unperturbed (exact) mode, with the axial
    force per Omega^2 ``m ((R + L)^2 - (R + x)^2) / 2`` (L = 1, m = 1).
    """
    phi, dphi = cantilever_mode(BETA_L[0])
    num = quad(lambda x: (0.5 * (1 - x * x) + hub_ratio * (1 - x)) * dphi(x) ** 2, 0, 1,
               epsabs=1e-13)[0]
    return num / quad(lambda x: phi(x) ** 2, 0, 1, epsabs=1e-13)[0]


def blade(n_el=10, hub=0.0, length=1.0, width=0.02, height=0.004, **kw):
    """Radial blade along +x from the hub radius, spinning about global z (flap = w)."""
    sec = BeamSection.rectangle(width, height, **STEEL)
    nodes, els = line_mesh([hub, 0, 0], [hub + length, 0, 0], n_el)
    return beam_model(nodes, els, sec, clamped_nodes=[0], spin_axis=[0, 0, 1], **kw), sec


# --------------------------------------------------------------------------- static
def test_static_tip_loads_are_exact_for_an_inclined_cantilever():
    """Tip deflections PL^3/3EI (both planes), PL/EA and torque TL/GJ.

    Reference: elementary beam theory; Hermite/linear elements are nodally exact for end
    loads, so the tolerance is round-off (1e-9 relative), on a beam inclined in space so the
    element frame transformation is exercised.
    """
    L, P = 0.8, 10.0
    sec = BeamSection.rectangle(0.03, 0.01, **STEEL)
    ex = np.array([1.0, 2.0, 2.0]) / 3.0
    ori = np.array([0.0, 0.0, 1.0])
    ey = ori - ex * (ori @ ex)
    ey /= np.linalg.norm(ey)
    ez = np.cross(ex, ey)
    nodes, els = line_mesh([0.1, -0.2, 0.3], np.array([0.1, -0.2, 0.3]) + L * ex, 4)
    model = beam_model(nodes, els, sec, orientation=ori, clamped_nodes=[0])
    tip = [model.dof_index(4, n) for n in ("u", "v", "w", "phi", "theta", "psi")]
    K = model.K.toarray()
    for direction, expected in ((ey, P * L**3 / (3 * sec.E_Pa * sec.Iz_m4)),
                                (ez, P * L**3 / (3 * sec.E_Pa * sec.Iy_m4)),
                                (ex, P * L / (sec.E_Pa * sec.area_m2))):
        f = np.zeros(model.n_dof)
        f[tip[:3]] = P * direction
        q = np.linalg.solve(K, f)
        assert q[tip[:3]] @ direction == pytest.approx(expected, rel=1e-9)
    f = np.zeros(model.n_dof)
    f[tip[3:]] = P * ex                                   # torque about the beam axis
    q = np.linalg.solve(K, f)
    assert q[tip[3:]] @ ex == pytest.approx(P * L / (sec.G_Pa * sec.J_m4), rel=1e-9)


# --------------------------------------------------------------------------- frequencies
def test_cantilever_bending_frequencies_converge_to_beta_l():
    """omega_n = (beta_n L)^2 sqrt(EI / (rho A L^4)), beta_n L = 1.8751, 4.6941, 7.8548.

    Reference: Euler-Bernoulli cantilever. Tolerance: the first mode within 0.1 % with 10
    elements (asked), errors falling with the mesh (h^4) from 2 to 10 elements; 5e-4 on modes
    1-3 with 20 elements. The beam is slender (L/h = 250): the rotary inertia of the Rayleigh
    beam lowers omega_1 by ~(beta r)^2 / 2 = 2e-6 below the Euler-Bernoulli value, which is
    the floor of the error.
    """
    errors = []
    for n_el in (2, 5, 10, 20):
        model, sec = _static_blade(n_el)
        w = modes_in_direction(model, "w", 3)
        exact = np.array(BETA_L) ** 2 * np.sqrt(sec.E_Pa * sec.Iy_m4
                                                 / (sec.rho_kg_m3 * sec.area_m2))
        errors.append(np.abs(w / exact - 1))
    errors = np.array(errors)
    assert errors[2, 0] < 1e-3
    assert errors[0, 0] > errors[1, 0] > errors[2, 0]
    assert errors[1, 0] / errors[2, 0] > 4          # ~h^4 down to the rotary-inertia floor
    assert np.all(errors[3] < 5e-4)
    # the other bending plane, through Iz
    model, sec = _static_blade(20)
    w = modes_in_direction(model, "v", 2)
    exact = np.array(BETA_L[:2]) ** 2 * np.sqrt(sec.E_Pa * sec.Iz_m4
                                                 / (sec.rho_kg_m3 * sec.area_m2))
    # wider in this plane (r^2 = Iz / A = 3.3e-5 m^2): the Rayleigh beam sits below the
    # Euler-Bernoulli value by about (beta_n r)^2 / 2, bounded here by (beta_n r)^2
    floor = np.array(BETA_L[:2]) ** 2 * sec.Iz_m4 / sec.area_m2
    assert np.all(w < exact * (1 + 1e-5)) and np.all(w > exact * (1 - floor))


def _static_blade(n_el):
    sec = BeamSection.rectangle(0.02, 0.004, **STEEL)
    nodes, els = line_mesh([0, 0, 0], [1.0, 0, 0], n_el)
    return beam_model(nodes, els, sec, clamped_nodes=[0]), sec


def test_axial_and_torsional_frequencies_of_a_clamped_free_rod():
    """omega_n = (2n - 1) pi / (2 L) c with c = sqrt(E / rho) (axial), sqrt(G / rho) (torsion).

    Reference: clamped-free rod. Linear elements with consistent mass overestimate omega by
    ~(k h)^2 / 24; tolerance (k h)^2 / 12 per mode (k = (2n - 1) pi / 2L, h = L / 40).
    A circular section so the torsion constant equals the polar moment.
    """
    L, n_el = 1.0, 40
    sec = BeamSection.circle(0.02, **STEEL)
    nodes, els = line_mesh([0, 0, 0], [0, 0, L], n_el)
    model = beam_model(nodes, els, sec, clamped_nodes=[0])
    sec_z = {"u": (2,), "phi": (5,)}                       # beam along z: w axial, psi twist
    M = model.M.toarray()
    lam, vec = sl.eigh(model.K.toarray(), M)
    ax, tw = [], []
    for k in np.argsort(lam):
        for motion, store in (("u", ax), ("phi", tw)):
            sel = np.isin(model.free_dofs % 6, sec_z[motion])
            Mv = M @ vec[:, k]
            if vec[sel, k] @ Mv[sel] > 0.99 * (vec[:, k] @ Mv):
                store.append(np.sqrt(lam[k]))
    k = (2 * np.arange(1, 4) - 1) * np.pi / (2 * L)
    tol = (k * L / n_el) ** 2 / 12
    rel_ax = np.array(ax[:3]) / (k * np.sqrt(sec.E_Pa / sec.rho_kg_m3)) - 1
    rel_tw = np.array(tw[:3]) / (k * np.sqrt(sec.G_Pa / sec.rho_kg_m3)) - 1
    assert np.all(np.abs(rel_ax) < tol) and np.all(np.abs(rel_tw) < tol)
    assert np.all(rel_ax > 0) and np.all(rel_tw > 0)      # consistent mass: upper bounds


def test_rotary_inertia_matches_the_rayleigh_simply_supported_beam():
    """omega_n^2 = EI k^4 / (rho A (1 + (I / A) k^2)), k = n pi / L (Rayleigh beam, pinned).

    Reference: Rayleigh beam, exact for simple supports. Stubby beam (L / h = 5) where the
    rotary-inertia correction is 1.6-13 %: the FE (40 elements) must match the Rayleigh value
    within 5e-5 and miss the Euler-Bernoulli value by more than 1 %.
    """
    L, h = 0.25, 0.05
    sec = BeamSection.rectangle(0.02, h, **STEEL)
    nodes, els = line_mesh([0, 0, 0], [L, 0, 0], 40)
    model = beam_model(nodes, els, sec, fixed_dofs=[(0, ("u", "v", "w", "phi")),
                                                    (40, ("v", "w"))])
    w = modes_in_direction(model, "w", 3)
    k = np.arange(1, 4) * np.pi / L
    EI, rA, r2 = sec.E_Pa * sec.Iy_m4, sec.rho_kg_m3 * sec.area_m2, sec.Iy_m4 / sec.area_m2
    rayleigh = np.sqrt(EI * k**4 / (rA * (1 + r2 * k**2)))
    euler = np.sqrt(EI * k**4 / rA)
    np.testing.assert_allclose(w, rayleigh, rtol=5e-5)
    assert np.all(euler / w - 1 > 0.007)
    assert euler[2] / w[2] - 1 > 0.05


def test_cantilever_with_tip_mass_matches_the_frequency_equation():
    """1 + cos(bL) cosh(bL) + mu bL (cos(bL) sinh(bL) - sin(bL) cosh(bL)) = 0, mu = m_t / (m L).

    Reference: Euler-Bernoulli cantilever with a tip point mass. Tolerance 2e-4 (20 elements).
    """
    sec = BeamSection.rectangle(0.02, 0.004, **STEEL)
    m_beam = sec.rho_kg_m3 * sec.area_m2 * 1.0
    mu = 0.5
    nodes, els = line_mesh([0, 0, 0], [1.0, 0, 0], 20)
    model = beam_model(nodes, els, sec, clamped_nodes=[0], point_masses={20: mu * m_beam})

    def char(b):
        return (1 + np.cos(b) * np.cosh(b)
                + mu * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b)))

    b1 = brentq(char, 0.5, 2.0)
    exact = b1**2 * np.sqrt(sec.E_Pa * sec.Iy_m4 / (sec.rho_kg_m3 * sec.area_m2))
    assert modes_in_direction(model, "w", 1)[0] == pytest.approx(exact, rel=2e-4)
    assert b1 < BETA_L[0] - 0.2                           # the mass matters


# --------------------------------------------------------------------------- rotation
def test_centrifugal_load_and_axial_force_of_a_radial_blade():
    """f_c = rho A Omega^2 int r dx; N(x) = rho A Omega^2 ((R + L)^2 - (R + x)^2) / 2 + m_t (R + L).

    Reference: equilibrium of a radial bar. The axial force must be exact at every element
    end (tolerance 1e-9 relative) and include a tip mass.
    """
    R, L, m_t = 0.3, 0.5, 0.05
    sec = BeamSection.rectangle(0.02, 0.004, **STEEL)
    nodes, els = line_mesh([R, 0, 0], [R + L, 0, 0], 5)
    model = beam_model(nodes, els, sec, clamped_nodes=[0], spin_axis=[0, 0, 3.0],
                       spin_origin=[0, 0, -1.0], point_masses={5: m_t})
    rA = sec.rho_kg_m3 * sec.area_m2
    free = beam_model(nodes, els, sec, spin_axis=[0, 0, 3.0], spin_origin=[0, 0, -1.0],
                      point_masses={5: m_t}, stress_stiffening=False)
    fc = free.expand(free.rotation.centrifugal_load)      # all nodes, root included
    assert fc[:, 0].sum() == pytest.approx(rA * (R * L + L**2 / 2) + m_t * (R + L), rel=1e-12)
    assert np.abs(fc[:, 1:3].sum(axis=0)).max() < 1e-12 * np.abs(fc).max()
    np.testing.assert_allclose(model.rotation.centrifugal_load,
                               free.rotation.centrifugal_load[model.free_dofs], rtol=1e-14)
    x = nodes[:, 0]
    N_exact = rA * ((R + L) ** 2 - x**2) / 2 + m_t * (R + L)
    N = model.axial_force_per_omega2
    np.testing.assert_allclose(N[:, 0], N_exact[:-1], rtol=1e-9)
    np.testing.assert_allclose(N[:, 1], N_exact[1:], rtol=1e-9)


def test_southwell_coefficient_of_the_first_flap_mode():
    """omega^2 = omega_0^2 + S Omega^2 with S = 1.1933 (hub radius 0) and 2.7642 (R = L).

    References: Wright et al. (1982) / Bhat (1986) S = 1.193 for R = 0; the exact value here is
    the Rayleigh quotient of the axial-force perturbation at the exact mode (first-order
    perturbation), ``S(R) = 1.19334 + 1.57088 R / L``. Hodges & Rutkowski (1981), Table 1:
    omega L^2 sqrt(rho A / EI) = 3.6817, 4.1373, 4.7973 (mode 1) and 22.181, 22.615, 23.320
    (mode 2) at lambda = Omega L^2 sqrt(rho A / EI) = 1, 2, 3.
    Tolerances: S within 1e-4 relative (10 elements, Omega small: lambda = 0.05, the curvature
    of omega^2(Omega^2) is < 1e-5 there); the table within 1e-4 (its 5 digits).
    """
    S0 = southwell_reference(0.0)
    assert S0 == pytest.approx(1.193, abs=5e-4)
    for hub in (0.0, 1.0):
        model, sec = blade(n_el=10, hub=hub)
        scale = np.sqrt(sec.E_Pa * sec.Iy_m4 / (sec.rho_kg_m3 * sec.area_m2))
        system = model.to_system()
        w0 = damped_frequencies(system.at_speed(0.0))[0]
        omega = 0.05 * scale
        w1 = damped_frequencies(system.at_speed(omega))[0]
        S = (w1**2 - w0**2) / omega**2
        assert S == pytest.approx(southwell_reference(hub), rel=1e-4)
    model, sec = blade(n_el=10)
    scale = np.sqrt(sec.E_Pa * sec.Iy_m4 / (sec.rho_kg_m3 * sec.area_m2))
    system = model.to_system()
    table = {1: (3.6817, 22.181), 2: (4.1373, 22.615), 3: (4.7973, 23.320)}
    for lam, (f1, f2) in table.items():
        w = modes_in_direction_at_speed(model, system, lam * scale)
        np.testing.assert_allclose(w[:2] / scale, [f1, f2], rtol=1e-4)


def modes_in_direction_at_speed(model, system, omega):
    """Flap (w) frequencies at speed, from K(Omega) (flap has no Coriolis coupling)."""
    return modes_in_direction(model, "w", 3, K=_dense(system.at_speed(omega).K))


@pytest.mark.parametrize("hub", [0.0, 1.0])
def test_southwell_coefficient_of_the_lead_lag_mode_checks_spin_softening(hub):
    """In-plane: omega^2 = omega_0^2 + (S - 1) Omega^2 (the -Omega^2 rho A v of K_d).

    Reference: as the flap test, S(R) = 1.19334 + 1.57088 R / L. Tolerance: 1e-4 relative
    without Coriolis (slender: rotary inertia (r / L)^2 beta^2 ~ 3e-5); with the Coriolis
    coupling to the axial modes, second-order perturbation bounds the extra shift of the
    coefficient by 4 w_lag^2 / (w_ax^2 - w_lag^2) (= 1.7e-4 here) and it must lower it.
    """
    model, sec = blade(n_el=10, hub=hub, width=0.01)
    rA = sec.rho_kg_m3 * sec.area_m2
    scale = np.sqrt(sec.E_Pa * sec.Iz_m4 / rA)
    omega = 0.02 * scale
    target = southwell_reference(hub) - 1
    K, M = model.K.toarray(), model.M.toarray()
    rot = model.rotation
    Kr = (rot.stress_stiffening - rot.spin_softening).toarray()
    lag0 = _lag_eig(model, K, M)
    lag1 = _lag_eig(model, K + omega**2 * Kr, M)
    assert (lag1 - lag0) / omega**2 == pytest.approx(target, rel=1e-4)
    system = model.to_system()
    w0 = damped_frequencies(system.at_speed(0.0))
    w1 = damped_frequencies(system.at_speed(omega))
    i = int(np.argmin(np.abs(w0 - np.sqrt(lag0))))
    s_coriolis = (w1[i] ** 2 - w0[i] ** 2) / omega**2
    w_ax = np.pi / 2 * np.sqrt(sec.E_Pa / sec.rho_kg_m3)
    bound = 4 * lag0 / (w_ax**2 - lag0)
    assert target - bound - 1e-4 * target < s_coriolis < target + 1e-4 * target


def _lag_eig(model, K, M):
    lam, vec = sl.eigh(K, M)
    for k in np.argsort(lam):
        if energy_fraction(model, M, vec[:, k], "v") > 0.9:
            return lam[k]
    raise AssertionError("no lead-lag mode")


def test_rotating_blade_twist_mode_checks_tension_torsion_and_propeller_terms():
    """Twist of a radial blade (chord in the plane of rotation): d(omega^2)/d(Omega^2) at 0
    = pi^2 / 12 + 1 / 4 + (Iz - Iy) / (Iy + Iz).

    Reference: first-order perturbation at the exact clamped-free twist mode sin(pi x / 2L)
    (L = 1, hub radius 0): the tension-torsion term int N (Ip / A) phi'^2 of K_w gives
    (pi / 2)^2 int (1 - x^2) cos^2 = pi^2 / 12 + 1 / 4, and the propeller moment of K_d
    (-Omega^2 rho (Iy - Iz) phi^2) gives (Iz - Iy) / Ip. Without Coriolis (the gyroscopic
    twist-flap coupling is proportional to the small rho Iy). Tolerance 3e-4: linear twist
    elements converge as h^2 (5e-4 with 10 elements, 1e-4 with 20).
    """
    model, sec = blade(n_el=20)
    K = model.K.toarray()
    rot = model.rotation
    Kr = (rot.stress_stiffening - rot.spin_softening).toarray()
    w0 = modes_in_direction(model, "phi", 1, K=K)[0]
    omega = 0.05 * w0
    w1 = modes_in_direction(model, "phi", 1, K=K + omega**2 * Kr)[0]
    expected = np.pi**2 / 12 + 0.25 + (sec.Iz_m4 - sec.Iy_m4) / (sec.Iz_m4 + sec.Iy_m4)
    assert (w1**2 - w0**2) / omega**2 == pytest.approx(expected, rel=3e-4)


def test_shaft_spinning_about_its_own_axis_whirls_at_omega_plus_minus_spin():
    """Rotating-frame frequencies of an axisymmetric shaft are |omega_n -+ Omega|.

    Reference: in the inertial frame Coriolis and centrifugal terms cancel for spin about the
    axis of symmetry (no prestress: f_c = 0), so each bending pair omega_n splits into
    omega_n -+ Omega in the rotating frame. Tolerance 1e-4: the only other effect is the
    rotary-inertia gyroscopic split, relative size (Omega / omega) (Ip / A) beta^2 ~ 1e-5.
    """
    sec = BeamSection.circle(0.01, **STEEL)
    nodes, els = line_mesh([0, 0, 0], [0, 0, 1.0], 20)
    model = beam_model(nodes, els, sec, clamped_nodes=[0], spin_axis=[0, 0, 1])
    assert np.abs(model.rotation.centrifugal_load).max() == 0.0
    system = model.to_system()
    w0 = damped_frequencies(system.at_speed(0.0))
    omega = 0.3 * w0[0]
    w1 = damped_frequencies(system.at_speed(omega))
    expected = np.sort([w0[0] - omega, w0[0] + omega, w0[2] - omega, w0[2] + omega])
    np.testing.assert_allclose(w1[:4], expected, rtol=1e-4)


def test_frequencies_at_speed_do_not_depend_on_the_global_frame():
    """Rotating the whole blade, its orientation vectors and the spin axis changes nothing.

    Reference: frame invariance. A bent, staggered two-part blade with a tip mass with a full
    inertia tensor, at Omega = 300 rad/s with material damping; tolerance 1e-8 relative.
    """
    nodes = np.array([[0.3, 0, 0], [0.35, 0.0, 0.01], [0.4, 0.01, 0.02], [0.45, 0.02, 0.02],
                      [0.5, 0.02, 0.0]])
    els = np.array([[0, 1], [1, 2], [2, 3], [3, 4]])
    secs = [BeamSection.rectangle(0.03 - 0.004 * i, 0.004, **STEEL) for i in range(4)]
    ori = np.array([[0, 1, 0.3], [0, 1, 0.5], [0, 1, 0.7], [0.1, 1, 0.9]])
    J = np.array([[2e-5, 3e-6, 0], [3e-6, 1e-5, 1e-6], [0, 1e-6, 2.5e-5]])
    pm = {4: (0.03, J)}
    kw = dict(clamped_nodes=[0], rayleigh=(1.0, 1e-5), spin_origin=[0.0, 0.0, 0.1])
    e = np.array([0.1, 0.2, 1.0])
    base = beam_model(nodes, els, secs, orientation=ori, point_masses=pm, spin_axis=e, **kw)
    Q = Rotation.from_rotvec([0.4, -1.1, 0.7]).as_matrix()
    moved = beam_model(nodes @ Q.T, els, secs, orientation=ori @ Q.T,
                       point_masses={4: (0.03, Q @ J @ Q.T)}, spin_axis=Q @ e,
                       **{**kw, "spin_origin": Q @ np.array(kw["spin_origin"])})
    for omega in (0.0, 300.0):
        a = damped_frequencies(base.to_system().at_speed(omega))
        b = damped_frequencies(moved.to_system().at_speed(omega))
        np.testing.assert_allclose(b, a, rtol=1e-8)
    # and the rotation terms matter at that speed
    assert np.abs(damped_frequencies(base.to_system().at_speed(300.0))[0]
                  / damped_frequencies(base.to_system().at_speed(0.0))[0] - 1) > 1e-3


# --------------------------------------------------------------------------- rigid body
def _rodrigues(theta):
    return Rotation.from_rotvec(theta).as_matrix()


def _left_jacobian(theta):
    a = np.linalg.norm(theta)
    S = skew(theta)
    if a < 1e-8:
        return np.eye(3) + 0.5 * S
    return np.eye(3) + (1 - np.cos(a)) / a**2 * S + (a - np.sin(a)) / a**3 * S @ S


def test_rigid_body_terms_linearise_the_exact_kinetic_energy():
    """M, G, K_d and f_c of a rigid body equal the linearisation of its exact kinetic energy.

    Reference: T = m |u' + Omega e x (r + u)|^2 / 2 + (Omega e + w)^T R J R^T (Omega e + w) / 2
    with R = exp(S(theta)) and w = J_l(theta) theta' (the left Jacobian of SO(3), checked
    here against a finite difference of R). Lagrange's equations linearised at q = 0 give
    M = T_q'q', Omega G = C - C^T (C = T_q'q), Omega^2 K_d = T_qq, Omega^2 f_c = T_q; these
    are evaluated by central differences (h = 1e-4, error ~1e-8) for a general inertia
    tensor, a skew spin axis and an off-axis body. Tolerance 1e-6 of the largest entry.
    """
    rng = np.random.default_rng(3)
    theta, dtheta = rng.normal(size=3) * 0.3, rng.normal(size=3)
    h = 1e-6
    dR = (_rodrigues(theta + h * dtheta) - _rodrigues(theta - h * dtheta)) / (2 * h)
    W = dR @ _rodrigues(theta).T
    np.testing.assert_allclose([W[2, 1], W[0, 2], W[1, 0]], _left_jacobian(theta) @ dtheta,
                               atol=1e-8)
    m = 1.7
    A = rng.normal(size=(3, 3))
    J = A @ A.T + 0.5 * np.eye(3)
    r0 = np.array([0.4, -0.2, 0.3])
    o = np.array([0.05, 0.1, -0.2])
    e = np.array([0.3, -0.5, 1.0]) / np.linalg.norm([0.3, -0.5, 1.0])
    Om = 1.3

    def kinetic(x):
        u, th, du, dth = x[:3], x[3:6], x[6:9], x[9:]
        v = du + Om * np.cross(e, r0 - o + u)
        R = _rodrigues(th)
        w = Om * e + _left_jacobian(th) @ dth
        return 0.5 * m * v @ v + 0.5 * w @ (R @ J @ R.T) @ w

    hh = 1e-4
    E = np.eye(12) * hh
    grad = np.array([(kinetic(E[i]) - kinetic(-E[i])) / (2 * hh) for i in range(12)])
    H = np.empty((12, 12))
    for i in range(12):
        for j in range(12):
            H[i, j] = (kinetic(E[i] + E[j]) - kinetic(E[i] - E[j]) - kinetic(-E[i] + E[j])
                       + kinetic(-E[i] - E[j])) / (4 * hh * hh)
    C = H[6:, :6]
    t = rigid_body_terms(m, J, r0, spin_axis=e * 2.0, spin_origin=o)
    scale = np.abs(H).max()
    np.testing.assert_allclose(t.M, H[6:, 6:], atol=1e-6 * scale)
    np.testing.assert_allclose(Om * t.G, C - C.T, atol=1e-6 * scale)
    np.testing.assert_allclose(Om**2 * t.Kd, H[:6, :6], atol=1e-6 * scale)
    np.testing.assert_allclose(Om**2 * t.fc, grad[:6], atol=1e-6 * scale)
    assert np.abs(t.fc[3:]).max() > 1e-2          # a centrifugal moment exists here


def test_rigid_motion_of_a_free_structure_reduces_to_the_equivalent_rigid_body():
    """Projected on rigid-body motions, the beam's M, G and f_c are the rigid body's.

    Reference: the kinetic energy of a rigid motion ``u = u_c + theta x (x - c)``, rotation
    theta, is that of one rigid body with the total mass at the centre of mass c and the
    inertia tensor ``sum (J_slice + rho A (|d|^2 I - d d^T)) dx`` (parallel axes). Hermite and
    linear shape functions reproduce rigid motions exactly, so ``Phi^T M Phi``,
    ``Phi^T G Phi`` and ``Phi^T f_c`` (force, and moment about c) must equal
    :func:`rigid_body_terms` to round-off (1e-12). This checks the integration of the rotary
    gyroscopic and centrifugal-moment terms along the elements. (K_d differs by the
    second-order kinematics of a finite rotation, which a linear FE model leaves to K_w.)
    """
    nodes = np.array([[0.3, 0, 0], [0.35, 0.0, 0.01], [0.4, 0.01, 0.02], [0.45, 0.02, 0.02],
                      [0.42, 0.05, 0.03]])
    els = np.array([[0, 1], [1, 2], [2, 3], [2, 4]])
    secs = [BeamSection.rectangle(0.03 - 0.004 * i, 0.004 + 0.002 * i, **STEEL)
            for i in range(4)]
    ori = np.array([[0, 1, 0.3], [0, 1, 0.5], [0, 1, 0.7], [1, 0, 0.9]])
    Jp = np.array([[2e-5, 3e-6, 0], [3e-6, 1e-5, 1e-6], [0, 1e-6, 2.5e-5]])
    e, o = np.array([0.1, 0.2, 1.0]), np.array([0.01, 0.0, 0.1])
    model = beam_model(nodes, els, secs, orientation=ori, point_masses={3: (0.03, Jp)},
                       spin_axis=e, spin_origin=o, stress_stiffening=False)
    # equivalent rigid body, element by element
    parts = []                                            # (mass, centre, inertia about it)
    for (i, j), s, v in zip(els, secs, ori, strict=True):
        d = nodes[j] - nodes[i]
        ln = np.linalg.norm(d)
        t = d / ln
        ez = np.cross(t, v)
        ez /= np.linalg.norm(ez)
        Lam = np.stack([t, np.cross(ez, t), ez])
        m = s.rho_kg_m3 * s.area_m2 * ln
        J = (Lam.T @ np.diag([s.Ip_m4, s.Iy_m4, s.Iz_m4]) @ Lam * s.rho_kg_m3 * ln
             + m * ln**2 / 12 * (np.eye(3) - np.outer(t, t)))
        parts.append((m, 0.5 * (nodes[i] + nodes[j]), J))
    parts.append((0.03, nodes[3], Jp))
    m_tot = sum(p[0] for p in parts)
    c = sum(p[0] * p[1] for p in parts) / m_tot
    J_tot = sum(J + m * ((p - c) @ (p - c) * np.eye(3) - np.outer(p - c, p - c))
                for m, p, J in parts)
    ref = rigid_body_terms(m_tot, J_tot, c, spin_axis=e, spin_origin=o)
    Phi = np.zeros((model.n_nodes, 6, 6))
    for k in range(3):
        a = np.eye(3)[k]
        Phi[:, k, k] = 1.0
        Phi[:, :3, 3 + k] = np.cross(a, nodes - c)
        Phi[:, 3 + k, 3 + k] = 1.0
    Phi = Phi.reshape(-1, 6)
    r = model.rotation
    for got, want in ((Phi.T @ model.M.toarray() @ Phi, ref.M),
                      (Phi.T @ r.gyroscopic.toarray() @ Phi, ref.G),
                      (Phi.T @ r.centrifugal_load, ref.fc)):
        np.testing.assert_allclose(got, want, atol=1e-12 * np.abs(want).max())
