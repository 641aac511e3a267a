"""Paper 001's two rotating shrouded blades as a case: ``[model] type = "blade_pair"`` with
``[analysis.campbell]`` (Figs 3-5) and ``[analysis.steady_state_sweep]`` (Figs 6-14).

The model is not a :class:`~fricdamp.structure.MechanicalSystem` but a
:class:`BladePairCaseModel` wrapping the 78-DOF
:class:`~fricdamp.models.blade_pair.BladePairModel` (two Rayleigh-beam blades with rigid
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
from fricdamp.runner import (
    AnalysisOutput,
    BuildContext,
    ModelObject,
    NotAMechanicalSystemError,
    RunContext,
    register_analysis,
    register_model,
)
from fricdamp.verdict import judge

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
    element between the shrouds (:class:`~fricdamp.models.blade_pair.BladePairParameters`).

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
    """The :class:`~fricdamp.models.blade_pair.BladePairParameters` of a ``[model]`` table
    (degrees to radians; raises ModelError)."""
    from fricdamp.models.blade_pair import BladePairParameters

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
        min_slip=spec.min_slip_m)


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
        """The :class:`~fricdamp.models.blade_pair.BladePairParameters`."""
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
    from fricdamp.models.blade_pair import build_blade_pair

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
    damping_source: Literal["converged", "linear"] = Field(
        "converged", description="B_e from the converged steady state, or from the response "
                                 "without friction (001 section 4.1 literally)")
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
    classification and ordering as :func:`~fricdamp.models.blade_pair_analyses.
    campbell_diagram`.

    Returns
    -------
    dict
        ``frequency_hz``, ``damping_ratio`` (n_modes, None beyond the complex pairs),
        ``complex_pairs``, ``real_eigenvalues``.
    """
    import scipy.linalg as sla

    from fricdamp.models.blade_pair_analyses import _blas1, _classify, _state_matrix

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


def crossing_speeds(rpm, frequency_hz, order: int) -> list[float]:
    """Speeds [rpm] where a branch ``f(rpm)`` [Hz] meets the line ``k rpm / 60``.

    Linear interpolation between grid points where ``f - k rpm / 60`` changes sign (NaN or
    missing points break the branch).
    """
    r = np.asarray(rpm, float)
    f = np.array([np.nan if v is None else v for v in frequency_hz], float)
    g = f - order * r / 60.0
    out = []
    for i in range(r.size - 1):
        a, b = g[i], g[i + 1]
        if not (np.isfinite(a) and np.isfinite(b)):
            continue
        if a == 0.0:
            out.append(float(r[i]))
        elif a * b < 0.0:
            out.append(float(r[i] + (r[i + 1] - r[i]) * a / (a - b)))
    if r.size and np.isfinite(g[-1]) and g[-1] == 0.0:
        out.append(float(r[-1]))
    return out


def run_campbell(model: BladePairCaseModel, spec: CampbellAnalysis,
                 ctx: RunContext) -> AnalysisOutput:
    """Campbell diagram of the 001 model (:func:`~fricdamp.models.blade_pair_analyses.
    campbell_diagram`), a zero-speed column if the range starts at 0
    (:func:`zero_speed_eigenvalues`), the crossings of the excitation lines and optionally
    the complex mode shapes."""
    import xarray as xr

    from fricdamp.models.blade_pair_analyses import campbell_diagram, complex_modes

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
                               "damping_ratio": modes["damping_ratio"]}

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

    first = [c for c in crossings.get(f"k{max(spec.excitation_orders)}", {}).get(
        "mode1_rpm", [])]
    f0 = F[0, 0]
    headline = (f"{len(camp['rpm'])} speeds {rpm[0]:g}-{rpm[-1]:g} rpm, {F.shape[0]} branches"
                + (f"; first {f0:.4g} Hz at {rpm[0]:g} rpm" if np.isfinite(f0) else "")
                + (f"; {max(spec.excitation_orders)} Omega meets branch 1 at {first[0]:.0f} rpm"
                   if first else ""))

    def figures():
        return _campbell_figures(camp, modes, spec)

    return AnalysisOutput(summary=camp, arrays=arrays, figures=figures, headline=headline,
                          top_level={"n_dof": obj.n_dof})


