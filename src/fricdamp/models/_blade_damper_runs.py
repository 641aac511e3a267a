"""Event-driven runs of the blade-damper model with restarts after round-off stalls.

Private helper of :mod:`fricdamp.models.blade_damper_analyses` (see :func:`simulate`).
"""

from __future__ import annotations

import logging
import re

import numpy as np

from fricdamp.errors import ConvergenceError
from fricdamp.models.blade_damper import BladeDamperSystem

log = logging.getLogger(__name__)


_FAIL_TIME = re.compile(r"at t = ([-+0-9.eE]+) s")


def _project_stuck(system: BladeDamperSystem, q, qd, stuck):
    """M-orthogonal projection of q' onto ``W_N^T q' = 0`` and ``W_T,i^T q' = 0`` (i stuck)."""
    WN, WT, _, _ = system.kinematics(q, qd)
    W = np.hstack([WN, WT[:, np.asarray(stuck, dtype=bool)]])
    MiW = (1.0 / np.diag(system.M))[:, None] * W
    return qd - MiW @ np.linalg.solve(W.T @ MiW, W.T @ qd)


def simulate(system: BladeDamperSystem, t0, t1, y0, t_eval, *, rtol, atol, max_events,
              max_restarts: int = 100):
    """:func:`~fricdamp.solvers.event.simulate_events` with restarts after round-off stalls.

    The DOP853 phases of the event solver let the slip velocity of a stuck contact drift by
    ~1e-12 of the velocity scale; when that contact then starts slipping, the drift can have
    the wrong sign and the solver's slip-reversal test (threshold 100 eps) fires at once, over
    and over ("chattering ... without time advancing"), or no configuration passes its
    consistency check. Such a run is restarted from its last stored sample (before the
    stall) with the velocities of the stuck contacts projected back onto their constraints
    (kinetic-energy change ~1e-17 J, summed in ``meta["restart_energy"]``); the restarts are
    counted in ``meta["restarts"]``. A failure that recurs without progress is returned as a
    failed result.
    """
    from fricdamp.solvers.event import simulate_events

    parts = []
    restarts: list[float] = []
    n = system.n_dof
    ts, y = float(t0), np.asarray(y0, dtype=float)
    # a state that ended a previous run in stick carries the same ~1e-12 drift: put it back
    q, qd = y[:n], y[n:]
    WT = system.tangent_jacobian(q)
    small = np.abs(WT.T @ qd) <= 1e-9 * (np.abs(WT).T @ np.abs(qd))
    qd_new = _project_stuck(system, q, qd, small)
    de = abs(system.kinetic_energy(qd) - system.kinetic_energy(qd_new))
    y = np.concatenate([q, qd_new])
    while True:
        te = t_eval[(t_eval >= ts) & (t_eval <= t1)]
        r = simulate_events(system, (ts, t1), y, t_eval=te, rtol=rtol, atol=atol,
                            max_events=max_events, throw=False)
        m = _FAIL_TIME.search(r.message) if r.status == -1 else None
        if r.success or m is None or len(restarts) >= max_restarts:
            parts.append((r, False))
            break
        if r.t.size > 1 and r.t[-1] > ts:
            parts.append((r, True))  # its last sample is the next run's first
        else:  # stalled before the first stored sample: rerun up to just before the stall
            te_ = ts + (1 - 1e-6) * (float(m.group(1)) - ts)
            r2 = None
            if te_ > ts:
                try:
                    r2 = simulate_events(system, (ts, te_), y, t_eval=np.array([ts, te_]),
                                         rtol=rtol, atol=atol, max_events=max_events,
                                         throw=False)
                except (ConvergenceError, IndexError, ValueError) as exc:  # solver edge case
                    log.info("rerun before the stall failed: %s", exc)
            if r2 is None or not r2.success or r2.t[-1] <= ts:
                parts.append((r, False))
                break
            r = r2
            parts.append((r, True))
        q, qd = r.q[-1], r.qd[-1]
        qd_new = _project_stuck(system, q, qd, r.modes[-1] == 0)
        de += abs(system.kinetic_energy(qd) - system.kinetic_energy(qd_new))
        log.info("event solver stalled (%s); restarted at t = %.17g s", r.message, r.t[-1])
        restarts.append(float(r.t[-1]))
        ts, y = float(r.t[-1]), np.concatenate([q, qd_new])
    res = parts[0][0] if len(parts) == 1 else _merge(parts)
    res.meta["restarts"] = len(restarts)
    res.meta["restart_times"] = restarts
    res.meta["restart_energy"] = de
    return res


def _merge(parts):
    """Concatenate EventResults of consecutive runs ``[(result, drop_last_sample), ...]``
    (cumulative energies continued)."""
    from dataclasses import replace

    cum = ("input_work", "friction_dissipation", "viscous_dissipation")
    energy = {k: [] for k in parts[0][0].energy}
    off = dict.fromkeys(cum, 0.0)
    keep = []
    for r, drop in parts:
        sl = slice(0, r.t.size - 1 if drop else r.t.size)
        keep.append(sl)
        for k, v in r.energy.items():
            energy[k].append((v + off[k] if k in cum else v)[sl])
        for k in cum:
            if r.energy[k].size:
                off[k] = off[k] + r.energy[k][-1]
    cat = {k: np.concatenate([getattr(r, k)[sl] for (r, _), sl in zip(parts, keep,
                                                                      strict=True)])
           for k in ("t", "q", "qd", "lambda_N", "lambda_T", "modes")}
    counters = {k: sum(getattr(r, k) for r, _ in parts) for k in
                ("n_events", "n_phases", "n_decisions", "n_rhs", "n_expm", "n_singular",
                 "projection_energy", "runtime_s")}
    return replace(parts[-1][0], **cat, events=tuple(e for r, _ in parts for e in r.events),
                   energy={k: np.concatenate(v) for k, v in energy.items()}, **counters,
                   meta={})
