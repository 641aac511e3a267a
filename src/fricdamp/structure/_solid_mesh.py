"""Solid meshes as read or generated: :class:`SolidMesh`, meshio conversion, box meshes.

Cells use meshio's (= VTK's) local node ordering, which is also Abaqus' ordering of C3D4,
C3D10, C3D8 and C3D20 (meshio reorders gmsh's tetra10 and hexahedron20 while reading):

* ``tetra``: vertices 0-3 with ``(p1 - p0) x (p2 - p0) . (p3 - p0) > 0``;
* ``tetra10``: + mid-side nodes of the edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3);
* ``hexahedron``: bottom face 0-1-2-3 counter-clockwise seen from the top face 4-5-6-7;
* ``hexahedron20``: + mid-side nodes of (0,1) (1,2) (2,3) (3,0) (4,5) (5,6) (6,7) (7,4)
  (0,4) (1,5) (2,6) (3,7).

Only meshio is used to read files; it is imported when a file is read, not with fricdamp.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fricdamp.errors import ModelError, as_finite_array, check_positive

__all__ = ["CELL_TYPES", "SolidMesh", "box_mesh", "mesh_from_meshio", "read_mesh"]

#: Number of nodes of each supported volume cell type (meshio names).
CELL_TYPES = {"tetra": 4, "tetra10": 10, "hexahedron": 8, "hexahedron20": 20}

#: Corner count and the element edges (vertex pairs, meshio order) of each cell family.
TET_EDGES = np.array([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)])
HEX_EDGES = np.array([(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
                      (0, 4), (1, 5), (2, 6), (3, 7)])
#: Faces (corner nodes, right-handed about the outward normal) of positively oriented cells.
TET_FACES = np.array([(0, 1, 3), (1, 2, 3), (2, 0, 3), (0, 2, 1)])
HEX_FACES = np.array([(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                      (3, 0, 4, 7)])

# topological dimension of meshio cell types (for gmsh MSH 2.2 physical tags)
_CELL_DIM = {"vertex": 0, "line": 1, "line3": 1, "triangle": 2, "triangle6": 2, "quad": 2,
             "quad8": 2, "quad9": 2, "tetra": 3, "tetra10": 3, "hexahedron": 3,
             "hexahedron20": 3, "hexahedron27": 3, "wedge": 3, "wedge15": 3, "pyramid": 3,
             "pyramid13": 3}


def corner_count(cell_type: str) -> int:
    """Number of vertices (corner nodes) of a cell type: 4 for tets, 8 for hexahedra."""
    return 4 if cell_type.startswith("tetra") else 8


def edge_table(cell_type: str) -> np.ndarray:
    """Edges ``(n_edges, 2)`` of a cell as local vertex pairs, in mid-side node order."""
    return TET_EDGES if cell_type.startswith("tetra") else HEX_EDGES


def face_table(cell_type: str) -> np.ndarray:
    """Faces of a cell as local node indices, outward oriented, mid-side nodes included.

    Returns ``(n_faces, 3|6|4|8)``: the corners, then (for quadratic cells) the mid-side
    nodes of the face edges (c0, c1), (c1, c2), ... in that order.
    """
    corners = TET_FACES if cell_type.startswith("tetra") else HEX_FACES
    if cell_type in ("tetra", "hexahedron"):
        return corners
    edges = edge_table(cell_type)
    nv = corner_count(cell_type)
    lookup = {frozenset(map(int, e)): nv + k for k, e in enumerate(edges)}
    mids = [[lookup[frozenset((int(f[i]), int(f[(i + 1) % len(f)])))] for i in range(len(f))]
            for f in corners]
    return np.hstack([corners, np.array(mids)])


def signed_volumes(points: np.ndarray, cells: np.ndarray, cell_type: str) -> np.ndarray:
    """Signed volume of the straight-sided cells spanned by the corners [m^3], ``(n_cells,)``.

    Hexahedra are split into 6 tetrahedra about the diagonal 0-6; the sum is the exact volume
    of a trilinear hexahedron. Negative values mean inverted (left-handed) cells.
    """
    p = points[cells[:, :corner_count(cell_type)]]
    if cell_type.startswith("tetra"):
        return _tet_volume(p[:, 0], p[:, 1], p[:, 2], p[:, 3])
    vol = np.zeros(len(cells))
    for a, b in ((1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)):
        vol += _tet_volume(p[:, 0], p[:, a], p[:, b], p[:, 6])
    return vol


def _tet_volume(a, b, c, d):
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0


# ---------------------------------------------------------------------------- SolidMesh
@dataclass(frozen=True, eq=False, repr=False)
class SolidMesh:
    """A volume mesh of linear or quadratic tetrahedra or hexahedra, as read or generated.

    Parameters
    ----------
    points : ndarray, shape (n_points, 3)
        Point coordinates [m].
    cell_type : str
        meshio cell type: ``"tetra"``, ``"tetra10"``, ``"hexahedron"`` or
        ``"hexahedron20"`` (node ordering in the module docstring).
    cells : ndarray of int, shape (n_cells, nodes_per_cell)
        Point indices of each cell.
    point_sets : dict of str to ndarray of int, optional
        Named point index sets (gmsh physical groups of any dimension, Abaqus nsets).
    cell_sets : dict of str to ndarray of int, optional
        Named cell index sets (material regions: gmsh volume groups, Abaqus elsets).

    Raises
    ------
    ModelError
        If the cell type is unknown, the mesh is empty, or an index is out of range.
    """

    points: np.ndarray
    cell_type: str
    cells: np.ndarray
    point_sets: dict[str, np.ndarray] = field(default_factory=dict)
    cell_sets: dict[str, np.ndarray] = field(default_factory=dict)

    def __repr__(self) -> str:
        from fricdamp.results import summary_repr

        return summary_repr(self)

    def __post_init__(self):
        points = as_finite_array("points", self.points)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0:
            raise ModelError(f"points must have shape (n_points, 3) with n_points >= 1, "
                             f"got {points.shape}")
        if self.cell_type not in CELL_TYPES:
            raise ModelError(f"cell_type must be one of {sorted(CELL_TYPES)}, "
                             f"got {self.cell_type!r}")
        cells = np.asarray(self.cells)
        npc = CELL_TYPES[self.cell_type]
        if cells.ndim != 2 or cells.shape[1] != npc or len(cells) == 0:
            raise ModelError(f"cells of type {self.cell_type} must have shape (n_cells, {npc}) "
                             f"with n_cells >= 1, got {cells.shape}")
        if not np.issubdtype(cells.dtype, np.integer):
            raise ModelError(f"cells must hold integer point indices, got dtype {cells.dtype}")
        if cells.min() < 0 or cells.max() >= len(points):
            raise ModelError(f"cells refer to points outside [0, {len(points) - 1}]: "
                             f"min {cells.min()}, max {cells.max()}")
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "cells", cells.astype(np.int64, copy=False))
        object.__setattr__(self, "point_sets", _check_sets("point_sets", self.point_sets,
                                                           len(points)))
        object.__setattr__(self, "cell_sets", _check_sets("cell_sets", self.cell_sets,
                                                          len(cells)))

    @property
    def n_cells(self) -> int:
        """Number of cells."""
        return len(self.cells)

    def volume(self) -> float:
        """Volume of the straight-sided cells [m^3] (mid-side node positions ignored)."""
        return float(signed_volumes(self.points, self.cells, self.cell_type).sum())


def _check_sets(name: str, sets: Mapping[str, Sequence[int]], n: int) -> dict[str, np.ndarray]:
    out = {}
    for key, idx in (sets or {}).items():
        arr = np.unique(np.asarray(idx, dtype=np.int64).ravel())
        if arr.size and (arr[0] < 0 or arr[-1] >= n):
            raise ModelError(f"{name}[{key!r}] refers to indices outside [0, {n - 1}]")
        out[str(key)] = arr
    return out


# ---------------------------------------------------------------------------- meshio
def read_mesh(path) -> SolidMesh:
    """Read a volume mesh with meshio (gmsh ``.msh``, Abaqus ``.inp``, ``.vtu``, ...), or an
    ANSYS archive (``.cdb``) with ``ansys-mapdl-reader``
    (:func:`fricdamp.structure.io.read_ansys_archive`: node and element components become
    the named sets, points are laid out by ANSYS node number).

    Parameters
    ----------
    path : str or path-like
        Mesh file; the format is chosen from the extension.

    Returns
    -------
    SolidMesh
        See :func:`mesh_from_meshio` for how physical groups and sets are mapped.

    Raises
    ------
    ModelError
        One line naming the file if it is missing, unreadable or holds no supported cells.
    """
    import meshio

    path = Path(path)
    if not path.is_file():
        raise ModelError(f"mesh file {path} does not exist")
    if path.suffix.lower() == ".cdb":
        from fricdamp.structure.io import read_ansys_archive

        return read_ansys_archive(path)
    try:
        m = meshio.read(path)
    except Exception as exc:  # noqa: BLE001 - meshio raises many types
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ModelError(f"cannot read mesh file {path}: {msg}") from exc
    try:
        return mesh_from_meshio(m)
    except ModelError as exc:
        raise ModelError(f"mesh file {path}: {exc}") from exc


def mesh_from_meshio(m) -> SolidMesh:
    """Convert a :class:`meshio.Mesh` to a :class:`SolidMesh`.

    The volume cells (one type among tetra, tetra10, hexahedron, hexahedron20) of all cell
    blocks are concatenated in block order. Named sets:

    * ``point_sets``: meshio point sets (Abaqus nsets) and, for every named cell set of any
      dimension (gmsh physical groups of points, curves, surfaces and volumes; Abaqus
      elsets), the points of its cells, mid-side points included;
    * ``cell_sets``: the named cell sets restricted to the volume cells (material regions).

    gmsh MSH 2.2 files, which meshio reads without cell sets, are handled through the
    ``gmsh:physical`` cell data and the physical names.

    Parameters
    ----------
    m : meshio.Mesh

    Returns
    -------
    SolidMesh

    Raises
    ------
    ModelError
        If there are no supported volume cells or several volume cell types.
    """
    blocks = list(m.cells)
    types = [b.type for b in blocks]
    vol_types = sorted({t for t in types if t in CELL_TYPES})
    other_3d = sorted({t for t in types if _CELL_DIM.get(t) == 3 and t not in CELL_TYPES})
    if not vol_types:
        extra = f" (unsupported: {other_3d})" if other_3d else ""
        raise ModelError(f"no volume cells of type {sorted(CELL_TYPES)} found{extra}; "
                         f"cell types present: {sorted(set(types))}. gmsh saves only cells of "
                         f"physical groups: add a volume physical group or set Mesh.SaveAll=1")
    if len(vol_types) > 1 or other_3d:
        raise ModelError(f"mixed volume cell types {vol_types + other_3d} are not supported; "
                         f"mesh with one element type")
    cell_type = vol_types[0]
    vol_blocks = [k for k, t in enumerate(types) if t == cell_type]
    offsets = np.cumsum([0] + [len(blocks[k].data) for k in vol_blocks])
    cells = np.concatenate([np.asarray(blocks[k].data) for k in vol_blocks])
    points = np.asarray(m.points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ModelError(f"points must be 3D, got shape {points.shape}")

    point_sets: dict[str, np.ndarray] = {
        str(k): np.asarray(v, dtype=np.int64).ravel() for k, v in (m.point_sets or {}).items()}
    cell_sets: dict[str, np.ndarray] = {}
    named = _named_cell_sets(m)
    for name, per_block in named.items():
        pts, vol = [], []
        for k, idx in enumerate(per_block):
            if idx is None or len(idx) == 0:
                continue
            idx = np.asarray(idx, dtype=np.int64)
            pts.append(np.asarray(blocks[k].data)[idx].ravel())
            if k in vol_blocks:
                vol.append(offsets[vol_blocks.index(k)] + idx)
        if pts:
            prev = point_sets.get(name, np.empty(0, np.int64))
            point_sets[name] = np.unique(np.concatenate([prev, *pts]))
        if vol:
            cell_sets[name] = np.unique(np.concatenate(vol))
    return SolidMesh(points=points, cell_type=cell_type, cells=cells,
                     point_sets=point_sets, cell_sets=cell_sets)


def _named_cell_sets(m) -> dict[str, list]:
    """Named cell sets as ``{name: [indices per cell block or None]}``."""
    sets = {str(k): list(v) for k, v in (m.cell_sets or {}).items()
            if not str(k).startswith("gmsh:")}
    if sets or "gmsh:physical" not in (m.cell_data or {}) or not m.field_data:
        return sets
    # MSH 2.2: physical tags per cell and names in field_data {name: [tag, dim]}
    tags = m.cell_data["gmsh:physical"]
    for name, (tag, dim) in m.field_data.items():
        per_block = [np.flatnonzero(np.asarray(tags[k]) == tag)
                     if _CELL_DIM.get(b.type) == dim else None for k, b in enumerate(m.cells)]
        sets[str(name)] = per_block
    return sets


# ---------------------------------------------------------------------------- box meshes
# skfem's hexahedron vertex i sits at the reference corner of meshio vertex _SK_HEX[i]
SK_HEX = np.array([6, 2, 5, 7, 1, 3, 4, 0])


def box_mesh(lengths: Sequence[float], divisions: Sequence[int], *,
             cell_type: str = "hexahedron", origin: Sequence[float] = (0.0, 0.0, 0.0)
             ) -> SolidMesh:
    """Structured mesh of a rectangular box ``[origin, origin + lengths]``.

    Generated with skfem's ``MeshHex1.init_tensor`` / ``MeshTet1.init_tensor`` (each
    hexahedron split into 6 tetrahedra for tets), converted to meshio node ordering and
    positive orientation; quadratic types get straight mid-side nodes.

    Parameters
    ----------
    lengths : sequence of 3 float
        Box edge lengths along x, y, z [m], > 0.
    divisions : sequence of 3 int
        Number of hexahedra along x, y, z, >= 1.
    cell_type : str
        ``"hexahedron"``, ``"hexahedron20"``, ``"tetra"`` or ``"tetra10"``.
    origin : sequence of 3 float
        Corner with the smallest coordinates [m].

    Returns
    -------
    SolidMesh
        With point sets ``"xmin"``, ``"xmax"``, ``"ymin"``, ``"ymax"``, ``"zmin"``,
        ``"zmax"`` (the points on each face) and no cell sets.

    Examples
    --------
    >>> m = box_mesh((0.2, 0.04, 0.006), (10, 2, 1), cell_type="hexahedron20")
    >>> m.cells.shape, len(m.point_sets["xmin"])
    ((20, 20), 13)
    """
    import skfem

    lengths = check_positive("lengths", lengths, unit="m")
    origin = as_finite_array("origin", origin)
    div = np.asarray(divisions)
    if lengths.shape != (3,) or origin.shape != (3,) or div.shape != (3,):
        raise ModelError("lengths, divisions and origin must each have 3 entries (x, y, z)")
    if not np.issubdtype(div.dtype, np.integer) or np.any(div < 1):
        raise ModelError(f"divisions must be integers >= 1, got {divisions!r}")
    if cell_type not in CELL_TYPES:
        raise ModelError(f"cell_type must be one of {sorted(CELL_TYPES)}, got {cell_type!r}")
    axes = [o + np.linspace(0.0, L, n + 1) for o, L, n in zip(origin, lengths, div, strict=True)]
    if cell_type.startswith("hexa"):
        sk = skfem.MeshHex1.init_tensor(*axes)
        cells = np.asarray(sk.t)[np.argsort(SK_HEX)].T.astype(np.int64)
    else:
        sk = skfem.MeshTet1.init_tensor(*axes)
        cells = np.asarray(sk.t).T.astype(np.int64)
    points = np.asarray(sk.p).T.copy()
    linear = "hexahedron" if cell_type.startswith("hexa") else "tetra"
    cells = orient_cells(points, cells, linear)
    if cell_type != linear:
        points, cells = add_midside_nodes(points, cells, linear)
    tol = 1e-9 * lengths.max()
    sets = {}
    for axis, name in enumerate("xyz"):
        sets[name + "min"] = np.flatnonzero(np.abs(points[:, axis] - axes[axis][0]) < tol)
        sets[name + "max"] = np.flatnonzero(np.abs(points[:, axis] - axes[axis][-1]) < tol)
    return SolidMesh(points=points, cell_type=cell_type, cells=cells, point_sets=sets)


def orient_cells(points: np.ndarray, cells: np.ndarray, cell_type: str) -> np.ndarray:
    """Return linear cells with negative volume mirrored to positive orientation."""
    vol = signed_volumes(points, cells, cell_type)
    cells = cells.copy()
    neg = vol < 0
    if cell_type == "tetra":
        cells[np.ix_(neg, [1, 2])] = cells[np.ix_(neg, [2, 1])]
    else:  # swap the bottom and top faces
        cells[neg] = cells[neg][:, [4, 5, 6, 7, 0, 1, 2, 3]]
    return cells


def add_midside_nodes(points: np.ndarray, cells: np.ndarray, cell_type: str
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Append straight mid-side points to linear cells: tetra -> tetra10, hexa -> hexa20.

    Returns
    -------
    points : ndarray, shape (n_points + n_edges, 3)
    cells : ndarray, shape (n_cells, 10 | 20)
    """
    edges = edge_table(cell_type)
    pairs = np.sort(cells[:, edges], axis=2).reshape(-1, 2)      # (n_cells * n_e, 2)
    uniq, inv = np.unique(pairs, axis=0, return_inverse=True)
    mids = 0.5 * (points[uniq[:, 0]] + points[uniq[:, 1]])
    new = len(points) + inv.reshape(len(cells), len(edges))
    return np.vstack([points, mids]), np.hstack([cells, new])
