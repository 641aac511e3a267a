"""Contact kinematics of the paper-000 blade-damper model (sympy derivation, lambdified).

References: Pfeiffer & Hajek (1992), paper 000, equations (8)-(15) (closing conditions),
(20)-(21) (linearised rolling constraints), (23)-(28) (relative velocities), (32)-(33).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper._kinematics import kinematics, linearised_kinematics

RNG = np.random.default_rng(20260101)


def _random_state(scale=1e-4, rot=0.05):
    q = np.zeros(7)
    q[:4] = RNG.uniform(-scale, scale, 4)
    q[4] = RNG.uniform(-rot, rot)
    return q


@pytest.fixture(params=["parabola", "circle"])
def system(request):
    return BladeDamperSystem(BladeDamperParameters(contour=request.param))


def test_paper_eq13_eq14_reproduced_symbol_for_symbol():
    """000 (13) and (14): contact parameters xi_i and the abscissa x_K1 of contact K1.

    The closed-form solution of the two gap equations must equal the paper's printed
    expressions at random (q1, q3, q5, gamma) for the parabola; tolerance 1e-12 relative
    (round-off of two different algebraic forms of the same expression).
    """
    kin = kinematics("parabola")
    p1, p2 = -80.0, 0.002
    for _ in range(20):
        q1, q3 = RNG.uniform(-2e-3, 2e-3, 2)
        q5 = RNG.uniform(-0.2, 0.2)
        g = RNG.uniform(0.5, 1.3)
        xi1, xi2 = kin.contact_parameter(q5, g, p1, p2)
        assert xi1 == pytest.approx(1 / np.tan(g + q5) / (2 * p1), rel=1e-12)
        assert xi2 == pytest.approx(-1 / np.tan(g - q5) / (2 * p1), rel=1e-12)
        rS, _, _ = kin.reduced(q1, q3, q5, g, p1, p2)
        _, _, _, _, _, arms = kin.terms(q1, q3, q5, rS[0], rS[1], 0.0, g, p1, p2)
        xK1 = rS[0] + arms[0, 0]
        paper = 0.5 * (q1 + q3) + np.sin(g) ** 2 * np.cos(g) / (
            2 * p1 * np.sin(g + q5) ** 2 * np.sin(g - q5))
        assert xK1 == pytest.approx(paper, rel=1e-12, abs=1e-15)
        # 000 (15): r_S = r_K1 - A02(q5) (xi1, eta1)
        eta1 = p1 * xi1**2 + p2
        A = np.array([[np.cos(q5), -np.sin(q5)], [np.sin(q5), np.cos(q5)]])
        assert np.allclose(arms[0], A @ [xi1, eta1], rtol=1e-12, atol=1e-16)


def test_closed_form_centre_closes_both_gaps(system):
    """000 (13)-(15) keep both contacts closed: g_N(q) = 0 to round-off (1e-15 m)."""
    for _ in range(10):
        z = _random_state(1e-3, 0.2)[:5]
        q, _ = system.full_state(z)
        assert np.max(np.abs(system.normal_gap(q))) < 1e-15


def _fd_grad(fun, q, h):
    out = []
    for k in range(q.size):
        e = np.zeros_like(q)
        e[k] = h[k]
        out.append((fun(q + e) - fun(q - e)) / (2 * h[k]))
    return np.array(out)


def test_normal_jacobian_is_gap_gradient(system):
    """W_N = dg_N/dq (000 (32)): central differences, step 1e-7 m / 1e-6 rad, tolerance
    1e-7 absolute on entries of order 1 (truncation error h^2 g''' ~ 1e-12 and round-off
    1e-16 m / 1e-7 m = 1e-9)."""
    h = np.array([1e-7] * 4 + [1e-6] + [1e-7] * 2)
    for _ in range(5):
        q = _random_state(1e-3, 0.2)
        q[5:] = RNG.uniform(-1e-3, 1e-3, 2)
        WN = system.normal_jacobian(q)
        fd = _fd_grad(system.normal_gap, q, h)
        assert np.allclose(WN, fd, atol=1e-7, rtol=0)


def test_tangent_jacobian_is_material_point_velocity(system):
    """gamma_T = W_T^T q' (000 (23)-(25)): the velocity of the damper material point at the
    contact minus the platform velocity, projected on the platform tangent. The material
    point is frozen in the body frame and its velocity found by central differences along
    the motion (step 1e-7 s); tolerance 1e-8 relative."""
    p = system.params
    g = p.gamma
    tangents = [np.array([np.sin(g), np.cos(g)]), np.array([np.sin(g), -np.cos(g)])]
    for _ in range(5):
        q = _random_state(1e-3, 0.2)
        q[5:] = RNG.uniform(-1e-3, 1e-3, 2)
        qd = RNG.normal(size=7) * np.array([1, 1, 1, 1, 100, 1, 1]) * 0.1
        arms = system.contact_points(q) - q[5:]
        A = np.array([[np.cos(q[4]), -np.sin(q[4])], [np.sin(q[4]), np.cos(q[4])]])
        body = [A.T @ a for a in arms]
        dt = 1e-7

        def material(i, s, body=body, q=q, qd=qd):
            qq = q + s * qd
            As = np.array([[np.cos(qq[4]), -np.sin(qq[4])], [np.sin(qq[4]), np.cos(qq[4])]])
            return qq[5:] + As @ body[i]

        expected = []
        for i, plat in ((0, 0), (1, 2)):
            v = (material(i, dt) - material(i, -dt)) / (2 * dt)
            expected.append(tangents[i] @ (v - np.array([qd[plat], 0.0])))
        assert np.allclose(system.slip_velocity(q, qd), expected, rtol=1e-8, atol=1e-12)


def test_wbar_terms_are_time_derivatives(system):
    """wbar = (dW/dt)^T q' (000 (32)-(33)): along q(t) = q + q' t (q'' = 0) the contact
    accelerations reduce to wbar; central differences of W(q(t))^T q', step 1e-6 s,
    tolerance 1e-6 relative."""
    for _ in range(5):
        q = _random_state(1e-3, 0.2)
        qd = RNG.normal(size=7) * np.array([1, 1, 1, 1, 100, 1, 1]) * 0.1
        WN, WT, wN, wT = system.kinematics(q, qd)
        dt = 1e-6
        dN = (system.normal_jacobian(q + dt * qd).T @ qd
              - system.normal_jacobian(q - dt * qd).T @ qd) / (2 * dt)
        dT = (system.tangent_jacobian(q + dt * qd).T @ qd
              - system.tangent_jacobian(q - dt * qd).T @ qd) / (2 * dt)
        assert np.allclose(wN, dN, rtol=1e-6, atol=1e-9 * np.abs(dN).max())
        assert np.allclose(wT, dT, rtol=1e-6, atol=1e-9 * np.abs(dT).max())


def test_linearised_forms_match_nonlinear_at_reference(system):
    """The hand-linearised damper centre and the paper's rolling constraints 000 (20)-(21)
    are the Jacobians of the nonlinear forms at q = 0 (tolerance 1e-12, round-off)."""
    p = system.params
    lin = system.linearised_kinematics()
    _, J, _ = system.damper_centre(0.0, 0.0, 0.0)
    assert np.allclose(J, lin["J"], rtol=1e-12, atol=1e-15)
    # reduced slip-velocity coefficients d gamma_T / d(q1', q3', q5') at q = 0
    q0 = np.zeros(7)
    T = np.zeros((7, 3))
    T[[0, 2, 4], [0, 1, 2]] = 1.0
    T[5:, :] = J
    G = system.tangent_jacobian(q0).T @ T
    assert np.allclose(G, lin["G"], rtol=1e-12, atol=1e-15)
    if p.contour == "parabola":
        # 000 (20): stick in K1 <=> q5' = p1 (q1' - q3'); 000 (21): K2 <=> q5' = -p1 (q1' - q3')
        assert G[0] @ [1.0, 0.0, p.p1] == pytest.approx(0.0, abs=1e-12)
        assert G[0] @ [0.0, 1.0, -p.p1] == pytest.approx(0.0, abs=1e-12)
        assert G[1] @ [1.0, 0.0, -p.p1] == pytest.approx(0.0, abs=1e-12)
        assert G[1] @ [0.0, 1.0, p.p1] == pytest.approx(0.0, abs=1e-12)


def test_linearised_kinematics_error_is_second_order(system):
    """Linearised vs nonlinear damper centre: the error is O(eps^2) in the displacement
    scale eps (000 (13)-(15) linearised): halving eps divides it by 4 (accepted 3.6-4.4:
    the third-order term still contributes a few percent at eps = 1e-2 rad)."""
    lin = system.linearised_kinematics()["J"]
    direction = np.array([0.7e-3, -0.4e-3, 1.0])  # (q1, q3, q5) per unit eps [m, m, rad]
    errs = []
    for eps in (2e-2, 1e-2, 5e-3):
        z = eps * direction
        rS, _, _ = system.damper_centre(*z)
        errs.append(np.linalg.norm(rS - lin @ z))
    for a, b in zip(errs[:-1], errs[1:], strict=True):
        assert 3.6 < a / b < 4.4


def test_common_translation_leaves_gaps_and_slip_unchanged(system):
    """Moving platforms and damper together horizontally (the stuck motion 000 (22))
    changes neither gap nor slip velocity: W_N^T t = W_T^T t = 0 for t = e1 + e3 + e_xS."""
    q = _random_state(1e-3, 0.1)
    t = np.zeros(7)
    t[[0, 2, 5]] = 1.0
    WN, WT, _, _ = system.kinematics(q, np.zeros(7))
    assert np.allclose(WN.T @ t, 0.0, atol=1e-14)
    assert np.allclose(WT.T @ t, 0.0, atol=1e-14)
    assert np.allclose(system.normal_gap(q + 1e-3 * t), system.normal_gap(q), atol=1e-17)


def test_lambdified_functions_are_cached():
    """The sympy derivation runs once per contour (functools cache)."""
    assert kinematics("parabola") is kinematics("parabola")
    lin = linearised_kinematics("circle", 0.9, -80.0, 0.002)
    assert lin["J"].shape == (2, 3) and lin["G"].shape == (2, 3)


def test_import_does_not_run_sympy():
    """Importing fricdamp.models must not import sympy or matplotlib (lazy derivation)."""
    code = ("import sys, fricdamp, fricdamp.models, fricdamp.models.blade_damper.studies; "
            "print('sympy' in sys.modules, 'matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split()
    assert out == ["False", "False"]
