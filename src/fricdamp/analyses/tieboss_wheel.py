"""Paper 003's bladed wheel with tie-boss contacts as a case: ``[model] type = "tieboss_wheel"``
with ``[analysis.modal]`` (Table 1), ``[analysis.campbell_by_nd]`` (Campbell diagram and
critical speeds 003 (1), Table 2), ``[analysis.free_attenuation]`` (the paper's damping
strategy, Figs 13-19) and ``[analysis.reduction_comparison]`` (full-order against
Craig-Bampton transients).

The model is not a :class:`~fricdamp.structure.MechanicalSystem` but a
:class:`TiebossWheelCaseModel`: the tuned beam sector of
:mod:`fricdamp.models.tieboss_wheel` (30 blades, tie-bosses at r = 0.44 m, contact planes at
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

Summary sections are dicts, so the lists ``decay`` and ``critical_speeds_rpm`` and the dict
``reduction`` are written at the top level (:attr:`fricdamp.runner.AnalysisOutput.top_level`)
by analyses with other names, whose own sections hold their key numbers. The keys are
documented in ``docs/cases_tieboss_wheel.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import MAX_STEPS, NonNegative, Positive, Section
from fricdamp.errors import CaseError
from fricdamp.runner import (
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
_ANALYSES = ("[analysis.modal], [analysis.campbell_by_nd], [analysis.free_attenuation] and "
             "[analysis.reduction_comparison]")

#: 003 section 3.2: damping ratios from the log decrement of the FEM envelopes.
PAPER_DAMPING_RATIO = {2: 0.012, 6: 0.022}
#: Open / stick / slip colours of the contact-state figures.
STATE_COLORS = ("#d9d9d9", "#1f77b4", "#d62728")

NodalDiameter = Annotated[int, Field(ge=0, le=1000)]
Pair = Annotated[list[Annotated[int, Field(ge=0, le=1000)]], Field(min_length=2, max_length=2)]


# ================================================================================ the model
class TiebossWheelSpec(Section):
    """``[model] type = "tieboss_wheel"``: paper 003's 30-blade wheel with tie-boss contacts
    (:class:`~fricdamp.models.tieboss_wheel.TiebossWheelParameters`, same names).

    The defaults are the library's (the paper's data and, for what it does not give, the
    documented choices tuned to its Table 1); tests/cli/test_tieboss_wheel_case.py checks that
    they agree.
    """

    # ---- wheel and blades (003 section 1.1)
    n_blades: int = Field(30, ge=3, le=360, description="blades (sectors) N")
    hub_inner_radius_m: Positive = Field(0.10, le=10.0, description="clamped radius of the "
                                                                    "disk web")
    hub_radius_m: Positive = Field(0.30, le=10.0, description="rim / blade-root radius")
    tieboss_radius_m: Positive = Field(0.44, le=10.0, description="tie-boss radius (003: "
                                                                  "0.44 m)")
    tip_radius_m: Positive = Field(0.50, le=10.0, description="blade tip radius")
    blade_width_m: Positive = Field(0.040, le=1.0, description="blade section, in its plane")
    blade_thickness_m: Positive = Field(0.006, le=1.0, description="blade section, along "
                                                                   "the flexural direction")
    blade_angle_deg: float = Field(45.0, ge=0.0, le=90.0, description="blade plane to the "
                                                                      "wheel plane")
    contact_plane_angle_deg: float = Field(45.0, ge=0.0, lt=90.0, description="beta_c of the "
                                           "contact plane (003: 45)")
    shoulder_diameter_m: Positive = Field(0.010, le=1.0, description="tie-boss shoulders")
    hub_thickness_m: Positive = Field(0.01004, le=1.0, description="disk web, axial (tuned)")
    hub_width_m: Positive = Field(0.100, le=1.0, description="disk web, tangential")
    rim_thickness_m: Positive = Field(0.005, le=1.0, description="rim beams, axial")
    rim_height_m: Positive = Field(0.02478, le=1.0, description="rim beams, radial (tuned)")
    tip_mass_kg: Positive = Field(0.4189, le=1e3, description="tip mass (tuned)")
    tip_inertia_kg_m2: NonNegative = Field(1.0e-4, le=1e3, description="its rotary inertia")
    tieboss_mass_kg: Positive = Field(0.030, le=1e3, description="tie-boss prism")
    tieboss_inertia_kg_m2: NonNegative = Field(2.0e-6, le=1e3, description="its rotary "
                                                                            "inertia")
    young_modulus_Pa: Positive = Field(2.1e11, description="E (steel)")
    density_kg_m3: Positive = Field(7850.0, description="rho (steel)")
    poisson_ratio: float = Field(0.3, gt=-1.0, le=0.5, description="nu")
    n_hub_elements: int = Field(3, ge=1, le=50, description="beam elements of the disk web")
    n_blade_elements: int = Field(10, ge=2, le=100, description="beam elements of the blade")
    # ---- damping (003 section 2.4)
    damping_ratio: float = Field(1.0e-3, ge=0.0, lt=1.0, description="material damping ratio "
                                                                     "(003: 0.1 %)")
    damping_band_hz: Annotated[list[Positive], Field(min_length=2, max_length=2)] = Field(
        [40.0, 60.0], description="[f1, f2] where the Rayleigh damping equals damping_ratio")
    # ---- contacts (003 section 2.4, (2))
    contact_offset_m: float = Field(1.0e-5, description="surface offset g0: > 0 interference "
                                                        "(003: 1e-5 m), < 0 a gap")
    contact_preload_N: NonNegative = Field(2.4, le=1e6, description="static normal force the "
                                           "calibration aims at (003: 2.4 N)")
    normal_stiffness_N_per_m: Positive = Field(4.654e5, description="normal penalty k_n "
                                               "(calibrated for 2.4 N)")
    tangential_stiffness_N_per_m: Positive | None = Field(
        None, description="tangential penalty k_t (default k_n)")
    mu_static: NonNegative = Field(0.4, le=5.0, description="mu_s of 003 (2)")
    mu_sliding: NonNegative = Field(0.2, le=5.0, description="mu_d of 003 (2), <= mu_s")
    decay_s_per_m: NonNegative = Field(4.0, le=1e6, description="DC of 003 (2)")
    calibrate_normal_stiffness: bool = Field(
        False, description="find k_n so that the wheel's prestress is contact_preload_N")

    @model_validator(mode="after")
    def _consistency(self):
        radii = (self.hub_inner_radius_m, self.hub_radius_m, self.tieboss_radius_m,
                 self.tip_radius_m)
        if not radii[0] < radii[1] < radii[2] < radii[3]:
            raise ValueError(
                "the radii must satisfy hub_inner_radius_m < hub_radius_m < tieboss_radius_m < "
                f"tip_radius_m, got {radii[0]:g}, {radii[1]:g}, {radii[2]:g}, {radii[3]:g} m")
        f1, f2 = self.damping_band_hz
        if not f1 < f2:
            raise ValueError(f"damping_band_hz = [{f1:g}, {f2:g}] must be two frequencies "
                             "f1 < f2 [Hz]")
        if self.mu_sliding > self.mu_static:
            raise ValueError(f"mu_sliding = {self.mu_sliding:g} must be <= mu_static = "
                             f"{self.mu_static:g} (003 (2): the sliding coefficient does not "
                             "exceed the static one)")
        lim = 0.01 * self.tieboss_radius_m
        if abs(self.contact_offset_m) > lim:
            raise ValueError(f"contact_offset_m = {self.contact_offset_m:g} m must lie in "
                             f"[{-lim:g}, {lim:g}] m (1 % of tieboss_radius_m: a small "
                             "interference > 0 or gap < 0)")
        if self.calibrate_normal_stiffness:
            if "normal_stiffness_N_per_m" in self.model_fields_set:
                raise ValueError("give either normal_stiffness_N_per_m or "
                                 "calibrate_normal_stiffness = true, not both")
            if self.contact_offset_m <= 0:
                raise ValueError(
                    f"contact_offset_m = {self.contact_offset_m:g} m must be > 0 m (an "
                    "interference) with calibrate_normal_stiffness = true: a gap or a zero "
                    "offset gives no prestress to calibrate the penalty against")
            if self.contact_preload_N <= 0:
                raise ValueError("contact_preload_N must be > 0 N with "
                                 "calibrate_normal_stiffness = true")
        return self


def tieboss_parameters(spec: TiebossWheelSpec):
    """The :class:`~fricdamp.models.tieboss_wheel.TiebossWheelParameters` of a ``[model]``
    table (same names; raises ModelError). The normal penalty is the table's, calibrated
    afterwards by the builder when ``calibrate_normal_stiffness`` is set."""
    from fricdamp.models.tieboss_wheel import TiebossWheelParameters

    kw = {f.name: getattr(spec, f.name) for f in fields(TiebossWheelParameters)}
    kw["damping_band_hz"] = tuple(spec.damping_band_hz)
    return TiebossWheelParameters(**kw)


@dataclass(frozen=True, eq=False)
class TiebossWheelCaseModel(ModelObject):
    """The model object of ``[model] type = "tieboss_wheel"``.

    Attributes
    ----------
    sector : TiebossSector
        The beam sector with its rotation terms (:func:`~fricdamp.models.tieboss_wheel.
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
        """The :class:`~fricdamp.models.tieboss_wheel.TiebossWheelParameters`."""
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
        fixed-interface modes per sector (:func:`~fricdamp.models.tieboss_wheel.build_wheel`),
        built once."""
        from fricdamp.models.tieboss_wheel import build_wheel

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
        from fricdamp.models.tieboss_wheel import prestress_normal_force

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
    from fricdamp.models.tieboss_wheel import build_sector, calibrate_normal_stiffness

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


def _last_period(run) -> np.ndarray:
    f = run.decay.mean_frequency_hz if run.decay is not None else 45.0
    return run.t >= run.t[-1] - 1.0 / f


# ================================================================================ modal
class ModalAnalysis(Section):
    """``[analysis.modal]``: open-contact eigenfrequencies by nodal diameter from one sector
    with the cyclic constraint (003 section 2.2, Table 1)."""

    n_modes: int = Field(2, ge=1, le=20, description="modes per ND (the first is the blade "
                                                     "family of Table 1)")


def _check_modal(model, spec: ModalAnalysis) -> None:
    _require_model(model, "[analysis.modal]")


def run_modal(model: TiebossWheelCaseModel, spec: ModalAnalysis,
              ctx: RunContext) -> AnalysisOutput:
    """Frequencies by ND (:func:`~fricdamp.models.tieboss_analyses.modal_by_nd`) and the
    comparison with Table 1."""
    import xarray as xr

    from fricdamp.models.tieboss_analyses import modal_by_nd
    from fricdamp.models.tieboss_wheel import TABLE1_EXPERIMENT_HZ

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


def _modal_figures(summary: dict) -> list:
    from fricdamp import plot
    from fricdamp.models.tieboss_wheel import TABLE1_EXPERIMENT_HZ, TABLE1_FEM_HZ

    nd = np.asarray(summary["nd"])
    F = np.asarray(summary["families_hz"])
    table = "table1" in summary
    fig, axes = plot.new_figure(1, 2 if table else 1, width=11.5 if table else 6.5,
                                height=4.2, title="Open-contact eigenfrequencies by nodal "
                                                  "diameter (003 Table 1)")
    ax = axes[0, 0]
    ax.plot(nd, F[:, 0], "k.-", label="model, first family (cyclic symmetry)")
    if table:
        for k, (n, pair) in enumerate(TABLE1_FEM_HZ.items()):
            ax.plot([n] * len(pair), pair, "s", mfc="none", color="C0",
                    label="003 Table 1, FEM" if k == 0 else None)
        for k, (n, pair) in enumerate(TABLE1_EXPERIMENT_HZ.items()):
            vals = [v for v in pair if v is not None]
            ax.plot([n] * len(vals), vals, "^", mfc="none", color="C1",
                    label="003 Table 1, experiment" if k == 0 else None)
    ax.set_xlabel("nodal diameter")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize="small", loc="lower right")
    if table:
        ax2 = axes[0, 1]
        rows = summary["table1"]
        x = [r["nd"] for r in rows]
        err = [100 * r["relative_error"] for r in rows]
        ax2.bar([str(v) for v in x], err, color="C0")
        for lim in (-1.0, 1.0):
            ax2.axhline(lim, color="0.4", ls="--", lw=0.8)
        ax2.axhline(0.0, color="k", lw=0.6)
        ax2.set_xlabel("nodal diameter")
        ax2.set_ylabel("model / paper FEM pair mean - 1 [%]")
        ax2.set_title("error to Table 1 (dashed: 1 %)", fontsize="small")
        ax2.set_ylim(-1.5, 1.5)
    return [("table1.png", "Open-contact eigenfrequencies by nodal diameter: the model's first "
             "family against 003 Table 1 (FEM pairs and experiment), and the relative error "
             "to the FEM pair means", fig)]


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
    obj = _require_model(model, "[analysis.campbell_by_nd]")
    _check_nds(obj, "critical_pairs", [nd for _, nd in spec.critical_pairs])


def run_campbell_by_nd(model: TiebossWheelCaseModel, spec: CampbellByNDAnalysis,
                       ctx: RunContext) -> AnalysisOutput:
    """Campbell diagram by ND (:func:`~fricdamp.models.tieboss_analyses.campbell_by_nd`) and
    the critical speeds (:func:`~fricdamp.models.tieboss_analyses.critical_speeds_by_nd`)."""
    import xarray as xr

    from fricdamp.models.tieboss_analyses import (
        TABLE2_ORDERS,
        campbell_by_nd,
        critical_speeds_by_nd,
    )

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


def _campbell_figures(camp, crit: list, spec: CampbellByNDAnalysis) -> list:
    import matplotlib

    from fricdamp import plot

    fig, axes = plot.new_figure(width=8.0, height=5.0, title=f"Campbell diagram by nodal "
                                f"diameter, p = {spec.pulses} pulses (003 Fig. 6, (1))")
    ax = axes[0, 0]
    cmap = matplotlib.colormaps["viridis"]
    nd_max = max(int(camp.nd.max()), 1)
    for k, nd in enumerate(camp.nd):
        ax.plot(camp.rpm, camp.frequency_hz[:, k], color=cmap(nd / nd_max), lw=1.1,
                label=f"{nd}ND" if nd in (0, 2, 6, nd_max) else None)
    fmin, fmax = float(camp.frequency_hz.min()), float(camp.frequency_hz.max())
    lo, hi = 0.9 * fmin, 1.05 * fmax
    orders = sorted(set(spec.orders) | {c["order"] for c in crit})
    for o in orders:
        f = spec.pulses * o * camp.rpm / 60.0
        ax.plot(camp.rpm, f, "k--", lw=0.8)
        inside = np.flatnonzero((f > lo) & (f < hi))
        if inside.size:
            i = inside[inside.size // 2]
            ax.annotate(f"o = {o}", (camp.rpm[i], f[i]), fontsize=8, xytext=(4, -2),
                        textcoords="offset points")
    labels = {"model": "critical speed 003 (1)", "paper": "003 Table 2 (measured)"}
    for c in crit:
        if c["rpm"] is not None:
            ax.plot(c["rpm"], c["frequency_hz"], "o", color="tab:red", ms=6,
                    label=labels.pop("model", None))
            ax.annotate(f"{c['rpm']:.0f} rpm ({c['nd']}ND, o = {c['order']})",
                        (c["rpm"], c["frequency_hz"]), fontsize=7, xytext=(5, -11),
                        textcoords="offset points")
        if "paper_rpm" in c:
            ax.plot(c["paper_rpm"], c["paper_frequency_hz"], "x", color="k", ms=7,
                    label=labels.pop("paper", None))
    ax.set_xlim(camp.rpm[0], camp.rpm[-1])
    ax.set_ylim(lo, hi)
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize="small", loc="lower right")
    return [("campbell.png", f"Campbell diagram: first-family frequencies by nodal diameter vs "
             f"speed (contacts open), the engine-order lines p o n / 60 of p = {spec.pulses} "
             "pulses and the critical speeds s = 60 f / (p o) (003 (1)) against Table 2", fig)]


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
    obj = _require_model(model, "[analysis.free_attenuation]")
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
    """Free decays of :func:`~fricdamp.models.tieboss_analyses.free_decay` for each ND on the
    Craig-Bampton wheel (compiled contact integrator)."""
    import xarray as xr

    from fricdamp.models.tieboss_analyses import free_decay, modal_by_nd

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


def _decay_figures(runs: list, obj: TiebossWheelCaseModel) -> list:
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.ticker import ScalarFormatter

    from fricdamp import plot

    N = obj.n_blades
    A = (f"B{N - 1}.right", "B0.left")
    B = ("B0.right", "B1.left")
    figs = []
    for run in runs:
        # Figs 13-14: the contact nodes of contacts A and B, with the probe's envelope
        fig, axes = plot.new_figure(1, 2, width=12.0, height=4.2, title=f"{run.nd}ND: free "
                                    "attenuation of the contact nodes (003 Figs 13-14)")
        for ax, keys, name in ((axes[0, 0], A, "contact A"), (axes[0, 1], B, "contact B")):
            for key, ls in zip(keys, ("-", "--"), strict=True):
                for c, comp in enumerate("xyz"):
                    ax.plot(run.t, 1e3 * run.nodes[key][:, c], ls, lw=0.7, color=f"C{c}",
                            label=f"{key} {comp}")
            ax.set_title(f"{name} ({keys[0]} | {keys[1]})", fontsize="small")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("displacement from rest [mm]")
        if run.decay is not None:
            env = run.decay.envelope
            axes[0, 1].plot(env.time, 1e3 * env.amplitude, "k.", ms=4,
                            label="envelope (B0.right along the flexural direction)")
        for ax in axes[0]:
            ax.legend(fontsize=6, ncols=2, loc="upper right")
        figs.append((f"decay_{run.nd}ND.png", f"{run.nd}ND: displacements (x, y, z in blade "
                     "0's frame) of the contact nodes of contacts A and B during the free "
                     "attenuation, with the envelope of the probe (003 Figs 13-14)", fig))

        # Figs 15-16: one period of the contact nodes' trajectories, relative motion, forces
        sel = _last_period(run)
        fig = Figure(figsize=(14.0, 4.4), layout="constrained")
        fig.suptitle(f"{run.nd}ND: contact-node trajectories over the last period "
                     "(003 Figs 15-16)", fontsize="medium")
        ax = fig.add_subplot(1, 3, 1, projection="3d")
        for key, c in zip(B + A, ("C0", "C1", "C2", "C3"), strict=True):
            x = 1e3 * run.nodes[key][sel]
            ax.plot(x[:, 0], x[:, 1], x[:, 2], color=c, lw=1, label=key)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")
        ax.legend(fontsize=6)
        ax2 = fig.add_subplot(1, 3, 2)
        for ci, name in ((0, "contact B (0)"), (N - 1, f"contact A ({N - 1})")):
            u = 1e6 * run.contact_displacement[sel, ci]
            ax2.plot(u[:, 1], u[:, 2], lw=1, label=name)
        ax2.set_xlabel("relative t1 (radial) [µm]")
        ax2.set_ylabel("relative t2 (in the plane) [µm]")
        ax2.set_title("relative motion in the contact plane", fontsize="small")
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize="small")
        ax3 = fig.add_subplot(1, 3, 3)
        t = run.t[sel]
        ax3.plot(t, 1e6 * run.contact_displacement[sel, 0, 0], label="approach u_n [µm]")
        ax3.plot(t, run.contact_force[sel, 0, 0], label="normal force N [N]")
        ax3.plot(t, np.hypot(run.contact_force[sel, 0, 1], run.contact_force[sel, 0, 2]),
                 label="|f_t| [N]")
        ax3.axhline(-1e6 * run.meta["offset_m"], color="0.5", lw=0.8, ls=":",
                    label="opening (u_n = -g0)")
        ax3.set_xlabel("time [s]")
        ax3.set_title("contact B: approach and forces", fontsize="small")
        ax3.grid(alpha=0.3)
        ax3.legend(fontsize="small")
        figs.append((f"trajectories_{run.nd}ND.png", f"{run.nd}ND: trajectories of the contact "
                     "nodes of contacts A and B over the last period, their relative motion in "
                     "the contact plane, and contact B's normal approach and forces "
                     "(003 Figs 15-16)", fig))

        # Figs 17-18: open / stick / slip of every contact over time
        if run.contact_status is not None:
            st = run.contact_status
            fig, axes = plot.new_figure(width=9.0, height=4.4, title=f"{run.nd}ND: contact "
                                        "states (003 Figs 17-18)")
            ax = axes[0, 0]
            ax.grid(False)
            ax.imshow(st.T, aspect="auto", interpolation="nearest", origin="lower",
                      cmap=ListedColormap(STATE_COLORS), vmin=0, vmax=2,
                      extent=(run.t[0], run.t[-1], -0.5, st.shape[1] - 0.5))
            for k, name in enumerate(("open (near contact)", "stick", "slip")):
                ax.plot([], [], "s", color=STATE_COLORS[k],
                        label=f"{name}: {100 * np.mean(st == k):.0f} %")
            ax.set_xlabel("time [s]")
            ax.set_ylabel("contact (blade j | j + 1)")
            ax.legend(fontsize="small", loc="upper right")
            figs.append((f"contact_states_{run.nd}ND.png", f"{run.nd}ND: state of each of the "
                         f"{N} tie-boss contacts over time: open, stick or slip "
                         "(003 Figs 17-18)", fig))

    # Fig. 19: envelopes with the log-decrement fit, amplitude-dependent ratio
    fig, axes = plot.new_figure(1, 2, width=12.0, height=4.4, title="Free-attenuation "
                                "envelopes and damping (003 Fig. 19)")
    a1, a2 = axes[0]
    for i, run in enumerate(runs):
        if run.decay is None:
            continue
        col = f"C{i % 10}"
        dec = run.decay
        env = dec.envelope
        a1.semilogy(env.time, 1e3 * env.amplitude, "o", ms=3.5, color=col,
                    label=f"{run.nd}ND envelope (probe)")
        delta = 2 * np.pi * run.damping_ratio / math.sqrt(1.0 - run.damping_ratio ** 2)
        tl = np.linspace(env.time[0], env.time[-1], 100)
        a1.semilogy(tl, 1e3 * env.amplitude[0] * np.exp(
            -delta * dec.mean_frequency_hz * (tl - env.time[0])), "-", lw=1, color=col,
            label=rf"log decrement: $\zeta$ = {100 * run.damping_ratio:.2f} %")
        cf = dec.coulomb
        a1.semilogy(tl, 1e3 * np.maximum(cf.intercept - cf.slope * tl, 1e-12), ":", lw=1,
                    color=col, label="linear (Coulomb) fit")
        a2.plot(1e3 * dec.amplitude, 100 * dec.damping_ratio, "o", ms=3, color=col,
                alpha=0.6, label=f"{run.nd}ND, successive peaks")
        hil = run.amplitude_decay
        if hil is not None and hil.amplitude.size >= 2:
            a2.plot(1e3 * hil.amplitude, 100 * hil.damping_ratio, "s-", ms=4, color=col,
                    label=f"{run.nd}ND, Hilbert cycles")
        a2.axhline(100 * run.damping_ratio, ls=":", lw=1, color=col,
                   label=f"{run.nd}ND, record average")
        if run.nd in PAPER_DAMPING_RATIO and obj.n_blades == 30:
            a2.axhline(100 * PAPER_DAMPING_RATIO[run.nd], ls="--", lw=0.8, color=col,
                       label=f"paper {run.nd}ND (log decrement)")
    a1.yaxis.set_minor_formatter(ScalarFormatter())
    a1.set_xlabel("time [s]")
    a1.set_ylabel("envelope of the probe [mm]")
    a2.set_xlabel("amplitude [mm]")
    a2.set_ylabel("damping ratio [%]")
    a2.set_title("amplitude-dependent ratio (alternate peak pairs differ by the drift of "
                 "the friction-locked rest position)", fontsize="x-small")
    if any(run.decay is not None for run in runs):
        a1.legend(fontsize="x-small")
        a2.legend(fontsize="x-small")
    else:
        a1.text(0.5, 0.5, "too few envelope peaks: lengthen duration_s", ha="center",
                transform=a1.transAxes)
    figs.append(("envelopes.png", "Envelopes of the free attenuations (peaks of the probe) "
                 "with the record-average log-decrement fit and the linear (Coulomb) fit, and "
                 "the amplitude-dependent damping ratio against the paper's values "
                 "(003 Fig. 19)", fig))
    return figs


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
    :func:`~fricdamp.models.tieboss_analyses.reduction_comparison` (same keys) with the
    signals kept for the figure."""
    import xarray as xr

    from fricdamp.models.tieboss_analyses import free_decay

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


def _reduction_figures(rf, rr, r: dict) -> list:
    from fricdamp import plot

    n = min(rf.t.size, rr.t.size)
    fig, axes = plot.new_figure(2, 1, width=9.0, height=2.8, sharex=True,
                                title=f"{r['nd']}ND free attenuation: full order "
                                      f"({r['full_dof']} DOFs) vs Craig-Bampton "
                                      f"({r['reduced_dof']} DOFs)")
    t = rf.t[:n]
    a1, a2 = axes[:, 0]
    a1.plot(t, 1e3 * rf.signal[:n], lw=1.2, label=f"full: zeta = "
            f"{100 * r['damping_ratio_full']:.3f} %")
    a1.plot(t, 1e3 * rr.signal[:n], "--", lw=1, label=f"reduced: zeta = "
            f"{100 * r['damping_ratio_reduced']:.3f} %")
    a1.set_ylabel("probe [mm]")
    a1.legend(fontsize="small", loc="upper right")
    d = rr.signal[:n] - rf.signal[:n]
    fac, unit = plot.si_scale(d, "m")
    a2.plot(t, d / fac, lw=0.8, color="C3")
    a2.set_ylabel(f"reduced - full [{unit}]")
    a2.set_xlabel("time [s]")
    return [("reduction.png", "Probe displacement of the free attenuation on the full-order "
             "wheel (general solver) and on the Craig-Bampton wheel (compiled path), and "
             "their difference", fig)]


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
