"""Cyclic-symmetry modal analysis against an independently assembled full wheel.

Reference: a 3D pin-jointed bar lattice "bladed wheel" (hub ring, tie ring, a twisted
three-node blade per sector, isotropic foundation springs), assembled node by node in the
*global Cartesian* frame by code in this file that shares nothing with
:mod:`fricdamp.structure.cyclic` except the element list. Bars are anisotropic (stiffness
only along the bar), so a wrong interface rotation ``R`` or phase would change the
spectrum. Checks (Thomas 1979; paper 003 classifies its wheel's modes this way):

* the union of the nodal-diameter spectra, each ``0 < nd < N/2`` counted twice, equals the
  full wheel's spectrum — for Cartesian and for cylindrical DOF frames, and for
  :func:`assemble_full`;
* every ND frequency is a double (resp. single) eigenvalue of the full wheel and the
  expanded travelling-wave shape solves the full eigenproblem;
* the sparse (ARPACK, complex Hermitian) and dense paths agree;
* a Craig–Bampton reduced sector assembles into a wheel whose frequencies converge from
  above to the full ones.

Tolerance 1e-8 relative (the brief's): dense LAPACK eigenvalues of these ~200-DOF
problems are accurate to ~1e-13 relative to the largest one and the spectral spread is
~1e3, so agreement is expected near 1e-11 (measured ~1e-13).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from threadpoolctl import threadpool_limits

from fricdamp.structure.cyclic import (
    CyclicSector,
    all_nd_frequencies,
    assemble_full,
    full_spectrum,
    nodal_diameter_modes,
)
from fricdamp.structure.reduction import craig_bampton_sector

RTOL = 1e-8

# node order: 0 L0, 1 L1 (left cut), 2 H, 3 B1, 4 B2, 5 B3 (interior), 6 R0, 7 R1 (right cut)
LEFT_NODES, RIGHT_NODES = (0, 1), (6, 7)
BARS = [  # (node a, node b, axial stiffness [N/m], mass [kg])
    (0, 2, 9.0e4, 0.20), (1, 2, 7.0e4, 0.15), (6, 2, 8.0e4, 0.20), (7, 2, 6.5e4, 0.15),
    (0, 7, 3.0e4, 0.10), (1, 6, 3.5e4, 0.10), (1, 3, 5.0e4, 0.12), (7, 3, 5.5e4, 0.12),
    (2, 3, 6.0e4, 0.10), (3, 4, 4.0e4, 0.08), (4, 5, 3.0e4, 0.06), (2, 4, 2.0e4, 0.05),
    (7, 4, 1.5e4, 0.05), (3, 5, 1.0e4, 0.04), (1, 4, 1.2e4, 0.04),
]
NODE_MASS = np.array([0.5, 0.4, 0.6, 0.3, 0.25, 0.35, 0.5, 0.4])  # boundary nodes: halves
GROUND = 2.0e3  # isotropic foundation stiffness per node [N/m] (halved on the cuts)


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # Dense LAPACK calls in the tests (references) and in MechanicalSystem's mass check run
    # ~8x slower with two contending BLAS threads on the 2-core machine.
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def node_positions(N):
    a = 2 * np.pi / N

    def cyl(r, t, z):
        return np.array([r * np.cos(t), r * np.sin(t), z])

    left = [cyl(1.0, 0.0, 0.0), cyl(1.5, 0.0, 0.15)]
    inner = [cyl(1.2, 0.5 * a, -0.1), cyl(2.0, 0.45 * a, 0.05), cyl(2.6, 0.55 * a, 0.12),
             cyl(3.2, 0.5 * a, -0.05)]
    right = [rot_z(a) @ p for p in left]
    return np.array(left + inner + right)


def rot_z(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def element_matrices(xa, xb, k, m):
    e = (xb - xa) / np.linalg.norm(xb - xa)
    kk = k * np.outer(e, e)
    Ke = np.block([[kk, -kk], [-kk, kk]])
    Me = m / 6 * np.kron(np.array([[2.0, 1.0], [1.0, 2.0]]), np.eye(3))
    return Ke, Me


def add(A, nodes, Ae):
    idx = np.concatenate([3 * n + np.arange(3) for n in nodes])
    A[np.ix_(idx, idx)] += Ae


def sector_cartesian(N):
    """Sector matrices in sector 0's Cartesian frame (8 nodes x 3 DOFs)."""
    X = node_positions(N)
    K, M = np.zeros((24, 24)), np.zeros((24, 24))
    for a, b, k, m in BARS:
        Ke, Me = element_matrices(X[a], X[b], k, m)
        add(K, (a, b), Ke)
        add(M, (a, b), Me)
    for n in range(8):
        share = 0.5 if n in LEFT_NODES + RIGHT_NODES else 1.0
        add(K, (n,), share * GROUND * np.eye(3))
        add(M, (n,), NODE_MASS[n] * np.eye(3))
    return M, K


