"""Cyclic Craig–Bampton with reduced cut interface, and wheel modes by nodal diameter.

References and tolerances:

* The assembled wheel (:func:`assemble_full`, itself checked against an independent global
  assembly in ``tests/validation/test_cyclic_vs_full.py``) solved by dense LAPACK ``eigh``
  is the reference of :func:`wheel_modes`: same spectrum to 1e-8 relative (both are
  backward-stable eigen-solvers on matrices whose stiffness spans ~8 decades, so a few
  1e-12 is expected), mass orthonormality and K-diagonality to 1e-10 (round-off of
  O(n) sums of unit-size products).
* The cyclic compatibility of the interface basis (module docstring of
  :mod:`fricdamp.structure.cyclic_reduction`) is an exact algebraic identity: checked to
  1e-12 relative to the mode amplitude.
* Symmetry of the reduced matrices is exact by construction (averaged with the transpose).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

import fricdamp.structure.cyclic_reduction as cr
from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import build_sector
from fricdamp.structure.cyclic import CyclicSector, assemble_full
from fricdamp.structure.cyclic_reduction import lattice_sector, reduce_sector, wheel_modes


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # dense LAPACK references run several times slower with two contending BLAS threads
    with threadpool_limits(limits=1, user_api="blas"):
        yield


@pytest.fixture(scope="module")
def beam():
    """Paper 003's tie-boss beam sector: 102 DOFs, 6 cut DOFs (Cartesian), N = 30."""
    return build_sector(rotation=False).cyclic


@pytest.fixture(scope="module")
def lattice():
    """Synthetic solid-like sector: 135 DOFs, 27 DOFs per cut (Cartesian), N = 12."""
    return lattice_sector(3, 5, 3, n_sectors=12, rayleigh=(2.0, 1e-6))


@pytest.fixture(scope="module")
def reduced(beam, lattice):
    return {"beam": reduce_sector(beam, n_modes=10, n_interface_modes=4),
            "lattice": reduce_sector(lattice, n_modes=8, n_interface_modes=10)}


def _dense_wheel(sector):
    w = assemble_full(sector)
    return w.M.toarray(), w.K.toarray(), w.D.toarray()


@pytest.mark.parametrize("case", ["beam", "lattice"])
def test_wheel_modes_equal_dense_eigh_of_the_assembled_wheel(reduced, case):
    red = reduced[case]
    wm = wheel_modes(red)
    Mw, Kw, _ = _dense_wheel(red.sector)
    assert wm.n_modes == Mw.shape[0]                 # complete
    lam = sla.eigh(Kw, Mw, eigvals_only=True)
    ref = np.sqrt(np.maximum(lam, 0.0))
    got = np.sort(wm.omega)
    np.testing.assert_allclose(got, ref, rtol=1e-8)
    np.testing.assert_array_equal(wm.omega[wm.ascending()], got)


@pytest.mark.parametrize("case", ["beam", "lattice"])
def test_wheel_modes_are_mass_orthonormal_and_stiffness_diagonal(reduced, case):
    wm = wheel_modes(reduced[case])
    Mw, Kw, _ = _dense_wheel(reduced[case].sector)
    P = wm.full_shapes()
    np.testing.assert_allclose(P.T @ Mw @ P, np.eye(wm.n_modes), atol=1e-10)
    scale = wm.omega.max() ** 2
    np.testing.assert_allclose((P.T @ Kw @ P) / scale, np.diag(wm.omega**2) / scale,
                               atol=1e-10)


def test_modal_damping_is_the_projected_rayleigh_damping(reduced):
    red = reduced["lattice"]
    assert red.rayleigh is None  # projected D of the sector, D = 2 M + 1e-6 K
    wm = wheel_modes(red)
    _, _, Dw = _dense_wheel(red.sector)
    P = wm.full_shapes()
    ref = wm.modal_damping(2.0, 1e-6)
    np.testing.assert_allclose(P.T @ Dw @ P, np.diag(ref), atol=1e-10 * ref.max())


