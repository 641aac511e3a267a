"""Solid tie-boss sector (paper 003 wheel) meshed with gmsh: groups, periodicity, sizes."""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import contact_frame
from fricdamp.models.tieboss_wheel.solid import (
    SolidWheelParameters,
    build_sector_mesh,
    build_solid_sector,
    contact_centres,
    match_periodic_nodes,
)

pytest.importorskip("gmsh")
pytest.importorskip("meshio")

COARSE = SolidWheelParameters(mesh_size_m=0.012)
GROUPS = ("clamp", "cut_left", "cut_right", "contact_left", "contact_right", "steel",
          "tipmass", "load", "probe", "probe_left", "tip")


def group_nodes(mesh, name):
    return mesh.point_sets[name]


@pytest.fixture(scope="module")
def coarse():
    return build_sector_mesh(COARSE)


def test_groups_present(coarse):
    assert set(GROUPS) <= set(coarse.point_sets)
    assert set(coarse.cell_sets) == {"steel", "tipmass"}
    assert coarse.cell_type == "tetra10"
    assert coarse.cell_sets["steel"].size + coarse.cell_sets["tipmass"].size == coarse.n_cells
    assert group_nodes(coarse, "load").size == 2
    for name in ("probe", "probe_left", "tip"):
        assert group_nodes(coarse, name).size == 1


def test_element_count_and_straight_edges(coarse):
    tets = coarse.cells
    assert 1000 < tets.shape[0] < 5000
    x = coarse.points
    # meshio order: mid-side nodes 4..9 on the edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3)
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    for k, (a, b) in enumerate(edges):
        mid = 0.5 * (x[tets[:, a]] + x[tets[:, b]])
        assert np.abs(x[tets[:, 4 + k]] - mid).max() < 1e-12


def test_default_mesh_size():
    """Paper 003: 89,000 hexahedra for the wheel, ~3,000 per sector; the default has more."""
    assert build_sector_mesh().n_cells >= 3000


@pytest.mark.parametrize("pair", [("cut_left", "cut_right"), ("contact_left", "contact_right")])
def test_periodic_faces_match_node_to_node(coarse, pair):
    p = COARSE
    left, right = (group_nodes(coarse, name) for name in pair)
    assert left.size == right.size > 20
    a = p.sector_angle_rad
    R = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0, 0, 1.0]])
    lo, ro = match_periodic_nodes(coarse.points, left, right, a)
    assert np.abs(coarse.points[ro] - coarse.points[lo] @ R.T).max() < 1e-9


def test_periodic_mismatch_is_detected(coarse):
    left, right = group_nodes(coarse, "cut_left"), group_nodes(coarse, "cut_right")
    with pytest.raises(ModelError, match="node for node"):
        match_periodic_nodes(coarse.points, left, right, 1.01 * COARSE.sector_angle_rad)


def test_contact_faces(coarse):
    p = COARSE
    frame = contact_frame(p.sector_angle_rad, p.contact_plane_angle_deg)
    c_right, c_left = contact_centres(p)
    x = coarse.points
    right = x[group_nodes(coarse, "contact_right")]
    assert right.shape[0] >= 25
    assert right.shape[0] == (2 * p.contact_divisions + 1) ** 2
    # on the cutting plane beta_B (through the wheel centre) and inside the square
    assert np.abs(right @ frame[0]).max() < 1e-9
    local = (right - c_right) @ frame.T
    assert np.abs(local[:, 1:]).max() == pytest.approx(p.contact_face_size_m / 2, rel=1e-9)
    assert np.allclose(x[group_nodes(coarse, "probe")], c_right, atol=1e-12)
    assert np.allclose(x[group_nodes(coarse, "probe_left")], c_left, atol=1e-12)
    assert np.linalg.norm(c_right) == pytest.approx(0.44)


