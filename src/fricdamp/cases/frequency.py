"""Frequency-domain analyses of a case: ``[analysis.frf]`` (harmonic balance through resonance
by arclength continuation) and ``[analysis.nma]`` (nonlinear modal analysis), plus the
``[model] type = "cantilever_beam"`` model they are shown on.

Summary contract (issue 4): ``frf: {"omega_rad_s", "amplitude_m", "dissipated_energy_J", ...}``
and ``nma: {"amplitude", "frequency_hz", "damping_ratio", ...}``; issue 14 adds to ``frf``
``stable: [bool per point]`` and ``bifurcations: [{"type": "fold" | "branch_point" |
"neimark_sacker" | "period_doubling", "omega_rad_s", "amplitude_m", ...}]`` (computed with
``stability = true``; null otherwise).
"""

from __future__ import annotations

import numpy as np
from pydantic import Field, model_validator

from fricdamp.case import NonNegative, Positive, Section
from fricdamp.cases.timedomain import _check_dof, _check_vector
from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.registry import (
    AnalysisOutput,
    BuildContext,
    RunContext,
    register_analysis,
    register_model,
)
from fricdamp.verdict import THRESHOLDS, harmonic_truncation, judge


# ------------------------------------------------------------------------------- model
class CantileverBeamModel(Section):
    """``[model] type = "cantilever_beam"``: clamped-free Euler-Bernoulli beam (bending in one
    plane). DOFs per free node k = 1..n_elements: deflection w_k (DOF 2k - 1) [m] and slope
    theta_k (DOF 2k) [rad]; node n_elements is the tip."""

    n_elements: int = Field(ge=1, le=2000, description="number of equal beam elements")
    length_m: Positive = Field(description="beam length L")
    E_Pa: Positive = Field(description="Young's modulus")
    rho_kg_m3: Positive = Field(description="density")
    area_m2: Positive = Field(description="cross-section area")
    inertia_m4: Positive = Field(description="second moment of area of the bending plane")
    rayleigh_alpha_per_s: NonNegative = Field(0.0, description="Rayleigh damping D = alpha M + "
                                                               "beta K: alpha")
    rayleigh_beta_s: NonNegative = Field(0.0, description="Rayleigh damping: beta")


def _build_cantilever(spec: CantileverBeamModel, ctx: BuildContext):
    from fricdamp.structure.beam import cantilever_beam

    ray = None
    if spec.rayleigh_alpha_per_s or spec.rayleigh_beta_s:
        ray = (spec.rayleigh_alpha_per_s, spec.rayleigh_beta_s)
    return cantilever_beam(spec.n_elements, spec.length_m, spec.E_Pa, spec.rho_kg_m3, spec.area_m2,
                           spec.inertia_m4, rayleigh=ray, name="cantilever")


register_model("cantilever_beam", CantileverBeamModel, _build_cantilever,
               description="clamped-free Euler-Bernoulli beam (w, theta per node)")


# ------------------------------------------------------------------------------- FRF
class FRF(Section):
    """``[analysis.frf]``: frequency response through resonance by harmonic balance (AFT)
    and pseudo-arclength continuation."""

    force_amplitude_N: list[float] = Field(
        min_length=1, description="amplitude F of F cos(2 pi f t), one entry per DOF")
    frequency_start_hz: Positive = Field(description="start of the frequency range")
    frequency_end_hz: Positive = Field(description="end of the frequency range")
    harmonics: int = Field(7, ge=1, le=200, description="highest harmonic H")
    samples: int | None = Field(None, ge=8, le=1_000_000,
                                description="AFT time samples per period (default 2^k >= 16 H)")
    response_dof: int | None = Field(None, ge=1, description="DOF whose amplitude is reported "
                                                             "(default: largest response)")
    step: Positive = Field(0.02, le=0.5, description="initial continuation step (scaled)")
    max_points: int = Field(2000, ge=10, le=100_000, description="largest number of points")
    stability: bool = Field(False, description="Hill stability of every point and detection of "
                                               "folds, branch points and Neimark-Sacker points")
    backbone_mode: int | None = Field(
        None, ge=1, le=1000, description="also compute this nonlinear mode (1 = lowest, "
                                         "contacts stuck) over the curve's amplitudes and draw "
                                         "its backbone on the FRF")

    @model_validator(mode="after")
    def _check(self):
        if not any(self.force_amplitude_N):
            raise ValueError("force_amplitude_N must have a non-zero entry")
        if self.frequency_start_hz == self.frequency_end_hz:
            raise ValueError("frequency_start_hz and frequency_end_hz must differ")
        return self