def wheel_reference(N):
    """Full wheel assembled node by node in the global Cartesian frame.

    Global node of sector j's local node n: ``6 j + n`` for n < 6; the right-cut nodes
    6, 7 are nodes 0, 1 of sector j + 1.
    """
    X0 = node_positions(N)
    n_nodes = 6 * N
    K, M = np.zeros((3 * n_nodes, 3 * n_nodes)), np.zeros((3 * n_nodes, 3 * n_nodes))

    def gid(j, n):
        return 6 * ((j + 1) % N) + (n - 6) if n >= 6 else 6 * j + n

    for j in range(N):
        X = X0 @ rot_z(j * 2 * np.pi / N).T
        for a, b, k, m in BARS:
            Ke, Me = element_matrices(X[a], X[b], k, m)
            add(K, (gid(j, a), gid(j, b)), Ke)
            add(M, (gid(j, a), gid(j, b)), Me)
        for n in range(8):
            share = 0.5 if n in LEFT_NODES + RIGHT_NODES else 1.0
            add(K, (gid(j, n),), share * GROUND * np.eye(3))
            add(M, (gid(j, n),), NODE_MASS[n] * np.eye(3))
    return M, K


def cut_dofs(nodes):
    return np.concatenate([3 * n + np.arange(3) for n in nodes])


def cartesian_sector(N, **kw):
    M, K = sector_cartesian(N)
    return CyclicSector(M=M, K=K, left=cut_dofs(LEFT_NODES), right=cut_dofs(RIGHT_NODES),
                        n_sectors=N, frame="cartesian", axis="z", **kw)


def cylindrical_sector(N):
    """Same sector with every node's DOFs in its local (e_r, e_theta, e_z) basis."""
    M, K = sector_cartesian(N)
    X = node_positions(N)
    Q = sla.block_diag(*[rot_z(np.arctan2(x[1], x[0])) for x in X])
    return CyclicSector(M=Q.T @ M @ Q, K=Q.T @ K @ Q, left=cut_dofs(LEFT_NODES),
                        right=cut_dofs(RIGHT_NODES), n_sectors=N, frame="cylindrical")


def reference_frequencies(N):
    M, K = wheel_reference(N)
    lam = sla.eigh(K, M, eigvals_only=True)
    return np.sqrt(lam) / (2 * np.pi)


@pytest.mark.parametrize("N", [12, 7])
def test_nd_spectra_equal_the_full_wheel(N):
    f_ref = reference_frequencies(N)
    n_ind = 18  # 6 independent nodes x 3
    assert f_ref.size == N * n_ind
    for sector in (cartesian_sector(N), cylindrical_sector(N)):
        F = all_nd_frequencies(sector, n_ind)
        np.testing.assert_allclose(full_spectrum(F, N), f_ref, rtol=RTOL)
    full = assemble_full(cartesian_sector(N))
    lam = sla.eigh(full.K.toarray(), full.M.toarray(), eigvals_only=True)
    np.testing.assert_allclose(np.sqrt(lam) / (2 * np.pi), f_ref, rtol=RTOL)


def test_wrong_interface_rotation_would_be_detected():
    # The same Cartesian matrices declared "cylindrical" (R = I) give a different spectrum:
    # the bar anisotropy makes the test above sensitive to R.
    N = 12
    M, K = sector_cartesian(N)
    wrong = CyclicSector(M=M, K=K, left=cut_dofs(LEFT_NODES), right=cut_dofs(RIGHT_NODES),
                         n_sectors=N, frame="cylindrical")
    err = np.abs(full_spectrum(all_nd_frequencies(wrong, 18), N) / reference_frequencies(N) - 1)
    assert err.max() > 1e-3


