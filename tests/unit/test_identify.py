"""Paper 002's post-processing pipeline (fricdamp.signals.identify) on exact synthetic signals.

The beams' motion is prescribed as a few harmonics (zero mean, so that the constants of
integration, which no accelerometer measures, are zero); the accelerometer readings follow from
the exact kinematics (tests/unit/test_rotational_joint_lagrange.py derives them), and the true
joint torque from 002 (8) on the true states. The pipeline must return the prescribed motion
and the loop area of the true torque. References: Bouchaala et al. 2014, Fig. 7, (8),
(26)-(27), appendix B.
"""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.signals.damping import paper002_damping_ratio
from fricdamp.signals.energy import loop_area
from fricdamp.signals.identify import (
    JointRigGeometry,
    acceleration_scale,
    estimate_frequency,
    identify_from_table,
    identify_joint,
    joint_torque,
)
from fricdamp.signals.records import read_signals_csv

GEOM = JointRigGeometry(sensor_a=-0.09, sensor_b=0.0, joint_arm1=0.091, sensor_c=0.09,
                        joint_arm2=0.091, beam2_mass=0.44, beam2_inertia=1.55e-3)
F0 = 30.0


def motion(t, scale=1e-3):
    """Zero-mean periodic states (theta1, theta2, x1) and their two derivatives, (3, 3, n)."""
    w = 2 * np.pi * F0
    comps = [  # (amplitude, harmonic, phase) per coordinate
        [(1.0, 1, 0.0), (0.08, 3, 0.7)],
        [(0.7, 1, -0.25), (0.05, 2, 1.1), (0.02, 5, -0.4)],
        [(0.15, 1, 0.3), (0.01, 3, 0.2)],
    ]
    out = np.zeros((3, 3, t.size))
    for i, cs in enumerate(comps):
        for amp, k, ph in cs:
            a = scale * amp
            out[i, 0] += a * np.sin(k * w * t + ph)
            out[i, 1] += a * k * w * np.cos(k * w * t + ph)
            out[i, 2] -= a * (k * w) ** 2 * np.sin(k * w * t + ph)
    return out


def readings(st, geom=GEOM, gravity=False):
    """Exact beam-fixed tangential accelerations at A, B, C."""
    (t1, w1, a1), (t2, _, a2), (_, _, ax) = st
    rel = t1 - t2
    ga = ax * np.cos(t1) + geom.sensor_a * a1
    gb = ax * np.cos(t1) + geom.sensor_b * a1
    gc = (ax * np.cos(t2) + geom.joint_arm1 * (a1 * np.cos(rel) - w1 ** 2 * np.sin(rel))
          + (geom.sensor_c + geom.joint_arm2) * a2)
    if gravity:
        ga, gb, gc = (ga + geom.gravity * np.sin(t1), gb + geom.gravity * np.sin(t1),
                      gc + geom.gravity * np.sin(t2))
    return ga, gb, gc


def true_loop(st, geom=GEOM):
    (t1, w1, a1), (t2, _, a2), (_, _, ax) = st
    return t1 - t2, joint_torque(geom, t1, t2, w1, a1, a2, ax)


def test_recovers_motion_torque_and_energy_exactly():
    """Whole periods, integer samples per period: FFT integration is exact for the
    band-limited motion, and the paper's kinematics are exact to O(theta^2) = 1e-6.
    Tolerances: rotations 1e-5 relative (the O(theta^2) kinematic terms), energy 1e-4."""
    n_per, spp = 6, 256
    t = np.arange(n_per * spp) / (F0 * spp)
    st = motion(t)
    res = identify_joint(t, *readings(st), GEOM, frequency_hz=F0)
    assert res.n_periods == n_per and not res.resampled
    for got, ref in ((res.theta1, st[0, 0]), (res.theta2, st[1, 0]), (res.x1, st[2, 0])):
        assert np.max(np.abs(got - ref)) < 1e-5 * np.max(np.abs(ref))
    rot, tor = true_loop(st)
    e_true = loop_area(rot, tor) / n_per
    assert e_true > 0
    assert res.dissipated_energy == pytest.approx(e_true, rel=1e-4)
    assert res.rotation_amplitude == pytest.approx(0.5 * np.ptp(rot), rel=1e-4)
    assert res.damping_ratio == pytest.approx(
        paper002_damping_ratio(res.dissipated_energy, res.rotation_amplitude,
                               res.torque_amplitude), rel=1e-14)
    assert res.to_dict()["dissipated_energy_J"] == res.dissipated_energy
    assert res.cycle_energy.shape == (n_per,)
    assert res.filtered_fraction < 1e-9  # nothing but harmonics in the signals (round-off)