def _check_frf(system, spec: FRF) -> None:
    _check_vector(spec.force_amplitude_N, system.n_dof, "force_amplitude_N")
    _check_dof(spec.response_dof, system.n_dof, "response_dof")


def run_frf(system, spec: FRF, ctx: RunContext) -> AnalysisOutput:

    from fricdamp.solvers.hb import frequency_response
    from fricdamp.structure.system import HarmonicLoad

    w0 = 2 * np.pi * spec.frequency_start_hz
    w1 = 2 * np.pi * spec.frequency_end_hz
    sys_ = system.with_loads(HarmonicLoad(np.asarray(spec.force_amplitude_N, float), w0))
    res = frequency_response(sys_, w0, w1, harmonics=spec.harmonics, samples=spec.samples,
                             step=spec.step, max_points=spec.max_points,
                             stability=spec.stability)
    if res.n_points == 0:
        raise ConvergenceError(f"frequency response: no converged point ({res.message})")
    dof = (spec.response_dof - 1 if spec.response_dof is not None
           else int(np.argmax(np.max(res.amplitude, axis=0))))
    amp = res.amplitude[:, dof]
    diss = res.dissipated_energy.sum(axis=1) if res.dissipated_energy.size else np.zeros(
        res.n_points)
    ipk = int(np.argmax(amp))
    notes = []
    f_lo, f_hi = sorted((spec.frequency_start_hz, spec.frequency_end_hz))
    f_pk = float(res.omega[ipk] / (2 * np.pi))
    # the largest amplitude at an end of the computed curve is not a resonance peak
    peak_truncated = res.n_points < 3 or ipk in (0, res.n_points - 1)
    failed = None
    if not res.success:
        f_last = float(res.omega[-1] / (2 * np.pi))
        failed = (f"the continuation stopped at {f_last:.4g} Hz of {f_lo:g}-{f_hi:g} Hz "
                  f"(status {res.status}): {res.message}")
    if peak_truncated:
        notes.append(f"the largest amplitude is at the end of the computed curve "
                     f"({f_pk:.4g} Hz): it is truncated, not a resonance peak"
                     + ("" if res.success else " (the curve is incomplete)"))
    summary = {
        "omega_rad_s": res.omega,
        "frequency_hz": res.omega / (2 * np.pi),
        "amplitude_m": amp,
        "dissipated_energy_J": diss,
        "external_work_J": res.external_work,
        "response_dof": dof + 1,
        "response_dof_name": system.names[dof],
        "peak_frequency_hz": f_pk,
        "peak_amplitude_m": float(amp[ipk]),
        "peak_truncated": bool(peak_truncated),
        "n_points": res.n_points,
        "harmonics": res.harmonics,
        "samples": res.samples,
        "method": res.method,
        "energy_balance_error": float(np.max(res.energy_balance_error)),
        "status": res.status,
        "message": res.message,
        "solver_runtime_s": float(res.wall_time),
        "stable": None,
        "bifurcations": None,
    }
    # harmonic truncation and AFT sampling at the largest response
    trunc = {}
    if np.all(np.isfinite(res.coefficients[ipk])):
        trunc = harmonic_truncation(sys_, float(res.omega[ipk]), res.coefficients[ipk],
                                    harmonics=res.harmonics, samples=res.samples)
    reasons = []
    w_scale = float(np.max(np.abs(res.external_work), initial=0.0))
    neg = float(np.min(diss, initial=0.0))
    if neg < -THRESHOLDS["negative_dissipation"] * max(w_scale, 1e-300):
        i_neg = int(np.argmin(diss))
        reasons.append(f"the contacts give energy back ({neg:.3g} J per cycle at "
                       f"{res.omega[i_neg] / (2 * np.pi):.4g} Hz): not a passive steady state; "
                       "increase harmonics or samples")
    for key in ("harmonic_truncation", "aft_sampling_error"):
        if trunc and trunc.get(key) is None:
            reasons.append(f"the {key.replace('_', ' ')} check at the peak did not converge "
                           f"({trunc.get(key + '_message', '')[:120]})")
    verdict = judge({"energy_balance_error": summary["energy_balance_error"],
                     "harmonic_truncation": trunc.get("harmonic_truncation"),
                     "aft_sampling_error": trunc.get("aft_sampling_error"),
                     "harmonics_check": trunc.get("H2"),
                     "peak_truncated": bool(peak_truncated)},
                    reasons=reasons, failed=failed)
    summary["harmonic_truncation"] = trunc.get("harmonic_truncation")
    summary["aft_sampling_error"] = trunc.get("aft_sampling_error")
    peak_word = "largest amplitude (at the end of the curve, truncated)" if peak_truncated \
        else "peak"
    headline = (f"{res.n_points} HB points (H = {res.harmonics}) in {res.wall_time:.2f} s; "
                f"{peak_word} {amp[ipk]:.3g} m of {system.names[dof]} at "
                f"{summary['peak_frequency_hz']:.4g} Hz; energy balance error "
                f"{summary['energy_balance_error']:.1e}")
    if summary["harmonic_truncation"] is not None:
        headline += f"; harmonic truncation {summary['harmonic_truncation']:.1e}"
    if res.stable is not None:
        summary.update({
            "stable": res.stable,
            "bifurcations": [b.as_dict(dof) for b in res.bifurcations],
            "floquet_max_real_per_s": res.floquet_exponents.real.max(axis=1),
            "n_unstable_points": int(np.sum(~res.stable)),
            "stability_error_per_s": float(res.stability_error),
            "stability_converged": res.stability_converged,
            "stability_method": "Hill (eigenvector-centrality sorting; H + 1 check)",
        })
        kinds = [f"{b.type} at {b.omega / (2 * np.pi):.4g} Hz" for b in res.bifurcations]
        headline += (f"; {summary['n_unstable_points']} unstable point"
                     f"{'s' if summary['n_unstable_points'] != 1 else ''}"
                     + (f", {', '.join(kinds)}" if kinds else ", no bifurcation"))
        if res.stability_converged is False:
            notes.append("the stability verdict changes at some checked points when the "
                         f"solution is re-solved with H + 1 = {res.harmonics + 1} harmonics: "
                         "increase harmonics")
        if any(not b.located for b in res.bifurcations):
            notes.append("some bifurcations could not be located between their two points; "
                         "the nearer point is reported (located = false)")
    arrays = {"curve": res.to_xarray()}
    backbone = None
    if spec.backbone_mode is not None:
        backbone = _backbone(system, spec, res, dof, amp, ipk, peak_truncated, summary, notes)
        if backbone is not None:      # its own names: merged with the curve in results.nc
            bds = backbone.to_xarray()
            arrays["backbone"] = bds.rename(
                {v: f"backbone_{v}" for v in [*bds.data_vars, "amplitude"]})

    def figures():
        from fricdamp import plot

        f = res.omega / (2 * np.pi)
        # conservative contacts (cubic springs): the friction energy is round-off, not drawn
        friction = np.max(np.abs(diss), initial=0.0) > 1e-8 * np.max(
            np.abs(res.external_work), initial=0.0)
        fig, axes = plot.new_figure(2 if friction else 1, 1, sharex=True,
                                    title=f"Frequency response (harmonic balance, H = "
                                          f"{res.harmonics})")
        fa, la = plot.si_scale(amp, "m")
        axes[0, 0].plot(f[ipk], amp[ipk] / fa, "o", ms=5, color="C1",
                        zorder=1 if res.stable is not None else 3)   # under fold markers
        if res.stable is None:
            axes[0, 0].plot(f, amp / fa, lw=1.5)
        else:
            plot.stability_line(axes[0, 0], f, amp / fa, res.stable, lw=1.5,
                                label="harmonic balance")
            marks = {"fold": "o", "branch_point": "s", "neimark_sacker": "D",
                     "period_doubling": "^"}
            for kind, mk in marks.items():
                bs = [b for b in res.bifurcations if b.type == kind]
                if bs:
                    axes[0, 0].plot([b.omega / (2 * np.pi) for b in bs],
                                    [b.amplitude[dof] / fa for b in bs], mk, ms=6, mfc="none",
                                    color="k", label=kind.replace("_", "-"))
            axes[0, 0].legend(fontsize="small")
        if backbone is not None:
            axes[0, 0].plot(summary["backbone_frequency_hz"],
                            np.asarray(summary["backbone_amplitude_m"]) / fa, "--", color="k",
                            lw=1.0, label=f"nonlinear mode {spec.backbone_mode} (backbone)")
            axes[0, 0].legend(fontsize="small")
        axes[0, 0].set_ylabel(f"amplitude of {plot.dof_label(system.names[dof])} [{la}]")
        if friction:
            fe, le = plot.si_scale(diss, "J")
            axes[1, 0].plot(f, diss / fe, lw=1.5, color="C3")
            axes[1, 0].set_ylabel(f"friction energy per cycle [{le}]")
        axes[-1, 0].set_xlabel("excitation frequency [Hz]")
        caption = ("Frequency response and friction energy per cycle" if friction
                   else "Frequency response")
        if res.stable is not None:
            caption += " (dashed: unstable by Hill's method)"
        return [("frf.png", caption, fig)]

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, verdict=verdict)


