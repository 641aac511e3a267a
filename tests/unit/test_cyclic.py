"""Cyclic sectors, full assembly, modes by nodal diameter, and sector import.

Reference (closed form): a ring of N masses m joined by springs k, each mass also held by a
ground spring k_g, has ``w_nd^2 = k_g/m + (4 k/m) sin^2(pi nd / N)`` for harmonic index
nd (standing/travelling waves ``u_j = exp(2 pi i nd j / N)``; Brillouin, *Wave Propagation
in Periodic Structures*, ch. 1). The sector used here is one ring spring between its left
node (DOF 0) and its right node (DOF 1), each carrying m/2 and k_g/2, so the assembled
ring has exactly that closed form.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from fricdamp.errors import ModelError
from fricdamp.solvers.modal import modes
from fricdamp.structure.cyclic import (
    CyclicSector,
    all_nd_frequencies,
    assemble_full,
    full_spectrum,
    nodal_diameter_modes,
)
from fricdamp.structure.io import read_ansys_full, read_matrix, read_sector

M_RING, K_RING, KG_RING = 2.0, 100.0, 30.0


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # Dense LAPACK calls in the tests (references) and in MechanicalSystem's mass check run
    # ~8x slower with two contending BLAS threads on the 2-core machine.
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def ring_sector(N, *, blade=None, sparse=False):
    """Ring sector: DOF 0 left, DOF 1 right; optional blade DOF 2 on the left node."""
    m, k, kg = M_RING, K_RING, KG_RING
    M = np.diag([m / 2, m / 2])
    K = np.array([[k + kg / 2, -k], [-k, k + kg / 2]])
    if blade is not None:
        mb, kb = blade
        M = np.diag([m / 2, m / 2, mb])
        K = np.pad(K, ((0, 1), (0, 1)))
        K[0, 0] += kb
        K[2, 2] += kb
        K[0, 2] = K[2, 0] = -kb
    if sparse:
        M, K = sp.csr_matrix(M), sp.csr_matrix(K)
    return CyclicSector(M=M, K=K, left=[0], right=[1], n_sectors=N)


def ring_omega(nd, N):
    return np.sqrt(KG_RING / M_RING + 4 * K_RING / M_RING * np.sin(np.pi * nd / N) ** 2)


@pytest.mark.parametrize("N", [12, 7, 2])
def test_ring_frequencies_by_nodal_diameter(N):
    # closed form; dense 1x1 problems: 1e-12 relative
    s = ring_sector(N)
    F = all_nd_frequencies(s, 1)
    assert F.shape == (N // 2 + 1, 1)
    np.testing.assert_allclose(2 * np.pi * F[:, 0], ring_omega(np.arange(N // 2 + 1), N),
                               rtol=1e-12)
    # harmonics nd and N - nd coincide
    for nd in range(1, N):
        a = nodal_diameter_modes(s, nd, 1).frequencies
        b = nodal_diameter_modes(s, N - nd, 1).frequencies
        np.testing.assert_allclose(a, b, rtol=1e-13)


def test_ring_full_assembly_is_the_circulant_matrix():
    N = 5
    full = assemble_full(ring_sector(N))
    assert full.is_sparse and full.n_dof == N
    k, kg = K_RING, KG_RING
    C = (2 * k + kg) * np.eye(N) - k * (np.roll(np.eye(N), 1, 0) + np.roll(np.eye(N), -1, 0))
    np.testing.assert_allclose(full.K.toarray(), C, rtol=1e-15)
    np.testing.assert_allclose(full.M.toarray(), M_RING * np.eye(N), rtol=1e-15)
    assert full.meta["cyclic"] == {"n_sectors": N, "n_independent": 1}


def test_spectrum_with_multiplicities_equals_full_assembly():
    # ring + blade: 2 independent DOFs per sector, N = 12 -> 24 wheel modes.
    N = 12
    s = ring_sector(N, blade=(0.7, 40.0))
    full = assemble_full(s)
    f_full = modes(full, full.n_dof).frequencies
    spec = full_spectrum(all_nd_frequencies(s, 2), N)
    np.testing.assert_allclose(spec, f_full, rtol=1e-12)


def test_cyclic_transform_imposes_the_phase_constraint():
    N = 12
    s = ring_sector(N, blade=(0.7, 40.0))
    for nd in range(N):
        T = s.cyclic_transform(nd)
        assert T.shape == (3, 2)
        real = (2 * nd) % N == 0
        assert np.isrealobj(T.toarray()) == real
        x = np.array([0.3 - 0.2j, 1.1 + 0.5j])
        u = T @ x
        assert u[1] == pytest.approx(np.exp(2j * np.pi * nd / N) * u[0], abs=1e-14)


def test_travelling_wave_shapes_solve_the_full_problem():
    N = 12
    s = ring_sector(N, blade=(0.7, 40.0))
    full = assemble_full(s)
    for nd in (0, 1, 5, 6):
        cm = nodal_diameter_modes(s, nd, 2)
        assert cm.multiplicity == (1 if nd in (0, 6) else 2)
        X = cm.full_shapes(s)
        for c in range(2):
            for part in (X[:, c].real, X[:, c].imag):
                if np.linalg.norm(part) < 1e-12:
                    continue
                r = full.K @ part - cm.omega[c] ** 2 * (full.M @ part)
                assert np.linalg.norm(r) <= 1e-10 * np.linalg.norm(full.K @ part)


def test_transform_and_dof_maps():
    N = 4
    s = ring_sector(N, blade=(0.7, 40.0))
    assert s.n_independent == 2 and s.n_full == 8
    np.testing.assert_array_equal(s.independent, [0, 2])
    np.testing.assert_array_equal(s.interior, [2])
    # right DOF of sector 3 is the left DOF of sector 0 (wrap-around)
    np.testing.assert_array_equal(s.full_dofs([0, 1, 2], j=3), [6, 0, 7])
    T = s.transform(1).toarray()
    np.testing.assert_array_equal(np.argmax(T, axis=1), [2, 4, 3])
    with pytest.raises(ModelError, match="sector index"):
        s.transform(4)


def test_contact_projection_between_neighbouring_blades():
    # contact: relative displacement blade(j) - blade(j+1); full rows are e_b(j) - e_b(j+1)
    N = 5
    s = ring_sector(N, blade=(0.7, 40.0))
    P = np.zeros((1, 6))
    P[0, 2] = 1.0
    P[0, 3 + 2] = -1.0
    Pf = s.contact_projection(P).toarray()
    assert Pf.shape == (N, s.n_full)
    for j in range(N):
        expect = np.zeros(s.n_full)
        expect[s.full_dofs(2, j)] += 1.0
        expect[s.full_dofs(2, (j + 1) % N)] -= 1.0
        np.testing.assert_array_equal(Pf[j], expect)
    with pytest.raises(ModelError, match="2 n"):
        s.contact_projection(np.zeros((1, 3)))


def test_cartesian_rotation_blocks():
    N = 8
    a = 2 * np.pi / N
    M = np.eye(6)
    K = np.eye(6) * 2.0
    s = CyclicSector(M=M, K=K, left=[0, 1, 2], right=[3, 4, 5], n_sectors=N,
                     frame="cartesian")
    R = s.rotation_matrix()
    np.testing.assert_allclose(R, [[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0],
                                   [0, 0, 1]], atol=1e-15)
    sx = CyclicSector(M=M, K=K, left=[0, 1, 2], right=[3, 4, 5], n_sectors=N,
                      frame="cartesian", axis="x")
    np.testing.assert_allclose(sx.rotation_matrix() @ [0, 1, 0], [0, np.cos(a), np.sin(a)],
                               atol=1e-15)
    sv = CyclicSector(M=M, K=K, left=[0, 1, 2], right=[3, 4, 5], n_sectors=N,
                      frame="cartesian", axis=[0, 0, 2.0])
    np.testing.assert_allclose(sv.rotation_matrix(), R, atol=1e-15)
    T = s.cyclic_transform(1).toarray()
    np.testing.assert_allclose(T[3:], np.exp(1j * a) * R, atol=1e-15)
    with pytest.raises(ModelError, match="transform"):
        s.full_dofs([3], j=0)


def test_sector_validation_errors():
    M, K = np.eye(3), np.eye(3)
    with pytest.raises(ModelError, match="disjoint"):
        CyclicSector(M=M, K=K, left=[0], right=[0], n_sectors=4)
    with pytest.raises(ModelError, match="same number"):
        CyclicSector(M=M, K=K, left=[0, 1], right=[2], n_sectors=4)
    with pytest.raises(ModelError, match="left"):
        CyclicSector(M=M, K=K, left=[5], right=[1], n_sectors=4)
    with pytest.raises(ModelError, match="n_sectors"):
        CyclicSector(M=M, K=K, left=[0], right=[1], n_sectors=1)
    with pytest.raises(ModelError, match="frame"):
        CyclicSector(M=M, K=K, left=[0], right=[1], n_sectors=4, frame="polar")
    with pytest.raises(ModelError, match="triples"):
        CyclicSector(M=M, K=K, left=[0], right=[1], n_sectors=4, frame="cartesian")
    Kn = K.copy()
    Kn[0, 1] = 0.5
    with pytest.raises(ModelError, match="symmetric"):
        CyclicSector(M=M, K=Kn, left=[0], right=[1], n_sectors=4)
    with pytest.raises(ModelError, match="positive definite"):
        CyclicSector(M=np.diag([1.0, 0.0, 1.0]), K=K, left=[0], right=[1], n_sectors=4)
    s = ring_sector(6)
    with pytest.raises(ModelError, match="nd"):
        nodal_diameter_modes(s, 6, 1)
    with pytest.raises(ModelError, match="n_modes"):
        nodal_diameter_modes(s, 0, 2)


# ----------------------------------------------------------------------------- import
def test_read_sector_from_matrix_market(tmp_path):
    s = ring_sector(12, blade=(0.7, 40.0))
    scipy.io.mmwrite(tmp_path / "M.mtx", sp.csr_matrix(s.M), symmetry="symmetric")
    scipy.io.mmwrite(tmp_path / "K.mtx", sp.csr_matrix(s.K), symmetry="symmetric")
    (tmp_path / "left.txt").write_text("# left cut\n0\n")
    r = read_sector(M=tmp_path / "M.mtx", K=str(tmp_path / "K.mtx"), n_sectors=12,
                    left_dofs=tmp_path / "left.txt", right_dofs=[1],
                    named_dofs={"tieboss": [2]})
    assert isinstance(r, CyclicSector)
    np.testing.assert_array_equal(r.named_dofs["tieboss"], [2])
    np.testing.assert_allclose(all_nd_frequencies(r, 2), all_nd_frequencies(s, 2), rtol=1e-14)
    # read_matrix keeps working for single matrices
    assert sp.issparse(read_matrix(tmp_path / "K.mtx"))


def test_read_sector_by_node_numbers_and_triangle_completion(tmp_path):
    # 3 nodes x 2 components; node 10 left, node 30 right, node 20 interior (contact).
    rng = np.random.default_rng(7)
    A = rng.standard_normal((6, 6))
    K = A @ A.T + 6 * np.eye(6)
    M = np.diag(rng.uniform(1, 2, 6))
    ref = np.array([[10, 0], [10, 1], [20, 0], [20, 1], [30, 0], [30, 1]])
    scipy.io.mmwrite(tmp_path / "K.mtx", sp.csr_matrix(np.triu(K)))  # upper triangle only
    scipy.io.mmwrite(tmp_path / "M.mtx", sp.csr_matrix(M))
    np.savetxt(tmp_path / "dofs.txt", ref, fmt="%d")
    r = read_sector(M=tmp_path / "M.mtx", K=tmp_path / "K.mtx", n_sectors=6,
                    dof_reference=tmp_path / "dofs.txt", left_nodes=[10], right_nodes=[30],
                    named_nodes={"contact": [20]})
    np.testing.assert_allclose(r.K.toarray(), K, rtol=1e-15)  # completed to symmetric
    np.testing.assert_array_equal(r.left, [0, 1])
    np.testing.assert_array_equal(r.right, [4, 5])
    np.testing.assert_array_equal(r.named_dofs["contact"], [2, 3])
    assert r.dof_names[3] == "n20.UY"
    with pytest.raises(ModelError, match="node 99"):
        read_sector(M=M, K=K, n_sectors=6, dof_reference=ref, left_nodes=[99],
                    right_nodes=[30])
    with pytest.raises(ModelError, match="DOF reference"):
        read_sector(M=M, K=K, n_sectors=6, left_nodes=[10], right_nodes=[30])
    with pytest.raises(ModelError, match="UX, UY, UZ"):  # 2 components: not a 3-vector
        read_sector(M=M, K=K, n_sectors=6, dof_reference=ref, left_nodes=[10],
                    right_nodes=[30], frame="cartesian")


def test_read_sector_input_errors(tmp_path):
    M, K = np.eye(3), np.eye(3)
    with pytest.raises(ModelError, match="does not exist"):
        read_sector(M=tmp_path / "nope.mtx", K=K, n_sectors=4, left_dofs=[0], right_dofs=[1])
    with pytest.raises(ModelError, match="either"):
        read_sector(M=M, K=K, n_sectors=4)
    with pytest.raises(ModelError, match="K must be"):
        read_sector(M=M, K=np.eye(2), n_sectors=4, left_dofs=[0], right_dofs=[1])
    with pytest.raises(ModelError, match="left_dofs"):
        read_sector(M=M, K=K, n_sectors=4, left_dofs=[0.5], right_dofs=[1])
    with pytest.raises(ModelError, match="named_nodes"):
        read_sector(M=M, K=K, n_sectors=4, left_dofs=[0], right_dofs=[1],
                    named_nodes={"c": [1]})


def test_ansys_full_without_the_reader_says_how_to_install(tmp_path, monkeypatch):
    f = tmp_path / "sector.full"
    f.write_bytes(b"\0" * 16)
    for mod in ("ansys", "ansys.mapdl", "ansys.mapdl.reader"):
        monkeypatch.setitem(sys.modules, mod, None)  # import fails as if not installed
    with pytest.raises(ModelError, match="pip install ansys-mapdl-reader"):
        read_sector(full=f, n_sectors=30, left_nodes=[1], right_nodes=[2])
    with pytest.raises(ModelError, match="does not exist"):
        read_ansys_full(tmp_path / "missing.full")


def test_ansys_full_adapter_with_a_stand_in_reader(tmp_path, monkeypatch):
    # Stand-in for ansys.mapdl.reader with the documented load_km(sort=True) contract:
    # upper-triangular K and M, (node, component) reference, constrained DOFs left as empty
    # rows. Checks our completion, removal of constrained DOFs and node lookup.
    import types

    K = np.array([[4.0, -1, 0, 0], [-1, 4, 0, -1], [0, 0, 0, 0], [0, -1, 0, 3]])
    M = np.diag([1.0, 2.0, 0.0, 1.5])
    ref = np.array([[1, 0], [2, 0], [3, 0], [4, 0]])

    class FakeFull:
        def load_km(self, as_sparse=True, sort=False):
            assert sort
            return ref, sp.csc_matrix(np.triu(K)), sp.csc_matrix(np.triu(M))

    fake = types.ModuleType("ansys.mapdl.reader")
    fake.read_binary = lambda path: FakeFull()
    pkg = types.ModuleType("ansys.mapdl")
    pkg.reader = fake
    monkeypatch.setitem(sys.modules, "ansys", types.ModuleType("ansys"))
    monkeypatch.setitem(sys.modules, "ansys.mapdl", pkg)
    monkeypatch.setitem(sys.modules, "ansys.mapdl.reader", fake)
    f = tmp_path / "sector.full"
    f.write_bytes(b"\0")
    r = read_sector(full=f, n_sectors=10, left_nodes=[1], right_nodes=[4],
                    named_nodes={"contact": [2]})
    keep = [0, 1, 3]
    np.testing.assert_allclose(r.K.toarray(), K[np.ix_(keep, keep)])
    np.testing.assert_allclose(r.M.toarray(), M[np.ix_(keep, keep)])
    np.testing.assert_array_equal(r.left, [0])
    np.testing.assert_array_equal(r.right, [2])
    np.testing.assert_array_equal(r.named_dofs["contact"], [1])
    assert r.dof_names == ("n1.UX", "n2.UX", "n4.UX")
