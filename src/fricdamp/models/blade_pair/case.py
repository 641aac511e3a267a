"""Paper 001's two rotating shrouded blades as a case: ``[model] type = "blade_pair"`` with
``[analysis.campbell]`` (Figs 3-5) and ``[analysis.steady_state_sweep]`` (Figs 6-14).

The model is not a :class:`~fricdamp.structure.MechanicalSystem` but a
:class:`BladePairCaseModel` wrapping the 78-DOF
:class:`~fricdamp.models.blade_pair.model.BladePairModel` (two Rayleigh-beam blades with rigid
shrouds and the rigid wedge between them, 001 (1)-(18)). Its two friction contacts (A, B) are
part of the model -- equivalent viscous damping on the slip ellipse, 001 (19)-(34) -- so
``[[contacts]]`` are refused, and the generic analyses (free decay, FRF, ...) that need a
MechanicalSystem get a clear CaseError instead of an AttributeError.

Summary contract (issue 5)::

    n_dof: 78                                                   (top level)
    campbell: {"rpm": [...], "frequency_hz": [[...] per mode], "excitation_orders": [15, 20, 30],
               ...}
    steady_state: [{"k", "friction_coefficient", "rpm", "semi_axes_A_m": [[a, b], ...],
                    "semi_axes_B_m", "dissipated_energy_J", "energy_balance_error", ...}, ...]
                                                                (top level)

``steady_state`` is a list, and summary sections are dicts, so it is written at the top level
(:attr:`fricdamp.runner.AnalysisOutput.top_level`) by ``[analysis.steady_state_sweep]``, whose
own section ``steady_state_sweep`` holds the key numbers (resonance peaks, convergence,
energy balance). Both analyses write ``n_dof``.

Units in the case file are SI with the unit in the key name; angles in degrees (``_deg``),
spin speeds in rpm (``_rpm``). The keys are documented in ``docs/cases_blade_pair.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from fricdamp.case import NonNegative, Positive, Section
from fricdamp.errors import CaseError
from fricdamp.registry import (
    AnalysisOutput,
    BuildContext,
    ModelObject,
    NotAMechanicalSystemError,
    RunContext,
    register_analysis,
    register_model,
)
from fricdamp.verdict import judge


def crossing_speeds(rpm, frequency_hz, order: int) -> list[float]:
    """Speeds [rpm] where a Campbell branch meets ``k rpm / 60`` (see
    :func:`fricdamp.models.blade_pair.studies.crossing_speeds`)."""
    from fricdamp.models.blade_pair.studies import crossing_speeds as _cs

    return _cs(rpm, frequency_hz, order)

__all__ = [
    "BladePairCaseModel",
    "BladePairSpec",
    "CampbellAnalysis",
    "NotAMechanicalSystemError",
    "SteadyStateSweepAnalysis",
    "blade_pair_parameters",
    "build_blade_pair_case",
    "run_campbell",
    "run_steady_state_sweep",
]

#: The model type and the analyses of this module (used in messages).
MODEL_TYPE = "blade_pair"
_ANALYSES = "[analysis.campbell] and [analysis.steady_state_sweep]"

Order = Annotated[int, Field(ge=1, le=1000)]
Inertia = Annotated[list[Positive], Field(min_length=3, max_length=3)]
Point = Annotated[list[float], Field(min_length=2, max_length=2)]
Pair = Annotated[list[float], Field(min_length=2, max_length=2)]

#: Keys that take one value for both contacts or a pair [A, B]: (bound, strict, unit).
_PAIR_KEYS = {"contact_stiffness_N_per_m": (0.0, True, "N/m"),
              "contact_width_m": (0.0, True, "m"),
              "contact_height_m": (0.0, True, "m"),
              "friction_coefficient": (0.0, False, "")}


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


# ================================================================================ the model
class BladePairSpec(Section):
    """``[model] type = "blade_pair"``: paper 001's two rotating blades with a wedge friction
    element between the shrouds (:class:`~fricdamp.models.blade_pair.model.BladePairParameters`).

    The defaults are the library's (BladePairParameters(): a plausible shrouded steam-turbine
    stage, the paper not giving its blades); tests/cli/test_blade_pair_case.py checks that they
    agree.
    """

    # ---- blades (001 (1)-(2))
    hub_radius_m: Positive = Field(0.40, le=10.0, description="radius of the blade root node")
    blade_length_m: Positive = Field(0.20, le=10.0, description="root node to tip (shroud) "
                                                                "node")
    n_elements: int = Field(5, ge=1, le=30, description="beam elements per blade (001: 5, "
                                                        "78 DOFs)")
    chord_m: Positive = Field(0.030, le=1.0, description="blade section along the stagger "
                                                         "direction")
    thickness_m: Positive = Field(0.011, le=1.0, description="blade section across it")
    stagger_deg: float = Field(35.0, ge=0.0, le=90.0, description="chord from the axial "
                                                                  "direction towards z")
    youngs_modulus_Pa: Positive = Field(2.16e11, description="E of blades and root")
    density_kg_per_m3: Positive = Field(7700.0, description="rho of blades and root")
    poisson_ratio: float = Field(0.3, gt=-1.0, le=0.5, description="nu")
    blade_damping_s: NonNegative = Field(2.0e-6, le=1.0, description="beta of B_B = beta K_s")
    root_length_m: Positive = Field(0.020, le=1.0, description="root (dovetail) element "
                                                               "between disk rim and root node")
    root_chord_m: Positive = Field(0.040, le=1.0, description="root section")
    root_thickness_m: Positive = Field(0.030, le=1.0, description="root section")
    shroud_mass_kg: Positive = Field(0.07, description="rigid shroud at the tip node")
    shroud_inertia_kg_m2: Inertia = Field([1.1e-5, 1.5e-5, 2.4e-5], description="shroud's "
                                          "principal moments about the tip node, (x, y, z)")
    n_blades: int = Field(60, ge=3, le=10_000, description="blades on the wheel: pitch "
                                                           "2 pi / n_blades")
    # ---- friction element (001 (5)-(6))
    damper_mass_kg: Positive = Field(0.015, description="wedge m_D")
    damper_inertia_kg_m2: Inertia = Field([3.1e-7, 2.6e-7, 6.8e-7], description="wedge's "
                                          "principal moments about D, (x, y, z)")
    damper_radius_m: Positive = Field(0.595, description="r_D, radius of the wedge's centre D")
    contact_points_m: Annotated[list[Point], Field(min_length=2, max_length=2)] = Field(
        [[0.003, -0.006], [0.003, 0.006]], description="[[x_A, z_A], [x_B, z_B]] from D in the "
                                                        "wedge frame, z_A < 0 < z_B")
    delta_a_deg: float = Field(45.0, gt=0.0, lt=90.0, description="plane a (contact A) to "
                                                                  "the radial direction")
    delta_b_deg: float = Field(30.0, gt=0.0, lt=90.0, description="plane b (contact B) to "
                                                                  "the radial direction")
    # ---- contacts (001 (12)-(18), (26)-(34))
    contact_stiffness_N_per_m: Pair = Field([2.0e8, 2.0e8], description="normal contact "
                                            "stiffness k (one value or [A, B])")
    contact_width_m: Pair = Field([0.008, 0.008], description="effective rectangle along xi "
                                                              "(one value or [A, B])")
    contact_height_m: Pair = Field([0.020, 0.020], description="effective rectangle along eta "
                                                               "(one value or [A, B])")
    contact_damping_s: NonNegative = Field(5.0e-6, le=1.0, description="beta_C of "
                                                                      "B_C = beta_C K_C")
    friction_coefficient: Pair = Field([0.1, 0.1], description="f (one value or [A, B]) where "
                                       "an analysis gives none")
    friction_exponent: Positive = Field(1.0, le=10.0, description="p of 001 (27), (32); "
                                                                  "1 = Coulomb")
    damping_rule: Literal["coulomb", "paper"] = Field(
        "coulomb", description="equivalent damping on the ellipse axes")
    min_slip_m: Positive = Field(1e-9, le=1e-3, description="slip below which a contact "
                                                            "counts as stuck")
    tangential_stiffness_N_per_m: Positive | None = Field(
        None, description="stick stiffness k_t of the contacts in the equivalent-damping law "
                          "(a Jenkins element: stuck contacts act as springs); none: the "
                          "paper's law")
    # ---- excitation (001 (3), (10)-(11), Table 1)
    tangential_force_order1_N: NonNegative = Field(20.0, description="F_t^(1) per node: "
                                                   "F^(k) = F^(1)/k outside the table")
    axial_force_order1_N: NonNegative = Field(10.0, description="F_ax^(1) per node")
    table_orders: list[Order] = Field([15, 20, 30], max_length=100, description="orders k "
                                      "with explicit amplitudes (001 Table 1)")
    table_tangential_force_N: list[NonNegative] = Field(
        [1.33, 1.0, 0.63], max_length=100, description="F_t per blade node for table_orders")
    table_axial_force_N: list[NonNegative] = Field(
        [0.66, 0.5, 0.3], max_length=100, description="F_ax per blade node for table_orders")

    @field_validator(*_PAIR_KEYS, mode="before")
    @classmethod
    def _one_or_pair(cls, v, info):
        bound, strict, unit = _PAIR_KEYS[info.field_name]
        if _is_number(v):
            if not math.isfinite(v):
                raise ValueError(f"must be a finite number, got {v!r}")
            if v < bound or (strict and v == bound):
                u = f" {unit}" if unit else ""
                raise ValueError(f"must be {'>' if strict else '>='} {bound:g}{u}, got {v:g}")
            return [v, v]
        if not isinstance(v, list):
            raise ValueError(f"must be a number (both contacts) or a pair [A, B], got {v!r}")
        return v

    @field_validator(*_PAIR_KEYS, mode="after")
    @classmethod
    def _pair_bounds(cls, v, info):
        bound, strict, unit = _PAIR_KEYS[info.field_name]
        for name, x in zip("AB", v, strict=True):
            if x < bound or (strict and x == bound):
                u = f" {unit}" if unit else ""
                raise ValueError(f"contact {name} must be {'>' if strict else '>='} "
                                 f"{bound:g}{u}, got {x:g}")
        return v

    @model_validator(mode="after")
    def _geometry(self):
        if self.root_length_m >= self.hub_radius_m:
            raise ValueError(f"root_length_m = {self.root_length_m:g} m must be smaller than "
                             f"hub_radius_m = {self.hub_radius_m:g} m (the root element starts "
                             "at the disk rim)")
        tip = self.hub_radius_m + self.blade_length_m
        top = tip + 0.5 * self.blade_length_m
        if not self.hub_radius_m < self.damper_radius_m < top:
            raise ValueError(f"damper_radius_m = {self.damper_radius_m:g} m must lie between "
                             f"hub_radius_m ({self.hub_radius_m:g} m) and the tip radius + half "
                             f"a blade length ({top:g} m)")
        (xa, za), (xb, zb) = self.contact_points_m
        if not za < 0.0 < zb:
            raise ValueError(f"contact_points_m needs z_A < 0 < z_B (A towards blade 2), got "
                             f"z_A = {za:g} m, z_B = {zb:g} m")
        for name, x, z in (("A", xa, za), ("B", xb, zb)):
            half = (self.damper_radius_m + x) * math.tan(math.pi / self.n_blades)
            if abs(z) >= half:
                raise ValueError(f"contact_points_m: |z_{name}| = {abs(z):g} m must be smaller "
                                 f"than the half pitch at its radius, {half:.4g} m")
        n = len(self.table_orders)
        if len(self.table_tangential_force_N) != n or len(self.table_axial_force_N) != n:
            raise ValueError(f"table_tangential_force_N and table_axial_force_N must have one "
                             f"entry per table_orders entry ({n}), got "
                             f"{len(self.table_tangential_force_N)} and "
                             f"{len(self.table_axial_force_N)}")
        if len(set(self.table_orders)) != n:
            raise ValueError(f"table_orders lists an order twice: {self.table_orders}")
        return self


def blade_pair_parameters(spec: BladePairSpec):
    """The :class:`~fricdamp.models.blade_pair.model.BladePairParameters` of a ``[model]`` table
    (degrees to radians; raises ModelError)."""
    from fricdamp.models.blade_pair.model import BladePairParameters

    return BladePairParameters(
        hub_radius=spec.hub_radius_m, blade_length=spec.blade_length_m,
        n_elements=spec.n_elements, chord=spec.chord_m, thickness=spec.thickness_m,
        stagger=math.radians(spec.stagger_deg), youngs_modulus=spec.youngs_modulus_Pa,
        density=spec.density_kg_per_m3, poisson=spec.poisson_ratio,
        blade_damping=spec.blade_damping_s, root_length=spec.root_length_m,
        root_chord=spec.root_chord_m, root_thickness=spec.root_thickness_m,
        shroud_mass=spec.shroud_mass_kg, shroud_inertia=tuple(spec.shroud_inertia_kg_m2),
        n_blades=spec.n_blades, damper_mass=spec.damper_mass_kg,
        damper_inertia=tuple(spec.damper_inertia_kg_m2), damper_radius=spec.damper_radius_m,
        contact_points=tuple(tuple(p) for p in spec.contact_points_m),
        delta_a=math.radians(spec.delta_a_deg), delta_b=math.radians(spec.delta_b_deg),
        contact_stiffness=tuple(spec.contact_stiffness_N_per_m),
        contact_width=tuple(spec.contact_width_m), contact_height=tuple(spec.contact_height_m),
        contact_damping=spec.contact_damping_s,
        friction_coefficient=tuple(spec.friction_coefficient),
        friction_exponent=spec.friction_exponent, damping_rule=spec.damping_rule,
        tangential_force_order1=spec.tangential_force_order1_N,
        axial_force_order1=spec.axial_force_order1_N,
        excitation_table=tuple(zip(spec.table_orders, spec.table_tangential_force_N,
                                   spec.table_axial_force_N, strict=True)),
        min_slip=spec.min_slip_m, tangential_stiffness=spec.tangential_stiffness_N_per_m)


def _frequencies(K: np.ndarray, M: np.ndarray) -> np.ndarray:
    import scipy.linalg as sla

    lam = sla.eigh(0.5 * (K + K.T), M, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)


@dataclass(frozen=True, eq=False)
class BladePairCaseModel(ModelObject):
    """The model object of ``[model] type = "blade_pair"``.

    Attributes
    ----------
    model : BladePairModel
        The assembled 001 model (DOFs ``[blade 1, wedge, blade 2]``, 001 (7)).
    """

    model: Any
    MODEL_TYPE: ClassVar[str] = MODEL_TYPE
    MODEL_DESCRIPTION: ClassVar[str] = "paper 001's two blades with a wedge"
    MODEL_ANALYSES: ClassVar[str] = _ANALYSES

    @property
    def n_dof(self) -> int:
        return int(self.model.n_dof)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.model.dof_names)

    @property
    def params(self):
        """The :class:`~fricdamp.models.blade_pair.model.BladePairParameters`."""
        return self.model.params

    def friction_coefficient(self):
        """The model's f: one float when A and B share it, else the pair (f_A, f_B)."""
        fa, fb = self.model.params.friction_coefficient
        return fa if fa == fb else (fa, fb)

    def describe(self) -> dict:
        """Key numbers for summary.json ``model``: layout, contacts, zero-speed frequencies.

        ``natural_frequencies_free_hz``: undamped, at zero speed (no normal load, so no
        friction), ``(K_s + K_C, M)``; the first is the wedge's axial translation, held by
        friction only (~0 Hz). ``natural_frequencies_stuck_hz``: the same with the six friction
        coordinates (slip along xi, eta and rotation about the normal, at A and B) locked.
        The first 12 of each.
        """
        import scipy.linalg as sla

        m = self.model
        p = m.params
        K0 = m.stiffness(0.0)
        T = sla.null_space(m.friction_projection)
        n_show = 12
        free = _frequencies(K0, m.M)[:n_show]
        stuck = _frequencies(T.T @ K0 @ T, T.T @ m.M @ T)[:n_show]
        ang = m.contact_angles
        return {
            "type": MODEL_TYPE,
            "n_dof": self.n_dof,
            "dof_names": list(self.names),
            "blade_dofs": int(m.n_blade_dof),
            "damper_dofs": 6,
            "contacts": [{"name": c, "law": "equivalent Coulomb friction on the slip ellipse "
                          f"(001 (26)-(34), rule {p.damping_rule!r})", "n_contacts": 1,
                          "n_dir": 3} for c in ("A", "B")],
            "pitch_angle_deg": math.degrees(p.pitch_angle),
            "contact_angles_deg": {k: math.degrees(v) for k, v in ang.items()},
            "torque_arms_m": [float(v) for v in m.torque_arms],
            "normal_loads_per_rad_s_squared_N_s2": [float(v) for v in m.normal_loads(1.0)],
            "tip_radius_m": p.tip_radius,
            "natural_frequencies_free_hz": free.tolist(),
            "natural_frequencies_stuck_hz": stuck.tolist(),
        }


