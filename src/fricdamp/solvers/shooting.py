"""Periodic orbits of stick-slip systems by shooting through exact switching events.

The stroboscopic (Poincare) map of a system forced with period ``T`` is the flow of the
event-driven solver (:func:`fricdamp.solvers.event.simulate_events`, exact set-valued Coulomb
friction, no regularisation) over ``n T``:

    P(y0) = y(t0 + n T; t0, y0),          y = [q, q'],

and a period-n orbit is a fixed point ``P(y0) = y0``, found by Newton's method with the
Jacobian ``dP/dy0 - I``. ``dP/dy0`` is the **monodromy matrix**: the product, phase by phase,
of the projection onto the phase's constraints, the state-transition matrix of the phase
(its variational equations) and the saltation matrix of the event that ends it. Its
eigenvalues are the Floquet multipliers; they are exact for stick-slip because the jumps
of the vector field at the switches enter through the saltation matrices rather than being
smoothed away.

Variational equations of a phase
--------------------------------
In a phase of fixed configuration (stuck set S, slip directions s) the state obeys a smooth
``y' = f(t, y)``, and a perturbation ``dy' = (df/dy) dy``. For a system with a
:class:`~fricdamp.solvers.event_system.LinearForm` the phase is the linear map of
:mod:`fricdamp.solvers.event_exact`, ``X(t) = exp(A (t - t0)) X(t0)`` with ``X(t0) = S0 y +
(load states)`` and ``y = E X``, so its transition matrix is exact:
``Phi = E exp(A dt) S0``. For a general
:class:`~fricdamp.solvers.event_system.ConstrainedSystem` ``df/dy`` is the central difference
of the configuration's vector field (the accelerations of the configuration solve, 000 (37)-(40))
and ``Phi' = (df/dy) Phi`` is integrated by DOP853 along the phase's dense output.
At the start of each phase the solver projects the state onto the phase's constraints
(closed normal gaps, zero slip velocity of the stuck contacts, M-orthogonally); its Jacobian
``Pi`` multiplies ``Phi`` (analytic for a LinearForm, central differences otherwise).

Saltation matrices (derived here)
---------------------------------
A phase ends when an event function ``h(t, y)`` of its configuration reaches zero at ``t_e``
(vector field ``f-`` before, ``f+`` after, the state continuous). A perturbation ``dy-`` of the
state just before the event moves the event to ``t_e + dt_e`` with, to first order,
``h_y . (dy- + f- dt_e) + h_t dt_e = 0``, i.e. ``dt_e = -h_y . dy- / hdot`` with
``hdot = h_y . f- + h_t`` the rate of h along the arriving flow (transversality: hdot != 0).
Between ``t_e`` and ``t_e + dt_e`` the perturbed motion follows the other field, so
``dy+ = dy- + (f- - f+) dt_e``, and

    S = I + (f+ - f-) h_y^T / hdot.

For the three stick-slip events, with ``gamma_i = W_T,i^T q'`` the slip velocity of contact i,
``a_i`` its rate, ``w_i = W_T,i`` and ``Delta qdd`` the jump of the accelerations (positions
and velocities are continuous, so ``f+ - f- = [0, Delta qdd]``):

* **slip -> stick** (000 (41)): ``h = s_i gamma_i``, ``h_y = s_i [d(W_T,i^T q')/dq, w_i]``,
  ``hdot = s_i a_i-`` (the relative deceleration that brings the contact to rest). In stick
  ``a_i+ = 0`` so ``h_y^T S = h_y^T (1 - hdot / hdot) = 0``: every perturbation leaves the
  event on the stick manifold, and each stuck contact contributes a zero multiplier.
* **slip reversal** (``s_i -> -s_i`` without sticking, ``mu_static |lambda_N|`` exceeded at
  once): same ``h`` and ``hdot``; for fixed normal load ``Delta qdd = M^-1 w_i 2 mu_sliding N_i
  s_i``, and ``det S = 1 + h_y . (f+ - f-) / hdot = a_i+ / a_i-``: the ratio of the relative
  accelerations after and before the reversal (< 1 in magnitude for the den Hartog oscillator:
  friction opposes the motion on both sides).
* **stick -> slip** (000 (43)): ``h(t, y) = mu_static |lambda_N| -+ lambda_T,i(t, y)`` (the
  friction reserve of the stuck configuration, lambda_T the stick multiplier); ``hdot`` is its
  rate along the stuck flow, and ``Delta qdd = M^-1 w_i (lambda_T+ - lambda_T-)`` with the
  force dropping from ``+-mu_static |lambda_N|`` to ``+-mu_sliding |lambda_N|``. With
  ``mu_static = mu_sliding`` the field is continuous and ``S = I``.

Unilateral contacts: a lift-off (``h = lambda_N``) is a smooth switch as above; an impact
(``h = g_N``, the gap of an open contact) also makes the state jump, ``y+ = g(y-)``, and
``S = G + (f+ - G f-) h_y^T / hdot`` with ``G = dg/dy`` (derived in
:meth:`_Linearizer.unilateral_saltation`). Grazing lift-offs and impacts, impacts cut short
by the Zeno velocity and several unilateral events at one instant are refused
(:class:`~fricdamp.errors.ConvergenceError`).

An event that keeps the configuration (grazing, a sign change of a constrained normal force
with the friction law written with ``|lambda_N|``) has ``f+ = f-`` and ``S = I``. Several
functions vanishing at once (a corner of the switching surfaces) have no unique saltation
matrix: the first one is used and the orbit is flagged (``n_simultaneous``).

References
----------
Leine & Nijmeijer (2004), Dynamics and Bifurcations of Non-Smooth Mechanical Systems, ch. 2-3
(saltation matrix, Filippov systems), ch. 7 (impacts); Mueller (1995), Calculation of
Lyapunov exponents for dynamic systems with discontinuities; Aizerman & Gantmakher (1958);
den Hartog (1931); paper 000 (29)-(46).
"""

from __future__ import annotations

import logging
import time as _time
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
from scipy.optimize import brentq

from fricdamp.errors import ConvergenceError, ModelError, as_finite_array
from fricdamp.results import ResultMixin
from fricdamp.solvers.event import _Run, impact_map
from fricdamp.solvers.event_exact import ExactPhase
from fricdamp.solvers.event_phase import EV_GAP, EV_NORMAL
from fricdamp.solvers.event_switch import OPEN, STICK
from fricdamp.solvers.event_system import ConstrainedSystem

log = logging.getLogger(__name__)

_EPS = np.finfo(float).eps


# =====================================================================================
# traced flow and monodromy
# =====================================================================================
@dataclass(frozen=True)
class Flow:
    """One traced run of the event-driven solver with its monodromy matrix.

    Attributes
    ----------
    y_end : ndarray, shape (2 n_dof,)
        State ``[q, q']`` at the end of the run.
    monodromy : ndarray, shape (2 n_dof, 2 n_dof)
        ``d y_end / d y0`` (projections, phase transitions and saltation matrices).
    result : EventResult
        The run's samples and events (no energies: its ``energy`` entries are NaN).
    n_simultaneous : int
        Events where several event functions vanished together (no unique saltation matrix).
    monodromy_error : float
        Error estimate of the Floquet multipliers' moduli from DOP853 phases: the largest
        change of a sorted |multiplier| between Magnus steps over whole and half DOP853
        steps (a fourth-order method: the half steps are ~16x better); 0 for exact phases.
    """

    y_end: np.ndarray
    monodromy: np.ndarray
    result: object
    trace: list = field(repr=False)
    n_simultaneous: int = 0
    monodromy_error: float = 0.0


