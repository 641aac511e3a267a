"""Unilateral normal contacts of the event-driven solver: input checks, impact law, and the
bilateral behaviour kept when release is off (fricdamp.solvers.event_impact)."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.solvers.event import simulate_events
from fricdamp.solvers.event_system import ConstrainedSystem


class PointMassOnStop(ConstrainedSystem):
    """Point mass (x, y) above a rigid stop y = 0 under gravity ``g`` and the loads
    ``(fx, -f0 + f1 cos(w t))``; one contact (gap y, tangent x), optionally unilateral."""

    n_dof = 2
    n_contacts = 1
    constant_mass = True

    def __init__(self, m=1.0, g=9.81, e=0.5, mu=0.0, fx=0.0, f0=0.0, f1=0.0, w=0.0,
                 unilateral=True):
        self.m, self.g, self.e = m, g, e
        self.fx, self.f0, self.f1, self.w = fx, f0, f1, w
        self.mu_static = np.array([mu])
        self.mu_sliding = np.array([mu])
        self.normal_constrained = np.array([True])
        self._uni = unilateral

    def unilateral_contacts(self):
        return np.array([self._uni])

    def restitution_coefficients(self):
        return np.array([self.e])

    def mass(self, q):
        return self.m * np.eye(2)

    def _load(self, t):
        return np.array([self.fx, -self.f0 + self.f1 * np.cos(self.w * t)])

    def h(self, t, q, qd):
        return self._load(t) - np.array([0.0, self.m * self.g])

    def tangent_jacobian(self, q):
        return np.array([[1.0], [0.0]])

    def tangent_wbar(self, q, qd):
        return np.zeros(1)

    def normal_gap(self, q):
        return np.array([q[1]])

    def normal_jacobian(self, q):
        return np.array([[0.0], [1.0]])

    def normal_wbar(self, q, qd):
        return np.zeros(1)

    def potential_energy(self, q):
        return self.m * self.g * q[1]

    def input_power(self, t, q, qd):
        return float(self._load(t) @ qd)

    def viscous_power(self, t, q, qd):
        return 0.0

    def max_frequency(self):
        return self.w


@pytest.mark.parametrize("e", [-0.1, 1.5, np.nan])
def test_restitution_outside_unit_interval_is_refused(e):
    with pytest.raises(ModelError, match=r"restitution coefficients must be 1 values in \[0, 1\]"):
        simulate_events(PointMassOnStop(e=e), (0.0, 0.1), [0, 0.1, 0, 0], progress=False)


def test_bad_unilateral_input_is_refused():
    s = PointMassOnStop()
    s.normal_constrained = np.array([False])
    with pytest.raises(ModelError, match="unilateral contact needs a constrained normal"):
        simulate_events(s, (0.0, 0.1), [0, 0.1, 0, 0], progress=False)
    with pytest.raises(ModelError, match="method='exact' does not handle unilateral"):
        simulate_events(PointMassOnStop(), (0.0, 0.1), [0, 0.1, 0, 0], method="exact",
                        progress=False)
    with pytest.raises(ModelError, match="penetrates unilateral contact 0"):
        simulate_events(PointMassOnStop(), (0.0, 0.1), [0, -1e-3, 0, 0], progress=False)
    with pytest.raises(ModelError, match="zeno_velocity must be >= 0"):
        simulate_events(PointMassOnStop(), (0.0, 0.1), [0, 0.1, 0, 0], zeno_velocity=-1.0,
                        progress=False)


def test_single_impact_obeys_newtons_law():
    """One impact at v = -2 m/s: v+ = -e v-, impulse m (1 + e) |v-|, loss (1 - e^2) m v^2 / 2
    (to 1e-9: the impact state comes from the dense output at rtol 1e-12)."""
    e, m, v = 0.7, 2.0, 2.0
    s = PointMassOnStop(m=m, g=0.0, e=e)
    r = simulate_events(s, (0.0, 0.1), [0, 0.05, 0.3, -v], rtol=1e-12, progress=False)
    (im,) = r.impacts
    assert im.time == pytest.approx(0.025, rel=1e-12)
    assert im.velocity_before[0] == pytest.approx(-v, rel=1e-12)
    assert im.velocity_after[0] == pytest.approx(e * v, rel=1e-12)
    assert im.impulse[0] == pytest.approx(m * (1 + e) * v, rel=1e-12)
    assert im.energy_loss == pytest.approx(0.5 * (1 - e**2) * m * v**2, rel=1e-9)
    assert r.energy["impact_loss"][-1] == pytest.approx(im.energy_loss, rel=1e-12)
    assert r.qd[-1, 0] == pytest.approx(0.3, rel=1e-12)  # frictionless impulse: x' unchanged
    assert r.energy_balance_error < 1e-10
    assert [(ev.kind, ev.to_mode) for ev in r.events] == [("impact", "open")]


def test_perfectly_elastic_bounces_keep_the_energy():
    """e = 1: every bounce returns to the drop height, no energy is lost (1e-9 relative)."""
    s = PointMassOnStop(e=1.0)
    r = simulate_events(s, (0.0, 2.0), [0, 0.5, 0, 0], t_eval=np.linspace(0, 2, 4001),
                        progress=False)
    assert len(r.impacts) == 3
    assert r.energy["impact_loss"][-1] == pytest.approx(0.0, abs=1e-12)
    assert r.q[:, 1].max() == pytest.approx(0.5, rel=1e-12)
    tk = np.sqrt(2 * 0.5 / 9.81)
    assert np.allclose(r.impact_times(), tk * np.array([1, 3, 5]), rtol=1e-10)
    assert r.energy_balance_error < 1e-9


def test_release_off_keeps_the_bilateral_contact(caplog):
    """With unilateral contacts off, a mass pulled off its stop stays on it: the normal force
    turns tensile (reported), no lift-off, and the run is the one of before."""
    w = 2 * np.pi * 10.0
    s = PointMassOnStop(e=0.0, f0=5.0, f1=30.0, w=w, unilateral=False)
    t0 = np.pi / (2 * w)
    with caplog.at_level(logging.WARNING, logger="fricdamp.solvers.event"):
        r = simulate_events(s, (t0, t0 + 2 * np.pi / w), [0, 0, 0, 0], progress=False)
    assert "would separate" in caplog.text
    assert r.lambda_N.min() < 0 and not r.impacts and r.lift_off_times().size == 0
    assert np.all(r.q[:, 1] == 0.0) and np.all(r.modes != 3)
    assert set(r.energy) >= {"impact_loss"} and np.all(r.energy["impact_loss"] == 0.0)


def test_flow_monodromy_through_one_bounce():
    """Shooting's flow through one impact of a ball (h0 = 0.5 m, v0 = 1 m/s up, x' = 0.3,
    e = 0.7) over t1 = 0.8 s: the monodromy is Phi(t1 - t_i) S Phi(t_i) with the free-flight
    transitions Phi(s) = [[1, s], [0, 1]] and the impact saltation matrix
    S = [[-e, 0], [-g (1 + e) / v_i, -e]] (v_i < 0 the arrival velocity) in y, and
    [[1, t1], [0, 1]] in x; to 1e-9 (DOP853 integrates the parabolas to round-off; the
    impact map is linear)."""
    from fricdamp.solvers.shooting import flow

    e, g, h0, v0, t1 = 0.7, 9.81, 0.5, 1.0, 0.8
    fl = flow(PointMassOnStop(e=e), (0.0, t1), [0.0, h0, 0.3, v0], rtol=1e-12, atol=1e-14)
    ti = (v0 + np.sqrt(v0**2 + 2 * g * h0)) / g
    vi = v0 - g * ti
    (im,) = fl.result.impacts
    assert im.time == pytest.approx(ti, rel=1e-12)

    def phi(s):
        return np.array([[1.0, s], [0.0, 1.0]])

    My = phi(t1 - ti) @ np.array([[-e, 0.0], [-g * (1 + e) / vi, -e]]) @ phi(ti)
    ref = np.zeros((4, 4))
    ref[np.ix_([0, 2], [0, 2])] = phi(t1)
    ref[np.ix_([1, 3], [1, 3])] = My
    assert np.allclose(fl.monodromy, ref, rtol=0, atol=1e-9)


class PointMassInGroove(PointMassOnStop):
    """Point mass in a V-groove: two frictionless walls with normals (-+sin b, cos b)."""

    n_contacts = 2

    def __init__(self, b=0.6, e=0.0, **kw):
        super().__init__(e=e, **kw)
        self.n = np.array([[-np.sin(b), np.cos(b)], [np.sin(b), np.cos(b)]]).T  # (2, 2)
        self.mu_static = self.mu_sliding = np.zeros(2)
        self.normal_constrained = np.ones(2, dtype=bool)

    def unilateral_contacts(self):
        return np.ones(2, dtype=bool)

    def restitution_coefficients(self):
        return np.full(2, self.e)

    def tangent_jacobian(self, q):
        return np.array([[np.cos(0.6), np.cos(0.6)], [np.sin(0.6), -np.sin(0.6)]])

    def tangent_wbar(self, q, qd):
        return np.zeros(2)

    def normal_gap(self, q):
        return self.n.T @ q

    def normal_jacobian(self, q):
        return self.n

    def normal_wbar(self, q, qd):
        return np.zeros(2)


@pytest.mark.parametrize("e", [0.0, 0.5])
def test_simultaneous_impact_in_a_groove(e):
    """Dropped onto the bottom of a V-groove (half angle b from the vertical normal), both
    walls are hit at once: one impulsive problem for both gives v+ = e v (vertical), the
    impulses m (1 + e) v / (2 cos b) each and the loss (1 - e^2) m v^2 / 2 (1e-10). With
    e = 0 the mass then rests in the groove: both contacts closed, each pressed by
    m g / (2 cos b) (1e-9)."""
    b, m, h0 = 0.6, 1.5, 0.2
    s = PointMassInGroove(b=b, e=e, m=m)
    r = simulate_events(s, (0.0, 0.3), [0, h0, 0, 0], rtol=1e-12, progress=False)
    im = r.impacts[0]
    v = np.sqrt(2 * 9.81 * h0)  # vertical impact speed; normal velocities -v cos b
    assert im.contacts == (0, 1)
    assert np.allclose(im.impulse, m * (1 + e) * v / (2 * np.cos(b)), rtol=1e-10)
    assert im.energy_loss == pytest.approx(0.5 * (1 - e**2) * m * v**2, rel=1e-10)
    assert np.allclose(im.velocity_after, e * v * np.cos(b), rtol=1e-10, atol=1e-14)
    if e == 0:
        assert len(r.impacts) == 1 and np.all(r.modes[-1] != 3)
        assert np.allclose(r.lambda_N[-1], m * 9.81 / (2 * np.cos(b)), rtol=1e-9)
