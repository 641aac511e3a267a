"""Rotation terms of a solid FE model spinning about a fixed axis: centrifugal load, spin
softening and stress stiffening (the matrices a Campbell diagram needs).

In the frame rotating at ``Omega`` about the unit axis ``e`` through the origin, a mass
particle at ``x`` feels the centrifugal force ``rho Omega^2 P x`` with ``P = I - e e^T``
(projection on the plane of rotation). With the FE interpolation ``x + u``:

* centrifugal load per ``Omega^2``: ``f_c = M_P x`` [N s^2], ``M_P = B M B`` with ``B`` the
  block-diagonal ``P`` per node (exact for the consistent mass of an isoparametric element:
  ``rho P (x + u)`` is interpolated by the same shape functions);
* spin softening per ``Omega^2``: ``M_P`` (the displacement-dependent part of the same force,
  which moves to the left-hand side with a minus sign);
* stress stiffening per ``Omega^2``: the geometric stiffness ``K_sigma(u_1)`` of the prestress
  of ``K u_1 = f_c`` (linear prestress; :func:`geometric_stiffness`).

So ``K(Omega) = K + Omega^2 (K_sigma(u_1) - M_P)`` (first order in the prestress, the same
form as :class:`~fricdamp.structure.system.RotationTerms`); the Coriolis coupling is not
included. Validation: a solid cantilever blade gives Southwell's coefficient of the first
flap mode, ``omega^2 = omega_0^2 + 1.1933 Omega^2`` (hub radius 0), and of the first lead-lag
mode, ``1.1933 - 1`` (tests/validation/test_solid_rotation.py).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.structure import _solid_fe
from fricdamp.structure._solid_mesh import SolidMesh
from fricdamp.structure.contact_patch import _axis_vector

__all__ = ["centrifugal_load", "geometric_stiffness", "spin_softening"]


def _projector(solid, axis) -> sp.csr_matrix:
    e = _axis_vector(axis)
    P = np.eye(3) - np.outer(e, e)
    return sp.kron(sp.identity(solid.n_nodes, format="csr"), sp.csr_matrix(P), format="csr")


def spin_softening(solid, axis="z") -> sp.csr_matrix:
    """``M_P`` [kg]: the spin-softening matrix per ``Omega^2`` (enters as ``-Omega^2 M_P``).

    Parameters
    ----------
    solid : SolidModel
    axis : {"x", "y", "z"} or array_like (3,)
        Spin axis through the origin.
    """
    B = _projector(solid, axis)
    return (B @ solid.M @ B).tocsr()


def centrifugal_load(solid, axis="z") -> np.ndarray:
    """Centrifugal load per ``Omega^2`` [N s^2] on every DOF: ``M_P x``."""
    return np.asarray(spin_softening(solid, axis) @ np.asarray(solid.points).ravel())


def geometric_stiffness(solid, u) -> sp.csr_matrix:
    """Geometric stiffness [N/m] of the small-strain stress of the displacement ``u``.

    Parameters
    ----------
    solid : SolidModel
        Assembled by :func:`~fricdamp.structure.solid.assemble_solid` (it keeps the Lamé
        constants of each element).
    u : array_like, shape (n_dof,)
        Displacement [m] in the model's DOF order (e.g. the static response to
        :func:`centrifugal_load` per ``Omega^2``: then the result is per ``Omega^2``).

    Returns
    -------
    scipy.sparse.csr_matrix, shape (n_dof, n_dof)
        Symmetric; positive semi-definite for a tensile prestress.
    """
    lame = getattr(solid, "lame", None)
    if lame is None:
        raise ModelError("geometric_stiffness needs a SolidModel from assemble_solid (it "
                         "keeps each element's Lamé constants)")
    u = np.asarray(u, dtype=float).reshape(-1)
    if u.shape != (solid.n_dof,) or not np.all(np.isfinite(u)):
        raise ModelError(f"u must be a finite vector of the model's {solid.n_dof} DOFs")
    mesh = SolidMesh(points=np.asarray(solid.points), cell_type=solid.cell_type,
                     cells=np.asarray(solid.elements))
    disc = _solid_fe.discretise(mesh, solid.element_type)
    if disc.nodes.shape != np.shape(solid.points) or not np.array_equal(
            disc.point_node, np.arange(solid.n_nodes)):
        raise ModelError("internal: the model's nodes are not all used by its elements")
    basis = _solid_fe.scalar_basis(disc)
    return _solid_fe.assemble_geometric(basis, disc.sk2node, lame[:, 0], lame[:, 1],
                                        u.reshape(-1, 3), solid.n_nodes)
