"""3D Rayleigh beam finite elements for blades rotating about a fixed axis, 001 (2).

Two-node straight elements with 6 DOFs per node, ``(u, v, w, phi, theta, psi)`` = the
translations along and the small rotations about the global x, y, z axes (of the frame that
rotates with the wheel). In the element frame (local x from node 1 to node 2, local y the part
of the orientation vector perpendicular to x, local z = x cross y):

* axial displacement and twist: linear interpolation;
* bending in the local x-y and x-z planes: cubic Hermite (Euler-Bernoulli, no shear
  deformation) with ``theta_z = v'`` and ``theta_y = -w'``;
* Rayleigh beam: the consistent mass holds the translational inertia rho A and the rotary
  inertia of the cross-section, rho diag(Ip, Iy, Iz) about the local axes.

All element matrices are integrals over the element evaluated with 4-point Gauss-Legendre
quadrature (exact for every integrand here, polynomials of degree <= 6), vectorised over
elements, then rotated to the global frame and assembled as scipy.sparse matrices.

Rotation about the spin axis (unit vector ``e`` through ``spin_origin``) adds, per 001 (2):

* ``G`` (per Omega, skew-symmetric): Coriolis terms ``2 rho A S(e)`` of the translations and
  the gyroscopic terms of the rotary inertia (:mod:`beam3d_rotation`);
* ``K_d`` (per Omega^2, symmetric, enters as ``-Omega^2 K_d``): spin softening, the
  centripetal term ``rho A (I - e e^T)`` of the translations and the rotary-inertia terms;
* ``f_c`` (per Omega^2): centrifugal force ``rho A (I - e e^T) r`` and moment ``(J e) x e``;
* ``K_w`` (per Omega^2, symmetric): stress stiffening, the geometric stiffness
  ``int N(x) (u'^2 + v'^2 + w'^2 + (Ip / A) phi'^2) dx / 2`` of the centrifugal axial force
  N(x) per Omega^2. N is found from the linear static problem ``K q = f_c`` on the supported
  structure (the nodal solution of Hermite/linear elements is exact for these polynomial
  loads) and, inside an element, from axial equilibrium with the linear distributed
  centrifugal load, so N(x) is the exact quadratic distribution of a radial blade.
  Spin softening is not included in the prestress solve (N is linear in Omega^2, as 001 (2)
  assumes) and only the axial force enters K_w (no bending-moment geometric terms).

The paper gives (2) without the matrices; they are derived here from the kinetic energy in the
rotating frame and proved by tests: cantilever, axial and torsional frequencies, the Rayleigh
rotary-inertia correction, Southwell coefficients of rotating cantilevers (flap and lead-lag),
a shaft spinning about its own axis, frame invariance, and a rigid-body linearisation.

References
----------
Przemieniecki (1968), *Theory of Matrix Structural Analysis*, ch. 5, 11, 15.
Hodges & Rutkowski (1981), AIAA J. 19(11) 1459-1466 (rotating cantilever frequencies).
Wright, Smith, Thompson & Bhat (1982), J. Appl. Mech. 49, 197-202 (Southwell coefficients).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fricdamp.errors import ModelError, as_finite_array, check_positive, check_range
from fricdamp.structure.beam3d_rotation import (
    inertia_tensor,
    rigid_body_terms,
    rotary_operators,
    spin_axis_unit,
    translational_operators,
)
from fricdamp.structure.system import MechanicalSystem, RotationTerms

__all__ = ["DOF_NAMES", "BeamModel", "BeamSection", "beam_model", "line_mesh",
           "local_element_matrices"]

#: Names of the 6 DOFs of a node, in order: translations x, y, z and rotations about x, y, z.
DOF_NAMES = ("u", "v", "w", "phi", "theta", "psi")
_ALIASES = {"ux": 0, "uy": 1, "uz": 2, "rx": 3, "ry": 4, "rz": 5, "vartheta": 4}

_GX, _GW = np.polynomial.legendre.leggauss(4)
_GX = 0.5 * (_GX + 1.0)   # Gauss points on [0, 1]
_GW = 0.5 * _GW


def _dof_code(name: str) -> int:
    if name in DOF_NAMES:
        return DOF_NAMES.index(name)
    if name in _ALIASES:
        return _ALIASES[name]
    raise ModelError(f"DOF name must be one of {DOF_NAMES} (or ux, uy, uz, rx, ry, rz), "
                     f"got {name!r}")


# ---------------------------------------------------------------------------- section
@dataclass(frozen=True)
class BeamSection:
    """Cross-section and material of a beam element (constant along the element).

    Parameters
    ----------
    area_m2 : float
        Area A [m^2], > 0.
    Iy_m4, Iz_m4 : float
        Second moments of area about the local y and z axes [m^4], > 0:
        ``Iy = int z^2 dA`` (bending in the local x-z plane), ``Iz = int y^2 dA``.
    J_m4 : float
        Torsion constant [m^4], > 0 (equals Iy + Iz only for circular sections).
    E_Pa : float
        Young's modulus [Pa], > 0.
    rho_kg_m3 : float
        Density [kg/m^3], > 0.
    G_Pa : float, optional
        Shear modulus [Pa], > 0. Give either G_Pa or nu.
    nu : float, optional
        Poisson's ratio in (-1, 0.5]; then ``G = E / (2 (1 + nu))``.
    Ip_m4 : float, optional
        Polar moment of area about the centroid [m^4] used for the rotary inertia of twist
        and the tension-twist stiffening; defaults to ``Iy + Iz``.

    Examples
    --------
    >>> s = BeamSection.rectangle(0.02, 0.005, E_Pa=210e9, rho_kg_m3=7800.0, nu=0.3)
    >>> round(s.area_m2 * 1e6, 3), round(s.G_Pa / 1e9, 2)
    (100.0, 80.77)
    """

    area_m2: float
    Iy_m4: float
    Iz_m4: float
    J_m4: float
    E_Pa: float
    rho_kg_m3: float
    G_Pa: float | None = None
    nu: float | None = None
    Ip_m4: float | None = None

    def __post_init__(self):
        for name, unit in (("area_m2", "m^2"), ("Iy_m4", "m^4"), ("Iz_m4", "m^4"),
                           ("J_m4", "m^4"), ("E_Pa", "Pa"), ("rho_kg_m3", "kg/m^3")):
            object.__setattr__(self, name, float(check_positive(
                f"BeamSection.{name}", getattr(self, name), unit=unit)))
        if (self.G_Pa is None) == (self.nu is None):
            if self.G_Pa is None:
                raise ModelError("BeamSection needs the shear modulus: give G_Pa [Pa] or "
                                 "Poisson's ratio nu")
            nu_implied = self.E_Pa / (2.0 * float(self.G_Pa)) - 1.0
            if abs(nu_implied - float(self.nu)) > 1e-6:
                raise ModelError(f"BeamSection: G_Pa = {self.G_Pa} and nu = {self.nu} "
                                 f"disagree (E / 2G - 1 = {nu_implied:.4g}); give only one")
        if self.nu is not None:
            nu = float(check_range("BeamSection.nu", self.nu, -1.0, 0.5, low_open=True))
            object.__setattr__(self, "nu", nu)
            if self.G_Pa is None:
                object.__setattr__(self, "G_Pa", self.E_Pa / (2.0 * (1.0 + nu)))
        object.__setattr__(self, "G_Pa", float(check_positive(
            "BeamSection.G_Pa", self.G_Pa, unit="Pa")))
        ip = self.Iy_m4 + self.Iz_m4 if self.Ip_m4 is None else self.Ip_m4
        object.__setattr__(self, "Ip_m4", float(check_positive("BeamSection.Ip_m4", ip,
                                                               unit="m^4")))

    @classmethod
    def rectangle(cls, width_m: float, height_m: float, *, E_Pa: float, rho_kg_m3: float,
                  G_Pa: float | None = None, nu: float | None = None) -> BeamSection:
        """Solid rectangle: ``width_m`` along local y, ``height_m`` along local z [m].

        Torsion constant from the Saint-Venant series (Timoshenko & Goodier)
        ``a b^3 / 3 (1 - 192 b / (pi^5 a) sum_(n odd) tanh(n pi a / 2b) / n^5)``, a >= b the
        sides (0.1406 a^4 for a square).
        """
        b_y = float(check_positive("width_m", width_m, unit="m"))
        h_z = float(check_positive("height_m", height_m, unit="m"))
        a, b = max(b_y, h_z), min(b_y, h_z)
        n = np.arange(1, 40, 2)
        series = np.sum(np.tanh(n * np.pi * a / (2.0 * b)) / n**5)
        J = a * b**3 / 3.0 * (1.0 - 192.0 * b / (np.pi**5 * a) * series)
        return cls(area_m2=b_y * h_z, Iy_m4=b_y * h_z**3 / 12.0, Iz_m4=h_z * b_y**3 / 12.0,
                   J_m4=J, E_Pa=E_Pa, rho_kg_m3=rho_kg_m3, G_Pa=G_Pa, nu=nu)

    @classmethod
    def circle(cls, diameter_m: float, *, E_Pa: float, rho_kg_m3: float,
               G_Pa: float | None = None, nu: float | None = None) -> BeamSection:
        """Solid circle of diameter ``diameter_m`` [m] (J = Ip = pi d^4 / 32)."""
        d = float(check_positive("diameter_m", diameter_m, unit="m"))
        inertia = np.pi * d**4 / 64.0
        return cls(area_m2=np.pi * d**2 / 4.0, Iy_m4=inertia, Iz_m4=inertia,
                   J_m4=2.0 * inertia, E_Pa=E_Pa, rho_kg_m3=rho_kg_m3, G_Pa=G_Pa, nu=nu)


def _section_arrays(sections, n_el: int) -> dict[str, np.ndarray]:
    if isinstance(sections, BeamSection):
        sections = [sections] * n_el
    sections = list(sections)
    if len(sections) != n_el:
        raise ModelError(f"sections must be one BeamSection or one per element ({n_el}), got "
                         f"{len(sections)}")
    for i, s in enumerate(sections):
        if not isinstance(s, BeamSection):
            raise ModelError(f"sections[{i}] must be a BeamSection, got {s!r}")

    def col(f):
        return np.array([f(s) for s in sections], dtype=float)

    return {
        "EA": col(lambda s: s.E_Pa * s.area_m2), "EIy": col(lambda s: s.E_Pa * s.Iy_m4),
        "EIz": col(lambda s: s.E_Pa * s.Iz_m4), "GJ": col(lambda s: s.G_Pa * s.J_m4),
        "rhoA": col(lambda s: s.rho_kg_m3 * s.area_m2),
        "rhoIp": col(lambda s: s.rho_kg_m3 * s.Ip_m4),
        "rhoIy": col(lambda s: s.rho_kg_m3 * s.Iy_m4),
        "rhoIz": col(lambda s: s.rho_kg_m3 * s.Iz_m4),
        "Ip_over_A": col(lambda s: s.Ip_m4 / s.area_m2),
    }


# ---------------------------------------------------------------------------- mesh
def line_mesh(start_m, end_m, n_elements: int) -> tuple[np.ndarray, np.ndarray]:
    """Straight line of ``n_elements`` equal elements from ``start_m`` to ``end_m``.

    Returns
    -------
    nodes : ndarray, shape (n_elements + 1, 3)
        Node coordinates [m]; node 0 at ``start_m``.
    elements : ndarray of int, shape (n_elements, 2)
        ``[[0, 1], [1, 2], ...]``.
    """
    if int(n_elements) != n_elements or n_elements < 1:
        raise ModelError(f"n_elements must be an integer >= 1, got {n_elements!r}")
    a = as_finite_array("start_m", start_m)
    b = as_finite_array("end_m", end_m)
    if a.shape != (3,) or b.shape != (3,):
        raise ModelError("start_m and end_m must be 3-vectors [m]")
    t = np.linspace(0.0, 1.0, int(n_elements) + 1)[:, None]
    idx = np.arange(int(n_elements))
    return a + t * (b - a), np.stack([idx, idx + 1], axis=1)


def _frames(nodes: np.ndarray, elements: np.ndarray, orientation) -> tuple[np.ndarray,
                                                                            np.ndarray]:
    """Element lengths (n_el,) and rotation matrices Lam (n_el, 3, 3), rows = local axes."""
    d = nodes[elements[:, 1]] - nodes[elements[:, 0]]
    length = np.linalg.norm(d, axis=1)
    scale = max(float(np.abs(nodes).max()), float(length.max()), 1e-300)
    bad = np.flatnonzero(length <= 1e-12 * scale)
    if bad.size:
        raise ModelError(f"element {int(bad[0])} has zero length (nodes "
                         f"{elements[bad[0]].tolist()} coincide)")
    ex = d / length[:, None]
    if orientation is None:
        v = np.tile([0.0, 1.0, 0.0], (len(ex), 1))
        along_y = np.abs(ex[:, 1]) > 1.0 - 1e-8
        v[along_y] = [-1.0, 0.0, 0.0]
    else:
        v = as_finite_array("orientation", orientation)
        if v.shape == (3,):
            v = np.tile(v, (len(ex), 1))
        if v.shape != ex.shape:
            raise ModelError(f"orientation must be a 3-vector or one per element "
                             f"({len(ex)}, 3), got shape {v.shape}")
    ez = np.cross(ex, v)
    nz = np.linalg.norm(ez, axis=1)
    nv = np.linalg.norm(v, axis=1)
    bad = np.flatnonzero(nz <= 1e-8 * np.maximum(nv, 1e-300))
    if bad.size:
        raise ModelError(f"orientation vector of element {int(bad[0])} is zero or parallel to "
                         "the element axis; give one that fixes the local y axis")
    ez /= nz[:, None]
    ey = np.cross(ez, ex)
    return length, np.stack([ex, ey, ez], axis=1)


# ---------------------------------------------------------------------------- elements
def _shape_functions(length: np.ndarray):
    """Interpolation at the Gauss points, each (n_el, n_gauss, rows, 12) in local DOFs.

    Returns Nu (3 rows: u, v, w), Nth (3 rows: theta_x, theta_y, theta_z), B (4 rows:
    u', v'', w'', phi') and dNu (3 rows: u', v', w').
    """
    n_el, xi, L = length.size, _GX[None, :], length[:, None]
    H = (1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3, 3 * xi**2 - 2 * xi**3,
         -xi**2 + xi**3)
    dH = (-6 * xi + 6 * xi**2, 1 - 4 * xi + 3 * xi**2, 6 * xi - 6 * xi**2, -2 * xi + 3 * xi**2)
    d2H = (-6 + 12 * xi, -4 + 6 * xi, 6 - 12 * xi, -2 + 6 * xi)
    shape = (n_el, _GX.size, 3, 12)
    Nu, Nth, dNu = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    B = np.zeros((n_el, _GX.size, 4, 12))
    one = np.ones_like(L)
    lin0, lin1 = (1 - xi) * one, xi * one
    # axial u and twist phi: linear
    Nu[..., 0, 0], Nu[..., 0, 6] = lin0, lin1
    Nth[..., 0, 3], Nth[..., 0, 9] = lin0, lin1
    B[..., 0, 0], B[..., 0, 6] = -one / L, one / L
    B[..., 3, 3], B[..., 3, 9] = -one / L, one / L
    # v(x) with theta_z = v'      (local DOFs v1=1, tz1=5, v2=7, tz2=11)
    # w(x) with theta_y = -w'     (local DOFs w1=2, ty1=4, w2=8, ty2=10)
    for k, (jv, jw, rot) in enumerate(((1, 2, False), (5, 4, True), (7, 8, False),
                                       (11, 10, True))):
        # rot: a rotation DOF, whose Hermite function is scaled by the length
        f = H[k] * L if rot else H[k] * one
        df = dH[k] * one if rot else dH[k] / L
        d2f = d2H[k] / L if rot else d2H[k] / L**2
        sw = -1.0 if rot else 1.0   # theta_y = -w'
        Nu[..., 1, jv], Nu[..., 2, jw] = f, sw * f
        Nth[..., 2, jv], Nth[..., 1, jw] = df, -sw * df
        dNu[..., 1, jv], dNu[..., 2, jw] = df, sw * df
        B[..., 1, jv], B[..., 2, jw] = d2f, sw * d2f
    dNu[..., 0, :] = B[..., 0, :]
    return Nu, Nth, B, dNu


def _integrate(length: np.ndarray, Na: np.ndarray, A: np.ndarray, Nb: np.ndarray | None = None,
               ) -> np.ndarray:
    """``int_0^l Na^T A Nb dx`` per element, (n_el, 12, 12); A (n_el, [n_g,] r, r)."""
    Nb = Na if Nb is None else Nb
    if A.ndim == 3:
        A = np.broadcast_to(A[:, None], (A.shape[0], _GX.size) + A.shape[1:])
    w = _GW[None, :] * length[:, None]
    return np.einsum("eg,egai,egab,egbj->eij", w, Na, A, Nb)


def local_element_matrices(length_m, section: BeamSection) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent Rayleigh mass of one element in its local frame.

    Parameters
    ----------
    length_m : float
        Element length [m].
    section : BeamSection

    Returns
    -------
    K, M : ndarray, shape (12, 12)
        Local DOFs ``(u, v, w, theta_x, theta_y, theta_z)`` at node 1 then node 2.
    """
    length = np.atleast_1d(check_positive("length_m", length_m, unit="m")).astype(float)
    sec = _section_arrays([section], 1)
    Nu, Nth, B, _ = _shape_functions(length)
    return _stiffness(length, sec, B)[0], _mass(length, sec, Nu, Nth)[0]


def _diag(*cols: np.ndarray) -> np.ndarray:
    out = np.zeros((cols[0].size, len(cols), len(cols)))
    for i, c in enumerate(cols):
        out[:, i, i] = c
    return out


def _stiffness(length, sec, B):
    return _integrate(length, B, _diag(sec["EA"], sec["EIz"], sec["EIy"], sec["GJ"]))


def _rotary_inertia(sec):
    return _diag(sec["rhoIp"], sec["rhoIy"], sec["rhoIz"])


def _mass(length, sec, Nu, Nth):
    rhoA = sec["rhoA"][:, None, None] * np.eye(3)
    return _integrate(length, Nu, rhoA) + _integrate(length, Nth, _rotary_inertia(sec))


# ---------------------------------------------------------------------------- model
@dataclass(frozen=True, eq=False, repr=False)
class BeamModel:
    """Assembled beam structure, reduced to its free DOFs.

    Attributes
    ----------
    nodes : ndarray, shape (n_nodes, 3)
        Node coordinates [m] in the rotating frame.
    elements : ndarray of int, shape (n_el, 2)
    free_dofs : ndarray of int, shape (n_dof,)
        Full DOF index ``6 node + k`` of each model DOF (k over :data:`DOF_NAMES`).
    M, K, D : scipy.sparse.csr_matrix, shape (n_dof, n_dof)
        Mass, static stiffness and material damping (zero if none was asked for).
    rotation : RotationTerms or None
        G, K_d, K_w (matrices, sparse) and f_c (vector) per Omega / Omega^2; None when no
        spin axis was given.
    spin_axis, spin_origin : ndarray, shape (3,) or None
    axial_force_per_omega2 : ndarray, shape (n_el, 2) or None
        Centrifugal axial force [N s^2 = N / (rad/s)^2] at the two ends of each element per
        unit Omega^2, tension positive.
    centrifugal_displacement_per_omega2 : ndarray, shape (n_nodes, 6) or None
        Static deflection of ``K q = f_c`` per Omega^2 [m s^2, rad s^2].
    """

    nodes: np.ndarray
    elements: np.ndarray
    free_dofs: np.ndarray
    M: sp.csr_matrix
    K: sp.csr_matrix
    D: sp.csr_matrix
    rotation: RotationTerms | None = None
    spin_axis: np.ndarray | None = None
    spin_origin: np.ndarray | None = None
    axial_force_per_omega2: np.ndarray | None = None
    centrifugal_displacement_per_omega2: np.ndarray | None = None
    name: str = "beam"
    _full_to_free: np.ndarray = field(init=False, repr=False)

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    def __post_init__(self):
        full_to_free = -np.ones(6 * self.nodes.shape[0], dtype=int)
        full_to_free[self.free_dofs] = np.arange(self.free_dofs.size)
        object.__setattr__(self, "_full_to_free", full_to_free)

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.elements.shape[0])

    @property
    def n_dof(self) -> int:
        return int(self.free_dofs.size)

    @property
    def dof_names(self) -> tuple[str, ...]:
        """``"u3"``, ``"phi3"``, ...: DOF name and node number of each model DOF."""
        return tuple(f"{DOF_NAMES[i % 6]}{i // 6}" for i in self.free_dofs)

    def full_dof_index(self, node: int, name: str) -> int:
        """Index ``6 node + k`` of a DOF among all ``6 n_nodes`` (fixed ones included)."""
        if int(node) != node or not 0 <= node < self.n_nodes:
            raise ModelError(f"node must be an integer in [0, {self.n_nodes - 1}], got "
                             f"{node!r}")
        return 6 * int(node) + _dof_code(name)

    def dof_index(self, node: int, name: str) -> int:
        """Index of DOF ``name`` of ``node`` in the model's (free) DOFs.

        Parameters
        ----------
        node : int
            Node number (row of ``nodes``).
        name : str
            One of ``u, v, w, phi, theta, psi`` (or ``ux, uy, uz, rx, ry, rz``).

        Raises
        ------
        ModelError
            If the DOF is fixed (clamped) or the node/name does not exist.
        """
        i = int(self._full_to_free[self.full_dof_index(node, name)])
        if i < 0:
            raise ModelError(f"DOF {name!r} of node {node} is fixed (clamped); it is not a "
                             "model DOF")
        return i

    def expand(self, q) -> np.ndarray:
        """Nodal values (n_nodes, 6) of a model vector q (n_dof,), zero at fixed DOFs."""
        q = np.asarray(q)
        if q.shape != (self.n_dof,):
            raise ModelError(f"q must have shape ({self.n_dof},), got {q.shape}")
        out = np.zeros(6 * self.n_nodes, dtype=np.result_type(q.dtype, float))
        out[self.free_dofs] = q
        return out.reshape(self.n_nodes, 6)

    def to_system(self, *, sparse: bool = True, **kwargs) -> MechanicalSystem:
        """The model as a :class:`MechanicalSystem` (rotation terms attached).

        Parameters
        ----------
        sparse : bool
            Keep scipy.sparse matrices (default) or convert all matrices to dense arrays.
        **kwargs
            Passed to MechanicalSystem (contacts, loads, static_load, name, meta).
        """
        def conv(A):
            return A if (sparse or A is None or not sp.issparse(A)) else A.toarray()

        rot = self.rotation
        if rot is not None and not sparse:
            rot = RotationTerms(gyroscopic=conv(rot.gyroscopic),
                                spin_softening=conv(rot.spin_softening),
                                stress_stiffening=conv(rot.stress_stiffening),
                                centrifugal_load=rot.centrifugal_load)
        kwargs.setdefault("name", self.name)
        meta = {"nodes_m": self.nodes, "elements": self.elements,
                "free_dofs": self.free_dofs, **kwargs.pop("meta", {})}
        return MechanicalSystem(M=conv(self.M), K=conv(self.K), D=conv(self.D), rotation=rot,
                                dof_names=self.dof_names, meta=meta, **kwargs)


