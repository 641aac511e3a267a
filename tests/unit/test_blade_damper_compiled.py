"""Compiled blade-damper kernels against the generic path (lambdified sympy kinematics and
the event solver's Evaluator), on random states and every stick/slip configuration.

Tolerance 1e-12 relative to each quantity's scale: both paths evaluate the same equations
(000 (37)-(40)) in a different order of floating-point operations. The scale of an
acceleration is that of the forces it sums, ``M^-1 (|h| + |W_N lambda_N| + |W_T lambda_T|)``:
the damper's rotation q5'' is a difference of contact moments divided by I5 = 1.6e-8 kg m^2
and loses six digits to cancellation in either path (both are equally right).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.solvers.event import simulate_events
from fricdamp.solvers.event_phase import NumericalPhase
from fricdamp.solvers.event_switch import Evaluator

RNG = np.random.default_rng(140)
TOL = 1e-12
MODES = [np.array(m, dtype=np.int64) for m in itertools.product((0, 1, -1), repeat=2)]


def _random_state(system):
    q, _ = system.full_state(np.concatenate([RNG.uniform(-2e-4, 2e-4, 4),
                                             RNG.uniform(-0.05, 0.05, 1)]))
    qd = np.concatenate([RNG.uniform(-0.3, 0.3, 4), RNG.uniform(-30, 30, 1),
                         RNG.uniform(-0.3, 0.3, 2)])
    return q, qd


def _close(a, b, scale=None):
    a, b = np.asarray(a, float), np.asarray(b, float)
    s = np.max(np.abs(b)) if scale is None else scale
    return np.max(np.abs(a - b)) <= TOL * max(s, 1e-300)


@pytest.mark.parametrize("contour", ["parabola", "circle"])
def test_compiled_kinematics_equal_lambdified(contour):
    p = BladeDamperParameters(contour=contour, gamma=np.deg2rad(RNG.uniform(35, 70)))
    fast = BladeDamperSystem(p)
    ref = BladeDamperSystem(p, compiled=False)
    for _ in range(20):
        q = np.concatenate([RNG.uniform(-1e-3, 1e-3, 4), RNG.uniform(-0.1, 0.1, 1),
                            RNG.uniform(-1e-3, 1e-3, 2)])
        u5 = RNG.uniform(-50, 50)
        a = fast.compiled_kernels().kinematics(q, u5)
        b = ref._terms(q, u5)[:5]
        for x, y in zip(a, b, strict=True):
            assert _close(x, y)


@pytest.mark.parametrize("contour", ["parabola", "circle"])
def test_compiled_rhs_and_events_equal_generic_path(contour):
    """Accelerations, contact forces, powers and event functions of all 9 configurations
    (stick, slip+, slip- at K1 and K2) and both normal-force signs."""
    p = BladeDamperParameters(contour=contour, excitation_amplitude=RNG.uniform(1, 10),
                              excitation_frequency=RNG.uniform(40, 80))
    fast = BladeDamperSystem(p)
    ref = BladeDamperSystem(p, compiled=False)
    ev_ref = Evaluator(ref)
    ev_fast = Evaluator(fast)
    assert ev_fast.compiled is not None and ev_ref.compiled is None
    for _ in range(3):
        q, qd = _random_state(fast)
        t = RNG.uniform(0, 0.1)
        y = np.concatenate([q, qd, np.zeros(3)])
        for modes, sig in itertools.product(MODES, ([1.0, 1.0], [1.0, -1.0])):
            sigma = np.array(sig)
            pt = ev_ref.point(t, q, qd)
            qdd, lamN, lamT = (a[:, 0] for a in ev_ref.solve(pt, modes, sigma))
            out = np.empty(17)
            ratio = fast.compiled_kernels().rhs(t, y, modes, sigma, out)
            assert ratio > 1e-13
            assert _close(out[:7], qd)
            terms = (np.abs(pt.h) + np.abs(pt.WN) @ np.abs(lamN)
                     + np.abs(pt.WT) @ np.abs(lamT)) / np.diag(ref.M)
            assert np.all(np.abs(out[7:14] - qdd) <= TOL * terms)
            ph_ref = NumericalPhase(ev_ref, modes, sigma, t, q, qd, 1e-8, 1e-12, np.inf)
            ph_fast = NumericalPhase(ev_fast, modes, sigma, t, q, qd, 1e-8, 1e-12, np.inf)
            r_ref, r_fast = ph_ref._rhs(t, y), ph_fast._rhs(t, y)
            assert np.all(np.abs(r_fast[7:14] - r_ref[7:14]) <= TOL * terms)
            assert _close(r_fast[14:], r_ref[14:])
            _, _, lNf, lTf, WTf = fast.compiled_kernels().solve_many(
                np.array([t]), y[:14, None].copy(), modes, sigma)
            assert _close(lNf[:, 0], lamN) and _close(lTf[:, 0], lamT, np.max(np.abs(lamN)))
            assert _close(WTf[:, :, 0], pt.WT)
            g_ref, s_ref = ph_ref._g(t, y)
            g_fast, s_fast = ph_fast._g(t, y)
            assert _close(g_fast, g_ref, np.max(s_ref)) and _close(s_fast, s_ref)
            assert _close(ph_fast.vel_scale, ph_ref.vel_scale)


def test_compiled_time_response_equals_generic():
    """Three forcing periods with stick-slip (58 Hz, 8 N) through both paths: same events and
    states to the DOP853 tolerance (rtol 1e-10: the paths differ in round-off only, which
    the step-size control amplifies at most to its tolerance)."""
    from fricdamp.models.blade_damper.studies import time_response

    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=58.0)
    a = time_response(BladeDamperSystem(p), 3.0, rtol=1e-10).result
    b = time_response(BladeDamperSystem(p, compiled=False), 3.0, rtol=1e-10).result
    assert a.n_events == b.n_events > 0
    scale = np.abs(b.q).max(axis=0) + 1e-12
    assert np.max(np.abs(a.q[-1] - b.q[-1]) / scale) < 1e-6


OPEN_MODES = [np.array(m, dtype=np.int64) for m in
              [(3, 0), (3, 1), (3, -1), (0, 3), (1, 3), (-1, 3), (3, 3)]]


def _lifted_state(system):
    """A random state with the damper lifted 2 um off both platforms (open gaps > 0)."""
    q, qd = _random_state(system)
    q = q.copy()
    q[6] -= 2e-6  # F_Z presses the damper outwards (+y) onto the platforms
    return q, qd


@pytest.mark.parametrize("contour", ["parabola", "circle"])
def test_compiled_open_contacts_equal_generic_path(contour):
    """A released damper (``release=True``) with one or both contacts open (mode OPEN = 3):
    accelerations, contact forces (zero at an open contact), event functions (the open
    contact's gap event), the projection onto the closed constraints and the switching solve
    with prescribed tangential forces, compiled against the generic path to 1e-12 of each
    quantity's scale. A compiled kernel that constrained an open contact would put a normal
    force there and fail every check."""
    p = BladeDamperParameters(contour=contour, excitation_amplitude=RNG.uniform(1, 10),
                              excitation_frequency=RNG.uniform(40, 80))
    fast = BladeDamperSystem(p, release=True)
    ref = BladeDamperSystem(p, compiled=False, release=True)
    ev_ref, ev_fast = Evaluator(ref), Evaluator(fast)
    assert ev_fast.compiled is not None and ev_fast._fused is not None
    assert ev_ref.compiled is None
    ck = fast.compiled_kernels()
    for _ in range(3):
        q, qd = _lifted_state(fast)
        assert np.all(ref.normal_gap(q) > 1e-7)
        t = RNG.uniform(0, 0.1)
        y = np.concatenate([q, qd, np.zeros(3)])
        for modes, sig in itertools.product(OPEN_MODES, ([1.0, 1.0], [1.0, -1.0])):
            sigma = np.array(sig)
            pt = ev_ref.point(t, q, qd)
            qdd, lamN, lamT = (a[:, 0] for a in ev_ref.solve(pt, modes, sigma))
            assert np.all(lamN[modes == 3] == 0) and np.all(lamT[modes == 3] == 0)
            out = np.empty(17)
            assert ck.rhs(t, y, modes, sigma, out) > 1e-13
            terms = (np.abs(pt.h) + np.abs(pt.WN) @ np.abs(lamN)
                     + np.abs(pt.WT) @ np.abs(lamT)) / np.diag(ref.M)
            assert np.all(np.abs(out[7:14] - qdd) <= TOL * terms)
            _, _, lNf, lTf, _ = ck.solve_many(np.array([t]), y[:14, None].copy(), modes, sigma)
            scale = max(np.max(np.abs(lamN)), 1e-300)
            assert _close(lNf[:, 0], lamN, scale) and _close(lTf[:, 0], lamT, scale)
            ph_ref = NumericalPhase(ev_ref, modes, sigma, t, q, qd, 1e-8, 1e-12, np.inf)
            ph_fast = NumericalPhase(ev_fast, modes, sigma, t, q, qd, 1e-8, 1e-12, np.inf)
            assert np.array_equal(ph_fast.kinds, ph_ref.kinds) and np.any(ph_ref.kinds == 4)
            g_ref, s_ref = ph_ref._g(t, y)
            g_fast, s_fast = ph_fast._g(t, y)
            assert _close(g_fast, g_ref, np.max(s_ref)) and _close(s_fast, s_ref)
            gap_ev = ph_ref.kinds == 4
            assert _close(g_fast[gap_ev], ref.normal_gap(q)[ph_ref.contacts[gap_ev]])
            # projection: the closed contacts' gaps and velocities, the stuck slip velocities
            qa, qda, dea = ev_ref.project(t, q, qd, modes)
            qb, qdb, deb = ev_fast.project(t, q, qd, modes)
            assert _close(qb, qa, np.max(np.abs(q))) and _close(qdb, qda, np.max(np.abs(qd)))
            assert abs(deb - dea) <= 1e-10 * max(dea, 1e-300)
            assert np.all(np.abs(ref.normal_gap(qb)[modes != 3]) <= 1e-15)
            # switching solve: a stuck contact's tangential force prescribed (mode 2)
            given_modes = np.where(modes == 0, 2, modes)
            given = np.zeros((2, 2))
            given[given_modes == 2, 1] = 1.0
            a = ev_ref.solve(pt, given_modes, sigma, given)
            ok, *b = ck.solve_point(pt.h, pt.WN, pt.WT, pt.wbN, pt.wbT, given_modes, sigma,
                                    given)
            assert ok
            for x, z in zip(b, a, strict=True):
                assert _close(x, z, max(np.max(np.abs(z)), 1e-300) * 1e2)


def test_compiled_release_response_equals_generic():
    """Twelve periods of the released damper beyond lift-off (gamma = 80 deg, 1 g, 8 N at
    52 Hz: it lifts off 6.9 periods in, then bursts of plastic impacts) through the compiled
    kernels (DOP853 phases and the event loop) and the generic path: the same lift-offs and
    impacts, lift-off and impact times within 1e-8 s and states within 1e-6 of the motion.
    The paths differ in round-off only, which the step-size control turns into different
    step sequences, so the two solutions differ by their integration errors (rtol 1e-8 per
    step, accumulated over ~1,000 steps and 115 impacts): measured 3e-8 of the motion (at a
    step bounded to 2e-4 s: 4e-12, lift-off times 8e-15 s)."""
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=52.0).with_(
        gamma_deg=80.0)
    T = 1.0 / 52.0
    res = []
    for kw in ({}, {"compiled": False}):
        s = BladeDamperSystem(p, release=True, **kw)
        y0 = np.concatenate([s.static_equilibrium().q, np.zeros(7)])
        res.append(simulate_events(s, (0.0, 12 * T), y0, t_eval=np.linspace(0, 12 * T, 1201),
                                   rtol=1e-8, atol=1e-12, max_events=40_000, progress=False))
    a, b = res
    assert a.success and b.success
    assert a.lift_off_times().size == b.lift_off_times().size >= 1
    assert a.impact_times().size == b.impact_times().size >= 1
    assert np.max(np.abs(a.lift_off_times() - b.lift_off_times())) <= 1e-8
    # the impact instants: the gap's zero, located on the compiled step (Brent) and by the
    # generic search
    assert np.max(np.abs(a.impact_times() - b.impact_times())) <= 1e-8
    scale = np.abs(b.q).max(axis=0) + 1e-12
    assert np.max(np.abs(a.q - b.q) / scale) <= 1e-6