def _campbell_axes(ax, camp: dict, fmax: float) -> None:
    """Branches (dots), excitation lines k rpm / 60 and their crossings up to ``fmax``."""
    rpm = np.asarray(camp["rpm"])
    F = np.array(camp["frequency_hz"], dtype=float)
    for i, row in enumerate(F):
        ax.plot(rpm, row, ".", ms=2.5, color="tab:blue",
                label=r"Im($\lambda$)/2$\pi$" if i == 0 else None)
    for k in camp["excitation_orders"]:
        line = k * rpm / 60.0
        ax.plot(rpm, line, "k--", lw=0.8)
        j = min(max(int(np.searchsorted(line, fmax)) - 1, 0), rpm.size - 1)
        ax.annotate(rf"{k}$\Omega$", (rpm[j], line[j]), fontsize=8,
                    textcoords="offset points", xytext=(-16, 4))
        for rs in camp["crossing_speeds"][f"k{k}"].values():
            ax.plot(rs, k * np.asarray(rs) / 60.0, "o", mfc="none", color="tab:red", ms=5)
    ax.set_ylim(0, fmax)
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_xlabel("spin speed [rpm]")
    ax.set_ylabel(r"Im($\lambda$)/2$\pi$ [Hz]")


def _campbell_figures(camp: dict, modes: dict | None, spec: CampbellAnalysis) -> list:
    from fricdamp import plot

    rpm = np.asarray(camp["rpm"])
    F = np.array(camp["frequency_hz"], dtype=float)
    Z = np.array(camp["damping_ratio"], dtype=float)
    what = (f"with the friction damping of the k = {camp['k']} steady state, f = "
            f"{camp['friction_coefficient']:g}" if camp["friction"] else "without friction")
    fig, axes = plot.new_figure(1, 2, width=12.0, height=4.6,
                                title=f"Campbell diagram (001 Figs 3-4), {what}")
    fmax = float(np.nanmax(F)) * 1.05 if np.isfinite(F).any() else 1.0
    _campbell_axes(axes[0, 0], camp, fmax)
    axes[0, 0].set_title(f"{F.shape[0]} lowest complex pairs", fontsize="small")
    zoom = 1.3 * max(camp["excitation_orders"]) * rpm[-1] / 60.0
    _campbell_axes(axes[0, 1], camp, min(zoom, fmax))
    axes[0, 1].set_title("excitation range; circles: k Omega meets a branch (resonance)",
                         fontsize="small")
    figs = [("campbell.png", f"Campbell diagram {what}: imaginary parts of the eigenvalues "
             "vs spin speed with the excitation lines k Omega (001 Figs 3-4); right: the "
             "range of the excitation lines", fig)]
    fig, axes = plot.new_figure(width=7.5, height=4.2, title="Damping ratios of the lowest "
                                                             "Campbell branches")
    az = axes[0, 0]
    for i in range(min(6, Z.shape[0])):
        az.semilogy(rpm, np.where(Z[i] > 0, Z[i], np.nan), ".-", ms=3, lw=0.8,
                    label=f"branch {i + 1}")
    az.set_xlabel("spin speed [rpm]")
    az.set_ylabel(r"damping ratio $-\mathrm{Re}\,\lambda/|\lambda|$ [-]")
    az.set_title(f"{what}; branches sorted by frequency at each speed", fontsize="small")
    az.legend(fontsize="small", ncols=2)
    figs.append(("campbell_damping.png", f"Damping ratios -Re(lambda)/|lambda| of the six "
                 f"lowest Campbell branches {what}", fig))
    if modes is not None:
        r = np.asarray(modes["blade_nodes_m"])
        n = len(modes["frequency_hz"])
        fig, axes = plot.new_figure(1, n, width=3.6 * n + 0.6, height=4.0,
                                    title=f"Complex mode shapes at {modes['rpm']:g} rpm "
                                          "(001 Fig. 5): tangential deflection w")
        for j, ax in enumerate(axes[0]):
            for b, style in (("blade1", "-"), ("blade2", "--")):
                w = np.array(modes[b][j])[:, 1]                       # (node, [re, im])
                ax.plot(w[:, 0], r, "tab:blue", ls=style, marker="o", ms=3,
                        label=f"{b} Re")
                ax.plot(w[:, 1], r, "tab:red", ls=style, marker="s", ms=3,
                        label=f"{b} Im")
            ax.set_title(f"{modes['frequency_hz'][j]:.1f} Hz, zeta = "
                         f"{modes['damping_ratio'][j]:.3g}", fontsize="small")
            ax.set_xlabel("w (largest DOF = 1) [-]")
            ax.locator_params(axis="x", nbins=4)
        axes[0, 0].set_ylabel("radius [m]")
        axes[0, 0].legend(fontsize="x-small")
        figs.append(("mode_shapes.png", f"Complex mode shapes at {modes['rpm']:g} rpm: real "
                     "and imaginary parts of the tangential deflection of both blades "
                     "(001 Fig. 5)", fig))
    return figs


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

    @model_validator(mode="after")
    def _check(self):
        _speed_range(self)
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
    from fricdamp.models.blade_pair_analyses import _sweep_entry, solve_steady_states

    rpm = np.linspace(spec.speed_min_rpm, spec.speed_max_rpm, spec.n_speeds)
    entries, raw = [], []
    for k in spec.orders:
        for f, res, damp in solve_steady_states(m, k, rpm, fcs, tol=spec.tolerance,
                                                max_iter=spec.max_iterations):
            e = _sweep_entry(m, k, rpm, f, res, damp)
            phi = np.abs(res.contact_response[:, [2, 5]])             # rotation amplitudes
            e["rotation_amplitude_A_rad"] = phi[:, 0].tolist()
            e["rotation_amplitude_B_rad"] = phi[:, 1].tolist()
            e["torque_arms_m"] = [float(v) for v in m.torque_arms]
            e["min_slip_m"] = float(damp.min_amplitude)
            e["min_rotation_rad"] = [float(v) for v in np.atleast_1d(damp.min_rotation)]
            entries.append(e)
            raw.append((k, f, res, damp))
    return entries, raw


