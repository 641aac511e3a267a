"""Import of structural matrices: Matrix Market files, ANSYS ``.full`` files, cyclic sectors.

* :func:`read_matrix` — one matrix from an array, a sparse matrix or a Matrix Market path.
* :func:`read_ansys_full` — mass and stiffness matrices and the (node, component) DOF
  reference from an ANSYS ``.full`` file, through the maintained reader library
  ``ansys-mapdl-reader`` (an optional dependency: it pulls VTK and PyVista, so it is not
  installed with fricdamp; ``pip install ansys-mapdl-reader`` to use it).
* :func:`read_ansys_archive` — a solid mesh with its node and element components from an
  ANSYS archive (``.cdb``, APDL ``CDWRITE``), through the same library; meshio does not
  read archives. :func:`~fricdamp.structure.solid.read_mesh` calls it for ``.cdb`` files.
* :func:`read_sector` — a :class:`~fricdamp.structure.cyclic.CyclicSector` from a user's
  sector matrices, with the left/right cut DOFs and the contact nodes named, so a real FE
  model runs the same pipeline as the built-in models (cyclic modes, Craig–Bampton,
  transients).
* :func:`solid_with_matrices` — a meshed solid sector whose mass and stiffness come from
  matrix files (Matrix Market or ANSYS ``.full``) instead of fricdamp's own assembly: the
  mesh gives the geometry (contact faces, normals, tributary areas, node sets), the files
  give the FE program's matrices, mapped onto the mesh nodes by their DOF reference.

FE programs often store only one triangle of a symmetric matrix (ANSYS ``.full`` files
hold the upper one); a matrix with exactly one empty strict triangle is completed to the
symmetric matrix on import (and says so in the log).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

from fricdamp.errors import ModelError

log = logging.getLogger(__name__)

#: Component labels of ANSYS DOF references (0-based component index).
COMPONENT_LABELS = ("UX", "UY", "UZ", "ROTX", "ROTY", "ROTZ")


def read_matrix(source, name: str = "matrix"):
    """Matrix from an array, a sparse matrix or a Matrix Market file path (``.mtx``)."""
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.is_file():
            raise ModelError(f"{name}: file {str(path)!r} does not exist")
        try:
            A = scipy.io.mmread(str(path))
        except (ValueError, OSError) as exc:
            raise ModelError(f"{name}: {str(path)!r} is not a readable Matrix Market file: "
                             f"{exc}") from exc
        return sp.csr_matrix(A) if sp.issparse(A) else np.asarray(A, float)
    return source


def _complete_triangle(A, name: str):
    """Symmetric matrix from one stored triangle; other matrices are returned unchanged."""
    if A is None or A.shape[0] != A.shape[1]:
        return A
    if sp.issparse(A):
        A = sp.csr_matrix(A, dtype=float)
        lo, up = sp.tril(A, -1), sp.triu(A, 1)
        n_lo, n_up = lo.count_nonzero(), up.count_nonzero()
        if (n_lo == 0) != (n_up == 0):
            log.info("%s: only one triangle stored; completed to a symmetric matrix", name)
            return sp.csr_matrix(A + (up.T if n_lo == 0 else lo.T))
        return A
    A = np.asarray(A, float)
    n_lo = np.count_nonzero(np.tril(A, -1))
    n_up = np.count_nonzero(np.triu(A, 1))
    if (n_lo == 0) != (n_up == 0):
        log.info("%s: only one triangle stored; completed to a symmetric matrix", name)
        return A + (np.triu(A, 1).T if n_lo == 0 else np.tril(A, -1).T)
    return A


def _import_mapdl_reader():
    try:
        from ansys.mapdl import reader
    except ImportError as exc:
        raise ModelError(
            "reading ANSYS .full and .cdb files needs the optional package ansys-mapdl-reader "
            "(it brings VTK and PyVista): pip install ansys-mapdl-reader. Alternatively "
            "export the matrices from ANSYS as Matrix Market files (APDL: *SMAT with "
            "IMPORT,FULL, then *EXPORT with format MMF) and pass their paths as M= and K="
        ) from exc
    return reader


#: VTK cell types of ANSYS archive elements -> meshio names (solids and the surface and
#: line elements whose components may name node sets, e.g. CONTA174 contact surfaces).
_VTK_TO_MESHIO = {1: "vertex", 3: "line", 5: "triangle", 9: "quad", 10: "tetra",
                  12: "hexahedron", 13: "wedge", 14: "pyramid", 21: "line3", 22: "triangle6",
                  23: "quad8", 24: "tetra10", 25: "hexahedron20", 26: "wedge15",
                  27: "pyramid13"}

#: Largest ANSYS node number accepted (points are laid out by node number, see below).
MAX_ARCHIVE_NODE_NUMBER = 50_000_000


def read_ansys_archive(path):
    """A solid mesh from an ANSYS archive file (``.cdb``, written by APDL ``CDWRITE``).

    Read with ``ansys-mapdl-reader`` (``Archive``); the cells keep VTK's node order, which
    is meshio's (SOLID186 -> ``hexahedron20``, SOLID187 -> ``tetra10``, SOLID185 ->
    ``hexahedron``; degenerate SOLID185/186 bricks come as wedges or pyramids, which
    fricdamp does not support: the mesh must be of one element type). Named sets:

    * node components (``CMBLOCK ... NODE``) become point sets;
    * element components (``CMBLOCK ... ELEM``) become cell sets (materials by region) and
      point sets of their nodes, so a component of contact or surface elements (CONTA174,
      SURF154) names the nodes of a contact face;
    * each material number ``i`` becomes a cell set ``"MAT<i>"``.

    **Points are laid out by ANSYS node number**: point ``k - 1`` is node ``k`` (numbers
    missing from the archive become unused points, outside every cell), so the 1-based
    position of a point *is* its ANSYS node number, and the DOF reference of a ``.full``
    file of the same model maps onto the mesh without translation (see
    :func:`solid_with_matrices`).

    Parameters
    ----------
    path : str or path-like
        ``.cdb`` file.

    Returns
    -------
    SolidMesh

    Raises
    ------
    ModelError
        One line naming the file: missing, unreadable, no supported volume cells, mixed
        element types, or node numbers above :data:`MAX_ARCHIVE_NODE_NUMBER`.
    """
    import meshio

    from fricdamp.structure._solid_mesh import mesh_from_meshio

    p = Path(path)
    if not p.is_file():
        raise ModelError(f"mesh file {p} does not exist")
    reader = _import_mapdl_reader()
    try:
        arch = reader.Archive(str(p), parse_vtk=True)
        grid = arch.grid
        nnum = np.asarray(grid.point_data["ansys_node_num"], dtype=np.int64)
        celltypes = np.asarray(grid.celltypes)
        conn = np.asarray(grid.cell_connectivity, dtype=np.int64)
        offsets = np.asarray(grid.offset if not hasattr(grid, "cell_offsets")
                             else grid.cell_offsets, dtype=np.int64)
        enum = np.asarray(grid.cell_data["ansys_elem_num"], dtype=np.int64)
        mat = np.asarray(grid.cell_data["ansys_material_type"], dtype=np.int64)
        node_comps = {str(k): np.asarray(v, dtype=np.int64)
                      for k, v in arch.node_components.items()}
        elem_comps = {str(k): np.asarray(v, dtype=np.int64)
                      for k, v in arch.element_components.items()}
    except ModelError:
        raise
    except Exception as exc:  # noqa: BLE001 - the reader raises many types
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ModelError(f"cannot read ANSYS archive {p}: {msg}") from exc
    if nnum.size == 0 or celltypes.size == 0:
        raise ModelError(f"mesh file {p}: the archive holds no nodes or no elements")
    if nnum.min() < 1 or nnum.max() > MAX_ARCHIVE_NODE_NUMBER:
        raise ModelError(f"mesh file {p}: node numbers must lie in [1, "
                         f"{MAX_ARCHIVE_NODE_NUMBER}], got {int(nnum.min())} to "
                         f"{int(nnum.max())}; compress them first (APDL NUMCMP,NODE)")
    # points laid out by node number; unused numbers sit on the first node (no cell uses
    # them, so they carry no DOF and do not move bounding boxes)
    points = np.repeat(np.asarray(grid.points[:1], dtype=float), int(nnum.max()), axis=0)
    points[nnum - 1] = np.asarray(grid.points, dtype=float)
    pos = nnum - 1  # grid point -> mesh point
    blocks, block_of_cell, index_in_block = [], np.empty(celltypes.size, np.int64), \
        np.empty(celltypes.size, np.int64)
    for vtk in np.unique(celltypes):
        name = _VTK_TO_MESHIO.get(int(vtk))
        if name is None:
            raise ModelError(f"mesh file {p}: VTK cell type {int(vtk)} is not supported")
        idx = np.flatnonzero(celltypes == vtk)
        npc = int(offsets[idx[0] + 1] - offsets[idx[0]])
        data = pos[conn[offsets[idx][:, None] + np.arange(npc)]]
        block_of_cell[idx] = len(blocks)
        index_in_block[idx] = np.arange(idx.size)
        blocks.append(meshio.CellBlock(name, data))
    cell_sets: dict[str, list] = {}

    def add_set(name, cells_mask):
        per = [[] for _ in blocks]
        for c in np.flatnonzero(cells_mask):
            per[block_of_cell[c]].append(index_in_block[c])
        cell_sets[name] = [np.asarray(x, dtype=np.int64) for x in per]

    for name, elems in elem_comps.items():
        add_set(name, np.isin(enum, elems))
    for m in np.unique(mat):
        add_set(f"MAT{int(m)}", mat == m)
    point_sets = {name: nodes[(nodes >= 1) & (nodes <= points.shape[0])] - 1
                  for name, nodes in node_comps.items()}
    for name, nodes in node_comps.items():
        missing = np.setdiff1d(nodes, nnum)
        if missing.size:
            raise ModelError(f"mesh file {p}: node component {name!r} names node "
                             f"{int(missing[0])}, which the archive does not define")
    m = meshio.Mesh(points, blocks, point_sets=point_sets, cell_sets=cell_sets)
    try:
        return mesh_from_meshio(m)
    except ModelError as exc:
        raise ModelError(f"mesh file {p}: {exc}") from exc


def read_ansys_full(path) -> tuple[sp.csr_matrix, sp.csr_matrix, np.ndarray]:
    """Mass and stiffness matrices of an ANSYS ``.full`` file.

    Parameters
    ----------
    path : str or path-like
        The ``Jobname.full`` file (symmetric matrices, consistent mass).

    Returns
    -------
    M, K : scipy.sparse.csr_matrix, shape (n, n)
        Mass [kg] and stiffness [N/m] matrices in the file's units, symmetric, with the
        constrained DOFs (empty rows) removed.
    dof_reference : ndarray of int, shape (n, 2)
        Node number and component (0 UX, 1 UY, 2 UZ, 3 ROTX, ...) of each DOF.

    Raises
    ------
    ModelError
        If the file is missing, ``ansys-mapdl-reader`` is not installed, or the file cannot
        be read (lumped or unsymmetric matrices are not supported by the reader).
    """
    p = Path(path)
    if not p.is_file():
        raise ModelError(f"full: file {str(p)!r} does not exist")
    reader = _import_mapdl_reader()
    try:
        full = reader.read_binary(str(p))
        dof_ref, k, m = full.load_km(as_sparse=True, sort=True)
    except (NotImplementedError, OSError, ValueError, RuntimeError) as exc:
        raise ModelError(f"full: cannot read {str(p)!r} with ansys-mapdl-reader: {exc}") from exc
    if k is None or m is None:
        raise ModelError(f"full: {str(p)!r} does not hold both a stiffness and a mass matrix")
    K = _complete_triangle(sp.csr_matrix(k, dtype=float), "K (.full)")
    M = _complete_triangle(sp.csr_matrix(m, dtype=float), "M (.full)")
    dof_ref = np.asarray(dof_ref, dtype=np.int64).reshape(-1, 2)
    active = (np.diff(K.indptr) > 0) | (np.diff(M.indptr) > 0)
    if not np.all(active):
        idx = np.flatnonzero(active)
        K, M, dof_ref = K[idx][:, idx], M[idx][:, idx], dof_ref[idx]
    return M, K, dof_ref


def _index_list(name: str, value) -> np.ndarray | None:
    """Integers from a sequence or a text file of integers."""
    if value is None:
        return None
    if isinstance(value, (str, os.PathLike)):
        p = Path(value)
        if not p.is_file():
            raise ModelError(f"{name}: file {str(p)!r} does not exist")
        try:
            arr = np.loadtxt(p, dtype=float, ndmin=1, comments=("#", "%")).reshape(-1)
        except ValueError as exc:
            raise ModelError(f"{name}: {str(p)!r} must hold integers only: {exc}") from exc
    else:
        arr = np.asarray(value, dtype=float).reshape(-1)
    if not np.all(np.isfinite(arr)) or np.any(arr != np.round(arr)):
        raise ModelError(f"{name} must hold integers, got {value!r}")
    return arr.astype(np.int64)


def _dof_reference(value, n: int) -> np.ndarray | None:
    if value is None:
        return None
    if isinstance(value, (str, os.PathLike)):
        p = Path(value)
        if not p.is_file():
            raise ModelError(f"dof_reference: file {str(p)!r} does not exist")
        arr = np.loadtxt(p, dtype=float, ndmin=2, comments=("#", "%"))
    else:
        arr = np.asarray(value, dtype=float)
    if arr.ndim != 2 or arr.shape != (n, 2) or np.any(arr != np.round(arr)):
        raise ModelError(f"dof_reference must be an integer array of shape ({n}, 2) (node, "
                         f"component per DOF), got shape {arr.shape}")
    ref = arr.astype(np.int64)
    if np.unique(ref, axis=0).shape[0] != n:
        raise ModelError("dof_reference lists a (node, component) pair twice")
    return ref


def _node_dofs(name: str, nodes: np.ndarray, ref: np.ndarray) -> tuple[np.ndarray, list]:
    """DOF indices of ``nodes`` (in node order, components ascending) and their components."""
    dofs, comps = [], []
    for node in nodes:
        idx = np.flatnonzero(ref[:, 0] == node)
        if idx.size == 0:
            raise ModelError(f"{name}: node {int(node)} has no DOF in the model")
        idx = idx[np.argsort(ref[idx, 1])]
        dofs.extend(idx.tolist())
        comps.append(tuple(ref[idx, 1].tolist()))
    return np.asarray(dofs, dtype=np.int64), comps


def _read_km(K, M, full, dof_reference, who: str):
    """``(M, K, ref)`` from Matrix Market paths/arrays or an ANSYS ``.full`` file (its DOF
    reference then; otherwise None), checked square and of one size."""
    if full is not None:
        if M is not None or K is not None:
            raise ModelError("give either full= (an ANSYS .full file) or M= and K=, not both")
        M, K, ref = read_ansys_full(full)
        if dof_reference is not None:
            raise ModelError("dof_reference comes from the .full file; do not pass it too")
    else:
        if M is None or K is None:
            raise ModelError(f"{who} needs M= and K= (Matrix Market paths or arrays) or "
                             "full= (an ANSYS .full file)")
        M = _complete_triangle(read_matrix(M, "M"), "M")
        K = _complete_triangle(read_matrix(K, "K"), "K")
        ref = None
    for nm, A in (("M", M), ("K", K)):
        if getattr(A, "ndim", 2) != 2 or A.shape[0] != A.shape[1]:
            raise ModelError(f"{nm} must be a square matrix, got shape {A.shape}")
    n = M.shape[0]
    if K.shape != (n, n):
        raise ModelError(f"K must be {n} x {n} like M, got {K.shape}")
    return M, K, ref


def read_sector(M=None, K=None, *, n_sectors: int, D=None, full=None, left_dofs=None,
                right_dofs=None, left_nodes=None, right_nodes=None,
                named_nodes: Mapping[str, Sequence[int]] | None = None,
                named_dofs: Mapping[str, Sequence[int]] | None = None, dof_reference=None,
                frame: str = "cylindrical", axis="z", name: str = "sector"):
    """A cyclic sector from a user's FE matrices.

    Parameters
    ----------
    M, K : path, array_like or sparse, shape (n, n)
        Sector mass [kg] and stiffness [N/m] matrices: Matrix Market paths (``.mtx``,
        symmetric or general storage; a single stored triangle is completed) or arrays.
        Omit them when ``full`` is given.
    n_sectors : int
        Number of sectors of the wheel (003: 30).
    D : path, array_like or sparse, optional
        Sector damping matrix [N s/m].
    full : path, optional
        ANSYS ``.full`` file with the sector's M and K (needs ``ansys-mapdl-reader``); its
        DOF reference lets cuts and contact nodes be given by node number.
    left_dofs, right_dofs : sequence of int or path, optional
        0-based DOF indices of the left and right cuts (``right_dofs[k]`` is the image of
        ``left_dofs[k]`` on the next sector), or text files holding them.
    left_nodes, right_nodes : sequence of int or path, optional
        Node numbers of the cuts instead (needs a DOF reference); node ``left_nodes[k]``
        pairs with ``right_nodes[k]`` and their DOFs are taken component by component.
    named_nodes : mapping of str to sequence of int, optional
        Named node groups (e.g. the contact nodes ``{"contact_A": [167179]}``), needs a DOF
        reference; stored as DOF indices in ``CyclicSector.named_dofs``.
    named_dofs : mapping of str to sequence of int, optional
        Named groups given directly as DOF indices.
    dof_reference : (n, 2) array_like or path, optional
        Node number and component of each DOF for Matrix Market input (taken from the file
        with ``full``).
    frame, axis
        DOF frames of the cuts (see :class:`~fricdamp.structure.cyclic.CyclicSector`).
        ANSYS nodal frames rotated to a cylindrical system give ``"cylindrical"``; global
        Cartesian DOFs give ``"cartesian"`` with ``axis`` the wheel axis.
    name : str
        Label.

    Returns
    -------
    CyclicSector

    Raises
    ------
    ModelError
        Missing files, inconsistent sizes, DOFs out of range, nodes not in the model, or
        ``.full`` input without ``ansys-mapdl-reader``.
    """
    from fricdamp.structure.cyclic import CyclicSector

    M, K, ref = _read_km(K, M, full, dof_reference, "read_sector")
    n = M.shape[0]
    if D is not None:
        D = _complete_triangle(read_matrix(D, "D"), "D")
        if D.shape != (n, n):
            raise ModelError(f"D must be {n} x {n} like M, got {D.shape}")
    if ref is None:
        ref = _dof_reference(dof_reference, n)

    by_dofs = left_dofs is not None or right_dofs is not None
    by_nodes = left_nodes is not None or right_nodes is not None
    if by_dofs == by_nodes:
        raise ModelError("give the cuts either as left_dofs= and right_dofs= or as "
                         "left_nodes= and right_nodes=")
    if by_dofs:
        left = _index_list("left_dofs", left_dofs)
        right = _index_list("right_dofs", right_dofs)
        if left is None or right is None:
            raise ModelError("give both left_dofs= and right_dofs=")
    else:
        if ref is None:
            raise ModelError("left_nodes/right_nodes need a DOF reference (dof_reference= "
                             "or an ANSYS .full file)")
        ln = _index_list("left_nodes", left_nodes)
        rn = _index_list("right_nodes", right_nodes)
        if ln is None or rn is None or ln.size != rn.size:
            raise ModelError("left_nodes and right_nodes must both be given, same length")
        left, lc = _node_dofs("left_nodes", ln, ref)
        right, rc = _node_dofs("right_nodes", rn, ref)
        for a, b, ca, cb in zip(ln, rn, lc, rc, strict=True):
            if ca != cb:
                raise ModelError(f"left node {int(a)} has components {ca} but right node "
                                 f"{int(b)} has {cb}; paired nodes need the same DOFs")
            if frame == "cartesian" and ca not in ((0, 1, 2), (0, 1, 2, 3, 4, 5)):
                raise ModelError(f"with frame='cartesian' each cut node needs the vector "
                                 f"components UX, UY, UZ (and ROTX, ROTY, ROTZ); node "
                                 f"{int(a)} has {ca}")
    named: dict[str, np.ndarray] = {}
    for key, nodes in dict(named_nodes or {}).items():
        if ref is None:
            raise ModelError("named_nodes need a DOF reference (dof_reference= or an ANSYS "
                             ".full file); give named_dofs= with DOF indices otherwise")
        named[str(key)] = _node_dofs(f"named_nodes[{key!r}]",
                                     _index_list(f"named_nodes[{key!r}]", nodes), ref)[0]
    for key, dofs in dict(named_dofs or {}).items():
        if str(key) in named:
            raise ModelError(f"name {key!r} is given both in named_nodes and named_dofs")
        named[str(key)] = _index_list(f"named_dofs[{key!r}]", dofs)
    dof_names = None
    if ref is not None:
        dof_names = tuple(
            f"n{nd}.{COMPONENT_LABELS[c] if 0 <= c < len(COMPONENT_LABELS) else c}"
            for nd, c in ref)
    return CyclicSector(M=M, K=K, D=D, left=left, right=right, n_sectors=n_sectors,
                        frame=frame, axis=axis, named_dofs=named, dof_names=dof_names,
                        name=name)


def solid_with_matrices(solid, *, K=None, M=None, full=None, dof_reference=None,
                        fixed_nodes: str | Sequence[int] | None = None):
    """A :class:`~fricdamp.structure.solid.SolidModel` with its K and M from matrix files.

    The mesh of ``solid`` keeps the geometry (faces, normals, tributary areas, node sets:
    what the contact patches and cyclic cuts need); the matrices of the FE program that
    made the model replace fricdamp's assembly, so an imported sector runs with exactly
    the stiffness and mass the engineer has (element formulation, materials, bolted parts).

    Parameters
    ----------
    solid : SolidModel
        The sector assembled from its mesh (:func:`~fricdamp.structure.solid.assemble_solid`);
        its matrices are replaced.
    K, M : path or sparse matrix, optional
        Stiffness [N/m] and mass [kg], Matrix Market files (``.mtx``; one stored triangle
        is completed). Give both, or ``full``.
    full : path, optional
        ANSYS ``.full`` file (needs ``ansys-mapdl-reader``); its DOF reference is used.
    dof_reference : (n, 2) array_like or path, optional
        Node number and component (0 UX, 1 UY, 2 UZ) of each matrix row, for Matrix Market
        input. **Node numbers are the 1-based positions of the points in the mesh file**
        (gmsh node tags when they are contiguous, the usual case). Default: the matrices
        are in fricdamp's own order, ``3 (node) + component`` over the FE nodes.
    fixed_nodes : str or sequence of int, optional
        The supported nodes (a node-set name, e.g. the clamp, or FE node indices): the only
        nodes whose DOFs may be absent from the matrices (FE programs drop constrained DOFs,
        as ANSYS ``.full`` files do).

    Returns
    -------
    SolidModel
        ``solid`` with ``K`` and ``M`` replaced (``parts`` emptied); absent DOFs of fixed
        nodes get unit diagonals (they are removed with the supports).

    Raises
    ------
    ModelError
        Unreadable or inconsistent files, rotational DOFs, nodes that are not in the mesh,
        or free DOFs missing from the matrices.
    """
    from dataclasses import replace

    M, K, ref = _read_km(K, M, full, dof_reference, "matrix import")
    K, M = sp.csr_matrix(K, dtype=float), sp.csr_matrix(M, dtype=float)
    n = K.shape[0]
    target = _mesh_targets(solid, ref if ref is not None else dof_reference, n,
                           "the matrices")
    present = np.zeros(solid.n_dof, dtype=bool)
    present[target] = True
    missing = np.flatnonzero(~present)
    if missing.size:
        fixed = np.zeros(solid.n_nodes, dtype=bool)
        if fixed_nodes is not None:
            fixed[solid.node_ids(fixed_nodes)] = True
        free_missing = missing[~fixed[missing // 3]]
        if free_missing.size:
            d = int(free_missing[0])
            pts = np.flatnonzero(solid.point_nodes == d // 3)
            where = (f"node {int(pts[0]) + 1}" if pts.size else
                     f"generated mid-side node {d // 3 + 1}")
            raise ModelError(f"{free_missing.size} DOF(s) of unsupported nodes are not in the "
                             f"matrices, first: {where} component {d % 3}; export the whole "
                             "sector or name its supports")
    Pm = sp.csr_matrix((np.ones(n), (target, np.arange(n))), shape=(solid.n_dof, n))
    pad = sp.diags((~present).astype(float))
    K_new = (Pm @ K @ Pm.T + pad).tocsr()
    M_new = (Pm @ M @ Pm.T + pad).tocsr()
    return replace(solid, K=K_new, M=M_new, parts={})


def matrix_on_mesh(solid, A, *, dof_reference=None, name: str = "matrix") -> sp.csr_matrix:
    """A further matrix of the FE program (e.g. stress stiffening or spin softening) mapped
    onto the DOFs of ``solid`` like :func:`solid_with_matrices` maps K and M: rows by
    ``dof_reference`` (node number = 1-based mesh point, component 0-2), or in fricdamp's
    order without it; absent DOFs get zero rows and columns.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (solid.n_dof, solid.n_dof)
    """
    A = sp.csr_matrix(_complete_triangle(read_matrix(A, name), name), dtype=float)
    n = A.shape[0]
    if A.shape != (n, n):
        raise ModelError(f"{name} must be a square matrix, got shape {A.shape}")
    target = _mesh_targets(solid, dof_reference, n, name)
    Pm = sp.csr_matrix((np.ones(n), (target, np.arange(n))), shape=(solid.n_dof, n))
    return (Pm @ A @ Pm.T).tocsr()


def _mesh_targets(solid, dof_reference, n: int, name: str) -> np.ndarray:
    """DOF of ``solid`` of each of ``n`` matrix rows: by the (node, component) reference
    (node = 1-based mesh point, component 0-2), or fricdamp's own order without one."""
    ref = dof_reference if isinstance(dof_reference, np.ndarray) and \
        dof_reference.dtype.kind == "i" and dof_reference.shape == (n, 2) else \
        _dof_reference(dof_reference, n)
    if ref is None:
        if n != solid.n_dof:
            raise ModelError(f"{name} have {n} rows but the mesh has {solid.n_dof} DOFs "
                             f"(3 x {solid.n_nodes} nodes); give a dof_reference to map "
                             "them (node number, component per row)")
        return np.arange(n)
    bad = (ref[:, 1] > 2) | (ref[:, 1] < 0)
    if np.any(bad):
        node, comp = ref[bad][0]
        raise ModelError(f"dof_reference: component {int(comp)} of node {int(node)} is not a "
                         "translation (0 UX, 1 UY, 2 UZ); solid sectors have no rotational "
                         "DOFs")
    n_pts = solid.point_nodes.size
    nodes = ref[:, 0]
    if nodes.min() < 1 or nodes.max() > n_pts:
        raise ModelError(f"dof_reference: node numbers must lie in [1, {n_pts}] (1-based "
                         f"positions of the mesh points), got {int(nodes.min())} to "
                         f"{int(nodes.max())}")
    fe = solid.point_nodes[nodes - 1]
    if np.any(fe < 0):
        raise ModelError(f"dof_reference: node {int(nodes[fe < 0][0])} is not a node of the "
                         "mesh's volume elements")
    return 3 * fe + ref[:, 1]