def _point_masses(point_masses, n_nodes, spin):
    """Per node: 6x6 mass, and (if spinning) G, Kd, fc of the rigid body."""
    out = []
    for node, spec in (point_masses or {}).items():
        if int(node) != node or not 0 <= node < n_nodes:
            raise ModelError(f"point_masses: node must be in [0, {n_nodes - 1}], got {node!r}")
        if isinstance(spec, (int, float, np.number)) or (
                isinstance(spec, np.ndarray) and spec.ndim == 0):
            mass, inertia = spec, 0.0
        else:
            try:
                mass, inertia = spec
            except (TypeError, ValueError):
                raise ModelError(f"point_masses[{node}] must be a mass [kg] or a pair (mass "
                                 f"[kg], inertia [kg m^2]), got {spec!r}") from None
        if spin is None:
            m = float(check_positive(f"point_masses[{node}] mass", mass, unit="kg"))
            Mb = np.zeros((6, 6))
            Mb[:3, :3] = m * np.eye(3)
            Mb[3:, 3:] = inertia_tensor(f"point_masses[{node}] inertia", inertia)
            out.append((int(node), Mb, None))
        else:
            e, o, nodes = spin
            out.append((int(node), None, rigid_body_terms(mass, inertia, nodes[int(node)],
                                                          spin_axis=e, spin_origin=o)))
    return out


