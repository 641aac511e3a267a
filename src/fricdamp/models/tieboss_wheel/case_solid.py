"""Paper 003 on solid finite-element wheels: ``[model] type = "tieboss_wheel_solid"`` (the
parametric tet10 sector of :mod:`fricdamp.models.tieboss_wheel.solid`) and ``[model] type =
"cyclic_sector"`` (a user's meshed sector, read with meshio).

Both build a :class:`~fricdamp.models.contact_wheel.WheelSector` -- the sparse sector with
its cyclic cuts, its two contact faces paired node by node into a
:class:`~fricdamp.structure.contact_patch.ContactPatch`, a probe and the load nodes -- and
run paper 003's strategy on the reduced wheel of :mod:`fricdamp.models.contact_wheel`. The
analyses are those of the beam wheel (same tables, same summary keys):

``[analysis.modal]``
    open-contact frequencies by ND 0..N/2 of the *unreduced* sector (sparse shift-invert with
    the complex cyclic constraint), Table 1 comparison, and the reduced wheel's first family
    beside it (``reduction_max_error``); figures: Table 1 and the mesh.
``[analysis.free_attenuation]``
    003 section 3 per ND on the reduced wheel with every node pair of every contact patch;
    top-level ``decay`` entries with ``state_fractions``; figures: decay envelopes and the
    contact-status maps over each face (003 Figs 17-18).
``[analysis.penalty_convergence]``
    the same decays for several penalty factors at the same prestress (the offset is
    re-calibrated for each): ``damping_ratio_2nd`` / ``_6nd`` against ``penalty_factor``.
``[analysis.mistuning]``
    blade-to-blade Young's-modulus scatter, the wheel assembled without cyclic symmetry from
    the reduced sectors, its split doublets (003 Table 1's pairs).

Summary contract (issue 12)::

    model: {"element_type", "n_elements_sector", "sector_dof", "wheel_dof", "reduced_dof",
            "contact_pairs_per_tieboss", "prestress_normal_force_N", "penalty_factor", ...}
    modal: {"nd": [0..15], "frequency_hz": [...], ...}
    decay: [{"nd", "damping_ratio", "initial_amplitude_m", "runtime_s",
             "energy_balance_error", "state_fractions": {"open", "stick", "slip"}}, ...]
    penalty_convergence: {"penalty_factor": [...], "damping_ratio_2nd": [...],
                          "damping_ratio_6nd": [...]}
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import Positive, Section
from fricdamp.errors import CaseError, ModelError
from fricdamp.registry import (
    AnalysisOutput,
    BuildContext,
    ModelObject,
    RunContext,
    register_analysis,
    register_model,
)

__all__ = ["CyclicSectorSpec", "MistuningAnalysis", "PenaltyConvergenceAnalysis",
           "SolidWheelCaseModel", "SolidWheelSpec", "paper_wheel_sector", "run_mistuning",
           "run_penalty_convergence",
           "run_solid_free_attenuation", "run_solid_modal"]

MODEL_TYPES = ("tieboss_wheel_solid", "cyclic_sector")
_ANALYSES = ("[analysis.modal], [analysis.campbell_by_nd], [analysis.free_attenuation], "
             "[analysis.penalty_convergence], [analysis.mistuning] and "
             "[analysis.cyclic_forced_response]")
STATE_COLORS = ("#d9d9d9", "#1f77b4", "#d62728")


# ================================================================================ schemas
class _PipelineSpec(Section):
    """Reduction, damping and contact keys shared by the solid model types."""

    n_modes: int = Field(30, ge=1, le=2000, description="fixed-interface modes of the "
                                                        "sector (Craig-Bampton)")
    n_interface_modes: int = Field(60, ge=1, le=5000, description="interface modes of the "
                                                                  "cyclic cut")
    damping_ratio: float = Field(1e-3, ge=0.0, le=0.5, description="material damping "
                                                                   "(003: 0.1 %)")
    damping_band_hz: Annotated[list[Positive], Field(min_length=2, max_length=2)] = Field(
        [40.0, 60.0], description="frequencies where the Rayleigh ratio is exact")
    mu_static: float = Field(0.4, ge=0.0, le=10.0, description="mu_s of 003 (2)")
    mu_sliding: float = Field(0.2, ge=0.0, le=10.0, description="mu_d of 003 (2)")
    decay_s_per_m: float = Field(4.0, ge=0.0, le=1e6, description="DC of 003 (2)")
    penalty_factor: Positive = Field(1.0, le=1e6, description="k_n = factor E A / h per "
                                                              "node pair")
    tangential_ratio: Positive = Field(1.0, le=1e3, description="k_t / k_n")
    prestress_N: Positive = Field(2.4, le=1e6, description="normal force per contact at "
                                                           "rest (003: 2.4 N)")

    @model_validator(mode="after")
    def _check_pipeline(self):
        if self.mu_sliding > self.mu_static:
            raise ValueError(f"mu_sliding ({self.mu_sliding}) must be <= mu_static "
                             f"({self.mu_static})")
        lo, hi = self.damping_band_hz
        if hi <= lo:
            raise ValueError(f"damping_band_hz must be increasing, got {self.damping_band_hz}")
        return self


class SolidWheelSpec(_PipelineSpec):
    """``[model] type = "tieboss_wheel_solid"``: paper 003's wheel as tet10 solid sectors.

    Geometry and mesh keys default to the tuned
    :class:`~fricdamp.models.tieboss_wheel.solid.SolidWheelParameters` (same names)."""

    mesh_size_m: Positive | None = Field(None, le=1.0, description="largest element size "
                                                                   "(default: the tuned "
                                                                   "mesh)")
    contact_divisions: int | None = Field(None, ge=1, le=40, description="element edges "
                                                                         "per contact-face "
                                                                         "side")
    n_blades: int | None = Field(None, ge=3, le=360, description="blades N")
    disk_thickness_m: Positive | None = Field(None, le=1.0, description="disk thickness")
    tipmass_density_kg_m3: Positive | None = Field(None, le=1e6, description="tip-mass "
                                                                             "density")
    young_modulus_Pa: Positive | None = Field(None, description="E (steel)")
    poisson_ratio: float | None = Field(None, gt=-1.0, lt=0.5, description="nu")
    density_kg_m3: Positive | None = Field(None, description="rho (steel)")


class CyclicSectorSpec(_PipelineSpec):
    """``[model] type = "cyclic_sector"``: a user's meshed sector (gmsh .msh, Abaqus .inp,
    VTU, ... read with meshio) with named node sets."""

    mesh: str = Field(..., min_length=1, description="mesh file, relative to the case file")
    n_sectors: int = Field(..., ge=2, le=1000, description="sectors N of the wheel")
    axis: Literal["x", "y", "z"] = Field("z", description="wheel axis")
    youngs_modulus_Pa: Positive = Field(2.1e11, description="E")
    poisson_ratio: float = Field(0.3, gt=-1.0, lt=0.5, description="nu")
    density_kg_m3: Positive = Field(7850.0, description="rho")
    element: Literal["tet4", "tet10", "hex8", "hex20"] | None = Field(
        None, description="element (default: from the mesh's cells)")
    probe_direction: Annotated[list[float], Field(min_length=3, max_length=3)] = Field(
        ..., description="direction of the probe signal (e.g. the blade's flexural one)")
    clamp: str = Field("clamp", description="node set: supported nodes")
    cut_left: str = Field("cut_left", description="node set: left cyclic cut")
    cut_right: str = Field("cut_right", description="node set: right cyclic cut (the left "
                                                    "one rotated by 360/N deg)")
    contact_left: str = Field("contact_left", description="node set: left contact face")
    contact_right: str = Field("contact_right", description="node set: right contact face")
    probe: str = Field("probe", description="node set: probe node (its first node)")
    load: str | None = Field("load", description="node set: where the ND forces act")
    materials: dict[str, dict[str, Positive]] = Field(
        default_factory=dict, description="per cell set: {density = ..., youngs_modulus = "
                                          "...} overrides")
    stiffness: str | None = Field(None, min_length=1, description="Matrix Market file of "
                                  "the sector's stiffness [N/m] (replaces the assembly; "
                                  "the mesh still gives the geometry)")
    mass: str | None = Field(None, min_length=1, description="Matrix Market file of the "
                             "sector's mass [kg]")
    full: str | None = Field(None, min_length=1, description="ANSYS .full file with the "
                             "sector's K and M (needs ansys-mapdl-reader)")
    dof_reference: str | None = Field(None, min_length=1, description="text file: node "
                                      "number (1-based mesh point) and component (0 UX, "
                                      "1 UY, 2 UZ) of each matrix row")
    stress_stiffening: str | None = Field(None, min_length=1, description="Matrix Market "
                                          "file: the FE program's stress-stiffening matrix "
                                          "at rotation_reference_rpm [N/m]")
    spin_softening: str | None = Field(None, min_length=1, description="Matrix Market file: "
                                       "the spin-softening matrix at rotation_reference_rpm "
                                       "[N/m] (positive: it is subtracted)")
    rotation_reference_rpm: Positive | None = Field(None, le=1e6, description="speed at which "
                                                    "the two rotation matrices were made")

    @model_validator(mode="after")
    def _check_dir(self):
        if not np.any(np.asarray(self.probe_direction)):
            raise ValueError("probe_direction must be a non-zero 3-vector")
        if (self.stiffness is None) != (self.mass is None):
            raise ValueError("stiffness and mass matrix files go together: give both or "
                             "neither")
        if self.full is not None and self.stiffness is not None:
            raise ValueError("give either full (an ANSYS .full file) or stiffness and mass "
                             "(Matrix Market files), not both")
        if self.dof_reference is not None and self.stiffness is None and \
                self.stress_stiffening is None and self.spin_softening is None:
            raise ValueError("dof_reference maps Matrix Market rows to mesh nodes: it needs "
                             "stiffness and mass (or rotation matrices)")
        given = self.stress_stiffening is not None or self.spin_softening is not None
        if given != (self.rotation_reference_rpm is not None):
            raise ValueError("stress_stiffening/spin_softening and rotation_reference_rpm go "
                             "together: the matrices scale with (speed / reference)^2")
        return self


# ================================================================================ model
@dataclass(frozen=True, eq=False)
class SolidWheelCaseModel(ModelObject):
    """The model object of the solid wheel types: a WheelSector, its contact settings and
    its reduction; the reduced wheel is built once, on first use."""

    sector: Any
    settings: Any
    n_modes: int
    n_interface_modes: int
    solid: Any = None
    paper: bool = False
    kind: str = "tieboss_wheel_solid"
    _cache: dict = field(default_factory=dict, repr=False)
    MODEL_TYPE: ClassVar[str] = "tieboss_wheel_solid"
    MODEL_DESCRIPTION: ClassVar[str] = "a wheel of solid FE sectors with contact patches"
    MODEL_ANALYSES: ClassVar[str] = _ANALYSES

    @property
    def n_blades(self) -> int:
        return int(self.sector.cyclic.n_sectors)

    @property
    def max_nd(self) -> int:
        return self.n_blades // 2

    @property
    def n_dof(self) -> int:
        return int(self.sector.info.get("wheel_dof", 0))

    @property
    def names(self) -> tuple[str, ...]:
        return ()

    def wheel(self):
        """The reduced wheel (:class:`~fricdamp.models.contact_wheel.ContactWheel`)."""
        if "wheel" not in self._cache:
            from fricdamp.models.contact_wheel import build_contact_wheel

            self._cache["wheel"] = build_contact_wheel(
                self.sector, n_modes=self.n_modes, n_interface_modes=self.n_interface_modes)
        return self._cache["wheel"]

    def offset(self, settings=None) -> tuple[float, float]:
        """(interference offset [m], mean normal force per contact at rest [N])."""
        s = self.settings if settings is None else settings
        key = ("offset", s.penalty_factor, s.tangential_ratio, s.prestress_N, s.mu_static,
               s.mu_sliding)
        if key not in self._cache:
            w = self.wheel()
            off, rest = w.calibrate_offset(s)
            self._cache[key] = (off, float(np.mean(w.normal_force_per_contact(rest))))
        return self._cache[key]

    def describe(self) -> dict:
        w = self.wheel()
        off, fn = self.offset()
        info = dict(self.sector.info)
        a, b = self.sector.rayleigh
        out = {"type": self.kind, "element_type": info.get("element_type"),
               "n_elements_sector": info.get("n_elements_sector"),
               "sector_dof": info.get("sector_dof"), "wheel_dof": info.get("wheel_dof"),
               "reduced_dof": int(w.reduced_dof),
               "contact_pairs_per_tieboss": int(self.sector.patch.n_pairs),
               "prestress_normal_force_N": fn, "penalty_factor": self.settings.penalty_factor,
               "contact_offset_m": off, "n_blades": self.n_blades,
               "n_modes": self.n_modes, "n_interface_modes": self.n_interface_modes,
               "contact_rows": int(w.basis.n_contacts * 3),
               "rayleigh_alpha_per_s": a, "rayleigh_beta_s": b,
               "reduction_timings_s": {k: float(v) for k, v in w.reduced.timings.items()}}
        out.update({k: v for k, v in info.items() if k not in out})
        return out


def _settings(spec: _PipelineSpec):
    from fricdamp.models.contact_wheel import ContactSettings

    return ContactSettings(mu_static=spec.mu_static, mu_sliding=spec.mu_sliding,
                           decay_s_per_m=spec.decay_s_per_m,
                           penalty_factor=spec.penalty_factor,
                           tangential_ratio=spec.tangential_ratio,
                           prestress_N=spec.prestress_N)


def paper_wheel_sector(params=None):
    """(WheelSector, SolidModel) of the parametric paper-003 sector
    (:func:`~fricdamp.models.tieboss_wheel.solid.build_solid_sector`: gmsh mesh, tet10 assembly,
    faces paired, probe along the blade's flexural direction)."""
    from fricdamp.models.tieboss_wheel.solid import build_solid_sector

    sector = build_solid_sector(params)
    return sector.wheel_sector, sector.model


def build_solid_wheel_case(spec: SolidWheelSpec, ctx: BuildContext) -> SolidWheelCaseModel:
    """Builder of ``[model] type = "tieboss_wheel_solid"``."""
    from dataclasses import replace

    from fricdamp.models.tieboss_wheel.solid import SolidWheelParameters

    p = SolidWheelParameters()
    changes = {k: getattr(spec, k) for k in ("mesh_size_m", "contact_divisions", "n_blades",
                                             "disk_thickness_m", "tipmass_density_kg_m3",
                                             "young_modulus_Pa", "poisson_ratio",
                                             "density_kg_m3")
               if getattr(spec, k) is not None}
    changes.update(damping_ratio=spec.damping_ratio,
                   damping_band_hz=tuple(spec.damping_band_hz))
    ws, solid = paper_wheel_sector(replace(p, **changes))
    return SolidWheelCaseModel(ws, _settings(spec), spec.n_modes, spec.n_interface_modes,
                               solid=solid, paper=True, kind="tieboss_wheel_solid")


def build_cyclic_sector_case(spec: CyclicSectorSpec, ctx: BuildContext) -> SolidWheelCaseModel:
    """Builder of ``[model] type = "cyclic_sector"``: read, assemble, pair the faces."""
    from fricdamp.models.contact_wheel import rayleigh_coefficients, sector_from_solid
    from fricdamp.structure.solid import assemble_solid, read_mesh

    path = Path(spec.mesh)
    if not path.is_absolute():
        path = Path(ctx.base_dir) / path
    if not path.is_file():
        raise CaseError(f"[model] mesh = {spec.mesh!r}: no such file ({path})")
    mesh = read_mesh(path)
    mats = {k: {("youngs_modulus" if kk.startswith("young") else kk): vv
                for kk, vv in v.items()} for k, v in spec.materials.items()}
    solid = assemble_solid(mesh, youngs_modulus=spec.youngs_modulus_Pa,
                           poisson_ratio=spec.poisson_ratio, density=spec.density_kg_m3,
                           element=spec.element, materials=mats or None)
    info = {"mesh_file": str(spec.mesh), "matrices": "assembled from the mesh"}
    if spec.stiffness is not None or spec.full is not None:
        from fricdamp.structure.io import solid_with_matrices

        def rel(name):
            value = getattr(spec, name)
            if value is None:
                return None
            q = Path(value)
            q = q if q.is_absolute() else Path(ctx.base_dir) / q
            if not q.is_file():
                raise CaseError(f"[model] {name} = {value!r}: no such file ({q})")
            return q

        try:
            solid = solid_with_matrices(solid, K=rel("stiffness"), M=rel("mass"),
                                        full=rel("full"), dof_reference=rel("dof_reference"),
                                        fixed_nodes=spec.clamp if spec.clamp in
                                        solid.node_sets else None)
        except ModelError as exc:
            raise CaseError(f"[model] matrix files: {exc}") from exc
        info["matrices"] = (f"ANSYS .full {spec.full}" if spec.full else
                            f"Matrix Market {spec.stiffness}, {spec.mass}")
    ws = sector_from_solid(
        solid, n_sectors=spec.n_sectors, youngs_modulus=spec.youngs_modulus_Pa,
        probe_direction=spec.probe_direction,
        rayleigh=rayleigh_coefficients(spec.damping_ratio, spec.damping_band_hz),
        axis=spec.axis, clamp=spec.clamp, cut_left=spec.cut_left, cut_right=spec.cut_right,
        contact_left=spec.contact_left, contact_right=spec.contact_right, probe=spec.probe,
        load=spec.load, info=info)
    model = SolidWheelCaseModel(ws, _settings(spec), spec.n_modes, spec.n_interface_modes,
                                solid=solid, paper=False, kind="cyclic_sector")
    if spec.rotation_reference_rpm is not None:
        model._cache["rotation"] = _user_rotation(spec, ctx, solid, ws)
    return model


def _user_rotation(spec: CyclicSectorSpec, ctx: BuildContext, solid, ws):
    """The FE program's rotation matrices, per Omega^2 on the sector's DOFs."""
    from fricdamp.structure.io import matrix_on_mesh
    from fricdamp.structure.system import RotationTerms

    ref = None
    if spec.dof_reference is not None:
        ref = Path(spec.dof_reference)
        ref = ref if ref.is_absolute() else Path(ctx.base_dir) / ref
    scale = (spec.rotation_reference_rpm * np.pi / 30.0) ** -2
    out = {}
    for key in ("stress_stiffening", "spin_softening"):
        value = getattr(spec, key)
        if value is None:
            continue
        q = Path(value)
        q = q if q.is_absolute() else Path(ctx.base_dir) / q
        if not q.is_file():
            raise CaseError(f"[model] {key} = {value!r}: no such file ({q})")
        try:
            A = matrix_on_mesh(solid, q, dof_reference=ref, name=key)
        except ModelError as exc:
            raise CaseError(f"[model] {key}: {exc}") from exc
        d = ws.solid_dofs
        out[key] = (scale * A[d][:, d]).tocsr()
    zero = 0 * ws.cyclic.K
    return RotationTerms(stress_stiffening=out.get("stress_stiffening", zero),
                         spin_softening=out.get("spin_softening", zero))


def is_solid(model) -> bool:
    return isinstance(model, SolidWheelCaseModel)


# ============================================================================= campbell
def rotation(model: SolidWheelCaseModel):
    """Rotation terms of the model's sector per Omega^2 (cached)."""
    from fricdamp.models.tieboss_wheel.solid_campbell import rotation_terms

    if model.solid is None:
        raise CaseError("[analysis.campbell_by_nd] needs the sector's solid model")
    if "rotation" not in model._cache:
        model._cache["rotation"] = rotation_terms(model.sector, model.solid)
    return model._cache["rotation"]


def run_solid_campbell(model: SolidWheelCaseModel, spec, ctx: RunContext) -> AnalysisOutput:
    """Campbell diagram by ND of the solid wheel (stress stiffening and spin softening of the
    solid, :mod:`fricdamp.models.tieboss_wheel.solid_campbell`) and the critical speeds
    003 (1); the same summary keys as the beam wheel's ``campbell_by_nd``. Each critical
    speed is checked by a
    direct eigen-solution of the unreduced sector at that speed (``ritz_error``)."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel._case_figures import _campbell_figures
    from fricdamp.models.tieboss_wheel.solid_campbell import (
        _at_speed,
        campbell_solid,
        critical_speeds_solid,
    )
    from fricdamp.models.tieboss_wheel.studies import (
        TABLE2_FREQUENCY_HZ,
        TABLE2_ORDERS,
        TABLE2_RPM,
    )
    from fricdamp.solvers.modal import critical_speeds
    from fricdamp.structure.cyclic import nodal_diameter_modes
    from fricdamp.verdict import judge

    rot = rotation(model)
    rpm = np.linspace(spec.speed_min_rpm, spec.speed_max_rpm, spec.n_speeds)
    camp = campbell_solid(model.sector, rot, rpm)
    pairs = [tuple(p) for p in spec.critical_pairs]
    crit = critical_speeds_solid(model.sector, rot, orders=pairs, pulses=spec.pulses,
                                 rpm_range=(spec.speed_min_rpm, spec.speed_max_rpm))
    paper = ({tuple(p) for p in TABLE2_ORDERS} if model.paper and model.n_blades == 30
             and spec.pulses == 8 else set())
    notes, ritz = [], 0.0
    for c in crit:
        if c["rpm"] is None:
            notes.append(f"the {c['nd']}ND branch does not meet the line p o n / 60 (o = "
                         f"{c['order']}) between {spec.speed_min_rpm:g} and "
                         f"{spec.speed_max_rpm:g} rpm: no critical speed there")
            continue
        direct = nodal_diameter_modes(_at_speed(model.sector.cyclic, rot,
                                                c["rpm"] * np.pi / 30.0), c["nd"], 1)
        ritz = max(ritz, abs(direct.frequencies[0] / c["frequency_hz"] - 1.0))
        if (c["order"], c["nd"]) in paper:
            o = c["order"]
            c.update(paper_rpm=TABLE2_RPM[o], paper_frequency_hz=TABLE2_FREQUENCY_HZ[o],
                     paper_formula_rpm=float(critical_speeds(TABLE2_FREQUENCY_HZ[o], o,
                                                             spec.pulses)))
    F = camp.frequency_hz
    summary = {"rpm": rpm.tolist(), "nd": camp.nd.tolist(), "frequency_hz": F.T.tolist(),
               "pulses": spec.pulses, "orders": list(spec.orders),
               "critical_pairs": [list(p) for p in pairs],
               "frequency_change_hz": (F[-1] - F[0]).tolist(),
               "coriolis": "neglected (O(Omega / w) ~ 2 % of these flexural modes at 450 rpm)",
               "rotation_terms": "solid: geometric stiffness of the zero-ND centrifugal "
                                 "prestress, spin softening of the consistent mass",
               "ritz_error": ritz}
    arrays = {"campbell": xr.Dataset(
        {"frequency": (("speed", "nd"), F, {"units": "Hz"})},
        coords={"rpm": ("speed", rpm, {"units": "rpm"}), "nd": ("nd", camp.nd)})}
    found = [c for c in crit if c["rpm"] is not None]
    headline = (f"{rpm.size} speeds {rpm[0]:g}-{rpm[-1]:g} rpm, {camp.nd.size} ND branches "
                "(solid); " + ("; ".join(
                    f"o = {c['order']} ({c['nd']}ND): {c['rpm']:.1f} rpm at "
                    f"{c['frequency_hz']:.2f} Hz"
                    + (f" (paper {c['paper_rpm']:g})" if "paper_rpm" in c else "")
                    for c in found) if found else "no critical speed in the range"))
    verdict = judge({"ritz_error": ritz}, thresholds={"ritz_error": 1e-6})

    def figures():
        return _campbell_figures(camp, crit, spec)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"critical_speeds_rpm": crit},
                          verdict=verdict)


# ================================================================================ modal
def run_solid_modal(model: SolidWheelCaseModel, spec, ctx: RunContext) -> AnalysisOutput:
    """Frequencies by ND of the unreduced sector, Table 1, the reduced wheel beside them."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel._case_figures import _modal_figures
    from fricdamp.models.tieboss_wheel.studies import modal_by_nd

    m = modal_by_nd(cyclic=model.sector.cyclic, n_modes=spec.n_modes)
    if not (model.paper and model.n_blades == 30):
        m.pop("table1", None)
        m.pop("max_table1_error", None)
    w = model.wheel()
    red = []
    for nd in m["nd"]:
        idx = np.flatnonzero(np.asarray(w.modes.nd) == nd)
        red.append(float(w.modes.omega[idx].min() / (2 * np.pi)))
    f = np.asarray(m["frequency_hz"])
    err = np.abs(np.asarray(red) / f - 1.0)
    summary = {"nd": m["nd"], "frequency_hz": m["frequency_hz"], "n_modes": spec.n_modes,
               "families_hz": m["families_hz"], "reduced_frequency_hz": red,
               "reduction_max_error": float(err.max()),
               "method": "unreduced sector, cyclic constraint, sparse shift-invert"}
    notes = []
    if "table1" in m:
        summary["table1"] = m["table1"]
        summary["max_table1_error"] = m["max_table1_error"]
        if m["max_table1_error"] > 0.01:
            notes.append(f"the first family is {100 * m['max_table1_error']:.3g} % off 003 "
                         "Table 1 (the default mesh is tuned to within 1 %)")
    if err.max() > 1e-3:
        notes.append(f"the reduced wheel's first family is up to {100 * err.max():.2g} % off "
                     "the unreduced sector's: raise n_interface_modes or n_modes")
    F = np.asarray(m["families_hz"])
    arrays = {"frequencies": xr.Dataset(
        {"frequency": (("nd", "mode"), F, {"units": "Hz"}),
         "reduced_frequency": (("nd",), np.asarray(red), {"units": "Hz"})},
        coords={"nd": ("nd", np.asarray(m["nd"])),
                "mode": ("mode", np.arange(1, F.shape[1] + 1))})}
    headline = (f"ND 0-{model.max_nd}: first family {f.min():.4g}-{f.max():.4g} Hz (open "
                f"contacts, {model.sector.info.get('sector_dof')} sector DOFs)")
    if "max_table1_error" in summary:
        headline += f"; Table 1 within {100 * summary['max_table1_error']:.2g} %"
    headline += f"; reduced wheel within {100 * err.max():.2g} %"

    def figures():
        return _modal_figures(summary) + _mesh_figure(model)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes)


