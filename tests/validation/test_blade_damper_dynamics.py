"""Event-driven dynamics of the paper-000 blade-damper model.

References: Pfeiffer & Hajek (1992), paper 000: configurations (1)-(4), equations of motion
with multipliers (29)-(40), switching rules (41)-(46). Checks: every configuration is
reached, the friction laws hold in each state, the energy balance closes, the frictionless
motion follows the free-sliding linearisation to second order in the amplitude, and a
negative normal force is reported, not hidden.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper_analyses import CONFIGURATIONS, time_response


def _kicked(p, v):
    """Static state with the independent velocities v = (q1', q2', q3', q4', q5')."""
    s = BladeDamperSystem(p)
    q, qd = s.full_state(s.static_equilibrium().q[:5], v)
    return s, np.concatenate([q, qd])


@pytest.fixture(scope="module")
def kicked_runs():
    """Platforms pushed apart (both contacts slip), with the damper spun either way so
    that either contact sticks first; 0.5 periods of 60 Hz."""
    p = BladeDamperParameters(excitation_amplitude=0.0)
    runs = []
    for w5 in (50.0, -50.0):
        s, y0 = _kicked(p, [-0.3, 0.0, 0.3, 0.0, w5])
        runs.append(time_response(s, 0.5, y0=y0, samples_per_period=200, rtol=1e-9))
    return p, runs


def test_all_four_configurations_are_reached(kicked_runs):
    """000 (1)-(4): slip/slip (5 DOF), slip/stick and stick/slip (4 DOF), stick/stick
    (3 DOF) all occur, each for a finite time."""
    _, runs = kicked_runs
    total = {name: sum(r.time_in_configuration[name] for r in runs) for name in CONFIGURATIONS}
    assert all(v > 1e-5 for v in total.values()), total
    for r in runs:
        assert r.ok, r.errors


def test_friction_laws_hold_in_each_state(kicked_runs):
    """000 (42): |lambda_T| <= mu_static lambda_N in stick, with zero slip velocity;
    000 (34), (44): lambda_T = -mu_sliding lambda_N sign(gamma_T) in slip. Tolerances:
    1e-9 of the normal force (the solver's multipliers are exact up to round-off) and
    1e-9 m/s of slip velocity in stick (DOP853 drift at rtol 1e-9)."""
    p, runs = kicked_runs
    for tr in runs:
        r = tr.result
        s = BladeDamperSystem(p)
        gam = np.array([s.slip_velocity(q, qd) for q, qd in zip(r.q, r.qd, strict=True)])
        N, T, m = r.lambda_N, r.lambda_T, r.modes
        stick = m == 0
        assert np.all(np.abs(T[stick]) <= p.mu_static * N[stick] * (1 + 1e-9))
        assert np.all(np.abs(gam[stick]) < 1e-9)
        slip = m != 0
        assert np.allclose(T[slip], -p.mu_sliding * N[slip] * m[slip], rtol=1e-9, atol=0)
        assert np.all(N > 0)


def test_energy_balance_of_forced_stick_slip():
    """Input work = friction + viscous dissipation + change of kinetic and potential energy
    (potential: springs and -F_Z yS). The solver integrates the powers with Gauss-Legendre
    quadrature on the DOP853 steps: relative residual below 1e-6 at rtol 1e-9."""
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=58.0)
    tr = time_response(p, 3.0, samples_per_period=100, rtol=1e-9)
    r = tr.result
    assert tr.ok, tr.errors
    assert r.energy["friction_dissipation"][-1] > 0
    assert sum(tr.time_in_configuration[c] for c in CONFIGURATIONS[1:]) > 0
    assert r.energy_balance_error < 1e-6


