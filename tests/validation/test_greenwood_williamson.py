"""Greenwood–Williamson contact and paper 002's rotational joint against closed forms.

References: Greenwood & Williamson, Proc. R. Soc. A 295 (1966) 300–319; REFERENCES.md
(F_{3/2}(0) = 0.430020); paper 002 (Bouchaala et al., IJSS 2014) (11)–(14), (17)–(27);
Johnson, Contact Mechanics (1985) §7.3 for the single-summit loop energy.
"""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erfc

from fricdamp.contact.rough import GreenwoodWilliamson, RoughRotationalJoint, gw_integral
from fricdamp.signals.energy import loop_area


def phi(s):
    return np.exp(-0.5 * s * s) / np.sqrt(2 * np.pi)


def f_quad(n, h):
    """F_n(h) by adaptive quadrature in y = s - h = t^2 (smooth for n = -1/2 too), scaled
    by phi(h) to avoid underflow: phi(h) int_0^inf 2 t^(2n+1) e^(-h t^2 - t^4/2) dt."""
    val, _ = quad(lambda t: 2 * t ** (2 * n + 1) * np.exp(-h * t * t - 0.5 * t**4), 0, np.inf,
                  epsabs=0, epsrel=1e-13, limit=400)
    return phi(h) * val


# ----------------------------------------------------------------------------- F_n(h)
def test_f32_at_zero_reference_value():
    assert gw_integral(1.5, 0.0) == pytest.approx(0.430020, abs=5e-7)  # REFERENCES.md


@pytest.mark.parametrize("n", [0.0, -0.5, 0.5, 1.0, 1.5, 2.5])
def test_gw_integral_against_quadrature(n):
    """pbdv route (h < 4, ~3e-11), Laguerre (h >= 4) and Hermite (h < -10) quadratures
    against scipy quad (1e-13 requested): 1e-9 relative leaves a 30x margin."""
    h = np.array([-14.0, -10.5, -9.5, -6.0, -2.0, 0.0, 1.0, 2.95, 3.99, 4.0, 5.0, 6.0, 9.0,
                  15.0, 25.0])
    got = gw_integral(n, h)
    ref = np.array([f_quad(n, x) for x in h])
    np.testing.assert_allclose(got, ref, rtol=1e-9)


def test_gw_integral_exact_low_orders():
    """F_0 = Q(h) = erfc(h/sqrt 2)/2 and F_1 = phi(h) - h Q(h), exactly."""
    h = np.linspace(-8, 8, 33)
    q = 0.5 * erfc(h / np.sqrt(2))
    np.testing.assert_allclose(gw_integral(0.0, h), q, rtol=1e-10)
    np.testing.assert_allclose(gw_integral(1.0, h), phi(h) - h * q, rtol=1e-9)


# ----------------------------------------------------------------------------- GW model
GW = GreenwoodWilliamson(summit_density=2e9, nominal_area=5.04e-4, summit_radius=50e-6,
                         summit_std=0.45e-6, E_star=115.4e9)


def direct(separation, integrand):
    """eta A_n int_d^inf integrand(z - d) phi_sigma(z) dz by quad over summit heights z."""
    s = GW.summit_std
    val, _ = quad(lambda z: integrand(z - separation) * phi(z / s) / s, separation,
                  separation + 40 * s, epsabs=0, epsrel=1e-12, limit=400,
                  points=[separation + k * s for k in (0.1, 1, 3)])
    return GW.summit_density * GW.nominal_area * val


@pytest.mark.parametrize("h", [-1.0, 0.0, 1.5, 3.0, 4.5])
def test_gw_load_area_count_against_direct_integration(h):
    """Sum of Hertz loads 4/3 E* R^1/2 w^3/2, areas pi R w and counts over the Gaussian
    summit heights (quad, 1e-12) against the closed forms: 1e-9 relative (the F_n route is
    good to 3e-11; the brief's 1e-6 is met with margin)."""
    d = h * GW.summit_std
    R, Es = GW.summit_radius, GW.E_star
    assert GW.load(d) == pytest.approx(
        direct(d, lambda w: 4 / 3 * Es * np.sqrt(R) * w**1.5), rel=1e-9)
    assert GW.real_area(d) == pytest.approx(direct(d, lambda w: np.pi * R * w), rel=1e-9)
    assert GW.n_contacts(d) == pytest.approx(direct(d, lambda w: 1.0), rel=1e-9)


def test_separation_for_load_round_trip():
    loads = np.array([1e-3, 1.0, 100.0, 1e4, 1e6])
    d = GW.separation_for_load(loads)
    np.testing.assert_allclose(GW.load(d), loads, rtol=1e-12)
    assert np.all(np.diff(d) < 0)  # more load, closer surfaces


# ----------------------------------------------------------------------------- joint
@pytest.fixture(scope="module")
def joint():
    return RoughRotationalJoint.paper_002(n_cells=(14, 9))


def per_summit_loop_energy(law, theta):
    """Sum over summit classes of the closed-form Mindlin loop energy at delta* = r theta:
    micro-slip W(q) (REFERENCES.md) below delta_s, 4 mu N (delta* - 0.8 delta_s) above."""
    F, ds = law.slip_force, law.slip_displacement
    dstar = law.arm * theta
    x = np.minimum(dstar / ds, 1.0)
    q = 1 - (1 - x) ** 1.5
    w_micro = 4.8 * F * ds * (1 - (1 - q) ** (5 / 3) - 5 * q / 6 * (1 + (1 - q) ** (2 / 3)))
    return np.sum(np.where(dstar < ds, w_micro, 4 * F * (dstar - 0.8 * ds)))


def joint_loop(joint, theta_amp, n=2000):
    th = theta_amp * np.cos(np.linspace(0, 4 * np.pi, 2 * n + 1))
    m = joint.drive(th)
    return th[n:-1], m[n:-1]


