"""The shaker's force channel in the joint identification (fricdamp.signals._identify_force).

Validation on the simulated rig of paper 002 (rough joint of Table 2): with the exact
signals the joint torque from the theta1 equation and the measured force agrees with the one
of 002 (8), and the shaker's work per cycle with the suspension's damping plus the joint's
loop area (the rig's own energy balance, closed by the Newmark integration to machine
precision, tests/unit/test_rotational_joint.py); a calibration error of the force channel
is flagged. Tolerances: the Newmark rule (200 steps per period) and the pipeline's spectral
differentiation differ by (w h)^2 / 12 ~ 8e-5 relative, so 1e-3 on the torque and 2e-4 of
the input on the balance are tight; a 5 % force error moves the torque by 9-13 % RMS and
the balance by 4.75 % of the input, above the default limits of 2 %.
"""

import json

import numpy as np
import pytest

from fricdamp.cli.identify import load_rig_file, main
from fricdamp.errors import CaseError, ModelError
from fricdamp.models.rotational_joint.model import RigParameters, RotationalJointRig, paper002_joint
from fricdamp.signals.identify import DrivenBeam, TrustThresholds, identify_joint

#: 1 N: micro-slip (rotation ~1e-6 rad, the joint takes 0.02 % of the input);
#: 5 N: gross slip (the joint takes 30 %)
LEVELS = (1.0, 5.0)


@pytest.fixture(scope="module")
def rig():
    return RotationalJointRig(paper002_joint())


@pytest.fixture(scope="module")
def records(rig):
    return {f0: rig.simulate(f0, periods=14, steps_per_period=200).accelerometers()
            for f0 in LEVELS}


def run(rig, tab, force_gain=1.0, **kw):
    p = rig.params
    kw.setdefault("diagnostics", False)
    return identify_joint(tab["time"], tab["A"], tab["B"], tab["C"], p.geometry(),
                          frequency_hz=30.0, periods=8, force=force_gain * tab["force"],
                          driven_beam=p.driven_beam(), **kw)


@pytest.mark.parametrize("f0", LEVELS)
def test_exact_signals_two_torques_and_energy_balance_agree(rig, records, f0):
    res = run(rig, records[f0])
    fc = res.force_check
    assert fc.torque_discrepancy < 1e-3
    assert fc.force_discrepancy < 1e-3  # the x1 equation
    assert 1.0 < fc.amplification < 5.0  # the free-hanging rig: well conditioned
    assert fc.imbalance_relative < 2e-4
    assert fc.dissipated_energy == pytest.approx(res.dissipated_energy, rel=1e-3)
    assert not fc.warnings and res.status == "unchecked"
    d = res.to_dict()
    assert d["torque_from_force"]["torque_relative_rms_difference"] == fc.torque_discrepancy
    eb = d["energy_balance"]
    assert eb["input_work_J"] == pytest.approx(eb["rig_dissipation_J"]
                                               + eb["joint_dissipation_J"], rel=2e-4)
    # micro-slip: the balance cannot resolve E_d, and says so
    assert (eb["joint_share_of_input"] < 0.02) == (f0 == 1.0)
    assert bool(fc.notes) == (f0 == 1.0)


@pytest.mark.parametrize("f0", LEVELS)
def test_force_calibration_error_is_flagged(rig, records, f0):
    res = run(rig, records[f0], force_gain=1.05)
    fc = res.force_check
    assert fc.torque_discrepancy > 0.05 and 0.045 < fc.imbalance_relative < 0.05
    assert fc.force_discrepancy == pytest.approx(0.05 / 1.05, rel=0.02)
    assert res.status == "unreliable" and len(fc.warnings) == 2
    assert "shaker force" in res.warnings[0] and "energy balance" in res.warnings[1]
    # the joint's own identification (002 (8), accelerometers only) is untouched
    assert res.dissipated_energy == run(rig, records[f0]).dissipated_energy
    # and with diagnostics the force check joins the trust verdict
    full = run(rig, records[f0], force_gain=1.05, diagnostics=True)
    assert full.status == "unreliable" and full.warnings[:2] == res.warnings[:2]
    # looser limits accept it
    loose = run(rig, records[f0], force_gain=1.05,
                thresholds=TrustThresholds(max_torque_discrepancy=0.2,
                                           max_energy_imbalance=0.06))
    assert not loose.force_check.warnings


def test_stiff_suspension_makes_the_force_torque_ill_conditioned():
    """RigParameters.paper_load_case(): beam 1's suspension carries ~440x the joint torque,
    so the simulated rig's own discretisation error (Newmark vs spectral derivatives, ~1e-4)
    leaves ~7 % between the torques: flagged, and the warning says why."""
    rig = RotationalJointRig(paper002_joint(), RigParameters.paper_load_case())
    tab = rig.simulate(500.0, periods=12, steps_per_period=200).accelerometers()
    res = run(rig, tab)
    fc = res.force_check
    assert fc.amplification > 300 and fc.torque_discrepancy > 0.02
    assert fc.imbalance_relative < 2e-4  # the balance itself still closes
    assert res.status == "unreliable" and "x the joint torque" in res.warnings[0]


