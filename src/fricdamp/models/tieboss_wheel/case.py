"""Paper 003's bladed wheel with tie-boss contacts as a case: ``[model] type = "tieboss_wheel"``
with ``[analysis.modal]`` (Table 1), ``[analysis.campbell_by_nd]`` (Campbell diagram and
critical speeds 003 (1), Table 2), ``[analysis.free_attenuation]`` (the paper's damping
strategy, Figs 13-19) and ``[analysis.reduction_comparison]`` (full-order against
Craig-Bampton transients).

The model is not a :class:`~fricdamp.structure.MechanicalSystem` but a
:class:`TiebossWheelCaseModel`: the tuned beam sector of
:mod:`fricdamp.models.tieboss_wheel.model` (30 blades, tie-bosses at r = 0.44 m, contact planes at
45 degrees, 12 degrees apart) from which the analyses build the cyclic, full and reduced
wheels. Its 30 contacts (normal penalty with the prestressing offset, separation, 2D Coulomb
friction with mu(v) of 003 (2)) are part of the model, so ``[[contacts]]`` are refused and the
generic analyses that need a MechanicalSystem get a clear CaseError.

Summary contract (issue 7)::

    modal: {"nd": [0, 1, ..., 15], "frequency_hz": [...], ...}      (the section of modal)
    decay: [{"nd": 2, "damping_ratio", "initial_amplitude_m", "runtime_s", ...},
            {"nd": 6, ...}]                          (top level, from free_attenuation)
    critical_speeds_rpm: [{"order", "frequency_hz", "rpm", ...}, ...]
                                                     (top level, from campbell_by_nd)
    reduction: {"full_dof", "reduced_dof", "damping_ratio_difference", ...}
                                                     (top level, from reduction_comparison)

Issue 17 (the rig test, :mod:`fricdamp.models.tieboss_wheel._case_forced`)::

    engine_order_map: [{"order", "nd", "rule", "excited_nds", ...}]   (excitation_orders)
    forced_response: [{"nd": 2, "order": 1, "rpm", "frequency_hz", "amplitude_m",
                       "dissipated_energy_J", "energy_balance_error", "peak_rpm"}, ...]
                                                     (cyclic_forced_response)
    damping_vs_amplitude: [{"nd", "amplitude_m", "damping_ratio",
                            "amplitude_definition"}, ...]            (damping_amplitude)
    mistuning: {"scatter", "amplification_factor", ...}   (mistuned_forced_response)

Summary sections are dicts, so the lists ``decay`` and ``critical_speeds_rpm`` and the dict
``reduction`` are written at the top level (:attr:`fricdamp.runner.AnalysisOutput.top_level`)
by analyses with other names, whose own sections hold their key numbers. The keys are
documented in ``docs/cases_tieboss_wheel.md``.

Layout: this module holds the model object, the analyses and their registration; the
``[model]`` table's schema is in :mod:`fricdamp.models.tieboss_wheel._case_spec` and the figures in
:mod:`fricdamp.models.tieboss_wheel._case_figures` (helpers that :mod:`fricdamp.runner` does not
auto-import; their names are importable from here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import MAX_STEPS, NonNegative, Positive, Section
from fricdamp.errors import CaseError
from fricdamp.models.tieboss_wheel._case_figures import (
    STATE_COLORS,  # noqa: F401 - re-exported
    _campbell_figures,
    _decay_figures,
    _modal_figures,
    _reduction_figures,
)
from fricdamp.models.tieboss_wheel._case_spec import (
    PAPER_DAMPING_RATIO,
    TiebossWheelSpec,
    tieboss_parameters,
)
from fricdamp.registry import (
    AnalysisOutput,
    BuildContext,
    ModelObject,
    NotAMechanicalSystemError,
    RunContext,
    register_analysis,
    register_model,
)

__all__ = [
    "CampbellByNDAnalysis",
    "FreeAttenuationAnalysis",
    "ModalAnalysis",
    "NotAMechanicalSystemError",
    "ReductionComparisonAnalysis",
    "TiebossWheelCaseModel",
    "TiebossWheelSpec",
    "build_tieboss_wheel_case",
    "run_campbell_by_nd",
    "run_free_attenuation",
    "run_modal",
    "run_reduction_comparison",
    "tieboss_parameters",
]

#: The model type and the analyses of this module (used in messages).
MODEL_TYPE = "tieboss_wheel"
_ANALYSES = ("[analysis.modal], [analysis.campbell_by_nd], [analysis.free_attenuation], "
             "[analysis.reduction_comparison], [analysis.excitation_orders], "
             "[analysis.cyclic_forced_response], [analysis.damping_amplitude] and "
             "[analysis.mistuned_forced_response]")

NodalDiameter = Annotated[int, Field(ge=0, le=1000)]
Pair = Annotated[list[Annotated[int, Field(ge=0, le=1000)]], Field(min_length=2, max_length=2)]


# ================================================================================ the model
@dataclass(frozen=True, eq=False)
class TiebossWheelCaseModel(ModelObject):
    """The model object of ``[model] type = "tieboss_wheel"``.

    Attributes
    ----------
    sector : TiebossSector
        The beam sector with its rotation terms (:func:`~fricdamp.models.tieboss_wheel.model.
        build_sector`); ``sector.parameters`` are the wheel's parameters (the calibrated
        penalty included).
    calibrated : bool
        Whether the normal penalty was calibrated for ``contact_preload_N``.
    """

    sector: Any
    calibrated: bool = False
    _wheels: dict = field(default_factory=dict, repr=False)
    MODEL_TYPE: ClassVar[str] = MODEL_TYPE
    MODEL_DESCRIPTION: ClassVar[str] = "paper 003's bladed wheel with tie-boss contacts"
    MODEL_ANALYSES: ClassVar[str] = _ANALYSES

    @property
    def params(self):
        """The :class:`~fricdamp.models.tieboss_wheel.model.TiebossWheelParameters`."""
        return self.sector.parameters

    @property
    def n_blades(self) -> int:
        return int(self.params.n_blades)

    @property
    def max_nd(self) -> int:
        """Largest nodal diameter, ``N // 2``."""
        return self.n_blades // 2

    def wheel(self, n_modes: int | None = None):
        """The full wheel (``n_modes=None``) or the Craig-Bampton wheel with ``n_modes``
        fixed-interface modes per sector (:func:`~fricdamp.models.tieboss_wheel.model.build_wheel`),
        built once."""
        from fricdamp.models.tieboss_wheel.model import build_wheel

        key = None if n_modes is None else int(n_modes)
        if key not in self._wheels:
            self._wheels[key] = build_wheel(self.sector, n_modes=key)
        return self._wheels[key]

    @property
    def n_dof(self) -> int:
        """DOFs of the full wheel (N x the independent DOFs of a sector)."""
        return int(self.n_blades * self.sector.cyclic.n_independent)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.wheel().system.names)

    def describe(self) -> dict:
        """Key numbers for summary.json ``model``: layout, contacts and the prestress."""
        from fricdamp.models.tieboss_wheel.model import prestress_normal_force

        p = self.params
        a, b = p.rayleigh()
        return {
            "type": MODEL_TYPE,
            "n_dof": self.n_dof,
            "n_blades": self.n_blades,
            "sector_dof": int(self.sector.cyclic.n_dof),
            "sector_independent_dof": int(self.sector.cyclic.n_independent),
            "nodal_diameters": [0, self.max_nd],
            "sector_angle_deg": 360.0 / self.n_blades,
            "contacts": [{"name": "tieboss", "law": "Contact3D: normal penalty with offset, "
                          "separation, 2D Coulomb friction with mu(v) of 003 (2)",
                          "n_contacts": self.n_blades, "n_dir": 3}],
            "normal_stiffness_N_per_m": p.normal_stiffness_N_per_m,
            "tangential_stiffness_N_per_m": p.tangential_stiffness,
            "normal_stiffness_calibrated": self.calibrated,
            "prestress_normal_force_N": prestress_normal_force(self.wheel()),
            "contact_offset_m": p.contact_offset_m,
            "rayleigh_alpha_per_s": a,
            "rayleigh_beta_s": b,
            "flexural_direction": self.sector.flexural_direction.tolist(),
            "contact_frame": self.sector.frame.tolist(),
        }