class _Linearizer:
    """Jacobians of a traced run (projection, phase transition, saltation)."""

    def __init__(self, run: _Run, rtol: float, atol: float):
        self.run = run
        self.ev = run.ev
        self.n = run.ev.n
        self.linear = run.lf is not None
        self.rtol, self.atol = rtol, atol
        #: transition of the last phase over whole DOP853 steps (error estimate)
        self.coarse = None

    # -------------------------------------------------------------- vector fields
    def field(self, t, y, modes, sigma):
        """[q', q''] of configuration ``modes`` at (t, y) (general systems)."""
        n = self.n
        ck = self.ev.compiled
        if ck is not None:
            out = np.empty(2 * n + 3)
            y2 = np.zeros(2 * n + 3)
            y2[:2 * n] = y
            if ck.rhs(t, y2, np.asarray(modes, np.int64), np.asarray(sigma, float),
                      out) > ck.SINGULAR:
                return out[:2 * n]
        pt = self.ev.point(t, y[:n], y[n:])
        qdd = self.ev.solve(pt, np.asarray(modes), np.asarray(sigma))[0][:, 0]
        return np.concatenate([y[n:], qdd])

    def _steps(self, y):
        n = self.n
        sq = max(np.abs(y[:n]).max(), 1e-300)
        sv = max(np.abs(y[n:]).max(), 1e-300)
        scale = np.concatenate([np.maximum(np.abs(y[:n]), sq), np.maximum(np.abs(y[n:]), sv)])
        return 6e-6 * scale

    def _fd(self, fun, y):
        """Central-difference Jacobian of fun at y (columns scaled by the state's size)."""
        steps = self._steps(y)
        cols = []
        for j, hj in enumerate(steps):
            e = np.zeros_like(y)
            e[j] = hj
            cols.append((np.asarray(fun(y + e)) - np.asarray(fun(y - e))) / (2 * hj))
        return np.column_stack(cols)

    # -------------------------------------------------------------- projections
    def projection(self, rec, stuck_extra=None):
        """Jacobian of the projection at the start of phase ``rec``."""
        n = self.n
        modes = np.array(rec.modes)
        if stuck_extra is not None:
            modes = np.where(stuck_extra, STICK, modes)
        if self.linear:
            P = np.eye(2 * n)
            if (modes == STICK).any():
                P[n:, n:] -= self.run.decider.projector(modes == STICK)
            return P
        if not (self.ev.constrained.any() or (modes == STICK).any()):
            return np.eye(2 * n)
        t = rec.t_start
        y = np.concatenate(rec.y_pre)
        ck = self.ev.compiled
        if (ck is not None and hasattr(ck, "projection_jacobian") and ck.fused_phases
                and self.ev.constrained.all()
                and (getattr(ck, "open_contacts", False) or not (modes == OPEN).any())):
            ratio, P = ck.projection_jacobian(y, modes.astype(np.int64))
            if ratio > ck.SINGULAR:  # the same differences in one compiled call
                return P

        def proj(y):
            q, qd, _ = self.ev.project(t, y[:n], y[n:], modes)
            return np.concatenate([q, qd])

        return self._fd(proj, y)

    # -------------------------------------------------------------- phase transition
    def transition(self, rec):
        n = self.n
        ph = rec.phase
        dt = rec.t_end - rec.t_start
        if isinstance(ph, ExactPhase):
            c = ph.cfg
            E = np.vstack([c.Eq, c.Eqd])
            return E @ sla.expm(c.A * dt) @ c.S0
        if dt <= 0:
            return np.eye(2 * n)

        # fourth-order Magnus steps on halves of the phase's own DOP853 steps (exact for a
        # constant Jacobian, however fast the motion: the exponential carries it); the
        # product over whole steps is kept in ``coarse`` for the error estimate
        ck = self.ev.compiled
        modes_c = np.asarray(rec.modes, np.int64)
        sigma_c = np.asarray(rec.sigma, float)
        if ck is not None and hasattr(ck, "transition") and getattr(ph, "_fused", False):
            # the Magnus steps below in one compiled call (blade damper)
            ratio, Phi, coarse = ck.transition(ph, rec.t_start, rec.t_end, modes_c, sigma_c)
            if ratio > ck.SINGULAR:
                self.coarse = coarse
                return Phi

        def jac(t):
            y = ph.y(np.array([t]))[:2 * n, 0]
            if ck is not None and hasattr(ck, "jacobian"):
                ratio, J = ck.jacobian(t, y, modes_c, sigma_c, self._steps(y))
                if ratio > ck.SINGULAR:
                    return J
            return self._fd(lambda yy: self.field(t, yy, rec.modes, rec.sigma), y)

        def magnus(a, b):
            h = b - a
            c = 0.5 * h / np.sqrt(3.0)
            m = 0.5 * (a + b)
            J1, J2 = jac(m - c), jac(m + c)
            omega = 0.5 * h * (J1 + J2) + (np.sqrt(3.0) / 12.0) * h * h * (J2 @ J1 - J1 @ J2)
            return sla.expm(omega)

        Phi = np.eye(2 * n)
        coarse = np.eye(2 * n)
        bounds = sorted({rec.t_start, rec.t_end} | {
            t for seg in ph.segments for t in seg[:2] if rec.t_start < t < rec.t_end})
        for a, b in zip(bounds[:-1], bounds[1:], strict=False):
            if b > a:
                m = 0.5 * (a + b)
                Phi = magnus(m, b) @ magnus(a, m) @ Phi
                coarse = magnus(a, b) @ coarse
        self.coarse = coarse
        return Phi

    # -------------------------------------------------------------- unilateral events
    def unilateral_saltation(self, rec, nxt, jump, scales):
        """Saltation matrix of a lift-off (``jump`` None) or an impact ending ``rec``, and
        1 if other contacts' events fired at the same instant (else 0).

        Derivation (Leine & Nijmeijer 2004, section 7.2; Mueller 1995). The phase ends where
        ``h(y) = 0``: the gap ``g_N(q)`` of an open contact (impact) or the normal force
        ``lambda_N(t, y)`` of a closed one (lift-off). At the event the state jumps,
        ``y+ = g(y-)`` (the impact map: impulse by Newton's law, then the projection onto
        the constraints the contacts keep; ``g`` = identity at a lift-off), and the vector
        field changes from ``f-`` (arriving configuration) to ``f+`` (the next one, at
        ``y+``). Perturb the state before the event by ``dy``: the perturbed motion reaches
        the surface at ``t_e + dt`` with ``h_y . (dy + f- dt) = 0`` (to first order; ``h_t``
        is included in ``hdot``), so ``dt = -h_y . dy / hdot``, ``hdot = h_y . f- + h_t``.
        Its state there is ``y- + dy + f- dt``, which jumps to
        ``g(y- + dy + f- dt) = y+ + G (dy + f- dt)``, ``G = dg/dy`` at ``y-``; meanwhile
        the unperturbed motion has moved on to ``y+ + f+ dt``. Compared at the same time
        ``t_e + dt``, the perturbation after the event is
        ``dy+ = G dy + (G f- - f+) dt``, i.e.

            S = G + (f+ - G f-) h_y^T / hdot.

        ``G`` acts only on ``dy - f- (h_y . dy) / hdot``, which is tangent to the surface,
        so how ``g`` is continued off the surface does not matter. For a lift-off ``G = I``
        and ``S`` is the standard saltation matrix. For the impact oscillator (stop at
        ``x = d``, ``h = d - x``, ``g(x, v) = (x, -e v)``) this gives
        ``S = [[-e, 0], [(a+ + e a-) / v-, -e]]`` (``a-+`` the accelerations before and
        after, ``v-`` the arrival velocity), ``det S = e^2``.

        ``G`` is the central difference of :func:`~fricdamp.solvers.event.impact_map`
        (its combinatorics fixed, the state scaled as in :meth:`_fd`): exact to round-off
        for an impact map linear in the state (constant ``W_N``, constant mass), else
        O(h^2) with h ~ 6e-6 of the state's size.
        """
        n = self.n
        t = rec.t_end
        ph = rec.phase
        fired = np.asarray(rec.hit.fired)
        kinds, contacts = ph.kinds[fired], ph.contacts[fired]
        want = EV_GAP if jump is not None else EV_NORMAL
        sel = [k for k, kk, c in zip(fired, kinds, contacts, strict=True)
               if kk == want and self.ev.unilateral[c]]
        i = int(sel[0])
        c = int(ph.contacts[i])
        # other contacts' events at the same instant: a corner, the first one is used
        n_sim = int(len(set(contacts.tolist())) > 1)
        y = np.concatenate(rec.y_end)
        f_minus = self.field(t, y, rec.modes, rec.sigma)

        def h(tt, yy):
            return ph._g(tt, np.concatenate([yy, np.zeros(3)]))[0][i]

        grad = self._fd(lambda yy: np.array([h(t, yy)]), y)[0]
        dt = 1e-6 * max(rec.t_end - rec.t_start, abs(t) * 1e-3, 1e-12)
        hdot = (h(t + dt, y + dt * f_minus) - h(t - dt, y - dt * f_minus)) / (2 * dt)
        y_next = np.concatenate(nxt.y_pre)
        if jump is None:
            G = np.eye(2 * n)
            jumped = y
            rate_scale = scales["force"] / scales["time"]
            what = f"lift-off of contact {c}"
        else:
            def g_map(yy):
                return np.concatenate(impact_map(self.ev, jump, yy[:n], yy[n:]))

            jumped = g_map(y)
            G = self._fd(g_map, y)
            rate_scale = scales["normal_speed"][c]
            what = f"impact of contact {c}"
        # the map must reproduce the state the run continued from (else several events
        # met at this instant and the single-event saltation matrix does not apply)
        sc = np.concatenate([np.full(n, scales["q"]), np.full(n, scales["qd"])])
        if np.max(np.abs(jumped - y_next) / sc) > 1e-8:
            raise ConvergenceError(
                f"{what} at t = {t:.10g} s: the state after the event is not the image of "
                "the state before it under this event alone (several events at one instant); "
                "no saltation matrix: this orbit cannot be shot")
        if not (np.isfinite(hdot) and abs(hdot) > 1e-6 * rate_scale):
            raise ConvergenceError(
                f"{what} at t = {t:.10g} s is grazing (rate of the event function "
                f"{hdot:.3g}, scale {rate_scale:.3g}): the saltation matrix is unbounded and "
                "the Floquet multipliers are not defined; shoot at another frequency or "
                "restitution")
        f_plus = self.field(t, np.asarray(nxt.phase.y0[:2 * n], float), nxt.modes, nxt.sigma)
        return G + np.outer(f_plus - G @ f_minus, grad) / hdot, n_sim

    # -------------------------------------------------------------- saltation
    def saltation(self, rec, nxt):
        """Saltation matrix of the event ending ``rec``; ``nxt`` is the next phase of
        positive duration (its configuration and start state give f+)."""
        n = self.n
        if nxt is None or np.array_equal(nxt.modes, rec.modes):
            return np.eye(2 * n), 0
        fired = np.asarray(rec.hit.fired)
        ph = rec.phase
        contacts = ph.contacts[fired]
        changed = np.flatnonzero(np.asarray(nxt.modes) != np.asarray(rec.modes))
        # the event function of a contact whose mode changed (the others only grazed)
        pick = [k for k, c in zip(fired, contacts, strict=True) if c in changed]
        i = pick[0] if pick else int(fired[0])
        n_sim = int(len(set(ph.contacts[pick].tolist())) > 1) if pick else 0
        t = rec.t_end
        if isinstance(ph, ExactPhase):
            c = ph.cfg
            X = ph.X(np.array([t]))[:, 0]
            E = np.vstack([c.Eq, c.Eqd])
            f_minus = E @ (c.A @ X)
            grad = c.Eev[i] @ c.S0
            hdot = float(c.Eev_d[i] @ X)
            c2 = nxt.phase.cfg
            f_plus = np.vstack([c2.Eq, c2.Eqd]) @ (c2.A @ nxt.phase.X0)
        else:
            y = np.concatenate(rec.y_end)
            f_minus = self.field(t, y, rec.modes, rec.sigma)
            # the event function's gradient (central differences, the steps of _fd) and its
            # rate along f-, all 30 values in one call of the phase's event functions
            steps = self._steps(y)
            dt = 1e-6 * max(rec.t_end - rec.t_start, abs(t) * 1e-3, 1e-12)
            Y = np.empty((2 * n, 2 * (2 * n) + 2))
            Y[:] = y[:, None]
            j = np.arange(2 * n)
            Y[j, 2 * j] += steps
            Y[j, 2 * j + 1] -= steps
            Y[:, -2] = y + dt * f_minus
            Y[:, -1] = y - dt * f_minus
            ts = np.full(Y.shape[1], t)
            ts[-2:] = (t + dt, t - dt)
            gv = ph._g_many(ts, Y)[0][i]
            grad = (gv[0:4 * n:2] - gv[1:4 * n:2]) / (2 * steps)
            hdot = (gv[-2] - gv[-1]) / (2 * dt)
            y2 = np.asarray(nxt.phase.y0[:2 * n])
            f_plus = self.field(t, y2, nxt.modes, nxt.sigma)
        if hdot == 0 or not np.isfinite(hdot):
            raise ConvergenceError(f"event at t = {t:.10g} s is not transversal (the event "
                                   "function's rate is zero: grazing); no saltation matrix")
        return np.eye(2 * n) + np.outer(f_plus - f_minus, grad) / hdot, n_sim


