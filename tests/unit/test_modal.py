"""Linear modal analysis, Campbell diagrams and critical speeds (fricdamp.solvers.modal).

References
----------
* Uniform spring-mass chains (Rayleigh, *Theory of Sound* §120): n equal masses m and
  springs k, fixed at one end and free at the other,
  ``w_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2n + 1)))``, shapes
  ``phi_j(i) = sin((2j - 1) pi i / (2n + 1))`` (i = 1..n); free at both ends,
  ``w_j = 2 sqrt(k/m) sin(j pi / (2n))``, j = 0..n-1.
* Viscously damped SDOF: ``lam = -zeta w +- i w sqrt(1 - zeta^2)``; stiffness-proportional
  damping ``D = beta K`` gives ``zeta_j = beta w_j / 2`` exactly.
* Spinning disk on a flexible shaft (tilt DOFs, diametral inertia I_d, polar I_p, tilt
  stiffness k): ``I_d w^2 -+ I_p Omega w - k = 0``, i.e.
  ``w_fw,bw = (+-I_p Omega + sqrt(I_p^2 Omega^2 + 4 I_d k)) / (2 I_d)``.
* Paper 003 eq. (1) and Table 2: ``s = 60 f_R / (p o)``.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from fricdamp.contact.jenkins import Jenkins
from fricdamp.errors import ModelError
from fricdamp.solvers.modal import (
    campbell,
    critical_speeds,
    mac,
    modes,
    whirl_direction,
)
from fricdamp.structure.builders import chain
from fricdamp.structure.system import ContactElement, MechanicalSystem, RotationTerms


@pytest.fixture(autouse=True)
def _one_blas_thread():
    # Dense LAPACK calls in the tests (references) and in MechanicalSystem's mass check run
    # ~8x slower with two contending BLAS threads on the 2-core machine.
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def uniform_chain(n, m=1.0, k=1.0, *, sparse=False, ground="first", **kw):
    """Chain of n masses m and springs k (ground="first": fixed-free, "none": free-free)."""
    main = np.full(n, 2 * k)
    main[-1] = k
    if ground == "none":
        main[0] = k
    K = sp.diags([main, np.full(n - 1, -k), np.full(n - 1, -k)], [0, 1, -1], format="csr")
    M = sp.identity(n, format="csr") * m
    if not sparse:
        M, K = M.toarray(), K.toarray()
    return MechanicalSystem(M=M, K=K, **kw)


def fixed_free_omega(n, m, k, j):
    return 2 * np.sqrt(k / m) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1)))


# ----------------------------------------------------------------------------- normal modes
def test_fixed_free_chain_dense_all_modes():
    # Closed form; dense LAPACK: eigenvalues to ~1e-14 of the largest, so 1e-10 relative on
    # frequencies of a 50-DOF chain (condition lam_max/lam_min ~ 1e4) is safe.
    n, m, k = 50, 2.0, 300.0
    res = modes(uniform_chain(n, m, k), n)
    j = np.arange(1, n + 1)
    assert res.kind == "undamped"
    np.testing.assert_allclose(res.omega, fixed_free_omega(n, m, k, j), rtol=1e-10)
    i = np.arange(1, n + 1)
    exact = np.sin(np.outer(i, 2 * j - 1) * np.pi / (2 * n + 1))
    np.testing.assert_allclose(np.diag(mac(res.shapes, exact)), 1.0, atol=1e-10)


def test_fixed_free_chain_sparse_4000_dofs():
    # ARPACK shift-invert at sigma = 0 on a sparse LU; a few thousand DOFs is the size the
    # solver must handle in about a second (measured 0.04 s; timing lives in benchmarks).
    # Tolerance 1e-9: ARPACK converges to machine precision in the inverted operator
    # (measured 5e-12). (Sizes > 3000 also skip MechanicalSystem's dense mass check.)
    n = 4000
    res = modes(uniform_chain(n, 1.5, 2.0e4, sparse=True), 8)
    np.testing.assert_allclose(res.omega, fixed_free_omega(n, 1.5, 2.0e4, np.arange(1, 9)),
                               rtol=1e-9)
    np.testing.assert_allclose(res.modal_masses, 1.0, rtol=1e-12)


def test_sigma_selects_modes_nearest_the_shift():
    n, m, k = 120, 1.0, 1.0e4
    exact = fixed_free_omega(n, m, k, np.arange(1, n + 1)) / (2 * np.pi)
    sigma = 0.5 * (exact[40] + exact[41]) + 0.1 * (exact[41] - exact[40])
    want = np.sort(exact[np.argsort(np.abs(exact - sigma))[:6]])
    for method in ("dense", "sparse"):
        res = modes(uniform_chain(n, m, k, sparse=True), 6, sigma=sigma, method=method)
        np.testing.assert_allclose(res.frequencies, want, rtol=1e-10)


@pytest.mark.parametrize("n, method", [(30, "dense"), (3500, "sparse")])
def test_free_free_chain_rigid_body_mode(n, method):
    # K is singular (free-free): the shift-invert factorisation at 0 fails and the shift is
    # nudged below 0; the rigid-body mode (w = 0) and the elastic ones
    # w_j = 2 sqrt(k/m) sin(j pi / (2n)) must come out. Rigid mode: w^2 ~ eps |K| ~ 1e-12
    # in this scaling, so f_0 < 1e-5 Hz.
    m, k = 1.0, 1.0e3
    res = modes(uniform_chain(n, m, k, ground="none", sparse=method == "sparse"), 5,
                method=method)
    assert res.frequencies[0] < 1e-5
    j = np.arange(1, 5)
    np.testing.assert_allclose(res.omega[1:], 2 * np.sqrt(k / m) * np.sin(j * np.pi / (2 * n)),
                               rtol=1e-8)
    rigid = res.shapes[:, 0] / res.shapes[0, 0]
    np.testing.assert_allclose(rigid, 1.0, atol=1e-8)


def test_modal_masses_and_normalisations():
    rng = np.random.default_rng(3)
    masses = rng.uniform(0.5, 2.0, 12)
    s = chain(masses, rng.uniform(50, 100, 12))
    a = modes(s, 12)  # mass-normalised
    b = modes(s, 12, normalize="max")
    np.testing.assert_allclose(a.shapes.T @ s.M @ a.shapes, np.eye(12), atol=1e-12)
    np.testing.assert_allclose(np.max(np.abs(b.shapes), axis=0), 1.0, rtol=1e-14)
    np.testing.assert_allclose(b.modal_masses, np.einsum("ij,ij->j", b.shapes, s.M @ b.shapes),
                               rtol=1e-12)
    # the "max"-normalised modal stiffness over modal mass is w^2 (Rayleigh quotient)
    kk = np.einsum("ij,ij->j", b.shapes, s.K @ b.shapes)
    np.testing.assert_allclose(kk / b.modal_masses, a.omega**2, rtol=1e-10)
    # effective masses of a base translation sum to the total mass (completeness)
    r = np.ones(12)
    eff = (a.shapes.T @ s.M @ r) ** 2
    assert eff.sum() == pytest.approx(masses.sum(), rel=1e-12)


def test_proportional_damping_ratios_from_normal_modes():
    # D = beta K: normal modes diagonalise D and zeta_j = beta w_j / 2 exactly.
    beta = 2e-4
    s = uniform_chain(20, 1.0, 1e4)
    res = modes(MechanicalSystem(M=s.M, K=s.K, D=beta * s.K), 20)
    assert res.kind == "undamped"  # symmetric D: auto picks normal modes
    np.testing.assert_allclose(res.damping_ratios, beta * res.omega / 2, rtol=1e-10)


# ----------------------------------------------------------------------------- complex modes
def test_damped_sdof_eigenvalue():
    m, k, zeta = 2.0, 800.0, 0.05
    wn = np.sqrt(k / m)
    s = MechanicalSystem(M=[[m]], K=[[k]], D=[[2 * zeta * m * wn]])
    res = modes(s, 1, kind="damped")
    lam = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    assert res.eigenvalues[0] == pytest.approx(lam, rel=1e-12)
    assert res.damping_ratios[0] == pytest.approx(zeta, rel=1e-12)
    assert res.frequencies[0] == pytest.approx(wn * np.sqrt(1 - zeta**2) / (2 * np.pi),
                                               rel=1e-12)


@pytest.mark.parametrize("n, method", [(40, "dense"), (3200, "sparse")])
def test_complex_modes_of_proportionally_damped_chain(n, method):
    # First-order form vs closed form: zeta_j = beta w_j / 2, damped frequency
    # w_j sqrt(1 - zeta_j^2). Sparse: ARPACK on (B + sA)^-1 A; tolerance 1e-8 on zeta covers
    # ARPACK's residual for well-separated eigenvalues (measured 2e-10).
    m, k, beta = 1.0, 1.0e4, 1e-3
    s = uniform_chain(n, m, k, sparse=method == "sparse")
    s = MechanicalSystem(M=s.M, K=s.K, D=beta * s.K)
    res = modes(s, 5, kind="damped", method=method)
    w = fixed_free_omega(n, m, k, np.arange(1, 6))
    zeta = beta * w / 2
    np.testing.assert_allclose(res.damping_ratios, zeta, rtol=1e-8)
    np.testing.assert_allclose(res.omega, w * np.sqrt(1 - zeta**2), rtol=1e-10)
    # shapes: q-part of the first-order eigenvectors equal the normal modes (MAC = 1)
    ref = modes(MechanicalSystem(M=s.M, K=s.K), 5, method=method)
    np.testing.assert_allclose(np.diag(mac(res.shapes, ref.shapes)), 1.0, atol=1e-9)
    np.testing.assert_allclose(res.modal_masses, 1.0, rtol=1e-12)


def spinning_disk(Id=2.0, Ip=3.0, k=1000.0, axial=None):
    """Tilt DOFs (theta_x, theta_y) of a disk; optional uncoupled axial DOF (m, k_z)."""
    G = Ip * np.array([[0.0, 1.0], [-1.0, 0.0]])
    M, K = np.diag([Id, Id]), np.diag([k, k])
    if axial is not None:
        mz, kz = axial
        M = np.diag([Id, Id, mz])
        K = np.diag([k, k, kz])
        G = np.pad(G, ((0, 1), (0, 1)))
    return MechanicalSystem(M=M, K=K, rotation=RotationTerms(gyroscopic=G))


def disk_closed_form(W, Id=2.0, Ip=3.0, k=1000.0):
    root = np.sqrt((Ip * W) ** 2 + 4 * Id * k)
    return (-Ip * W + root) / (2 * Id), (Ip * W + root) / (2 * Id)


def test_gyroscopic_disk_forward_and_backward_whirl():
    # Closed form (module docstring). For G = Ip [[0, 1], [-1, 0]] the higher root satisfies
    # k - w^2 Id = -w Ip Omega, so row 1 gives phi_y = -i phi_x: a counter-clockwise orbit
    # (forward whirl for positive spin about z); the lower root gives phi_y = +i phi_x.
    W = 50.0
    res = modes(spinning_disk(), 2, speed=W)
    assert res.kind == "damped"
    wb, wf = disk_closed_form(W)
    np.testing.assert_allclose(res.omega, [wb, wf], rtol=1e-12)
    np.testing.assert_allclose(res.damping_ratios, 0.0, atol=1e-12)  # conservative
    np.testing.assert_array_equal(whirl_direction(res.shapes, 0, 1), [-1, 1])
    ratio = res.shapes[1] / res.shapes[0]
    np.testing.assert_allclose(ratio, [1j, -1j], atol=1e-12)


def test_campbell_closed_form_and_tracking_through_a_crossing():
    # Forward whirl rises through an uncoupled axial mode (w_z constant). MAC tracking must
    # keep the axial branch flat, whereas sorting by frequency would swap the branches.
    mz, kz = 1.0, 60.0**2
    sys3 = spinning_disk(axial=(mz, kz))
    W = np.linspace(0.0, 120.0, 61)
    res = campbell(sys3, W, 3)
    wb, wf = disk_closed_form(W)
    wz = np.sqrt(kz / mz)
    assert wf[0] < wz < wf[-1]  # there is a crossing
    omega = 2 * np.pi * res.frequencies
    # identify branches at the last speed, then check them along the whole sweep
    cols = [int(np.argmin(np.abs(omega[-1] - x))) for x in (wb[-1], wz, wf[-1])]
    assert sorted(cols) == [0, 1, 2]
    np.testing.assert_allclose(omega[:, cols[0]], wb, rtol=1e-10)
    np.testing.assert_allclose(omega[:, cols[1]], wz, rtol=1e-10)
    np.testing.assert_allclose(omega[:, cols[2]], wf, rtol=1e-10)
    assert np.all(res.tracking_mac[2:] > 0.99)  # after the split of the double mode
    np.testing.assert_allclose(res.rpm, W * 30 / np.pi)
    # crossing of the constant axial branch with the line f = p o Omega / 2 pi is exact
    # under linear interpolation and equals 003 (1): s = 60 f / (p o)
    cr = [c for c in res.crossings(orders=[1], pulses=2) if c.mode == cols[1]]
    assert len(cr) == 1
    assert cr[0].rpm == pytest.approx(float(critical_speeds(wz / (2 * np.pi), 1, 2)),
                                      rel=1e-12)
    ds = res.to_xarray()
    assert ds["frequency"].shape == (61, 3)


def test_campbell_without_rotation_is_flat():
    s = uniform_chain(5, 1.0, 100.0)
    res = campbell(s, [0.0, 10.0, 20.0], 3)
    np.testing.assert_allclose(res.frequencies, np.tile(res.frequencies[0], (3, 1)),
                               rtol=1e-13)


def test_speed_argument_and_spin_softening():
    # K(Omega) = K - Omega^2 Kd for a 1-DOF: w^2 = (k - Omega^2 kd) / m.
    s = MechanicalSystem(M=[[2.0]], K=[[500.0]],
                         rotation=RotationTerms(spin_softening=[[0.5]]))
    res = modes(s, 1, speed=10.0)
    assert res.omega[0] == pytest.approx(np.sqrt((500.0 - 100 * 0.5) / 2.0), rel=1e-13)


def test_stuck_contacts_add_their_tangent_stiffness():
    # A Jenkins element to ground at the tip, stuck: same modes as an extra spring k_t.
    n, kt = 6, 250.0
    base = uniform_chain(n, 1.0, 100.0)
    P = np.zeros((1, n))
    P[0, -1] = 1.0
    withc = base.with_contacts(ContactElement(Jenkins(kt, 1.0), P))
    K2 = base.K.copy()
    K2[-1, -1] += kt
    np.testing.assert_allclose(modes(withc, n, contacts="stuck").omega,
                               modes(MechanicalSystem(M=base.M, K=K2), n).omega, rtol=1e-12)
    np.testing.assert_allclose(modes(withc, n).omega, modes(base, n).omega, rtol=1e-12)


# ----------------------------------------------------------------------------- 003 (1)
def test_critical_speeds_paper_003_table_2():
    # 003 Table 2: p = 8 pulses, o = 1 at f_R = 44.53 Hz -> 334 rpm (2ND);
    # o = 3 at f_R = 49.20 Hz -> 123 rpm (6ND). The paper rounds to whole rpm.
    s = critical_speeds([44.53, 49.20], [1, 3], 8)
    np.testing.assert_allclose(s, [60 * 44.53 / 8, 60 * 49.20 / 24], rtol=1e-15)
    np.testing.assert_array_equal(np.round(s), [334, 123])
    # broadcasting over orders
    assert critical_speeds(44.53, [1, 2, 3], 8).shape == (3,)


def test_result_export(tmp_path):
    res = modes(uniform_chain(4, 1.0, 10.0), 2)
    ds = res.to_xarray()
    np.testing.assert_allclose(ds["frequency"].values, res.frequencies)
    res.save(tmp_path / "m.npz")
    with np.load(tmp_path / "m.npz") as z:
        np.testing.assert_allclose(z["frequency"], res.frequencies)
    res.save(tmp_path / "m.nc")
    assert res.plot() is not None
    cam = campbell(spinning_disk(), np.linspace(0.0, 50.0, 5), 2)
    cam.save(tmp_path / "c.npz")
    with np.load(tmp_path / "c.npz") as z:
        np.testing.assert_allclose(z["frequency"], cam.frequencies)
        np.testing.assert_allclose(z["speed"], cam.speeds)
    assert cam.plot(orders=[1, 2], pulses=8) is not None


# ----------------------------------------------------------------------------- errors
def test_bad_arguments_raise_model_errors():
    s = uniform_chain(4, 1.0, 10.0)
    with pytest.raises(ModelError, match="n_modes"):
        modes(s, 0)
    with pytest.raises(ModelError, match="n_modes"):
        modes(s, 5)
    with pytest.raises(ModelError, match="sigma"):
        modes(s, 2, sigma=-1.0)
    with pytest.raises(ModelError, match="kind"):
        modes(s, 2, kind="complex")
    with pytest.raises(ModelError, match="normalize"):
        modes(s, 2, normalize="unit")
    K = s.K.copy()
    K[0, 1] += 1.0
    with pytest.raises(ModelError, match="symmetric"):
        modes(MechanicalSystem(M=s.M, K=K), 2, kind="undamped")
    with pytest.raises(ModelError, match="orders"):
        critical_speeds(44.0, 0, 8)
    with pytest.raises(ModelError, match="pulses"):
        critical_speeds(44.0, 1, 1.5)
    with pytest.raises(ModelError, match="frequencies_hz"):
        critical_speeds(-1.0, 1, 8)
    with pytest.raises(ModelError, match="speeds_rad_s"):
        campbell(s, [], 2)
