"""ANSYS archive (``.cdb``) meshes: ``read_mesh`` through ansys-mapdl-reader (structure/io.py).

ansys-mapdl-reader is the optional extra ``[ansys]``; CI installs it (README's test command).

References:

* ANSYS-written files shipped with the reader: ``HexBeam.cdb`` (SOLID186, a 1 x 1 x 5 bar of
  2 x 2 x 10 bricks) must give the *same* model as fricdamp's own structured ``box_mesh`` of
  that bar (hex20, validated against Timoshenko in test_solid_closed_forms.py): equal
  eigenfrequencies to 1e-9 prove that SOLID186's node order (corners, then the 12 mid-side
  nodes) is read as meshio's ``hexahedron20`` order -- a swapped mid-side node distorts the
  element and moves them by percents. ``file.full`` holds that bar's K and M from ANSYS
  (nodes 1-21, the z = 0 face, constrained): mapped onto the archive's mesh by node number
  it must give the .full's own frequencies (1e-8, two eigen-solvers).
* A round trip through the reader's own writer (``save_as_archive``) of the coarse example
  sector with permuted, gapped node numbers and two materials: the same geometry, node sets
  and element sets, and the same frequencies as the gmsh route (1e-9).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse.linalg as spla

reader = pytest.importorskip("ansys.mapdl.reader")

from fricdamp.errors import ModelError  # noqa: E402
from fricdamp.structure.solid import (  # noqa: E402
    SolidMesh,
    assemble_solid,
    box_mesh,
    read_mesh,
)

MESH = Path(__file__).resolve().parents[2] / "examples" / "meshes" / "tieboss_sector_coarse.msh"
STEEL = dict(youngs_modulus=2.1e11, poisson_ratio=0.3, density=7850.0)


def _clamped_frequencies(solid, clamp, n=8):
    """Lowest n frequencies [Hz] with the clamp's DOFs removed (dense below 2,000 DOFs,
    sparse shift-invert above)."""
    fixed = solid.dofs[solid.node_ids(clamp)].ravel()
    free = np.setdiff1d(np.arange(solid.n_dof), fixed)
    k = solid.K[free][:, free]
    m = solid.M[free][:, free]
    if free.size < 2000:
        lam = sla.eigh(k.toarray(), m.toarray(), eigvals_only=True,
                       subset_by_index=[0, n - 1])
    else:
        lam = np.sort(spla.eigsh(k.tocsc(), n, m.tocsc(), sigma=0.0, which="LM",
                                 return_eigenvectors=False))
    return np.sqrt(lam) / (2 * np.pi)


def _with_clamp(mesh: SolidMesh, nodes) -> SolidMesh:
    return SolidMesh(mesh.points, mesh.cell_type, mesh.cells,
                     point_sets={**mesh.point_sets, "clamp": nodes}, cell_sets=mesh.cell_sets)


def test_ansys_hex20_bar_equals_the_structured_box_mesh():
    from ansys.mapdl.reader import examples

    m = read_mesh(examples.hexarchivefile)
    assert m.cell_type == "hexahedron20" and m.cells.shape == (40, 20)
    assert m.volume() == pytest.approx(5.0, rel=1e-12)
    # node and element components become named sets
    assert {"NCOMP2", "NODE_SELECTION", "ECOMP1", "ECOMP2", "MAT1"} <= set(m.point_sets)
    assert m.cell_sets["ECOMP1"].size == 22 and m.cell_sets["MAT1"].size == 40
    z0 = np.flatnonzero(np.abs(m.points[:, 2]) < 1e-12)
    assert z0.size == 21
    f_cdb = _clamped_frequencies(assemble_solid(_with_clamp(m, z0), **STEEL), "clamp")
    b = box_mesh((1.0, 1.0, 5.0), (2, 2, 10), cell_type="hexahedron20")
    f_box = _clamped_frequencies(assemble_solid(b, **STEEL), "zmin")
    np.testing.assert_allclose(f_cdb, f_box, rtol=1e-9)


def test_full_file_maps_onto_the_archive_mesh_by_node_number():
    from ansys.mapdl.reader import examples

    from fricdamp.structure.io import read_ansys_full, solid_with_matrices

    M, K, ref = read_ansys_full(examples.fullfile)
    lam = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True, subset_by_index=[0, 7])
    f_full = np.sqrt(lam) / (2 * np.pi)
    m = read_mesh(examples.hexarchivefile)
    clamp = np.setdiff1d(np.arange(1, m.points.shape[0] + 1), ref[:, 0]) - 1
    np.testing.assert_array_equal(np.abs(m.points[clamp, 2]) < 1e-12, True)
    solid = solid_with_matrices(assemble_solid(_with_clamp(m, clamp), **STEEL),
                                full=examples.fullfile, fixed_nodes="clamp")
    np.testing.assert_allclose(_clamped_frequencies(solid, "clamp"), f_full, rtol=1e-8)


def _sector_archive(tmp_path, materials=True):
    """The coarse example sector written by ansys-mapdl-reader: node numbers 1000 + 3 p + 1
    for a random permutation p, materials 1 (steel) and 2 (tip mass) as MAT numbers."""
    import pyvista as pv
    from ansys.mapdl.reader import save_as_archive

    m = read_mesh(MESH)
    grid = pv.UnstructuredGrid({24: m.cells}, m.points)
    nn = 1000 + 3 * np.random.default_rng(1).permutation(m.points.shape[0]) + 1
    grid.point_data["ansys_node_num"] = nn.astype(np.int32)
    mat = np.ones(m.n_cells, np.int32)
    mat[m.cell_sets["tipmass"]] = 2
    grid.cell_data["ansys_material_type"] = mat
    for k, v in m.point_sets.items():
        a = np.zeros(m.points.shape[0], bool)
        a[v] = True
        grid.point_data[k.upper()] = a
    path = tmp_path / "sector.cdb"
    save_as_archive(str(path), grid)
    return m, nn, path


def test_sector_round_trip_through_the_ansys_writer(tmp_path):
    m, nn, path = _sector_archive(tmp_path)
    a = read_mesh(path)
    assert a.cell_type == "tetra10"
    assert a.points.shape[0] == nn.max()  # laid out by node number
    # NBLOCK stores 13 significant digits
    np.testing.assert_allclose(a.points[nn - 1], m.points, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(a.cells, (nn - 1)[m.cells])
    for k, v in m.point_sets.items():
        np.testing.assert_array_equal(a.point_sets[k.upper()], np.sort(nn[v] - 1))
    np.testing.assert_array_equal(a.cell_sets["MAT2"], m.cell_sets["tipmass"])
    s_msh = assemble_solid(m, materials={"tipmass": {"density": 24250.0}}, **STEEL)
    s_cdb = assemble_solid(a, materials={"MAT2": {"density": 24250.0}}, **STEEL)
    assert s_cdb.n_dof == s_msh.n_dof  # unused node numbers carry no DOF
    np.testing.assert_allclose(_clamped_frequencies(s_cdb, "CLAMP", 6),
                               _clamped_frequencies(s_msh, "clamp", 6), rtol=1e-9)


def test_mixed_element_types_and_missing_files_are_one_line_errors(tmp_path):
    from ansys.mapdl.reader import examples

    with pytest.raises(ModelError, match=r"sector\.cdb: mixed volume cell types "
                                         r"\['hexahedron', 'wedge'\]"):
        read_mesh(examples.sector_archive_file)
    with pytest.raises(ModelError, match="does not exist"):
        read_mesh(tmp_path / "absent.cdb")
    bad = tmp_path / "bad.cdb"
    bad.write_text("this is no archive\n")
    with pytest.raises(ModelError, match=r"bad\.cdb"):
        read_mesh(bad)
