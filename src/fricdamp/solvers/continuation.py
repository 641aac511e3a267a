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

References
----------
Seydel (2010), *Practical Bifurcation and Stability Analysis*, Springer, ch. 4.
Krack & Gross (2019), *Harmonic Balance for Nonlinear Vibration Problems*, ch. 4.
"""

from __future__ import annotations

import contextlib
import logging
import math
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
    "blas_threads",
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
    so the solvers default to one thread. Entering the context costs ~1 ms: use it once
    around a whole run, never per solve.
    """
    if n is None:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=int(n), user_api="blas")


# ---------------------------------------------------------------------------- linear algebra
class _Factor:
    """LU factorisation of a dense or sparse square matrix; ``ok`` False if singular."""

    __slots__ = ("lu", "sparse", "ok", "A", "checked")

    def __init__(self, A):
        self.sparse = sp.issparse(A)
        self.ok = True
        self.checked = False
        try:
            if self.sparse:
                # threshold pivoting (prefer the diagonal unless 1000x smaller than the column
                # maximum) on a minimum-degree ordering: 3-5x less fill and time than strict
                # partial pivoting on HB Jacobians; the first solve is checked and the
                # factorisation redone with partial pivoting if it lost accuracy
                self.A = A.tocsc() if A.format != "csc" else A
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

    def solve(self, b):
        if not self.sparse:
            return sla.lu_solve(self.lu, b, check_finite=False)
        x = self.lu.solve(b)
        if not self.checked:
            self.checked = True
            res = np.max(np.abs(self.A @ x - b))
            scale = np.max(np.abs(b)) + 1e-300
            if not np.isfinite(res) or res > 1e-8 * scale:
                logger.debug("threshold-pivoted LU inaccurate (%.2e): partial pivoting", res)
                self.lu = spla.splu(self.A)
                x = self.lu.solve(b)
        return x


class _Bordered:
    """Assemble ``[[J, c], [t^T, s]]`` fast, caching the sparse pattern between calls."""

    def __init__(self):
        self._key = None
        self._A = None

    def __call__(self, J, c, t, s):
        n = J.shape[0]
        if not sp.issparse(J):
            A = np.empty((n + 1, n + 1))
            A[:n, :n] = J
            A[:n, n] = c
            A[n, :n] = t
            A[n, n] = s
            return A
        J = J.tocsc() if J.format != "csc" else J
        if not J.has_sorted_indices:
            J = J.sorted_indices()
        key = (J.nnz, n)
        if (self._key != key or not np.array_equal(self._indptr, J.indptr)
                or not np.array_equal(self._indices, J.indices)):
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
        data = np.empty(J.nnz + 2 * n + 1)
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
        else:
            self._A.data = data
        return self._A


def _norm(r) -> float:
    return float(np.max(np.abs(r))) if len(r) else 0.0


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
           line_search: bool = True, step_tol: float = 0.0) -> NewtonResult:
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

    Returns
    -------
    NewtonResult
    """
    x = np.array(x0, dtype=float)
    r, J = fun(x)
    nev = 1
    rn = _norm(r)
    for it in range(max_iter + 1):
        if not np.isfinite(rn):
            return NewtonResult(x, False, "residual is not finite", it, rn, nev)
        if rn <= tol:
            return NewtonResult(x, True, "converged", it, rn, nev)
        if it == max_iter:
            break
        F = _Factor(J)
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
    """

    x: np.ndarray
    lam: np.ndarray
    iterations: np.ndarray
    turning_points: tuple[int, ...]
    status: int
    message: str
    n_evaluations: int
    n_factorizations: int

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
                       blas: int | None = 1, throw: bool = False) -> ContinuationResult:
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
    blas : int or None
        BLAS threads during the run (default 1, see :func:`blas_threads`); None leaves the
        pools alone.
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
                        start_max_iter, callback)
    if throw and not out.success:
        raise ConvergenceError(f"continuation failed: {out.message}")
    return out