def _parse_fixed(clamped_nodes, fixed_dofs, n_nodes) -> np.ndarray:
    fixed = np.zeros(6 * n_nodes, dtype=bool)
    for node in clamped_nodes:
        if int(node) != node or not 0 <= node < n_nodes:
            raise ModelError(f"clamped_nodes: node must be in [0, {n_nodes - 1}], got {node!r}")
        fixed[6 * int(node): 6 * int(node) + 6] = True
    for item in fixed_dofs:
        try:
            node, names = item
        except (TypeError, ValueError):
            raise ModelError(f"fixed_dofs entries must be (node, name or names), got "
                             f"{item!r}") from None
        if int(node) != node or not 0 <= node < n_nodes:
            raise ModelError(f"fixed_dofs: node must be in [0, {n_nodes - 1}], got {node!r}")
        for nm in ([names] if isinstance(names, str) else names):
            fixed[6 * int(node) + _dof_code(nm)] = True
    return fixed


def beam_model(nodes_xyz, elements, sections: BeamSection | Sequence[BeamSection], *,
               orientation=None, clamped_nodes: Sequence[int] = (),
               fixed_dofs: Sequence[tuple[int, str | Sequence[str]]] = (),
               point_masses: Mapping[int, float | tuple] | None = None,
               rayleigh: tuple[float, float] | None = None,
               loss_factor: tuple[float, float] | None = None,
               spin_axis=None, spin_origin=(0.0, 0.0, 0.0),
               stress_stiffening: bool = True, name: str = "beam") -> BeamModel:
    """Assemble a 3D Rayleigh beam structure, optionally rotating, 001 (2).

    Parameters
    ----------
    nodes_xyz : array_like, shape (n_nodes, 3)
        Node coordinates [m] in the rotating frame.
    elements : array_like of int, shape (n_el, 2)
        Node pairs; every node must belong to an element.
    sections : BeamSection or sequence of n_el BeamSection
    orientation : (3,) or (n_el, 3), optional
        Vector fixing each element's local y axis (its part perpendicular to the element).
        Default global y, or global -x for elements along y (local z then = global z).
    clamped_nodes : sequence of int
        Nodes with all 6 DOFs fixed.
    fixed_dofs : sequence of (node, name or names)
        Further single fixed DOFs, e.g. ``[(0, ("u", "v", "w")), (8, "w")]``.
    point_masses : mapping node -> mass [kg] or (mass [kg], inertia [kg m^2])
        Rigid bodies with their centre of mass at the node; inertia a scalar, 3 principal
        values along the global axes, or a 3x3 tensor about the node.
    rayleigh : (alpha [1/s], beta [s]), optional
        Material damping ``D = alpha M + beta K``.
    loss_factor : (eta, omega_ref [rad/s]), optional
        Material loss factor eta made viscous at omega_ref: ``D = eta / omega_ref K``.
        Exclusive with ``rayleigh``.
    spin_axis : (3,), optional
        Direction of the spin axis; when given, the rotation terms are built.
    spin_origin : (3,)
        A point on the spin axis [m].
    stress_stiffening : bool
        Build K_w from the centrifugal prestress (needs supports making K non-singular).
    name : str

    Returns
    -------
    BeamModel
        Use ``model.to_system()`` and ``system.at_speed(Omega)`` for the system at speed:
        ``D + Omega G``, ``K + Omega^2 (K_w - K_d)``, load ``Omega^2 f_c``.

    Raises
    ------
    ModelError
        Bad geometry, sections, supports or damping; singular prestress problem.

    Examples
    --------
    >>> import numpy as np
    >>> sec = BeamSection.rectangle(0.02, 0.004, E_Pa=2.1e11, rho_kg_m3=7850.0, nu=0.3)
    >>> nodes, els = line_mesh([0.3, 0, 0], [0.5, 0, 0], 5)
    >>> blade = beam_model(nodes, els, sec, clamped_nodes=[0], spin_axis=[0, 0, 1])
    >>> blade.n_dof, blade.dof_index(5, "w")
    (30, 26)
    >>> sys = blade.to_system().at_speed(100.0)
    """
    nodes = as_finite_array("nodes_xyz", nodes_xyz)
    if nodes.ndim != 2 or nodes.shape[1] != 3 or nodes.shape[0] < 2:
        raise ModelError(f"nodes_xyz must have shape (n_nodes >= 2, 3), got {nodes.shape}")
    els = np.asarray(elements)
    if els.ndim != 2 or els.shape[1] != 2 or els.shape[0] < 1 or not np.issubdtype(
            els.dtype, np.integer):
        raise ModelError(f"elements must be an integer array of shape (n_el, 2), got "
                         f"{els.shape} {els.dtype}")
    n_nodes, n_el = nodes.shape[0], els.shape[0]
    if els.min() < 0 or els.max() >= n_nodes or np.any(els[:, 0] == els[:, 1]):
        raise ModelError(f"elements must join two different nodes in [0, {n_nodes - 1}]")
    lonely = np.setdiff1d(np.arange(n_nodes), els)
    if lonely.size:
        raise ModelError(f"node {int(lonely[0])} belongs to no element")
    if rayleigh is not None and loss_factor is not None:
        raise ModelError("give either rayleigh or loss_factor, not both")
    sec = _section_arrays(sections, n_el)
    length, Lam = _frames(nodes, els, orientation)
    T = np.zeros((n_el, 12, 12))
    for b in range(4):
        T[:, 3 * b:3 * b + 3, 3 * b:3 * b + 3] = Lam
    el_dofs = (6 * els[:, :, None] + np.arange(6)).reshape(n_el, 12)
    n_full = 6 * n_nodes
    rows = np.broadcast_to(el_dofs[:, :, None], (n_el, 12, 12)).ravel()
    cols = np.broadcast_to(el_dofs[:, None, :], (n_el, 12, 12)).ravel()

    def assemble(local):
        glob = np.einsum("eai,eab,ebj->eij", T, local, T)
        return sp.coo_matrix((glob.ravel(), (rows, cols)), shape=(n_full, n_full)).tocsr()

    Nu, Nth, B, dNu = _shape_functions(length)
    k_loc = _stiffness(length, sec, B)
    K = assemble(k_loc)
    M = assemble(_mass(length, sec, Nu, Nth))

    spin = None
    if spin_axis is not None:
        e = spin_axis_unit(spin_axis)
        o = as_finite_array("spin_origin", spin_origin)
        if o.shape != (3,):
            raise ModelError("spin_origin must be a 3-vector [m]")
        spin = (e, o, nodes)
    pm = _point_masses(point_masses, n_nodes, spin)
    for node, Mb, rb in pm:
        Mb = rb.M if rb is not None else Mb
        M = M + _node_block(Mb, node, n_full)

    fixed = _parse_fixed(clamped_nodes, fixed_dofs, n_nodes)
    free = np.flatnonzero(~fixed)
    if free.size == 0:
        raise ModelError("every DOF is fixed: the model has no DOFs")

    def reduce(A):
        return A[free][:, free].tocsr()

    rotation = axial = udef = None
    if spin is not None:
        e, o, _ = spin
        el = np.einsum("eij,j->ei", Lam, e)               # spin axis in element axes
        Gt, Pt = translational_operators(el)
        J0 = _rotary_inertia(sec)
        Gr, Kr, mom = rotary_operators(el, J0)
        rhoA = sec["rhoA"][:, None, None]
        G = assemble(_integrate(length, Nu, rhoA * Gt) + _integrate(length, Nth, Gr))
        Kd = assemble(_integrate(length, Nu, rhoA * Pt) + _integrate(length, Nth, Kr))
        # centrifugal load: rho A P r(x) and the moment (J e) x e, in element axes
        r0 = np.einsum("eij,ej->ei", Lam, nodes[els[:, 0]] - o)
        r = r0[:, None, :] + (_GX[None, :, None] * length[:, None, None]) * np.eye(3)[0]
        body = sec["rhoA"][:, None, None] * np.einsum("eij,egj->egi", Pt, r)
        w = _GW[None, :] * length[:, None]
        fc_loc = (np.einsum("eg,egai,ega->ei", w, Nu, body)
                  + np.einsum("eg,egai,ea->ei", w, Nth, mom))
        fc = np.zeros(n_full)
        np.add.at(fc, el_dofs, np.einsum("eai,ea->ei", T, fc_loc))
        for node, _, rb in pm:
            G = G + _node_block(rb.G, node, n_full)
            Kd = Kd + _node_block(rb.Kd, node, n_full)
            fc[6 * node:6 * node + 6] += rb.fc
        Kw = None
        if stress_stiffening:
            udef, axial, Kw_loc = _prestress(K, fc, free, el_dofs, T, k_loc, fc_loc,
                                             length, sec, body, dNu, B)
            Kw = reduce(assemble(Kw_loc))
        rotation = RotationTerms(gyroscopic=reduce(G), spin_softening=reduce(Kd),
                                 stress_stiffening=Kw, centrifugal_load=fc[free])

    Mr, Kr_ = reduce(M), reduce(K)
    D = sp.csr_matrix(Mr.shape)
    if rayleigh is not None:
        alpha, beta = _pair("rayleigh", rayleigh, ("alpha [1/s]", "beta [s]"))
        D = (alpha * Mr + beta * Kr_).tocsr()
    elif loss_factor is not None:
        eta, omega_ref = _pair("loss_factor", loss_factor, ("eta", "omega_ref [rad/s]"))
        check_positive("loss_factor omega_ref", omega_ref, unit="rad/s")
        D = (eta / omega_ref * Kr_).tocsr()
    return BeamModel(nodes=nodes, elements=els, free_dofs=free, M=Mr, K=Kr_, D=D,
                     rotation=rotation, spin_axis=None if spin is None else spin[0],
                     spin_origin=None if spin is None else spin[1],
                     axial_force_per_omega2=axial,
                     centrifugal_displacement_per_omega2=udef, name=name)


