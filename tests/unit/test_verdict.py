"""Verdicts and error estimates (issue 15): the estimates measure what they claim.

References: Newmark's average-acceleration rule turns a linear oscillator by
``2 atan(omega h / 2)`` per step (Hughes, The Finite Element Method, 1987, sec. 9.3), so its
period error is ``omega h / (2 atan(omega h / 2)) - 1``; the test measures the period of the
integrated oscillator and compares.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import CheckError, ModelError
from fricdamp.limits import check_harmonics_memory, check_time_memory
from fricdamp.solvers.timestep import simulate
from fricdamp.structure import chain
from fricdamp.verdict import (
    FAILED,
    OK,
    UNRELIABLE,
    Verdict,
    combine,
    exit_code,
    judge,
    newmark_period_error,
    time_result_verdict,
    time_step_error,
)

ONE_HZ = chain([1.0], [4 * np.pi**2])


def _measured_period(t, x):
    """Period from the upward zero crossings (linear interpolation between samples)."""
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return float(np.mean(np.diff(tc)))


@pytest.mark.parametrize("steps_per_period", [2.5, 6.0, 20.0])
def test_period_error_formula_matches_the_integrated_oscillator(steps_per_period):
    """The closed-form period error equals the measured one of a 1 Hz oscillator.

    Zero crossings interpolated linearly between samples: at 2.5-6 steps per period that
    interpolation errs by a few % of a step per crossing, averaged over ~10-40 crossings:
    tolerance 1 % of the period error itself or 2e-4 absolute."""
    dt = 1.0 / steps_per_period
    res = simulate(ONE_HZ, 40.0, dt, q0=[1.0], v0=[0.0], progress=False)
    # the discrete solution is cos(theta k) exactly; its zero crossings are those of a
    # continuous cosine of the same phase rate, so compare with the analytic phase rate
    theta = 2 * np.arctan(2 * np.pi * dt / 2)
    assert _measured_period(res.t, res.q[:, 0]) == pytest.approx(
        2 * np.pi / theta * dt, rel=0.05)
    expected = 2 * np.pi * dt / theta - 1.0
    assert float(newmark_period_error(2 * np.pi * dt)) == pytest.approx(expected, rel=1e-12)
    est = time_step_error(ONE_HZ, res, dt)
    assert est["period_error"] == pytest.approx(expected, rel=1e-9)
    assert est["steps_per_period"] == pytest.approx(steps_per_period, rel=1e-9)


def test_small_step_limit_is_omega_h_squared_over_12():
    wh = np.array([1e-5, 1e-3, 1e-2])
    assert np.allclose(newmark_period_error(wh), wh**2 / 12, rtol=1e-4)


def test_one_hz_at_2_5_steps_is_unreliable_though_its_energy_balance_is_exact():
    """Issue 15: 4e-15 energy balance error, 42 % wrong. The verdict sees the 40 %."""
    res = simulate(ONE_HZ, 10.0, 0.4, q0=[1.0], progress=False)
    assert res.energy_balance_error < 1e-12
    v = time_result_verdict(ONE_HZ, res, 0.4)
    assert v.status == UNRELIABLE
    assert v.estimates["period_error"] == pytest.approx(0.398, abs=1e-3)
    assert any("period error" in r and "time step" in r for r in v.reasons)


def test_api_simulate_with_a_bad_dt_gets_an_unreliable_verdict():
    """Issue 15: simulate(..., dt=0.1, throw=False) returned success=True silently; the
    verdict on its result says unreliable (period error 3.3 % at 10 steps per period)."""
    res = simulate(ONE_HZ, 10.0, 0.1, q0=[1.0], throw=False, progress=False)
    assert res.success
    v = time_result_verdict(ONE_HZ, res, 0.1)
    assert v.status == UNRELIABLE and v.estimates["period_error"] > 0.03


def test_fine_step_is_ok():
    res = simulate(ONE_HZ, 3.0, 1e-3, q0=[1.0], progress=False)
    v = time_result_verdict(ONE_HZ, res, 1e-3)
    assert v.status == OK, v.reasons
    assert v.estimates["period_error"] < 1e-5


def test_modes_without_energy_do_not_count():
    """A stiff second mode that is never excited does not flag a run (share < 1 %)."""
    import scipy.linalg as sla

    sys2 = chain([1.0, 1e-6], [4 * np.pi**2, 1e3], ground="first")   # mode 2 near 5 kHz
    # initial displacement along the first mode only
    lam, phi = sla.eigh(np.asarray(sys2.K.toarray() if hasattr(sys2.K, "toarray")
                                   else sys2.K), np.diag([1.0, 1e-6]))
    q0 = phi[:, 0] / phi[0, 0] * 1e-3
    res = simulate(sys2, 2.0, 2e-3, q0=q0, progress=False)
    est = time_step_error(sys2, res, 2e-3)
    assert est["mode_count"] == 1
    assert est["max_frequency_hz"] == pytest.approx(np.sqrt(lam[0]) / (2 * np.pi), rel=1e-9)


def test_verdict_combination_and_exit_codes():
    ok = Verdict()
    bad = Verdict.unreliable("x")
    dead = Verdict.failed("y")
    assert combine([]) == OK
    assert combine([ok, bad]) == UNRELIABLE
    assert combine([bad, dead, ok]) == FAILED
    assert [exit_code(s) for s in (OK, FAILED, UNRELIABLE)] == [0, 1, 3]
    with pytest.raises(ValueError, match="verdict status"):
        Verdict("fine")


def test_judge_thresholds():
    assert judge({"energy_balance_error": 0.573}).status == UNRELIABLE
    assert judge({"energy_balance_error": 1e-4}).status == OK
    assert judge({"energy_balance_error": float("nan")}).status == OK   # not available
    assert judge({"energy_balance_error": 1e-4}, failed="stopped").status == FAILED
    d = judge({"harmonic_truncation": 0.05}).to_dict()
    assert d["verdict"] == UNRELIABLE and "H too small" in d["reasons"][0]


def test_negative_dissipation_is_unreliable():
    e = {k: np.zeros(5) for k in ("input_work", "kinetic", "strain", "contact_stored",
                                  "viscous_dissipation")}
    e["kinetic"] = np.array([0.1, 0.1, 0.1, 0.15, 0.2])
    e["contact_dissipation"] = np.array([0.0, 0.0, 0.0, -0.05, -0.1])

    class R:
        energy = e
        energy_balance_error = 0.0
        v = np.zeros((5, 1))
        success = True

    v = time_result_verdict(ONE_HZ, R(), 0.01)
    assert v.status == UNRELIABLE and v.estimates["negative_dissipation"] == pytest.approx(0.5)


# ------------------------------------------------------------------------------ sizes
def test_memory_checks_name_the_parameter():
    with pytest.raises(CheckError, match=r"^dt = 1e-12 would need about .*TiB"):
        check_time_memory(1.0, 1e-12, 1)
    assert check_time_memory(1.0, 1e-3, 1) == 1000
    with pytest.raises(CheckError, match=r"^harmonics = 1000000000 would need"):
        check_harmonics_memory(10**9, None, 1, 1)
    check_harmonics_memory(7, None, 16, 1)
    with pytest.raises(ModelError, match="harmonics must be an integer >= 1"):
        check_harmonics_memory(0, None, 1)


def test_harmonic_balance_refuses_a_billion_harmonics_before_allocating():
    from fricdamp.contact import Jenkins
    from fricdamp.solvers.hb import harmonic_balance
    from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem

    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
                         contacts=(ContactElement(Jenkins(1.0, 0.05), [[1.0]]),),
                         loads=(HarmonicLoad([0.1], omega=1.0),))
    with pytest.raises(CheckError, match="harmonics = 1000000000"):
        harmonic_balance(s, 1.2, harmonics=10**9)


# ------------------------------------------------------------------ harmonic balance
def _duffing():
    from fricdamp.contact import CubicSpring
    from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem

    return MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
                            contacts=(ContactElement(CubicSpring(0.5), [[1.0]]),),
                            loads=(HarmonicLoad([0.03], omega=1.0),))


def test_frequency_response_verdict_follows_its_status():
    """A continuation stopped by max_points is failed and its largest amplitude, at the end
    of the computed curve, is truncated; the complete curve is ok with an interior peak."""
    from fricdamp.solvers.hb import frequency_response

    short = frequency_response(_duffing(), 0.8, 1.6, harmonics=3, max_points=10)
    assert short.status != 0
    assert short.verdict.status == FAILED and short.peak_truncated
    full = frequency_response(_duffing(), 0.8, 1.6, harmonics=3)
    assert full.success and full.verdict.status == OK and not full.peak_truncated


def test_harmonic_truncation_tracks_the_true_truncation_error():
    """Jenkins oscillator in gross slip (F_s = 0.05, F = 0.1, Omega = 1.2). The true error of
    the amplitude at H is measured against H = 41; the estimate (re-solve at min(2H+1, H+10))
    must be of its size: within a factor 3, or 1e-4 absolute (the H = 41 reference and the
    AFT grids differ at that level). H = 1: 1.9 % true error; H = 7: 5e-4."""
    from fricdamp.contact import Jenkins
    from fricdamp.solvers.hb import harmonic_balance
    from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem
    from fricdamp.verdict import harmonic_truncation

    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
                         contacts=(ContactElement(Jenkins(1.0, 0.05), [[1.0]]),),
                         loads=(HarmonicLoad([0.1], omega=1.0),))
    ref = harmonic_balance(s, 1.2, harmonics=41)
    est = {}
    for H in (1, 3, 7):
        ss = harmonic_balance(s, 1.2, harmonics=H)
        e = harmonic_truncation(s, 1.2, ss.coefficients, harmonics=H, samples=ss.samples)
        true = abs(ss.amplitude[0] - ref.amplitude[0]) / ref.amplitude[0]
        est[H] = e["harmonic_truncation"]
        assert est[H] <= 3 * true + 1e-4 and true <= 3 * est[H] + 1e-4, (H, est[H], true)
    assert est[1] > 10 * est[7]


def test_contact_that_dissipates_more_than_it_received_is_unreliable():
    """Issue 15's stiff-contact run: the contact "dissipated" 0.2 J of 0.1 J, energy balance
    error 0.573, exit 0. Reproduced here by a law that books twice its true dissipation (the
    bookkeeping error a bad contact integration makes): the verdict is unreliable, and the
    reason names the energy balance."""
    from fricdamp.contact import Jenkins
    from fricdamp.structure import ContactElement

    class DoubleBooked(Jenkins):
        def dissipation(self, state_old, state_new, force_new):
            return 2.0 * super().dissipation(state_old, state_new, force_new)

    s = chain([1.0], [2000.0]).with_contacts(ContactElement(DoubleBooked(1e6, 5.0), [[1.0]]))
    res = simulate(s, 0.5, 1e-4, q0=[0.01], progress=False)     # 0.1 J initial energy
    e = res.energy
    assert e["contact_dissipation"][-1] > 1.5 * (e["kinetic"][0] + e["strain"][0]) / 2
    v = time_result_verdict(s, res, 1e-4)
    assert res.energy_balance_error > 0.1 and v.status == UNRELIABLE
    assert any(r.startswith("energy balance error") for r in v.reasons)


def test_default_verdict_of_an_analysis_without_one():
    """Analyses that do not judge themselves (the tie-boss wheels') are ok unless they report
    failure; an energy balance over the limit is recorded and noted, not judged."""
    from fricdamp.runner import AnalysisOutput, default_verdict

    out = AnalysisOutput(summary={"energy_balance_error": 0.0306})
    v = default_verdict(out)
    assert v.status == OK and v.estimates["energy_balance_over_limit"] is True
    assert any("0.0306 exceeds the limit 0.01" in n for n in out.notes)
    assert default_verdict(AnalysisOutput(summary={"energy_balance_error": 1e-4})).estimates == {
        "energy_balance_error": 1e-4}
    v = default_verdict(AnalysisOutput(summary={"success": False, "message": "diverged"}))
    assert v.status == FAILED and v.reasons == ("diverged",)
