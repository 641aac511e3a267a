"""Cyclic symmetry: one sector, the full assembly, and modal analysis by nodal diameter.

A bladed wheel of ``N`` identical sectors is described by one sector's matrices and two
index sets of interface DOFs: the *left* cut and the *right* cut, the right cut being the
left cut rotated by the sector angle ``alpha = 2 pi / N``. Sector ``j`` is sector 0 rotated
by ``j alpha``; its DOFs are expressed in its own frame (sector 0's frame rotated by
``j alpha``), so every sector has the same matrices. The right cut of sector ``j`` is the
left cut of sector ``j + 1``, which gives the compatibility condition (derived here, not
taken from a paper)::

    R^j u_R^(j) = R^(j+1) u_L^(j+1)   =>   u_R^(j) = R u_L^(j+1)

with ``R`` the rotation by ``alpha`` about the wheel axis acting on each (x, y, z) triple of
vector components when the DOF frames are Cartesian (``frame="cartesian"``), and ``R = I``
when they are cylindrical (``frame="cylindrical"``: radial, tangential, axial components
map 1:1).

**Nodal diameters.** A motion with ``nd`` nodal diameters (harmonic index) is
``u^(j) = u~ exp(i j phi)``, ``phi = 2 pi nd / N``. The compatibility condition then
becomes the complex cyclic constraint on one sector::

    u_R = exp(i phi) R u_L,     u = T_nd [u_L; u_I]

and the modes of that harmonic are those of the Hermitian pencil
``(T_nd^H K T_nd, T_nd^H M T_nd)`` — real for ``nd = 0`` and ``nd = N/2``. Harmonics ``nd``
and ``N - nd`` have the same frequencies (complex-conjugate shapes): for
``0 < nd < N/2`` each frequency is a double mode of the full wheel (two standing waves,
the real and imaginary parts of the travelling wave), for ``nd = 0`` and ``N/2`` a single
one. The union over ``nd = 0 .. floor(N/2)`` with these multiplicities is the full wheel's
spectrum, which ``tests/validation/test_cyclic_vs_full.py`` checks against an independent
global assembly.

Full-assembly DOF numbering: sector ``j`` contributes its *independent* DOFs (all DOFs
except the right cut, in their sector order) at full indices
``j * n_independent + position``; its right cut is expressed through the next sector's
left cut.

References
----------
Thomas, D. L. (1979). Dynamics of rotationally periodic structures. Int. J. Numer. Meth.
Eng. 14, 81–102. Paper 003: modal analysis of the 30-blade wheel by nodal diameter.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.structure.eigen import _dof_array, eigenpairs
from fricdamp.structure.system import MechanicalSystem

_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix by ``angle`` [rad] about the unit vector ``axis`` (Rodrigues)."""
    k = axis
    Kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * Kx + (1.0 - np.cos(angle)) * (Kx @ Kx)


