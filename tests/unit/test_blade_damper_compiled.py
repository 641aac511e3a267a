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
