"""Paper-003 bladed wheel as a parametric 3D solid sector, meshed with gmsh (tet10).

The beam model :mod:`fricdamp.models.tieboss_wheel.model` reduces the wheel of paper 003 to
beams; this module builds the same wheel as a solid: one sector of the 30, meshed with
second-order tetrahedra by gmsh (OpenCASCADE kernel), its cut faces and its tie-boss
contact faces meshed periodically so that neighbouring sectors match node for node.

Geometry (SI; wheel axis z; sector 0 centred on +x; ``alpha = 2 pi / N``, ``h = alpha/2``)
--------------------------------------------------------------------------------------------
* **disk**: the annular sector ``clamp_radius_m <= r <= rim_radius_m``, ``|theta| <= h``,
  ``|z| <= disk_thickness_m / 2``. Its inner cylindrical face is the group ``clamp`` (all
  DOFs fixed: the hub of 003 section 1.1); its side faces ``theta = -h, +h`` are
  ``cut_left`` and ``cut_right``.
* **root**: a block standing for the two 45-degree finger consoles of 003 section 1.1, from
  ``rim_radius_m - root_embedding_m`` (inside the disk) to ``root_radius_m``, of
  ``root_width_m`` along the blade chord and ``root_thickness_m`` along its normal.
* **blade**: a plate from ``root_radius_m`` to ``tip_radius_m``, ``blade_width_m`` x
  ``blade_thickness_m``, whose plane contains the radial x-axis at ``blade_angle_deg`` to the
  wheel plane: chord ``c = (0, cos b, -sin b)``, flexural direction (normal to the blade,
  the plane alpha_0 of 003) ``d = (0, sin b, cos b)``, the convention of the beam model:
  the flexural motion then lies in the contact planes, "to allow the blade to move freely
  during flexural vibrations" (003 section 1.1); the mirror chord ``(0, cos b, sin b)``
  would make it normal to them.
* **tie-boss** at ``tieboss_radius_m`` (003: 0.44 m): a boss around the blade (a box
  ``boss_radial_m`` x ``boss_width_m`` (chord) x ``boss_thickness_m`` (along d), the nuts of
  the suspension bolt) and two shoulders. The right contact face ``F_R`` is a square of side
  ``contact_face_size_m`` on the cutting plane beta_B of 003 Fig. 2 (through the mid radial
  ``zeta_B = e_r(h)``, perpendicular to the wheel plane and turned by
  ``contact_plane_angle_deg`` about ``zeta_B``), centred at ``r_tb e_r(h)``, its edges along
  ``t1 = e_r(h)`` and ``t2 = sin(b) e_t(h) + cos(b) e_z``; its normal is
  ``n = cos(b) e_t(h) - sin(b) e_z`` (:func:`fricdamp.models.tieboss_wheel.model.contact_frame`).
  The left face ``F_L`` is ``F_R`` rotated by ``-alpha`` about z, so sector j's right face
  is sector j+1's left face. Each shoulder is the oblique prism swept from its face to the
  centre of the boss (nearly along ``-/+ e_t``, like the suspension bolt of 003); its end
  face is cut by the cutting plane "at a certain angle" (003 section 1.1).
* **tip mass**: the weights bolted on both faces of the blade end (003 section 1.1): the
  block ``tipmass_length_m`` (radial, ending at ``tip_radius_m``) x ``blade_width_m`` x
  ``tipmass_thickness_m`` (along d) less the blade, its own volume ``tipmass`` of density
  ``tipmass_density_kg_m3`` (a tuning knob standing for their mass, ~0.42 kg as the beam
  model's ``tip_mass_kg``; its centre of mass is ``tipmass_length_m / 2`` inside the tip).

Every part beyond the rim lies between the sector's two cutting planes
(:func:`~fricdamp.models.tieboss_wheel._solid_geometry.check_clearance`), so neighbours never
overlap at rest.

Groups of the mesh: surfaces ``clamp``, ``cut_left``, ``cut_right``, ``contact_left``,
``contact_right``; volumes ``steel``, ``tipmass``; points ``probe`` (centre of ``F_R``, where
the paper reads its contact nodes, N165136 etc., "in the midst of each contact surface"),
``probe_left`` (centre of ``F_L``), ``tip`` (centre of the blade tip section) and ``load``
(two nodes: the centres of the boss faces normal to d, the "two nodes of the tie-boss prism
of each blade" where 003 section 3 applies its modal forces).

Mesh: tet10 with straight edges (``Mesh.SecondOrderLinear``: mid-side nodes at the edge
midpoints), global size ``mesh_size_m``, Netgen-optimised (no flat slivers in the blade).
The right cut and contact faces are meshed as the left ones rotated by ``alpha``
(``gmsh.model.mesh.setPeriodic``), checked node by node after meshing. The contact faces
are structured (``contact_divisions`` cells per side: 49 nodes per face by default) so
that their centres are nodes. Default (6 mm): 7,600 tet10, 41,800 DOFs per clamped sector
(paper 003: 89,000 hexahedra for the wheel, ~3,000 per sector); ``mesh_size_m = 0.0037``
gives 110,000 DOFs.

Model and tuning
----------------
:func:`build_solid_sector` assembles the sector (:func:`fricdamp.structure.solid.
assemble_solid`, steel E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3, the tip mass at its own
density), removes the clamped DOFs and returns a :class:`SolidSector`: the
:class:`~fricdamp.structure.cyclic.CyclicSector` (Cartesian frames about z) with the named
DOF groups ``contact_left``, ``contact_right``, ``probe``, ``probe_left``, ``load`` and
``tip``, and the :class:`~fricdamp.models.contact_wheel.WheelSector` (contact patch,
Rayleigh damping) of the contact-wheel pipeline.

The paper gives no disk dimensions; :func:`tune_solid_parameters` fits the disk thickness,
the clamp radius and the tip-mass density to the open-contact first family of 003 Table 1
(FEM column, pair means at 2-6 ND; 50.3 Hz at 15 ND), on the default mesh. Result (the
defaults): ``disk_thickness_m = 10.22 mm``, ``clamp_radius_m = 0.1574 m``,
``tipmass_density_kg_m3 = 24130`` (tip mass 0.463 kg at r = 0.492 m, as the beam model's
0.42 kg at 0.50 m for the blade's first mode):

====  ==========  ==========  ======
ND    model [Hz]  003 [Hz]    error
====  ==========  ==========  ======
0     43.53       --
1     43.73       --
2     44.51       44.355      +0.35 %
3     45.89       46.17       -0.61 %
4     47.29       47.395      -0.22 %
5     48.29       48.16       +0.27 %
6     48.91       48.56       +0.72 %
10    49.85       --
15    50.06       50.3        -0.48 %
====  ==========  ==========  ======

The family rises monotonically with ND, as in the paper (the disk's out-of-plane stiffness
grows with ND). Mesh convergence: the coarse 12 mm mesh is 0.35-0.41 % stiffer than the
default, a 3.7 mm mesh (110,000 DOFs) 0.17-0.19 % softer. Checked by
``tests/validation/test_tieboss_solid_modal.py``.
"""

