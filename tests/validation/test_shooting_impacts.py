"""Shooting through impacts and lift-off (unilateral contacts) against closed forms.

Models (built here, frictionless unilateral stop, DOP853 phases at rtol 1e-12):

* **impact oscillator** ``m x'' + c x' + k x = F cos(w t)`` with a rigid stop at ``x = d``
  (gap ``d - x >= 0``), Newton's law ``x'+ = -e x'-`` (m = k = F = 1, c = 0.02, e = 0.8).
  Between impacts the motion is linear, ``y(t) = y_p(t) + exp(A (t - t_i)) (y(t_i+) -
  y_p(t_i))`` with the periodic particular solution ``y_p``; the period-1 orbit with one
  impact per period is the root ``(t_i, v)`` of ``y(t_i + T-) = (d, v)`` from
  ``y(t_i+) = (d, -e v)`` (two equations, solved here by ``fsolve`` to a residual below
  1e-13, and checked not to reach the stop between impacts). Its monodromy is
  ``exp(A (t0 + T - t_i)) S exp(A (t_i - t0))`` with the impact saltation matrix
  ``S = [[-e, 0], [(a+ + e a-) / v, -e]]`` (Leine & Nijmeijer 2004, section 7.2; Bishop
  1994, "Impact oscillators"), whose determinant ``e^2 exp(-c T / m)`` is checked too.
* **lift-off**: a mass m1 = 1 held on a stop (gap q1 >= 0) by a preload of 1 N, coupled by a
  spring-damper to m2 = 0.5, and pulled by F cos(w t) with F > 1 N: every period it lifts
  off (normal force reaching zero), flies, and re-impacts plastically (e = 0).

Tolerances: the orbit's impact phase, impact velocity and section state to 1e-8 (the
event solver locates the impact to round-off on the DOP853 dense output, rtol 1e-12: the
observed errors are ~1e-11). The monodromy of shooting against the closed form to 1e-8
(relative to its norm): the linear phases' transitions are Magnus steps of a constant
Jacobian (exact up to the central-difference Jacobian's round-off) and the impact map's
Jacobian is a central difference of a linear map. Against finite differences of the
Poincare map (central, step h = 1e-6 relative): truncation O(h^2) ~ 1e-12 plus the DOP853
error over the step, ~1e-12 / 1e-6 = 1e-6 at worst, so 1e-6 relative (observed 3e-10 to
5e-9).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import fsolve

from fricdamp.errors import ConvergenceError
from fricdamp.solvers.event import simulate_events
from fricdamp.solvers.event_system import ConstrainedSystem
from fricdamp.solvers.shooting import flow, shoot

RTOL, ATOL = 1e-12, 1e-14


class LinearStop(ConstrainedSystem):
    """``M q'' + C q' + K q = f0 + f1 cos(w t)`` with one frictionless unilateral stop,
    gap ``g_N = d + w_N . q >= 0``, restitution ``e``."""

    n_contacts = 1
    constant_mass = True

    def __init__(self, M, C, K, f0, f1, w, wN, d, e):
        self.M, self.C, self.K = (np.atleast_2d(np.asarray(a, float)) for a in (M, C, K))
        self.n_dof = self.M.shape[0]
        self.f0, self.f1 = np.asarray(f0, float), np.asarray(f1, float)
        self.w, self.wN, self.d, self.e = w, np.asarray(wN, float), d, e
        self.mu_static = np.zeros(1)
        self.mu_sliding = np.zeros(1)
        self.normal_constrained = np.array([True])

    def unilateral_contacts(self):
        return np.array([True])

    def restitution_coefficients(self):
        return np.array([self.e])

    def mass(self, q):
        return self.M

    def h(self, t, q, qd):
        return self.f0 + self.f1 * np.cos(self.w * t) - self.C @ qd - self.K @ q

    def tangent_jacobian(self, q):
        return np.zeros((self.n_dof, 1))

    def tangent_wbar(self, q, qd):
        return np.zeros(1)

    def normal_gap(self, q):
        return np.array([self.d + self.wN @ q])

    def normal_jacobian(self, q):
        return self.wN[:, None]

    def normal_wbar(self, q, qd):
        return np.zeros(1)

    def max_frequency(self):
        return self.w


# ------------------------------------------------------------------ impact oscillator
M_, C_, K_, F_, E_ = 1.0, 0.02, 1.0, 1.0, 0.8


def impact_oscillator(w, d):
    return LinearStop([[M_]], [[C_]], [[K_]], [0.0], [F_], w, [-1.0], d, E_)


class ImpactOrbit:
    """Closed-form period-1 orbit (one impact per period) of the impact oscillator."""

    def __init__(self, w, d, guess):
        self.w, self.d, self.T = w, d, 2 * np.pi / w
        self.A = np.array([[0.0, 1.0], [-K_ / M_, -C_ / M_]])
        self.Z = F_ / (K_ - M_ * w**2 + 1j * C_ * w)
        E = sla.expm(self.A * self.T)

        def res(u):
            tau, v = u
            return self.yp(tau) + E @ (np.array([d, -E_ * v]) - self.yp(tau)) - [d, v]

        sol = fsolve(res, guess, xtol=1e-12)
        assert np.abs(res(sol)).max() < 1e-13
        self.tau, self.v = sol[0] % self.T, sol[1]
        assert self.v > 0
        ts = np.linspace(1e-9, self.T - 1e-9, 4001)
        assert max(self.state(self.tau + s)[0] for s in ts) < d  # no contact in between

    def yp(self, t):
        z = self.Z * np.exp(1j * self.w * t)
        return np.array([z.real, (1j * self.w * z).real])

    def state(self, t):
        s = (t - self.tau) % self.T
        return self.yp(t) + sla.expm(self.A * s) @ (np.array([self.d, -E_ * self.v])
                                                   - self.yp(self.tau))

    def saltation(self):
        f = F_ * np.cos(self.w * self.tau) - K_ * self.d
        a_minus, a_plus = (f - C_ * self.v) / M_, (f + C_ * E_ * self.v) / M_
        return np.array([[-E_, 0.0], [(a_plus + E_ * a_minus) / self.v, -E_]])

    def monodromy(self, t0):
        ti = t0 + (self.tau - t0) % self.T
        return (sla.expm(self.A * (t0 + self.T - ti)) @ self.saltation()
                @ sla.expm(self.A * (ti - t0)))


def fd_monodromy(system, t0, t1, y, h=1e-6):
    """Central differences of the Poincare map through the event solver (monodromy off)."""
    n2 = y.size
    scale = np.maximum(np.abs(y), np.abs(y).max())
    cols = []
    for j in range(n2):
        e = np.zeros(n2)
        e[j] = h * scale[j]
        yp = flow(system, (t0, t1), y + e, rtol=RTOL, atol=ATOL, monodromy=False).y_end
        ym = flow(system, (t0, t1), y - e, rtol=RTOL, atol=ATOL, monodromy=False).y_end
        cols.append((yp - ym) / (2 * e[j]))
    return np.column_stack(cols)


# (w, d, guess (t_i, v) for fsolve): stable period-1 orbits (|mu| ~ 0.77-0.78)
CASES = [(1.6, 0.3, (0.18, 2.4)), (2.4, 0.0, (1.23, 0.86))]


@pytest.mark.parametrize("w, d, guess", CASES)
def test_impact_oscillator_orbit_and_multipliers(w, d, guess):
    """Shooting from rest (20 transient periods) finds the one-impact period-1 orbit: impact
    phase, impact velocity and section state to 1e-8; monodromy against the closed form
    ``exp(A (T - s)) S exp(A s)`` to 1e-8 (relative) and its determinant to e^2 exp(-c T);
    against finite differences of the Poincare map to 1e-6 (see the module docstring)."""
    s = impact_oscillator(w, d)
    ref = ImpactOrbit(w, d, guess)
    T = ref.T
    o = shoot(s, T, np.zeros(2), period_multiple=1, transient_periods=20, rtol=RTOL, atol=ATOL)
    assert o.success and o.stable
    scale = np.array([np.abs(o.q).max(), np.abs(o.qd).max()])
    assert np.all(np.abs(o.y0 - ref.state(0.0)) <= 1e-8 * scale)
    fl = flow(s, (0.0, T), o.y0, rtol=RTOL, atol=ATOL, monodromy=False)
    (im,) = fl.result.impacts
    assert im.time == pytest.approx(ref.tau, abs=1e-8 * T)
    assert -im.velocity_before[0] == pytest.approx(ref.v, rel=1e-8)
    assert im.velocity_after[0] == pytest.approx(E_ * ref.v, rel=1e-8)
    Mref = ref.monodromy(0.0)
    assert np.abs(o.monodromy - Mref).max() <= 1e-8 * np.abs(Mref).max()
    assert np.linalg.det(o.monodromy) == pytest.approx(E_**2 * np.exp(-C_ * T / M_), rel=1e-8)
    mu_ref = np.sort_complex(np.linalg.eigvals(Mref))
    assert np.allclose(np.sort_complex(o.multipliers), mu_ref, rtol=0, atol=1e-8)
    Mfd = fd_monodromy(s, 0.0, T, o.y0)
    assert np.abs(o.monodromy - Mfd).max() <= 1e-6 * np.abs(Mref).max()


def test_impact_oscillator_unstable_orbit_repels():
    """w = 2.8, d = 0: past the period-doubling of the one-impact orbit (closed-form
    multipliers -2.89 and -0.21). Newton from the closed-form state perturbed by 1e-3
    converges to it, with the multipliers to 1e-8 of the closed form and ``stable`` False;
    a start 1e-6 off the orbit leaves it (distance x 100 within 20 periods) in the event
    solver, while from the stable orbit at w = 2.4 the same perturbation decays below
    1e-10 in 60 periods (0.78^60 ~ 4e-7 of it)."""
    w, d = 2.8, 0.0
    s = impact_oscillator(w, d)
    ref = ImpactOrbit(w, d, (1.03, 0.39))
    T = ref.T
    y_ref = ref.state(0.0)
    o = shoot(s, T, y_ref * (1 + 1e-3), period_multiple=1, transient_periods=0, rtol=RTOL,
              atol=ATOL)
    assert o.success and not o.stable
    mu_ref = np.sort_complex(np.linalg.eigvals(ref.monodromy(0.0)))
    assert mu_ref.real.min() < -1
    assert np.allclose(np.sort_complex(o.multipliers), mu_ref, rtol=0, atol=1e-8)
    # time integration from a perturbed start
    y = o.y0 + 1e-6 * np.abs(o.y0).max() * np.array([1.0, 0.0])
    r = simulate_events(s, (0.0, 20 * T), y, t_eval=np.arange(21) * T, rtol=RTOL, atol=ATOL,
                        progress=False)
    dist = np.abs(np.column_stack([r.q[:, 0], r.qd[:, 0]])[np.isin(r.t, np.arange(21) * T)]
                  - o.y0).max(axis=1)
    assert dist.max() > 100 * dist[0]

    w2, d2, guess2 = CASES[1]
    s2 = impact_oscillator(w2, d2)
    ref2 = ImpactOrbit(w2, d2, guess2)
    y2 = ref2.state(0.0)
    T2 = ref2.T
    r2 = simulate_events(s2, (0.0, 60 * T2), y2 + 1e-6 * np.abs(y2).max() * np.array([1, 0]),
                         t_eval=[0.0, 60 * T2], rtol=RTOL, atol=ATOL, progress=False)
    assert np.abs(np.array([r2.q[-1, 0], r2.qd[-1, 0]]) - y2).max() < 1e-10


# ------------------------------------------------------------------ lift-off
def lift_off_system(F, w):
    return LinearStop(np.diag([1.0, 0.5]), [[0.1, -0.05], [-0.05, 0.05]],
                      [[3.0, -2.0], [-2.0, 2.0]], [-1.0, 0.0], [F, 0.0], w, [1.0, 0.0], 0.0,
                      0.0)


@pytest.mark.parametrize("F, w", [(2.5, 1.0), (3.0, 1.5)])
def test_lift_off_orbit_multipliers_against_finite_differences(F, w):
    """Each period: one lift-off (lambda_N = 0, smooth switch), a flight, one plastic impact.
    Shooting converges (residual <= 1e-10); the monodromy matches central differences of the
    Poincare map to 1e-6 relative (module docstring); the closed phase constrains q1 and
    q1', so two multipliers are zero (to 1e-12), the two others a complex pair inside."""
    s = lift_off_system(F, w)
    T = 2 * np.pi / w
    o = shoot(s, T, np.zeros(4), period_multiple=1, transient_periods=20, rtol=RTOL, atol=ATOL)
    assert o.success and o.residual <= 1e-10 and o.stable
    fl = flow(s, (0.0, T), o.y0, rtol=RTOL, atol=ATOL, monodromy=False)
    assert sorted(e.kind for e in fl.result.events) == ["impact", "lift-off"]
    Mfd = fd_monodromy(s, 0.0, T, o.y0)
    assert np.abs(o.monodromy - Mfd).max() <= 1e-6 * np.abs(Mfd).max()
    mu = np.abs(o.multipliers)
    assert np.all(mu[2:] < 1e-12) and 0.1 < mu[0] < 1