def build_blade_pair_case(spec: BladePairSpec, ctx: BuildContext) -> BladePairCaseModel:
    """Builder of ``[model] type = "blade_pair"`` (raises ModelError)."""
    from fricdamp.models.blade_pair.model import build_blade_pair

    return BladePairCaseModel(build_blade_pair(blade_pair_parameters(spec)))


def _require_model(model, table: str) -> BladePairCaseModel:
    if not isinstance(model, BladePairCaseModel):
        raise CaseError(f"{table} needs [model] type = {MODEL_TYPE!r} (paper 001's two blades "
                        "with a wedge)")
    return model


def _speed_range(spec) -> None:
    if spec.speed_max_rpm <= spec.speed_min_rpm:
        raise ValueError(f"speed_max_rpm ({spec.speed_max_rpm:g} rpm) must be larger than "
                         f"speed_min_rpm ({spec.speed_min_rpm:g} rpm)")


def _f_label(f) -> str:
    a = np.atleast_1d(np.asarray(f, float))
    return f"{a[0]:g}" if a.size == 1 or a[0] == a[1] else f"[{a[0]:g}, {a[1]:g}]"


# ================================================================================ Campbell
class CampbellAnalysis(Section):
    """``[analysis.campbell]``: imaginary parts of the eigenvalues of the linearised 001 (8)
    vs spin speed, with the equivalent friction damping of a steady state (001 section 4.1,
    Figs 3-4), the excitation lines ``k Omega`` and optionally complex mode shapes (Fig. 5)."""

    speed_min_rpm: NonNegative = Field(0.0, le=1e5, description="lowest speed (0 allowed: "
                                       "no normal load, no friction)")
    speed_max_rpm: Positive = Field(2500.0, le=1e5, description="highest speed")
    n_speeds: int = Field(51, ge=2, le=2000, description="speeds, evenly spaced")
    n_modes: int = Field(15, ge=1, description="lowest complex pairs reported")
    excitation_orders: list[Order] = Field([15, 20, 30], min_length=1, max_length=20,
                                           description="orders k of the lines f = k rpm / 60")
    friction: bool = Field(True, description="include the equivalent friction damping B_e")
    steady_state_order: Order = Field(30, description="order k of the steady state whose "
                                                      "B_e enters (001 Fig. 3: 30)")
    friction_coefficient: NonNegative | None = Field(
        None, description="f of that steady state (default the model's)")
    damping_source: Literal["linear", "converged"] = Field(
        "linear", description="B_e from the response without friction damping (001 section "
                              "4.1), or from the converged steady state")
    mode_shapes_speed_rpm: Positive | None = Field(
        None, le=1e5, description="speed of the complex mode shapes (001 Fig. 5: 2000); "
                                  "none if absent")
    n_mode_shapes: int = Field(3, ge=1, le=10, description="mode shapes drawn")

    @model_validator(mode="after")
    def _check(self):
        _speed_range(self)
        if len(set(self.excitation_orders)) != len(self.excitation_orders):
            raise ValueError(f"excitation_orders lists an order twice: {self.excitation_orders}")
        return self


