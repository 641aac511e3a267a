"""Lab-ready input of the identification: rounded time stamps, sample-index columns, sample
rate, skipped metadata rows, time units, voltage channels with sensitivities [mV/g], the
start-up transient, and the energy-based damping ratio (issue 16, paper 002 part)."""

import json

import numpy as np
import pytest

from fricdamp.cli.identify import main
from fricdamp.errors import ModelError
from fricdamp.signals.identify import JointRigGeometry, identify_from_table, identify_joint
from fricdamp.signals.records import read_signals_csv, uniform_time

GEOM = JointRigGeometry(sensor_a=-0.09, sensor_b=0.0, joint_arm1=0.091, sensor_c=0.09,
                        joint_arm2=0.091, beam2_mass=0.44, beam2_inertia=1.55e-3)
F0, FS = 30.0, 5120.0
W = 2 * np.pi * F0
G0 = 9.80665


def _signals(t, envelope=None):
    """Readings (linear kinematics) of a periodic motion, optionally with an envelope."""
    env = np.ones_like(t) if envelope is None else envelope(t)
    a1 = -W * W * 1e-3 * (np.sin(W * t) + 0.1 * np.sin(3 * W * t + 0.7)) * env
    a2 = -W * W * 0.7e-3 * np.sin(W * t - 0.25) * env
    ax = -W * W * 1.5e-4 * np.sin(W * t + 0.3) * env
    return (ax + GEOM.sensor_a * a1, ax + GEOM.sensor_b * a1,
            ax + GEOM.joint_arm1 * a1 + (GEOM.sensor_c + GEOM.joint_arm2) * a2)


T = np.arange(int(12 * FS / F0)) / FS
SIG = _signals(T)
REF = identify_joint(T, *SIG, GEOM, frequency_hz=F0, diagnostics=False)


# ----------------------------------------------------------------------------- time bases
def test_rounded_time_stamps_are_snapped():
    t7 = np.round(T, 7)  # 1/5120 s written with 7 decimals: 2.6e-4 of a step off
    t2, dt, snapped = uniform_time(t7)
    assert snapped and dt == 1 / FS
    np.testing.assert_allclose(t2, np.arange(T.size) / FS, rtol=0, atol=1e-15)
    res = identify_joint(t7, *SIG, GEOM, frequency_hz=F0, diagnostics=False)
    assert res.time_snapped and res.dissipated_energy == pytest.approx(
        REF.dissipated_energy, rel=1e-12)
    # rounding to a quarter of a step still passes (no block of stamps is offset)
    assert uniform_time(np.round(T, 4))[1] == 1 / FS


def test_gaps_and_odd_rates():
    t = T.copy()
    t[500:] += 0.3 / FS  # a jump of 0.3 step: a gap, not rounding
    with pytest.raises(ModelError, match="uniformly spaced"):
        uniform_time(t)
    t = np.delete(T, 700)  # a dropped sample
    with pytest.raises(ModelError, match="uniformly spaced"):
        uniform_time(t)
    odd = np.arange(2000) / 5119.7  # not a whole number of hertz: kept as it is
    assert uniform_time(odd)[1] == pytest.approx(1 / 5119.7, rel=1e-12)
    with pytest.raises(ModelError, match="strictly increasing"):
        uniform_time([0.0, 1.0, 1.0, 2.0])


# ----------------------------------------------------------------------------- CSV reading
def _write(path, head, cols, fmt="{:.10e}", pre=""):
    rows = np.column_stack(cols)
    lines = [head] + [",".join(fmt.format(x) for x in r) for r in rows]
    path.write_text(pre + "\n".join(lines) + "\n")
    return path


def test_sample_index_column_is_not_seconds(tmp_path):
    k = np.arange(T.size)
    p = _write(tmp_path / "idx.csv", "Sample,A [m/s^2],B [m/s^2],C [m/s^2]", (k, *SIG))
    with pytest.raises(ModelError, match="'Sample' is a sample index"):
        read_signals_csv(p)
    tab = read_signals_csv(p, sample_rate=FS)
    assert list(tab) == ["time", "A", "B", "C"] and tab["time"][1] == 1 / FS
    got = identify_from_table(tab, GEOM, frequency_hz=F0, diagnostics=False)
    assert got.dissipated_energy == pytest.approx(REF.dissipated_energy, rel=1e-9)
    # unnamed consecutive integers are an index too; a named time column is preferred
    p2 = _write(tmp_path / "n.csv", "n,A [g],B [g],C [g]", (k, *(x / G0 for x in SIG)))
    with pytest.raises(ModelError, match="sample index"):
        read_signals_csv(p2)
    p3 = _write(tmp_path / "both.csv", "Sample,Time [ms],A [g],B [g],C [g]",
                (k, 1e3 * T, *(x / G0 for x in SIG)))
    tab3 = read_signals_csv(p3)
    assert tab3.time_column == "Time" and tab3["time"][-1] == pytest.approx(T[-1])


