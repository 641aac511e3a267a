"""Exact event-driven stick-slip integration ("patching", paper 000 section 2.4-2.5).

The motion is split into smooth phases, in each of which every contact either sticks or
slips in a known direction. Within a phase the equations of motion with Lagrange multipliers
(000 (37)-(40), :mod:`fricdamp.solvers.event_switch`) are integrated exactly for linear
systems (:class:`~fricdamp.solvers.event_system.CoulombSystem`: modal solution or matrix
exponential, :mod:`fricdamp.solvers.event_exact`) or by DOP853 with dense output for a general
:class:`~fricdamp.solvers.event_system.ConstrainedSystem` (:mod:`fricdamp.solvers.event_phase`).
The phase ends at the first event (000 (45)-(46)):

* a slipping contact's relative velocity reaches zero (000 (41));
* a sticking contact's friction saturation ``mu_static |lambda_N| - |lambda_T|`` reaches zero
  (000 (43));
* a constrained normal force changes sign (reported: bilateral contacts stay closed);
* for unilateral contacts (:meth:`~fricdamp.solvers.event_system.ConstrainedSystem.
  unilateral_contacts`): a closed contact's normal force reaches zero (lift-off: the contact
  opens), an open contact's gap reaches zero (an impact, :mod:`fricdamp.solvers.event_impact`:
  Newton's law with restitution, frictionless impulses; impacts slower than the Zeno velocity
  are plastic and close the contact).

The event is located by Brent's method to round-off; the right end of the final bracket
(where the event function is already non-positive) starts the next phase. A function that
dips below zero and back between two samples (grazing: a friction reserve touching the limit,
a slip velocity nearly stopping) is found from its derivative in exact phases and, in DOP853
phases, by a search of the dense output wherever the samples show a small local minimum
(:func:`~fricdamp.solvers.event_phase.dip_windows`). Events of several
contacts within round-off of each other are one event. The new configuration of all contacts
with zero slip velocity is decided together by the friction complementarity problem
(Lemke's method, :func:`~fricdamp.solvers.event_switch.solve_friction_lcp`), with a
breakaway cascade for ``mu_static > mu_sliding`` (:func:`~fricdamp.solvers.event_switch.
decide_modes`). Stick is kept whenever it is consistent; when several configurations with
the most stuck contacts are consistent (``mu_static > mu_sliding``, e.g. two symmetric
contacts of which either may break away) a warning is logged and the switch is listed in
``EventResult.meta["ambiguous_switches"]``. In DOP853 phases, roots closer than their
integration uncertainty are one event (:func:`~fricdamp.solvers.event_phase.first_event`).
Before deciding after a DOP853 phase, the velocity is projected (M-orthogonally) onto zero
slip velocity of every contact the decision concerns (the stuck ones, the one that just
reached zero, those at round-off from it); at the start of every phase it is projected onto
the stuck constraints (exact phases hold those to round-off anyway).
A DOP853 phase lets a stuck contact's slip velocity drift by its integration error; removing
that drift only after the decision would move the slip velocity of a contact that has just
been told to slip off zero, possibly against its slip direction, and the next phase would end
at once (endlessly). The kinetic-energy change of the projections (integration error and
round-off) is reported in ``EventResult.projection_energy``. Frictionless contacts
(``mu_static = mu_sliding = 0``) carry no friction events.

Energy terms are integrated by 8-point Gauss-Legendre quadrature over sub-intervals of a
quarter of the fastest period (exact phases) or over the DOP853 steps, so the energy balance
``input = friction + viscous + change of kinetic + potential`` checks the solution itself.
"""

from __future__ import annotations

import logging
import time as _time
from dataclasses import dataclass, field

import numpy as np

from fricdamp.errors import ConvergenceError, ModelError, as_finite_array
from fricdamp.results import ResultMixin
from fricdamp.solvers.event_exact import ExactPhase, LinearConfig
from fricdamp.solvers.event_impact import Impact, close_gaps, impulse
from fricdamp.solvers.event_phase import (
    EV_GAP,
    EV_NORMAL,
    EV_SLIP,
    EV_STICK_NEG,
    EV_STICK_POS,
    NumericalPhase,
)
from fricdamp.solvers.event_switch import (
    MODE_NAMES,
    OPEN,
    SLIP_NEG,
    SLIP_POS,
    STICK,
    Evaluator,
    LinearDecider,
)
from fricdamp.solvers.event_system import ConstrainedSystem, CoulombSystem, LinearForm

log = logging.getLogger(__name__)

_EPS = np.finfo(float).eps
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
ENERGY_KEYS = ("input_work", "friction_dissipation", "viscous_dissipation", "kinetic",
               "potential", "impact_loss")


@dataclass(frozen=True)
class SwitchEvent:
    """One mode change of one contact.

    Attributes
    ----------
    time : float
        Event time [s].
    contact : int
        Contact index.
    from_mode, to_mode : str
        ``"stick"``, ``"slip+"`` or ``"slip-"`` (kind ``"friction"``); ``"compression"`` or
        ``"tension"`` (kind ``"normal"``: sign change of a bilateral normal force); the old
        mode and ``"open"`` (kind ``"lift-off"``); ``"open"`` and ``"closed"`` (contact
        stays closed) or ``"open"`` (it bounces) (kind ``"impact"``).
    kind : str
        ``"friction"``, ``"normal"``, ``"lift-off"`` or ``"impact"``.
    """

    time: float
    contact: int
    from_mode: str
    to_mode: str
    kind: str = "friction"