_CONFIGS: dict[int, tuple] = {}


def _share_caches(run) -> None:
    """Give ``run`` the LinearConfig cache and the switching decider (with its projector
    cache) of its LinearForm, kept while the form lives: the many flows of one shooting
    problem then build each configuration once."""
    lf = run.lf
    entry = _CONFIGS.get(id(lf))
    if entry is None or entry[0]() is not lf or not (
            np.array_equal(entry[2].mu_s, run.decider.mu_s)
            and np.array_equal(entry[2].mu_d, run.decider.mu_d)):
        if len(_CONFIGS) > 64:
            for key in [k for k, e in _CONFIGS.items() if e[0]() is None]:
                del _CONFIGS[key]
        entry = (weakref.ref(lf), {}, run.decider)
        _CONFIGS[id(lf)] = entry
    run.configs = entry[1]
    run.decider = entry[2]
    run.decider.ambiguities = []


def flow(system: ConstrainedSystem, t_span, y0, *, t_eval=None, method: str = "auto",
         rtol: float = 1e-10, atol: float = 1e-12, max_events: int = 100_000,
         max_step: float = np.inf, monodromy: bool = True, keep_phases: bool = True) -> Flow:
    """Event-driven flow over ``t_span`` from ``y0`` with its monodromy matrix.

    Parameters
    ----------
    system : ConstrainedSystem
        System with stick-slip contacts (e.g. :class:`CoulombSystem`), optionally with
        unilateral contacts (lift-off and impacts; DOP853 phases).
    t_span : (float, float)
        Start and end time [s].
    y0 : array_like, shape (2 n_dof,)
        ``[q, q']`` at ``t_span[0]`` [m, m/s].
    t_eval : array_like, optional
        Sample times of the returned history (default: both ends).
    method, rtol, atol, max_events, max_step
        As in :func:`~fricdamp.solvers.event.simulate_events` (rtol/atol also set the
        accuracy of the variational equations of DOP853 phases).
    monodromy : bool
        Compute ``d y_end / d y0`` (False: the flow only, monodromy is NaN).
    keep_phases : bool
        Keep the phase records (``Flow.trace``: exact extrema, the monodromy). With
        ``monodromy=False`` and ``keep_phases=False`` the run may go through a system's
        compiled event loop (the blade damper's), which keeps no records; ``trace`` is then
        empty. Same flow either way.

    Returns
    -------
    Flow

    Raises
    ------
    ConvergenceError
        The run failed, or (``monodromy=True``) an impact or lift-off of the run is grazing,
        cut short by the Zeno velocity, one of several unilateral events at one instant,
        or at the end of the run: no saltation matrix.
    """
    if not isinstance(system, ConstrainedSystem):
        raise ModelError(f"system must be a ConstrainedSystem, got {type(system).__name__}")
    system.check()
    t0, t1 = (float(v) for v in t_span)
    n = int(system.n_dof)
    y = as_finite_array("y0", y0)
    if y.shape != (2 * n,):
        raise ModelError(f"y0 must hold [q, q'] with {2 * n} entries, got {y.shape}")
    if method not in ("auto", "exact", "dop853"):
        raise ModelError(f"method must be 'auto', 'exact' or 'dop853', got {method!r}")
    uni = np.asarray(system.unilateral_contacts(), dtype=bool)
    if method == "exact" and uni.any():
        raise ModelError("method='exact' does not handle unilateral contacts (lift-off and "
                         "impacts); use method='dop853'")
    lf = system.linear_form() if method in ("auto", "exact") and not uni.any() else None
    if method == "exact" and lf is None:
        raise ModelError("method='exact' needs a system with a linear form")
    te = np.array([t0, t1]) if t_eval is None else np.asarray(t_eval, float)
    wall = _time.perf_counter()
    run = _Run(system, lf, t0, t1, te, rtol, atol, max_step)
    if lf is not None:
        _share_caches(run)
    run.trace = [] if (monodromy or keep_phases) else None
    run.with_energy = False
    # nor the mechanical energy of every sample (a Python call per phase): a flow's
    # result carries no energies (all NaN)
    run._mech = lambda q, qd: (np.full(len(q), np.nan), np.full(len(q), np.nan))
    run.start(y[:n], y[n:])
    status, message = run.loop(int(max_events))
    if status != 0:
        raise ConvergenceError(message)
    res = run.result(status, message, _time.perf_counter() - wall)
    trace = run.trace
    if trace is None:  # the last sample is the state at t1 (an end is always recorded)
        return Flow(np.concatenate([res.q[-1], res.qd[-1]]), np.full((2 * n, 2 * n), np.nan),
                    res, [], 0, float("nan"))
    y_end = np.concatenate(trace[-1].y_end)
    if not monodromy:
        return Flow(y_end, np.full((2 * n, 2 * n), np.nan), res, trace, 0, float("nan"))
    lin = _Linearizer(run, min(rtol, 1e-8), atol)
    # contacts put at rest by the start decision are projected too
    gam = system.tangent_jacobian(y[:n]).T @ y[n:] if n else np.zeros(0)
    start_stuck = np.asarray(trace[0].modes) == STICK
    start_stuck |= np.abs(gam) == 0
    start_stuck &= np.asarray(trace[0].modes) != OPEN
    scales = _unilateral_scales(run, res, t1 - t0) if uni.any() else None
    Phi = np.eye(2 * n)
    coarse = np.eye(2 * n)  # the same product with whole Magnus steps (DOP853 phases)
    n_sim = 0
    positive = [k for k, r in enumerate(trace) if r.t_end > r.t_start or r.hit is None]
    for idx, k in enumerate(positive):
        rec = trace[k]
        P = lin.projection(rec, start_stuck if idx == 0 else None)
        lin.coarse = None
        tr = lin.transition(rec)
        Phi = tr @ (P @ Phi)
        coarse = (tr if lin.coarse is None else lin.coarse) @ (P @ coarse)
        if rec.hit is not None:
            nxt = trace[positive[idx + 1]] if idx + 1 < len(positive) else None
            if scales is not None and _unilateral_event(run, rec):
                if nxt is None:
                    raise ConvergenceError(
                        f"a lift-off or impact at t = {rec.t_end:.10g} s ends the run: move "
                        "the Poincare section (t0) off the event")
                if nxt is not trace[k + 1]:
                    raise ConvergenceError(
                        f"a lift-off or impact at t = {rec.t_end:.10g} s is followed by "
                        "further events at the same instant (grazing, or an impact that "
                        "closes the contact in tension): no saltation matrix; this orbit "
                        "cannot be shot")
                jump = run.jumps.get(k)
                if jump is not None and jump.zeno:
                    raise ConvergenceError(
                        f"the impact at t = {rec.t_end:.10g} s was slower than the Zeno "
                        "velocity (an accumulation of impacts, cut short by a plastic one): "
                        "its saltation matrices are not resolved, the Floquet multipliers "
                        "would be wrong; shoot at another frequency or restitution")
                S, sim = lin.unilateral_saltation(rec, nxt, jump, scales)
                n_sim += sim
                Phi = S @ Phi
                coarse = S @ coarse
                continue
            S, sim = lin.saltation(rec, nxt)
            n_sim += sim
            Phi = S @ Phi
            coarse = S @ coarse
    err = 0.0
    if not lin.linear:
        a = np.sort(np.abs(np.linalg.eigvals(Phi)))
        b = np.sort(np.abs(np.linalg.eigvals(coarse)))
        err = float(np.max(np.abs(a - b)))
    return Flow(y_end, Phi, res, trace, n_sim, err)


