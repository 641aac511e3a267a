"""Mistuned wheels: per-blade scatter assembled into the full wheel, without cyclic symmetry.

A tuned wheel's modes come in doublets (the cos and sin standing waves of each nodal
diameter 0 < ND < N/2 share one frequency). Real wheels are slightly mistuned -- blade to
blade scatter of Young's modulus, of a bolted tip mass -- and the doublets split: paper 003's
Table 1 lists each ND as a pair of close frequencies. :func:`mistuned_wheel` assembles the
wheel of (typically reduced) sectors with a stiffness factor per sector and extra point
masses, sparse, and :func:`mistuned_modes` solves it by shift-invert Lanczos and labels each
mode with its dominant ND (the discrete Fourier transform of the probe over the blades).

First-order perturbation theory (derived here): let the sector stiffness be ``(1 + d_j) K``
and ``x`` the sector shape of a tuned doublet of ND k (``x^H K x = lambda``, travelling wave
``x exp(i k j alpha)``), ``kappa = x^T K x`` (``|kappa| <= lambda``, equal when ``x`` is real
up to a phase, as for blade-dominated modes). In the doublet's standing waves the
perturbation is ``lambda D_0 I + [[Re S, Im S], [Im S, -Re S]]`` with ``S = kappa conj(D_2k)``
and ``D_h = (1/N) sum_j d_j exp(-i h j alpha)``, so the doublet splits by
``Delta lambda = 2 |kappa| |D_2k|``, i.e. ``Delta f / f = |D_2k| |kappa| / lambda``: only the
harmonic 2k of the scatter (and its alias N - 2k) splits ND k.
``tests/validation/test_mistuning.py`` checks it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.structure.cyclic import CyclicSector

__all__ = ["MistunedModes", "mistuned_modes", "mistuned_wheel"]


def _global_index(sector: CyclicSector, j: int) -> np.ndarray:
    """Wheel DOF of every sector DOF of sector j (right cut -> next sector's left cut)."""
    N, n_ind = sector.n_sectors, sector.n_independent
    idx = np.empty(sector.n_dof, dtype=np.int64)
    indep = sector.independent
    idx[indep] = j * n_ind + np.arange(n_ind)
    pos = np.full(sector.n_dof, -1, dtype=np.int64)
    pos[indep] = np.arange(n_ind)
    idx[sector.right] = ((j + 1) % N) * n_ind + pos[sector.left]
    return idx


def mistuned_wheel(sector: CyclicSector, *, stiffness_factors=None, added_mass=None,
                   mass_dofs=None) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Wheel stiffness and mass with per-sector scatter (sparse, ``N n_independent`` DOFs).

    Parameters
    ----------
    sector : CyclicSector
        The (reduced) sector; its cut DOFs must correspond 1:1 (``frame="cylindrical"``, as a
        reduced sector of :func:`~fricdamp.structure.cyclic_reduction.reduce_sector`).
    stiffness_factors : array_like, shape (N,), optional
        ``1 + d_j``: sector j's stiffness is ``(1 + d_j) K`` (Young's modulus scatter), > 0.
    added_mass : array_like, shape (N,), optional
        Mass [kg] added on ``mass_dofs`` of sector j (e.g. a tip-mass scatter), >= -the mass
        that keeps M positive definite.
    mass_dofs : sequence of int, optional
        Sector DOFs that carry ``added_mass`` (the x, y, z translations of one node).

    Returns
    -------
    K, M : scipy.sparse.csr_matrix
        In the numbering of :func:`~fricdamp.structure.cyclic.assemble_full`.
    """
    if not isinstance(sector, CyclicSector):
        raise ModelError(f"sector must be a CyclicSector, got {type(sector).__name__}")
    if sector.frame != "cylindrical":
        raise ModelError("mistuned_wheel needs a sector whose cut DOFs correspond 1:1 "
                         "(frame='cylindrical', e.g. a reduced sector)")
    N = sector.n_sectors
    fac = np.ones(N) if stiffness_factors is None else np.asarray(stiffness_factors, float)
    if fac.shape != (N,) or not np.all(np.isfinite(fac)) or fac.min() <= 0:
        raise ModelError(f"stiffness_factors must be {N} finite factors > 0")
    dm = np.zeros(N) if added_mass is None else np.asarray(added_mass, float)
    if dm.shape != (N,) or not np.all(np.isfinite(dm)):
        raise ModelError(f"added_mass must be {N} finite masses [kg]")
    if np.any(dm != 0) and mass_dofs is None:
        raise ModelError("added_mass needs mass_dofs (the sector DOFs that carry it)")
    Ks, Ms = sp.coo_matrix(sector.K), sp.coo_matrix(sector.M)
    rows_k, cols_k, vals_k, rows_m, cols_m, vals_m = [], [], [], [], [], []
    md = np.zeros(0, dtype=np.int64) if mass_dofs is None else np.asarray(mass_dofs, np.int64)
    for j in range(N):
        g = _global_index(sector, j)
        rows_k.append(g[Ks.row])
        cols_k.append(g[Ks.col])
        vals_k.append(fac[j] * Ks.data)
        rows_m.append(g[Ms.row])
        cols_m.append(g[Ms.col])
        vals_m.append(Ms.data)
        if dm[j] != 0:
            rows_m.append(g[md])
            cols_m.append(g[md])
            vals_m.append(np.full(md.size, dm[j]))
    n = N * sector.n_independent
    K = sp.csr_matrix((np.concatenate(vals_k), (np.concatenate(rows_k),
                                                np.concatenate(cols_k))), shape=(n, n))
    M = sp.csr_matrix((np.concatenate(vals_m), (np.concatenate(rows_m),
                                                np.concatenate(cols_m))), shape=(n, n))
    return K, M


@dataclass(frozen=True, repr=False)
class MistunedModes:
    """Lowest modes of a mistuned wheel.

    Attributes
    ----------
    frequency_hz : ndarray, shape (n_modes,)
        Eigenfrequencies [Hz], ascending.
    nd : ndarray of int, shape (n_modes,)
        Dominant nodal diameter of each mode (largest DFT harmonic of the probe over blades).
    localisation : ndarray, shape (n_modes,)
        Largest blade amplitude over the RMS blade amplitude (sqrt(2) for a tuned standing
        wave, up to sqrt(N) for a mode on one blade).
    probe : ndarray, shape (N, n_modes)
        Probe displacement of every blade along the probe direction.
    """

    frequency_hz: np.ndarray
    nd: np.ndarray
    localisation: np.ndarray
    probe: np.ndarray

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    def doublet_split_hz(self, nd: int) -> float:
        """Frequency difference [Hz] of the two lowest modes of ``nd`` (the split doublet)."""
        f = self.frequency_hz[self.nd == nd]
        if f.size < 2:
            raise ModelError(f"fewer than two modes of {nd}ND were computed")
        return float(f[1] - f[0])


def mistuned_modes(sector: CyclicSector, n_modes: int, *, probe_dofs, probe_direction=None,
                   stiffness_factors=None, added_mass=None, mass_dofs=None,
                   shift_hz: float = 0.0) -> MistunedModes:
    """The ``n_modes`` modes of the mistuned wheel nearest ``shift_hz``.

    ``probe_dofs``: sector DOFs of the probe (3 translations, or one DOF); with
    ``probe_direction`` the probe signal is their component along it. Other parameters as
    :func:`mistuned_wheel`.
    """
    from fricdamp.structure.reduction import eigenpairs

    K, M = mistuned_wheel(sector, stiffness_factors=stiffness_factors, added_mass=added_mass,
                          mass_dofs=mass_dofs)
    lam, X = eigenpairs(K, M, int(n_modes), shift=(2 * np.pi * shift_hz) ** 2,
                        method="sparse")
    N = sector.n_sectors
    pd = np.atleast_1d(np.asarray(probe_dofs, np.int64))
    d = np.ones(pd.size) if probe_direction is None else np.asarray(probe_direction, float)
    probe = np.stack([d @ X[_global_index(sector, j)[pd]] for j in range(N)])   # (N, n)
    spec = np.abs(np.fft.rfft(probe, axis=0))
    nd = np.argmax(spec, axis=0)
    rms = np.sqrt(np.mean(probe ** 2, axis=0))
    loc = np.abs(probe).max(axis=0) / np.where(rms > 0, rms, 1.0)
    return MistunedModes(frequency_hz=np.sqrt(np.maximum(lam, 0)) / (2 * np.pi), nd=nd,
                         localisation=loc, probe=probe)