def build_tieboss_wheel_case(spec: TiebossWheelSpec, ctx: BuildContext) -> TiebossWheelCaseModel:
    """Builder of ``[model] type = "tieboss_wheel"`` (raises ModelError)."""
    from fricdamp.models.tieboss_wheel.model import build_sector, calibrate_normal_stiffness

    p = tieboss_parameters(spec)
    if spec.calibrate_normal_stiffness:
        p = p.with_(normal_stiffness_N_per_m=calibrate_normal_stiffness(p))
    return TiebossWheelCaseModel(build_sector(p, rotation=True),
                                 calibrated=spec.calibrate_normal_stiffness)


def _require_model(model, table: str) -> TiebossWheelCaseModel:
    if not isinstance(model, TiebossWheelCaseModel):
        raise CaseError(f"{table} needs [model] type = {MODEL_TYPE!r} (paper 003's bladed "
                        "wheel)")
    return model


def _check_nds(model: TiebossWheelCaseModel, key: str, nds) -> None:
    bad = [nd for nd in nds if nd > model.max_nd]
    if bad:
        raise CaseError(f"{key} = {list(nds)}: ND {bad[0]} does not exist; a wheel of "
                        f"{model.n_blades} blades has nodal diameters 0 to {model.max_nd}")


def _solver_notes(ctx: RunContext) -> tuple[str, list[str]]:
    """Integrator of the transients from ``[solver]`` and notes on the settings not used."""
    s = ctx.solver
    notes = []
    if s.method == "hht" and s.alpha != -0.05:
        notes.append(f"[solver] alpha = {s.alpha:g} is not used: the wheel's transients run "
                     "HHT with alpha = -0.05")
    if s.tol != 1e-10 or s.max_iter != 30:
        notes.append("[solver] tol and max_iter are not used: the wheel's transients use "
                     "tol = 1e-10 and 30 iterations")
    return s.method, notes