def _mesh_figure(model: SolidWheelCaseModel) -> list:
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    solid = model.solid
    if solid is None:
        return []
    fig = Figure(figsize=(11.0, 5.0), layout="constrained")
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    facets = solid.boundary_facets
    corners = facets[:, :3] if facets.shape[1] in (3, 6) else facets[:, :4]
    tri = solid.points[corners]
    ax.add_collection3d(Poly3DCollection(tri, facecolor="0.75", edgecolor="0.25",
                                         linewidth=0.1))
    for name, color in (("contact_left", "C3"), ("contact_right", "C3"), ("cut_left", "C0"),
                        ("cut_right", "C0"), ("clamp", "k")):
        nodes = solid.node_sets.get(name)
        if nodes is not None and len(nodes):
            x = solid.points[nodes]
            ax.scatter(x[:, 0], x[:, 1], x[:, 2], s=1.5, color=color)
    lo, hi = solid.points.min(axis=0), solid.points.max(axis=0)
    c, r = 0.5 * (lo + hi), 0.5 * (hi - lo).max()
    ax.set(xlim=(c[0] - r, c[0] + r), ylim=(c[1] - r, c[1] + r), zlim=(c[2] - r, c[2] + r),
           xlabel="x [m]", ylabel="y [m]", zlabel="z [m]")
    info = model.sector.info
    ax.set_title(f"one sector: {info.get('n_elements_sector')} {info.get('element_type')} "
                 f"elements, {info.get('sector_dof')} DOFs (red: contact faces, blue: cuts)",
                 fontsize="small")
    ax2 = fig.add_subplot(1, 2, 2)
    N = model.n_blades
    for j in range(N):
        a = 2 * np.pi * j / N
        Rz = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        xy = solid.points[corners[::7, 0], :2] @ Rz.T
        ax2.plot(xy[:, 0], xy[:, 1], ",", color="C0" if j else "C3")
    ax2.set_aspect("equal")
    ax2.set(xlabel="x [m]", ylabel="y [m]")
    ax2.set_title(f"the wheel: {N} sectors, {info.get('wheel_dof')} DOFs (sector 0 red)",
                  fontsize="small")
    return [("mesh.png", "The solid sector mesh (contact faces and cyclic cuts marked) and "
             "the wheel of its rotated copies", fig)]


