"""Compiled right-hand side, constraint solve and event functions of the blade-damper model.

The event-driven solver spends a blade-damper forcing period in a few hundred configuration
solves (000 (37)-(40)) and event-function evaluations. Through the generic path each one goes
through the lambdified kinematics and :class:`~fricdamp.solvers.event_switch.Evaluator`
(about 100 us of Python overhead for a 7-DOF, 2-contact problem). Here they are fused into
numba kernels:

* the contact kinematics 000 (5)-(28) (gaps, ``W_N``, ``W_T``, ``wbar_N``, ``wbar_T``) are
  printed once from the sympy derivation of :mod:`fricdamp.models.blade_damper._kinematics`
  as scalar Python source (common subexpressions eliminated), written to the package's
  cache directory (``$FRICDAMP_CACHE_DIR``, else ``$XDG_CACHE_HOME/fricdamp``, else
  ``~/.cache/fricdamp``; never the repository), imported and compiled with
  ``numba.njit(cache=True)``: generated once per contour shape and source version, compiled
  once per machine;
* the configuration solve (elimination of q'' from the constraint equations, a 2-4 unknown
  system solved by LU with partial pivoting), the power terms and the event functions are
  the hand-written kernels below, the same equations as
  :meth:`fricdamp.solvers.event_switch.Evaluator.solve` and
  :meth:`fricdamp.solvers.event_phase.NumericalPhase._g`.

* whole DOP853 phases (generated with the rest, ``phase_run``): SciPy's DOP853 step-size
  control, initial step and dense output re-coded step for step, each step's dense output
  kept as arrays and its event functions screened at its quarter points (as
  :meth:`~fricdamp.solvers.event_phase.NumericalPhase.advance` does); only a step whose
  samples change sign goes back to Python (:func:`~fricdamp.solvers.event_phase.first_event`),
  whose root refinement is SciPy's ``brentq`` re-coded on the step's dense output
  (``refine_root``); and the projection onto the constraints (``project``). The
  Runge-Kutta sums run in another order than SciPy's BLAS products, so the step sequence
  differs by round-off and the responses agree to the integration accuracy
  (``tests/unit/test_blade_damper_fused.py``).

* the event loop (generated with the rest, ``event_loop``, source and driver in
  :mod:`fricdamp.models.blade_damper._fastloop`): phases, switching decisions and samples
  of many events in one call, with the kernels above; it leaves to the Python loop of
  :mod:`fricdamp.solvers.event` every switch it would not take exactly as that loop does.

A configuration whose constraint matrix is (numerically) singular returns status 1 (4 from
``phase_run``) and the caller falls back to the generic path (minimum-norm multipliers).

The generic path stays the reference: ``tests/unit/test_blade_damper_compiled.py`` compares
both on random states and all configurations to 1e-12.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from fricdamp._numba_cache import njit

# layout of the parameter vector ``par`` (one float64 array: one argument to type-check)
_MINV, _K, _D, _F0 = 0, 7, 56, 105
_FE, _RATIO, _PHASE, _OMEGA, _GAMMA, _P1, _P2, _MUS, _MUD = range(112, 121)
PAR_SIZE = 121

STICK = 0
OPEN = 3  # event_switch.OPEN: a released contact that lifted off


def parameter_vector(system) -> np.ndarray:
    """The ``par`` vector of a :class:`~fricdamp.models.blade_damper.model.BladeDamperSystem`."""
    p = system.params
    par = np.empty(PAR_SIZE)
    par[_MINV:_MINV + 7] = 1.0 / np.diag(system.M)
    par[_K:_K + 49] = system.K.ravel()
    par[_D:_D + 49] = system.D.ravel()
    par[_F0:_F0 + 7] = 0.0
    par[_F0 + 6] = p.centrifugal_force
    par[_FE] = p.excitation_amplitude
    par[_RATIO] = p.excitation_ratio
    par[_PHASE] = p.excitation_phase
    par[_OMEGA] = p.omega
    par[_GAMMA], par[_P1], par[_P2] = p.gamma, p.p1, p.p2
    par[_MUS], par[_MUD] = p.mu_static, p.mu_sliding
    return par


# ----------------------------------------------------------------------------- kernels
@njit(cache=True)
def _lu_solve(A, b, n):
    """Solve the leading n x n block ``A x = b`` in place (partial pivoting); returns
    ``min |u_ii| / max |u_ii|`` (0: singular)."""
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                p = i
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        if A[k, k] == 0.0:
            return 0.0
        for i in range(k + 1, n):
            f = A[i, k] / A[k, k]
            for j in range(k + 1, n):
                A[i, j] -= f * A[k, j]
            b[i] -= f * b[k]
    umin, umax = np.inf, 0.0
    for k in range(n):
        u = abs(A[k, k])
        umin = min(umin, u)
        umax = max(umax, u)
    for k in range(n - 1, -1, -1):
        s = b[k]
        for i in range(k + 1, n):
            s -= A[k, i] * b[i]
        b[k] = s / A[k, k]
    return umin / umax


@njit(cache=True)
def forces(t, q, qd, par, h):
    """``h = F0 + F_E(t) - K q - D q'`` (the model's :meth:`h`)."""
    wt = par[_OMEGA] * t
    for i in range(7):
        s = par[_F0 + i]
        for j in range(7):
            s -= par[_K + 7 * i + j] * q[j] + par[_D + 7 * i + j] * qd[j]
        h[i] = s
    h[1] += par[_FE] * np.cos(wt)
    h[3] += par[_FE] * par[_RATIO] * np.cos(wt + par[_PHASE])


@njit(cache=True)
def configuration_solve(h, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN, lamT):
    """Accelerations and contact forces of one configuration, 000 (37)-(40).

    The normals of the closed contacts are constrained (their gaps stay closed); an open
    contact (mode ``OPEN``, a released damper that lifted off) carries no force. Unknowns:
    ``lambda_N`` of the closed contacts and ``lambda_T`` of the stuck ones. A slipping
    contact's friction force is ``-mu_sliding sigma_i s_i lambda_N,i`` (``sigma`` the tracked
    sign of the normal force), so its normal column is ``W_N,i - mu_sliding sigma_i s_i
    W_T,i``. Returns the pivot ratio of the constraint system (<= 1e-13: singular, outputs
    undefined; 1 when no contact is closed).
    """
    mud = par[_MUD]
    # columns of B (force directions) and C (constraint gradients)
    B = np.empty((7, 4))
    C = np.empty((7, 4))
    rhs = np.empty(4)
    m = 0
    for i in range(2):
        if modes[i] == OPEN:
            continue
        s = 0.0 if modes[i] == STICK else float(modes[i])
        f = mud * sigma[i] * s
        for k in range(7):
            B[k, m] = WN[k, i] - WT[k, i] * f
            C[k, m] = WN[k, i]
        rhs[m] = wbN[i]
        m += 1
    for i in range(2):
        if modes[i] == STICK:
            for k in range(7):
                B[k, m] = WT[k, i]
                C[k, m] = WT[k, i]
            rhs[m] = wbT[i]
            m += 1
    MiF = np.empty(7)
    for k in range(7):
        MiF[k] = par[_MINV + k] * h[k]
    A = np.zeros((4, 4))
    x = np.empty(4)
    for a in range(m):
        s = rhs[a]
        for k in range(7):
            s += C[k, a] * MiF[k]
        x[a] = -s
        for b in range(m):
            s = 0.0
            for k in range(7):
                s += C[k, a] * par[_MINV + k] * B[k, b]
            A[a, b] = s
    ratio = _lu_solve(A, x, m) if m > 0 else 1.0
    for k in range(7):
        s = MiF[k]
        for b in range(m):
            s += par[_MINV + k] * B[k, b] * x[b]
        qdd[k] = s
    j = 0
    for i in range(2):
        if modes[i] == OPEN:
            lamN[i] = 0.0
        else:
            lamN[i] = x[j]
            j += 1
    for i in range(2):
        if modes[i] == STICK:
            lamT[i] = x[j]
            j += 1
        elif modes[i] == OPEN:
            lamT[i] = 0.0
        else:
            lamT[i] = -mud * float(modes[i]) * abs(lamN[i])
    return ratio


@njit(cache=True)
def configuration_solve_given(h, WN, WT, wbN, wbT, modes, sigma, given, par, QDD, LN, LT):
    """:meth:`fricdamp.solvers.event_switch.Evaluator.solve` with GIVEN contacts (mode 2:
    tangential force prescribed, one column of ``given`` (2, k) per right-hand side) and
    open contacts (mode ``OPEN``, no force): ``QDD`` (7, k), ``LN``, ``LT`` (2, k). Returns
    the pivot ratio (<= 1e-13: singular; 1 when no contact is closed)."""
    mud = par[_MUD]
    k = given.shape[1]
    B = np.empty((7, 4))
    C = np.empty((7, 4))
    rhs = np.empty(4)
    m = 0
    for i in range(2):
        if modes[i] == OPEN:
            continue
        s = float(modes[i]) if (modes[i] == 1 or modes[i] == -1) else 0.0
        f = mud * sigma[i] * s
        for r in range(7):
            B[r, m] = WN[r, i] - WT[r, i] * f
            C[r, m] = WN[r, i]
        rhs[m] = wbN[i]
        m += 1
    for i in range(2):
        if modes[i] == STICK:
            for r in range(7):
                B[r, m] = WT[r, i]
                C[r, m] = WT[r, i]
            rhs[m] = wbT[i]
            m += 1
    A0 = np.zeros((4, 4))
    for a in range(m):
        for b in range(m):
            acc = 0.0
            for r in range(7):
                acc += C[r, a] * par[_MINV + r] * B[r, b]
            A0[a, b] = acc
    worst = 1.0
    A = np.empty((4, 4))
    x = np.empty(4)
    MiF = np.empty(7)
    for col in range(k):
        for r in range(7):
            fr = h[r]
            for i in range(2):
                if modes[i] == 2:
                    fr += WT[r, i] * given[i, col]
            MiF[r] = par[_MINV + r] * fr
        for a in range(m):
            acc = rhs[a]
            for r in range(7):
                acc += C[r, a] * MiF[r]
            x[a] = -acc
            for b in range(m):
                A[a, b] = A0[a, b]
        if m > 0:
            worst = min(worst, _lu_solve(A, x, m))
        for r in range(7):
            acc = MiF[r]
            for b in range(m):
                acc += par[_MINV + r] * B[r, b] * x[b]
            QDD[r, col] = acc
        j = 0
        for i in range(2):
            if modes[i] == OPEN:
                LN[i, col] = 0.0
            else:
                LN[i, col] = x[j]
                j += 1
        for i in range(2):
            if modes[i] == STICK:
                LT[i, col] = x[j]
                j += 1
            elif modes[i] == 2:
                LT[i, col] = given[i, col]
            elif modes[i] == OPEN:
                LT[i, col] = 0.0
            else:
                LT[i, col] = -mud * float(modes[i]) * abs(LN[i, col])
    return worst


@njit(cache=True)
def powers(t, qd, WT, lamT, par):
    """Input power of F_E, viscous power ``q'^T D q'`` and friction power ``lambda_T . gamma_T``."""
    wt = par[_OMEGA] * t
    p_in = par[_FE] * (np.cos(wt) * qd[1] + par[_RATIO] * np.cos(wt + par[_PHASE]) * qd[3])
    p_visc = 0.0
    for i in range(7):
        for j in range(7):
            p_visc += qd[i] * par[_D + 7 * i + j] * qd[j]
    p_fric = 0.0
    for i in range(2):
        g = 0.0
        for k in range(7):
            g += WT[k, i] * qd[k]
        p_fric += lamT[i] * g
    return p_in, p_visc, p_fric


@njit(cache=True)
def event_values(WT, qd, lamN, lamT, sigma, kinds, contacts, lim, sgn, g, scale, vel, q, gap,
                 WN):
    """Event functions of a configuration (the kinds of :mod:`fricdamp.solvers.event_phase`:
    0 slip velocity, 1/2 friction reserve at the +/- limit, 3 normal force, 4 the gap of an
    open contact) and their scales; ``vel`` is raised to ``|W_T|^T |q'|`` per contact."""
    gam = np.zeros(2)
    vs = np.zeros(2)
    for i in range(2):
        for k in range(7):
            gam[i] += WT[k, i] * qd[k]
            vs[i] += abs(WT[k, i]) * abs(qd[k])
        vel[i] = max(vel[i], vs[i])
    for e in range(kinds.size):
        c = contacts[e]
        absN = sigma[c] * lamN[c]
        res = lim[e] * absN
        kd = kinds[e]
        if kd == 0:
            g[e] = sgn[e] * gam[c]
            scale[e] = vs[c]
        elif kd == 4:
            g[e] = gap[c]
            acc = abs(gap[c])
            for k in range(7):
                acc += abs(WN[k, c]) * abs(q[k])
            scale[e] = acc
        else:
            if kd == 1:
                g[e] = res - lamT[c]
            elif kd == 2:
                g[e] = res + lamT[c]
            else:
                g[e] = sigma[c] * lamN[c]
            scale[e] = abs(res) + abs(lamT[c]) + abs(lamN[c])