def test_layout_grouped_by_nodal_diameter(reduced):
    red = reduced["lattice"]
    wm = wheel_modes(red)
    N, m = red.sector.n_sectors, red.sector.n_independent
    assert wm.nds.tolist() == list(range(N // 2 + 1))
    assert np.all(np.diff(wm.nd) >= 0)
    for nd in wm.nds:
        sl = wm.columns(nd)
        kinds = wm.kind[sl]
        if nd in (0, N // 2):
            assert sl.stop - sl.start == m and set(kinds) == {"real"}
        else:
            assert sl.stop - sl.start == 2 * m
            assert kinds[0::2].tolist() == ["cos"] * m and kinds[1::2].tolist() == ["sin"] * m
            np.testing.assert_array_equal(wm.omega[sl][0::2], wm.omega[sl][1::2])
        assert np.all(np.diff(wm.omega[sl]) >= 0)


def test_subset_of_nodal_diameters_and_modes(reduced):
    red = reduced["lattice"]
    full = wheel_modes(red)
    part = wheel_modes(red, nds=[3, 0], n_modes_per_nd=4)
    assert part.nds.tolist() == [0, 3] and part.n_modes == 4 + 8
    for nd in (0, 3):
        np.testing.assert_allclose(part.omega[part.columns(nd)],
                                   full.omega[full.columns(nd)][:part.columns(nd).stop
                                                                - part.columns(nd).start],
                                   rtol=1e-10)


@pytest.mark.parametrize("case", ["beam", "lattice"])
def test_group_shapes_are_rows_of_full_shapes(reduced, case):
    red = reduced[case]
    wm = wheel_modes(red)
    s = red.sector
    P = wm.full_shapes()
    pos = {int(d): k for k, d in enumerate(s.independent)}
    for name in s.named_dofs:
        G = wm.group_shapes(name)
        rows = np.array([[j * s.n_independent + pos[int(d)] for d in s.named_dofs[name]]
                         for j in range(s.n_sectors)])
        np.testing.assert_allclose(G, P[rows], rtol=0, atol=1e-14)
    # right cut of sector j (cylindrical: 1:1) is the left cut of sector j + 1
    GL, GR = wm.group_shapes(s.left), wm.group_shapes(s.right)
    np.testing.assert_allclose(GR, np.roll(GL, -1, axis=0), atol=1e-12)
    out = np.empty_like(GL)
    assert wm.group_shapes(s.left, out=out) is out


def test_group_shapes_in_each_sector_frame_for_cartesian_cuts(lattice):
    """On the (unreduced, Cartesian) lattice: u_R^(j) = R u_L^(j+1), R about z by alpha."""
    wm = wheel_modes(lattice, nds=[0, 1, 5, 6])
    R = lattice.interface_rotation().toarray()
    GL, GR = wm.group_shapes(lattice.left), wm.group_shapes(lattice.right)
    np.testing.assert_allclose(GR, np.einsum("ab,jbm->jam", R, np.roll(GL, -1, axis=0)),
                               atol=1e-12 * abs(GL).max())


def test_interface_basis_is_cyclic_consistent(lattice, reduced):
    """The expanded reduced wheel satisfies the original cyclic compatibility exactly.

    Derivation (module docstring): u_L = V xi_L, u_R = Rb V xi_R and xi_R^(j) = xi_L^(j+1)
    give u_R^(j) = Rb u_L^(j+1), the compatibility of the original Cartesian sector.
    """
    red = reduced["lattice"]
    T = red.expansion
    Rb = lattice.interface_rotation().toarray()
    n_im = red.n_interface_modes
    np.testing.assert_allclose(T[lattice.right, n_im:2 * n_im],
                               Rb @ T[lattice.left, :n_im], atol=1e-15)
    wm = wheel_modes(red)
    Q = np.einsum("ar,jrm->jam", T, wm.group_shapes(np.arange(red.sector.n_dof)))
    uL, uR = Q[:, lattice.left], Q[:, lattice.right]
    np.testing.assert_allclose(uR, np.einsum("ab,jbm->jam", Rb, np.roll(uL, -1, axis=0)),
                               atol=1e-12 * abs(Q).max())


def _cut_guyan(sector):
    """Dense static condensation of the whole sector onto its two cuts (reference)."""
    K, M = sector.K.toarray(), sector.M.toarray()
    c = np.concatenate([sector.left, sector.right])
    o = np.setdiff1d(np.arange(sector.n_dof), c)
    X = -np.linalg.solve(K[np.ix_(o, o)], K[np.ix_(o, c)])
    T = np.zeros((sector.n_dof, c.size))
    T[c, np.arange(c.size)] = 1.0
    T[o] = X
    return T.T @ K @ T, T.T @ M @ T


@pytest.mark.parametrize("interface", ["cyclic", "junction"])
def test_interface_basis_against_dense_guyan_reference(lattice, interface):
    """V^T M_J V = I with M_J the junction's Guyan mass (groups condensed, reference: dense
    condensation of the whole sector); ``junction`` also diagonalises K_J, ``cyclic`` starts
    with the lowest nd = 0 mode of the cut pencil with u_R = Rb u_L."""
    red = reduce_sector(lattice, n_modes=8, n_interface_modes=10, interface=interface)
    V, nb = red.interface_basis, lattice.n_interface
    Kc, Mc = _cut_guyan(lattice)
    Rb = lattice.interface_rotation().toarray()
    L, R = slice(0, nb), slice(nb, 2 * nb)
    MJ = Mc[L, L] + Rb.T @ Mc[R, R] @ Rb
    KJ = Kc[L, L] + Rb.T @ Kc[R, R] @ Rb
    np.testing.assert_allclose(V.T @ MJ @ V, np.eye(10), atol=1e-10)
    w2 = (2 * np.pi * red.interface_frequencies) ** 2
    if interface == "junction":
        np.testing.assert_allclose(V.T @ KJ @ V / w2.max(), np.diag(w2) / w2.max(),
                                   atol=1e-10)
        assert np.all(red.interface_nds == -1) and np.all(np.diff(w2) > 0)
    else:
        T0 = np.vstack([np.eye(nb), Rb])
        lam, X = sla.eigh(T0.T @ Kc @ T0, T0.T @ Mc @ T0)
        x = X[:, 0] / np.sqrt(X[:, 0] @ MJ @ X[:, 0])
        assert red.interface_nds[0] == 0
        np.testing.assert_allclose(w2[0], lam[0], rtol=1e-10)
        np.testing.assert_allclose(abs(V[:, 0] @ MJ @ x), 1.0, atol=1e-10)
        assert np.all(np.diff(w2) >= 0) and set(red.interface_nds) <= set(range(7))


def test_cyclic_interface_basis_is_prefix_stable(lattice):
    """More interface modes only append columns (nested Ritz spaces, monotone convergence)."""
    small = reduce_sector(lattice, n_modes=8, n_interface_modes=6).interface_basis
    large = reduce_sector(lattice, n_modes=8, n_interface_modes=20).interface_basis
    np.testing.assert_allclose(large[:, :6], small, atol=1e-10 * abs(small).max())


@pytest.mark.parametrize("case", ["beam", "lattice"])
def test_reduced_matrices_are_exactly_symmetric(reduced, case):
    s = reduced[case].sector
    for A in (s.M, s.K, s.D):
        A = A.toarray() if hasattr(A, "toarray") else np.asarray(A)
        np.testing.assert_array_equal(A, A.T)


def test_kept_groups_stay_physical(beam, reduced):
    red = reduced["beam"]
    s = red.sector
    n_im = red.n_interface_modes
    # overlapping groups (probe == contact_right) are kept once, in order of appearance
    assert red.kept_dofs.tolist() == [90, 91, 92, 96, 97, 98, 66, 67, 68, 84, 85, 86]
    for name, dofs in beam.named_dofs.items():
        idx = s.named_dofs[name]
        np.testing.assert_array_equal(idx, red.reduced_index(dofs))
        E = np.zeros((idx.size, s.n_dof))
        E[np.arange(idx.size), idx] = 1.0
        np.testing.assert_array_equal(red.expansion[dofs], E)   # unit expansion rows
        assert idx.min() >= 2 * n_im
    assert s.frame == "cylindrical"
    assert s.left.tolist() == list(range(n_im))
    assert s.right.tolist() == list(range(n_im, 2 * n_im))
    q = np.arange(s.n_dof, dtype=float)
    assert red.expand(q)[beam.named_dofs["tip"]].tolist() == q[s.named_dofs["tip"]].tolist()


def test_rayleigh_argument_sets_reduced_damping(lattice, reduced):
    red = reduce_sector(lattice, n_modes=8, n_interface_modes=10, rayleigh=(2.0, 1e-6))
    s = red.sector
    assert red.rayleigh == (2.0, 1e-6)
    np.testing.assert_array_equal(s.D, 2.0 * s.M + 1e-6 * s.K)
    ref = reduced["lattice"].sector.D      # projection of the sector's D = 2 M + 1e-6 K
    np.testing.assert_allclose(s.D, ref, atol=1e-10 * abs(ref).max())


def test_streamed_constraint_modes_equal_stored(lattice, reduced, monkeypatch):
    monkeypatch.setattr(cr, "STORE_BYTES", 0)      # forces the adjoint-solve path
    monkeypatch.setattr(cr, "BLOCK_BYTES", 8 * 100 * 7)  # and several solve blocks
    red = reduce_sector(lattice, n_modes=8, n_interface_modes=10)
    ref = reduced["lattice"]
    np.testing.assert_allclose(red.interface_frequencies, ref.interface_frequencies,
                               rtol=1e-10)
    np.testing.assert_allclose(abs(red.expansion), abs(ref.expansion),
                               atol=1e-9 * abs(ref.expansion).max())
    lam = sla.eigh(red.sector.K, red.sector.M, eigvals_only=True)
    np.testing.assert_allclose(lam, sla.eigh(ref.sector.K, ref.sector.M, eigvals_only=True),
                               rtol=1e-9)


def test_sparse_fixed_interface_modes_equal_dense():
    s = lattice_sector(4, 6, 4, n_sectors=12)        # 288 interior DOFs
    dense = reduce_sector(s, n_modes=6, n_interface_modes=5, method="dense")
    sparse = reduce_sector(s, n_modes=6, n_interface_modes=5, method="sparse")
    np.testing.assert_allclose(sparse.fixed_interface_frequencies,
                               dense.fixed_interface_frequencies, rtol=1e-9)
    assert set(sparse.timings) == {"factorise", "fixed_interface_modes", "constraint_modes",
                                   "interface_modes", "projection"}


@pytest.mark.parametrize("kwargs, name", [
    ({"n_modes": -1}, "n_modes"),
    ({"n_modes": 2.5}, "n_modes"),
    ({"n_modes": 10_000}, "n_modes"),
    ({"n_interface_modes": 0}, "n_interface_modes"),
    ({"n_interface_modes": 28}, "n_interface_modes"),
    ({"method": "lanczos"}, "method"),
    ({"interface": "free"}, "interface"),
    ({"interface_tolerance": 0.0}, "interface_tolerance"),
    ({"interface_tolerance": "1e-3"}, "interface_tolerance"),
    ({"rayleigh": (1.0,)}, "rayleigh"),
    ({"rayleigh": (-1.0, 0.0)}, "rayleigh"),
    ({"keep": {"bad": [10_000]}}, r"keep\['bad'\]"),
    ({"keep": {"cut": [0, 1, 2]}}, r"keep\['cut'\]"),
    ({"keep": [1, 2]}, "keep"),
])
def test_reduce_sector_rejects_bad_input(lattice, kwargs, name):
    args = {"n_modes": 4, "n_interface_modes": 5, **kwargs}
    with pytest.raises(ModelError, match=name) as info:
        reduce_sector(lattice, **args)
    assert "\n" not in str(info.value)


def test_reduce_sector_rejects_floating_interior_and_non_sectors():
    # DOF 3 is interior and held by nothing: K_ii is singular
    K = np.array([[1.0, -1.0, 0.0, 0.0], [-1.0, 2.0, -1.0, 0.0], [0.0, -1.0, 1.0, 0.0],
                  [0.0, 0.0, 0.0, 0.0]])
    s = CyclicSector(M=np.eye(4), K=K, left=[0], right=[2], n_sectors=5)
    for args, name in (((s,), "K_ii"), ((s.M,), "sector")):
        with pytest.raises(ModelError, match=name) as info:
            reduce_sector(*args, n_modes=1, n_interface_modes=1)
        assert "\n" not in str(info.value)


@pytest.mark.parametrize("kwargs, name", [
    ({"nds": [7]}, "nds"),
    ({"nds": [1, 1]}, "nds"),
    ({"nds": [0.5]}, "nds"),
    ({"n_modes_per_nd": 0}, "n_modes_per_nd"),
    ({"n_modes_per_nd": 10_000}, "n_modes_per_nd"),
])
def test_wheel_modes_rejects_bad_input(reduced, kwargs, name):
    with pytest.raises(ModelError, match=name) as info:
        wheel_modes(reduced["lattice"], **kwargs)
    assert "\n" not in str(info.value)


def test_wheel_modes_bad_group_and_arguments(reduced):
    wm = wheel_modes(reduced["lattice"], nds=[1], n_modes_per_nd=2)
    for bad in ("nope", [10_000]):
        with pytest.raises(ModelError, match="name_or_dofs"):
            wm.group_shapes(bad)
    with pytest.raises(ModelError, match="out"):
        wm.group_shapes("probe", out=np.empty((1, 1, 1)))
    with pytest.raises(ModelError, match="nd"):
        wm.columns(2)
    with pytest.raises(ModelError, match="^b "):
        wm.modal_damping(0.0, np.nan)
    with pytest.raises(ModelError, match="red"):
        wheel_modes("sector")