# ================================================================================ decay
def _decay_entry(run, model) -> dict:
    from fricdamp.models.tieboss_wheel._case_spec import PAPER_DAMPING_RATIO

    e = run.summary()
    e["paper_damping_ratio"] = (PAPER_DAMPING_RATIO.get(run.nd) if model.paper
                                and model.n_blades == 30 else None)
    if run.decay is not None:
        env = run.decay.envelope
        e["envelope_time_s"] = env.time.tolist()
        e["envelope_m"] = env.amplitude.tolist()
    else:
        e["frequency_hz"] = None
    return e


def _decays(model, spec, settings, offset, ctx):
    w = model.wheel()
    method = ctx.solver.method
    runs = []
    for nd in spec.nodal_diameters:
        runs.append(w.free_decay(nd, amplitude_m=spec.amplitude_m, duration_s=spec.duration_s,
                                 dt=spec.time_step_s, settings=settings, offset=offset,
                                 forcing=spec.forcing, save_every=spec.save_every,
                                 method=method, progress=ctx.progress))
    return runs


def run_solid_free_attenuation(model: SolidWheelCaseModel, spec,
                               ctx: RunContext) -> AnalysisOutput:
    """003's strategy on the reduced solid wheel for each ND (module docstring)."""
    import xarray as xr

    from fricdamp.models.tieboss_wheel._case_spec import PAPER_DAMPING_RATIO

    off, fn = model.offset()
    notes = []
    if spec.n_modes != 10:
        notes.append("[analysis.free_attenuation] n_modes is not used by the solid wheel (its "
                     "reduction is set in [model])")
    runs = _decays(model, spec, model.settings, off, ctx)
    entries = [_decay_entry(r, model) for r in runs]
    if spec.compare_modal_forcing:
        other = "modal" if spec.forcing == "tieboss" else "tieboss"
        w = model.wheel()
        for e, r in zip(entries, runs, strict=True):
            e[f"damping_ratio_{other}_forcing"] = w.free_decay(
                r.nd, amplitude_m=spec.amplitude_m, duration_s=spec.duration_s,
                dt=spec.time_step_s, settings=model.settings, offset=off, forcing=other,
                save_every=spec.save_every, method=ctx.solver.method,
                progress=ctx.progress).damping_ratio
    for r in runs:
        if r.decay is None:
            notes.append(f"{r.nd}ND: too few envelope peaks for a damping ratio in "
                         f"{spec.duration_s:g} s; lengthen duration_s")
    ebe = max(r.energy_balance_error for r in runs)
    if ebe > 1e-3:
        notes.append(f"energy balance error {ebe:.2g}: reduce time_step_s")
    notes += _loose_notes(runs)
    summary = {
        "nodal_diameters": list(spec.nodal_diameters),
        "damping_ratio": {f"{r.nd}ND": r.damping_ratio for r in runs},
        "frequency_hz": {f"{e['nd']}ND": e["frequency_hz"] for e in entries},
        "reduced_dof": model.wheel().reduced_dof, "contact_pairs": int(
            model.wheel().basis.n_contacts), "forcing": spec.forcing,
        "method": ctx.solver.method, "energy_balance_error": float(ebe),
        "prestress_normal_force_N": fn, "contact_offset_m": off,
        "transient_runtime_s": float(sum(r.runtime_s for r in runs)),
        "transient_cpu_s": float(sum(r.cpu_s for r in runs)),
    }
    if model.paper and model.n_blades == 30:
        summary["paper_damping_ratio"] = {f"{k}ND": v for k, v in PAPER_DAMPING_RATIO.items()}
    n = min(r.t.size for r in runs)
    arrays = {"decay": xr.Dataset(
        {"probe": (("nd", "time"), np.stack([r.signal[:n] for r in runs]), {"units": "m"}),
         "blades": (("nd", "time", "blade"), np.stack([r.blades[:n] for r in runs]),
                    {"units": "m"}),
         "contact_status": (("nd", "time", "contact", "pair"),
                            np.stack([r.status[:n] for r in runs]),
                            {"meaning": "0 open, 1 stick, 2 slip"})},
        coords={"nd": ("nd", np.asarray(spec.nodal_diameters)),
                "time": ("time", runs[0].t[:n], {"units": "s"})})}
    if all(r.resultants is not None for r in runs):
        nc = min(r.t_contacts.size for r in runs)

        def stack(get):
            return np.stack([get(r.resultants)[:nc] for r in runs])

        arrays["contact_resultants"] = xr.Dataset(
            {"normal_force": (("nd", "time", "contact"), stack(lambda q: q.normal_force),
                              {"units": "N", "meaning": "compression positive"}),
             "tangential_force": (("nd", "time", "contact", "tangent"),
                                  stack(lambda q: q.tangential_force), {"units": "N"}),
             "moment": (("nd", "time", "contact", "axis"), stack(lambda q: q.moment),
                        {"units": "N m", "meaning": "about the face centroid: twisting "
                         "(normal), tilting (t1, t2)"}),
             "center_of_pressure": (("nd", "time", "contact", "tangent"),
                                    stack(lambda q: q.center_of_pressure),
                                    {"units": "m", "meaning": "from the face centroid"})},
            coords={"nd": ("nd", np.asarray(spec.nodal_diameters)),
                    "time": ("time", runs[0].t_contacts[:nc], {"units": "s"}),
                    "tangent": ("tangent", ["t1", "t2"]),
                    "axis": ("axis", ["n", "t1", "t2"])})
    headline = ", ".join(
        f"{r.nd}ND: zeta {100 * r.damping_ratio:.3g} %"
        + (f" (paper {100 * PAPER_DAMPING_RATIO[r.nd]:.2g} %)"
           if model.paper and r.nd in PAPER_DAMPING_RATIO else "") for r in runs) \
        + (f" from {1e3 * spec.amplitude_m:.3g} mm over {spec.duration_s:g} s; "
           f"{summary['contact_pairs']} node pairs, {summary['reduced_dof']} reduced DOFs; "
           f"transients {summary['transient_runtime_s']:.3g} s")

    def figures():
        return _decay_figures(runs, model)

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"decay": entries},
                          verdict=_decay_verdict(runs, spec.time_step_s, spec.duration_s))


