"""Craig–Bampton reduction and the symmetric eigen-solver shared by the structure layer.

Craig–Bampton (Craig & Bampton 1968) keeps a set of *boundary* DOFs ``b`` physically and
represents the *interior* DOFs ``i`` by static constraint modes plus ``n_modes``
fixed-interface normal modes::

    q = T [u_b; eta],   T = [[I, 0], [Psi, Phi]]   (rows in b, i order)
    Psi = -K_ii^{-1} K_ib,   (K_ii - w_k^2 M_ii) phi_k = 0,   phi_k^T M_ii phi_k = 1

The reduced matrices are the Galerkin projections ``T^T M T``, ``T^T K T``, ``T^T D T``
(rotation terms too). ``K_r`` is block diagonal (the constraint modes are K-orthogonal to
the fixed-interface modes), ``M_r[eta, eta] = I`` and ``K_r[eta, eta] = diag(w_k^2)``.
Because the basis is a Rayleigh–Ritz subspace, every reduced eigenfrequency lies above
the corresponding full one and decreases monotonically as fixed-interface modes are
added (Cauchy interlacing); with ``n_modes = 0`` the method is Guyan's static
condensation, exact for static loads on the boundary DOFs.

Contact elements whose projections touch only boundary DOFs reduce to contact elements
with the same law acting through ``P T`` (the interior columns vanish), so the friction
nonlinearity stays exact and a time integrator runs on the small model; by default the
DOFs touched by contacts are added to the boundary for that reason.

:func:`craig_bampton_sector` reduces a :class:`~fricdamp.structure.cyclic.CyclicSector`
keeping its left/right interface DOFs and its named (contact) DOFs, so the reduced sector
assembles into a reduced wheel with :func:`~fricdamp.structure.cyclic.assemble_full`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.structure.eigen import (  # noqa: F401 (moved there, kept here)
    DENSE_MAX,
    _dense,
    _dof_array,
    _eigenpairs,
    _factor,
    _hermitian_part,
    _sparse_if_worth,
    eigenpairs,
)
from fricdamp.structure.system import (
    ContactElement,
    HarmonicLoad,
    MechanicalSystem,
    RotationTerms,
    TimeLoad,
)

if TYPE_CHECKING:
    from fricdamp.structure.cyclic import CyclicSector

def _contact_dofs(system: MechanicalSystem) -> np.ndarray:
    cols = []
    for c in system.contacts:
        P = c.projection
        if sp.issparse(P):
            cols.append(np.unique(sp.csr_matrix(P).indices))
        else:
            cols.append(np.flatnonzero(np.any(np.asarray(P) != 0, axis=0)))
    return np.unique(np.concatenate(cols)) if cols else np.zeros(0, dtype=np.int64)


def _project(A, T: np.ndarray) -> np.ndarray:
    """``T^T A T`` for dense T and dense or sparse A."""
    return T.T @ np.asarray(A @ T)


@dataclass(frozen=True, repr=False)
class ReducedSystem:
    """A Craig–Bampton reduced system and the way back to the full DOFs.

    Attributes
    ----------
    system : MechanicalSystem
        Reduced system with ``n_boundary + n_modes`` coordinates: the boundary DOFs (in
        :attr:`boundary_dofs` order, same units) followed by the fixed-interface modal
        coordinates (mass-normalised, [sqrt(kg) m]). Contacts, loads and rotation terms
        are projected.
    transformation : ndarray, shape (n_full, n_reduced)
        ``q_full = transformation @ q_reduced``.
    boundary_dofs : ndarray of int, shape (n_boundary,)
        Full-model indices of the retained DOFs.
    fixed_interface_frequencies : ndarray, shape (n_modes,)
        Eigenfrequencies [Hz] of the kept fixed-interface modes.
    """

    system: MechanicalSystem
    transformation: np.ndarray
    boundary_dofs: np.ndarray
    fixed_interface_frequencies: np.ndarray

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    @property
    def n_modes(self) -> int:
        return self.fixed_interface_frequencies.size

    @property
    def n_boundary(self) -> int:
        return self.boundary_dofs.size

    @property
    def n_full(self) -> int:
        return self.transformation.shape[0]

    def expand(self, q_reduced) -> np.ndarray:
        """Full DOFs from reduced coordinates.

        ``q_reduced`` has shape (n_reduced,) or (n_t, n_reduced) (a time history, as in
        ``TimeResult.q``); the result has shape (n_full,) or (n_t, n_full).
        """
        q = np.asarray(q_reduced)
        if q.shape[-1] != self.transformation.shape[1]:
            raise ModelError(f"q_reduced must have {self.transformation.shape[1]} entries in "
                             f"its last axis, got shape {q.shape}")
        return q @ self.transformation.T

    def reduce_vector(self, f) -> np.ndarray:
        """Reduced load ``T^T f`` of a full load vector ``f`` (n_full,) [N]."""
        f = np.asarray(f)
        if f.shape[-1] != self.n_full:
            raise ModelError(f"f must have {self.n_full} entries, got shape {f.shape}")
        return f @ self.transformation

    def reduced_index(self, full_dofs) -> np.ndarray:
        """Positions in the reduced coordinates of retained full DOFs."""
        dofs = np.atleast_1d(np.asarray(full_dofs, dtype=np.int64))
        pos = np.full(self.n_full, -1, dtype=np.int64)
        pos[self.boundary_dofs] = np.arange(self.n_boundary)
        if np.any((dofs < 0) | (dofs >= self.n_full)):
            raise ModelError(f"full_dofs must lie in [0, {self.n_full - 1}]")
        out = pos[dofs]
        if np.any(out < 0):
            raise ModelError(f"DOFs {dofs[out < 0].tolist()} are not retained (boundary) DOFs "
                             "of the reduced system")
        return out


def craig_bampton(system: MechanicalSystem, boundary_dofs: Sequence[int], n_modes: int, *,
                  keep_contact_dofs: bool = True, method: str = "auto") -> ReducedSystem:
    """Craig–Bampton reduction of ``system`` onto ``boundary_dofs`` plus ``n_modes`` modes.

    Parameters
    ----------
    system : MechanicalSystem
        Full system (dense or sparse). Its rotation terms, loads, static load and contacts
        are projected with the same transformation.
    boundary_dofs : sequence of int
        DOFs kept physically (interfaces, excitation points, contact DOFs).
    n_modes : int
        Number of fixed-interface modes kept, ``0 <= n_modes <= n_interior`` (0: Guyan).
    keep_contact_dofs : bool
        Add every DOF touched by a contact projection to the boundary (default; appended
        after ``boundary_dofs`` in ascending order, see ``boundary_dofs`` of the result), so the
        contact forces act on physical DOFs and the reduction leaves them exact. With
        ``False`` a contact on interior DOFs acts through the (approximate) projected
        kinematics ``P T``.
    method : {"auto", "dense", "sparse"}
        Eigen-solver for the fixed-interface modes (see :func:`eigenpairs`).

    Returns
    -------
    ReducedSystem

    Raises
    ------
    ModelError
        For bad DOF indices, ``n_modes`` out of range, or a singular interior stiffness
        ``K_ii`` (an interior part that is not held by the boundary).

    Examples
    --------
    >>> from fricdamp.structure import chain
    >>> red = craig_bampton(chain([1.0] * 4, [1.0] * 4), [3], n_modes=3)
    >>> red.system.n_dof
    4
    """
    if not isinstance(system, MechanicalSystem):
        raise ModelError(f"system must be a MechanicalSystem, got {type(system).__name__}")
    n = system.n_dof
    b = _dof_array("boundary_dofs", boundary_dofs, n)
    if keep_contact_dofs:
        extra = np.setdiff1d(_contact_dofs(system), b)
        b = np.concatenate([b, extra]).astype(np.int64)
    if b.size == 0:
        raise ModelError("boundary_dofs must hold at least one DOF (or give contacts)")
    mask = np.ones(n, dtype=bool)
    mask[b] = False
    i = np.flatnonzero(mask)
    n_i = i.size
    if int(n_modes) != n_modes or not 0 <= n_modes <= n_i:
        raise ModelError(f"n_modes must be an integer in [0, {n_i}] (interior DOFs), "
                         f"got {n_modes!r}")
    n_modes = int(n_modes)
    K, M = system.K, system.M
    sparse = sp.issparse(K)

    def block(A, r, c):
        if sp.issparse(A):
            A = sp.csr_matrix(A)
            return A[r][:, c]
        return np.asarray(A)[np.ix_(r, c)]

    T = np.zeros((n, b.size + n_modes))
    T[b, np.arange(b.size)] = 1.0
    freqs = np.zeros(0)
    if n_i:
        Kii, Kib, Mii = block(K, i, i), block(K, i, b), block(M, i, i)
        solve = _factor(Kii, sparse=sparse, definite=True)
        if solve is None:
            raise ModelError("the interior stiffness K_ii is singular: part of the structure "
                             "is not held by the boundary DOFs; add DOFs to boundary_dofs")
        T[np.ix_(i, np.arange(b.size))] = -solve(_dense(Kib).astype(float))
        if n_modes:
            lam, Phi = eigenpairs(Kii, Mii, n_modes, method=method)
            T[np.ix_(i, b.size + np.arange(n_modes))] = Phi
            freqs = np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)

    Mr = _hermitian_part(_project(M, T))
    Kr = _project(K, T)
    if float(abs(K - K.T).max()) == 0.0:
        Kr = _hermitian_part(Kr)
    Dr = _project(system.D, T)
    contacts = []
    for c in system.contacts:
        Pr = sp.csr_matrix(np.asarray(c.projection @ T))
        Pr.data[np.abs(Pr.data) <= 1e-14 * max(abs(Pr.data).max(initial=0.0), 1e-300)] = 0.0
        Pr.eliminate_zeros()
        contacts.append(ContactElement(law=c.law, projection=Pr, name=c.name))
    loads = []
    for ld in system.loads:
        if isinstance(ld, HarmonicLoad):
            loads.append(replace(ld, amplitude=ld.amplitude @ T))
        elif isinstance(ld, TimeLoad):
            loads.append(replace(ld, shape=ld.shape @ T))
        else:  # pragma: no cover - MechanicalSystem only admits the two kinds
            raise ModelError(f"cannot reduce load {ld!r}")
    rotation = None
    if system.rotation is not None:
        r = system.rotation
        rotation = RotationTerms(
            gyroscopic=None if r.gyroscopic is None else _project(r.gyroscopic, T),
            spin_softening=None if r.spin_softening is None else _project(r.spin_softening, T),
            stress_stiffening=(None if r.stress_stiffening is None
                               else _project(r.stress_stiffening, T)),
            centrifugal_load=(None if r.centrifugal_load is None
                              else np.asarray(r.centrifugal_load, float) @ T),
        )
    names = system.names
    dof_names = tuple(names[k] for k in b) + tuple(f"eta{k + 1}" for k in range(n_modes))
    reduced = MechanicalSystem(
        M=Mr, K=Kr, D=Dr, contacts=tuple(contacts), static_load=system.static_load @ T,
        loads=tuple(loads), rotation=rotation, dof_names=dof_names,
        name=f"{system.name} (Craig-Bampton, {b.size} boundary DOFs + {n_modes} modes)",
        meta={**system.meta, "craig_bampton": {"n_boundary": int(b.size),
                                               "n_modes": n_modes}},
    )
    return ReducedSystem(system=reduced, transformation=T, boundary_dofs=b,
                         fixed_interface_frequencies=freqs)


@dataclass(frozen=True, repr=False)
class ReducedSector:
    """A Craig–Bampton reduced cyclic sector.

    Attributes
    ----------
    sector : CyclicSector
        The reduced sector: its DOFs are the left interface, the right interface, the other
        kept DOFs (``keep_dofs`` and the named DOFs of the original sector), then the
        fixed-interface modal coordinates. ``named_dofs`` refer to the reduced indices.
        Assemble it with :func:`~fricdamp.structure.cyclic.assemble_full`.
    reduction : ReducedSystem
        The sector reduction (transformation from reduced to original sector DOFs).
    """

    sector: CyclicSector
    reduction: ReducedSystem

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    def reduced_index(self, sector_dofs) -> np.ndarray:
        """Reduced-sector indices of original sector DOFs that were kept."""
        return self.reduction.reduced_index(sector_dofs)

    def expand(self, q_reduced) -> np.ndarray:
        """Original sector DOFs from reduced sector coordinates, (..., n_sector_dofs)."""
        return self.reduction.expand(q_reduced)


def craig_bampton_sector(sector: CyclicSector, n_modes: int, *, keep_dofs: Sequence[int] = (),
                         method: str = "auto") -> ReducedSector:
    """Craig–Bampton reduction of a cyclic sector keeping interfaces and contact DOFs.

    Parameters
    ----------
    sector : CyclicSector
        The sector to reduce.
    n_modes : int
        Fixed-interface modes kept (the interface, named and ``keep_dofs`` DOFs fixed).
    keep_dofs : sequence of int
        Further sector DOFs to keep physically (excitation points, probes). The sector's
        ``named_dofs`` (contact nodes) are always kept.
    method : {"auto", "dense", "sparse"}
        Eigen-solver for the fixed-interface modes.

    Returns
    -------
    ReducedSector
        Its ``sector`` assembles into the reduced wheel; frequencies of that wheel converge
        from above to the full wheel's as ``n_modes`` grows.
    """
    from fricdamp.structure.cyclic import CyclicSector

    if not isinstance(sector, CyclicSector):
        raise ModelError(f"sector must be a CyclicSector, got {type(sector).__name__}")
    n = sector.n_dof
    keep = list(_dof_array("keep_dofs", keep_dofs, n))
    for dofs in sector.named_dofs.values():
        keep.extend(int(d) for d in dofs)
    interface = np.concatenate([sector.left, sector.right])
    others = [d for d in dict.fromkeys(keep) if d not in set(interface.tolist())]
    boundary = np.concatenate([interface, np.asarray(others, dtype=np.int64)]).astype(np.int64)
    system = MechanicalSystem(M=sector.M, K=sector.K, D=sector.D, dof_names=sector.dof_names,
                              name=sector.name)
    red = craig_bampton(system, boundary, n_modes, keep_contact_dofs=False, method=method)
    nb = sector.n_interface
    named = {k: red.reduced_index(v) for k, v in sector.named_dofs.items()}
    rs = red.system
    new = CyclicSector(M=rs.M, K=rs.K, D=rs.D, left=np.arange(nb), right=np.arange(nb, 2 * nb),
                       n_sectors=sector.n_sectors, frame=sector.frame, axis=sector.axis,
                       named_dofs=named, dof_names=rs.dof_names,
                       name=f"{sector.name} (Craig-Bampton, {n_modes} modes)")
    return ReducedSector(sector=new, reduction=red)
