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


def test_monodromy_compiled_equals_python(system, monkeypatch):
    f = system.params.excitation_frequency
    y0 = np.concatenate([system.static_equilibrium().q, np.zeros(7)])
    r = time_response(system, 6.0, y0=y0).result
    y = np.concatenate([r.q[-1], r.qd[-1]])
    t0 = 6.0 / f
    fast = flow(system, (t0, t0 + 1.0 / f), y, rtol=1e-9)
    calls = {"transition": 0, "projection_jacobian": 0}
    for name in calls:
        orig = getattr(BladeDamperKernels, name)

        def refuse(self, *a, _name=name, _orig=orig, **k):
            calls[_name] += 1
            out = list(_orig(self, *a, **k))
            out[0] = 0.0  # "singular": the Python path takes over
            return tuple(out)
        monkeypatch.setattr(BladeDamperKernels, name, refuse)
    slow = flow(system, (t0, t0 + 1.0 / f), y, rtol=1e-9)
    assert calls["transition"] >= 3 and calls["projection_jacobian"] >= 3
    assert np.array_equal(fast.y_end, slow.y_end)
    M, R = fast.monodromy, slow.monodromy
    assert np.abs(M - R).max() <= 1e-9 * np.abs(R).max()
    assert abs(fast.monodromy_error - slow.monodromy_error) <= 1e-9
