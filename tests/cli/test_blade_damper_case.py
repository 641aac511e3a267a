"""Paper 000 case files through the command line: bad input and a two-point design sweep."""

import json

import pytest
import xarray as xr

from fricdamp.cli.app import main

BASE = """
name = "bd"
[model]
type = "blade_damper"
{model}
[analysis.eigenfrequencies]
"""


@pytest.mark.parametrize("model, word", [
    ("gamma_deg = 95.0", "gamma_deg"),
    ("gamma_deg = 0.0", "gamma_deg"),
    ("damper_mass_kg = -1e-3", "damper_mass_kg"),
    ("mu_static = 0.2\nmu_sliding = 0.3", "mu_sliding"),
    ("p1_per_m = 10.0", "p1_per_m"),
    ("gama_deg = 50.0", "gama_deg"),
    ("masses_kg = [1.0, 1.0, 1.0]", "masses_kg"),
    ("centrifugal_force_N = 100.0\ncentrifugal_acceleration_m_per_s2 = 1e5", "centrifugal"),
])
def test_bad_model_exits_2_with_the_key(assert_rejected, model, word):
    assert_rejected(BASE.format(model=model), [word])


@pytest.mark.parametrize("keys, words", [
    ("release = true\nrestitution = 1.5", ["restitution", "<= 1"]),
    ("release = true\nrestitution = -0.1", ["restitution", ">= 0"]),
    ('release = "yes"', ["release", "true or false"]),
    ("restitution = 0.5", ["restitution", "only with release = true"]),
])
def test_bad_design_release_keys_exit_2(assert_rejected, keys, words):
    """``[analysis.damper_design]`` ``release`` (bool) and ``restitution`` (0..1, only with
    release; issue 14): one-line errors naming the key and its range."""
    assert_rejected(BASE.format(model="") + "[analysis.damper_design]\n" + keys + "\n",
                    ["damper_design", *words])


def test_contacts_refused(assert_rejected):
    assert_rejected(BASE.format(model="") + """
[[contacts]]
type = "jenkins"
dofs = [1]
stiffness_N_per_m = 1e4
slip_force_N = 1.0
""", ["contacts"])


def test_eigenfrequencies_of_the_default_rig(tmp_path):
    """Stuck eigenfrequencies of the documented default rig (3 modes, ascending) and the
    sliding linearisation (the blades' four modes close to them)."""
    p = tmp_path / "bd.toml"
    p.write_text(BASE.format(model=""))
    assert main(["run", str(p), "--out", str(tmp_path / "out")]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())["eigenfrequencies"]
    fs = s["stuck_eigenfrequencies_hz"]
    assert len(fs) == 3 and fs == sorted(fs) and 40 < fs[0] < 60


@pytest.mark.slow
def test_design_sweep_two_points(tmp_path):
    """`fricdamp sweep` over the damper mass (serial, 2 points): one value per point, and the
    resonant amplitude equals the single-design run of the same mass."""
    from pathlib import Path

    case = Path(__file__).resolve().parents[2] / "examples" / "cases" / "damper_sweep.toml"
    out = tmp_path / "sweep"
    code = main(["sweep", str(case), "--grid", "damper_mass_kg=1e-3,2e-3",
                 "--grid", "gamma_deg=50", "--serial", "--out", str(out)])
    assert code == 0
    ds = xr.open_dataset(out / "sweep.nc", engine="scipy")
    var = [v for v in ds.data_vars if v.endswith("blade_amplitude_m")][0]
    assert ds[var].shape == (2, 1)
    single = tmp_path / "single"
    assert main(["run", str(case), "--out", str(single)]) == 0
    a1 = json.loads((single / "summary.json").read_text())["blade_resonance"]["blade_amplitude_m"]
    assert float(ds[var].sel(damper_mass_kg=1e-3).values.ravel()[0]) == pytest.approx(a1,
                                                                                    rel=1e-9)


def test_time_response_without_a_periodic_orbit_is_unreliable(tmp_path):
    """1 g, 65 deg, F_e = 8 N at 50.915 Hz: no periodic orbit is stable there and the
    response beats (test_blade_damper_orbits.py). With a budget of 10 periods the orbit
    search must say it found no steady state: period_multiple 0,
    stable false, verdict unreliable (exit 3), never a transient called steady."""
    p = tmp_path / "bd.toml"
    p.write_text(BASE.format(model="gamma_deg = 65.0").replace(
        "[analysis.eigenfrequencies]", """[analysis.time_response]
periods = 3
excitation_amplitude_N = 8.0
excitation_frequency_hz = 50.915
max_orbit_periods = 10
"""))
    assert main(["run", str(p), "--out", str(tmp_path / "out"), "--no-progress"]) == 3
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    tr = s["time_response"]
    assert tr["period_multiple"] == 0 and tr["stable"] is False
    assert tr["orbit"]["periodic"] is False and tr["cpu_s_per_period"] > 0
    v = s["verdict"]["analyses"]["time_response"]
    assert v["verdict"] == "unreliable"
    assert any("no stable periodic orbit" in r for r in v["reasons"])
