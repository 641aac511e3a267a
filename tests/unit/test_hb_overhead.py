"""The Python path of an HB evaluation and of the corrector (issue 13): work buffers kept
between calls never leak into results, and the small helpers keep the values of the numpy
calls they replace."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from fricdamp.solvers import continuation as cont
from fricdamp.solvers._hb_formulations import _Full, _Setup
from tests.unit.test_hb_reuse import ring


def test_direct_evaluations_return_fresh_arrays_and_follow_the_load_scale():
    s = _Setup(ring(12), 3, 32)
    form = _Full(s, dense=False)
    assert form._jenkins_step() is not None
    rng = np.random.default_rng(5)
    x1, x2 = (0.05 * rng.standard_normal(form.N) for _ in range(2))
    kw = dict(scale=2.0, x_scale=1.3)
    # the generic path (AFT result requested) is the reference, load scales alternating
    for x, ls in ((x1, 1.0), (x2, 0.4), (x1, 1.0), (x2, 0.0)):
        r_ref, _, d_ref, _, _ = form.evaluate(x, 1.02, load_scale=ls, **kw)
        r, J, d, _, _ = form.evaluate(x, 1.02, load_scale=ls, aft_result=False,
                                      deferred=True, **kw)
        r_keep, d_keep = r.copy(), d.copy()
        form.evaluate(x2 if x is x1 else x1, 0.97, load_scale=ls, aft_result=False, **kw)
        # a later evaluation overwrote the work buffers, not the returned arrays
        assert np.array_equal(r, r_keep) and np.array_equal(d, d_keep)
        assert np.array_equal(r, r_ref) and np.array_equal(d, d_ref)


def test_norm_and_append_as_numpy():
    r = np.array([0.5, -3.0, 2.0])
    assert cont._norm(r) == 3.0 and cont._norm(np.zeros(0)) == 0.0
    assert np.isnan(cont._norm(np.array([1.0, np.nan, -4.0])))
    assert np.array_equal(cont._append(r, 7.0), np.append(r, 7.0))


def test_bordered_matrix_of_a_fixed_pattern_updates_its_values():
    rng = np.random.default_rng(2)
    J = cont.mark_fixed_pattern(sp.random(80, 80, density=0.1, format="csc", random_state=3)
                                + sp.identity(80, format="csc"))
    J.sort_indices()
    border = cont._Bordered()
    for _ in range(3):
        J.data = rng.standard_normal(J.nnz)
        c, t = rng.standard_normal(80), rng.standard_normal(80)
        A = border(J, c, t, 0.3).toarray()
        ref = np.block([[J.toarray(), c[:, None]], [t[None, :], np.array([[0.3]])]])
        assert np.array_equal(A, ref)
