"""Hill stability and bifurcations of harmonic balance (fricdamp.solvers.hb_stability).

References and tolerances
-------------------------
* Linear oscillator: the Floquet exponents are the eigenvalues ``-zeta w +- i w_d`` (exact;
  1e-10).
* Duffing oscillator ``m x'' + c x' + k x + k3 x^3 = F cos(W t)`` with the cubic_spring law.
  One harmonic ``x = a cos(W t - phi)``, ``A = a^2``, ``Delta = k - m W^2``, ``kappa = 3/4 k3``:
  the amplitude equation is ``Phi(A, W) = A (Delta + kappa A)^2 + (c W)^2 A - F^2 = 0``; a fold
  (turning point in W) is where also ``dPhi/dA = (Delta + kappa A)(Delta + 3 kappa A)
  + (c W)^2 = 0`` (implicit function theorem; this is also the determinant of the
  one-harmonic balance Jacobian in (a1, b1), so points with dPhi/dA < 0 are unstable). For
  given W the second equation is a quadratic in A, ``A = (-2 Delta +- sqrt(Delta^2 - 3 (c
  W)^2)) / (3 kappa)``, and the first is then solved for W by brentq. The backbone (c = 0,
  F = 0) is ``W^2 = k/m + 3/4 (k3/m) a^2``. With H = 1 harmonic balance solves exactly these
  equations (the AFT projection of x^3 is exact for N >= 4H + 1 samples): folds within 1e-9.
  With H = 5 the third harmonic (~1.4 % of a at the upper fold, a = 1.2) shifts the folds by
  the order of (a3 / a) times the share of the cubic force in the restoring force (~0.35):
  bound 0.5 % (upper) and 0.05 % (lower fold, a = 0.35, a3/a ~ 0.1 %); measured 0.15 % and
  0.003 %. H = 5 is converged: H = 7 moves the folds by < 1e-8.
* Liouville's formula: the exponents sum to the period average of the trace of the state
  Jacobian: ``-c/m`` for the Duffing oscillator, ``mu (1 - <x^2>)`` for the van der Pol
  oscillator (so a Neimark-Sacker point, a complex pair on the imaginary axis, has
  ``<x^2> = 1``); checked to the harmonic truncation.
* Time integration (scipy DOP853, rtol 1e-11; and fricdamp's own Newmark stepping through the
  cubic_spring law): a point found stable stays on the orbit, an unstable one leaves it, at the
  growth rate of the largest exponent (3 %).
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from fricdamp.contact import CubicSpring, Jenkins
from fricdamp.contact.base import ContactLaw, LawStep
from fricdamp.errors import ModelError
from fricdamp.solvers.aft import HarmonicBasis
from fricdamp.solvers.continuation import locate_on_branch, solve_and_continue
from fricdamp.solvers.hb import frequency_response, harmonic_balance, load_response
from fricdamp.solvers.hb_stability import hill_stability
from fricdamp.solvers.nma import nonlinear_modes
from fricdamp.solvers.timestep import simulate
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem

M_, K_, C_, K3, F_ = 1.0, 1.0, 0.02, 0.5, 0.03


def duffing(F=F_, c=C_, k3=K3):
    return MechanicalSystem(M=[[M_]], K=[[K_]], D=[[c]],
                            contacts=(ContactElement(CubicSpring(k3), [[1.0]]),),
                            loads=(HarmonicLoad([F], omega=1.0),))


def _fold_roots(g, w_lo=1.0001, w_hi=3.0, n=6000):
    """Roots (W, sign) of g(W, sign) = 0 on a grid refined by brentq."""
    ws = np.linspace(w_lo, w_hi, n)
    out = []
    for sgn in (1.0, -1.0):
        vals = np.array([g(w, sgn) for w in ws])
        for i in range(n - 1):
            if np.isfinite(vals[i]) and np.isfinite(vals[i + 1]) and vals[i] * vals[i + 1] < 0:
                w = brentq(lambda w, s=sgn: g(w, s), ws[i], ws[i + 1], xtol=1e-15)
                out.append((w, sgn))
    return sorted(out)


def duffing_folds(m=M_, k=K_, c=C_, k3=K3, F=F_, k_shift=0.0):
    """Sorted (W, a) where Phi = 0 and the fold condition with Delta + k_shift hold (see the
    module docstring; k_shift = 2 k_c gives the branch points of the coupled pair)."""
    kap = 0.75 * k3

    def amp2(w, sgn):
        d = k + k_shift - m * w * w
        disc = d * d - 3 * (c * w) ** 2
        if disc < 0:
            return np.nan
        A = (-2 * d + sgn * np.sqrt(disc)) / (3 * kap)
        return A if A > 0 else np.nan

    def g(w, sgn):
        A = amp2(w, sgn)
        d = k - m * w * w
        return A * (d + kap * A) ** 2 + (c * w) ** 2 * A - F * F

    return [(w, float(np.sqrt(amp2(w, sgn)))) for w, sgn in _fold_roots(g)]


def _folds(fr):
    return sorted((b.omega, b.amplitude[0]) for b in fr.bifurcations if b.type == "fold")


# ============================================================================ linear
@pytest.mark.parametrize("omega", [0.3, 1.0, 2.7])
def test_linear_oscillator_exponents_closed_form(omega):
    """m = 1, k = 4, c = 0.1: lambda = -0.05 +- i sqrt(4 - 0.0025) whatever Omega; the
    imaginary-part criterion picks the copies lambda + i k Omega (|k| <= H) of smallest
    |Im|: the same multipliers."""
    sys_ = MechanicalSystem(M=[[1.0]], K=[[4.0]], D=[[0.1]], loads=(HarmonicLoad([1.0], 1.0),))
    ss = harmonic_balance(sys_, omega, harmonics=4)
    fl = hill_stability(sys_, ss)
    exact = -0.05 + 1j * np.sqrt(4 - 0.05**2) * np.array([1.0, -1.0])
    np.testing.assert_allclose(np.sort_complex(fl.exponents), np.sort_complex(exact),
                               atol=1e-10)
    assert fl.stable and fl.exponent_error < 1e-10 and fl.verdict_agrees
    fi = hill_stability(sys_, ss, sorting="imaginary", check_harmonics=None)
    wd = np.sqrt(4 - 0.05**2)
    k = np.arange(-4, 5)
    np.testing.assert_allclose(np.abs(fi.exponents.imag), np.min(np.abs(wd - k * omega)),
                               atol=1e-10)
    np.testing.assert_allclose(np.sort_complex(fi.multipliers),
                               np.sort_complex(fl.multipliers), atol=1e-9)


def test_bad_arguments_named():
    sys_ = duffing()
    ss = harmonic_balance(sys_, 1.0, harmonics=3)
    with pytest.raises(ModelError, match="sorting"):
        hill_stability(sys_, ss, sorting="centre")
    with pytest.raises(ModelError, match="check_harmonics"):
        hill_stability(sys_, ss, check_harmonics=3)
    with pytest.raises(ModelError, match="tol"):
        hill_stability(sys_, ss, tol=0.0)
    with pytest.raises(ModelError, match="sorting"):
        frequency_response(sys_, 0.8, 1.2, stability=True, sorting="x")


# ============================================================================ Duffing
@pytest.fixture(scope="module")
def duffing_curves():
    return {H: frequency_response(duffing(), 0.8, 1.6, harmonics=H, stability=True)
            for H in (1, 5, 7)}


def test_duffing_folds_one_harmonic_closed_form(duffing_curves):
    ref = duffing_folds()
    fr = duffing_curves[1]
    assert fr.success and len(ref) == 2
    got = _folds(fr)
    assert len(got) == 2
    for (w, a), (wr, ar) in zip(got, ref, strict=True):
        assert w == pytest.approx(wr, rel=1e-9)
        assert a == pytest.approx(ar, rel=1e-7)
    assert all(b.located and abs(b.multiplier - 1) < 1e-8 for b in fr.bifurcations)


def test_duffing_folds_five_harmonics_within_bound(duffing_curves):
    (w1, _), (w2, _) = duffing_folds()
    (h1, _), (h2, _) = _folds(duffing_curves[5])
    assert abs(h1 / w1 - 1) < 5e-4 and abs(h2 / w2 - 1) < 5e-3
    (g1, _), (g2, _) = _folds(duffing_curves[7])
    assert g1 == pytest.approx(h1, rel=1e-8) and g2 == pytest.approx(h2, rel=1e-8)
    assert duffing_curves[5].stability_error < 1e-6 and duffing_curves[5].stability_converged


def test_duffing_backbone():
    """Undamped, unforced: the one-harmonic nonlinear mode is W^2 = k/m + 3/4 (k3/m) a^2
    (1e-9); the damped upper fold lies on it within the half-power width c/(2m) = 1 %."""
    free = MechanicalSystem(M=[[M_]], K=[[K_]], D=[[0.0]],
                            contacts=(ContactElement(CubicSpring(K3), [[1.0]]),))
    a = np.array([0.2, 0.5, 1.0, 1.5])
    nm = nonlinear_modes(free, 0, a, harmonics=1, amplitude_dof=0)
    np.testing.assert_allclose(nm.frequency, np.sqrt(K_ / M_ + 0.75 * K3 / M_ * a**2),
                               rtol=1e-9)
    (_, _), (w_up, a_up) = duffing_folds()
    assert w_up == pytest.approx(np.sqrt(K_ / M_ + 0.75 * K3 / M_ * a_up**2), rel=1e-2)


def test_duffing_middle_branch_unstable(duffing_curves):
    for H, fr in duffing_curves.items():
        i1, i2 = sorted(b.after_point for b in fr.bifurcations if b.type == "fold")
        assert [b.type for b in fr.bifurcations] == ["fold", "fold"], H
        expected = np.ones(fr.n_points, bool)
        expected[i1 + 1: i2 + 1] = False
        np.testing.assert_array_equal(fr.stable, expected, err_msg=f"H = {H}")
        # Liouville: the exponents sum to -c/m
        np.testing.assert_allclose(fr.floquet_exponents.real.sum(axis=1), -C_ / M_, atol=1e-9)


def test_duffing_one_harmonic_verdict_closed_form(duffing_curves):
    """H = 1: unstable exactly where dPhi/dA < 0 (points with |dPhi/dA| > 1e-6)."""
    fr = duffing_curves[1]
    A = fr.fundamental[:, 0] ** 2
    d = K_ - M_ * fr.omega**2
    kap = 0.75 * K3
    dphi = (d + kap * A) * (d + 3 * kap * A) + (C_ * fr.omega) ** 2
    sel = np.abs(dphi) > 1e-6
    np.testing.assert_array_equal(fr.stable[sel], dphi[sel] > 0)


def _three_solutions(W=1.15, H=7):
    fr = frequency_response(duffing(), 0.8, 1.6, harmonics=H)
    sys_w = duffing().with_loads(HarmonicLoad([F_], omega=W))
    out = []
    for i in range(fr.n_points - 1):
        if (fr.omega[i] - W) * (fr.omega[i + 1] - W) <= 0:
            s = (W - fr.omega[i]) / (fr.omega[i + 1] - fr.omega[i])
            g = fr.coefficients[i] + s * (fr.coefficients[i + 1] - fr.coefficients[i])
            out.append(harmonic_balance(sys_w, W, harmonics=H, initial_guess=g, tol=1e-12))
    return sys_w, out


def _start(ss):
    X = ss.coefficients
    k = np.arange(1, ss.harmonics + 1)
    return X[:, 0] + X[:, 1::2].sum(axis=1), ss.omega * (k * X[:, 2::2]).sum(axis=1)


def test_duffing_stability_matches_time_integration():
    """W = 1.15: upper and lower solutions stable, middle unstable. From the HB state (H = 7),
    DOP853 stays within 1e-5 of the stable orbits for 100 periods and leaves the unstable
    one at the rate of its largest exponent (3 %); fricdamp's Newmark stepping with the
    cubic_spring law (64 steps per period, 60 periods) gives the same verdicts."""
    W = 1.15
    T = 2 * np.pi / W
    sys_w, sols = _three_solutions(W)
    assert len(sols) == 3 and all(s.success for s in sols)
    fls = [hill_stability(sys_w, s) for s in sols]
    assert [f.stable for f in fls] == [True, False, True]

    def rhs(t, y):
        return [y[1], (F_ * np.cos(W * t) - C_ * y[1] - K_ * y[0] - K3 * y[0] ** 3) / M_]

    for ss, fl in zip(sols, fls, strict=True):
        (x0,), (v0,) = _start(ss)
        n_per = 100 if fl.stable else 250
        ts = np.arange(n_per + 1) * T
        sol = solve_ivp(rhs, (0, ts[-1]), [x0, v0], method="DOP853", rtol=1e-11, atol=1e-13,
                        t_eval=ts)
        dev = np.hypot(sol.y[0] - x0, (sol.y[1] - v0) / W)
        if fl.stable:
            assert dev.max() < 1e-5
        else:
            assert dev[-1] > 0.3
            ok = (dev > 1e-6) & (dev < 1e-3)
            rate = np.polyfit(ts[ok], np.log(dev[ok]), 1)[0]
            assert rate == pytest.approx(fl.max_real, rel=3e-2)
        r = simulate(sys_w, 60 * T, T / 64, q0=[x0], v0=[v0], progress=False)
        strobe = np.abs(r.q[::64, 0] - x0)[-10:]
        if fl.stable:
            assert strobe.max() < 0.05 * ss.amplitude[0]
        else:
            assert strobe.max() > 0.3 * ss.amplitude[0]


def test_duffing_load_folds_closed_form():
    """Continuation in the load at W = 1.2, H = 1: F(A) from the amplitude equation has its
    turning points where dPhi/dA = 0, i.e. A = (-2 Delta +- sqrt(Delta^2 - 3 (c W)^2)) /
    (3 kappa), F = sqrt(Phi + F^2) there (1e-9)."""
    W = 1.2
    fr_l = load_response(duffing(), W, 0.1, 10.0, harmonics=1, stability=True)
    d, kap = K_ - M_ * W**2, 0.75 * K3
    A = (-2 * d + np.array([1.0, -1.0]) * np.sqrt(d * d - 3 * (C_ * W) ** 2)) / (3 * kap)
    F = np.sqrt(A * (d + kap * A) ** 2 + (C_ * W) ** 2 * A)
    folds = sorted((b.load_scale * F_, b.amplitude[0] ** 2) for b in fr_l.bifurcations)
    assert [b.type for b in fr_l.bifurcations] == ["fold", "fold"]
    np.testing.assert_allclose(folds, sorted(zip(F, A, strict=True)), rtol=1e-9)
    assert np.sum(~fr_l.stable) > 0 and fr_l.stable[0] and fr_l.stable[-1]


# ============================================================================ branch points
def test_branch_points_of_symmetric_pair_closed_form():
    """Two identical Duffing oscillators, coupling spring kc = 0.02, forced in phase: the
    in-phase solution is the single oscillator's, and it loses stability to antisymmetric
    perturbations where the antisymmetric block of the one-harmonic Jacobian is singular,
    i.e. the fold condition with Delta + 2 kc (a symmetry-breaking pitchfork): with H = 1 two
    branch points, on the middle and on the lower branch, at the closed-form frequencies and
    amplitudes (1e-8), with multiplier +1; the in-phase solution is stable beyond the second."""
    kc = 0.02
    K = np.array([[K_ + kc, -kc], [-kc, K_ + kc]])
    pair = MechanicalSystem(M=np.eye(2), K=K, D=C_ * np.eye(2),
                            contacts=(ContactElement(CubicSpring(K3, n_contacts=2), np.eye(2)),),
                            loads=(HarmonicLoad([F_, F_], omega=1.0),))
    fr = frequency_response(pair, 0.8, 1.6, harmonics=1, stability=True, method="full")
    bps = [b for b in fr.bifurcations if b.type == "branch_point"]
    ref = duffing_folds(k_shift=2 * kc)
    assert [b.type for b in fr.bifurcations] == ["fold", "branch_point", "fold", "branch_point"]
    assert len(ref) == 2
    got = sorted((b.omega, b.amplitude[0]) for b in bps)
    for (w, a), (wr, ar) in zip(got, ref, strict=True):
        assert w == pytest.approx(wr, rel=1e-8) and a == pytest.approx(ar, rel=1e-7)
    for b in bps:
        assert b.located and abs(b.multiplier - 1) < 1e-7
        # in phase (to the conditioning of the singular antisymmetric direction there)
        assert b.amplitude[0] == pytest.approx(b.amplitude[1], rel=1e-6)
    last = bps[-1].after_point
    assert not fr.stable[last] and fr.stable[last + 1:].all()


# ============================================================================ Neimark-Sacker
class VanDerPolDamper(ContactLaw):
    """f = mu u^2 v (with D = -mu: the van der Pol oscillator), memoryless, vectorised."""

    n_dir, n_state, n_contacts, velocity_dependent = 1, 0, 1, True

    def __init__(self, mu):
        self.mu = mu

    def initial_state(self):
        return np.zeros((1, 0))

    def step(self, state, u, v=None):
        u, v = np.reshape(u, (1, 1)), np.reshape(v, (1, 1))
        return LawStep(self.mu * u**2 * v, (2 * self.mu * u * v)[:, :, None],
                       (self.mu * u**2)[:, :, None], np.zeros((1, 0)))

    def stored_energy(self, state, u):
        return np.zeros(1)

    def march(self, u_history, state=None, v_history=None):
        return self.mu * u_history**2 * v_history, np.zeros((1, 0))


def test_neimark_sacker_of_forced_van_der_pol():
    """x'' - mu (1 - x^2) x' + x = F cos(W t), mu = 0.2, F = 0.4, H = 5: the locked branch
    is stable between two Neimark-Sacker points, where <x^2> = 1 (Liouville, 1e-6) and the
    critical multipliers are complex on the unit circle; the exponents sum to mu (1 - <x^2>)
    at every point; from the HB state beyond the NS point DOP853 leaves the orbit."""
    mu, F = 0.2, 0.4
    vdp = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[-mu]],
                           contacts=(ContactElement(VanDerPolDamper(mu), [[1.0]]),),
                           loads=(HarmonicLoad([F], omega=1.0),))
    fr = frequency_response(vdp, 0.5, 1.5, harmonics=5, stability=True)
    assert fr.success
    ns = [b for b in fr.bifurcations if b.type == "neimark_sacker"]
    assert len(ns) == 2 and len(fr.bifurcations) == 2
    for b in ns:
        X = b.coefficients[0]
        assert X[0] ** 2 + 0.5 * np.sum(X[1:] ** 2) == pytest.approx(1.0, abs=1e-6)
        assert abs(abs(b.multiplier) - 1) < 1e-8 and 0.05 < abs(np.angle(b.multiplier)) < 3.0
    X = fr.coefficients[:, 0]
    msq = X[:, 0] ** 2 + 0.5 * np.sum(X[:, 1:] ** 2, axis=1)
    np.testing.assert_allclose(fr.floquet_exponents.real.sum(axis=1), mu * (1 - msq),
                               atol=1e-3 * mu)
    i1, i2 = sorted(b.after_point for b in ns)
    assert fr.stable[i1 + 1: i2 + 1].all() and not fr.stable[: i1 + 1].any()
    # beyond the upper NS point: the orbit is left (quasi-periodic motion)
    j = i2 + 3
    W = float(fr.omega[j])
    (x0,), (v0,) = _start(fr.steady_state(j))
    T = 2 * np.pi / W
    ts = np.arange(151) * T
    sol = solve_ivp(lambda t, y: [y[1], F * np.cos(W * t) + mu * (1 - y[0] ** 2) * y[1] - y[0]],
                    (0, ts[-1]), [x0, v0], method="DOP853", rtol=1e-10, atol=1e-12, t_eval=ts)
    assert np.hypot(sol.y[0] - x0, (sol.y[1] - v0) / W)[-20:].max() > 0.1


# ============================================================================ friction
def test_jenkins_oscillator_decay_rate_needs_memory_term():
    """m = k = 1, c = 0.04, Jenkins k_t = 1, F_s = 0.05, F = 0.1 cos(1.1 t) (gross slip each
    half period): a 5 % perturbation of the HB state decays in time integration (Newmark,
    512 steps per period) at the rate of the largest Hill exponent (5 %), -0.054 1/s; the
    memoryless AFT tangent alone would give -c/2 = -0.02 1/s."""
    sys_ = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.04]],
                            contacts=(ContactElement(Jenkins(1.0, 0.05), [[1.0]]),),
                            loads=(HarmonicLoad([0.1], omega=1.1),))
    W = 1.1
    ss = harmonic_balance(sys_, W, harmonics=15, samples=512)
    fl = hill_stability(sys_, ss, check_harmonics=None)
    assert fl.stable and fl.max_real < -0.04
    q0, v0 = _start(ss)
    basis = HarmonicBasis.create(15, 512)
    st = sys_.contacts[0].law.periodic_response(
        (basis.synthesis @ ss.coefficients.T)[:, :, None]).state
    T, n = 2 * np.pi / W, 512
    ref = simulate(sys_, 30 * T, T / n, q0=q0, v0=v0, states0=[st], progress=False)
    per = simulate(sys_, 30 * T, T / n, q0=1.05 * q0, v0=1.05 * v0, states0=[st],
                   progress=False)
    d = np.hypot(per.q[::n, 0] - ref.q[::n, 0], (per.v[::n, 0] - ref.v[::n, 0]) / W)
    t = np.arange(d.size) * T
    ok = (d > 1e-9) & (d < 1e-2)
    rate = np.polyfit(t[ok], np.log(d[ok]), 1)[0]
    assert rate == pytest.approx(fl.max_real, rel=5e-2)


@pytest.mark.slow
def test_beam_friction_frf_all_stable_and_time_integration():
    """examples/cases/beam_friction_frf.toml (H = 7): every point of the FRF is stable, no
    bifurcation; at the friction-damped peak, time integration (Newmark, 256 steps per
    period) from the HB state stays within 0.5 % of the amplitude of the orbit, and a 5 %
    perturbation decays at the rate of the largest exponent within 25 % (Hill: -16 1/s;
    contact stuck, the first mode's structural -0.22 1/s)."""
    from pathlib import Path

    from fricdamp.runner import build_system, load_case

    case = Path(__file__).resolve().parents[2] / "examples" / "cases" / "beam_friction_frf.toml"
    system = build_system(load_case(case))
    Fv = np.zeros(16)
    Fv[14] = 0.3
    sys_ = system.with_loads(HarmonicLoad(Fv, 2 * np.pi * 60))
    fr = frequency_response(sys_, 2 * np.pi * 60, 2 * np.pi * 110, harmonics=7, stability=True)
    assert fr.success and fr.stable.all() and fr.bifurcations == ()
    assert fr.stability_converged
    W, _ = fr.peak(14)
    sys_w = system.with_loads(HarmonicLoad(Fv, W))
    ss = harmonic_balance(sys_w, W, harmonics=7)
    fl = hill_stability(sys_w, ss, check_harmonics=None)
    assert fl.stable and fl.max_real < -5.0
    q0, v0 = _start(ss)
    c = system.contacts[0]
    basis = HarmonicBasis.create(7, 512)
    st = c.law.periodic_response((basis.synthesis @ (c.projection @ ss.coefficients).T
                                  )[:, :, None]).state
    T, n, P = 2 * np.pi / W, 256, 30
    ref = simulate(sys_w, P * T, T / n, q0=q0, v0=v0, states0=[st], progress=False)
    assert np.abs(ref.q[::n, 14] - q0[14]).max() < 5e-3 * ss.amplitude[14]
    per = simulate(sys_w, P * T, T / n, q0=1.05 * q0, v0=1.05 * v0, states0=[st],
                   progress=False)
    d = np.abs(per.q[::n, 14] - ref.q[::n, 14]) / ss.amplitude[14]
    t = np.arange(d.size) * T
    ok = (t > 2 * T) & (d > 1e-9) & (d < 3e-2)
    rate = np.polyfit(t[ok], np.log(d[ok]), 1)[0]
    assert rate == pytest.approx(fl.max_real, rel=0.25)


# ============================================================================ test functions
def test_continuation_locates_fold_and_branch_point():
    """Problem-agnostic: the circle x^2 + lam^2 = 1 has folds at lam = +-1 (x = 0); the
    transcritical x (x - lam) = 0 followed along x = 0 has a branch point at lam = 0: the
    bordered determinant changes sign there, the tangent's lam component does not."""
    def circle(x, lam):
        return np.array([x[0] ** 2 + lam**2 - 1]), np.array([[2 * x[0]]]), np.array([2 * lam])

    res = solve_and_continue(np.array([-1.0]), circle, 0.0, 2.0, 0.05, tol=1e-13,
                             test_functions=True, reversal_tolerance=10.0, max_steps=60)
    i = res.turning_points[0]
    loc = locate_on_branch(circle, res.x[i], res.lam[i], res.x[i + 1], res.lam[i + 1],
                           res.tangents[i], lambda p: p.tangent[-1], lam_scale=res.lam_scale,
                           tol=1e-13)
    assert loc.converged and abs(abs(loc.point.lam) - 1) < 1e-12 and abs(loc.point.x[0]) < 1e-6

    def trans(x, lam):
        return np.array([x[0] * (x[0] - lam)]), np.array([[2 * x[0] - lam]]), np.array([-x[0]])

    res = solve_and_continue(np.array([0.0]), trans, -1.0, 1.0, 0.07, tol=1e-13,
                             test_functions=True)
    assert res.success
    flips = np.nonzero(res.det_sign[:-1] * res.det_sign[1:] < 0)[0]
    assert len(flips) == 1 and not res.turning_points
    i = flips[0]
    ref = {}

    def det(p):
        ref.setdefault("l", p.log_abs_det)
        return p.det_sign * np.exp(p.log_abs_det - ref["l"])

    loc = locate_on_branch(trans, res.x[i], res.lam[i], res.x[i + 1], res.lam[i + 1],
                           res.tangents[i], det, lam_scale=res.lam_scale, tol=1e-13)
    assert loc.converged and abs(loc.point.lam) < 1e-9
