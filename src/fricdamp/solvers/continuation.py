"""Newton's method and pseudo-arclength continuation of ``R(x, lam) = 0``.

This module knows nothing of the problem: it sees a residual function and its Jacobian.
``residual(x, lam)`` returns ``(r, J_x, J_lam)`` with ``r`` shape (n,), ``J_x`` the
Jacobian dR/dx as a dense (n, n) array or a scipy sparse matrix, and ``J_lam`` = dR/dlam
shape (n,). The continuation follows the solution curve through turning points (folds in
lam) with a tangent predictor, a Newton corrector on the hyperplane orthogonal to the
tangent (Keller's pseudo-arclength condition), and an adaptive step. One factorisation of
the bordered Jacobian per Newton iteration; the tangent at a converged point reuses the last
factorisation.

A failed corrector is retried with half the step; when the step falls below ``ds_min``
the run stops and the result says so (``status``, ``message``) and holds the points
converged until then: a non-converged point is never returned as a solution.

Test functions along the path: every point keeps its unit tangent (in the scaled variables),
whose parameter component changes sign at a fold (turning point); with
``test_functions=True`` the sign of the determinant of the bordered Jacobian
``[[J_x, J_lam], [t^T]]`` is kept too: with the tangents oriented continuously it changes
sign at a simple branch point and not at a fold (Seydel 2010, sec. 5.3; Allgower & Georg
2003, ch. 8). :func:`locate_on_branch` finds the zero of any such test function between two
points by regula falsi on the arclength, each trial point corrected back onto the path.

References
----------
Seydel (2010), *Practical Bifurcation and Stability Analysis*, Springer, ch. 4-5.
Allgower & Georg (2003), *Introduction to Numerical Continuation Methods*, SIAM, ch. 8.
Krack & Gross (2019), *Harmonic Balance for Nonlinear Vibration Problems*, ch. 4.
"""

from __future__ import annotations

import contextlib
import logging
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fricdamp.errors import ConvergenceError, ModelError

__all__ = [
    "ContinuationResult",
    "NewtonResult",
    "PathPoint",
    "blas_threads",
    "locate_on_branch",
    "newton",
    "solve_and_continue",
]

logger = logging.getLogger(__name__)

#: Status codes of :class:`ContinuationResult`.
STATUS_MESSAGES = {
    0: "reached the end of the parameter interval",
    1: "maximum number of continuation steps reached",
    2: "continuation stalled: the corrector failed down to the minimum step",
    3: "the path turned back and left the parameter interval at its start",
    4: "stopped by the callback",
    -1: "no solution at the start parameter: Newton failed from the initial guess",
}


def blas_threads(n: int | None):
    """Context limiting the BLAS thread pools to ``n`` threads (no-op for None).

    Small dense solves (a few hundred unknowns) are dominated by thread start-up and
    contention on a 2-core machine: a 330 x 330 ``numpy.linalg.solve`` measured 19 ms with
    the default pool and 1.1 ms with one thread (benchmarks/bench_hb_ring.py reports both),
    so the solvers default to one thread.

    The BLAS libraries of the process are found once (``threadpoolctl.ThreadpoolController``,
    ~1.3 ms: it walks every loaded shared library) and found again only when modules were
    imported since, which is how a new BLAS arrives; entering the context then costs ~20 us
    instead of ~1.3 ms (a single-point harmonic balance costs a few ms).
    """
    if n is None:
        return contextlib.nullcontext()
    from threadpoolctl import ThreadpoolController

    controller, n_modules = _BLAS_CONTROLLER
    if controller is None or n_modules != len(sys.modules):
        controller = ThreadpoolController()
        _BLAS_CONTROLLER[:] = [controller, len(sys.modules)]
    return controller.limit(limits=int(n), user_api="blas")


#: (threadpoolctl controller, number of imported modules when it was built)
_BLAS_CONTROLLER: list = [None, -1]


# ---------------------------------------------------------------------------- linear algebra
class _Ordering:
    """Fill-reducing column ordering of one sparsity pattern, chosen once and reused.

    SuperLU (through SciPy) recomputes its ordering at every factorisation and exposes no
    symbolic reuse. Newton steps and continuation points factorise matrices of one fixed
    pattern, so the ordering is chosen once per pattern by measurement and then applied
    as a symmetric permutation ``B = A[p][:, p]`` (one gather of the values through a
    precomputed map), with SuperLU told to keep the column order (``NATURAL``): the first
    factorisation uses the minimum-degree ordering on ``A + A^T`` and records it, the second
    the pattern's own order, the third the recorded ordering as a permutation; the one with
    the least fill (nnz(L) + nnz(U)) serves every later factorisation. Every trial is a
    valid factorisation of its matrix, so nothing is factorised twice. Measured on the ring
    of 480 Jenkins contacts (H = 5, 5,281 unknowns): 10 ms with the minimum-degree ordering
    recomputed, 3.8 ms reusing the order (benchmarks/bench_hb_ring.py).
    """

    __slots__ = ("indptr", "indices", "n", "trials", "perm", "map", "B", "block",
                 "block_size")

    #: The dense-block LU serves a pattern if its storage (dense blocks, padded rows) is at
    #: most this multiple of SuperLU's fill nnz(L) + nnz(U): ring of 30 Jenkins contacts 1.2
    #: (block LU 3x faster); a structure whose DOF blocks are sparse (harmonics coupled at
    #: a few contact DOFs only) has ~5, and SuperLU's scalar sparsity wins there.
    BLOCK_FILL_RATIO = 2.0

    def __init__(self, A, block_size: int | None = None):
        self.indptr = A.indptr.copy()
        self.indices = A.indices.copy()
        self.n = A.shape[0]
        self.trials = []            # (fill, perm or None)
        self.perm = self.map = self.B = None
        self.block = None
        # block LU requested and not yet decided: decided after SuperLU's first
        # factorisation of the pattern, whose fill is the yardstick (then None)
        self.block_size = block_size if block_size is not None and block_size > 1 else None

    def matches(self, A) -> bool:
        return (A.shape[0] == self.n and A.indptr.size == self.indptr.size
                and A.indices.size == self.indices.size
                and np.array_equal(A.indptr, self.indptr)
                and np.array_equal(A.indices, self.indices))

    def _use(self, perm):
        """Prepare B = A[perm][:, perm] (CSC, sorted) and the value map from A's data."""
        n = self.n
        # values 1..nnz (not 0..: an explicit zero could be dropped by the indexing)
        A = sp.csc_matrix((np.arange(1, self.indices.size + 1, dtype=float), self.indices,
                           self.indptr), shape=(n, n))
        B = A[perm][:, perm].tocsc()
        B.sort_indices()
        self.map = B.data.astype(np.int64) - 1
        B.data = np.empty(self.map.size)
        self.B = B
        self.perm = perm

    def factor_block(self, A):
        """Dense-block factors (:mod:`fricdamp.solvers._sparse_lu`) of a matrix of this
        pattern, or None: no block analysis, or a pivot failed the threshold rule (then
        SuperLU pivots across blocks). After 20 failures in more than a quarter of the
        factorisations the block path is given up for this pattern."""
        if self.block is None and self.block_size is not None and self.trials:
            from fricdamp.solvers._sparse_lu import BlockLU

            b = BlockLU(A, self.block_size)
            fill = min(f for f, _ in self.trials)
            self.block_size = None
            if b.ok and b.size <= self.BLOCK_FILL_RATIO * fill:
                self.block = b
            else:
                logger.debug("block LU: storage %d vs SuperLU fill %d, SuperLU kept", b.size,
                             fill)
        b = self.block
        if b is None:
            return None
        F = b.factor(A.data)
        if F is None and b.failures > max(20, b.calls // 4):
            logger.debug("block LU: %d pivot failures, SuperLU from now on", b.failures)
            self.block = None
        return F

    def factor(self, A):
        """(SuperLU object, permutation or None) for a matrix of this pattern."""
        k = len(self.trials)
        if k == 0:
            lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=1e-3)
            self.trials.append((lu.L.nnz + lu.U.nnz, np.asarray(lu.perm_c, dtype=np.int64)))
            return lu, None
        if k == 1:
            lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=1e-3)
            self.trials.append((lu.L.nnz + lu.U.nnz, None))
            self._use(self.trials[0][1])
            return lu, None
        if k == 2:
            self.B.data = A.data[self.map]
            lu = spla.splu(self.B, permc_spec="NATURAL", diag_pivot_thresh=1e-3)
            fill_p = lu.L.nnz + lu.U.nnz
            self.trials.append((fill_p, self.perm))
            if self.trials[1][0] < fill_p:      # the pattern's own order fills less
                self.perm = self.map = self.B = None
            return lu, self.trials[2][1]
        if self.perm is None:
            return spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=1e-3), None
        self.B.data = A.data[self.map]
        return spla.splu(self.B, permc_spec="NATURAL", diag_pivot_thresh=1e-3), self.perm


