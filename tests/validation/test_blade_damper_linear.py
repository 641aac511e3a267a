"""Eigenfrequencies of the paper-000 blade-damper model against an independent linearisation.

The reference below does not use the sympy derivation: the contact geometry is found by
brute force (the support point of the damper contour in the direction of each platform
normal, by bounded scalar maximisation), the constraint Jacobians and the Hessian of the
centrifugal potential by finite differences of those nonlinear constraint equations.

* Stuck system (000 (4), (22)): null space of the four constraint gradients (two gaps, two
  stick conditions) -> projected M and K (including the geometric stiffness of the normal
  preload) -> eigenfrequencies.
* Free-sliding system (000 (1), mu = 0): reduced coordinates (q1..q5), damper centre from
  the two gap equations, potential 0.5 z^T K z - F_Z yS(z) -> finite-difference Hessian.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import minimize_scalar

from fricdamp.models import BladeDamperParameters, BladeDamperSystem


# ------------------------------------------------------------------ independent geometry
class Reference:
    """Brute-force contact geometry of the planar damper between two platform lines."""

    def __init__(self, p: BladeDamperParameters):
        self.p = p
        g = p.gamma
        self.n = [np.array([-np.cos(g), np.sin(g)]), np.array([np.cos(g), np.sin(g)])]
        self.t = [np.array([np.sin(g), np.cos(g)]), np.array([np.sin(g), -np.cos(g)])]
        if p.contour == "parabola":
            self.width = 0.05
            self.f = lambda x: p.p1 * x**2 + p.p2
        else:
            R = -1 / (2 * p.p1)
            self.width = R * (1 - 1e-12)
            self.f = lambda x: p.p2 - R + np.sqrt(R**2 - x**2)
        self.X0 = [self.support(i, 0.0)[1] for i in range(2)]

    def support(self, i, q5):
        """(max of n_i . A(q5) rho(xi), body point rho) over the contour."""
        A = np.array([[np.cos(q5), -np.sin(q5)], [np.sin(q5), np.cos(q5)]])

        def neg(x):
            return -self.n[i] @ (A @ [x, self.f(x)])

        r = minimize_scalar(neg, bounds=(-self.width, self.width), method="bounded",
                            options={"xatol": 1e-14})
        rho = np.array([r.x, self.f(r.x)])
        return -r.fun, A @ rho

    def gaps(self, q):
        out = []
        for i, plat in ((0, 0), (1, 2)):
            X = self.X0[i] + np.array([q[plat], 0.0])
            h, _ = self.support(i, q[4])
            out.append(self.n[i] @ (X - q[5:7]) - h)
        return np.array(out)

    def slip_rows(self, q):
        """Rows r_i with gamma_T,i = r_i . q' (material point of the damper at K_i)."""
        rows = []
        for i, plat in ((0, 0), (1, 2)):
            _, arm = self.support(i, q[4])
            r = np.zeros(7)
            r[5:7] = self.t[i]
            r[4] = self.t[i] @ np.array([-arm[1], arm[0]])
            r[plat] -= self.t[i][0]
            rows.append(r)
        return np.array(rows)

    def centre(self, z):
        """Damper centre closing both gaps: n_i . r_S = n_i . X_i - h_i (linear in r_S)."""
        A = np.array(self.n)
        b = [self.n[i] @ (self.X0[i] + np.array([z[plat], 0.0])) - self.support(i, z[4])[0]
             for i, plat in ((0, 0), (1, 2))]
        return np.linalg.solve(A, b)


def _fd_jacobian(fun, x, h):
    cols = []
    for k in range(x.size):
        e = np.zeros_like(x)
        e[k] = h[k]
        cols.append((fun(x + e) - fun(x - e)) / (2 * h[k]))
    return np.array(cols).T


def _eig_hz(K, M):
    lam = sla.eigh(K, M, eigvals_only=True)
    return np.sqrt(lam) / (2 * np.pi)


CASES = [BladeDamperParameters(),
         BladeDamperParameters().with_(gamma_deg=40.0, centrifugal_force=60.0),
         BladeDamperParameters(contour="circle", p1=-60.0, p2=3e-3).with_(gamma_deg=60.0)]