def test_offsets_and_drifts_are_removed():
    """Sensor offsets and linear drifts are not part of the periodic motion: the drift
    estimate (means of the first and last periods) and the harmonic filter remove them
    exactly (tolerance 1e-9, round-off)."""
    n_per, spp = 12, 200
    t = np.arange(n_per * spp) / (F0 * spp)
    st = motion(t)
    ga, gb, gc = readings(st)
    ref = identify_joint(t, ga, gb, gc, GEOM, frequency_hz=F0)
    drift = 0.3 + 0.5 * t / t[-1]
    res = identify_joint(t, ga + drift, gb - 0.5 * drift, gc + 0.1 - 2 * drift, GEOM,
                         frequency_hz=F0)
    assert res.dissipated_energy == pytest.approx(ref.dissipated_energy, rel=1e-9)
    assert np.max(np.abs(res.theta2 - ref.theta2)) < 1e-9 * np.max(np.abs(ref.theta2))
    assert res.filtered_fraction > 1e-2 > ref.filtered_fraction


def test_a_decaying_transient_is_mostly_filtered_out():
    """A slow decaying oscillation (7 Hz, not a harmonic) leaks onto the harmonic lines only
    through its change over the window: after 5 time constants, 1e-3 of the energy."""
    n_per, spp = 30, 200
    t = np.arange(n_per * spp) / (F0 * spp)
    st = motion(t)
    ga, gb, gc = readings(st)
    junk = 2.0 * np.exp(-5 * t / t[-1] * 3) * np.sin(2 * np.pi * 7 * t)
    ref = identify_joint(t, ga, gb, gc, GEOM, frequency_hz=F0, periods=15)
    res = identify_joint(t, ga + junk, gb, gc, GEOM, frequency_hz=F0, periods=15)
    assert res.dissipated_energy == pytest.approx(ref.dissipated_energy, rel=1e-3)


def test_highpass_filter_gives_the_same_loop_on_clean_whole_periods():
    n_per, spp = 4, 256
    t = np.arange(n_per * spp) / (F0 * spp)
    st = motion(t)
    h = identify_joint(t, *readings(st), GEOM, frequency_hz=F0, filter="highpass")
    c = identify_joint(t, *readings(st), GEOM, frequency_hz=F0)
    assert h.dissipated_energy == pytest.approx(c.dissipated_energy, rel=1e-10)


def test_incommensurate_sampling_is_resampled():
    """9973 Hz for 30 Hz (332.43 samples per period, no whole number of samples in 8 to 10
    periods): cubic-spline resampling of whole periods onto 360 points per period (the next
    fast FFT length above 333).
    Reference: the true loop on the same time grid, so only the spline error remains,
    O((w h)^4) ~ 1e-7 at the 5th harmonic; tolerance 1e-5."""
    fs = 9973.0
    t = np.arange(int(10.4 * fs / F0)) / fs
    st = motion(t)
    res = identify_joint(t, *readings(st), GEOM, frequency_hz=F0, periods=10)
    assert res.resampled and res.n_periods == 10 and res.samples_per_period == 360
    assert np.diff(res.time) == pytest.approx(1 / (F0 * 360), rel=1e-9)
    rot, tor = true_loop(motion(res.time))
    assert res.dissipated_energy == pytest.approx(loop_area(rot, tor) / 10, rel=1e-5)


def test_lab_rate_uses_whole_sample_groups_of_periods():
    """10240 Hz for 30 Hz: 3 periods are exactly 1024 samples, so 9 of the 10 periods asked
    are taken as sampled (no interpolation). The energy is the true loop's on those samples
    (round-off), and the synchronous average cycle() is the true loop at its phases."""
    fs = 10240.0
    t = np.arange(int(10.4 * fs / F0)) / fs
    st = motion(t)
    res = identify_joint(t, *readings(st), GEOM, frequency_hz=F0, periods=10)
    assert not res.resampled and res.n_periods == 9 and res.time.size == 3072
    st_w = motion(res.time)
    rot, tor = true_loop(st_w)
    assert res.dissipated_energy == pytest.approx(loop_area(rot, tor) / 9, rel=1e-5)
    assert res.cycle_energy.sum() == pytest.approx(9 * res.dissipated_energy, rel=1e-12)
    r, f = res.cycle(64)
    tc = res.time[0] + np.arange(64) / (64 * F0)
    rot_c, tor_c = true_loop(motion(tc))
    assert np.max(np.abs(r - rot_c)) < 1e-5 * np.max(np.abs(rot_c))
    assert np.max(np.abs(f - tor_c)) < 1e-4 * np.max(np.abs(tor_c))


def test_frequency_is_estimated_when_not_given():
    """Hann + log-parabola peak interpolation: relative error < 1e-4 on 20 periods."""
    fs = 5000.0
    t = np.arange(int(20 * fs / F0)) / fs
    st = motion(t)
    ga = readings(st)[0]
    f = estimate_frequency(ga, 1 / fs)
    assert f == pytest.approx(F0, rel=1e-4)
    res = identify_joint(t, *readings(st), GEOM)
    assert res.frequency_hz == pytest.approx(F0, rel=1e-4)