def mark_fixed_pattern(A):
    """Promise that the sparsity pattern of the scipy matrix object ``A`` (its ``indptr`` and
    ``indices``) never changes, only its ``data``: a matrix object seen again is then not
    compared entry by entry with the pattern of its analysis (~0.1 ms per factorisation at
    10^4 entries). Returns ``A``."""
    A._fricdamp_fixed_pattern = True
    return A


def _fixed_pattern(A) -> bool:
    return getattr(A, "_fricdamp_fixed_pattern", False)


class _Orderings:
    """The orderings of the patterns met in one solve (usually one or two).

    ``block_size``: factorise by dense blocks of this many consecutive unknowns (the 2H+1
    harmonics of a DOF for harmonic balance; :mod:`fricdamp.solvers._sparse_lu`), the
    symbolic analysis kept per pattern; None: SuperLU only.
    """

    def __init__(self, block_size: int | None = None):
        self.items: list[_Ordering] = []
        self.block_size = block_size
        self._last = (None, None)

    def get(self, A) -> _Ordering:
        if A is self._last[0] and _fixed_pattern(A):
            return self._last[1]
        for o in self.items:
            if o.matches(A):
                break
        else:
            o = _Ordering(A, self.block_size)
            self.items = [o] + self.items[:3]
        self._last = (A, o)
        return o


