"""Orbit continuation through impacts, and a period-2 impact orbit (issue 14, item 1).

Model: the impact oscillator of ``test_shooting_impacts`` (m = k = F = 1, c = 0.02, rigid
stop at x = d, restitution e = 0.8; its closed-form one-impact orbit ``ImpactOrbit``).

* :func:`~fricdamp.solvers.shooting.continue_orbits` follows the one-impact period-1 orbit
  from w = 1.5 to 1.8 (d = 0.3) in steps of 0.05, each point from the secant prediction of
  the two before: the section state and the Floquet multipliers of every point against the
  closed form (root of the two impact equations and ``exp(A (T - s)) S exp(A s)``), to 1e-8
  as in ``test_shooting_impacts`` (DOP853 at rtol 1e-12 locates the impacts to ~1e-11).
* w = 2.68, d = 0: the one-impact orbit has flipped (closed-form multipliers -1.42 and
  -0.43; at 2.65 they are -0.85 and -0.72, at 2.8 -2.89 and -0.21, see
  ``test_impact_oscillator_unstable_orbit_repels``; from 2.71 on the response from rest is
  no longer periodic). Shooting with ``period_multiple = 2`` from rest (after a transient of
  40 periods) converges to a period-2 orbit with two impacts per 2T of different velocities
  (a genuine period-2 orbit, not the period-1 orbit twice), all its multipliers inside the
  unit circle (so it is the attractor), and it is what the event solver settles on from
  rest: after 300 periods (|mu| = 0.61 per 2T: a start 1 off decays to 0.61^150 ~ 1e-32)
  the state on the section agrees with the orbit to 1e-7 of its range, and returns to it
  after 2T. Independent check of both the period-2 orbit and its stability: a long plain
  integration.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.solvers.event import simulate_events
from fricdamp.solvers.shooting import continue_orbits, flow, shoot
from tests.validation.test_shooting_impacts import (
    ATOL,
    RTOL,
    ImpactOrbit,
    impact_oscillator,
)


def test_continuation_follows_the_one_impact_orbit():
    """Six frequencies, w = 1.5 ... 1.75 (d = 0.3): every point converged, its section
    state within 1e-8 of the closed form's (relative to the motion's range) and its
    multipliers within 1e-8 of the closed-form monodromy's eigenvalues."""
    d = 0.3
    omegas = np.arange(1.5, 1.76, 0.05)
    br = continue_orbits(lambda w: impact_oscillator(w, d), omegas, y0=np.zeros(2),
                         period_multiple=1, transient_periods=30, rtol=RTOL, atol=ATOL)
    assert np.all(br.success) and np.all(br.stable)
    guess = (0.2, 2.2)
    for w, o in zip(omegas, br.orbits, strict=True):
        ref = ImpactOrbit(w, d, guess)
        guess = (ref.tau, ref.v)
        scale = np.array([np.abs(o.q).max(), np.abs(o.qd).max()])
        assert np.all(np.abs(o.y0 - ref.state(0.0)) <= 1e-8 * scale), w
        mu_ref = np.sort_complex(np.linalg.eigvals(ref.monodromy(0.0)))
        assert np.allclose(np.sort_complex(o.multipliers), mu_ref, rtol=0, atol=1e-8), w


@pytest.mark.slow
def test_period_two_impact_orbit_is_the_attractor_after_the_flip():
    """w = 2.68, d = 0 (see the module docstring): period-2 orbit by shooting, two impacts of
    different velocities per 2T, stable; the long integration from rest lands on it."""
    w, d = 2.68, 0.0
    s = impact_oscillator(w, d)
    T = 2 * np.pi / w
    p1 = ImpactOrbit(w, d, (1.1, 0.55))  # the flipped one-impact orbit
    mu1 = np.linalg.eigvals(p1.monodromy(0.0))
    assert mu1.real.min() < -1.2 and np.all(np.abs(mu1.imag) < 1e-12)
    # from rest after a short transient (Newton near the flipped period-1 orbit would
    # converge to that orbit, which is a period-2 fixed point too)
    o = shoot(s, T, np.zeros(2), period_multiple=2, transient_periods=40, rtol=RTOL,
              atol=ATOL)
    assert o.success and o.period_multiple == 2 and o.stable
    assert np.abs(o.multipliers).max() < 0.7
    fl = flow(s, (0.0, 2 * T), o.y0, t_eval=[0.0, T, 2 * T], rtol=RTOL, atol=ATOL,
              monodromy=False)
    v = sorted(-im.velocity_before[0] for im in fl.result.impacts)
    assert len(v) == 2 and v[1] - v[0] > 0.01 * v[1]  # 0.446 and 0.457 (2.5 %)
    # not the period-1 orbit twice
    assert np.abs(o.y0 - p1.state(0.0)).max() > 1e-3
    n = 300
    r = simulate_events(s, (0.0, (n + 2) * T), np.zeros(2),
                        t_eval=np.array([n * T, (n + 1) * T, (n + 2) * T]), rtol=RTOL,
                        atol=ATOL, progress=False)
    ys = np.column_stack([r.q[:, 0], r.qd[:, 0]])
    at = [np.flatnonzero(np.isclose(r.t, k * T, rtol=0, atol=1e-12 * T))[0]
          for k in (n, n + 1, n + 2)]
    scale = np.array([np.ptp(o.q), np.ptp(o.qd)])
    # n even: the section state of the same phase of the period-2 orbit (o.y0 at t = 0)
    # or of its other half (the orbit one period on): which one depends on the transient
    other = fl.result
    y_half = np.array([other.q[np.argmin(np.abs(other.t - T)), 0],
                       other.qd[np.argmin(np.abs(other.t - T)), 0]])
    d0 = min(np.abs(ys[at[0]] - o.y0).max(), np.abs(ys[at[0]] - y_half).max())
    assert d0 <= 1e-7 * scale.max()
    # two periods later it is back (period 2), one period later on the other half
    assert np.abs(ys[at[2]] - ys[at[0]]).max() <= 1e-7 * scale.max()
    assert np.abs(ys[at[1]] - ys[at[0]]).max() > 1e-3 * scale.max()