def run_steady_state_sweep(model: BladePairCaseModel, spec: SteadyStateSweepAnalysis,
                           ctx: RunContext) -> AnalysisOutput:
    """Steady states vs speed (:func:`~fricdamp.models.blade_pair_analyses.
    solve_steady_states`) for every order and friction coefficient, and the orbits
    (:func:`~fricdamp.models.blade_pair_analyses.orbits`) at the orbit speeds."""
    import xarray as xr

    from fricdamp.models.blade_pair_analyses import orbits

    obj = _require_model(model, "[analysis.steady_state_sweep]")
    m = obj.model
    fcs = (list(spec.friction_coefficients) if spec.friction_coefficients is not None
           else [obj.friction_coefficient()])
    entries, raw = _sweep_entries(m, spec, fcs)
    o_rpm = spec.orbit_speeds()
    orb = {k: orbits(m, k, o_rpm, fcs, n_points=spec.orbit_points) for k in spec.orders} \
        if o_rpm else {}

    notes, peaks = [], {}
    for e, (k, f, res, _) in zip(entries, raw, strict=True):
        W = np.asarray(e["dissipated_energy_J"])
        i = int(np.nanargmax(W))
        peaks[f"k{k}_f{_f_label(f)}"] = {
            "peak_rpm": e["rpm"][i], "peak_dissipated_energy_J": float(W[i]),
            "max_major_semi_axis_A_m": max(a for a, _ in e["semi_axes_A_m"]),
            "max_major_semi_axis_B_m": max(a for a, _ in e["semi_axes_B_m"]),
            "stuck_fraction": float(np.mean(np.array(e["stuck_A"]) & np.array(e["stuck_B"]))),
            "converged": e["converged"]}
        if not e["converged"]:
            bad = np.flatnonzero(~res.converged)
            notes.append(f"k = {k}, f = {_f_label(f)}: {bad.size} of {res.converged.size} "
                         f"speeds did not converge (first at {e['rpm'][bad[0]]:.4g} rpm); the "
                         "equivalent damping may have no fixed point there (raise "
                         "max_iterations or add damping)")
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
        "peaks": peaks,
    }

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
                                             {"units": "m"})},
        coords=sweep_coords)}
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
                f"({name} at {best['peak_rpm']:.0f} rpm); energy balance {ebe:.1e}")

    def figures():
        return _sweep_figures(entries, orb, o_rpm, spec)

    # sweeps with speeds where the equivalent-damping iteration found no fixed point
    n_bad = sum(int(np.sum(~np.asarray(e["converged"], bool))) for e in entries)
    verdict = judge({"energy_balance_error": float(ebe), "unconverged_sweeps": n_bad},
                    reasons=[f"{n_bad} sweep(s) have speeds without a converged steady "
                             "state (see the notes)"] if n_bad else [])
    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, top_level={"n_dof": obj.n_dof, "steady_state": entries},
                          verdict=verdict)