def _unilateral_event(run, rec) -> bool:
    """The event ending ``rec`` is a lift-off or an impact of a unilateral contact."""
    ph = rec.phase
    fired = np.asarray(rec.hit.fired)
    kinds, contacts = ph.kinds[fired], ph.contacts[fired]
    return bool(np.any((kinds == EV_GAP) | ((kinds == EV_NORMAL) & run.uni[contacts])))


def _unilateral_scales(run, res, duration):
    """Scales of the transversality checks of lift-offs and impacts: the largest |q|, |q'|,
    |lambda_N| of the run, its duration and per contact the largest normal speed scale
    ``|W_N|^T |q'|``."""
    q, qd = res.q, res.qd
    WN = np.abs(np.asarray(run.system.normal_jacobian(q[0]), float))
    return {"q": max(float(np.abs(q).max()), 1e-300),
            "qd": max(float(np.abs(qd).max()), 1e-300),
            "force": max(float(np.abs(res.lambda_N).max()), 1e-300),
            "time": max(float(duration), 1e-300),
            "normal_speed": np.maximum(WN.T @ np.abs(qd).max(axis=0), 1e-300)}


# =====================================================================================
# periodic orbits
# =====================================================================================
@dataclass(frozen=True, repr=False)
class PeriodicOrbit(ResultMixin):
    """A periodic orbit found by shooting.

    Attributes
    ----------
    period : float
        Excitation period T [s]; the orbit's period is ``period_multiple * T``.
    period_multiple : int
        n of the period-n orbit.
    t0 : float
        Time of the Poincare section [s].
    y0 : ndarray, shape (2 n_dof,)
        ``[q, q']`` on the orbit at ``t0`` [m, m/s].
    amplitude : ndarray, shape (n_dof,)
        Half peak-to-peak displacement over the orbit [m] (extrema located on the exact
        solution, not on samples).
    multipliers : ndarray of complex, shape (2 n_dof,)
        Floquet multipliers (eigenvalues of the monodromy matrix over ``n T``), by
        decreasing modulus. Each stuck contact and each constrained normal gives zeros.
    monodromy : ndarray, shape (2 n_dof, 2 n_dof)
    stable : bool
        All multipliers inside the unit circle (``max |mu| < 1 - stability_margin``).
    success : bool
        Newton converged (``residual <= tol``).
    residual : float
        ``max |P(y0) - y0|`` scaled per component by the orbit's largest |q| and |q'|.
    iterations : int
    message : str
    t, q, qd : ndarray, shapes (n_t,), (n_t, n_dof), (n_t, n_dof)
        Samples over one orbit (plus event times).
    modes : ndarray of int8, shape (n_t, n_contacts)
    n_events : int
        Switching events per orbit.
    n_simultaneous : int
        Events where several switching functions vanished together.
    method : str
        ``"exact"`` or ``"dop853"``.
    runtime_s : float
    dof_names : tuple of str
    """

    period: float
    period_multiple: int
    t0: float
    y0: np.ndarray
    amplitude: np.ndarray
    multipliers: np.ndarray
    monodromy: np.ndarray
    stable: bool
    success: bool
    residual: float
    iterations: int
    message: str
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    modes: np.ndarray
    n_events: int
    n_simultaneous: int
    method: str
    runtime_s: float
    dof_names: tuple = ()

    @property
    def omega(self) -> float:
        """Excitation circular frequency 2 pi / T [rad/s] (``omega_rad_s``)."""
        return 2 * np.pi / self.period

    @property
    def omega_rad_s(self) -> float:
        """Excitation circular frequency 2 pi / T [rad/s]."""
        return 2 * np.pi / self.period

    @property
    def frequency_hz(self) -> float:
        """Excitation frequency 1 / T [Hz]."""
        return 1.0 / self.period

    @property
    def floquet_multipliers_abs(self) -> np.ndarray:
        return np.abs(self.multipliers)

    def _judge(self):
        """``failed`` if Newton did not converge; the residual, the largest |multiplier|
        and the number of simultaneous events recorded (stability is a property of the
        orbit, not an error: an unstable orbit is a correct answer)."""
        from fricdamp.results import status_verdict

        mu = float(np.max(np.abs(self.multipliers))) if self.multipliers.size else None
        return status_verdict(self.success, self.message,
                              {"residual": float(self.residual), "max_multiplier_abs": mu,
                               "n_simultaneous": int(self.n_simultaneous)})

    def to_xarray(self):
        """``xarray.Dataset``: one orbit (q, q', contact modes over time), the amplitudes
        and the Floquet multipliers (real and imaginary parts)."""
        import xarray as xr

        dofs = list(self.dof_names) or [f"q{i + 1}" for i in range(self.q.shape[1])]
        return xr.Dataset(
            {"q": (("time", "dof"), self.q, {"units": "m", "long_name": "displacement"}),
             "qd": (("time", "dof"), self.qd, {"units": "m/s", "long_name": "velocity"}),
             "mode": (("time", "contact"), np.asarray(self.modes),
                      {"long_name": "contact mode (0 stick, +1/-1 slip direction)"}),
             "amplitude": (("dof",), self.amplitude, {"units": "m"}),
             "multiplier_real": (("multiplier",), self.multipliers.real, {"units": "1"}),
             "multiplier_imag": (("multiplier",), self.multipliers.imag, {"units": "1"}),
             "y0": (("state",), self.y0, {"units": "m, m/s"})},
            coords={"time": ("time", self.t, {"units": "s"}), "dof": dofs},
            attrs={"frequency_hz": self.frequency_hz, "period_s": float(self.period),
                   "period_multiple": int(self.period_multiple), "stable": int(self.stable),
                   "success": int(self.success), "residual": float(self.residual),
                   "message": self.message, "method": self.method,
                   "n_events": int(self.n_events)})

    def summary(self) -> dict:
        """JSON-able key numbers (the ``periodic_orbit`` results contract)."""
        return {
            "amplitude_m": [float(a) for a in self.amplitude],
            "period_multiple": int(self.period_multiple),
            "floquet_multipliers_abs": [float(a) for a in self.floquet_multipliers_abs],
            "stable": bool(self.stable),
            "converged": bool(self.success),
            "residual": float(self.residual),
        }

    def plot(self, dofs=None, axes=None):
        """Phase portrait q' vs q of the orbit; returns the axes."""
        import matplotlib.pyplot as plt

        if axes is None:
            _, axes = plt.subplots(figsize=(5, 4), layout="constrained")
        for i in (range(self.q.shape[1]) if dofs is None else dofs):
            axes.plot(self.q[:, i], self.qd[:, i], lw=1, label=self.dof_names[i]
                      if self.dof_names else f"q{i + 1}")
        axes.set_xlabel("q [m]")
        axes.set_ylabel("q' [m/s]")
        axes.legend(fontsize="small")
        return axes