def _campbell_friction(model: BladePairCaseModel, spec: CampbellAnalysis):
    if spec.friction_coefficient is not None:
        return spec.friction_coefficient
    f = model.friction_coefficient()
    if not isinstance(f, float):
        raise CaseError(f"friction_coefficient: the model's is a pair {list(f)}; give the "
                        "steady state's f here (one value for both contacts)")
    return f


def _check_campbell(model, spec: CampbellAnalysis) -> None:
    model = _require_model(model, "[analysis.campbell]")
    if spec.n_modes > model.n_dof:
        raise CaseError(f"n_modes = {spec.n_modes}: the model has {model.n_dof} DOFs, so at "
                        f"most {model.n_dof} complex pairs")
    if spec.friction:
        _campbell_friction(model, spec)


def zero_speed_eigenvalues(model, n_modes: int) -> dict:
    """Eigenvalues at zero speed: ``(M, B + B_C, K_s + K_C)`` in first-order form.

    At Omega = 0 the normal loads ``N ~ Omega^2`` (001 (6)) vanish and with them every
    friction force, so the linearised system is exactly the one without friction damping
    (the equivalent damping ``c ~ f N / (k Omega a)`` tends to 0 with Omega as well). Same
    classification and ordering as :func:`~fricdamp.models.blade_pair.studies.
    campbell_diagram`.

    Returns
    -------
    dict
        ``frequency_hz``, ``damping_ratio`` (n_modes, None beyond the complex pairs),
        ``complex_pairs``, ``real_eigenvalues``.
    """
    import scipy.linalg as sla

    from fricdamp.models.blade_pair.studies import _blas1, _classify, _state_matrix

    with _blas1():
        A = _state_matrix(np.linalg.inv(model.M), model.stiffness(0.0),
                          model.damping(0.0, gyroscopic=False))
        lam = sla.eig(A, right=False, check_finite=False)
    up, n_real, n_complex = _classify(lam)
    m = min(int(n_modes), up.size)
    f = [float(v) for v in up[:m].imag / (2 * np.pi)] + [None] * (int(n_modes) - m)
    z = [float(v) for v in -up[:m].real / np.abs(up[:m])] + [None] * (int(n_modes) - m)
    return {"frequency_hz": f, "damping_ratio": z, "complex_pairs": n_complex,
            "real_eigenvalues": n_real}