# ----------------------------------------------------------------------------- generation
_FUSED = '''

from fricdamp.models.blade_damper._compiled import (configuration_solve, event_values,
                                                     forces, powers)


@njit(cache=True)
def _kin_state(q, qd, par, gap, WN, WT, wbN, wbT):
    kin(q[0], q[2], q[4], q[5], q[6], qd[4], par[{g}], par[{p1}], par[{p2}],
        gap, WN, WT, wbN, wbT)


@njit(cache=True)
def rhs(t, y, modes, sigma, par, out):
    """[q', q'', input power, viscous power, friction power] (17,); returns the pivot ratio."""
    q = y[:7]
    qd = y[7:14]
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
    h = np.empty(7)
    forces(t, q, qd, par, h)
    qdd = np.empty(7)
    lamN = np.empty(2)
    lamT = np.empty(2)
    ratio = configuration_solve(h, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN, lamT)
    for k in range(7):
        out[k] = qd[k]
        out[7 + k] = qdd[k]
    p_in, p_visc, p_fric = powers(t, qd, WT, lamT, par)
    out[14] = p_in
    out[15] = p_visc
    out[16] = p_fric
    return ratio


@njit(cache=True)
def jacobian(t, y, modes, sigma, par, steps, J):
    """Central-difference Jacobian (14, 14) of [q', q''] with the given steps; smallest
    pivot ratio."""
    out = np.empty(17)
    fp = np.empty(14)
    worst = 1.0
    yy = np.empty(14)
    for j in range(14):
        for k in range(14):
            yy[k] = y[k]
        yy[j] = y[j] + steps[j]
        worst = min(worst, rhs(t, yy, modes, sigma, par, out))
        for k in range(14):
            fp[k] = out[k]
        yy[j] = y[j] - steps[j]
        worst = min(worst, rhs(t, yy, modes, sigma, par, out))
        for k in range(14):
            J[k, j] = (fp[k] - out[k]) / (2.0 * steps[j])
    return worst


@njit(cache=True)
def solve_many(ts, Y, modes, sigma, par, QDD, LN, LT, WTS):
    """Configuration solves at the columns of Y (14 or more, n_t); smallest pivot ratio."""
    worst = 1.0
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    h = np.empty(7)
    qdd = np.empty(7)
    lamN = np.empty(2)
    lamT = np.empty(2)
    for j in range(ts.size):
        q = np.ascontiguousarray(Y[:7, j])
        qd = np.ascontiguousarray(Y[7:14, j])
        _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
        forces(ts[j], q, qd, par, h)
        r = configuration_solve(h, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN, lamT)
        worst = min(worst, r)
        QDD[:, j] = qdd
        LN[:, j] = lamN
        LT[:, j] = lamT
        WTS[:, :, j] = WT
    return worst


@njit(cache=True)
def events_many(ts, Y, modes, sigma, par, kinds, contacts, lim, sgn, G, S, vel):
    """Event functions and scales at the columns of Y; smallest pivot ratio."""
    worst = 1.0
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    h = np.empty(7)
    qdd = np.empty(7)
    lamN = np.empty(2)
    lamT = np.empty(2)
    g = np.empty(kinds.size)
    s = np.empty(kinds.size)
    for j in range(ts.size):
        q = np.ascontiguousarray(Y[:7, j])
        qd = np.ascontiguousarray(Y[7:14, j])
        _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
        forces(ts[j], q, qd, par, h)
        r = configuration_solve(h, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN, lamT)
        worst = min(worst, r)
        event_values(WT, qd, lamN, lamT, sigma, kinds, contacts, lim, sgn, g, s, vel, q,
                     gap, WN)
        G[:, j] = g
        S[:, j] = s
    return worst
'''