def test_summit_loads_sum_to_preload(joint):
    """002 (24): N = sum N_i. The Gauss–Jacobi height classes integrate the Hertz load
    y^(3/2) phi(h+y) spectrally (1e-13 with 24 classes): 1e-10 relative."""
    assert joint.total_normal_load == pytest.approx(joint.preload, rel=1e-10)
    assert joint.gw.load(joint.separation) == pytest.approx(100.0, rel=1e-12)


def test_initial_stiffness_and_slip_moment_against_gw_integrals(joint):
    """Continuum forms on the cell grid: k = eta (8/C) (R sigma)^1/2 F_1/2(h) sum A_c r_c^2,
    M_s = mu (P / A_n) sum A_c r_c (uniform nominal pressure). Spectral quadrature: 1e-10.
    The FD secant of the traced moment at 1e-12 rad checks the kinematics (error ~ q ~ 1e-4)."""
    gw, a = joint.gw, joint.asperities
    h = joint.separation / gw.summit_std
    C = a.compliance[0]
    ac, r = joint.cell_area, joint.cell_radius
    k_gw = gw.summit_density * 8 / C * np.sqrt(gw.summit_radius * gw.summit_std) \
        * gw_integral(0.5, h) * np.sum(ac * r**2)
    assert joint.initial_stiffness == pytest.approx(k_gw, rel=1e-10)
    ms = a.mu[0] * joint.preload / gw.nominal_area * np.sum(ac * r)
    assert joint.slip_moment == pytest.approx(ms, rel=1e-10)
    th = 1e-12
    m = joint.drive(np.array([0.0, th]))[1]
    assert m / th == pytest.approx(k_gw, rel=2e-4)


def test_loop_energy_equals_sum_of_single_summit_closed_forms(joint):
    """The joint loop, from micro-slip to gross slip, against the sum over its summit
    classes of the single-contact closed forms: checks the kinematics delta = r theta, the
    moment sum (002 (25)) and the per-class Masing loops together. Sampling: 2000 points
    per cycle, trapezoid error (2 pi / 2000)^2 / 6 = 1.6e-6 for each smooth loop; classes
    that just reach gross slip add a kink between samples: 1e-4 relative."""
    for theta in [1e-8, 3e-7, 2e-6, 1e-5]:
        th, m = joint_loop(joint, theta)
        W = loop_area(th, m)
        assert W == pytest.approx(per_summit_loop_energy(joint.asperities, theta), rel=1e-4)


def max_q(joint, theta):
    """Largest T*/(mu N) over the summit classes at amplitude theta (virgin curve)."""
    a = joint.asperities
    x = np.minimum(a.arm * theta / a.slip_displacement, 1.0)
    return float(np.max(1 - (1 - x) ** 1.5))


def test_loop_energy_positive_increasing_and_cubic_at_small_amplitude(joint):
    """Paper 002 Fig. 16: dissipated energy grows with the rotation amplitude. Micro-slip:
    with every summit class below its delta_s, W = sum c_i theta^3 (1 + 2 q_i / 3 + ...)
    (series of the closed form), so the log-log slope between theta and 2 theta is
    3 + O(q): bounded here by 2 q_max(2 theta) (q_max ~ 5e-3 at 1e-10 rad)."""
    amps = np.array([1e-10, 2e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4])
    W = np.array([loop_area(*joint_loop(joint, a)) for a in amps])
    assert np.all(W > 0)
    assert np.all(np.diff(W) > 0)
    slope = np.log(W[1] / W[0]) / np.log(2.0)
    assert 3.0 < slope < 3.0 + 2 * max_q(joint, amps[1])
    # not cubic any more once the small summits reach gross slip
    assert np.log(W[-1] / W[-2]) / np.log(10.0) < 2.0


def test_small_amplitude_coefficient_against_gw_integral(joint):
    """Micro-slip limit: W -> theta^3 sum r^3 (8a/C)^3 C / (36 a mu N) per summit, i.e. with
    002 (12)-(13) W / theta^3 -> (512/36)(3/4) / (C^2 mu E*) (R/sigma)^1/2 eta F_-1/2(h)
    sum A_c r_c^3. The next term of the series, 2 q_i / 3 per class, is bounded by q_max
    (~2.5e-3 at 1e-10 rad); the quadrature error of F_-1/2 is ~1e-12."""
    gw, a = joint.gw, joint.asperities
    h = joint.separation / gw.summit_std
    C, mu = a.compliance[0], a.mu[0]
    coef = (512 / 36 * 0.75 / (C**2 * mu * gw.E_star) * np.sqrt(gw.summit_radius / gw.summit_std)
            * gw.summit_density * gw_integral(-0.5, h)
            * np.sum(joint.cell_area * joint.cell_radius**3))
    theta = 1e-10
    W = loop_area(*joint_loop(joint, theta))
    assert 1.0 < W / theta**3 / coef < 1.0 + max_q(joint, theta)


def test_damping_ratio_rises_with_amplitude_paper_002_fig17(joint):
    """002 (26)-(27): xi = (4/pi) E_d / (4 theta_max M_max) rises with the amplitude
    (Fig. 17) and tends to 4/pi (rigid-plastic loop) in gross slip."""
    amps = np.array([1e-8, 1e-7, 1e-6, 1e-5, 1e-3])
    xi = []
    for a in amps:
        th, m = joint_loop(joint, a)
        xi.append(4 / np.pi * loop_area(th, m) / (4 * a * np.abs(m).max()))
    xi = np.array(xi)
    assert np.all(np.diff(xi) > 0)
    assert xi[-1] == pytest.approx(4 / np.pi, rel=2e-2)
