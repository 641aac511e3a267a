"""A free decay whose record carries two modes (10 Hz and 13.7 Hz, equally excited) is
judged unreliable through the decay identification's own verdict (issue 18): exit 3, the
reason names the second mode; the single-mode decay of the same chain stays ok."""

from __future__ import annotations

import json

import numpy as np
import pytest

K = (2 * np.pi * 10.0) ** 2                                  # in-phase mode 10 Hz
KC = 0.5 * ((2 * np.pi * 13.7) ** 2 - K)                     # out-of-phase mode 13.7 Hz

CASE = f"""\
name = "two_modes"
[model]
type = "chain"
masses_kg = [1.0, 1.0]
springs_N_per_m = [{K!r}, {KC!r}, {K!r}]
dampers_Ns_per_m = [0.5, 0.0, 0.5]
ground = "both"
[analysis.free_decay]
initial_displacement_m = {{x0}}
response_dof = 1
duration_s = 2.0
time_step_s = 5.0e-4
"""


@pytest.mark.parametrize("x0, expected", [("[1.0e-3, 0.0]", "unreliable"),
                                          ("[1.0e-3, 1.0e-3]", "ok")])
def test_two_mode_free_decay_is_unreliable(cli, write_case, tmp_path, x0, expected):
    out = tmp_path / "out"
    code, _, err = cli("run", write_case(CASE.replace("{x0}", x0)), "--out", out,
                       "--no-progress")
    s = json.loads((out / "summary.json").read_text())
    fd = s["verdict"]["analyses"]["free_decay"]
    assert fd["verdict"] == expected, fd
    if expected == "unreliable":
        assert code == 3, err
        assert any("two modes" in r for r in fd["reasons"]), fd["reasons"]
        assert s["free_decay"]["second_mode_ratio"] > 0.5
    else:
        assert code == 0, err
        assert s["free_decay"]["second_mode_ratio"] < 0.02