_PHASE_SRC = '''

from scipy.integrate._ivp import dop853_coefficients as _dc

from fricdamp.models.blade_damper._compiled import _MINV, OPEN, STICK, _lu_solve

_NS = 12
_DA = np.ascontiguousarray(_dc.A, dtype=np.float64)
_DB = np.ascontiguousarray(_dc.B, dtype=np.float64)
_DC = np.ascontiguousarray(_dc.C, dtype=np.float64)
_DE3 = np.ascontiguousarray(_dc.E3, dtype=np.float64)
_DE5 = np.ascontiguousarray(_dc.E5, dtype=np.float64)
_DD = np.ascontiguousarray(_dc.D, dtype=np.float64)
_NY = 17


@njit(cache=True)
def _stage_y(y, K, a_row, s, h, out):
    for k in range(_NY):
        acc = 0.0
        for j in range(s):
            acc += K[j, k] * a_row[j]
        out[k] = y[k] + acc * h


@njit(cache=True)
def dense_eval(t_old, h, y_old, F, t, out):
    """DOP853 dense output of one step at t (scipy's Dop853DenseOutput)."""
    x = (t - t_old) / h
    for k in range(out.size):
        out[k] = 0.0
    for i in range(7):
        f = F[6 - i]
        for k in range(out.size):
            out[k] += f[k]
            if i % 2 == 0:
                out[k] *= x
            else:
                out[k] *= 1.0 - x
    for k in range(out.size):
        out[k] += y_old[k]


@njit(cache=True)
def dense_many(TA, TB, YOLD, FF, idx, ts, Y):
    """Dense output at ts (segment idx[j] for ts[j]) into the columns of Y (17, n)."""
    out = np.empty(_NY)
    for j in range(ts.size):
        m = idx[j]
        dense_eval(TA[m], TB[m] - TA[m], YOLD[m], FF[m], ts[j], out)
        for k in range(_NY):
            Y[k, j] = out[k]


@njit(cache=True)
def _norm_err(K, h, scale):
    e5 = 0.0
    e3 = 0.0
    for k in range(_NY):
        a5 = 0.0
        a3 = 0.0
        for j in range(13):
            a5 += K[j, k] * _DE5[j]
            a3 += K[j, k] * _DE3[j]
        a5 /= scale[k]
        a3 /= scale[k]
        e5 += a5 * a5
        e3 += a3 * a3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    denom = e5 + 0.01 * e3
    return abs(h) * e5 / np.sqrt(denom * _NY)


@njit(cache=True)
def _rms(x, scale):
    s = 0.0
    for k in range(_NY):
        v = x[k] / scale[k]
        s += v * v
    return np.sqrt(s / _NY)


@njit(cache=True)
def _g_at(t, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn, vel,
          tol_i, ytmp, g, s):
    dense_eval(TA[j], TB[j] - TA[j], YOLD[j], FF[j], t, ytmp)
    q = ytmp[:7]
    qd = ytmp[7:14]
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    hh = np.empty(7)
    qdd = np.empty(7)
    lamN = np.empty(2)
    lamT = np.empty(2)
    _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
    forces(t, q, qd, par, hh)
    configuration_solve(hh, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN, lamT)
    event_values(WT, qd, lamN, lamT, sigma, kinds, contacts, lim, sgn, g, s, vel, q,
                     gap, WN)
    return g[i] + tol_i


@njit(cache=True)
def event_value(j, i, t, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn, vel):
    """Event function i at t on the dense output of step j (raises ``vel`` as _g does)."""
    return _g_at(t, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn, vel,
                 0.0, np.empty(_NY), np.empty(kinds.size), np.empty(kinds.size))


@njit(cache=True)
def refine_root(j, i, ta, tb, h_scale, tol_i, TA, TB, YOLD, FF, modes, sigma, par, kinds,
                contacts, lim, sgn, vel):
    """Root of event function i (plus its round-off level tol_i) in (ta, tb] of step j:
    :func:`fricdamp.solvers.event_phase._refine` with SciPy's ``brentq`` (brentq.c) on the
    step's dense output; returns a time where the function is <= 0."""
    eps = 2.220446049250313e-16
    ytmp = np.empty(_NY)
    g = np.empty(kinds.size)
    s = np.empty(kinds.size)
    xtol = 4 * eps * max(abs(ta), abs(tb), h_scale)
    if tb - ta <= xtol:
        return tb
    fa = _g_at(ta, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn, vel,
               tol_i, ytmp, g, s)
    fb = _g_at(tb, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn, vel,
               tol_i, ytmp, g, s)
    if fb > 0 or fa <= 0:
        return tb if fb > 0 else ta
    rtol = 4 * eps
    xpre, xcur = ta, tb
    fpre, fcur = fa, fb
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    r = xcur
    if fpre == 0:
        r = xpre
    elif fcur == 0:
        r = xcur
    else:
        for _ in range(200):
            if fpre != 0 and fcur != 0 and (np.signbit(fpre) != np.signbit(fcur)):
                xblk = xpre
                fblk = fpre
                spre = scur = xcur - xpre
            if abs(fblk) < abs(fcur):
                xpre = xcur
                xcur = xblk
                xblk = xpre
                fpre = fcur
                fcur = fblk
                fblk = fpre
            delta = (xtol + rtol * abs(xcur)) / 2
            sbis = (xblk - xcur) / 2
            if fcur == 0 or abs(sbis) < delta:
                break
            if abs(spre) > delta and abs(fcur) < abs(fpre):
                if xpre == xblk:
                    stry = -fcur * (xcur - xpre) / (fcur - fpre)
                else:
                    dpre = (fpre - fcur) / (xpre - xcur)
                    dblk = (fblk - fcur) / (xblk - xcur)
                    stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
                if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                    spre = scur
                    scur = stry
                else:
                    spre = sbis
                    scur = sbis
            else:
                spre = sbis
                scur = sbis
            xpre = xcur
            fpre = fcur
            if abs(scur) > delta:
                xcur += scur
            else:
                xcur += delta if sbis > 0 else -delta
            fcur = _g_at(xcur, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts,
                         lim, sgn, vel, tol_i, ytmp, g, s)
        r = xcur
    step = xtol
    while r < tb and _g_at(r, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
                           sgn, vel, tol_i, ytmp, g, s) > 0:
        r = min(tb, r + step)
        step *= 2
    return r


@njit(cache=True)
def dip_windows(v, tol, sits, wa, wb):
    """:func:`fricdamp.solvers.event_phase.dip_windows` on the five samples v (the function
    plus its round-off level tol): the windows' first and last sample indices into wa, wb;
    returns their number."""
    c = max(abs(v[0] - 2.0 * v[1] + v[2]), abs(v[1] - 2.0 * v[2] + v[3]),
            abs(v[2] - 2.0 * v[3] + v[4]))
    n = 0
    if not c > tol:
        return n
    for k in range(5):
        if not (0.0 < v[k] <= c):
            continue
        if (k > 0 and v[k] > v[k - 1]) or (k < 4 and v[k] > v[k + 1]) or (k == 0 and sits):
            continue
        wa[n] = max(k - 1, 0)
        wb[n] = min(k + 1, 4)
        n += 1
    return n


@njit(cache=True)
def dip_search(j, i, ta, tb, tol_i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
               sgn, vel):
    """A time in [ta, tb] where event function i plus tol_i is <= 0 on the dense output of
    step j, or NaN: :func:`fricdamp.solvers.event_phase.dip_search` (Brent's bounded
    minimisation, Brent's localmin, window mapped to [0, 1], location to 1e-5 of the
    window, stopped at the first point <= 0), operation for operation."""
    ytmp = np.empty(_NY)
    g = np.empty(kinds.size)
    s = np.empty(kinds.size)
    span = tb - ta
    xatol = 1e-5
    eps_sqrt = np.sqrt(2.2e-16)
    gold = 0.5 * (3.0 - np.sqrt(5.0))
    a = 0.0
    b = 1.0
    v = a + gold * (b - a)
    w = v
    x = v
    d = 0.0
    e = 0.0
    fx = _g_at(ta + x * span, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
               sgn, vel, tol_i, ytmp, g, s)
    if fx <= 0:
        return ta + x * span
    n_eval = 1
    fv = fx
    fw = fx
    mid = 0.5 * (a + b)
    tol1 = eps_sqrt * abs(x) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(x - mid) > tol2 - 0.5 * (b - a) and n_eval < 100:
        golden = True
        if abs(e) > tol1:
            golden = False
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = d
            if abs(p) < abs(0.5 * q * r) and p > q * (a - x) and p < q * (b - x):
                d = p / q
                u = x + d
                if (u - a) < tol2 or (b - u) < tol2:
                    d = tol1 * (1.0 if mid >= x else -1.0)
            else:
                golden = True
        if golden:
            e = (a - x) if x >= mid else (b - x)
            d = gold * e
        u = x + (1.0 if d >= 0 else -1.0) * max(abs(d), tol1)
        fu = _g_at(ta + u * span, j, i, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
                   sgn, vel, tol_i, ytmp, g, s)
        n_eval += 1
        if fu <= 0:
            return ta + u * span
        if fu <= fx:
            if u >= x:
                a = x
            else:
                b = x
            v = w
            fv = fw
            w = x
            fw = fx
            x = u
            fx = fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v = w
                fv = fw
                w = u
                fw = fu
            elif fu <= fv or v == x or v == w:
                v = u
                fv = fu
        mid = 0.5 * (a + b)
        tol1 = eps_sqrt * abs(x) + xatol / 3.0
        tol2 = 2.0 * tol1
    return np.nan


@njit(cache=True)
def phase_run(y, f, t_end, modes, sigma, par, rtol, atol, max_step, kinds, contacts, lim,
              sgn, g_prev, scale, vel, TA, TB, YOLD, FF, m, GI, stats):
    """DOP853 steps of one configuration (scipy's DOP853 step-size control and dense output),
    each step screened for events at the quarter points of its dense output: a sign change
    among the samples (the step's start and quarter points) or a window of
    :func:`dip_windows` (a small local minimum: a possible dip between samples).

    State in/out: ``y`` (17), ``f`` (17, rhs at y), ``stats`` = [t, h_abs, n_rhs, first]
    (``h_abs <= 0``: start of the phase, f is evaluated and the initial step chosen as scipy
    does; ``first`` != 0: the samples before the next step are the phase start). Steps are
    appended to TA/TB/YOLD/FF from index m. Returns (status, m): 0 reached t_end, 1 the last
    step may hold an event (its four samples in GI, the samples before in g_prev on entry),
    2 buffers full, 3 step size too small, 4 singular constraint system (generic path).
    """
    nev = kinds.size
    atol_state = 0.0
    for k in range(14):
        atol_state = max(atol_state, atol[k])
    v5 = np.empty(5)
    wa = np.empty(5, dtype=np.int64)
    wb = np.empty(5, dtype=np.int64)
    K = np.empty((16, _NY))
    ynew = np.empty(_NY)
    ytmp = np.empty(_NY)
    sc = np.empty(_NY)
    out = np.empty(_NY)
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    hh = np.empty(7)
    qdd = np.empty(7)
    lamN = np.empty(2)
    lamT = np.empty(2)
    g = np.empty(nev)
    s = np.empty(nev)
    n_rhs = 0
    err_exp = -1.0 / 8.0
    t = stats[0]
    h_abs = stats[1]
    first = stats[3] != 0.0
    if h_abs <= 0.0:
        if rhs(t, y, modes, sigma, par, f) <= 1e-13:
            return 4, m
        n_rhs += 1
        # scipy.integrate._ivp.common.select_initial_step
        interval = abs(t_end - t)
        for k in range(_NY):
            sc[k] = atol[k] + abs(y[k]) * rtol
        d0 = _rms(y, sc)
        d1 = _rms(f, sc)
        if d0 < 1e-5 or d1 < 1e-5:
            h0 = 1e-6
        else:
            h0 = 0.01 * d0 / d1
        h0 = min(h0, interval)
        for k in range(_NY):
            ytmp[k] = y[k] + h0 * f[k]
        if rhs(t + h0, ytmp, modes, sigma, par, out) <= 1e-13:
            return 4, m
        n_rhs += 1
        for k in range(_NY):
            ynew[k] = (out[k] - f[k])
        d2 = _rms(ynew, sc) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100 * h0, h1, interval, max_step)
    while True:
        if m >= TA.size:
            stats[0] = t
            stats[1] = h_abs
            stats[2] += n_rhs
            return 2, m
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                stats[0] = t
                stats[2] += n_rhs
                return 3, m
            t_new = t + h_abs
            if t_new - t_end > 0:
                t_new = t_end
            h = t_new - t
            h_abs = abs(h)
            for k in range(_NY):
                K[0, k] = f[k]
            for st in range(1, _NS):
                _stage_y(y, K, _DA[st], st, h, ytmp)
                if rhs(t + _DC[st] * h, ytmp, modes, sigma, par, out) <= 1e-13:
                    return 4, m
                for k in range(_NY):
                    K[st, k] = out[k]
            for k in range(_NY):
                acc = 0.0
                for j in range(_NS):
                    acc += K[j, k] * _DB[j]
                ynew[k] = y[k] + h * acc
            if rhs(t + h, ynew, modes, sigma, par, out) <= 1e-13:
                return 4, m
            for k in range(_NY):
                K[12, k] = out[k]
            n_rhs += 12
            for k in range(_NY):
                sc[k] = atol[k] + max(abs(y[k]), abs(ynew[k])) * rtol
            en = _norm_err(K, h, sc)
            if en < 1.0:
                if en == 0.0:
                    factor = 10.0
                else:
                    factor = min(10.0, 0.9 * en ** err_exp)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(0.2, 0.9 * en ** err_exp)
            rejected = True
        # dense output of the accepted step (three extra stages)
        for st in range(13, 16):
            _stage_y(y, K, _DA[st], st, h, ytmp)
            if rhs(t + _DC[st] * h, ytmp, modes, sigma, par, out) <= 1e-13:
                return 4, m
            for k in range(_NY):
                K[st, k] = out[k]
        n_rhs += 3
        Fm = FF[m]
        for k in range(_NY):
            dy = ynew[k] - y[k]
            Fm[0, k] = dy
            Fm[1, k] = h * K[0, k] - dy
            Fm[2, k] = 2.0 * dy - h * (K[12, k] + K[0, k])
            for r in range(4):
                acc = 0.0
                for j in range(16):
                    acc += _DD[r, j] * K[j, k]
                Fm[3 + r, k] = h * acc
            YOLD[m, k] = y[k]
        TA[m] = t
        TB[m] = t_new
        m += 1
        for k in range(_NY):
            y[k] = ynew[k]
            f[k] = K[12, k]
        t_old = t
        t = t_new
        # event screening at the quarter points (NumericalPhase.advance / first_event)
        flag = False
        if nev > 0:
            for c in range(4):
                tc = t_old + h * 0.25 * (c + 1)
                dense_eval(t_old, h, YOLD[m - 1], Fm, tc, ytmp)
                q = ytmp[:7]
                qd = ytmp[7:14]
                _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
                forces(tc, q, qd, par, hh)
                if configuration_solve(hh, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN,
                                       lamT) <= 1e-13:
                    return 4, m
                event_values(WT, qd, lamN, lamT, sigma, kinds, contacts, lim, sgn, g, s, vel, q,
                     gap, WN)
                for e in range(nev):
                    GI[e, c] = g[e]
                    scale[e] = max(scale[e], s[e])
            for e in range(nev):
                tol = 1e2 * 2.220446049250313e-16 * scale[e] + 2.2250738585072014e-308
                if kinds[e] == 4:  # a gap: its integration error (NumericalPhase._tol)
                    tol = max(tol, rtol * scale[e] + atol_state)
                if first and g_prev[e] + tol <= 0.0:
                    flag = True
                prev = g_prev[e] + tol
                v5[0] = prev
                for c in range(4):
                    cur = GI[e, c] + tol
                    if prev > 0.0 and cur <= 0.0:
                        flag = True
                    prev = cur
                    v5[c + 1] = cur
                if not flag and dip_windows(v5, tol, first and v5[0] <= 2.0 * tol, wa,
                                            wb) > 0:
                    flag = True
        stats[0] = t
        stats[1] = h_abs
        if flag:
            stats[2] += n_rhs
            return 1, m
        first = False
        stats[3] = 0.0
        for e in range(nev):
            g_prev[e] = GI[e, 3]
        if t == t_end:
            stats[2] += n_rhs
            return 0, m


@njit(cache=True)
def close_gap_set(q, qd, idx, n, par):
    """Move q in place (M-weighted Gauss-Newton, at most 5 steps) so that the gaps of the n
    contacts ``idx[:n]`` are zero to 1e-15 (1 + max |q|); False: a singular step."""
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    A = np.zeros((4, 4))
    x = np.empty(4)
    for it in range(5 if n > 0 else 0):
        _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
        qmax = 0.0
        for k in range(7):
            qmax = max(qmax, abs(q[k]))
        done = True
        for a in range(n):
            if abs(gap[idx[a]]) > 1e-15 * (1 + qmax):
                done = False
        if done:
            break
        for a in range(n):
            x[a] = gap[idx[a]]
            for b in range(n):
                acc = 0.0
                for k in range(7):
                    acc += WN[k, idx[a]] * par[_MINV + k] * WN[k, idx[b]]
                A[a, b] = acc
        if _lu_solve(A, x, n) <= 1e-13:
            return False
        for k in range(7):
            acc = 0.0
            for a in range(n):
                acc += WN[k, idx[a]] * x[a]
            q[k] -= par[_MINV + k] * acc
    return True


@njit(cache=True)
def project(q, qd, modes, par, q_out, qd_out):
    """:meth:`fricdamp.solvers.event_switch.Evaluator.project` for the blade damper: Gauss-Newton
    (M-weighted) on the closed normal gaps (an open contact, mode ``OPEN``, is free), then the
    M-orthogonal projection of q' onto ``W_N^T q' = 0`` of the closed contacts and the stuck
    contacts' ``W_T^T q' = 0``. Returns (pivot ratio, |kinetic energy change|); a ratio
    <= 1e-13 means use the generic path."""
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    A = np.zeros((4, 4))
    x = np.empty(4)
    W = np.empty((7, 4))
    closed = np.empty(2, dtype=np.int64)
    nc = 0
    for i in range(2):
        if modes[i] != OPEN:
            closed[nc] = i
            nc += 1
    for k in range(7):
        q_out[k] = q[k]
    if not close_gap_set(q_out, qd, closed, nc, par):
        return 0.0, 0.0
    _kin_state(q_out, qd, par, gap, WN, WT, wbN, wbT)
    m = 0
    for a in range(nc):
        for k in range(7):
            W[k, m] = WN[k, closed[a]]
        m += 1
    for i in range(2):
        if modes[i] == STICK:
            for k in range(7):
                W[k, m] = WT[k, i]
            m += 1
    if m == 0:
        for k in range(7):
            qd_out[k] = qd[k]
        return 1.0, 0.0
    for a in range(m):
        acc = 0.0
        for k in range(7):
            acc += W[k, a] * qd[k]
        x[a] = acc
        for b in range(m):
            acc = 0.0
            for k in range(7):
                acc += W[k, a] * par[_MINV + k] * W[k, b]
            A[a, b] = acc
    ratio = _lu_solve(A, x, m)
    if ratio <= 1e-13:
        return ratio, 0.0
    e0 = 0.0
    e1 = 0.0
    for k in range(7):
        corr = 0.0
        for b in range(m):
            corr += W[k, b] * x[b]
        qd_out[k] = qd[k] - par[_MINV + k] * corr
        e0 += qd[k] * qd[k] / par[_MINV + k]
        e1 += qd_out[k] * qd_out[k] / par[_MINV + k]
    return ratio, abs(0.5 * e0 - 0.5 * e1)

'''