def _decay_verdict(runs, dt: float, duration: float):
    """Verdict on solid decays: energy balance, Newmark period error of each decaying mode
    (its frequency times the step), the share of steps accepted at the loose residual
    (limit 1 %: beyond it the contact history is not the converged one), and a damping
    ratio for every ND."""
    from fricdamp.verdict import THRESHOLDS, judge, newmark_period_error

    n_steps = max(int(round(duration / dt)), 1)
    freq = [r.decay.mean_frequency_hz for r in runs if r.decay is not None]
    est = {"energy_balance_error": max(r.energy_balance_error for r in runs),
           "period_error": float(max((newmark_period_error(2 * np.pi * f * dt)
                                      for f in freq), default=0.0)),
           "loose_step_fraction": max(r.meta.get("n_loose_steps", 0) for r in runs) / n_steps}
    reasons = [f"{r.nd}ND: too few envelope peaks for a damping ratio (lengthen duration_s)"
               for r in runs if r.decay is None]
    return judge(est, thresholds={**THRESHOLDS, "loose_step_fraction": 1e-2},
                 reasons=reasons)


def _loose_notes(runs) -> list[str]:
    """Notes on steps accepted at a loose Newton residual (see integrate_modal)."""
    out = []
    for r in runs:
        n = r.meta.get("n_loose_steps", 0)
        if n:
            out.append(f"{r.nd}ND (penalty factor {r.meta['penalty_factor']:g}): {n} time "
                       f"steps accepted at a Newton residual up to "
                       f"{r.meta['largest_loose_residual']:.1e} of the displacement scale "
                       "(stick/slip cycling); energy balance error "
                       f"{r.energy_balance_error:.2g}")
    return out