def run_campbell(model: BladePairCaseModel, spec: CampbellAnalysis,
                 ctx: RunContext) -> AnalysisOutput:
    """Campbell diagram of the 001 model (:func:`~fricdamp.models.blade_pair.studies.
    campbell_diagram`), a zero-speed column if the range starts at 0
    (:func:`zero_speed_eigenvalues`), the crossings of the excitation lines and optionally
    the complex mode shapes."""
    import xarray as xr

    from fricdamp.models.blade_pair.studies import campbell_diagram, complex_modes

    obj = _require_model(model, "[analysis.campbell]")
    m = obj.model
    rpm = np.linspace(spec.speed_min_rpm, spec.speed_max_rpm, spec.n_speeds)
    f = _campbell_friction(obj, spec) if spec.friction else 0.0
    opts = dict(order=spec.steady_state_order, friction_coefficient=f, friction=spec.friction,
                damping_source=spec.damping_source)
    camp = campbell_diagram(m, rpm[rpm > 0], n_modes=spec.n_modes,
                            excitation_orders=spec.excitation_orders, **opts)
    if rpm[0] == 0.0:
        z = zero_speed_eigenvalues(m, spec.n_modes)
        camp["rpm"] = [0.0] + camp["rpm"]
        for key in ("frequency_hz", "damping_ratio"):
            camp[key] = [[z[key][i]] + row for i, row in enumerate(camp[key])]
        for key in ("complex_pairs", "real_eigenvalues"):
            camp[key] = [z[key]] + camp[key]
    camp.pop("runtime_s", None)  # the runner times the analysis
    crossings = {}
    for k in spec.excitation_orders:
        crossings[f"k{k}"] = {f"mode{i + 1}_rpm": crossing_speeds(camp["rpm"], row, k)
                              for i, row in enumerate(camp["frequency_hz"][:6])}
    camp["crossing_speeds"] = crossings
    camp["zero_speed_note"] = ("at 0 rpm the normal loads vanish (001 (6)): the eigenvalues "
                               "are those of (M, B + B_C, K_s + K_C), without friction")
    modes = None
    if spec.mode_shapes_speed_rpm is not None:
        modes = complex_modes(m, spec.mode_shapes_speed_rpm, n_modes=spec.n_mode_shapes,
                              **opts)
        camp["mode_shapes"] = {"rpm": modes["rpm"], "frequency_hz": modes["frequency_hz"],
                               "damping_ratio": modes["damping_ratio"],
                               "normalised_on": modes["normalised_on"]}

    F = np.array(camp["frequency_hz"], dtype=float)
    Z = np.array(camp["damping_ratio"], dtype=float)
    coords = {"rpm": ("speed", np.asarray(camp["rpm"]), {"units": "rpm"}),
              "mode": ("mode", np.arange(1, F.shape[0] + 1))}
    arrays = {"eigenvalues": xr.Dataset(
        {"frequency_hz": (("mode", "speed"), F, {"units": "Hz"}),
         "damping_ratio": (("mode", "speed"), Z, {"units": "1"}),
         "complex_pairs": ("speed", np.asarray(camp["complex_pairs"])),
         "real_eigenvalues": ("speed", np.asarray(camp["real_eigenvalues"]))},
        coords=coords)}
    if modes is not None:
        X = np.array(modes["shapes"])                                   # (n, n_modes, 2)
        arrays["mode_shapes"] = xr.Dataset(
            {"shape_real": (("dof", "shape"), X[..., 0]),
             "shape_imag": (("dof", "shape"), X[..., 1]),
             "shape_frequency_hz": ("shape", np.asarray(modes["frequency_hz"]),
                                    {"units": "Hz"})},
            coords={"dof": ("dof", list(obj.names)),
                    "shape": ("shape", np.arange(1, X.shape[1] + 1))})

    # the headline crossing: the one next to the friction-energy peak of the steady state
    # whose damping enters (the resonance the sweep shows), not merely branch 1's first
    k_s = spec.steady_state_order
    r_pos = np.asarray(camp["rpm"], float)
    r_pos = r_pos[r_pos > 0]
    cross_k = sorted((c, i + 1) for i, row in enumerate(camp["frequency_hz"])
                     for c in crossing_speeds(camp["rpm"], row, k_s))
    peak_rpm = None
    if spec.friction and r_pos.size >= 2 and f > 0:
        from fricdamp.models.blade_pair.studies import steady_state_sweep

        e = steady_state_sweep(m, k_s, r_pos, [f])[0]
        peak_rpm = float(r_pos[int(np.argmax(e["dissipated_energy_J"]))])
    camp["steady_state_peak_rpm"] = peak_rpm
    near = None
    if cross_k:
        ref = peak_rpm if peak_rpm is not None else cross_k[0][0]
        near = min(cross_k, key=lambda cb: abs(cb[0] - ref))
    camp["peak_crossing"] = ({"rpm": near[0], "branch": near[1], "order": k_s}
                             if near else None)
    f0 = F[0, 0]
    headline = (f"{len(camp['rpm'])} speeds {rpm[0]:g}-{rpm[-1]:g} rpm, {F.shape[0]} branches"
                + (f"; first {f0:.4g} Hz at {rpm[0]:g} rpm" if np.isfinite(f0) else "")
                + (f"; {k_s} Omega meets branch {near[1]} at {near[0]:.0f} rpm" if near else "")
                + (_peak_phrase(k_s, f, peak_rpm, near[0], r_pos)
                   if near and peak_rpm is not None else ""))

    def figures():
        from fricdamp.models.blade_pair._case_figures import campbell_figures

        return campbell_figures(camp, modes, spec)

    return AnalysisOutput(summary=camp, arrays=arrays, figures=figures, headline=headline,
                          top_level={"n_dof": obj.n_dof})


