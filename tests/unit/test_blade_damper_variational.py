"""Compiled linearisation of blade-damper phases (``_variational``) against the Python path.

Shooting's monodromy matrix multiplies, phase by phase, the Jacobian of the projection and
the transition matrix of the variational equation (fourth-order Magnus steps on the halves
of the phase's DOP853 steps). The kernels of :mod:`fricdamp.models.blade_damper._variational`
do the same arithmetic as :class:`fricdamp.solvers.shooting._Linearizer` in one call per
phase: the same dense output, the same central-difference Jacobians with the same steps, and
a matrix exponential by the [13/13] Pade approximant with scaling and squaring instead of
SciPy's ``expm``. Tolerances: the exponential agrees with SciPy's to 1e-13 of ``||exp(A)||``
(both are backward stable to about 10 unit round-offs times the condition of the
exponential, which is modest for these norms); the monodromy matrix of one forcing period
(about 16 phases, 200 Magnus steps, |mu|max ~ 1) to 1e-9 of its largest entry, room for
round-off growing through the products (measured 2026-11-29: below 1e-12).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper._compiled import BladeDamperKernels
from fricdamp.models.blade_damper.studies import time_response
from fricdamp.solvers.shooting import flow


@pytest.fixture(scope="module")
def system():
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=51.0
                              ).with_(gamma_deg=65.0)
    return BladeDamperSystem(p)


@pytest.mark.parametrize("scale", [1e-6, 0.3, 4.0, 40.0, 900.0])
def test_expm_matches_scipy(system, scale):
    mod = BladeDamperKernels(system).mod
    rng = np.random.default_rng(7)
    for _ in range(5):
        A = rng.standard_normal((14, 14))
        A *= scale / np.abs(A).sum(axis=0).max()
        if scale > 100:  # fast decaying components beside slow ones, as in the phases
            A -= np.diag(np.linspace(0.0, scale / 20.0, 14))
        E = np.empty((14, 14))
        mod.expm_pade13(A, E)
        ref = sla.expm(A)
        assert np.abs(E - ref).max() <= 1e-13 * np.abs(ref).max()


def test_expm_of_a_badly_scaled_phase_matrix(system):
    """A Magnus step's matrix h [[0, I], [-K, -C]] with the damper's rocking (784 Hz) beside
    the blades (50 Hz): ||A||_1 ~ 2e3 but a spectral radius ~ 0.5. Scaling by the norm alone
    squares 9 times more than needed and loses 2e-9 (measured); scaling by the norms of A's
    powers keeps round-off level against a 30-digit reference (mpmath)."""
    import mpmath

    mod = BladeDamperKernels(system).mod
    rng = np.random.default_rng(3)
    w = 2 * np.pi * np.array([50.0, 52.0, 100.0, 784.0, 60.0, 97.0, 51.0])
    Q = np.linalg.qr(rng.standard_normal((7, 7)))[0]
    K = Q @ np.diag(w ** 2) @ Q.T
    C = 1e-3 * K + 2.0 * np.eye(7)
    h = 1e-4
    A = h * np.block([[np.zeros((7, 7)), np.eye(7)], [-K, -C]])
    assert np.abs(A).sum(axis=0).max() > 1e3
    with mpmath.workdps(30):
        ref = np.array(mpmath.expm(mpmath.matrix(A.tolist())).tolist(), dtype=float)
    E = np.empty((14, 14))
    mod.expm_pade13(A, E)
    assert np.abs(E - ref).max() <= 1e-14 * np.abs(ref).max()


def test_expm_of_a_rotation_is_exact(system):
    """exp of [[0, w], [-w, 0]] t is the rotation by w t (closed form), here w t = 20 rad."""
    mod = BladeDamperKernels(system).mod
    a = 20.0
    A = np.array([[0.0, a], [-a, 0.0]])
    E = np.empty((2, 2))
    mod.expm_pade13(A, E)
    ref = np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
    assert np.abs(E - ref).max() <= 1e-13


def _python_path(monkeypatch) -> dict:
    """Make the compiled linearisation report "singular", so that the Python path of
    shooting._Linearizer takes over; returns the counts of refused calls."""
    calls = {"transition": 0, "projection_jacobian": 0}
    for name in calls:
        orig = getattr(BladeDamperKernels, name)

        def refuse(self, *a, _name=name, _orig=orig, **k):
            calls[_name] += 1
            out = list(_orig(self, *a, **k))
            out[0] = 0.0  # "singular": the Python path takes over
            return tuple(out)
        monkeypatch.setattr(BladeDamperKernels, name, refuse)
    return calls


def test_monodromy_compiled_equals_python(system, monkeypatch):
    f = system.params.excitation_frequency
    y0 = np.concatenate([system.static_equilibrium().q, np.zeros(7)])
    r = time_response(system, 6.0, y0=y0).result
    y = np.concatenate([r.q[-1], r.qd[-1]])
    t0 = 6.0 / f
    fast = flow(system, (t0, t0 + 1.0 / f), y, rtol=1e-9)
    calls = _python_path(monkeypatch)
    slow = flow(system, (t0, t0 + 1.0 / f), y, rtol=1e-9)
    assert calls["transition"] >= 3 and calls["projection_jacobian"] >= 3
    assert np.array_equal(fast.y_end, slow.y_end)
    M, R = fast.monodromy, slow.monodromy
    assert np.abs(M - R).max() <= 1e-9 * np.abs(R).max()
    assert abs(fast.monodromy_error - slow.monodromy_error) <= 1e-9


def test_released_monodromy_through_lift_off(monkeypatch):
    """The released damper beyond lift-off (gamma = 80 deg, 52 Hz, 8 N) over the 1.7 ms in
    which contact K1 lifts off (its normal force reaches zero at t = 0.131884 s) and the
    damper flies free of it (the first impact follows at 0.13333 s): Magnus transitions and
    projections of phases with an open contact. The compiled linearisation equals the Python
    path (1e-9 of the largest entry, as above), and the monodromy predicts the flow of
    perturbed starts (put back on the closed contacts): central differences at 1e-7 of each
    coordinate's scale agree to 1e-4 of it (measured 7.6e-6, the differences' truncation
    error). The lift-off's saltation matrix is the identity here (the normal force, and with
    it the vector field, is continuous through zero), so this checks the open phases; the
    impact saltation is validated in tests/validation/test_orbit_continuation_impacts.py."""
    from fricdamp.solvers.event import simulate_events
    from fricdamp.solvers.event_switch import Evaluator

    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=52.0).with_(
        gamma_deg=80.0)
    s = BladeDamperSystem(p, release=True)
    y0 = np.concatenate([s.static_equilibrium().q, np.zeros(7)])
    t0, t1 = 0.1315, 0.1332
    r = simulate_events(s, (0.0, t0), y0, rtol=1e-10, atol=1e-13, progress=False)
    y = np.concatenate([r.q[-1], r.qd[-1]])
    fast = flow(s, (t0, t1), y, rtol=1e-10)
    modes = [tuple(rec.modes) for rec in fast.trace]
    assert any(3 in m for m in modes) and 3 not in modes[0]
    scale = np.concatenate([np.abs(r.q).max(axis=0), np.abs(r.qd).max(axis=0)])
    ev = Evaluator(s)

    def on_constraints(yy):
        # a perturbed start put back on the closed contacts (the flow's own first step,
        # whose Jacobian is the monodromy's first factor; a start penetrating a unilateral
        # contact is refused)
        q, qd, _ = ev.project(t0, yy[:7], yy[7:], np.asarray(fast.trace[0].modes))
        return np.concatenate([q, qd])

    E = np.zeros(14)
    for j in range(14):
        dy = np.zeros(14)
        dy[j] = 1e-7 * scale[j]
        yp = flow(s, (t0, t1), on_constraints(y + dy), rtol=1e-12, monodromy=False).y_end
        ym = flow(s, (t0, t1), on_constraints(y - dy), rtol=1e-12, monodromy=False).y_end
        fd = (yp - ym) / (2 * dy[j])
        E = np.maximum(E, np.abs(fd - fast.monodromy[:, j]) * scale[j])
    assert np.all(E <= 1e-4 * scale)
    calls = _python_path(monkeypatch)
    slow = flow(s, (t0, t1), y, rtol=1e-10)
    assert calls["transition"] >= 2 and calls["projection_jacobian"] >= 2
    assert np.array_equal(fast.y_end, slow.y_end)
    M, R = fast.monodromy, slow.monodromy
    assert np.abs(M - R).max() <= 1e-9 * np.abs(R).max()
