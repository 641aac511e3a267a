"""``[model] type = "blade_pair"`` with ``[analysis.campbell]`` and
``[analysis.steady_state_sweep]`` (paper 001, issue 5): bad input, defaults, the results
contract, and the runner's top-level summary keys it relies on.

The physics of the full example case is checked in tests/examples/check_blade_pair.py; here:
every invalid input gives exit code 2 and one line naming the key and what is allowed, the
schema's defaults are the library's, and a small run honours the summary contract.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from cli_cases import bad_params, contacts_refused, replace_once

from fricdamp.runner import REGISTRY, AnalysisOutput, Registry, run_case

#: A small valid case: the default model, a coarse Campbell diagram and one short sweep.
CASE = """\
name = "blade_pair_small"

[model]
type = "blade_pair"
shroud_mass_kg = 0.07
delta_a_deg = 45.0

[analysis.campbell]
speed_min_rpm = 0.0
speed_max_rpm = 600.0
n_speeds = 4
n_modes = 4

[analysis.steady_state_sweep]
orders = [30]
friction_coefficients = [0.05, 0.3]
speed_min_rpm = 300.0
speed_max_rpm = 450.0
n_speeds = 7
orbit_speeds_rpm = [390.0]
"""


# (id, (old, new) substitution in CASE, substrings expected in the one-line message)
BAD = [
    ("negative_shroud_mass", ("shroud_mass_kg = 0.07", "shroud_mass_kg = -0.07"),
     ["[model] shroud_mass_kg", "must be > 0 kg", "got -0.07"]),
    ("negative_damper_mass", ("shroud_mass_kg = 0.07", "damper_mass_kg = -0.015"),
     ["[model] damper_mass_kg", "must be > 0 kg", "got -0.015"]),
    ("negative_stick_stiffness", ("shroud_mass_kg = 0.07", "tangential_stiffness_N_per_m = -1.0"),
     ["[model] tangential_stiffness_N_per_m", "must be > 0", "got -1"]),
    ("hb_samples_below_nyquist",
     ("n_speeds = 7", "n_speeds = 7\nhb_harmonics = 9\nhb_samples = 16"),
     ["hb_samples = 16", ">= 2 hb_harmonics + 1 = 19"]),
    ("angle_above_90", ("delta_a_deg = 45.0", "delta_a_deg = 95.0"),
     ["[model] delta_a_deg", "must be < 90 deg", "got 95"]),
    ("angle_90", ("delta_a_deg = 45.0", "delta_b_deg = 90.0"),
     ["[model] delta_b_deg", "must be < 90 deg", "got 90"]),
    ("angle_zero", ("delta_a_deg = 45.0", "delta_a_deg = 0.0"),
     ["[model] delta_a_deg", "must be > 0 deg", "got 0"]),
    ("angle_negative", ("delta_a_deg = 45.0", "delta_b_deg = -30.0"),
     ["[model] delta_b_deg", "must be > 0 deg", "got -30"]),
    ("stagger_above_90", ("delta_a_deg = 45.0", "stagger_deg = 120.0"),
     ["[model] stagger_deg", "must be <= 90 deg"]),
    ("typo_model_key", ("delta_a_deg = 45.0", "delta_a = 45.0"),
     ["unknown key 'delta_a' in [model]", "did you mean 'delta_a_deg'"]),
    ("typo_analysis_key", ("n_modes = 4", "n_mode = 4"),
     ["unknown key 'n_mode' in [analysis.campbell]", "did you mean 'n_modes'"]),
    ("unknown_analysis", ("[analysis.steady_state_sweep]", "[analysis.steady_state]"),
     ["unknown analysis [analysis.steady_state]", "did you mean 'steady_state_sweep'"]),
    ("string_for_number", ("shroud_mass_kg = 0.07", 'shroud_mass_kg = "0.07"'),
     ["shroud_mass_kg", "must be a number", "a string"]),
    ("negative_stiffness_scalar", ("shroud_mass_kg = 0.07",
                                   "contact_stiffness_N_per_m = -2.0e8"),
     ["[model] contact_stiffness_N_per_m", "must be > 0 N/m", "got -2e+08"]),
    ("negative_stiffness_pair", ("shroud_mass_kg = 0.07",
                                 "contact_stiffness_N_per_m = [2.0e8, -1.0]"),
     ["contact_stiffness_N_per_m", "contact B must be > 0 N/m", "got -1"]),
    ("pair_too_long", ("shroud_mass_kg = 0.07", "contact_width_m = [0.008, 0.008, 0.008]"),
     ["contact_width_m", "at most 2 entries"]),
    ("negative_friction", ("shroud_mass_kg = 0.07", "friction_coefficient = -0.1"),
     ["[model] friction_coefficient", "must be >= 0", "got -0.1"]),
    ("contact_points_sides", ("shroud_mass_kg = 0.07",
                              "contact_points_m = [[0.003, 0.006], [0.003, -0.006]]"),
     ["contact_points_m needs z_A < 0 < z_B"]),
    ("contact_points_beyond_pitch", ("shroud_mass_kg = 0.07",
                                     "contact_points_m = [[0.003, -0.05], [0.003, 0.006]]"),
     ["contact_points_m: |z_A| = 0.05 m must be smaller than the half pitch"]),
    ("damper_inside_hub", ("shroud_mass_kg = 0.07", "damper_radius_m = 0.3"),
     ["damper_radius_m = 0.3 m must lie between hub_radius_m"]),
    ("inertia_length", ("shroud_mass_kg = 0.07", "shroud_inertia_kg_m2 = [1.0e-5, 1.0e-5]"),
     ["shroud_inertia_kg_m2", "at least 3 entries"]),
    ("table_lengths", ("shroud_mass_kg = 0.07", "table_orders = [15, 20]"),
     ["table_tangential_force_N and table_axial_force_N must have one entry per "
      "table_orders entry (2)"]),
    ("bad_rule", ("shroud_mass_kg = 0.07", 'damping_rule = "viscous"'),
     ["damping_rule", "'coulomb'", "'paper'"]),
    ("too_few_blades", ("shroud_mass_kg = 0.07", "n_blades = 2"),
     ["[model] n_blades", "must be >= 3"]),
    ("speed_range_inverted", ("speed_min_rpm = 0.0", "speed_min_rpm = 700.0"),
     ["[analysis.campbell]", "speed_max_rpm (600 rpm) must be larger than speed_min_rpm "
      "(700 rpm)"]),
    ("sweep_from_zero", ("speed_min_rpm = 300.0", "speed_min_rpm = 0.0"),
     ["[analysis.steady_state_sweep] speed_min_rpm", "must be > 0"]),
    ("too_many_modes", ("n_modes = 4", "n_modes = 79"),
     ["[analysis.campbell] n_modes = 79: the model has 78 DOFs"]),
    ("repeated_order", ("orders = [30]", "orders = [30, 30]"),
     ["orders lists an order twice"]),
    ("campbell_needs_one_f", ("shroud_mass_kg = 0.07", "friction_coefficient = [0.1, 0.2]"),
     ["[analysis.campbell] friction_coefficient: the model's is a pair [0.1, 0.2]"]),
    contacts_refused("[analysis.campbell]", "blade_pair"),
]


@pytest.mark.parametrize("old_new, expected", bad_params(BAD))
def test_invalid_input_exits_2_with_one_clear_line(assert_rejected, old_new, expected):
    assert_rejected(replace_once(CASE, *old_new), expected)


def test_blade_pair_analyses_need_the_blade_pair_model(assert_rejected, base_case):
    """[analysis.campbell] on a chain model: exit 2 naming the model type it needs."""
    assert_rejected(base_case + "\n[analysis.campbell]\nn_speeds = 3\n",
            ["[analysis.campbell] needs [model] type = 'blade_pair'"])


def test_generic_analyses_refused_on_the_blade_pair_model(assert_rejected):
    """A MechanicalSystem analysis on the paper-001 model: exit 2 (not an internal error),
    saying which analyses apply; nothing is written."""
    text = ('[model]\ntype = "blade_pair"\n\n[analysis.forced_response]\n'
            "force_amplitude_N = [" + ", ".join(["1.0"] + ["0.0"] * 77) + "]\n"
            "frequency_hz = 100.0\nperiods = 2\nsteps_per_period = 16\n")
    assert_rejected(text, ["not a MechanicalSystem", "[analysis.campbell]"], commands=("run",))


def test_schema_defaults_are_the_library_defaults():
    """The case's defaults build BladePairParameters() exactly (angles converted from degrees
    to within one rounding), so the case and the library cannot drift apart."""
    from dataclasses import asdict

    from fricdamp.models.blade_pair.model import BladePairParameters
    from fricdamp.runner import BuildContext

    entry = REGISTRY.models["blade_pair"]
    obj = entry.fn(entry.schema(), BuildContext(base_dir="."))
    mine, ref = asdict(obj.params), asdict(BladePairParameters())
    assert mine.keys() == ref.keys()
    for key in ref:
        if key in ("stagger", "delta_a", "delta_b"):
            assert mine[key] == pytest.approx(ref[key], rel=1e-15), key
        else:
            assert mine[key] == ref[key], key
    assert obj.n_dof == 78 and len(obj.names) == 78
    assert not hasattr(obj, "with_loads")  # AttributeError subclass: hasattr still works


def test_angles_and_pairs_reach_the_model():
    """Degrees become radians (the contact-plane angles of the built model), one value is
    shared by both contacts and a pair is kept per contact."""
    from fricdamp.runner import BuildContext

    entry = REGISTRY.models["blade_pair"]
    spec = entry.schema(delta_a_deg=50.0, delta_b_deg=20.0, stagger_deg=10.0,
                        contact_stiffness_N_per_m=3.0e8, friction_coefficient=[0.1, 0.2])
    obj = entry.fn(spec, BuildContext(base_dir="."))
    ang = obj.model.contact_angles
    assert ang["delta_a"] == pytest.approx(math.radians(50.0), rel=1e-15)
    assert ang["delta_b"] == pytest.approx(math.radians(20.0), rel=1e-15)
    assert obj.params.stagger == pytest.approx(math.radians(10.0), rel=1e-15)
    assert obj.params.contact_stiffness == (3.0e8, 3.0e8)
    assert obj.params.friction_coefficient == (0.1, 0.2)
    assert obj.friction_coefficient() == (0.1, 0.2)


def test_small_run_honours_the_contract(cli, write_case, tmp_path):
    """Issue 5: top-level n_dof = 78, campbell {rpm, frequency_hz per mode, excitation_orders}
    and the top-level steady_state list with its keys; the figures and the headlines."""
    out = tmp_path / "out"
    code, stdout, err = cli("run", write_case(CASE), "--out", out)
    s = json.loads((out / "summary.json").read_text())
    # exit 3 exactly when the sweep is unreliable (eqlin off HB at a peak, issue 16)
    sweep_verdict = s["verdict"]["analyses"]["steady_state_sweep"]["verdict"]
    assert code == (3 if sweep_verdict == "unreliable" else 0), err
    assert s["n_dof"] == 78 and s["model"]["n_dof"] == 78 and s["model"]["type"] == "blade_pair"

    c = s["campbell"]
    assert c["rpm"] == pytest.approx([0.0, 200.0, 400.0, 600.0])
    assert c["excitation_orders"] == [15, 20, 30]
    assert len(c["frequency_hz"]) == 4 and all(len(row) == 4 for row in c["frequency_hz"])
    assert all(isinstance(v, float) for row in c["frequency_hz"] for v in row)

    ss = s["steady_state"]
    assert isinstance(ss, list) and len(ss) == 2
    for e, f in zip(ss, (0.05, 0.3), strict=True):
        assert e["k"] == 30 and e["friction_coefficient"] == f
        assert e["rpm"] == pytest.approx(np.linspace(300.0, 450.0, 7))
        for key in ("semi_axes_A_m", "semi_axes_B_m"):
            assert len(e[key]) == 7 and all(len(ab) == 2 for ab in e[key])
        assert len(e["dissipated_energy_J"]) == 7
        assert 0 <= e["energy_balance_error"] < 1e-6
        # issue 16: HB beside eqlin, ratios, bands; stuck points dissipate exactly 0
        hb = e["hb"]
        assert hb["rpm"] == e["rpm"]
        assert len(hb["tip_amplitude_m"]) == len(hb["dissipated_energy_J"]) == 7
        assert len(e["eqlin_over_hb_energy"]) == 7
        assert all(len(b) == 2 and b[0] <= b[1] for b in e["disagreement_band_rpm"])
        both = (np.array(e["stuck_A"]) & np.array(e["stuck_B"])
                & np.array(e["rotation_stuck_A"]) & np.array(e["rotation_stuck_B"]))
        assert all(w == 0.0 for w, b in zip(e["dissipated_energy_J"], both, strict=True) if b)
        assert all(a == [0.0, 0.0] for a, st in zip(e["semi_axes_A_m"], e["stuck_A"],
                                                    strict=True) if st)
    assert ss[0]["hb"]["success"] == [True] * 7
    # gross slip at 390 rpm (k = 30, f = 0.05): HB and eqlin within 10 %
    i = ss[0]["rpm"].index(400.0)
    assert abs(ss[0]["eqlin_over_hb_energy"][i] - 1) < 0.1
    sec = s["steady_state_sweep"]
    assert sec["energy_balance_error"] == max(e["energy_balance_error"] for e in ss)
    assert s["energy_balance_error"] == sec["energy_balance_error"]
    assert set(sec["peaks"]) == {"k30_f0.05", "k30_f0.3"}
    assert set(s["files"]["figures"]) == {
        "campbell.png", "campbell_damping.png", "semi_axes.png", "inclination.png",
        "dissipated_energy.png", "tip_amplitude.png", "orbits_k30.png"}
    assert "campbell: 4 speeds 0-600 rpm" in stdout
    assert "steady_state_sweep: 1 orders x 2 friction coefficients x 7 speeds" in stdout


# ------------------------------------------------------------------- runner: top-level keys
def _registry(*outputs):
    """A registry with the chain model and one analysis per AnalysisOutput (a1, a2, ...)."""
    from fricdamp.case import Section

    class Empty(Section):
        pass

    reg = Registry()
    reg.models["chain"] = REGISTRY.models["chain"]
    for i, out in enumerate(outputs, start=1):
        reg.register_analysis(f"a{i}", Empty, lambda system, spec, ctx, out=out: out)
    return reg


def _case(reg, n):
    from fricdamp.case import parse_case

    data = {"model": {"type": "chain", "masses_kg": [1.0], "springs_N_per_m": [1.0]},
            "analysis": {f"a{i}": {} for i in range(1, n + 1)}}
    return parse_case(data, reg)


def test_top_level_keys_are_merged_and_equal_values_may_repeat(tmp_path):
    """AnalysisOutput.top_level lands at the top of summary.json; two analyses may give the
    same key with the same value (n_dof); numpy values are converted."""
    reg = _registry(AnalysisOutput({"x": 1}, top_level={"n_dof": np.int64(3),
                                                         "items": [{"a": 1}]}),
                    AnalysisOutput({"y": 2}, top_level={"n_dof": 3}))
    res = run_case(_case(reg, 2), tmp_path / "out", registry=reg)
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["n_dof"] == 3 and s["items"] == [{"a": 1}]
    assert s["a1"]["x"] == 1 and s["a2"]["y"] == 2
    assert res.summary["n_dof"] == 3


@pytest.mark.parametrize("top, other, match", [
    ({"model": 1}, None, "'model' is reserved"),
    ({"files": []}, None, "'files' is reserved"),
    ({"a2": 1}, {}, "'a2' is reserved"),
    ({"n_dof": 3}, {"n_dof": 4}, "set by another analysis to a different value"),
])
def test_top_level_keys_may_not_clash(tmp_path, top, other, match):
    """A reserved key, another analysis's section or a different value: ValueError before
    anything is written."""
    outs = [AnalysisOutput({}, top_level=top)]
    if other is not None:
        outs.append(AnalysisOutput({}, top_level=other))
    reg = _registry(*outs)
    with pytest.raises(ValueError, match=match):
        run_case(_case(reg, len(outs)), tmp_path / "out", registry=reg)
    assert not (tmp_path / "out").exists()


def test_stick_stiffness_reaches_the_model():
    """tangential_stiffness_N_per_m: the equivalent-damping law becomes the Jenkins one."""
    from fricdamp.models.blade_pair.case import BladePairSpec
    from fricdamp.models.blade_pair.model import JenkinsEllipseDamping
    from fricdamp.runner import BuildContext

    entry = REGISTRY.models["blade_pair"]
    spec = BladePairSpec(tangential_stiffness_N_per_m=1.0e8)
    obj = entry.fn(spec, BuildContext(base_dir="."))
    assert obj.params.tangential_stiffness == 1.0e8
    assert isinstance(obj.model.friction_damping([100.0]), JenkinsEllipseDamping)