def test_each_nd_mode_is_a_mode_of_the_full_wheel_with_its_multiplicity():
    N = 12
    M_ref, K_ref = wheel_reference(N)
    f_ref = reference_frequencies(N)
    sector = cartesian_sector(N)
    # sector j's DOFs are in its own frame: global = R^j (per node triple)
    Qg = sla.block_diag(*[np.kron(np.eye(6), rot_z(j * 2 * np.pi / N)) for j in range(N)])
    for nd in range(N // 2 + 1):
        cm = nodal_diameter_modes(sector, nd, 18)
        X = Qg @ cm.full_shapes(sector)
        for c in range(18):
            f = cm.frequencies[c]
            close = np.abs(f_ref / f - 1) < 1e-8
            # an accidental coincidence with another ND would only add to the count
            assert close.sum() >= cm.multiplicity
            parts = [p for p in (X[:, c].real, X[:, c].imag) if np.linalg.norm(p) > 1e-12]
            B = np.column_stack(parts)
            R = K_ref @ B - (2 * np.pi * f) ** 2 * (M_ref @ B)
            assert np.linalg.norm(R) <= 1e-9 * np.linalg.norm(K_ref @ B)
            if cm.multiplicity == 2:  # cosine and sine standing waves: a 2-D eigenspace
                s = np.linalg.svd(B / np.linalg.norm(B, axis=0), compute_uv=False)
                assert s[-1] > 1e-3 * s[0]


def test_sparse_complex_hermitian_path_matches_dense():
    # ARPACK shift-invert on the complex Hermitian ND pencil vs LAPACK zhegv; 1e-10 relative
    # (ARPACK converges to machine precision in the inverted operator).
    N = 12
    s = cartesian_sector(N)
    for nd in (0, 1, 4, 6):
        a = nodal_diameter_modes(s, nd, 5, method="sparse").frequencies
        b = nodal_diameter_modes(s, nd, 5, method="dense").frequencies
        np.testing.assert_allclose(a, b, rtol=1e-10)
    c = nodal_diameter_modes(s, 3, 4, sigma=float(b[2]), method="sparse").frequencies
    d = nodal_diameter_modes(s, 3, 18, method="dense").frequencies
    want = np.sort(d[np.argsort(np.abs(d - b[2]))[:4]])
    np.testing.assert_allclose(c, want, rtol=1e-10)


def test_craig_bampton_sector_converges_to_the_full_wheel_from_above():
    # Rayleigh-Ritz: every reduced frequency >= the exact one (slack 1e-12 relative for
    # round-off) and non-increasing as fixed-interface modes are added; with all interior
    # modes the reduction is exact (square invertible T).
    N = 12
    sector = cartesian_sector(N, named_dofs={"blade_tip": cut_dofs((5,))})
    f_ref = reference_frequencies(N)
    n_int = 24 - 12 - 3  # interior DOFs left once cuts and the named tip node are kept
    prev = None
    for n_modes in (0, 2, 4, 6, n_int):
        red = craig_bampton_sector(sector, n_modes)
        assert red.sector.n_dof == 12 + 3 + n_modes
        np.testing.assert_array_equal(red.sector.named_dofs["blade_tip"], [12, 13, 14])
        n_low = min(red.sector.n_independent, 6)
        F = full_spectrum(all_nd_frequencies(red.sector, n_low), N)
        # compare the lowest modes of the wheel (the reduced wheel has fewer modes)
        low = F[: 3 * N]
        assert np.all(low >= f_ref[: low.size] * (1 - 1e-12))
        if prev is not None:
            assert np.all(low <= prev * (1 + 1e-12))
        prev = low
    np.testing.assert_allclose(prev, f_ref[: prev.size], rtol=1e-10)
    # the reduced sector assembles like any other and matches its own ND analysis
    red = craig_bampton_sector(sector, 4)
    wheel = assemble_full(red.sector)
    lam = sla.eigh(wheel.K.toarray(), wheel.M.toarray(), eigvals_only=True)
    by_nd = all_nd_frequencies(red.sector, red.sector.n_independent)
    np.testing.assert_allclose(np.sqrt(lam) / (2 * np.pi), full_spectrum(by_nd, N), rtol=RTOL)
