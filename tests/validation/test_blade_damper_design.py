"""Steady state and design study of the paper-000 blade damper (000 Fig. 12)."""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper.studies import (
    default_design_band,
    design_study,
    pulloff_curve,
    resonance_amplitude,
    steady_state_amplitude,
)


def _stuck_q4(p, f):
    """|q4| of the stuck 3-DOF system (000 (22)) solved directly: (K - w^2 M + i w D) z = F,
    with F = (0, F_e, F_e ratio e^{i phase}) on (u, q2, q4)."""
    L = BladeDamperSystem(p).stuck_system()
    w = 2 * np.pi * np.asarray(f)
    F = np.array([0.0, p.excitation_amplitude,
                  p.excitation_amplitude * p.excitation_ratio * np.exp(1j * p.excitation_phase)])
    return np.array([abs(np.linalg.solve(L.K - wi**2 * L.M + 1j * wi * L.D, F)[2])
                     for wi in w])


def test_stuck_design_points_are_exact():
    """Below the pull-off amplitude at every frequency of the band the damper never slips,
    so the resonant amplitude is the peak of the stuck system's linear response, which does
    not depend on the damper mass (to its 1 g in 0.8 kg) or on gamma. Reference: the 3-DOF
    system solved here on a 4001-point grid; tolerance 1e-4 relative (grid of 401 points in
    the study: the peak is flat to second order, (0.5 * step / half-power width)^2 ~ 1e-4)."""
    p = BladeDamperParameters(excitation_amplitude=0.3)
    f = default_design_band(p)
    ds = design_study(p, (1e-3, 2e-3), (50.0, 65.0), frequency_hz=f)
    fine = np.linspace(f[0], f[-1], 4001)
    for im, m in enumerate((1e-3, 2e-3)):
        ref = _stuck_q4(p.with_(damper_mass=m), fine).max()
        assert np.allclose(ds.blade_amplitude_m[0, im], ref, rtol=1e-4)
    assert ds.converged.all() and not ds.errors
    d = ds.to_dict()
    assert set(d) >= {"damper_mass_kg", "gamma_deg", "blade_amplitude_m", "optimum"}
    assert np.array(d["blade_amplitude_m"]).shape == (2, 2)
    opt = d["optimum"]
    assert opt["blade_amplitude_m"] == pytest.approx(np.min(d["blade_amplitude_m"]))
    assert set(opt) >= {"damper_mass_kg", "gamma_deg", "blade_amplitude_m"}


def test_steady_state_below_pulloff_is_the_stuck_response():
    p = BladeDamperParameters(excitation_amplitude=0.5, excitation_frequency=50.0)
    assert p.excitation_amplitude < pulloff_curve(p, [50.0]).F_e_limit_N[0]
    ss = steady_state_amplitude(p)
    assert ss.converged and ss.periods == 0
    assert ss.amplitude_m == pytest.approx(_stuck_q4(p, [50.0])[0], rel=1e-12)


@pytest.mark.slow
def test_friction_limits_the_resonance():
    """Above the pull-off amplitude the damper slips and dissipates: at the second stuck
    resonance (62.7 Hz, blades in opposition) the event-driven steady amplitude stays well
    below the stuck (linear) response at the same excitation (< 0.5 of it). The steady
    state is checked by the energy balance of four more periods: the mechanical energy
    returns to its value (change below 10 % of the input work: the stick-slip steady state
    here is not periodic, the contacts take turns irregularly) and friction dissipates a
    good part of the input; the amplitude stays within 10 % of the steady value (the
    largest over the 8-period window)."""
    from fricdamp.models.blade_damper.studies import time_response

    p = BladeDamperParameters(excitation_amplitude=3.0)
    f0 = BladeDamperSystem(p).stuck_system().eigenfrequencies()[1]
    assert p.excitation_amplitude > pulloff_curve(p, [f0]).F_e_limit_N[0]
    pp = p.with_(excitation_frequency=float(f0))
    ss = steady_state_amplitude(pp, chunk_periods=8.0, max_periods=48.0, tol=0.05,
                                method="window")
    assert ss.converged and not ss.errors and ss.periods > 0
    assert ss.amplitude_m < 0.5 * _stuck_q4(pp, [f0])[0]
    tr = time_response(pp, 4.0, y0=ss.y_end, t_start=ss.periods / f0, samples_per_period=100)
    e = tr.result.energy
    mech = e["kinetic"] + e["potential"]
    assert abs(mech[-1] - mech[0]) < 0.1 * e["input_work"][-1]
    assert e["friction_dissipation"][-1] > 0.1 * e["input_work"][-1]
    amp = 0.5 * np.ptp(tr.result.q[:, 3])
    assert amp == pytest.approx(ss.amplitude_m, rel=0.1)


def test_resonance_sweep_contract():
    """The window method's fine sweep (kept for comparison; shooting's peak search is
    exercised by the blade_damper_pulloff case)."""
    p = BladeDamperParameters(excitation_amplitude=8.0)  # slips across the first resonance
    r = resonance_amplitude(p, [50.5, 51.5], chunk_periods=3.0, max_periods=6.0, tol=0.05,
                            resolution_hz=0.25, method="window")
    assert r["amplitude_m"].shape == (2,) and r["stuck"].dtype == bool
    assert not r["stuck"].any()
    assert np.isfinite(r["peak_amplitude_m"]) and 50.5 <= r["peak_hz"] <= 51.5
    # the fine sweep fills the bracket of the largest sample in 0.25 Hz steps
    np.testing.assert_allclose(r["refined_hz"], [50.75, 51.0, 51.25])
    assert len(r["refined_amplitude_m"]) == 3
    assert r["peak_amplitude_m"] >= max(np.nanmax(r["amplitude_m"]),
                                        max(r["refined_amplitude_m"]))


def test_design_study_rejects_bad_grids():
    with pytest.raises(ModelError, match="damper_masses_kg"):
        design_study(BladeDamperParameters(), (0.0,), (50.0,))
    with pytest.raises(ModelError, match="gammas_deg"):
        design_study(BladeDamperParameters(), (1e-3,), (95.0,))


def test_optimum_skips_designs_that_violate_the_model():
    """A design whose sweep reported a negative normal force (the damper would lift off) is
    not a valid optimum even if its amplitude is the smallest."""
    from fricdamp.models.blade_damper.studies import DesignStudy

    A = np.array([[[3.0, 1.0], [2.0, 4.0]]])
    ds = DesignStudy(damper_mass_kg=np.array([1e-3, 2e-3]), gamma_deg=np.array([50.0, 80.0]),
                     parabolas=((-80.0, 2e-3),), blade_amplitude_m=A,
                     peak_frequency_hz=np.full(A.shape, 51.0), converged=np.ones(A.shape, bool),
                     valid=np.array([[[True, False], [True, True]]]),
                     centrifugal_acceleration=1e5, frequency_hz=np.array([51.0]))
    assert ds.optimum == {"damper_mass_kg": 2e-3, "gamma_deg": 50.0, "p1_per_m": -80.0,
                          "p2_m": 2e-3, "blade_amplitude_m": 2.0}
    assert ds.to_dict()["parabolas"][0]["valid"] == [[True, False], [True, True]]