# ================================================================================ modal
class ModalAnalysis(Section):
    """``[analysis.modal]``: open-contact eigenfrequencies by nodal diameter from one sector
    with the cyclic constraint (003 section 2.2, Table 1)."""

    n_modes: int = Field(2, ge=1, le=20, description="modes per ND (the first is the blade "
                                                     "family of Table 1)")


def _solid(model):
    """The solid-wheel model object, or None (paper 003 on solid sectors shares these
    analyses: :mod:`fricdamp.models.tieboss_wheel.case_solid`)."""
    from fricdamp.models.tieboss_wheel import case_solid as solid

    return solid if solid.is_solid(model) else None


def _check_modal(model, spec: ModalAnalysis) -> None:
    if _solid(model) is None:
        _require_model(model, "[analysis.modal]")


def run_modal(model: TiebossWheelCaseModel, spec: ModalAnalysis,
              ctx: RunContext) -> AnalysisOutput:
    """Frequencies by ND (:func:`~fricdamp.models.tieboss_wheel.studies.modal_by_nd`) and the
    comparison with Table 1."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel.model import TABLE1_EXPERIMENT_HZ
    from fricdamp.models.tieboss_wheel.studies import modal_by_nd

    if (solid := _solid(model)) is not None:
        return solid.run_solid_modal(model, spec, ctx)
    obj = _require_model(model, "[analysis.modal]")
    m = modal_by_nd(obj.sector, n_modes=spec.n_modes)
    summary = {"nd": m["nd"], "frequency_hz": m["frequency_hz"], "n_modes": spec.n_modes,
               "families_hz": m["families_hz"]}
    if "table1" in m:
        summary["table1"] = m["table1"]
        summary["max_table1_error"] = m["max_table1_error"]
        summary["paper_experiment_hz"] = {str(k): list(v)
                                          for k, v in TABLE1_EXPERIMENT_HZ.items()}
    F = np.asarray(m["families_hz"])
    arrays = {"frequencies": xr.Dataset(
        {"frequency": (("nd", "mode"), F, {"units": "Hz"})},
        coords={"nd": ("nd", np.asarray(m["nd"])),
                "mode": ("mode", np.arange(1, F.shape[1] + 1))})}
    f = np.asarray(m["frequency_hz"])
    headline = (f"ND 0-{obj.max_nd}: first family {f.min():.4g}-{f.max():.4g} Hz (open "
                "contacts)")
    notes = []
    if "max_table1_error" in m:
        headline += f"; Table 1 within {100 * m['max_table1_error']:.2g} %"
        if m["max_table1_error"] > 0.01:
            notes.append(f"the first family is {100 * m['max_table1_error']:.3g} % off 003 "
                         "Table 1 (the defaults are tuned to within 0.5 %)")

    def figures():
        return _modal_figures(summary)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes)


# ================================================================================ Campbell
class CampbellByNDAnalysis(Section):
    """``[analysis.campbell_by_nd]``: first-family frequencies by ND of the rotating wheel
    (stress stiffening and spin softening), the engine-order lines ``p o n / 60`` and the
    critical speeds 003 (1) (Fig. 6, Table 2). Writes the top-level ``critical_speeds_rpm``."""

    speed_min_rpm: NonNegative = Field(60.0, le=1e5, description="lowest speed (003 run-up: "
                                                                 "60 rpm)")
    speed_max_rpm: Positive = Field(450.0, le=1e5, description="highest speed (003: 450 rpm)")
    n_speeds: int = Field(40, ge=2, le=2000, description="speeds, evenly spaced")
    pulses: int = Field(8, ge=1, le=1000, description="pulses per revolution p (003: 8)")
    orders: list[Annotated[int, Field(ge=1, le=1000)]] = Field(
        [1, 2, 3], min_length=1, max_length=20, description="orders o of the lines drawn")
    critical_pairs: list[Pair] = Field(
        [[1, 2], [3, 6]], min_length=1, max_length=50,
        description="[o, nd]: order and nodal diameter of each critical speed (003 Table 2)")

    @model_validator(mode="after")
    def _check(self):
        if self.speed_max_rpm <= self.speed_min_rpm:
            raise ValueError(f"speed_max_rpm ({self.speed_max_rpm:g} rpm) must be larger than "
                             f"speed_min_rpm ({self.speed_min_rpm:g} rpm)")
        for o, _ in self.critical_pairs:
            if o < 1:
                raise ValueError(f"critical_pairs: the order o of [{o}, nd] must be >= 1")
        if len({tuple(p) for p in self.critical_pairs}) != len(self.critical_pairs):
            raise ValueError(f"critical_pairs lists a pair twice: {self.critical_pairs}")
        return self


def _check_campbell(model, spec: CampbellByNDAnalysis) -> None:
    obj = model if _solid(model) is not None else _require_model(
        model, "[analysis.campbell_by_nd]")
    _check_nds(obj, "critical_pairs", [nd for _, nd in spec.critical_pairs])


def run_campbell_by_nd(model: TiebossWheelCaseModel, spec: CampbellByNDAnalysis,
                       ctx: RunContext) -> AnalysisOutput:
    """Campbell diagram by ND (:func:`~fricdamp.models.tieboss_wheel.studies.campbell_by_nd`) and
    the critical speeds (:func:`~fricdamp.models.tieboss_wheel.studies.critical_speeds_by_nd`)."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel.studies import (
        TABLE2_ORDERS,
        campbell_by_nd,
        critical_speeds_by_nd,
    )

    if (solid := _solid(model)) is not None:
        return solid.run_solid_campbell(model, spec, ctx)
    obj = _require_model(model, "[analysis.campbell_by_nd]")
    rpm = np.linspace(spec.speed_min_rpm, spec.speed_max_rpm, spec.n_speeds)
    camp = campbell_by_nd(obj.sector, rpm=rpm)
    pairs = [tuple(p) for p in spec.critical_pairs]
    crit = critical_speeds_by_nd(obj.sector, orders=pairs, pulses=spec.pulses,
                                 rpm_range=(spec.speed_min_rpm, spec.speed_max_rpm))
    paper = {tuple(p) for p in TABLE2_ORDERS} if obj.n_blades == 30 and spec.pulses == 8 \
        else set()
    notes = []
    for c in crit:
        if (c["order"], c["nd"]) not in paper:   # paper values only for 003's own pairs
            for k in ("paper_rpm", "paper_frequency_hz", "paper_formula_rpm"):
                c.pop(k, None)
        if c["rpm"] is None:
            notes.append(f"the {c['nd']}ND branch does not meet the line p o n / 60 (o = "
                         f"{c['order']}) between {spec.speed_min_rpm:g} and "
                         f"{spec.speed_max_rpm:g} rpm: no critical speed there")
    F = camp.frequency_hz                                     # (speed, nd)
    summary = {"rpm": rpm.tolist(), "nd": camp.nd.tolist(),
               "frequency_hz": F.T.tolist(), "pulses": spec.pulses,
               "orders": list(spec.orders), "critical_pairs": [list(p) for p in pairs],
               "frequency_change_hz": (F[-1] - F[0]).tolist(),
               "coriolis": "neglected (O(Omega / w) ~ 2 % of these flexural modes at 450 rpm)"}
    arrays = {"campbell": xr.Dataset(
        {"frequency": (("speed", "nd"), F, {"units": "Hz"})},
        coords={"rpm": ("speed", rpm, {"units": "rpm"}), "nd": ("nd", camp.nd)})}
    found = [c for c in crit if c["rpm"] is not None]
    headline = (f"{rpm.size} speeds {rpm[0]:g}-{rpm[-1]:g} rpm, {camp.nd.size} ND branches; "
                + ("; ".join(f"o = {c['order']} ({c['nd']}ND): {c['rpm']:.1f} rpm at "
                             f"{c['frequency_hz']:.2f} Hz"
                             + (f" (paper {c['paper_rpm']:g})" if "paper_rpm" in c else "")
                             for c in found) if found else "no critical speed in the range"))

    def figures():
        return _campbell_figures(camp, crit, spec)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"critical_speeds_rpm": crit})