@pytest.mark.parametrize("mode", [2, 4], ids=["platform", "rocking"])
def test_frictionless_motion_follows_sliding_linearisation_to_second_order(mode):
    """With (practically) no friction and no damping, a free vibration started in an
    eigenmode of the free-sliding linearisation (000 (1)) stays in it: the deviation from
    the linear solution over one period is O(eps^2) or smaller. Halving the amplitude divides
    deviation/eps by 2 (quadratic terms; 4 for the rocking mode, whose symmetry cancels
    them): accepted 1.7-4.6; at eps the deviation is below 5 % of eps.
    mu = 1e-9 instead of 0: the friction force (1e-7 N) changes the motion by ~1e-8
    relative, and the solver's friction complementarity problem is degenerate at mu = 0."""
    p = BladeDamperParameters(mu_static=1e-9, mu_sliding=1e-9,
                              dampings=(0.0, 0.0, 0.0, 0.0), excitation_amplitude=0.0)
    s = BladeDamperSystem(p)
    L = s.sliding_system()
    lam, V = sla.eigh(L.K, L.M)
    w = np.sqrt(lam[mode])
    phi = V[:, mode] / np.max(np.abs(V[:, mode] * [1, 1, 1, 1, 1e-2]))  # q5 scaled by 1e-2 m
    z0 = s.static_equilibrium().q[:5]
    rel = []
    for eps in (1e-4, 0.5e-4):
        q, qd = s.full_state(z0, eps * w * phi)
        pp = p.with_(excitation_frequency=w / (2 * np.pi))
        tr = time_response(BladeDamperSystem(pp), 1.0, y0=np.concatenate([q, qd]),
                           samples_per_period=100, rtol=1e-10, atol=1e-14)
        assert tr.ok, tr.errors
        r = tr.result
        lin = z0[None] + eps * np.outer(np.sin(w * r.t), phi)
        scale = np.maximum(np.abs(eps * phi), 1e-3 * np.abs(eps * phi).max())
        rel.append(np.max(np.abs(r.q[:, :5] - lin) / scale))
        assert r.energy_balance_error < 1e-7
    assert rel[0] < 0.05
    assert 1.7 < rel[0] / rel[1] < 4.6


def test_negative_normal_force_is_reported():
    """With a tiny centrifugal force (0.01 N) the 1 g damper cannot follow the wedge when
    the platforms, kicked towards each other, spring back apart (the damper would need
    m5 cot(gamma) q'' ~ 0.1 N to follow): a normal force becomes negative. The model keeps
    the contacts closed (as the paper does) but the result says so instead of hiding it."""
    p = BladeDamperParameters(centrifugal_force=0.01, excitation_amplitude=0.0)
    s, y0 = _kicked(p, [0.3, 0.0, -0.3, 0.0, 0.0])
    tr = time_response(s, 0.3, y0=y0, samples_per_period=200, rtol=1e-7)
    assert not tr.ok
    assert tr.min_normal_force < 0
    assert any("negative normal force" in e for e in tr.errors)


def test_phase_plot_data():
    """000 Fig. 8: (t, q4, q4') of the last periods."""
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=58.0)
    tr = time_response(p, 2.0, samples_per_period=50)
    t, x, v = tr.phase_plot(3, last_periods=1.0)
    assert t.size == x.size == v.size > 40
    assert t[0] >= t[-1] - 1 / 58.0 - 1e-12


def test_circular_damper_runs_through_stick_slip_with_energy_balance():
    """The circular contour (000 section 3.1: parabolic and circular dampers) goes through
    the same configurations; energy balance below 1e-6 at rtol 1e-9."""
    p = BladeDamperParameters(contour="circle", excitation_amplitude=0.0)
    s, y0 = _kicked(p, [-0.3, 0.0, 0.3, 0.0, 50.0])
    tr = time_response(s, 0.5, y0=y0, samples_per_period=200, rtol=1e-9)
    assert tr.ok, tr.errors
    assert sum(v > 0 for v in tr.time_in_configuration.values()) >= 3
    assert tr.result.energy_balance_error < 1e-6
