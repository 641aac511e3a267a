"""Verdicts: every result says whether it can be trusted, and why not.

A :class:`Verdict` is ``ok``, ``unreliable`` (computed, but an error estimate exceeds its
threshold: the reasons say which and what to do) or ``failed`` (the solver did not deliver
what was asked). It carries the error estimates it was judged on, so the numbers behind the
verdict travel with the result (API, ``summary.json``, report, exit code).

Estimates and their thresholds (:data:`THRESHOLDS`):

``energy_balance_error`` (time integration and harmonic balance), limit 1e-2
    Largest energy residual relative to the run's energy scale. Damping ratios and loop
    energies are ratios of dissipated to stored energy: an unaccounted 1 % of the energy
    scale is an error of that order on them.
``period_error`` (time integration), limit 1e-2
    Relative period error of the Newmark rule, ``omega h / (2 atan(omega h / 2)) - 1``
    (Hughes 1987, sec. 9.3; ``~ (omega h)^2 / 12`` for small steps), for the highest linear
    mode that carries at least 1 % of the kinetic energy of the run. The energy balance of the
    average-acceleration rule is exact for the linear part, so it cannot see this error; 1 %
    is reached at about 18 steps per period of that mode (a 1 Hz oscillator at 2.5 steps per
    period: 40 %). The modes are those of the linear part (contacts open): a stuck contact
    stiffens the structure, so this is a lower bound of the error of the stuck motion; the
    energy balance covers the integration of the contact forces.
``step_doubling_error`` (``free_decay``, ``forced_response``), limit 2e-2
    The run is repeated with twice the step; for a second-order rule the error of the run is
    about a third of the difference (Richardson). Compared is what does not depend on the
    phase: the mechanical-energy history of a free decay (relative to its largest value), the
    amplitudes of the last period of a forced response (relative to the largest). It sees the
    time-step error of the contact forces too (stick-slip transitions between samples). The
    limit is the response accuracy used for harmonic truncation below.
``harmonic_truncation`` (harmonic balance), limit 2e-2
    Largest relative change of the amplitudes, and of the energy dissipated per cycle, when
    the peak point is solved again with more harmonics (``H -> min(2H + 1, H + 10)``). A
    friction loop has a corner at every stick-slip transition, so its harmonics decay slowly;
    2 % is the accuracy an engineer reads off a frequency response curve.
``aft_sampling_error`` (harmonic balance), limit 1e-2
    The same change when the peak point is solved again with twice the AFT samples.
``negative_dissipation`` (all), limit 0
    A passive contact cannot give energy back over a cycle or a decay; energy dissipated
    below ``-1e-6`` of the energy scale means the contact forces are not integrated right.

Exit codes of ``fricdamp run`` (:func:`exit_code`): 0 ok, 1 failed, 2 bad input (raised
before anything is computed), 3 computed but unreliable.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "FAILED",
    "OK",
    "THRESHOLDS",
    "UNRELIABLE",
    "Verdict",
    "combine",
    "exit_code",
    "harmonic_truncation",
    "judge",
    "newmark_period_error",
    "time_result_verdict",
    "time_step_error",
    "verdict_block",
]

OK, UNRELIABLE, FAILED = "ok", "unreliable", "failed"
_RANK = {OK: 0, UNRELIABLE: 1, FAILED: 2}

#: Limits of the error estimates (module docstring): above them a result is unreliable.
THRESHOLDS: dict[str, float] = {
    "energy_balance_error": 1e-2,
    "period_error": 1e-2,
    "step_doubling_error": 2e-2,
    "harmonic_truncation": 2e-2,
    "aft_sampling_error": 1e-2,
    "negative_dissipation": 1e-6,
}

#: What to do when an estimate is over its limit (the end of the reason).
_ADVICE = {
    "energy_balance_error": "reduce the time step, or soften the contact stiffness",
    "period_error": "reduce the time step",
    "step_doubling_error": "reduce the time step (steps per period)",
    "harmonic_truncation": "H too small: increase harmonics",
    "aft_sampling_error": "increase samples",
    "negative_dissipation": "the contact forces are not integrated right: reduce the time step",
}


@dataclass(frozen=True)
class Verdict:
    """Whether a result can be trusted.

    Attributes
    ----------
    status : {"ok", "unreliable", "failed"}
    reasons : tuple of str
        Why it is not ok (one sentence each, saying what to do); empty when ok.
    estimates : dict of str -> float or None
        The error estimates it was judged on (keys of :data:`THRESHOLDS` and others).
    """

    status: str = OK
    reasons: tuple[str, ...] = ()
    estimates: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.status not in _RANK:
            raise ValueError(f"verdict status must be 'ok', 'unreliable' or 'failed', got "
                             f"{self.status!r}")
        object.__setattr__(self, "reasons", tuple(str(r) for r in self.reasons))
        object.__setattr__(self, "estimates", dict(self.estimates))

    @property
    def ok(self) -> bool:
        return self.status == OK

    @classmethod
    def failed(cls, reason: str, estimates: Mapping | None = None) -> Verdict:
        return cls(FAILED, (reason,), dict(estimates or {}))

    @classmethod
    def unreliable(cls, reasons: Iterable[str] | str, estimates: Mapping | None = None
                   ) -> Verdict:
        reasons = (reasons,) if isinstance(reasons, str) else tuple(reasons)
        return cls(UNRELIABLE, reasons, dict(estimates or {}))

    def worse(self, status: str, reason: str) -> Verdict:
        """A copy at least as bad as ``status`` with ``reason`` added."""
        new = status if _RANK[status] > _RANK[self.status] else self.status
        return Verdict(new, (*self.reasons, reason), self.estimates)

    def with_estimates(self, **estimates) -> Verdict:
        return Verdict(self.status, self.reasons, {**self.estimates, **estimates})

    def to_dict(self) -> dict:
        """``{"verdict", "reasons", "estimates"}`` (JSON-able: non-finite numbers -> None)."""
        est = {}
        for k, v in self.estimates.items():
            if isinstance(v, (float, np.floating)):
                v = float(v) if math.isfinite(v) else None
            elif isinstance(v, np.integer):
                v = int(v)
            est[k] = v
        return {"verdict": self.status, "reasons": list(self.reasons), "estimates": est}

    def __str__(self) -> str:
        return self.status if self.ok else f"{self.status}: {'; '.join(self.reasons)}"


def combine(verdicts: Iterable[Verdict]) -> str:
    """The overall status: the worst of ``verdicts`` (``ok`` for none)."""
    worst = OK
    for v in verdicts:
        if _RANK[v.status] > _RANK[worst]:
            worst = v.status
    return worst


def verdict_block(verdicts: Mapping[str, Verdict]) -> dict:
    """``summary.json["verdict"]`` of a command: ``{"overall": worst status, "analyses":
    {name: {"verdict", "reasons", "estimates"}}}`` (the results contract of ``run``, also
    written by ``identify`` and ``fit``)."""
    return {"overall": combine(verdicts.values()),
            "analyses": {name: v.to_dict() for name, v in verdicts.items()}}


def exit_code(status: str) -> int:
    """Exit code of a run whose overall verdict is ``status``: 0 ok, 3 unreliable, 1 failed."""
    return {OK: 0, UNRELIABLE: 3, FAILED: 1}[status]


def judge(estimates: Mapping, *, thresholds: Mapping | None = None, reasons=(),
          failed: str | None = None) -> Verdict:
    """The verdict on a set of estimates against their limits.

    Parameters
    ----------
    estimates : mapping
        Estimates by name; those named in ``thresholds`` (default :data:`THRESHOLDS`) are
        judged (None or NaN: not available, not judged), the others only recorded.
        ``negative_dissipation`` is the most negative dissipated energy relative to the
        energy scale, given as a positive number (0 when there is none).
    reasons : iterable of str
        Further reasons for ``unreliable`` found by the caller.
    failed : str, optional
        A reason for ``failed`` (the solver did not finish).
    """
    lim = dict(THRESHOLDS if thresholds is None else thresholds)
    out = list(reasons)
    for key, value in estimates.items():
        if key not in lim or value is None:
            continue
        v = float(value)
        if math.isnan(v):
            continue
        if v > lim[key]:
            advice = _ADVICE.get(key, "check the settings")
            out.append(f"{key.replace('_', ' ')} {v:.3g} exceeds {lim[key]:g}: {advice}")
    if failed:
        return Verdict(FAILED, (failed, *out), dict(estimates))
    return Verdict(UNRELIABLE if out else OK, tuple(out), dict(estimates))


# ================================================================== time integration
def newmark_period_error(omega_h) -> np.ndarray:
    """Relative period error of Newmark's average-acceleration rule at ``omega h``.

    The discrete solution of ``x'' + omega^2 x = 0`` turns by ``2 atan(omega h / 2)`` per
    step, so its period is ``T omega h / (2 atan(omega h / 2))``; the error grows like
    ``(omega h)^2 / 12`` and without bound as the step nears the period / 2.
    """
    wh = np.abs(np.asarray(omega_h, dtype=float))
    small = wh < 1e-4
    safe = np.where(small, 1.0, wh)
    return np.where(small, wh**2 / 12.0, safe / (2.0 * np.arctan(safe / 2.0)) - 1.0)


def _dense(A) -> np.ndarray:
    import scipy.sparse as sp

    return A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)


def time_step_error(system, result, dt: float, *, share: float = 0.01,
                    max_dense: int = 600, max_samples: int = 4000) -> dict:
    """Period error of the linear part for the modes that carry the motion of ``result``.

    Parameters
    ----------
    system : MechanicalSystem
        The integrated system (``M``, ``K`` of its linear part are used).
    result : TimeResult
        Its time history (velocities ``v``, shape (n_t, n_dof)).
    dt : float
        The time step [s] (not the spacing of the saved samples).
    share : float
        A mode counts when it carries at least this share of the kinetic energy summed over
        the saved samples.
    max_dense : int
        Up to this many DOFs the modes are computed (dense eigenproblem); above, the
        kinetic-energy-weighted frequency ``sqrt(sum v.K v / sum v.M v)`` of the motion is
        used instead (one number, an upper bound of the frequencies that carry energy on
        average).
    max_samples : int
        At most this many saved samples, spread over the run, enter the energy shares.

    Returns
    -------
    dict
        ``period_error`` (of the highest mode counted), ``max_frequency_hz`` (that mode),
        ``steps_per_period`` (of that mode at ``dt``), ``mode_count`` (modes counted) or
        ``period_error`` None if the velocities are all zero.
    """
    V = np.asarray(result.v, dtype=float)
    if V.size == 0 or not np.any(V):
        return {"period_error": None, "max_frequency_hz": None, "steps_per_period": None}
    if V.shape[0] > max_samples:   # the energy shares are averages: a subsample will do
        V = V[np.linspace(0, V.shape[0] - 1, max_samples).astype(int)]
    V = V[np.all(np.isfinite(V), axis=1)]
    n = V.shape[1]
    M, K = system.M, system.K
    if n <= max_dense:
        import scipy.linalg as sla

        Md, Kd = _dense(M), _dense(K)
        lam, phi = sla.eigh(0.5 * (Kd + Kd.T), 0.5 * (Md + Md.T))   # phi^T M phi = I
        omega = np.sqrt(np.clip(lam, 0.0, None))
        eta_dot = V @ (Md @ phi)                                     # modal velocities
        e = np.sum(eta_dot**2, axis=0)
        tot = float(np.sum(e))
        if tot <= 0:
            return {"period_error": None, "max_frequency_hz": None, "steps_per_period": None}
        counted = e >= share * tot
        w = float(np.max(omega[counted]))
        n_counted = int(np.sum(counted))
    else:
        kin = np.einsum("ti,ti->", V, np.asarray((M @ V.T).T))
        pot = np.einsum("ti,ti->", V, np.asarray((K @ V.T).T))
        if kin <= 0:
            return {"period_error": None, "max_frequency_hz": None, "steps_per_period": None}
        w = float(np.sqrt(max(pot, 0.0) / kin))
        n_counted = None
    err = float(newmark_period_error(w * dt))
    return {"period_error": err, "max_frequency_hz": w / (2 * np.pi),
            "steps_per_period": (2 * np.pi / (w * dt)) if w > 0 else None,
            "mode_count": n_counted}


def _dissipation_estimate(energy: Mapping) -> float:
    """Most negative cumulative dissipation relative to the energy scale (>= 0)."""
    mech = energy["kinetic"] + energy["strain"] + energy["contact_stored"]
    diss = energy["contact_dissipation"] + energy["viscous_dissipation"]
    scale = max(float(np.max(np.abs(energy["input_work"]))), float(np.max(np.abs(mech))),
                float(np.max(np.abs(diss))))
    if scale == 0:
        return 0.0
    lowest = min(float(np.min(energy["contact_dissipation"] - energy["contact_dissipation"][0])),
                 float(np.min(energy["viscous_dissipation"] - energy["viscous_dissipation"][0])))
    return max(0.0, -lowest / scale)


def time_result_verdict(system, result, dt: float, *, reasons=(),
                        estimates: Mapping | None = None) -> Verdict:
    """The verdict on a time history from :func:`fricdamp.solvers.timestep.simulate`.

    Estimates: ``energy_balance_error``, ``period_error`` (:func:`time_step_error`) with
    ``max_frequency_hz`` and ``steps_per_period``, and ``negative_dissipation``, plus the
    caller's ``estimates`` (e.g. ``step_doubling_error``), all judged against
    :data:`THRESHOLDS`. A run that stopped early (``status != 0``) is ``failed``.
    """
    est = {"energy_balance_error": float(result.energy_balance_error)}
    try:
        est.update(time_step_error(system, result, dt))
    except Exception as exc:  # noqa: BLE001 - an estimate that cannot be made is not a failure
        est["period_error"] = None
        reasons = (*reasons, f"the time-step error could not be estimated ({exc})")
    est["negative_dissipation"] = _dissipation_estimate(result.energy)
    est.update(estimates or {})
    failed = None
    if not result.success:
        failed = f"the integration stopped at t = {float(result.t[-1]):.6g} s: {result.message}"
    return judge(est, reasons=reasons, failed=failed)


# ================================================================== harmonic balance
def harmonic_truncation(system, omega: float, coefficients, *, harmonics: int,
                        samples: int, dof: int | None = None) -> dict:
    """Change of a harmonic-balance point when solved with more harmonics and more samples.

    The point (``coefficients``, shape (n_dof, 2H+1), at ``omega`` [rad/s]) is solved again
    from itself with ``H2 = min(2H + 1, H + 10)`` harmonics (default samples for H2), and
    with ``H`` harmonics but twice the AFT samples.

    Returns
    -------
    dict
        ``harmonic_truncation``: largest relative change of the amplitudes (of ``dof``, or
        of all DOFs relative to the largest) and of the energy dissipated per cycle, ``H2``;
        ``aft_sampling_error``: the same for twice the samples. None where the re-solve
        did not converge (``*_message`` says why).
    """
    from fricdamp.solvers.hb import harmonic_balance

    X = np.asarray(coefficients, dtype=float)
    H = int(harmonics)
    H2 = min(2 * H + 1, H + 10)

    def solve(h, n_samples, guess):
        return harmonic_balance(system, float(omega), harmonics=h, samples=n_samples,
                                initial_guess=guess)

    def change(ref, new):
        a0, a1 = np.asarray(ref.amplitude), np.asarray(new.amplitude)
        if dof is not None:
            da = abs(a1[dof] - a0[dof]) / max(abs(a1[dof]), 1e-300)
        else:
            da = float(np.max(np.abs(a1 - a0)) / max(float(np.max(np.abs(a1))), 1e-300))
        w0, w1 = float(np.sum(ref.dissipated_energy)), float(np.sum(new.dissipated_energy))
        floor = 1e-6 * max(abs(float(new.external_work)), 1e-300)
        dw = abs(w1 - w0) / abs(w1) if abs(w1) > floor else 0.0
        return float(max(da, dw))

    out: dict = {"H2": H2}
    ref = solve(H, samples, X)
    if not ref.success:
        return {**out, "harmonic_truncation": None, "aft_sampling_error": None,
                "harmonic_truncation_message": ref.message}
    guess = np.zeros((X.shape[0], 2 * H2 + 1))
    guess[:, : 2 * H + 1] = X
    more = solve(H2, None, guess)
    if more.success:
        out["harmonic_truncation"] = change(ref, more)
    else:
        out["harmonic_truncation"] = None
        out["harmonic_truncation_message"] = more.message
    finer = solve(H, 2 * int(samples), X)
    if finer.success:
        out["aft_sampling_error"] = change(ref, finer)
    else:
        out["aft_sampling_error"] = None
        out["aft_sampling_error_message"] = finer.message
    return out
