"""The direct Jenkins AFT step of the full HB formulation (issue 13, cost per point).

``_Full.evaluate(..., aft_result=False)`` calls the compiled Jenkins AFT step for all
contacts with kept buffers instead of the generic :func:`fricdamp.solvers.aft.aft` driver.
It runs the same kernels on the same data in the same order, so the residual, its Jacobian
and dr/dOmega must be *identical* (bit for bit) to the generic path, and a frequency
response computed through it must give the same curve: same points, coefficients equal to
1e-8 relative to the largest (measured: 0, bitwise). Other laws (and subclasses of
Jenkins) keep the generic path.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.solvers import hb
from fricdamp.solvers._hb_formulations import _Full, _Setup
from fricdamp.structure import ContactElement, MechanicalSystem


def ring(n=30, split=False, law=Jenkins):
    K = sp.lil_matrix((n, n))
    P = sp.lil_matrix((n, n))
    for i in range(n):
        j = (i + 1) % n
        K[i, i] += 1.1
        K[i, j] -= 0.05
        K[j, i] -= 0.05
        P[i, i] = -1.0
        P[i, j] = 1.0
    P = P.tocsr()
    if split:        # two Jenkins elements with different parameters
        h = n // 2
        contacts = (ContactElement(law(0.5, 0.02, n_contacts=h), P[:h], name="a"),
                    ContactElement(law(0.7, 0.015, n_contacts=n - h), P[h:], name="b"))
    else:
        contacts = (ContactElement(law(0.5, 0.02, n_contacts=n), P, name="jenkins"),)
    return MechanicalSystem(M=sp.identity(n, format="csr"), K=K.tocsr(),
                            D=0.005 * sp.identity(n, format="csr"), contacts=contacts,
                            loads=(hb.engine_order_load(n, 3, 0.01),), name="ring")


@pytest.mark.parametrize("n, harmonics, split", [(30, 5, False), (30, 5, True),
                                                  (10, 3, True)])
def test_direct_step_identical_to_generic_aft(n, harmonics, split):
    s = _Setup(ring(n, split=split), harmonics, 64)
    form = _Full(s)
    assert form.dense == (n == 10)          # 70 unknowns: the dense Jacobian
    assert form._jenkins_step() is not None
    rng = np.random.default_rng(3)
    for omega, load_scale in ((0.95, 1.0), (1.05, 0.7)):
        # amplitudes from 1e-3 to 0.1 along the ring: stuck and slipping contacts
        amp = np.repeat(np.geomspace(1e-3, 0.1, s.n), s.nh)
        x = amp * rng.standard_normal(form.N)
        kw = dict(scale=3.0, x_scale=1.7, load_scale=load_scale)
        r0, J0, d0, _, res = form.evaluate(x, omega, **kw)
        J0 = J0.copy()                      # the sparse Jacobian's data is replaced
        r1, J1, d1, xi1, res1 = form.evaluate(x, omega, aft_result=False, **kw)
        assert res is not None and res1 is None and xi1 is None
        assert np.array_equal(r0, r1) and np.array_equal(d0, d1)
        dense = (lambda J: J) if form.dense else (lambda J: J.toarray())
        assert np.array_equal(dense(J0), dense(J1))
        # stuck and slipping contacts both present, so both branches of the step are covered
        limit = np.concatenate([c.law.slip_force for c in s.contacts])
        slipping = np.abs(res.f_time).max(axis=0) >= (1 - 1e-12) * limit
        assert 0 < np.mean(slipping) < 1


def test_curve_same_through_direct_step(monkeypatch):
    system = ring()
    fast = hb.frequency_response(system, 0.9, 1.3, harmonics=5, samples=64)
    monkeypatch.setattr(_Full, "_jenkins_step", lambda self: None)
    slow = hb.frequency_response(system, 0.9, 1.3, harmonics=5, samples=64)
    assert fast.success and slow.success
    assert fast.n_points == slow.n_points and fast.n_factorizations == slow.n_factorizations
    scale = np.abs(slow.coefficients).max()
    assert np.abs(fast.coefficients - slow.coefficients).max() <= 1e-8 * scale
    assert np.abs(fast.omega - slow.omega).max() <= 1e-8 * slow.omega.max()
    assert fast.peak(0)[1] == pytest.approx(slow.peak(0)[1], rel=1e-8)


def test_other_laws_keep_generic_path():
    class MyJenkins(Jenkins):
        pass

    assert _Full(_Setup(ring(split=True, law=MyJenkins), 3, 32))._jenkins_step() is None


def test_deferred_jacobian_identical_and_safe_after_a_later_evaluation():
    """``evaluate(..., deferred=True)`` returns the Jacobian as a callable that assembles the
    same matrix (bit for bit) when called; called after another evaluation overwrote the
    kept contact blocks, it still gives the Jacobian at its own point."""
    from fricdamp.solvers.continuation import jacobian_of

    s = _Setup(ring(), 5, 64)
    form = _Full(s)
    rng = np.random.default_rng(5)
    amp = np.repeat(np.geomspace(1e-3, 0.1, s.n), s.nh)
    x1, x2 = (amp * rng.standard_normal(form.N) for _ in range(2))
    kw = dict(scale=3.0, x_scale=1.7, aft_result=False)
    J1 = form.evaluate(x1, 1.05, **kw)[1].toarray()
    J2 = form.evaluate(x2, 0.97, **kw)[1].toarray()
    r1, thunk1, d1, _, _ = form.evaluate(x1, 1.05, deferred=True, **kw)
    assert callable(thunk1)
    assert np.array_equal(jacobian_of(thunk1).toarray(), J1)
    thunk1 = form.evaluate(x1, 1.05, deferred=True, **kw)[1]
    r2, thunk2, _, _, _ = form.evaluate(x2, 0.97, deferred=True, **kw)
    assert np.array_equal(thunk1().toarray(), J1)       # blocks overwritten: evaluated again
    assert np.array_equal(jacobian_of(thunk2).toarray(), J2)
    assert np.array_equal(r1, form.evaluate(x1, 1.05, **kw)[0])


_FRESH = """
import sys
import numpy as np
import scipy.sparse as sp
from fricdamp.contact import Jenkins
from fricdamp.solvers import hb
from fricdamp.structure import ContactElement, MechanicalSystem
n = 30
K = 1.1 * np.eye(n) - 0.05 * (np.roll(np.eye(n), 1, 1) + np.roll(np.eye(n), -1, 1))
P = np.roll(np.eye(n), 1, 1) - np.eye(n)
system = MechanicalSystem(M=sp.identity(n, format="csr"), K=sp.csr_matrix(K),
                          D=0.005 * sp.identity(n, format="csr"),
                          contacts=(ContactElement(Jenkins(0.5, 0.02, n_contacts=n),
                                                   sp.csr_matrix(P)),),
                          loads=(hb.engine_order_load(n, 3, 0.01),))
before = set(sys.modules)
fr = hb.frequency_response(system, 0.9, 1.3, harmonics=3, samples=32, max_points=5)
assert fr.n_points == 5 and fr.method == "full-sparse", (fr.n_points, fr.method)
print(sorted(m for m in set(sys.modules) - before if m.startswith("numba")))
"""


def test_sparse_hb_curve_loads_no_numba_array_modules():
    """The kernels of a sparse full-formulation curve of Jenkins contacts (linear residual,
    projections, Jenkins AFT step, Jacobian values, bordering, block LU analysis, numeric
    factorisation and solve, residual check) allocate nothing: loading their cached code in
    a fresh process imports none of numba's array modules (``numba.np.arrayobj`` and the
    ~10 modules it pulls in, ~0.06 s of CPU). The second process runs from the caches that
    the first wrote."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    for _ in range(2):
        out = subprocess.run([sys.executable, "-c", _FRESH], capture_output=True, text=True,
                             env=env, check=True)
    assert out.stdout.strip() == "[]", out.stdout