def _backbone(system, spec: FRF, res, dof: int, amp, ipk: int, peak_truncated: bool,
              summary: dict, notes: list):
    """Nonlinear mode ``spec.backbone_mode`` (EPMC) at 24 fundamental amplitudes of the
    response DOF, geometric from 1/100 of the curve's largest fundamental to 1.2 times it;
    adds the ``backbone_*`` keys to ``summary`` and returns the NonlinearModes (None, with a
    note, when no point converges)."""
    from fricdamp.solvers.nma import nonlinear_modes

    top = float(np.max(res.fundamental[:, dof]))
    try:
        nm = nonlinear_modes(system.with_loads(), spec.backbone_mode - 1,
                             np.geomspace(top / 100, 1.2 * top, 24), harmonics=spec.harmonics,
                             samples=spec.samples, amplitude_dof=dof)
    except (ModelError, ConvergenceError) as exc:
        notes.append(f"the backbone (nonlinear mode {spec.backbone_mode}) failed: {exc}")
        return None
    if nm.amplitude.size == 0:
        notes.append(f"the backbone (nonlinear mode {spec.backbone_mode}) has no converged "
                     f"point ({nm.message})")
        return None
    a_bb = nm.dof_amplitude[:, dof]
    at_peak = None
    if not peak_truncated and a_bb[0] <= amp[ipk] <= a_bb[-1] and np.all(np.diff(a_bb) > 0):
        at_peak = float(np.interp(amp[ipk], a_bb, nm.frequency_hz))
    summary.update({
        "backbone_mode": spec.backbone_mode,
        "backbone_frequency_hz": nm.frequency_hz,
        "backbone_amplitude_m": a_bb,
        "backbone_damping_ratio": nm.damping_ratio,
        "backbone_frequency_at_peak_hz": at_peak,
    })
    if not nm.success:
        notes.append(f"the backbone stopped at {nm.amplitude[-1]:.3g} m of {1.2 * top:.3g} m "
                     f"({nm.message})")
    return nm


