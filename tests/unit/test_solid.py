"""Unit tests of the 3D solid finite elements (structure/solid.py and its _solid_* modules).

Patch tests on distorted meshes, rigid-body modes and exact mass and inertia, the fast
assembly against scikit-fem's own ``asm(linear_elasticity)``, node and DOF numbering, named
sets, surface facets and nodal areas, material regions, mesh reading (gmsh, Abaqus, VTU)
and the input errors. Closed-form frequencies are in validation/test_solid_closed_forms.py.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.linalg as sl
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

from fricdamp.errors import ModelError
from fricdamp.structure._solid_mesh import add_midside_nodes
from fricdamp.structure.solid import (
    SolidMesh,
    SolidModel,
    assemble_solid,
    box_mesh,
    mesh_from_meshio,
    read_mesh,
)

E, NU, RHO = 210e9, 0.3, 7800.0
STEEL = dict(youngs_modulus=E, poisson_ratio=NU, density=RHO)
LAM, MU = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
SIZE = np.array([1.0, 0.8, 0.6])
#: element -> (linear cell type of the generated box, input cell type)
CASES = {"tet4": ("tetra", "tetra"), "tet10": ("tetra", "tetra10"),
         "hex8": ("hexahedron", "hexahedron"), "hex20": ("hexahedron", "hexahedron20")}


@pytest.fixture(autouse=True)
def _one_blas_thread():
    with threadpool_limits(limits=1):
        yield


def jiggled_box(element: str, *, seed: int = 0, curved: bool = False) -> SolidMesh:
    """A 3x3x3 box mesh with interior vertices moved randomly by up to 0.2 h per axis.

    Quadratic meshes get straight mid-side nodes after the jiggling (affine tet10 / straight
    hex20); ``curved`` also moves the interior mid-side points off the chord midpoints (tet10
    then uses skfem's isoparametric MeshTet2).
    """
    linear, cell_type = CASES[element]
    base = box_mesh(SIZE, (3, 3, 3), cell_type=linear)
    rng = np.random.default_rng(seed)
    p = base.points.copy()
    inner = np.all((p > 1e-9) & (p < SIZE - 1e-9), axis=1)
    p[inner] += rng.uniform(-0.2, 0.2, (inner.sum(), 3)) * SIZE / 3
    cells = base.cells
    if cell_type != linear:
        p, cells = add_midside_nodes(p, cells, linear)
        if curved:
            mid = np.arange(len(base.points), len(p))
            inner = mid[np.all((p[mid] > 1e-9) & (p[mid] < SIZE - 1e-9), axis=1)]
            p[inner] += rng.uniform(-0.05, 0.05, (len(inner), 3)) * SIZE / 3
    return SolidMesh(points=p, cell_type=cell_type, cells=cells)


def rigid_modes(points: np.ndarray) -> np.ndarray:
    """(3 n, 6) rigid translations and small rotations about the origin, node-major."""
    n = len(points)
    R = np.zeros((n, 3, 6))
    for i in range(3):
        R[:, i, i] = 1.0
    x, y, z = points.T
    R[:, 1, 3], R[:, 2, 3] = -z, y          # rotation about x
    R[:, 0, 4], R[:, 2, 4] = z, -x          # about y
    R[:, 0, 5], R[:, 1, 5] = -y, x          # about z
    return R.reshape(3 * n, 6)


# ---------------------------------------------------------------------------- patch tests
@pytest.mark.parametrize("element,curved", [("tet4", False), ("tet10", False), ("tet10", True),
                                            ("hex8", False), ("hex20", False)])
def test_patch_test_reproduces_constant_strain_on_distorted_mesh(element, curved):
    """Irons' patch test: a linear displacement imposed on the boundary of a distorted mesh
    is reproduced in the interior, with the exact constant-strain energy.

    Reference: Zienkiewicz, Taylor & Zhu (2013), sec. 9.3. Tolerance 1e-10 relative: the
    field lies in every element's span, so only round-off (cond(K) ~ 1e4 times eps) remains.
    """
    model = assemble_solid(jiggled_box(element, seed=1, curved=curved), **STEEL)
    A = np.array([[1.0, 0.3, -0.2], [0.1, -0.5, 0.4], [0.25, 0.2, 0.7]]) * 1e-3
    u_exact = (model.points @ A.T + np.array([1e-4, -2e-4, 3e-4])).ravel()
    on_face = np.any((np.abs(model.points) < 1e-9) | (np.abs(model.points - SIZE) < 1e-9), axis=1)
    bnd = model.set_dofs(np.flatnonzero(on_face))
    free = np.setdiff1d(np.arange(model.n_dof), bnd)
    K = model.K
    u = u_exact.copy()
    u[free] = spla.spsolve(K[free][:, free].tocsc(), -K[free][:, bnd] @ u_exact[bnd])
    assert np.max(np.abs(u - u_exact)) < 1e-10 * np.max(np.abs(u_exact))
    eps = 0.5 * (A + A.T)
    energy = 0.5 * np.prod(SIZE) * (LAM * np.trace(eps) ** 2 + 2 * MU * np.sum(eps * eps))
    assert 0.5 * u @ (K @ u) == pytest.approx(energy, rel=1e-10)


# ---------------------------------------------------------------------------- rigid body, mass
@pytest.mark.parametrize("element", list(CASES))
def test_free_solid_has_six_rigid_body_modes(element):
    """K annihilates the 6 rigid-body fields to round-off and (K, M) has exactly 6 zero
    eigenvalues: the 7th is > 1e9 times the largest of the first 6 (round-off level)."""
    model = assemble_solid(jiggled_box(element, seed=2), **STEEL)
    R = rigid_modes(model.points)
    scale = abs(model.K).max() * np.abs(R).max()
    assert np.max(np.abs(model.K @ R)) < 1e-11 * scale
    w2 = sl.eigh(model.K.toarray(), model.M.toarray(), eigvals_only=True)
    assert np.max(np.abs(w2[:6])) < 1e-9 * w2[6]
    assert w2[6] > 0


@pytest.mark.parametrize("element", list(CASES))
def test_total_mass_and_rotary_inertia_are_exact(element):
    """Mass = rho V (every element, distorted mesh) and, on a regular box, the moment of
    inertia about the centroidal x axis rho V (Ly^2 + Lz^2) / 12: the quadrature rules are
    exact for these polynomial integrands (relative tolerance 1e-12, round-off)."""
    jig = assemble_solid(jiggled_box(element, seed=3), **STEEL)
    assert jig.total_mass() == pytest.approx(RHO * np.prod(SIZE), rel=1e-12)
    linear, cell_type = CASES[element]
    model = assemble_solid(box_mesh(SIZE, (3, 2, 2), cell_type=cell_type, origin=-SIZE / 2),
                           **STEEL)
    rot = rigid_modes(model.points)[:, 3]
    inertia = RHO * np.prod(SIZE) * (SIZE[1] ** 2 + SIZE[2] ** 2) / 12
    assert rot @ (model.M @ rot) == pytest.approx(inertia, rel=1e-12)


@pytest.mark.parametrize("element,curved", [("tet4", False), ("tet10", False), ("tet10", True),
                                            ("hex8", False), ("hex20", False)])
def test_fast_assembly_equals_skfem_linear_elasticity(element, curved):
    """The batched assembly equals skfem's asm(linear_elasticity) and vector mass form,
    with per-element materials, to round-off (1e-13 of the largest entry)."""
    mesh = jiggled_box(element, seed=4, curved=curved)
    mesh = dataclasses.replace(mesh, cell_sets={"hard": np.arange(0, mesh.n_cells, 3)})
    kw = dict(STEEL, materials={"hard": {"youngs_modulus": 3 * E, "poisson_ratio": 0.2,
                                         "density": 2 * RHO}})
    fast = assemble_solid(mesh, **kw)
    ref = assemble_solid(mesh, method="skfem", **kw)
    for A, B in ((fast.K, ref.K), (fast.M, ref.M)):
        assert abs(A - B).max() < 1e-13 * abs(B).max()
        assert abs(A - A.T).max() == 0.0


# ---------------------------------------------------------------------------- numbering
def test_quadratic_mesh_nodes_are_its_points_and_match_generated_midside_nodes():
    """A tetra10 mesh keeps its point numbering; tet10 on the tetra mesh appends the same
    mid-side nodes, and both give the same K and M after matching nodes by position."""
    quad = box_mesh((0.3, 0.2, 0.1), (3, 2, 1), cell_type="tetra10")
    lin = box_mesh((0.3, 0.2, 0.1), (3, 2, 1), cell_type="tetra")
    a = assemble_solid(quad, **STEEL)
    b = assemble_solid(lin, element="tet10", **STEEL)
    np.testing.assert_array_equal(a.point_nodes, np.arange(len(quad.points)))
    np.testing.assert_array_equal(b.point_nodes, np.arange(len(lin.points)))
    np.testing.assert_array_equal(a.dofs, np.arange(a.n_dof).reshape(-1, 3))
    np.testing.assert_array_equal(a.set_dofs([2, 0]), [6, 7, 8, 0, 1, 2])
    order_a = np.lexsort(np.round(a.points, 12).T)
    order_b = np.lexsort(np.round(b.points, 12).T)
    np.testing.assert_allclose(a.points[order_a], b.points[order_b], atol=1e-15)
    perm = np.empty(a.n_nodes, dtype=int)
    perm[order_a] = order_b                       # node of b at the position of node i of a
    d = b.dofs[perm].ravel()
    for A, B in ((a.K, b.K), (a.M, b.M)):
        assert abs(A - B[d][:, d]).max() < 1e-12 * abs(A).max()
    for name in ("xmin", "ymax", "zmin"):     # face sets complete with generated mid-nodes
        np.testing.assert_array_equal(np.sort(perm[a.node_sets[name]]), b.node_sets[name])
    np.testing.assert_array_equal(a.elements[:, :4], quad.cells[:, :4])


def test_node_helpers():
    model = assemble_solid(box_mesh((0.4, 0.2, 0.1), (4, 2, 1), cell_type="hexahedron20"),
                           **STEEL)
    root = model.nodes_where(lambda x: x[:, 0] < 1e-9)
    np.testing.assert_array_equal(root, model.node_sets["xmin"])
    assert model.element_size("xmin") == pytest.approx(0.1)
    assert model.n_elements == 8 and model.element_type == "hex20"
    with pytest.raises(ModelError, match="node set 'nope' not found"):
        model.set_dofs("nope")
    with pytest.raises(ModelError, match="node indices must lie in"):
        model.set_dofs([model.n_nodes])
    with pytest.raises(ModelError, match="predicate must return"):
        model.nodes_where(lambda x: x[:, 0][:3] > 0)


# ---------------------------------------------------------------------------- surfaces
@pytest.mark.parametrize("element", list(CASES))
def test_face_areas_and_outward_normals(element):
    """Facets of the box faces: positive nodal weights summing to the face area, unit
    outward normals, and the whole boundary area 2 (ab + bc + ca) (flat facets: exact)."""
    L = np.array([0.3, 0.2, 0.1])
    model = assemble_solid(box_mesh(L, (3, 2, 2), cell_type=CASES[element][1]), **STEEL)
    for axis, name in enumerate("xyz"):
        for side, sign in (("min", -1.0), ("max", 1.0)):
            facets = model.surface_facets(name + side)
            nodes, areas = model.tributary_areas(facets)
            area = np.prod(np.delete(L, axis))
            assert np.all(areas > 0)
            assert areas.sum() == pytest.approx(area, rel=1e-12)
            np.testing.assert_array_equal(nodes, model.node_sets[name + side])
            expected = sign * np.eye(3)[axis]
            np.testing.assert_allclose(model.facet_normals(facets),
                                       np.tile(expected, (len(facets), 1)), atol=1e-12)
            _, normals = model.node_normals(facets)
            np.testing.assert_allclose(normals, np.tile(expected, (len(normals), 1)),
                                       atol=1e-12)
    total = model.facet_areas(model.boundary_facets).sum()
    assert total == pytest.approx(2 * (L[0] * L[1] + L[1] * L[2] + L[2] * L[0]), rel=1e-12)


def test_quadratic_facet_weights_are_equal_shares_of_sub_facets():
    """A flat tri6 of area A: corners get A/12 (a third of their corner sub-triangle),
    mid-side nodes A/4 (a third of three sub-triangles); a flat quad8 of area A: corners
    A/24, mid-side nodes A/8 + A/8 (two corner triangles of A/8 shared by 3, plus a quarter
    of the inner quadrilateral of area A/2). All positive, unlike consistent weights."""
    model = assemble_solid(box_mesh((1.0, 1.0, 1.0), (1, 1, 1), cell_type="tetra10"),
                           **STEEL)
    facet = model.surface_facets("zmin")[:1]
    nodes, w = model.tributary_areas(facet)
    A = model.facet_areas(facet)[0]
    np.testing.assert_allclose(w[np.isin(nodes, facet[0, :3])], A / 12, rtol=1e-12)
    np.testing.assert_allclose(w[np.isin(nodes, facet[0, 3:])], A / 4, rtol=1e-12)
    hexm = assemble_solid(box_mesh((1.0, 1.0, 1.0), (1, 1, 1), cell_type="hexahedron20"),
                          **STEEL)
    facet = hexm.surface_facets("zmax")
    nodes, w = hexm.tributary_areas(facet)
    np.testing.assert_allclose(w[np.isin(nodes, facet[0, :4])], 1 / 24, rtol=1e-12)
    np.testing.assert_allclose(w[np.isin(nodes, facet[0, 4:])], 1 / 12 + 1 / 8, rtol=1e-12)


# ---------------------------------------------------------------------------- materials
def test_material_regions_parts_and_scaling():
    """Per-set materials, parts summing to K and M, and with_scaled_parts equal to
    re-assembly with the scaled modulus and density (round-off)."""
    mesh = box_mesh((0.4, 0.1, 0.1), (4, 1, 1), cell_type="hexahedron20")
    mesh = dataclasses.replace(mesh, cell_sets={"tip": np.array([3])})
    kw = dict(poisson_ratio=NU, element="hex20")
    model = assemble_solid(mesh, youngs_modulus=E, density=RHO, split_by_set=True,
                           materials={"tip": {"density": 20000.0}}, **kw)
    assert model.total_mass() == pytest.approx(0.001 * (3 * RHO + 20000.0), rel=1e-12)
    assert set(model.parts) == {"rest", "tip"}
    assert abs(model.K - sum(k for k, _ in model.parts.values())).max() == 0.0
    tuned = model.with_scaled_parts(stiffness={"tip": 2.0}, mass={"tip": 0.5, "rest": 1.5})
    ref = assemble_solid(mesh, youngs_modulus=E, density=1.5 * RHO,
                         materials={"tip": {"density": 10000.0, "youngs_modulus": 2 * E}}, **kw)
    for A, B in ((tuned.K, ref.K), (tuned.M, ref.M)):
        assert abs(A - B).max() < 1e-13 * abs(B).max()
    with pytest.raises(ModelError, match="unknown regions"):
        model.with_scaled_parts(mass={"blade": 2.0})
    plain = assemble_solid(mesh, youngs_modulus=E, density=RHO, **kw)
    with pytest.raises(ModelError, match="split_by_set=True"):
        plain.with_scaled_parts(mass={"tip": 2.0})


# ---------------------------------------------------------------------------- errors
@pytest.mark.parametrize("kwargs,match", [
    (dict(youngs_modulus=0.0), "youngs_modulus must be > 0"),
    (dict(poisson_ratio=0.5), r"poisson_ratio must lie in \(-1.0, 0.5\)"),
    (dict(poisson_ratio=-1.0), "poisson_ratio"),
    (dict(density=-1.0), "density must be > 0"),
    (dict(density=float("nan")), "density must be finite"),
    (dict(element="tet4"), "element must be one of"),
    (dict(method="dense"), "method must be"),
    (dict(materials={"nope": {"density": 1.0}}), r"materials\['nope'\]: no such cell set"),
    (dict(materials={"a": {"rho": 1.0}}), "unknown keys"),
    (dict(materials={"a": {"density": 1.0}, "b": {"density": 2.0}}), "overlaps"),
    (dict(materials={"a": {"poisson_ratio": 0.7}}), r"materials\['a'\]\['poisson_ratio'\]"),
])
def test_assemble_rejects_bad_parameters(kwargs, match):
    mesh = box_mesh((0.2, 0.1, 0.1), (2, 1, 1), cell_type="tetra10")
    mesh = dataclasses.replace(mesh, cell_sets={"a": np.arange(6), "b": np.arange(5, 12)})
    with pytest.raises(ModelError, match=match) as info:
        assemble_solid(mesh, **{**STEEL, **kwargs})
    assert "\n" not in str(info.value)


def test_mesh_defects_are_reported():
    mesh = box_mesh((0.2, 0.1, 0.1), (2, 1, 1), cell_type="tetra")
    flipped = mesh.cells.copy()
    flipped[4, [1, 2]] = flipped[4, [2, 1]]
    with pytest.raises(ModelError, match="1 inverted or degenerate element.*cell 4"):
        assemble_solid(dataclasses.replace(mesh, cells=flipped), **STEEL)
    hexa = box_mesh((0.2, 0.1, 0.1), (2, 1, 1))
    flipped = hexa.cells.copy()
    flipped[1] = flipped[1, [4, 5, 6, 7, 0, 1, 2, 3]]
    with pytest.raises(ModelError, match="inverted.*cell 1"):
        assemble_solid(dataclasses.replace(hexa, cells=flipped), **STEEL)
    hex20 = box_mesh((0.2, 0.1, 0.1), (2, 1, 1), cell_type="hexahedron20")
    bent = hex20.points.copy()
    bent[hex20.cells[0, 8]] += [0.0, 0.01, 0.0]
    with pytest.raises(ModelError, match="curved edges are not supported"):
        assemble_solid(dataclasses.replace(hex20, points=bent), **STEEL)
    tet10 = box_mesh((0.2, 0.1, 0.1), (2, 1, 1), cell_type="tetra10")
    points = np.vstack([tet10.points, tet10.points[tet10.cells[0, 4]]])
    cells = tet10.cells.copy()
    cells[0, 4] = len(points) - 1                 # a duplicate mid-side point in one cell
    with pytest.raises(ModelError, match="non-conforming"):
        assemble_solid(SolidMesh(points=points, cell_type="tetra10", cells=cells), **STEEL)


@pytest.mark.parametrize("kwargs,match", [
    (dict(cell_type="wedge"), "cell_type must be one of"),
    (dict(cells=np.zeros((0, 4), int)), r"must have shape \(n_cells, 4\)"),
    (dict(cells=np.array([[0, 1, 2, 9]])), "outside"),
    (dict(points=np.zeros((4, 2))), r"shape \(n_points, 3\)"),
    (dict(point_sets={"a": [7]}), r"point_sets\['a'\]"),
])
def test_solid_mesh_rejects_bad_input(kwargs, match):
    base = dict(points=np.eye(4, 3), cell_type="tetra", cells=np.array([[3, 0, 1, 2]]))
    with pytest.raises(ModelError, match=match):
        SolidMesh(**{**base, **kwargs})


# ---------------------------------------------------------------------------- reading
def _write_gmsh_block(path, *, order: int, version: float = 4.1, volume_group: bool = True):
    """A 0.1 x 0.02 x 0.01 m block with a half-cylinder boss, physical groups "body"
    (volume), "root" (x = 0 face), "boss" (cylindrical face) and "corner" (a point).
    Returns the number of triangles gmsh put on the root face."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("block")
        box = gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.02, 0.01)
        cyl = gmsh.model.occ.addCylinder(0.05, 0.01, 0.01, 0, 0, 0.01, 0.005)
        gmsh.model.occ.fuse([(3, box)], [(3, cyl)])
        gmsh.model.occ.synchronize()
        surfaces = [t for _, t in gmsh.model.getEntities(2)]
        root = [t for t in surfaces if abs(gmsh.model.occ.getCenterOfMass(2, t)[0]) < 1e-9]
        boss = [t for t in surfaces if gmsh.model.getType(2, t) == "Cylinder"]
        corner = [t for _, t in gmsh.model.getEntities(0)
                  if np.allclose(gmsh.model.getValue(0, t, []), 0.0)]
        if volume_group:
            gmsh.model.addPhysicalGroup(3, [t for _, t in gmsh.model.getEntities(3)],
                                        name="body")
        gmsh.model.addPhysicalGroup(2, root, name="root")
        gmsh.model.addPhysicalGroup(2, boss, name="boss")
        gmsh.model.addPhysicalGroup(0, corner, name="corner")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.006)
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(order)
        n_root = sum(len(tags[0]) for tags in
                     (gmsh.model.mesh.getElements(2, t)[1] for t in root))
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return n_root


