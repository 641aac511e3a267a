"""Tie-boss wheel, paper 003: open-contact modes by ND (Table 1), cyclic vs full assembly,
Campbell diagram and critical speeds (Table 2, eq. (1)), prestress of 2.4 N.

Tolerances: Table 1 within 1 % (the issue's acceptance; the tuned model errs <= 0.52 %);
cyclic and full-assembly frequencies to 1e-7 relative (two eigen-solvers on the same
matrices; ARPACK converges to ~1e-10); critical speeds within 2 % of Table 2 (the paper's
f_R come from the experiment with prestressed contacts, ours from the open-contact model,
whose 2ND/6ND frequencies differ from them by 1.5 %/0.8 %).
"""

import numpy as np
import pytest

from fricdamp.models.tieboss_wheel.model import (
    TABLE1_FEM_HZ,
    build_sector,
    build_wheel,
    calibrate_normal_stiffness,
    prestress_normal_force,
    table1_targets,
)
from fricdamp.models.tieboss_wheel.studies import (
    campbell_by_nd,
    critical_speeds_by_nd,
    full_wheel_frequencies,
    modal_by_nd,
)
from fricdamp.structure.cyclic import full_spectrum


@pytest.fixture(scope="module")
def sector():
    return build_sector()


def test_table1_open_contact_frequencies_within_1_percent(sector):
    res = modal_by_nd(sector)
    f = np.asarray(res["frequency_hz"])
    assert res["nd"] == list(range(16))
    for nd, pair in TABLE1_FEM_HZ.items():
        assert f[nd] == pytest.approx(np.mean(pair), rel=0.01), nd
    assert res["max_table1_error"] < 0.01
    # monotone rise with ND towards the clamped-blade limit (003 section 2.2)
    assert (np.diff(f[1:]) > 0).all()
    assert f[15] - f[14] < 0.05


def test_cyclic_equals_full_assembly(sector):
    """Both give the same frequencies: the 30 lowest modes of the assembled open-contact
    wheel (2880 DOFs) are the first family by ND with multiplicities 1 (0ND, 15ND), 2."""
    wheel = build_wheel(sector)
    by_nd = np.array(modal_by_nd(sector)["frequency_hz"])[:, None]
    expected = full_spectrum(by_nd, 30)
    np.testing.assert_allclose(full_wheel_frequencies(wheel), expected, rtol=1e-7)


def test_campbell_stress_stiffening_and_critical_speeds(sector):
    """Frequencies rise with speed by at most ~1.5 Hz up to 450 rpm (003 section 2.3: "the
    eigenfrequencies of the wheel change very slightly (up to 1.5 Hz)"); the crossings of the
    2ND and 6ND branches with the o = 1 and o = 3 lines of p = 8 pulses are 334 and 123 rpm
    within 2 %, and satisfy s = 60 f_R / (p o) exactly (003 (1))."""
    c = campbell_by_nd(sector, rpm=[0.0, 200.0, 450.0], nds=[2, 6, 15])
    rise = c.frequency_hz[-1] - c.frequency_hz[0]
    assert (np.diff(c.frequency_hz, axis=0) > 0).all()
    assert (rise > 0.5).all() and (rise < 1.6).all()
    crit = critical_speeds_by_nd(sector)
    for entry in crit:
        assert entry["rpm"] == pytest.approx(entry["paper_rpm"], rel=0.02)
        assert entry["paper_formula_rpm"] == pytest.approx(entry["paper_rpm"], abs=0.5)
        assert entry["rpm"] == pytest.approx(60 * entry["frequency_hz"] / (8 * entry["order"]),
                                             rel=1e-12)
    assert [e["nd"] for e in crit] == [2, 6]


def test_prestress_from_the_offset_is_2_4_N():
    """003 section 2.4: the offset 1e-5 m gives 2.4 N of normal force in the wheel; the
    default penalty is the calibrated one (to 0.5 %), and calibration reproduces it."""
    wheel = build_wheel()
    assert prestress_normal_force(wheel) == pytest.approx(2.4, rel=5e-3)
    kn = calibrate_normal_stiffness()
    assert kn == pytest.approx(wheel.parameters.normal_stiffness_N_per_m, rel=5e-3)


def test_table1_targets_are_pair_means():
    tg = table1_targets()
    assert tg[2] == pytest.approx(44.355) and tg[15] == 50.3
