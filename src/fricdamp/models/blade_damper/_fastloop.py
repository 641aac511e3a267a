"""Compiled event loop of the blade damper: many phases and switches in one kernel call.

With the DOP853 phases compiled (``phase_run`` of :mod:`fricdamp.models.blade_damper.
_compiled`), a blade-damper forcing period at the resonance spent most of its time in the
Python bookkeeping of each event (the run loop, the switching decision, the sampling). The
kernel ``event_loop`` (generated into the same module as ``phase_run``, source
:data:`LOOP_SRC`) takes the whole loop of :meth:`fricdamp.solvers.event._Run.loop` for the
common case, step for step:

* projection onto the configuration's constraints (``project``, as ``_Run._project``);
* the phase: the event functions at its start, ``phase_run`` (DOP853 steps screened for
  events and dips), and :func:`~fricdamp.solvers.event_phase.first_event` with the compiled
  root refinement (``refine_root``), dip search (``dip_search``) and the root-uncertainty
  grouping (``time_tol`` of
  :meth:`~fricdamp.solvers.event_phase.NumericalPhase._advance_fused`);
* the samples at the requested times and the phase start (``_Run._record``: q, q',
  lambda_N, lambda_T, modes and the cumulative input, viscous and friction work from the
  integrated power components of the dense output, as ``NumericalPhase.energy``);
* the switch (``_Run._switch``): normal-force sign changes, must-slip contacts, the
  candidates at zero slip velocity, the projection onto them, and the decision
  (:func:`~fricdamp.solvers.event_switch.decide_modes` with the affine maps and the
  verification of :meth:`~fricdamp.solvers.event_switch.Evaluator.decide`: the
  single-candidate clip rule, the breakaway cascade with the friction LCP solved by the
  compiled Lemke kernel :func:`~fricdamp.solvers.event_kernels.lemke_kernel`, the
  consistency check ``_consistent`` and the choice among several consistent configurations
  ``_select``);
* for the released damper (``release=True``, unilateral contacts): the lift-off of a contact
  whose normal force reaches zero (it opens, mode ``OPEN``, whose only event is its gap),
  and the impact of an open contact whose gap reaches zero (``_Run._impact``: the instant at
  the gap's own zero, ``_gap_zero``; the gaps closed by Gauss-Newton, ``_close_gaps``;
  Newton's impact law as an LCP in the normal impulses by Lemke, ``_impulse``; the Zeno
  velocity of the gap tolerance, contacts set separating slower than it held closed; the
  modes after the impulse), with the impacts and their energy loss recorded as the Python
  loop records them.

Whatever the kernel would not do exactly as the Python path does stops it at the start of
the phase concerned (the state just after the last completed switch, before the projection),
with a reason code: a singular constraint system (the Python path takes minimum-norm
multipliers), a step size too small, an event at the phase start or a phase of zero length
(chattering), ``max_events``, a failed Lemke solve, a cascade whose result is inconsistent
(the Python path enumerates), several consistent configurations with the most stuck
contacts and the same number of them stuck before the event (the Python path logs a
warning and records the ambiguity), an impact whose gap zero lies on an earlier step or
two gaps closing at once, a failed impulse. The Python loop then takes that one phase and
switch and hands back (:class:`FastLoop`). Runs with a trace (shooting), a given
``zeno_velocity`` or frictionless contacts never take the kernel.
"""

from __future__ import annotations

import numpy as np

# reasons the kernel stops before a phase (``cnt[7]``); 0: finished, 1: buffers full
REASONS = {
    0: "finished",
    1: "output buffers full",
    10: "singular projection",
    11: "singular configuration solve in a phase",
    12: "DOP853 step size too small",
    13: "event at the phase start or a phase of zero length",
    14: "max_events reached",
    15: "Lemke's method failed",
    16: "several consistent configurations share the best score (_select warns)",
    17: "the breakaway cascade is inconsistent (enumeration)",
    18: "singular configuration solve in a switching decision",
    19: "an impact whose gap zero is not on the hit's step, or two gaps at once",
    20: "a singular or failed impulse (Lemke) or gap closure at an impact",
}

