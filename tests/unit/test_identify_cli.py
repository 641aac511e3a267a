"""``fricdamp identify`` (fricdamp.cli.identify): rig TOML, CSV and UFF input, outputs, errors.

The numbers written must be the library's (identify_from_table on the same file); the input
errors must exit with status 2 and one line naming the key or the file.
"""

import json

import numpy as np
import pytest

from fricdamp.cli.identify import load_rig_file, main
from fricdamp.contact import Jenkins
from fricdamp.errors import CaseError
from fricdamp.models.rotational_joint.model import RigParameters, RotationalJointRig
from fricdamp.signals.identify import identify_from_table
from fricdamp.signals.records import read_signals_csv

RIG = """
[rig]
beam1_length_m = 0.200
beam2_length_m = 0.200
joint_offset_m = 0.009
beam2_mass_kg = 0.4396
sensor_mass_kg = 0.00994
sensor_a_m = -0.090
sensor_b_m = 0.0
sensor_c_m = 0.090

[channels]
A = "acc_A"
B = "acc_B"
C = "acc_C"

[processing]
frequency_hz = 30.0
periods = 6
"""


@pytest.fixture(scope="module")
def response():
    rig = RotationalJointRig(Jenkins(6e4, 0.13))
    return rig.simulate(5.0, periods=12, steps_per_period=160)


@pytest.fixture
def files(tmp_path, response):
    tab = response.accelerometers()
    head = "time [s],acc_A [m/s^2],acc_B [m/s^2],acc_C [m/s^2]"
    body = np.column_stack([tab[k] for k in ("time", "A", "B", "C")])
    lines = [head] + [",".join(f"{x:.15e}" for x in row) for row in body]
    sig = tmp_path / "signals.csv"
    sig.write_text("\n".join(lines) + "\n")
    rig = tmp_path / "rig.toml"
    rig.write_text(RIG)
    return sig, rig


def test_rig_file_gives_the_paper_geometry(files):
    _, rig = files
    spec, geom = load_rig_file(rig)
    ref = RigParameters().geometry()
    assert geom == ref
    assert spec.processing.periods == 6


def test_identify_csv_writes_the_library_numbers(files, tmp_path, response, capsys):
    sig, rig = files
    out = tmp_path / "out"
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    spec, geom = load_rig_file(rig)
    ref = identify_from_table(read_signals_csv(sig), geom,
                              channels={"A": "acc_A", "B": "acc_B", "C": "acc_C"},
                              frequency_hz=30.0, periods=6)
    ident = summary["identification"]
    assert ident["dissipated_energy_J"] == pytest.approx(ref.dissipated_energy, rel=1e-12)
    assert ident["damping_ratio"] == pytest.approx(ref.damping_ratio, rel=1e-12)
    # and it is the model's loop energy (closed loop; tolerance 1 %, see the validation test)
    assert ident["dissipated_energy_J"] == pytest.approx(response.dissipated_energy(6),
                                                         rel=0.01)
    loop = np.loadtxt(out / "loop.csv", delimiter=",", skiprows=1)
    assert loop.shape == (160, 3)
    assert (out / "loop.png").stat().st_size > 1000
    assert "dissipated energy" in capsys.readouterr().out


def test_simulated_csv_round_trip(tmp_path, response):
    """RigResponse.write_csv writes what read_signals_csv and the pipeline read (channels
    A, B, C in m/s^2): the closed loop through files, within 1 %."""
    path = tmp_path / "sim.csv"
    response.write_csv(path)
    tab = read_signals_csv(path)
    assert tab.units["A"] == "m/s^2" and "force" in tab
    ident = identify_from_table(tab, RigParameters().geometry(), frequency_hz=30.0, periods=6)
    assert ident.dissipated_energy == pytest.approx(response.dissipated_energy(6), rel=0.01)


def test_options_override_the_rig_file(files, tmp_path):
    sig, rig = files
    out = tmp_path / "o2"
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out), "--periods", "4",
                 "--kinematics", "exact"]) == 0
    ident = json.loads((out / "summary.json").read_text())["identification"]
    assert ident["n_periods"] == 4 and ident["kinematics"] == "exact"


