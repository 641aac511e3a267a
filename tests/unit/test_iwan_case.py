"""``[[contacts]] type = "iwan"`` in case files (case.py IwanContact, runner.py _build_iwan).

Validation against Segalman's closed form (Segalman 2005, J. Appl. Mech. 72, 752): the
energy of a symmetric cycle in micro-slip is ``E = 4 R A^(3+chi) / ((chi+2)(chi+3))``.

* ``[analysis.hysteresis]`` drives the law from the case file: its loop energies match the
  closed form within 0.6 % (the discretised law is within 0.5 % of the continuum from
  ``30 min_ratio phi_max`` to ``phi_max``, tests/unit/test_iwan.py; plus the trapezoidal loop
  area of 2000 samples);
* ``[analysis.forced_response]`` integrates a 1-DOF oscillator on the Iwan joint through
  the time solver: an Iwan (Masing) loop between two reversal points depends only on them,
  so the contact's loop energy over the last period is the closed form at the contact's
  amplitude, whatever the waveform (within 1 %: the discretisation's 0.5 % plus what is left
  of the transient after 25 periods; measured 0.02-0.17 %); and two force levels give the
  micro-slip exponent ``3 + chi`` to 0.02.
"""

import numpy as np
import pytest

from fricdamp.case import parse_case
from fricdamp.contact.iwan import Iwan
from fricdamp.errors import CaseError
from fricdamp.runner import REGISTRY, build_system, compute_case

CONTACT = {"type": "iwan", "name": "joint", "dofs": [1], "stiffness_N_per_m": 1.0e6,
           "slip_force_N": 10.0, "chi": -0.5, "beta": 0.2}


def case(analysis: dict, contact=None, **model):
    data = {"model": {"type": "chain", "masses_kg": [1.0], "springs_N_per_m": [1.0e5],
                      "dampers_Ns_per_m": [20.0], **model},
            "contacts": [dict(CONTACT, **(contact or {}))], "analysis": analysis}
    return parse_case(data, REGISTRY, default_name="iwan")


def closed_form(amplitude, k=1e6, fs=10.0, chi=-0.5, beta=0.2):
    """Segalman's micro-slip energy, computed here from the four parameters."""
    c = (chi + 1) / (chi + 2)
    phi_max = fs * (1 + beta) / (k * (beta + c))
    R = fs * (chi + 1) / (phi_max ** (chi + 2) * (beta + c))
    assert np.all(np.asarray(amplitude) <= phi_max)
    return 4 * R * np.asarray(amplitude) ** (chi + 3) / ((chi + 2) * (chi + 3))


def test_case_builds_the_iwan_law():
    system = build_system(case({"hysteresis": {"amplitudes_m": [1e-6]}},
                               contact={"n_elements": 50, "min_ratio": 1e-3}), REGISTRY)
    (el,) = system.contacts
    law = el.law
    assert isinstance(law, Iwan) and el.name == "joint"
    assert law.n_elements == 50 and law.min_ratio == 1e-3
    assert law.element_stiffness.sum() == pytest.approx(1e6, rel=1e-12)
    assert law.element_slip_force.sum() == pytest.approx(10.0, rel=1e-12)


def test_hysteresis_matches_segalman_closed_form():
    amps = [1e-7, 1e-6, 1e-5]  # phi_max = 2.25e-5 m
    out = compute_case(case({"hysteresis": {"amplitudes_m": amps, "samples_per_cycle": 2000}}))
    s = out.outputs["hysteresis"].summary
    entry = s["contacts"]["joint"]
    np.testing.assert_allclose(entry["loop_energy_J"], closed_form(amps), rtol=6e-3)
    np.testing.assert_allclose(entry["closed_form_J"], closed_form(amps), rtol=1e-12)
    assert s["max_closed_form_error"] < 6e-3


def test_forced_response_through_the_time_solver():
    energies, amps = [], []
    for force in (1.0, 3.0):
        out = compute_case(case({"forced_response": {"force_amplitude_N": [force],
                                                     "frequency_hz": 50.0, "periods": 25,
                                                     "steps_per_period": 100}}))
        s = out.outputs["forced_response"].summary
        c = s["contacts"]["joint"]
        a = c["relative_displacement_amplitude_m"]
        e = c["dissipated_energy_per_cycle_J"]
        a, e = float(np.ravel(a)[0]), float(np.ravel(e)[0])
        assert e == pytest.approx(float(closed_form(a)), rel=0.01), force
        assert s["cycle_energy_balance_error"] < 0.01
        energies.append(e)
        amps.append(a)
    slope = np.log(energies[1] / energies[0]) / np.log(amps[1] / amps[0])
    assert slope == pytest.approx(2.5, abs=0.02)  # 3 + chi


@pytest.mark.parametrize("key, value, word", [("chi", -1.0, "chi"), ("chi", 1.5, "chi"),
                                              ("beta", -0.1, "beta"),
                                              ("slip_force_N", 0.0, "slip_force_N"),
                                              ("n_elements", 1, "n_elements"),
                                              ("min_ratio", 1.0, "min_ratio"),
                                              ("stiffnes_N_per_m", 1.0, "stiffnes_N_per_m")])
def test_bad_iwan_keys_are_named(key, value, word):
    with pytest.raises(CaseError, match=word):
        case({"hysteresis": {"amplitudes_m": [1e-6]}}, contact={key: value})