def test_skip_rows_time_column_and_unit(tmp_path):
    meta = "Instrument: DAQ-9000\nOperator: lab\nDate: 2024-01-01\n"
    p = _write(tmp_path / "meta.csv", "stamp,A [g],B [g],C [g]",
               (1e3 * T, *(x / G0 for x in SIG)), pre=meta)
    with pytest.raises(ModelError):
        read_signals_csv(p)
    tab = read_signals_csv(p, skip_rows=3, time_column="stamp", time_unit="ms")
    assert tab["time"][-1] == pytest.approx(T[-1], rel=1e-12)
    with pytest.raises(ModelError, match="sample_rate must be > 0"):
        read_signals_csv(p, skip_rows=3, sample_rate=-1.0)


def test_cli_reads_a_lab_file(tmp_path):
    """7-decimal ms stamps after metadata, channels in mV with the paper's sensitivities."""
    sens = {"A": 10.35, "B": 10.79, "C": 10.29}  # mV/g, paper 002 section 2
    mv = [x / G0 * sens[r] for x, r in zip(SIG, "ABC", strict=True)]
    p = _write(tmp_path / "lab.csv", "stamp [s],acc_A [mV],acc_B [mV],acc_C [mV]",
               (np.round(T, 7), *mv), pre="# exported\nRate: 5120 Hz\n")
    rig = tmp_path / "rig.toml"
    rig.write_text("""[rig]
beam1_length_m = 0.2
beam2_length_m = 0.2
joint_offset_m = 0.009
beam2_mass_kg = 0.44
sensor_mass_kg = 0.0
sensor_a_m = -0.09
sensor_b_m = 0.0
sensor_c_m = 0.09
beam2_inertia_kg_m2 = 1.55e-3

[channels]
A = "acc_A"
B = "acc_B"
C = "acc_C"
sensitivity_mV_per_g = {A = 10.35, B = 10.79}

[input]
skip_rows = 2
time_column = "stamp"
""")
    out = tmp_path / "out"
    code = main(["identify", str(p), "--rig", str(rig), "--out", str(out), "--frequency",
                 "30", "--sensitivity", "C=10.29", "--no-diagnostics"])
    assert code == 0
    d = json.loads((out / "identification.json").read_text())
    assert d["dissipated_energy_J"] == pytest.approx(REF.dissipated_energy, rel=1e-7)
    assert d["time_snapped"] and d["status"] == "unchecked"
    # the same file through --sample-rate (the stamps are then ignored)
    out2 = tmp_path / "out2"
    assert main(["identify", str(p), "--rig", str(rig), "--out", str(out2), "--sample-rate",
                 "5120", "--frequency", "30", "--sensitivity", "C=10.29",
                 "--no-diagnostics"]) == 0
    d2 = json.loads((out2 / "identification.json").read_text())
    assert d2["dissipated_energy_J"] == pytest.approx(REF.dissipated_energy, rel=1e-7)


