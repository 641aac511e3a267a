"""Block-sparse LU with a kept symbolic analysis, for the Jacobians of harmonic balance.

Newton steps and continuation points factorise matrices of one fixed sparsity pattern. The
HB Jacobian of the full formulation couples the 2H+1 harmonic coefficients of one DOF
(unknowns ``dof * (2H+1) + h``) densely wherever a contact acts, so its natural unit is the
dense block of a DOF: SuperLU (through SciPy) finds these blocks again at every call
(supernodes), redoes its ordering, symbolic analysis and pivot search, and on the ring of
30 Jenkins contacts (331 unknowns, 1.7e4 entries in L + U) spends ~0.5 ms per
factorisation, most of it not in arithmetic.

:class:`BlockLU` does the analysis once per pattern: the block pattern (blocks of
``block_size`` consecutive unknowns, the remainder -- the border row of the continuation --
a block of its own), a fill-reducing block ordering (SuperLU's minimum degree on the block
graph or the natural order, whichever fills less), the block patterns of L and U
(Gilbert-Peierls depth-first search, CSparse ``cs_reach``) and the place of every matrix
entry in the factor storage. Each factorisation is then one compiled left-looking pass over
dense blocks (:mod:`fricdamp.solvers._sparse_lu_kernels`): ``U_KJ = L_KK^-1 P_K X_KJ``,
``X_IJ -= L_IK U_KJ``, then the panel of column J (its diagonal block and the blocks below)
with partial pivoting inside the diagonal block.

Stability: the pivot chosen inside the diagonal block must satisfy the threshold-pivoting
rule of :mod:`fricdamp.solvers.continuation` against the whole column, ``|pivot| >=
threshold * max |candidates below|`` (threshold 1e-3, SuperLU's ``diag_pivot_thresh`` used
there); otherwise :meth:`BlockLU.factor` returns None and the caller factorises with
SuperLU's pivoting instead. The factorisation is then a threshold-pivoted LU like SuperLU's
(another pivot sequence), so solutions agree with SuperLU's to rounding.

References
----------
Gilbert & Peierls (1988), SIAM J. Sci. Stat. Comput. 9, 862-874.
Davis (2006), *Direct Methods for Sparse Linear Systems*, SIAM (``cs_reach``, ``cs_lu``).
Demmel, Eisenstat, Gilbert, Li & Liu (1999), SIAM J. Matrix Anal. Appl. 20, 720-755
(supernodal LU, threshold pivoting).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from fricdamp._numba_cache import njit
from fricdamp.solvers._sparse_lu_kernels import _SOLVE_PAD, _block_numeric, _block_solve2

__all__ = ["BlockLU", "BlockFactors"]

#: Rows of the stored blocks are padded to a multiple of this (4 doubles: one AVX2 vector).
_PAD = 4


# ---------------------------------------------------------------------------- compiled kernels
def _symbolic(n, Cp, Ci):
    """Patterns of L (strictly lower) and U (strictly upper, topological order) of C = LU.

    Without pivoting (``C`` already permuted). Returns (Lp, Li, Up, Ui, ok); ``ok`` False if
    a diagonal entry is structurally zero. The compiled pass (:func:`_symbolic_pass`)
    allocates nothing; it is repeated with larger ``Li``/``Ui`` if they were too short.
    """
    cap = max(2 * Ci.size, 16)
    Lp = np.zeros(n + 1, np.int64)
    Up = np.zeros(n + 1, np.int64)
    mark = np.empty(n, np.int64)
    xi = np.empty(n, np.int64)
    pstack = np.empty(n, np.int64)
    while True:
        Li = np.empty(cap, np.int64)
        Ui = np.empty(cap, np.int64)
        nl, nu, ok = _symbolic_pass(n, Cp, Ci, Lp, Li, Up, Ui, mark, xi, pstack)
        if nl >= 0:
            return Lp, Li[:nl].copy(), Up, Ui[:nu].copy(), bool(ok)
        cap *= 2


@njit(cache=True, nogil=True)
def _symbolic_pass(n, Cp, Ci, Lp, Li, Up, Ui, mark, xi, pstack):  # pragma: no cover
    """The depth-first searches of :func:`_symbolic` into the given arrays (no allocation:
    loading its cached code needs none of numba's array-allocation modules). Returns
    (nnz L, nnz U, ok), or (-1, -1, False) if Li or Ui is too short."""
    cap_l = Li.size
    cap_u = Ui.size
    for i in range(n):
        mark[i] = -1
    Lp[0] = 0
    Up[0] = 0
    nl = 0
    nu = 0
    ok = True
    for j in range(n):
        top = n
        for pc in range(Cp[j], Cp[j + 1]):
            i0 = Ci[pc]
            if mark[i0] == j:
                continue
            head = 0
            xi[0] = i0
            while head >= 0:
                k = xi[head]
                if mark[k] != j:
                    mark[k] = j
                    pstack[head] = Lp[k] if k < j else 0
                done = True
                if k < j:
                    for p in range(pstack[head], Lp[k + 1]):
                        i = Li[p]
                        if mark[i] == j:
                            continue
                        pstack[head] = p
                        head += 1
                        xi[head] = i
                        done = False
                        break
                if done:
                    head -= 1
                    top -= 1
                    xi[top] = k
        has_diag = False
        for px in range(top, n):
            i = xi[px]
            if i < j:
                if nu >= cap_u:
                    return -1, -1, False
                Ui[nu] = i
                nu += 1
            elif i == j:
                has_diag = True
            else:
                if nl >= cap_l:
                    return -1, -1, False
                Li[nl] = i
                nl += 1
        Lp[j + 1] = nl
        Up[j + 1] = nu
        if not has_diag:
            ok = False
    return nl, nu, ok


@njit(cache=True, nogil=True)
def _entry_map(indptr, indices, blk, pos, start, ld, Lp, Li, Up, Ui, Loff, Uoff, Doff,
               nB, out, where):  # pragma: no cover - compiled
    """Storage index ``out`` of every entry of the (scalar) CSC matrix in the block factors
    (``where``: nB work entries)."""
    for i in range(nB):
        where[i] = -1
    n = indptr.size - 1
    for c in range(n):
        J = pos[blk[c]]
        for p in range(Up[J], Up[J + 1]):
            where[Ui[p]] = Uoff[p]
        where[J] = Doff[J]
        for p in range(Lp[J], Lp[J + 1]):
            where[Li[p]] = Loff[p]
        cl = c - start[blk[c]]
        lJ = ld[J]
        for p in range(indptr[c], indptr[c + 1]):
            r = indices[p]
            I = pos[blk[r]]
            out[p] = where[I] + (r - start[blk[r]]) * lJ + cl
        for p in range(Up[J], Up[J + 1]):
            where[Ui[p]] = -1
        where[J] = -1
        for p in range(Lp[J], Lp[J + 1]):
            where[Li[p]] = -1


@njit(cache=True, nogil=True)
def bordered_values(Jdata, old, extra, lastcol, c, t, s, out):  # pragma: no cover - compiled
    """Values of the bordered matrix ``[[J, c], [t^T, s]]`` in its CSC pattern (see
    :class:`fricdamp.solvers.continuation._Bordered`)."""
    for i in range(Jdata.size):
        out[old[i]] = Jdata[i]
    for i in range(extra.size):
        out[extra[i]] = t[i]
    for i in range(c.size):
        out[lastcol + i] = c[i]
    out[out.size - 1] = s


@njit(cache=True, nogil=True)
def csc_residual_norm(n, indptr, indices, data, x, b, r):  # pragma: no cover - compiled
    """``max |A x - b|`` for A in CSC form (NaN if not finite); ``r``: n work entries."""
    for i in range(n):
        r[i] = -b[i]
    for j in range(n):
        xj = x[j]
        for p in range(indptr[j], indptr[j + 1]):
            r[indices[p]] += data[p] * xj
    m = 0.0
    for i in range(n):
        a = abs(r[i])
        if not a <= m:
            m = a
    return m


# ---------------------------------------------------------------------------- analysis
def _block_fill(nB, Cp, Ci, bsz_new) -> tuple[float, tuple]:
    Lp, Li, Up, Ui, ok = _symbolic(nB, Cp, Ci)
    if not ok:
        return np.inf, (Lp, Li, Up, Ui)
    col = np.repeat(np.arange(nB), np.diff(Lp))
    fill = float(np.sum(bsz_new[Li] * bsz_new[col]) + np.sum(
        bsz_new[Ui] * bsz_new[np.repeat(np.arange(nB), np.diff(Up))]) + np.sum(bsz_new**2))
    return fill, (Lp, Li, Up, Ui)


class BlockLU:
    """Symbolic analysis of one sparsity pattern for dense-block LU (see the module).

    Parameters
    ----------
    A : scipy.sparse CSC matrix, sorted indices
        A matrix of the pattern (only its pattern is used).
    block_size : int
        Consecutive unknowns ``[b * block_size, (b + 1) * block_size)`` form block b; the
        last ``n % block_size`` unknowns form one more block.
    threshold : float
        Threshold-pivoting parameter (see the module).
    """

    __slots__ = ("n", "indptr", "indices", "nB", "bsz", "ld", "bnew", "sperm", "Lp", "Li", "Up",
                 "Ui", "Loff", "Uoff", "Doff", "size", "pstart", "amap", "threshold", "ok",
                 "failures", "calls", "_work")

    def __init__(self, A, block_size: int, threshold: float = 1e-3):
        n = A.shape[0]
        self.n = n
        self.indptr = np.asarray(A.indptr, dtype=np.int64)
        self.indices = np.asarray(A.indices, dtype=np.int64)
        self.threshold = float(threshold)
        self.failures = 0
        self.calls = 0
        nb = max(int(block_size), 1)
        n_full = n // nb
        start = np.arange(n_full + 1, dtype=np.int64) * nb
        if n_full * nb < n:
            start = np.append(start, n)
        nB = start.size - 1
        self.nB = nB
        bsz_old = np.diff(start)
        blk = np.repeat(np.arange(nB, dtype=np.int64), bsz_old)
        # block pattern (with the diagonal), symmetrised for the ordering
        col = np.repeat(np.arange(n), np.diff(self.indptr))
        Bp = sp.csc_matrix((np.ones(col.size), (blk[self.indices], blk[col])), shape=(nB, nB))
        Bp = (Bp + Bp.T + sp.identity(nB)).tocsc()
        Bp.sort_indices()
        candidates = [np.arange(nB, dtype=np.int64)]
        if nB > 2:
            import scipy.sparse.linalg as spla

            # minimum degree on the block graph (values: diagonally dominant, no pivoting)
            W = Bp.copy()
            W.data = np.where(W.indices == np.repeat(np.arange(nB), np.diff(W.indptr)),
                              4.0 * nB, 1.0)
            lu = spla.splu(W, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0)
            perm_c = np.asarray(lu.perm_c, dtype=np.int64)
            q = np.empty(nB, np.int64)
            q[perm_c] = np.arange(nB)
            candidates.append(q)
        best = None
        for q in candidates:                # q[new] = old block
            C = Bp[q][:, q].tocsc()
            C.sort_indices()
            fill, pat = _block_fill(nB, C.indptr.astype(np.int64),
                                    C.indices.astype(np.int64), bsz_old[q])
            if best is None or fill < best[0]:
                best = (fill, q, pat)
        fill, q, (Lp, Li, Up, Ui) = best
        self.ok = bool(np.isfinite(fill))
        pos = np.empty(nB, np.int64)
        pos[q] = np.arange(nB)
        bsz = bsz_old[q].astype(np.int64)
        self.bsz = bsz
        ld = ((bsz + _PAD - 1) // _PAD) * _PAD   # rows padded to whole SIMD vectors
        self.ld = ld
        self.bnew = np.concatenate([[0], np.cumsum(bsz)]).astype(np.int64)
        self.sperm = np.concatenate([np.arange(start[b], start[b + 1]) for b in q]
                                    ).astype(np.int64)
        self.Lp, self.Li, self.Up, self.Ui = Lp, Li, Up, Ui
        # storage: per block column, its U blocks, the diagonal block, its L blocks
        Loff = np.empty(Li.size, np.int64)
        Uoff = np.empty(Ui.size, np.int64)
        Doff = np.empty(nB, np.int64)
        off = 0
        for J in range(nB):
            lJ = int(ld[J])
            for p in range(Up[J], Up[J + 1]):
                Uoff[p] = off
                off += int(bsz[Ui[p]]) * lJ
            Doff[J] = off
            off += int(bsz[J]) * lJ
            for p in range(Lp[J], Lp[J + 1]):
                Loff[p] = off
                off += int(bsz[Li[p]]) * lJ
        self.Loff, self.Uoff, self.Doff, self.size = Loff, Uoff, Doff, off
        self.pstart = self.bnew[:-1].copy()
        self.amap = np.empty(self.indices.size, np.int64)
        _entry_map(self.indptr, self.indices, blk, pos, start.astype(np.int64), ld, Lp, Li,
                   Up, Ui, Loff, Uoff, Doff, nB, self.amap, np.empty(nB, np.int64))
        # work arrays of the factorisation kernel (block positions, panel rows, growth),
        # kept: nothing in them outlives a call (one factorisation at a time per analysis)
        m = int(ld.max()) if nB else 0
        self._work = (np.empty(nB, np.int64), np.empty(m * (m + 4)), np.empty(3))

    def matches(self, A) -> bool:
        return (A.shape[0] == self.n and A.indices.size == self.indices.size
                and np.array_equal(A.indptr, self.indptr)
                and np.array_equal(A.indices, self.indices))

    def factor(self, data) -> BlockFactors | None:
        """Factors of the matrix with values ``data`` (CSC order of the pattern), or None
        if a pivot fails the threshold rule (factorise with pivoting across blocks)."""
        if not self.ok:
            return None
        self.calls += 1
        S = np.empty(self.size)
        piv = np.empty(self.n, np.int64)
        where, work, stats = self._work
        status = _block_numeric(np.ascontiguousarray(data, dtype=float), self.amap, self.nB,
                                self.bsz, self.ld, self.Lp, self.Li, self.Up, self.Ui, self.Loff,
                                self.Uoff, self.Doff, S, piv, self.pstart, self.threshold,
                                where, work, stats)
        if status != 0:
            self.failures += 1
            return None
        l_max, u_max, a_max = stats.tolist()
        return BlockFactors(self, S, piv, l_max * u_max / a_max
                            if math.isfinite(l_max) and a_max > 0 else math.inf)


class BlockFactors:
    """Numeric factors from :meth:`BlockLU.factor` (own values, shared analysis)."""

    __slots__ = ("sym", "S", "piv", "growth")

    def __init__(self, sym: BlockLU, S, piv, growth: float = np.inf):
        self.sym, self.S, self.piv = sym, S, piv
        #: element growth ``max |L| max |U| / max |A|`` (NaN or inf if not finite or not
        #: measured): the backward error of the factors is ~ n eps growth max |A|, as for
        #: partial pivoting with its growth (Wilkinson)
        self.growth = float(growth)

    def solve(self, b):
        """``A^-1 b`` for b of shape (n,) or (n, k)."""
        b = np.asarray(b, dtype=float)
        if b.ndim != 1:
            cols = [self.solve_pair(b[:, k], b[:, k + 1] if k + 1 < b.shape[1] else b[:, k])
                    for k in range(0, b.shape[1], 2)]
            return np.stack([x for pair in cols for x in pair][: b.shape[1]], axis=1)
        return self.solve_pair(b, b)[0]

    def solve_pair(self, b, c):
        """``(A^-1 b, A^-1 c)`` for 1-D b and c, in one sweep (:func:`_block_solve2`)."""
        s = self.sym
        x = np.empty(s.n)
        y = np.empty(s.n)
        _block_solve2(np.ascontiguousarray(b, dtype=float), np.ascontiguousarray(c, dtype=float),
                      x, y, s.sperm, s.nB, s.bsz, s.ld, s.bnew, s.Lp, s.Li, s.Up, s.Ui,
                      s.Loff, s.Uoff, s.Doff, self.S, self.piv, s.pstart,
                      np.empty(s.n + _SOLVE_PAD), np.empty(s.n + _SOLVE_PAD))
        return x, y

    def diagonal_and_sign(self) -> tuple[np.ndarray, float]:
        """Diagonal of U and the sign of the row interchanges (the symmetric block
        permutation leaves the determinant unchanged)."""
        s = self.sym
        d = np.empty(s.n)
        swaps = 0
        for J in range(s.nB):
            nJ, lJ, d0, q0 = int(s.bsz[J]), int(s.ld[J]), int(s.Doff[J]), int(s.pstart[J])
            d[s.bnew[J]: s.bnew[J] + nJ] = self.S[d0: d0 + nJ * lJ: lJ + 1]
            swaps += int(np.count_nonzero(self.piv[q0: q0 + nJ] != np.arange(nJ)))
        return d, (-1.0 if swaps % 2 else 1.0)

    @property
    def fill(self) -> int:
        """Stored entries of L and U (dense blocks, rows padded)."""
        return int(self.sym.size)