from __future__ import annotations

import functools
import logging
import os
import tempfile
import time
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from fricdamp.errors import ModelError, check_positive, check_range
from fricdamp.models.contact_wheel import WheelSector, rayleigh_coefficients, sector_from_solid
from fricdamp.models.tieboss_wheel._solid_geometry import (
    blade_axes,
    contact_geometry,
    mesh_sector_msh,
    rotation_z,
)
from fricdamp.models.tieboss_wheel.model import TABLE1_FEM_HZ, table1_targets
from fricdamp.structure.cyclic import CyclicSector, nodal_diameter_modes

__all__ = [
    "TABLE1_FEM_HZ",
    "SolidSector",
    "SolidWheelParameters",
    "assemble_sector_model",
    "build_sector_mesh",
    "build_solid_sector",
    "first_family_frequencies",
    "match_periodic_nodes",
    "tune_solid_parameters",
]

log = logging.getLogger(__name__)


# ------------------------------------------------------------------------------ parameters
@dataclass(frozen=True)
class SolidWheelParameters:
    """Parameters of the solid tie-boss sector (SI units; angles in degrees by name).

    Defaults: the paper's data (30 blades, tie-boss at r = 0.44 m, 45-degree blades and
    contact planes), the beam model's blade (0.30-0.50 m, 40 x 6 mm), documented choices
    for what the paper does not give, and the disk, root and tip mass tuned to Table 1
    (:func:`tune_solid_parameters`).

    Attributes
    ----------
    n_blades : int
        Number of blades (sectors) N >= 3 (003: 30).
    clamp_radius_m, rim_radius_m : float
        Clamped inner radius and outer radius of the disk [m].
    disk_thickness_m : float
        Axial thickness of the disk [m].
    root_radius_m, root_width_m, root_thickness_m, root_embedding_m : float
        Root block (the consoles): outer radius (= blade root) [m], size along the chord
        and along the flexural direction [m], depth inside the disk [m].
    tieboss_radius_m, tip_radius_m : float
        Radius of the tie-boss (003: 0.44 m) and of the blade tip [m].
    blade_width_m, blade_thickness_m : float
        Blade chord and thickness [m].
    blade_angle_deg, contact_plane_angle_deg : float
        Angle of the blade plane to the wheel plane and of the cutting planes (003: 45 and
        45) [deg], in [0, 90) and [0, 90).
    boss_radial_m, boss_width_m, boss_thickness_m : float
        Boss box: radial size, size along the chord, size along the flexural direction [m].
    contact_face_size_m : float
        Side of the square contact faces [m].
    tipmass_length_m, tipmass_thickness_m : float
        Tip-mass block around the blade end: radial length and size along the flexural
        direction [m] (> blade thickness; its chord is the blade's).
    tipmass_density_kg_m3 : float
        Density of the tip-mass block [kg/m^3] (sets its mass).
    young_modulus_Pa, poisson_ratio, density_kg_m3 : float
        Steel (also the tip-mass stiffness).
    damping_ratio : float
        Material damping ratio [-] (003: 0.1 %), Rayleigh, equal at ``damping_band_hz``.
    damping_band_hz : (float, float)
        The two frequencies [Hz] of the Rayleigh damping, ``0 < f1 < f2``.
    mesh_size_m : float
        Largest element edge [m], in [1.5 mm, 30 mm].
    contact_divisions : int
        Cells per edge of the structured contact faces, in [2, 8] (3: 18 triangles, 49
        nodes per face; 2: 25 nodes).
    """

    n_blades: int = 30
    clamp_radius_m: float = 0.1574
    rim_radius_m: float = 0.28
    disk_thickness_m: float = 0.01022
    root_radius_m: float = 0.30
    root_width_m: float = 0.040
    root_thickness_m: float = 0.014
    root_embedding_m: float = 0.006
    tieboss_radius_m: float = 0.44
    tip_radius_m: float = 0.50
    blade_width_m: float = 0.040
    blade_thickness_m: float = 0.006
    blade_angle_deg: float = 45.0
    contact_plane_angle_deg: float = 45.0
    boss_radial_m: float = 0.012
    boss_width_m: float = 0.024
    boss_thickness_m: float = 0.016
    contact_face_size_m: float = 0.010
    tipmass_length_m: float = 0.016
    tipmass_thickness_m: float = 0.036
    tipmass_density_kg_m3: float = 24130.0
    young_modulus_Pa: float = 2.1e11
    poisson_ratio: float = 0.3
    density_kg_m3: float = 7850.0
    damping_ratio: float = 1.0e-3
    damping_band_hz: tuple[float, float] = (40.0, 60.0)
    mesh_size_m: float = 0.006
    contact_divisions: int = 3

    def __post_init__(self):
        n = self.n_blades
        if isinstance(n, bool) or int(n) != n or n < 3:
            raise ModelError(f"n_blades must be an integer >= 3, got {n!r}")
        object.__setattr__(self, "n_blades", int(n))
        for name in ("clamp_radius_m", "rim_radius_m", "disk_thickness_m", "root_radius_m",
                     "root_width_m", "root_thickness_m", "root_embedding_m",
                     "tieboss_radius_m", "tip_radius_m", "blade_width_m",
                     "blade_thickness_m", "boss_radial_m", "boss_width_m",
                     "boss_thickness_m", "contact_face_size_m", "tipmass_length_m",
                     "tipmass_thickness_m", "tipmass_density_kg_m3", "young_modulus_Pa",
                     "density_kg_m3"):
            unit = name.rsplit("_", 1)[-1].replace("kg", "kg/").replace("m3", "m^3")
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name),
                                                                unit=unit)))
        if not (self.clamp_radius_m < self.rim_radius_m < self.root_radius_m
                < self.tieboss_radius_m < self.tip_radius_m):
            raise ModelError(
                "radii must satisfy clamp_radius_m < rim_radius_m < root_radius_m < "
                f"tieboss_radius_m < tip_radius_m, got {self.clamp_radius_m}, "
                f"{self.rim_radius_m}, {self.root_radius_m}, {self.tieboss_radius_m}, "
                f"{self.tip_radius_m} m")
        for name in ("blade_angle_deg", "contact_plane_angle_deg"):
            object.__setattr__(self, name, float(check_range(
                name, getattr(self, name), 0.0, 90.0, unit="deg", high_open=True)))
        object.__setattr__(self, "poisson_ratio", float(check_range(
            "poisson_ratio", self.poisson_ratio, 0.0, 0.5, high_open=True)))
        spans = {"root_embedding_m": (self.root_embedding_m,
                                      0.5 * (self.rim_radius_m - self.clamp_radius_m)),
                 "boss_radial_m": (self.boss_radial_m, 2.0 * min(
                     self.tieboss_radius_m - self.root_radius_m,
                     self.tip_radius_m - self.tieboss_radius_m)),
                 "contact_face_size_m": (self.contact_face_size_m, self.boss_radial_m),
                 "tipmass_length_m": (self.tipmass_length_m,
                                      self.tip_radius_m - self.tieboss_radius_m
                                      - self.boss_radial_m / 2)}
        for name, (value, high) in spans.items():
            check_range(name, value, 0.0, high, unit="m", low_open=True, high_open=True)
        if self.tipmass_thickness_m <= self.blade_thickness_m:
            raise ModelError(f"tipmass_thickness_m must be > blade_thickness_m = "
                             f"{self.blade_thickness_m} m, got {self.tipmass_thickness_m}")
        object.__setattr__(self, "mesh_size_m", float(check_range(
            "mesh_size_m", self.mesh_size_m, 0.0015, 0.030, unit="m")))
        object.__setattr__(self, "damping_ratio", float(check_range(
            "damping_ratio", self.damping_ratio, 0.0, 1.0, high_open=True)))
        band = tuple(float(v) for v in np.ravel(self.damping_band_hz))
        if len(band) != 2 or not 0.0 < band[0] < band[1] or not np.isfinite(band[1]):
            raise ModelError(f"damping_band_hz must be two frequencies 0 < f1 < f2 [Hz], got "
                             f"{self.damping_band_hz!r}")
        object.__setattr__(self, "damping_band_hz", band)
        k = self.contact_divisions
        if isinstance(k, bool) or int(k) != k or not 2 <= k <= 8:
            raise ModelError(f"contact_divisions must be an integer in [2, 8], got {k!r}")
        object.__setattr__(self, "contact_divisions", int(k))

    # ---------------------------------------------------------------- derived
    @property
    def sector_angle_rad(self) -> float:
        """Blade pitch ``alpha = 2 pi / N`` [rad]."""
        return 2.0 * np.pi / self.n_blades

    @property
    def contact_mesh_size(self) -> float:
        """Element edge along the contact-face sides [m]."""
        return self.contact_face_size_m / self.contact_divisions

    @property
    def tipmass_volume_m3(self) -> float:
        """Volume of the tip-mass block less the blade [m^3]."""
        return self.tipmass_length_m * self.blade_width_m * (self.tipmass_thickness_m
                                                              - self.blade_thickness_m)

    @property
    def tipmass_kg(self) -> float:
        """Mass of the tip-mass block [kg]."""
        return self.tipmass_density_kg_m3 * self.tipmass_volume_m3

    def with_(self, **changes) -> SolidWheelParameters:
        """Copy with some parameters changed (validated again)."""
        return replace(self, **changes)

    def to_dict(self) -> dict:
        """Plain dict (JSON-ready) of all parameters."""
        d = asdict(self)
        d["damping_band_hz"] = list(self.damping_band_hz)
        return d

    def geometry_key(self) -> SolidWheelParameters:
        """The parameters that set the mesh (material entries reset to the defaults)."""
        d = SolidWheelParameters.__dataclass_fields__
        return replace(self, **{k: d[k].default for k in _MATERIAL_FIELDS})