# ------------------------------------------------------------------------------- NMA
class NMA(Section):
    """``[analysis.nma]``: amplitude-dependent frequency and damping ratio of one mode
    (extended periodic motion concept)."""

    mode: int = Field(1, ge=1, le=1000, description="mode number (1 = lowest, contacts stuck)")
    amplitude_dof: int = Field(ge=1, description="DOF at which the amplitude is measured")
    amplitudes_m: list[Positive] = Field(min_length=2, description="increasing fundamental "
                                                                   "amplitudes at amplitude_dof")
    harmonics: int = Field(7, ge=1, le=200, description="highest harmonic H")
    samples: int | None = Field(None, ge=8, le=1_000_000, description="AFT samples per period")

    @model_validator(mode="after")
    def _increasing(self):
        a = np.asarray(self.amplitudes_m)
        if np.any(np.diff(a) <= 0):
            raise ValueError("amplitudes_m must be strictly increasing")
        return self


def _check_nma(system, spec: NMA) -> None:
    _check_dof(spec.amplitude_dof, system.n_dof, "amplitude_dof")


def run_nma(system, spec: NMA, ctx: RunContext) -> AnalysisOutput:
    from fricdamp.solvers.nma import nonlinear_modes

    res = nonlinear_modes(system.with_loads(), spec.mode - 1, spec.amplitudes_m,
                          harmonics=spec.harmonics, samples=spec.samples,
                          amplitude_dof=spec.amplitude_dof - 1)
    if res.amplitude.size == 0:
        raise ConvergenceError(f"nonlinear modal analysis: no converged point ({res.message})")
    notes = []
    failed = None
    if not res.success:
        failed = (f"the nonlinear mode stopped at amplitude {res.amplitude[-1]:.3g} of "
                  f"{spec.amplitudes_m[-1]:.3g} (status {res.status}): {res.message}")
    diss = res.dissipated_energy.sum(axis=1) if res.dissipated_energy.size else np.zeros(
        res.amplitude.size)
    summary = {
        "amplitude": res.amplitude,
        "amplitude_unit": "m",
        "amplitude_dof": spec.amplitude_dof,
        "frequency_hz": res.frequency_hz,
        "damping_ratio": res.damping_ratio,
        "dissipated_energy_J": diss,
        "linear_frequency_hz": float(res.linear_frequency / (2 * np.pi)),
        "linear_damping_ratio": float(res.linear_damping_ratio),
        "damping_ratio_definition": "energy-based modal ratio xi / (2 omega) of the EPMC",
        "energy_balance_error": float(np.max(res.energy_balance_error)),
        "status": res.status,
        "message": res.message,
    }
    imax = int(np.argmax(res.damping_ratio))
    headline = (f"mode {spec.mode}: {res.frequency_hz[0]:.4g} -> {res.frequency_hz[-1]:.4g} Hz, "
                f"largest damping ratio {100 * res.damping_ratio[imax]:.3g} % at "
                f"{res.amplitude[imax]:.3g} m")

    def figures():
        from fricdamp import plot

        fig = plot.damping_vs_amplitude(res.amplitude, res.damping_ratio, res.frequency_hz,
                                        title=f"Nonlinear mode {spec.mode} (H = "
                                              f"{res.harmonics})")
        return [("nma.png", "Nonlinear mode: damping ratio and frequency vs amplitude", fig)]

    trunc, reasons = _nma_truncation(system, spec, res)
    summary["harmonic_truncation"] = trunc
    verdict = judge({"energy_balance_error": summary["energy_balance_error"],
                     "harmonic_truncation": trunc}, reasons=reasons, failed=failed)
    return AnalysisOutput(summary=summary, arrays={"modes": res.to_xarray()}, figures=figures,
                          headline=headline, notes=notes, verdict=verdict)


