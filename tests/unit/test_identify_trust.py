"""Diagnostics of the joint identification (fricdamp.signals._identify_trust).

Signals are exact readings of a prescribed periodic motion (as in test_identify.py), so the
true loop is known. The Monte Carlo is checked against first-order propagation (finite
differences of the pipeline with respect to each channel's gain, delay and each sensor's
position), the conditioning against the prescribed amplitudes, the block scatter and the
verdict against records made to fail.
"""

import dataclasses

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.signals.energy import loop_area
from fricdamp.signals.identify import (
    JointRigGeometry,
    MeasurementUncertainty,
    TrustThresholds,
    identify_joint,
    joint_torque,
)

GEOM = JointRigGeometry(sensor_a=-0.09, sensor_b=0.0, joint_arm1=0.091, sensor_c=0.09,
                        joint_arm2=0.091, beam2_mass=0.44, beam2_inertia=1.55e-3)
F0 = 30.0
W = 2 * np.pi * F0
#: (amplitude, harmonic, phase) of theta1, theta2, x1 (x 1e-3): the joint rotation
#: theta1 - theta2 has a fundamental of |1 - 0.7 exp(-0.25 i)| = 0.3906e-3 rad
COMPS = [[(1.0, 1, 0.0), (0.08, 3, 0.7)],
         [(0.7, 1, -0.25), (0.05, 2, 1.1), (0.02, 5, -0.4)],
         [(0.15, 1, 0.3), (0.01, 3, 0.2)]]


def motion(t, comps=COMPS, scale=1e-3):
    out = np.zeros((3, 3, t.size))
    for i, cs in enumerate(comps):
        for amp, k, ph in cs:
            a = scale * amp
            out[i, 0] += a * np.sin(k * W * t + ph)
            out[i, 1] += a * k * W * np.cos(k * W * t + ph)
            out[i, 2] -= a * (k * W) ** 2 * np.sin(k * W * t + ph)
    return out


def readings(st, geom=GEOM):
    (t1, w1, a1), (t2, _, a2), (_, _, ax) = st
    rel = t1 - t2
    ga = ax * np.cos(t1) + geom.sensor_a * a1
    gb = ax * np.cos(t1) + geom.sensor_b * a1
    gc = (ax * np.cos(t2) + geom.joint_arm1 * (a1 * np.cos(rel) - w1 ** 2 * np.sin(rel))
          + (geom.sensor_c + geom.joint_arm2) * a2)
    return ga, gb, gc


def true_energy(t, n_per):
    (t1, w1, a1), (t2, _, a2), (_, _, ax) = motion(t)
    return loop_area(t1 - t2, joint_torque(GEOM, t1, t2, w1, a1, a2, ax)) / n_per


N_PER, SPP = 15, 128
T = np.arange(N_PER * SPP) / (F0 * SPP)
SIGNALS = readings(motion(T))


def test_clean_record_is_ok_and_its_interval_holds_the_truth():
    res = identify_joint(T, *SIGNALS, GEOM, frequency_hz=F0)
    tr = res.trust
    e = true_energy(T, N_PER)
    assert res.status == "ok" and tr.reliable and not res.warnings
    lo, hi = tr.energy_interval
    assert lo < e < hi and lo > 0
    assert tr.relative_width == pytest.approx((hi - lo) / res.dissipated_energy)
    assert tr.block_energies.size == 5 and tr.block_scatter < 1e-9
    assert np.all(tr.noise_std < 1e-9 * np.std(SIGNALS[0]))
    # conditioning: the prescribed fundamentals (tolerance: O(theta^2) kinematics)
    ratio = abs(1 - 0.7 * np.exp(-0.25j))
    assert tr.conditioning["joint_to_beam_rotation"] == pytest.approx(ratio, rel=1e-4)
    assert tr.conditioning["amplification"] == pytest.approx(1 / ratio, rel=1e-4)
    d = res.to_dict()
    assert d["confidence_95"]["dissipated_energy_J"] == [lo, hi]
    assert d["status"] == "ok" and d["warnings"] == []
    assert set(d["confidence_contributions"]) == {"noise", "position", "sensitivity", "delay"}


def _pipeline_energy(gains=(1, 1, 1), delays=(0, 0, 0), positions=None):
    geom = GEOM if positions is None else dataclasses.replace(
        GEOM, sensor_a=positions[0], sensor_b=positions[1], sensor_c=positions[2])
    chans = [g * readings(motion(T - d))[j] for j, (g, d) in enumerate(zip(gains, delays,
                                                                           strict=True))]
    return identify_joint(T, *chans, geom, frequency_hz=F0, diagnostics=False,
                          skip_periods=0).dissipated_energy


@pytest.mark.parametrize("source, std, step", [("sensitivity", 1e-4, 1e-6),
                                               ("delay", 2e-7, 1e-8),
                                               ("position", 5e-5, 1e-7)])
