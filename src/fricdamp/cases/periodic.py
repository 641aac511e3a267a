"""``[analysis.periodic_orbit]``: periodic orbit of a case with Coulomb contacts by shooting.

The case's MechanicalSystem and its ``type = "coulomb"`` contacts become a
:class:`~fricdamp.solvers.event_system.CoulombSystem` (exact set-valued friction, rigid
stick: the contacts' penalty stiffness is not used), forced by ``F cos(2 pi f t)``; the orbit
is found by :func:`fricdamp.solvers.shooting.shoot` (Newton on the stroboscopic map, exact
Floquet multipliers through the saltation matrices).
"""

from __future__ import annotations

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import Positive, Section
from fricdamp.errors import CaseError, ConvergenceError
from fricdamp.registry import AnalysisOutput, RunContext, register_analysis
from fricdamp.verdict import judge

#: Newton residual above which a converged orbit is called unreliable.
RESIDUAL_LIMIT = 1e-8


class PeriodicOrbitAnalysis(Section):
    """``[analysis.periodic_orbit]``: periodic orbit under F cos(2 pi f t) by shooting
    through exact stick-slip (rigid stick), with its Floquet multipliers."""

    force_amplitude_N: list[float] = Field(
        min_length=1, description="amplitude F of F cos(2 pi f t), one entry per DOF")
    frequency_hz: Positive = Field(description="excitation frequency f")
    period_multiple: int | None = Field(
        None, ge=1, le=64, description="n of the period-n orbit (default: detected from the "
                                       "return map of the transient)")
    transient_periods: int = Field(20, ge=0, le=100_000,
                                   description="periods integrated before Newton")
    max_multiple: int = Field(8, ge=1, le=64,
                              description="largest period multiple tried by the detection")
    tol: Positive = Field(1e-11, lt=1e-4, description="Newton tolerance on the scaled "
                                                      "return-map residual")
    max_iter: int = Field(30, ge=1, le=500, description="Newton iterations")

    @model_validator(mode="after")
    def _force(self):
        if not any(self.force_amplitude_N):
            raise ValueError("force_amplitude_N must have a non-zero entry")
        return self


def coulomb_system(system, load=None):
    """The CoulombSystem of a MechanicalSystem whose contacts all use the Coulomb law.

    Each contact row of a ``ContactElement`` projection becomes a friction direction with
    the law's normal load and mu_static, mu_sliding; the penalty stiffness is dropped (rigid
    stick). Raises CaseError for other laws, a velocity-dependent mu (``decay_s_per_m > 0``)
    or no contact at all.
    """
    from fricdamp.contact.coulomb import Coulomb
    from fricdamp.solvers.event_system import CoulombSystem

    rows, N, mus, mud, names = [], [], [], [], []
    if not system.contacts:
        raise CaseError("periodic_orbit needs at least one [[contacts]] table with type = "
                        "\"coulomb\" (the orbit of a linear system is its forced response)")
    for el in system.contacts:
        law = el.law
        if not isinstance(law, Coulomb):
            raise CaseError(f"periodic_orbit: contact {el.name!r} uses {type(law).__name__}; "
                            "shooting through exact stick-slip supports type = \"coulomb\" "
                            "contacts only (use [analysis.frf] for other laws)")
        if np.any(law.decay > 0):
            raise CaseError(f"periodic_orbit: contact {el.name!r} has decay_s_per_m > 0 "
                            "(velocity-dependent mu); exact stick-slip needs a constant "
                            "sliding coefficient: set decay_s_per_m = 0")
        P = np.asarray(el.projection.toarray() if hasattr(el.projection, "toarray")
                       else el.projection, float).reshape(-1, system.n_dof)
        for k in range(P.shape[0]):
            rows.append(P[k])
            N.append(law.normal_load[k])
            mus.append(law.mu_static[k])
            mud.append(law.mu_sliding[k])
            names.append(el.name if P.shape[0] == 1 else f"{el.name}[{k + 1}]")
    base = system.with_contacts()
    if load is not None:
        base = base.with_loads(load)
    return CoulombSystem(base, np.array(rows), np.array(N), np.array(mus),
                         mu_sliding=np.array(mud), contact_names=tuple(names))


def _check(system, spec: PeriodicOrbitAnalysis) -> None:
    n = system.n_dof
    if len(spec.force_amplitude_N) != n:
        raise CaseError(f"force_amplitude_N must have one entry per DOF ({n}), got "
                        f"{len(spec.force_amplitude_N)}")
    if getattr(system, "rotation", None) is not None:
        raise CaseError("periodic_orbit: the model has rotation terms; evaluate them at a "
                        "speed first (not supported from a case file)")
    coulomb_system(system)


