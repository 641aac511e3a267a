"""Steady stick-slip responses of the blade damper as periodic orbits (shooting).

:func:`steady_orbit` replaces "integrate until two windows agree within 5 %" (which called
slowly beating transients converged) by Newton's method on the stroboscopic map through
exact stick-slip (:func:`fricdamp.solvers.shooting.shoot`), with the orbit's Floquet
multipliers, its period multiple and its practical stability.

The transient is integrated in chunks and the return map read after each
(:func:`fricdamp.solvers.shooting.detect_period_multiple`: which period multiple n, and how
far ``|y_k - y_(k-n)|``, scaled); Newton starts once that distance is below
``shoot_distance`` (1e-3). On this nonsmooth map Newton from 1e-2 often fails, and one
iteration (a flow over n periods with its monodromy, and a line search) costs as much as
about 10 n periods of plain integration at the resonance, so integrating the transient is
usually the cheaper way to a good start. An orbit that cannot belong to a neutral family
(no contact stuck throughout the last chunk) is tried earlier, from ``early_distance``
(1e-2) with a few iterations: an isolated stable orbit is the same answer from wherever
Newton reaches it. An unstable period-1 orbit with a real multiplier below -1 (a flip)
sends the search to n = 2.

Neutral multipliers and the member of a family
-----------------------------------------------
When a contact sticks during the whole orbit (e.g. at 58 Hz, F_e = 8 N), the tangential
preload it locked in is never released: the orbit belongs to a one-parameter family with a
multiplier exactly 1, and which member the structure settles on depends on its history (the
transient before the contact last slipped) -- sensitively: 400 periods from the same start
end at q4 amplitudes 0.8298 mm (DOP853 rtol 1e-8 and 1e-9) and 0.8465 mm (rtol 1e-10).
Shooting keeps the linearised invariant of that family (the locked-in preload) while it
iterates, so it converges to the member of the state it starts from only up to the
invariant's second-order drift. :func:`steady_orbit` therefore continues the transient by
``chunk_periods`` and shoots again until two successive orbits agree to ``tol`` (relative
amplitude of q4); an isolated stable orbit (no neutral direction) is accepted at once.
Stability follows :func:`fricdamp.solvers.shooting.neutral_stability`: stable when every
multiplier other than the neutral ones lies inside the unit circle.

When no periodic orbit of period multiple up to ``max_multiple`` is stable within the budget
(e.g. the period-1 orbit at 62.3 Hz with a complex pair at |mu| = 1.14: a Neimark-Sacker
beating), the response is not periodic; the steady amplitude is then the largest half
peak-to-peak of q4 over two windows at the end of the budget (its last ``2 window_periods``
periods, sampled densely as they are integrated), reported with
``periodic = False`` and ``converged`` telling whether the two windows agree (a stationary
quasi-periodic or chaotic response) or not (still a transient).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np

from fricdamp.errors import ConvergenceError, ModelError, as_finite_array

__all__ = ["SteadyOrbit", "steady_orbit"]


@dataclass(frozen=True)
class SteadyOrbit:
    """Steady response at one excitation frequency, from shooting.

    Attributes
    ----------
    frequency_hz : float
    amplitude_m : float
        q4 amplitude [m]: half peak-to-peak over the orbit (exact extrema), or the largest
        over two windows of a long integration when the response is not periodic.
    amplitudes_m : ndarray, shape (7,)
        Half peak-to-peak of every coordinate over the orbit [m, rad].
    periodic : bool
        A stable periodic orbit was found (False: quasi-periodic or chaotic response).
    period_multiple : int
        n of the period-n orbit (0 when not periodic).
    stable : bool
        Practical stability (neutral multipliers of always-stuck contacts excluded).
    stable_strict : bool
        All multipliers strictly inside the unit circle.
    max_multiplier : float
        Largest |mu| other than the neutral ones.
    multipliers_abs : ndarray
        All |mu| by decreasing modulus.
    neutral_contacts : tuple of int
        Contacts stuck during the whole orbit whose neutral direction was excluded.
    converged : bool
        Periodic: Newton converged and, with neutral contacts, two successive orbits agreed
        to ``tol``. Not periodic: the response is stationary (two windows' amplitudes agree
        to ``stationarity_tol``).
    residual : float
        Newton residual of the last orbit.
    periods : int
        Transient periods integrated before the section (``y_end`` is the state there).
    t_section : float
        Time of the section [s].
    y_end : ndarray, shape (14,)
        State on the orbit at ``t_section`` (warm start for the next frequency).
    min_normal_force_N : float
        Smallest normal contact force over the orbit (or the window) [N].
    time_in_configuration : dict of str -> float
        Time [s] in each configuration over one orbit.
    cpu_s : float
        Process CPU time of the call [s].
    errors : tuple of str
    orbit : PeriodicOrbit or None
    notes : tuple of str
        Released system (``release``): shooting attempts that failed (e.g. an accumulation
        of impacts cut short by the Zeno velocity, whose saltation matrices are not
        resolved); the response is then measured over windows (``periodic`` False), which
        is not an error.
    """

    frequency_hz: float
    amplitude_m: float
    amplitudes_m: np.ndarray
    periodic: bool
    period_multiple: int
    stable: bool
    stable_strict: bool
    max_multiplier: float
    multipliers_abs: np.ndarray
    neutral_contacts: tuple
    converged: bool
    residual: float
    periods: int
    t_section: float
    y_end: np.ndarray
    min_normal_force_N: float
    time_in_configuration: dict
    cpu_s: float
    errors: tuple = ()
    orbit: object = field(default=None, repr=False, compare=False)
    notes: tuple = ()

    def summary(self) -> dict:
        return {"frequency_hz": float(self.frequency_hz), "amplitude_m": float(self.amplitude_m),
                "periodic": bool(self.periodic), "period_multiple": int(self.period_multiple),
                "stable": bool(self.stable), "stable_strict": bool(self.stable_strict),
                "max_multiplier_excluding_neutral": float(self.max_multiplier),
                "floquet_multipliers_abs": [float(m) for m in self.multipliers_abs],
                "neutral_contacts": [int(i) for i in self.neutral_contacts],
                "converged": bool(self.converged), "residual": float(self.residual),
                "transient_periods": int(self.periods),
                "min_normal_force_N": float(self.min_normal_force_N)}


def _configuration_times(res, release: bool = False) -> dict:
    from fricdamp.models.blade_damper.configurations import time_in_configuration

    return time_in_configuration(res.t, res.modes, release=release)


def _tail_windows(tail, t_end, width):
    """The two windows ``[t_end - 2 width, t_end - width]`` and ``[t_end - width, t_end]``
    from the densely sampled chunks ``tail`` (EventResults ending at ``t_end``); None when
    they do not cover both."""
    tol = 1e-12 * max(abs(t_end), 1.0)
    if not tail or tail[0].t[0] > t_end - 2 * width + tol or abs(tail[-1].t[-1] - t_end) > tol:
        return None
    cols = {k: np.concatenate([getattr(r, k) for r in tail])
            for k in ("t", "q", "lambda_N", "modes")}
    out = []
    for a, b in ((t_end - 2 * width, t_end - width), (t_end - width, t_end)):
        sel = (cols["t"] >= a - tol) & (cols["t"] <= b + tol)
        out.append(SimpleNamespace(**{k: v[sel] for k, v in cols.items()}))
    return out


def steady_orbit(params, *, y0=None, t_start: float = 0.0, transient_periods: int = 0,
                 chunk_periods: int = 10, max_periods: int = 400, tol: float = 1e-6,
                 shoot_distance: float = 1e-3, max_multiple: int = 4, max_shots: int = 6,
                 max_iter: int = 8, rtol: float = 1e-9, window_periods: int = 20,
                 stationarity_tol: float = 0.01, early_distance: float = 1e-2,
                 early_max_iter: int = 4, max_early_shots: int = 2) -> SteadyOrbit:
    """Steady stick-slip response at ``params.excitation_frequency`` by shooting.

    Parameters
    ----------
    params : BladeDamperParameters or BladeDamperSystem
    y0 : array_like, shape (14,), optional
        State ``[q, q']`` at ``t_start``; default the static state at rest.
    t_start : float
        Start time [s] (sets the excitation phase of y0).
    transient_periods : int
        Periods integrated before the return map is first read.
    chunk_periods : int
        Periods of integration between two readings of the return map (at least
        ``2 max_multiple + 1``); shooting starts once the scaled return distance of the
        period multiple it shows is below ``shoot_distance``.
    max_periods : int
        Transient budget [periods]; at its end the orbit is shot if the return distance is
        below ``30 shoot_distance``, and without a stable orbit the response is reported as
        not periodic.
    tol : float
        Relative agreement of two successive orbits' q4 amplitudes (neutral families).
    shoot_distance : float
        Scaled return distance ``|y_k - y_(k-n)|`` below which Newton is started. Newton on
        this nonsmooth map converges in 2-4 iterations from 1e-3 but often not at all from
        1e-2, and an iteration (flow with its monodromy, line search) costs as much as 30-100
        periods of plain integration: the transient is cheaper to integrate than to shoot.
    max_multiple : int
        Largest period multiple searched when the period-1 orbit is not stable.
    max_shots : int
        Shooting attempts.
    max_iter : int
        Newton iterations per attempt (a converging attempt needs 2-4).
    rtol : float
        DOP853 tolerance (the shooting tolerance is 100 rtol on the scaled residual).
    window_periods : int
        Without a stable periodic orbit: the last two windows of this many periods of the
        budget (or two more, integrated after it, when the search stopped before the
        budget's end or the budget is shorter); the amplitude is the larger of their q4 half
        peak-to-peak values.
    stationarity_tol : float
        The non-periodic response is stationary (``converged``) when the two windows'
        amplitudes agree to this relative tolerance.
    early_distance : float
        When no contact stuck throughout the last chunk (so an orbit near it cannot belong
        to a neutral family of always-stuck contacts: its member would not depend on the
        history) and the transient is slow (shrinking at the last chunk's rate, more than
        ``5 n`` chunks still to go to ``shoot_distance``), Newton is tried already below this
        return distance, with ``early_max_iter`` iterations, at most ``max_early_shots``
        times; a converged,
        stable orbit without neutral contacts is accepted as at ``shoot_distance``,
        anything else lets the transient continue. A Newton iteration on a period-n orbit
        costs about 10 n periods of integration at the resonance, a chunk 10.

    Returns
    -------
    SteadyOrbit
    """
    from fricdamp.models.blade_damper.configurations import RELEASED_NORMAL_FORCE_TOL_N, _system
    from fricdamp.solvers.event_switch import STICK
    from fricdamp.solvers.shooting import _return_map, flow, neutral_stability, shoot

    c0 = time.process_time()
    s = _system(params)
    p = s.params
    for name, v in (("transient_periods", transient_periods), ("chunk_periods", chunk_periods),
                    ("max_periods", max_periods), ("max_multiple", max_multiple)):
        if int(v) != v or v < (0 if name == "transient_periods" else 1):
            raise ModelError(f"{name} must be an integer >= "
                             f"{0 if name == 'transient_periods' else 1}, got {v!r}")
    T = 1.0 / p.excitation_frequency
    # a released contact opens instead of pulling: only round-off may remain below zero
    tensile = -RELEASED_NORMAL_FORCE_TOL_N if s.release else 0.0
    why = ("a released contact is tensile (solver error)" if s.release else
           "the damper would lift off, which this no-separation model excludes")
    y = (np.concatenate([s.static_equilibrium().q, np.zeros(7)]) if y0 is None
         else as_finite_array("y0", y0).copy())
    t = float(t_start)
    done = 0
    errors: list[str] = []
    notes: list[str] = []  # released: failed shots (the windows measure the response)

    def advance(k):
        nonlocal y, t, done
        if k <= 0:
            return None
        fl = flow(s, (t, t + k * T), y, t_eval=np.linspace(t, t + k * T, 20 * k + 1),
                  monodromy=False, keep_phases=False, rtol=rtol)
        y, t, done = fl.y_end, t + k * T, done + k
        return fl.result

    def orbit_at(nmul, iters=max_iter):
        try:
            o = shoot(s, T, y, t0=t, transient_periods=0, period_multiple=nmul,
                      max_iter=iters, rtol=rtol)
        except ConvergenceError as exc:
            (notes if s.release else errors).append(f"shooting failed at t = {t:.6g} s: {exc}")
            return None, None
        return o, (neutral_stability(s, o) if o.success else None)

    def stable_orbit(n_det):
        """Shoot the period multiple the return map shows, then the others that the
        multipliers suggest; the stable orbit found (or the last converged one)."""
        o, ns = orbit_at(n_det)
        found = (o, ns) if o is not None and o.success else None
        if found is not None and ns.stable:
            return found
        tried = {n_det}
        if n_det != 1:
            o, ns = orbit_at(1)
            tried.add(1)
            if o is not None and o.success:
                if ns.stable:
                    return o, ns
                found = (o, ns)
        if found is not None and 2 not in tried and 2 <= max_multiple and np.any(
                (np.abs(found[0].multipliers.imag) < 1e-9)
                & (found[0].multipliers.real < -1.0)):
            o, ns = orbit_at(2)  # a real multiplier below -1: period doubling
            if o is not None and o.success:
                return o, ns
        return found

    prev_amp = np.nan
    best = None  # (orbit, neutral stability) of the last converged orbit
    shots = early = 0
    k = max(int(chunk_periods), 2 * int(max_multiple) + 1)
    # the two windows of a response without a stable orbit are the budget's last
    # 2 window_periods periods, sampled densely as they are integrated
    tail_from = int(max_periods) - 2 * int(window_periods)
    tail: list = []
    last_det = None  # (n, distance) of the previous chunk

    def chunks_left(dist, prev):
        """Chunks until the return distance reaches shoot_distance at the rate of the last
        chunk (inf when it did not shrink or n changed: no estimate)."""
        if prev is None or prev[0] != n_det or not 0 < dist < prev[1]:
            return np.inf
        return np.log(shoot_distance / dist) / np.log(dist / prev[1])

    try:
        advance(int(transient_periods))
        while True:
            # the return map of the next k periods: which n, and is it close enough?
            dense = tail_from >= 0 and done + k > tail_from
            n_det, y_d, dist, res_k = _return_map(s, T, y, t0=t, periods=k,
                                                  max_multiple=max_multiple, rtol=rtol,
                                                  samples_per_period=20 if dense else 1)
            if dense:
                tail.append(res_k)
            prev_det, last_det = last_det, (n_det, dist)
            y, t, done = y_d, t + k * T, done + k
            last = done + k > max_periods
            # at the end of the budget Newton is still tried from somewhat further out, but
            # not from a transient that is far from any orbit (it would fail, at a cost)
            if dist <= shoot_distance or (last and dist <= 30 * shoot_distance):
                shots += 1
                found = stable_orbit(n_det)
                if found is not None:
                    best = found
                    o, ns = found
                    if ns.stable:
                        amp = float(o.amplitude[3])
                        if not ns.neutral_contacts or abs(amp - prev_amp) <= tol * amp:
                            break
                        prev_amp = amp
            elif (dist <= early_distance and early < int(max_early_shots)
                  and np.isfinite(left := chunks_left(dist, prev_det)) and left > 5 * n_det
                  and not np.any(np.all(res_k.modes == STICK, axis=0))):
                # an isolated orbit near a slow transient: Newton (an iteration costs about
                # n chunks' worth: monodromy over n periods and line search) is cheaper than
                # the chunks still needed to reach shoot_distance
                early += 1
                o, ns = orbit_at(n_det, int(early_max_iter))
                if (o is not None and o.success and ns.stable
                        and not ns.neutral_contacts):
                    best = (o, ns)
                    break
            if last or shots >= int(max_shots):
                break
    except ConvergenceError as exc:
        errors.append(f"solver: {exc}")
        best = None
    if best is not None and best[1].stable:
        o, ns = best
        converged = bool(o.success and (not ns.neutral_contacts
                                        or abs(o.amplitude[3] - prev_amp) <= tol * o.amplitude[3]))
        fin = flow(s, (o.t0, o.t0 + o.period_multiple * T), o.y0,
                   t_eval=np.linspace(o.t0, o.t0 + o.period_multiple * T,
                                      100 * o.period_multiple + 1), monodromy=False, rtol=rtol)
        minN = float(fin.result.lambda_N.min())
        if minN < tensile:
            errors.append(f"negative normal force {minN:.4g} N on the orbit: " + why)
        return SteadyOrbit(
            frequency_hz=p.excitation_frequency, amplitude_m=float(o.amplitude[3]),
            amplitudes_m=np.asarray(o.amplitude), periodic=True,
            period_multiple=int(o.period_multiple), stable=True,
            stable_strict=bool(ns.stable_strict), max_multiplier=float(ns.max_multiplier),
            multipliers_abs=np.abs(o.multipliers), neutral_contacts=tuple(ns.neutral_contacts),
            converged=converged, residual=float(o.residual), periods=int(done),
            t_section=float(o.t0), y_end=np.asarray(o.y0), min_normal_force_N=minN,
            time_in_configuration=_configuration_times(fin.result, s.release),
            cpu_s=time.process_time() - c0, errors=tuple(errors), orbit=o, notes=tuple(notes))
    # no stable periodic orbit: the response beats (quasi-periodic or chaotic); its
    # amplitude is the largest half peak-to-peak over two windows (the budget's last
    # 2 window_periods periods, or two further windows when the search stopped early),
    # stationary when they agree to stationarity_tol
    res = None
    a12 = []
    minN_all = np.inf
    windows = _tail_windows(tail, t, window_periods * T)
    try:
        for i in range(2):
            res = windows[i] if windows is not None else advance(int(window_periods))
            a12.append(float(0.5 * np.ptp(res.q[:, 3])))
            minN_all = min(minN_all, float(res.lambda_N.min()))
            if minN_all < tensile:
                break
    except ConvergenceError as exc:
        errors.append(f"solver: {exc}")
        res = None
    amp = max(a12) if res is not None else float("nan")
    stationary = bool(len(a12) == 2 and abs(a12[1] - a12[0]) <= stationarity_tol * amp)
    minN = minN_all if res is not None else float("nan")
    if minN < tensile:
        errors.append(f"negative normal force {minN:.4g} N: " + why)
    o, ns = best if best is not None else (None, None)
    return SteadyOrbit(
        frequency_hz=p.excitation_frequency, amplitude_m=amp,
        amplitudes_m=(0.5 * np.ptp(res.q, axis=0) if res is not None else np.full(7, np.nan)),
        periodic=False, period_multiple=0, stable=False, stable_strict=False,
        max_multiplier=float(ns.max_multiplier) if ns is not None else float("nan"),
        multipliers_abs=np.abs(o.multipliers) if o is not None else np.zeros(0),
        neutral_contacts=tuple(ns.neutral_contacts) if ns is not None else (),
        converged=stationary, residual=float(o.residual) if o is not None else float("nan"),
        periods=int(done), t_section=float(t), y_end=y, min_normal_force_N=minN,
        time_in_configuration=(_configuration_times(res, s.release) if res is not None
                               else {}),
        cpu_s=time.process_time() - c0, errors=tuple(errors), orbit=o, notes=tuple(notes))