def test_monte_carlo_matches_first_order_propagation(source, std, step):
    """Small uncertainties: the 95 % half-width is 1.96 sigma of the linearised E_d,
    sigma^2 = sum_c (dE/dp_c)^2 std^2 (central differences). Tolerance 8 %: the Monte Carlo's
    quantiles from 1000 draws are good to ~3-4 %."""
    grads = []
    for c in range(3):
        if source == "sensitivity":
            up = _pipeline_energy(gains=[1 + step * (j == c) for j in range(3)])
            dn = _pipeline_energy(gains=[1 - step * (j == c) for j in range(3)])
        elif source == "delay":
            up = _pipeline_energy(delays=[step * (j == c) for j in range(3)])
            dn = _pipeline_energy(delays=[-step * (j == c) for j in range(3)])
        else:
            base = np.array([GEOM.sensor_a, GEOM.sensor_b, GEOM.sensor_c])
            # the pipeline's position is perturbed, not the sensor's: same spread
            up = _pipeline_energy(positions=base + step * (np.arange(3) == c))
            dn = _pipeline_energy(positions=base - step * (np.arange(3) == c))
        grads.append((up - dn) / (2 * step))
    sigma = std * np.sqrt(np.sum(np.square(grads)))
    unc = MeasurementUncertainty(position_std_m=std if source == "position" else 0,
                                 sensitivity_std=std if source == "sensitivity" else 0,
                                 delay_std_s=std if source == "delay" else 0, noise=False)
    res = identify_joint(T, *SIGNALS, GEOM, frequency_hz=F0, uncertainty=unc, skip_periods=0)
    lo, hi = res.trust.energy_interval
    assert 0.5 * (hi - lo) == pytest.approx(1.96 * sigma, rel=0.08)
    assert res.trust.contributions[source] == pytest.approx(
        1.96 * sigma / res.dissipated_energy, rel=0.15)


def test_noise_level_is_estimated_between_the_harmonics():
    rng = np.random.default_rng(3)
    sd = np.array([0.02, 0.05, 0.01])
    noisy = [x + s * rng.standard_normal(x.size) for x, s in zip(SIGNALS, sd, strict=True)]
    res = identify_joint(T, *noisy, GEOM, frequency_hz=F0)
    np.testing.assert_allclose(res.trust.noise_std, sd, rtol=0.1)  # median of 940 bins


def test_ill_conditioned_noisy_record_is_flagged():
    """The beams rotate almost together (joint rotation 0.5 % of theirs) and the sensors
    carry 3 % noise: blocks disagree, the interval is wide, exit status unreliable."""
    comps = [c[:] for c in COMPS]
    comps[1] = [(0.995, 1, -0.004)]
    st = motion(T, comps)
    rng = np.random.default_rng(0)
    sig = [x + 3e-2 * np.std(x) * rng.standard_normal(x.size) for x in readings(st)]
    res = identify_joint(T, *sig, GEOM, frequency_hz=F0)
    tr = res.trust
    assert res.status == "unreliable"
    assert tr.conditioning["joint_to_beam_rotation"] < 0.01
    assert any("ill-conditioned" in w for w in res.warnings)
    assert tr.block_scatter > 0.1 and any("separate blocks" in w for w in res.warnings)
    assert tr.relative_width > 0.2


def test_thresholds_and_short_records():
    # a generous threshold turns a flagged result into an ok one; a strict one the reverse
    strict = identify_joint(T, *SIGNALS, GEOM, frequency_hz=F0,
                            thresholds=TrustThresholds(max_relative_width=1e-4))
    assert strict.status == "unreliable" and "limit 0.01 %" in strict.warnings[0]
    short = identify_joint(T[:6 * SPP], *(x[:6 * SPP] for x in SIGNALS), GEOM,
                           frequency_hz=F0)
    assert short.trust.block_energies.size == 2
    assert any("only 2 block(s)" in w for w in short.warnings)
    unchecked = identify_joint(T, *SIGNALS, GEOM, frequency_hz=F0, diagnostics=False)
    assert unchecked.trust is None and unchecked.status == "unchecked"


@pytest.mark.parametrize("kwargs, word", [
    ({"position_std_m": -1e-3}, "position_std_m"),
    ({"sensitivity_std": np.nan}, "sensitivity_std"),
    ({"samples": 5}, "samples"),
])
def test_bad_uncertainties_are_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        MeasurementUncertainty(**kwargs)


@pytest.mark.parametrize("kwargs, word", [
    ({"max_relative_width": 0.0}, "max_relative_width"),
    ({"block_periods": 0}, "block_periods"),
    ({"min_blocks": 1}, "min_blocks"),
])
def test_bad_thresholds_are_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        TrustThresholds(**kwargs)