def _continue(x0, residual, lam0, lam1, ds, ds_min, ds_max, x_scale, lam_scale, tol,
              max_iter, max_steps, target_it, max_angle, rev_tol, start_max_iter, callback):
    n = x0.size
    xs = np.broadcast_to(np.asarray(x_scale, dtype=float), (n,)).copy()
    if np.any(xs <= 0) or not np.all(np.isfinite(xs)):
        raise ModelError("x_scale must be finite and > 0")
    scalar_xs = bool(np.all(xs == xs[0]))
    unit_xs = scalar_xs and xs[0] == 1.0
    ds_min = ds / 1000.0 if ds_min is None else float(ds_min)
    ds_max = 10.0 * ds if ds_max is None else float(ds_max)
    direction = 1.0 if lam1 > lam0 else -1.0
    lam_lo = min(lam0, lam1) - rev_tol * abs(lam1 - lam0)
    lam_hi = max(lam0, lam1) + rev_tol * abs(lam1 - lam0)
    cos_max = math.cos(math.radians(max_angle))
    counters = {"ev": 0, "fact": 0}
    border = _Bordered()

    def scaled(y):
        """Residual in scaled variables y = [x / xs, lam / lam_scale]."""
        x = y[:n] * xs
        r, Jx, Jl = residual(x, y[n] * lam_scale)
        counters["ev"] += 1
        r = np.asarray(r, dtype=float)
        if unit_xs:
            pass
        elif scalar_xs:
            Jx = Jx * xs[0]
        elif sp.issparse(Jx):
            Jx = Jx @ sp.diags(xs)
        else:
            Jx = Jx * xs[None, :]
        return r, Jx, np.asarray(Jl, dtype=float) * lam_scale

    def fixed_lam(lam):
        def f(xx):
            r, Jx, _ = scaled(np.append(xx, lam))
            return r, Jx
        return f

    # ---- first point at lam_start
    res0 = newton(fixed_lam(lam0 / lam_scale), x0 / xs, tol=tol, max_iter=start_max_iter)
    counters["ev"] += 0
    if not res0.success:
        msg = f"{STATUS_MESSAGES[-1]} at lam = {lam0:g} ({res0.message})"
        return ContinuationResult(np.empty((0, n)), np.empty(0), np.empty(0, int), (), -1, msg,
                                  counters["ev"], res0.iterations)
    counters["fact"] += res0.iterations
    y = np.append(res0.x, lam0 / lam_scale)
    pts_y = [y.copy()]
    pts_it = [res0.iterations]

    # initial tangent: J dx = -J_lam, oriented towards lam_end
    r, Jx, Jl = scaled(y)
    F = _Factor(Jx)
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
            y_new, it, ok, Fa = _corrector(scaled, y_pred, t, tol, max_iter, border, counters)
            if ok:
                rhs = np.zeros(n + 1)
                rhs[n] = 1.0
                t_new = Fa.solve(rhs)
                nt = np.linalg.norm(t_new)
                if not np.all(np.isfinite(t_new)) or nt == 0:
                    ok = False
                else:
                    t_new /= nt
                    cos_a = float(t_new @ t)
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
                          line_search=False)
            counters["fact"] += rese.iterations
            if rese.success:
                y_new = np.append(rese.x, lam_end_s)
                it = rese.iterations
        y, t = y_new, t_new
        pts_y.append(y.copy())
        pts_it.append(it)
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
        if it <= target_it - 1:
            fac = 2.0 if it <= max(target_it - 2, 1) else 1.5
        elif it <= target_it:
            fac = 1.0
        else:
            fac = max(0.5, target_it / it)
        step_ds = min(max(step_ds * fac, ds_min), ds_max)

    Y = np.array(pts_y)
    msg = STATUS_MESSAGES[status]
    if status == 2:
        msg += (f" (ds_min = {ds_min:.3g}) after lam = {Y[-1, n] * lam_scale:.6g}; last "
                "converged point returned; try smaller ds/ds_min, more harmonics or samples, "
                "or a looser tol")
    return ContinuationResult(Y[:, :n] * xs, Y[:, n] * lam_scale, np.array(pts_it, dtype=int),
                              tuple(turning), status, msg, counters["ev"], counters["fact"])


def _corrector(scaled, y_pred, t, tol, max_iter, border, counters):
    """Newton on [R(y); t.(y - y_pred)] = 0. Returns (y, iterations, ok, last factor)."""
    n = y_pred.size - 1
    y = y_pred.copy()
    r, Jx, Jl = scaled(y)
    rn = _norm(r)
    rn0 = rn
    Fa = None
    for it in range(max_iter + 1):
        if not np.isfinite(rn):
            return y, it, False, None
        if rn <= tol and Fa is not None:
            return y, it, True, Fa
        if rn <= tol:
            # converged at the predictor: factor once for the tangent
            Fa = _Factor(border(Jx, Jl, t[:n], t[n]))
            counters["fact"] += 1
            return y, it, Fa.ok, Fa
        if it == max_iter or rn > 1e6 * max(rn0, tol):
            break
        A = border(Jx, Jl, t[:n], t[n])
        Fa = _Factor(A)
        counters["fact"] += 1
        if not Fa.ok:
            return y, it, False, None
        g = float(t @ (y - y_pred))
        dy = -Fa.solve(np.append(r, g))
        y = y + dy
        r, Jx, Jl = scaled(y)
        rn = _norm(r)
    return y, max_iter, False, None
