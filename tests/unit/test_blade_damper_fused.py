"""Compiled DOP853 phases of the blade damper against SciPy's DOP853 (the path before).

``BladeDamperSystem(compiled_phases=True)`` (default) takes whole DOP853 steps, their dense
output, the event screening and the root refinement in compiled code, and projects the
state onto the constraints there too; ``compiled_phases=False`` is SciPy's DOP853 calling the
compiled right-hand side with the generic projection. Same method, same step-size control,
same event functions: the two differ by round-off in the Runge-Kutta sums (BLAS vs loops),
which the error estimate amplifies into slightly different step sequences, so the responses
agree to the integration accuracy (rtol 1e-8), not bit for bit.

Stated tolerance: after 6 forcing periods the same switching sequence (contact and new mode
of every event), event times within 2e-7 of the period, and the final state within 1e-6 of
each coordinate's range of motion, away from resonance (58 Hz, 4-6 switches per period) and
at the friction-damped resonance (51 Hz, gamma = 65 degrees, 6-16 per period). Measured
(2026-11-28): 5.6e-8 of the period and 3.6e-7 of the range at 58 Hz; 1.2e-8 and 2.9e-8 at
51 Hz.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from fricdamp.errors import ConvergenceError
from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper.studies import time_response
from fricdamp.solvers.event_switch import Evaluator

RNG = np.random.default_rng(1414)


@pytest.mark.parametrize("f_hz, gamma_deg", [(58.0, 50.0), (51.0, 65.0)])
def test_fused_phases_equal_scipy_dop853(f_hz, gamma_deg):
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=f_hz
                              ).with_(gamma_deg=gamma_deg)
    new, old = BladeDamperSystem(p), BladeDamperSystem(p, compiled_phases=False)
    y0 = np.concatenate([new.static_equilibrium().q, np.zeros(7)])
    # start on the stick-slip motion (the transient from rest takes a few periods)
    r = time_response(old, 4.0, y0=y0).result
    y0 = np.concatenate([r.q[-1], r.qd[-1]])
    t0 = 4.0 / f_hz
    a = time_response(new, 6.0, y0=y0, t_start=t0).result
    b = time_response(old, 6.0, y0=y0, t_start=t0).result
    assert a.success and b.success
    assert a.n_events == b.n_events > 6 * 3
    assert [(e.contact, e.to_mode) for e in a.events] == [(e.contact, e.to_mode)
                                                          for e in b.events]
    assert np.max(np.abs(np.array([e.time for e in a.events])
                         - np.array([e.time for e in b.events]))) < 2e-7 / f_hz
    scale = np.ptp(b.q, axis=0)
    assert np.all(np.abs(a.q[-1] - b.q[-1]) <= 1e-6 * scale)
    assert np.all(np.abs(a.qd[-1] - b.qd[-1]) <= 1e-6 * np.ptp(b.qd, axis=0))
    # the energy balance closes as well on both paths
    assert a.energy_balance_error < 1e-6 and b.energy_balance_error < 1e-6
    # the same work: the step sequences differ only where the error estimate is near 1
    assert a.n_rhs > 0 and abs(a.n_rhs - b.n_rhs) < 0.1 * b.n_rhs


def test_compiled_projection_equals_generic():
    """Gauss-Newton on the gaps and the M-orthogonal velocity projection, compiled vs the
    generic Evaluator.project (lambdified kinematics), in every stick/slip configuration."""
    p = BladeDamperParameters(gamma=np.deg2rad(55.0))
    fast = Evaluator(BladeDamperSystem(p))
    ref = Evaluator(BladeDamperSystem(p, compiled=False))
    for modes in itertools.product((0, 1, -1), repeat=2):
        m = np.array(modes)
        for _ in range(5):
            q, _ = fast.system.full_state(np.concatenate([RNG.uniform(-2e-4, 2e-4, 4),
                                                          RNG.uniform(-0.05, 0.05, 1)]))
            q = q + RNG.uniform(-1e-9, 1e-9, 7)  # off the constraints
            qd = np.concatenate([RNG.uniform(-0.3, 0.3, 4), RNG.uniform(-30, 30, 1),
                                 RNG.uniform(-0.3, 0.3, 2)])
            q1, qd1, e1 = fast.project(0.0, q, qd, m)
            q2, qd2, e2 = ref.project(0.0, q, qd, m)
            assert np.max(np.abs(q1 - q2)) <= 1e-15 * (1 + np.max(np.abs(q)))
            assert np.max(np.abs(qd1 - qd2)) <= 1e-12 * np.max(np.abs(qd))
            assert abs(e1 - e2) <= 1e-10 * max(e2, 0.5 * qd @ fast.system.M @ qd * 1e-6)
            # the projected state satisfies the constraints
            g = fast.system.normal_gap(q1)
            assert np.all(np.abs(g) <= 1e-15 * (1 + np.abs(q).max()))
            WN, WT, _, _ = fast.system.kinematics(q1, qd1)
            assert np.all(np.abs(WN.T @ qd1) <= 1e-12 * np.abs(qd).max())
            stick = m == 0
            assert np.all(np.abs(WT[:, stick].T @ qd1) <= 1e-12 * np.abs(qd).max())


def test_compiled_switching_solve_equals_generic():
    """Evaluator.solve with GIVEN contacts (the switching problem's affine maps, several
    right-hand sides) and plain configurations: compiled vs generic, to 1e-12 of the scale."""
    p = BladeDamperParameters(gamma=np.deg2rad(60.0), excitation_amplitude=5.0)
    fast = Evaluator(BladeDamperSystem(p))
    ref = Evaluator(BladeDamperSystem(p, compiled=False))
    assert fast._fused is not None and ref._fused is None
    for modes in itertools.product((0, 1, -1, 2), repeat=2):
        m = np.array(modes)
        for sigma in (np.ones(2), np.array([1.0, -1.0])):
            q, _ = fast.system.full_state(np.concatenate([RNG.uniform(-2e-4, 2e-4, 4),
                                                          RNG.uniform(-0.05, 0.05, 1)]))
            qd = np.concatenate([RNG.uniform(-0.3, 0.3, 4), RNG.uniform(-30, 30, 1),
                                 RNG.uniform(-0.3, 0.3, 2)])
            t = RNG.uniform(0, 0.1)
            given = RNG.uniform(-20, 20, (2, 3)) if (m == 2).any() else None
            a = fast.solve(fast.point(t, q, qd), m, sigma, given)
            b = ref.solve(ref.point(t, q, qd), m, sigma, given)
            lam_scale = np.abs(b[1]).max() + np.abs(b[2]).max()
            acc_scale = np.max(np.abs(b[0])) + lam_scale / p.damper_inertia
            assert np.max(np.abs(a[0] - b[0])) <= 1e-12 * acc_scale
            assert np.max(np.abs(a[1] - b[1])) <= 1e-12 * lam_scale
            assert np.max(np.abs(a[2] - b[2])) <= 1e-12 * lam_scale


@pytest.mark.parametrize("seed", range(4))
def test_compiled_lemke_equals_python_lemke(seed):
    """The compiled Lemke kernel takes the same pivots as event_switch.lemke: same z on
    random friction LCPs with normal forces coupled to the friction forces (H != 0, as in the
    blade damper), including degenerate ones (a zero right-hand side entry) and unsolvable
    ones (ray termination)."""
    from fricdamp.solvers.event_switch import solve_friction_lcp

    rng = np.random.default_rng(300 + seed)
    for _ in range(25):
        k = 1 + int(rng.integers(0, 3))
        R = rng.normal(size=(k, k))
        G = R @ R.T + 0.2 * np.eye(k)
        b = 2 * rng.normal(size=k)
        if rng.random() < 0.3:
            b[0] = 0.0
        H = 0.3 * rng.normal(size=(k, k))
        c = rng.uniform(0.2, 2.0, size=k)
        mu = rng.uniform(0.1, 0.6, size=k)
        try:
            l1, a1 = solve_friction_lcp(G, b, H, c, mu)
        except ConvergenceError:  # no solution (a ray): the kernel says so too
            with pytest.raises(ConvergenceError, match="ray"):
                solve_friction_lcp(G, b, H, c, mu, compiled=True)
            continue
        l2, a2 = solve_friction_lcp(G, b, H, c, mu, compiled=True)
        assert np.max(np.abs(l1 - l2)) <= 1e-12 * (1 + np.abs(l1).max())
        assert np.max(np.abs(a1 - a2)) <= 1e-12 * (1 + np.abs(a1).max())
