"""Paper 003's damping strategy on the tie-boss wheel: free attenuation of the 2ND and 6ND
modes from the static deformation under modal forces, damping from the envelope.

Paper's results (003 section 3.2, Fig. 19): damping ratios from the logarithmic decrement
of the FEM envelopes "1.2 % for 2ND and 2.2 % for 6ND" at displacements up to 0.5 mm, the
6ND mode damped more than the 2ND one, an almost linear (Coulomb-like) decrease of the
amplitude, contacts in sliding and near-contact (open) states (Figs 17-18). The paper's
model is an 89,000-element ANSYS model of a rig whose dimensions it does not give; ours is
a beam model tuned to its Table 1, so the ratios are compared "to the order", within a
factor 1.5, and the qualitative findings exactly. Decay frequencies are compared with the
resonances of Table 2 measured with prestressed contacts (44.53 and 49.20 Hz) within 2 %.
"""

import numpy as np
import pytest
import scipy.io

from fricdamp.models.tieboss_wheel.model import build_sector, build_wheel, sector_from_cyclic
from fricdamp.models.tieboss_wheel.studies import (
    free_decay,
    initial_deformation,
    modal_by_nd,
    reduction_comparison,
)
from fricdamp.structure.io import read_sector

PAPER = {2: 0.012, 6: 0.022}
TABLE2_HZ = {2: 44.53, 6: 49.20}


@pytest.fixture(scope="module")
def sector():
    return build_sector(rotation=False)


@pytest.fixture(scope="module")
def wheel(sector):
    return build_wheel(sector, n_modes=10)


@pytest.fixture(scope="module")
def runs(wheel):
    return {nd: free_decay(wheel, nd, amplitude_m=5e-4, duration_s=0.1, dt=1e-5)
            for nd in (2, 6)}


def test_damping_ratios_of_the_order_of_the_paper_and_6nd_above_2nd(runs):
    for nd, r in runs.items():
        assert r.initial_amplitude_m == pytest.approx(5e-4, rel=0.01)
        assert PAPER[nd] / 1.5 < r.damping_ratio < PAPER[nd] * 1.5, (nd, r.damping_ratio)
        assert r.energy_balance_error < 1e-3
    assert runs[6].damping_ratio > 1.5 * runs[2].damping_ratio


def test_decay_is_coulomb_like_and_contacts_slide_and_open(runs):
    for nd, r in runs.items():
        assert r.decay.model == "coulomb"
        assert r.decay.mean_frequency_hz == pytest.approx(TABLE2_HZ[nd], rel=0.02)
        frac = r.summary()["state_fractions"]
        assert frac["slip"] > 0.3 and frac["open"] > 0.05 and frac["stick"] > 0.01


def test_amplitude_dependent_ratio_rises_as_the_amplitude_falls(wheel):
    """Dry friction: the equivalent ratio grows as the amplitude decays (~ 1 / A for a
    Coulomb decay, REFERENCES.md), seen cycle by cycle on the Hilbert envelope."""
    r = free_decay(wheel, 6, amplitude_m=5e-4, duration_s=0.25, dt=2e-5)
    a, z = r.amplitude_decay.amplitude, r.amplitude_decay.damping_ratio
    assert a.size >= 6
    assert np.corrcoef(a, z)[0, 1] < -0.8
    assert z[-1] > 1.5 * z[0]


def test_open_wheel_decay_gives_the_rayleigh_ratio(sector):
    """Contacts held open (a 4 mm gap): the wheel is linear and a pure-mode start (forcing
    "modal", static response phi / w^2) decays at the Rayleigh ratio a / 2w + b w / 2 of
    the ND frequency: the whole identification chain against a closed form, to 1 % (peak
    interpolation and the 0.1 s record). With the paper's tie-boss point forces the higher
    modes of the same ND beat in the probe and bias the 0.1 s log decrement upwards."""
    import dataclasses

    p = sector.parameters.with_(contact_offset_m=-4e-3)
    w = build_wheel(dataclasses.replace(sector, parameters=p), n_modes=6)
    a, b = p.rayleigh()
    for nd in (2, 6):
        r = free_decay(w, nd, amplitude_m=5e-4, duration_s=0.1, dt=2e-5, forcing="modal")
        om = 2 * np.pi * r.decay.mean_frequency_hz
        assert r.damping_ratio == pytest.approx(a / (2 * om) + b * om / 2, rel=0.01)
        assert (r.contact_status == 0).all()
    paper_way = free_decay(w, 2, amplitude_m=5e-4, duration_s=0.1, dt=2e-5)
    assert paper_way.damping_ratio > 1.2 * (a / (2 * om) + b * om / 2)