def _cache_dir() -> Path:
    env = os.environ.get("FRICDAMP_CACHE_DIR")
    if env:
        base = Path(env)
    else:
        xdg = os.environ.get("XDG_CACHE_HOME")
        base = (Path(xdg) if xdg else Path.home() / ".cache") / "fricdamp"
    for d in (base, Path(tempfile.gettempdir()) / "fricdamp-cache"):
        try:
            d.mkdir(parents=True, exist_ok=True)
            probe = d / ".write-test"
            probe.write_text("")
            probe.unlink()
            return d
        except OSError:
            continue
    raise OSError(f"no writable cache directory for the compiled blade-damper kernels "
                  f"(tried {base}); set FRICDAMP_CACHE_DIR")


def kinematics_source(contour: str) -> str:
    """Python source of ``kin(q1, q3, q5, xS, yS, u5, gamma, p1, p2, gap, WN, WT, wbN, wbT)``
    printed from the sympy derivation (common subexpressions eliminated, ``math`` calls)."""
    import sympy as sp
    from sympy.printing.pycode import PythonCodePrinter

    from fricdamp.models.blade_damper._kinematics import derive

    d = derive(contour)
    q1, _, q3, _, q5, xS, yS = d["q"]
    u5 = d["u"][4]
    gamma, p1, p2 = d["params"]
    targets = ([(f"gap[{i}]", d["gap"][i]) for i in range(2)]
               + [(f"WN[{k}, {i}]", d["W_N"][k, i]) for k in range(7) for i in range(2)]
               + [(f"WT[{k}, {i}]", d["W_T"][k, i]) for k in range(7) for i in range(2)]
               + [(f"wbN[{i}]", d["wbar_N"][i]) for i in range(2)]
               + [(f"wbT[{i}]", d["wbar_T"][i]) for i in range(2)])
    subs, reduced = sp.cse([sp.sympify(e) for _, e in targets],
                           symbols=sp.numbered_symbols("x"))
    pr = PythonCodePrinter({"fully_qualified_modules": True})
    lines = [f"    {pr.doprint(s)} = {pr.doprint(e)}" for s, e in subs]
    lines += [f"    {n} = {pr.doprint(e)}" for (n, _), e in zip(targets, reduced, strict=True)]
    head = (f'"""Generated from the sympy kinematics of the blade-damper model ({contour}); '
            'do not edit."""\nimport math\n\nimport numpy as np\n\n'
            "from fricdamp._numba_cache import njit\n\n\n"
            "@njit(cache=True)\n"
            "def kin(q1, q3, q5, xS, yS, u5, gamma, p1, p2, gap, WN, WT, wbN, wbT):\n")
    if {str(v) for v in (q1, q3, q5, xS, yS, u5, gamma, p1, p2)} != {
            "q1", "q3", "q5", "xS", "yS", "u5", "gamma", "p1", "p2"}:
        raise RuntimeError("the sympy symbols of the kinematics changed their names")
    body = "\n".join(lines)
    from fricdamp.models.blade_damper._fastloop import LOOP_SRC
    from fricdamp.models.blade_damper._variational import VAR_SRC

    return (head + body + "\n" + _FUSED.format(g=_GAMMA, p1=_P1, p2=_P2) + _PHASE_SRC
            + LOOP_SRC + VAR_SRC)


