"""Paper 003's rig test on the beam wheel as case-file analyses (issue 17).

* ``[analysis.excitation_orders]``: the electromagnet pattern decomposed into revolution
  harmonics and nodal diameters; which ND each order excites and where (top-level
  ``engine_order_map``; :mod:`fricdamp.models.tieboss_wheel.excitation`).
* ``[analysis.cyclic_forced_response]``: forced response around each critical speed by
  cyclic harmonic balance (top-level ``forced_response``;
  :func:`~fricdamp.models.tieboss_wheel.forced.forced_response_by_nd`).
* ``[analysis.damping_amplitude]``: damping ratio of the resonant state against its
  amplitude for each ND (top-level ``damping_vs_amplitude``;
  :func:`~fricdamp.models.tieboss_wheel.forced.damping_vs_amplitude`).
* ``[analysis.mistuned_forced_response]``: amplification factor of a wheel with blade
  stiffness scatter, friction on and off (top-level ``mistuning``;
  :func:`~fricdamp.models.tieboss_wheel.forced.mistuned_amplification`).

Registered by :mod:`fricdamp.models.tieboss_wheel.case` (which imports this helper); the
leading underscore keeps :mod:`fricdamp.runner`'s auto-import away.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import Positive, Section
from fricdamp.errors import CaseError
from fricdamp.registry import AnalysisOutput, RunContext, register_analysis

#: 003 Table 2: maximum displacements [m] of the rotary tests by ND (tests 1-3, 4-6).
TABLE2_AMPLITUDES_M = {2: (0.6e-3, 0.9e-3, 1.2e-3), 6: (0.5e-3, 0.7e-3, 1.0e-3)}
#: 003 section 3.2: damping ratios of the FEM envelopes (computed up to 0.5 mm).
PAPER_FEM_DAMPING = {2: 0.012, 6: 0.022}
PAPER_FEM_MAX_AMPLITUDE_M = 0.5e-3

Order = Annotated[int, Field(ge=1, le=100)]
Pair = Annotated[list[Annotated[int, Field(ge=0, le=1000)]], Field(min_length=2,
                                                                  max_length=2)]


def _model(model, table: str):
    from fricdamp.models.tieboss_wheel.case import TiebossWheelCaseModel

    if not isinstance(model, TiebossWheelCaseModel):
        raise CaseError(f"{table} needs [model] type = 'tieboss_wheel' (the beam wheel; of "
                        "these the solid wheel has [analysis.cyclic_forced_response])")
    return model


def _check_nd(model, key: str, nds) -> None:
    bad = [nd for nd in nds if nd > model.max_nd]
    if bad:
        raise CaseError(f"{key}: ND {bad[0]} does not exist; a wheel of {model.n_blades} "
                        f"blades has nodal diameters 0 to {model.max_nd}")


def _range(spec):
    lo, hi = spec.frequency_range_hz
    if not lo < hi:
        raise ValueError(f"frequency_range_hz = [{lo:g}, {hi:g}] must be [low, high] with "
                         "low < high [Hz]")


# ================================================================================ orders
class ExcitationOrdersAnalysis(Section):
    """``[analysis.excitation_orders]``: the rig's electromagnet pulses decomposed into
    revolution harmonics and nodal diameters, the ND each order excites (stationary and
    rotor-synchronous rules) and the speeds where it resonates. Writes ``engine_order_map``."""

    n_magnets: int = Field(8, ge=1, le=360, description="electromagnets, equally spaced "
                                                        "(003: 8)")
    pairs: list[Pair] = Field([[0, 4], [1, 5], [2, 6], [3, 7]], min_length=1, max_length=180,
                              description="wired pairs, 0-based (003: opposite magnets)")
    both_cases: bool = Field(True, description="each pair fires when blade 0 passes either "
                                               "magnet (003 cases 15 and 51: p = 8)")
    synchronous: bool = Field(True, description="pulses triggered by blade 0 (the rig); "
                                                "false: magnets always on")
    pulse_width_deg: Positive = Field(10.0, lt=360.0, description="half-sine pulse length "
                                                                  "in degrees of rotation")
    field_width_deg: Positive = Field(4.0, lt=360.0, description="Gaussian reach of a "
                                                                 "magnet [deg]")
    orders: list[Order] = Field([1, 2, 3], min_length=1, max_length=20,
                                description="orders o (harmonic p o)")
    measured_critical_speeds: list[Annotated[list[float], Field(min_length=2, max_length=2)]] \
        = Field([[1, 334.0], [3, 123.0]], max_length=20,
                description="[o, rpm] measured (003 Table 2); picks the ND per order")

    @model_validator(mode="after")
    def _check(self):
        for a, b in self.pairs:
            if a >= self.n_magnets or b >= self.n_magnets:
                raise ValueError(f"pairs hold magnets 0..{self.n_magnets - 1}, got "
                                 f"[{a}, {b}]")
        return self


def _check_orders(model, spec) -> None:
    _model(model, "[analysis.excitation_orders]")


def run_excitation_orders(model, spec: ExcitationOrdersAnalysis,
                          ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.tieboss_wheel.excitation import (
        ElectromagnetRig,
        engine_order_content,
        engine_order_map,
    )
    from fricdamp.models.tieboss_wheel.studies import campbell_by_nd

    obj = _model(model, "[analysis.excitation_orders]")
    rig = ElectromagnetRig(n_blades=obj.n_blades, n_magnets=spec.n_magnets,
                           pairs=tuple(tuple(p) for p in spec.pairs),
                           both_cases=spec.both_cases, synchronous=spec.synchronous,
                           pulse_width_deg=spec.pulse_width_deg,
                           field_width_deg=spec.field_width_deg)
    cache: dict = {}

    def branch(k, rpm):
        key = (k, round(rpm, 6))
        if key not in cache:
            cache[key] = float(campbell_by_nd(obj.sector, rpm=[rpm], nds=[k]).frequency_hz[0, 0])
        return cache[key]

    measured = {int(o): float(r) for o, r in spec.measured_critical_speeds}
    emap = engine_order_map(rig, orders=spec.orders, branch_hz=branch, measured_rpm=measured)
    stationary = engine_order_map(ElectromagnetRig(
        n_blades=obj.n_blades, n_magnets=spec.n_magnets, synchronous=False,
        field_width_deg=spec.field_width_deg), orders=spec.orders)
    for e, s in zip(emap, stationary, strict=True):
        e["stationary_pattern_nds"] = s["excited_nds"]
    forces = rig.forces(720)
    content = np.abs(engine_order_content(forces))
    summary = {"pulses_per_rev": rig.pulses_per_rev, "synchronous": rig.synchronous,
               "orders": [e["order"] for e in emap], "nd": [e["nd"] for e in emap],
               "rule": emap[0]["rule"]}
    headline = "; ".join(f"o = {e['order']} (n = {e['harmonic']}): {e['nd']}ND"
                         + (f" at {e['crossing_rpm'][str(e['nd'])]:.0f} rpm"
                            if e.get("crossing_rpm") and e["nd"] is not None else "")
                         + f" (stationary rule: {e['stationary_rule_nd']}ND)" for e in emap)

    def figures():
        from fricdamp.models.tieboss_wheel._case_figures import _orders_figures

        return _orders_figures(emap, forces, content, obj, branch)

    return AnalysisOutput(summary=summary, figures=figures, headline=headline,
                          top_level={"engine_order_map": emap})


# ================================================================================ forced
class CyclicForcedResponseAnalysis(Section):
    """``[analysis.cyclic_forced_response]``: forced response of the rotating wheel around
    the critical speed of each (order, ND) by cyclic harmonic balance on one sector, the
    excitation locked to ``p o`` times the speed. Writes ``forced_response``."""

    pairs: list[Pair] = Field([[1, 2], [3, 6]], min_length=1, max_length=20,
                              description="[o, nd] (from [analysis.excitation_orders])")
    pulses: int = Field(8, ge=1, le=1000, description="pulses per revolution p")
    force_N: Positive = Field(2.0, le=1e4, description="travelling-wave force per blade at "
                                                       "the tie-boss [N]")
    frequency_range_hz: Annotated[list[Positive], Field(min_length=2, max_length=2)] = Field(
        [40.0, 52.0], description="blade-frame excitation frequencies swept [Hz]")
    n_modes: int = Field(4, ge=0, le=100, description="Craig-Bampton modes per sector")
    harmonics: int = Field(5, ge=1, le=30, description="harmonics H")
    samples: int = Field(120, ge=8, le=4096, description="AFT samples per period")

    @model_validator(mode="after")
    def _check(self):
        _range(self)
        if self.samples < 2 * self.harmonics + 1:
            raise ValueError(f"samples = {self.samples} must be >= 2 harmonics + 1 = "
                             f"{2 * self.harmonics + 1}")
        return self


def _is_solid(model) -> bool:
    from fricdamp.models.tieboss_wheel.case_solid import is_solid

    return is_solid(model)


def _check_forced(model, spec) -> None:
    obj = model if _is_solid(model) else _model(model, "[analysis.cyclic_forced_response]")
    _check_nd(obj, "pairs", [nd for _, nd in spec.pairs])


def _solid_forced_entry(model, o: int, nd: int, spec) -> dict:
    """The ``forced_response`` entry of a solid wheel (same keys as the beam wheel's):
    cyclic HB on the reduced solid sector with every node pair of its contact patch,
    speed-locked with the solid's own stress stiffening and spin softening
    (:mod:`fricdamp.models.tieboss_wheel.solid_forced`)."""
    from fricdamp.models.tieboss_wheel.case_solid import rotation
    from fricdamp.models.tieboss_wheel.solid_forced import solid_forced_response

    E = float(spec.pulses) * int(o)
    off, _ = model.offset()
    lo, hi = spec.frequency_range_hz
    r = solid_forced_response(model.wheel(), nd, lo, hi, force_N=spec.force_N,
                              settings=model.settings, offset=off,
                              harmonics=spec.harmonics, samples=spec.samples, step=0.01,
                              rotation=rotation(model), excitations_per_rev=E)
    res = r.response
    i = int(np.argmax(r.amplitude_m))
    rpm = 60.0 * r.frequency_hz / E
    return {
        "nd": int(nd), "order": int(o), "pulses": int(spec.pulses),
        "force_N": float(spec.force_N), "rpm": rpm.tolist(),
        "frequency_hz": r.frequency_hz.tolist(), "amplitude_m": r.amplitude_m.tolist(),
        "dissipated_energy_J": r.dissipated_energy_J.tolist(),
        "energy_balance_error": r.energy_balance_error if res.n_points else None,
        "peak_rpm": float(rpm[i]), "peak_frequency_hz": float(r.frequency_hz[i]),
        "peak_amplitude_m": float(r.amplitude_m[i]),
        "damping_ratio_at_peak": float(r.damping_ratio[i]), "tip_ratio": None,
        "n_points": res.n_points, "status": res.status, "message": res.message,
        "n_modes": None, "harmonics": res.harmonics, "samples": res.samples,
        "time_per_point_s": r.cpu_s_per_point, "runtime_s": res.runtime_s,
        "hb_unknowns": r.unknowns, "contact_pairs_per_tieboss": model.wheel().n_pairs,
    }


def run_cyclic_forced_response(model, spec: CyclicForcedResponseAnalysis,
                               ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.tieboss_wheel.forced import forced_response_by_nd

    solid = _is_solid(model)
    obj = model if solid else _model(model, "[analysis.cyclic_forced_response]")
    entries, notes = [], []
    if solid and spec.n_modes != 4:
        notes.append("[analysis.cyclic_forced_response] n_modes is not used by the solid "
                     "wheel (its reduction is set in [model])")
    for o, nd in spec.pairs:
        if solid:
            e = _solid_forced_entry(obj, o, nd, spec)
        else:
            e = forced_response_by_nd(obj.sector, nd, o, pulses=spec.pulses,
                                      force_N=spec.force_N,
                                      frequency_range_hz=tuple(spec.frequency_range_hz),
                                      n_modes=spec.n_modes, harmonics=spec.harmonics,
                                      samples=spec.samples)
        entries.append(e)
        if e["status"] != 0:
            notes.append(f"{nd}ND (o = {o}): the continuation stopped early: {e['message']}")
        if e["energy_balance_error"] is not None and e["energy_balance_error"] > 1e-6:
            notes.append(f"{nd}ND: energy balance error {e['energy_balance_error']:.2g}")
    summary = {"pairs": [list(p) for p in spec.pairs], "force_N": spec.force_N,
               "peak_rpm": [e["peak_rpm"] for e in entries],
               "peak_amplitude_m": [e["peak_amplitude_m"] for e in entries],
               "damping_ratio_at_peak": [e["damping_ratio_at_peak"] for e in entries],
               "energy_balance_error": max((e["energy_balance_error"] or 0.0)
                                           for e in entries),
               "time_per_point_s": [e["time_per_point_s"] for e in entries]}
    headline = "; ".join(
        f"{e['nd']}ND o = {e['order']}: peak {1e3 * e['peak_amplitude_m']:.3g} mm at "
        f"{e['peak_rpm']:.1f} rpm ({e['peak_frequency_hz']:.2f} Hz), zeta "
        f"{100 * e['damping_ratio_at_peak']:.2g} %, {e['n_points']} points "
        f"{1e3 * e['time_per_point_s']:.2g} ms each" for e in entries)

    def figures():
        from fricdamp.models.tieboss_wheel._case_figures import _forced_figures

        return _forced_figures(entries)

    return AnalysisOutput(summary=summary, figures=figures, headline=headline, notes=notes,
                          top_level={"forced_response": entries})


# ================================================================================ zeta(A)
class DampingAmplitudeAnalysis(Section):
    """``[analysis.damping_amplitude]``: damping ratio against amplitude for each ND from
    the resonance peaks of cyclic HB responses at several load levels,
    ``zeta = W_d / (4 pi E_max)``. Writes ``damping_vs_amplitude``."""

    nodal_diameters: list[Annotated[int, Field(ge=0, le=1000)]] = Field(
        [2, 6], min_length=1, max_length=16, description="NDs (003: 2, 6)")
    orders: list[Order] | None = Field([1, 3], description="order of each ND: the response "
                                       "is speed-locked (p o); omit for the wheel at rest")
    pulses: int = Field(8, ge=1, le=1000, description="pulses per revolution p")
    force_levels_N: list[list[Positive]] = Field(
        [[0.55, 0.6, 0.7, 0.8, 1.0, 1.5, 2.0, 2.5], [1.3, 1.4, 1.7, 2.0, 2.5, 3.0, 4.0]],
        description="travelling-wave forces per blade [N], one list per ND")
    frequency_range_hz: Annotated[list[Positive], Field(min_length=2, max_length=2)] = Field(
        [40.0, 52.0], description="frequencies swept per level [Hz]")
    n_modes: int = Field(4, ge=0, le=100, description="Craig-Bampton modes per sector")
    harmonics: int = Field(5, ge=1, le=30, description="harmonics H")
    samples: int = Field(120, ge=8, le=4096, description="AFT samples per period")
    release_duration_s: float = Field(0.0, ge=0.0, le=5.0, description="> 0: also release "
                                      "the largest level's resonant state and integrate the "
                                      "free decay of the rotating wheel this long")
    release_time_step_s: Positive = Field(1e-5, le=1e-3, description="its time step")

    @model_validator(mode="after")
    def _check(self):
        _range(self)
        if self.release_duration_s > 0 and self.orders is None:
            raise ValueError("release_duration_s > 0 needs orders (the release is from the "
                             "speed-locked resonance)")
        if len(self.force_levels_N) != len(self.nodal_diameters):
            raise ValueError(f"force_levels_N needs one list per ND ({len(self.nodal_diameters)}"
                             f"), got {len(self.force_levels_N)}")
        if self.orders is not None and len(self.orders) != len(self.nodal_diameters):
            raise ValueError("orders needs one order per ND")
        return self


def _check_damping(model, spec) -> None:
    _check_nd(_model(model, "[analysis.damping_amplitude]"), "nodal_diameters",
              spec.nodal_diameters)


def run_damping_amplitude(model, spec: DampingAmplitudeAnalysis,
                          ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.tieboss_wheel.forced import damping_vs_amplitude

    obj = _model(model, "[analysis.damping_amplitude]")
    entries, notes = [], []
    for i, nd in enumerate(spec.nodal_diameters):
        o = None if spec.orders is None else spec.orders[i]
        e = damping_vs_amplitude(obj.sector, nd, spec.force_levels_N[i], order=o,
                                 pulses=spec.pulses,
                                 frequency_range_hz=tuple(spec.frequency_range_hz),
                                 n_modes=spec.n_modes, harmonics=spec.harmonics,
                                 samples=spec.samples)
        if obj.n_blades == 30 and nd in PAPER_FEM_DAMPING:
            e["paper_fem_damping_ratio"] = PAPER_FEM_DAMPING[nd]
            e["paper_fem_max_amplitude_m"] = PAPER_FEM_MAX_AMPLITUDE_M
            e["paper_test_amplitudes_m"] = list(TABLE2_AMPLITUDES_M[nd])
            A, z = np.asarray(e["amplitude_m"]), np.asarray(e["damping_ratio"])
            if A.size >= 2:
                e["damping_ratio_at_paper_test_amplitudes"] = [
                    float(np.exp(np.interp(np.log(a), np.log(A), np.log(z))))
                    if A[0] <= a <= A[-1] else None for a in TABLE2_AMPLITUDES_M[nd]]
        if spec.release_duration_s > 0:
            from fricdamp.models.tieboss_wheel.forced import release_decay

            e["release_decay"] = release_decay(
                obj.sector, nd, o, force_N=max(spec.force_levels_N[i]), pulses=spec.pulses,
                frequency_range_hz=tuple(spec.frequency_range_hz), n_modes=spec.n_modes,
                harmonics=spec.harmonics, samples=spec.samples,
                duration_s=spec.release_duration_s, dt=spec.release_time_step_s)
        skipped = len(spec.force_levels_N[i]) - len(e["amplitude_m"])
        if skipped:
            notes.append(f"{nd}ND: {skipped} load level(s) without a resonance inside "
                         "frequency_range_hz (contacts stuck) left out")
        if len(e["amplitude_m"]) < 6:
            notes.append(f"{nd}ND: only {len(e['amplitude_m'])} amplitudes (the contract "
                         "asks for 6 over 0.1-1.5 mm): add force levels")
        entries.append(e)
    summary = {"nodal_diameters": list(spec.nodal_diameters),
               "amplitude_range_m": [[min(e["amplitude_m"], default=None),
                                      max(e["amplitude_m"], default=None)] for e in entries],
               "damping_ratio_range": [[min(e["damping_ratio"], default=None),
                                        max(e["damping_ratio"], default=None)]
                                       for e in entries]}
    headline = "; ".join(
        f"{e['nd']}ND: zeta {100 * max(e['damping_ratio']):.3g} -> "
        f"{100 * min(e['damping_ratio']):.3g} % over {1e3 * min(e['amplitude_m']):.2g}-"
        f"{1e3 * max(e['amplitude_m']):.2g} mm" for e in entries if e["amplitude_m"])

    def figures():
        from fricdamp.models.tieboss_wheel._case_figures import _damping_amplitude_figures

        return _damping_amplitude_figures(entries)

    return AnalysisOutput(summary=summary, figures=figures, headline=headline, notes=notes,
                          top_level={"damping_vs_amplitude": entries})


# ================================================================================ mistuning
class MistunedForcedResponseAnalysis(Section):
    """``[analysis.mistuned_forced_response]``: forced response of the assembled wheel (full
    HB, Craig-Bampton sectors) with blade-to-blade stiffness scatter, friction on (the
    contacts) and off (contacts removed); amplification factor = largest blade amplitude /
    tuned amplitude. Writes ``mistuning``."""

    nodal_diameter: int = Field(2, ge=0, le=1000, description="ND of the travelling wave")
    force_N: Positive = Field(2.0, le=1e4, description="force per blade at the tie-boss")
    scatter: list[Annotated[float, Field(gt=0.0, le=0.2)]] = Field(
        [0.01, 0.03], min_length=1, max_length=10, description="standard deviations of the "
                                                                "stiffness factor")
    seed: int = Field(1, ge=0, description="random seed")
    frequency_range_hz: Annotated[list[Positive], Field(min_length=2, max_length=2)] = Field(
        [43.0, 46.5], description="frequencies swept [Hz]")
    n_modes: int = Field(4, ge=0, le=100, description="Craig-Bampton modes per sector")
    harmonics: int = Field(3, ge=1, le=15, description="harmonics H of the full-wheel HB")
    samples: int = Field(120, ge=8, le=4096, description="AFT samples per period")

    @model_validator(mode="after")
    def _check(self):
        _range(self)
        return self


def _check_mistuned(model, spec) -> None:
    _check_nd(_model(model, "[analysis.mistuned_forced_response]"), "nodal_diameter",
              [spec.nodal_diameter])


def run_mistuned_forced_response(model, spec: MistunedForcedResponseAnalysis,
                                 ctx: RunContext) -> AnalysisOutput:
    from fricdamp.models.tieboss_wheel.forced import mistuned_amplification

    obj = _model(model, "[analysis.mistuned_forced_response]")
    wheel = obj.wheel(spec.n_modes)
    kw = dict(seed=spec.seed, frequency_range_hz=tuple(spec.frequency_range_hz),
              harmonics=spec.harmonics, samples=spec.samples)
    on = mistuned_amplification(wheel, spec.nodal_diameter, spec.force_N, spec.scatter,
                                friction=True, **kw)
    off = mistuned_amplification(wheel, spec.nodal_diameter, spec.force_N, spec.scatter,
                                 friction=False, **kw)
    mist = {"scatter": on["scatter"], "amplification_factor": on["amplification_factor"],
            "amplification_factor_no_friction": off["amplification_factor"],
            "peak_amplitude_m": on["peak_amplitude_m"],
            "peak_amplitude_no_friction_m": off["peak_amplitude_m"],
            "peak_frequency_hz": on["peak_frequency_hz"],
            "peak_frequency_no_friction_hz": off["peak_frequency_hz"],
            "blade_of_peak": on["blade_of_peak"], "nd": spec.nodal_diameter,
            "force_N": spec.force_N, "seed": spec.seed, "status": on["status"],
            "friction_off": "contacts removed (open tie-bosses), linear wheel",
            "scatter_kind": "sector stiffness factor 1 + s delta_j, delta_j standard normal"}
    notes = [f"scatter {s:g}: the full-wheel continuation stopped early (status {st})"
             for s, st in zip(on["scatter"], on["status"], strict=True) if st != 0]
    summary = {k: mist[k] for k in ("scatter", "amplification_factor",
                                    "amplification_factor_no_friction")}
    headline = ", ".join(f"s = {s:g}: AF {a:.3g} (no friction {b:.3g})" for s, a, b in zip(
        mist["scatter"], mist["amplification_factor"],
        mist["amplification_factor_no_friction"], strict=True))
    return AnalysisOutput(summary=summary, headline=headline, notes=notes,
                          top_level={"mistuning": mist})


register_analysis("excitation_orders", ExcitationOrdersAnalysis, run_excitation_orders,
                  check=_check_orders,
                  description="003's electromagnet pulses by revolution harmonic and ND "
                              "(engine_order_map)")
register_analysis("cyclic_forced_response", CyclicForcedResponseAnalysis,
                  run_cyclic_forced_response, check=_check_forced,
                  description="forced response around critical speeds by cyclic HB")
register_analysis("damping_amplitude", DampingAmplitudeAnalysis, run_damping_amplitude,
                  check=_check_damping,
                  description="damping ratio vs amplitude from resonance energies by ND")
register_analysis("mistuned_forced_response", MistunedForcedResponseAnalysis,
                  run_mistuned_forced_response, check=_check_mistuned,
                  description="amplification factor vs blade scatter, friction on and off")