# ================================================================================ free decay
class FreeAttenuationAnalysis(Section):
    """``[analysis.free_attenuation]``: the paper's damping strategy (003 section 3) for each
    ND on the Craig-Bampton wheel: modal forces at the tie-bosses, static solution with the
    contacts, free attenuation, envelope and log decrement. Writes the top-level ``decay``."""

    nodal_diameters: list[NodalDiameter] = Field([2, 6], min_length=1, max_length=16,
                                                 description="NDs of the modes (003: 2, 6)")
    amplitude_m: Positive = Field(5e-4, le=0.01, description="initial probe displacement "
                                                             "(003: up to 0.5 mm)")
    duration_s: Positive = Field(0.1, le=10.0, description="length of the attenuation "
                                                           "(003: 0.1 s)")
    time_step_s: Positive = Field(1e-5, le=1e-3, description="time step (003: 5e-6 s)")
    save_every: int = Field(5, ge=1, le=1000, description="store every k-th step")
    n_modes: int = Field(10, ge=0, le=200, description="fixed-interface modes per sector of "
                                                       "the Craig-Bampton wheel")
    forcing: Literal["tieboss", "modal"] = Field(
        "tieboss", description="modal forces at the tie-bosses (003) or M phi on all DOFs")
    compare_modal_forcing: bool = Field(True, description="also decay from a pure-mode start "
                                                          "(damping_ratio_modal_forcing)")

    @model_validator(mode="after")
    def _check(self):
        if len(set(self.nodal_diameters)) != len(self.nodal_diameters):
            raise ValueError(f"nodal_diameters lists an ND twice: {self.nodal_diameters}")
        _check_steps(self)
        return self