def _neutral_functionals(system, M, y0, modes, invariance_tol=1e-5, details=False):
    """Invariants ``l`` (rows, unit norm) of the linearised return map M from contacts stuck
    at every sample of ``modes``; see :class:`NeutralStability` for the rule."""
    M = np.asarray(M, float)
    N = M.shape[0]
    n = N // 2
    modes = np.asarray(modes)
    q0 = np.asarray(y0[:n], float)
    always = [i for i in range(modes.shape[1]) if modes.shape[0] and np.all(modes[:, i] == STICK)]
    rows, kept, res = [], [], []
    if always and np.all(np.isfinite(M)):
        WT = np.asarray(system.tangent_jacobian(q0), float)
        cons = np.flatnonzero(np.asarray(system.normal_constrained, bool))
        WN = (np.asarray(system.normal_jacobian(q0), float)[:, cons] if cons.size
              else np.zeros((n, 0)))
        for i in always:
            B = np.zeros((1 + cons.size, N))
            B[0, :n] = WT[:, i]
            B[1:, :n] = WN.T
            B /= np.maximum(np.linalg.norm(B, axis=1), 1e-300)[:, None]
            _, _, Vt = np.linalg.svd((M - np.eye(N)).T @ B.T)
            ell = Vt[-1] @ B
            r = float(np.linalg.norm(ell @ (M - np.eye(N))) / max(np.linalg.norm(ell), 1e-300))
            res.append(r)
            if r <= invariance_tol:
                rows.append(ell / np.linalg.norm(ell))
                kept.append(i)
    L = np.array(rows) if rows else np.zeros((0, N))
    return (L, kept, res) if details else L


@dataclass(frozen=True)
class NeutralStability:
    """Stability of an orbit with the neutral directions of always-stuck contacts excluded.

    A contact that sticks during the whole orbit never releases its tangential preload: the
    orbits with a slightly different locked-in preload (a different place where the contact
    sticks) are periodic too, so the orbit belongs to a one-parameter family per such contact
    and has a multiplier exactly 1 (neutral; paper 000's damper at 58 Hz, 8 N: K1 sticks all
    the time). Time integration stays on whichever member it reached: such an orbit is
    stable in the practical sense when all *other* multipliers lie inside the unit circle.

    The rule (:func:`neutral_stability`): for each contact stuck at every sample of the
    orbit, the invariant of the linearised return map is sought in the span of its
    tangential displacement functional ``[W_T,i(q0), 0]`` and the normal ones ``[W_N,j(q0),
    0]`` of the constrained contacts (the return map begins with the projection onto closed
    gaps): the unit row ``l`` minimising ``|l (M - I)|`` (smallest singular value). If that
    residual is at most ``invariance_tol``, ``l`` is the known neutral direction: the
    multipliers of M restricted to ``ker l`` (which M maps into itself) are the others. A
    contact that slips somewhere, or a residual above the tolerance, excludes nothing.

    Attributes
    ----------
    stable : bool
        Every multiplier but the excluded neutral ones has ``|mu| < 1 - stability_margin``.
    stable_strict : bool
        All multipliers inside (False whenever a neutral multiplier exists).
    max_multiplier : float
        Largest |mu| after the exclusion.
    multipliers : ndarray of complex, shape (2 n_dof - n_neutral,)
        Multipliers of the restricted map, by decreasing modulus.
    neutral_contacts : tuple of int
        Contacts whose neutral direction was excluded.
    invariance_residuals : tuple of float
        ``|l (M - I)|`` of each always-stuck contact (excluded when <= the tolerance).
    """

    stable: bool
    stable_strict: bool
    max_multiplier: float
    multipliers: np.ndarray
    neutral_contacts: tuple
    invariance_residuals: tuple

    def summary(self) -> dict:
        return {"stable": bool(self.stable), "stable_strict": bool(self.stable_strict),
                "max_multiplier_excluding_neutral": float(self.max_multiplier),
                "neutral_contacts": [int(i) for i in self.neutral_contacts],
                "invariance_residuals": [float(r) for r in self.invariance_residuals]}


