"""The ``[model] type = "tieboss_wheel"`` table of paper 003's wheel: its schema
(:class:`TiebossWheelSpec`), the library parameters it maps to (:func:`tieboss_parameters`) and
the paper's damping ratios the analyses compare with.

A helper of :mod:`fricdamp.models.tieboss_wheel.case` (which re-exports these names and registers
the model type); its leading underscore keeps :mod:`fricdamp.runner`'s auto-import away.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Annotated

from pydantic import Field, model_validator

from fricdamp.case import NonNegative, Positive, Section

#: 003 section 3.2: damping ratios from the log decrement of the FEM envelopes.
PAPER_DAMPING_RATIO = {2: 0.012, 6: 0.022}


class TiebossWheelSpec(Section):
    """``[model] type = "tieboss_wheel"``: paper 003's 30-blade wheel with tie-boss contacts
    (:class:`~fricdamp.models.tieboss_wheel.model.TiebossWheelParameters`, same names).

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
    """The :class:`~fricdamp.models.tieboss_wheel.model.TiebossWheelParameters` of a ``[model]``
    table (same names; raises ModelError). The normal penalty is the table's, calibrated
    afterwards by the builder when ``calibrate_normal_stiffness`` is set."""
    from fricdamp.models.tieboss_wheel.model import TiebossWheelParameters

    kw = {f.name: getattr(spec, f.name) for f in fields(TiebossWheelParameters)}
    kw["damping_band_hz"] = tuple(spec.damping_band_hz)
    return TiebossWheelParameters(**kw)
