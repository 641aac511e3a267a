"""Newton and pseudo-arclength continuation on problems with known solution curves.

The S-curve ``x^3 - x + lam = 0`` has folds at x = +-1/sqrt(3), lam = -+2/(3 sqrt 3): the
continuation must follow it through both turning points (natural continuation in lam
cannot). Every returned point must satisfy the equation to the tolerance.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers.continuation import newton, solve_and_continue

LAM_FOLD = 2.0 / (3.0 * np.sqrt(3.0))


def s_curve(x, lam):
    r = x**3 - x + lam
    return r, np.diag(3 * x**2 - 1), np.ones_like(x)


def s_curve_sparse(x, lam):
    r, J, Jl = s_curve(x, lam)
    return r, sp.csc_matrix(J), Jl


@pytest.mark.parametrize("fun", [s_curve, s_curve_sparse])
def test_s_curve_through_two_folds(fun):
    x0 = np.array([1.3])
    res = solve_and_continue(x0, fun, -1.0, 1.0, 0.05, tol=1e-12)
    assert res.success, res.message
    assert res.lam[-1] == pytest.approx(1.0, abs=1e-14)
    # the end lies on the lower branch: the real root of x^3 - x + 1 = 0
    assert res.x[-1, 0] == pytest.approx(-1.324717957244746, abs=1e-10)
    for x, lam in zip(res.x, res.lam, strict=True):
        assert abs(x[0] ** 3 - x[0] + lam) <= 1e-11
    assert len(res.turning_points) == 2
    lam_turn = sorted(abs(res.lam[i]) for i in res.turning_points)
    for lt in lam_turn:   # folds detected within one step of the exact fold
        assert lt == pytest.approx(LAM_FOLD, abs=0.05)
    upper = res.lam[: res.turning_points[1] + 1]   # up to the second fold: lam <= fold
    assert upper.max() <= LAM_FOLD + 1e-9 and upper.max() > LAM_FOLD - 0.02
    assert res.n_factorizations > 0 and res.n_evaluations >= res.n_points


def test_vector_problem_with_scaling():
    """Decoupled copies with very different scales: x_scale makes the steps uniform."""
    sc = np.array([1.0, 1e-6])

    def fun(x, lam):
        y = x / sc
        r = y**3 - y + lam
        return r, np.diag((3 * y**2 - 1) / sc), np.ones(2)

    res = solve_and_continue(np.array([1.3, 1.3e-6]), fun, -1.0, 1.0, 0.05, x_scale=sc,
                             tol=1e-12)
    assert res.success
    np.testing.assert_allclose(res.x[-1] / sc, -1.324717957244746, atol=1e-9)


def test_stall_is_reported_with_converged_points_only():
    """No solution beyond lam = 0.5: the run stops (status 2) and keeps converged points."""

    def fun(x, lam):
        if lam > 0.5:
            return np.array([np.nan]), np.array([[1.0]]), np.array([1.0])
        return x - lam, np.array([[1.0]]), np.array([-1.0])

    res = solve_and_continue(np.array([0.0]), fun, 0.0, 1.0, 0.1, ds_min=1e-4)
    assert res.status == 2 and not res.success
    assert "stalled" in res.message and "last converged point" in res.message
    assert res.lam.max() <= 0.5
    np.testing.assert_allclose(res.x[:, 0], res.lam, atol=1e-12)
    with pytest.raises(ConvergenceError, match="stalled"):
        solve_and_continue(np.array([0.0]), fun, 0.0, 1.0, 0.1, ds_min=1e-4, throw=True)


def test_turning_back_out_of_the_interval():
    """x^2 + lam = 0 from lam = -1 folds at lam = 0 and returns to lam = -1: status 3."""

    def fun(x, lam):
        return x**2 + lam, np.diag(2 * x), np.ones(1)

    res = solve_and_continue(np.array([1.0]), fun, -1.0, 1.0, 0.05)
    assert res.status == 3 and not res.success
    assert res.x[-1, 0] < 0 and len(res.turning_points) == 1


def test_no_start_solution():
    def fun(x, lam):
        return x**2 + 1.0, np.diag(2 * x), np.zeros(1)

    res = solve_and_continue(np.array([0.5]), fun, 0.0, 1.0, 0.1, start_max_iter=20)
    assert res.status == -1 and res.n_points == 0 and "Newton failed" in res.message


def test_callback_stops():
    res = solve_and_continue(np.array([1.3]), s_curve, -1.0, 1.0, 0.05,
                             callback=lambda x, lam: lam > -0.8)
    assert res.status == 4 and res.lam[-1] > -0.8


def test_newton_line_search_and_failures():
    # arctan: plain Newton diverges from x0 = 3, backtracking converges
    def f(x):
        with np.errstate(over="ignore"):
            return np.arctan(x), np.diag(1 / (1 + x**2))

    assert not newton(f, [3.0], line_search=False, max_iter=20).success
    res = newton(f, [3.0])
    assert res.success and abs(res.x[0]) < 1e-10
    sing = newton(lambda x: (x**2 + 1, np.zeros((1, 1))), [0.0])
    assert not sing.success and "singular" in sing.message


@pytest.mark.parametrize("kw", [{"ds": -1.0}, {"lam_end": -1.0}, {"lam_scale": 0.0}])
def test_bad_arguments(kw):
    args = {"ds": 0.1, "lam_end": 1.0}
    args.update({k: v for k, v in kw.items() if k in args})
    extra = {k: v for k, v in kw.items() if k not in args}
    with pytest.raises(ModelError):
        solve_and_continue(np.array([1.3]), s_curve, -1.0, args["lam_end"], args["ds"],
                           **extra)