def _peak_phrase(k: int, f: float, peak_rpm: float, cross_rpm: float, rpm) -> str:
    """Headline clause relating the steady state's energy peak to the nearest crossing."""
    step = float(np.max(np.diff(rpm))) if len(rpm) > 1 else 0.0
    if abs(cross_rpm - peak_rpm) <= step:
        return f", at the k = {k}, f = {f:g} friction-energy peak ({peak_rpm:.0f} rpm)"
    return (f"; the k = {k}, f = {f:g} friction-energy peak ({peak_rpm:.0f} rpm) is not at a "
            "crossing (a slip/stick optimum, not a resonance)")


# ================================================================================ steady states
class SteadyStateSweepAnalysis(Section):
    """``[analysis.steady_state_sweep]``: equivalent-linear steady states vs spin speed for
    each excitation order k and friction coefficient f (001 section 3): ellipse semi-axes and
    inclinations at A and B (Figs 6-8), friction energy per period (Figs 9-11), orbits at
    chosen speeds (Figs 12-14). Writes the top-level ``steady_state`` list."""

    orders: list[Order] = Field([15, 20, 30], min_length=1, max_length=10,
                                description="excitation orders k (w_k = k Omega)")
    friction_coefficients: list[NonNegative] | None = Field(
        None, min_length=1, max_length=10, description="f at both contacts, one sweep each "
                                                       "(default the model's)")
    speed_min_rpm: Positive = Field(100.0, le=1e5, description="lowest speed")
    speed_max_rpm: Positive = Field(2500.0, le=1e5, description="highest speed")
    n_speeds: int = Field(120, ge=2, le=5000, description="speeds, evenly spaced")
    orbit_speeds_rpm: list[Positive] | None = Field(
        None, max_length=6, description="speeds of the orbit plots (default the quartiles of "
                                        "the range; [] for none)")
    orbit_points: int = Field(73, ge=8, le=2000, description="points per orbit curve")
    tolerance: Positive = Field(1e-8, lt=1e-2, description="fixed-point tolerance (relative "
                                                           "change of the orbits)")
    max_iterations: int = Field(2000, ge=1, le=100_000, description="iterations per speed")
    # ---- the multi-harmonic stick-slip reference beside the equivalent linearisation
    harmonic_balance: bool = Field(True, description="also solve every speed by HB-AFT "
                                   "with Jenkins contacts, continued in speed")
    hb_harmonics: int = Field(5, ge=1, le=30, description="HB harmonics H")
    hb_samples: int = Field(64, ge=8, le=4096, description="AFT samples per period")
    hb_tangential_stiffness_N_per_m: Positive = Field(
        1e8, description="stick stiffness k_t of HB's Jenkins contacts (the model's "
                         "tangential_stiffness_N_per_m if given)")
    disagreement_threshold: Positive = Field(0.1, lt=10.0, description="relative eqlin/HB "
                                             "difference flagged (0.1 = 10 %)")
    negligible_fraction: NonNegative = Field(1e-3, lt=1.0, description="energies and tip "
                                             "amplitudes below this fraction of the sweep's "
                                             "largest are not flagged")
    normal_load_warning_ratio: Positive = Field(0.5, le=1.0, description="warn where the "
                                                "normal-force oscillation exceeds this "
                                                "fraction of the static normal load")
    crossing_window: int = Field(3, ge=1, le=50, description="grid steps around a peak "
                                 "searched for Campbell crossings")

    @model_validator(mode="after")
    def _check(self):
        _speed_range(self)
        if self.harmonic_balance and self.hb_samples < 2 * self.hb_harmonics + 1:
            raise ValueError(f"hb_samples = {self.hb_samples} must be >= 2 hb_harmonics + 1 "
                             f"= {2 * self.hb_harmonics + 1}")
        if len(set(self.orders)) != len(self.orders):
            raise ValueError(f"orders lists an order twice: {self.orders}")
        fcs = self.friction_coefficients or []
        if len(set(fcs)) != len(fcs):
            raise ValueError(f"friction_coefficients lists a value twice: {fcs}")
        return self

    def orbit_speeds(self) -> list[float]:
        if self.orbit_speeds_rpm is not None:
            return list(self.orbit_speeds_rpm)
        lo, hi = self.speed_min_rpm, self.speed_max_rpm
        return [lo + q * (hi - lo) for q in (0.25, 0.5, 0.75)]


def _check_sweep(model, spec: SteadyStateSweepAnalysis) -> None:
    _require_model(model, "[analysis.steady_state_sweep]")


