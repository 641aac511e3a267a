"""``[model] type = "tieboss_wheel"`` with ``[analysis.modal]``, ``[analysis.campbell_by_nd]``,
``[analysis.free_attenuation]`` and ``[analysis.reduction_comparison]`` (paper 003, issue 7):
bad input, defaults, the calibration of the penalty, and the results contract.

The physics of the full example case is checked in tests/examples/check_tieboss_wheel.py; here:
every invalid input gives exit code 2 and one line naming the key and what is allowed, the
schema's defaults are the library's, and a small run honours the summary contract.
"""

from __future__ import annotations

import json
from dataclasses import asdict

import pytest
from cli_cases import bad_params, contacts_refused, replace_once

from fricdamp.runner import REGISTRY, BuildContext

#: A small valid case: the default wheel, a coarse Campbell diagram, short decays (0.04 s, about
#: two periods, on a 4-mode Craig-Bampton wheel) and a short full-order comparison.
CASE = """\
name = "tieboss_small"

[model]
type = "tieboss_wheel"
contact_offset_m = 1.0e-5
mu_static = 0.4

[analysis.modal]
n_modes = 1

[analysis.campbell_by_nd]
n_speeds = 3
critical_pairs = [[1, 2], [3, 6]]

[analysis.free_attenuation]
nodal_diameters = [2, 6]
duration_s = 0.04
time_step_s = 4.0e-5
save_every = 2
n_modes = 4
compare_modal_forcing = false

[analysis.reduction_comparison]
nodal_diameter = 2
n_modes = 4
duration_s = 0.04
time_step_s = 4.0e-5
save_every = 2
"""


# (id, (old, new) substitution in CASE, substrings expected in the one-line message)
BAD = [
    ("negative_offset_with_calibration",
     ("contact_offset_m = 1.0e-5", "contact_offset_m = -1.0e-5\ncalibrate_normal_stiffness = "
                                   "true"),
     ["[model]", "contact_offset_m = -1e-05 m must be > 0 m",
      "calibrate_normal_stiffness = true"]),
    ("offset_too_large", ("contact_offset_m = 1.0e-5", "contact_offset_m = 0.01"),
     ["contact_offset_m = 0.01 m must lie in [-0.0044, 0.0044] m"]),
    ("mu_sliding_above_static", ("mu_static = 0.4", "mu_static = 0.2\nmu_sliding = 0.3"),
     ["mu_sliding = 0.3 must be <= mu_static = 0.2"]),
    ("negative_mu", ("mu_static = 0.4", "mu_static = -0.4"),
     ["[model] mu_static", "must be >= 0", "got -0.4"]),
    ("typo_model_key", ("mu_static = 0.4", "mu_statc = 0.4"),
     ["unknown key 'mu_statc' in [model]", "did you mean 'mu_static'"]),
    ("typo_analysis_key", ("nodal_diameters = [2, 6]", "nodal_diameter = [2, 6]"),
     ["unknown key 'nodal_diameter' in [analysis.free_attenuation]",
      "did you mean 'nodal_diameters'"]),
    ("unknown_analysis", ("[analysis.free_attenuation]", "[analysis.free_attenuaton]"),
     ["unknown analysis [analysis.free_attenuaton]", "did you mean 'free_attenuation'"]),
    ("nd_above_15", ("nodal_diameters = [2, 6]", "nodal_diameters = [2, 16]"),
     ["[analysis.free_attenuation] nodal_diameters = [2, 16]: ND 16 does not exist",
      "a wheel of 30 blades has nodal diameters 0 to 15"]),
    ("nd_negative", ("nodal_diameters = [2, 6]", "nodal_diameters = [-1, 6]"),
     ["[analysis.free_attenuation] nodal_diameters entry 1", "must be >= 0", "got -1"]),
    ("nd_twice", ("nodal_diameters = [2, 6]", "nodal_diameters = [6, 6]"),
     ["nodal_diameters lists an ND twice"]),
    ("nd_above_n_over_2", ("mu_static = 0.4", "mu_static = 0.4\nn_blades = 10"),
     ["ND 6 does not exist; a wheel of 10 blades has nodal diameters 0 to 5"]),
    ("critical_nd_above_15", ("critical_pairs = [[1, 2], [3, 6]]",
                              "critical_pairs = [[1, 2], [3, 16]]"),
     ["[analysis.campbell_by_nd] critical_pairs", "ND 16 does not exist"]),
    ("critical_order_zero", ("critical_pairs = [[1, 2], [3, 6]]",
                             "critical_pairs = [[0, 2]]"),
     ["critical_pairs: the order o of [0, nd] must be >= 1"]),
    ("reduction_nd_above_15", ("nodal_diameter = 2", "nodal_diameter = 20"),
     ["[analysis.reduction_comparison] nodal_diameter = [20]: ND 20 does not exist"]),
    ("both_stiffness_and_calibration",
     ("mu_static = 0.4", "mu_static = 0.4\nnormal_stiffness_N_per_m = 4.0e5\n"
                         "calibrate_normal_stiffness = true"),
     ["give either normal_stiffness_N_per_m or calibrate_normal_stiffness = true"]),
    ("negative_tieboss_mass", ("mu_static = 0.4", "mu_static = 0.4\ntieboss_mass_kg = -0.03"),
     ["[model] tieboss_mass_kg", "must be > 0 kg", "got -0.03"]),
    ("radii_order", ("mu_static = 0.4", "mu_static = 0.4\ntieboss_radius_m = 0.6"),
     ["hub_inner_radius_m < hub_radius_m < tieboss_radius_m < tip_radius_m",
      "0.1, 0.3, 0.6, 0.5 m"]),
    ("contact_plane_90", ("mu_static = 0.4", "mu_static = 0.4\ncontact_plane_angle_deg = 90.0"),
     ["[model] contact_plane_angle_deg", "must be < 90 deg"]),
    ("damping_band_order", ("mu_static = 0.4", "mu_static = 0.4\ndamping_band_hz = [60.0, 40.0]"),
     ["damping_band_hz = [60, 40] must be two frequencies f1 < f2"]),
    ("too_few_blades", ("mu_static = 0.4", "mu_static = 0.4\nn_blades = 2"),
     ["[model] n_blades", "must be >= 3"]),
    ("negative_time_step", ("time_step_s = 4.0e-5\nsave_every = 2\nn_modes = 4\ncompare",
                            "time_step_s = -4.0e-5\nsave_every = 2\nn_modes = 4\ncompare"),
     ["[analysis.free_attenuation] time_step_s", "must be > 0 s"]),
    ("too_few_steps", ("duration_s = 0.04\ntime_step_s = 4.0e-5\nsave_every = 2\nn_modes = 4\n"
                       "compare", "duration_s = 0.001\ntime_step_s = 4.0e-5\nsave_every = 2\n"
                                  "n_modes = 4\ncompare"),
     ["at least 100 time steps are needed"]),
    ("bad_forcing", ("compare_modal_forcing = false", 'forcing = "pressure"'),
     ["[analysis.free_attenuation] forcing", "'tieboss'", "'modal'"]),
    ("speed_range_inverted", ("n_speeds = 3", "n_speeds = 3\nspeed_min_rpm = 500.0"),
     ["speed_max_rpm (450 rpm) must be larger than speed_min_rpm (500 rpm)"]),
    ("string_for_number", ("mu_static = 0.4", 'mu_static = "0.4"'),
     ["mu_static", "must be a number", "a string"]),
    contacts_refused("[analysis.modal]", "tieboss_wheel"),
]