@pytest.mark.parametrize("p", CASES, ids=["default", "g40_FZ60", "circle_g60"])
def test_stuck_eigenfrequencies_vs_independent_linearisation(p):
    """Tolerance 1e-9 relative: the finite-difference constraint gradients (step 1e-7) are
    accurate to ~1e-10 (observed agreement ~1e-13); the projected geometric stiffness of the
    normal preload must vanish (a common translation leaves the gaps unchanged), which this
    reference includes."""
    s = BladeDamperSystem(p)
    st = s.static_equilibrium()
    ref = Reference(p)
    q0 = st.q
    h = np.full(7, 1e-7)
    C = np.vstack([_fd_jacobian(ref.gaps, q0, h), ref.slip_rows(q0)])  # (4, 7)
    N = sla.null_space(C)
    assert N.shape == (7, 3)
    # geometric stiffness of the preload: -sum lambda_N,i d2 g_i/dq2 (finite differences)
    Kg = np.zeros((7, 7))
    for i in range(2):
        H = _fd_jacobian(lambda x, i=i: _fd_jacobian(lambda y: ref.gaps(y)[i:i + 1], x,
                                                     np.full(7, 1e-5))[0], q0, np.full(7, 1e-5))
        Kg -= st.normal_force[i] * 0.5 * (H + H.T)
    M3 = N.T @ s.M @ N
    K3 = N.T @ (s.K + Kg) @ N
    f_ref = np.sort(_eig_hz(K3, M3))
    f = s.stuck_system().eigenfrequencies()
    assert np.allclose(f, f_ref, rtol=1e-9)


@pytest.mark.parametrize("p", CASES, ids=["default", "g40_FZ60", "circle_g60"])
def test_sliding_eigenfrequencies_vs_independent_linearisation(p):
    """Frictionless 5-DOF linearisation: M = J^T M7 J with J = d(q)/d(z) and
    K = K_springs - F_Z d2yS/dz2, both by finite differences of the brute-force centre
    (steps 1e-6 m / 1e-5 rad for J, 1e-5 m / 1e-4 rad for the Hessian). Tolerance 1e-6
    relative: nested central differences of the centre, whose support values are found to
    ~1e-19 m, leave ~1e-8 (observed 4e-8 at most)."""
    s = BladeDamperSystem(p)
    st = s.static_equilibrium()
    ref = Reference(p)
    z0 = st.q[:5]
    # the static state is an equilibrium of the reference potential too
    grad_yS = _fd_jacobian(lambda z: ref.centre(z)[1:2], z0,
                           np.array([1e-6, 1e-6, 1e-6, 1e-6, 1e-5]))[0]
    grad = s.K[:5, :5] @ z0 - p.centrifugal_force * grad_yS
    assert np.max(np.abs(grad)) < 1e-6 * p.centrifugal_force
    Jc = _fd_jacobian(ref.centre, z0, np.array([1e-6, 1e-6, 1e-6, 1e-6, 1e-5]))  # (2, 5)
    J = np.vstack([np.eye(5), Jc])
    M5 = J.T @ s.M @ J
    hh = np.array([1e-5, 1e-5, 1e-5, 1e-5, 1e-4])
    H = _fd_jacobian(lambda z: _fd_jacobian(lambda y: ref.centre(y)[1:2], z, hh)[0], z0, hh)
    K5 = s.K[:5, :5] - p.centrifugal_force * 0.5 * (H + H.T)
    f_ref = np.sort(_eig_hz(K5, M5))
    f = s.sliding_system().eigenfrequencies()
    assert np.allclose(f, f_ref, rtol=1e-6)


def test_stuck_eigenfrequencies_do_not_depend_on_gamma_or_contour():
    """000 (22): the stuck system is m1 + m3 + m5 on k1 + k3 with the blades; the contact
    geometry drops out (the paper's observation that the dip frequencies move with gamma and
    the parabola in Fig. 11 must come from differences between its rig configurations)."""
    f0 = BladeDamperSystem(BladeDamperParameters()).stuck_system().eigenfrequencies()
    for p in CASES[1:]:
        assert np.allclose(BladeDamperSystem(p).stuck_system().eigenfrequencies(), f0,
                           rtol=1e-12)


def test_stuck_eigenfrequencies_bracket_sliding_ones_for_blades():
    """Sticking couples the platforms: the stuck system has one platform mode fewer than
    the sliding one (3 vs 5 modes) and, by Rayleigh's interlacing for a constrained system,
    its k-th frequency lies between the k-th and (k+2)-th frequencies of the sliding one."""
    s = BladeDamperSystem(BladeDamperParameters())
    fs = s.stuck_system().eigenfrequencies()
    fl = s.sliding_system().eigenfrequencies()
    for k in range(3):
        assert fl[k] <= fs[k] * (1 + 1e-12) and fs[k] <= fl[k + 2] * (1 + 1e-12)