def _sweep_entries(m, spec: SteadyStateSweepAnalysis, fcs: list) -> tuple[list, list]:
    """The contract entries (one per order x f) and the raw (k, f, result, damping) tuples."""
    from fricdamp.models.blade_pair.studies import _sweep_entry, solve_steady_states

    rpm = np.linspace(spec.speed_min_rpm, spec.speed_max_rpm, spec.n_speeds)
    entries, raw = [], []
    for k in spec.orders:
        for f, res, damp in solve_steady_states(m, k, rpm, fcs, tol=spec.tolerance,
                                                max_iter=spec.max_iterations):
            e = _sweep_entry(m, k, rpm, f, res, damp)
            phi = np.abs(res.contact_response[:, [2, 5]])             # rotation amplitudes
            phi = np.where(np.column_stack([e["rotation_stuck_A"], e["rotation_stuck_B"]]),
                           0.0, phi)
            e["rotation_amplitude_A_rad"] = phi[:, 0].tolist()
            e["rotation_amplitude_B_rad"] = phi[:, 1].tolist()
            e["torque_arms_m"] = [float(v) for v in m.torque_arms]
            e["min_slip_m"] = float(damp.min_amplitude)
            e["min_rotation_rad"] = [float(v) for v in np.atleast_1d(damp.min_rotation)]
            entries.append(e)
            raw.append((k, f, res, damp))
    return entries, raw


def _hb_pass(m, spec: SteadyStateSweepAnalysis, entries: list, raw: list) -> dict:
    """HB beside every eqlin sweep (in place: the entries gain ``hb``, the ratios and the
    bands); also the eqlin with the stick stiffness of HB (issue 16: does a stick spring
    move eqlin's stick threshold towards HB's?). Returns timings and counts."""
    import time

    from fricdamp.models.blade_pair.hb import compare_with_hb, hb_entry, hb_speed_sweep
    from fricdamp.models.blade_pair.model import build_blade_pair
    from fricdamp.models.blade_pair.studies import (
        _sweep_entry,
        solve_steady_states,
    )

    kt = m.params.tangential_stiffness or spec.hb_tangential_stiffness_N_per_m
    m_kt = m if m.params.tangential_stiffness else build_blade_pair(
        m.params.with_(tangential_stiffness=kt))
    t_hb = t_eq = 0.0
    n_fail = 0
    for e, (k, f, res, _) in zip(entries, raw, strict=True):
        rpm = np.asarray(e["rpm"])
        fab = np.broadcast_to(np.asarray(f, float), (2,))
        if not np.all(fab > 0):
            e["hb"] = None
            continue
        t0 = time.perf_counter()
        if m_kt is m:
            res_kt, e_kt = res, e
        else:
            (_, res_kt, damp_kt), = solve_steady_states(m_kt, k, rpm, [f], tol=spec.tolerance,
                                                        max_iter=spec.max_iterations)
            e_kt = _sweep_entry(m_kt, k, rpm, f, res_kt, damp_kt)
        t1 = time.perf_counter()
        hb = hb_speed_sweep(m, k, rpm, fab, tangential_stiffness=kt,
                            harmonics=spec.hb_harmonics, samples=spec.hb_samples,
                            guide=res_kt.response)
        t2 = time.perf_counter()
        t_eq += t1 - t0
        t_hb += t2 - t1
        n_fail += int(np.sum(~hb.success))
        e["hb"] = hb_entry(hb)
        opts = dict(threshold=spec.disagreement_threshold, negligible=spec.negligible_fraction)
        cmp_ = compare_with_hb(rpm, e["dissipated_energy_J"], e["tip_amplitude_m"],
                               hb.dissipated_energy, hb.tip_amplitude.max(axis=1),
                               hb.success, **opts)
        e.update(cmp_)
        if m_kt is not m:
            c_kt = compare_with_hb(rpm, e_kt["dissipated_energy_J"], e_kt["tip_amplitude_m"],
                                   hb.dissipated_energy, hb.tip_amplitude.max(axis=1),
                                   hb.success, **opts)
            e["eqlin_with_stick_stiffness"] = {
                "tangential_stiffness_N_per_m": kt,
                "dissipated_energy_J": e_kt["dissipated_energy_J"],
                "tip_amplitude_m": e_kt["tip_amplitude_m"],
                "stuck_A": e_kt["stuck_A"], "stuck_B": e_kt["stuck_B"],
                "eqlin_over_hb_energy": c_kt["eqlin_over_hb_energy"],
                "disagreement_band_rpm": c_kt["disagreement_band_rpm"],
                "disagreement_speeds": int(np.sum(c_kt["disagreement"]))}
    return {"hb_runtime_s": t_hb, "eqlin_stick_stiffness_runtime_s": t_eq,
            "hb_failed_speeds": n_fail, "hb_tangential_stiffness_N_per_m": float(kt)}


def _stick_agreement(e: dict, other: dict) -> float | None:
    """Fraction of the speeds (HB converged) where a sweep's stick flags of A and B both
    agree with HB's."""
    hb = e.get("hb")
    if not hb:
        return None
    ok = np.asarray(hb["success"], bool)
    if not ok.any():
        return None
    same = ((np.asarray(other["stuck_A"]) == np.asarray(hb["stuck_A"]))
            & (np.asarray(other["stuck_B"]) == np.asarray(hb["stuck_B"])))
    return float(np.mean(same[ok]))