class _Factor:
    """LU factorisation of a dense or sparse square matrix; ``ok`` False if singular.

    ``orderings`` (sparse only): an :class:`_Orderings` shared by the factorisations of one
    solve, so that the fill-reducing ordering of a pattern is computed once; with its
    ``block_size``, the dense-block LU of :mod:`fricdamp.solvers._sparse_lu` is tried first
    (SuperLU if a pivot fails its threshold rule).
    """

    __slots__ = ("lu", "sparse", "ok", "A", "checked", "perm", "block", "tangent")

    def __init__(self, A, orderings: _Orderings | None = None):
        self.sparse = sp.issparse(A)
        self.ok = True
        self.checked = False
        self.perm = None
        self.block = None
        self.tangent = None
        try:
            if self.sparse:
                # threshold pivoting (prefer the diagonal unless 1000x smaller than the column
                # maximum) on a minimum-degree ordering: 3-5x less fill and time than strict
                # partial pivoting on HB Jacobians; the first solve is checked and the
                # factorisation redone with partial pivoting if it lost accuracy
                self.A = A.tocsc() if A.format != "csc" else A
                if orderings is not None:
                    if not self.A.has_sorted_indices:
                        self.A = self.A.sorted_indices()
                    o = orderings.get(self.A)
                    self.block = o.factor_block(self.A)
                    if self.block is None:
                        self.lu, self.perm = o.factor(self.A)
                else:
                    self.lu = spla.splu(self.A, permc_spec="MMD_AT_PLUS_A",
                                        diag_pivot_thresh=1e-3)
            else:
                with np.errstate(all="ignore"):
                    import warnings

                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        self.lu = sla.lu_factor(A, check_finite=False)
                d = np.abs(np.diagonal(self.lu[0]))
                if not np.all(np.isfinite(d)) or d.min() <= 1e-14 * max(d.max(), 1e-300):
                    self.ok = False
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            self.ok = False

    def log_det(self) -> tuple[float, float]:
        """(sign, log |det|) of the factorised matrix (sign 0 if singular).

        A symmetric permutation ``A[p][:, p]`` has the determinant of ``A``.
        """
        if self.block is not None:
            d, sign = self.block.diagonal_and_sign()
        elif self.sparse:
            d = self.lu.U.diagonal()
            sign = _perm_sign(self.lu.perm_r) * _perm_sign(self.lu.perm_c)
        else:
            d = np.diagonal(self.lu[0])
            piv = self.lu[1]
            sign = -1.0 if np.count_nonzero(piv != np.arange(piv.size)) % 2 else 1.0
        if not np.all(np.isfinite(d)) or np.any(d == 0):
            return 0.0, -np.inf
        sign *= -1.0 if np.count_nonzero(d < 0) % 2 else 1.0
        return float(sign), float(np.sum(np.log(np.abs(d))))

    def _lu_solve(self, b):
        if self.block is not None:
            return self.block.solve(b)
        if self.perm is None:
            return self.lu.solve(b)
        y = self.lu.solve(b[self.perm])
        x = np.empty_like(y)
        x[self.perm] = y
        return x

    def solve_with(self, b, e):
        """``A^-1 b``, and ``A^-1 e`` kept in :attr:`tangent` when the dense-block factors
        give it in the same sweep (:meth:`BlockFactors.solve_pair`: for factors larger than
        the cache the second right-hand side costs a fraction of a solve), else left None.
        ``b`` is checked as the first solve of :meth:`solve` is."""
        block = self.block
        if block is None or b.ndim != 1:
            return self.solve(b)
        x, y = block.solve_pair(b, e)
        if not self.checked:
            x = self._check(b, x)
            if self.block is None:          # refactorised by SuperLU: y is not its solve
                return x
        self.tangent = y
        return x

    def solve(self, b):
        if not self.sparse:
            return sla.lu_solve(self.lu, b, check_finite=False)
        x = self._lu_solve(b)
        if not self.checked:
            x = self._check(b, x)
        return x

    #: Dense-block factors whose element growth ``max |L| max |U| / max |A|`` is at most
    #: this skip the residual check: their backward error (~ n eps growth max |A|, the
    #: bound of partial pivoting with its own growth) is that of the partial-pivoting
    #: refactorisation the check would fall back to. Rings of 30 and 480 Jenkins contacts
    #: (all 1,761 factorisations of their default and fine curves): growth 1.0-44, median
    #: 1.0-1.5; residuals of sampled solves 1e-16-2e-14 of |b| (the check asks 1e-8). A
    #: pivot kept by the threshold rule against larger entries below it (multipliers up to
    #: 1e3) is what raises the growth, and the residual is then checked.
    GROWTH_UNCHECKED = 1e2

    def _check(self, b, x):
        """The first solve's residual check (see the class): ``x`` or the solution of the
        partial-pivoting refactorisation. Not done for dense-block factors of small element
        growth (:attr:`GROWTH_UNCHECKED`)."""
        if not self.checked:
            self.checked = True
            if self.block is not None and self.block.growth <= self.GROWTH_UNCHECKED:
                return x
            if self.block is not None and b.ndim == 1:
                from fricdamp.solvers._sparse_lu import csc_residual_norm

                A = self.A
                res = csc_residual_norm(A.shape[0], A.indptr, A.indices, A.data, x,
                                        np.ascontiguousarray(b, dtype=float),
                                        np.empty(A.shape[0]))
            else:
                res = np.max(np.abs(self.A @ x - b))
            scale = _norm(b) + 1e-300
            if not np.isfinite(res) or res > 1e-8 * scale:
                logger.debug("threshold-pivoted LU inaccurate (%.2e): partial pivoting", res)
                self.lu = spla.splu(self.A)
                self.perm = None
                self.block = None
                x = self.lu.solve(b)
        return x


def _perm_sign(perm) -> float:
    """Sign (+1 or -1) of a permutation given as an index array."""
    perm = np.asarray(perm)
    seen = np.zeros(perm.size, dtype=bool)
    transpositions = 0
    for i in range(perm.size):
        if seen[i]:
            continue
        j, length = i, 0
        while not seen[j]:
            seen[j] = True
            j = int(perm[j])
            length += 1
        transpositions += length - 1
    return -1.0 if transpositions % 2 else 1.0


class _Bordered:
    """Assemble ``[[J, c], [t^T, s]]`` fast, caching the sparse pattern between calls."""

    def __init__(self):
        self._key = None
        self._A = None
        self._J = None

    def __call__(self, J, c, t, s):
        n = J.shape[0]
        if J is self._J and _fixed_pattern(J):
            same = True         # the object of the last call, its pattern promised fixed
        elif not sp.issparse(J):
            A = np.empty((n + 1, n + 1))
            A[:n, :n] = J
            A[:n, n] = c
            A[n, :n] = t
            A[n, n] = s
            return A
        else:
            J = J.tocsc() if J.format != "csc" else J
            if not J.has_sorted_indices:
                J = J.sorted_indices()
            key = (J.nnz, n)
            same = self._key == key and (np.array_equal(self._indptr, J.indptr)
                                         and np.array_equal(self._indices, J.indices))
        self._J = J
        if not same:
            self._key = key
            self._indptr = J.indptr.copy()
            self._indices = J.indices.copy()
            counts = np.diff(J.indptr)
            col = np.repeat(np.arange(n), counts)
            self._old = np.arange(J.nnz) + col          # entry shift by one per column
            new_indptr = np.empty(n + 2, dtype=np.int64)
            new_indptr[: n + 1] = J.indptr + np.arange(n + 1)
            new_indptr[n + 1] = new_indptr[n] + n + 1
            self._extra = new_indptr[1: n + 1] - 1       # last slot of each column: row n
            idx = np.empty(J.nnz + 2 * n + 1, dtype=np.int64)
            idx[self._old] = J.indices
            idx[self._extra] = n
            idx[new_indptr[n]:] = np.arange(n + 1)
            self._new_indptr = new_indptr
            self._new_indices = idx
            self._lastcol = new_indptr[n]
            self._A = None
        data = np.empty(self._new_indices.size)
        if n >= 64:
            from fricdamp.solvers._sparse_lu import bordered_values

            bordered_values(J.data, self._old, self._extra, self._lastcol,
                            np.ascontiguousarray(c, dtype=float),
                            np.ascontiguousarray(t, dtype=float), float(s), data)
        else:
            data[self._old] = J.data
            data[self._extra] = t
            data[self._lastcol: self._lastcol + n] = c
            data[-1] = s
        # the bordered matrix is factorised at once; reuse one object (format checks of a
        # new scipy matrix cost ~0.1 ms per Newton step)
        if self._A is None:
            self._A = sp.csc_matrix((data, self._new_indices, self._new_indptr),
                                    shape=(n + 1, n + 1))
            self._A.has_sorted_indices = True
            mark_fixed_pattern(self._A)
        else:
            self._A.data = data
        return self._A


def _norm(r) -> float:
    # the method, not np.max: ~3 us less per call on a few hundred entries (same value)
    return float(np.abs(r).max()) if len(r) else 0.0