def test_exact_kinematics_at_large_angles_with_gravity_sensing():
    """Rotations of 0.15 rad: the paper's linear relations (B.1)-(B.10) miss O(theta^2) and
    gravity's g sin(theta) in the readings; the exact kinematics recover the energy
    (fixed point converging by a factor ~theta^2 per pass; tolerance 1e-4)."""
    n_per, spp = 4, 512
    t = np.arange(n_per * spp) / (F0 * spp)
    st = motion(t, scale=0.15)
    rot, tor = true_loop(st)
    e_true = loop_area(rot, tor) / n_per
    g = readings(st, gravity=True)
    exact = identify_joint(t, *g, GEOM, frequency_hz=F0, kinematics="exact",
                           gravity_sensing=True, iterations=6)
    paper = identify_joint(t, *g, GEOM, frequency_hz=F0)
    assert exact.dissipated_energy == pytest.approx(e_true, rel=1e-4)
    assert abs(paper.dissipated_energy / e_true - 1) > 1e-2  # why "exact" exists


def test_units_and_csv_round_trip(tmp_path):
    """A CSV in g with units in the header gives the same loop as the signals in m/s^2."""
    assert acceleration_scale("g") == 9.80665
    assert acceleration_scale(" m/s^2 ") == 1.0
    assert acceleration_scale("mm/s2") == 1e-3
    with pytest.raises(ModelError, match="unknown acceleration unit"):
        acceleration_scale("furlong/fortnight^2")
    with pytest.raises(ModelError, match="no acceleration unit"):
        acceleration_scale("", channel="acc_A")
    n_per, spp = 5, 128
    t = np.arange(n_per * spp) / (F0 * spp)
    st = motion(t)
    ga, gb, gc = readings(st)
    ref = identify_joint(t, ga, gb, gc, GEOM, frequency_hz=F0)
    path = tmp_path / "signals.csv"
    rows = np.column_stack((t * 1e3, ga / 9.80665, gb / 9.80665, gc / 9.80665))
    head = "t [ms];acc_A [g];acc_B [g];acc_C [g]"
    lines = [head] + [";".join(f"{x:.15e}".replace(".", ",") for x in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    tab = read_signals_csv(path)
    got = identify_from_table(tab, GEOM, channels={"A": "acc_A", "B": "acc_B", "C": "acc_C"},
                              frequency_hz=F0)
    assert got.dissipated_energy == pytest.approx(ref.dissipated_energy, rel=1e-9)
    assert got.source == str(path)
    with pytest.raises(ModelError, match="no column 'A'"):
        identify_from_table(tab, GEOM)
    # a unit given explicitly overrides the header
    tab.units["acc_A"] = ""
    with pytest.raises(ModelError, match="no acceleration unit"):
        identify_from_table(tab, GEOM, channels={"A": "acc_A", "B": "acc_B", "C": "acc_C"})
    got2 = identify_from_table(tab, GEOM, channels={"A": "acc_A", "B": "acc_B", "C": "acc_C"},
                               units="g", frequency_hz=F0)
    assert got2.dissipated_energy == pytest.approx(ref.dissipated_energy, rel=1e-9)


def test_bad_records_are_rejected_with_clear_messages():
    t = np.arange(2000) / 6000.0
    g = np.sin(2 * np.pi * F0 * t)
    with pytest.raises(ModelError, match="uniformly spaced"):
        t2 = t.copy()
        t2[500:] += 1e-5
        identify_joint(t2, g, g, g, GEOM, frequency_hz=F0)
    with pytest.raises(ModelError, match="samples per period"):
        identify_joint(t, g, g, g, GEOM, frequency_hz=1000.0)
    with pytest.raises(ModelError, match="holds 10"):  # 2000 samples, 200 per period
        identify_joint(t, g, g, g, GEOM, frequency_hz=F0, periods=50)
    with pytest.raises(ModelError, match="gamma_b has 1999 samples"):
        identify_joint(t, g, g[:-1], g, GEOM, frequency_hz=F0)
    with pytest.raises(ModelError, match="kinematics"):
        identify_joint(t, g, g, g, GEOM, frequency_hz=F0, kinematics="linear")
    with pytest.raises(ModelError, match="finite"):
        bad = g.copy()
        bad[3] = np.nan
        identify_joint(t, bad, g, g, GEOM, frequency_hz=F0)
    with pytest.raises(ModelError, match="must differ"):
        JointRigGeometry(0.01, 0.01, 0.09, 0.09, 0.09, 0.4, 1e-3)
    with pytest.raises(ModelError, match="beam2_mass"):
        JointRigGeometry(-0.09, 0.0, 0.09, 0.09, 0.09, -0.4, 1e-3)