def test_identify_uff(files, tmp_path, response):
    pyuff = pytest.importorskip("pyuff")
    _, rig = files
    tab = response.accelerometers()
    path = tmp_path / "signals.uff"
    u = pyuff.UFF(str(path))
    for i, (name, col) in enumerate((("acc_A", "A"), ("acc_B", "B"), ("acc_C", "C"))):
        ds = pyuff.prepare_58(binary=1, func_type=1, rsp_node=i + 1, rsp_dir=1, ref_node=0,
                              ref_dir=0, data=tab[col], x=tab["time"], id1=name,
                              abscissa_spacing=1, abscissa_spec_data_type=17,
                              ordinate_spec_data_type=12, orddenom_spec_data_type=0,
                              ordinate_axis_units_lab="m/s^2", abscissa_axis_units_lab="s")
        u.write_sets(ds, mode="add")  # a fresh file (pyuff's "overwrite" mangles 58b)
    out = tmp_path / "uff_out"
    assert main(["identify", str(path), "--rig", str(rig), "--out", str(out)]) == 0
    ident = json.loads((out / "summary.json").read_text())["identification"]
    assert ident["dissipated_energy_J"] == pytest.approx(response.dissipated_energy(6),
                                                         rel=0.01)


@pytest.mark.parametrize("edit, message", [
    (("sensor_c_m = 0.090", "sensor_c_m = 0.090\nsensor_d_m = 0.0"), "unknown key 'sensor_d_m'"),
    (("joint_offset_m = 0.009", "joint_offset_m = 0.2"), "joint_offset_m must be <"),
    (("beam2_mass_kg = 0.4396", "beam2_mass_kg = -1.0"), "beam2_mass_kg"),
    (("sensor_b_m = 0.0", "sensor_b_m = -0.090"), "must differ"),
    (('C = "acc_C"', 'C = "acc_X"'), "no column 'acc_X'"),
    (("frequency_hz = 30.0", "frequency_hz = 1000.0"), "samples per period"),
])
def test_bad_input_exits_2_with_one_line(files, tmp_path, capsys, edit, message):
    sig, rig = files
    rig.write_text(RIG.replace(*edit))
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_missing_files(files, tmp_path, capsys):
    sig, rig = files
    assert main(["identify", str(tmp_path / "none.csv"), "--rig", str(rig)]) == 2
    assert "does not exist" in capsys.readouterr().err
    with pytest.raises(CaseError, match="does not exist"):
        load_rig_file(tmp_path / "none.toml")


def test_identification_json_and_exit_3_when_unreliable(files, tmp_path, capsys):
    """identification.json carries the results contract of issue 16; a result whose 95 %
    interval is wider than [trust] max_relative_width exits with 3 (outputs written)."""
    sig, rig = files
    out = tmp_path / "ok"
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out)]) == 0
    d = json.loads((out / "identification.json").read_text())
    for key in ("dissipated_energy_J", "damping_ratio", "confidence_95", "block_scatter",
                "conditioning", "warnings"):
        assert key in d
    lo, hi = d["confidence_95"]["dissipated_energy_J"]
    assert lo < d["dissipated_energy_J"] < hi
    assert set(d["confidence_95"]) >= {"dissipated_energy_J", "damping_ratio"}
    assert d["status"] == "ok" and d["exit_code"] == 0
    assert d["warnings"] == [w for w in d["warnings"] if "block(s)" in w]  # 12 periods: a note
    summary = json.loads((out / "summary.json").read_text())
    assert summary["identification"]["confidence_95"] == d["confidence_95"]
    capsys.readouterr()
    rig.write_text(RIG + "\n[trust]\nmax_relative_width = 1e-6\n")
    out3 = tmp_path / "unreliable"
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out3)]) == 3
    d3 = json.loads((out3 / "identification.json").read_text())
    assert d3["status"] == "unreliable" and d3["exit_code"] == 3
    assert "interval of E_d" in d3["warnings"][0]
    assert (out3 / "loop.png").is_file()
    assert "fricdamp: warning:" in capsys.readouterr().err
    # no diagnostics: the interval is not checked, a right record is not unreliable
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out3),
                 "--no-diagnostics"]) == 0