_MATERIAL_FIELDS = ("tipmass_density_kg_m3", "young_modulus_Pa", "poisson_ratio",
                    "density_kg_m3", "damping_ratio", "damping_band_hz")


# ------------------------------------------------------------------------------ mesh
@functools.lru_cache(maxsize=8)
def _mesh_cached(key: SolidWheelParameters):
    """(``.msh`` text, read-only SolidMesh) of a geometry, periodicity checked."""
    import meshio

    from fricdamp.structure.solid import mesh_from_meshio

    msh = mesh_sector_msh(key)
    with tempfile.TemporaryDirectory(prefix="fricdamp_tieboss_") as tmp:
        path = os.path.join(tmp, "sector.msh")
        with open(path, "w", encoding="ascii") as fh:
            fh.write(msh.text)
        mesh = mesh_from_meshio(meshio.read(path, file_format="gmsh"))
    for right, left in (("cut_right", "cut_left"), ("contact_right", "contact_left")):
        match_periodic_nodes(mesh.points, mesh.point_sets[left], mesh.point_sets[right],
                             key.sector_angle_rad)
    for arr in (mesh.points, mesh.cells, *mesh.point_sets.values(),
                *mesh.cell_sets.values()):
        arr.flags.writeable = False          # shared by every caller of the cache
    return msh, mesh