def _pair(name, value, labels) -> tuple[float, float]:
    try:
        a, b = value
    except (TypeError, ValueError):
        raise ModelError(f"{name} must be a pair ({labels[0]}, {labels[1]}), got "
                         f"{value!r}") from None
    a = float(check_positive(f"{name} {labels[0]}", a, allow_zero=True))
    b = float(check_positive(f"{name} {labels[1]}", b, allow_zero=True))
    return a, b


def _node_block(block: np.ndarray, node: int, n_full: int) -> sp.csr_matrix:
    idx = 6 * node + np.arange(6)
    r, c = np.meshgrid(idx, idx, indexing="ij")
    return sp.csr_matrix((block.ravel(), (r.ravel(), c.ravel())), shape=(n_full, n_full))


def _prestress(K, fc, free, el_dofs, T, k_loc, fc_loc, length, sec, body, dNu, B):
    """Static centrifugal deflection, axial forces and local geometric stiffness per Omega^2.

    The element end forces ``k d - f`` of the exact nodal solution give the axial force N1 at
    node 1 (tension positive); inside the element ``N(s) = N1 - int_0^s p`` with the linear
    distributed axial load p = (rho A P r)_x.
    """
    Kff = K[free][:, free].tocsc()
    try:
        u_free = spla.splu(Kff).solve(fc[free])
    except RuntimeError:
        u_free = np.full(free.size, np.nan)
    scale = np.abs(fc).max()
    if not np.all(np.isfinite(u_free)) or (
            scale > 0 and np.abs(Kff @ u_free - fc[free]).max() > 1e-6 * scale):
        raise ModelError("stress_stiffening needs the centrifugal prestress K q = f_c, but K "
                         "is singular on the free DOFs: support the structure (clamped_nodes "
                         "or fixed_dofs) or pass stress_stiffening=False")
    u = np.zeros(K.shape[0])
    u[free] = u_free
    d_loc = np.einsum("eij,ej->ei", T, u[el_dofs])
    f_end = np.einsum("eij,ej->ei", k_loc, d_loc) - fc_loc
    N1 = -f_end[:, 0]
    p = body[:, :, 0]                                     # axial load at the Gauss points
    # p is linear in xi: recover p(0) and its slope from two Gauss points
    slope = (p[:, 1] - p[:, 0]) / (_GX[1] - _GX[0])
    p0 = p[:, 0] - slope * _GX[0]
    xi = _GX[None, :]
    N = N1[:, None] - length[:, None] * (p0[:, None] * xi + 0.5 * slope[:, None] * xi**2)
    N_end = N1 - length * (p0 + 0.5 * slope)
    A = np.broadcast_to(N[:, :, None, None] * np.eye(3), N.shape + (3, 3))
    twist = N[:, :, None, None] * sec["Ip_over_A"][:, None, None, None]
    Kw = _integrate(length, dNu, A) + _integrate(length, B[:, :, 3:4], twist)
    return (u.reshape(-1, 6), np.stack([N1, N_end], axis=1), Kw)
