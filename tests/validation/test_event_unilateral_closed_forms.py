"""Unilateral contacts of the event-driven solver against closed forms: the bouncing ball
(Newton's impact law, accumulation of impacts) and the lift-off of a mass pressed against a
stop by a harmonic force. References: elementary mechanics (free fall, Newton's law of
restitution); Leine & Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical
Systems* (2004), section 7.4 (bouncing ball, Zeno time)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from fricdamp.solvers.event import simulate_events

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "unit"))
from test_event_unilateral import PointMassOnStop  # noqa: E402  (the test system)

G = 9.81


@pytest.mark.parametrize("e", [0.5, 0.8])
def test_bouncing_ball(e):
    """Dropped from h0 = 0.5 m: first impact at t0 = sqrt(2 h0 / g) with v0 = sqrt(2 g h0);
    impact k (k >= 1) at t0 + 2 v0 (e + ... + e^k) / g; apex heights h0 e^(2k); flight times
    2 v0 e^k / g (ratio e); accumulation (Zeno) time t_inf = t0 + 2 v0 e / (g (1 - e)).
    Tolerances: impact times 1e-12 relative (first 12 impacts; the impact instant is the
    zero of the gap on the dense output), flight-time ratios 1e-9 and apex heights (sampled at
    the closed-form apex times) 1e-10 relative (first 6 bounces); DOP853 at rtol 1e-10.
    The solver closes the contact at the first impact slower than the Zeno velocity
    vz = sqrt(2 g atol) (a bounce lower than the gap tolerance atol = 1e-12 m at y = 0),
    about 4.4e-6 m/s, so it comes to rest at most 2 vz / (g (1 - e)) before t_inf (and
    never after it); then it rests: lambda_N = m g to 1e-9. Energy balance (input 0 = impact
    loss + change of mechanical energy) to 1e-10 of the drop energy; energy is conserved in
    flight to 1e-12 relative."""
    h0, rtol = 0.5, 1e-10
    v0, t0 = np.sqrt(2 * G * h0), np.sqrt(2 * h0 / G)
    t_inf = t0 + 2 * v0 * e / (G * (1 - e))
    s = PointMassOnStop(e=e)
    kk = np.arange(12)
    ref = t0 + 2 * v0 * np.cumsum(np.r_[0.0, e ** kk[1:]]) / G  # impact times
    t_apex = ref[:6] + v0 * e ** (kk[:6] + 1) / G  # apex of bounce k + 1
    te = np.union1d(np.linspace(0.0, t_inf + 0.5, 20001), t_apex)
    r = simulate_events(s, (0.0, te[-1]), [0, h0, 0, 0], t_eval=te, rtol=rtol,
                        progress=False)
    assert r.success
    ti = r.impact_times()
    assert np.allclose(ti[:12], ref, rtol=1e-12, atol=0)
    flights = np.diff(ti[:7])
    assert np.allclose(flights[1:] / flights[:-1], e, rtol=1e-9)
    apex = r.q[np.isin(r.t, t_apex), 1]
    assert np.allclose(apex, h0 * e ** (2 * (kk[:6] + 1)), rtol=1e-10, atol=0)
    vz = np.sqrt(2 * G * 1e-12)
    rest = ti[-1]
    assert r.impacts[-1].plastic == (0,)
    assert t_inf - 2 * vz / (G * (1 - e)) <= rest <= t_inf + 1e-12
    after = r.t > rest + 1e-9
    assert np.all(r.q[after, 1] == pytest.approx(0.0, abs=1e-15))
    assert np.allclose(r.lambda_N[after, 0], s.m * G, rtol=1e-9)
    assert np.all(r.modes[after, 0] != 3)
    mech = r.energy["kinetic"] + r.energy["potential"]
    scale = s.m * G * h0
    assert abs(r.energy_residual).max() < 1e-10 * scale
    assert r.energy["impact_loss"][-1] == pytest.approx(scale, rel=1e-10)
    flight = (r.t > ti[1] + 1e-6) & (r.t < ti[2] - 1e-6)
    assert np.ptp(mech[flight]) < 1e-12 * scale


def test_lift_off_under_harmonic_force():
    """A mass m = 1 kg on a stop, pressed by gravity and f0 = 5 N, pulled by f1 cos(w t)
    (f1 = 30 N, 10 Hz). In contact lambda_N = m g + f0 - f1 cos(w t), which vanishes at
    t* = (2 pi - arccos((m g + f0) / f1)) / w: the lift-off instant (to 1e-12 s). The free
    flight y(t) = -(g + f0/m)(t - t*)^2 / 2 + f1 / (m w^2) (cos w t* - cos w t
    - w sin(w t*) (t - t*)) returns to y = 0 at the root t_c found by Brent's method here:
    the impact time (to 1e-9 s) and velocity (1e-8 relative). With e = 0 the mass stays on
    the stop after it (plastic impact, compressive force) until the next lift-off, one
    period later. Energy balance (input = friction + impact loss + change of mechanical
    energy) to 1e-6 of the input work (DOP853 at max_step 1e-3 s: the work integrals are not
    error-controlled)."""
    m, f0, f1, fhz = 1.0, 5.0, 30.0, 10.0
    w = 2 * np.pi * fhz
    s = PointMassOnStop(m=m, e=0.0, f0=f0, f1=f1, w=w, mu=0.3, fx=1.0)
    ta = np.pi / (2 * w)
    r = simulate_events(s, (ta, ta + 3 / fhz), [0, 0, 0, 0], max_step=1e-3, progress=False)
    ts = (2 * np.pi - np.arccos((m * G + f0) / f1)) / w
    lo = r.lift_off_times()
    assert np.allclose(lo, ts + np.arange(3) / fhz, rtol=0, atol=1e-12)

    def y(t):
        d = t - ts
        return (-(G + f0 / m) * d**2 / 2
                + f1 / (m * w**2) * (np.cos(w * ts) - np.cos(w * t) - w * np.sin(w * ts) * d))

    def yd(t):
        return -(G + f0 / m) * (t - ts) + f1 / (m * w) * (np.sin(w * t) - np.sin(w * ts))

    tc = brentq(y, ts + 1e-3, ts + 1 / fhz, xtol=1e-15)
    assert np.allclose(r.impact_times(), tc + np.arange(2) / fhz, rtol=0, atol=1e-9)
    for im in r.impacts:
        assert im.velocity_before[0] == pytest.approx(yd(tc), rel=1e-8)
        assert im.velocity_after[0] == pytest.approx(0.0, abs=1e-12)
    closed = (r.t > tc + 1e-9) & (r.t < ts + 1 / fhz - 1e-9)
    assert np.all(r.modes[closed, 0] != 3) and r.lambda_N[closed, 0].min() >= -1e-9
    assert r.energy_balance_error < 1e-6
    assert r.energy["impact_loss"][-1] > 0.1 * r.energy["input_work"][-1]
