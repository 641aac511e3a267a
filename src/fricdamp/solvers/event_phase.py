"""Smooth phases between switching events: shared event location and DOP853 phases.

A phase object integrates one stick/slip configuration from its start ``t0`` and offers
``advance(t_end) -> Hit | None`` (the first event), ``outputs(t)`` (q, q', lambda_N,
lambda_T) and ``energy(t)`` (cumulative input, viscous and friction work). Exact phases of linear
systems live in :mod:`fricdamp.solvers.event_exact`; :class:`NumericalPhase` integrates a
general :class:`~fricdamp.solvers.event_system.ConstrainedSystem` with DOP853.

Event location
--------------
Event functions are sampled on a grid of step ``pi / (4 w_max)`` (w_max the largest
|eigenvalue| or load frequency, so that no function turns twice between samples) together with
their exact derivatives; a sign change from positive to non-positive, or a sampled interval
whose derivative changes sign with a non-positive minimum (a grazing dip), is refined by
Brent's method to round-off. DOP853 phases test each step at its end and at three interior
points of the dense output; a dip between those samples (grazing) is looked for where the
samples show a small local minimum (:func:`dip_windows`, :func:`dip_search`). Roots of several
functions closer than round-off (exact phases) or than their integration uncertainty (DOP853:
``rtol`` times the function's scale over its rate, so that round-off does not decide which of
two symmetric contacts breaks away first) are one event.

Grazing in DOP853 phases
------------------------
A function that dips below its threshold and comes back between two samples (a stuck
contact's friction reserve touching the limit briefly, a slip velocity nearly stopping) has
no sign change among the samples. The samples of a step (its start and its quarter points,
spacing d = h/4) are searched for it where they show a local minimum v_k (the value plus the
round-off level) with ``0 < v_k <= c``, c the largest |second difference| of the step's five
samples (:func:`dip_windows`). That trigger cannot miss a dip the samples resolve: the step
is at most a quarter of the fastest period (``pi / (4 w_max)``), so no function turns twice
within two sample spacings, and a minimum inside ``(t_k, t_k+1)`` makes t_k or t_k+1 a local
minimum of the samples (else the function would rise and fall again between t_k-1 and t_k+2);
the minimum lies at most d/2 from the nearer sample, so it is at most ``max|g''| d^2 / 8``
below it, while the second differences are ``g'' d^2`` at their centres: the trigger leaves a
factor 8 for the variation of g'' over the step. A local minimum is a small fraction of the
function's amplitude A below the samples (``c <= A (w_max d)^2 <= A (pi/16)^2``, 4 %), so only
samples within a few per cent of the threshold start a search (and none where the second
differences are at round-off: the dip could then be no deeper). At the start of a phase, a
function that sits at zero (a contact that just switched, set slipping or stuck by a
consistent decision, so moving away from its limit) is not searched at the phase start.
The search (:func:`dip_search`) is Brent's bounded minimisation (golden section with
parabolic steps, Brent's ``localmin``) of the event function on the
step's dense output over the two sample intervals around the local minimum (one at the ends
of the step), the location to 1e-5 of that window (the minimum's value to ``2e-10 c`` or
better), stopped as soon as a point below the threshold is found; the event then fires at
the first root before that point (Brent's root finder on the bracket from the left sample,
unique there since the function turns once). A step ending at a local minimum is searched on
its last interval and the next step on its first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import DOP853
from scipy.optimize import brentq

from fricdamp.errors import ConvergenceError
from fricdamp.solvers.event_switch import OPEN, STICK

_EPS = np.finfo(float).eps

# event-function kinds
EV_SLIP, EV_STICK_POS, EV_STICK_NEG, EV_NORMAL, EV_GAP = 0, 1, 2, 3, 4
# EV_GAP: the gap g_N(q) of an open (unilateral) contact reached 0 (an impact)
# EV_STICK_POS: reserve mu|N| - lambda_T reached 0 (lambda_T at +limit: slips in -)
# EV_STICK_NEG: reserve mu|N| + lambda_T reached 0 (lambda_T at -limit: slips in +)


class _Singular(Exception):
    """A compiled phase met a singular constraint system (redundant constraints)."""


class _Step:
    """Interpolant of one compiled DOP853 step (scipy's dense output, same coefficients)."""

    __slots__ = ("ph", "j")

    def __init__(self, ph, j):
        self.ph, self.j = ph, j

    def __call__(self, t):
        ph, j = self.ph, self.j
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        Y = ph._ck.dense_many(ph._TA, ph._TB, ph._YOLD, ph._FF,
                              np.full(tt.size, j, dtype=np.int64), np.ascontiguousarray(tt))
        return Y[:, 0] if np.ndim(t) == 0 else Y


@dataclass
class Hit:
    """An event found in a phase: right-bracket time and the fired event functions."""

    t: float
    fired: np.ndarray  # indices into the phase's event list
    immediate: bool = False


def event_list(modes, constrained, frictionless=None):
    """(kind, contact) of every event function of a configuration, as two int arrays.

    A frictionless contact (``mu_static = mu_sliding = 0``, flagged in ``frictionless``) has no
    friction events: its tangential force is zero whatever its slip velocity does. An open
    contact (mode ``OPEN``) has one event, its gap reaching zero (``EV_GAP``).
    """
    kinds, contacts = [], []
    for i, m in enumerate(modes):
        if m == OPEN:  # an open contact: only its gap
            kinds.append(EV_GAP)
            contacts.append(i)
            continue
        if frictionless is not None and frictionless[i]:
            pass
        elif m == STICK:
            kinds += [EV_STICK_POS, EV_STICK_NEG]
            contacts += [i, i]
        else:
            kinds.append(EV_SLIP)
            contacts.append(i)
        if constrained[i]:
            kinds.append(EV_NORMAL)
            contacts.append(i)
    return np.array(kinds, dtype=int), np.array(contacts, dtype=int)


def _refine(g, ta, tb, h_scale):
    """Root of g in (ta, tb] with g(ta) > 0 >= g(tb) (as sampled); returns a t with g(t) <= 0
    (the right end of the final bracket). If a re-evaluation disagrees with the samples in
    the last bits (samples propagated by a matrix product), the sampled end is returned."""
    xtol = 4 * _EPS * max(abs(ta), abs(tb), h_scale)
    if tb - ta <= xtol:
        return tb
    fa, fb = g(ta), g(tb)
    if fb > 0 or fa <= 0:
        return tb if fb > 0 else ta
    r = brentq(g, ta, tb, xtol=xtol, rtol=4 * _EPS, maxiter=200)
    step = xtol
    while r < tb and g(r) > 0:
        r = min(tb, r + step)
        step *= 2
    return r


#: Brent's bounded minimisation in dip_search: location tolerance (share of the window)
DIP_XATOL = 1e-5
_DIP_MAXFUN = 100


def dip_windows(v, tol, sits=False):
    """Sample windows to search for a dip of one event function (see the module docstring).

    Parameters
    ----------
    v : sequence of 5 floats
        The function plus its round-off level at a step's start and quarter points.
    tol : float
        Its round-off level.
    sits : bool
        The step starts the phase and the function sits at zero there (``v[0] <= 2 tol``):
        its start is not a candidate.

    Returns
    -------
    list of (a, b)
        Sample indices bounding each window: ``(k - 1, k + 1)`` around a local minimum
        ``v[k]`` of the samples with ``0 < v[k] <= c`` (c the largest |second difference|),
        clipped to ``[0, 4]`` at the ends of the step. Empty unless ``c`` exceeds ``tol``:
        a function whose samples curve by round-off can fall at most ``c / 8`` below them,
        a fraction of round-off.
    """
    c = max(abs(v[0] - 2.0 * v[1] + v[2]), abs(v[1] - 2.0 * v[2] + v[3]),
            abs(v[2] - 2.0 * v[3] + v[4]))
    out = []
    if not c > tol:
        return out
    for k in range(5):
        if not (0.0 < v[k] <= c):
            continue
        if (k > 0 and v[k] > v[k - 1]) or (k < 4 and v[k] > v[k + 1]) or (k == 0 and sits):
            continue
        out.append((max(k - 1, 0), min(k + 1, 4)))
    return out


def dip_search(g, ta, tb):
    """A time in [ta, tb] where ``g <= 0``, or None: Brent's bounded minimisation of g.

    Brent's ``localmin`` (Brent, Algorithms for Minimization without Derivatives, 1973,
    ch. 5: golden section and parabolic steps, in his notation x, w, v for the best, second
    and previous second point; the algorithm of :func:`scipy.optimize.fminbound`) on the
    window mapped to [0, 1], location tolerance ``DIP_XATOL`` (1e-5 of the window), stopped at
    the first point with ``g <= 0``. The blade damper's compiled ``dip_search`` is the same
    algorithm operation for operation.
    """
    span = tb - ta

    def f(u):
        return g(ta + u * span)

    eps_sqrt = np.sqrt(2.2e-16)
    gold = 0.5 * (3.0 - np.sqrt(5.0))
    a, b = 0.0, 1.0
    v = a + gold * (b - a)
    w, x = v, v
    d = e = 0.0
    fx = f(x)
    if fx <= 0:
        return ta + x * span
    n_eval = 1
    fv = fw = fx
    mid = 0.5 * (a + b)
    tol1 = eps_sqrt * abs(x) + DIP_XATOL / 3.0
    tol2 = 2.0 * tol1
    while abs(x - mid) > tol2 - 0.5 * (b - a) and n_eval < _DIP_MAXFUN:
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
        fu = f(u)
        n_eval += 1
        if fu <= 0:
            return ta + u * span
        if fu <= fx:
            if u >= x:
                a = x
            else:
                b = x
            v, fv = w, fw
            w, fw = x, fx
            x, fx = u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv = w, fw
                w, fw = u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
        mid = 0.5 * (a + b)
        tol1 = eps_sqrt * abs(x) + DIP_XATOL / 3.0
        tol2 = 2.0 * tol1
    return None


def first_event(tt, G, gi, tol, first, GD=None, gdi=None, time_tol=None, refine=None,
                dip=None):
    """Earliest event among sampled event functions.

    An event function fires when it falls below ``-tol`` (its round-off level): a function
    that sits at zero (a contact that just switched, or a friction reserve that is
    identically zero) does not fire, one that crosses zero does, located to round-off.

    Parameters
    ----------
    tt : ndarray, shape (n_s,)
        Sample times; ``tt[0]`` is the phase start when ``first``.
    G : ndarray, shape (n_ev, n_s)
        Event function samples.
    gi : callable (i, t) -> float
        Event function i at time t.
    tol : ndarray, shape (n_ev,)
        Round-off level of each function.
    first : bool
        True for the first samples of a phase: a function already below ``-tol`` at
        ``tt[0]`` fires immediately.
    GD, gdi : optional
        Derivative samples and evaluator: an interval where the function stays above the
        threshold at both ends but its derivative changes sign is searched for a dip
        (grazing) below it.
    time_tol : callable (i, t) -> float, optional
        Uncertainty [s] of the root of function i at t from the integration error (a phase
        whose event functions come from a numerical solution). Roots whose uncertainty
        intervals overlap the earliest one's are one event; without it (exact phases) only
        roots within round-off are grouped.
    refine : callable (i, ta, tb, h_scale, tol_i) -> float, optional
        Replaces :func:`_refine` on ``gi(i, t) + tol_i`` (a compiled root finder doing the
        same).
    dip : callable (i, ta, tb, tol_i) -> float or None, optional
        DOP853 phases (five samples: the step's start and quarter points): the windows of
        :func:`dip_windows` are searched for a dip below the threshold by ``dip`` (a time
        in the window where ``gi(i, t) + tol_i <= 0``, or None; :func:`dip_search` on
        ``gi`` when True is given). A window is searched with the interval it starts in;
        a root found beyond that interval waits for the roots of the next one.

    Returns
    -------
    None, or ``(t, fired, immediate)``: the event time (right end of the final bracket of
    the latest of the grouped roots) and the indices of the functions whose roots lie
    within round-off of the earliest one, or ``(tt[0], indices, True)``.
    """
    Gs = G + tol[:, None]
    if first:
        imm = np.flatnonzero(Gs[:, 0] <= 0)
        if imm.size:
            return tt[0], imm, True
    roots = np.full(G.shape[0], np.inf)
    windows = [[] for _ in range(G.shape[0])]
    if dip is not None:
        if dip is True:
            def dip(i, a, b, tol_i):
                return dip_search(lambda t: gi(i, t) + tol_i, a, b)
        for i in range(G.shape[0]):
            windows[i] = dip_windows(Gs[i], tol[i], first and Gs[i, 0] <= 2 * tol[i])
    for j in range(tt.size - 1):
        for i in range(G.shape[0]):
            g = Gs[i]
            if not (g[j] > 0 and np.isinf(roots[i])):
                continue

            def gs(t, i=i):
                return gi(i, t) + tol[i]

            if g[j + 1] <= 0:
                if refine is not None:
                    roots[i] = refine(i, tt[j], tt[j + 1], tt[j + 1] - tt[j], tol[i])
                else:
                    roots[i] = _refine(gs, tt[j], tt[j + 1], tt[j + 1] - tt[j])
            elif GD is not None and GD[i, j] < 0 and GD[i, j + 1] > 0:
                tm = brentq(lambda t, i=i: gdi(i, t), tt[j], tt[j + 1],
                            xtol=4 * _EPS * max(abs(tt[j]), tt[j + 1] - tt[j]), rtol=4 * _EPS)
                if gs(tm) <= 0:
                    roots[i] = _refine(gs, tt[j], tm, tt[j + 1] - tt[j])
            for a, b in windows[i]:  # all samples of a window are > 0
                if a != j or not np.isinf(roots[i]):
                    continue
                tm = dip(i, tt[a], tt[b], tol[i])
                if tm is not None:  # the first root before the point below the threshold
                    if refine is not None:
                        roots[i] = refine(i, tt[a], tm, tt[j + 1] - tt[j], tol[i])
                    else:
                        roots[i] = _refine(gs, tt[a], tm, tt[j + 1] - tt[j])
        if np.isfinite(roots).any() and (roots.min() <= tt[j + 1] or j == tt.size - 2):
            best = roots.min()
            window = np.full(roots.size, 1e3 * _EPS * max(abs(best), tt[j + 1] - tt[j]))
            if time_tol is not None:
                ib = int(np.argmin(roots))
                dt_best = time_tol(ib, best)
                for i in np.flatnonzero(np.isfinite(roots)):
                    if i != ib and roots[i] > best + window[i]:
                        window[i] = max(window[i], dt_best + time_tol(i, roots[i]))
            group = roots <= best + window
            return float(roots[group].max()), np.flatnonzero(group), False
    return None


# =====================================================================================
# DOP853 phases of a general ConstrainedSystem
# =====================================================================================
class NumericalPhase:
    """One phase of a general system integrated by DOP853 with dense output.

    The cumulative input, viscous and friction work of the phase are integrated with the state
    (three extra components ``W' = P(t, q, q')``, evaluated from the same configuration solve
    as the accelerations), so the energies come from the dense output at no extra solves and
    with the integrator's order. They are excluded from the step-size control (their absolute
    tolerance is infinite): the steps are those the motion needs, and the work integrals are
    the Runge-Kutta quadrature of the power over them. A system without power hooks (NaN
    input or viscous power) gets NaN energies.
    """

    _interior = np.array([0.25, 0.5, 0.75, 1.0])

    def __init__(self, ev, modes, sigma, t0, q0, qd0, rtol, atol, max_step):
        self.ev = ev
        self.modes = np.array(modes, dtype=int)
        self.sigma = np.array(sigma, dtype=float)
        self.t0 = float(t0)
        self.n = ev.n
        self.y0 = np.concatenate([q0, qd0, np.zeros(3)])
        self.kinds, self.contacts = event_list(self.modes, ev.constrained, ev.frictionless)
        self.rtol, self.atol, self.max_step = rtol, atol, max_step
        self._segs: list[tuple[float, float, object]] = []
        self.n_rhs = 0
        self.vel_scale = np.zeros(ev.nc)
        self.h = np.inf
        mus = ev.mu_s
        self._lim = mus[self.contacts]
        self._sgn = np.where(self.modes[self.contacts] == STICK, 0,
                             self.modes[self.contacts]).astype(float)
        s = ev.system
        #: compiled kernels of the system (ConstrainedSystem.compiled_kernels), if any
        self._ck = getattr(ev, "compiled", None)
        #: whole DOP853 steps in compiled code (kernels with ``phase_run``): the steps are kept
        #: as arrays (start, end, start state, interpolation coefficients), not objects
        self._fused = bool(getattr(self._ck, "fused_phases", False))
        self._m = 0
        self._ylast = None
        if self._fused:  # the kernels integrate the input and viscous power themselves
            self._has_power = np.ones(3, dtype=bool)
        else:
            self._has_power = np.array([np.isfinite(s.input_power(self.t0, q0, qd0)),
                                        np.isfinite(s.viscous_power(self.t0, q0, qd0)), True])
        # the state's tolerances as given; the work integrals are not step-size controlled
        a = np.broadcast_to(np.asarray(atol, dtype=float), (2 * self.n,))
        self._atol = np.concatenate([a, np.full(3, 1e300)])
        if self._ck is not None:
            self._modes_c = np.ascontiguousarray(self.modes, dtype=np.int64)
            self._lim_c = np.ascontiguousarray(self._lim, dtype=float)
            self._sgn_c = np.ascontiguousarray(self._sgn, dtype=float)
            self._kinds_c = np.ascontiguousarray(self.kinds, dtype=np.int64)
            self._contacts_c = np.ascontiguousarray(self.contacts, dtype=np.int64)

    def _solve(self, t, y):
        n = self.n
        pt = self.ev.point(t, y[:n], y[n:2 * n])
        qdd, lamN, lamT = self.ev.solve(pt, self.modes, self.sigma)
        return pt, qdd[:, 0], lamN[:, 0], lamT[:, 0]

    def _rhs(self, t, y):
        self.n_rhs += 1
        n = self.n
        if self._ck is not None:
            out = np.empty(2 * n + 3)
            if self._ck.rhs(t, y, self._modes_c, self.sigma, out) > self._ck.SINGULAR:
                if not self._has_power[0]:
                    out[2 * n] = 0.0
                if not self._has_power[1]:
                    out[2 * n + 1] = 0.0
                return out
        pt, qdd, _, lamT = self._solve(t, y)
        q, qd = y[:n], y[n:2 * n]
        s = self.ev.system
        p_in = s.input_power(t, q, qd) if self._has_power[0] else 0.0
        p_visc = s.viscous_power(t, q, qd) if self._has_power[1] else 0.0
        out = np.empty(2 * n + 3)
        out[:n] = qd
        out[n:2 * n] = qdd
        out[2 * n] = p_in
        out[2 * n + 1] = p_visc
        out[2 * n + 2] = lamT @ (pt.WT.T @ qd)
        return out

    def _g_many(self, ts, Y):
        """Event functions and scales at the columns of Y, (n_ev, n_t) each."""
        if self._ck is not None:
            vel = self.vel_scale.copy()
            r, G, S = self._ck.events_many(ts, np.ascontiguousarray(Y), self._modes_c,
                                           self.sigma, self._kinds_c, self._contacts_c,
                                           self._lim_c, self._sgn_c, vel)
            if r > self._ck.SINGULAR:
                self.vel_scale = vel
                return G, S
        cols = [self._g_generic(t, Y[:, j]) for j, t in enumerate(ts)]
        return (np.column_stack([g for g, _ in cols]), np.column_stack([c for _, c in cols]))

    def _g(self, t, y):
        if self._ck is not None:
            G, S = self._g_many(np.array([float(t)]), np.asarray(y, float)[:2 * self.n, None])
            return G[:, 0], S[:, 0]
        return self._g_generic(t, y)

    def _g_generic(self, t, y):
        pt, _, lamN, lamT = self._solve(t, y[:2 * self.n])
        gam = pt.WT.T @ pt.qd
        self.vel_scale = np.maximum(self.vel_scale, np.abs(pt.WT).T @ np.abs(pt.qd))
        c = self.contacts
        absN = np.where(self.ev.constrained[c], self.sigma[c] * lamN[c], np.abs(lamN[c]))
        g = np.empty(c.size)
        k = self.kinds
        g[k == EV_SLIP] = (self._sgn * gam[c])[k == EV_SLIP]
        res = self._lim * absN
        g[k == EV_STICK_POS] = (res - lamT[c])[k == EV_STICK_POS]
        g[k == EV_STICK_NEG] = (res + lamT[c])[k == EV_STICK_NEG]
        g[k == EV_NORMAL] = (self.sigma[c] * lamN[c])[k == EV_NORMAL]
        scale = np.where(k == EV_SLIP, np.abs(pt.WT[:, c]).T @ np.abs(pt.qd),
                         np.abs(res) + np.abs(lamT[c]) + np.abs(lamN[c]))
        gap = k == EV_GAP
        if gap.any():
            gN = np.asarray(self.ev.system.normal_gap(pt.q), dtype=float)
            g[gap] = gN[c[gap]]
            scale[gap] = (np.abs(pt.WN[:, c[gap]]).T @ np.abs(pt.q)) + np.abs(gN[c[gap]])
        return g, scale

    def _gap_zero(self, fired, t_hit, interp):
        """The impact instant: the zero of the gaps themselves before ``t_hit``.

        A gap event fires at a penetration of its tolerance (the integration error, see
        :meth:`_tol`); the gap of an approaching contact crossed zero shortly before. Its
        zero is located by Brent's method on the dense output (the right end of the final
        bracket, where the gap is <= 0), so the impact state has the velocity at contact
        rather than after a penetration (which would shift every later bounce). Returns
        ``t_hit`` unchanged if no gap is positive shortly before (a grazing contact).
        """
        if self._fused and np.size(fired) == 1:
            t = self._gap_zero_fused(int(np.ravel(fired)[0]), t_hit)
            if t is not None:
                return t
        sys_gap = self.ev.system.normal_gap
        c = self.contacts[fired]

        def gap(t):
            return float(np.max(np.asarray(sys_gap(self.y(t)[:self.n, 0]), float)[c]))

        span = t_hit - self.t0
        dt = 1e-6 * span
        while dt <= span:
            ta = t_hit - dt
            if gap(ta) > 0:
                return _refine(gap, ta, t_hit, span)
            dt *= 4
        return t_hit

    def _gap_zero_fused(self, i, t_hit):
        """:meth:`_gap_zero` for one gap event (index i) of a compiled phase: the same search
        in compiled code (the kernels' ``gap_zero``, which the compiled event loop uses too)
        on the stored step holding ``t_hit``; None if the search reaches back into an
        earlier step (the generic search takes it)."""
        if self._m == 0:
            return None
        t = self._ck.gap_zero(i, t_hit, self.t0, self._m, self._TA, self._TB, self._YOLD,
                              self._FF, self._modes_c, self.sigma, self._kinds_c,
                              self._contacts_c, self._lim_c, self._sgn_c, self.vel_scale)
        return None if np.isnan(t) else float(t)

    def _tol(self):
        """Round-off level of each event function; for gaps (an integrated position) the
        integration error ``rtol * scale + atol`` instead, so that the error of a gap that
        just opened with zero velocity does not count as an impact."""
        tol = 1e2 * _EPS * self._scale + np.finfo(float).tiny
        gap = self.kinds == EV_GAP
        if gap.any():
            tol[gap] = np.maximum(tol[gap], self.rtol * self._scale[gap]
                                  + float(np.max(self.atol)))
        return tol

    @property
    def segments(self) -> list[tuple[float, float, object]]:
        """The DOP853 steps ``(t_start, t_end, interpolant)`` of the phase."""
        if not self._fused:
            return self._segs
        return [(float(self._TA[j]), float(self._TB[j]), _Step(self, j))
                for j in range(self._m)]

    def y(self, t):
        """State at times t (n_t,) from the dense output, shape (2 n + 3, n_t)."""
        if self._ylast is not None and self._ylast[0] is t:
            return self._ylast[1]  # the same sample times again (outputs, then energy)
        key = t
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self._fused:
            m = self._m
            if m == 0:
                return np.repeat(self.y0[:, None], t.size, axis=1)
            idx = np.clip(np.searchsorted(self._TA[:m], t, side="right") - 1, 0, m - 1)
            out = self._ck.dense_many(self._TA, self._TB, self._YOLD, self._FF,
                                      np.ascontiguousarray(idx, dtype=np.int64),
                                      np.ascontiguousarray(t))
            out[:, t <= self.t0] = self.y0[:, None]
            if isinstance(key, np.ndarray) and key.size > 1:
                self._ylast = (key, out)
            return out
        out = np.empty((2 * self.n + 3, t.size))
        segs = self._segs
        starts = np.array([s[0] for s in segs])
        idx = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(segs) - 1)
        for j in np.unique(idx):
            sel = idx == j
            out[:, sel] = segs[j][2](t[sel])
        at0 = t <= self.t0
        out[:, at0] = self.y0[:, None]
        return out

    def advance(self, t_end) -> Hit | None:
        if t_end <= self.t0:
            return None
        if self._fused:
            vel0 = self.vel_scale.copy()
            try:
                return self._advance_fused(t_end)
            except _Singular:
                # a configuration with redundant constraints: the generic path for the phase
                self._fused, self._m, self.vel_scale, self.n_rhs = False, 0, vel0, 0
        if self.kinds.size == 0:
            return self._integrate_to(t_end)
        g0, sc0 = self._g(self.t0, self.y0)
        self._scale = sc0
        solver = DOP853(self._rhs, self.t0, self.y0, t_end, rtol=self.rtol, atol=self._atol,
                        max_step=self.max_step)
        g_prev, t_prev = g0, self.t0
        first = True
        while solver.status == "running":
            msg = solver.step()
            if solver.status == "failed":
                raise ConvergenceError(f"DOP853 failed at t = {solver.t:.6g} s: {msg}; loosen "
                                       "rtol/atol or check the system for a singular mass")
            interp = solver.dense_output()
            ta, tb = solver.t_old, solver.t
            self._segs.append((ta, tb, interp))
            ts = ta + (tb - ta) * self._interior
            Gi, Si = self._g_many(ts, interp(ts))
            G = np.column_stack([g_prev, Gi])
            self._scale = np.maximum(self._scale, Si.max(axis=1))
            tt = np.concatenate([[t_prev], ts])
            def gfun(i, t, f=interp):
                return self._g(t, f(t))[0][i]

            def time_tol(i, t, f=interp, h=tb - ta):
                # root uncertainty: the event function's integration error (rtol times its
                # scale) over its rate; at most a hundredth of the step
                dt = 1e-6 * h
                rate = abs(gfun(i, t + dt) - gfun(i, t - dt)) / (2 * dt)
                err = self.rtol * self._scale[i]
                return min(err / rate, 1e-2 * h) if rate > 0 else 1e-2 * h

            found = first_event(tt, G, gfun, self._tol(), first, time_tol=time_tol, dip=True)
            first = False
            if found is not None:
                t_hit = found[0]
                if not found[2] and np.all(self.kinds[found[1]] == EV_GAP):
                    t_hit = self._gap_zero(found[1], t_hit, interp)
                return Hit(t_hit, found[1], immediate=found[2])
            g_prev, t_prev = G[:, -1], tb
        return None

    def _advance_fused(self, t_end):
        """:meth:`advance` with the DOP853 steps and the event screening in compiled code
        (the same step-size control, dense output and event samples); only a step whose
        samples change sign or show a dip window (:func:`dip_windows`) comes back here for
        :func:`first_event` (with the compiled root finder and dip search)."""
        ck = self._ck
        n_ev = self.kinds.size
        ny = 2 * self.n + 3
        if n_ev:
            g_prev, sc0 = self._g(self.t0, self.y0)
            g_prev = np.array(g_prev, dtype=float)
            self._scale = np.array(sc0, dtype=float)
        else:
            g_prev, self._scale = np.zeros(0), np.zeros(0)
        cap = 64
        self._TA, self._TB = np.empty(cap), np.empty(cap)
        self._YOLD, self._FF = np.empty((cap, ny)), np.empty((cap, 7, ny))
        y = self.y0.copy()
        f = np.empty(ny)
        GI = np.empty((n_ev, 4))
        stats = np.array([self.t0, 0.0, 0.0, 1.0])
        atol = np.ascontiguousarray(self._atol)
        while True:
            status, m = ck.phase_run(y, f, t_end, self._modes_c, self.sigma, self.rtol, atol,
                                     self.max_step, self._kinds_c, self._contacts_c,
                                     self._lim_c, self._sgn_c, g_prev, self._scale,
                                     self.vel_scale, self._TA, self._TB, self._YOLD, self._FF,
                                     self._m, GI, stats)
            self._m = m
            self.n_rhs = int(stats[2])
            if status == 4:
                raise _Singular
            if status == 3:
                raise ConvergenceError(
                    f"DOP853 failed at t = {stats[0]:.6g} s: Required step size is less than "
                    "spacing between numbers.; loosen rtol/atol or check the system for a "
                    "singular mass")
            if status == 2:
                cap = 2 * self._TA.size
                for name in ("_TA", "_TB", "_YOLD", "_FF"):
                    old = getattr(self, name)
                    new = np.empty((cap,) + old.shape[1:])
                    new[:m] = old[:m]
                    setattr(self, name, new)
                continue
            if status == 0:
                return None
            j = m - 1
            ta, tb = float(self._TA[j]), float(self._TB[j])
            ts = ta + (tb - ta) * self._interior
            G = np.column_stack([g_prev, GI])
            tt = np.concatenate([[ta], ts])
            step = _Step(self, j)

            def gfun(i, t, f=step):
                return self._g(t, f(t))[0][i]

            def gval(i, t, j=j):
                return ck.refine_value(j, i, t, self._TA, self._TB, self._YOLD, self._FF,
                                       self._modes_c, self.sigma, self._kinds_c,
                                       self._contacts_c, self._lim_c, self._sgn_c,
                                       self.vel_scale)

            def time_tol(i, t, h=tb - ta):
                dt = 1e-6 * h
                rate = abs(gval(i, t + dt) - gval(i, t - dt)) / (2 * dt)
                err = self.rtol * self._scale[i]
                return min(err / rate, 1e-2 * h) if rate > 0 else 1e-2 * h

            def refine(i, a, b, h_scale, tol_i, j=j):
                return ck.refine_root(j, i, a, b, h_scale, tol_i, self._TA, self._TB,
                                      self._YOLD, self._FF, self._modes_c, self.sigma,
                                      self._kinds_c, self._contacts_c, self._lim_c,
                                      self._sgn_c, self.vel_scale)

            def dip(i, a, b, tol_i, j=j):
                t = ck.dip_search(j, i, a, b, tol_i, self._TA, self._TB, self._YOLD, self._FF,
                                  self._modes_c, self.sigma, self._kinds_c, self._contacts_c,
                                  self._lim_c, self._sgn_c, self.vel_scale)
                return None if np.isnan(t) else t

            found = first_event(tt, G, gfun, self._tol(), stats[3] != 0.0,
                                time_tol=time_tol, refine=refine, dip=dip)
            if found is not None:
                t_hit = found[0]
                if not found[2] and np.all(self.kinds[found[1]] == EV_GAP):
                    t_hit = self._gap_zero(found[1], t_hit, step)
                return Hit(t_hit, found[1], immediate=found[2])
            stats[3] = 0.0
            g_prev = np.ascontiguousarray(GI[:, -1])
            if tb >= t_end:
                return None

    def _integrate_to(self, t_end):
        solver = DOP853(self._rhs, self.t0, self.y0, t_end, rtol=self.rtol, atol=self._atol,
                        max_step=self.max_step)
        while solver.status == "running":
            msg = solver.step()
            if solver.status == "failed":
                raise ConvergenceError(f"DOP853 failed at t = {solver.t:.6g} s: {msg}")
            self._segs.append((solver.t_old, solver.t, solver.dense_output()))
        return None

    def outputs(self, t):
        Y = self.y(t)
        n = self.n
        nt = Y.shape[1]
        nc = self.ev.nc
        if self._ck is not None:
            ts = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=float)))
            r, _, lamN, lamT, _ = self._ck.solve_many(ts, np.ascontiguousarray(Y[:2 * n]),
                                                      self._modes_c, self.sigma)
            if r > self._ck.SINGULAR:
                return Y[:n].T, Y[n:2 * n].T, lamN.T.copy(), lamT.T.copy()
        lamN = np.empty((nt, nc))
        lamT = np.empty((nt, nc))
        for j in range(nt):
            _, _, lamN[j], lamT[j] = self._solve(float(np.atleast_1d(t)[j]), Y[:2 * n, j])
        return Y[:n].T, Y[n:2 * n].T, lamN, lamT

    def energy(self, times):
        """Cumulative input, viscous and friction work [J] from ``times[0]``, (3, n_times)."""
        W = self.y(times)[2 * self.n:]
        W = W - W[:, :1]
        W[~self._has_power] = np.nan
        return W


__all__ = ["EV_GAP", "EV_NORMAL", "EV_SLIP", "EV_STICK_NEG", "EV_STICK_POS", "Hit",
           "NumericalPhase", "dip_search", "dip_windows", "event_list", "first_event"]