@pytest.mark.parametrize("order,version", [(2, 4.1), (1, 4.1), (2, 2.2)])
def test_read_gmsh_physical_groups(tmp_path, order, version):
    """Physical groups of every dimension become point sets (mid-side nodes included),
    the volume group a cell set; root facets equal gmsh's triangles on that face; the
    tet10 boss surface (curved edges, isoparametric) has nearly the exact area."""
    path = tmp_path / "block.msh"
    n_root = _write_gmsh_block(path, order=order, version=version)
    mesh = read_mesh(path)
    assert mesh.cell_type == ("tetra10" if order == 2 else "tetra")
    assert set(mesh.point_sets) == {"body", "root", "boss", "corner"}
    assert set(mesh.cell_sets) == {"body"}
    assert len(mesh.cell_sets["body"]) == mesh.n_cells
    np.testing.assert_allclose(mesh.points[mesh.point_sets["corner"]], [[0.0, 0.0, 0.0]])
    model = assemble_solid(mesh, **STEEL)
    root = model.surface_facets("root")
    assert len(root) == n_root
    assert set(root.ravel()) == set(model.node_sets["root"])
    assert np.all(np.abs(model.points[model.node_sets["root"], 0]) < 1e-12)
    nodes, areas = model.tributary_areas(model.surface_facets("boss"))
    exact = 2 * np.pi * 0.005 * 0.01           # lateral area of the boss cylinder
    # chordal (straight) tri3 facets lose O(h^2 / r^2); curved tri6 facets O(h^4)
    assert areas.sum() == pytest.approx(exact, rel=3e-3 if order == 2 else 5e-2)
    assert np.all(areas > 0)
    vol = 0.1 * 0.02 * 0.01 + np.pi * 0.005 ** 2 * 0.01
    assert model.total_mass() == pytest.approx(RHO * vol, rel=2e-3 if order == 2 else 3e-2)


