"""Craig–Bampton reduction (fricdamp.structure.reduction).

References
----------
Craig, R. R. & Bampton, M. C. C. (1968). Coupling of substructures for dynamic analyses.
AIAA J. 6(7), 1313–1319. Properties checked: the constraint modes are K-orthogonal to the
fixed-interface modes (block-diagonal reduced K); Guyan's static condensation is exact
for static loads on the boundary DOFs; as a Rayleigh–Ritz method on nested subspaces the
reduced frequencies lie above the exact ones and decrease monotonically as modes are
added (Cauchy interlacing); with every interior mode the transformation is square and
invertible, so the reduced model reproduces the full one exactly — also in a friction
transient, because contacts on boundary DOFs keep their exact kinematics.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from fricdamp.contact.jenkins import Jenkins
from fricdamp.errors import ModelError
from fricdamp.solvers.modal import modes
from fricdamp.solvers.timestep import simulate
from fricdamp.structure.builders import chain
from fricdamp.structure.cyclic import CyclicSector, all_nd_frequencies, full_spectrum
from fricdamp.structure.reduction import craig_bampton, craig_bampton_sector, eigenpairs
from fricdamp.structure.system import (
    ContactElement,
    HarmonicLoad,
    MechanicalSystem,
    RotationTerms,
    TimeLoad,
)


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # Dense LAPACK calls in the tests (references) and in MechanicalSystem's mass check run
    # ~8x slower with two contending BLAS threads on the 2-core machine.
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def random_chain(n=60, seed=1, sparse=False):
    rng = np.random.default_rng(seed)
    s = chain(rng.uniform(0.5, 1.5, n), rng.uniform(500, 1500, n))
    if sparse:
        return MechanicalSystem(M=sp.csr_matrix(s.M), K=sp.csr_matrix(s.K))
    return s


@pytest.mark.parametrize("sparse", [False, True])
def test_transformation_structure(sparse):
    s = random_chain(30, sparse=sparse)
    b = [29, 10]
    red = craig_bampton(s, b, 6)
    T = red.transformation
    assert T.shape == (30, 8)
    np.testing.assert_array_equal(T[b][:, :2], np.eye(2))
    np.testing.assert_array_equal(T[b][:, 2:], 0.0)
    Kr, Mr = red.system.K, red.system.M
    lam = (2 * np.pi * red.fixed_interface_frequencies) ** 2
    scale = np.abs(Kr).max()
    np.testing.assert_allclose(Kr[:2, 2:], 0.0, atol=1e-11 * scale)  # K-orthogonality
    np.testing.assert_allclose(Kr[2:, 2:], np.diag(lam), atol=1e-11 * scale)
    np.testing.assert_allclose(Mr[2:, 2:], np.eye(6), atol=1e-12)
    # the fixed-interface frequencies are those of the structure with b clamped
    keep = [i for i in range(30) if i not in b]
    Kd = s.K.toarray() if sparse else s.K
    Md = s.M.toarray() if sparse else s.M
    clamped = MechanicalSystem(M=Md[np.ix_(keep, keep)], K=Kd[np.ix_(keep, keep)])
    np.testing.assert_allclose(red.fixed_interface_frequencies, modes(clamped, 6).frequencies,
                               rtol=1e-10)
    assert red.system.dof_names[:2] == ("q30", "q11") and red.system.dof_names[2] == "eta1"


@pytest.mark.parametrize("n_modes", [0, 5])
def test_static_condensation_exact_for_boundary_loads(n_modes):
    # K_r = T^T K T with a boundary load f: q = T K_r^-1 T^T f equals K^-1 f to round-off
    # (the modal block decouples and sees no load). 1e-10: K condition ~1e4 here.
    s = random_chain(40)
    b = [39, 15, 3]
    red = craig_bampton(s, b, n_modes)
    f = np.zeros(40)
    f[b] = [2.0, -1.0, 0.5]
    q_full = np.linalg.solve(s.K, f)
    q_red = red.expand(np.linalg.solve(red.system.K, red.reduce_vector(f)))
    np.testing.assert_allclose(q_red, q_full, rtol=1e-10, atol=1e-12 * np.abs(q_full).max())


def test_frequencies_converge_from_above_monotonically():
    s = random_chain(60)
    exact = modes(s, 3).frequencies
    prev = None
    errors = {}
    for n_modes in range(1, 59):  # (Guyan, n_modes = 0, has only 2 modes)
        red = craig_bampton(s, [59, 30], n_modes)
        f = modes(red.system, 3).frequencies
        # Rayleigh-Ritz bound (round-off slack 1e-12)
        assert np.all(f >= exact * (1 - 1e-12))
        if prev is not None:  # nested subspaces: non-increasing
            assert np.all(f <= prev * (1 + 1e-12))
        prev = f
        errors[n_modes] = np.max(f / exact - 1)
    # A 1-D chain's fixed-interface spectrum grows only linearly, so convergence is slow
    # (algebraic); with 45 of the 58 interior modes the lowest three are within 1e-6, and
    # the complete basis is exact.
    assert errors[45] <= 1e-6
    assert errors[58] <= 1e-12
    assert errors[4] > 1e-3  # the bound is not trivially met


def test_reduced_friction_transient_matches_full():
    # Chain with a Jenkins contact to ground on DOF 20 (added to the boundary automatically)
    # and a harmonic tip load near the first resonance (stick-slip). With every interior
    # mode the reduced transient equals the full one up to the Newton tolerance (1e-10);
    # truncated bases converge towards it.
    n = 30
    s = chain([0.1] * n, [1e4] * n, dampers=[0.2] * n)
    P = np.zeros((1, n))
    P[0, 20] = 1.0
    amp = np.zeros(n, complex)
    amp[-1] = 5.0
    f1 = modes(s, 1).frequencies[0]
    law = Jenkins(3e3, 0.5)
    sysc = s.with_contacts(ContactElement(law, P)).with_loads(
        HarmonicLoad(amp, 2 * np.pi * 1.1 * f1))
    t_end, dt = 0.3, 2e-4
    ref = simulate(sysc, t_end, dt, progress=False)
    assert np.abs(ref.contact_force[0]).max() == pytest.approx(0.5)  # it slips
    errs = []
    for n_modes in (4, 8, 16, 28):
        red = craig_bampton(sysc, [n - 1], n_modes)
        np.testing.assert_array_equal(red.boundary_dofs, [n - 1, 20])
        Pr = red.system.contacts[0].projection.toarray()
        np.testing.assert_array_equal(Pr, np.eye(1, 2 + n_modes, 1))  # exact, physical DOF
        out = simulate(red.system, t_end, dt, progress=False)
        q = red.expand(out.q)
        errs.append(np.abs(q - ref.q).max() / np.abs(ref.q).max())
        if n_modes == 28:
            np.testing.assert_allclose(out.contact_force[0], ref.contact_force[0], atol=1e-8)
    assert errs[-1] < 1e-8
    assert errs[0] > errs[1] > errs[2] > errs[3]


def test_loads_rotation_terms_and_static_load_are_projected():
    rng = np.random.default_rng(5)
    s = random_chain(12)
    G = rng.standard_normal((12, 12))
    G = G - G.T
    Kd = np.diag(rng.uniform(1, 2, 12))
    fc = rng.standard_normal(12)
    amp = rng.standard_normal(12) + 1j * rng.standard_normal(12)
    shape = rng.standard_normal(12)
    full = MechanicalSystem(
        M=s.M, K=s.K, static_load=rng.standard_normal(12),
        loads=(HarmonicLoad(amp, 3.0), TimeLoad(shape, np.sin)),
        rotation=RotationTerms(gyroscopic=G, spin_softening=Kd, centrifugal_load=fc))
    red = craig_bampton(full, [0, 11], 4)
    T = red.transformation
    Om = 7.0
    a, b = full.at_speed(Om), red.system.at_speed(Om)
    np.testing.assert_allclose(b.D, T.T @ a.D @ T, atol=1e-12)
    np.testing.assert_allclose(b.K, T.T @ a.K @ T, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(b.static_load, T.T @ a.static_load, atol=1e-12)
    for t in (0.0, 0.3):
        np.testing.assert_allclose(red.system.external_force(t), T.T @ full.external_force(t),
                                   atol=1e-12)


def test_expand_shapes_and_index_maps():
    red = craig_bampton(random_chain(10), [9, 4], 3)
    assert red.n_boundary == 2 and red.n_modes == 3 and red.n_full == 10
    assert red.expand(np.zeros(5)).shape == (10,)
    assert red.expand(np.zeros((7, 5))).shape == (7, 10)
    np.testing.assert_array_equal(red.reduced_index([4, 9]), [1, 0])
    with pytest.raises(ModelError, match="not retained"):
        red.reduced_index([3])
    with pytest.raises(ModelError, match="q_reduced"):
        red.expand(np.zeros(4))


def test_errors():
    s = random_chain(6)
    with pytest.raises(ModelError, match="n_modes"):
        craig_bampton(s, [5], 6)
    with pytest.raises(ModelError, match="boundary_dofs"):
        craig_bampton(s, [6], 1)
    with pytest.raises(ModelError, match="boundary_dofs"):
        craig_bampton(s, [1, 1], 1)
    with pytest.raises(ModelError, match="at least one"):
        craig_bampton(s, [], 1)
    # an interior DOF held by nothing: K_ii singular
    K = np.zeros((3, 3))
    K[0, 0], K[1, 1] = 2.0, 1.0
    K[0, 1] = K[1, 0] = -1.0
    with pytest.raises(ModelError, match="singular"):
        craig_bampton(MechanicalSystem(M=np.eye(3), K=K), [0], 1)
    with pytest.raises(ModelError, match="method"):
        eigenpairs(np.eye(3), np.eye(3), 1, method="lanczos")


def test_sector_reduction_keeps_named_dofs_and_converges():
    # ring + 8-mass blade per sector (cylindrical, 1 DOF per node), blade tip named as the
    # contact DOF. Reduced sector -> ND spectra converge from above to the unreduced ones.
    N, nb = 12, 8
    n = 2 + nb
    M = np.diag([1.0, 1.0] + [0.3] * nb)
    K = np.zeros((n, n))

    def spring(i, j, k):
        K[i, i] += k
        K[j, j] += k
        K[i, j] -= k
        K[j, i] -= k

    spring(0, 1, 200.0)
    K[0, 0] += 50.0
    K[1, 1] += 50.0
    chain_nodes = [0] + list(range(2, n))
    for a, b in zip(chain_nodes[:-1], chain_nodes[1:], strict=True):
        spring(a, b, 400.0)
    sector = CyclicSector(M=M, K=K, left=[0], right=[1], n_sectors=N,
                          named_dofs={"tip": [n - 1]})
    exact = full_spectrum(all_nd_frequencies(sector, 3), N)
    prev = None
    for n_modes in range(0, nb):
        red = craig_bampton_sector(sector, n_modes)
        assert red.sector.named_dofs["tip"].tolist() == [2]
        np.testing.assert_array_equal(red.reduced_index([0, 1, n - 1]), [0, 1, 2])
        f = full_spectrum(all_nd_frequencies(red.sector, min(3, red.sector.n_independent)),
                          N)[: exact.size]
        assert np.all(f >= exact[: f.size] * (1 - 1e-12))
        if prev is not None and prev.size == f.size:
            assert np.all(f <= prev * (1 + 1e-12))
        prev = f
    red = craig_bampton_sector(sector, nb - 1)  # all interior modes: exact
    np.testing.assert_allclose(full_spectrum(all_nd_frequencies(red.sector, 3), N), exact,
                               rtol=1e-10)
    assert red.expand(np.zeros(red.sector.n_dof)).shape == (n,)
    with pytest.raises(ModelError, match="CyclicSector"):
        craig_bampton_sector(MechanicalSystem(M=M, K=K), 2)