@dataclass(frozen=True, repr=False)
class CyclicSector:
    """One sector of a cyclically symmetric structure.

    Parameters
    ----------
    M, K : array_like or sparse, shape (n, n)
        Sector mass [kg] and stiffness [N/m] matrices (symmetric; M positive definite).
    left, right : sequence of int, shape (n_b,)
        DOF indices of the left and right cuts; ``right[k]`` is the DOF that coincides with
        ``left[k]`` of the next sector. Disjoint, no repeats.
    n_sectors : int
        Number of sectors N >= 2 in the full wheel.
    D : array_like or sparse, shape (n, n), optional
        Sector viscous damping [N s/m] (used by :func:`assemble_full`).
    frame : {"cylindrical", "cartesian"}
        Frame of the DOFs. ``cylindrical``: the components of the left and right DOFs
        correspond 1:1. ``cartesian``: consecutive triples of ``left`` (and ``right``) are
        the x, y, z components of one vector (displacement or rotation) of a node, and the
        right triple equals ``R`` times the next sector's left triple.
    axis : {"x", "y", "z"} or array_like (3,)
        Wheel axis (Cartesian frames only; default ``"z"``). Sector ``j+1`` lies at
        ``+alpha`` about this axis from sector ``j`` (right-hand rule).
    named_dofs : mapping of str to sequence of int, optional
        Named DOF groups (contact nodes, probes), e.g. ``{"tieboss_left": [12, 13, 14]}``.
    dof_names : sequence of str, optional
        Labels of the sector DOFs.
    name : str
        Label.
    """

    M: object
    K: object
    left: np.ndarray
    right: np.ndarray
    n_sectors: int
    D: object = None
    frame: str = "cylindrical"
    axis: object = "z"
    named_dofs: Mapping[str, np.ndarray] = field(default_factory=dict)
    dof_names: tuple[str, ...] | None = None
    name: str = "sector"

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    def __post_init__(self):
        base = MechanicalSystem(M=self.M, K=self.K, D=self.D, dof_names=self.dof_names)
        K = base.K
        scale = float(abs(K).max()) if K.shape[0] else 0.0
        if scale > 0 and float(abs(K - K.T).max()) > 1e-8 * scale:
            raise ModelError("sector stiffness K must be symmetric (|K - K^T| <= 1e-8 |K|)")
        n = base.n_dof
        object.__setattr__(self, "M", base.M)
        object.__setattr__(self, "K", base.K)
        object.__setattr__(self, "D", base.D)
        object.__setattr__(self, "dof_names", base.dof_names)
        left = _dof_array("left", self.left, n)
        right = _dof_array("right", self.right, n)
        if left.size == 0 or left.size != right.size:
            raise ModelError(f"left and right must list the same number (>= 1) of DOFs, got "
                             f"{left.size} and {right.size}")
        if np.intersect1d(left, right).size:
            raise ModelError("left and right interface DOFs must be disjoint, shared: "
                             f"{np.intersect1d(left, right).tolist()}")
        object.__setattr__(self, "left", left)
        object.__setattr__(self, "right", right)
        if int(self.n_sectors) != self.n_sectors or self.n_sectors < 2:
            raise ModelError(f"n_sectors must be an integer >= 2, got {self.n_sectors!r}")
        object.__setattr__(self, "n_sectors", int(self.n_sectors))
        if self.frame not in ("cylindrical", "cartesian"):
            raise ModelError(f"frame must be 'cylindrical' or 'cartesian', got {self.frame!r}")
        if self.frame == "cartesian" and left.size % 3:
            raise ModelError("with frame='cartesian' the interface DOFs must come in (x, y, z) "
                             f"triples, got {left.size} DOFs per cut")
        if isinstance(self.axis, str):
            if self.axis not in _AXES:
                raise ModelError(f"axis must be 'x', 'y', 'z' or a 3-vector, got {self.axis!r}")
        else:
            a = np.asarray(self.axis, float).reshape(-1)
            if a.size != 3 or not np.all(np.isfinite(a)) or np.linalg.norm(a) == 0:
                raise ModelError(f"axis must be a finite non-zero 3-vector, got {self.axis!r}")
            object.__setattr__(self, "axis", tuple(a / np.linalg.norm(a)))
        named = {}
        for key, dofs in dict(self.named_dofs or {}).items():
            named[str(key)] = _dof_array(f"named_dofs[{key!r}]", np.atleast_1d(dofs), n)
        object.__setattr__(self, "named_dofs", named)
        mask = np.ones(n, dtype=bool)
        mask[right] = False
        independent = np.flatnonzero(mask)
        object.__setattr__(self, "_independent", independent)
        pos = np.full(n, -1, dtype=np.int64)
        pos[independent] = np.arange(independent.size)
        object.__setattr__(self, "_position", pos)

    # ----------------------------------------------------------------- geometry
    @property
    def n_dof(self) -> int:
        """Number of sector DOFs (including both cuts)."""
        return self.M.shape[0]

    @property
    def n_interface(self) -> int:
        """Number of DOFs on one cut."""
        return self.left.size

    @property
    def independent(self) -> np.ndarray:
        """Sector DOFs that are not on the right cut, in sector order."""
        return self._independent

    @property
    def interior(self) -> np.ndarray:
        """Sector DOFs on neither cut."""
        mask = np.ones(self.n_dof, dtype=bool)
        mask[self.left] = False
        mask[self.right] = False
        return np.flatnonzero(mask)

    @property
    def n_independent(self) -> int:
        return self._independent.size

    @property
    def n_full(self) -> int:
        """Number of DOFs of the assembled wheel, ``N * n_independent``."""
        return self.n_sectors * self.n_independent

    @property
    def sector_angle(self) -> float:
        """Sector angle ``2 pi / N`` [rad]."""
        return 2.0 * np.pi / self.n_sectors

    @property
    def nodal_diameters(self) -> np.ndarray:
        """The distinct harmonic indices ``0 .. floor(N/2)``."""
        return np.arange(self.n_sectors // 2 + 1)

    def rotation_matrix(self) -> np.ndarray:
        """3 x 3 rotation by the sector angle about the axis (identity if cylindrical)."""
        if self.frame == "cylindrical":
            return np.eye(3)
        axis = np.asarray(_AXES[self.axis] if isinstance(self.axis, str) else self.axis)
        return _rotation(axis, self.sector_angle)

    def interface_rotation(self) -> sp.csr_matrix:
        """``R`` acting on the cut DOFs, shape (n_b, n_b): ``u_R^(j) = R u_L^(j+1)``."""
        nb = self.n_interface
        if self.frame == "cylindrical":
            return sp.identity(nb, format="csr")
        return sp.block_diag([self.rotation_matrix()] * (nb // 3), format="csr")

    # ----------------------------------------------------------------- transformations
    def _transform(self, factor: complex, next_offset: int, n_cols: int,
                   self_offset: int) -> sp.csr_matrix:
        n = self.n_dof
        ind = self._independent
        R = sp.coo_matrix(self.interface_rotation())
        rows = np.concatenate([ind, self.right[R.row]])
        cols = np.concatenate([self_offset + np.arange(ind.size),
                               next_offset + self._position[self.left[R.col]]])
        vals = np.concatenate([np.ones(ind.size), factor * R.data])
        dtype = complex if np.iscomplexobj(vals) else float
        return sp.csr_matrix((vals.astype(dtype), (rows, cols)), shape=(n, n_cols))

    def transform(self, j: int) -> sp.csr_matrix:
        """Sparse ``T_j``, shape (n, n_full): DOFs of sector ``j`` are ``T_j @ q_full``."""
        N = self.n_sectors
        if int(j) != j or not 0 <= j < N:
            raise ModelError(f"sector index j must be an integer in [0, {N - 1}], got {j!r}")
        m = self.n_independent
        return self._transform(1.0, ((int(j) + 1) % N) * m, self.n_full, int(j) * m)

    def cyclic_transform(self, nd: int) -> sp.csr_matrix:
        """``T_nd``, shape (n, n_independent): sector DOFs of harmonic ``nd`` from the
        independent ones, ``u_R = exp(2 pi i nd / N) R u_L`` (real for nd = 0, N/2)."""
        nd = self._check_nd(nd)
        phase = np.exp(2j * np.pi * nd / self.n_sectors)
        if 2 * nd % self.n_sectors == 0:
            phase = float(np.round(phase.real))
        return self._transform(phase, 0, self.n_independent, 0)

    def full_dofs(self, dofs, j: int = 0) -> np.ndarray:
        """Full-wheel indices of sector ``j``'s DOFs ``dofs``.

        Independent DOFs map to their own full index; right-cut DOFs map to the next
        sector's left-cut DOFs (cylindrical frames only: with Cartesian frames a right-cut
        DOF is a combination of several full DOFs — use :meth:`transform`).
        """
        T = self.transform(j)
        d = _dof_array("dofs", np.atleast_1d(dofs), self.n_dof)
        sub = T[d]
        if np.any(np.diff(sub.indptr) != 1) or not np.allclose(sub.data, 1.0):
            raise ModelError("some DOFs are right-cut DOFs in Cartesian frames, which are not "
                             "single full DOFs; use transform(j) instead")
        return sub.indices.astype(np.int64)

    def contact_projection(self, projection) -> sp.csr_matrix:
        """Full-wheel projection of a contact repeated in every sector.

        Parameters
        ----------
        projection : array_like or sparse, shape (m, 2 n)
            Rows of local relative displacements of one sector's contacts: the first ``n``
            columns act on the sector's own DOFs, the last ``n`` on the next sector's DOFs,
            each in its own sector frame (for Cartesian frames express the next sector's
            vectors in this sector's frame with :meth:`rotation_matrix`).

        Returns
        -------
        scipy.sparse.csr_matrix, shape (N m, n_full)
            Row block ``j`` is sector ``j``'s contacts; use with a law of ``N * n_contacts``
            contacts (sector-major order).
        """
        P = sp.csr_matrix(projection, dtype=float) if sp.issparse(projection) else \
            sp.csr_matrix(np.atleast_2d(np.asarray(projection, float)))
        n = self.n_dof
        if P.shape[1] != 2 * n:
            raise ModelError(f"projection must have 2 n = {2 * n} columns (this sector, next "
                             f"sector), got shape {P.shape}")
        Pa, Pb = P[:, :n], P[:, n:]
        N = self.n_sectors
        blocks = [Pa @ self.transform(j) + Pb @ self.transform((j + 1) % N) for j in range(N)]
        return sp.vstack(blocks, format="csr")

    def _check_nd(self, nd) -> int:
        N = self.n_sectors
        if int(nd) != nd or not 0 <= nd < N:
            raise ModelError(f"nd (nodal diameter) must be an integer in [0, {N - 1}], "
                             f"got {nd!r}")
        return int(nd)


# --------------------------------------------------------------------------- assembly
def _stack_transform(sector: CyclicSector) -> sp.csr_matrix:
    return sp.vstack([sector.transform(j) for j in range(sector.n_sectors)], format="csr")


def assemble_full(sector: CyclicSector, **kwargs) -> MechanicalSystem:
    """Assemble the full wheel (sparse) from ``N`` copies of ``sector``.

    Parameters
    ----------
    sector : CyclicSector
        The sector; the right cut of sector ``j`` is tied to the left cut of ``j + 1``.
    **kwargs
        Passed to :class:`MechanicalSystem` (contacts, loads, static_load, name, ...).
        Build contacts with :meth:`CyclicSector.contact_projection` or
        :meth:`CyclicSector.full_dofs`.

    Returns
    -------
    MechanicalSystem
        ``N * n_independent`` DOFs (sparse CSR matrices), sector-major numbering (see the
        module docstring); ``meta["cyclic"]`` records ``n_sectors`` and ``n_independent``.

    Examples
    --------
    >>> import numpy as np
    >>> s = CyclicSector(M=np.eye(2), K=np.array([[1.0, -1.0], [-1.0, 1.0]]), left=[0],
    ...                  right=[1], n_sectors=3)
    >>> assemble_full(s).K.toarray().tolist()
    [[2.0, -1.0, -1.0], [-1.0, 2.0, -1.0], [-1.0, -1.0, 2.0]]
    """
    if not isinstance(sector, CyclicSector):
        raise ModelError(f"sector must be a CyclicSector, got {type(sector).__name__}")
    N = sector.n_sectors
    T = _stack_transform(sector)

    def big(A):
        A = sp.csr_matrix(A)
        return sp.csr_matrix(T.T @ sp.block_diag([A] * N, format="csr") @ T)

    names = sector.dof_names or tuple(f"q{k + 1}" for k in range(sector.n_dof))
    dof_names = tuple(f"s{j}.{names[d]}" for j in range(N) for d in sector.independent)
    kwargs.setdefault("name", f"{sector.name} x {N}")
    kwargs.setdefault("dof_names", dof_names)
    meta = dict(kwargs.pop("meta", {}))
    meta["cyclic"] = {"n_sectors": N, "n_independent": sector.n_independent}
    return MechanicalSystem(M=big(sector.M), K=big(sector.K), D=big(sector.D), meta=meta,
                            **kwargs)


# --------------------------------------------------------------------------- modes by ND
@dataclass(frozen=True, repr=False)
class CyclicModes:
    """Modes of one harmonic index (nodal diameter) of a cyclic structure.

    Attributes
    ----------
    nd : int
        Harmonic index (nodal diameter).
    n_sectors : int
        Number of sectors N.
    frequencies : ndarray, shape (n_modes,)
        Eigenfrequencies [Hz], ascending.
    shapes : ndarray, shape (n_sector_dofs, n_modes)
        Complex sector shapes ``u~`` (real for nd = 0 and N/2) satisfying
        ``u_R = exp(2 pi i nd / N) R u_L``, normalised so that ``u~^H M u~ = 1`` [1/sqrt(kg)]
        over the independent sector DOFs (``T_nd^H M T_nd``).
    multiplicity : int
        1 for nd = 0 and N/2, else 2 (each frequency is a double mode of the wheel).
    """

    nd: int
    n_sectors: int
    frequencies: np.ndarray
    shapes: np.ndarray

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    @property
    def multiplicity(self) -> int:
        return 1 if (2 * self.nd) % self.n_sectors == 0 else 2

    @property
    def omega(self) -> np.ndarray:
        """Angular eigenfrequencies [rad/s]."""
        return 2 * np.pi * self.frequencies

    def full_shapes(self, sector: CyclicSector) -> np.ndarray:
        """Travelling-wave shapes of the assembled wheel, shape (n_full, n_modes).

        Sector ``j``'s independent DOFs are ``exp(i j phi) u~``. Their real and imaginary
        parts are the two standing-wave modes of the double frequency (``0 < nd < N/2``).
        """
        N = self.n_sectors
        ind = sector.independent
        phase = np.exp(2j * np.pi * self.nd * np.arange(N) / N)
        out = phase[:, None, None] * self.shapes[ind][None, :, :]
        return out.reshape(N * ind.size, -1)


def nodal_diameter_modes(sector: CyclicSector, nd: int, n_modes: int, *, sigma: float = 0.0,
                         method: str = "auto") -> CyclicModes:
    """Modes of harmonic index ``nd`` from one sector with the complex cyclic constraint.

    Parameters
    ----------
    sector : CyclicSector
        The sector.
    nd : int
        Nodal diameter / harmonic index, ``0 <= nd < N`` (``nd`` and ``N - nd`` coincide).
    n_modes : int
        Number of modes, ``1 <= n_modes <= n_independent``.
    sigma : float
        Frequency [Hz] around which modes are sought (0: the lowest).
    method : {"auto", "dense", "sparse"}
        Eigen-solver (see :func:`fricdamp.structure.reduction.eigenpairs`).

    Returns
    -------
    CyclicModes

    Notes
    -----
    Damping is ignored (undamped normal modes of the Hermitian pencil).
    """
    if not isinstance(sector, CyclicSector):
        raise ModelError(f"sector must be a CyclicSector, got {type(sector).__name__}")
    nd = sector._check_nd(nd)
    if not np.isfinite(sigma) or sigma < 0:
        raise ModelError(f"sigma must be a frequency >= 0 Hz, got {sigma!r}")
    T = sector.cyclic_transform(nd)
    TH = T.conj().T

    def red(A):
        R = TH @ (sp.csr_matrix(A) @ T)
        return sp.csr_matrix(R)

    lam, X = eigenpairs(red(sector.K), red(sector.M), n_modes,
                        shift=(2 * np.pi * sigma) ** 2, method=method)
    f = np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)
    shapes = np.asarray(T @ X)
    if not np.iscomplexobj(T):
        shapes = shapes.real
    return CyclicModes(nd=nd, n_sectors=sector.n_sectors, frequencies=f, shapes=shapes)


def all_nd_frequencies(sector: CyclicSector, n_modes: int, *, sigma: float = 0.0,
                       method: str = "auto") -> np.ndarray:
    """Lowest ``n_modes`` frequencies [Hz] of every nodal diameter.

    Returns
    -------
    ndarray, shape (floor(N/2) + 1, n_modes)
        Row ``nd`` holds the frequencies of nodal diameter ``nd`` (ascending); for
        ``0 < nd < N/2`` each is a double frequency of the wheel.
    """
    return np.array([nodal_diameter_modes(sector, nd, n_modes, sigma=sigma,
                                          method=method).frequencies
                     for nd in sector.nodal_diameters])


def full_spectrum(frequencies_by_nd: np.ndarray, n_sectors: int) -> np.ndarray:
    """Wheel frequencies [Hz] from :func:`all_nd_frequencies`, each with its multiplicity.

    Parameters
    ----------
    frequencies_by_nd : ndarray, shape (floor(N/2) + 1, n_modes)
    n_sectors : int

    Returns
    -------
    ndarray, sorted ascending; double modes appear twice.
    """
    F = np.asarray(frequencies_by_nd, float)
    if F.ndim != 2 or F.shape[0] != n_sectors // 2 + 1:
        raise ModelError(f"frequencies_by_nd must have shape ({n_sectors // 2 + 1}, n_modes), "
                         f"got {F.shape}")
    parts = [np.repeat(F[nd], 1 if (2 * nd) % n_sectors == 0 else 2) for nd in range(F.shape[0])]
    return np.sort(np.concatenate(parts))


__all__ = [
    "CyclicModes",
    "CyclicSector",
    "all_nd_frequencies",
    "assemble_full",
    "full_spectrum",
    "nodal_diameter_modes",
]