def neutral_stability(system: ConstrainedSystem, orbit: PeriodicOrbit, *,
                      invariance_tol: float = 1e-5,
                      stability_margin: float = 1e-6) -> NeutralStability:
    """Practical stability of a periodic orbit: neutral multipliers of always-stuck contacts
    excluded by their invariant (see :class:`NeutralStability` for the rule).

    Parameters
    ----------
    system : ConstrainedSystem
        The system the orbit belongs to (its ``W_T``, ``W_N`` at the section state are used).
    orbit : PeriodicOrbit
        A converged orbit (its monodromy and sampled contact modes).
    invariance_tol : float
        Largest ``|l (M - I)|`` (unit l) accepted as an exact invariant. The monodromy of
        DOP853 phases carries errors of about 1e-7 (Magnus steps and central differences; the
        blade damper's neutral multiplier comes out as 1.00000003), exact phases round-off;
        a contact that is not neutral gives O(0.1-1).
    stability_margin : float
        ``stable`` when the remaining ``max |mu| < 1 - stability_margin``.

    Returns
    -------
    NeutralStability
    """
    M = np.asarray(orbit.monodromy, float)
    N = M.shape[0]
    modes = np.asarray(orbit.modes)
    mu_all = np.linalg.eigvals(M)
    strict = bool(np.abs(mu_all).max() < 1 - stability_margin) if N else True
    L, kept, res = _neutral_functionals(system, M, orbit.y0, modes, invariance_tol,
                                        details=True)
    if L.shape[0]:
        _, sv, Vt = np.linalg.svd(L)
        rank = int(np.sum(sv > 1e-8 * sv[0]))
        Q = Vt[rank:].T  # orthonormal basis of ker L, mapped into itself by M
        mu = np.linalg.eigvals(Q.T @ M @ Q)
    else:
        mu = mu_all
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    mx = float(np.abs(mu).max()) if mu.size else 0.0
    return NeutralStability(stable=bool(mx < 1 - stability_margin), stable_strict=strict,
                            max_multiplier=mx, multipliers=mu, neutral_contacts=tuple(kept),
                            invariance_residuals=tuple(res))


def _scales(q, qd):
    sq = max(float(np.abs(q).max()) if q.size else 0.0, 1e-300)
    sv = max(float(np.abs(qd).max()) if qd.size else 0.0, 1e-300)
    return sq, sv


def _amplitudes(trace, n_dof):
    """Exact half peak-to-peak per DOF over the phases of a traced orbit.

    Each phase is sampled (17 points); the extreme samples are refined where the velocity
    changes sign beside them (Brent's method on q'_j to round-off) and compared with the
    phase ends."""
    lo = np.full(n_dof, np.inf)
    hi = np.full(n_dof, -np.inf)
    for rec in trace:
        ta, tb = rec.t_start, rec.t_end
        if tb <= ta:
            continue
        ts = np.linspace(ta, tb, 17)
        q, qd = rec.phase.outputs(ts)[:2]
        lo = np.minimum(lo, q.min(axis=0))
        hi = np.maximum(hi, q.max(axis=0))
        for j in range(n_dof):
            for k in (int(np.argmin(q[:, j])), int(np.argmax(q[:, j]))):
                for a, b in ((k - 1, k), (k, k + 1)):
                    if a < 0 or b >= ts.size or not qd[a, j] * qd[b, j] < 0:
                        continue

                    def vel(t, rec=rec, j=j):
                        return float(rec.phase.outputs(np.array([t]))[1][0, j])

                    tr = brentq(vel, ts[a], ts[b], xtol=4 * _EPS * max(abs(tb), tb - ta),
                                rtol=4 * _EPS)
                    v = float(rec.phase.outputs(np.array([tr]))[0][0, j])
                    lo[j], hi[j] = min(lo[j], v), max(hi[j], v)
    return 0.5 * (hi - lo)


def detect_period_multiple(system: ConstrainedSystem, period: float, y0, *, t0: float = 0.0,
                           periods: int = 40, max_multiple: int = 8, method: str = "auto",
                           rtol: float = 1e-10, atol: float = 1e-12) -> tuple[int, np.ndarray,
                                                                              float]:
    """Period multiple of the attractor reached from ``y0`` (return-map detection).

    Integrates ``periods`` excitation periods, samples the stroboscopic map, and returns the
    smallest n <= max_multiple whose return distance ``|y_k - y_{k-n}|`` (scaled, over the
    last ``max_multiple`` samples) is within 10 times the smallest one found.

    Returns
    -------
    n : int
    y_end : ndarray, shape (2 n_dof,)
        The final state (a starting guess for shooting).
    distance : float
        Scaled return distance of n (small when the transient has settled).
    """
    n, y_end, dist, _ = _return_map(system, period, y0, t0=t0, periods=periods,
                                    max_multiple=max_multiple, method=method, rtol=rtol,
                                    atol=atol)
    return n, y_end, dist


