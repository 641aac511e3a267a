"""Gmsh (OpenCASCADE) geometry and periodic tet10 mesh of one solid tie-boss sector.

Private helper of :mod:`fricdamp.models.tieboss_wheel.solid`: builds the sector described in its
module docstring from a :class:`~fricdamp.models.tieboss_wheel.solid.SolidWheelParameters`, meshes
it with second-order tetrahedra whose cut faces and contact faces are periodic (the right
face is the left face rotated by the sector angle, node for node) and returns the ``.msh``
text (format 4.1, ASCII). Gmsh is imported, initialised and finalised inside
:func:`mesh_sector_msh` only; a caller's own gmsh session is left as it was.
"""

from __future__ import annotations

import logging
import os
import tempfile
import time
from dataclasses import dataclass

import numpy as np

from fricdamp.errors import ModelError

log = logging.getLogger(__name__)

_EZ = np.array([0.0, 0.0, 1.0])


def e_r(angle: float) -> np.ndarray:
    """Radial unit vector at ``angle`` [rad] about z."""
    return np.array([np.cos(angle), np.sin(angle), 0.0])


def e_t(angle: float) -> np.ndarray:
    """Tangential unit vector at ``angle`` [rad] about z."""
    return np.array([-np.sin(angle), np.cos(angle), 0.0])


def rotation_z(angle: float) -> np.ndarray:
    """3 x 3 rotation by ``angle`` [rad] about z."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def blade_axes(blade_angle_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Chord direction ``c`` and flexural direction ``d`` of the blade of sector 0.

    The blade plane contains the radial x-axis at ``blade_angle_deg`` to the wheel plane:
    ``c = (0, cos b, -sin b)``, ``d = (0, sin b, cos b)`` (as in the beam model, so the
    flexural motion lies in the 45-degree contact plane).
    """
    b = np.deg2rad(blade_angle_deg)
    return np.array([0.0, np.cos(b), -np.sin(b)]), np.array([0.0, np.sin(b), np.cos(b)])


@dataclass(frozen=True)
class ContactGeometry:
    """The two contact faces of sector 0 (square faces on the cutting planes of 003 Fig. 2).

    Attributes
    ----------
    centre_right, centre_left : ndarray, shape (3,)
        Face centres [m]: ``r_tb e_r(+h)`` and its image rotated by ``-alpha``.
    frame_right : ndarray, shape (3, 3)
        Rows ``(n, t1, t2)`` of the right face: ``n = cos(b) e_t(h) - sin(b) e_z`` (pointing
        into the next sector), ``t1 = e_r(h)``, ``t2 = sin(b) e_t(h) + cos(b) e_z``.
    frame_left : ndarray, shape (3, 3)
        The same rows rotated by ``-alpha`` (the left face's ``n`` points into the sector).
    """

    centre_right: np.ndarray
    centre_left: np.ndarray
    frame_right: np.ndarray
    frame_left: np.ndarray


def contact_geometry(p) -> ContactGeometry:
    """Contact faces of sector 0 for the parameters ``p`` (:class:`ContactGeometry`)."""
    h = 0.5 * p.sector_angle_rad
    b = np.deg2rad(p.contact_plane_angle_deg)
    frame = np.stack([np.cos(b) * e_t(h) - np.sin(b) * _EZ, e_r(h),
                      np.sin(b) * e_t(h) + np.cos(b) * _EZ])
    Rm = rotation_z(-p.sector_angle_rad)
    c_r = p.tieboss_radius_m * e_r(h)
    return ContactGeometry(centre_right=c_r, centre_left=Rm @ c_r, frame_right=frame,
                           frame_left=frame @ Rm.T)


def _box_corners(x0, x1, width, thickness, c, d) -> np.ndarray:
    """Corners (8, 3) of a box along x of chord ``width`` and ``thickness`` in the blade axes."""
    return np.array([[x, 0, 0] + s * width / 2 * c + t * thickness / 2 * d
                     for x in (x0, x1) for s in (-1, 1) for t in (-1, 1)])