@pytest.mark.parametrize("old_new, expected", bad_params(BAD))
def test_invalid_input_exits_2_with_one_clear_line(assert_rejected, old_new, expected):
    assert_rejected(replace_once(CASE, *old_new), expected)


@pytest.mark.parametrize("name", ["modal", "campbell_by_nd", "free_attenuation",
                                  "reduction_comparison"])
def test_tieboss_analyses_need_the_tieboss_model(assert_rejected, base_case, name):
    """A tie-boss analysis on a chain model: exit 2 naming the model type it needs."""
    assert_rejected(base_case + f"\n[analysis.{name}]\n",
            [f"[analysis.{name}] needs [model] type = 'tieboss_wheel'"])


def test_generic_analyses_refused_on_the_tieboss_model(assert_rejected):
    """A MechanicalSystem analysis on the paper-003 model: exit 2 (not an internal error),
    saying which analyses apply; nothing is written."""
    text = ('[model]\ntype = "tieboss_wheel"\n\n[analysis.free_decay]\n'
            "initial_displacement_m = [" + ", ".join(["1.0e-3"] + ["0.0"] * 2879) + "]\n"
            "duration_s = 0.01\ntime_step_s = 1.0e-4\n")
    assert_rejected(text, ["not a MechanicalSystem", "[analysis.free_attenuation]"],
                    commands=("run",))


def test_schema_defaults_are_the_library_defaults():
    """The case's defaults build TiebossWheelParameters() exactly (same names), so the case
    and the library cannot drift apart."""
    from fricdamp.models.tieboss_wheel.model import TiebossWheelParameters

    entry = REGISTRY.models["tieboss_wheel"]
    spec = entry.schema()
    obj = entry.fn(spec, BuildContext(base_dir="."))
    assert asdict(obj.params) == asdict(TiebossWheelParameters())
    assert set(entry.schema.model_fields) == {f for f in asdict(TiebossWheelParameters())} | {
        "calibrate_normal_stiffness"}
    assert not obj.calibrated
    assert obj.n_dof == 2880 and len(obj.names) == 2880
    assert not hasattr(obj, "with_loads")  # AttributeError subclass: hasattr still works


