"""Designs beyond lift-off are computed, not discarded (issue 14): ``release=True`` threads the
released blade damper (unilateral normal contacts: lift-off and impacts,
``BladeDamperSystem(release=True)``) through ``time_response``, ``steady_state_amplitude``,
``resonance_amplitude`` and ``design_study``.

The lifting-off design is the one of tests/validation/test_blade_damper_release.py and
test_blade_damper_design_workers.py: 1 g damper, F_Z = 100 N (a_c = 1e5 m/s^2), F_e = 8 N,
gamma = 80 deg near 51.5-52 Hz (the no-separation model turns a normal force tensile there);
65 deg does not lift off. The budgets are small (window method, 12 periods): these tests
check the plumbing and the contract, not converged amplitudes.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.blade_damper.configurations import (
    CONFIGURATIONS,
    RELEASED_CONFIGURATIONS,
    configuration_codes,
    time_in_configuration,
)
from fricdamp.models.blade_damper.model import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper.studies import (
    design_study,
    resonance_amplitude,
    steady_state_amplitude,
    time_response,
)

P8 = BladeDamperParameters(excitation_amplitude=8.0)
LIFTS = P8.with_(gamma_deg=80.0, excitation_frequency=52.0)
KW = dict(damper_masses_kg=[1e-3], gammas_deg=[65.0, 80.0], frequency_hz=[47.0, 51.5],
          centrifugal_acceleration=1e5, boundary_refinements=0, method="window",
          chunk_periods=4, max_periods=12, resolution_hz=None)


def test_configuration_codes_keep_the_four_and_add_open():
    modes = np.array([[0, 0], [0, 1], [2, 0], [1, 2], [3, 0], [3, 2], [0, 3], [1, 3], [3, 3]])
    assert configuration_codes(modes).tolist() == list(range(9))
    assert RELEASED_CONFIGURATIONS[:4] == CONFIGURATIONS and len(CONFIGURATIONS) == 4
    assert [RELEASED_CONFIGURATIONS[k] for k in configuration_codes(modes[4:])] == [
        "open/stick", "open/slip", "stick/open", "slip/open", "open/open"]
    tic = time_in_configuration([0.0, 1.0, 3.0, 6.0], modes[[0, 4, 8, 8]])
    assert tic["stick/stick"] == 1.0 and tic["open/stick"] == 2.0 and tic["open/open"] == 3.0
    assert set(time_in_configuration([0.0, 1.0], modes[:2])) == set(CONFIGURATIONS)


def test_released_time_response_lifts_off_without_crashing():
    """8 periods from the static state: the damper first lifts off about 6.9 periods in
    (test_blade_damper_release.py); the open configurations are counted, the normal forces
    stay compressive (>= -1e-6 N) and the run is not flagged."""
    tr = time_response(LIFTS, 8.0, samples_per_period=50, release=True)
    assert tr.ok, tr.errors
    assert np.any(tr.configuration >= 4)
    assert set(tr.time_in_configuration) == set(RELEASED_CONFIGURATIONS)
    assert sum(tr.time_in_configuration.values()) == pytest.approx(8.0 / 52.0, rel=1e-9)
    assert 0 < tr.open_fraction < 0.5
    assert tr.min_normal_force >= -1e-6
    bilateral = time_response(LIFTS, 8.0, samples_per_period=50)
    assert not bilateral.ok and bilateral.min_normal_force < -1.0
    assert bilateral.open_fraction == 0.0


def test_below_lift_off_release_changes_nothing():
    """65 deg does not lift off: the released model never opens a contact, so it is the
    no-separation model and gives the same stepped sine (stuck point at 47 Hz, periodic orbit
    by shooting at 56 Hz). Tolerance 1e-9 relative: both integrate the same closed-contact
    phases (the gap event never fires); measured equal to the last digit."""
    p = P8.with_(gamma_deg=65.0)
    f = [47.0, 56.0]
    a = resonance_amplitude(p, f, resolution_hz=None)
    b = resonance_amplitude(p, f, resolution_hz=None, release=True, restitution=0.5)
    assert not a["errors"] and not b["errors"]
    assert b["release"] and not a["release"]
    assert b["stuck"].tolist() == a["stuck"].tolist() == [True, False]
    np.testing.assert_allclose(b["amplitude_m"], a["amplitude_m"], rtol=1e-9)
    assert b["open_fraction"] == 0.0
    assert b["min_normal_force_N"] == pytest.approx(a["min_normal_force_N"], rel=1e-9)


def test_stuck_shortcut_only_while_compressive():
    """Below the pull-off amplitude the stuck steady state is exact; with release only if
    its normal forces stay compressive. 80 deg at 2 N, 52 Hz: stuck and compressive, so the
    shortcut stands (same amplitude, no integration) with or without release."""
    p = LIFTS.with_(excitation_amplitude=2.0)
    a = steady_state_amplitude(p)
    b = steady_state_amplitude(p, release=True)
    assert a.method == b.method == "stuck" and a.min_normal_force_N > 0
    assert b.amplitude_m == a.amplitude_m and b.open_fraction == 0.0
    assert set(b.time_in_configuration) == set(RELEASED_CONFIGURATIONS)


def test_design_beyond_lift_off_is_computed():
    """A two-design study (1 g; 65 deg valid, 80 deg lifts off at 51.5 Hz): without release
    the 80-deg design is invalid and not released; with release it is recomputed with the
    released model: finite amplitude, ``released``, normal forces >= -1e-6 N on the released
    run, a contact open part of the time; it stays invalid, the no-separation optimum does
    not move, and ``optimum_with_release`` is over both designs."""
    plain = design_study(P8, **KW)
    rel = design_study(P8, release=True, restitution=0.0, **KW)
    for d in (plain, rel):
        assert d.valid[0, 0].tolist() == [True, False]
        assert d.lift_off[0, 0].tolist() == [False, True]
        assert d.min_normal_force_N[0, 0, 1] < 0
        assert d.optimum["gamma_deg"] == 65.0
    assert plain.released is None and not plain.release
    assert rel.released[0, 0].tolist() == [False, True]
    assert np.isfinite(rel.blade_amplitude_m[0, 0, 1])
    assert rel.released_min_normal_force_N[0, 0, 1] >= -1e-6
    assert 0 < rel.open_fraction[0, 0, 1] < 1
    assert np.isnan(rel.open_fraction[0, 0, 0])
    # the valid design is not recomputed: the same numbers
    assert rel.blade_amplitude_m[0, 0, 0] == plain.blade_amplitude_m[0, 0, 0]
    d, dp = rel.to_dict(), plain.to_dict()
    assert set(dp) <= set(d) and set(dp["parabolas"][0]) <= set(d["parabolas"][0])
    assert d["release"] and d["n_released_designs"] == 1 and dp["n_released_designs"] == 0
    assert d["optimum"] == dp["optimum"]
    assert d["parabolas"][0]["released"] == [[False, True]]
    assert d["parabolas"][0]["open_fraction"][0][0] is None
    best = d["optimum_with_release"]
    a = rel.blade_amplitude_m[0, 0]
    assert best["blade_amplitude_m"] == a.min()
    assert best["beyond_lift_off"] == bool(a[1] < a[0])
    assert dp["optimum_with_release"] == {**dp["optimum"], "beyond_lift_off": False}


@pytest.mark.parametrize("kw, match", [
    (dict(release=1), "release must be True or False"),
    (dict(release="yes"), "release must be True or False"),
    (dict(release=True, restitution=1.5), r"restitution must be a number in \[0, 1\]"),
    (dict(release=True, restitution=-0.1), r"restitution must be a number in \[0, 1\]"),
    (dict(release=True, restitution=True), r"restitution must be a number in \[0, 1\]"),
    (dict(release=True, restitution=float("nan")), r"restitution must be a number in \[0, 1\]"),
])
def test_design_study_input(kw, match):
    with pytest.raises(ModelError, match=match):
        design_study(P8, **{**KW, **kw})


def test_released_system_survives_the_frequency_steps():
    """A released system given to resonance_amplitude stays released at every frequency
    (its parameters are rebuilt per frequency with its options)."""
    s = BladeDamperSystem(P8.with_(gamma_deg=65.0), release=True, restitution=0.3)
    r = resonance_amplitude(s, [47.0], resolution_hz=None)
    assert r["release"]
    r = resonance_amplitude(s, [47.0], resolution_hz=None, release=False)
    assert not r["release"]


def test_released_designs_run_in_the_workers():
    """workers=2 gives the serial results with release (the released recomputations share the
    pool with the lift-off bisections; progress counts them)."""
    serial = design_study(P8, release=True, **{**KW, "boundary_refinements": 1})
    ticks = []
    par = design_study(P8, release=True, workers=2, progress=lambda d, n: ticks.append((d, n)),
                       **{**KW, "boundary_refinements": 1})
    assert par.to_dict() == serial.to_dict()
    assert serial.to_dict()["n_released_designs"] == 1
    assert ticks[-1][0] == ticks[-1][1] == 4  # two grid designs, one bisection, one released


@pytest.mark.slow
def test_released_design_by_shooting():
    """The default steady states (shooting, here with a 60-period budget) of the 80-deg design
    beyond lift-off: the released 1 g damper leaves the wedge and rides on one platform (a
    contact open nearly all the time at resonance), so the blade amplitude is about three
    times the no-separation 65-deg design's (measured 26.3 mm at 51.95 Hz against 8.84 mm;
    the no-separation model gave 8.0 mm with a normal force of -44 N): the best design stays
    the one without lift-off. Shooting that cannot resolve an accumulation of impacts is a
    note, not an error (the windows measure the response). About 40 s of CPU."""
    d = design_study(P8, damper_masses_kg=[1e-3], gammas_deg=[65.0, 80.0],
                     frequency_hz=np.linspace(47.0, 56.0, 3), centrifugal_acceleration=1e5,
                     boundary_refinements=0, orbit_periods=60, release=True)
    assert d.released[0, 0].tolist() == [False, True]
    a = d.blade_amplitude_m[0, 0]
    assert np.all(np.isfinite(a)) and a[1] > 2 * a[0]
    assert d.released_min_normal_force_N[0, 0, 1] >= -1e-6
    assert d.open_fraction[0, 0, 1] > 0.5
    best = d.optimum_released
    assert not best["beyond_lift_off"] and best["gamma_deg"] == 65.0
    assert not any("released:" in e for e in d.errors)