def run_steady_state_sweep(model: BladePairCaseModel, spec: SteadyStateSweepAnalysis,
                           ctx: RunContext) -> AnalysisOutput:
    """Steady states vs speed (:func:`~fricdamp.models.blade_pair.studies.
    solve_steady_states`) for every order and friction coefficient, HB beside them
    (:func:`~fricdamp.models.blade_pair.hb.hb_speed_sweep`), the Campbell crossings at the
    peaks (:func:`~fricdamp.models.blade_pair.studies.peak_crossing`) and the orbits
    (:func:`~fricdamp.models.blade_pair.studies.orbits`) at the orbit speeds."""
    import time

    import xarray as xr

    from fricdamp.models.blade_pair.studies import orbits, peak_crossing

    obj = _require_model(model, "[analysis.steady_state_sweep]")
    m = obj.model
    fcs = (list(spec.friction_coefficients) if spec.friction_coefficients is not None
           else [obj.friction_coefficient()])
    t0 = time.perf_counter()
    entries, raw = _sweep_entries(m, spec, fcs)
    t_eqlin = time.perf_counter() - t0
    hb_info = _hb_pass(m, spec, entries, raw) if spec.harmonic_balance else {}
    o_rpm = spec.orbit_speeds()
    orb = {k: orbits(m, k, o_rpm, fcs, n_points=spec.orbit_points) for k in spec.orders} \
        if o_rpm else {}

    notes, peaks, reasons = [], {}, []
    n_cross = {"eqlin": 0, "hb": 0}
    thr = spec.disagreement_threshold
    for e, (k, f, res, _) in zip(entries, raw, strict=True):
        label = f"k = {k}, f = {_f_label(f)}"
        W = np.asarray(e["dissipated_energy_J"])
        i = int(np.nanargmax(W))
        pc = peak_crossing(m, k, f, e["rpm"], i, window=spec.crossing_window)
        n_cross["eqlin"] += pc["at_crossing"]
        nfr = np.maximum(e["normal_force_ratio_A"], e["normal_force_ratio_B"])
        peak = {
            "peak_rpm": e["rpm"][i], "peak_dissipated_energy_J": float(W[i]),
            "max_major_semi_axis_A_m": max(a for a, _ in e["semi_axes_A_m"]),
            "max_major_semi_axis_B_m": max(a for a, _ in e["semi_axes_B_m"]),
            "stuck_fraction": float(np.mean(np.array(e["stuck_A"]) & np.array(e["stuck_B"]))),
            "converged": e["converged"],
            "campbell_crossings_rpm": pc["crossings_rpm"],
            "peak_at_crossing": pc["at_crossing"],
            "max_normal_force_ratio": float(np.max(nfr)),
            "normal_force_ratio_at_peak": float(nfr[i])}
        e["peak_at_campbell_crossing"] = pc["at_crossing"]
        hb = e.get("hb")
        if hb:
            Wh = np.array([np.nan if v is None else v for v in hb["dissipated_energy_J"]])
            j = int(np.nanargmax(Wh)) if np.isfinite(Wh).any() else None
            if j is not None:
                pch = peak_crossing(m, k, f, e["rpm"], j, window=spec.crossing_window)
                n_cross["hb"] += pch["at_crossing"]
                peak.update({"hb_peak_rpm": e["rpm"][j],
                             "hb_peak_dissipated_energy_J": float(Wh[j]),
                             "hb_peak_at_crossing": pch["at_crossing"]})
            rW, rt = e["eqlin_over_hb_energy"][i], e["eqlin_over_hb_tip_amplitude"][i]
            peak.update({"eqlin_over_hb_energy_at_peak": rW,
                         "eqlin_over_hb_tip_amplitude_at_peak": rt,
                         "disagreement_band_rpm": e["disagreement_band_rpm"]})
            kt_e = e.get("eqlin_with_stick_stiffness")
            peak["stick_agreement_with_hb"] = _stick_agreement(e, e)
            if kt_e:
                peak["stick_agreement_with_hb_stick_stiffness"] = _stick_agreement(e, kt_e)
                peak["disagreement_speeds"] = int(np.sum(e["disagreement"]))
                peak["disagreement_speeds_stick_stiffness"] = kt_e["disagreement_speeds"]
            if not hb["success"][i]:
                notes.append(f"{label}: HB did not converge at the eqlin peak "
                             f"({e['rpm'][i]:.0f} rpm): that peak is not cross-checked")
            elif e["disagreement"][i]:
                what = []
                if rW is None or abs(rW - 1) > thr:
                    what.append("friction energy " + ("eqlin > 0, HB 0" if rW is None
                                                      else f"x{rW:.3g}"))
                if rt is None or abs(rt - 1) > thr:
                    what.append("tip amplitude " + ("n/a" if rt is None else f"x{rt:.3g}"))
                reasons.append(f"{label}: at the reported peak ({e['rpm'][i]:.0f} rpm) the "
                               f"slip-ellipse linearisation differs from multi-harmonic HB by "
                               f"more than {thr:.0%} ({', '.join(what)}): use HB there")
            if e["disagreement_band_rpm"]:
                notes.append(f"{label}: eqlin and HB differ by more than {thr:.0%} at "
                             f"{int(np.sum(e['disagreement']))} of {len(e['rpm'])} speeds, "
                             "bands " + ", ".join(f"{lo:.0f}-{hi:.0f}" for lo, hi in
                                                  e["disagreement_band_rpm"]) + " rpm")
        if np.max(nfr) >= 1.0:
            reasons.append(f"{label}: the normal-force oscillation reaches "
                           f"{np.max(nfr):.2f} N0 (lift-off) at "
                           f"{e['rpm'][int(np.argmax(nfr))]:.0f} rpm: the constant normal load "
                           "of 001 (6) does not hold")
        elif np.max(nfr) > spec.normal_load_warning_ratio:
            notes.append(f"{label}: the normal-force oscillation reaches {np.max(nfr):.2f} N0 "
                         f"at {e['rpm'][int(np.argmax(nfr))]:.0f} rpm (warning above "
                         f"{spec.normal_load_warning_ratio:g}; lift-off at 1): the constant "
                         "normal load of 001 (6) is doubtful there")
        peaks[f"k{k}_f{_f_label(f)}"] = peak
        if not e["converged"]:
            bad = np.flatnonzero(~res.converged)
            notes.append(f"{label}: {bad.size} of {res.converged.size} "
                         f"speeds did not converge (first at {e['rpm'][bad[0]]:.4g} rpm); the "
                         "equivalent damping may have no fixed point there (raise "
                         "max_iterations or add damping)")
    if hb_info.get("hb_failed_speeds"):
        notes.append(f"HB did not converge at {hb_info['hb_failed_speeds']} speed(s) "
                     "(NaN / null there)")
    ebe = max(e["energy_balance_error"] for e in entries)
    summary = {
        "orders": list(spec.orders),
        "friction_coefficients": [e["friction_coefficient"] for e in entries[:len(fcs)]],
        "speed_min_rpm": spec.speed_min_rpm, "speed_max_rpm": spec.speed_max_rpm,
        "n_speeds": spec.n_speeds,
        "orbit_speeds_rpm": o_rpm,
        "energy_balance_error": float(ebe),
        "all_converged": all(e["converged"] for e in entries),
        "eqlin_iterations": int(sum(e["total_iterations"] for e in entries)),
        "eqlin_runtime_s": t_eqlin,
        "peaks": peaks,
        "peaks_at_campbell_crossings": {"eqlin": n_cross["eqlin"],
                                        "hb": n_cross["hb"] if spec.harmonic_balance else None,
                                        "sweeps": len(entries)},
        **hb_info,
    }
    if spec.harmonic_balance:
        n_dis = [int(np.sum(e["disagreement"])) for e in entries if e.get("hb")]
        summary["disagreement_speeds"] = int(sum(n_dis))
        kt_dis = [e["eqlin_with_stick_stiffness"]["disagreement_speeds"] for e in entries
                  if e.get("eqlin_with_stick_stiffness")]
        if kt_dis:
            summary["disagreement_speeds_stick_stiffness"] = int(sum(kt_dis))
        hb_err = [e["hb"]["energy_balance_error"] for e in entries if e.get("hb")]
        summary["hb_energy_balance_error"] = float(max(hb_err)) if hb_err else None

    rpm = np.asarray(entries[0]["rpm"])
    fab = np.array([np.broadcast_to(np.asarray(f, float), (2,)) for _, f, _, _ in raw])

    def stack(key, col=None):
        a = np.array([e[key] for e in entries], dtype=float)
        return a if col is None else a[..., col]

    dims = ("sweep", "speed")
    sweep_coords = {"order": ("sweep", np.array([k for k, _, _, _ in raw])),
                    "friction_coefficient_A": ("sweep", fab[:, 0]),
                    "friction_coefficient_B": ("sweep", fab[:, 1]),
                    "rpm": ("speed", rpm, {"units": "rpm"})}
    arrays = {"steady_state": xr.Dataset(
        {"major_semi_axis_A": (dims, stack("semi_axes_A_m", 0), {"units": "m"}),
         "minor_semi_axis_A": (dims, stack("semi_axes_A_m", 1), {"units": "m"}),
         "major_semi_axis_B": (dims, stack("semi_axes_B_m", 0), {"units": "m"}),
         "minor_semi_axis_B": (dims, stack("semi_axes_B_m", 1), {"units": "m"}),
         "inclination_A": (dims, stack("inclination_A_rad"), {"units": "rad"}),
         "inclination_B": (dims, stack("inclination_B_rad"), {"units": "rad"}),
         "rotation_amplitude_A": (dims, stack("rotation_amplitude_A_rad"), {"units": "rad"}),
         "rotation_amplitude_B": (dims, stack("rotation_amplitude_B_rad"), {"units": "rad"}),
         "dissipated_energy": (dims, stack("dissipated_energy_J"), {"units": "J"}),
         "external_work": (dims, stack("external_work_J"), {"units": "J"}),
         "tip_tangential_amplitude_blade1": (dims, stack("tip_tangential_amplitude_m", 0),
                                             {"units": "m"}),
         "tip_tangential_amplitude_blade2": (dims, stack("tip_tangential_amplitude_m", 1),
                                             {"units": "m"}),
         "tip_amplitude": (dims, stack("tip_amplitude_m"), {"units": "m"}),
         "normal_force_ratio_A": (dims, stack("normal_force_ratio_A"), {"units": "1"}),
         "normal_force_ratio_B": (dims, stack("normal_force_ratio_B"), {"units": "1"})},
        coords=sweep_coords)}
    if spec.harmonic_balance and all(e.get("hb") for e in entries):
        def hb_stack(key):
            return np.array([[np.nan if v is None else v for v in e["hb"][key]]
                             for e in entries], dtype=float)

        def ratio(key):
            return np.array([[np.nan if v is None else v for v in e[key]] for e in entries],
                            dtype=float)

        ds = arrays["steady_state"]
        ds["hb_dissipated_energy"] = (dims, hb_stack("dissipated_energy_J"), {"units": "J"})
        ds["hb_tip_amplitude"] = (dims, hb_stack("tip_amplitude_m"), {"units": "m"})
        ds["eqlin_over_hb_energy"] = (dims, ratio("eqlin_over_hb_energy"), {"units": "1"})
        ds["eqlin_over_hb_tip_amplitude"] = (dims, ratio("eqlin_over_hb_tip_amplitude"),
                                             {"units": "1"})
    if orb:
        xi = np.array([[[o[c][i]["xi_m"] for c in ("A", "B")] for i in range(len(o_rpm))]
                       for k in spec.orders for o in orb[k]])
        eta = np.array([[[o[c][i]["eta_m"] for c in ("A", "B")] for i in range(len(o_rpm))]
                        for k in spec.orders for o in orb[k]])
        od = ("sweep", "orbit_speed", "contact", "point")
        arrays["orbits"] = xr.Dataset(
            {"orbit_xi": (od, xi, {"units": "m"}), "orbit_eta": (od, eta, {"units": "m"})},
            coords={**{k: v for k, v in sweep_coords.items() if k != "rpm"},
                    "orbit_rpm": ("orbit_speed", np.asarray(o_rpm, float), {"units": "rpm"}),
                    "contact": ("contact", ["A", "B"])})

    name, best = max(peaks.items(), key=lambda kv: kv[1]["peak_dissipated_energy_J"])
    w_max = best["peak_dissipated_energy_J"]
    headline = (f"{len(spec.orders)} orders x {len(fcs)} friction coefficients x "
                f"{spec.n_speeds} speeds; largest friction energy {w_max:.3g} J per period "
                f"({name} at {best['peak_rpm']:.0f} rpm); energy balance {ebe:.1e}; "
                f"{n_cross['eqlin']} of {len(entries)} energy peaks at a Campbell crossing"
                + (f"; HB beside eqlin: {summary['disagreement_speeds']} speeds differ by "
                   f"> {thr:.0%}" if spec.harmonic_balance else ""))

    def figures():
        from fricdamp.models.blade_pair._case_figures import sweep_figures

        return sweep_figures(entries, orb, o_rpm, spec)

    # sweeps with speeds where the equivalent-damping iteration found no fixed point
    n_bad = sum(int(np.sum(~np.asarray(e["converged"], bool))) for e in entries)
    if n_bad:
        reasons.insert(0, f"{n_bad} sweep(s) have speeds without a converged steady state "
                          "(see the notes)")
    verdict = judge({"energy_balance_error": float(ebe), "unconverged_sweeps": n_bad,
                     "disagreement_speeds": summary.get("disagreement_speeds")},
                    reasons=reasons)
    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"n_dof": obj.n_dof, "steady_state": entries},
                          verdict=verdict)


register_model(MODEL_TYPE, BladePairSpec, build_blade_pair_case,
               description="paper 001's two rotating shrouded blades with a wedge friction "
                           "element (78 DOFs)")
register_analysis("campbell", CampbellAnalysis, run_campbell, check=_check_campbell,
                  description="Campbell diagram with friction damping and k Omega lines")
register_analysis("steady_state_sweep", SteadyStateSweepAnalysis, run_steady_state_sweep,
                  check=_check_sweep,
                  description="equivalent-linear steady states vs rpm: slip ellipses, "
                              "friction energy, orbits")
