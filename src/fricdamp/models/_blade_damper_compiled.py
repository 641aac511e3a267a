"""Compiled right-hand side, constraint solve and event functions of the blade-damper model.

The event-driven solver spends a blade-damper forcing period in a few hundred configuration
solves (000 (37)-(40)) and event-function evaluations. Through the generic path each one goes
through the lambdified kinematics and :class:`~fricdamp.solvers.event_switch.Evaluator`
(about 100 us of Python overhead for a 7-DOF, 2-contact problem). Here they are fused into
numba kernels:

* the contact kinematics 000 (5)-(28) (gaps, ``W_N``, ``W_T``, ``wbar_N``, ``wbar_T``) are
  printed once from the sympy derivation of :mod:`fricdamp.models._blade_damper_kinematics`
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

A configuration whose constraint matrix is (numerically) singular returns status 1 and the
caller falls back to the generic path (minimum-norm multipliers).

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
from numba import njit

# layout of the parameter vector ``par`` (one float64 array: one argument to type-check)
_MINV, _K, _D, _F0 = 0, 7, 56, 105
_FE, _RATIO, _PHASE, _OMEGA, _GAMMA, _P1, _P2, _MUS, _MUD = range(112, 121)
PAR_SIZE = 121

STICK = 0


def parameter_vector(system) -> np.ndarray:
    """The ``par`` vector of a :class:`~fricdamp.models.blade_damper.BladeDamperSystem`."""
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

    Both normals are constrained (the gaps stay closed). Unknowns: ``lambda_N`` of both
    contacts and ``lambda_T`` of the stuck ones. A slipping contact's friction force is
    ``-mu_sliding sigma_i s_i lambda_N,i`` (``sigma`` the tracked sign of the normal force),
    so its normal column is ``W_N,i - mu_sliding sigma_i s_i W_T,i``. Returns the pivot ratio
    of the constraint system (<= 1e-13: singular, outputs undefined).
    """
    mud = par[_MUD]
    # columns of B (force directions) and C (constraint gradients)
    B = np.empty((7, 4))
    C = np.empty((7, 4))
    rhs = np.empty(4)
    m = 0
    for i in range(2):
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
    ratio = _lu_solve(A, x, m)
    for k in range(7):
        s = MiF[k]
        for b in range(m):
            s += par[_MINV + k] * B[k, b] * x[b]
        qdd[k] = s
    lamN[0], lamN[1] = x[0], x[1]
    j = 2
    for i in range(2):
        if modes[i] == STICK:
            lamT[i] = x[j]
            j += 1
        else:
            lamT[i] = -mud * float(modes[i]) * abs(lamN[i])
    return ratio


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
def event_values(WT, qd, lamN, lamT, sigma, kinds, contacts, lim, sgn, g, scale, vel):
    """Event functions of a configuration (the kinds of :mod:`fricdamp.solvers.event_phase`:
    0 slip velocity, 1/2 friction reserve at the +/- limit, 3 normal force) and their scales;
    ``vel`` is raised to ``|W_T|^T |q'|`` per contact."""
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

from fricdamp.models._blade_damper_compiled import (configuration_solve, event_values,
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
        event_values(WT, qd, lamN, lamT, sigma, kinds, contacts, lim, sgn, g, s, vel)
        G[:, j] = g
        S[:, j] = s
    return worst
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

    from fricdamp.models._blade_damper_kinematics import derive

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
            'do not edit."""\nimport math\n\nimport numpy as np\nfrom numba import njit\n\n\n'
            "@njit(cache=True)\n"
            "def kin(q1, q3, q5, xS, yS, u5, gamma, p1, p2, gap, WN, WT, wbN, wbT):\n")
    if {str(v) for v in (q1, q3, q5, xS, yS, u5, gamma, p1, p2)} != {
            "q1", "q3", "q5", "xS", "yS", "u5", "gamma", "p1", "p2"}:
        raise RuntimeError("the sympy symbols of the kinematics changed their names")
    body = "\n".join(lines)
    return head + body + "\n" + _FUSED.format(g=_GAMMA, p1=_P1, p2=_P2)


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

    def solve_many(self, ts, Y, modes, sigma):
        nt = ts.size
        QDD = np.empty((7, nt))
        LN = np.empty((2, nt))
        LT = np.empty((2, nt))
        WT = np.empty((7, 2, nt))
        r = self.mod.solve_many(ts, Y, modes, sigma, self.par, QDD, LN, LT, WT)
        return r, QDD, LN, LT, WT

    def events_many(self, ts, Y, modes, sigma, kinds, contacts, lim, sgn, vel):
        G = np.empty((kinds.size, ts.size))
        S = np.empty((kinds.size, ts.size))
        r = self.mod.events_many(ts, Y, modes, sigma, self.par, kinds, contacts, lim, sgn,
                                 G, S, vel)
        return r, G, S