LOOP_SRC = '''

from fricdamp.models.blade_damper._compiled import _MUD, _MUS, configuration_solve_given
from fricdamp.solvers.event_kernels import lemke_kernel

_EPS = 2.220446049250313e-16
_TINY = 2.2250738585072014e-308
_QUARTERS = np.array([0.25, 0.5, 0.75, 1.0])


@njit(cache=True)
def _event_list(modes, par):
    """:func:`fricdamp.solvers.event_phase.event_list` (both normals constrained, friction;
    an open contact has its gap event only): kinds, contacts, limits (mu_static) and slip
    signs of the event functions."""
    n = 0
    for i in range(2):
        n += 1 if modes[i] == OPEN else (3 if modes[i] == STICK else 2)
    kinds = np.empty(n, dtype=np.int64)
    contacts = np.empty(n, dtype=np.int64)
    lim = np.empty(n)
    sgn = np.empty(n)
    e = 0
    for i in range(2):
        if modes[i] == OPEN:
            kinds[e] = 4
            contacts[e] = i
            e += 1
            continue
        if modes[i] == STICK:
            kinds[e] = 1
            contacts[e] = i
            kinds[e + 1] = 2
            contacts[e + 1] = i
            e += 2
        else:
            kinds[e] = 0
            contacts[e] = i
            e += 1
        kinds[e] = 3
        contacts[e] = i
        e += 1
    for e in range(n):
        lim[e] = par[_MUS]
        c = contacts[e]
        sgn[e] = 0.0 if modes[c] == STICK else float(modes[c])
    return kinds, contacts, lim, sgn


@njit(cache=True)
def _time_tol(j, i, t, h, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn,
              vel, rtol, scale):
    """``time_tol`` of NumericalPhase._advance_fused: the root uncertainty of function i."""
    dt = 1e-6 * h
    ga = event_value(j, i, t + dt, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
                     sgn, vel)
    gb = event_value(j, i, t - dt, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
                     sgn, vel)
    rate = abs(ga - gb) / (2 * dt)
    if rate > 0:
        return min(rtol * scale[i] / rate, 1e-2 * h)
    return 1e-2 * h


@njit(cache=True)
def _first_event(j, ta, tb, g_prev, GI, scale, first, TA, TB, YOLD, FF, modes, sigma, par,
                 kinds, contacts, lim, sgn, vel, rtol, fired, atol_max):
    """:func:`fricdamp.solvers.event_phase.first_event` on the samples of step j (its start
    and quarter points) with ``refine_root``, ``dip_search`` and ``_time_tol``. Returns
    (code, t): code -1 no event, 0 an event at t (``fired`` marks the grouped functions), 1
    immediate."""
    nev = kinds.size
    tt = np.empty(5)
    tt[0] = ta
    for c in range(4):
        tt[c + 1] = ta + (tb - ta) * _QUARTERS[c]
    tol = np.empty(nev)
    Gs = np.empty((nev, 5))
    for e in range(nev):
        tol[e] = 1e2 * _EPS * scale[e] + _TINY
        if kinds[e] == 4:  # NumericalPhase._tol: a gap's integration error
            tol[e] = max(tol[e], rtol * scale[e] + atol_max)
        Gs[e, 0] = g_prev[e] + tol[e]
        for c in range(4):
            Gs[e, c + 1] = GI[e, c] + tol[e]
    if first:
        imm = False
        for e in range(nev):
            fired[e] = Gs[e, 0] <= 0
            imm = imm or fired[e]
        if imm:
            return 1, ta
    roots = np.full(nev, np.inf)
    # dip windows (dip_windows): searched with the interval they start in
    nw = np.zeros(nev, dtype=np.int64)
    WA = np.empty((nev, 5), dtype=np.int64)
    WB = np.empty((nev, 5), dtype=np.int64)
    v5 = np.empty(5)
    for e in range(nev):
        for c in range(5):
            v5[c] = Gs[e, c]
        nw[e] = dip_windows(v5, tol[e], first and Gs[e, 0] <= 2 * tol[e], WA[e], WB[e])
    for jj in range(4):
        anyroot = False
        for i in range(nev):
            if not (Gs[i, jj] > 0 and np.isinf(roots[i])):
                continue
            if Gs[i, jj + 1] <= 0:
                roots[i] = refine_root(j, i, tt[jj], tt[jj + 1], tt[jj + 1] - tt[jj], tol[i],
                                       TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts,
                                       lim, sgn, vel)
            for w in range(nw[i]):
                a = WA[i, w]
                if a != jj or not np.isinf(roots[i]):
                    continue
                tm = dip_search(j, i, tt[a], tt[WB[i, w]], tol[i], TA, TB, YOLD, FF, modes,
                                sigma, par, kinds, contacts, lim, sgn, vel)
                if not np.isnan(tm):
                    roots[i] = refine_root(j, i, tt[a], tm, tt[jj + 1] - tt[jj], tol[i], TA,
                                           TB, YOLD, FF, modes, sigma, par, kinds, contacts,
                                           lim, sgn, vel)
        ib = -1
        best = np.inf
        for i in range(nev):
            if np.isfinite(roots[i]):
                anyroot = True
                if roots[i] < best:
                    best = roots[i]
                    ib = i
        if anyroot and (best <= tt[jj + 1] or jj == 3):
            w0 = 1e3 * _EPS * max(abs(best), tt[jj + 1] - tt[jj])
            window = np.full(nev, w0)
            h = tb - ta
            dt_best = _time_tol(j, ib, best, h, TA, TB, YOLD, FF, modes, sigma, par, kinds,
                                contacts, lim, sgn, vel, rtol, scale)
            for i in range(nev):
                if np.isfinite(roots[i]) and i != ib and roots[i] > best + window[i]:
                    window[i] = max(window[i], dt_best + _time_tol(
                        j, i, roots[i], h, TA, TB, YOLD, FF, modes, sigma, par, kinds,
                        contacts, lim, sgn, vel, rtol, scale))
            t_hit = -np.inf
            for i in range(nev):
                fired[i] = roots[i] <= best + window[i]
                if fired[i]:
                    t_hit = max(t_hit, roots[i])
            return 0, t_hit
    return -1, tb


@njit(cache=True)
def _point(t, q, qd, par, WN, WT, wbN, wbT, h):
    """The Evaluator's Point at (t, q, q'): kinematics (with q5') and the forces h."""
    gap = np.empty(2)
    _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
    forces(t, q, qd, par, h)


@njit(cache=True)
def _affine(new, cand, k, sigma, par, h, WN, WT, wbN, wbT, G, b, H, c):
    """``affine`` of Evaluator.decide: the candidates' relative accelerations ``G lam + b``
    and normal-force magnitudes ``H lam + c`` (candidates marked GIVEN in ``new``).
    Returns the pivot ratio of the solves."""
    given = np.zeros((2, k + 1))
    for a in range(k):
        given[cand[a], a + 1] = 1.0
    QDD = np.empty((7, k + 1))
    LN = np.empty((2, k + 1))
    LT = np.empty((2, k + 1))
    r = configuration_solve_given(h, WN, WT, wbN, wbT, new, sigma, given, par, QDD, LN, LT)
    acc = np.empty((k, k + 1))
    nrm = np.empty((k, k + 1))
    for a in range(k):
        i = cand[a]
        for col in range(k + 1):
            s = 0.0
            for r7 in range(7):
                s += WT[r7, i] * QDD[r7, col]
            acc[a, col] = s + wbT[i]
            nrm[a, col] = sigma[i] * LN[i, col]
    for a in range(k):
        b[a] = acc[a, 0]
        c[a] = nrm[a, 0]
        for bb in range(k):
            G[a, bb] = acc[a, bb + 1] - acc[a, 0]
            H[a, bb] = nrm[a, bb + 1] - nrm[a, 0]
    return r


@njit(cache=True)
def _friction_lcp(G, b, H, c, mu, lam, a):
    """:func:`fricdamp.solvers.event_switch.solve_friction_lcp` (compiled Lemke); returns
    the Lemke status (0 solved)."""
    k = b.size
    if k == 1 and H[0, 0] == 0 and G[0, 0] > 0:
        lim = mu[0] * c[0]
        lam[0] = min(max(-b[0] / G[0, 0], -lim), lim)
        a[0] = G[0, 0] * lam[0] + b[0]
        return 0
    IH = np.empty((k, k))
    for i in range(k):
        for j in range(k):
            IH[i, j] = (1.0 if i == j else 0.0) + mu[i] * H[i, j]
    E = np.linalg.inv(IH)
    mc = np.empty(k)
    for i in range(k):
        mc[i] = mu[i] * c[i]
    GE = np.zeros((k, k))
    QE = np.zeros((k, k))
    for i in range(k):
        for j in range(k):
            s = 0.0
            s2 = 0.0
            for m in range(k):
                s += G[i, m] * E[m, j]
                s2 += (mu[i] * H[i, m] - (1.0 if i == m else 0.0)) * E[m, j]
            GE[i, j] = s
            QE[i, j] = s2
    A = np.zeros((2 * k, 2 * k))
    q = np.empty(2 * k)
    for i in range(k):
        A[i, k + i] = 1.0
        s = 0.0
        s2 = 0.0
        for j in range(k):
            A[i, j] = GE[i, j]
            A[k + i, j] = QE[i, j]
            s += GE[i, j] * mc[j]
            s2 += QE[i, j] * mc[j]
        q[i] = b[i] - s
        q[k + i] = mc[i] - s2
    z, status = lemke_kernel(A, q, 50 * (q.size + 1))
    if status != 0:
        return status
    for i in range(k):
        s = 0.0
        for j in range(k):
            s += E[i, j] * (z[j] - mc[j])
        lam[i] = s
    for i in range(k):
        s = 0.0
        for j in range(k):
            s += G[i, j] * lam[j]
        a[i] = s + b[i]
    return 0


@njit(cache=True)
def _consistent(new, decided, sigma, par, h, WN, WT, wbN, wbT):
    """``_consistent`` of event_switch with Evaluator.decide's ``verify``: 1 consistent,
    0 not, -1 singular solve."""
    zero = np.zeros((2, 1))
    QDD = np.empty((7, 1))
    LN = np.empty((2, 1))
    LT = np.empty((2, 1))
    if configuration_solve_given(h, WN, WT, wbN, wbT, new, sigma, zero, par, QDD, LN,
                                 LT) <= 1e-13:
        return -1
    parts = np.empty((7, 3))
    for r in range(7):
        ft = WT[r, 0] * LT[0, 0] + WT[r, 1] * LT[1, 0]
        fn = WN[r, 0] * LN[0, 0] + WN[r, 1] * LN[1, 0]
        parts[r, 0] = par[_MINV + r] * h[r]
        parts[r, 1] = par[_MINV + r] * ft
        parts[r, 2] = par[_MINV + r] * fn
    mus = par[_MUS]
    for i in range(2):
        if not decided[i]:
            continue
        a = wbT[i]
        for r in range(7):
            a += WT[r, i] * QDD[r, 0]
        ascale = abs(wbT[i])
        for p in range(3):
            s = 0.0
            for r in range(7):
                s += WT[r, i] * parts[r, p]
            ascale += abs(s)
        if new[i] != STICK:
            if new[i] * a < -1e-9 * ascale:
                return 0
        else:
            lim = mus * abs(LN[i, 0])
            lt = abs(LT[i, 0])
            if lt > lim + 1e-9 * (lim + lt):
                return 0
    return 1


@njit(cache=True)
def _decide(t, q, qd, modes, cand_mask, must, sigma, par, new):
    """:meth:`fricdamp.solvers.event_switch.Evaluator.decide_at` with
    :func:`~fricdamp.solvers.event_switch.decide_modes` for the blade damper. Writes the new
    modes into ``new``; returns 0, or the reason code (15, 16, 17, 18) for which the
    decision is left to the Python path."""
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    h = np.empty(7)
    _point(t, q, qd, par, WN, WT, wbN, wbT, h)
    mus, mud = par[_MUS], par[_MUD]
    decided = np.zeros(2, dtype=np.bool_)
    cand = np.empty(2, dtype=np.int64)
    k = 0
    anymust = False
    for i in range(2):
        new[i] = modes[i]
        if must[i] != 0:
            new[i] = must[i]
            decided[i] = True
            anymust = True
        elif cand_mask[i]:
            new[i] = 2  # GIVEN
            decided[i] = True
            cand[k] = i
            k += 1
    cand = cand[:k]
    if k:
        G = np.empty((k, k))
        b = np.empty(k)
        H = np.empty((k, k))
        c = np.empty(k)
        if _affine(new, cand, k, sigma, par, h, WN, WT, wbN, wbT, G, b, H, c) <= 1e-13:
            return 18
        if k == 1 and not anymust and H[0, 0] == 0 and G[0, 0] > 0:
            i = cand[0]
            lim = mus * c[0]
            if abs(b[0]) <= G[0, 0] * lim * (1 + 1e3 * _EPS):
                new[i] = STICK
            else:
                new[i] = 1 if b[0] > 0 else -1
            return 0
        broke = np.zeros(k, dtype=np.bool_)
        mu_b = np.empty(k)
        lam = np.empty(k)
        a = np.empty(k)
        slipping = np.zeros(k, dtype=np.bool_)
        for _ in range(k + 1):
            for m in range(k):
                mu_b[m] = mud if broke[m] else mus
            if _friction_lcp(G, b, H, c, mu_b, lam, a) != 0:
                return 15
            bmax = 0.0
            gmax = 0.0
            lmax = 0.0
            for m in range(k):
                bmax = max(bmax, abs(b[m]))
                lmax = max(lmax, abs(mu_b[m] * c[m]), abs(lam[m]))
                for mm in range(k):
                    gmax = max(gmax, abs(G[m, mm]))
            scale = max(bmax, gmax * lmax, 1e-300)
            newly = False
            for m in range(k):
                slipping[m] = abs(a[m]) > 1e3 * _EPS * scale
                if slipping[m] and not broke[m] and mud < mus:
                    broke[m] = True
                    newly = True
            if not newly:
                break
        for m in range(k):
            if slipping[m]:
                new[cand[m]] = 1 if a[m] > 0 else (-1 if a[m] < 0 else 0)
            else:
                new[cand[m]] = STICK
    ok = _consistent(new, decided, sigma, par, h, WN, WT, wbN, wbT)
    if ok < 0:
        return 18
    if ok == 0:
        return 17
    if k >= 2 and mus > mud:
        # _select: every consistent assignment of the candidates scored by (stuck, stuck
        # before the event and still stuck); the unique best is taken, a tie is left to the
        # Python loop (which warns and records the ambiguity)
        trial = new.copy()
        pick = new.copy()
        best0 = -1
        best1 = -1
        nalt = 0
        for code in range(3 ** k):
            ns = 0
            nw = 0
            rest = code
            for m in range(k - 1, -1, -1):
                d = rest % 3
                rest //= 3
                trial[cand[m]] = 0 if d == 0 else (1 if d == 1 else -1)
                if d == 0:
                    ns += 1
                    if modes[cand[m]] == STICK:
                        nw += 1
            if ns < best0 or (ns == best0 and nw < best1):
                continue
            ok = _consistent(trial, decided, sigma, par, h, WN, WT, wbN, wbT)
            if ok < 0:
                return 18
            if ok == 1:
                if ns > best0 or nw > best1:
                    best0 = ns
                    best1 = nw
                    nalt = 0
                    for i in range(2):
                        pick[i] = trial[i]
                nalt += 1
        if nalt > 1:
            return 16
        if nalt == 1:
            for i in range(2):
                new[i] = pick[i]
    return 0


@njit(cache=True)
def _gap_zero(i, t_hit, t0, m, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn,
              vel):
    """:meth:`fricdamp.solvers.event_phase.NumericalPhase._gap_zero_fused`: the zero of gap
    event i before ``t_hit`` on the stored step holding it (NaN: the search reaches back into
    an earlier step, the Python loop takes it)."""
    j = np.searchsorted(TA[:m], t_hit, side="right") - 1
    j = min(max(j, 0), m - 1)
    v = vel.copy()
    span = t_hit - t0
    dt = 1e-6 * span
    while dt <= span:
        ta = t_hit - dt
        if ta < TA[j]:
            return np.nan
        if event_value(j, i, ta, TA, TB, YOLD, FF, modes, sigma, par, kinds, contacts, lim,
                       sgn, v) > 0:
            return refine_root(j, i, ta, t_hit, span, 0.0, TA, TB, YOLD, FF, modes, sigma,
                               par, kinds, contacts, lim, sgn, v)
        dt *= 4
    return t_hit


@njit(cache=True)
def _close_gaps(q, qd, hit, par):
    """:func:`fricdamp.solvers.event_impact.close_gaps`: q moved (M-weighted Gauss-Newton,
    5 iterations) so that the gaps of the contacts in ``hit`` are zero. False: singular."""
    idx = np.empty(2, dtype=np.int64)
    n = 0
    for i in range(2):
        if hit[i]:
            idx[n] = i
            n += 1
    return close_gap_set(q, qd, idx, n, par)


@njit(cache=True)
def _impulse(WN, qd, par, uset, bset, e, qd_plus, Lam):
    """:func:`fricdamp.solvers.event_impact.impulse` for the two contacts: Newton's impact
    law as an LCP in the normal impulses of ``uset`` (Lemke), the closed rows of ``bset``
    eliminated by their Schur complement. Returns Lemke's status (0 solved)."""
    u = np.empty(2, dtype=np.int64)
    b = np.empty(2, dtype=np.int64)
    nu = 0
    nb = 0
    for i in range(2):
        Lam[i] = 0.0
        if uset[i]:
            u[nu] = i
            nu += 1
        if bset[i]:
            b[nb] = i
            nb += 1
    gm = np.zeros(2)
    for i in range(2):
        for k in range(7):
            gm[i] += WN[k, i] * qd[k]
    for k in range(7):
        qd_plus[k] = qd[k]
    if nu + nb == 0:
        return 0
    MiWu = np.empty((7, nu))
    MiWb = np.empty((7, nb))
    for k in range(7):
        for a in range(nu):
            MiWu[k, a] = par[_MINV + k] * WN[k, u[a]]
        for a in range(nb):
            MiWb[k, a] = par[_MINV + k] * WN[k, b[a]]
    A = np.empty((nu, nu))
    qv = np.empty(nu)
    for a in range(nu):
        qv[a] = (1.0 + e[u[a]]) * gm[u[a]]
        for c in range(nu):
            acc = 0.0
            for k in range(7):
                acc += WN[k, u[a]] * MiWu[k, c]
            A[a, c] = acc
    P = np.empty((nb, nb))
    Gbu = np.empty((nb, nu))
    if nb:
        Gbb = np.empty((nb, nb))
        for a in range(nb):
            for c in range(nb):
                acc = 0.0
                for k in range(7):
                    acc += WN[k, b[a]] * MiWb[k, c]
                Gbb[a, c] = acc
            for c in range(nu):
                acc = 0.0
                for k in range(7):
                    acc += WN[k, b[a]] * MiWu[k, c]
                Gbu[a, c] = acc
        P = np.linalg.pinv(Gbb, rcond=1e-12)
        PG = P @ Gbu
        Pg = np.zeros(nb)
        for a in range(nb):
            for c in range(nb):
                Pg[a] += P[a, c] * gm[b[c]]
        for a in range(nu):
            for c in range(nu):
                acc = 0.0
                for d in range(nb):
                    acc += Gbu[d, a] * PG[d, c]
                A[a, c] -= acc
            acc = 0.0
            for d in range(nb):
                acc += Gbu[d, a] * Pg[d]
            qv[a] -= acc
    Lu = np.zeros(nu)
    if nu:
        S = 0.5 * (A + A.T)
        Lu, status = lemke_kernel(S, qv, 50 * (nu + 1))
        if status != 0:
            return status
    for a in range(nu):
        Lam[u[a]] = Lu[a]
    if nb:
        rhs = np.empty(nb)
        for d in range(nb):
            acc = gm[b[d]]
            for a in range(nu):
                acc += Gbu[d, a] * Lu[a]
            rhs[d] = acc
        for a in range(nb):
            acc = 0.0
            for d in range(nb):
                acc += P[a, d] * rhs[d]
            Lam[b[a]] = -acc
    for k in range(7):
        acc = 0.0
        for a in range(nu):
            acc += MiWu[k, a] * Lu[a]
        acc2 = 0.0
        for a in range(nb):
            acc2 += MiWb[k, a] * Lam[b[a]]
        qd_plus[k] = qd[k] + acc + acc2
    return 0


@njit(cache=True)
def _impact(t, q, qd, modes, sigma, hit, uni, rest, par, rtol, atol_max, qd_plus, rec, evk,
            evold):
    """:meth:`fricdamp.solvers.event._Run._impact` for the blade damper (Zeno velocity from
    the gap tolerance): closes the gaps of ``hit`` in q, writes the velocity after the
    impulse into ``qd_plus``, updates ``modes`` and ``sigma``; ``rec`` = [gamma_N- (2),
    gamma_N+ (2), impulses (2), energy loss, hit (2), plastic (2)]; ``evk`` per contact the
    event to log (0 none, 1 impact that stays open, 2 impact that closes, 3 lift-off) with
    the mode before in ``evold``. Returns 0, or 20 (singular gap closure, failed Lemke)."""
    if not _close_gaps(q, qd, hit, par):
        return 20
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    h = np.empty(7)
    _kin_state(q, qd, par, gap, WN, WT, wbN, wbT)
    forces(t, q, qd, par, h)
    gm = np.zeros(2)
    vscale = np.zeros(2)
    vz = np.empty(2)
    for i in range(2):
        af = wbN[i]
        gt = 0.0
        for k in range(7):
            gm[i] += WN[k, i] * qd[k]
            vscale[i] += abs(WN[k, i]) * abs(qd[k])
            af += WN[k, i] * par[_MINV + k] * h[k]
            gt += abs(WN[k, i]) * abs(q[k])
        vz[i] = np.sqrt(2.0 * abs(af) * (rtol * gt + atol_max))
    vtol = 1e3 * _EPS * max(vscale[0], vscale[1])
    approaching = np.zeros(2, dtype=np.bool_)
    plastic = np.zeros(2, dtype=np.bool_)
    e = np.empty(2)
    closed = np.zeros(2, dtype=np.bool_)
    uset = np.zeros(2, dtype=np.bool_)
    bset = np.zeros(2, dtype=np.bool_)
    held = np.zeros(2, dtype=np.bool_)
    for i in range(2):
        approaching[i] = hit[i] and gm[i] < -vtol
        plastic[i] = approaching[i] and -gm[i] <= vz[i]
        e[i] = 0.0 if plastic[i] else rest[i]
        closed[i] = modes[i] != OPEN
        uset[i] = (closed[i] and uni[i]) or approaching[i]
        bset[i] = closed[i] and not uni[i]
    Lam = np.empty(2)
    if _impulse(WN, qd, par, uset, bset, e, qd_plus, Lam) != 0:
        return 20
    gp = np.zeros(2)
    for i in range(2):
        for k in range(7):
            gp[i] += WN[k, i] * qd_plus[k]
    u2 = np.empty(2, dtype=np.bool_)
    b2 = np.empty(2, dtype=np.bool_)
    for _ in range(2):
        anyslow = False
        for i in range(2):
            if uset[i] and not held[i] and gp[i] > vtol and gp[i] <= vz[i]:
                held[i] = True
                anyslow = True
        if not anyslow:
            break
        for i in range(2):
            u2[i] = uset[i] and not held[i]
            b2[i] = (closed[i] and not uni[i]) or held[i]
        if _impulse(WN, qd, par, u2, b2, e, qd_plus, Lam) != 0:
            return 20
        for i in range(2):
            gp[i] = 0.0
            for k in range(7):
                gp[i] += WN[k, i] * qd_plus[k]
    e0 = 0.0
    e1 = 0.0
    for k in range(7):
        e0 += qd[k] * qd[k] / par[_MINV + k]
        e1 += qd_plus[k] * qd_plus[k] / par[_MINV + k]
    for i in range(2):
        plastic[i] = plastic[i] or held[i]
        rec[i] = gm[i]
        rec[2 + i] = gp[i]
        rec[4 + i] = Lam[i]
        rec[7 + i] = 1.0 if hit[i] else 0.0
        rec[9 + i] = 1.0 if plastic[i] else 0.0
    rec[6] = 0.5 * e0 - 0.5 * e1
    for i in range(2):
        evk[i] = 0
        evold[i] = modes[i]
        gam = 0.0
        vs = 0.0
        for k in range(7):
            gam += WT[k, i] * qd_plus[k]
            vs += abs(WT[k, i]) * abs(qd_plus[k])
        moving = abs(gam) > 1e3 * _EPS * vs
        old = modes[i]
        if uni[i] and (uset[i] or hit[i]):
            sep = gp[i] > vtol
            if sep:
                modes[i] = OPEN
            elif old == OPEN or (old == STICK and moving):
                if moving:
                    modes[i] = 1 if gam >= 0 else -1
                else:
                    modes[i] = STICK
                sigma[i] = 1.0
            if hit[i]:
                evk[i] = 1 if sep else 2
            elif old != OPEN and sep:
                evk[i] = 3
        elif not uni[i] and closed[i] and old == STICK and moving:
            modes[i] = 1 if gam >= 0 else -1
    return 0


@njit(cache=True)
def event_loop(st, q, qd, modes, sigma, par, t1, rtol, atol, max_step, te, acc, max_events,
               OT, OQ, OQD, OLN, OLT, OM, OE, LOGT, LOGI, cnt, seen, uni, rest, IMPT, IMPR):
    """Phases and switches from the state (st[0] = t, q, q', modes, sigma) towards t1, as
    :meth:`fricdamp.solvers.event._Run.loop` takes them (see the module
    :mod:`fricdamp.models.blade_damper._fastloop`).

    In/out: ``st`` = [t, projection energy, impact loss], q, qd, modes, sigma (the state at
    the start of the next phase, before its projection), ``acc`` (3) the work accumulated at
    that start, ``cnt`` = [n_events, n_phases, n_decisions, n_rhs, n_samples, n_log, phases
    done, reason, n_impacts]; out: samples (``OT``, ``OQ``, ``OQD``, ``OLN``, ``OLT``,
    ``OM``, ``OE`` = input, viscous, friction work, impact loss) from index cnt[4], the event
    log (``LOGT``; ``LOGI`` = contact, from, to, kind 0 friction / 1 normal / 2 lift-off /
    3 impact, whose "to" is 1 closed, 0 open) from cnt[5], the impacts (``IMPT`` times,
    ``IMPR`` rows of :func:`_impact`'s record) from cnt[8], ``seen`` (25) the configurations
    met (modes -1..3 per contact). ``uni`` marks the unilateral contacts (a released damper:
    lift-off and impacts with restitution ``rest``). Everything is committed per completed
    phase and switch. Returns 0 finished (t1 reached), 1 buffers full, else a reason code
    (see ``REASONS``).
    """
    cap = 64
    TA = np.empty(cap)
    TB = np.empty(cap)
    YOLD = np.empty((cap, _NY))
    FF = np.empty((cap, 7, _NY))
    qp = np.empty(7)
    qdp = np.empty(7)
    q2 = np.empty(7)
    qd2 = np.empty(7)
    y = np.empty(_NY)
    f = np.empty(_NY)
    y0 = np.empty(_NY)
    stats = np.empty(4)
    gap = np.empty(2)
    WN = np.empty((7, 2))
    WT = np.empty((7, 2))
    wbN = np.empty(2)
    wbT = np.empty(2)
    hh = np.empty(7)
    qdd = np.empty(7)
    lamN = np.empty(2)
    lamT = np.empty(2)
    yt = np.empty(_NY)
    new = np.empty(2, dtype=np.int64)
    sig = np.empty(2)
    must = np.zeros(2, dtype=np.int64)
    cand = np.zeros(2, dtype=np.bool_)
    fired_slip = np.zeros(2, dtype=np.bool_)
    lift = np.zeros(2, dtype=np.bool_)
    gap_hit = np.zeros(2, dtype=np.bool_)
    mw = np.empty(2, dtype=np.int64)
    qdi = np.empty(7)
    rec = np.empty(11)
    evk = np.empty(2, dtype=np.int64)
    evold = np.empty(2, dtype=np.int64)
    atol_max = 0.0
    for k in range(14):
        atol_max = max(atol_max, atol[k])
    while True:
        t0 = st[0]
        if cnt[0] >= max_events:
            cnt[7] = 14
            return 14
        # ---- _Run._project(modes): onto the phase's constraints
        r, de = project(q, qd, modes, par, qp, qdp)
        if r <= 1e-13:
            cnt[7] = 10
            return 10
        pe = st[1] + de
        # ---- NumericalPhase.__init__ and _advance_fused
        kinds, contacts, lim, sgn = _event_list(modes, par)
        nev = kinds.size
        for k in range(7):
            y0[k] = qp[k]
            y0[7 + k] = qdp[k]
        y0[14] = 0.0
        y0[15] = 0.0
        y0[16] = 0.0
        vel = np.zeros(2)
        g_prev = np.empty(nev)
        scale = np.empty(nev)
        _kin_state(qp, qdp, par, gap, WN, WT, wbN, wbT)
        forces(t0, qp, qdp, par, hh)
        if configuration_solve(hh, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN,
                               lamT) <= 1e-13:
            cnt[7] = 11
            return 11
        event_values(WT, qdp, lamN, lamT, sigma, kinds, contacts, lim, sgn, g_prev, scale,
                     vel, qp, gap, WN)
        for k in range(_NY):
            y[k] = y0[k]
        stats[0] = t0
        stats[1] = 0.0
        stats[2] = 0.0
        stats[3] = 1.0
        GI = np.empty((nev, 4))
        fired = np.zeros(nev, dtype=np.bool_)
        m = 0
        hit = False
        t_stop = t1
        while True:
            status, m = phase_run(y, f, t1, modes, sigma, par, rtol, atol, max_step, kinds,
                                  contacts, lim, sgn, g_prev, scale, vel, TA, TB, YOLD, FF,
                                  m, GI, stats)
            if status == 4:
                cnt[7] = 11
                return 11
            if status == 3:
                cnt[7] = 12
                return 12
            if status == 2:
                cap2 = 2 * TA.size
                TA2 = np.empty(cap2)
                TB2 = np.empty(cap2)
                YOLD2 = np.empty((cap2, _NY))
                FF2 = np.empty((cap2, 7, _NY))
                TA2[:m] = TA[:m]
                TB2[:m] = TB[:m]
                YOLD2[:m] = YOLD[:m]
                FF2[:m] = FF[:m]
                TA, TB, YOLD, FF = TA2, TB2, YOLD2, FF2
                continue
            if status == 0:
                break
            j = m - 1
            ta, tb = TA[j], TB[j]
            code, th = _first_event(j, ta, tb, g_prev, GI, scale, stats[3] != 0.0, TA, TB,
                                    YOLD, FF, modes, sigma, par, kinds, contacts, lim, sgn,
                                    vel, rtol, fired, atol_max)
            if code == 1:
                cnt[7] = 13
                return 13
            if code == 0:
                hit = True
                t_stop = th
                # an impact: at the zero of the gap itself (NumericalPhase._gap_zero)
                ngap = 0
                nfired = 0
                ig = -1
                for e in range(nev):
                    if fired[e]:
                        nfired += 1
                        if kinds[e] == 4:
                            ngap += 1
                            ig = e
                if ngap > 0 and ngap == nfired:
                    if ngap > 1:
                        cnt[7] = 19
                        return 19
                    t_stop = _gap_zero(ig, th, t0, m, TA, TB, YOLD, FF, modes, sigma, par,
                                       kinds, contacts, lim, sgn, vel)
                    if np.isnan(t_stop):
                        cnt[7] = 19
                        return 19
                break
            stats[3] = 0.0
            for e in range(nev):
                g_prev[e] = GI[e, 3]
            if tb >= t1:
                break
        if hit and t_stop <= t0:
            cnt[7] = 13
            return 13
        # ---- _Run._record: samples at the phase start and the t_eval inside the phase
        lo = np.searchsorted(te, t0, side="right")
        hi = np.searchsorted(te, t_stop, side="left")
        nin = max(hi - lo, 0)
        ntimes = nin + 2
        n_rec = ntimes if not hit else ntimes - 1
        n0 = cnt[4]
        if n0 + n_rec > OT.size:
            cnt[7] = 1
            return 1
        nlog0 = cnt[5]
        if nlog0 + 8 > LOGT.size or cnt[8] + 1 > IMPT.size:
            cnt[7] = 1
            return 1
        Y = np.empty((_NY, ntimes))
        times = np.empty(ntimes)
        times[0] = t0
        for a in range(nin):
            times[1 + a] = te[lo + a]
        times[ntimes - 1] = t_stop
        for a in range(ntimes):
            tk = times[a]
            if tk <= t0:
                for k in range(_NY):
                    Y[k, a] = y0[k]
                continue
            idx = np.searchsorted(TA[:m], tk, side="right") - 1
            idx = min(max(idx, 0), m - 1)
            dense_eval(TA[idx], TB[idx] - TA[idx], YOLD[idx], FF[idx], tk, yt)
            for k in range(_NY):
                Y[k, a] = yt[k]
        for a in range(ntimes):
            qa = np.ascontiguousarray(Y[:7, a])
            qda = np.ascontiguousarray(Y[7:14, a])
            _kin_state(qa, qda, par, gap, WN, WT, wbN, wbT)
            forces(times[a], qa, qda, par, hh)
            if configuration_solve(hh, WN, WT, wbN, wbT, modes, sigma, par, qdd, lamN,
                                   lamT) <= 1e-13:
                cnt[7] = 11
                return 11
            if a < n_rec:
                OT[n0 + a] = times[a]
                for k in range(7):
                    OQ[n0 + a, k] = Y[k, a]
                    OQD[n0 + a, k] = Y[7 + k, a]
                for i in range(2):
                    OLN[n0 + a, i] = lamN[i]
                    OLT[n0 + a, i] = lamT[i]
                    OM[n0 + a, i] = modes[i]
                for p in range(3):
                    OE[n0 + a, p] = acc[p] + Y[14 + p, a]
                OE[n0 + a, 3] = st[2]
        if not hit:
            # the run ends at t1: commit
            for p in range(3):
                acc[p] += Y[14 + p, ntimes - 1]
            for k in range(7):
                q[k] = Y[k, ntimes - 1]
                qd[k] = Y[7 + k, ntimes - 1]
            st[0] = t_stop
            st[1] = pe
            cnt[1] += 1
            cnt[3] += int(stats[2])
            cnt[4] = n0 + n_rec
            cnt[6] += 1
            seen[(modes[0] + 1) * 5 + modes[1] + 1] = 1
            cnt[7] = 0
            return 0
        # ---- _Run._switch at t_stop
        ts = t_stop
        for k in range(7):
            qp[k] = Y[k, ntimes - 1]
            qdp[k] = Y[7 + k, ntimes - 1]
        nlog = nlog0
        for i in range(2):
            must[i] = 0
            fired_slip[i] = False
            lift[i] = False
            gap_hit[i] = False
            sig[i] = sigma[i]
            mw[i] = modes[i]
        for e in range(nev):
            if not fired[e]:
                continue
            kd = kinds[e]
            c = contacts[e]
            if kd == 3 and uni[c]:
                lift[c] = True
            elif kd == 4:
                gap_hit[c] = True
            elif kd == 1:
                must[c] = -1
            elif kd == 2:
                must[c] = 1
            elif kd == 0:
                fired_slip[c] = True
            else:
                LOGT[nlog] = ts
                LOGI[nlog, 0] = c
                LOGI[nlog, 1] = 1 if sig[c] > 0 else -1
                sig[c] *= -1
                LOGI[nlog, 2] = 1 if sig[c] > 0 else -1
                LOGI[nlog, 3] = 1
                nlog += 1
        # _Run._unilateral_switch: lift-offs, then the impact of the gaps that closed
        loss = 0.0
        impacted = False
        if lift[0] or lift[1] or gap_hit[0] or gap_hit[1]:
            for i in range(2):
                if lift[i] and mw[i] != OPEN:
                    LOGT[nlog] = ts
                    LOGI[nlog, 0] = i
                    LOGI[nlog, 1] = mw[i]
                    LOGI[nlog, 2] = OPEN
                    LOGI[nlog, 3] = 2
                    nlog += 1
                    mw[i] = OPEN
            for i in range(2):
                gap_hit[i] = gap_hit[i] and mw[i] == OPEN
            if gap_hit[0] or gap_hit[1]:
                if _impact(ts, qp, qdp, mw, sig, gap_hit, uni, rest, par, rtol, atol_max, qdi,
                           rec, evk, evold) != 0:
                    cnt[7] = 20
                    return 20
                impacted = True
                loss = rec[6]
                for k in range(7):
                    qdp[k] = qdi[k]
                for i in range(2):
                    if evk[i] == 0:
                        continue
                    LOGT[nlog] = ts
                    LOGI[nlog, 0] = i
                    if evk[i] == 3:
                        LOGI[nlog, 1] = evold[i]
                        LOGI[nlog, 2] = OPEN
                        LOGI[nlog, 3] = 2
                    else:
                        LOGI[nlog, 1] = OPEN
                        LOGI[nlog, 2] = 0 if evk[i] == 1 else 1
                        LOGI[nlog, 3] = 3
                    nlog += 1
            for i in range(2):
                if mw[i] == OPEN:
                    must[i] = 0
                    fired_slip[i] = False
        # candidates: stuck, fired slip, or at zero slip velocity (Evaluator.tangent_velocity)
        _kin_state(qp, qdp, par, gap, WN, WT, wbN, wbT)
        pm = np.empty(2, dtype=np.int64)
        for i in range(2):
            gam = 0.0
            vs = 0.0
            for k in range(7):
                gam += WT[k, i] * qdp[k]
                vs += abs(WT[k, i]) * abs(qdp[k])
            vs = max(vs, vel[i])
            cand[i] = (mw[i] == STICK or fired_slip[i] or abs(gam) <= 1e3 * _EPS * vs) \
                and mw[i] != OPEN
            pm[i] = STICK if (cand[i] or must[i] != 0) else mw[i]
        r, de = project(qp, qdp, pm, par, q2, qd2)
        if r <= 1e-13:
            cnt[7] = 10
            return 10
        for i in range(2):
            cand[i] = cand[i] and must[i] == 0
        code = _decide(ts, q2, qd2, mw, cand, must, sig, par, new)
        if code != 0:
            cnt[7] = code
            return code
        for i in range(2):
            if new[i] != mw[i]:
                LOGT[nlog] = ts
                LOGI[nlog, 0] = i
                LOGI[nlog, 1] = mw[i]
                LOGI[nlog, 2] = new[i]
                LOGI[nlog, 3] = 0
                nlog += 1
        # ---- commit the phase and the switch
        for p in range(3):
            acc[p] += Y[14 + p, ntimes - 1]
        seen[(modes[0] + 1) * 5 + modes[1] + 1] = 1
        if impacted:
            IMPT[cnt[8]] = ts
            for k in range(11):
                IMPR[cnt[8], k] = rec[k]
            cnt[8] += 1
            st[2] += loss
        for i in range(2):
            sigma[i] = sig[i]
            modes[i] = new[i]
        for k in range(7):
            q[k] = q2[k]
            qd[k] = qd2[k]
        st[0] = ts
        st[1] = pe + de
        cnt[0] += 1
        cnt[1] += 1
        cnt[2] += 1
        cnt[3] += int(stats[2])
        cnt[4] = n0 + n_rec
        cnt[5] = nlog
        cnt[6] += 1
'''


