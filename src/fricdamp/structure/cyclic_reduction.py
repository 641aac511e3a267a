"""Cyclic Craig–Bampton with a reduced cut interface, and wheel modes by cyclic symmetry.

:func:`reduce_sector` turns a large FE sector (10^4–10^5 DOF, sparse) into a small
:class:`~fricdamp.structure.cyclic.CyclicSector` whose cut DOFs are *interface modal
coordinates*; :func:`wheel_modes` gives every mode of the wheel assembled from it by
nodal diameter, without ever forming the wheel.

**Craig–Bampton step.** The boundary is ``b = [L, R, G]``: the left cut, the right cut and
the kept groups (contact patches, probes). With ``i`` the other (interior) DOFs::

    u_i = X_b u_b + Phi eta,   X_b = -K_ii^{-1} K_ib,   K_ii Phi = M_ii Phi Lambda

The constraint modes ``X_b`` come from one sparse LU of ``K_ii`` (SuperLU in symmetric
mode) applied to blocks of right-hand sides; the fixed-interface modes ``Phi`` from
shift-invert Lanczos on the same factorisation. The Guyan matrices of the boundary are
``K^G = K_bb + K_bi X_b`` and ``M^G = [I; X_b]^T M [I; X_b]``; condensing the kept groups
statically (``u_G = S u_c``, ``S = -K^G_GG^{-1} K^G_Gc``) gives the Guyan matrices
``K_c, M_c`` of the two cuts ``c = [L, R]`` of a sector whose groups move freely.

**One interface basis for both cuts (derived here).** In the wheel the right cut of sector
``j`` and the left cut of sector ``j+1`` are one *junction*; with ``Rb`` the block rotation
by the sector angle acting on the (x, y, z) triples of the cut (:meth:`CyclicSector.
interface_rotation`, identity for cylindrical frames) compatibility reads
``u_R^(j) = Rb u_L^(j+1)``. Every junction is the same, so ONE real basis ``V``
(``n_b x n_interface_modes``) serves both cuts, each in its own frame::

    u_L = V xi_L,     u_R = Rb V xi_R

Then ``u_R^(j) = Rb u_L^(j+1)`` is ``Rb V xi_R^(j) = Rb V xi_L^(j+1)``, that is
``xi_R^(j) = xi_L^(j+1)`` (``V`` has full column rank): the interface coordinates
correspond 1:1 and the reduced sector is a cyclic sector with ``frame="cylindrical"``,
``left = xi_L``, ``right = xi_R``. The sector basis is::

    q = T [xi_L; xi_R; u_G; eta],   T = [[V, 0, 0, 0],        (rows L)
                                        [0, Rb V, 0, 0],      (rows R)
                                        [0, 0, I, 0],         (rows G)
                                        [X_L V, X_R Rb V, X_G, Phi]]   (rows i)

Every motion of the reduced wheel is a motion of the Craig–Bampton wheel whose junction
displacements lie in ``span V``: the reduced wheel is a Rayleigh–Ritz (Galerkin) model of
the Craig–Bampton wheel and, for every nodal diameter, of the full sector's cyclic problem,
whatever real ``V``. Its frequencies lie above the exact ones, decrease monotonically as
columns are appended to ``V`` (nested subspaces, Cauchy interlacing) and equal plain
Craig–Bampton's (:func:`~fricdamp.structure.reduction.craig_bampton_sector`) when
``n_interface_modes = n_b`` (``V`` square and invertible).

**Which V.** The metric is the junction's Guyan mass ``M_J = M_c,LL + Rb^T M_c,RR Rb`` (the
kinetic energy of a junction displacement ``w = u_L^(j+1)`` with the neighbouring cuts held:
``w^T M_c,LL w`` in sector ``j+1`` plus ``(Rb w)^T M_c,RR (Rb w)`` in sector ``j``); likewise
``K_J``. Two choices (``interface=``):

* ``"junction"``: the lowest eigenvectors of ``K_J V = M_J V Omega^2``, the characteristic
  constraint modes of one junction with its neighbours clamped.
* ``"cyclic"`` (default): the characteristic constraint modes of the whole wheel's
  interface (Castanier, Tan & Pierre 2001: eigenvectors of the *assembled* Guyan interface
  matrices). That assembly is block-circulant, so its eigenvectors are the per-nodal-diameter
  modes of ``(T_nd^H K_c T_nd, T_nd^H M_c T_nd)``, ``T_nd = [I; exp(i phi) Rb]``,
  ``phi = 2 pi nd / N``, of size ``n_b``. Their left-cut shapes (real and imaginary parts),
  taken over all ``nd = 0 .. floor(N/2)`` in ascending eigenvalue, are orthonormalised in
  ``M_J``; a shape whose part outside the basis so far is below ``interface_tolerance`` of
  its norm is skipped (the same shape recurs in neighbouring nodal diameters). The
  selection is prefix-stable, so larger ``n_interface_modes`` only append columns.

The junction pencil sees each sector clamped one sector away, which overstiffens the smooth
cut shapes of the low wheel modes: on a 2592-DOF lattice sector (288 DOFs per cut, N = 30,
20 fixed-interface modes) the first-family frequencies at 0 and 2 ND are 5 % (6 modes),
1.6 % (24), 0.3 % (48) high with ``"junction"`` and at the Craig–Bampton floor (1e-4) with 6
``"cyclic"`` modes, all of ND 0, 2, 6, 15 (two families) with 12. With the groups *held*
instead of condensed (contact patches next to the cut) the junction modes were worse still
(155 % with 6, 4 % with 96 of 288). ``tests/unit/test_cyclic_reduction.py`` checks the
compatibility and ``tests/validation/test_cyclic_reduction_wheel.py`` the convergence.

**Wheel modes.** For a harmonic index ``nd`` the reduced sector's cyclic problem is the
Hermitian pencil ``(T_nd^H K T_nd, T_nd^H M T_nd)`` of size ``n_independent`` (a few hundred):
dense ``eigh``. A sector eigenvector ``x`` (``x^H M_nd x = 1``) is the travelling wave
``q_j = exp(i j phi) x`` of the assembled wheel, of mass ``N``. Its real and imaginary
parts are M-orthogonal standing waves of mass ``N / 2`` for ``0 < nd < N/2``; for ``nd = 0``
and ``N / 2`` the wave is real. Scaled by ``sqrt(2/N)`` (cos and sin) and ``1/sqrt(N)``
(real) they are real mass-orthonormal wheel modes, and the union over
``nd = 0 .. floor(N/2)`` of all of them (``N n_independent`` modes) is a complete
eigenbasis of :func:`~fricdamp.structure.cyclic.assemble_full` of the reduced sector.

References
----------
Craig, R. R. & Bampton, M. C. C. (1968). Coupling of substructures for dynamic analyses.
AIAA J. 6, 1313–1319. Castanier, M. P., Tan, Y.-C. & Pierre, C. (2001). Characteristic
constraint modes for component mode synthesis. AIAA J. 39, 1182–1187. Thomas, D. L. (1979).
Dynamics of rotationally periodic structures. Int. J. Numer. Meth. Eng. 14, 81–102.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fricdamp.errors import ModelError
from fricdamp.structure.cyclic import CyclicSector
from fricdamp.structure.eigen import DENSE_MAX, _dof_array, eigenpairs

logger = logging.getLogger(__name__)

#: Constraint modes of the boundary are kept in memory (one n_interior x n_boundary array)
#: up to this many bytes; beyond, the Guyan mass is accumulated block by block with one
#: extra (adjoint) solve per boundary DOF instead.
STORE_BYTES = 1 << 30

#: Right-hand sides are solved in blocks of at most this many bytes (n_interior x block).
BLOCK_BYTES = 64 << 20

#: Largest reduced sector (independent DOFs) whose wheel modes :func:`wheel_modes` computes
#: by dense ``eigh``.
WHEEL_DENSE_MAX = 6000


# --------------------------------------------------------------------------- kernels
def _symmetric(A: np.ndarray) -> np.ndarray:
    return 0.5 * (A + A.conj().T)


def _csr(A) -> sp.csr_matrix:
    return sp.csr_matrix(A) if sp.issparse(A) else sp.csr_matrix(np.asarray(A, float))


def _factorise(Kii: sp.csc_matrix):
    """Sparse LU of the (symmetric positive definite) interior stiffness, or None if singular.

    SuperLU in symmetric mode (minimum degree on ``A + A^T``, diagonal pivots) fills ~20 %
    less and factorises ~25 % faster than the default COLAMD ordering on a 30k-DOF lattice
    sector; a zero pivot falls back to partial pivoting.
    """
    attempts = ({"permc_spec": "MMD_AT_PLUS_A", "diag_pivot_thresh": 0.0,
                 "options": {"SymmetricMode": True}}, {})
    for kwargs in attempts:
        try:
            lu = spla.splu(Kii, **kwargs)
        except RuntimeError:  # "Factor is exactly singular"
            continue
        d = np.abs(lu.U.diagonal())
        if d.size and np.all(np.isfinite(d)) and d.min() > 1e-14 * d.max():
            return lu
    return None


def _blocks(n_cols: int, n_rows: int):
    """Column slices of at most :data:`BLOCK_BYTES` of an (n_rows, n_cols) float array."""
    step = max(1, min(n_cols, BLOCK_BYTES // (8 * max(n_rows, 1))))
    for start in range(0, n_cols, step):
        yield slice(start, min(start + step, n_cols))


def _solve(lu, B) -> np.ndarray:
    """``K_ii^{-1} B`` for a dense or sparse (n_i, k) right-hand side, in column blocks."""
    n_i = lu.shape[0]
    out = np.empty((n_i, B.shape[1]))
    for c in _blocks(B.shape[1], n_i):
        Bc = B[:, c]
        out[:, c] = lu.solve(np.asarray(Bc.toarray() if sp.issparse(Bc) else Bc, float))
    return out


def _fixed_interface_modes(lu, Kii, Mii, n_modes: int, method: str):
    """Lowest ``n_modes`` eigenpairs of ``(K_ii, M_ii)``, reusing the LU of ``K_ii``."""
    n_i = Kii.shape[0]
    if n_modes == 0:
        return np.zeros(0), np.zeros((n_i, 0))
    dense = method == "dense" or (method == "auto" and (n_i <= DENSE_MAX
                                                         or n_modes >= n_i // 2))
    if dense or n_modes >= n_i - 1:
        return eigenpairs(Kii, Mii, n_modes, method="dense")
    from threadpoolctl import threadpool_limits

    # ARPACK keeps its operator in a reference cycle: reach the factorisation through a box
    # emptied afterwards, so it is freed with the reduction, not at the next collection
    box = [lu.solve]
    op = spla.LinearOperator((n_i, n_i), matvec=lambda b: box[0](b),
                             matmat=lambda b: box[0](b), dtype=float)
    v0 = np.random.default_rng(12345).standard_normal(n_i)
    try:
        with threadpool_limits(limits=1, user_api="blas"):
            lam, X = spla.eigsh(Kii, k=n_modes, M=Mii, sigma=0.0, which="LM", OPinv=op,
                                v0=v0, ncv=min(n_i, max(2 * n_modes + 1, 20)), tol=0.0)
    finally:
        box.clear()
    order = np.argsort(lam)
    lam, X = lam[order], X[:, order]
    X = X / np.sqrt(np.einsum("ij,ij->j", X, Mii @ X))
    return lam, X


class _ConstraintModes:
    """``X_b = -K_ii^{-1} K_ib`` and the boundary Guyan matrices, by blocks of columns.

    Stored (one dense n_i x n_b array) when it fits :data:`STORE_BYTES`, else streamed:
    ``X_b^T Z = -K_bi K_ii^{-1} Z`` replaces the stored product (one more solve per
    column, ``K`` symmetric).
    """

    def __init__(self, lu, K, M, i, b):
        n_i, n_b = i.size, b.size
        Ki, Mi = K[i], M[i]
        self.lu, self.Kib, self.Kbi = lu, Ki[:, b], sp.csr_matrix(K[b][:, i])
        Mib, Mbi, Mii = Mi[:, b], sp.csr_matrix(M[b][:, i]), sp.csr_matrix(Mi[:, i])
        self.X = np.empty((n_i, n_b)) if 8 * n_i * n_b <= STORE_BYTES else None
        KG = K[b][:, b].toarray()
        MG = M[b][:, b].toarray()
        for c in _blocks(n_b, n_i):
            Xc = -_solve(lu, self.Kib[:, c])
            KG[:, c] += self.Kbi @ Xc
            MG[:, c] += Mbi @ Xc
            if self.X is not None:
                self.X[:, c] = Xc
            else:
                MG[:, c] -= self.Kbi @ _solve(lu, Mib[:, c].toarray() + Mii @ Xc)
        if self.X is not None:  # MG = M_bb + P + P^T + X^T M_ii X, P = M_bi X (in MG now)
            MG += MG.T - M[b][:, b].toarray()
            G2 = np.zeros((n_b, n_b))
            for c in _blocks(n_b, n_i):           # upper block triangle only: half the flops
                G2[:c.stop, c] = self.X[:, :c.stop].T @ (Mii @ self.X[:, c])
            MG += np.triu(G2) + np.triu(G2, 1).T
        self.KG, self.MG = _symmetric(KG), _symmetric(MG)

    def interior(self, C: np.ndarray) -> np.ndarray:
        """Interior displacements ``X_b C`` of boundary displacements ``C`` (n_b, k)."""
        if self.X is not None:
            return self.X @ C
        return -_solve(self.lu, self.Kib @ C)


def _condense_groups(KG, MG, n_c: int):
    """Guyan matrices of the cuts (first ``n_c`` boundary DOFs), the groups condensed."""
    if KG.shape[0] == n_c:
        return KG, MG
    c, g = slice(0, n_c), slice(n_c, None)
    try:
        S = -sla.solve(KG[g, g], KG[g, c], assume_a="pos")
    except (np.linalg.LinAlgError, sla.LinAlgError):
        raise ModelError("keep: the kept DOFs are not held when the cuts are fixed (their "
                         "Guyan stiffness is singular)") from None
    Kc = KG[c, c] + KG[c, g] @ S
    MgS = MG[c, g] @ S
    Mc = MG[c, c] + MgS + MgS.T + S.T @ MG[g, g] @ S
    return _symmetric(Kc), _symmetric(Mc)


def _rotate(A, Rb, left: bool, right: bool):
    """``Rb^T A`` / ``A Rb`` / ``Rb^T A Rb`` for the sparse block rotation ``Rb``."""
    if left:
        A = np.asarray(Rb.T @ A)
    if right:
        A = np.asarray((Rb.T @ A.T).T)
    return A


def _junction(Kc, Mc, Rb, n_b):
    """Junction Guyan matrices ``K_J, M_J`` and the cross blocks ``B = A_LR Rb``."""
    L, R = slice(0, n_b), slice(n_b, 2 * n_b)
    KJ = Kc[L, L] + _rotate(Kc[R, R], Rb, True, True)
    MJ = Mc[L, L] + _rotate(Mc[R, R], Rb, True, True)
    return (_symmetric(KJ), _symmetric(MJ), _rotate(Kc[L, R], Rb, False, True),
            _rotate(Mc[L, R], Rb, False, True))


def _cyclic_interface_basis(KJ, MJ, BK, BM, n_sectors: int, n_im: int, tol: float):
    """Characteristic constraint modes of the wheel's interface, one real basis (docstring).

    With ``T_nd = [I; e Rb]``, ``e = exp(i phi)``: ``T_nd^H A_c T_nd = A_J + e B + conj(e) B^T``
    (``B = A_c,LR Rb``), formed in O(n_b^2) per nodal diameter. Returns ``V`` (n_b, n_im)
    with ``V^T M_J V = I``, and per column the eigenvalue [(rad/s)^2] and nodal diameter of
    the interface mode it came from.
    """
    n_b = KJ.shape[0]
    C = sla.cholesky(MJ, lower=False)                 # M_J = C^T C: M_J-norms are 2-norms
    p = min(n_b, max(n_im, 8))      # the O(n_b^3) reduction dominates: p costs little
    while True:
        lams, tags, Y, bound = [], [], [], np.inf
        for nd in range(n_sectors // 2 + 1):
            e = np.exp(2j * np.pi * nd / n_sectors)
            if (2 * nd) % n_sectors == 0:
                e = e.real
            top = min(n_b, p + 1)
            lam, X = sla.eigh(_symmetric(KJ + e * BK + np.conj(e) * BK.T),
                              _symmetric(MJ + e * BM + np.conj(e) * BM.T),
                              subset_by_index=[0, top - 1], check_finite=False)
            if top > p:                               # the (p+1)-th bounds the exact stream
                bound = min(bound, lam[p])
                lam, X = lam[:p], X[:, :p]
            CX = C @ X
            parts = [CX.real] + ([CX.imag] if np.iscomplexobj(CX) else [])
            for part_index, part in enumerate(parts):
                lams.append(lam)
                tags.append(np.column_stack([np.full(lam.size, nd), np.arange(lam.size),
                                             np.full(lam.size, part_index)]))
                Y.append(part)
        lams, tags, Y = np.concatenate(lams), np.concatenate(tags), np.hstack(Y)
        order = np.lexsort((tags[:, 2], tags[:, 1], tags[:, 0], lams))
        order = order[lams[order] <= bound]
        Q = np.empty((n_b, n_im))
        picked, k = [], 0                             # candidate columns taken, count
        for threshold in (tol, 1e-10):
            for j in order:
                if k == n_im:
                    break
                y = Y[:, j]
                size = np.linalg.norm(y)
                for _ in range(2):                    # Gram-Schmidt, twice is enough
                    y = y - Q[:, :k] @ (Q[:, :k].T @ y)
                norm = np.linalg.norm(y)
                if norm > threshold * size:
                    Q[:, k] = y / norm
                    picked.append(j)
                    k += 1
            if k == n_im or p < n_b:                  # second pass only on the full stream
                break
        if k == n_im:
            V = sla.solve_triangular(C, Q, lower=False)
            return V, lams[picked], tags[picked, 0].astype(np.int64)
        if p == n_b:  # pragma: no cover - the nd = 0 modes alone span the cut
            raise ModelError("interface_tolerance: the interface modes do not span "
                             f"{n_im} independent shapes")
        p = min(n_b, 2 * p)


# --------------------------------------------------------------------------- reduction
@dataclass(frozen=True, repr=False)
class CyclicReducedSector:
    """A cyclic sector reduced by Craig–Bampton with characteristic interface modes.

    Attributes
    ----------
    sector : CyclicSector
        The reduced sector, ``frame="cylindrical"``, DOFs ``[xi_L, xi_R, u_G, eta]``:
        ``n_interface_modes`` left and right interface coordinates [sqrt(kg) m] (``left``,
        ``right``), the kept DOFs (physical, original units and Cartesian sector frame,
        listed in ``named_dofs`` with reduced indices), and the fixed-interface modal
        coordinates [sqrt(kg) m]. M, K, D symmetric. Assemble it with
        :func:`~fricdamp.structure.cyclic.assemble_full` or take its modes with
        :func:`wheel_modes`.
    expansion : ndarray, shape (n, n_reduced)
        ``q_sector = expansion @ q_reduced`` (original sector DOFs).
    interface_basis : ndarray, shape (n_b, n_interface_modes)
        ``V``: left cut ``u_L = V xi_L``, right cut ``u_R = Rb V xi_R``; ``V^T M_J V = I``.
    interface_frequencies : ndarray, shape (n_interface_modes,)
        Eigenfrequency [Hz] of the interface mode behind each column of ``V``.
    interface_nds : ndarray of int, shape (n_interface_modes,)
        Its nodal diameter (``interface="cyclic"``) or -1 (``"junction"``).
    fixed_interface_frequencies : ndarray, shape (n_modes,)
        Eigenfrequencies [Hz] of the kept fixed-interface modes.
    kept_dofs : ndarray of int, shape (n_kept,)
        Original sector indices of the kept DOFs, in reduced order (reduced indices
        ``2 n_interface_modes + arange(n_kept)``).
    rayleigh : tuple of float or None
        ``(a, b)`` [1/s, s] if the reduced damping was set to ``a M_r + b K_r``.
    timings : mapping of str to float
        Wall time [s] of each stage: ``factorise``, ``fixed_interface_modes``,
        ``constraint_modes``, ``interface_modes``, ``projection``.
    """

    sector: CyclicSector
    expansion: np.ndarray
    interface_basis: np.ndarray
    interface_frequencies: np.ndarray
    interface_nds: np.ndarray
    fixed_interface_frequencies: np.ndarray
    kept_dofs: np.ndarray
    rayleigh: tuple[float, float] | None = None
    timings: Mapping[str, float] = field(default_factory=dict)

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    @property
    def n_interface_modes(self) -> int:
        return self.interface_basis.shape[1]

    @property
    def n_modes(self) -> int:
        return self.fixed_interface_frequencies.size

    def expand(self, q_reduced) -> np.ndarray:
        """Original sector DOFs from reduced ones: (..., n_reduced) -> (..., n)."""
        q = np.asarray(q_reduced)
        if q.shape[-1] != self.expansion.shape[1]:
            raise ModelError(f"q_reduced must have {self.expansion.shape[1]} entries in its "
                             f"last axis, got shape {q.shape}")
        return q @ self.expansion.T

    def reduce_vector(self, f) -> np.ndarray:
        """Reduced load ``T^T f`` of sector loads ``f`` [N], (..., n) -> (..., n_reduced)."""
        f = np.asarray(f)
        if f.shape[-1] != self.expansion.shape[0]:
            raise ModelError(f"f must have {self.expansion.shape[0]} entries in its last "
                             f"axis, got shape {f.shape}")
        return f @ self.expansion

    def reduced_index(self, sector_dofs) -> np.ndarray:
        """Reduced indices of kept original sector DOFs."""
        n = self.expansion.shape[0]
        dofs = np.atleast_1d(np.asarray(sector_dofs, dtype=np.int64))
        if np.any((dofs < 0) | (dofs >= n)):
            raise ModelError(f"sector_dofs must lie in [0, {n - 1}]")
        pos = np.full(n, -1, dtype=np.int64)
        pos[self.kept_dofs] = 2 * self.n_interface_modes + np.arange(self.kept_dofs.size)
        out = pos[dofs]
        if np.any(out < 0):
            raise ModelError(f"sector_dofs {dofs[out < 0].tolist()} are not kept DOFs of the "
                             "reduced sector")
        return out


def _kept_groups(sector: CyclicSector, keep) -> tuple[dict[str, np.ndarray], np.ndarray]:
    groups = sector.named_dofs if keep is None else keep
    if not isinstance(groups, Mapping):
        raise ModelError("keep must be a mapping of group names to DOF lists, got "
                         f"{type(keep).__name__}")
    cut = np.zeros(sector.n_dof, dtype=bool)
    cut[sector.left] = True
    cut[sector.right] = True
    named = {}
    for key, dofs in groups.items():
        d = _dof_array(f"keep[{key!r}]", np.atleast_1d(dofs), sector.n_dof)
        if np.any(cut[d]):
            raise ModelError(f"keep[{key!r}] must not hold cut (left/right) DOFs, which are "
                             f"replaced by interface modes; got {d[cut[d]].tolist()}")
        named[str(key)] = d
    listed = np.concatenate([np.zeros(0, dtype=np.int64), *named.values()])
    first = np.sort(np.unique(listed, return_index=True)[1])
    return named, listed[first].astype(np.int64)  # union, in order of first appearance


def _check_count(name: str, value, lo: int, hi: int, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer, float)) or \
            int(value) != value or not lo <= value <= hi:
        raise ModelError(f"{name} must be an integer in [{lo}, {hi}] ({what}), got {value!r}")
    return int(value)


def reduce_sector(sector: CyclicSector, *, keep: Mapping[str, Sequence[int]] | None = None,
                  n_modes: int, n_interface_modes: int, interface: str = "cyclic",
                  interface_tolerance: float = 1e-3, method: str = "auto",
                  rayleigh: tuple[float, float] | None = None) -> CyclicReducedSector:
    """Cyclic Craig–Bampton reduction with the cut interface reduced (module docstring).

    Parameters
    ----------
    sector : CyclicSector
        The sector (sparse or dense M, K; Cartesian or cylindrical frames).
    keep : mapping of str to sequence of int, optional
        Groups of sector DOFs kept physically (contact patches, probes, load points);
        default ``sector.named_dofs``. Groups may overlap; they must not touch the cuts.
    n_modes : int
        Fixed-interface modes, ``0 <= n_modes <= n_interior``.
    n_interface_modes : int
        Columns of the interface basis ``V``, ``1 <= n_interface_modes <= n_b`` (``n_b``:
        DOFs of one cut); ``n_b`` reproduces plain Craig–Bampton.
    interface : {"cyclic", "junction"}
        Interface modes of the whole wheel's Guyan interface by nodal diameter (default),
        or of one junction with its neighbours clamped (module docstring).
    interface_tolerance : float
        ``"cyclic"`` only: an interface shape is skipped when its part outside the basis
        so far is below this fraction of its ``M_J``-norm, ``0 < tol < 1``.
    method : {"auto", "dense", "sparse"}
        Eigen-solver of the fixed-interface modes (``sparse``: shift-invert Lanczos on the
        LU of ``K_ii`` already used for the constraint modes; ``auto``: dense up to
        :data:`~fricdamp.structure.reduction.DENSE_MAX` interior DOFs).
    rayleigh : (float, float), optional
        ``(a, b)``: set the reduced damping to ``a M_r + b K_r`` [a in 1/s, b in s]
        instead of projecting ``sector.D`` (the same when ``D = a M + b K``, and cheaper).

    Returns
    -------
    CyclicReducedSector
        ``sector`` has ``2 n_interface_modes + n_kept + n_modes`` DOFs.

    Raises
    ------
    ModelError
        For a bad argument (the message names it), or a singular ``K_ii`` (part of the
        sector held by neither the cuts nor the kept DOFs).

    Notes
    -----
    Cost (``n_i`` interior, ``n_bd = 2 n_b + n_kept`` boundary DOFs): one sparse LU of
    ``K_ii``, ``n_bd`` solves (``2 n_bd`` when the constraint modes exceed
    :data:`STORE_BYTES`), one ``n_bd x n_i x n_bd`` product for the Guyan mass, and for
    ``"cyclic"`` ``floor(N/2) + 1`` dense Hermitian eigenproblems of size ``n_b``. Stage
    timings are returned in ``timings``.

    Examples
    --------
    >>> s = lattice_sector(3, 5, 2, n_sectors=12)
    >>> red = reduce_sector(s, n_modes=4, n_interface_modes=5)
    >>> red.sector.n_dof, red.sector.frame, red.sector.named_dofs["probe"].tolist()
    (29, 'cylindrical', [22, 23, 24])
    """
    t0 = time.perf_counter()
    if not isinstance(sector, CyclicSector):
        raise ModelError(f"sector must be a CyclicSector, got {type(sector).__name__}")
    if method not in ("auto", "dense", "sparse"):
        raise ModelError(f"method must be 'auto', 'dense' or 'sparse', got {method!r}")
    if interface not in ("cyclic", "junction"):
        raise ModelError(f"interface must be 'cyclic' or 'junction', got {interface!r}")
    if not (isinstance(interface_tolerance, (int, float, np.floating))
            and 0 < interface_tolerance < 1):
        raise ModelError(f"interface_tolerance must be a number in (0, 1), got "
                         f"{interface_tolerance!r}")
    named, kept = _kept_groups(sector, keep)
    n, n_b = sector.n_dof, sector.n_interface
    L, R = sector.left, sector.right
    mask = np.ones(n, dtype=bool)
    mask[L] = mask[R] = False
    mask[kept] = False
    i = np.flatnonzero(mask)
    n_i = i.size
    n_modes = _check_count("n_modes", n_modes, 0, n_i, "interior DOFs")
    n_im = _check_count("n_interface_modes", n_interface_modes, 1, n_b, "DOFs of one cut")
    if rayleigh is not None:
        try:
            a_r, b_r = (float(v) for v in rayleigh)
        except (TypeError, ValueError):
            raise ModelError(f"rayleigh must be a pair (a, b) of numbers, got {rayleigh!r}"
                             ) from None
        if not (np.isfinite(a_r) and np.isfinite(b_r)) or a_r < 0 or b_r < 0:
            raise ModelError(f"rayleigh must be a pair (a, b) of finite numbers >= 0, got "
                             f"{rayleigh!r}")
        rayleigh = (a_r, b_r)
    if n_i == 0:
        raise ModelError("keep: the sector has no interior DOFs left to reduce")

    K, M = _csr(sector.K), _csr(sector.M)
    Kii = sp.csc_matrix(K[i][:, i])
    Mii = sp.csc_matrix(M[i][:, i])
    timings = {}
    lu = _factorise(Kii)
    if lu is None:
        raise ModelError("sector: the interior stiffness K_ii is singular (part of the sector "
                         "is held by neither the cuts nor the kept DOFs); clamp it or keep "
                         "more DOFs")
    t1 = time.perf_counter()
    timings["factorise"] = t1 - t0

    lam, Phi = _fixed_interface_modes(lu, Kii, Mii, n_modes, method)
    t2 = time.perf_counter()
    timings["fixed_interface_modes"] = t2 - t1

    boundary = np.concatenate([L, R, kept])
    modes = _ConstraintModes(lu, K, M, i, boundary)
    t3 = time.perf_counter()
    timings["constraint_modes"] = t3 - t2

    Rb = sector.interface_rotation()
    Kc, Mc = _condense_groups(modes.KG, modes.MG, 2 * n_b)
    KJ, MJ, BK, BM = _junction(Kc, Mc, Rb, n_b)
    del Kc, Mc
    try:
        if interface == "junction":
            lam_v, V = sla.eigh(KJ, MJ, subset_by_index=[0, n_im - 1], check_finite=False)
            nd_v = np.full(n_im, -1, dtype=np.int64)
        else:
            V, lam_v, nd_v = _cyclic_interface_basis(KJ, MJ, BK, BM, sector.n_sectors, n_im,
                                                     float(interface_tolerance))
    except np.linalg.LinAlgError as exc:
        raise ModelError(f"sector: the cuts' Guyan mass is not positive definite ({exc})"
                         ) from None
    RV = np.asarray(Rb @ V)
    t4 = time.perf_counter()
    timings["interface_modes"] = t4 - t3

    n_g = kept.size
    n_red = 2 * n_im + n_g + n_modes
    C = np.zeros((boundary.size, 2 * n_im + n_g))    # boundary DOFs of the static columns
    C[:n_b, :n_im] = V
    C[n_b:2 * n_b, n_im:2 * n_im] = RV
    C[2 * n_b:, 2 * n_im:] = np.eye(n_g)
    T = np.zeros((n, n_red))
    T[boundary, :2 * n_im + n_g] = C
    T[i, :2 * n_im + n_g] = modes.interior(C)
    T[i, 2 * n_im + n_g:] = Phi
    del modes

    Mr = _symmetric(T.T @ (M @ T))
    Kr = _symmetric(T.T @ (K @ T))
    if rayleigh is not None:
        Dr = rayleigh[0] * Mr + rayleigh[1] * Kr
    else:
        Dr = _symmetric(T.T @ (_csr(sector.D) @ T))
    timings["projection"] = time.perf_counter() - t4

    names = sector.dof_names or tuple(f"q{k + 1}" for k in range(n))
    dof_names = (tuple(f"xiL{k + 1}" for k in range(n_im))
                 + tuple(f"xiR{k + 1}" for k in range(n_im))
                 + tuple(names[d] for d in kept) + tuple(f"eta{k + 1}" for k in range(n_modes)))
    pos = np.full(n, -1, dtype=np.int64)
    pos[kept] = 2 * n_im + np.arange(n_g)
    reduced = CyclicSector(
        M=Mr, K=Kr, D=Dr, left=np.arange(n_im), right=n_im + np.arange(n_im),
        n_sectors=sector.n_sectors, frame="cylindrical",
        named_dofs={k: pos[v] for k, v in named.items()}, dof_names=dof_names,
        name=f"{sector.name} (cyclic CB, {n_im} interface + {n_modes} modes)")
    logger.debug("reduce_sector %s: %d -> %d DOFs, timings %s", sector.name, n, n_red,
                 {k: round(v, 3) for k, v in timings.items()})
    return CyclicReducedSector(
        sector=reduced, expansion=T, interface_basis=V,
        interface_frequencies=np.sqrt(np.maximum(lam_v, 0.0)) / (2 * np.pi),
        interface_nds=nd_v,
        fixed_interface_frequencies=np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi),
        kept_dofs=kept, rayleigh=rayleigh, timings=timings)


# --------------------------------------------------------------------------- wheel modes
@dataclass(frozen=True, repr=False)
class WheelModes:
    """Real, mass-orthonormal modes of a cyclic wheel, computed by nodal diameter.

    Modes are **grouped by nodal diameter** (``nds`` ascending), ascending in frequency
    within each group; for ``0 < nd < N/2`` each sector eigenvector gives two adjacent
    modes, the standing waves ``cos`` then ``sin`` of the same frequency. Use
    :meth:`ascending` for the permutation that sorts all modes by frequency.

    Attributes
    ----------
    sector : CyclicSector
        The sector whose wheel this is (e.g. ``CyclicReducedSector.sector``).
    omega : ndarray, shape (n_modes,)
        Angular eigenfrequencies [rad/s].
    nd : ndarray of int, shape (n_modes,)
        Nodal diameter (harmonic index) of each mode.
    kind : ndarray of str, shape (n_modes,)
        ``"real"`` (nd = 0 or N/2), ``"cos"`` or ``"sin"`` (standing waves).
    sector_index : ndarray of int, shape (n_modes,)
        Index of the mode's sector eigenvector within its nodal diameter.
    nds : ndarray of int, shape (n_nd,)
        The nodal diameters computed, ascending.
    sector_shapes : tuple of ndarray, each shape (n_sector_dofs, n_modes_nd)
        Per entry of ``nds``: the sector shapes ``u~ = T_nd x`` [1/sqrt(kg)], complex
        (real for nd = 0, N/2), ``x^H T_nd^H M T_nd x = 1``. Sector ``j`` of the wheel
        moves as ``Re/Im(exp(2 pi i nd j / N) u~)`` times ``sqrt(2/N)`` (cos/sin) or as
        ``(+1)^j u~`` (nd = 0), ``(-1)^j u~`` (nd = N/2) times ``1/sqrt(N)`` (real).

    Notes
    -----
    With ``M_w``, ``K_w`` the matrices of :func:`~fricdamp.structure.cyclic.assemble_full`
    and ``Phi`` = :meth:`full_shapes`: ``Phi^T M_w Phi = I`` and
    ``Phi^T K_w Phi = diag(omega^2)``.
    """

    sector: CyclicSector
    omega: np.ndarray
    nd: np.ndarray
    kind: np.ndarray
    sector_index: np.ndarray
    nds: np.ndarray
    sector_shapes: tuple[np.ndarray, ...]

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    @property
    def n_modes(self) -> int:
        return self.omega.size

    @property
    def n_sectors(self) -> int:
        return self.sector.n_sectors

    @property
    def frequencies(self) -> np.ndarray:
        """Eigenfrequencies [Hz], shape (n_modes,)."""
        return self.omega / (2 * np.pi)

    def ascending(self) -> np.ndarray:
        """Permutation (n_modes,) sorting the modes by frequency (stable)."""
        return np.argsort(self.omega, kind="stable")

    def columns(self, nd: int) -> slice:
        """The modes (columns) of nodal diameter ``nd``."""
        for k, start, m, mult in self._layout():
            if self.nds[k] == nd:
                return slice(start, start + mult * m)
        raise ModelError(f"nd must be one of the computed nodal diameters "
                         f"{self.nds.tolist()}, got {nd!r}")

    def _layout(self):
        start = 0
        for k, nd in enumerate(self.nds):
            mult = 1 if (2 * int(nd)) % self.n_sectors == 0 else 2
            m = self.sector_shapes[k].shape[1]
            yield k, start, m, mult
            start += mult * m

    def _dofs(self, name_or_dofs) -> np.ndarray:
        if isinstance(name_or_dofs, str):
            try:
                return self.sector.named_dofs[name_or_dofs]
            except KeyError:
                raise ModelError(f"name_or_dofs must be a named group of the sector "
                                 f"{sorted(self.sector.named_dofs)} or DOF indices, got "
                                 f"{name_or_dofs!r}") from None
        return _dof_array("name_or_dofs", np.atleast_1d(name_or_dofs), self.sector.n_dof)

    def group_shapes(self, name_or_dofs, *, out: np.ndarray | None = None) -> np.ndarray:
        """Wheel mode shapes at a DOF group of every sector.

        Parameters
        ----------
        name_or_dofs : str or sequence of int
            A named group of :attr:`sector` or sector DOF indices (right-cut DOFs allowed).
        out : ndarray, shape (n_sectors, n_group_dofs, n_modes), optional
            C-contiguous float64 array to fill (saves the first-touch cost of a fresh
            allocation, most of the time for large groups: 1 s of 1.1 s for 250 DOFs x 30
            sectors x 8730 modes on the 2-core reference machine).

        Returns
        -------
        ndarray, shape (n_sectors, n_group_dofs, n_modes)
            ``[j, k, m]``: DOF ``k`` of the group in sector ``j`` (in sector ``j``'s own
            frame) of real mass-normalised wheel mode ``m`` [1/sqrt(kg)].
        """
        g = self._dofs(name_or_dofs)
        N = self.n_sectors
        j = np.arange(N)
        shape = (N, g.size, self.n_modes)
        if out is None:
            out = np.empty(shape)
        elif (not isinstance(out, np.ndarray) or out.shape != shape or out.dtype != np.float64
              or not out.flags.c_contiguous):
            raise ModelError(f"out must be a C-contiguous float64 array of shape {shape}")
        for k, start, m, mult in self._layout():
            Y = self.sector_shapes[k][g]
            phi = 2 * np.pi * int(self.nds[k]) / N
            if mult == 1:
                sign = np.round(np.cos(phi * j)) / np.sqrt(N)
                np.multiply(sign[:, None, None], Y.real[None], out=out[:, :, start:start + m])
            else:
                # adjacent (cos, sin) columns are the (real, imaginary) parts of one
                # complex number: write the travelling wave straight into them
                wave = out[:, :, start:start + 2 * m].view(np.complex128)
                np.multiply((np.sqrt(2.0 / N) * np.exp(1j * phi * j))[:, None, None],
                            Y[None], out=wave)
        return out

    def full_shapes(self) -> np.ndarray:
        """Mode shapes of the assembled wheel, shape (n_full, n_modes) [1/sqrt(kg)].

        In the DOF numbering of :func:`~fricdamp.structure.cyclic.assemble_full` (sector-major
        independent DOFs). Dense: for small models and tests.
        """
        ind = self.sector.independent
        return self.group_shapes(ind).reshape(self.n_sectors * ind.size, self.n_modes)

    def modal_damping(self, a: float, b: float) -> np.ndarray:
        """Diagonal modal damping ``a + b omega^2`` [1/s] of Rayleigh damping ``a M + b K``.

        Parameters
        ----------
        a : float
            Mass-proportional coefficient [1/s].
        b : float
            Stiffness-proportional coefficient [s].

        Returns
        -------
        ndarray, shape (n_modes,)
            ``Phi^T D Phi`` (diagonal); the damping ratios are ``(a / omega + b omega) / 2``.
        """
        for name, v in (("a", a), ("b", b)):
            if not np.isfinite(v):
                raise ModelError(f"{name} must be a finite Rayleigh coefficient, got {v!r}")
        return float(a) + float(b) * self.omega**2


def wheel_modes(red, *, nds: Sequence[int] | None = None,
                n_modes_per_nd: int | None = None) -> WheelModes:
    """Modes of the wheel assembled from a (reduced) sector, by cyclic symmetry.

    Parameters
    ----------
    red : CyclicReducedSector or CyclicSector
        The sector (its ``n_independent`` must not exceed :data:`WHEEL_DENSE_MAX`: reduce
        a large sector first with :func:`reduce_sector`).
    nds : sequence of int, optional
        Nodal diameters, each in ``[0, floor(N/2)]`` (default: all).
    n_modes_per_nd : int, optional
        Lowest sector modes per nodal diameter, ``1 <= n <= n_independent`` (default all:
        then the modes of all nodal diameters are a complete eigenbasis of the wheel).

    Returns
    -------
    WheelModes
        Grouped by nodal diameter (see :class:`WheelModes`).

    Raises
    ------
    ModelError
        For a bad argument (the message names it) or a sector too large for dense ``eigh``.

    Examples
    --------
    >>> red = reduce_sector(lattice_sector(3, 5, 2, n_sectors=12), n_modes=4,
    ...                     n_interface_modes=5)
    >>> wm = wheel_modes(red)
    >>> wm.n_modes == red.sector.n_full, wm.group_shapes("probe").shape
    (True, (12, 3, 288))
    """
    sector = red.sector if isinstance(red, CyclicReducedSector) else red
    if not isinstance(sector, CyclicSector):
        raise ModelError(f"red must be a CyclicReducedSector or CyclicSector, got "
                         f"{type(red).__name__}")
    N, n_ind = sector.n_sectors, sector.n_independent
    if n_ind > WHEEL_DENSE_MAX:
        raise ModelError(f"red must have at most {WHEEL_DENSE_MAX} independent DOFs for dense "
                         f"wheel modes, got {n_ind}; reduce it with reduce_sector first")
    all_nds = sector.nodal_diameters
    if nds is None:
        nds = all_nds
    else:
        arr = np.atleast_1d(np.asarray(nds))
        if (arr.ndim != 1 or arr.size == 0 or not np.issubdtype(arr.dtype, np.integer)
                or arr.min() < 0 or arr.max() > N // 2 or np.unique(arr).size != arr.size):
            raise ModelError(f"nds must be distinct integers in [0, {N // 2}], got {nds!r}")
        nds = np.sort(arr.astype(np.int64))
    if n_modes_per_nd is None:
        m = n_ind
    elif (isinstance(n_modes_per_nd, bool) or int(n_modes_per_nd) != n_modes_per_nd
          or not 1 <= n_modes_per_nd <= n_ind):
        raise ModelError(f"n_modes_per_nd must be an integer in [1, {n_ind}], got "
                         f"{n_modes_per_nd!r}")
    else:
        m = int(n_modes_per_nd)
    Kd = sector.K.toarray() if sp.issparse(sector.K) else np.asarray(sector.K)
    Md = sector.M.toarray() if sp.issparse(sector.M) else np.asarray(sector.M)
    omega, nd_of, kind, index, shapes = [], [], [], [], []
    for nd in nds:
        T = sector.cyclic_transform(int(nd)).toarray()
        TH = T.conj().T
        Kc, Mc = _symmetric(TH @ Kd @ T), _symmetric(TH @ Md @ T)
        try:
            lam, X = sla.eigh(Kc, Mc, subset_by_index=None if m == n_ind else [0, m - 1],
                              check_finite=False)
        except np.linalg.LinAlgError as exc:
            raise ModelError(f"red: the sector mass is not positive definite ({exc})") from None
        w = np.sqrt(np.maximum(lam, 0.0))
        shapes.append(T @ X)
        k = np.arange(m)
        if (2 * int(nd)) % N == 0:
            omega.append(w)
            index.append(k)
            kind.append(np.full(m, "real"))
        else:
            omega.append(np.repeat(w, 2))
            index.append(np.repeat(k, 2))
            kind.append(np.tile(np.array(["cos", "sin"]), m))
        nd_of.append(np.full(omega[-1].size, int(nd), dtype=np.int64))
    return WheelModes(sector=sector, omega=np.concatenate(omega), nd=np.concatenate(nd_of),
                      kind=np.concatenate(kind), sector_index=np.concatenate(index),
                      nds=np.asarray(nds, dtype=np.int64), sector_shapes=tuple(shapes))


# --------------------------------------------------------------------------- test sector
def lattice_sector(n_radial: int, n_tangential: int, n_axial: int, *, n_sectors: int = 30,
                   inner_radius_m: float = 1.0, outer_radius_m: float = 1.5,
                   height_m: float = 0.2, bar_stiffness_N: float = 1e6,
                   node_mass_kg: float = 1e-2,
                   rayleigh: tuple[float, float] | None = None) -> CyclicSector:
    """A synthetic 3D solid-like sector (braced truss lattice) with large cut faces.

    Nodes on the cylindrical grid ``r x theta x z`` (``n_radial + 1`` radii, of which the
    inner one is clamped, ``n_tangential`` angles from ``-alpha/2`` to ``+alpha/2``,
    ``n_axial`` heights) are joined to their 26 grid neighbours by bars of axial stiffness
    ``bar_stiffness_N / length`` [N/m]; bars and nodal masses on a cut face count half
    (they are shared with the neighbour sector), so the assembled wheel is the lattice ring.
    Cartesian DOF frames (x, y, z per node), wheel axis z; sparse M (lumped), K.

    Parameters
    ----------
    n_radial, n_tangential, n_axial : int
        Grid size: ``>= 1``, ``>= 4``, ``>= 2``. Each cut has ``3 n_radial n_axial`` DOFs,
        the sector ``3 n_radial n_tangential n_axial``.
    n_sectors : int
        Number of sectors (>= 3).
    inner_radius_m, outer_radius_m, height_m : float
        Geometry [m].
    bar_stiffness_N : float
        Axial rigidity ``EA`` [N] of every bar.
    node_mass_kg : float
        Mass of an interior node [kg].
    rayleigh : (float, float), optional
        Damping ``D = a M + b K``.

    Returns
    -------
    CyclicSector
        Named groups ``contact_left`` / ``contact_right`` (the outer-radius nodes next to
        each cut, all heights: ``3 n_axial`` DOFs each) and ``probe`` (the outer top node
        at mid angle).
    """
    for name, v, lo in (("n_radial", n_radial, 1), ("n_tangential", n_tangential, 4),
                        ("n_axial", n_axial, 2), ("n_sectors", n_sectors, 3)):
        if isinstance(v, bool) or int(v) != v or v < lo:
            raise ModelError(f"{name} must be an integer >= {lo}, got {v!r}")
    if not 0 < inner_radius_m < outer_radius_m or not height_m > 0:
        raise ModelError("inner_radius_m, outer_radius_m, height_m must satisfy "
                         "0 < inner < outer and height > 0")
    nr, nt, nz = int(n_radial) + 1, int(n_tangential), int(n_axial)
    h = np.pi / n_sectors
    r = np.linspace(inner_radius_m, outer_radius_m, nr)
    th = np.linspace(-h, h, nt)
    z = np.linspace(0.0, height_m, nz)
    I, J, Z = (a.ravel() for a in np.meshgrid(np.arange(nr), np.arange(nt), np.arange(nz),
                                               indexing="ij"))
    xyz = np.column_stack([r[I] * np.cos(th[J]), r[I] * np.sin(th[J]), z[Z]])
    node = np.arange(I.size).reshape(nr, nt, nz)
    ea, eb = [], []
    for off in [(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)
                if (a, b, c) > (0, 0, 0)]:
        i2, j2, k2 = I + off[0], J + off[1], Z + off[2]
        ok = (i2 >= 0) & (i2 < nr) & (j2 >= 0) & (j2 < nt) & (k2 >= 0) & (k2 < nz)
        ea.append(node[I[ok], J[ok], Z[ok]])
        eb.append(node[i2[ok], j2[ok], k2[ok]])
    ea, eb = np.concatenate(ea), np.concatenate(eb)
    d = xyz[eb] - xyz[ea]
    length = np.linalg.norm(d, axis=1)
    e = d / length[:, None]
    face = ((J[ea] == 0) & (J[eb] == 0)) | ((J[ea] == nt - 1) & (J[eb] == nt - 1))
    k = np.where(face, 0.5, 1.0) * bar_stiffness_N / length
    ke = k[:, None, None] * e[:, :, None] * e[:, None, :]
    three = np.arange(3)
    rows, cols, vals = [], [], []
    for p, q, sgn in ((ea, ea, 1.0), (eb, eb, 1.0), (ea, eb, -1.0), (eb, ea, -1.0)):
        rr = np.broadcast_to(3 * p[:, None, None] + three[None, :, None], ke.shape)
        cc = np.broadcast_to(3 * q[:, None, None] + three[None, None, :], ke.shape)
        rows.append(rr.ravel())
        cols.append(cc.ravel())
        vals.append((sgn * ke).ravel())
    n_all = 3 * I.size
    K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n_all, n_all))
    mass = np.where((J == 0) | (J == nt - 1), 0.5, 1.0) * node_mass_kg
    free = np.flatnonzero(np.repeat(I > 0, 3))
    pos = np.full(n_all, -1, dtype=np.int64)
    pos[free] = np.arange(free.size)
    K = K[free][:, free]
    M = sp.diags(np.repeat(mass, 3)[free]).tocsr()

    def dofs(nodes) -> np.ndarray:
        return pos[(3 * np.asarray(nodes)[:, None] + three).ravel()]

    named = {"contact_left": dofs(node[nr - 1, 1, :]),
             "contact_right": dofs(node[nr - 1, nt - 2, :]),
             "probe": dofs([node[nr - 1, nt // 2, nz - 1]])}
    D = None if rayleigh is None else rayleigh[0] * M + rayleigh[1] * K
    return CyclicSector(M=M, K=K, D=D, left=dofs(node[1:, 0, :].ravel()),
                        right=dofs(node[1:, nt - 1, :].ravel()), n_sectors=n_sectors,
                        frame="cartesian", axis="z", named_dofs=named,
                        name=f"lattice sector {n_radial}x{n_tangential}x{n_axial}")


__all__ = [
    "CyclicReducedSector",
    "WheelModes",
    "lattice_sector",
    "reduce_sector",
    "wheel_modes",
]