def test_zeno_orbit_is_refused():
    """A ball bouncing on a floor (e = 0.5) accumulates impacts and is brought to rest by a
    plastic impact below the Zeno velocity: its monodromy is refused with a clear error."""
    s = LinearStop([[1.0]], [[0.0]], [[0.0]], [-9.81], [0.0], 0.0, [1.0], 0.0, 0.5)
    with pytest.raises(ConvergenceError, match="Zeno velocity"):
        flow(s, (0.0, 2.0), [0.5, 0.0], rtol=1e-10, atol=1e-12)


class FrictionStop(LinearStop):
    """A point mass (x, y) on springs, y >= 0 a unilateral stop with Coulomb friction mu in x
    (``LinearStop`` with the tangent direction x)."""

    def __init__(self, mu, **kw):
        super().__init__(**kw)
        self.mu_static = np.array([mu])
        self.mu_sliding = np.array([mu])

    def tangent_jacobian(self, q):
        return np.array([[1.0], [0.0]])


def friction_stop(e):
    return FrictionStop(0.3, M=np.eye(2), C=np.diag([0.05, 0.05]), K=np.diag([1.0, 2.0]),
                        f0=[0.0, -1.0], f1=[0.8, 1.6], w=1.0, wN=[0.0, 1.0], d=0.0, e=e)


