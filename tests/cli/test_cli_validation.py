"""Invalid case files: exit code 2 and one line on stderr naming the key and what is allowed.

Each case below breaks one rule of docs/cases.md; the test checks the exit code, that stderr
is a single line without a traceback, and that the line names the offending key (and the
allowed range or the valid choices).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io
from cli_cases import bad_params, replace_once

# (id, (old, new) substitution in the base case, substrings expected in the message)
BAD = [
    ("typo_key", ("masses_kg", "masss_kg"),
     ["unknown key 'masss_kg'", "[model]", "did you mean 'masses_kg'"]),
    ("typo_top_level", ('name = "one_dof"', 'nmae = "one_dof"'),
     ["unknown key 'nmae'", "did you mean 'name'"]),
    ("string_for_number", ("masses_kg = [1.0]", 'masses_kg = ["1.0"]'),
     ["masses_kg entry 1", "must be a number (> 0 kg)", "'1.0'", "a string"]),
    ("negative_mass", ("masses_kg = [1.0]", "masses_kg = [-1.0]"),
     ["[model] masses_kg entry 1", "must be > 0 kg", "got -1"]),
    ("negative_mu", ("slip_force_N = 1.0", "mu = -0.1\nnormal_load_N = 10.0"),
     ["[[contacts]] #1 (jenkins) mu", "must be >= 0", "got -0.1"]),
    ("zero_contact_stiffness", ("stiffness_N_per_m = 1.0e4", "stiffness_N_per_m = 0.0"),
     ["stiffness_N_per_m", "must be > 0 N/m", "got 0"]),
    ("negative_spring", ("springs_N_per_m = [1.0e4]", "springs_N_per_m = [-1.0e4]"),
     ["springs_N_per_m entry 1", "must be > 0 N/m"]),
    ("nan_scalar", ("duration_s = 0.5", "duration_s = nan"),
     ["[analysis.free_decay] duration_s", "finite"]),
    ("nan_in_list", ("initial_displacement_m = [1.0e-3]", "initial_displacement_m = [nan]"),
     ["initial_displacement_m entry 1", "finite"]),
    ("inf_spring", ("springs_N_per_m = [1.0e4]", "springs_N_per_m = [inf]"),
     ["springs_N_per_m entry 1", "finite"]),
    ("float_for_integer", ("time_step_s = 5.0e-4", "time_step_s = 5.0e-4\nsave_every = 2.5"),
     ["save_every", "must be an integer", ">= 1"]),
    ("dof_out_of_range", ("dofs = [1]", "dofs = [3]"),
     ["dofs = [3]", "DOF 3 does not exist", "1 DOF", "numbered 1 to 1"]),
    ("dof_zero", ("dofs = [1]", "dofs = [0]"),
     ["dofs entry 1", "must be >= 1"]),
    ("vector_length",
     ("initial_displacement_m = [1.0e-3]", "initial_displacement_m = [1.0e-3, 0.0]"),
     ["[analysis.free_decay]", "initial_displacement_m", "one entry per DOF (1)"]),
    ("springs_count", ("springs_N_per_m = [1.0e4]", "springs_N_per_m = [1.0e4, 2.0e4]"),
     ["springs_N_per_m must have 1 entry", "ground = 'first'"]),
    ("unknown_analysis", ("[analysis.free_decay]", "[analysis.free_decy]"),
     ["unknown analysis [analysis.free_decy]", "did you mean 'free_decay'"]),
    ("unknown_model_type", ('type = "chain"', 'type = "chian"'),
     ["[model] type = 'chian'", "did you mean 'chain'", "'matrices'"]),
    ("unknown_contact_type", ('type = "jenkins"', 'type = "jenkin"'),
     ["[[contacts]] #1", "did you mean 'jenkins'"]),
    ("missing_key", ("duration_s = 0.5\n", ""),
     ["[analysis.free_decay]", "missing the required key 'duration_s'", "> 0 s"]),
    ("slip_twice", ("slip_force_N = 1.0", "slip_force_N = 1.0\nmu = 0.3\nnormal_load_N = 3.0"),
     ["either slip_force_N or mu"]),
    ("between_same_dof", ("dofs = [1]", "between = [1, 1]"),
     ["between must name two different DOFs"]),
    ("dofs_and_between", ("dofs = [1]", "dofs = [1]\nbetween = [1, 2]"),
     ["exactly one of dofs", "between"]),
    ("step_longer_than_run", ("time_step_s = 5.0e-4", "time_step_s = 1.0"),
     ["time_step_s (1 s) must be smaller than duration_s (0.5 s)"]),
    ("starts_at_rest", ("initial_displacement_m = [1.0e-3]", "initial_displacement_m = [0.0]"),
     ["non-zero entry", "nothing to decay"]),
    ("solver_method", ("time_step_s = 5.0e-4", 'time_step_s = 5.0e-4\n\n[solver]\nmethod = "rk4"'),
     ["[solver] method", "'newmark'", "'hht'", "'rk4'"]),
    ("hht_alpha_range", ("time_step_s = 5.0e-4", "time_step_s = 5.0e-4\n\n[solver]\nalpha = 0.2"),
     ["[solver] alpha must be <= 0"]),
    ("contact_name_with_space", ('name = "slider"', 'name = "my slider"'),
     ["[[contacts]] #1 (jenkins) name must contain only letters"]),
    ("bad_case_name", ('name = "one_dof"', 'name = "../escape"'),
     ["name must contain only letters"]),
    ("table_expected", ('[model]\ntype = "chain"', 'solver = 3\n\n[model]\ntype = "chain"'),
     ["solver must be a table, got 3 (an integer)"]),
]


@pytest.mark.parametrize("sub, expected", bad_params(BAD))
def test_invalid_case_exit_2_one_clear_line(assert_rejected, base_case, sub, expected):
    # `run` rejects the same case the same way, before writing anything
    assert_rejected(replace_once(base_case, *sub), expected, commands=("check", "run"))


def test_duplicate_contact_names(assert_rejected, base_case):
    extra = ('\n[[contacts]]\ntype = "jenkins"\nname = "slider"\ndofs = [1]\n'
             "stiffness_N_per_m = 1.0\nslip_force_N = 1.0\n")
    text = replace_once(base_case, "[analysis.free_decay]", extra + "\n[analysis.free_decay]")
    assert_rejected(text, ["'slider' is used twice"])


def test_hysteresis_unknown_contact(assert_rejected, base_case):
    text = base_case + '\n[analysis.hysteresis]\namplitudes_m = [1e-3]\ncontacts = ["slidr"]\n'
    assert_rejected(text, ["[analysis.hysteresis] contacts: there is no contact named 'slidr'"])


def test_invalid_toml_and_missing_file(cli, write_case, tmp_path):
    code, _, err = cli("check", write_case("[model\ntype = 1"))
    assert code == 2 and "is not valid TOML" in err and "line 1" in err
    code, _, err = cli("check", tmp_path / "nope.toml")
    assert code == 2 and "does not exist" in err


def test_missing_model_table(assert_rejected):
    assert_rejected("[analysis.free_decay]\nduration_s = 1.0\n", ["no [model] table"])


MATRICES_CASE = """\
[model]
type = "matrices"
mass = "M.mtx"
stiffness = "K.mtx"
rayleigh_beta_s = 1e-4

