"""Contact patches between neighbouring sectors: node pairs, frames, areas and penalties.

A tie-boss (or shroud) contact of a cyclic wheel joins the *right* contact face of sector
``j`` to the *left* contact face of sector ``j + 1``. Meshed conformally, the left face of
one sector rotated by the sector angle ``alpha`` about the wheel axis coincides node by node
with the right face of the same sector (so the right face of sector ``j`` meets the left face
of sector ``j + 1``). A :class:`ContactPatch` holds, per node pair:

* the right-face node and its partner on the left face (``R x_left[partner] = x_right``);
* the local frame, rows ``(n, t1, t2)`` in the sector's Cartesian components: ``n`` the
  outward unit normal of the right face (pointing from sector j into sector j + 1), ``t1``
  the radial direction projected on the tangent plane, ``t2 = n x t1``;
* its tributary area ``A`` [m^2] (positive nodal shares of the face area);

so that the relative displacement of pair p of contact j, in its frame, is::

    u_p = Lambda_p (u_right^(j)[p] - R u_left^(j+1)[partner(p)])        (u_n > 0 closes)

with each sector's displacements in its own Cartesian frame and ``R`` the rotation by
``alpha`` (derived from the frames of :mod:`fricdamp.structure.cyclic`: sector ``j + 1``'s
components rotated by ``R`` are sector ``j``'s).

**Penalty stiffness** is set as finite-element codes set it (ANSYS FKN, Abaqus default
penalty): ``k_n = factor * E * A / h`` per pair, with ``E`` the Young's modulus of the
underlying solid and ``h`` the size of the elements at the face, and ``k_t = ratio * k_n``.
The physics does not fix ``factor``; results must converge as it grows (the wheel study
shows it). The **prestress** comes from an interference ``offset`` taken up by the penalty
in series with the structure's compliance (:mod:`fricdamp.models.tieboss_solid_wheel`
calibrates it to a target normal force).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ModelError, check_positive

__all__ = ["ContactPatch", "PatchResultants", "pair_faces", "patch_from_faces",
           "rotation_about"]


def _axis_vector(axis) -> np.ndarray:
    if isinstance(axis, str):
        if axis not in ("x", "y", "z"):
            raise ModelError(f"axis must be 'x', 'y', 'z' or a 3-vector, got {axis!r}")
        axis = np.eye(3)["xyz".index(axis)]
    a = np.asarray(axis, dtype=float).reshape(-1)
    if a.size != 3 or not np.all(np.isfinite(a)) or np.linalg.norm(a) == 0:
        raise ModelError(f"axis must be a finite non-zero 3-vector, got {axis!r}")
    return a / np.linalg.norm(a)


def rotation_about(axis, angle: float) -> np.ndarray:
    """3 x 3 rotation matrix by ``angle`` [rad] about the unit vector ``axis``."""
    a = _axis_vector(axis)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def pair_faces(right_xyz, left_xyz, sector_angle: float, *, axis="z",
               tol: float | None = None) -> np.ndarray:
    """Partner of every right-face node on the left face: ``R x_left[partner] = x_right``.

    Parameters
    ----------
    right_xyz, left_xyz : array_like, shape (n, 3)
        Node coordinates [m] of the right and left contact faces of one sector.
    sector_angle : float
        Sector angle alpha [rad] (2 pi / N).
    axis : {"x", "y", "z"} or array_like (3,)
        Wheel axis.
    tol : float, optional
        Matching tolerance [m] (default 1e-6 of the face size).

    Returns
    -------
    ndarray of int, shape (n,)

    Raises
    ------
    ModelError
        If the faces have different node counts or do not match node to node (the mesh
        is not conformal between neighbouring sectors).
    """
    xr = np.asarray(right_xyz, dtype=float).reshape(-1, 3)
    xl = np.asarray(left_xyz, dtype=float).reshape(-1, 3)
    if xr.shape != xl.shape or xr.shape[0] == 0:
        raise ModelError(f"the contact faces must have the same number (>= 1) of nodes, got "
                         f"{xr.shape[0]} (right) and {xl.shape[0]} (left)")
    rot = (rotation_about(axis, sector_angle) @ xl.T).T
    size = float(np.ptp(xr, axis=0).max()) or float(np.abs(xr).max())
    tol = 1e-6 * size if tol is None else float(tol)
    from scipy.spatial import cKDTree

    dist, idx = cKDTree(rot).query(xr)
    if np.max(dist) > tol or np.unique(idx).size != idx.size:
        raise ModelError(f"the left contact face rotated by the sector angle does not match "
                         f"the right face node to node (largest distance {np.max(dist):.3g} m "
                         f"> {tol:.3g} m): mesh the faces periodically")
    return idx.astype(np.int64)


@dataclass(frozen=True)
class PatchResultants:
    """Resultant force and moment of a contact patch's node-pair forces.

    The pair forces are those of the contact law, ``(f_n, f_t1, f_t2)`` in each pair's frame
    (``f_n > 0`` compression): the force with which the patch pushes sector ``j + 1`` (its
    negative acts on sector ``j``). Resultants are taken about the patch's area centroid
    ``c`` and written in its mean frame ``(n, t1, t2)`` (:attr:`ContactPatch.mean_frame`)::

        F = sum_p Lambda_p^T f_p,      M = sum_p (x_p - c) x (Lambda_p^T f_p)

    Attributes
    ----------
    normal_force : ndarray, shape (...)
        ``F . n`` [N] (compression positive).
    tangential_force : ndarray, shape (..., 2)
        ``(F . t1, F . t2)`` [N].
    moment : ndarray, shape (..., 3)
        ``(M . n, M . t1, M . t2)`` [N m]: the twisting moment about the normal (from the
        tangential forces) and the two tilting moments (from how the pressure is spread
        over the face: zero for a uniform pressure, large in edge contact).
    center_of_pressure : ndarray, shape (..., 2)
        Where the normal forces act, ``sum f_n x / sum f_n - c`` along (t1, t2) [m]; NaN
        where the patch carries no normal force.
    """

    normal_force: np.ndarray
    tangential_force: np.ndarray
    moment: np.ndarray
    center_of_pressure: np.ndarray


@dataclass(frozen=True, repr=False)
class ContactPatch:
    """Node pairs of one sector's contact: right face of sector j to left face of j + 1.

    Attributes
    ----------
    right : ndarray of int, shape (n_pairs,)
        Indices of the pairs' nodes in the right-face node list.
    left : ndarray of int, shape (n_pairs,)
        Indices of their partners in the left-face node list.
    positions : ndarray, shape (n_pairs, 3)
        Right-face node coordinates [m] (sector frame).
    frames : ndarray, shape (n_pairs, 3, 3)
        Rows n, t1, t2 of each pair's frame (sector Cartesian components).
    areas : ndarray, shape (n_pairs,)
        Tributary areas [m^2].
    element_size : float
        Size h of the elements at the face [m] (for the penalty).
    sector_angle : float
        [rad]
    axis : tuple of 3 floats
    """

    right: np.ndarray
    left: np.ndarray
    positions: np.ndarray
    frames: np.ndarray
    areas: np.ndarray
    element_size: float
    sector_angle: float
    axis: tuple = (0.0, 0.0, 1.0)

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    @property
    def n_pairs(self) -> int:
        return self.right.size

    @property
    def area(self) -> float:
        """Total face area [m^2]."""
        return float(self.areas.sum())

    @property
    def rotation(self) -> np.ndarray:
        """R: rotation by the sector angle about the axis."""
        return rotation_about(self.axis, self.sector_angle)

    def normal_stiffness(self, youngs_modulus: float, penalty_factor: float) -> np.ndarray:
        """Per-pair normal penalty ``factor E A / h`` [N/m], shape (n_pairs,)."""
        E = float(check_positive("youngs_modulus", youngs_modulus, unit="Pa"))
        fac = float(check_positive("penalty_factor", penalty_factor))
        return fac * E * self.areas / self.element_size

    def law(self, *, youngs_modulus: float, penalty_factor: float, offset: float,
            mu_static: float, mu_sliding: float | None = None, decay: float = 0.0,
            tangential_ratio: float = 1.0, n_sectors: int = 1) -> Contact3D:
        """Contact3D law of the patch repeated for ``n_sectors`` contacts (pairs fastest).

        ``offset`` [m] > 0 is the interference (prestress), the same on every pair;
        ``tangential_ratio`` sets ``k_t = ratio * k_n`` (ANSYS FKT, default 1).
        """
        kn = np.tile(self.normal_stiffness(youngs_modulus, penalty_factor), n_sectors)
        ratio = float(check_positive("tangential_ratio", tangential_ratio))
        return Contact3D(kn, ratio * kn, mu_static, offset=offset, mu_sliding=mu_sliding,
                         decay=decay, n_contacts=kn.size)

    @property
    def centroid(self) -> np.ndarray:
        """Area-weighted centre of the pairs ``sum A x / sum A`` [m], shape (3,)."""
        return self.areas @ self.positions / self.areas.sum()

    @property
    def mean_frame(self) -> np.ndarray:
        """Rows ``(n, t1, t2)`` of the patch: the area-weighted mean normal, the mean first
        tangent made orthogonal to it, and ``t2 = n x t1`` (equal to every pair's frame on
        a plane face), shape (3, 3)."""
        n = self.areas @ self.frames[:, 0]
        n /= np.linalg.norm(n)
        t1 = self.areas @ self.frames[:, 1]
        t1 -= (t1 @ n) * n
        t1 /= np.linalg.norm(t1)
        return np.stack([n, t1, np.cross(n, t1)])

    def resultants(self, forces) -> PatchResultants:
        """Resultant force, moment and centre of pressure of pair forces.

        Parameters
        ----------
        forces : array_like, shape (..., n_pairs, 3)
            Pair forces ``(f_n, f_t1, f_t2)`` [N] in the pairs' frames (e.g. the
            ``contact_force`` of a transient for one contact), any leading shape.

        Returns
        -------
        PatchResultants
            See there for the definitions and sign conventions.
        """
        f = np.asarray(forces, dtype=float)
        if f.ndim < 2 or f.shape[-2:] != (self.n_pairs, 3):
            raise ModelError(f"forces must have shape (..., {self.n_pairs}, 3), got {f.shape}")
        glob = np.einsum("pab,...pa->...pb", self.frames, f)      # Lambda_p^T f_p
        arm = self.positions - self.centroid
        F = glob.sum(axis=-2)
        M = np.cross(arm, glob).sum(axis=-2)
        E = self.mean_frame
        fn = f[..., 0]
        N = fn.sum(axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            cp = np.einsum("...p,pa->...a", fn, arm) / N[..., None]
        cp = np.where((N > 0)[..., None], cp, np.nan)
        return PatchResultants(normal_force=F @ E[0], tangential_force=F @ E[1:].T,
                               moment=M @ E.T, center_of_pressure=cp @ E[1:].T)

    def face_coordinates(self) -> np.ndarray:
        """In-plane coordinates (along t1, t2) of the pairs from the face centre [m],
        shape (n_pairs, 2), for contact-status maps."""
        c = self.positions - self.positions.mean(axis=0)
        t1, t2 = self.frames[0, 1], self.frames[0, 2]
        return np.column_stack([c @ t1, c @ t2])

    def wheel_rows(self, right_shapes, left_shapes) -> np.ndarray:
        """Contact rows of the whole wheel from mode shapes on both faces of every sector.

        Parameters
        ----------
        right_shapes, left_shapes : ndarray, shape (N, 3 n_face_nodes, n_modes)
            Shapes on the right / left face nodes (x, y, z of each node, in the face-node
            order) of every sector, each in its own sector's components.

        Returns
        -------
        ndarray, shape (N * 3 n_pairs, n_modes)
            Rows ``3 (j n_pairs + p) + (n, t1, t2)``: contact j joins sector j's right
            face to sector j + 1's left face.
        """
        Gr = np.asarray(right_shapes)
        Gl = np.asarray(left_shapes)
        N, _, n_modes = Gr.shape
        R = self.rotation
        ir = (3 * self.right[:, None] + np.arange(3)).ravel()
        il = (3 * self.left[:, None] + np.arange(3)).ravel()
        out = np.empty((N, self.n_pairs, 3, n_modes))
        for j in range(N):
            ur = Gr[j][ir].reshape(self.n_pairs, 3, n_modes)
            ul = Gl[(j + 1) % N][il].reshape(self.n_pairs, 3, n_modes)
            rel = ur - np.einsum("ab,pbm->pam", R, ul)
            out[j] = np.einsum("pab,pbm->pam", self.frames, rel)
        return out.reshape(N * 3 * self.n_pairs, n_modes)


def patch_from_faces(right_xyz, left_xyz, *, right_areas, right_normals, sector_angle: float,
                     element_size: float, axis="z", tol: float | None = None) -> ContactPatch:
    """Build a :class:`ContactPatch` from the two contact faces of one sector.

    Parameters
    ----------
    right_xyz, left_xyz : array_like, shape (n, 3)
        Face node coordinates [m] (sector frame).
    right_areas : array_like, shape (n,)
        Tributary area of each right-face node [m^2] (> 0).
    right_normals : array_like, shape (n, 3)
        Outward unit normals of the right face at its nodes (pointing into sector j + 1).
    sector_angle : float
        [rad]
    element_size : float
        Element size at the face [m].
    axis : {"x", "y", "z"} or array_like (3,)
    tol : float, optional
        Node-matching tolerance [m].
    """
    xr = np.asarray(right_xyz, dtype=float).reshape(-1, 3)
    partner = pair_faces(xr, left_xyz, sector_angle, axis=axis, tol=tol)
    A = np.asarray(right_areas, dtype=float).reshape(-1)
    if A.shape != (xr.shape[0],) or not np.all(np.isfinite(A)) or A.min() <= 0:
        raise ModelError(f"right_areas must be {xr.shape[0]} tributary areas > 0 m^2")
    nrm = np.asarray(right_normals, dtype=float).reshape(-1, 3)
    if nrm.shape != xr.shape or not np.all(np.isfinite(nrm)):
        raise ModelError(f"right_normals must have shape {xr.shape}")
    nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    h = float(check_positive("element_size", element_size, unit="m"))
    a = _axis_vector(axis)
    radial = xr - np.outer(xr @ a, a)
    radial /= np.linalg.norm(radial, axis=1, keepdims=True)
    t1 = radial - np.sum(radial * nrm, axis=1, keepdims=True) * nrm
    norms = np.linalg.norm(t1, axis=1)
    if norms.min() < 1e-6:
        raise ModelError("a contact face normal is radial: the radial direction cannot set "
                         "the first tangent")
    t1 /= norms[:, None]
    t2 = np.cross(nrm, t1)
    frames = np.stack([nrm, t1, t2], axis=1)
    return ContactPatch(right=np.arange(xr.shape[0]), left=partner, positions=xr,
                        frames=frames, areas=A, element_size=h,
                        sector_angle=float(sector_angle), axis=tuple(a))
