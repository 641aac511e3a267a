"""Closed-loop validation of paper 002's measurement pipeline (Fig. 7).

The rig (3-DOF Lagrange model 002 (1)-(10), (A.2)) is simulated at 30 Hz with the paper's
rough joint (Table 2, 100 N preload, slip torque 0.134 N m); the three accelerometers are
sampled from the simulation (exact beam-fixed kinematics), optionally with noise; the
pipeline (kinematics (B.1)-(B.10), FFT integration over whole periods, torque (8), loop
area) must recover the loop energy of the joint model over the same periods.

Requirement (the issue): within 1 % without noise, within 5 % with noise. Measured: ~2e-4
without noise from micro-slip to gross slip (the difference between Newmark's trapezoidal
integration and the exact spectral one), 0.4 % with 5 % noise at the onset of gross slip.

Noise limits what is identifiable: the joint rotation is the small difference of the beams'
rotations (0.2 % of theta1 in micro-slip with this rig), so accelerometer noise must be small
compared with that ratio; the 5 % noise case is therefore run where the joint slips.
"""

import numpy as np
import pytest

from fricdamp.models.rotational_joint.model import (
    RotationalJointRig,
    closed_loop_identification,
    paper002_joint,
    paper002_results,
)

PERIODS, SPP, ANALYSED = 20, 200, 8


@pytest.fixture(scope="module")
def rig():
    return RotationalJointRig(paper002_joint())


@pytest.fixture(scope="module")
def responses(rig):
    return {f: rig.simulate(f, periods=PERIODS, steps_per_period=SPP) for f in (0.5, 2.0, 5.0)}


@pytest.mark.parametrize("force, regime", [(0.5, "micro-slip"), (2.0, "partial slip"),
                                           (5.0, "gross slip")])
def test_noise_free_within_1_percent(rig, responses, force, regime):
    res = responses[force]
    cl = closed_loop_identification(rig, force, response=res, analysed_periods=ANALYSED)
    assert cl.relative_error < 0.01, (regime, cl.to_dict())
    # the regime is the one named: paper 002's xi from micro-slip to gross slip
    xi = cl.identification.damping_ratio
    assert {"micro-slip": xi < 0.2, "partial slip": 0.2 < xi < 1.0,
            "gross slip": xi > 1.0}[regime], xi
    # the energy balance of the simulation itself (Newmark, trapezoidal bookkeeping)
    assert res.energy_balance_error < 1e-6


def test_results_contract(rig, responses):
    d = closed_loop_identification(rig, 2.0, response=responses[2.0],
                                   analysed_periods=ANALYSED).to_dict()
    for key in ("dissipated_energy_J_model", "dissipated_energy_J_identified",
                "relative_error"):
        assert np.isfinite(d[key])
    assert d["relative_error"] == pytest.approx(
        abs(d["dissipated_energy_J_identified"] / d["dissipated_energy_J_model"] - 1),
        rel=1e-12)


def test_paper002_results_summary():
    """The summary.json blocks of examples/cases/rotational_joint.toml."""
    summary, curves, cl = paper002_results(amplitudes=[1e-6, 1e-4, 1e-2], periods=12,
                                           steps_per_period=120, analysed_periods=4)
    j = summary["joint"]
    assert len(j["amplitude_rad"]) == len(j["dissipated_energy_J"]) == 3
    assert j["damping_ratio"] == sorted(j["damping_ratio"])           # Fig. 17: rising
    ident = summary["identification"]
    assert ident["relative_error"] < 0.01
    assert ident["dissipated_energy_J_model"] == cl.model_energy


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_five_percent_noise_within_5_percent(rig, responses, seed):
    """White noise of 5 % of each channel's RMS; the harmonic filter keeps the lines of the
    excitation only (noise falls by ~sqrt(bins))."""
    cl = closed_loop_identification(rig, 5.0, response=responses[5.0],
                                    analysed_periods=ANALYSED, noise=0.05, seed=seed)
    assert cl.relative_error < 0.05, cl.to_dict()
    assert cl.identification.filtered_fraction > 0.02  # the noise was there


def test_gravity_sensing_accelerometers(rig, responses):
    """Sensors that read g sin(theta) (piezoelectric ones do at 30 Hz): the exact kinematics
    account for it and stay within 1 %."""
    cl = closed_loop_identification(rig, 5.0, response=responses[5.0],
                                    analysed_periods=ANALYSED, gravity_sensing=True,
                                    kinematics="exact")
    assert cl.relative_error < 0.01, cl.to_dict()


def test_paper_force_large_rotations(rig):
    """60 N, the lowest force of the paper's range: gross slip with 0.1 rad rotations. The
    exact kinematics recover the energy within 1 %; the paper's linear relations are a
    few percent off there (O(theta^2) terms against a joint torque that is ~1 % of beam 2's
    inertial torque)."""
    res = rig.simulate(60.0, periods=PERIODS, steps_per_period=SPP)
    exact = closed_loop_identification(rig, 60.0, response=res, analysed_periods=ANALYSED,
                                       kinematics="exact")
    paper = closed_loop_identification(rig, 60.0, response=res, analysed_periods=ANALYSED)
    assert exact.relative_error < 0.01, exact.to_dict()
    assert 0.5 * np.ptp(res.steady_loop(1)[0]) > 0.05
    assert paper.relative_error > exact.relative_error