def _return_map(system, period, y0, *, t0=0.0, periods=40, max_multiple=8, method="auto",
                rtol=1e-10, atol=1e-12, samples_per_period=1):
    """:func:`detect_period_multiple` that also returns the run's ``EventResult``, sampled
    ``samples_per_period`` times per period (the stroboscopic samples among them)."""
    periods = max(int(periods), 2 * max_multiple + 1)
    spp = max(int(samples_per_period), 1)
    dense = t0 + period * (np.arange(periods * spp + 1) / spp)
    te = dense[::spp]
    fl = flow(system, (t0, te[-1]), y0, t_eval=dense, method=method, rtol=rtol, atol=atol,
              monodromy=False, keep_phases=False)
    res = fl.result
    n = system.n_dof
    # the samples at the stroboscopic times (event times are added to t: pick ours)
    idx = np.searchsorted(res.t, te, side="left")
    idx = np.minimum(idx, res.t.size - 1)
    Y = np.hstack([res.q[idx], res.qd[idx]])
    Y[-1] = fl.y_end
    sq, sv = _scales(res.q[idx[len(idx) // 2:]], res.qd[idx[len(idx) // 2:]])
    scale = np.concatenate([np.full(n, sq), np.full(n, sv)])
    d = []
    for m in range(1, max_multiple + 1):
        last = Y[-max_multiple:]
        prev = Y[-max_multiple - m:-m]
        d.append(float(np.max(np.abs(last - prev) / scale)))
    d = np.array(d)
    best = float(d.min())
    m = int(np.flatnonzero(d <= 10 * best + 1e-14)[0]) + 1
    return m, fl.y_end, float(d[m - 1]), res


#: largest scaled Newton step of :func:`_newton` (max |step_i| / scale_i, the scales being
#: the largest |q| and |q'| of the motion): one motion's size
_MAX_STEP = 1.0


def _newton(system, period, nmul, t0, y, tol, max_iter, kw):
    """Newton with backtracking on ``P^n(y) - y``.

    Returns (y, flow at y, scaled residual, iterations, message)."""
    n = int(system.n_dof)
    t1 = t0 + nmul * period
    unilateral = bool(np.asarray(system.unilateral_contacts(), dtype=bool).any())
    # piecewise-linear systems (a linear form, exact phases) keep the full Newton step: their
    # map is piecewise affine and any trial state is a cheap, exact flow
    capped = system.linear_form() is None
    # trials with the monodromy, so that an accepted trial is the next iterate as it stands:
    # with unilateral contacts (whose refusal of grazing and Zeno orbits rejects a trial
    # point) and for piecewise-linear systems (exact phases: the monodromy is one matrix
    # exponential per phase, cheaper than integrating the accepted point again)
    trial_monodromy = unilateral or not capped

    def evaluate(yy, monodromy=True):
        if monodromy:
            fl = flow(system, (t0, t1), yy, **kw)
        else:  # a line-search trial: the flow only (a compiled event loop may take it)
            fl = flow(system, (t0, t1), yy, **{**kw, "monodromy": False,
                                                "keep_phases": False})
        q, qd = fl.result.q, fl.result.qd
        sq, sv = _scales(np.vstack([q, yy[None, :n]]), np.vstack([qd, yy[None, n:]]))
        scale = np.concatenate([np.full(n, sq), np.full(n, sv)])
        r = fl.y_end - yy
        return fl, r, float(np.max(np.abs(r) / scale)), scale

    fl, r, norm, scale = evaluate(y)
    it = 0
    message = "converged"
    while norm > tol and it < max_iter:
        it += 1
        A = fl.monodromy - np.eye(2 * n)
        # a contact stuck during the whole orbit makes the fixed point non-isolated (a
        # family of orbits with multiplier 1, see NeutralStability); the step then keeps
        # its invariant l . y (the locked-in tangential preload, which the dynamics keep
        # too), instead of jumping along the family by (residual / |mu - 1|)
        L = _neutral_functionals(system, fl.monodromy, y, fl.result.modes)
        if L.shape[0]:
            step = -np.linalg.lstsq(np.vstack([A, L]), np.concatenate([r, np.zeros(len(L))]),
                                    rcond=1e-12)[0]
        else:
            try:
                step = -np.linalg.solve(A, r)
            except np.linalg.LinAlgError:
                step = -np.linalg.lstsq(A, r, rcond=1e-14)[0]
        # a step longer than the motion itself (scaled) leaves the region where the map's
        # linearisation says anything (a multiplier near 1 not caught as neutral): its
        # trial states are far off any motion (a damper rotated by thousands of radians,
        # through singular contact geometry), so the line search starts at that length
        size = float(np.max(np.abs(step) / scale))
        lam = min(1.0, _MAX_STEP / size) if (capped and size > 0) else 1.0
        best = None
        for _ in range(10):
            try:
                trial = evaluate(y + lam * step, monodromy=trial_monodromy)
            except (ConvergenceError, ZeroDivisionError):
                # (a compiled kernel's division by zero at a degenerate trial state)
                trial = None
            except ModelError:
                # a trial state inside a unilateral stop (penetration): shorten the step
                if not unilateral:
                    raise
                trial = None
            if trial is not None and (best is None or trial[2] < best[0][2]):
                best = (trial, lam)
            if trial is not None and trial[2] < (1 - 1e-4 * lam) * norm:
                break
            lam *= 0.5
        if best is None:
            message = "the solver failed at every Newton trial point"
            break
        lam = best[1]
        y = y + lam * step
        if trial_monodromy:
            fl, r, norm, scale = best[0]
            continue
        # the flow with its monodromy at the accepted point only (the trials' flows were
        # taken without: most of an iteration's cost when the first trial is refused)
        try:
            fl, r, norm, scale = evaluate(y)
        except ConvergenceError as exc:
            message = f"no monodromy matrix at the accepted Newton point: {exc}"
            y = y - lam * step  # (y, fl, r) stay those of the last evaluated point
            break
    if norm > tol and message == "converged":
        message = (f"Newton did not converge in {max_iter} iterations (residual {norm:.3g} > "
                   f"tol {tol:g}) for period multiple {nmul}; try another y0, more "
                   "transient_periods or another period_multiple")
    return y, fl, norm, it, message


def shoot(
system: ConstrainedSystem, period: float, y0=None, *, period_multiple: int | None = None,
          t0: float = 0.0, transient_periods: int = 5, max_multiple: int = 8,
          detect_periods: int = 40,
          tol: float = 1e-11, max_iter: int = 30, method: str = "auto", rtol: float = 1e-10,
          atol: float = 1e-12, stability_margin: float = 1e-6, samples_per_period: int = 64,
          throw: bool = False) -> PeriodicOrbit:
    """Periodic orbit of a forced stick-slip system by Newton on the stroboscopic map.

    Parameters
    ----------
    system : ConstrainedSystem
        Forced with period ``period`` (e.g. a :class:`CoulombSystem` with harmonic loads).
    period : float
        Excitation period T [s] (> 0).
    y0 : array_like, shape (2 n_dof,), optional
        Starting state at ``t0`` (default rest at q = 0). It is first integrated over
        ``transient_periods`` periods unless ``transient_periods = 0``.
    period_multiple : int, optional
        n of the period-n orbit sought. By default a period-1 orbit is sought first from the
        transient; if Newton fails or the orbit is unstable, ``detect_periods`` more periods
        are integrated and n is read from their return map (:func:`detect_period_multiple`).
    t0 : float
        Time of the Poincare section [s].
    transient_periods : int
        Periods integrated before Newton (a starting guess near the attractor).
    max_multiple : int
        Largest n tried by the detection.
    detect_periods : int
        Periods integrated for the detection (at least ``2 max_multiple + 1``).
    tol : float
        Newton tolerance on the scaled residual ``|P(y0) - y0|`` (positions scaled by the
        orbit's largest |q|, velocities by its largest |q'|); with DOP853 phases at least
        ``100 rtol`` (the return map's own error).
    max_iter : int
        Newton iterations (each with a backtracking line search).
    method, rtol, atol
        Event-driven solver settings (exact phases for a LinearForm; DOP853 otherwise).
    stability_margin : float
        ``stable`` when ``max |mu| < 1 - stability_margin``.
    samples_per_period : int
        Samples of the returned orbit per excitation period.
    throw : bool
        Raise :class:`ConvergenceError` when Newton fails (default: ``success=False``).

    Returns
    -------
    PeriodicOrbit

    Examples
    --------
    den Hartog's oscillator ``x'' + x + 0.3 sgn(x') = cos(0.8 t)`` (non-stop motion):

    >>> import numpy as np
    >>> from fricdamp.structure.system import MechanicalSystem, HarmonicLoad
    >>> from fricdamp.solvers.event_system import CoulombSystem
    >>> s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], 0.8),))
    >>> orbit = shoot(CoulombSystem(s, [1.0], 0.3, 1.0), 2 * np.pi / 0.8)
    >>> V, U = 1 / (1 - 0.8**2), np.tan(np.pi / 1.6) / 0.8
    >>> bool(abs(orbit.amplitude[0] - np.sqrt(V**2 - 0.09 * U**2)) < 1e-9), orbit.stable
    (True, True)
    """
    wall = _time.perf_counter()
    if not isinstance(system, ConstrainedSystem):
        raise ModelError(f"system must be a ConstrainedSystem, got {type(system).__name__}")
    if not (np.isfinite(period) and period > 0):
        raise ModelError(f"period must be > 0 s, got {period!r}")
    n = int(system.n_dof)
    y = np.zeros(2 * n) if y0 is None else as_finite_array("y0", y0).copy()
    if y.shape != (2 * n,):
        raise ModelError(f"y0 must hold [q, q'] with {2 * n} entries, got {y.shape}")
    if period_multiple is not None and int(period_multiple) < 1:
        raise ModelError(f"period_multiple must be >= 1, got {period_multiple!r}")
    lf = system.linear_form()
    if lf is not None and lf.frequencies.size:
        cycles = lf.frequencies * period / (2 * np.pi)
        if np.any(np.abs(cycles - np.round(cycles)) > 1e-9 * np.maximum(cycles, 1)) or np.any(
                np.round(cycles) < 1):
            raise ModelError(
                f"period = {period!r} s is not a period of the excitation (load frequencies "
                f"{np.round(lf.frequencies, 12).tolist()} rad/s make {cycles.tolist()} cycles "
                "in it): give the excitation's period; a subharmonic orbit is found with "
                "period_multiple")
    kw = dict(method=method, rtol=rtol, atol=atol)
    if method == "dop853" or lf is None:
        # the return map carries the DOP853 error: a residual below it cannot be reached
        tol = max(tol, 100 * rtol)
    if transient_periods > 0:
        y = flow(system, (t0, t0 + transient_periods * period), y, monodromy=False,
                 keep_phases=False, **kw).y_end

    def stable_of(fl):
        mu = np.abs(np.linalg.eigvals(fl.monodromy))
        return bool(mu.max() < 1 - stability_margin) if mu.size else True

    if period_multiple is not None:
        nmul = int(period_multiple)
        y, fl, norm, it, message = _newton(system, period, nmul, t0, y, tol, max_iter, kw)
    else:
        # a stable period-1 orbit near the transient is the attractor it approaches;
        # otherwise the return map of a longer transient says which n to look for
        y1, fl, norm, it, message = _newton(system, period, 1, t0, y, tol, max_iter, kw)
        nmul = 1
        if norm <= tol and stable_of(fl):
            y = y1
        else:
            nmul, y_d, _ = detect_period_multiple(
                system, period, y, t0=t0, periods=max(detect_periods, 2 * max_multiple + 1),
                max_multiple=max_multiple, **kw)
            if nmul == 1 and norm <= tol:
                y = y1  # the unstable period-1 orbit is what the return map shows
            else:
                y, fl, norm, it2, message = _newton(system, period, nmul, t0, y_d, tol,
                                                    max_iter, kw)
                it += it2
    success = norm <= tol
    if not success and throw:
        raise ConvergenceError(message)
    t1 = t0 + nmul * period
    # final orbit: samples and exact extrema
    te = np.linspace(t0, t1, nmul * int(samples_per_period) + 1)
    fin = flow(system, (t0, t1), y, t_eval=te, monodromy=False, **kw)
    res = fin.result
    amp = _amplitudes(fin.trace, n)
    mult = np.linalg.eigvals(fl.monodromy)
    mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    stable = bool(np.abs(mult).max() < 1 - stability_margin) if mult.size else True
    return PeriodicOrbit(
        period=float(period), period_multiple=nmul, t0=float(t0), y0=y, amplitude=amp,
        multipliers=mult, monodromy=fl.monodromy, stable=stable, success=bool(success),
        residual=float(norm), iterations=it, message=message, t=res.t, q=res.q, qd=res.qd,
        modes=res.modes, n_events=int(res.n_events), n_simultaneous=int(fl.n_simultaneous),
        method=res.method, runtime_s=_time.perf_counter() - wall,
        dof_names=tuple(res.dof_names))


# =====================================================================================
# continuation in frequency
# =====================================================================================
@dataclass(frozen=True, repr=False)
class OrbitBranch(ResultMixin):
    """Periodic orbits along the excitation frequency.

    Attributes
    ----------
    omega : ndarray, shape (n_points,)
        Excitation circular frequencies [rad/s] (kept for compatibility: ``frequency_hz``
        [Hz], ``omega_rad_s``).
    orbits : tuple of PeriodicOrbit
    amplitude : ndarray, shape (n_points, n_dof)
        [m]; NaN where shooting failed.
    stable : ndarray of bool, shape (n_points,)
    success : ndarray of bool, shape (n_points,)
        Per point (``verdict`` judges the branch).
    """

    omega: np.ndarray
    orbits: tuple
    amplitude: np.ndarray
    stable: np.ndarray
    success: np.ndarray

    @property
    def frequency_hz(self) -> np.ndarray:
        """Excitation frequencies [Hz], shape (n_points,)."""
        return self.omega / (2 * np.pi)

    @property
    def omega_rad_s(self) -> np.ndarray:
        """Excitation circular frequencies [rad/s] (the same as ``omega``)."""
        return self.omega

    def _judge(self):
        """``failed`` when no point converged, ``unreliable`` when some did not (their
        amplitudes are NaN)."""
        from fricdamp.results import status_verdict

        ok = np.asarray(self.success, bool)
        bad = int(np.sum(~ok))
        reasons = () if bad == 0 else (
            f"shooting failed at {bad} of {ok.size} frequencies: refine the frequency grid "
            "or raise max_refine",)
        return status_verdict(bool(np.any(ok)), "shooting failed at every frequency",
                              {"failed_points": bad}, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` over the frequency points: amplitude per DOF, stability and
        success flags."""
        import xarray as xr

        names = (self.orbits[0].dof_names if self.orbits and self.orbits[0].dof_names
                 else [f"q{i + 1}" for i in range(self.amplitude.shape[1])])
        return xr.Dataset(
            {"amplitude": (("point", "dof"), self.amplitude, {"units": "m"}),
             "stable": (("point",), np.asarray(self.stable, bool)),
             "success": (("point",), np.asarray(self.success, bool))},
            coords={"frequency": ("point", self.frequency_hz, {"units": "Hz"}),
                    "omega": ("point", self.omega, {"units": "rad/s"}), "dof": list(names)})

    def plot(self, dof: int = 0, ax=None):
        """Amplitude of ``dof`` [m] vs excitation frequency [Hz], unstable orbits dashed
        (open markers); returns the axes."""
        import matplotlib.pyplot as plt

        from fricdamp.plot import stability_line

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
        stability_line(ax, self.frequency_hz, self.amplitude[:, dof],
                       np.asarray(self.stable, bool), marker="o", ms=3)
        ax.set_xlabel("excitation frequency [Hz]")
        name = (self.orbits[0].dof_names[dof] if self.orbits and self.orbits[0].dof_names
                else f"q{dof + 1}")
        ax.set_ylabel(f"amplitude of {name} [m]")
        ax.grid(alpha=0.3)
        return ax


def continue_orbits(build: Callable[[float], ConstrainedSystem], omegas: Sequence[float], *,
                    y0=None, period_multiple: int = 1, max_refine: int = 4,
                    **shoot_kwargs) -> OrbitBranch:
    """Follow a period-n orbit along the excitation frequency (sequential continuation).

    Each point starts Newton from a secant prediction through the two previous solutions
    on the section ``t0`` (the first from a transient of ``y0``). When Newton fails, the
    step is halved (up to ``max_refine`` times) and the intermediate points are solved
    first; points that still fail are returned with ``success=False``. Friction orbits
    under harmonic forcing have no folds in frequency here (den Hartog); a branch with
    folds needs arclength continuation (harmonic balance does that).

    Parameters
    ----------
    build : callable omega -> ConstrainedSystem
        The system forced at circular frequency omega [rad/s].
    omegas : sequence of float
        Frequencies [rad/s] (monotonic).
    y0 : array_like, optional
        Starting state of the first point's transient.
    period_multiple : int
        n of the followed orbit.
    shoot_kwargs
        Passed to :func:`shoot`.

    Returns
    -------
    OrbitBranch
    """
    om = as_finite_array("omegas", omegas).ravel()
    if om.size == 0 or np.any(om <= 0):
        raise ModelError("omegas must be a non-empty sequence of frequencies > 0 rad/s")
    done: list[tuple[float, PeriodicOrbit]] = []

    def solve(w, guess, first):
        kw = dict(shoot_kwargs)
        if not first:
            kw["transient_periods"] = 0
        return shoot(build(float(w)), 2 * np.pi / w, guess, period_multiple=period_multiple,
                     **kw)

    def predict(w):
        ok = [(ww, o) for ww, o in done if o.success]
        if not ok:
            return y0, True
        if len(ok) == 1:
            return ok[-1][1].y0, False
        (wa, oa), (wb, ob) = ok[-2], ok[-1]
        return ob.y0 + (ob.y0 - oa.y0) * (w - wb) / (wb - wa), False

    def attempt(w, level):
        guess, first = predict(w)
        orb = solve(w, guess, first)
        if not orb.success and not first and level < max_refine and done:
            w_prev = done[-1][0]
            attempt(0.5 * (w_prev + w), level + 1)
            guess, _ = predict(w)
            orb = solve(w, guess, False)
        done.append((float(w), orb))
        return orb

    out = []
    for w in om:
        out.append(attempt(w, 0))
    n = out[0].amplitude.size
    amp = np.array([o.amplitude if o.success else np.full(n, np.nan) for o in out])
    return OrbitBranch(om.copy(), tuple(out), amp, np.array([o.stable for o in out]),
                       np.array([o.success for o in out]))


__all__ = ["Flow", "NeutralStability", "OrbitBranch", "PeriodicOrbit", "continue_orbits",
           "detect_period_multiple", "neutral_stability",
           "flow", "shoot"]