class FastLoop:
    """Runs the compiled ``event_loop`` on a :class:`fricdamp.solvers.event._Run` and writes
    its results into the run as the Python loop would (samples, events, counters, state).

    Parameters
    ----------
    kernels : fricdamp.models.blade_damper._compiled.BladeDamperKernels

    Attributes
    ----------
    stops : dict
        Reason code (see :data:`REASONS`) -> how often the kernel left a phase to Python.
    """

    #: spare sample rows per call beyond the requested times left (one per phase start)
    SPARE = 512

    def __init__(self, kernels):
        self.mod = kernels.mod
        self.par = kernels.par
        self.stops: dict[int, int] = {}

    def advance(self, run, max_events: int) -> bool:
        """Phases and switches of ``run`` from its current state (the start of a phase,
        before its projection) until ``run.t1`` (returns True) or a phase the kernel leaves
        to the Python loop (returns False; the run's state is then the start of that
        phase)."""
        from fricdamp.solvers.event import SwitchEvent
        from fricdamp.solvers.event_impact import Impact
        from fricdamp.solvers.event_switch import MODE_NAMES

        te = np.ascontiguousarray(run.t_eval, dtype=float)
        st = np.array([float(run.t), float(run.proj_energy), float(run.impact_loss)])
        q = np.array(run.q, dtype=float)
        qd = np.array(run.qd, dtype=float)
        modes = np.array(run.modes, dtype=np.int64)
        sigma = np.array(run.sigma, dtype=float)
        acc = np.array(run.acc, dtype=float)
        if not np.all(np.isfinite(acc)):
            acc = np.zeros(3)  # energies not wanted (NaN): the kernel's are discarded
        atol = np.concatenate([np.broadcast_to(np.asarray(run.atol, dtype=float), (14,)),
                               np.full(3, 1e300)])
        cnt = np.array([run.n_events, run.n_phases, run.n_decisions, run.n_rhs, 0, 0, 0, 0,
                        0], dtype=np.int64)
        seen = np.zeros(25, dtype=np.int64)
        uni = np.ascontiguousarray(run.uni, dtype=np.bool_)
        rest = np.ascontiguousarray(run.ev.restitution, dtype=float)
        done = 0
        while True:
            cap = int(te.size - np.searchsorted(te, st[0], "right")) + self.SPARE
            OT = np.empty(cap)
            OQ, OQD = np.empty((cap, 7)), np.empty((cap, 7))
            OLN, OLT = np.empty((cap, 2)), np.empty((cap, 2))
            OM = np.empty((cap, 2), dtype=np.int8)
            OE = np.empty((cap, 4))
            LOGT = np.empty(8 * self.SPARE)
            LOGI = np.empty((8 * self.SPARE, 4), dtype=np.int64)
            IMPT = np.empty(self.SPARE)
            IMPR = np.empty((self.SPARE, 11))
            cnt[4:] = 0
            with np.errstate(under="ignore"):
                status = int(self.mod.event_loop(
                    st, q, qd, modes, sigma, self.par, float(run.t1), float(run.rtol), atol,
                    float(run.max_step), te, acc, int(max_events), OT, OQ, OQD, OLN, OLT, OM,
                    OE, LOGT, LOGI, cnt, seen, uni, rest, IMPT, IMPR))
            done += int(cnt[6])
            n = int(cnt[4])
            if n:
                e = np.full((n, 3), np.nan) if not run.with_energy else OE[:n, :3]
                kin, pot = run._mech(OQ[:n], OQD[:n])
                run.out.append((OT[:n].copy(), OQ[:n].copy(), OQD[:n].copy(),
                                OLN[:n].copy(), OLT[:n].copy(), OM[:n].copy(),
                                e[:, 0].copy(), -e[:, 2], e[:, 1].copy(), kin, pot,
                                OE[:n, 3].copy()))
            for j in range(int(cnt[5])):
                c, a, b, kind = (int(v) for v in LOGI[j])
                if kind == 1:
                    run.events.append(SwitchEvent(
                        float(LOGT[j]), c, "compression" if a > 0 else "tension",
                        "compression" if b > 0 else "tension", "normal"))
                elif kind == 2:
                    run.events.append(SwitchEvent(float(LOGT[j]), c, MODE_NAMES[a], "open",
                                                  "lift-off"))
                elif kind == 3:
                    run.events.append(SwitchEvent(float(LOGT[j]), c, "open",
                                                  "closed" if b == 1 else "open", "impact"))
                else:
                    run.events.append(SwitchEvent(float(LOGT[j]), c, MODE_NAMES[a],
                                                  MODE_NAMES[b]))
            for j in range(int(cnt[8])):
                r = IMPR[j]
                run.impacts.append(Impact(
                    float(IMPT[j]), tuple(int(c) for c in np.flatnonzero(r[7:9])),
                    r[0:2].copy(), r[2:4].copy(), r[4:6].copy(), float(r[6]),
                    tuple(int(c) for c in np.flatnonzero(r[9:11]))))
            run.impact_loss = float(st[2])
            if status != 1:
                break
        if status not in (0, 1):
            self.stops[status] = self.stops.get(status, 0) + 1
        for code in np.flatnonzero(seen):
            run.configs.setdefault((int(code) // 5 - 1, int(code) % 5 - 1), None)
        run.t = float(st[0])
        run.proj_energy = float(st[1])
        run.q, run.qd = q, qd
        run.modes, run.sigma = modes.astype(int), sigma
        run.acc = acc if run.with_energy else np.full(3, np.nan)
        run.n_events, run.n_phases, run.n_decisions, run.n_rhs = (int(v) for v in cnt[:4])
        run.fast_phases += done
        return status == 0