def _sweep_figures(entries: list, orb: dict, o_rpm: list, spec: SteadyStateSweepAnalysis
                   ) -> list:
    from fricdamp import plot

    orders = list(spec.orders)
    floor = 1e-12

    # Figs 6-7: semi-axes vs rpm, one row per order, contacts A and B side by side
    fig, axes = plot.new_figure(len(orders), 2, width=11.5, height=3.4, sharex=True,
                                title="Semi-axes of the slip ellipses vs spin speed "
                                      "(001 Figs 6-7): solid major, dotted minor")
    for row, k in enumerate(orders):
        for col, c in enumerate("AB"):
            ax = axes[row, col]
            for e in (e for e in entries if e["k"] == k):
                ab = np.array(e[f"semi_axes_{c}_m"])
                line, = ax.semilogy(e["rpm"], np.maximum(ab[:, 0], floor), lw=1,
                                    label=f"f = {_f_label(e['friction_coefficient'])}")
                ax.semilogy(e["rpm"], np.maximum(ab[:, 1], floor), ":", lw=1,
                            color=line.get_color())
            ax.set_title(f"contact {c}, k = {k}", fontsize="small")
            ax.set_ylabel("semi-axis [m]")
        axes[row, 0].legend(fontsize="x-small", ncols=2)
    for ax in axes[-1]:
        ax.set_xlabel("spin speed [rpm]")
    figs = [("semi_axes.png", "Major (solid) and minor (dotted) semi-axes of the elliptical "
             "slip orbits of A and B vs spin speed, per order and friction coefficient "
             f"(001 Figs 6-7; floored at {floor:g} m for the log scale)", fig)]

    # Fig. 8: inclinations
    fig, axes = plot.new_figure(1, len(orders), width=4.0 * len(orders) + 0.5, height=3.8,
                                title="Inclination of the major axes (001 Fig. 8)")
    for ax, k in zip(axes[0], orders, strict=True):
        for e in (e for e in entries if e["k"] == k):
            line, = ax.plot(e["rpm"], e["inclination_A_rad"], lw=1,
                            label=f"A, f = {_f_label(e['friction_coefficient'])}")
            ax.plot(e["rpm"], e["inclination_B_rad"], "--", lw=1, color=line.get_color())
        ax.set_title(f"k = {k} (solid A, dashed B)", fontsize="small")
        ax.set_xlabel("spin speed [rpm]")
        ax.set_ylim(0, np.pi)
    axes[0, 0].set_ylabel(r"inclination from $\xi$ [rad]")
    axes[0, 0].legend(fontsize="x-small")
    figs.append(("inclination.png", "Inclination of the major axis of the slip ellipses to "
                 "the xi axis of each contact plane (001 Fig. 8)", fig))

    # Figs 9-11: dissipated energy vs rpm
    fig, axes = plot.new_figure(1, len(orders), width=4.0 * len(orders) + 0.5, height=3.8,
                                title="Energy dissipated by friction per period T_k "
                                      "(001 Figs 9-11)")
    for ax, k in zip(axes[0], orders, strict=True):
        for e in (e for e in entries if e["k"] == k):
            ax.semilogy(e["rpm"], np.maximum(e["dissipated_energy_J"], floor), lw=1,
                        label=f"f = {_f_label(e['friction_coefficient'])}")
        ax.set_title(f"k = {k}", fontsize="small")
        ax.set_xlabel("spin speed [rpm]")
    axes[0, 0].set_ylabel("friction energy per period [J]")
    axes[0, 0].legend(fontsize="x-small")
    figs.append(("dissipated_energy.png", "Energy dissipated by friction at A and B per "
                 "excitation period vs spin speed, one curve per friction coefficient "
                 "(001 Figs 9-11)", fig))

    # Figs 12-14: orbits
    for k in orders if orb else []:
        n = len(o_rpm)
        fig, axes = plot.new_figure(2, n, width=3.6 * n + 0.6, height=3.3,
                                    title=f"Slip orbits for k = {k} (001 Figs 12-14)")
        for col, r in enumerate(o_rpm):
            for row, c in enumerate("AB"):
                ax = axes[row, col]
                big = [o[c][col]["semi_axes_m"][0] for o in orb[k]]
                fac, unit = plot.si_scale(big, "m")
                for o in orb[k]:
                    e = o[c][col]
                    ax.plot(np.array(e["xi_m"]) / fac, np.array(e["eta_m"]) / fac, lw=1,
                            label=f"f = {_f_label(o['friction_coefficient'])}")
                ax.set_title(f"{c}, {r:.0f} rpm", fontsize="small")
                ax.set_xlabel(rf"$\xi$ [{unit}]")
                ax.set_ylabel(rf"$\eta$ [{unit}]")
                ax.set_aspect("equal", adjustable="datalim")
                ax.locator_params(nbins=5)
        axes[0, 0].legend(fontsize="x-small")
        figs.append((f"orbits_k{k}.png", f"Elliptical slip orbits of the contact points A "
                     f"and B in their contact planes for k = {k} at "
                     f"{', '.join(f'{r:.0f}' for r in o_rpm)} rpm, one curve per friction "
                     "coefficient (001 Figs 12-14; a stuck contact's orbit is a dot)", fig))
    return figs


register_model(MODEL_TYPE, BladePairSpec, build_blade_pair_case,
               description="paper 001's two rotating shrouded blades with a wedge friction "
                           "element (78 DOFs)")
register_analysis("campbell", CampbellAnalysis, run_campbell, check=_check_campbell,
                  description="Campbell diagram with friction damping and k Omega lines")
register_analysis("steady_state_sweep", SteadyStateSweepAnalysis, run_steady_state_sweep,
                  check=_check_sweep,
                  description="equivalent-linear steady states vs rpm: slip ellipses, "
                              "friction energy, orbits")