def _check_steps(spec) -> None:
    n = spec.duration_s / spec.time_step_s
    if n > MAX_STEPS:
        raise ValueError(f"duration_s / time_step_s = {n:.3g} time steps; at most "
                         f"{MAX_STEPS:.0e} are allowed")
    if n < 100:
        raise ValueError(f"duration_s / time_step_s = {n:.3g}: at least 100 time steps are "
                         "needed (003: 20,000)")
    if n / spec.save_every < 50:
        raise ValueError(f"save_every = {spec.save_every} keeps {n / spec.save_every:.3g} "
                         "samples; at least 50 are needed for the envelope")


def _check_free_attenuation(model, spec: FreeAttenuationAnalysis) -> None:
    obj = model if _solid(model) is not None else _require_model(
        model, "[analysis.free_attenuation]")
    _check_nds(obj, "nodal_diameters", spec.nodal_diameters)


def _decay_entry(run, obj: TiebossWheelCaseModel) -> dict:
    e = run.summary()
    e["paper_damping_ratio"] = PAPER_DAMPING_RATIO.get(run.nd) if obj.n_blades == 30 else None
    if run.decay is not None:
        env = run.decay.envelope
        e["envelope_time_s"] = env.time.tolist()
        e["envelope_m"] = env.amplitude.tolist()
        e["envelope_cycles"] = env.cycle.tolist()
        e["viscous_fit_damping_ratio"] = run.decay.viscous.damping_ratio
        e["coulomb_fit_decrement_per_cycle_m"] = run.decay.coulomb.decrement_per_cycle
    else:
        e["frequency_hz"] = None
    return e


