"""Unit checks of rough.py: F_n(h) routes, GW input checks, height classes, joint protocol."""

import numpy as np
import pytest
from scipy.special import erfc

from fricdamp.contact.mindlin import RotationalMindlin
from fricdamp.contact.rough import (
    GreenwoodWilliamson,
    RoughRotationalJoint,
    gw_integral,
    height_classes,
)
from fricdamp.errors import ModelError

GW_ARGS = dict(summit_density=2e9, nominal_area=5.04e-4, summit_radius=50e-6,
               summit_std=0.45e-6, E_star=115.4e9)


# ----------------------------------------------------------------------------- F_n(h)
def test_gw_integral_shapes_and_limits():
    assert isinstance(gw_integral(1.5, 0.3), float)
    h = np.linspace(-3, 3, 6).reshape(2, 3)
    assert gw_integral(1.5, h).shape == (2, 3)
    assert gw_integral(1.5, np.inf) == 0.0
    assert gw_integral(1.5, 60.0) == 0.0  # underflow, not nan
    # h -> -inf: F_n(h) ~ |h|^n (1 + n(n-1)/(2 h^2)); at h = -30 to 1e-6
    assert gw_integral(1.5, -30.0) == pytest.approx(30**1.5 * (1 + 0.375 / 900), rel=1e-6)


@pytest.mark.parametrize("h0", [4.0, -10.0])
def test_gw_integral_continuous_across_route_switches(h0):
    """Switch points between pbdv and the quadratures: F_0 there is the exact Q(h)."""
    h = np.array([np.nextafter(h0, -np.inf), h0, np.nextafter(h0, np.inf)])
    np.testing.assert_allclose(gw_integral(0.0, h), 0.5 * erfc(h / np.sqrt(2)), rtol=1e-10)
    f = gw_integral(1.5, h)
    assert abs(f[0] / f[2] - 1) < 1e-10


@pytest.mark.parametrize("n, h, word", [(-1.0, 0.0, "n"), (np.nan, 0.0, "n"),
                                        (1.5, np.nan, "h"), (1.5, -np.inf, "h")])
def test_gw_integral_bad_input(n, h, word):
    with pytest.raises(ModelError, match=word):
        gw_integral(n, h)


# ----------------------------------------------------------------------------- GW
@pytest.mark.parametrize("name", list(GW_ARGS))
def test_gw_parameters_checked(name):
    with pytest.raises(ModelError, match=name):
        GreenwoodWilliamson(**{**GW_ARGS, name: -1.0})
    with pytest.raises(ModelError, match=name):
        GreenwoodWilliamson(**{**GW_ARGS, name: [1.0, 2.0]})


def test_separation_for_load_errors():
    gw = GreenwoodWilliamson(**GW_ARGS)
    for bad in (0.0, -5.0, [1.0, 0.0]):
        with pytest.raises(ModelError, match="load must be > 0"):
            gw.separation_for_load(bad)
    with pytest.raises(ModelError, match="too small"):
        gw.separation_for_load(1e-320)
    with pytest.raises(ModelError, match="too large"):
        gw.separation_for_load(1e30)
    assert isinstance(gw.separation_for_load(10.0), float)
    assert gw.separation_for_load(np.array([[10.0, 20.0]])).shape == (1, 2)


def test_gw_load_scale_at_zero_separation():
    gw = GreenwoodWilliamson(**GW_ARGS)
    assert gw.load(0.0) == pytest.approx(gw.load_scale * 0.4300199936622599, rel=1e-12)


# ----------------------------------------------------------------------------- height classes
@pytest.mark.parametrize("h", [-2.0, 0.0, 3.0, 8.0])
def test_height_classes_moments(h):
    """Spectral for y^(3/2), y^(1/2), y^(-1/2) (weight y^-1/2); algebraic for the count."""
    y, p = height_classes(h, 24)
    assert np.all(y > 0) and np.all(p > 0)
    for n in (1.5, 0.5, -0.5):
        assert np.sum(p * y**n) == pytest.approx(gw_integral(n, h), rel=1e-9)
    assert np.sum(p) == pytest.approx(gw_integral(0.0, h), rel=2e-2)
    with pytest.raises(ModelError, match="n_heights"):
        height_classes(h, 1)


# ----------------------------------------------------------------------------- joint
@pytest.fixture(scope="module")
def small_joint():
    return RoughRotationalJoint.paper_002(n_cells=(6, 4), n_heights=10)


def test_joint_bad_parameters():
    with pytest.raises(ModelError, match="n_cells"):
        RoughRotationalJoint.paper_002(n_cells=(0, 3))
    with pytest.raises(ModelError, match="hole_radius"):
        RoughRotationalJoint.paper_002(hole_radius=1.0)
    with pytest.raises(ModelError, match="preload"):
        RoughRotationalJoint.paper_002(preload=0.0)
    with pytest.raises(ModelError, match="unknown"):
        RoughRotationalJoint.paper_002(sigma=1e-6)
    with pytest.raises(ModelError, match="axis"):
        RoughRotationalJoint.paper_002(axis=(0.0, 0.0, 1.0))