@functools.cache
def compiled_module(contour: str = "parabola"):
    """The generated kernel module for ``contour`` (generated and written on first use)."""
    import numba

    src = kinematics_source(contour)
    own = Path(__file__).read_bytes()
    key = hashlib.sha256(src.encode() + own + numba.__version__.encode()).hexdigest()[:16]
    path = _cache_dir() / f"blade_damper_{contour}_{key}.py"
    if not path.exists():
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(src)
        os.replace(tmp, path)
    name = f"_fricdamp_blade_damper_{contour}_{key}"
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


class BladeDamperKernels:
    """Compiled phase kernels of one blade-damper system (the ``compiled_kernels`` hook of
    :class:`~fricdamp.solvers.event_system.ConstrainedSystem`).

    Methods return the smallest pivot ratio of the constraint solves; the caller uses the
    generic path when it is <= ``SINGULAR`` (redundant constraints).
    """

    SINGULAR = 1e-13

    def __init__(self, system):
        self.par = parameter_vector(system)
        self.mod = compiled_module(system.params.contour)
        self.n = 7
        #: NumericalPhase takes whole steps through :meth:`phase_run`
        self.fused_phases = bool(getattr(system, "compiled_phases", True))
        #: the compiled event loop (phases and switches) offered to the event solver
        self.compiled_loop = self.fused_phases and bool(getattr(system, "compiled_loop",
                                                                 True))
        #: the kernels know open contacts (mode ``OPEN``: a released damper that lifted off;
        #: the gap events of DOP853 phases, lift-off and impacts in the event loop)
        self.open_contacts = True
        self._fastloop = None

    def kinematics(self, q, u5=0.0):
        """``(gap (2,), W_N (7, 2), W_T (7, 2), wbar_N (2,), wbar_T (2,))`` at q, q5' = u5."""
        p = self.par
        gap, WN, WT = np.empty(2), np.empty((7, 2)), np.empty((7, 2))
        wbN, wbT = np.empty(2), np.empty(2)
        self.mod.kin(float(q[0]), float(q[2]), float(q[4]), float(q[5]), float(q[6]),
                     float(u5), p[_GAMMA], p[_P1], p[_P2], gap, WN, WT, wbN, wbT)
        return gap, WN, WT, wbN, wbT

    def rhs(self, t, y, modes, sigma, out):
        return self.mod.rhs(float(t), y, modes, sigma, self.par, out)

    def jacobian(self, t, y, modes, sigma, steps):
        """Central-difference Jacobian (14, 14) of ``[q', q'']`` (steps (14,)); ratio, J."""
        J = np.empty((14, 14))
        r = self.mod.jacobian(float(t), np.ascontiguousarray(y[:14], dtype=float), modes,
                              sigma, self.par, np.ascontiguousarray(steps, dtype=float), J)
        return r, J

    def transition(self, phase, t_start, t_end, modes, sigma):
        """Transition matrix of the fused DOP853 phase ``phase`` over [t_start, t_end]
        (Magnus steps, :mod:`fricdamp.models.blade_damper._variational`): ``(ratio, Phi,
        coarse)`` with ``coarse`` the product over whole steps."""
        Phi, coarse = np.empty((14, 14)), np.empty((14, 14))
        r = self.mod.transition(phase._TA, phase._TB, phase._YOLD, phase._FF, int(phase._m),
                                float(phase.t0), np.ascontiguousarray(phase.y0, dtype=float),
                                float(t_start), float(t_end), modes, sigma, self.par, Phi,
                                coarse)
        return r, Phi, coarse

    def projection_jacobian(self, y, modes):
        """Central-difference Jacobian (14, 14) of :meth:`project` at y = [q, q']: ``(ratio,
        P)``."""
        P = np.empty((14, 14))
        r = self.mod.projection_jacobian(np.ascontiguousarray(y[:14], dtype=float),
                                         np.ascontiguousarray(modes, dtype=np.int64),
                                         self.par, P)
        return r, P

    def solve_many(self, ts, Y, modes, sigma):
        nt = ts.size
        QDD = np.empty((7, nt))
        LN = np.empty((2, nt))
        LT = np.empty((2, nt))
        WT = np.empty((7, 2, nt))
        r = self.mod.solve_many(ts, Y, modes, sigma, self.par, QDD, LN, LT, WT)
        return r, QDD, LN, LT, WT

    def phase_run(self, y, f, t_end, modes, sigma, rtol, atol, max_step, kinds, contacts,
                  lim, sgn, g_prev, scale, vel, TA, TB, YOLD, FF, m, GI, stats):
        """DOP853 steps of one phase with event screening (see the generated ``phase_run``);
        returns ``(status, m)``."""
        return self.mod.phase_run(y, f, float(t_end), modes, sigma, self.par, float(rtol),
                                  atol, float(max_step), kinds, contacts, lim, sgn, g_prev,
                                  scale, vel, TA, TB, YOLD, FF, int(m), GI, stats)

    def project(self, q, qd, modes):
        """Compiled :meth:`Evaluator.project` (both normals closed): ``(ok, q, qd, dE)``."""
        q_out, qd_out = np.empty(7), np.empty(7)
        r, de = self.mod.project(np.ascontiguousarray(q, dtype=float),
                        np.ascontiguousarray(qd, dtype=float),
                        np.ascontiguousarray(modes, dtype=np.int64), self.par, q_out, qd_out)
        return r > self.SINGULAR, q_out, qd_out, de

    def solve_point(self, h, WN, WT, wbN, wbT, modes, sigma, given=None):
        """Compiled ``Evaluator.solve`` at a point (both normals constrained); ``(ok, qdd,
        lamN, lamT)`` with one column per column of ``given`` (2, k) (default k = 1)."""
        g = np.zeros((2, 1)) if given is None else np.ascontiguousarray(given, dtype=float)
        k = g.shape[1]
        QDD, LN, LT = np.empty((7, k)), np.empty((2, k)), np.empty((2, k))
        r = configuration_solve_given(h, WN, WT, wbN, wbT, modes, sigma, g, self.par,
                                      QDD, LN, LT)
        return r > self.SINGULAR, QDD, LN, LT

    def refine_root(self, j, i, ta, tb, h_scale, tol_i, TA, TB, YOLD, FF, modes, sigma, kinds,
                    contacts, lim, sgn, vel):
        """Root of event function i in (ta, tb] of stored step j (see ``refine_root``)."""
        return self.mod.refine_root(int(j), int(i), float(ta), float(tb), float(h_scale),
                                    float(tol_i), TA, TB, YOLD, FF, modes, sigma, self.par,
                                    kinds, contacts, lim, sgn, vel)

    def dip_search(self, j, i, ta, tb, tol_i, TA, TB, YOLD, FF, modes, sigma, kinds, contacts,
                   lim, sgn, vel):
        """A time in [ta, tb] of stored step j where event function i plus tol_i is <= 0, or
        NaN (see the generated ``dip_search``)."""
        return self.mod.dip_search(int(j), int(i), float(ta), float(tb), float(tol_i), TA, TB,
                                   YOLD, FF, modes, sigma, self.par, kinds, contacts, lim, sgn,
                                   vel)

    def gap_zero(self, i, t_hit, t0, m, TA, TB, YOLD, FF, modes, sigma, kinds, contacts, lim,
                 sgn, vel):
        """The zero of gap event i before ``t_hit`` on the stored step holding it (NaN: on
        an earlier step; see ``_gap_zero`` of :mod:`fricdamp.models.blade_damper._fastloop`);
        ``vel`` is not changed."""
        return self.mod._gap_zero(int(i), float(t_hit), float(t0), int(m), TA, TB, YOLD, FF,
                                  modes, sigma, self.par, kinds, contacts, lim, sgn, vel)

    def refine_value(self, j, i, t, TA, TB, YOLD, FF, modes, sigma, kinds, contacts, lim,
                     sgn, vel):
        """Event function i at t on the dense output of stored step j."""
        return self.mod.event_value(int(j), int(i), float(t), TA, TB, YOLD, FF, modes, sigma,
                                    self.par, kinds, contacts, lim, sgn, vel)

    def dense_many(self, TA, TB, YOLD, FF, idx, ts):
        """Dense output (17, n_t) at ``ts`` from the stored steps ``idx``."""
        Y = np.empty((17, ts.size))
        self.mod.dense_many(TA, TB, YOLD, FF, idx, ts, Y)
        return Y

    def event_loop(self, run, max_events):
        """Phases and switches of the run ``run`` (a :class:`fricdamp.solvers.event._Run`)
        in the compiled event loop (:mod:`fricdamp.models.blade_damper._fastloop`) until
        its end or a phase the loop leaves to Python; returns True when the run is
        finished."""
        if self._fastloop is None:
            from fricdamp.models.blade_damper._fastloop import FastLoop

            self._fastloop = FastLoop(self)
        return self._fastloop.advance(run, max_events)

    def events_many(self, ts, Y, modes, sigma, kinds, contacts, lim, sgn, vel):
        G = np.empty((kinds.size, ts.size))
        S = np.empty((kinds.size, ts.size))
        r = self.mod.events_many(ts, Y, modes, sigma, self.par, kinds, contacts, lim, sgn,
                                 G, S, vel)
        return r, G, S