def test_calibration_hits_the_requested_prestress():
    """calibrate_normal_stiffness: the wheel's static normal force at rest (003: 2.4 N from
    the offset) equals contact_preload_N (Brent's method to 1e-10 in log k_n: 1e-6), and for
    2.4 N it reproduces the default penalty (rounded to 4 digits: 1e-3)."""
    entry = REGISTRY.models["tieboss_wheel"]
    obj = entry.fn(entry.schema(calibrate_normal_stiffness=True, contact_preload_N=3.0),
                   BuildContext(base_dir="."))
    info = obj.describe()
    assert info["normal_stiffness_calibrated"]
    assert info["prestress_normal_force_N"] == pytest.approx(3.0, rel=1e-6)
    k3 = info["normal_stiffness_N_per_m"]
    obj = entry.fn(entry.schema(calibrate_normal_stiffness=True), BuildContext(base_dir="."))
    k24 = obj.params.normal_stiffness_N_per_m
    assert k24 == pytest.approx(entry.schema().normal_stiffness_N_per_m, rel=1e-3)
    assert k3 > k24  # more prestress from the same offset needs a stiffer penalty


def test_small_run_honours_the_contract(cli, write_case, tmp_path):
    """Issue 7: modal {nd 0..15, frequency_hz}, the top-level lists decay and
    critical_speeds_rpm and the table reduction, with their keys; figures and headlines."""
    out = tmp_path / "out"
    code, stdout, err = cli("run", write_case(CASE), "--out", out)
    assert code == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert s["model"]["type"] == "tieboss_wheel" and s["model"]["n_dof"] == 2880

    m = s["modal"]
    assert m["nd"] == list(range(16)) and len(m["frequency_hz"]) == 16
    assert all(isinstance(v, float) for v in m["frequency_hz"])

    decay = s["decay"]
    assert isinstance(decay, list) and [d["nd"] for d in decay] == [2, 6]
    for d in decay:
        assert {"damping_ratio", "initial_amplitude_m", "runtime_s"} <= set(d)
        assert d["initial_amplitude_m"] == pytest.approx(5e-4, rel=0.01)
        assert d["n_dof"] == 30 * (15 + 4)
    assert "damping_ratio_modal_forcing" not in decay[0]     # compare_modal_forcing = false
    assert set(s["free_attenuation"]["damping_ratio"]) == {"2ND", "6ND"}

    crit = s["critical_speeds_rpm"]
    assert isinstance(crit, list) and len(crit) == 2
    for c, (o, nd) in zip(crit, ((1, 2), (3, 6)), strict=True):
        assert (c["order"], c["nd"]) == (o, nd)
        assert c["rpm"] == pytest.approx(60.0 * c["frequency_hz"] / (8 * o), rel=1e-12)
    assert s["campbell_by_nd"]["rpm"] == pytest.approx([60.0, 255.0, 450.0])
    assert len(s["campbell_by_nd"]["frequency_hz"]) == 16

    red = s["reduction"]
    assert red["full_dof"] == 2880 and red["reduced_dof"] == 30 * 19
    assert red["damping_ratio_difference"] >= 0
    # the reduced decay of the comparison is the free attenuation's 2ND run (same wheel,
    # start and steps): identical numbers
    assert red["damping_ratio_reduced"] == pytest.approx(decay[0]["damping_ratio"], rel=1e-12)
    assert s["energy_balance_error"] == max(s["free_attenuation"]["energy_balance_error"],
                                            s["reduction_comparison"]["energy_balance_error"])

    assert set(s["files"]["figures"]) == {
        "table1.png", "campbell.png", "decay_2ND.png", "decay_6ND.png",
        "trajectories_2ND.png", "trajectories_6ND.png", "contact_states_2ND.png",
        "contact_states_6ND.png", "envelopes.png", "reduction.png"}
    assert "modal: ND 0-15" in stdout
    assert "campbell_by_nd: 3 speeds 60-450 rpm" in stdout
    assert "free_attenuation: 2ND: zeta" in stdout
    assert "reduction_comparison: 2ND: full 2880 DOFs" in stdout