@pytest.mark.parametrize("frequency", ["45", "17"])
def test_wrong_excitation_frequency_exits_3(files, tmp_path, capsys, frequency):
    """Issue 15: identify with the wrong excitation frequency reported a negative dissipated
    energy (45 Hz for a 30 Hz record) with exit 0. A given frequency more than 5 % away from
    the signals' strongest line is unreliable (exit 3), whatever the sign of the area."""
    sig, rig = files
    out = tmp_path / f"f{frequency}"
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out),
                 "--frequency", frequency]) == 3
    d = json.loads((out / "identification.json").read_text())
    assert d["status"] == "unreliable"
    assert "is not the signals' strongest line" in d["warnings"][0]


def test_wrong_excitation_frequency_without_diagnostics_exits_3(files, tmp_path, capsys):
    """Issue 15, rerun as written with --no-diagnostics: 45 Hz for a 30 Hz record gave a
    negative loop area and exit 0 with the warnings only in the log. The frequency check and
    the sign of the area need no diagnostics: unreliable, exit 3, the verdict as last line."""
    sig, rig = files
    out = tmp_path / "f45"
    capsys.readouterr()
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out),
                 "--frequency", "45", "--no-diagnostics"]) == 3
    d = json.loads((out / "identification.json").read_text())
    assert d["status"] == "unreliable" and d["dissipated_energy_J"] < 0
    assert "is not the signals' strongest line" in d["warnings"][0]
    assert any("is not positive" in w for w in d["warnings"])
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("fricdamp: warning: verdict: unreliable (identification): the "
                              "given excitation frequency 45 Hz")


def test_summary_carries_the_verdict_of_the_results_contract(files, tmp_path, capsys):
    """summary.json gains verdict = {overall, analyses: {identification: {verdict, reasons,
    estimates}}} as for fricdamp run; an ok identification ends with 'verdict: ok'."""
    sig, rig = files
    out = tmp_path / "ok"
    capsys.readouterr()
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out)]) == 0
    v = json.loads((out / "summary.json").read_text())["verdict"]
    assert v["overall"] == "ok"
    ident = v["analyses"]["identification"]
    assert ident["verdict"] == "ok" and ident["reasons"] == []
    assert ident["estimates"]["dissipated_energy_J"] > 0 and ident["estimates"]["diagnostics"]
    assert capsys.readouterr().out.strip().splitlines()[-1] == "verdict: ok"
    out45 = tmp_path / "f45"
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(out45),
                 "--frequency", "45"]) == 3
    v = json.loads((out45 / "summary.json").read_text())["verdict"]
    assert v["overall"] == "unreliable"
    assert "strongest line" in v["analyses"]["identification"]["reasons"][0]


def test_output_folder_is_checked_before_computing(files, tmp_path, capsys, monkeypatch):
    """An --out that is a file is refused in one line before the signals are processed."""
    import fricdamp.signals.identify as ident_module

    def never(*a, **k):
        raise AssertionError("computed before the output folder was checked")

    monkeypatch.setattr(ident_module, "identify_from_table", never)
    sig, rig = files
    blocker = tmp_path / "afile"
    blocker.write_text("x")
    capsys.readouterr()
    assert main(["identify", str(sig), "--rig", str(rig), "--out", str(blocker)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is a file; choose another --out" in err[0]


@pytest.mark.parametrize("which", ["signals", "rig"])
@pytest.mark.parametrize("path, message", [
    ("/dev/zero", "is not a regular file (a device or pipe)"),
    (".", "is a folder, not a file"),
])
def test_devices_and_folders_are_not_files(files, tmp_path, capsys, which, path, message):
    """Why (faults): ``check /dev/zero`` hung and ``mass = "."`` said "does not exist". The
    signal and rig files of identify are refused at once as what they are (exit 2)."""
    sig, rig = files
    args = [path if which == "signals" else str(sig), "--rig",
            path if which == "rig" else str(rig)]
    capsys.readouterr()
    assert main(["identify", *args, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and "does not exist" not in err[0]
    assert f"{'signal' if which == 'signals' else 'rig'} file {path!r}" in err[0]