def _append(r, g: float):
    """``np.append(r, g)`` for a 1-D array ``r`` (a third of its time)."""
    out = np.empty(r.size + 1)
    out[:-1] = r
    out[-1] = g
    return out


def jacobian_of(J):
    """The Jacobian ``J``, or ``J()`` if it is deferred.

    A residual may return, instead of its Jacobian, a zero-argument callable that
    assembles it: Newton's method and the corrector call it only at the iterates where
    they factorise (not where they stop, nor at rejected line-search trials). It must be
    called before the residual is evaluated again, or else return the Jacobian at its own
    point anyway (e.g. by evaluating again).
    """
    return J() if callable(J) else J


# ---------------------------------------------------------------------------- Newton
@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`newton`.

    Attributes
    ----------
    x : ndarray, shape (n,)
        Last iterate (the solution when ``success``).
    success : bool
    message : str
    iterations : int
        Newton iterations (factorisations).
    residual_norm : float
        Max-norm of the residual at ``x``.
    n_evaluations : int
        Residual evaluations.
    """

    x: np.ndarray
    success: bool
    message: str
    iterations: int
    residual_norm: float
    n_evaluations: int


def newton(fun: Callable, x0, *, tol: float = 1e-10, max_iter: int = 50,
           line_search: bool = True, step_tol: float = 0.0,
           block_size: int | None = None, _orderings: _Orderings | None = None
           ) -> NewtonResult:
    """Solve ``fun(x) = 0`` by Newton's method with optional backtracking.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> (r, J)`` with r shape (n,) and J dense (n, n) or scipy sparse.
    x0 : array_like, shape (n,)
        Initial guess.
    tol : float
        Convergence when ``max |r| <= tol`` (scale the residual in ``fun``).
    max_iter : int
        Largest number of Newton iterations.
    line_search : bool
        Halve the step (up to 12 times) while ``|r|`` does not decrease; useful far from
        the solution and across the kinks of stick-slip residuals.
    step_tol : float
        Also stop successfully when ``max |dx| <= step_tol`` and ``|r| <= 1e3 tol``.
    block_size : int, optional
        Sparse Jacobians: factorise by dense blocks of this many consecutive unknowns
        (see :func:`solve_and_continue`).

    Returns
    -------
    NewtonResult
    """
    x = np.array(x0, dtype=float)
    r, J = fun(x)
    nev = 1
    rn = _norm(r)
    orderings = _Orderings(block_size) if _orderings is None else _orderings
    for it in range(max_iter + 1):
        if not np.isfinite(rn):
            return NewtonResult(x, False, "residual is not finite", it, rn, nev)
        if rn <= tol:
            return NewtonResult(x, True, "converged", it, rn, nev)
        if it == max_iter:
            break
        F = _Factor(jacobian_of(J), orderings)
        if not F.ok:
            return NewtonResult(x, False, "singular Jacobian", it, rn, nev)
        dx = -F.solve(r)
        lam = 1.0
        for _ in range(13 if line_search else 1):
            xt = x + lam * dx
            rt, Jt = fun(xt)
            nev += 1
            rtn = _norm(rt)
            if not line_search or (np.isfinite(rtn) and rtn < rn):
                break
            lam *= 0.5
        else:
            # no decrease: take the full step anyway (kinks can trap a monotone search)
            xt = x + dx
            rt, Jt = fun(xt)
            nev += 1
            rtn = _norm(rt)
        x, r, J, rn = xt, rt, Jt, rtn
        if step_tol > 0 and _norm(lam * dx) <= step_tol and rn <= 1e3 * tol:
            return NewtonResult(x, True, "converged (step)", it + 1, rn, nev)
    return NewtonResult(x, False, f"no convergence in {max_iter} iterations "
                        f"(|r| = {rn:.3g} > tol = {tol:.3g})", max_iter, rn, nev)


# ---------------------------------------------------------------------------- continuation
@dataclass(frozen=True)
class ContinuationResult:
    """Points of a continued solution path.

    Attributes
    ----------
    x : ndarray, shape (n_points, n)
        Converged solutions (unscaled).
    lam : ndarray, shape (n_points,)
        Parameter at each point.
    iterations : ndarray, shape (n_points,)
        Newton iterations of each point.
    turning_points : tuple of int
        Indices of points after which the path turned back in lam (folds).
    status : int
        0 success; 1 max steps; 2 stalled; 3 turned back out of the interval; 4 callback;
        -1 no start solution. See ``STATUS_MESSAGES``.
    message : str
    n_evaluations, n_factorizations : int
        Residual evaluations and LU factorisations, in total.
    tangents : ndarray, shape (n_points, n + 1), optional
        Unit tangent at each point in the scaled variables ``(x / x_scale, lam /
        lam_scale)``, oriented along the path; its last component changes sign at folds.
    det_sign : ndarray, shape (n_points,), optional
        Sign of the determinant of the bordered Jacobian ``[[J_x, J_lam], [t^T]]`` at each
        point (only with ``test_functions=True``): it changes sign at simple branch points.
    x_scale : ndarray, shape (n,), optional
    lam_scale : float
        The scaling of the path variables (for :func:`locate_on_branch`).
    """

    x: np.ndarray
    lam: np.ndarray
    iterations: np.ndarray
    turning_points: tuple[int, ...]
    status: int
    message: str
    n_evaluations: int
    n_factorizations: int
    tangents: np.ndarray | None = None
    det_sign: np.ndarray | None = None
    x_scale: np.ndarray | None = None
    lam_scale: float = 1.0

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def n_points(self) -> int:
        return int(self.lam.size)


def solve_and_continue(x0, residual: Callable, lam_start: float, lam_end: float, ds: float,
                       *, ds_min: float | None = None, ds_max: float | None = None,
                       x_scale=1.0, lam_scale: float = 1.0, tol: float = 1e-9,
                       max_iter: int = 10, max_steps: int = 2000, target_iterations: int = 3,
                       max_angle_deg: float = 25.0, reversal_tolerance: float = 0.1,
                       start_max_iter: int = 100, callback: Callable | None = None,
                       test_functions: bool = False, reuse_factorization: bool = False,
                       blas: int | None = 1, block_size: int | None = None,
                       throw: bool = False) -> ContinuationResult:
    """Continue the solutions of ``residual(x, lam) = 0`` from ``lam_start`` to ``lam_end``.

    Parameters
    ----------
    x0 : array_like, shape (n,)
        Initial guess of the solution at ``lam_start``.
    residual : callable
        ``residual(x, lam) -> (r, J_x, J_lam)``, r shape (n,), J_x dense (n, n) or sparse,
        J_lam shape (n,). Scale r so that ``max |r| <= tol`` means converged.
    lam_start, lam_end : float
        Parameter interval; the path may run backwards in lam (turning points).
    ds : float
        Initial arclength step in the scaled variables ``(x / x_scale, lam / lam_scale)``.
    ds_min, ds_max : float, optional
        Step bounds (default ``ds / 1000`` and ``10 ds``).
    x_scale : float or ndarray (n,)
        Typical magnitude of x (arclength metric and step size).
    lam_scale : float
        Typical change of lam (e.g. the interval length).
    tol : float
        Residual tolerance (max-norm).
    max_iter : int
        Newton iterations per corrector before the step is halved.
    max_steps : int
        Largest number of continuation points.
    target_iterations : int
        The step grows when the corrector needs fewer iterations, shrinks when more.
    max_angle_deg : float
        A step whose tangent turns by more than this (in the scaled variables) is rejected
        and retried with half the step (stays on the branch near sharp bends).
    reversal_tolerance : float
        Stop (status 3) when lam leaves the interval at its start by this fraction.
    start_max_iter : int
        Newton iterations (with backtracking) allowed for the first point.
    callback : callable, optional
        ``callback(x, lam)`` after each accepted point; return True to stop (status 4).
    test_functions : bool
        Also record the sign of the determinant of the bordered Jacobian at each point
        (``det_sign``, for branch points); costs one O(n) pass over each factorisation.
    reuse_factorization : bool
        Chord steps: keep the factorisation of the bordered Jacobian across corrector
        iterations and points while each step reduces the residual at least 4-fold, and
        compute each tangent by iterative refinement on it (exact to 1e-10, else the
        Jacobian at the point is factorised). Pays when a factorisation costs several
        residual evaluations (sparse systems of thousands of unknowns); the points satisfy
        the same tolerance, but the step control sees more (cheaper) iterations, so the
        points are placed differently. Ignored with ``test_functions`` (which needs a
        factorisation at every point).
    blas : int or None
        BLAS threads during the run (default 1, see :func:`blas_threads`); None leaves the
        pools alone.
    block_size : int, optional
        Sparse Jacobians whose unknowns come in densely coupled groups of ``block_size``
        consecutive unknowns (harmonic balance: the 2H+1 coefficients of a DOF) are
        factorised by dense blocks with the symbolic analysis kept per sparsity pattern
        (:mod:`fricdamp.solvers._sparse_lu`; SuperLU where a pivot fails the threshold
        rule). The solutions are the same to rounding; None: SuperLU.
    throw : bool
        Raise ConvergenceError instead of returning a failed status.

    Returns
    -------
    ContinuationResult
    """
    if not (np.isfinite(lam_start) and np.isfinite(lam_end)) or lam_start == lam_end:
        raise ModelError(f"lam_start and lam_end must be finite and different, got "
                         f"{lam_start!r}, {lam_end!r}")
    if not (ds > 0 and np.isfinite(ds)):
        raise ModelError(f"ds must be > 0, got {ds!r}")
    if not lam_scale > 0:
        raise ModelError(f"lam_scale must be > 0, got {lam_scale!r}")
    with blas_threads(blas):
        out = _continue(np.array(x0, dtype=float), residual, float(lam_start), float(lam_end),
                        float(ds), ds_min, ds_max, x_scale, float(lam_scale), tol, max_iter,
                        max_steps, target_iterations, max_angle_deg, reversal_tolerance,
                        start_max_iter, callback, bool(test_functions),
                        bool(reuse_factorization), block_size)
    if throw and not out.success:
        raise ConvergenceError(f"continuation failed: {out.message}")
    return out


def _scaled_residual(residual, n, x_scale, lam_scale, counters):
    """``residual`` in the scaled variables y = [x / x_scale, lam / lam_scale]."""
    xs = np.broadcast_to(np.asarray(x_scale, dtype=float), (n,)).copy()
    if np.any(xs <= 0) or not np.all(np.isfinite(xs)):
        raise ModelError("x_scale must be finite and > 0")
    scalar_xs = bool(np.all(xs == xs[0]))
    unit_xs = scalar_xs and xs[0] == 1.0

    def scale_jx(Jx):
        if unit_xs:
            return Jx
        if scalar_xs:
            return Jx * xs[0]
        if sp.issparse(Jx):
            return Jx @ sp.diags(xs)
        return Jx * xs[None, :]

    def scaled(y):
        x = y[:n] * xs
        r, Jx, Jl = residual(x, y[n] * lam_scale)
        counters["ev"] += 1
        r = np.asarray(r, dtype=float)
        if callable(Jx):        # deferred (see jacobian_of): scaled when assembled
            if not unit_xs:
                Jx = _deferred_scaled(Jx, scale_jx)
        else:
            Jx = scale_jx(Jx)
        return r, Jx, np.asarray(Jl, dtype=float) * lam_scale

    return scaled, xs


def _deferred_scaled(J, scale_jx):
    return lambda: scale_jx(J())


def _continue(x0, residual, lam0, lam1, ds, ds_min, ds_max, x_scale, lam_scale, tol,
              max_iter, max_steps, target_it, max_angle, rev_tol, start_max_iter, callback,
              test_functions=False, reuse_factorization=False, block_size=None):
    n = x0.size
    counters = {"ev": 0, "fact": 0}
    scaled, xs = _scaled_residual(residual, n, x_scale, lam_scale, counters)
    ds_min = ds / 1000.0 if ds_min is None else float(ds_min)
    ds_max = 10.0 * ds if ds_max is None else float(ds_max)
    direction = 1.0 if lam1 > lam0 else -1.0
    lam_lo = min(lam0, lam1) - rev_tol * abs(lam1 - lam0)
    lam_hi = max(lam0, lam1) + rev_tol * abs(lam1 - lam0)
    cos_max = math.cos(math.radians(max_angle))
    border = _Bordered()
    orderings = _Orderings(block_size)
    # the determinant test function needs a factorisation at every point: Newton then
    chord = _Chord() if reuse_factorization and not test_functions else None

    def fixed_lam(lam):
        def f(xx):
            r, Jx, _ = scaled(np.append(xx, lam))
            return r, Jx
        return f

    # ---- first point at lam_start
    res0 = newton(fixed_lam(lam0 / lam_scale), x0 / xs, tol=tol, max_iter=start_max_iter,
                  block_size=block_size, _orderings=orderings)
    counters["ev"] += 0
    if not res0.success:
        msg = f"{STATUS_MESSAGES[-1]} at lam = {lam0:g} ({res0.message})"
        return ContinuationResult(np.empty((0, n)), np.empty(0), np.empty(0, int), (), -1, msg,
                                  counters["ev"], res0.iterations, np.empty((0, n + 1)),
                                  np.empty(0) if test_functions else None, xs, lam_scale)
    counters["fact"] += res0.iterations
    y = np.append(res0.x, lam0 / lam_scale)
    pts_y = [y.copy()]
    pts_it = [res0.iterations]

    # initial tangent: J dx = -J_lam, oriented towards lam_end
    r, Jx, Jl = scaled(y)
    Jx = jacobian_of(Jx)
    F = _Factor(Jx, orderings)
    counters["fact"] += 1
    if F.ok:
        dx = -F.solve(Jl)
        t = np.append(dx, 1.0)
    else:  # start on a fold: use any null direction through the bordered system
        e = np.zeros(n + 1)
        e[n] = 1.0
        A = border(Jx, Jl, e[:n], 1.0)
        F2 = _Factor(A)
        counters["fact"] += 1
        rhs = np.zeros(n + 1)
        rhs[n] = 1.0
        t = F2.solve(rhs)
    t /= np.linalg.norm(t)
    if t[n] * direction < 0:
        t = -t
    pts_t = [t.copy()]
    pts_det = []
    if test_functions:
        Fb = _Factor(border(Jx, Jl, t[:n], t[n]), orderings)
        counters["fact"] += 1
        pts_det.append(Fb.log_det()[0] if Fb.ok else 0.0)

    status, turning = None, []
    step_ds = ds
    lam_end_s = lam1 / lam_scale
    while status is None:
        if len(pts_y) >= max_steps:
            status = 1
            break
        # ---- predictor and corrector
        accepted = False
        while not accepted:
            y_pred = y + step_ds * t
            y_new, it, ok, Fa = _corrector(scaled, y_pred, t, tol, max_iter, border, counters,
                                           orderings, chord)
            if ok:
                if chord is not None:
                    t_new = chord.tangent(t, border, orderings, counters)
                elif Fa.tangent is not None:     # given by the corrector's last solve
                    t_new = Fa.tangent.copy()
                else:
                    rhs = np.zeros(n + 1)
                    rhs[n] = 1.0
                    t_new = Fa.solve(rhs)
                nt = 0.0 if t_new is None else np.linalg.norm(t_new)
                if t_new is None or not np.all(np.isfinite(t_new)) or nt == 0:
                    ok = False
                else:
                    t_new /= nt
                    cos_a = float(t_new.dot(t))
                    if cos_a < cos_max and step_ds > ds_min * 1.0001:
                        ok = False   # the path bends too much for this step: refine
            if ok:
                accepted = True
                break
            if step_ds <= ds_min * 1.0001:
                status = 2
                break
            step_ds = max(step_ds / 2.0, ds_min)
        if status is not None:
            break
        # ---- accept
        if t_new[n] * t[n] < 0:
            turning.append(len(pts_y) - 1)
        lam_new = y_new[n]
        passed_end = (lam_new - lam_end_s) * direction >= 0
        if passed_end:
            # finish exactly at lam_end: interpolate and solve at fixed lam
            frac = (lam_end_s - y[n]) / (lam_new - y[n]) if lam_new != y[n] else 1.0
            guess = y[:n] + frac * (y_new[:n] - y[:n])
            rese = newton(fixed_lam(lam_end_s), guess, tol=tol, max_iter=max_iter,
                          line_search=False, block_size=block_size, _orderings=orderings)
            counters["fact"] += rese.iterations
            if rese.success:
                y_new = np.append(rese.x, lam_end_s)
                it = rese.iterations
        if test_functions:
            pts_det.append(Fa.log_det()[0])
        y, t = y_new, t_new
        pts_y.append(y.copy())
        pts_it.append(it)
        pts_t.append(t.copy())
        if passed_end:
            status = 0
            break
        lam_u = y[n] * lam_scale
        if lam_u < lam_lo or lam_u > lam_hi:
            status = 3
            break
        if callback is not None and callback(y[:n] * xs, lam_u):
            status = 4
            break
        # ---- step adaptation
        if chord is not None:
            it = chord.newton_iterations(tol)
        if it <= target_it - 1:
            fac = 2.0 if it <= max(target_it - 2, 1) else 1.5
        elif it <= target_it:
            fac = 1.0
        else:
            fac = max(0.5, target_it / it)
        step_ds = min(max(step_ds * fac, ds_min), ds_max)

    # the points as one array: a copy of the x parts only, scaled only if x_scale is not 1
    # (ring of 480 Jenkins contacts: 670 points of 5,281 unknowns, 28 MB a copy, fresh
    # memory ~0.1 s each)
    X = np.array([p[:n] for p in pts_y])
    if not np.all(xs == 1.0):
        X *= xs
    lam_path = np.array([p[n] for p in pts_y])
    msg = STATUS_MESSAGES[status]
    if status == 2:
        msg += (f" (ds_min = {ds_min:.3g}) after lam = {lam_path[-1] * lam_scale:.6g}; last "
                "converged point returned; try smaller ds/ds_min, more harmonics or samples, "
                "or a looser tol")
    return ContinuationResult(X, lam_path * lam_scale, np.array(pts_it, dtype=int),
                              tuple(turning), status, msg, counters["ev"], counters["fact"],
                              np.array(pts_t), np.array(pts_det) if test_functions else None,
                              xs, lam_scale)


def _corrector(scaled, y_pred, t, tol, max_iter, border, counters, orderings=None,
               chord=None):
    """Newton on [R(y); t.(y - y_pred)] = 0. Returns (y, iterations, ok, last factor).

    With ``chord`` (a :class:`_Chord`), the factorisation kept from earlier steps or points
    is used as long as each step reduces the residual by :data:`_Chord.CONTRACTION`; then
    the bordered Jacobian is factorised at the current iterate (a Newton step). Its
    ``jacobian`` holds the Jacobian of the last evaluation, at the returned point.
    """
    n = y_pred.size - 1
    y = y_pred.copy()
    r, Jx, Jl = scaled(y)
    rn = _norm(r)
    rn0 = rn
    if chord is None:
        e_n = np.zeros(n + 1)
        e_n[n] = 1.0
        Fa = None
        for it in range(max_iter + 1):
            if not np.isfinite(rn):
                return y, it, False, None
            if rn <= tol and Fa is not None:
                return y, it, True, Fa
            if rn <= tol:
                # converged at the predictor: factor once for the tangent
                Fa = _Factor(border(jacobian_of(Jx), Jl, t[:n], t[n]), orderings)
                counters["fact"] += 1
                return y, it, Fa.ok, Fa
            if it == max_iter or rn > 1e6 * max(rn0, tol):
                break
            A = border(jacobian_of(Jx), Jl, t[:n], t[n])
            Fa = _Factor(A, orderings)
            counters["fact"] += 1
            if not Fa.ok:
                return y, it, False, None
            g = float(t.dot(y - y_pred))       # (ndarray.dot: ~0.6 us less than @)
            # with the next tangent's right-hand side where that is nearly free (dense-block
            # factors): the last factorisation of a converged corrector gives the tangent
            dy = -Fa.solve_with(_append(r, g), e_n)
            y = y + dy
            r, Jx, Jl = scaled(y)
            rn = _norm(r)
        return y, max_iter, False, None

    # Broyden's method on the kept factorisation B0 (Kelley 1995, sec. 7.3, "brsol"): the
    # inverse of the updated Jacobian acts through B0^-1 and the stored steps s_j
    chord.r0 = rn0
    it = 0
    steps: list[np.ndarray] = []
    while True:
        if not np.isfinite(rn):
            chord.F = None
            return y, it, False, None
        if rn <= tol:
            chord.jacobian = (jacobian_of(Jx), Jl)
            return y, it, True, chord.F
        if it >= chord.max_iter(max_iter) or rn > 1e6 * max(rn0, tol):
            chord.F = None
            return y, it, False, None
        if chord.F is None or chord.stale or len(steps) > _Chord.MAX_UPDATES:
            chord.F = _Factor(border(jacobian_of(Jx), Jl, t[:n], t[n]), orderings)
            counters["fact"] += 1
            chord.stale = False
            steps = []
            if not chord.F.ok:
                chord.F = None
                return y, it, False, None
        g = float(t @ (y - y_pred))
        z = -chord.F.solve(np.append(r, g))
        for j in range(len(steps) - 1):
            sj = steps[j]
            z += steps[j + 1] * ((sj @ z) / (sj @ sj))
        if steps:
            sn = steps[-1]
            den = 1.0 - (sn @ z) / (sn @ sn)
            if abs(den) < 1e-12:
                chord.stale = True
                continue
            z /= den
        y_try = y + z
        r_try, Jx_try, Jl_try = scaled(y_try)
        rn_try = _norm(r_try)
        it += 1
        if steps and not rn_try < rn:
            # the updated Jacobian no longer describes the problem: discard the step and
            # factorise the Jacobian at the current iterate
            chord.stale = True
            continue
        steps.append(z)
        if not rn_try <= _Chord.CONTRACTION * rn:
            chord.stale = True      # slow contraction: factorise at the next iterate
        y, r, Jx, Jl, rn = y_try, r_try, Jx_try, Jl_try, rn_try


class _Chord:
    """The factorisation of the bordered Jacobian kept across corrector steps and points.

    A factorisation of a few thousand unknowns costs 5-25 residual evaluations (ring of
    480 Jenkins contacts, H = 5: 5.9 ms against 0.93 ms for the residual with its Jacobian
    and 0.23 ms per solve), so the corrector reuses the last one while each step reduces
    the residual at least 4-fold (:data:`CONTRACTION`), and refactorises at the current
    iterate otherwise (a Newton step). The tangent at a converged point is the solution of
    the bordered system with the Jacobian at that point, by iterative refinement on the kept
    factorisation (:meth:`tangent`); if the refinement does not converge in a few solves
    the Jacobian at the point is factorised, so the tangent is the same as with Newton's
    method to the refinement tolerance.
    """

    CONTRACTION = 0.5
    MAX_UPDATES = 8
    #: relative change of the tangent below which the refinement has converged
    TANGENT_TOL = 1e-5
    TANGENT_SOLVES = 4

    def __init__(self):
        self.F = None
        self.stale = False
        self.jacobian = None
        self.r0 = 0.0

    @staticmethod
    def max_iter(max_iter: int) -> int:
        # linear convergence takes more (cheap) steps than Newton's
        return 3 * max_iter

    def newton_iterations(self, tol: float) -> int:
        """Newton iterations that the predictor's residual would have needed.

        The step control targets a number of Newton iterations; chord steps converge
        linearly and take more, which would shrink the steps for nothing. Newton's count
        follows from the residual at the predictor r0 by quadratic convergence,
        ``r0^(2^k) <= tol`` (residuals scaled to O(1)): on the ring of 30 Jenkins contacts
        the Newton corrector took 1, 2, 3, 4 iterations at median r0 = 3e-5, 2e-3, 4e-2,
        0.17, which this formula gives for tol = 1e-9.
        """
        r0 = self.r0
        if not r0 > tol:
            return 0
        if r0 >= 0.5:
            return 5
        return max(1, math.ceil(math.log2(math.log(tol) / math.log(r0))))

    def tangent(self, t, border, orderings, counters):
        """Unit tangent at the converged point (the bordered system with its Jacobian)."""
        Jx, Jl = self.jacobian
        n = t.size - 1
        e = np.zeros(n + 1)
        e[n] = 1.0

        def apply(z):
            return np.append(Jx @ z[:n] + Jl * z[n], t @ z)

        z = self.F.solve(e) if self.F is not None else None
        if z is not None and np.all(np.isfinite(z)):
            for _ in range(self.TANGENT_SOLVES):
                dz = self.F.solve(e - apply(z))
                z = z + dz
                if not np.all(np.isfinite(z)):
                    break
                if _norm(dz) <= self.TANGENT_TOL * _norm(z):
                    return z
        self.F = _Factor(border(Jx, Jl, t[:n], t[n]), orderings)
        counters["fact"] += 1
        self.stale = False
        if not self.F.ok:
            self.F = None
            return None
        return self.F.solve(e)


# ---------------------------------------------------------------------------- test functions
@dataclass(frozen=True)
class PathPoint:
    """A point of a continued path, as a test function sees it.

    Attributes
    ----------
    x : ndarray, shape (n,)
        Solution (unscaled).
    lam : float
        Parameter.
    tangent : ndarray, shape (n + 1,)
        Unit tangent in the scaled variables ``(x / x_scale, lam / lam_scale)``, oriented like
        the tangent of the start point.
    det_sign, log_abs_det : float
        Sign and log of the absolute determinant of the bordered Jacobian at the point (its
        last row is the chord of the located segment; see :func:`locate_on_branch`).
    """

    x: np.ndarray
    lam: float
    tangent: np.ndarray
    det_sign: float
    log_abs_det: float


@dataclass(frozen=True)
class BranchLocation:
    """Outcome of :func:`locate_on_branch`.

    Attributes
    ----------
    point : PathPoint or None
        The located point (the trial with the smallest ``|test|``), None if no trial
        converged.
    value : float
        The test function there.
    converged : bool
        The bracket shrank below ``xtol`` (or the test vanished) with every trial on the path.
    message : str
    trials : int
        Corrector solves (each one trial point).
    """

    point: PathPoint | None
    value: float
    converged: bool
    message: str
    trials: int


def locate_on_branch(residual: Callable, x_a, lam_a: float, x_b, lam_b: float, tangent_a,
                     test: Callable, *, x_scale=1.0, lam_scale: float = 1.0, tol: float = 1e-9,
                     max_iter: int = 10, xtol: float = 1e-9, max_trials: int = 40,
                     values: tuple[float, float] | None = None) -> BranchLocation:
    """Zero of a test function on the path between two of its points (folds, bifurcations).

    The trial points lie on the hyperplanes ``c . (y - y_a) = sigma`` orthogonal to the chord
    ``c = y_b - y_a`` (scaled variables), each corrected onto ``R(x, lam) = 0`` by Newton on the
    bordered system, and ``sigma`` is found by the Illinois variant of regula falsi, which
    keeps the bracket and converges superlinearly for a test function that crosses zero
    linearly (the parameter component of the tangent at a fold, the determinant of the
    bordered Jacobian at a branch point, the real part of a critical Floquet exponent).

    Parameters
    ----------
    residual : callable
        As for :func:`solve_and_continue`.
    x_a, lam_a, x_b, lam_b : array_like, float
        Two converged points of the path (unscaled) between which ``test`` changes sign.
    tangent_a : array_like, shape (n + 1,)
        Tangent at ``a`` in the scaled variables (``ContinuationResult.tangents[i]``); only its
        orientation is used.
    test : callable
        ``test(PathPoint) -> float``.
    x_scale, lam_scale : ndarray or float
        The scaling of the continuation (``ContinuationResult.x_scale``, ``.lam_scale``).
    tol, max_iter : float, int
        Corrector tolerance (max-norm of the residual) and iterations.
    xtol : float
        Stop when the bracket is shorter than ``xtol`` times the chord.
    max_trials : int
        Largest number of trial points.
    values : (float, float), optional
        ``test`` at a and b if already known (saves two corrector solves).

    Returns
    -------
    BranchLocation
    """
    x_a = np.asarray(x_a, dtype=float)
    n = x_a.size
    counters = {"ev": 0, "fact": 0}
    scaled, xs = _scaled_residual(residual, n, x_scale, lam_scale, counters)
    y_a = np.append(x_a / xs, lam_a / lam_scale)
    y_b = np.append(np.asarray(x_b, dtype=float) / xs, lam_b / lam_scale)
    chord = y_b - y_a
    length = float(np.linalg.norm(chord))
    if length == 0.0:
        raise ModelError("locate_on_branch needs two different points")
    c = chord / length
    t_ref = np.asarray(tangent_a, dtype=float)
    border = _Bordered()
    orderings = _Orderings()
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    trials = 0

    def at(sigma):
        nonlocal trials
        trials += 1
        y_pred = y_a + (sigma / length) * chord
        y, _, ok, _ = _corrector(scaled, y_pred, c, tol, max_iter, border, counters,
                                 orderings)
        if not ok:
            return None, np.nan
        # tangent and determinant from the Jacobian at the converged point itself (the
        # corrector's last factorisation is at the previous iterate: near a fold the tangent
        # is sensitive to that difference)
        _, Jx, Jl = scaled(y)
        Fa = _Factor(border(jacobian_of(Jx), Jl, c[:n], c[n]), orderings)
        if not Fa.ok:
            return None, np.nan
        t = Fa.solve(rhs)
        t /= np.linalg.norm(t)
        if t @ t_ref < 0:
            t = -t
        sign, logdet = Fa.log_det()
        pt = PathPoint(y[:n] * xs, float(y[n] * lam_scale), t, sign, logdet)
        return pt, float(test(pt))

    if values is None:
        pa, fa = at(0.0)
        pb, fb = at(length)
    else:
        (fa, fb), pa, pb = values, None, None
    if not (np.isfinite(fa) and np.isfinite(fb)):
        return BranchLocation(None, np.nan, False, "the corrector failed at an end point",
                              trials)
    best = (pa, fa) if abs(fa) <= abs(fb) else (pb, fb)
    if fa == 0.0 or fb == 0.0:
        if best[0] is None:
            best = at(0.0) if fa == 0.0 else at(length)
        return BranchLocation(best[0], 0.0, True, "test function zero at an end point", trials)
    if fa * fb > 0:
        return BranchLocation(best[0], best[1], False,
                              "the test function has the same sign at both points", trials)
    sa, sb = 0.0, length
    side = 0
    converged = False
    message = f"bracket not below xtol in {max_trials} trials"
    while trials < max_trials:
        sc = (sa * fb - sb * fa) / (fb - fa)
        if not (min(sa, sb) < sc < max(sa, sb)):
            sc = 0.5 * (sa + sb)
        pc, fc = at(sc)
        for shift in (1e-3, -2e-3):      # a trial exactly on a singular point: move off it
            if pc is not None or trials >= max_trials:
                break
            sc += shift * (sb - sa)
            pc, fc = at(sc)
        if pc is None:
            message = f"the corrector failed at arclength {sc:.3g} of {length:.3g}"
            break
        if best[0] is None or abs(fc) < abs(best[1]):
            best = (pc, fc)
        if fc == 0.0:
            converged, message = True, "test function zero"
            break
        if fc * fb > 0:
            sb, fb = sc, fc
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            sa, fa = sc, fc
            if side == 1:
                fb *= 0.5
            side = 1
        if abs(sb - sa) <= xtol * length:
            converged, message = True, "converged"
            break
    return BranchLocation(best[0], float(best[1]), converged, message, trials)