def run_free_attenuation(model: TiebossWheelCaseModel, spec: FreeAttenuationAnalysis,
                         ctx: RunContext) -> AnalysisOutput:
    """Free decays of :func:`~fricdamp.models.tieboss_wheel.studies.free_decay` for each ND on the
    Craig-Bampton wheel (compiled contact integrator)."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel.studies import free_decay, modal_by_nd

    if (solid := _solid(model)) is not None:
        return solid.run_solid_free_attenuation(model, spec, ctx)
    obj = _require_model(model, "[analysis.free_attenuation]")
    method, notes = _solver_notes(ctx)
    wheel = obj.wheel(spec.n_modes)
    kw = {"amplitude_m": spec.amplitude_m, "duration_s": spec.duration_s,
          "dt": spec.time_step_s, "method": method, "save_every": spec.save_every}
    open_hz = modal_by_nd(wheel, n_modes=1)["frequency_hz"]   # the reduced wheel's own
    runs, entries = [], []
    for nd in spec.nodal_diameters:
        run = free_decay(wheel, nd, forcing=spec.forcing, **kw)
        e = _decay_entry(run, obj)
        e["open_contact_frequency_hz"] = open_hz[nd]
        if spec.compare_modal_forcing:
            other = "modal" if spec.forcing == "tieboss" else "tieboss"
            z = free_decay(wheel, nd, forcing=other, **kw).damping_ratio
            e[f"damping_ratio_{other}_forcing"] = z
        runs.append(run)
        entries.append(e)
        if run.decay is None:
            notes.append(f"{nd}ND: too few envelope peaks for a damping ratio in "
                          f"{spec.duration_s:g} s; lengthen duration_s")
    ebe = max(r.energy_balance_error for r in runs)
    if ebe > 1e-3:
        notes.append(f"energy balance error {ebe:.2g}: reduce time_step_s")
    summary = {
        "nodal_diameters": list(spec.nodal_diameters),
        "damping_ratio": {f"{r.nd}ND": r.damping_ratio for r in runs},
        "paper_damping_ratio": {f"{k}ND": v for k, v in PAPER_DAMPING_RATIO.items()},
        "frequency_hz": {f"{e['nd']}ND": e["frequency_hz"] for e in entries},
        "reduced_dof": wheel.n_dof, "n_modes": spec.n_modes, "forcing": spec.forcing,
        "method": method, "energy_balance_error": float(ebe),
        "transient_runtime_s": float(sum(r.runtime_s for r in runs)),
    }
    n = min(r.t.size for r in runs)
    st = [r.contact_status for r in runs]
    data = {
        "probe": (("nd", "time"), np.stack([r.signal[:n] for r in runs]), {"units": "m"}),
        "contact_displacement": (("nd", "time", "contact", "direction"),
                                 np.stack([r.contact_displacement[:n] for r in runs]),
                                 {"units": "m"}),
        "contact_force": (("nd", "time", "contact", "direction"),
                          np.stack([r.contact_force[:n] for r in runs]), {"units": "N"}),
        "contact_node": (("nd", "node", "time", "component"),
                         np.stack([[r.nodes[k][:n] for k in r.nodes] for r in runs]),
                         {"units": "m"}),
    }
    if all(s is not None for s in st):
        data["contact_status"] = (("nd", "time", "contact"), np.stack([s[:n] for s in st]),
                                  {"meaning": "0 open, 1 stick, 2 slip"})
    arrays = {"decay": xr.Dataset(data, coords={
        "nd": ("nd", np.asarray(spec.nodal_diameters)),
        "time": ("time", runs[0].t[:n], {"units": "s"}),
        "contact": ("contact", np.arange(runs[0].contact_displacement.shape[1])),
        "direction": ("direction", ["n", "t1", "t2"]),
        "node": ("node", list(runs[0].nodes)), "component": ("component", ["x", "y", "z"])})}
    headline = ", ".join(
        f"{r.nd}ND: zeta {100 * r.damping_ratio:.3g} %"
        + (f" (paper {100 * PAPER_DAMPING_RATIO[r.nd]:.2g} %)"
           if r.nd in PAPER_DAMPING_RATIO and obj.n_blades == 30 else "") for r in runs) \
        + (f" from {1e3 * spec.amplitude_m:.3g} mm over {spec.duration_s:g} s on {wheel.n_dof} "
           f"DOFs (CB, {spec.n_modes} modes); transients {summary['transient_runtime_s']:.2g} s")

    def figures():
        return _decay_figures(runs, obj)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"decay": entries})


# ================================================================================ reduction
class ReductionComparisonAnalysis(Section):
    """``[analysis.reduction_comparison]``: the same free attenuation on the full-order wheel
    (general solver) and on the Craig-Bampton wheel (compiled path). Writes the top-level
    ``reduction``."""

    nodal_diameter: NodalDiameter = Field(2, description="ND of the decay compared")
    n_modes: int = Field(10, ge=0, le=200, description="fixed-interface modes per sector")
    amplitude_m: Positive = Field(5e-4, le=0.01, description="initial probe displacement")
    duration_s: Positive = Field(0.1, le=10.0, description="length of the attenuation")
    time_step_s: Positive = Field(1e-5, le=1e-3, description="time step")
    save_every: int = Field(5, ge=1, le=1000, description="store every k-th step")

    @model_validator(mode="after")
    def _check(self):
        _check_steps(self)
        return self


def _check_reduction(model, spec: ReductionComparisonAnalysis) -> None:
    obj = _require_model(model, "[analysis.reduction_comparison]")
    _check_nds(obj, "nodal_diameter", [spec.nodal_diameter])


def run_reduction_comparison(model: TiebossWheelCaseModel, spec: ReductionComparisonAnalysis,
                             ctx: RunContext) -> AnalysisOutput:
    """Full-order (:func:`~fricdamp.solvers.timestep.simulate`) against Craig-Bampton
    (:func:`~fricdamp.solvers.fast_transient.integrate_contact3d`) free decays of one ND, as
    :func:`~fricdamp.models.tieboss_wheel.studies.reduction_comparison` (same keys) with the
    signals kept for the figure."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel.studies import free_decay

    obj = _require_model(model, "[analysis.reduction_comparison]")
    method, notes = _solver_notes(ctx)
    full, red = obj.wheel(None), obj.wheel(spec.n_modes)
    kw = {"amplitude_m": spec.amplitude_m, "duration_s": spec.duration_s,
          "dt": spec.time_step_s, "method": method, "save_every": spec.save_every}
    nd = spec.nodal_diameter
    rf = free_decay(full, nd, solver="simulate", **kw)
    rr = free_decay(red, nd, solver="fast", **kw)
    n = min(rf.t.size, rr.t.size)
    dev = float(np.max(np.abs(rf.signal[:n] - rr.signal[:n])) / abs(rf.signal[0]))
    diff = abs(rr.damping_ratio / rf.damping_ratio - 1.0)
    red_dict = {
        "nd": nd, "full_dof": full.n_dof, "reduced_dof": red.n_dof, "n_modes": spec.n_modes,
        "damping_ratio_full": rf.damping_ratio, "damping_ratio_reduced": rr.damping_ratio,
        "damping_ratio_difference": diff,
        "frequency_full_hz": rf.decay.mean_frequency_hz if rf.decay is not None else None,
        "frequency_reduced_hz": rr.decay.mean_frequency_hz if rr.decay is not None else None,
        "initial_amplitude_full_m": rf.initial_amplitude_m,
        "initial_amplitude_reduced_m": rr.initial_amplitude_m,
        "runtime_full_s": rf.runtime_s, "runtime_reduced_s": rr.runtime_s,
        "speed_ratio": rf.runtime_s / rr.runtime_s, "max_signal_difference": dev,
        "duration_s": spec.duration_s, "dt_s": spec.time_step_s, "method": method,
        "energy_balance_error_full": rf.energy_balance_error,
        "energy_balance_error_reduced": rr.energy_balance_error,
    }
    summary = {k: red_dict[k] for k in ("nd", "full_dof", "reduced_dof", "n_modes",
                                        "damping_ratio_difference", "max_signal_difference",
                                        "speed_ratio")}
    summary["energy_balance_error"] = max(rf.energy_balance_error, rr.energy_balance_error)
    if not math.isfinite(diff):
        notes.append("no damping ratio from one of the decays: lengthen duration_s")
    elif diff > 0.05:
        notes.append(f"the reduced wheel's damping ratio is {100 * diff:.3g} % off the full "
                     "wheel's: raise n_modes")
    arrays = {"probe": xr.Dataset(
        {"probe_full": ("time", rf.signal[:n], {"units": "m"}),
         "probe_reduced": ("time", rr.signal[:n], {"units": "m"})},
        coords={"time": ("time", rf.t[:n], {"units": "s"})})}
    headline = (f"{nd}ND: full {full.n_dof} DOFs zeta {100 * rf.damping_ratio:.3g} %, reduced "
                f"{red.n_dof} DOFs {100 * rr.damping_ratio:.3g} % (difference "
                f"{100 * diff:.2g} %); transients {rf.runtime_s:.3g} s vs {rr.runtime_s:.2g} s "
                f"({red_dict['speed_ratio']:.3g}x)")

    def figures():
        return _reduction_figures(rf, rr, red_dict)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"reduction": red_dict})


register_model(MODEL_TYPE, TiebossWheelSpec, build_tieboss_wheel_case,
               description="paper 003's 30-blade wheel with tie-boss friction contacts")
register_analysis("modal", ModalAnalysis, run_modal, check=_check_modal,
                  description="open-contact eigenfrequencies by nodal diameter (003 Table 1)")
register_analysis("campbell_by_nd", CampbellByNDAnalysis, run_campbell_by_nd,
                  check=_check_campbell,
                  description="Campbell diagram by ND and critical speeds 003 (1)")
register_analysis("free_attenuation", FreeAttenuationAnalysis, run_free_attenuation,
                  check=_check_free_attenuation,
                  description="003's damping strategy: static deformation, free decay, "
                              "log decrement per ND")
register_analysis("reduction_comparison", ReductionComparisonAnalysis,
                  run_reduction_comparison, check=_check_reduction,
                  description="full-order vs Craig-Bampton free attenuation")

# issue 17: the rig test (excitation orders, cyclic forced response, zeta(A), mistuning);
# imported here so that the runner's import of this module registers them
from fricdamp.models.tieboss_wheel import _case_forced as _tieboss_forced  # noqa: E402, F401