def check_clearance(p) -> None:
    """Raise ModelError if a part of the sector outside the disk crosses a contact plane.

    Each sector must lie between its two cutting planes (normal ``n_L`` and ``n_R``
    through the wheel centre) beyond the rim, or it would overlap its neighbours.
    """
    c, d = blade_axes(p.blade_angle_deg)
    g = contact_geometry(p)
    n_r, n_l = g.frame_right[0], g.frame_left[0]
    parts = {
        "root_width_m/root_thickness_m": (p.rim_radius_m, p.root_radius_m, p.root_width_m,
                                          p.root_thickness_m),
        "blade_width_m/blade_thickness_m": (p.root_radius_m, p.tip_radius_m, p.blade_width_m,
                                            p.blade_thickness_m),
        "boss_width_m/boss_thickness_m": (p.tieboss_radius_m - p.boss_radial_m / 2,
                                          p.tieboss_radius_m + p.boss_radial_m / 2,
                                          p.boss_width_m, p.boss_thickness_m),
        "tipmass_thickness_m": (p.tip_radius_m - p.tipmass_length_m, p.tip_radius_m,
                                p.blade_width_m, p.tipmass_thickness_m),
    }
    for names, (x0, x1, w, t) in parts.items():
        xyz = _box_corners(x0, x1, w, t, c, d)
        worst = max(float(np.max(xyz @ n_r)), float(np.max(-(xyz @ n_l))))
        if worst >= 0.0:
            raise ModelError(f"{names} too large: the part reaches {worst * 1e3:.2f} mm beyond "
                             "the contact plane into the neighbouring sector; make it smaller")


# ------------------------------------------------------------------------------ gmsh
_OPTIONS = {
    "General.Terminal": 0,
    "General.NumThreads": 1,
    "Mesh.ElementOrder": 2,
    "Mesh.SecondOrderLinear": 1,
    "Mesh.MshFileVersion": 4.1,
    "Mesh.Binary": 0,
    "Mesh.SaveAll": 0,
    "Mesh.MeshSizeFromCurvature": 0,
    "Mesh.Optimize": 1,
    # Netgen's optimiser removes the flat slivers of the one-layer blade mesh: without it
    # the default mesh is 0.3 % stiffer than a 3x finer one, with it 0.1 %
    "Mesh.OptimizeNetgen": 1,
}


class _GmshSession:
    """Context manager: a fresh gmsh model; gmsh finalised (or the caller's session
    restored: its current model and the options changed here) on exit."""

    def __init__(self, name: str):
        self.name = name

    def __enter__(self):
        import gmsh

        self.gmsh = gmsh
        self.owner = not gmsh.isInitialized()
        if self.owner:
            gmsh.initialize(readConfigFiles=False, interruptible=False)
            self.saved = {}
            self.previous = None
        else:
            self.previous = gmsh.model.getCurrent()
            self.saved = {k: gmsh.option.getNumber(k) for k in
                          (*_OPTIONS, "Mesh.MeshSizeMax", "Mesh.MeshSizeMin")}
        for key, val in _OPTIONS.items():
            gmsh.option.setNumber(key, val)
        gmsh.model.add(self.name)
        return gmsh

    def __exit__(self, *exc):
        gmsh = self.gmsh
        if self.owner:
            gmsh.finalize()
            return False
        gmsh.model.remove()
        for key, val in self.saved.items():
            gmsh.option.setNumber(key, val)
        if self.previous:
            gmsh.model.setCurrent(self.previous)
        return False


def _surface_samples(gmsh, tag: int) -> np.ndarray:
    """Points of the boundary of surface ``tag``: vertices and curve midpoints (the
    parametric box of a trimmed face reaches beyond the face)."""
    pts = []
    for dim, t in gmsh.model.getBoundary([(2, tag)], combined=False, oriented=False):
        (u0,), (u1,) = gmsh.model.getParametrizationBounds(dim, t)
        pts.append(gmsh.model.getValue(dim, t, [u0, 0.5 * (u0 + u1), u1]))
    return np.concatenate([np.ravel(q) for q in pts]).reshape(-1, 3)


def _surfaces_where(gmsh, test, tol: float) -> list[int]:
    out = []
    for _, tag in gmsh.model.getEntities(2):
        xyz = _surface_samples(gmsh, tag)
        if np.all(np.abs(test(xyz)) < tol):
            out.append(tag)
    return out


def _square_residual(x: np.ndarray, frame: np.ndarray, half: float) -> np.ndarray:
    """Distance-like residual of points ``x`` (from the centre) to a square face: zero on
    the face (in its plane, within ``half`` along both in-plane axes)."""
    q = x @ frame.T
    return np.maximum(np.abs(q[:, 0]), np.maximum(np.abs(q[:, 1:]) - half, 0.0).max(axis=1))


def _affine(R: np.ndarray) -> list[float]:
    A = np.eye(4)
    A[:3, :3] = R
    return A.ravel().tolist()


