"""``[model] type = "cyclic_sector"`` with the FE program's own matrices (issue 12, item 5):
``stiffness``/``mass`` Matrix Market files (or an ANSYS ``.full``) replace fricdamp's
assembly, the mesh keeps the geometry.

References, computed here independently of the case's pipeline:

* an FE program's export of the shipped coarse sector, made as ANSYS makes it: the supported
  (clamp) DOFs dropped, the rows in its own node order (here a random permutation), one
  triangle stored (``symmetry = "symmetric"``) and a (node, component) reference per row.
  Read back through the case, the open-contact frequencies by ND equal those of the mesh
  route to round-off (1e-9: the same matrices, the same eigensolver);
* the stiffness scaled by 1.21 gives every frequency times 1.1 exactly (to the eigensolver's
  1e-9): proof that the pipeline uses the files, not its own assembly.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

MESH = Path(__file__).resolve().parents[2] / "examples" / "meshes" / "tieboss_sector_coarse.msh"

CASE = f"""\
name = "import_matrices"

[model]
type = "cyclic_sector"
mesh = "{MESH.as_posix()}"
n_sectors = 30
materials = {{ tipmass = {{ density = 24250.0 }} }}
probe_direction = [0.0, 0.70710678, 0.70710678]
n_modes = 12
n_interface_modes = 24
stiffness = "K.mtx"
mass = "M.mtx"
dof_reference = "dofs.txt"