def test_bad_force_input(rig, records):
    tab, p = records[1.0], rig.params
    args = (tab["time"], tab["A"], tab["B"], tab["C"], p.geometry())
    with pytest.raises(ModelError, match="force and driven_beam go together"):
        identify_joint(*args, force=tab["force"])
    with pytest.raises(ModelError, match="force has 3 samples"):
        identify_joint(*args, force=[1.0, 2.0, 3.0], driven_beam=p.driven_beam())
    with pytest.raises(ModelError, match="beam1_mass"):
        DrivenBeam(0.0, 1e-3, -0.1)
    with pytest.raises(ModelError, match="suspension_damping"):
        DrivenBeam(0.4, 1e-3, -0.1, suspension_damping=-1.0)


SHAKER = """
[shaker]
beam1_mass_kg = 0.4396
shaker_arm_m = -0.100
suspension_stiffness_N_per_m = 870.0
suspension_damping_N_s_per_m = 16.6
suspension_torsional_stiffness_N_m_per_rad = 17.4
suspension_torsional_damping_N_m_s_per_rad = 0.33
"""

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
force = "F"
force_unit = "mV"
force_sensitivity_mV_per_N = 100.0

[processing]
frequency_hz = 30.0
periods = 8
"""


def write(tmp_path, tab, gain=1.0):
    head = "time [s],A [m/s^2],B [m/s^2],C [m/s^2],F [mV]"
    body = np.column_stack([tab["time"], tab["A"], tab["B"], tab["C"],
                            100.0 * gain * tab["force"]])
    sig = tmp_path / f"signals{gain}.csv"
    sig.write_text("\n".join([head] + [",".join(f"{x:.15e}" for x in row) for row in body])
                   + "\n")
    return sig


def test_cli_force_channel(tmp_path, rig, records, capsys):
    tab = records[5.0]
    rig_file = tmp_path / "rig.toml"
    rig_file.write_text(RIG + SHAKER)
    spec, _ = load_rig_file(rig_file)
    # I1 from 002 (9) with the rig file's masses and positions = the simulated rig's
    from fricdamp.cli.identify import driven_beam

    assert driven_beam(spec).beam1_inertia == pytest.approx(rig.params.inertia1, rel=1e-12)
    base = ["identify", "--rig", str(rig_file), "--no-diagnostics"]
    code = main([*base[:1], str(write(tmp_path, tab)), *base[1:], "--out",
                 str(tmp_path / "ok")])
    d = json.loads((tmp_path / "ok" / "identification.json").read_text())
    assert code == 0, capsys.readouterr()
    assert d["torque_from_force"]["torque_relative_rms_difference"] < 1e-3
    assert d["energy_balance"]["residual_relative_to_input"] < 2e-4
    code = main([*base[:1], str(write(tmp_path, tab, 1.05)), *base[1:], "--out",
                 str(tmp_path / "bad")])
    d = json.loads((tmp_path / "bad" / "identification.json").read_text())
    assert code == 3 and d["status"] == "unreliable"
    assert "energy balance" in " ".join(d["warnings"])
    # a force column without [shaker]: one-line error, exit 2
    rig_file.write_text(RIG)
    with pytest.raises(CaseError, match=r"\[channels\] force = 'F' needs a \[shaker\]"):
        load_rig_file(rig_file)


def test_summary_verdict_carries_the_force_estimates(tmp_path, records, capsys):
    rig_file = tmp_path / "rig.toml"
    rig_file.write_text(RIG + SHAKER)
    out = tmp_path / "out"
    assert main(["identify", str(write(tmp_path, records[5.0])), "--rig", str(rig_file),
                 "--no-diagnostics", "--out", str(out)]) == 0, capsys.readouterr()
    summary = json.loads((out / "summary.json").read_text())
    est = summary["verdict"]["analyses"]["identification"]["estimates"]
    assert est["torque_from_force_rms_difference"] < 1e-3
    assert est["energy_balance_residual"] < 2e-4


def test_closed_loop_uses_the_simulated_force_on_request(rig):
    from fricdamp.models.rotational_joint.model import closed_loop_identification

    res = rig.simulate(5.0, periods=12, steps_per_period=160)
    plain = closed_loop_identification(rig, 5.0, response=res, analysed_periods=6,
                                       diagnostics=False)
    assert plain.identification.force_check is None
    assert "torque_from_force" not in plain.to_dict()
    cl = closed_loop_identification(rig, 5.0, response=res, analysed_periods=6,
                                    diagnostics=False, use_force=True)
    d = cl.to_dict()
    assert d["torque_from_force"]["torque_relative_rms_difference"] < 1e-3
    assert d["energy_balance"]["residual_relative_to_input"] < 2e-4
    assert cl.identified_energy == plain.identified_energy