[[contacts]]
type = "jenkins"
between = [1, 2]
stiffness_N_per_m = 1.0e3
slip_force_N = 1.0

[analysis.free_decay]
initial_displacement_m = [1.0e-3, 0.0]
duration_s = 0.1
time_step_s = 1.0e-3
"""


@pytest.mark.parametrize("M, words", [
    (np.diag([1.0, 2.0]), None),
    (np.array([[1.0, 1.0], [1.0, 1.0]]), "positive definite"),       # singular
    (np.array([[1.0, 0.5], [0.0, 1.0]]), "symmetric"),               # non-symmetric
    (np.array([[1.0, 0.0], [0.0, -1.0]]), "positive definite"),      # negative mass
    (np.array([[1.0, 0.0], [0.0, np.nan]]), "finite"),               # NaN in a file
])
def test_matrix_market_model(cli, write_case, tmp_path, M, words):
    scipy.io.mmwrite(str(tmp_path / "M.mtx"), M)
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), np.array([[2e4, -1e4], [-1e4, 1e4]]))
    code, out, err = cli("check", write_case(MATRICES_CASE))
    if words is None:
        assert code == 0, err
        assert "matrices model with 2 DOFs" in out
    else:
        assert code == 2
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1
        assert "[model]" in err and words in err, err


def test_missing_matrix_file_named(cli, write_case, tmp_path):
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), np.eye(2))
    code, _, err = cli("check", write_case(MATRICES_CASE))
    assert code == 2 and "mass = 'M.mtx'" in err and "does not exist" in err


def test_valid_case_checks_ok(cli, write_case, base_case):
    code, out, err = cli("check", write_case(base_case))
    assert code == 0, err
    assert out.startswith("ok:") and "1 DOF" in out and "free_decay" in out