[analysis.modal]
n_modes = 1
"""


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """The sector's matrices as an FE program exports them (see the module docstring)."""
    import meshio

    from fricdamp.structure.solid import assemble_solid, mesh_from_meshio

    solid = assemble_solid(mesh_from_meshio(meshio.read(MESH)), youngs_modulus=2.1e11,
                           poisson_ratio=0.3, density=7850.0,
                           materials={"tipmass": {"density": 24250.0}})
    clamp = np.zeros(solid.n_nodes, dtype=bool)
    clamp[solid.node_sets["clamp"]] = True
    keep = solid.dofs[~clamp].ravel()
    keep = np.random.default_rng(1).permutation(keep)
    mesh_point = np.empty(solid.n_nodes, dtype=np.int64)     # FE node -> mesh point
    ok = solid.point_nodes >= 0
    mesh_point[solid.point_nodes[ok]] = np.flatnonzero(ok)
    ref = np.column_stack([mesh_point[keep // 3] + 1, keep % 3])
    d = tmp_path_factory.mktemp("export")
    K = solid.K[keep][:, keep].tocoo()
    M = solid.M[keep][:, keep].tocoo()
    scipy.io.mmwrite(str(d / "K.mtx"), K, symmetry="symmetric")
    scipy.io.mmwrite(str(d / "M.mtx"), M, symmetry="symmetric")
    scipy.io.mmwrite(str(d / "K121.mtx"), 1.21 * K, symmetry="symmetric")
    np.savetxt(d / "dofs.txt", ref, fmt="%d", header="node component (0 UX, 1 UY, 2 UZ)")
    # a model missing free DOFs: the first unsupported node's DOFs dropped
    free_node = int(np.flatnonzero(~clamp)[0])
    part = np.isin(keep // 3, [free_node], invert=True)
    scipy.io.mmwrite(str(d / "Kpart.mtx"), solid.K[keep[part]][:, keep[part]].tocoo(),
                     symmetry="symmetric")
    scipy.io.mmwrite(str(d / "Mpart.mtx"), solid.M[keep[part]][:, keep[part]].tocoo(),
                     symmetry="symmetric")
    np.savetxt(d / "dofs_part.txt", ref[part], fmt="%d")
    # rotation matrices at 300 rpm, as an FE program gives them (fricdamp's own, exported)
    from fricdamp.models.contact_wheel import sector_from_solid
    from fricdamp.models.tieboss_wheel.solid_campbell import rotation_terms

    ws = sector_from_solid(solid, n_sectors=30, youngs_modulus=2.1e11,
                           probe_direction=[0, 1, 1])
    rot = rotation_terms(ws, solid)
    pos = np.full(solid.n_dof, -1)
    pos[ws.solid_dofs] = np.arange(ws.solid_dofs.size)
    w2 = (300 * np.pi / 30) ** 2
    for key in ("stress_stiffening", "spin_softening"):
        A = w2 * getattr(rot, key)
        scipy.io.mmwrite(str(d / f"{key}.mtx"), A[pos[keep]][:, pos[keep]].tocoo(),
                         symmetry="symmetric")
    return d, solid


def _run(cli, d, text, name):
    path = d / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = cli("run", path, "--out", d / name)
    assert code == 0, err
    return json.loads((d / name / "summary.json").read_text())


def test_matrix_files_give_the_mesh_routes_frequencies(cli, exported):
    from fricdamp.models.contact_wheel import sector_from_solid
    from fricdamp.models.tieboss_wheel.studies import modal_by_nd

    d, solid = exported
    s = _run(cli, d, CASE, "files")
    assert s["model"]["matrices"].startswith("Matrix Market")
    ws = sector_from_solid(solid, n_sectors=30, youngs_modulus=2.1e11,
                           probe_direction=[0, 1, 1])
    ref = np.asarray(modal_by_nd(cyclic=ws.cyclic, n_modes=1)["frequency_hz"])
    f = np.asarray(s["modal"]["frequency_hz"])
    np.testing.assert_allclose(f, ref, rtol=1e-9)
    assert s["model"]["sector_dof"] == ws.cyclic.n_dof
    # the files are what the pipeline uses: K x 1.21 -> f x 1.1
    s2 = _run(cli, d, CASE.replace('stiffness = "K.mtx"', 'stiffness = "K121.mtx"'), "stiff")
    np.testing.assert_allclose(s2["modal"]["frequency_hz"], 1.1 * f, rtol=1e-9)


def test_api_maps_rows_by_reference_and_refuses_missing_free_dofs(exported):
    from fricdamp.errors import ModelError
    from fricdamp.structure.io import solid_with_matrices

    d, solid = exported
    back = solid_with_matrices(solid, K=d / "K.mtx", M=d / "M.mtx",
                               dof_reference=d / "dofs.txt", fixed_nodes="clamp")
    free = np.ones(solid.n_nodes, dtype=bool)
    free[solid.node_sets["clamp"]] = False
    f = solid.dofs[free].ravel()
    assert abs(back.K[f][:, f] - solid.K[f][:, f]).max() == 0.0
    assert abs(back.M[f][:, f] - solid.M[f][:, f]).max() == 0.0
    with pytest.raises(ModelError, match="not in the matrices, first: node"):
        solid_with_matrices(solid, K=d / "Kpart.mtx", M=d / "Mpart.mtx",
                            dof_reference=d / "dofs_part.txt", fixed_nodes="clamp")
    with pytest.raises(ModelError, match="the clamp|supports"):
        solid_with_matrices(solid, K=d / "K.mtx", M=d / "M.mtx", dof_reference=d / "dofs.txt")
    with pytest.raises(ModelError, match="give a dof_reference"):
        solid_with_matrices(solid, K=d / "K.mtx", M=d / "M.mtx")
    with pytest.raises(ModelError, match="needs M= and K="):
        solid_with_matrices(solid, K=d / "K.mtx")
    small = sp.identity(3, format="csr")
    with pytest.raises(ModelError, match="not a translation"):
        solid_with_matrices(solid, K=small, M=small, dof_reference=[[1, 0], [1, 1], [1, 3]])


BAD = [
    ("stiffness_alone", ('mass = "M.mtx"\n', ""), ["stiffness and mass matrix files go "
                                                   "together"]),
    ("full_and_mtx", ('mass = "M.mtx"\n', 'mass = "M.mtx"\nfull = "sector.full"\n'),
     ["give either full"]),
    ("missing_file", ('"K.mtx"', '"nothing.mtx"'), ["[model] stiffness", "no such file"]),
    ("rotation_without_speed", ('mass = "M.mtx"\n', 'mass = "M.mtx"\nspin_softening = "M.mtx"\n'),
     ["rotation_reference_rpm go together"]),
]


@pytest.mark.parametrize("old, new, expected", [b[1] + (b[2],) for b in BAD],
                         ids=[b[0] for b in BAD])
def test_bad_matrix_input_exits_2(cli, exported, old, new, expected):
    d, _ = exported
    path = d / "bad.toml"
    path.write_text(CASE.replace(old, new, 1), encoding="utf-8")
    code, out, err = cli("run", path, "--out", d / "bad_out")
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    for e in expected:
        assert e in err, (e, err)


def test_the_fe_programs_rotation_matrices_give_the_same_campbell(cli, exported):
    """stress_stiffening / spin_softening files at 300 rpm (the matrices fricdamp computes
    itself, exported in the FE program's order) give the Campbell diagram and critical speeds
    of fricdamp's own rotation terms (1e-8: the same matrices scaled by (n / 300)^2)."""
    from fricdamp.models.contact_wheel import sector_from_solid
    from fricdamp.models.tieboss_wheel.solid_campbell import (
        campbell_solid,
        critical_speeds_solid,
        rotation_terms,
    )

    d, solid = exported
    files = CASE.replace('dof_reference = "dofs.txt"\n', 'dof_reference = "dofs.txt"\n'
                         'stress_stiffening = "stress_stiffening.mtx"\n'
                         'spin_softening = "spin_softening.mtx"\n'
                         'rotation_reference_rpm = 300.0\n')
    files += "\n[analysis.campbell_by_nd]\nn_speeds = 3\n"
    theirs = _run(cli, d, files, "rot_files")
    ws = sector_from_solid(solid, n_sectors=30, youngs_modulus=2.1e11,
                           probe_direction=[0, 1, 1])
    rot = rotation_terms(ws, solid)
    own = campbell_solid(ws, rot, theirs["campbell_by_nd"]["rpm"])
    np.testing.assert_allclose(theirs["campbell_by_nd"]["frequency_hz"], own.frequency_hz.T,
                               rtol=1e-8)
    crit = critical_speeds_solid(ws, rot, orders=[(1, 2), (3, 6)])
    for a, b in zip(theirs["critical_speeds_rpm"], crit, strict=True):
        assert a["rpm"] == pytest.approx(b["rpm"], rel=1e-8)