@pytest.mark.parametrize("flag, message", [
    (["--sensitivity", "A=-1"], "--sensitivity must be like"),
    (["--sensitivity", "D=10"], "--sensitivity must be like"),
    (["--skip-periods", "many"], "--skip-periods must be"),
    (["--sample-rate", "0"], "--sample-rate must be > 0"),
    (["--position-std", "-1"], "--position-std must be >= 0"),
])
def test_bad_options_exit_2(tmp_path, capsys, flag, message):
    p = _write(tmp_path / "s.csv", "time [s],A [m/s^2],B [m/s^2],C [m/s^2]", (T, *SIG))
    rig = tmp_path / "rig.toml"
    rig.write_text("[rig]\nbeam1_length_m = 0.2\nbeam2_length_m = 0.2\njoint_offset_m = 0.009"
                   "\nbeam2_mass_kg = 0.44\nsensor_mass_kg = 0.0\nsensor_a_m = -0.09\n"
                   "sensor_b_m = 0.0\nsensor_c_m = 0.09\n")
    assert main(["identify", str(p), "--rig", str(rig), "--out", str(tmp_path / "o"),
                 *flag]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_sensitivity_needs_voltage_channels():
    tab = {"time": T, "A": SIG[0], "B": SIG[1], "C": SIG[2]}

    class Tab(dict):
        units = {"A": "m/s^2", "B": "m/s^2", "C": "m/s^2"}

    with pytest.raises(ModelError, match="not a voltage"):
        identify_from_table(Tab(tab), GEOM, sensitivity_mV_per_g={"A": 10.0})
    volts = Tab({"time": T, "A": SIG[0] / G0 * 0.01, "B": SIG[1], "C": SIG[2]})
    volts.units = {"A": "V", "B": "m/s^2", "C": "m/s^2"}
    got = identify_from_table(volts, GEOM, sensitivity_mV_per_g={"A": 10.0},
                              frequency_hz=F0, diagnostics=False)
    assert got.dissipated_energy == pytest.approx(REF.dissipated_energy, rel=1e-12)


# ----------------------------------------------------------------------------- transient
def test_start_up_transient_is_excluded_by_default():
    """The motion grows over its first 4 periods (a force ramp): those periods, and only
    about those, are dropped, and the energy is the steady one (1e-9)."""
    t = np.arange(int(20 * FS / F0)) / FS
    ramp = lambda x: np.where(x < 4 / F0, 0.5 * (1 - np.cos(np.pi * x * F0 / 4)), 1.0)  # noqa: E731
    sig = _signals(t, ramp)
    auto = identify_joint(t, *sig, GEOM, frequency_hz=F0, diagnostics=False)
    assert 4 <= auto.skipped_periods <= 5
    steady = identify_joint(t, *_signals(t), GEOM, frequency_hz=F0, diagnostics=False,
                            periods=auto.n_periods)
    assert auto.dissipated_energy == pytest.approx(steady.dissipated_energy, rel=1e-9)
    whole = identify_joint(t, *sig, GEOM, frequency_hz=F0, diagnostics=False, skip_periods=0)
    assert whole.skipped_periods == 0
    assert abs(whole.dissipated_energy / steady.dissipated_energy - 1) > 0.02
    # periods reaching into the transient are honoured, with a warning
    long = identify_joint(t, *sig, GEOM, frequency_hz=F0, periods=18)
    assert long.n_periods == 18 and any("start-up transient" in w for w in long.warnings)


def test_frequency_estimate_is_refined_by_the_phase_drift():
    t = np.arange(int(20 * FS / F0)) / FS
    f_true = 30.0137
    sig = [x for x in _signals(t * f_true / F0)]
    res = identify_joint(t, *sig, GEOM, diagnostics=False)
    assert res.frequency_hz == pytest.approx(f_true, rel=1e-7)


# ----------------------------------------------------------------------------- damping ratio
def test_energy_based_damping_ratio_equals_the_paper_one_for_an_elliptic_loop():
    """Pure fundamentals: the loop is an ellipse (to O(theta^2)), so E_d / (pi theta_max
    M_max) and E_d / (pi Theta_1 M_1) agree; tolerance 2e-4: the sampled peaks miss the true
    ones by up to 1 - cos(pi / 180) = 1.5e-4 (180 samples per period after resampling)."""
    t = np.arange(int(6 * FS / F0)) / FS
    a1 = -W * W * 1e-3 * np.sin(W * t)
    a2 = -W * W * 0.7e-3 * np.sin(W * t - 0.25)
    ax = -W * W * 1.5e-4 * np.sin(W * t + 0.3)
    sig = (ax + GEOM.sensor_a * a1, ax + GEOM.sensor_b * a1,
           ax + GEOM.joint_arm1 * a1 + (GEOM.sensor_c + GEOM.joint_arm2) * a2)
    res = identify_joint(t, *sig, GEOM, frequency_hz=F0, diagnostics=False, n_harmonics=1)
    assert res.damping_ratio_energy == pytest.approx(res.damping_ratio, rel=2e-4)