def test_read_gmsh_without_volume_group_says_what_to_do(tmp_path):
    path = tmp_path / "surfaces_only.msh"
    _write_gmsh_block(path, order=1, volume_group=False)
    with pytest.raises(ModelError, match="surfaces_only.msh.*Mesh.SaveAll=1"):
        read_mesh(path)


def test_abaqus_and_vtu_round_trips(tmp_path):
    """meshio writes a hex20 mesh with nsets and elsets to Abaqus .inp (and VTU); reading it
    back gives the same points, cells and sets, hence the same K."""
    meshio = pytest.importorskip("meshio")
    mesh = box_mesh((0.2, 0.04, 0.02), (4, 2, 1), cell_type="hexahedron20")
    tip = np.flatnonzero(mesh.points[mesh.cells[:, :8], 0].min(axis=1) > 0.149)
    m = meshio.Mesh(mesh.points, [("hexahedron20", mesh.cells)],
                    point_sets={"ROOT": mesh.point_sets["xmin"]},
                    cell_sets={"TIP": [tip]})
    path = tmp_path / "bar.inp"
    m.write(path)
    back = read_mesh(path)
    np.testing.assert_allclose(back.points, mesh.points, atol=1e-12)
    np.testing.assert_array_equal(back.cells, mesh.cells)
    np.testing.assert_array_equal(back.point_sets["ROOT"], mesh.point_sets["xmin"])
    np.testing.assert_array_equal(back.cell_sets["TIP"], tip)
    a = assemble_solid(mesh, **STEEL)
    b = assemble_solid(back, **STEEL)
    assert abs(a.K - b.K).max() < 1e-10 * abs(a.K).max()
    vtu = tmp_path / "bar.vtu"
    meshio.Mesh(mesh.points, [("hexahedron20", mesh.cells)]).write(vtu)
    np.testing.assert_array_equal(read_mesh(vtu).cells, mesh.cells)
    assert isinstance(mesh_from_meshio(m), SolidMesh)


