"""Compiled pieces of the HB engine (issue 13): the dense-block sparse LU with its kept
symbolic analysis, the one-call AFT step of Jenkins elements, the compiled peak amplitude.

References: each piece against the code path it replaces, in the same run -- SuperLU and
dense LAPACK for the LU (solutions and determinants; tolerances: a backward-stable LU of
these well-conditioned matrices reproduces the solution to ~1e3 eps), the generic
``periodic_response`` + DFT route for the AFT step (same march, sums reordered: 1e-13),
the vectorised numpy grid-and-Newton search for the peak amplitude (same algorithm: 1e-13).
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.solvers._sparse_lu import BlockLU
from fricdamp.solvers.aft import HarmonicBasis
from fricdamp.solvers.continuation import _Factor, _Orderings


def _matrix(n, density, seed, dominant=True):
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=density, random_state=seed, format="csc")
    if dominant:
        A = A + sp.diags(rng.uniform(0.5, 1.0, n))
    A = sp.csc_matrix(A)
    A.sort_indices()
    return A


@pytest.mark.parametrize("n, block", [(5, 2), (40, 3), (200, 7), (331, 11), (60, 1)])
def test_block_lu_solves_and_determinant(n, block):
    A = _matrix(n, 0.05, 2)
    analysis = BlockLU(A, block)
    assert analysis.ok
    rng = np.random.default_rng(1)
    for _ in range(3):
        B = A.copy()
        B.data = A.data * (1.0 + 0.1 * rng.standard_normal(A.nnz))
        F = analysis.factor(B.data)
        assert F is not None
        b = rng.standard_normal(n)
        x = F.solve(b)
        x_ref = np.linalg.solve(B.toarray(), b)
        assert np.max(np.abs(x - x_ref)) <= 1e-10 * np.max(np.abs(x_ref))
        d, sign = F.diagonal_and_sign()
        s_ref, l_ref = np.linalg.slogdet(B.toarray())
        assert sign * np.prod(np.sign(d)) == s_ref
        assert np.sum(np.log(np.abs(d))) == pytest.approx(l_ref, rel=1e-10, abs=1e-10)
        X = F.solve(np.stack([b, 2 * b], axis=1))       # several right-hand sides
        np.testing.assert_allclose(X[:, 1], 2 * x, rtol=1e-14, atol=1e-300)


def test_block_lu_refuses_a_bad_kept_pivot_and_factor_falls_back():
    # blocks of 2: [[eps, 1], [1, eps]] in the diagonal block of block 0 is fine (in-block
    # pivoting), but a diagonal block that is tiny against the rows below fails the
    # threshold rule: the factorisation is refused and _Factor uses SuperLU instead
    n = 4
    A = sp.csc_matrix(np.array([[1e-9, 0.0, 1.0, 0.0],
                                [0.0, 1e-9, 0.0, 1.0],
                                [1.0, 0.0, 1.0, 0.0],
                                [0.0, 1.0, 0.0, 1.0]]))
    A.sort_indices()
    analysis = BlockLU(A, 2)
    assert analysis.factor(A.data) is None
    assert analysis.failures == 1
    F = _Factor(A, _Orderings(block_size=2))
    assert F.ok and F.block is None
    b = np.arange(1.0, n + 1)
    np.testing.assert_allclose(A @ F.solve(b), b, rtol=1e-12, atol=1e-12)


def _block_matrix(n_blocks, size, seed):
    """Dense blocks on a sparse block pattern (like an HB Jacobian), plus a border row."""
    rng = np.random.default_rng(seed)
    pattern = sp.random(n_blocks, n_blocks, density=0.1, random_state=seed) + sp.identity(
        n_blocks)
    A = sp.kron(pattern, rng.uniform(-1, 1, (size, size))).tolil()
    A[np.arange(A.shape[0]), np.arange(A.shape[0])] = 4.0 * size
    n = A.shape[0]
    B = sp.lil_matrix((n + 1, n + 1))
    B[:n, :n] = A
    B[n, :n] = rng.standard_normal(n)
    B[:n, n] = rng.standard_normal(n)[:, None]
    B[n, n] = 1.0
    B = sp.csc_matrix(B)
    B.sort_indices()
    return B


def test_factor_with_blocks_matches_superlu():
    A = _block_matrix(30, 11, 5)
    n = A.shape[0]
    b = np.random.default_rng(2).standard_normal(n)
    orderings = _Orderings(block_size=11)
    F_first = _Factor(A, orderings)         # SuperLU: its fill decides for the pattern
    F_block = _Factor(A, orderings)
    F_super = _Factor(A, _Orderings())
    assert F_first.block is None and F_block.block is not None and F_super.block is None
    x_b, x_s = F_block.solve(b), F_super.solve(b)
    assert np.max(np.abs(x_b - x_s)) <= 1e-11 * np.max(np.abs(x_s))
    assert F_block.log_det()[0] == F_super.log_det()[0]
    assert F_block.log_det()[1] == pytest.approx(F_super.log_det()[1], rel=1e-12)


@pytest.mark.parametrize("size", [11, 9, 7])
def test_rows_as_vectors_give_the_bits_of_the_general_loops(monkeypatch, size):
    # stored rows of 4, 8, 12 or 16 (_PAD = 4 or 8; the border block has rows of 4 or 8)
    # are factorised as <4 x double> vectors (_column_w), rows padded to 20 by the scalar
    # loops (_column_any). Every real entry sees the same operations in the same order, so
    # the factors are the same to the bit (no tolerance); the solves sum the products with
    # a block in the order of their vectors (rows of 4-16) or of the scalar loop (20): the
    # same solutions to rounding (1e-14 of these diagonally dominant matrices)
    from fricdamp.solvers import _sparse_lu

    A = _block_matrix(30, size, 7)
    rng = np.random.default_rng(3)
    data = A.data * (1.0 + 0.1 * rng.standard_normal(A.nnz))
    factors = []
    for pad in (4, 8, 20):
        monkeypatch.setattr(_sparse_lu, "_PAD", pad)
        F = BlockLU(A, size).factor(data)
        assert F is not None
        factors.append(F)
    assert [int(F.sym.ld[0]) for F in factors] == ([12, 16, 20] if size > 8 else [8, 8, 20])
    d0, s0 = factors[0].diagonal_and_sign()
    b = rng.standard_normal(A.shape[0])
    x0 = factors[0].solve(b)
    for F in factors[1:]:
        d, sign = F.diagonal_and_sign()
        assert np.array_equal(d, d0) and sign == s0
        assert np.array_equal(F.piv, factors[0].piv)
        assert np.array_equal(F.S[F.sym.Doff[0]: F.sym.Doff[0] + size],
                              factors[0].S[factors[0].sym.Doff[0]: factors[0].sym.Doff[0]
                                           + size])
        assert np.max(np.abs(F.solve(b) - x0)) <= 1e-14 * np.max(np.abs(x0))
    B = sp.csc_matrix((data, A.indices, A.indptr), shape=A.shape)
    assert np.max(np.abs(B @ x0 - b)) <= 1e-12 * np.max(np.abs(b))
    # two right-hand sides in one sweep (rows of 12 against the block of the right-hand
    # side held in registers, sums reordered): the same solutions to rounding (1e-13:
    # a few hundred eps of these diagonally dominant matrices)
    e = np.zeros(A.shape[0])
    e[-1] = 1.0
    x_ref = np.linalg.solve(B.toarray(), np.stack([b, e], axis=1))
    for F in factors:
        x, y = F.solve_pair(b, e)
        assert np.max(np.abs(x - x_ref[:, 0])) <= 1e-13 * np.max(np.abs(x_ref[:, 0]))
        assert np.max(np.abs(y - x_ref[:, 1])) <= 1e-13 * np.max(np.abs(x_ref[:, 1]))


def test_block_lu_not_used_where_blocks_are_sparse():
    # a scattered pattern: dense blocks of 11 would store far more than SuperLU's fill
    A = _matrix(331, 0.01, 6)
    orderings = _Orderings(block_size=11)
    _Factor(A, orderings)
    F = _Factor(A, orderings)
    assert F.block is None and orderings.items[0].block is None


def _element_growth(F, A):
    """max |L| max |U| / max |A| of dense-block factors, from their storage (reference);
    the unit diagonal of L counts as 1."""
    s, S = F.sym, F.S
    l_max, u_max = 1.0, 0.0
    for J in range(s.nB):
        nJ, lJ = int(s.bsz[J]), int(s.ld[J])
        D = S[s.Doff[J]: s.Doff[J] + nJ * lJ].reshape(nJ, lJ)[:, :nJ]
        u_max = max(u_max, np.abs(np.triu(D)).max())
        l_max = max(l_max, np.abs(np.tril(D, -1)).max())
        for p in range(s.Up[J], s.Up[J + 1]):
            u_max = max(u_max, np.abs(S[s.Uoff[p]: s.Uoff[p] + s.bsz[s.Ui[p]] * lJ]).max())
        for p in range(s.Lp[J], s.Lp[J + 1]):
            l_max = max(l_max, np.abs(S[s.Loff[p]: s.Loff[p] + s.bsz[s.Li[p]] * lJ]).max())
    return l_max * u_max / np.abs(A.data).max()


@pytest.mark.parametrize("scale, checked", [(1.0, False), (1e-4, True)])
def test_element_growth_decides_the_residual_check(monkeypatch, scale, checked):
    # the kernel reports the element growth max |L| max |U| / max |A| of its factors (the
    # reference computed here from the storage: the same maxima, 1e-15). The first solve's
    # residual check is skipped when it is small (block LU as accurate as the partial
    # pivoting the check would fall back to), and done when a diagonal block 1e4 times
    # smaller than its neighbours keeps pivots ~200 times smaller than the entries below
    # them (threshold rule 1e-3: accepted; multipliers ~200, growth ~1e3)
    from fricdamp.solvers import _sparse_lu

    A = _block_matrix(30, 11, 5).tolil()
    A[:11, :11] = A[:11, :11] * scale
    A = sp.csc_matrix(A)
    A.sort_indices()
    F = BlockLU(A, 11).factor(A.data)
    assert F.growth == pytest.approx(_element_growth(F, A), rel=1e-15)
    assert (F.growth > _Factor.GROWTH_UNCHECKED) == checked
    calls = []
    norm = _sparse_lu.csc_residual_norm
    monkeypatch.setattr(_sparse_lu, "csc_residual_norm",
                        lambda *args: calls.append(1) or norm(*args))
    orderings = _Orderings(block_size=11)
    _Factor(A, orderings)                   # SuperLU: its fill decides for the pattern
    Fb = _Factor(A, orderings)
    b = A @ np.ones(A.shape[0])
    x = Fb.solve(b)
    assert Fb.block is not None and len(calls) == int(checked)
    assert np.max(np.abs(x - 1.0)) <= 1e-12


def test_jenkins_harmonic_response_equals_periodic_route():
    H, N = 5, 64
    basis = HarmonicBasis.create(H, N)
    rng = np.random.default_rng(0)
    nc = 40
    # amplitudes from fully stuck (0.1 F_s/k_t) to gross slip (10 F_s/k_t), with a mean
    amp = np.geomspace(0.05, 20.0, nc)[:, None] * 0.02 / 0.5
    X = rng.normal(size=(nc, 2 * H + 1)) * amp
    X[:, 3:] *= 0.3
    law = Jenkins(0.5, 0.02, n_contacts=nc)
    state = rng.normal(scale=0.01, size=(nc, 1))
    for st in (None, state):
        hr = law.harmonic_response(X[:, None, :], basis.synthesis, basis.analysis,
                                   state=st)
        u = (basis.synthesis @ X.T)[:, :, None]
        pr = law.periodic_response(u, basis=basis.synthesis, state=st)
        f_ref = (basis.analysis @ pr.force[:, :, 0]).T
        J_ref = np.einsum("hi,icj->chj", basis.analysis, pr.jacobian[:, :, 0, 0, :])
        np.testing.assert_allclose(hr.force[:, 0, :], f_ref, rtol=0, atol=1e-13 * 0.02)
        np.testing.assert_allclose(hr.jacobian, J_ref, rtol=0, atol=1e-13 * 0.5)
        np.testing.assert_allclose(hr.force_time[:, :, 0], pr.force[:, :, 0], atol=1e-15)
        np.testing.assert_allclose(hr.state, pr.state, atol=1e-15)
        assert hr.periods == pr.periods and hr.converged == pr.converged
    # a batch of copies (points of a curve) gives the copies' results
    X3 = np.stack([X, 0.5 * X, 2 * X])[:, :, None, :]
    hb3 = law.harmonic_response(X3, basis.synthesis, basis.analysis, jacobian=False)
    for p, f in enumerate((1.0, 0.5, 2.0)):
        one = law.harmonic_response(f * X[:, None, :], basis.synthesis, basis.analysis,
                                    jacobian=False)
        np.testing.assert_array_equal(hb3.force[p], one.force)


def _peak_numpy(X, n_grid=128):
    """The vectorised implementation that the compiled peak search replaced."""
    C = X.reshape(-1, X.shape[-1]).copy()
    C[:, 0] = 0.0
    H = (C.shape[1] - 1) // 2
    tau_g = 2 * np.pi * np.arange(n_grid) / n_grid
    k = np.arange(1, H + 1)
    S = np.concatenate([np.ones((n_grid, 1)), np.stack(
        [np.cos(np.outer(tau_g, k)), np.sin(np.outer(tau_g, k))], axis=2).reshape(n_grid, -1)],
        axis=1)
    xs = C @ S.T
    i = np.argmax(np.abs(xs), axis=1)
    sgn = np.sign(xs[np.arange(C.shape[0]), i])
    tau = 2 * np.pi * i / n_grid
    a, b = C[:, 1::2], C[:, 2::2]
    for _ in range(3):
        ck, sk = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
        d1 = np.sum(k * (-a * sk + b * ck), axis=1)
        d2 = np.sum(-(k**2) * (a * ck + b * sk), axis=1)
        ok = d2 * sgn < 0
        tau = np.where(ok, tau - d1 / np.where(ok, d2, 1.0), tau)
    ck, sk = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
    val = np.abs(np.sum(a * ck + b * sk, axis=1))
    return np.maximum(val, np.abs(xs).max(axis=1)).reshape(X.shape[:-1])


def test_compiled_peak_amplitude_equals_numpy_search():
    from fricdamp.solvers.hb import peak_amplitude

    rng = np.random.default_rng(4)
    X = rng.normal(size=(7, 9, 11)) * np.geomspace(1, 1e-3, 11)
    np.testing.assert_allclose(peak_amplitude(X), _peak_numpy(X), rtol=1e-13)
    # a pure cosine: the amplitude exactly
    Y = np.zeros((1, 11))
    Y[0, 1] = 2.5
    Y[0, 0] = 7.0
    assert peak_amplitude(Y)[0] == pytest.approx(2.5, rel=1e-15)
