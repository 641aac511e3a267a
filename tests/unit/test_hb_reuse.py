"""Reuse in the HB continuation (issue 13): fill-reducing orderings kept per sparsity
pattern, the compiled Jacobian scatter, and the opt-in Broyden corrector.

References: the frequency response of the ring of 30 Jenkins contacts (the peers' benchmark,
benchmarks/bench_hb_ring.py) computed by the implementation before these changes (commit
6df22a0: SuperLU with its ordering recomputed at every factorisation, ``np.bincount``
scatter). With the Newton corrector the same points are computed, so the peak (parabola
through the three largest points) must agree to 1e-8 relative: the changes reorder the
floating-point work only (measured agreement ~1e-12).
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.solvers import hb
from fricdamp.solvers._hb_formulations import _Full, _Setup
from fricdamp.solvers.continuation import _Factor, _Orderings, solve_and_continue
from fricdamp.structure import ContactElement, MechanicalSystem

#: Peak (Omega [rad/s], amplitude of DOF 0 [m]) and points of the ring of 30, H = 5, N = 64,
#: Omega 0.9 -> 1.3, default steps, by the implementation of commit 6df22a0.
REFERENCE_PEAK = (1.046901368735, 0.1536493859274)
REFERENCE_POINTS = 81


def ring(n=30):
    K = sp.lil_matrix((n, n))
    P = sp.lil_matrix((n, n))
    for i in range(n):
        j = (i + 1) % n
        K[i, i] += 1.1
        K[i, j] -= 0.05
        K[j, i] -= 0.05
        P[i, i] = -1.0
        P[i, j] = 1.0
    return MechanicalSystem(M=sp.identity(n, format="csr"), K=K.tocsr(),
                            D=0.005 * sp.identity(n, format="csr"),
                            contacts=(ContactElement(Jenkins(0.5, 0.02, n_contacts=n),
                                                     P.tocsr(), name="jenkins"),),
                            loads=(hb.engine_order_load(n, 3, 0.01),), name="ring")


def test_ring_peak_unchanged_by_ordering_reuse_and_compiled_scatter():
    fr = hb.frequency_response(ring(), 0.9, 1.3, harmonics=5, samples=64)
    assert fr.success, fr.message
    assert fr.method == "full-sparse"
    assert fr.n_points == REFERENCE_POINTS
    w, a = fr.peak(0)
    assert w == pytest.approx(REFERENCE_PEAK[0], rel=1e-8)
    assert a == pytest.approx(REFERENCE_PEAK[1], rel=1e-8)


def _physical_residual(system, fr):
    """max |S X + P^T f(P X) - F| / max |F| over the points of a curve."""
    s = _Setup(system, fr.harmonics, fr.samples)
    form = _Full(s)
    f_ref = np.abs(s.F_ex).max()
    return max(np.abs(form.evaluate(X.ravel(), w, jacobian=False)[0]).max() / f_ref
               for X, w in zip(fr.coefficients, fr.omega, strict=True))


def test_broyden_corrector_points_are_solutions(monkeypatch):
    # the opt-in corrector places its points differently (its step control sees other
    # iterations), so its points are checked against the residual itself: the continuation
    # tolerance is 1e-9 on the residual scaled by the load, 1e-8 leaves room for rounding
    system = ring()
    monkeypatch.setattr(hb, "REUSE_FACTORIZATION", True)
    fr = hb.frequency_response(system, 0.9, 1.3, harmonics=5, samples=64)
    assert fr.success, fr.message
    assert _physical_residual(system, fr) <= 1e-8
    # fewer factorisations than points x Newton iterations: the factorisation is reused
    assert fr.n_factorizations < 2 * fr.n_points
    # the peak lies within the sampling error of the reference curve (its 81 points are
    # ~0.005 rad/s apart at the peak: the parabola vertex moves by ~1e-3 relative)
    w, a = fr.peak(0)
    assert a == pytest.approx(REFERENCE_PEAK[1], rel=2e-3)
    assert w == pytest.approx(REFERENCE_PEAK[0], rel=1e-3)


def test_ordering_kept_per_pattern_and_solves_exact():
    rng = np.random.default_rng(3)
    n = 60
    # an arrow matrix numbered badly: its dense row and column first, so the natural
    # order fills completely and the minimum-degree ordering (kept) does not
    A = (sp.random(n, n, density=0.02, random_state=4) + 10 * sp.identity(n)).tolil()
    A[0, :] = 1.0
    A[:, 0] = 1.0
    A = sp.csc_matrix(A)
    orderings = _Orderings()
    b = rng.standard_normal(n)
    fills = []
    for k in range(5):
        B = A.copy()
        B.data = B.data * (1.0 + 0.1 * k)
        F = _Factor(B, orderings)
        assert F.ok
        x = F.solve(b)
        assert np.max(np.abs(B @ x - b)) <= 1e-12 * np.max(np.abs(b))
        fills.append(F.lu.L.nnz + F.lu.U.nnz)
        sign, logdet = F.log_det()
        s_ref, l_ref = np.linalg.slogdet(B.toarray())
        assert sign == s_ref and logdet == pytest.approx(l_ref, rel=1e-10)
    assert len(orderings.items) == 1
    # trial 1 is the natural order, trial 2 the kept minimum-degree permutation: the one
    # with less fill serves from then on
    assert fills[1] > 3 * fills[2]
    assert fills[2] == fills[3] == fills[4]


def test_broyden_on_a_smooth_path():
    # S-curve x^3 - x + lam = 0 through both folds, sparse Jacobian: every point a solution
    def fun(x, lam):
        return x**3 - x + lam, sp.csc_matrix(np.diag(3 * x**2 - 1)), np.ones_like(x)

    res = solve_and_continue(np.array([1.3]), fun, -1.0, 1.0, 0.05, tol=1e-12,
                             reuse_factorization=True)
    assert res.success, res.message
    assert len(res.turning_points) == 2
    for x, lam in zip(res.x, res.lam, strict=True):
        assert abs(x[0] ** 3 - x[0] + lam) <= 1e-11
