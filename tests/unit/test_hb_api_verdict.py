"""Harmonic-balance results judge their own harmonic truncation through the Python API.

Issue 15: "the HB energy balance restates the residual (1e-13 even with one harmonic):
nothing tells the user that H is too small". ``SteadyState.verdict`` and
``FrequencyResponse.verdict`` now solve the point (the largest response of a curve) again
with more harmonics and twice the AFT samples (:func:`fricdamp.verdict.harmonic_truncation`)
and are ``unreliable`` above the documented limits (2 % and 1 %). Reference: the README's
2-DOF chain with a Jenkins damper at its stick-slip resonance, where one harmonic misses the
amplitude by 15 % (measured against H = 3 re-solves) and seven harmonics are within 0.2 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.solvers import frequency_response, harmonic_balance
from fricdamp.structure import ContactElement, HarmonicLoad, chain


@pytest.fixture(scope="module")
def system():
    s = chain([1.0, 0.5], [1e3, 5e2], dampers=[0.5, 0.2],
              contacts=[ContactElement(Jenkins(800.0, 2.0), [[0.0, 1.0]], "damper")])
    return s.with_loads(HarmonicLoad([0.0, 3.0], 20.0))


@pytest.fixture(scope="module")
def frf7(system):
    return frequency_response(system, 20.0, 60.0, harmonics=7)


def test_one_harmonic_at_the_resonance_is_flagged_h_too_small(system, frf7):
    i = int(np.argmax(frf7.amplitude.max(axis=1)))
    one = harmonic_balance(system, float(frf7.omega[i]), harmonics=1)
    assert one.success and one.energy_balance_error < 1e-6   # the balance cannot see it
    v = one.verdict
    assert v.status == "unreliable"
    assert v.estimates["harmonic_truncation"] > 0.02
    assert any("H too small" in r for r in v.reasons)
    seven = harmonic_balance(system, float(frf7.omega[i]), harmonics=7)
    assert seven.verdict.status == "ok"
    assert seven.verdict.estimates["harmonic_truncation"] < 0.02


def test_frequency_response_judges_the_truncation_at_its_peak(frf7):
    v = frf7.verdict
    assert v.status == "ok"
    assert 0 < v.estimates["harmonic_truncation"] < 0.02
    assert v.estimates["aft_sampling_error"] < 0.01
    assert frf7.verdict is v                      # judged once, then kept
    # a point of the curve keeps the system and judges itself the same way
    i = int(np.argmax(frf7.amplitude.max(axis=1)))
    assert frf7.steady_state(i).verdict.estimates["harmonic_truncation"] == pytest.approx(
        v.estimates["harmonic_truncation"], rel=1e-6)
