"""examples/cases/duffing_frf.toml through the command line: the stability keys of
``[analysis.frf]`` (issue 14) and their contract.

The physics (folds against the one-harmonic closed form, the unstable middle branch) is
checked in tests/examples/check_duffing_frf.py; here: the keys, their types, the figure, the
default (no stability: null), and that the new key is validated like the others.
"""

from __future__ import annotations

import json
from pathlib import Path

CASE = Path(__file__).resolve().parents[2] / "examples" / "cases" / "duffing_frf.toml"


def test_summary_has_stability_and_bifurcations(cli, tmp_path):
    code, out, err = cli("run", CASE, "--out", tmp_path / "out")
    assert code == 0, err
    frf = json.loads((tmp_path / "out" / "summary.json").read_text())["frf"]
    n = frf["n_points"]
    assert isinstance(frf["stable"], list) and len(frf["stable"]) == n
    assert all(isinstance(s, bool) for s in frf["stable"])
    assert 0 < frf["n_unstable_points"] == frf["stable"].count(False) < n
    assert len(frf["floquet_max_real_per_s"]) == n
    keys = {"type", "omega_rad_s", "frequency_hz", "amplitude_m", "load_scale", "after_point",
            "floquet_multiplier_abs", "floquet_multiplier_angle_rad", "located"}
    assert [b["type"] for b in frf["bifurcations"]] == ["fold", "fold"]
    for b in frf["bifurcations"]:
        assert set(b) == keys and isinstance(b["amplitude_m"], float)
    # the keys that existed before stay
    for key in ("omega_rad_s", "amplitude_m", "peak_frequency_hz", "energy_balance_error"):
        assert key in frf
    assert "fold at" in out and (tmp_path / "out" / "frf.png").is_file()


def test_stability_off_gives_null(cli, write_case, tmp_path):
    text = CASE.read_text().replace("stability = true", "stability = false")
    code, _, err = cli("run", write_case(text), "--out", tmp_path / "out")
    assert code == 0, err
    frf = json.loads((tmp_path / "out" / "summary.json").read_text())["frf"]
    assert frf["stable"] is None and frf["bifurcations"] is None
    assert "n_unstable_points" not in frf


def test_stability_must_be_a_boolean(assert_rejected):
    text = CASE.read_text().replace("stability = true", 'stability = "yes"')
    line = assert_rejected(text, ["[analysis.frf] stability"])
    assert "yes" in line


def test_cubic_spring_needs_k3(assert_rejected):
    text = CASE.read_text().replace("k3_N_per_m3 = 2.0e9", "k3 = 2.0e9")
    assert_rejected(text, ["[[contacts]]", "k3"])
