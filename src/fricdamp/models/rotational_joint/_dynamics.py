"""Equations of motion of paper 002's rig as compiled kernels, and its Newmark integrator.

The mass matrix, the velocity, gravity and suspension terms, the shaker's generalised force
and the energies of 002 (6) / (A.2), the Newton step of the Newmark average-acceleration rule
(numba), and ``_newmark``, the time loop behind :meth:`RotationalJointRig.simulate`. The
equations and the integration scheme are written out in
:mod:`fricdamp.models.rotational_joint.model`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from fricdamp.errors import ConvergenceError

if TYPE_CHECKING:
    from fricdamp.models.rotational_joint._rig import RotationalJointRig


# par = [I1, I2, m1, m2, d3, d5, g, k_t, c_t, k_x, c_x, d_F]
@njit(cache=True, nogil=True)
def _rig_mass(q, par):  # pragma: no cover - compiled
    t1, t2 = q[0], q[1]
    m2, d3, d5 = par[3], par[4], par[5]
    c12 = m2 * d3 * d5 * math.cos(t1 - t2)
    c13 = m2 * d3 * math.cos(t1)
    c23 = m2 * d5 * math.cos(t2)
    M = np.empty((3, 3))
    M[0, 0], M[0, 1], M[0, 2] = par[0] + m2 * d3 * d3, c12, c13
    M[1, 0], M[1, 1], M[1, 2] = c12, par[1] + m2 * d5 * d5, c23
    M[2, 0], M[2, 1], M[2, 2] = c13, c23, par[2] + m2
    return M


@njit(cache=True, nogil=True)
def _rig_internal(q, v, par):  # pragma: no cover - compiled
    t1, t2, x1 = q[0], q[1], q[2]
    w1, w2, vx = v[0], v[1], v[2]
    m2, d3, d5, g = par[3], par[4], par[5], par[6]
    s12 = math.sin(t1 - t2)
    out = np.empty(3)
    out[0] = (m2 * d3 * d5 * w2 * w2 * s12 + m2 * g * d3 * math.sin(t1)
              + par[7] * t1 + par[8] * w1)
    out[1] = -m2 * d3 * d5 * w1 * w1 * s12 + m2 * g * d5 * math.sin(t2)
    out[2] = (-m2 * d5 * w2 * w2 * math.sin(t2) - m2 * d3 * w1 * w1 * math.sin(t1)
              + par[9] * x1 + par[10] * vx)
    return out


@njit(cache=True, nogil=True)
def _rig_excitation(q, force, par):  # pragma: no cover - compiled
    out = np.empty(3)
    out[0] = force * par[11] * math.cos(q[0])
    out[1] = 0.0
    out[2] = force
    return out


@njit(cache=True, nogil=True)
def _rig_energies(q, v, par):  # pragma: no cover - compiled
    """(kinetic, potential) [J]."""
    M = _rig_mass(q, par)
    kin = 0.0
    for i in range(3):
        for j in range(3):
            kin += 0.5 * v[i] * M[i, j] * v[j]
    m2, d3, d5, g = par[3], par[4], par[5], par[6]
    pot = (m2 * g * (d5 * (1.0 - math.cos(q[1])) + d3 * (1.0 - math.cos(q[0])))
           + 0.5 * par[7] * q[0] * q[0] + 0.5 * par[9] * q[2] * q[2])
    return kin, pot


@njit(cache=True, nogil=True)
def _rig_newton(q, v, a, q1, f1, kt, force1, h, par):  # pragma: no cover - compiled
    """Newton update dq of the Newmark step equation at q1 (joint force f1, tangent kt).

    Residual ``M(q1) a1 + h + g + s + P^T f1 - Q`` with the Newmark a1, v1 of q1; Jacobian
    with the mass, the velocity terms' and dampers' derivatives, gravity, suspension and
    joint stiffness (the angle derivatives of M(q) a1 omitted). Returns (dq, a1, v1).
    """
    c0, c1, c2 = 4.0 / (h * h), 2.0 / h, 4.0 / h
    a1 = c0 * (q1 - q) - c2 * v - a
    v1 = v + 0.5 * h * (a + a1)
    M = _rig_mass(q1, par)
    R = M @ a1 + _rig_internal(q1, v1, par) - _rig_excitation(q1, force1, par)
    R[0] += f1
    R[1] -= f1
    m2, d3, d5, g = par[3], par[4], par[5], par[6]
    s12 = math.sin(q1[0] - q1[1])
    J = c0 * M
    J[0, 0] += c1 * par[8] + par[7] + m2 * g * d3 * math.cos(q1[0]) + kt
    J[0, 1] += c1 * 2.0 * m2 * d3 * d5 * v1[1] * s12 - kt
    J[1, 0] += -c1 * 2.0 * m2 * d3 * d5 * v1[0] * s12 - kt
    J[1, 1] += m2 * g * d5 * math.cos(q1[1]) + kt
    J[2, 0] += -c1 * 2.0 * m2 * d3 * v1[0] * math.sin(q1[0])
    J[2, 1] += -c1 * 2.0 * m2 * d5 * v1[1] * math.sin(q1[1])
    J[2, 2] += c1 * par[10] + par[9]
    dq = np.linalg.solve(J, -R)
    return dq, a1, v1


def _newmark(rig: RotationalJointRig, q, v, h, n_steps, force, tol, max_iter) -> dict:
    """Newmark average acceleration with Newton on the 3 coordinates (module docstring).

    A step is accepted when the Newton update computed at the current iterate is below
    ``tol`` times the coordinates' scale; the iterate (not iterate + update) is kept, so the
    committed contact state is exactly the one of the accepted coordinates.
    """
    par = rig._par()
    law = rig.joint
    damp = np.array([par[8], 0.0, par[10]])
    u1 = np.zeros((1, 1))

    state = law.initial_state()
    u1[0, 0] = q[0] - q[1]
    r = law.step(state, u1)
    fj, state = float(r.force.reshape(-1)[0]), r.state
    F = force(0.0)
    Pf = np.array([fj, -fj, 0.0])
    a = np.linalg.solve(_rig_mass(q, par), _rig_excitation(q, F, par)
                        - _rig_internal(q, v, par) - Pf)

    n = n_steps + 1
    T = h * np.arange(n)
    Q, V, A = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    ROT, TOR, FRC = np.empty(n), np.empty(n), np.empty(n)
    E = {k: np.zeros(n) for k in ("input_work", "joint_work", "suspension_dissipation",
                                   "kinetic", "potential")}
    Q[0], V[0], A[0], ROT[0], TOR[0], FRC[0] = q, v, a, q[0] - q[1], fj, F
    E["kinetic"][0], E["potential"][0] = _rig_energies(q, v, par)
    w_in = w_joint = w_sus = 0.0
    n_newton = 0
    scale = max(float(np.max(np.abs(q))), 1e-12)
    for k in range(1, n):
        t1 = T[k]
        F1 = force(t1)
        q1 = q + h * v + 0.25 * h * h * a  # predictor: a1 = a
        converged = False
        for _ in range(max_iter + 1):
            u1[0, 0] = q1[0] - q1[1]
            rr = law.step(state, u1)
            f1 = float(rr.force.reshape(-1)[0])
            kt = float(rr.stiffness.reshape(-1)[0])
            dq, a1, v1 = _rig_newton(q, v, a, q1, f1, kt, F1, h, par)
            n_newton += 1
            scale = max(scale, float(np.max(np.abs(q1))))
            if float(np.max(np.abs(dq))) <= tol * scale:
                converged = True
                break
            q1 = q1 + dq
        if not converged:
            raise ConvergenceError(f"the rig's Newton iteration did not converge at t = {t1:.6g}"
                                   f" s within {max_iter} iterations (last update "
                                   f"{float(np.max(np.abs(dq))):.3g}); try more "
                                   "steps_per_period")
        dqs = q1 - q
        w_in += 0.5 * float((_rig_excitation(q, F, par) + _rig_excitation(q1, F1, par)) @ dqs)
        w_sus += 0.5 * float((damp * (v + v1)) @ dqs)
        w_joint += 0.5 * (fj + f1) * ((q1[0] - q1[1]) - (q[0] - q[1]))
        q, v, a, fj, F, state = q1, v1, a1, f1, F1, rr.state
        Q[k], V[k], A[k], ROT[k], TOR[k], FRC[k] = q, v, a, q[0] - q[1], fj, F
        E["input_work"][k], E["joint_work"][k], E["suspension_dissipation"][k] = (
            w_in, w_joint, w_sus)
        E["kinetic"][k], E["potential"][k] = _rig_energies(q, v, par)
    return dict(t=T, q=Q, v=V, a=A, rotation=ROT, torque=TOR, force=FRC, energy=E,
                n_newton=n_newton)
