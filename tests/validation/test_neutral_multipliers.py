"""Neutral Floquet multipliers of always-stuck contacts and the practical stability rule.

A contact that sticks during a whole orbit keeps whatever tangential preload it locked in:
the orbit belongs to a family, with a multiplier exactly 1. :func:`neutral_stability`
excludes that direction by its invariant (the contact's tangential displacement functional,
projected on the closed gaps) and judges the remaining multipliers.

References: Leine & Nijmeijer (2004), ch. 3 (invariant manifolds of non-smooth maps);
closed-form multipliers of the stuck linear system ``exp(A T)``.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp.solvers.event_system import CoulombSystem
from fricdamp.solvers.shooting import neutral_stability, shoot
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem

W = 0.8


def _two_dof(d1, normal_load):
    """m1 = m2 = 1 kg, k1 = k2 = 1 N/m (ground-m1-m2), dashpot d1 on m1, 0.02 on m2; 0.2 N
    at W on m1; a Coulomb contact on m2 (to ground) with the given normal load (mu = 1)."""
    M = np.eye(2)
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    D = np.diag([d1, 0.02])
    s = MechanicalSystem(M=M, K=K, D=D, loads=(HarmonicLoad([0.2, 0.0], W),))
    return CoulombSystem(s, directions=[[0.0, 1.0]], normal_load=normal_load, mu_static=1.0), \
        M, K, D


def test_always_stuck_contact_multipliers_equal_the_stuck_system_closed_form():
    """m2 never slips (mu N = 10 N >> spring force): multipliers {1 (neutral preload), 0
    (stuck velocity), exp(A T) of m1 with m2 held}. Exact phases: tolerance 1e-10."""
    cs, M, K, D = _two_dof(0.05, 10.0)
    orb = shoot(cs, 2 * np.pi / W, period_multiple=1)
    assert orb.success and np.all(orb.modes == 0)
    assert np.abs(orb.multipliers[0] - 1.0) < 1e-10  # the neutral one
    assert not orb.stable  # the strict criterion cannot call it stable
    ns = neutral_stability(cs, orb)
    assert ns.neutral_contacts == (0,) and ns.invariance_residuals[0] < 1e-10
    A = np.array([[0.0, 1.0], [-K[0, 0] / M[0, 0], -D[0, 0] / M[0, 0]]])
    ref = np.sort(np.abs(np.linalg.eigvals(sla.expm(A * 2 * np.pi / W))))[::-1]
    got = np.abs(ns.multipliers)
    assert got.size == 3
    np.testing.assert_allclose(got[:2], ref, rtol=1e-10)
    assert got[2] < 1e-10
    assert ns.stable and not ns.stable_strict
    assert ns.max_multiplier == pytest.approx(ref[0], rel=1e-10)


def test_rule_still_finds_an_unstable_always_stuck_orbit():
    """Negative damping on m1 (d1 = -0.05): the stuck system grows, exp(0.025 T) per period;
    excluding the neutral direction must not hide that (the rule can fail)."""
    cs, M, K, D = _two_dof(-0.05, 10.0)
    orb = shoot(cs, 2 * np.pi / W, period_multiple=1)
    ns = neutral_stability(cs, orb)
    assert ns.neutral_contacts == (0,)
    assert not ns.stable
    assert ns.max_multiplier == pytest.approx(np.exp(0.025 * 2 * np.pi / W), rel=1e-9)


def test_slipping_contact_excludes_nothing():
    """mu N = 0.05 N: m2 slips twice per period; no neutral direction, the rule reduces to
    the strict criterion."""
    cs, *_ = _two_dof(0.05, 0.05)
    orb = shoot(cs, 2 * np.pi / W)
    assert orb.success and np.any(orb.modes != 0)
    ns = neutral_stability(cs, orb)
    assert ns.neutral_contacts == () and ns.stable == orb.stable == ns.stable_strict
    np.testing.assert_allclose(np.abs(ns.multipliers), np.abs(orb.multipliers), rtol=1e-12)