def _nma_truncation(system, spec: NMA, res) -> tuple[float | None, list[str]]:
    """Largest relative change of the frequency and damping ratio over the computed
    amplitudes when the mode is computed again with ``min(2H + 1, H + 10)`` harmonics."""
    from fricdamp.solvers.nma import nonlinear_modes

    H2 = min(2 * res.harmonics + 1, res.harmonics + 10)
    amps = np.asarray(res.amplitude, float)
    more = nonlinear_modes(system.with_loads(), spec.mode - 1, amps, harmonics=H2,
                           amplitude_dof=spec.amplitude_dof - 1)
    n = min(more.amplitude.size, amps.size)
    if n == 0 or not more.success:
        return None, [f"the harmonic truncation check with H = {H2} did not converge "
                      f"({more.message})"]
    df = np.abs(more.frequency_hz[:n] - res.frequency_hz[:n]) / np.abs(more.frequency_hz[:n])
    zeta = np.abs(more.damping_ratio[:n])
    dz = np.abs(more.damping_ratio[:n] - res.damping_ratio[:n]) / np.maximum(
        zeta, 1e-12 * np.max(zeta, initial=0.0) + 1e-300)
    return float(max(np.max(df), np.max(dz))), []


register_analysis("frf", FRF, run_frf, check=_check_frf,
                  description="frequency response through resonance by harmonic balance")
register_analysis("nma", NMA, run_nma, check=_check_nma,
                  description="nonlinear modal analysis: frequency and damping vs amplitude")