@dataclass(frozen=True)
class PhaseRecord:
    """One smooth phase of a run (kept when the run is traced, e.g. by shooting).

    ``y_pre`` is the state (q, q') handed to the phase before the projection onto its
    constraints, ``y_end`` the state at ``t_end`` (left limit); ``hit`` the event that ended
    the phase (None at the end of the run); ``modes`` and ``sigma`` its configuration.
    """

    phase: object
    t_start: float
    t_end: float
    hit: object
    modes: np.ndarray
    sigma: np.ndarray
    y_pre: tuple
    y_end: tuple


@dataclass
class ImpactMap:
    """The jump ``y+ = g(y-)`` of one impact of a traced run, with its combinatorics fixed
    (shooting differentiates it, see :func:`impact_map`).

    ``hit``: contacts whose gap closed; ``unilateral`` / ``bilateral``: the rows of the
    impulsive problem (complementarity / equality); ``restitution``: the coefficients used
    (0 for plastic); ``zeno``: an impact taken as plastic, or a contact held closed, because
    it was slower than the Zeno velocity (an accumulation of impacts cut short);
    ``projection_modes``: the configuration whose constraints the velocities were projected
    onto after the impact (None: no projection).
    """

    t: float
    hit: np.ndarray
    unilateral: np.ndarray
    bilateral: np.ndarray
    restitution: np.ndarray
    zeno: bool = False
    projection_modes: np.ndarray | None = None


def impact_map(ev: Evaluator, jump: ImpactMap, q, qd):
    """``(q+, q'+)`` of the impact ``jump`` from the state ``(q, q')`` just before it: the
    impact position (gaps of ``jump.hit`` closed), the impulse of the fixed active set and
    the velocity projection that followed (the same steps as the run took)."""
    q = close_gaps(ev, np.asarray(q, float), jump.hit)
    qd = impulse(ev, q, np.asarray(qd, float), jump.unilateral, jump.bilateral,
                 jump.restitution)[0]
    if jump.projection_modes is not None:
        q, qd, _ = ev.project(jump.t, q, qd, jump.projection_modes)
    return q, qd


