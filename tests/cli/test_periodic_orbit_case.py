"""examples/cases/den_hartog_orbit.toml through the command line: the ``periodic_orbit``
results contract (issue 14) and its bad-input errors.

The physics (amplitude vs den Hartog's closed form, multipliers vs the reversal accelerations)
is checked in tests/examples/check_den_hartog_orbit.py; here: the keys, their types, the
figure, and clear errors for cases shooting cannot take.
"""

from __future__ import annotations

import json
from pathlib import Path

CASE = Path(__file__).resolve().parents[2] / "examples" / "cases" / "den_hartog_orbit.toml"


def test_summary_has_the_periodic_orbit_contract(cli, tmp_path):
    code, out, err = cli("run", CASE, "--out", tmp_path / "out")
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    po = summary["periodic_orbit"]
    for key, kind in (("amplitude_m", list), ("period_multiple", int),
                      ("floquet_multipliers_abs", list), ("stable", bool),
                      ("converged", bool), ("residual", float)):
        assert isinstance(po[key], kind), key
    assert len(po["amplitude_m"]) == 1 and len(po["floquet_multipliers_abs"]) == 2
    assert po["residual"] < 1e-8
    assert "period-1 orbit" in out and (tmp_path / "out" / "periodic_orbit.png").is_file()


def test_given_period_multiple_is_used(cli, write_case, tmp_path):
    text = CASE.read_text().replace("frequency_hz = 4.0", "frequency_hz = 4.0\nperiod_multiple = 2")
    code, _, err = cli("run", write_case(text), "--out", tmp_path / "out")
    assert code == 0, err
    po = json.loads((tmp_path / "out" / "summary.json").read_text())["periodic_orbit"]
    assert po["period_multiple"] == 2 and po["converged"]


def test_jenkins_contact_is_rejected(assert_rejected):
    text = CASE.read_text().replace('type = "coulomb"', 'type = "jenkins"').replace(
        "mu_static = 1.0", "mu = 1.0")
    assert_rejected(text, ["periodic_orbit", "coulomb"])


def test_velocity_dependent_mu_is_rejected(assert_rejected):
    text = CASE.read_text().replace("mu_static = 1.0", "mu_static = 1.0\ndecay_s_per_m = 2.0")
    assert_rejected(text, ["decay_s_per_m"])


def test_force_needs_one_entry_per_dof(assert_rejected):
    text = CASE.read_text().replace("force_amplitude_N = [10.0]", "force_amplitude_N = [10.0, 0.0]")
    assert_rejected(text, ["force_amplitude_N", "one entry per DOF"])


def test_period_multiple_must_be_positive(assert_rejected):
    text = CASE.read_text().replace("frequency_hz = 4.0", "frequency_hz = 4.0\nperiod_multiple = 0")
    assert_rejected(text, ["period_multiple"])
