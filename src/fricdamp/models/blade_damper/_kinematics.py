"""Symbolic contact kinematics of the planar blade-damper model of paper 000.

The nonlinear closing conditions 000 (5)-(15) and the relative velocities 000 (23)-(28) are
derived here once with sympy, turned into plain Python/numpy functions with ``lambdify`` and
kept in memory (:func:`kinematics`). Nothing here runs at import time: the sympy work is done
on the first call (about one second) so that ``import fricdamp`` stays fast.

Geometry (derived again from the mechanics; the extracted text of the paper garbles some of
it, e.g. ``b0`` in 000 (12) must read ``p2 - cot(gamma)**2 / (4 p1)``)::

    frame 0:  x along the platform motion q1, q3; y radially outwards (F_Z acts along +y)
    damper:   body frame (xi, eta), rotation q5, centre of mass S = (xS, yS);
              contour eta = p1 xi**2 + p2 (parabola, p1 < 0 < p2, 000 (10)) or the circle with
              the same apex height p2 and apex curvature, radius R = -1/(2 p1)
    line 1:   platform of blade 1, slope cot(gamma) 000 (11)-(12), translating with q1,
              tangent t1 = (sin g, cos g), normal n1 = (-cos g, sin g) (from damper to platform)
    line 2:   platform of blade 2, slope -cot(gamma), translating with q3,
              tangent t2 = (sin g, -cos g), normal n2 = (cos g, sin g)

In the reference configuration (q = 0) the damper is unrotated with S at the origin and
touches both lines. The tangency condition 000 (9) gives the contour parameter of the contact
points in closed form, 000 (13): ``xi1 = cot(g + q5)/(2 p1)``, ``xi2 = -cot(g - q5)/(2 p1)``
(circle: ``xi1 = -R cos(g + q5)``, ``xi2 = R cos(g - q5)``). With the arms
``a_i = A02(q5) (xi_i, eta_i)`` (000 (8)) the two bilateral normal constraints are the gaps

    g_i(q) = n_i . (X_i(q1 or q3) - r_S - a_i(q5)) = 0,

linear in r_S, so r_S(q1, q3, q5) follows in closed form: that is 000 (13)-(15) (a unit test
checks the expression for x_K1 of 000 (14) symbol for symbol at random points). The tangential
relative velocity of the damper material point against the platform, 000 (23)-(24),

    gamma_T,i = t_i . (r_S' + q5' e_z x a_i - (q1' or q3') e_x),

is the quantity that vanishes in stiction (rolling without sliding, 000 (16)-(21)).

Generalised coordinates follow 000 (30): q = (q1, q2, q3, q4, q5, xS, yS).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

CONTOURS = ("parabola", "circle")
N_DOF = 7
DOF_NAMES = ("q1", "q2", "q3", "q4", "q5", "xS", "yS")


@dataclass(frozen=True)
class KinematicsFunctions:
    """Lambdified contact kinematics for one contour shape.

    Every function takes the geometric parameters ``(gamma, p1, p2)`` last (``gamma`` in rad,
    ``p1`` in 1/m, ``p2`` in m).

    Attributes
    ----------
    contour : str
        ``"parabola"`` or ``"circle"``.
    terms : callable
        ``terms(q1, q3, q5, xS, yS, u5, gamma, p1, p2) -> (gap, W_N, W_T, wbar_N, wbar_T, arms)``
        with ``gap`` (2,) [m], ``W_N``, ``W_T`` (7, 2) [-, m for the q5 row], ``wbar_N``,
        ``wbar_T`` (2,) [m/s^2] and ``arms`` (2, 2) [m] (row i: r_Ki - r_S in frame 0).
    reduced : callable
        ``reduced(q1, q3, q5, gamma, p1, p2) -> (r_S, J, H)``: the closed-form centre of the
        damper (2,) [m] of 000 (13)-(15), its Jacobian (2, 3) and Hessian (2, 3, 3) with
        respect to ``(q1, q3, q5)``.
    contact_parameter : callable
        ``contact_parameter(q5, gamma, p1, p2) -> (xi1, xi2)`` [m], 000 (13).
    """

    contour: str
    terms: Callable
    reduced: Callable
    contact_parameter: Callable


def _contour_point(sp, contour, slope_angle, p1, p2):
    """Body-frame point (xi, eta) of the contour whose tangent makes ``slope_angle`` with xi.

    ``slope_angle`` is the angle of the platform line seen in the body frame; tangency 000 (9)
    requires d eta / d xi = tan(slope_angle).
    """
    if contour == "parabola":
        xi = sp.tan(slope_angle) / (2 * p1)
        eta = p1 * xi**2 + p2
    else:  # circle of radius R = -1/(2 p1) with apex at eta = p2
        R = -1 / (2 * p1)
        # eta = p2 - R + sqrt(R^2 - xi^2); eta' = -xi / sqrt(R^2 - xi^2) = tan(alpha)
        xi = -R * sp.sin(slope_angle)
        eta = p2 - R + R * sp.cos(slope_angle)
    return xi, eta


@functools.cache
def derive(contour: str) -> dict:
    """Derive the contact kinematics symbolically (sympy), once per contour shape.

    Returns
    -------
    dict
        sympy symbols and expressions: ``q`` (7 symbols), ``u`` (7 velocity symbols),
        ``params`` (gamma, p1, p2), ``xi`` (2,), ``arms`` (2x2 Matrix), ``gap`` (2,),
        ``W_N``, ``W_T`` (7x2 Matrices), ``wbar_N``, ``wbar_T`` (2,), ``gamma_T`` (2,),
        ``r_S_reduced`` (2,) as functions of (q1, q3, q5).
    """
    if contour not in CONTOURS:
        raise ValueError(f"contour must be one of {CONTOURS}, got {contour!r}")
    import sympy as sp

    q = sp.symbols("q1 q2 q3 q4 q5 xS yS", real=True)
    u = sp.symbols("u1:8", real=True)
    gamma, p1, p2 = sp.symbols("gamma p1 p2", real=True)
    q1, _, q3, _, q5, xS, yS = q
    c, s = sp.cos(gamma), sp.sin(gamma)
    t = [sp.Matrix([s, c]), sp.Matrix([s, -c])]
    n = [sp.Matrix([-c, s]), sp.Matrix([c, s])]
    A = sp.Matrix([[sp.cos(q5), -sp.sin(q5)], [sp.sin(q5), sp.cos(q5)]])  # 000 (8)
    # line slopes seen from the rotated body frame: pi/2 - (gamma + q5) and -(pi/2 - gamma + q5)
    angles = [sp.pi / 2 - gamma - q5, -(sp.pi / 2 - gamma) - q5]
    xi, arms = [], []
    for ang in angles:
        x_i, e_i = _contour_point(sp, contour, ang, p1, p2)
        xi.append(x_i)
        arms.append(A * sp.Matrix([x_i, e_i]))
    arms0 = [a.subs(q5, 0) for a in arms]
    X = [arms0[0] + sp.Matrix([q1, 0]), arms0[1] + sp.Matrix([q3, 0])]
    r_S = sp.Matrix([xS, yS])
    gap = [n[i].dot(X[i] - r_S - arms[i]) for i in range(2)]
    W_N = sp.Matrix([[sp.diff(g, qk) for g in gap] for qk in q])  # (7, 2)
    # damper material point velocity at K_i minus platform velocity, along the tangent
    platform_u = [u[0], u[2]]
    gamma_T = []
    for i in range(2):
        a = arms[i]
        v_d = sp.Matrix([u[5] - u[4] * a[1], u[6] + u[4] * a[0]])
        gamma_T.append(t[i].dot(v_d - sp.Matrix([platform_u[i], 0])))
    W_T = sp.Matrix([[sp.diff(gt, uk) for gt in gamma_T] for uk in u])  # (7, 2)
    uvec = sp.Matrix(u)

    def wbar(W):
        # d/dt (W^T) u with q'' = 0: sum_k dW/dq_k u_k, transposed, times u
        dW = sp.zeros(*W.shape)
        for k in range(N_DOF):
            dW += sp.diff(W, q[k]) * u[k]
        return list(dW.T * uvec)

    wbar_N = wbar(W_N)
    wbar_T = wbar(W_T)
    # closed-form damper centre 000 (13)-(15): gaps are linear in r_S
    sol = sp.solve(gap, [xS, yS], dict=True)[0]
    r_S_red = [sol[xS], sol[yS]]
    return {
        "q": q, "u": u, "params": (gamma, p1, p2), "xi": xi, "arms": arms,
        "gap": gap, "W_N": W_N, "W_T": W_T, "wbar_N": wbar_N, "wbar_T": wbar_T,
        "gamma_T": gamma_T, "r_S_reduced": r_S_red,
    }


@functools.cache
def kinematics(contour: str = "parabola") -> KinematicsFunctions:
    """Lambdified kinematics for ``contour``, derived on first use and cached in memory."""
    import sympy as sp

    d = derive(contour)
    q, u, par = d["q"], d["u"], d["params"]
    q1, _, q3, _, q5, xS, yS = q
    arms = sp.Matrix([[d["arms"][i][j] for j in range(2)] for i in range(2)])
    terms = sp.lambdify(
        (q1, q3, q5, xS, yS, u[4], *par),
        (sp.Matrix(d["gap"]), d["W_N"], d["W_T"], sp.Matrix(d["wbar_N"]),
         sp.Matrix(d["wbar_T"]), arms),
        modules="numpy", cse=True,
    )
    z = (q1, q3, q5)
    rS = sp.Matrix(d["r_S_reduced"])
    J = rS.jacobian(z)
    H = [sp.hessian(rS[k], z) for k in range(2)]
    reduced = sp.lambdify((q1, q3, q5, *par), (rS, J, H[0], H[1]), modules="numpy", cse=True)
    xi_f = sp.lambdify((q5, *par), tuple(d["xi"]), modules="numpy", cse=True)

    def terms_np(q1_, q3_, q5_, xS_, yS_, u5_, gamma_, p1_, p2_):
        g, WN, WT, wN, wT, ar = terms(q1_, q3_, q5_, xS_, yS_, u5_, gamma_, p1_, p2_)
        return (np.asarray(g, dtype=float).reshape(2), np.asarray(WN, dtype=float),
                np.asarray(WT, dtype=float), np.asarray(wN, dtype=float).reshape(2),
                np.asarray(wT, dtype=float).reshape(2), np.asarray(ar, dtype=float))

    def reduced_np(q1_, q3_, q5_, gamma_, p1_, p2_):
        r, Jm, H0, H1 = reduced(q1_, q3_, q5_, gamma_, p1_, p2_)
        return (np.asarray(r, dtype=float).reshape(2), np.asarray(Jm, dtype=float),
                np.stack([np.asarray(H0, dtype=float), np.asarray(H1, dtype=float)]))

    def xi_np(q5_, gamma_, p1_, p2_):
        return tuple(float(v) for v in xi_f(q5_, gamma_, p1_, p2_))

    return KinematicsFunctions(contour=contour, terms=terms_np, reduced=reduced_np,
                               contact_parameter=xi_np)


def linearised_kinematics(contour: str, gamma: float, p1: float, p2: float) -> dict:
    """Hand-linearised kinematics at q = 0 (the paper's linear forms), as a check.

    Derived by hand from the gap equations at q5 = 0 with ``xi1 = -xi2``, ``eta1 = eta2``:

    * damper centre: ``xS = (q1 + q3)/2 + q5 (cos g eta1 + sin g xi1)/cos g``,
      ``yS = cot g (q3 - q1)/2``;
    * relative velocities: ``gamma_T1 = (q3' - q1')/(2 sin g) + q5' xi1/cos g``,
      ``gamma_T2 = (q1' - q3')/(2 sin g) + q5' xi1/cos g``. For the parabola
      ``xi1/cos g = 1/(2 p1 sin g)``, so stiction in K1 reads ``q5' = p1 (q1' - q3')`` and in
      K2 ``q5' = -p1 (q1' - q3')``: the paper's 000 (20), (21).

    Returns
    -------
    dict
        ``J`` (2, 3): d(xS, yS)/d(q1, q3, q5); ``G`` (2, 3): d(gamma_T1, gamma_T2)/d(q1', q3',
        q5') (reduced to the 5 independent coordinates).
    """
    c, s = np.cos(gamma), np.sin(gamma)
    if contour == "parabola":
        xi1 = (c / s) / (2 * p1)
        eta1 = p1 * xi1**2 + p2
    else:
        R = -1.0 / (2 * p1)
        xi1 = -R * c
        eta1 = p2 - R + R * s
    D = c * eta1 + s * xi1
    J = np.array([[0.5, 0.5, D / c], [-0.5 * c / s, 0.5 * c / s, 0.0]])
    k5 = xi1 / c
    G = np.array([[-1 / (2 * s), 1 / (2 * s), k5], [1 / (2 * s), -1 / (2 * s), k5]])
    return {"J": J, "G": G}