def run_periodic_orbit(system, spec: PeriodicOrbitAnalysis, ctx: RunContext) -> AnalysisOutput:
    """Shooting for the periodic orbit; see :class:`PeriodicOrbitAnalysis`."""
    import xarray as xr

    from fricdamp.solvers.shooting import shoot
    from fricdamp.structure import HarmonicLoad

    omega = 2 * np.pi * spec.frequency_hz
    cs = coulomb_system(system, HarmonicLoad(np.asarray(spec.force_amplitude_N, float), omega))
    try:
        orbit = shoot(cs, 1.0 / spec.frequency_hz, period_multiple=spec.period_multiple,
                      transient_periods=spec.transient_periods, max_multiple=spec.max_multiple,
                      tol=spec.tol, max_iter=spec.max_iter)
    except ConvergenceError as exc:  # the event-driven solver itself failed
        raise ConvergenceError(f"periodic_orbit at {spec.frequency_hz:g} Hz: {exc}") from None
    names = list(system.names)
    summary = orbit.summary()
    mu_max = float(orbit.floquet_multipliers_abs.max()) if orbit.multipliers.size else 0.0
    summary.update({
        "frequency_hz": spec.frequency_hz,
        "dof_names": names,
        "period_multiple_detected": spec.period_multiple is None,
        "max_floquet_multiplier_abs": mu_max,
        "floquet_multipliers_real": [float(m.real) for m in orbit.multipliers],
        "floquet_multipliers_imag": [float(m.imag) for m in orbit.multipliers],
        "section_state": [float(v) for v in orbit.y0],
        "switches_per_orbit": int(orbit.n_events),
        "simultaneous_switches": int(orbit.n_simultaneous),
        "newton_iterations": int(orbit.iterations),
        "message": orbit.message,
        "method": orbit.method,
        "solver_runtime_s": float(orbit.runtime_s),
    })
    notes = []
    reasons = []
    if orbit.n_simultaneous:
        reasons.append(f"{orbit.n_simultaneous} switch(es) of several contacts at once: the "
                       "saltation matrix there is not unique, the multipliers are uncertain")
    if orbit.success and not orbit.stable and mu_max < 1 + 1e-6:
        notes.append(f"the largest Floquet multiplier is {mu_max:.8f}: marginally stable "
                     "(a free rigid-body motion or an undamped mode that friction does not "
                     "reach)")
    if not orbit.success:
        notes.append(orbit.message)
    verdict = judge({"shooting_residual": orbit.residual},
                    thresholds={"shooting_residual": RESIDUAL_LIMIT}, reasons=reasons,
                    failed=None if orbit.success else orbit.message)
    amp = orbit.amplitude
    i = int(np.argmax(amp))
    headline = (f"period-{orbit.period_multiple} orbit at {spec.frequency_hz:g} Hz "
                f"({'converged' if orbit.success else 'NOT converged'}, residual "
                f"{orbit.residual:.1e}): amplitude {amp[i]:.4g} m of {names[i]}, "
                f"{orbit.n_events} switches per orbit, max |Floquet multiplier| {mu_max:.4f} "
                f"({'stable' if orbit.stable else 'unstable'}); {orbit.runtime_s:.2f} s")
    arrays = {"orbit": xr.Dataset(
        {"q": (("time", "dof"), orbit.q, {"units": "m"}),
         "qd": (("time", "dof"), orbit.qd, {"units": "m/s"}),
         "mode": (("time", "contact"), orbit.modes,
                  {"long_name": "contact mode (0 stick, +1/-1 slip direction)"})},
        coords={"time": ("time", orbit.t, {"units": "s"}), "dof": names,
                "contact": list(cs.contact_names)},
        attrs={"period_multiple": orbit.period_multiple, "stable": int(orbit.stable),
               "residual": orbit.residual})}

    def figures():
        import matplotlib.pyplot as plt

        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(10, 4))
        orbit.plot(axes=ax0)
        ax0.set_title(f"Periodic orbit (period {orbit.period_multiple} T) at "
                      f"{spec.frequency_hz:g} Hz", fontsize=10)
        for j, name in enumerate(names):
            ax1.plot(orbit.t, orbit.q[:, j], lw=1, label=name)
        ax1.set_xlabel("time [s]")
        ax1.set_ylabel("q [m]")
        ax1.set_title(f"max |Floquet multiplier| = {mu_max:.4f} "
                      f"({'stable' if orbit.stable else 'unstable'})", fontsize=10)
        ax1.grid(alpha=0.3)
        ax1.legend(fontsize="small")
        fig.tight_layout()
        return [("periodic_orbit.png", "Periodic orbit by shooting: phase portrait and time "
                 "history over one orbit", fig)]

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, verdict=verdict)


register_analysis("periodic_orbit", PeriodicOrbitAnalysis, run_periodic_orbit, check=_check,
                  description="periodic orbit by shooting through exact stick-slip, "
                              "Floquet multipliers (Coulomb contacts)")