def test_paper_002_defaults():
    j = RoughRotationalJoint.paper_002(n_cells=(4, 4), n_heights=8)
    assert j.gw.summit_std == 0.45e-6 and j.asperities.mu[0] == 0.15
    assert j.gw.nominal_area == pytest.approx(28e-3 * 18e-3, rel=1e-14)
    assert j.preload == 100.0
    assert j.gw.E_star == pytest.approx(210e9 / (2 * (1 - 0.09)), rel=1e-14)


def test_joint_merges_symmetric_cells_without_changing_totals():
    """Cells at equal radius are merged; an off-centre axis (no symmetry) keeps all cells.
    Totals that do not depend on r agree exactly; the merged sum over r matches the cells."""
    centred = RoughRotationalJoint.paper_002(n_cells=(6, 4), n_heights=6)
    shifted = RoughRotationalJoint.paper_002(n_cells=(6, 4), n_heights=6, axis=(1e-3, 0.3e-3))
    assert centred.asperities.n_contacts == 6 * 6  # 24 cells -> 6 radii (4-fold symmetry)
    assert shifted.asperities.n_contacts == 24 * 6
    assert centred.total_normal_load == pytest.approx(shifted.total_normal_load, rel=1e-13)
    for j in (centred, shifted):  # M_s = mu (sum N / A_n) sum A_c r_c: uniform pressure
        ms = j.asperities.mu[0] * j.total_normal_load / j.gw.nominal_area * j.cell_area
        assert j.slip_moment == pytest.approx(ms * j.cell_radius.sum(), rel=1e-12)


def test_hole_removes_area_and_keeps_preload():
    j = RoughRotationalJoint.paper_002(n_cells=(14, 9), n_heights=16, hole_radius=4e-3)
    assert j.cell_radius.min() >= 4e-3
    assert j.gw.nominal_area == pytest.approx(j.cell_area * j.cell_radius.size, rel=1e-14)
    assert j.gw.nominal_area < 28e-3 * 18e-3
    assert j.total_normal_load == pytest.approx(100.0, rel=1e-9)  # 16 classes: ~1e-11


def test_joint_step_matches_march_and_sum_of_asperities(small_joint):
    j = small_joint
    th = 3e-6 * np.sin(np.linspace(0, 3 * np.pi, 120)) * np.linspace(1.0, 0.3, 120)
    m_march, st_march = j.march(th[:, None, None])
    st = j.initial_state()
    for i, t in enumerate(th):
        r = j.step(st, [t])
        st = r.state
        assert r.force[0, 0] == pytest.approx(m_march[i, 0, 0], rel=1e-12, abs=1e-18)
    np.testing.assert_array_equal(st, st_march)
    # the same as the RotationalMindlin contacts driven individually and summed
    a = j.asperities
    solo = RotationalMindlin(a.mu, a.normal_load, a.contact_radius, a.compliance, a.arm,
                             multiplicity=a.multiplicity)
    f = solo.drive(np.repeat(th[:, None], a.n_contacts, axis=1))
    np.testing.assert_allclose(f.sum(axis=1), m_march[:, 0, 0], rtol=1e-12,
                               atol=1e-15 * j.slip_moment)


@pytest.mark.parametrize("theta0", [2e-7, 2e-6])
def test_joint_tangent_matches_finite_difference(small_joint, theta0):
    j = small_joint
    st = j.step(j.initial_state(), [1.5 * theta0]).state  # load, then unload towards theta0
    r = j.step(st, [theta0])
    h = 1e-6 * theta0
    fd = (j.step(st, [theta0 + h]).force - j.step(st, [theta0 - h]).force) / (2 * h)
    # summits whose branch ends within +-h (kinks) would spoil the difference: the classes'
    # kinks are at isolated theta, and 1e-6 steps avoid them; central FD error ~1e-10
    assert r.stiffness[0, 0, 0] == pytest.approx(fd[0, 0], rel=1e-6)


def test_joint_energy_balance_non_negative_dissipation(small_joint):
    j = small_joint
    th = np.concatenate([np.linspace(0, 4e-6, 300), np.linspace(4e-6, -1e-6, 300)[1:],
                         np.linspace(-1e-6, 2e-6, 300)[1:]])
    st = j.initial_state()
    m = np.zeros_like(th)
    e = np.zeros_like(th)
    for i in range(1, th.size):
        r = j.step(st, [th[i]])
        st = r.state
        m[i] = r.force[0, 0]
        e[i] = j.stored_energy(st, [th[i]])[0]
    work = np.concatenate([[0.0], np.cumsum(0.5 * (m[1:] + m[:-1]) * np.diff(th))])
    diss = work - e
    scale = j.slip_moment * 4e-6
    assert np.diff(diss).min() > -1e-8 * scale  # trapezoid error of the work per step
    assert diss[-1] > 0