@dataclass(frozen=True, repr=False)
class EventResult(ResultMixin):
    """Stick-slip time history from :func:`simulate_events`.

    Samples are the requested ``t_eval`` plus every phase start (event times); at an event
    time the values are those *after* the switch (right limits).

    Attributes
    ----------
    t : ndarray, shape (n_t,)
        Sample times [s], non-decreasing.
    q, qd : ndarray, shape (n_t, n_dof)
        Generalised coordinates [m] and velocities [m/s].
    lambda_N, lambda_T : ndarray, shape (n_t, n_contacts)
        Normal and tangential contact forces [N] (``lambda_N`` < 0: tension, reported).
    modes : ndarray of int8, shape (n_t, n_contacts)
        0 stick, +1 slip with positive, -1 with negative relative velocity, 3 open (a
        unilateral contact that has lifted off).
    events : tuple of SwitchEvent
        Every mode change, in time order.
    energy : dict of ndarray, each (n_t,)
        ``input_work``, ``friction_dissipation``, ``viscous_dissipation``, ``impact_loss``
        (cumulative from ``t[0]``), ``kinetic`` and ``potential`` [J]. NaN where the system
        has no energy hook.
    impacts : tuple of Impact
        Every impact of a unilateral contact (:class:`~fricdamp.solvers.event_impact.Impact`),
        in time order.
    success, status, message
        ``status`` 0 finished, 1 ``max_events`` reached, -1 failure (with ``throw=False``).
    n_events, n_phases, n_decisions, n_configurations, n_rhs, n_expm, n_singular : int
        Events located, smooth phases, switching decisions (complementarity problems),
        distinct configurations, DOP853 right-hand sides, matrix exponentials (exact-phase
        fallback), configurations with redundant constraints.
    projection_energy : float
        Sum of |kinetic energy change| [J] of the velocity projections at stick entries.
    method : str
        ``"exact"`` or ``"dop853"``.
    verdict : fricdamp.verdict.Verdict
        ``failed`` when the run stopped early; else judged on the energy balance (exact up to
        round-off for exact phases) and on negative friction dissipation.
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    lambda_N: np.ndarray
    lambda_T: np.ndarray
    modes: np.ndarray
    events: tuple[SwitchEvent, ...]
    energy: dict[str, np.ndarray]
    success: bool = True
    status: int = 0
    message: str = "finished"
    n_events: int = 0
    n_phases: int = 0
    n_decisions: int = 0
    n_configurations: int = 0
    n_rhs: int = 0
    n_expm: int = 0
    n_singular: int = 0
    projection_energy: float = 0.0
    method: str = "exact"
    runtime_s: float = 0.0
    dof_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()
    meta: dict = field(default_factory=dict, compare=False)
    impacts: tuple = ()

    # ----------------------------------------------------------------- helpers
    def event_times(self, contact: int | None = None, to_mode: str | None = None) -> np.ndarray:
        """Times [s] of the mode changes, optionally of one contact and/or to one mode."""
        return np.array([e.time for e in self.events if e.kind == "friction"
                         and (contact is None or e.contact == contact)
                         and (to_mode is None or e.to_mode == to_mode)])

    def lift_off_times(self, contact: int | None = None) -> np.ndarray:
        """Times [s] at which closed unilateral contacts opened: their normal force reached
        zero, or an impact on another contact set them separating (not the bounces of an
        impacting contact, see :meth:`impact_times`)."""
        return np.array([e.time for e in self.events if e.kind == "lift-off"
                         and (contact is None or e.contact == contact)])

    def impact_times(self, contact: int | None = None) -> np.ndarray:
        """Times [s] of the impacts (of one contact)."""
        return np.array([im.time for im in self.impacts
                         if contact is None or contact in im.contacts])

    @property
    def energy_residual(self) -> np.ndarray:
        """``input - friction - viscous - impact loss - (dT + dV)`` [J], shape (n_t,)."""
        e = self.energy
        mech = e["kinetic"] + e["potential"]
        return (e["input_work"] - e["friction_dissipation"] - e["viscous_dissipation"]
                - e.get("impact_loss", 0.0) - (mech - mech[0]))

    @property
    def energy_balance_error(self) -> float:
        """Largest |energy residual| relative to the largest energy term of the run."""
        e = self.energy
        scale = max(float(np.max(np.abs(e[k]))) for k in ENERGY_KEYS)
        if scale == 0:
            return 0.0
        return float(np.max(np.abs(self.energy_residual)) / scale)

    def _judge(self):
        from fricdamp.results import status_verdict

        est = {}
        ebe = self.energy_balance_error
        if np.isfinite(ebe):
            est["energy_balance_error"] = float(ebe)
            e = self.energy
            scale = max(float(np.max(np.abs(e[k]))) for k in ENERGY_KEYS)
            diss = e["friction_dissipation"] - e["friction_dissipation"][0]
            est["negative_dissipation"] = (max(0.0, -float(np.min(diss)) / scale)
                                           if scale > 0 else 0.0)
        failed = None if self.success else (
            f"the integration stopped at t = {float(self.t[-1]):.6g} s: {self.message}")
        return status_verdict(self.success, failed or "", est)

    # ----------------------------------------------------------------- export
    def to_xarray(self):
        """``xarray.Dataset`` with dims time, dof, contact and event."""
        import xarray as xr

        ds = xr.Dataset(
            {
                "q": (("time", "dof"), self.q, {"units": "m", "long_name": "displacement"}),
                "qd": (("time", "dof"), self.qd, {"units": "m/s", "long_name": "velocity"}),
                "lambda_N": (("time", "contact"), self.lambda_N,
                             {"units": "N", "long_name": "normal contact force"}),
                "lambda_T": (("time", "contact"), self.lambda_T,
                             {"units": "N", "long_name": "tangential contact force"}),
                "mode": (("time", "contact"), self.modes,
                         {"long_name": "contact mode (0 stick, +1/-1 slip direction)"}),
                "event_time": (("event",), np.array([e.time for e in self.events]),
                               {"units": "s"}),
                "event_contact": (("event",), np.array([e.contact for e in self.events],
                                                       dtype=int)),
                "event_from": (("event",), np.array([e.from_mode for e in self.events],
                                                    dtype=str)),
                "event_to": (("event",), np.array([e.to_mode for e in self.events], dtype=str)),
                "event_kind": (("event",), np.array([e.kind for e in self.events], dtype=str)),
            },
            coords={"time": ("time", self.t, {"units": "s"}), "dof": list(self.dof_names),
                    "contact": list(self.contact_names)},
            attrs={"method": self.method, "success": int(self.success), "status": self.status,
                   "message": self.message, "n_events": self.n_events,
                   "energy_balance_error": self.energy_balance_error},
        )
        for k in ENERGY_KEYS:
            ds[f"energy_{k}"] = (("time",), self.energy[k], {"units": "J"})
        return ds

    def plot(self, dofs=None, axes=None):
        """Displacements, friction forces and contact modes vs time; returns the axes."""
        import matplotlib.pyplot as plt

        if axes is None:
            _, axes = plt.subplots(3, 1, figsize=(7, 6), sharex=True)
        idx = range(self.q.shape[1]) if dofs is None else dofs
        for i in idx:
            axes[0].plot(self.t, self.q[:, i], lw=1, label=self.dof_names[i])
        axes[0].set_ylabel("q [m]")
        for j, name in enumerate(self.contact_names):
            axes[1].plot(self.t, self.lambda_T[:, j], lw=1, label=name)
            axes[2].step(self.t, self.modes[:, j], where="post", lw=1, label=name)
        axes[1].set_ylabel("friction force [N]")
        axes[2].set_ylabel("mode")
        axes[2].set_yticks([-1, 0, 1], ["slip-", "stick", "slip+"])
        axes[2].set_xlabel("time [s]")
        for ax in axes:
            ax.grid(alpha=0.3)
            ax.legend(loc="upper right", fontsize="small")
        return axes


# =====================================================================================
def _progress_default() -> bool:
    import os
    import sys

    return bool(sys.stderr.isatty()) and not os.environ.get("CI")


class _EventProgress:
    """tqdm bar of an event-driven run: the share of ``t_span`` done and the events so far.

    It wraps the run's per-phase record (called once per phase) and touches tqdm at most
    every ``interval`` seconds of wall time, so the event loop pays one clock read per phase;
    the bar shows up only after ``delay`` seconds (short runs print nothing). tqdm is
    imported only when the bar is asked for.
    """

    def __init__(self, run, t0: float, t1: float, *, interval: float = 0.2,
                 delay: float = 1.0):
        import sys

        from tqdm.auto import tqdm

        self.run, self.t0, self.span, self.interval = run, t0, t1 - t0, interval
        self.bar = tqdm(total=1000, desc="event-driven", leave=False, file=sys.stderr,
                        delay=delay, mininterval=interval,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| "
                                   "[{elapsed}<{remaining}{postfix}]")
        self.n_updates = 0
        self._next = _time.perf_counter() + interval
        record = run._record

        def _record(phase, t_stop, last):
            out = record(phase, t_stop, last)
            now = _time.perf_counter()
            if now >= self._next:
                self._next = now + self.interval
                self.update(t_stop)
            return out

        run._record = _record

    def update(self, t: float) -> None:
        self.n_updates += 1
        done = int(1000 * min(max((t - self.t0) / self.span, 0.0), 1.0))
        if done > self.bar.n:
            self.bar.update(done - self.bar.n)
        self.bar.set_postfix_str(f"{self.run.n_events} events, t = {t:.6g} s", refresh=False)

    def close(self) -> None:
        self.bar.close()


def _check_load_frequencies(system) -> None:
    """Every HarmonicLoad of the structure has its ``omega``: a time-domain run needs it
    (harmonic balance does not, so it is optional on the load)."""
    structure = getattr(system, "system", None)
    for i, ld in enumerate(getattr(structure, "loads", ()) or ()):
        if getattr(ld, "omega", 0.0) is None and hasattr(ld, "harmonic"):
            raise ModelError(
                f"system.loads[{i}] ({ld!r}) has no omega: give the excitation frequency in "
                f"rad/s (HarmonicLoad(amplitude, omega) or load.with_omega(omega)) for an "
                f"event-driven run")


def simulate_events(system: ConstrainedSystem, t_span, y0, *, t_eval=None,
                    method: str = "auto", rtol: float = 1e-10, atol: float = 1e-12,
                    max_events: int = 100_000, max_step: float = np.inf,
                    throw: bool = True, progress: bool | None = None,
                    zeno_velocity: float | None = None) -> EventResult:
    """Integrate a stick-slip system exactly from event to event.

    Parameters
    ----------
    system : ConstrainedSystem
        E.g. a :class:`CoulombSystem` (linear structure, fixed normal loads).
    t_span : (float, float)
        Start and end time [s].
    y0 : array_like, shape (2 n_dof,)
        Initial ``[q, q']`` [m, m/s]. A contact whose slip velocity is zero starts in the mode
        the switching decision gives (stick if the static friction can hold it). With DOP853
        phases, a slip velocity below ``rtol`` times its scale counts as zero (the state a
        previous run ended with in stick carries that much integration error); the velocities
        are then projected onto rest (counted in ``projection_energy``).
    t_eval : array_like, shape (n,), optional
        Sample times [s] inside ``t_span`` (sorted); default 1001 uniform samples. Event times
        are always added.
    method : {"auto", "exact", "dop853"}
        ``"exact"`` integrates each phase in closed form (systems with a
        :meth:`~ConstrainedSystem.linear_form`); ``"dop853"`` uses the Runge-Kutta method of
        order 8 with dense output; ``"auto"`` picks exact when possible.
    rtol, atol : float
        DOP853 tolerances (relative; absolute in the units of q and q'). Not used by exact
        phases, whose only error is round-off.
    max_events : int
        Stop after this many events (status 1).
    max_step : float
        Largest DOP853 step [s]; it is also bounded by ``pi / (4 w)`` with
        ``w = system.max_frequency()`` so that events of stuck phases are not stepped over.
    throw : bool
        Raise :class:`ConvergenceError` on failure or when ``max_events`` is reached (default);
        with False return the history so far with ``success=False``.
    progress : bool, optional
        Show a tqdm progress bar (share of ``t_span`` done, events so far) on long runs: it
        appears after 1 s and is refreshed at most every 0.2 s; default: only when stderr is
        a terminal and outside CI.
    zeno_velocity : float, optional
        Unilateral contacts only: an impact with a normal approach speed at or below this
        [m/s] is plastic (the contact closes), and a contact that an impulse would set
        separating at or below it is held closed; this ends an accumulation of impacts
        (Zeno behaviour, e.g. a bouncing ball coming to rest, a wedged damper rattling
        between two platforms) after finitely many events. Default, per contact,
        ``sqrt(2 a_N tol_gap)``: the speed of a bounce whose apex height stays below the gap
        tolerance ``tol_gap = rtol |W_N|^T |q| + atol`` (``a_N`` the normal relative
        acceleration without contact forces at the impact; ``sqrt(2 g atol)`` for a ball
        on a floor at y = 0). The time of rest of a ball is then found to
        ``2 zeno_velocity / (g (1 - e))``.

    Returns
    -------
    EventResult

    Raises
    ------
    ModelError
        Bad input (names the parameter).
    ConvergenceError
        No consistent configuration, chattering (Zeno) or too many events (``throw=True``).

    References
    ----------
    Pfeiffer & Hajek (1992), paper 000, equations (29)-(46); den Hartog (1931).

    Examples
    --------
    >>> import numpy as np
    >>> from fricdamp.structure.system import MechanicalSystem
    >>> s = MechanicalSystem(M=[[1.0]], K=[[1.0]])
    >>> cs = CoulombSystem(s, directions=[1.0], normal_load=0.1, mu_static=1.0)
    >>> res = simulate_events(cs, (0.0, 20.0), [1.0, 0.0])   # free decay: 0.2 per half cycle
    >>> np.round(res.q[res.t == res.event_times()[0], 0], 12)
    array([-0.8])
    """
    wall = _time.perf_counter()
    if not isinstance(system, ConstrainedSystem):
        raise ModelError(f"system must be a ConstrainedSystem (e.g. CoulombSystem), got "
                         f"{type(system).__name__}")
    system.check()
    _check_load_frequencies(system)
    span = as_finite_array("t_span", t_span)
    if span.shape != (2,) or not span[1] > span[0]:
        raise ModelError(f"t_span must be (t0, t1) with t1 > t0 [s], got {t_span!r}")
    t0, t1 = float(span[0]), float(span[1])
    n = int(system.n_dof)
    y = as_finite_array("y0", y0)
    if y.shape != (2 * n,):
        raise ModelError(f"y0 must hold [q, q'] with 2 n_dof = {2 * n} entries, got {y.shape}")
    if t_eval is None:
        t_eval = np.linspace(t0, t1, 1001)
    te = as_finite_array("t_eval", t_eval).ravel()
    if np.any(np.diff(te) < 0):
        raise ModelError("t_eval must be sorted in increasing order")
    if te.size and (te[0] < t0 - 1e-12 * abs(t1 - t0) or te[-1] > t1 + 1e-12 * abs(t1 - t0)):
        raise ModelError(f"t_eval must lie inside t_span [{t0}, {t1}] s")
    if method not in ("auto", "exact", "dop853"):
        raise ModelError(f"method must be 'auto', 'exact' or 'dop853', got {method!r}")
    for name, v in (("rtol", rtol), ("atol", atol)):
        if not (np.isfinite(v) and v > 0):
            raise ModelError(f"{name} must be > 0, got {v!r}")
    if int(max_events) < 0:
        raise ModelError(f"max_events must be >= 0, got {max_events!r}")
    if zeno_velocity is not None and not (np.isfinite(zeno_velocity) and zeno_velocity >= 0):
        raise ModelError(f"zeno_velocity must be >= 0 m/s, got {zeno_velocity!r}")
    uni = np.asarray(system.unilateral_contacts(), dtype=bool)
    if method == "exact" and uni.any():
        raise ModelError("method='exact' does not handle unilateral contacts (lift-off and "
                         "impacts); use method='dop853'")
    lf = system.linear_form() if method in ("auto", "exact") and not uni.any() else None
    if method == "exact" and lf is None:
        raise ModelError("method='exact' needs a system with a linear form (a CoulombSystem "
                         "with harmonic loads only); use method='dop853'")
    run = _Run(system, lf, t0, t1, te, rtol, atol, max_step, zeno_velocity=zeno_velocity)
    show = _progress_default() if progress is None else bool(progress)
    bar = _EventProgress(run, t0, t1) if show else None
    status, message = 0, "finished"
    try:
        run.start(y[:n], y[n:])
        status, message = run.loop(int(max_events))
    except ConvergenceError as exc:
        if throw:
            raise
        status, message = -1, str(exc)
    finally:
        if bar is not None:
            bar.close()
    if status == 1 and throw:
        raise ConvergenceError(message)
    res = run.result(status, message, _time.perf_counter() - wall)
    if np.any(res.lambda_N[:, np.asarray(system.normal_constrained, bool) & ~uni] < 0):
        log.warning("a constrained normal force became negative (tension): the contact would "
                    "separate, which this solver does not model")
    return res


class _Run:
    """State of one simulate_events call."""

    def __init__(self, system, lf: LinearForm | None, t0, t1, t_eval, rtol, atol, max_step,
                 zeno_velocity=None):
        self.system = system
        self.ev = Evaluator(system)
        #: unilateral contacts (lift-off and impacts): DOP853 phases only
        self.uni = self.ev.unilateral
        if self.uni.any():
            lf = None
        self.zeno_velocity = zeno_velocity
        self.impact_loss = 0.0
        self.impacts: list[Impact] = []
        self.lf = lf
        self.decider = self.ev if lf is None else LinearDecider(lf, self.ev.mu_s, self.ev.mu_d)
        self.t0, self.t1, self.t_eval = t0, t1, t_eval
        w = float(system.max_frequency())
        if w > 0:
            max_step = min(max_step, np.pi / (4 * w))
        self.rtol, self.atol, self.max_step = rtol, atol, max_step
        self.nc = self.ev.nc
        self.configs: dict[tuple, LinearConfig] = {}
        self.out: list[tuple] = []
        self.events: list[SwitchEvent] = []
        self.acc = np.zeros(3)  # input, viscous, friction accumulated at phase start
        self.n_events = self.n_phases = self.n_decisions = 0
        self.n_rhs = self.n_expm = 0
        self.proj_energy = 0.0
        #: optional list of PhaseRecord (shooting's variational equations need the phases)
        self.trace: list | None = None
        #: traced runs: the impact map of each unilateral event, by the index in ``trace``
        #: of the phase it ends (shooting's saltation matrices, see ``ImpactMap``)
        self.jumps: dict[int, ImpactMap] = {}
        #: integrate the work terms (shooting's return maps do without: NaN energies)
        self.with_energy = True
        #: phases taken by the system's compiled event loop (see ``_compiled_loop``)
        self.fast_phases = 0

    # ------------------------------------------------------------ start and decisions
    def start(self, q, qd):
        ev = self.ev
        self.t = self.t0
        self.sigma = np.ones(self.nc)
        self.q, self.qd = np.array(q, float), np.array(qd, float)
        gam, vs = self.decider.tangent_velocity(self.t, q, qd)
        # at rest within the phases' accuracy (a state that ended a numerical phase in stick
        # carries the integration error): put exactly at rest before deciding
        zero_tol = 1e3 * _EPS if self.lf is not None else max(1e3 * _EPS, self.rtol)
        opened = self._initially_open(q, qd) if self.uni.any() else np.zeros(self.nc, bool)
        cand = (np.abs(gam) <= zero_tol * vs) & ~ev.frictionless & ~opened
        modes = np.where(cand, STICK, np.where(gam < 0, SLIP_NEG, SLIP_POS))
        modes[ev.frictionless] = SLIP_POS
        modes[opened] = OPEN
        if cand.any() or opened.any():
            self._project(modes)
            q, qd = self.q, self.qd
        if ev.constrained.any():
            pt = ev.point(self.t, q, qd)
            for _ in range(3 + self.nc):
                _, lamN, _ = ev.solve(pt, modes, self.sigma)
                tens = ev.constrained & (modes != OPEN) & (lamN[:, 0] * self.sigma < 0)
                lift = tens & self.uni
                if lift.any():  # a unilateral contact in tension at the start: open
                    for c in np.flatnonzero(lift):
                        self.events.append(SwitchEvent(float(self.t), int(c),
                                                       MODE_NAMES[int(modes[c])], "open",
                                                       "lift-off"))
                    modes[lift] = OPEN
                    cand &= ~lift
                    continue
                flip = tens
                if not flip.any():
                    break
                self.sigma[flip] *= -1
        if cand.any():
            self.n_decisions += 1
            modes = self.decider.decide_at(self.t, q, qd, modes, cand,
                                           np.zeros(self.nc, dtype=int), self.sigma)
        self.modes = modes

    def _gap_tol(self, q):
        """Gap tolerance [m] per contact: the integration error of a position."""
        WN = np.asarray(self.system.normal_jacobian(q), float)
        return self.rtol * (np.abs(WN).T @ np.abs(q)) + float(np.max(self.atol))

    def _initially_open(self, q, qd):
        """Unilateral contacts open at the start: a positive gap, or a zero gap with a
        non-zero normal velocity (a separating contact, or one about to impact at once)."""
        gap = np.asarray(self.system.normal_gap(q), float)
        tol = self._gap_tol(q)
        WN = np.asarray(self.system.normal_jacobian(q), float)
        gN, vs = WN.T @ qd, np.abs(WN).T @ np.abs(qd)
        bad = self.uni & (gap < -tol)
        if bad.any():
            c = int(np.flatnonzero(bad)[0])
            raise ModelError(f"the initial state penetrates unilateral contact {c}: gap = "
                             f"{gap[c]:.6g} m < 0; start with gaps >= 0")
        return self.uni & ((gap > tol) | (np.abs(gN) > max(self.rtol, 1e3 * _EPS) * vs))

    def _phase(self):
        key = tuple(int(m) for m in self.modes)
        if self.lf is not None:
            cfg = self.configs.get(key)
            if cfg is None:
                cfg = LinearConfig(self.lf, self.modes, self.ev.mu_s, self.ev.mu_d)
                if len(self.configs) > 256:
                    self.configs.clear()
                self.configs[key] = cfg
            return ExactPhase(cfg, self.t, self.q, self.qd)
        self.configs.setdefault(key, None)
        return NumericalPhase(self.ev, self.modes, self.sigma, self.t, self.q, self.qd,
                              self.rtol, self.atol, self.max_step)

    # ------------------------------------------------------------ main loop
    def _project(self, modes):
        """Project the velocities onto the constraints of ``modes`` (see ``project``)."""
        self.q, self.qd, de = self.decider.project(self.t, self.q, self.qd, modes)
        self.proj_energy += de

    def _compiled_loop(self):
        """The system's compiled event loop (``compiled_kernels().event_loop(run,
        max_events) -> finished``), when it can take this run: DOP853 phases with the
        compiled kernels, contacts with friction (unilateral ones only if the kernels know
        open contacts and the Zeno velocity is the default), no trace (shooting needs the
        phases). It takes phases and switches until the end or a phase it leaves to this
        loop (anything it would not do exactly as this loop does), and hands over at the
        start of that phase."""
        if self.lf is not None or self.trace is not None or self.ev.frictionless.any():
            return None
        ck = self.ev._fused
        if ck is None or not getattr(ck, "compiled_loop", False):
            return None
        if self.uni.any() and not (getattr(ck, "open_contacts", False)
                                   and self.zeno_velocity is None):
            return None  # impacts in the kernel: with the Zeno velocity of the gap tolerance
        return getattr(ck, "event_loop", None)

    def loop(self, max_events):
        zeno = 0
        fast = self._compiled_loop()
        while True:
            if fast is not None:
                done = self.fast_phases
                if fast(self, max_events):
                    return 0, "finished"
                if self.fast_phases > done:
                    zeno = 0
            y_pre = (self.q, self.qd) if self.trace is not None else None
            self._project(self.modes)
            phase = self._phase()
            self.n_phases += 1
            with np.errstate(under="ignore"):
                hit = phase.advance(self.t1)
                t_stop = self.t1 if hit is None else hit.t
                q_stop, qd_stop = self._record(phase, t_stop, last=hit is None)
            if self.trace is not None:
                self.trace.append(PhaseRecord(phase, float(phase.t0), float(t_stop), hit,
                                              self.modes.copy(), self.sigma.copy(), y_pre,
                                              (q_stop, qd_stop)))
            self.n_rhs += getattr(phase, "n_rhs", 0)
            self.n_expm += getattr(phase, "n_expm", 0)
            if hit is None:
                return 0, "finished"
            if self.n_events >= max_events:
                return 1, (f"max_events = {max_events} reached at t = {t_stop:.10g} s; raise "
                           "max_events (or check for chattering)")
            self.n_events += 1
            zeno = zeno + 1 if t_stop <= phase.t0 else 0
            if zeno > 50:
                raise ConvergenceError(
                    f"chattering at t = {t_stop:.17g} s: 50 switches without time advancing "
                    "(Zeno behaviour or an inconsistent contact configuration)")
            self.t, self.q, self.qd = t_stop, q_stop, qd_stop
            self._switch(phase, hit)

    def _switch(self, phase, hit):
        nc = self.nc
        kinds, contacts = phase.kinds[hit.fired], phase.contacts[hit.fired]
        must = np.zeros(nc, dtype=int)
        fired_slip = np.zeros(nc, dtype=bool)
        lift = np.zeros(nc, dtype=bool)
        gap_hit = np.zeros(nc, dtype=bool)
        for k, c in zip(kinds, contacts, strict=True):
            if k == EV_NORMAL and self.uni[c]:
                lift[c] = True
            elif k == EV_GAP:
                gap_hit[c] = True
            elif k == EV_STICK_POS:
                must[c] = SLIP_NEG
            elif k == EV_STICK_NEG:
                must[c] = SLIP_POS
            elif k == EV_SLIP:
                fired_slip[c] = True
            elif k == EV_NORMAL:
                old = "compression" if self.sigma[c] > 0 else "tension"
                self.sigma[c] *= -1
                new = "compression" if self.sigma[c] > 0 else "tension"
                self.events.append(SwitchEvent(float(self.t), int(c), old, new, "normal"))
        if lift.any() or gap_hit.any():
            self._unilateral_switch(lift, gap_hit)
            is_open = self.modes == OPEN
            must[is_open] = 0
            fired_slip &= ~is_open
        gam, vs = self.decider.tangent_velocity(self.t, self.q, self.qd)
        vs = np.maximum(vs, phase.vel_scale)
        cand = ((self.modes == STICK) | fired_slip | (np.abs(gam) <= 1e3 * _EPS * vs))
        cand &= ~self.ev.frictionless & (self.modes != OPEN)
        # Every contact at zero slip velocity is put exactly there before deciding: a
        # numerical phase lets a stuck contact's velocity drift by its integration error, and
        # removing that drift afterwards (at the next phase's projection) would move the
        # velocities of the contacts that just reached zero off zero, possibly against the
        # direction they were given to slip in (the next phase would then end at once, again
        # and again). Exact phases hold stuck contacts at rest to round-off: nothing to do.
        if self.lf is None:
            self._project(np.where(cand | (must != 0), STICK, self.modes))
            jump = self.jumps.get(len(self.trace) - 1) if self.trace is not None else None
            if jump is not None:
                jump.projection_modes = np.where(cand | (must != 0), STICK, self.modes)
        cand &= must == 0
        self.n_decisions += 1
        new = self.decider.decide_at(self.t, self.q, self.qd, self.modes, cand, must, self.sigma)
        for c in np.flatnonzero(new != self.modes):
            self.events.append(SwitchEvent(float(self.t), int(c), MODE_NAMES[int(self.modes[c])],
                                           MODE_NAMES[int(new[c])]))
        self.modes = new

    def _unilateral_switch(self, lift, gap_hit):
        """Open the contacts in ``lift``; resolve the impact of those in ``gap_hit``."""
        for c in np.flatnonzero(lift & (self.modes != OPEN)):
            self.events.append(SwitchEvent(float(self.t), int(c), MODE_NAMES[int(self.modes[c])],
                                           "open", "lift-off"))
            self.modes[c] = OPEN
        hit = gap_hit & (self.modes == OPEN)
        if hit.any():
            self._impact(hit)

    def _impact(self, hit):
        """Impact of the open contacts ``hit`` whose gap reached zero (event_impact)."""
        ev, s = self.ev, self.system
        q = close_gaps(ev, self.q, hit)
        qd = self.qd
        pt = ev.point(self.t, q, qd)
        WN = pt.WN
        gm = WN.T @ qd
        vscale = np.abs(WN).T @ np.abs(qd)
        if self.zeno_velocity is None:
            # a bounce whose apex height v^2 / (2 a_N) stays below the gap tolerance is not
            # resolved (a_N: the normal relative acceleration without contact forces)
            a_free = np.abs(WN.T @ pt.mass_factor(pt.h) + pt.wbN)
            vz = np.sqrt(2.0 * a_free * self._gap_tol(q))
        else:
            vz = np.full(self.nc, float(self.zeno_velocity))
        vtol = 1e3 * _EPS * float(vscale.max())
        approaching = hit & (gm < -vtol)
        plastic = approaching & (-gm <= vz)
        e = np.where(plastic, 0.0, self.ev.restitution)
        closed = (self.modes != OPEN) & ev.constrained
        uni_set = (closed & self.uni) | approaching
        held = np.zeros(self.nc, dtype=bool)
        qd_plus, lam = impulse(ev, q, qd, uni_set, closed & ~self.uni, e)
        gp = WN.T @ qd_plus
        for _ in range(self.nc):
            # contacts the impulse would set separating slower than the Zeno velocity are
            # held closed (their flight would not be resolved either)
            slow = uni_set & ~held & (gp > vtol) & (gp <= vz)
            if not slow.any():
                break
            held |= slow
            qd_plus, lam = impulse(ev, q, qd, uni_set & ~held, (closed & ~self.uni) | held, e)
            gp = WN.T @ qd_plus
        if self.trace is not None:
            self.jumps[len(self.trace) - 1] = ImpactMap(
                self.t, hit.copy(), uni_set & ~held, (closed & ~self.uni) | held, e.copy(),
                bool((plastic & (self.ev.restitution > 0)).any() or held.any()))
        plastic |= held
        M = np.asarray(s.mass(q), float)
        loss = 0.5 * float(qd @ M @ qd - qd_plus @ M @ qd_plus)
        self.impact_loss += loss
        self.impacts.append(Impact(float(self.t), tuple(int(c) for c in np.flatnonzero(hit)),
                                   gm, gp, lam, loss,
                                   tuple(int(c) for c in np.flatnonzero(plastic))))
        # after the impulse: separating contacts are open, the others closed
        sep = self.uni & (uni_set | hit) & (gp > vtol)
        gam, vs = ev.tangent_velocity(self.t, q, qd_plus)
        moving = np.abs(gam) > 1e3 * _EPS * vs
        old = self.modes.copy()
        for c in np.flatnonzero(self.uni & (uni_set | hit)):
            if sep[c]:
                self.modes[c] = OPEN
            elif old[c] == OPEN or (old[c] == STICK and moving[c]):
                # closing (or a stuck contact the impulse set sliding): slip, or decided
                self.modes[c] = (SLIP_POS if gam[c] >= 0 or ev.frictionless[c]
                                 else SLIP_NEG) if moving[c] or ev.frictionless[c] else STICK
                self.sigma[c] = 1.0
            if hit[c]:
                self.events.append(SwitchEvent(float(self.t), int(c), "open",
                                               "open" if sep[c] else "closed", "impact"))
            elif old[c] != OPEN and sep[c]:
                self.events.append(SwitchEvent(float(self.t), int(c), MODE_NAMES[int(old[c])],
                                               "open", "lift-off"))
        for c in np.flatnonzero(~self.uni & closed & (old == STICK) & moving):
            self.modes[c] = SLIP_POS if gam[c] >= 0 else SLIP_NEG
        self.q, self.qd = q, qd_plus

    # ------------------------------------------------------------ outputs and energy
    def _record(self, phase, t_stop, last):
        """Store the samples of a phase; return the state at its end."""
        ts = phase.t0
        if t_stop <= ts and not last:
            return self.q, self.qd
        te = self.t_eval
        inside = te[np.searchsorted(te, ts, "right"):np.searchsorted(te, t_stop, "left")]
        times = np.empty(inside.size + 2)
        times[0] = ts
        times[1:-1] = inside
        times[-1] = t_stop
        n_rec = times.size if (last and t_stop > ts) else times.size - 1
        q, qd, lamN, lamT = phase.outputs(times)
        cum = (self._energy(phase, times) if self.with_energy
               else np.full((3, times.size), np.nan))
        e = self.acc[:, None] + cum[:, :n_rec]
        self.acc = self.acc + cum[:, -1]
        kin, pot = self._mech(q[:n_rec], qd[:n_rec])
        modes = np.repeat(self.modes[None].astype(np.int8), n_rec, axis=0)
        self.out.append((times[:n_rec], q[:n_rec], qd[:n_rec], lamN[:n_rec], lamT[:n_rec], modes,
                         e[0], -e[2], e[1], kin, pot, np.full(n_rec, self.impact_loss)))
        return q[-1], qd[-1]

    def _energy(self, phase, times):
        """Cumulative (input, viscous, friction) work from times[0] at ``times``, (3, n)."""
        ts, t_stop = times[0], times[-1]
        if t_stop <= ts:
            return np.zeros((3, times.size))
        if isinstance(phase, NumericalPhase) or phase.cfg.eigen:
            return phase.energy(times)
        h = phase.h  # an exact phase without an eigen-decomposition: quadrature of its power
        nsub = 1 if not np.isfinite(h) else int(np.ceil((t_stop - ts) / h))
        bps = np.linspace(ts, t_stop, nsub + 1)
        bps = np.union1d(bps, times)
        a, b = bps[:-1], bps[1:]
        nodes = (0.5 * (b - a))[:, None] * (_GL_X + 1.0)[None] + a[:, None]
        p = np.array(phase.powers(nodes.ravel())).reshape(3, a.size, _GL_X.size)
        seg = np.einsum("kij,j->ki", p, _GL_W) * (0.5 * (b - a))[None]
        cum = np.concatenate([np.zeros((3, 1)), np.cumsum(seg, axis=1)], axis=1)
        return cum[:, np.searchsorted(bps, times)]

    def _mech(self, q, qd):
        if self.lf is not None:
            kin = 0.5 * np.einsum("ti,ij,tj->t", qd, self.lf.M, qd)
            pot = 0.5 * np.einsum("ti,ij,tj->t", q, self.lf.K, q)
            return kin, pot
        s = self.system
        many = getattr(s, "mechanical_energy_many", None)  # optional vectorised hook
        if many is not None:
            return many(q, qd)
        kin = np.array([0.5 * v @ np.asarray(s.mass(x), float) @ v
                        for x, v in zip(q, qd, strict=True)])
        pot = np.array([s.potential_energy(x) for x in q], dtype=float)
        return kin, pot

    def result(self, status, message, runtime):
        s = self.system
        n, nc = self.ev.n, self.nc
        if self.out:
            cols = [np.concatenate(c, axis=0) for c in zip(*self.out, strict=True)]
        else:
            cols = [np.zeros(0), np.zeros((0, n)), np.zeros((0, n)), np.zeros((0, nc)),
                    np.zeros((0, nc)), np.zeros((0, nc), np.int8)] + [np.zeros(0)] * 6
        t, q, qd, lamN, lamT, modes = cols[:6]
        energy = dict(zip(ENERGY_KEYS, cols[6:12], strict=True))
        return EventResult(
            t=t, q=q, qd=qd, lambda_N=lamN, lambda_T=lamT, modes=modes,
            events=tuple(self.events), energy=energy, success=status == 0, status=status,
            message=message, n_events=self.n_events, n_phases=self.n_phases,
            n_decisions=self.n_decisions, n_configurations=len(self.configs),
            n_rhs=self.n_rhs, n_expm=self.n_expm, n_singular=self.ev.n_singular,
            projection_energy=self.proj_energy,
            method="exact" if self.lf is not None else "dop853", runtime_s=runtime,
            dof_names=tuple(s.dof_names), contact_names=tuple(s.contact_names),
            meta={"ambiguous_switches": [(t, [m.tolist() for m in alts])
                                         for t, alts in self.decider.ambiguities]},
            impacts=tuple(self.impacts))


__all__ = ["ConstrainedSystem", "CoulombSystem", "EventResult", "LinearForm", "SwitchEvent",
           "simulate_events"]