def _status_instants(run) -> list[int]:
    """Saved instants for the status maps: the start, the largest slip fraction in the first
    and in the last third of the record."""
    frac = np.mean(run.status[:, :2] == 2, axis=(1, 2))
    n = frac.size
    first = int(np.argmax(frac[: max(n // 3, 1)]))
    last = int(n - n // 3 + np.argmax(frac[n - n // 3:])) if n >= 3 else n - 1
    return sorted({min(1, n - 1), first, last})


def _decay_figures(runs, model) -> list:
    from matplotlib.lines import Line2D

    from fricdamp import plot

    figs = []
    fig, axes = plot.new_figure(len(runs), 1, width=8.0, height=3.0,
                                title="Free attenuation of the solid wheel (003 section 3)")
    for ax, r in zip(axes[:, 0], runs, strict=True):
        ax.plot(r.t, 1e3 * r.signal, lw=0.6, color="C0", label="probe, blade 0")
        if r.decay is not None:
            env = r.decay.envelope
            ax.plot(env.time, 1e3 * env.amplitude, "o", ms=3, color="C3", label="envelope")
        ax.set_ylabel("displacement [mm]")
        ax.set_title(f"{r.nd}ND: zeta = {100 * r.damping_ratio:.3g} %", fontsize="small")
        ax.legend(fontsize="small", loc="upper right")
    axes[-1, 0].set_xlabel("time [s]")
    figs.append(("decay.png", "Probe displacement of blade 0 and its envelope for each ND "
                 "(damping ratio from the logarithmic decrement)", fig))
    xy = model.sector.patch.face_coordinates() * 1e3
    for r in runs:
        inst = _status_instants(r)
        fig, axes = plot.new_figure(2, len(inst), width=3.2 * len(inst) + 1.0, height=3.0,
                                    title=f"Contact status over the faces, {r.nd}ND "
                                          "(003 Figs 17-18)")
        N = r.status.shape[1]
        for col, i in enumerate(inst):
            for row, (c, name) in enumerate(((0, "B (blades 0 | 1)"),
                                             (N - 1, f"A (blades {N - 1} | 0)"))):
                ax = axes[row, col]
                st = r.status[i, c]
                ax.scatter(xy[:, 0], xy[:, 1], c=[STATE_COLORS[s] for s in st], s=40,
                           edgecolors="k", linewidths=0.3)
                ax.set_aspect("equal")
                ax.set_title(f"contact {name}, t = {1e3 * r.t[i]:.2f} ms", fontsize="x-small")
                ax.set_xlabel("t1 (radial) [mm]", fontsize="x-small")
                ax.set_ylabel("t2 [mm]", fontsize="x-small")
        handles = [Line2D([], [], marker="o", ls="", color=c, label=lab)
                   for c, lab in zip(STATE_COLORS, ("open", "stick", "slip"), strict=True)]
        fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize="small")
        figs.append((f"contact_status_{r.nd}nd.png", f"{r.nd}ND: state of every node pair of "
                     "contacts A and B at chosen instants (grey open, blue stick, red slip)",
                     fig))
    if all(r.resultants is not None for r in runs):
        figs.append(_resultant_figure(runs))
    return figs


def _resultant_figure(runs):
    """Resultants of contact B (blades 0 | 1) over each decay: forces and moments."""
    from fricdamp import plot

    fig, axes = plot.new_figure(len(runs), 2, width=10.0, height=2.8,
                                title="Contact B (blades 0 | 1): resultants over the face")
    for row, r in zip(axes, runs, strict=True):
        q, t = r.resultants, 1e3 * r.t_contacts
        row[0].plot(t, q.normal_force[:, 0], color="C0", label="normal N")
        row[0].plot(t, np.hypot(*q.tangential_force[:, 0].T), color="C3",
                    label="tangential |T|")
        row[0].set_ylabel("force [N]")
        row[0].set_title(f"{r.nd}ND", fontsize="small")
        row[1].plot(t, 1e3 * q.moment[:, 0, 0], color="C2", label="twisting M_n")
        row[1].plot(t, 1e3 * np.hypot(q.moment[:, 0, 1], q.moment[:, 0, 2]), color="C1",
                    label="tilting |M_t|")
        row[1].set_ylabel("moment [N mm]")
        for ax in row:
            ax.legend(fontsize="x-small", loc="upper right")
    for ax in axes[-1]:
        ax.set_xlabel("time [ms]")
    return ("contact_resultants.png", "Resultant normal and tangential force of contact B and "
            "its moments about the face centroid (twisting about the normal, tilting from "
            "how the pressure is spread: edge contact)", fig)


# ================================================================================ penalty
class PenaltyConvergenceAnalysis(Section):
    """``[analysis.penalty_convergence]``: damping against the penalty factor at the same
    prestress (the offset is re-calibrated for each factor)."""

    penalty_factors: list[Positive] = Field([1.0, 10.0, 100.0], min_length=3, max_length=10,
                                            description="factors of k_n = factor E A / h")
    nodal_diameters: list[Annotated[int, Field(ge=0, le=1000)]] = Field(
        [2, 6], min_length=1, max_length=4, description="NDs of the decays")
    amplitude_m: Positive = Field(5e-4, le=0.01, description="initial probe displacement")
    duration_s: Positive = Field(0.1, le=10.0, description="length of each attenuation")
    time_step_s: Positive = Field(2e-5, le=1e-3, description="time step")
    save_every: int = Field(2, ge=1, le=1000, description="store every k-th step")
    forcing: Literal["tieboss", "modal"] = Field("tieboss", description="ND forces")

    @model_validator(mode="after")
    def _check(self):
        f = self.penalty_factors
        if sorted(f) != f or len(set(f)) != len(f):
            raise ValueError(f"penalty_factors must be increasing, got {f}")
        if f[-1] / f[0] < 100.0 * (1 - 1e-12):
            raise ValueError(f"penalty_factors must span at least 100x, got {f}")
        return self


def _check_penalty(model, spec) -> None:
    if not is_solid(model):
        raise CaseError("[analysis.penalty_convergence] needs [model] type = "
                        "'tieboss_wheel_solid' or 'cyclic_sector'")
    bad = [nd for nd in spec.nodal_diameters if nd > model.max_nd]
    if bad:
        raise CaseError(f"nodal_diameters = {spec.nodal_diameters}: ND {bad[0]} does not "
                        f"exist; the wheel has nodal diameters 0 to {model.max_nd}")


def run_penalty_convergence(model: SolidWheelCaseModel, spec: PenaltyConvergenceAnalysis,
                            ctx: RunContext) -> AnalysisOutput:
    """Decays for each penalty factor at the same prestress (module docstring)."""
    zeta = {nd: [] for nd in spec.nodal_diameters}
    offsets, forces = [], []
    loose, all_runs = [], []
    for fac in spec.penalty_factors:
        s = model.settings.with_(penalty_factor=float(fac))
        off, fn = model.offset(s)
        offsets.append(off)
        forces.append(fn)
        runs = _decays(model, spec, s, off, ctx)
        all_runs += runs
        loose += _loose_notes(runs)
        for r in runs:
            zeta[r.nd].append(r.damping_ratio)
    summary = {"penalty_factor": list(spec.penalty_factors), "offset_m": offsets,
               "prestress_normal_force_N": forces}
    rel = {}
    for nd, z in zeta.items():
        summary[f"damping_ratio_{nd}nd"] = z
        rel[nd] = abs(z[-1] / z[-2] - 1.0) if z[-2] else float("inf")
    summary["relative_change_last"] = {f"{nd}ND": v for nd, v in rel.items()}
    summary["converged"] = bool(all(v <= 0.05 for v in rel.values()))
    notes = loose + ([] if summary["converged"] else [
        "the damping still moves by more than 5 % between the two largest penalty factors"])
    headline = "; ".join(
        f"{nd}ND zeta " + " / ".join(f"{100 * v:.3g}" for v in z) + " %"
        for nd, z in zeta.items()) + " at penalty factors " + " / ".join(
        f"{f:g}" for f in spec.penalty_factors)

    def figures():
        from fricdamp import plot

        fig, axes = plot.new_figure(1, 1, width=6.0, height=3.8,
                                    title="Damping against the contact penalty (same "
                                          "prestress)")
        ax = axes[0, 0]
        for nd, z in zeta.items():
            ax.semilogx(spec.penalty_factors, 100 * np.asarray(z), "o-", label=f"{nd}ND")
        ax.set_xlabel("penalty factor (k_n = factor E A / h)")
        ax.set_ylabel("damping ratio [%]")
        ax.legend(fontsize="small")
        return [("penalty_convergence.png", "Damping ratio by ND against the penalty factor "
                 "at the same 2.4 N prestress", fig)]

    verdict = _decay_verdict(all_runs, spec.time_step_s, spec.duration_s)
    if not summary["converged"]:
        from fricdamp.verdict import judge

        verdict = judge(verdict.estimates, thresholds={}, reasons=(
            *verdict.reasons, "the damping moves by more than 5 % between the two largest "
            "penalty factors: not converged in the penalty"))
    return AnalysisOutput(summary=summary, arrays={}, figures=figures, headline=headline,
                          notes=notes, verdict=verdict)


# ================================================================================ mistuning
class MistuningAnalysis(Section):
    """``[analysis.mistuning]``: Young's-modulus scatter from blade to blade (normal, seeded),
    the wheel of reduced sectors assembled without cyclic symmetry, its lowest modes with the
    split doublets (003 Table 1 lists each ND as a pair)."""

    youngs_modulus_scatter: float = Field(0.005, ge=0.0, le=0.2, description="standard "
                                          "deviation of the per-blade stiffness factor")
    seed: int = Field(1, ge=0, description="random seed of the scatter")
    n_modes: int = Field(32, ge=2, le=500, description="lowest modes of the wheel")


def _check_mistuning(model, spec) -> None:
    if not is_solid(model):
        raise CaseError("[analysis.mistuning] needs [model] type = 'tieboss_wheel_solid' or "
                        "'cyclic_sector'")


def run_mistuning(model: SolidWheelCaseModel, spec: MistuningAnalysis,
                  ctx: RunContext) -> AnalysisOutput:
    """Doublet splits of the mistuned wheel (:func:`~fricdamp.structure.mistuning.
    mistuned_modes`), open contacts."""
    from fricdamp.models.tieboss_wheel.model import TABLE1_FEM_HZ
    from fricdamp.structure.mistuning import mistuned_modes

    w = model.wheel()
    red = w.reduced.sector
    N = model.n_blades
    rng = np.random.default_rng(spec.seed)
    factors = 1.0 + spec.youngs_modulus_scatter * rng.standard_normal(N)
    if factors.min() <= 0:
        raise CaseError("[analysis.mistuning] youngs_modulus_scatter is so large that a "
                        "blade's stiffness factor is <= 0")
    mm = mistuned_modes(red, spec.n_modes, probe_dofs=red.named_dofs["probe"][:3],
                        probe_direction=model.sector.probe_direction,
                        stiffness_factors=factors)
    tuned = mistuned_modes(red, spec.n_modes, probe_dofs=red.named_dofs["probe"][:3],
                           probe_direction=model.sector.probe_direction)
    splits = {}
    for nd in range(1, (N - 1) // 2 + 1):
        if np.count_nonzero(mm.nd == nd) >= 2:
            splits[f"{nd}ND"] = mm.doublet_split_hz(nd)
    summary = {"youngs_modulus_scatter": spec.youngs_modulus_scatter, "seed": spec.seed,
               "stiffness_factors": factors.tolist(),
               "frequency_hz": mm.frequency_hz.tolist(), "nd": mm.nd.tolist(),
               "tuned_frequency_hz": tuned.frequency_hz.tolist(),
               "localisation": mm.localisation.tolist(), "doublet_split_hz": splits}
    if model.paper and N == 30:
        summary["table1_split_hz"] = {f"{nd}ND": pair[1] - pair[0]
                                      for nd, pair in TABLE1_FEM_HZ.items() if len(pair) == 2}
    shown = [k for k in ("2ND", "3ND", "4ND", "5ND", "6ND") if k in splits]
    headline = (f"E scatter {100 * spec.youngs_modulus_scatter:.2g} %: doublet splits "
                + ", ".join(f"{k} {splits[k]:.3g} Hz" for k in shown))

    def figures():
        from fricdamp import plot

        fig, axes = plot.new_figure(1, 1, width=6.5, height=3.8, title="Mistuned wheel: "
                                    "split doublets (open contacts)")
        ax = axes[0, 0]
        ax.plot(tuned.nd, tuned.frequency_hz, "o", mfc="none", color="0.4", label="tuned")
        ax.plot(mm.nd, mm.frequency_hz, "x", color="C3",
                label=f"E scatter {100 * spec.youngs_modulus_scatter:.2g} %")
        if "table1_split_hz" in summary:
            for k, (nd, pair) in enumerate((n, p) for n, p in TABLE1_FEM_HZ.items()
                                           if len(p) == 2):
                ax.plot([nd, nd], pair, "s", mfc="none", color="C0",
                        label="003 Table 1, FEM pairs" if k == 0 else None)
        ax.set_xlabel("nodal diameter (dominant DFT harmonic of the probes)")
        ax.set_ylabel("frequency [Hz]")
        ax.legend(fontsize="small")
        return [("mistuning.png", "Frequencies of the mistuned wheel by dominant ND against "
                 "the tuned doublets and 003 Table 1's pairs", fig)]

    return AnalysisOutput(summary=summary, arrays={}, figures=figures, headline=headline)


# ================================================================================ registry
register_model("tieboss_wheel_solid", SolidWheelSpec, build_solid_wheel_case,
               description="paper 003's wheel as solid tet10 sectors with contact patches")
register_model("cyclic_sector", CyclicSectorSpec, build_cyclic_sector_case,
               description="a user's meshed cyclic sector with contact faces")
register_analysis("mistuning", MistuningAnalysis, run_mistuning, check=_check_mistuning,
                  description="blade-to-blade scatter: split doublets of the wheel")
register_analysis("penalty_convergence", PenaltyConvergenceAnalysis, run_penalty_convergence,
                  check=_check_penalty,
                  description="damping of the solid wheel against the contact penalty factor")
