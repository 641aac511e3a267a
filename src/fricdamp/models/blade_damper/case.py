"""Paper 000's blade-damper model as a case: ``[model] type = "blade_damper"`` with
``[analysis.eigenfrequencies]``, ``[analysis.time_response]`` (000 Fig. 8),
``[analysis.pulloff_curves]`` (Figs 9-11) and ``[analysis.damper_design]`` (Fig. 12), plus
``[analysis.blade_resonance]`` (one design's resonant blade amplitude: the scalar a design sweep
or optimisation needs).

Summary contract (issue 3), top-level keys::

    pulloff: [{"gamma_deg", "F_Z_N", "frequency_hz": [...], "F_e_limit_N": [...],
               "stuck_eigenfrequencies_hz": [...]}, ...]          (one per (gamma, F_Z) pair)
    design: {"damper_mass_kg": [...], "gamma_deg": [...], "blade_amplitude_m": [[...]],
             "optimum": {"damper_mass_kg", "gamma_deg", "blade_amplitude_m"},
             "optimum_on_validity_boundary": bool,                        (issue 14)
             "validity_boundary": [{"damper_mass_kg", "gamma_valid_deg",
                                    "gamma_invalid_deg", ...}, ...],      (one per mass)
             "release": bool, "restitution", "n_released_designs",         (issue 14)
             "optimum_with_release": {..., "beyond_lift_off": bool}}

and in the ``time_response`` section (issue 14): ``period_multiple``, ``stable``,
``cpu_s_per_period`` and ``orbit`` (the steady periodic orbit by shooting).

The model object is a :class:`~fricdamp.models.blade_damper.model.BladeDamperSystem` (set-valued
Coulomb friction at two contacts, integrated by the exact event-driven solver); its contacts
are part of the model. Keys are documented in ``docs/cases_blade_damper.md``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import NonNegative, Positive, Section
from fricdamp.errors import CaseError, ModelError
from fricdamp.registry import (
    AnalysisOutput,
    BuildContext,
    ModelObject,
    RunContext,
    register_analysis,
    register_model,
)
from fricdamp.verdict import judge

MODEL_TYPE = "blade_damper"
_ANALYSES = ("[analysis.eigenfrequencies], [analysis.time_response], [analysis.pulloff_curves], "
             "[analysis.damper_design] and [analysis.blade_resonance]")

Four = Annotated[list[float], Field(min_length=4, max_length=4)]
Angle = Annotated[float, Field(gt=0, lt=90)]


# ================================================================================ the model
class BladeDamperModel(Section):
    """``[model] type = "blade_damper"``: two blades (two masses each) and a damper between
    their platforms (000 Fig. 6). Defaults: the documented lab-rig assumptions of
    :class:`~fricdamp.models.blade_damper.model.BladeDamperParameters`."""

    masses_kg: Four = Field([0.30, 0.15, 0.30, 0.165], description="m1..m4")
    stiffnesses_N_per_m: Four = Field([7.2e4, 2.3e4, 8.6e4, 2.6e4], description="k1..k4")
    dampings_Ns_per_m: Four = Field([2.9, 1.2, 3.2, 1.3], description="d1..d4")
    damper_mass_kg: Positive = Field(1.0e-3, description="damper mass m_D")
    damper_gyration_radius_m: Positive = Field(4.0e-3, description="I_D = m_D r_g^2")
    gamma_deg: Angle = Field(50.0, description="block angle gamma")
    p1_per_m: float = Field(-80.0, lt=0, description="contour eta = p1 xi^2 + p2")
    p2_m: Positive = Field(2.0e-3, description="apex height of the contour")
    contour: Literal["parabola", "circle"] = Field("parabola", description="contour shape")
    mu_static: NonNegative = Field(0.35, description="static friction coefficient")
    mu_sliding: NonNegative = Field(0.30, description="sliding friction coefficient")
    centrifugal_force_N: Positive | None = Field(
        None, description="F_Z (default 100 N unless centrifugal_acceleration is given)")
    centrifugal_acceleration_m_per_s2: Positive | None = Field(
        None, description="F_Z = m_D a_c (a rotor: the force grows with the damper mass)")
    excitation_amplitude_N: NonNegative = Field(1.0, description="F_e of F_E1 = F_e cos(Omega t)")
    excitation_ratio: NonNegative = Field(1.0, description="F_E2 = ratio F_e cos(Omega t + phi)")
    excitation_phase_deg: float = Field(90.0, ge=-360, le=360, description="phi")
    excitation_frequency_hz: Positive = Field(60.0, description="f_e = Omega / 2 pi")

    @model_validator(mode="after")
    def _checks(self):
        if self.mu_sliding > self.mu_static:
            raise ValueError(f"mu_sliding must not exceed mu_static (0 <= mu_sliding <= "
                             f"mu_static), got {self.mu_sliding} > {self.mu_static}")
        if self.centrifugal_force_N is not None and \
                self.centrifugal_acceleration_m_per_s2 is not None:
            raise ValueError("give centrifugal_force_N or centrifugal_acceleration_m_per_s2, "
                             "not both")
        if any(m <= 0 for m in self.masses_kg) or any(k <= 0 for k in self.stiffnesses_N_per_m):
            raise ValueError("masses_kg and stiffnesses_N_per_m must be > 0")
        if any(d < 0 for d in self.dampings_Ns_per_m):
            raise ValueError("dampings_Ns_per_m must be >= 0")
        return self


def blade_damper_parameters(spec: BladeDamperModel):
    """:class:`BladeDamperParameters` of a ``[model]`` table."""
    from fricdamp.models.blade_damper.model import BladeDamperParameters

    if spec.centrifugal_acceleration_m_per_s2 is not None:
        fz = spec.damper_mass_kg * spec.centrifugal_acceleration_m_per_s2
    else:
        fz = 100.0 if spec.centrifugal_force_N is None else spec.centrifugal_force_N
    return BladeDamperParameters(
        masses=tuple(spec.masses_kg), stiffnesses=tuple(spec.stiffnesses_N_per_m),
        dampings=tuple(spec.dampings_Ns_per_m), damper_mass=spec.damper_mass_kg,
        damper_gyration_radius=spec.damper_gyration_radius_m,
        gamma=float(np.deg2rad(spec.gamma_deg)), p1=spec.p1_per_m, p2=spec.p2_m,
        contour=spec.contour, mu_static=spec.mu_static, mu_sliding=spec.mu_sliding,
        centrifugal_force=fz, excitation_amplitude=spec.excitation_amplitude_N,
        excitation_ratio=spec.excitation_ratio,
        excitation_phase=float(np.deg2rad(spec.excitation_phase_deg)),
        excitation_frequency=spec.excitation_frequency_hz)


@dataclass(frozen=True, eq=False)
class BladeDamperCaseModel(ModelObject):
    """The model object of ``[model] type = "blade_damper"``."""

    params: Any
    n_dof: ClassVar[int] = 7
    names: ClassVar[tuple[str, ...]] = ("q1", "q2", "q3", "q4", "q5", "x_S", "y_S")
    MODEL_TYPE: ClassVar[str] = MODEL_TYPE
    MODEL_DESCRIPTION: ClassVar[str] = "paper 000's blades with a friction damper"
    MODEL_ANALYSES: ClassVar[str] = _ANALYSES

    def describe(self) -> dict:
        from fricdamp.models.blade_damper.studies import (
            sliding_eigenfrequencies,
            stuck_eigenfrequencies,
        )

        p = self.params
        return {"n_dof": 7, "dof_names": list(self.names), "contacts": [
                    {"name": "K1", "law": "Coulomb (set-valued)"},
                    {"name": "K2", "law": "Coulomb (set-valued)"}],
                "gamma_deg": p.gamma_deg, "F_Z_N": p.centrifugal_force,
                "damper_mass_kg": p.damper_mass,
                "stuck_eigenfrequencies_hz": stuck_eigenfrequencies(p).tolist(),
                "sliding_eigenfrequencies_hz": sliding_eigenfrequencies(p).tolist()}


def build_blade_damper_case(spec: BladeDamperModel, ctx: BuildContext) -> BladeDamperCaseModel:
    return BladeDamperCaseModel(blade_damper_parameters(spec))


register_model(MODEL_TYPE, BladeDamperModel, build_blade_damper_case,
               description="paper 000: two blades and a friction damper (exact stick-slip)")


def _model(obj) -> BladeDamperCaseModel:
    if not isinstance(obj, BladeDamperCaseModel):
        raise CaseError(f"this analysis needs [model] type = {MODEL_TYPE!r}")
    return obj


def _params(obj, spec):
    """The model's parameters with the section's excitation overrides applied (the optional
    ``excitation_amplitude_N`` and ``excitation_frequency_hz`` keys of the section)."""
    ch = {}
    if getattr(spec, "excitation_amplitude_N", None) is not None:
        ch["excitation_amplitude"] = spec.excitation_amplitude_N
    if getattr(spec, "excitation_frequency_hz", None) is not None:
        ch["excitation_frequency"] = spec.excitation_frequency_hz
    p = _model(obj).params
    return p.with_(**ch) if ch else p


def _check(obj, spec) -> None:
    _model(obj)


# ============================================================================ eigenfrequencies
class Eigenfrequencies(Section):
    """``[analysis.eigenfrequencies]``: the fully stuck 3-DOF system and the free-sliding
    linearisation (no keys)."""


def run_eigenfrequencies(obj, spec: Eigenfrequencies, ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.blade_damper.studies import (
        sliding_eigenfrequencies,
        stuck_eigenfrequencies,
    )

    p = _model(obj).params
    fs = stuck_eigenfrequencies(p)
    fl = sliding_eigenfrequencies(p)
    summary = {"stuck_eigenfrequencies_hz": fs.tolist(),
               "sliding_eigenfrequencies_hz": [None if not np.isfinite(x) else float(x)
                                               for x in fl]}
    return AnalysisOutput(summary=summary, headline=(
        "stuck: " + ", ".join(f"{x:.4g}" for x in fs) + " Hz; sliding: "
        + ", ".join(f"{x:.4g}" for x in fl if np.isfinite(x)) + " Hz"))


# ============================================================================ time response
class TimeResponseAnalysis(Section):
    """``[analysis.time_response]``: event-driven stick-slip response and its steady periodic
    orbit by shooting (000 Fig. 8)."""

    periods: Positive = Field(30.0, le=10_000, description="excitation periods simulated")
    samples_per_period: int = Field(200, ge=8, le=100_000, description="output samples")
    excitation_amplitude_N: NonNegative | None = Field(
        None, description="overrides [model] excitation_amplitude_N")
    excitation_frequency_hz: Positive | None = Field(
        None, description="overrides [model] excitation_frequency_hz")
    phase_plot_periods: Positive = Field(5.0, description="last periods shown in the phase plot")
    max_orbit_periods: int = Field(
        400, ge=10, le=100_000,
        description="transient budget [periods] of the search for the steady periodic orbit")


def run_time_response(obj, spec: TimeResponseAnalysis, ctx: RunContext) -> AnalysisOutput:
    import xarray as xr

    from fricdamp.models.blade_damper.orbits import steady_orbit
    from fricdamp.models.blade_damper.studies import CONFIGURATIONS, time_response

    p = _params(obj, spec)
    t0 = time.perf_counter()
    c0 = time.process_time()
    tr = time_response(p, spec.periods, samples_per_period=spec.samples_per_period)
    cpu_run = time.process_time() - c0
    r = tr.result
    T = 1.0 / p.excitation_frequency
    last = r.t >= r.t[-1] - T
    q4 = r.q[last, 3]
    last_amp = float(0.5 * (q4.max() - q4.min()))
    # the steady state the run approaches: its periodic orbit by shooting, continued from
    # the run's end state (000 Fig. 8 shows a closed orbit)
    so = None
    if tr.ok:
        so = steady_orbit(p, y0=np.concatenate([r.q[-1], r.qd[-1]]), t_start=float(r.t[-1]),
                          max_periods=spec.max_orbit_periods)
    periodic = bool(so is not None and so.periodic)
    notes = [f"model assumption violated: {e}" for e in tr.errors]
    summary = {
        "excitation_amplitude_N": p.excitation_amplitude,
        "excitation_frequency_hz": p.excitation_frequency,
        "blade_amplitude_m": float(so.amplitude_m) if periodic else last_amp,
        "last_period_amplitude_m": last_amp,
        "period_multiple": int(so.period_multiple) if periodic else 0,
        "stable": bool(periodic and so.stable),
        "cpu_s_per_period": cpu_run / spec.periods,
        "orbit": None if so is None else so.summary(),
        "time_in_configuration_s": {k: float(v) for k, v in tr.time_in_configuration.items()},
        "n_events": len(r.events),
        "min_normal_force_N": float(tr.min_normal_force),
        "energy_balance_error": float(r.energy_balance_error),
        "errors": list(tr.errors) + ([] if so is None else list(so.errors)),
        "solver_runtime_s": time.perf_counter() - t0,
    }
    ds = r.to_xarray() if hasattr(r, "to_xarray") else xr.Dataset()
    orbit_text = (f"steady orbit of period {so.period_multiple} T, "
                  f"{'stable' if so.stable else 'unstable'}, q4 amplitude {so.amplitude_m:.3g} m"
                  if periodic else "no stable periodic orbit found")
    headline = (f"{spec.periods:g} periods at {p.excitation_frequency:g} Hz, F_e = "
                f"{p.excitation_amplitude:g} N: {len(r.events)} events; {orbit_text}; "
                f"energy balance {summary['energy_balance_error']:.1e}")

    def figures():
        from fricdamp import plot

        t, x, xd = tr.phase_plot(3, spec.phase_plot_periods)
        fig, axes = plot.new_figure(1, 2, width=10.0, height=3.8,
                                    title="Blade 2 (q4): phase plot (000 Fig. 8) and contact "
                                          "configurations")
        ax1, ax2 = axes[0]
        fa, la = plot.si_scale(x, "m")
        fv, lv = plot.si_scale(xd, "m/s")
        ax1.plot(x / fa, xd / fv, lw=0.6, color="0.6",
                 label=f"last {spec.phase_plot_periods:g} periods of the run")
        if periodic and so.orbit is not None:
            o = so.orbit
            ax1.plot(o.q[:, 3] / fa, o.qd[:, 3] / fv, lw=1.4, color="C3",
                     label=f"periodic orbit ({so.period_multiple} T, "
                           f"{'stable' if so.stable else 'unstable'})")
        ax1.set_xlabel(f"q4 [{la}]")
        ax1.set_ylabel(f"dq4/dt [{lv}]")
        ax1.legend(fontsize="small")
        ax2.step(r.t, tr.configuration, where="post", lw=0.8)
        ax2.set_yticks(range(len(CONFIGURATIONS)), CONFIGURATIONS)
        ax2.set_xlabel("time [s]")
        ax2.set_ylabel("contacts K1/K2")
        return [("time_response.png", "Phase plot of blade 2: the run and its periodic orbit "
                 "by shooting; contact configurations (stick/slip of K1 and K2) over time",
                 fig)]

    # a solver that stopped is a failure; a negative normal force (the no-separation model
    # violated, e.g. when the complementarity solver fails) makes every number unreliable;
    # so does a steady state that is not a converged, stable periodic orbit
    failed = next((e for e in tr.errors if e.startswith("solver:")), None)
    reasons = [f"{e}; the response is not that of the model" for e in tr.errors
               if not e.startswith("solver:")]
    if so is not None:
        if not periodic:
            reasons.append(f"no stable periodic orbit of period multiple <= 4 within "
                           f"{spec.max_orbit_periods} periods: the response beats (not "
                           "periodic); blade_amplitude_m is the last period's")
        elif not so.converged:
            reasons.append(f"the periodic orbit did not converge (residual {so.residual:.2g}); "
                           "increase max_orbit_periods")
        reasons.extend(f"steady orbit: {e}" for e in so.errors)
    verdict = judge({"energy_balance_error": summary["energy_balance_error"],
                     "min_normal_force_N": summary["min_normal_force_N"]},
                    reasons=reasons, failed=failed)
    return AnalysisOutput(summary=summary, arrays={"response": ds}, figures=figures,
                          headline=headline, notes=notes, verdict=verdict)


# ============================================================================ pull-off
class PulloffCurves(Section):
    """``[analysis.pulloff_curves]``: pull-off amplitude vs frequency (000 Figs 9-11)."""

    gammas_deg: list[Angle] = Field([40.0, 50.0, 60.0], min_length=1, description="gamma")
    centrifugal_forces_N: list[Positive] = Field([60.0, 100.0, 140.0], min_length=1,
                                                 description="F_Z")
    frequency_start_hz: Positive = Field(10.0, description="start of the frequency range")
    frequency_end_hz: Positive = Field(250.0, description="end of the frequency range")
    n_frequencies: int = Field(961, ge=2, le=100_000, description="frequencies (linear grid)")
    confirm_at_hz: list[Positive] = Field(
        [], description="frequencies where event-driven runs just below and above the limit "
                        "confirm it (model's gamma and F_Z)")
    confirm_margin: float = Field(0.02, gt=0, lt=0.5, description="relative margin of those runs")

    @model_validator(mode="after")
    def _range(self):
        if self.frequency_end_hz <= self.frequency_start_hz:
            raise ValueError("frequency_end_hz must be > frequency_start_hz")
        return self


def run_pulloff(obj, spec: PulloffCurves, ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.blade_damper.studies import confirm_pulloff, pulloff_curves

    p = _model(obj).params
    f = np.linspace(spec.frequency_start_hz, spec.frequency_end_hz, spec.n_frequencies)
    curves = pulloff_curves(p, spec.gammas_deg, spec.centrifugal_forces_N, frequency_hz=f)
    checks = []
    for fc in spec.confirm_at_hz:
        c = confirm_pulloff(p, fc, margin=spec.confirm_margin)
        checks.append({"frequency_hz": c.frequency_hz, "F_e_limit_N": c.F_e_limit_N,
                       "slipped_below": bool(c.slipped[0]), "slipped_above": bool(c.slipped[1]),
                       "confirmed": bool(not c.slipped[0] and c.slipped[1])})
    notes = [f"event-driven runs do not confirm the pull-off limit at {c['frequency_hz']:g} Hz"
             for c in checks if not c["confirmed"]]
    summary = {"n_curves": len(curves), "gammas_deg": list(spec.gammas_deg),
               "centrifugal_forces_N": list(spec.centrifugal_forces_N),
               "confirmations": checks,
               "min_F_e_limit_N": [float(np.min(c["F_e_limit_N"])) for c in curves]}
    headline = (f"{len(curves)} curves over {f[0]:g}-{f[-1]:g} Hz; "
                f"{sum(c['confirmed'] for c in checks)}/{len(checks)} limits confirmed by "
                "event-driven runs")

    def figures():
        from fricdamp import plot

        gam = list(dict.fromkeys(c["gamma_deg"] for c in curves))
        fig, axes = plot.new_figure(1, len(gam), width=4.2 * len(gam), height=3.8,
                                    title="Pull-off amplitude F_e,limit (000 Figs 9-11)")
        for ax, g in zip(axes[0], gam, strict=True):
            for c in (c for c in curves if c["gamma_deg"] == g):
                ax.semilogy(c["frequency_hz"], c["F_e_limit_N"], lw=1,
                            label=f"F_Z = {c['F_Z_N']:g} N")
            first = next(c for c in curves if c["gamma_deg"] == g)
            for fe in first["stuck_eigenfrequencies_hz"]:
                ax.axvline(fe, color="0.6", lw=0.6, ls=":")
            ax.set_title(f"gamma = {g:g} deg", fontsize="small")
            ax.set_xlabel("excitation frequency [Hz]")
            ax.set_ylabel("F_e,limit [N]")
            ax.legend(fontsize="small")
        return [("pulloff.png", "Pull-off amplitude vs excitation frequency; dotted: stuck "
                 "eigenfrequencies", fig)]

    verdict = judge({"unconfirmed_limits": sum(not c["confirmed"] for c in checks)},
                    reasons=[f"the event-driven runs around the pull-off limit at "
                             f"{c['frequency_hz']:g} Hz do not confirm it (slip below: "
                             f"{c['slipped_below']}, above: {c['slipped_above']})"
                             for c in checks if not c["confirmed"]])
    return AnalysisOutput(summary=summary, figures=figures, headline=headline, notes=notes,
                          top_level={"pulloff": curves}, verdict=verdict)


# ============================================================================ design
class DamperDesign(Section):
    """``[analysis.damper_design]``: resonant blade amplitude over damper mass and gamma
    (000 Fig. 12)."""

    damper_masses_kg: list[Positive] = Field([0.5e-3, 1e-3, 2e-3], min_length=1,
                                             description="damper masses")
    gammas_deg: list[Angle] = Field([50.0, 65.0], min_length=1, description="block angles")
    parabolas: list[Annotated[list[float], Field(min_length=2, max_length=2)]] | None = Field(
        None, description="[p1 (1/m), p2 (m)] pairs; default the model's")
    n_frequencies: int = Field(6, ge=2, le=200, description="stepped-sine frequencies")
    resolution_hz: Positive | None = Field(
        0.25, description="frequency resolution of the peak search around each resonance "
                          "(None: no search)")
    boundary_refinements: int = Field(
        3, ge=0, le=12, description="bisection steps on gamma towards the lift-off boundary "
                                    "per damper mass (0: none)")
    centrifugal_acceleration_m_per_s2: Positive | None = Field(
        None, description="F_Z = m_D a_c (default: the model's F_Z / m_D)")
    excitation_amplitude_N: Positive | None = Field(
        None, description="overrides [model] excitation_amplitude_N")
    workers: int = Field(1, ge=1, le=256, description="processes running the designs (the "
                                                      "number of cores; same results)")
    release: bool = Field(
        False, description="recompute the designs that lift off with the released model "
                           "(damper lift-off and impacts) instead of discarding them")
    restitution: float = Field(
        0.0, ge=0, le=1, description="restitution coefficient (0..1) of the damper-platform "
                                     "impacts (with release)")

    @model_validator(mode="after")
    def _restitution_needs_release(self):
        if self.restitution != 0 and not self.release:
            raise ValueError("restitution applies only with release = true (without it the "
                             "damper never lifts off, so it never impacts)")
        return self


def run_design(obj, spec: DamperDesign, ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.blade_damper.studies import default_design_band, design_study

    p = _params(obj, spec)
    if spec.parabolas is not None:
        for p1, p2 in spec.parabolas:
            if not (p1 < 0 < p2):
                raise CaseError(f"[analysis.damper_design] parabolas: each pair must have "
                                f"p1 < 0 1/m and p2 > 0 m, got [{p1}, {p2}]")
    t0 = time.perf_counter()
    f = default_design_band(p, spec.n_frequencies)
    bar = None
    if ctx.progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(spec.damper_masses_kg) * len(spec.gammas_deg)
                   * len(spec.parabolas or [None]), desc="damper designs", unit="design",
                   leave=False)
    try:
        d = design_study(p, spec.damper_masses_kg, spec.gammas_deg,
                         [tuple(x) for x in spec.parabolas] if spec.parabolas else None,
                         frequency_hz=f, resolution_hz=spec.resolution_hz,
                         centrifugal_acceleration=spec.centrifugal_acceleration_m_per_s2,
                         boundary_refinements=spec.boundary_refinements,
                         workers=spec.workers, release=spec.release,
                         restitution=spec.restitution,
                         progress=None if bar is None else _progress(bar))
    finally:
        if bar is not None:
            bar.close()
    design = d.to_dict()
    opt = design["optimum"]
    notes = [f"design point: {e}" for e in design.get("errors", [])][:10]
    n_refined = sum(len(b["refined"]) for b in design["validity_boundary"])
    summary = {"optimum": opt, "n_designs": int(np.size(d.blade_amplitude_m)),
               "n_valid_designs": int(np.sum(d.valid)),
               "n_boundary_designs": n_refined,
               "optimum_on_validity_boundary": design["optimum_on_validity_boundary"],
               "validity_boundary": [{k: b[k] for k in ("p1_per_m", "p2_m", "damper_mass_kg",
                                                        "gamma_valid_deg", "gamma_invalid_deg")}
                                     for b in design["validity_boundary"]],
               "converged": design["converged"],
               "n_nonperiodic_steady_states": design["n_nonperiodic_steady_states"],
               "excitation_amplitude_N": p.excitation_amplitude,
               "release": design["release"], "restitution": design["restitution"],
               "n_released_designs": design["n_released_designs"],
               "optimum_with_release": design["optimum_with_release"],
               "runtime_s_solver": time.perf_counter() - t0}
    headline = (f"{summary['n_designs']} designs + {n_refined} on the lift-off boundary; "
                f"smallest resonant blade amplitude {opt['blade_amplitude_m']:.3g} m at m_D = "
                f"{opt['damper_mass_kg']:g} kg, gamma = {opt['gamma_deg']:.4g} deg"
                + (" (on the lift-off boundary)" if summary["optimum_on_validity_boundary"]
                   else ""))
    best = design["optimum_with_release"]
    if spec.release and best["beyond_lift_off"]:
        headline += (f"; beyond lift-off {best['blade_amplitude_m']:.3g} m at m_D = "
                     f"{best['damper_mass_kg']:g} kg, gamma = {best['gamma_deg']:.4g} deg "
                     "(damper rattles)")

    def figures():
        from fricdamp import plot

        A = np.asarray(design["blade_amplitude_m"], float)
        fig, axes = plot.new_figure(title="Damper design (000 Fig. 12): resonant amplitude of "
                                          "blade 2")
        ax = axes[0, 0]
        fa, la = plot.si_scale(A, "m")
        ok = np.asarray(design["parabolas"][0]["valid"], bool)
        rel = np.asarray(design["parabolas"][0]["released"], bool)
        mg = np.asarray(design["damper_mass_kg"]) * 1e3
        for j, g in enumerate(design["gamma_deg"]):
            (line,) = ax.plot(mg, np.where(ok[:, j], A[:, j], np.nan) / fa, "o-", ms=4,
                              label=f"gamma = {g:g} deg")
            bad = ~ok[:, j] & ~rel[:, j] & np.isfinite(A[:, j])
            if bad.any():
                ax.plot(mg[bad], A[bad, j] / fa, "x", color=line.get_color(), ms=7)
            if rel[:, j].any():  # beyond lift-off, computed with the released model
                ax.plot(mg[rel[:, j]], A[rel[:, j], j] / fa, "^", mfc="none", ms=7,
                        color=line.get_color())
        if rel.any():
            ax.plot([], [], "k^", mfc="none", label="beyond lift-off (released model)")
        if not (ok | rel).all():
            ax.plot([], [], "kx", label="invalid (damper lifts off or solver failed)")
        bnd = [b for b in design["validity_boundary"]
               if b["p1_per_m"] == design["parabolas"][0]["p1_per_m"]
               and b["p2_m"] == design["parabolas"][0]["p2_m"]
               and b["gamma_invalid_deg"] is not None and b["blade_amplitude_m"] is not None]
        if bnd:
            ax.plot([b["damper_mass_kg"] * 1e3 for b in bnd],
                    [b["blade_amplitude_m"] / fa for b in bnd], "s--", color="k", ms=5,
                    mfc="none", lw=0.8, label="largest gamma without lift-off")
        ax.plot(opt["damper_mass_kg"] * 1e3, opt["blade_amplitude_m"] / fa, "k*", ms=12,
                label="optimum")
        ax.set_xlabel("damper mass [g]")
        ax.set_ylabel(f"resonant q4 amplitude [{la}]")
        ax.legend(fontsize="small")
        return [("design.png", "Resonant blade amplitude vs damper mass and block angle", fig)]

    n_bad = summary["n_designs"] - summary["n_valid_designs"]
    reasons = [] if summary["n_valid_designs"] else [
        "no design point is valid (the damper lifts off or the solver failed)"]
    # a valid design with a steady state that is neither a converged periodic orbit nor a
    # stationary beating response has an uncertain resonant amplitude: the optimum is
    # unreliable when that design is the optimum or within CLOSE of it (it could be)
    shaky = _unconverged_valid_designs(design)
    opt_a = opt["blade_amplitude_m"]
    close = [(m, g, a) for m, g, a in shaky if np.isfinite(opt_a) and a <= (1 + CLOSE) * opt_a]
    if close:
        reasons.append("the optimum is uncertain: design(s) " + ", ".join(
            f"m_D = {m:g} kg, gamma = {g:.4g} deg ({a:.3g} m)" for m, g, a in close)
            + f" within {CLOSE:.0%} of the optimum have steady states that are neither "
            "converged periodic orbits nor stationary beating responses (a transient is not a "
            "steady state)")
    elif shaky:
        notes.append(f"{len(shaky)} valid design(s) have unconverged steady states (amplitude "
                     f"more than {CLOSE:.0%} above the optimum, which they cannot change): "
                     + ", ".join(f"m_D = {m:g} kg, gamma = {g:.4g} deg" for m, g, _ in shaky))
    if design["n_released_designs"]:
        notes.append(f"{design['n_released_designs']} design(s) beyond lift-off computed with "
                     f"the released model (restitution {design['restitution']:g}); they stay "
                     "invalid (the damper rattles); best over all computed designs: "
                     f"{best['blade_amplitude_m']:.3g} m at m_D = {best['damper_mass_kg']:g} "
                     f"kg, gamma = {best['gamma_deg']:.4g} deg"
                     + (" (beyond lift-off)" if best["beyond_lift_off"] else ""))
    if design["n_nonperiodic_steady_states"]:
        notes.append(f"{design['n_nonperiodic_steady_states']} stick-slip steady states have "
                     "no stable periodic orbit (beating responses, amplitude from two long "
                     "windows)")
    verdict = judge({"invalid_designs": n_bad}, reasons=reasons)
    return AnalysisOutput(summary=summary, figures=figures, headline=headline, notes=notes,
                          top_level={"design": design}, verdict=verdict)


#: Relative margin over the optimum within which an unconverged design could be the optimum.
CLOSE = 0.10


def _unconverged_valid_designs(design) -> list[tuple[float, float, float]]:
    """(damper mass, gamma, amplitude) of the valid designs (grid and boundary bisection) with
    a steady state that did not converge."""
    out = []
    for par in design["parabolas"]:
        for i, m in enumerate(design["damper_mass_kg"]):
            for j, g in enumerate(design["gamma_deg"]):
                if par["valid"][i][j] and not par["converged"][i][j]:
                    out.append((m, g, float(par["blade_amplitude_m"][i][j])))
    for b in design["validity_boundary"]:
        out.extend((b["damper_mass_kg"], r["gamma_deg"], r["blade_amplitude_m"])
                   for r in b["refined"] if r["valid"] and not r["converged"])
    return out


def _progress(bar):
    def update(done, total):
        bar.total = total
        bar.update(done - bar.n)
    return update


# ============================================================================ one design
class BladeResonance(Section):
    """``[analysis.blade_resonance]``: largest steady amplitude of blade 2 over a stepped
    sine across the band of the first two modes (one point of a design study)."""

    n_frequencies: int = Field(6, ge=2, le=200, description="stepped-sine frequencies")
    resolution_hz: Positive | None = Field(
        0.25, description="frequency resolution of the peak search around the resonance "
                          "(None: no search)")
    excitation_amplitude_N: Positive | None = Field(
        None, description="overrides [model] excitation_amplitude_N")


def run_blade_resonance(obj, spec: BladeResonance, ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.blade_damper.studies import default_design_band, resonance_amplitude

    p = _params(obj, spec)
    f = default_design_band(p, spec.n_frequencies)
    r = resonance_amplitude(p, f, resolution_hz=spec.resolution_hz)
    summary = {"blade_amplitude_m": float(r["peak_amplitude_m"]),
               "peak_frequency_hz": float(r["peak_hz"]),
               "damper_mass_kg": p.damper_mass, "gamma_deg": p.gamma_deg,
               "F_Z_N": p.centrifugal_force,
               "frequency_hz": np.asarray(r["frequency_hz"]).tolist(),
               "amplitude_m": np.asarray(r["amplitude_m"]).tolist(),
               "converged": bool(np.all(r["converged"]) and r["all_converged"])}
    if r["errors"]:
        raise ModelError("; ".join(r["errors"][:3]))
    verdict = judge({}, reasons=[] if summary["converged"] else
                    ["some stepped-sine points did not reach a steady state (a converged, "
                     "stable periodic orbit)"])
    return AnalysisOutput(summary=summary, verdict=verdict, headline=(
        f"resonant blade amplitude {summary['blade_amplitude_m']:.3g} m at "
        f"{summary['peak_frequency_hz']:.4g} Hz"))


register_analysis("eigenfrequencies", Eigenfrequencies, run_eigenfrequencies, check=_check,
                  description="stuck and free-sliding eigenfrequencies (paper 000)")
register_analysis("time_response", TimeResponseAnalysis, run_time_response, check=_check,
                  description="event-driven stick-slip response, phase plot (paper 000)")
register_analysis("pulloff_curves", PulloffCurves, run_pulloff, check=_check,
                  description="pull-off amplitude vs frequency (paper 000 Figs 9-11)")
register_analysis("damper_design", DamperDesign, run_design, check=_check,
                  description="resonant blade amplitude over damper mass and gamma (Fig. 12)")
register_analysis("blade_resonance", BladeResonance, run_blade_resonance, check=_check,
                  description="resonant blade amplitude of one damper design (paper 000)")
