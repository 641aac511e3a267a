"""Harmonic balance residuals, Jacobians, formulations, results and error handling.

References: the linear frequency response ``Z_k(Omega) Q_k = F_k`` (exact for a linear
system); the one-harmonic Jenkins oscillator equation with the closed-form a1, b1 of
REFERENCES.md; agreement between the full and the condensed formulations (same discrete
equations, eliminated exactly).
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers import hb
from fricdamp.solvers.hb import (
    engine_order_load,
    frequency_response,
    harmonic_balance,
    peak_amplitude,
)
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem, TimeLoad


def _two_dof(damping="rayleigh", static=True):
    M = np.diag([1.0, 2.0])
    K = np.array([[3.0, -1.0], [-1.0, 2.0]])
    D = 0.01 * K + 0.02 * M if damping == "rayleigh" else np.array([[0.05, 0.0], [0.0, 0.0]])
    P = np.array([[1.0, -1.0], [0.0, 1.0]])
    return MechanicalSystem(
        M=M, K=K, D=D, contacts=(ContactElement(Jenkins([0.7, 1.2], [0.03, 0.05]), P),),
        loads=(HarmonicLoad([0.1, 0.05j], omega=1.0), HarmonicLoad([0.0, 0.02], 1.0, 3)),
        static_load=[0.01, 0.0] if static else None)


def _forms(s):
    return [hb._Full(s, dense=True), hb._Full(s, dense=False), hb._Condensed(s, "modal"),
            hb._Condensed(s, "direct")]


@pytest.mark.parametrize("which", range(4))
def test_jacobian_matches_finite_differences(which):
    """Analytic Jacobian and dR/dOmega of every formulation vs central differences.

    Central differences with h = 1e-7 on a piecewise-smooth residual: error ~h^2 terms plus
    kinks crossed (unlikely at a random point); tolerance 1e-6 relative.
    """
    s = hb._Setup(_two_dof(damping="rayleigh"), 4, 64)
    form = _forms(s)[which]
    rng = np.random.default_rng(which)
    x = rng.normal(size=form.N) * 0.1
    w = 1.1
    r, J, dr, _, _ = form.evaluate(x, w)
    J = J.toarray() if sp.issparse(J) else J
    h = 1e-7
    Jfd = np.empty_like(J)
    for j in range(form.N):
        e = np.zeros(form.N)
        e[j] = h
        Jfd[:, j] = (form.evaluate(x + e, w, jacobian=False)[0]
                     - form.evaluate(x - e, w, jacobian=False)[0]) / (2 * h)
    drfd = (form.evaluate(x, w + h, jacobian=False)[0]
            - form.evaluate(x, w - h, jacobian=False)[0]) / (2 * h)
    np.testing.assert_allclose(J, Jfd, atol=1e-6 * np.abs(J).max())
    np.testing.assert_allclose(dr, drfd, atol=1e-6 * np.abs(dr).max())


def test_full_and_condensed_agree():
    """Both formulations solve the same discrete equations: coefficients agree to 1e-12."""
    sysm = _two_dof()
    a = harmonic_balance(sysm, 1.1, harmonics=4, samples=64, method="full")
    b = harmonic_balance(sysm, 1.1, harmonics=4, samples=64, method="condensed")
    assert a.success and b.success
    assert a.method == "full-dense" and b.method == "condensed-modal"
    np.testing.assert_allclose(a.coefficients, b.coefficients, atol=1e-12 * np.abs(
        a.coefficients).max())
    # non-classical damping forces the direct condensation
    c = harmonic_balance(_two_dof(damping="local"), 1.1, harmonics=4, samples=64,
                         method="condensed")
    d = harmonic_balance(_two_dof(damping="local"), 1.1, harmonics=4, samples=64,
                         method="full")
    assert c.method == "condensed-direct" and c.success and d.success
    np.testing.assert_allclose(c.coefficients, d.coefficients,
                               atol=1e-11 * np.abs(d.coefficients).max())


def test_linear_system_is_exact():
    """Without contacts HB reproduces the complex linear solution Z_k^-1 F_k (1e-12)."""
    M = np.diag([1.0, 1.5, 0.5])
    K = np.array([[4.0, -2.0, 0.0], [-2.0, 5.0, -3.0], [0.0, -3.0, 3.0]])
    D = 0.03 * K
    F1 = np.array([1.0, 0.5j, 0.0])
    F2 = np.array([0.0, 0.0, 0.3 - 0.1j])
    sysm = MechanicalSystem(M=M, K=K, D=D, loads=(HarmonicLoad(F1, 1.0),
                                                  HarmonicLoad(F2, 1.0, 2)),
                            static_load=[0.2, 0.0, -0.1])
    w = 1.3
    ss = harmonic_balance(sysm, w, harmonics=3, samples=16)
    for k, F in ((1, F1), (2, F2)):
        Q = np.linalg.solve(K - (k * w) ** 2 * M + 1j * k * w * D, F)
        np.testing.assert_allclose(ss.coefficients[:, 2 * k - 1], Q.real, atol=1e-12)
        np.testing.assert_allclose(ss.coefficients[:, 2 * k], -Q.imag, atol=1e-12)
    np.testing.assert_allclose(ss.coefficients[:, 0], np.linalg.solve(K, [0.2, 0.0, -0.1]),
                               atol=1e-12)
    np.testing.assert_allclose(ss.coefficients[:, 5:], 0.0, atol=1e-14)  # harmonic 3 unloaded
    # linear energy balance: load work = viscous dissipation
    assert ss.energy_balance_error < 1e-10


def test_one_harmonic_jenkins_oscillator_closed_form():
    """H = 1: [(k - m w^2) A + a1(A)]^2 + b1(A)^2 = F^2 with REFERENCES.md a1, b1.

    The AFT samples the force at N = 4096 points: relative error ~(2 pi/N)^2 = 2e-6, so
    the amplitude is checked to 1e-5.
    """
    m, k, kt, fs, F = 1.0, 1.0, 1.0, 0.05, 0.1
    sysm = MechanicalSystem(M=[[m]], K=[[k]], contacts=(ContactElement(Jenkins(kt, fs),
                                                                       [[1.0]]),),
                            loads=(HarmonicLoad([F], 1.0),))
    for w in (0.8, 1.15, 1.3, 1.6):
        ss = harmonic_balance(sysm, w, harmonics=1, samples=4096)
        assert ss.success
        A = ss.fundamental if hasattr(ss, "fundamental") else np.hypot(*ss.coefficients[0, 1:])
        th = np.arccos(1 - 2 * fs / (kt * A))
        a1 = kt * A / np.pi * (th - 0.5 * np.sin(2 * th)) if A > fs / kt else kt * A
        b1 = -4 * fs / np.pi * (1 - fs / (kt * A)) if A > fs / kt else 0.0
        lhs = np.hypot((k - m * w**2) * A + a1, b1)
        assert lhs == pytest.approx(F, rel=1e-5)
        assert ss.dissipated_energy[0] == pytest.approx(
            max(4 * fs * (A - fs / kt), 0.0), rel=1e-4, abs=1e-12)


def test_peak_amplitude_of_trigonometric_polynomial():
    """max |x - c0| refined by Newton equals a 2e5-point brute force (grid error < 1e-8)."""
    rng = np.random.default_rng(7)
    X = rng.normal(size=(5, 2, 11))
    tau = np.linspace(0, 2 * np.pi, 200_001)
    k = np.arange(1, 6)
    S = np.hstack([np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))])
    C = np.concatenate([X[..., 1::2], X[..., 2::2]], axis=-1).reshape(10, 10)
    brute = np.abs(C @ S.T).max(axis=1).reshape(5, 2)
    np.testing.assert_allclose(peak_amplitude(X), brute, rtol=1e-8)
    assert np.all(peak_amplitude(X) >= brute * (1 - 1e-12))


def test_frequency_response_energy_balance_and_exports():
    """Every FRF point balances energy (Newton tol 1e-9 -> error << 1e-3); exports work."""
    sysm = _two_dof()
    fr = frequency_response(sysm, 0.5, 2.0, harmonics=5, samples=64)
    assert fr.success, fr.message
    assert fr.omega[0] == pytest.approx(0.5) and fr.omega[-1] == pytest.approx(2.0)
    assert np.all(fr.energy_balance_error < 1e-6)
    assert np.all(fr.dissipated_energy >= -1e-15)
    assert fr.coefficients.shape == (fr.n_points, 2, 11)
    ds = fr.to_xarray()
    assert ds["amplitude"].shape == (fr.n_points, 2)
    assert ds.attrs["status"] == 0
    ss = fr.steady_state(3)
    t, q = ss.time_history(64)
    assert q.shape == (64, 2) and t[1] == pytest.approx(2 * np.pi / fr.omega[3] / 64)
    ax = fr.plot(dof=1)
    assert ax.get_xlabel().startswith("excitation frequency")


def test_frequency_response_reports_incomplete_curve():
    """max_points reached: status 1, points converged, throw=True raises."""
    sysm = _two_dof()
    fr = frequency_response(sysm, 0.5, 2.0, harmonics=3, samples=32, max_points=4)
    assert fr.status == 1 and not fr.success and fr.n_points == 4
    assert "maximum number" in fr.message
    with pytest.raises(ConvergenceError, match="incomplete"):
        frequency_response(sysm, 0.5, 2.0, harmonics=3, samples=32, max_points=4, throw=True)


def test_failed_newton_is_not_a_solution():
    """An unreachable tolerance: status != 0, no points / success False, message says so."""
    sysm = _two_dof()
    fr = frequency_response(sysm, 0.5, 2.0, harmonics=3, samples=32, tol=1e-30)
    assert fr.status == -1 and fr.n_points == 0 and not fr.success
    assert "Newton failed" in fr.message or "no solution" in fr.message
    ss = harmonic_balance(sysm, 1.0, harmonics=3, samples=32, tol=1e-30, max_iter=3)
    assert not ss.success and ss.status == 1 and "no solution" in ss.message
    assert np.all(np.isnan(ss.coefficients)) and np.isnan(ss.energy_balance_error)
    with pytest.raises(ConvergenceError):
        harmonic_balance(sysm, 1.0, harmonics=3, samples=32, tol=1e-30, max_iter=3,
                         throw=True)


def test_engine_order_load_phases():
    ld = engine_order_load(6, 2, 0.5, dofs_per_sector=2, dof=1)
    a = ld.amplitude
    assert a.shape == (12,) and np.all(a[0::2] == 0)
    np.testing.assert_allclose(np.abs(a[1::2]), 0.5)
    np.testing.assert_allclose(np.angle(a[3] / a[1]), -2 * np.pi * 2 / 6)
    with pytest.raises(ModelError, match="dof"):
        engine_order_load(6, 2, 0.5, dofs_per_sector=2, dof=2)


@pytest.mark.parametrize("kwargs, word", [
    ({"omega": -1.0}, "omega"),
    ({"omega": 1.0, "harmonics": 0}, "harmonics"),
    ({"omega": 1.0, "harmonics": 3, "samples": 6}, "samples"),
    ({"omega": 1.0, "harmonics": 3, "method": "magic"}, "method"),
])
def test_bad_arguments_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        harmonic_balance(_two_dof(), **kwargs)


def test_unsupported_loads_and_rotation_named():
    sysm = _two_dof()
    with pytest.raises(ModelError, match="harmonics"):
        harmonic_balance(sysm, 1.0, harmonics=2)       # the load at harmonic 3
    with pytest.raises(ModelError, match="TimeLoad"):
        harmonic_balance(sysm.with_loads(TimeLoad([1.0, 0.0], np.sin)), 1.0)
    from fricdamp.structure import RotationTerms

    rot = MechanicalSystem(M=np.eye(2), K=np.eye(2), rotation=RotationTerms(
        centrifugal_load=np.ones(2)))
    with pytest.raises(ModelError, match="at_speed"):
        harmonic_balance(rot, 1.0)
    with pytest.raises(ModelError, match="omega_start"):
        frequency_response(sysm, 0.0, 1.0, harmonics=3)


def test_free_floating_structure_uses_full_formulation():
    """K singular (a mass held only by its contact): auto picks the full formulation."""
    sysm = MechanicalSystem(M=np.eye(2), K=np.array([[1.0, 0.0], [0.0, 0.0]]),
                            D=0.01 * np.eye(2),
                            contacts=(ContactElement(Jenkins(2.0, 0.5), [[-1.0, 1.0]]),),
                            loads=(HarmonicLoad([0.1, 0.0], 1.0),))
    ss = harmonic_balance(sysm, 1.2, harmonics=3)
    assert ss.success and ss.method.startswith("full")
    with pytest.raises(ModelError, match="method='full'"):
        harmonic_balance(sysm, 1.2, harmonics=3, method="condensed")


def test_load_response_matches_fixed_level_solutions():
    """Continuation in the load scale: each point equals the HB solution at that level."""
    M = np.diag([1.0, 2.0, 1.0])
    K = np.array([[3.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.5]])
    sysm = MechanicalSystem(M=M, K=K, D=0.01 * K,
                            contacts=(ContactElement(Jenkins(1.0, 0.05), [[1.0, 0, 0]]),),
                            loads=(HarmonicLoad([0.1, 0, 0], omega=1.0),))
    for method in ("full", "condensed"):
        lr = hb.load_response(sysm, 1.0, 0.1, 5.0, harmonics=5, method=method)
        assert lr.success and lr.parameter == "load"
        assert lr.load_scale[0] == pytest.approx(0.1) and lr.load_scale[-1] == pytest.approx(5)
        np.testing.assert_allclose(lr.omega, 1.0)
        assert np.all(lr.energy_balance_error < 1e-6)
        i = lr.n_points // 2
        ss = harmonic_balance(sysm.with_loads(HarmonicLoad([0.1 * lr.load_scale[i], 0, 0],
                                                           omega=1.0)), 1.0, harmonics=5)
        np.testing.assert_allclose(lr.coefficients[i], ss.coefficients,
                                   atol=1e-8 * np.abs(ss.coefficients).max())
        # stuck at low level (no dissipation), slipping at high level
        assert lr.dissipated_energy[0, 0] < 1e-12 < lr.dissipated_energy[-1, 0]