def test_solver_settings_that_are_not_used_give_notes(cli, write_case, tmp_path):
    """[solver] alpha, tol, max_iter do not reach the wheel's transients: a note says so."""
    text = (CASE.split("[analysis.modal]")[0]
            + "[analysis.free_attenuation]\nnodal_diameters = [6]\nduration_s = 0.01\n"
              "time_step_s = 5.0e-5\nsave_every = 1\nn_modes = 2\ncompare_modal_forcing = "
              "false\n\n[solver]\nmethod = \"hht\"\nalpha = -0.1\ntol = 1.0e-8\n")
    out = tmp_path / "out"
    code, stdout, err = cli("run", write_case(text), "--out", out)
    assert code == 0, err
    s = json.loads((out / "summary.json").read_text())
    notes = " ".join(s["notes"])
    assert "alpha = -0.1 is not used" in notes and "tol and max_iter are not used" in notes
    assert "too few envelope peaks" in notes               # 0.01 s: half a period
    assert s["decay"][0]["method"] == "hht" and s["decay"][0]["damping_ratio"] is None


#: Issue 17, small: the rig-test analyses on a coarse setting (one order, a narrow sweep,
#: two load levels per ND, one scatter level, H = 1 for the full-wheel HB).
RIG_CASE = """\
name = "tieboss_rig_small"

[model]
type = "tieboss_wheel"

[analysis.excitation_orders]
orders = [1, 3]
pulse_width_deg = 10.0

[analysis.cyclic_forced_response]
pairs = [[3, 6]]
force_N = 2.0
frequency_range_hz = [48.0, 50.0]
harmonics = 3

[analysis.damping_amplitude]
nodal_diameters = [6]
orders = [3]
force_levels_N = [[2.0, 3.0]]
frequency_range_hz = [48.0, 50.0]
harmonics = 3

[analysis.mistuned_forced_response]
nodal_diameter = 6
scatter = [0.02]
frequency_range_hz = [48.6, 49.6]
harmonics = 1
samples = 30
"""


def test_rig_test_run_honours_the_contract(cli, write_case, tmp_path):
    """Issue 17: engine_order_map, forced_response, damping_vs_amplitude and mistuning at the
    top level with their keys; figures and headlines."""
    out = tmp_path / "out"
    code, stdout, err = cli("run", write_case(RIG_CASE), "--out", out)
    assert code == 0, err
    s = json.loads((out / "summary.json").read_text())
    emap = s["engine_order_map"]
    assert [e["order"] for e in emap] == [1, 3] and [e["nd"] for e in emap] == [2, 6]
    assert all({"order", "nd", "rule"} <= set(e) for e in emap)
    (fr,) = s["forced_response"]
    assert (fr["nd"], fr["order"]) == (6, 3)
    for key in ("rpm", "frequency_hz", "amplitude_m", "dissipated_energy_J"):
        assert len(fr[key]) == fr["n_points"] > 3, key
    assert fr["energy_balance_error"] < 1e-6 and 110 < fr["peak_rpm"] < 130
    (dva,) = s["damping_vs_amplitude"]
    assert dva["nd"] == 6 and len(dva["amplitude_m"]) == len(dva["damping_ratio"]) == 2
    assert dva["damping_ratio"][0] > dva["damping_ratio"][1]       # falls with amplitude
    assert "contact node" in dva["amplitude_definition"]
    mis = s["mistuning"]
    assert mis["scatter"] == [0.0, 0.02] and mis["amplification_factor"][0] == 1.0
    assert len(mis["amplification_factor_no_friction"]) == 2
    assert {"engine_orders.png", "forced_response.png", "damping_vs_amplitude.png"} <= set(
        s["files"]["figures"])
    assert "excitation_orders: o = 1 (n = 8): 2ND" in stdout
    assert "cyclic_forced_response: 6ND o = 3: peak" in stdout


@pytest.mark.parametrize("name", ["excitation_orders", "cyclic_forced_response",
                                  "damping_amplitude", "mistuned_forced_response"])
def test_rig_analyses_need_the_tieboss_model(assert_rejected, base_case, name):
    assert_rejected(base_case + f"\n[analysis.{name}]\n",
                    [f"[analysis.{name}] needs [model] type = 'tieboss_wheel'"])


@pytest.mark.parametrize("old_new, expected", [
    (("frequency_range_hz = [48.0, 50.0]\nharmonics = 3\n\n[analysis.damping",
      "frequency_range_hz = [50.0, 48.0]\nharmonics = 3\n\n[analysis.damping"),
     ["[analysis.cyclic_forced_response]", "low < high"]),
    (("pairs = [[3, 6]]", "pairs = [[3, 16]]"), ["ND 16 does not exist", "0 to 15"]),
    (("force_levels_N = [[2.0, 3.0]]", "force_levels_N = [[2.0], [3.0]]"),
     ["force_levels_N needs one list per ND"]),
    (("orders = [1, 3]\npulse", "orders = [1, 3]\npairs = [[0, 9]]\npulse"),
     ["pairs hold magnets 0..7"]),
])
def test_rig_bad_input_exits_2(assert_rejected, old_new, expected):
    assert_rejected(replace_once(RIG_CASE, *old_new), expected)