def test_read_errors_name_the_file(tmp_path):
    with pytest.raises(ModelError, match="nothere.msh does not exist"):
        read_mesh(tmp_path / "nothere.msh")
    bad = tmp_path / "garbage.inp"
    bad.write_text("*NODE\n1, a, b\n")
    with pytest.raises(ModelError, match="garbage.inp") as info:
        read_mesh(bad)
    assert "\n" not in str(info.value)


def test_model_is_sparse_and_frozen():
    model = assemble_solid(box_mesh((0.2, 0.1, 0.1), (2, 1, 1)), **STEEL)
    assert isinstance(model, SolidModel)
    assert model.K.format == "csr" and model.M.format == "csr"
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.K = None


def test_export_to_meshio_round_trips_the_fe_mesh(tmp_path):
    """tet10 generated on a tetra mesh exported with a mode shape, written to VTU and read
    back: the same nodes (mid-side nodes included) and elements, the field as (n, 3)."""
    model = assemble_solid(box_mesh((0.2, 0.1, 0.1), (2, 1, 1), cell_type="tetra"),
                           element="tet10", **STEEL)
    shape = np.arange(model.n_dof, dtype=float)
    path = tmp_path / "mode.vtu"
    model.to_meshio({"mode_1": shape}).write(path)
    back = read_mesh(path)
    assert back.cell_type == "tetra10"
    np.testing.assert_allclose(back.points, model.points)
    np.testing.assert_array_equal(back.cells, model.elements)
    with pytest.raises(ModelError, match=r"point_data\['bad'\]"):
        model.to_meshio({"bad": np.zeros(5)})