def test_frictional_lift_off_orbit_against_finite_differences():
    """A mass pressed on a stop with friction (mu = 0.3), forced in x and y: per period a
    plastic impact, a slip reversal and a lift-off while slipping. The monodromy (impact,
    friction and lift-off saltation matrices) matches central differences of the Poincare map
    to 1e-6 relative (observed 2e-8); two zero multipliers of the closed phase."""
    s = friction_stop(0.0)
    T = 2 * np.pi
    o = shoot(s, T, np.zeros(4), period_multiple=1, transient_periods=20, rtol=RTOL, atol=ATOL)
    assert o.success and o.stable
    fl = flow(s, (0.0, T), o.y0, rtol=RTOL, atol=ATOL, monodromy=False)
    assert sorted(e.kind for e in fl.result.events) == ["friction", "impact", "lift-off"]
    Mfd = fd_monodromy(s, 0.0, T, o.y0)
    assert np.abs(o.monodromy - Mfd).max() <= 1e-6 * np.abs(Mfd).max()
    assert np.all(np.abs(o.multipliers[2:]) < 1e-12)


def test_chattering_orbit_is_refused_by_shoot():
    """The same system with e = 0.5 re-closes through an accumulation of bounces, ended by a
    plastic impact below the Zeno velocity: shoot raises ConvergenceError saying so."""
    with pytest.raises(ConvergenceError, match="Zeno velocity"):
        shoot(friction_stop(0.5), 2 * np.pi, np.zeros(4), period_multiple=1,
              transient_periods=20, rtol=RTOL, atol=ATOL)
