"""Closed-loop validation of the identification's verdict (issue 16, paper 002 part).

The rig (002 (1)-(10), (A.2)) with paper 002's rough joint (Table 2, 100 N) is simulated at
30 Hz; its accelerometers are sampled (exact kinematics) with white noise, and the pipeline's
95 % interval and status are compared with the joint model's own loop energy over the same
periods. Requirements (issue 16): a 1 %-noise micro-slip record either lands within its
stated interval or is flagged; a clean gross-slip record is not flagged. Measured (default
uncertainties: 0.5 mm, 0.5 %, 1 us, the record's noise): micro-slip at 1 N is flagged
(interval ~+-1000 % of E_d, sensitivity the largest source) and holds the model's energy;
gross slip at 5 N is ok, +-5 % wide, and holds it.
"""

import numpy as np
import pytest

from fricdamp.models.rotational_joint.model import RotationalJointRig, paper002_joint
from fricdamp.signals.identify import MeasurementUncertainty, identify_joint

PERIODS, SPP = 24, 200


@pytest.fixture(scope="module")
def rig():
    return RotationalJointRig(paper002_joint())


@pytest.fixture(scope="module")
def responses(rig):
    return {f: rig.simulate(f, periods=PERIODS, steps_per_period=SPP) for f in (1.0, 5.0)}


def _identify(rig, res, noise, seed, **kw):
    tab = res.accelerometers(noise=noise, seed=seed)
    ident = identify_joint(tab["time"], tab["A"], tab["B"], tab["C"], rig.params.geometry(),
                           frequency_hz=30.0, **kw)
    return ident, res.dissipated_energy(ident.n_periods)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_micro_slip_with_one_percent_noise_is_flagged_or_within(rig, responses, seed):
    ident, e_model = _identify(rig, responses[1.0], 0.01, seed)
    lo, hi = ident.trust.energy_interval
    assert lo <= e_model <= hi or ident.status == "unreliable"
    # what happens in fact: both (the interval is honest, and far too wide to be used)
    assert ident.status == "unreliable" and lo <= e_model <= hi
    assert ident.trust.block_scatter > 0.1
    assert ident.trust.conditioning["joint_to_beam_rotation"] < 0.01


def test_clean_gross_slip_is_not_flagged(rig, responses):
    ident, e_model = _identify(rig, responses[5.0], 0.0, 0)
    lo, hi = ident.trust.energy_interval
    assert ident.status == "ok", ident.warnings
    assert lo <= e_model <= hi and ident.trust.relative_width < 0.2
    assert ident.skipped_periods >= 3  # the 3-period force ramp is the start-up transient
    xlo, xhi = ident.trust.damping_ratio_interval
    assert xlo <= ident.damping_ratio <= xhi


def test_noise_interval_coverage(rig, responses):
    """Noise alone (no calibration errors), 5 % of each channel's RMS, 20 records: the 95 %
    interval holds the model's energy in >= 17 of 20 (binomial: P(<= 16 | 0.95) = 1.6 %).
    Measured 93-95 % on 100 records."""
    unc = MeasurementUncertainty(position_std_m=0.0, sensitivity_std=0.0, delay_std_s=0.0)
    hits = 0
    for seed in range(20):
        ident, e_model = _identify(rig, responses[5.0], 0.05, 100 + seed, uncertainty=unc)
        lo, hi = ident.trust.energy_interval
        hits += lo <= e_model <= hi
    assert hits >= 17


def test_energy_based_damping_ratio_ignores_rate_and_harmonics(rig):
    """Gross slip (5 N): paper 002's xi from peak-to-peak values drops by ~16 % when only 5
    harmonics are kept; xi_E = E_d / (pi Theta_1 M_1) moves by < 0.2 % over 480 and 240
    samples per period and 5, 10 or all harmonics (the energy itself by < 0.2 %)."""
    res = rig.simulate(5.0, periods=16, steps_per_period=480)
    tab = res.accelerometers()
    geom = rig.params.geometry()
    xi, xi_e = {}, {}
    for dec in (1, 2):
        for nh in (None, 10, 5):
            s = slice(None, None, dec)
            i = identify_joint(tab["time"][s], tab["A"][s], tab["B"][s], tab["C"][s], geom,
                               frequency_hz=30.0, n_harmonics=nh, diagnostics=False)
            xi[dec, nh], xi_e[dec, nh] = i.damping_ratio, i.damping_ratio_energy
    e = np.array(list(xi_e.values()))
    assert np.ptp(e) / np.mean(e) < 2e-3
    assert xi[1, 5] / xi[1, None] < 0.9
