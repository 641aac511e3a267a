"""Slip-orbit ellipse and equivalent viscous damping of friction, 001 (19)-(34).

References: paper 001 (23)-(27), (31)-(33); Coulomb's work f N x path length; the exact
first harmonic of Coulomb friction on an ellipse (derived in contact/equivalent.py, checked
here against an FFT of the friction force itself).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate
from scipy.special import ellipe

from fricdamp.contact.equivalent import (
    EllipseFrictionDamping,
    ellipse_damping,
    ellipse_perimeter,
    friction_torque,
    orbit_damping_matrix,
    rectangle_mean_radius,
    slip_ellipse,
    torsional_damping,
)
from fricdamp.errors import ModelError

RNG = np.random.default_rng(7)


def _sampled_orbit(xi, eta, n=4096):
    tau = 2 * np.pi * np.arange(n) / n
    z = np.exp(1j * tau)
    return np.real(xi * z), np.real(eta * z), tau


def test_ellipse_semi_axes_and_inclination_match_the_svd_of_the_orbit():
    """001 (23)-(25): a, b are the singular values of [[xi', -xi''], [eta', -eta'']] and the
    major axis is its first left singular vector (exact linear algebra, 1e-12)."""
    xi = RNG.normal(size=50) + 1j * RNG.normal(size=50)
    eta = RNG.normal(size=50) + 1j * RNG.normal(size=50)
    e = slip_ellipse(xi * 1e-6, eta * 1e-6)
    for i in range(50):
        A = np.array([[xi[i].real, -xi[i].imag], [eta[i].real, -eta[i].imag]]) * 1e-6
        U, sv, _ = np.linalg.svd(A)
        assert e.major[i] == pytest.approx(sv[0], rel=1e-12)
        assert e.minor[i] == pytest.approx(sv[1], rel=1e-10, abs=1e-18)
        d = np.array([np.cos(e.inclination[i]), np.sin(e.inclination[i])])
        assert abs(abs(d @ U[:, 0]) - 1.0) < 1e-10
        assert 0.0 <= e.inclination[i] < np.pi
        # the phase of (25) is where the point is at the end of the major axis
        z = np.exp(1j * e.phase[i])
        r = np.hypot(np.real(xi[i] * z), np.real(eta[i] * z)) * 1e-6
        assert r == pytest.approx(e.major[i], rel=1e-12)


def test_ellipse_special_orbits():
    """A straight orbit has b = 0 and the inclination of the line; a circle a = b."""
    e = slip_ellipse(3e-6 * np.exp(0.4j) * np.cos(0.3), 3e-6 * np.exp(0.4j) * np.sin(0.3))
    assert float(e.major) == pytest.approx(3e-6, rel=1e-12)
    assert float(e.minor) < 1e-18
    assert float(e.inclination) == pytest.approx(0.3, abs=1e-12)
    c = slip_ellipse(2e-6, -2e-6j)
    assert float(c.major) == pytest.approx(2e-6) and float(c.minor) == pytest.approx(2e-6)
    x, y = slip_ellipse(2e-6, 1e-6j).points(9)
    assert np.allclose(x**2 / 4e-12 + y**2 / 1e-12, 1.0)


def test_points_trace_the_sampled_orbit():
    """The closed curve of SlipEllipse.points lies on the orbit of the complex amplitudes."""
    xi, eta = 1e-6 * (0.7 + 0.2j), 1e-6 * (-0.3 + 0.9j)
    x, y = slip_ellipse(xi, eta).points(200)
    xs, ys, _ = _sampled_orbit(xi, eta)
    d = np.min(np.hypot(x[:, None] - xs[None], y[:, None] - ys[None]), axis=1)
    assert d.max() < 2e-9            # sampling of the reference orbit: 4096 points


def test_coulomb_rule_limits_of_001_27():
    """Straight orbit: 4 f N / (pi a w) (001 (27), p = 1) and 4 f N a per cycle; circle:
    f N / (a w) on both axes and 2 pi a f N per cycle (Coulomb's work)."""
    fN, w, a = 0.1 * 100.0, 800.0, 3e-6
    ca, _ = ellipse_damping(a, 0.0, 100.0, 0.1, w, min_ratio=1e-9)
    assert float(ca) == pytest.approx(4 * fN / (np.pi * a * w), rel=1e-7)
    assert np.pi * w * float(ca) * a**2 == pytest.approx(4 * fN * a, rel=1e-7)
    ca, cb = ellipse_damping(a, a, 100.0, 0.1, w)
    assert float(ca) == pytest.approx(fN / (a * w), rel=1e-13)
    assert float(cb) == pytest.approx(fN / (a * w), rel=1e-13)
    assert np.pi * w * (ca * a**2 + cb * a**2) == pytest.approx(2 * np.pi * a * fN, rel=1e-13)


@pytest.mark.parametrize("ratio", [0.02, 0.3, 0.75])
def test_coulomb_rule_is_the_first_harmonic_of_coulomb_friction(ratio):
    """The describing function of T = -f N v/|v| on an ellipse, computed by FFT of the force
    itself, is diagonal in the ellipse axes (no stiffness, no coupling) with the closed
    forms of contact/equivalent.py (FFT of 2^14 samples: 1e-6)."""
    a, b, w, fN = 2e-6, ratio * 2e-6, 500.0, 3.0
    n = 2**14
    tau = 2 * np.pi * np.arange(n) / n
    v = w * np.stack([-a * np.sin(tau), b * np.cos(tau)])      # x = a cos, y = b sin
    T = -fN * v / np.linalg.norm(v, axis=0)
    # first harmonic T = Re(T1 e^{i tau}); velocity amplitude V1 = i w (a, -i b)
    T1 = 2 / n * T @ np.exp(-1j * tau)
    X1 = np.array([a, -1j * b])
    Cdf = -T1 / (1j * w * X1)                                     # per axis, T = -c v
    ca, cb = ellipse_damping(a, b, fN, 1.0, w)
    assert Cdf.real == pytest.approx([float(ca), float(cb)], rel=1e-6)
    assert np.abs(Cdf.imag).max() < 1e-6 * float(ca)             # no stiffness part
    # and by quadrature of the integrals in the docstring
    g = lambda t: np.sqrt(a**2 * np.sin(t) ** 2 + b**2 * np.cos(t) ** 2)  # noqa: E731
    Ia = integrate.quad(lambda t: np.sin(t) ** 2 / g(t), 0, 2 * np.pi, limit=200)[0]
    assert float(ca) == pytest.approx(fN / (np.pi * w) * Ia, rel=1e-9)


def test_dissipation_is_f_N_times_the_perimeter():
    """pi w (c_a a^2 + c_b b^2) = f N x perimeter (Coulomb's work; perimeter 4 a E(m) from
    scipy's complete elliptic integral, an independent formula), 1e-12."""
    a = RNG.uniform(1e-7, 1e-5, 30)
    b = a * RNG.uniform(0.0, 1.0, 30)
    ca, cb = ellipse_damping(a, b, 50.0, 0.2, 300.0, min_amplitude=1e-15, min_ratio=1e-12)
    W = np.pi * 300.0 * (ca * a**2 + cb * b**2)
    per = 4 * a * ellipe(1 - (b / a) ** 2)
    assert np.allclose(W, 10.0 * per, rtol=1e-9)
    assert np.allclose(ellipse_perimeter(a, b), per, rtol=1e-12)
    assert float(ellipse_perimeter(1.0, 0.0)) == 4.0


def test_paper_rule_and_exponent():
    """001 (27) literally: 4 f N/(pi a w) per axis, energy 4 f N (a + b); p scales by
    (w a)^(1-p)."""
    a, b, w, fN = 2e-6, 5e-7, 700.0, 4.0
    ca, cb = ellipse_damping(a, b, fN, 1.0, w, rule="paper")
    assert float(ca) == pytest.approx(4 * fN / (np.pi * a * w))
    assert float(cb) == pytest.approx(4 * fN / (np.pi * b * w))
    assert np.pi * w * (ca * a**2 + cb * b**2) == pytest.approx(4 * fN * (a + b))
    ca2, cb2 = ellipse_damping(a, b, fN, 1.0, w, rule="paper", exponent=0.8)
    assert float(ca2) == pytest.approx(4 * fN / (np.pi * (a * w) ** 0.8))
    assert float(cb2) == pytest.approx(4 * fN / (np.pi * (b * w) ** 0.8))


def test_floors_keep_the_coefficients_finite():
    """A vanishing orbit (stuck contact) is evaluated at the floor, not at zero."""
    ca, cb = ellipse_damping(0.0, 0.0, 10.0, 0.1, 100.0, min_amplitude=1e-9)
    assert np.isfinite(ca) and np.isfinite(cb)
    assert float(ca) == pytest.approx(1.0 / (1e-9 * 100.0))       # circle at the floor
    ca, cb = ellipse_damping(1e-6, 0.0, 10.0, 0.1, 100.0, rule="paper", min_ratio=1e-3)
    assert float(cb) == pytest.approx(4.0 / (np.pi * 1e-9 * 100.0))


def test_orbit_damping_matrix_rotates_the_axis_coefficients():
    """001 (29)-(30): eigenvalues c_a, c_b with the major axis as eigenvector of c_a."""
    C = orbit_damping_matrix(5.0, 2.0, 0.6)
    lam, V = np.linalg.eigh(C)
    assert lam == pytest.approx([2.0, 5.0])
    assert abs(abs(V[:, 1] @ [np.cos(0.6), np.sin(0.6)]) - 1) < 1e-12


def test_torsional_damping_dissipates_4_M0_phi():
    """001 (32): b = 4 M_0 / (pi phi w) dissipates 4 M_0 phi per cycle (1D slip)."""
    b = torsional_damping(2e-5, 0.3, 900.0)
    assert np.pi * 900.0 * float(b) * (2e-5) ** 2 == pytest.approx(4 * 0.3 * 2e-5)


def test_rectangle_mean_radius_and_friction_torque():
    """Mean distance from the centre: 0.382598 s for a square (known constant), quadrature
    for a rectangle (1e-9)."""
    assert float(rectangle_mean_radius(2.0, 2.0)) == pytest.approx(
        2 * (np.sqrt(2) + np.log(1 + np.sqrt(2))) / 6, rel=1e-14)
    a, h = 0.008, 0.02
    num = integrate.dblquad(lambda y, x: np.hypot(x, y), -a / 2, a / 2, -h / 2, h / 2,
                            epsabs=1e-16)[0] / (a * h)
    assert float(rectangle_mean_radius(a, h)) == pytest.approx(num, rel=1e-9)
    assert float(friction_torque(100.0, 0.1, a, h)) == pytest.approx(10.0 * num, rel=1e-9)


def test_ellipse_friction_damping_model_layout_and_energy():
    """Contact coordinates (xi, eta, rotation) per contact, block-diagonal damping, groups;
    the dissipation equals f N perimeter + 4 M_0 phi (Coulomb's work, 1e-10)."""
    N = np.array([[30.0, 20.0], [60.0, 40.0]])
    model = EllipseFrictionDamping(N, [0.1, 0.2], torque_arm=[0.005, 0.004],
                                   min_amplitude=1e-12)
    assert model.n_rows == 6 and model.groups.tolist() == [0, 0, 1, 2, 2, 3]
    assert model.atol.tolist() == pytest.approx([1e-12, 2e-10, 1e-12, 2.5e-10])
    s = np.array([[1e-6, 2e-6j, 3e-5, 4e-6 + 1e-6j, 1e-6, 2e-5j],
                  [2e-6, 1e-6, 1e-5j, 1e-6, -3e-6j, 1e-5]])
    w = np.array([400.0, 800.0])
    C = model.matrix(s, w)
    assert C.shape == (2, 6, 6)
    assert np.allclose(C, np.swapaxes(C, 1, 2))
    assert np.all(C[:, :3, 3:] == 0) and np.all(C[:, 2, :2] == 0)
    W = model.dissipation(s, w)
    e = model.orbits(s)
    fN = np.array([0.1, 0.2]) * N
    phi = np.abs(s[:, [2, 5]])
    expected = fN * ellipse_perimeter(e.major, e.minor) + 4 * fN * [0.005, 0.004] * phi
    assert np.allclose(W, expected, rtol=1e-10)
    # per batch point loads through batch_index
    C1 = model.matrix(s[1:], w[1:], np.array([1]))
    assert np.allclose(C1[0], C[1])
    assert not model.stuck(s).any()
    assert model.stuck(np.zeros((1, 6))).all()


def test_ellipse_friction_damping_without_torsion_has_one_group_per_contact():
    model = EllipseFrictionDamping([5.0, 5.0, 5.0], 0.3)
    assert model.n_rows == 6 and model.groups.tolist() == [0, 0, 1, 1, 2, 2]
    assert model.matrix(np.full(6, 1e-6 + 0j), 100.0).shape == (6, 6)


@pytest.mark.parametrize("kwargs, match", [
    (dict(normal_load=-1.0, friction_coefficient=0.1), "normal_load"),
    (dict(normal_load=1.0, friction_coefficient=-0.1), "friction_coefficient"),
    (dict(normal_load=[1.0, 2.0], friction_coefficient=[0.1, 0.2, 0.3]), "friction_coeff"),
    (dict(normal_load=1.0, friction_coefficient=0.1, rule="exact"), "rule"),
    (dict(normal_load=1.0, friction_coefficient=0.1, exponent=0.0), "exponent"),
    (dict(normal_load=1.0, friction_coefficient=0.1, torque_arm=[1.0, 2.0]), "torque_arm"),
    (dict(normal_load=1.0, friction_coefficient=0.1, min_ratio=2.0), "min_ratio"),
])
def test_bad_input_is_rejected_with_the_parameter_name(kwargs, match):
    with pytest.raises(ModelError, match=match):
        EllipseFrictionDamping(**kwargs)


def test_bad_coordinates_and_function_arguments():
    model = EllipseFrictionDamping(1.0, 0.1)
    with pytest.raises(ModelError, match="2 entries"):
        model.matrix(np.zeros(3, complex), 1.0)
    with pytest.raises(ModelError, match="omega"):
        ellipse_damping(1e-6, 1e-6, 1.0, 0.1, 0.0)
    with pytest.raises(ModelError, match="side_a"):
        rectangle_mean_radius(0.0, 1.0)


def test_rectangle_twist_stiffness_is_the_polar_moment_of_a_uniform_stiffness():
    """k_r = (k_t / (a h)) int (x^2 + y^2) dA over the rectangle (scipy.integrate.dblquad,
    1e-10); the stick-stiffness law of paper 001's case lives here and is re-exported."""
    from fricdamp.contact.equivalent import JenkinsEllipseDamping, rectangle_twist_stiffness
    from fricdamp.models.blade_pair import model as blade_pair

    kt, a, h = 3.0e6, 0.012, 0.005
    polar, _ = integrate.dblquad(lambda y, x: x * x + y * y, -a / 2, a / 2, -h / 2, h / 2,
                                 epsabs=0, epsrel=1e-12)
    assert rectangle_twist_stiffness(kt, a, h) == pytest.approx(kt * polar / (a * h),
                                                                rel=1e-10)
    assert blade_pair.JenkinsEllipseDamping is JenkinsEllipseDamping
    model = blade_pair.build_blade_pair()
    p = model.params
    np.testing.assert_allclose(model.rotational_stick_stiffness(kt),
                               rectangle_twist_stiffness(kt, np.array(p.contact_width),
                                                         np.array(p.contact_height)))
    with pytest.raises(ModelError, match="tangential_stiffness"):
        rectangle_twist_stiffness(0.0, a, h)