def test_mesh_cache_and_file(tmp_path, coarse):
    from fricdamp.structure.solid import read_mesh

    path = tmp_path / "sector.msh"
    again = build_sector_mesh(COARSE.with_(tipmass_density_kg_m3=9000.0), path=path)
    assert again is coarse                      # same geometry: cached
    assert not coarse.points.flags.writeable
    assert path.read_text().startswith("$MeshFormat\n4.1 0")
    back = read_mesh(path)
    assert np.array_equal(back.points, coarse.points)
    assert np.array_equal(back.point_sets["contact_right"], coarse.point_sets["contact_right"])


def test_gmsh_finalized(coarse):
    import gmsh

    assert not gmsh.isInitialized()


@pytest.mark.parametrize("changes, match", [
    ({"disk_thickness_m": -0.01}, "disk_thickness_m must be > 0"),
    ({"rim_radius_m": 0.35}, "radii must satisfy"),
    ({"mesh_size_m": 0.0005}, r"mesh_size_m must lie in \[0.0015, 0.03\]"),
    ({"contact_divisions": 1}, r"contact_divisions must be an integer in \[2, 8\]"),
    ({"blade_angle_deg": 95.0}, r"blade_angle_deg must lie in \[0.0, 90.0\)"),
    ({"contact_face_size_m": 0.02}, "contact_face_size_m must lie in"),
])
def test_bad_parameters_one_line(changes, match):
    with pytest.raises(ModelError, match=match) as info:
        SolidWheelParameters(**changes)
    assert "\n" not in str(info.value)


def test_overlapping_neighbours_rejected():
    with pytest.raises(ModelError, match="blade_width_m/blade_thickness_m too large") as info:
        build_sector_mesh(SolidWheelParameters(blade_width_m=0.06, root_width_m=0.03))
    assert "\n" not in str(info.value)


def rotation(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@pytest.fixture(scope="module")
def sector():
    pytest.importorskip("skfem")
    return build_solid_sector(COARSE)


def test_sector_groups(sector):
    cyc = sector.cyclic
    n_face = (2 * COARSE.contact_divisions + 1) ** 2
    sizes = {"contact_left": 3 * n_face, "contact_right": 3 * n_face, "load": 6, "probe": 3,
             "probe_left": 3, "tip": 3}
    assert {k: cyc.named_dofs[k].size for k in sizes} == sizes
    assert cyc.frame == "cartesian" and cyc.n_sectors == 30
    assert sector.wheel_sector.patch.n_pairs == n_face
    assert sector.n_dof == sector.kept_dofs.size == cyc.K.shape[0]
    clamped = sector.model.dofs[sector.model.node_sets["clamp"]].ravel()
    assert np.intersect1d(clamped, sector.kept_dofs).size == 0


def test_sector_cuts_and_contacts_pair_by_rotation(sector):
    R = rotation(COARSE.sector_angle_rad)
    x = sector.model.points
    left = x[sector.kept_dofs[sector.cyclic.left[0::3]] // 3]
    right = x[sector.kept_dofs[sector.cyclic.right[0::3]] // 3]
    assert np.abs(right - left @ R.T).max() < 1e-9
    assert np.all(sector.kept_dofs[sector.cyclic.left] % 3 == np.tile([0, 1, 2], len(left)))
    cl, cr = sector.group_points("contact_left"), sector.group_points("contact_right")
    assert np.abs(cr - cl @ R.T).max() < 1e-9
    assert np.allclose(sector.group_points("probe")[0], contact_centres(COARSE)[0])


def test_sector_masses(sector):
    """The tip-mass volume is the block less the blade: exact on straight-edged tets."""
    _, M_tip = sector.model.parts["tipmass"]
    ex = np.zeros(sector.model.n_dof)
    ex[0::3] = 1.0
    assert ex @ (M_tip @ ex) == pytest.approx(COARSE.tipmass_kg, rel=1e-9)
    assert 0.4 < COARSE.tipmass_kg < 0.5
    facets = sector.contact_facets("right")
    assert facets.shape == (2 * COARSE.contact_divisions ** 2, 6)
    area = sector.model.facet_areas(facets).sum()
    assert area == pytest.approx(COARSE.contact_face_size_m ** 2, rel=1e-9)
    normals = sector.model.facet_normals(facets)
    assert np.allclose(normals, sector.frame[0], atol=1e-9)
