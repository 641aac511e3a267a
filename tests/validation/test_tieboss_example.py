"""The summary.json contract of the tie-boss wheel case and the 003 example script.

Contract (issue): ``modal: {"nd": [0..15], "frequency_hz": [...]}``; ``decay: [{"nd": 2,
"damping_ratio", "initial_amplitude_m", "runtime_s"}, {"nd": 6, ...}]``;
``critical_speeds_rpm: [{"order", "frequency_hz", "rpm"}, ...]``; ``reduction: {"full_dof",
"reduced_dof", "damping_ratio_difference"}``. Numbers are checked against the paper where
the other tests of this group justify the tolerances (Table 1 within 1 %, Table 2 speeds
within 2 %, 6ND damped more than 2ND).
"""

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from fricdamp.models.tieboss_wheel.studies import run_tieboss_case

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "003_tieboss_wheel.py"


def test_case_contract():
    s = run_tieboss_case(duration_s=0.06, dt=2e-5, n_modes=4, compare_full=False)
    assert s["modal"]["nd"] == list(range(16)) and len(s["modal"]["frequency_hz"]) == 16
    assert s["modal"]["max_table1_error"] < 0.01
    assert [d["nd"] for d in s["decay"]] == [2, 6]
    for d in s["decay"]:
        assert {"damping_ratio", "initial_amplitude_m", "runtime_s"} <= set(d)
        assert d["initial_amplitude_m"] == pytest.approx(5e-4, rel=0.01)
    assert s["decay"][1]["damping_ratio"] > s["decay"][0]["damping_ratio"]
    for c in s["critical_speeds_rpm"]:
        assert {"order", "frequency_hz", "rpm"} <= set(c)
        assert c["rpm"] == pytest.approx(c["paper_rpm"], rel=0.02)
    r = s["reduction"]
    assert r["full_dof"] == 2880 and r["reduced_dof"] == 30 * (15 + 4)
    json.dumps(s)                                       # JSON-ready


@pytest.mark.slow
def test_example_makes_figures_and_summary(tmp_path):
    spec = importlib.util.spec_from_file_location("example_003", EXAMPLE)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    s = mod.main(tmp_path, compare_full=False, long_decay_s=0.15)
    for name in s["figures"]:
        assert (tmp_path / name).stat().st_size > 10_000
    assert len(s["figures"]) == 9
    z = {d["nd"]: d["damping_ratio"] for d in s["decay"]}
    assert z[6] > z[2] > 0.005
    saved = json.loads((tmp_path / "summary.json").read_text())
    np.testing.assert_allclose(saved["modal"]["frequency_hz"], s["modal"]["frequency_hz"])