def _build(gmsh, p) -> dict:
    """OCC geometry of sector 0; returns the entity tags of the groups."""
    occ = gmsh.model.occ
    alpha = p.sector_angle_rad
    h = 0.5 * alpha
    b = np.deg2rad(p.blade_angle_deg)
    c, d = blade_axes(p.blade_angle_deg)
    # disk: annular sector in the wheel plane, extruded over its thickness
    z0 = -0.5 * p.disk_thickness_m
    centre = occ.addPoint(0.0, 0.0, z0)
    corners = [occ.addPoint(*(r * e_r(a) + [0.0, 0.0, z0])) for r, a in
               ((p.clamp_radius_m, -h), (p.rim_radius_m, -h), (p.rim_radius_m, h),
                (p.clamp_radius_m, h))]
    curves = [occ.addLine(corners[0], corners[1]),
              occ.addCircleArc(corners[1], centre, corners[2]),
              occ.addLine(corners[2], corners[3]),
              occ.addCircleArc(corners[3], centre, corners[0])]
    base = occ.addPlaneSurface([occ.addCurveLoop(curves)])
    disk = [dt for dt in occ.extrude([(2, base)], 0.0, 0.0, p.disk_thickness_m) if dt[0] == 3]
    occ.remove([(0, centre)])

    def blade_box(x0, x1, width, thickness):
        tag = occ.addBox(x0, -width / 2, -thickness / 2, x1 - x0, width, thickness)
        occ.rotate([(3, tag)], 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -b)   # y -> c, z -> d
        return (3, tag)

    root = blade_box(p.rim_radius_m - p.root_embedding_m, p.root_radius_m, p.root_width_m,
                     p.root_thickness_m)
    blade = blade_box(p.root_radius_m, p.tip_radius_m, p.blade_width_m, p.blade_thickness_m)
    boss = blade_box(p.tieboss_radius_m - p.boss_radial_m / 2,
                     p.tieboss_radius_m + p.boss_radial_m / 2, p.boss_width_m,
                     p.boss_thickness_m)
    weights = blade_box(p.tip_radius_m - p.tipmass_length_m, p.tip_radius_m, p.blade_width_m,
                        p.tipmass_thickness_m)
    # shoulders: oblique prisms from each contact face to the centre of the boss
    g = contact_geometry(p)
    target = np.array([p.tieboss_radius_m, 0.0, 0.0])
    half = 0.5 * p.contact_face_size_m

    def square(centre_xyz, frame):
        u, v = frame[1], frame[2]
        pts = [occ.addPoint(*(centre_xyz + half * (i * u + j * v)))
               for i, j in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        lines = [occ.addLine(pts[k], pts[(k + 1) % 4]) for k in range(4)]
        return occ.addPlaneSurface([occ.addCurveLoop(lines)])

    shoulders = []
    for cen, frame in ((g.centre_right, g.frame_right), (g.centre_left, g.frame_left)):
        face = square(cen, frame)
        shoulders += [dt for dt in occ.extrude([(2, face)], *(target - cen)) if dt[0] == 3]
    steel, _ = occ.fuse(disk, [root, blade, boss, *shoulders])
    # tip mass: the weights bolted on both faces of the blade end (the block less the blade)
    tipmass, _ = occ.cut([weights], steel, removeObject=True, removeTool=False)
    if len(steel) != 1:
        raise ModelError(f"the steel parts did not fuse into one volume ({len(steel)} "
                         "volumes): check that root, blade, boss and shoulders touch")
    # embedded points: blade tip centre, two load points (the probes, at the centres of the
    # structured contact faces, are mesh nodes by construction: see _add_probe_points)
    points = {"tip": np.array([p.tip_radius_m, 0.0, 0.0]),
              "load_a": target + 0.5 * p.boss_thickness_m * d,
              "load_b": target - 0.5 * p.boss_thickness_m * d}
    ptags = {k: occ.addPoint(*v) for k, v in points.items()}
    _, omap = occ.fragment([*steel, *tipmass], [(0, t) for t in ptags.values()])
    occ.synchronize()
    steel_v = [t for dim, t in omap[0] if dim == 3]
    tip_v = [t for m in omap[1:1 + len(tipmass)] for dim, t in m if dim == 3]
    pt_out = {k: [t for dim, t in omap[1 + len(tipmass) + i] if dim == 0]
              for i, k in enumerate(ptags)}
    if len(steel_v) != 1 or not tip_v or any(len(v) != 1 for v in pt_out.values()):
        raise ModelError("gmsh fragment gave an unexpected topology (steel "
                         f"{steel_v}, tip mass {tip_v}, points {pt_out})")

    tol = 1e-9 * p.tip_radius_m * 100
    groups = {
        "cut_left": _surfaces_where(gmsh, lambda x: x @ e_t(-h), tol),
        "cut_right": _surfaces_where(gmsh, lambda x: x @ e_t(h), tol),
        "clamp": _surfaces_where(gmsh, lambda x: np.hypot(x[:, 0], x[:, 1])
                                 - p.clamp_radius_m, tol),
    }
    for side, cen, frame in (("right", g.centre_right, g.frame_right),
                             ("left", g.centre_left, g.frame_left)):
        groups[f"contact_{side}"] = _surfaces_where(
            gmsh, lambda x, cen=cen, frame=frame: _square_residual(x - cen, frame, half), tol)
    for name, tags in groups.items():
        if len(tags) != 1:
            raise ModelError(f"the sector geometry has {len(tags)} surfaces in group {name!r} "
                             "(expected 1): the parameters make parts intersect the faces")
    groups["steel"] = steel_v
    groups["tipmass"] = tip_v
    groups["tip"] = pt_out["tip"]
    groups["load"] = pt_out["load_a"] + pt_out["load_b"]
    return groups


_DIMS = {"clamp": 2, "cut_left": 2, "cut_right": 2, "contact_left": 2, "contact_right": 2,
         "steel": 3, "tipmass": 3, "tip": 0, "load": 0}


def _add_probe_points(gmsh, p) -> None:
    """Physical point groups ``probe`` / ``probe_left``: the mesh nodes at the contact-face
    centres, as point elements of discrete point entities (added after meshing)."""
    g = contact_geometry(p)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    xyz = np.reshape(xyz, (-1, 3))
    for name, centre in (("probe", g.centre_right), ("probe_left", g.centre_left)):
        k = int(np.argmin(np.linalg.norm(xyz - centre, axis=1)))
        dist = float(np.linalg.norm(xyz[k] - centre))
        if dist > 1e-9:
            raise ModelError(f"no mesh node at the contact-face centre ({dist:.3g} m away)")
        ent = gmsh.model.addDiscreteEntity(0)
        gmsh.model.mesh.addElements(0, ent, [15], [[gmsh.model.mesh.getMaxElementTag() + 1]],
                                    [[int(tags[k])]])
        gmsh.model.addPhysicalGroup(0, [ent], name=name)


@dataclass(frozen=True)
class MeshText:
    """The ``.msh`` text of a sector and how long it took."""

    text: str
    seconds: float


def mesh_sector_msh(p) -> MeshText:
    """Build, mesh (tet10, periodic faces) and write the sector; return the ``.msh`` text.

    Raises
    ------
    ModelError
        If the geometry is inconsistent (see :func:`check_clearance`) or gmsh fails.
    """
    check_clearance(p)
    t0 = time.perf_counter()
    with _GmshSession("tieboss_solid_sector") as gmsh:
        try:
            groups = _build(gmsh, p)
        except Exception as exc:
            if isinstance(exc, ModelError):
                raise
            raise ModelError(f"gmsh could not build the sector geometry: {exc}") from None
        for name, tags in groups.items():
            gmsh.model.addPhysicalGroup(_DIMS[name], tags, name=name)
        R = rotation_z(p.sector_angle_rad)
        for right, left in (("cut_right", "cut_left"), ("contact_right", "contact_left")):
            gmsh.model.mesh.setPeriodic(2, groups[right], groups[left], _affine(R))
        gmsh.option.setNumber("Mesh.MeshSizeMax", p.mesh_size_m)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        # structured contact faces: ``contact_divisions`` cells per edge, so the face
        # centre is a node (a vertex for even divisions, the mid-side node of the central
        # cell's diagonal for odd ones)
        for name in ("contact_left", "contact_right"):
            for tag in groups[name]:
                for _, curve in gmsh.model.getBoundary([(2, tag)], combined=False,
                                                       oriented=False):
                    gmsh.model.mesh.setTransfiniteCurve(curve, p.contact_divisions + 1)
                gmsh.model.mesh.setTransfiniteSurface(tag)
        try:
            gmsh.model.mesh.generate(3)
        except Exception as exc:
            raise ModelError(f"gmsh could not mesh the sector (mesh_size_m = "
                             f"{p.mesh_size_m}): {exc}") from None
        _add_probe_points(gmsh, p)
        with tempfile.TemporaryDirectory(prefix="fricdamp_tieboss_") as tmp:
            path = os.path.join(tmp, "sector.msh")
            gmsh.write(path)
            with open(path, encoding="ascii") as fh:
                text = fh.read()
    seconds = time.perf_counter() - t0
    log.info("meshed the solid tie-boss sector (mesh_size_m=%g) in %.2f s", p.mesh_size_m,
             seconds)
    return MeshText(text=text, seconds=seconds)