def match_periodic_nodes(points, left, right, sector_angle: float, *,
                         tol: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    """Order two node sets so that ``points[right[k]] = R points[left[k]]``.

    Parameters
    ----------
    points : array_like, shape (n_nodes, 3)
        Node coordinates [m].
    left, right : array_like of int
        Node indices of the left and right faces.
    sector_angle : float
        Rotation angle alpha [rad] about z.
    tol : float
        Largest allowed distance [m] between a right node and its rotated left partner.

    Returns
    -------
    left, right : ndarray of int, shape (n,)
        The pairs, in the order of ``left`` sorted.

    Raises
    ------
    ModelError
        If the faces do not match node to node within ``tol``.
    """
    from scipy.spatial import cKDTree

    x = np.asarray(points, dtype=float)
    left = np.sort(np.asarray(left, dtype=np.int64))
    right = np.asarray(right, dtype=np.int64)
    if left.size != right.size or left.size == 0:
        raise ModelError(f"periodic faces must have the same number (>= 1) of nodes, got "
                         f"{left.size} (left) and {right.size} (right)")
    rotated = x[left] @ rotation_z(sector_angle).T
    dist, idx = cKDTree(x[right]).query(rotated)
    if dist.max() > tol or np.unique(idx).size != idx.size:
        raise ModelError(f"the right face is not the left face rotated by the sector angle "
                         f"node for node (largest distance {dist.max():.3g} m > {tol:.3g} m)")
    return left, right[idx]


def build_sector_mesh(params: SolidWheelParameters | None = None, path=None):
    """Mesh one sector (tet10, periodic cut and contact faces) with gmsh.

    Meshes are cached in-process per geometry (the material entries do not count): a
    second call with the same geometry returns the same read-only mesh.

    Parameters
    ----------
    params : SolidWheelParameters, optional
        Geometry and mesh sizes (default: the tuned defaults).
    path : str or path-like, optional
        Also write the mesh there (gmsh format 4.1, ASCII; :func:`~fricdamp.structure.
        solid.read_mesh` reads it back).

    Returns
    -------
    SolidMesh
        ``tetra10`` cells (meshio node order), points [m]; ``point_sets`` for every group
        (module docstring: the surface, volume and point groups), ``cell_sets`` for the
        volumes ``steel`` and ``tipmass``.

    Raises
    ------
    ModelError
        If the parameters give an invalid geometry, gmsh fails or the periodic faces do not
        match node for node (1e-9 m).

    Examples
    --------
    >>> mesh = build_sector_mesh(SolidWheelParameters(mesh_size_m=0.012))
    >>> [mesh.point_sets[g].size for g in ("contact_left", "contact_right", "load")]
    [49, 49, 2]
    """
    p = SolidWheelParameters() if params is None else params
    if not isinstance(p, SolidWheelParameters):
        raise ModelError(f"params must be SolidWheelParameters, got {type(p).__name__}")
    msh, mesh = _mesh_cached(p.geometry_key())
    if path is not None:
        with open(path, "w", encoding="ascii") as fh:
            fh.write(msh.text)
    return mesh


def contact_centres(params: SolidWheelParameters | None = None):
    """Centres [m] of the right and left contact faces of sector 0, shapes (3,)."""
    g = contact_geometry(SolidWheelParameters() if params is None else params)
    return g.centre_right, g.centre_left


# ------------------------------------------------------------------------------ model
def assemble_sector_model(params: SolidWheelParameters | None = None, *,
                          split_by_set: bool = True):
    """Mesh and assemble the sector (no supports): a :class:`~fricdamp.structure.solid.
    SolidModel` with steel everywhere but the ``tipmass`` volume.

    With ``split_by_set`` the model keeps the parts ``"rest"`` (steel) and ``"tipmass"``
    so that a new tip-mass density costs a sum of matrices
    (:meth:`~fricdamp.structure.solid.SolidModel.with_scaled_parts`), not an assembly.
    """
    from fricdamp.structure.solid import assemble_solid

    p = SolidWheelParameters() if params is None else params
    return assemble_solid(build_sector_mesh(p), youngs_modulus=p.young_modulus_Pa,
                          poisson_ratio=p.poisson_ratio, density=p.density_kg_m3,
                          materials={"tipmass": {"density": p.tipmass_density_kg_m3}},
                          split_by_set=split_by_set)


@dataclass(frozen=True, eq=False)
class SolidSector:
    """One solid sector of the tie-boss wheel, clamped, ready for the cyclic pipeline.

    Attributes
    ----------
    model : SolidModel
        The assembled sector without supports (all FE nodes, mid-side nodes included).
    cyclic : CyclicSector
        Clamped sector: ``n_dof = 3 (n_nodes - n_clamped)``, Cartesian frames about z, cuts
        ordered so that ``right[k]`` is ``left[k]`` rotated by ``+alpha``. Named DOF
        groups (x, y, z triples, reduced numbering): ``contact_left``, ``contact_right``
        (pair k of the right face is node k of both lists), ``probe``, ``probe_left``,
        ``load`` (2 nodes) and ``tip``.
    wheel_sector : WheelSector
        The same sector with its contact patch and Rayleigh damping, for
        :func:`fricdamp.models.contact_wheel.build_contact_wheel`.
    parameters : SolidWheelParameters
    kept_dofs : ndarray of int, shape (cyclic.n_dof,)
        DOF of ``model`` of each reduced DOF (``reduced -> model``).
    frame : ndarray, shape (3, 3)
        Rows ``(n, t1, t2)`` of the right contact face (n into the next sector).
    flexural_direction : ndarray, shape (3,)
        Unit normal of blade 0's plane (the direction of the first-family motion).
    timings : dict of str to float
        Seconds spent meshing (0 when cached) and assembling.
    """

    model: object
    cyclic: CyclicSector
    wheel_sector: WheelSector
    parameters: SolidWheelParameters
    kept_dofs: np.ndarray
    frame: np.ndarray
    flexural_direction: np.ndarray
    timings: dict = field(default_factory=dict)

    @property
    def n_dof(self) -> int:
        """DOFs of the clamped sector."""
        return self.cyclic.n_dof

    def group_nodes(self, name: str) -> np.ndarray:
        """FE nodes (of :attr:`model`) of a named DOF group, in the group's triple order."""
        if name not in self.cyclic.named_dofs:
            raise ModelError(f"unknown group {name!r}; the sector has "
                             f"{sorted(self.cyclic.named_dofs)}")
        return self.kept_dofs[self.cyclic.named_dofs[name][0::3]] // 3

    def group_points(self, name: str) -> np.ndarray:
        """Coordinates [m] of the nodes of a named DOF group, shape (n, 3)."""
        return self.model.points[self.group_nodes(name)]

    def contact_facets(self, side: str = "right") -> np.ndarray:
        """tri6 facets (FE nodes of :attr:`model`, outward) of a contact face, (n, 6)."""
        if side not in ("left", "right"):
            raise ModelError(f"side must be 'left' or 'right', got {side!r}")
        return self.model.surface_facets(f"contact_{side}")


def _solid_sector(p: SolidWheelParameters, model, timings: dict) -> SolidSector:
    n_nodes = model.n_nodes
    fixed = np.zeros(n_nodes, dtype=bool)
    fixed[model.node_sets["clamp"]] = True
    kept = np.sort(model.dofs[~fixed].ravel())
    _, d = blade_axes(p.blade_angle_deg)
    g = contact_geometry(p)
    info = {"tetrahedra": int(model.n_elements), "mesh_size_m": p.mesh_size_m,
            "contact_nodes_per_face": int(model.node_sets["contact_right"].size)}
    ws = sector_from_solid(model, n_sectors=p.n_blades, youngs_modulus=p.young_modulus_Pa,
                           probe_direction=d,
                           rayleigh=rayleigh_coefficients(p.damping_ratio, p.damping_band_hz),
                           info=info)
    if ws.cyclic.n_dof != kept.size:
        raise ModelError(f"internal: {ws.cyclic.n_dof} sector DOFs, expected {kept.size}")
    pos = np.full(model.n_dof, -1, dtype=np.int64)
    pos[kept] = np.arange(kept.size)
    named = dict(ws.cyclic.named_dofs)
    for name in ("tip", "probe_left"):
        named[name] = pos[model.dofs[model.node_sets[name]].ravel()]
    cyc = replace(ws.cyclic, named_dofs=named, name="solid tie-boss sector")
    return SolidSector(model=model, cyclic=cyc, wheel_sector=replace(ws, cyclic=cyc),
                       parameters=p, kept_dofs=kept, frame=g.frame_right,
                       flexural_direction=d, timings=dict(timings))


def build_solid_sector(params: SolidWheelParameters | None = None) -> SolidSector:
    """Mesh, assemble and clamp the solid tie-boss sector (module docstring).

    Parameters
    ----------
    params : SolidWheelParameters, optional
        Default: the tuned defaults.

    Returns
    -------
    SolidSector

    Raises
    ------
    ModelError
        Invalid geometry, meshing failure or non-periodic faces.
    """
    p = SolidWheelParameters() if params is None else params
    if not isinstance(p, SolidWheelParameters):
        raise ModelError(f"params must be SolidWheelParameters, got {type(p).__name__}")
    t0 = time.perf_counter()
    cached = _mesh_cached.cache_info().hits
    build_sector_mesh(p)
    t_mesh = 0.0 if _mesh_cached.cache_info().hits > cached else time.perf_counter() - t0
    t1 = time.perf_counter()
    model = assemble_sector_model(p)
    timings = {"mesh_s": t_mesh, "assembly_s": time.perf_counter() - t1}
    return _solid_sector(p, model, timings)


def first_family_frequencies(sector: SolidSector, nds=(2, 3, 4, 5, 6, 15), *,
                             timings: dict | None = None) -> dict[int, float]:
    """First eigenfrequency [Hz] of each nodal diameter, open contacts.

    The lowest mode of each ND is the first (blade flexural) family: cyclic modal
    analysis of the clamped sector (:func:`~fricdamp.structure.cyclic.nodal_diameter_modes`,
    sparse shift-invert). ``timings``, if given, receives the seconds per ND.
    """
    out = {}
    for nd in nds:
        t0 = time.perf_counter()
        out[int(nd)] = float(nodal_diameter_modes(sector.cyclic, int(nd), 1,
                                                  method="sparse").frequencies[0])
        if timings is not None:
            timings[int(nd)] = time.perf_counter() - t0
    return out


# ------------------------------------------------------------------------------ tuning
_DENSITY_ONLY = ("tipmass_density_kg_m3",)


def tune_solid_parameters(params: SolidWheelParameters | None = None, *,
                          names=("disk_thickness_m", "clamp_radius_m",
                                 "tipmass_density_kg_m3"),
                          targets: dict[int, float] | None = None, bounds=None,
                          max_evaluations: int = 40,
                          diff_step: float = 0.02) -> tuple[SolidWheelParameters, dict]:
    """Tune geometry and tip-mass density so the first family matches Table 1.

    Least squares (``scipy.optimize.least_squares``, trust region, bounded) on the relative
    errors ``f(nd) / f_target(nd) - 1`` of :func:`first_family_frequencies`, in the
    variables ``1 + log(p / p_start)`` (so the step is a relative change of p). A change
    of the tip-mass density alone re-uses the assembled parts
    (``SolidModel.with_scaled_parts``); a geometric change re-meshes, so the frequencies
    carry a small remeshing noise (~0.05 %): the relative finite-difference step
    ``diff_step`` is kept well above it.

    Parameters
    ----------
    params : SolidWheelParameters, optional
        Start values (default: the defaults).
    names : sequence of str
        Float parameters tuned.
    targets : dict nd -> Hz, optional
        Default :func:`fricdamp.models.tieboss_wheel.model.table1_targets` (pair means of the FEM
        column of Table 1 at 2-6 ND, 50.3 Hz at 15 ND).
    bounds : (sequence, sequence), optional
        Lower and upper bounds (default: a factor 2 around the start values).
    max_evaluations : int
        Budget of frequency evaluations (each: one sector, ``len(targets)`` eigen-solves).
    diff_step : float
        Relative finite-difference step.

    Returns
    -------
    params : SolidWheelParameters
    report : dict
        ``nd``, ``target_hz``, ``model_hz``, ``relative_error``, ``tuned`` and
        ``evaluations``.
    """
    from scipy.optimize import least_squares

    p0 = SolidWheelParameters() if params is None else params
    tg = table1_targets() if targets is None else {int(k): float(v)
                                                   for k, v in targets.items()}
    nds = sorted(tg)
    if max(nds) > p0.n_blades // 2:
        raise ModelError(f"targets hold nd = {max(nds)} > N/2 = {p0.n_blades // 2}")
    names = tuple(names)
    for nm in names:
        if nm not in SolidWheelParameters.__dataclass_fields__ or not isinstance(
                getattr(p0, nm), float):
            raise ModelError(f"cannot tune {nm!r}: not a float parameter")
    start = np.array([getattr(p0, nm) for nm in names])
    lo, hi = (np.full(len(names), 1.0 - np.log(2.0)), np.full(len(names), 1.0 + np.log(2.0))) \
        if bounds is None else (1.0 + np.log(np.asarray(bounds[0], float) / start),
                                1.0 + np.log(np.asarray(bounds[1], float) / start))
    ft = np.array([tg[nd] for nd in nds])
    state = {"key": None, "model": None, "n": 0}

    def make(x):
        return p0.with_(**dict(zip(names, (float(v) for v in start * np.exp(x - 1.0)),
                                   strict=True)))

    def frequencies(p):
        if state["key"] != p.geometry_key():
            state["key"] = p.geometry_key()
            state["model"] = assemble_sector_model(p)
            state["rho"] = p.tipmass_density_kg_m3
        model = state["model"].with_scaled_parts(
            mass={"tipmass": p.tipmass_density_kg_m3 / state["rho"]})
        state["n"] += 1
        f = first_family_frequencies(_solid_sector(p, model, {}), nds)
        res = np.array([f[nd] for nd in nds])
        log.info("tune %d: %s -> %s Hz", state["n"],
                 {nm: round(getattr(p, nm), 6) for nm in names}, np.round(res, 3).tolist())
        return res

    def residual(x):
        return frequencies(make(x)) / ft - 1.0

    sol = least_squares(residual, np.clip(np.ones(len(names)), lo, hi), bounds=(lo, hi),
                        diff_step=diff_step, x_scale=1.0, max_nfev=int(max_evaluations))
    tuned = make(sol.x)
    fm = frequencies(tuned)
    report = {"nd": nds, "target_hz": ft.tolist(), "model_hz": fm.tolist(),
              "relative_error": (fm / ft - 1.0).tolist(),
              "tuned": {nm: getattr(tuned, nm) for nm in names},
              "tipmass_kg": tuned.tipmass_kg, "evaluations": state["n"]}
    return tuned, report