def test_friction_is_the_damping_mechanism(sector):
    """mu = 0 (contacts only push and separate): the ratio falls to ~0.13 %, the Rayleigh
    0.1 % plus what the normal impacts hand to the strongly damped high modes; with the
    paper's friction it is 7 to 15 times larger."""
    import dataclasses

    p = sector.parameters.with_(mu_static=0.0, mu_sliding=0.0)
    w = build_wheel(dataclasses.replace(sector, parameters=p), n_modes=6)
    r = free_decay(w, 6, amplitude_m=5e-4, duration_s=0.1, dt=2e-5, forcing="modal")
    assert 0.9e-3 < r.damping_ratio < 1.6e-3
    wf = build_wheel(sector, n_modes=6)
    rf = free_decay(wf, 6, amplitude_m=5e-4, duration_s=0.1, dt=2e-5, forcing="modal")
    assert rf.damping_ratio > 7 * r.damping_ratio


def test_time_step_converged(wheel):
    """dt = 1e-5 s (2200 steps per period) against 5e-6 s (the paper's step): < 0.5 %."""
    init = initial_deformation(wheel, 2, 5e-4)
    z = [free_decay(wheel, 2, dt=dt, duration_s=0.1, initial=init).damping_ratio
         for dt in (1e-5, 5e-6)]
    assert z[0] == pytest.approx(z[1], rel=5e-3)


def test_user_sector_from_matrix_market_runs_the_same_pipeline(sector, tmp_path):
    """Write the sector's M and K as Matrix Market files, read them back with read_sector
    naming the contact nodes, and run the modal and decay pipeline: same results as the
    built-in sector (to rounding of the 17-digit files)."""
    cyc = sector.cyclic
    scipy.io.mmwrite(str(tmp_path / "M.mtx"), cyc.M, precision=17, symmetry="symmetric")
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), cyc.K, precision=17, symmetry="symmetric")
    named = {k: list(cyc.named_dofs[k]) for k in ("contact_left", "contact_right", "tieboss",
                                                    "probe")}
    user = read_sector(M=tmp_path / "M.mtx", K=tmp_path / "K.mtx", n_sectors=30,
                       left_dofs=cyc.left, right_dofs=cyc.right, named_dofs=named,
                       frame="cartesian", axis="z", name="user sector")
    ts = sector_from_cyclic(user, sector.frame, sector.parameters,
                            flexural_direction=sector.flexural_direction)
    f_user = modal_by_nd(ts)["frequency_hz"]
    np.testing.assert_allclose(f_user, modal_by_nd(sector)["frequency_hz"], rtol=1e-10)
    a = free_decay(build_wheel(ts, n_modes=4), 2, duration_s=0.02, dt=2e-5)
    b = free_decay(build_wheel(sector, n_modes=4), 2, duration_s=0.02, dt=2e-5)
    np.testing.assert_allclose(a.signal, b.signal, rtol=0, atol=1e-9 * 5e-4)


@pytest.mark.slow
def test_reduced_matches_full_order(sector):
    """Craig-Bampton wheel (10 fixed-interface modes per sector, 750 DOFs, compiled path)
    against the full-order wheel (2880 DOFs, general simulate): damping ratios within 5 %
    (the issue's target; measured 0.2 %) and probe histories within 1 % of the amplitude."""
    r = reduction_comparison(sector.parameters, nd=2, n_modes=10, duration_s=0.06, dt=2e-5)
    assert r["full_dof"] == 2880 and r["reduced_dof"] == 750
    assert r["damping_ratio_difference"] < 0.05
    assert r["max_signal_difference"] < 0.01
    assert r["speed_ratio"] > 1.0
