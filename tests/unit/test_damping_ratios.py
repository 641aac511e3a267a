"""The named damping ratios against the linear viscous and Coulomb closed forms.

References
----------
REFERENCES.md "Damping ratios": zeta = E_d / (4 pi E_s), E_s = peak strain energy; eta = 2 zeta;
paper 002 (26)-(27): xi = (4/pi) E_d / (4 theta_max M_max) = E_d / (pi theta_max M_max).
Linear viscous loop f = k u + c u', u = A cos(w t): E_d = pi c w A^2, E_s = k A^2 / 2,
|f|_max = A sqrt(k^2 + (c w)^2). Coulomb slider: E_d = 4 F A, zeta_eq = 2 F / (pi k A).

The loops are sampled at N equally spaced phases over one period. The trapezoidal loop area
cancels the elastic part exactly and returns pi c w A^2 sin(h)/h, h = 2 pi / N (a closed
form: checked to 1e-12); the ratios built on it therefore carry the relative error h^2/6 =
5e-7 at N = 3600 (tolerance 1e-6). The sampled peak force misses the true peak by at most
(pi/N)^2 / 2 = 4e-7 relative.
"""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.signals.damping import (
    coulomb_equivalent_ratio,
    energy_damping_ratio,
    equivalent_viscous_damping,
    log_decrement_from_zeta,
    loss_factor,
    paper002_damping_ratio,
    paper002_supplied_energy,
    zeta_from_log_decrement,
)
from fricdamp.signals.energy import loop_area, peak_strain_energy

N = 3600


def viscous_loop(k, c, omega, amplitude, n=N, phase0=0.0):
    theta = phase0 + 2 * np.pi * np.arange(n) / n
    u = amplitude * np.cos(theta)
    v = -amplitude * omega * np.sin(theta)
    return u, k * u + c * v


@pytest.mark.parametrize("zeta", [0.005, 0.02, 0.1])
def test_viscous_ellipse_energy_ratio_is_modal_zeta_at_resonance(zeta):
    """m = 2 kg, k = 800 N/m, c = 2 zeta sqrt(k m), driven at w = w_n: E_d / (4 pi E_s) = zeta."""
    m, k, A = 2.0, 800.0, 3e-3
    wn = np.sqrt(k / m)
    c = 2 * zeta * np.sqrt(k * m)
    u, f = viscous_loop(k, c, wn, A)
    e_d = loop_area(u, f)
    h = 2 * np.pi / N
    assert e_d == pytest.approx(np.pi * c * wn * A**2 * np.sin(h) / h, rel=1e-12)
    e_s = peak_strain_energy(u, f)
    assert e_s == pytest.approx(0.5 * k * A**2, rel=1e-12)  # tip sampled: v = 0 there
    assert energy_damping_ratio(e_d, e_s) == pytest.approx(zeta, rel=1e-6)
    assert loss_factor(e_d, e_s) == pytest.approx(2 * zeta, rel=1e-6)
    # the energy ratio is c w / (2 k) at any frequency: only at w_n is it the modal zeta
    u2, f2 = viscous_loop(k, c, 0.5 * wn, A)
    assert energy_damping_ratio(loop_area(u2, f2), peak_strain_energy(u2, f2)) == pytest.approx(
        0.5 * zeta, rel=1e-6)
    assert equivalent_viscous_damping(e_d, wn, A) == pytest.approx(c, rel=1e-6)


def test_secant_strain_energy_with_off_sample_tips():
    """Tips between samples (0.37 of a step off): quadratic interpolation of u and f at the
    tip keeps E_s = k A^2/2 to O(h^3) relative (h = 2 pi / 720: 1e-6 covers it)."""
    k, c, w, A = 800.0, 5.0, 20.0, 3e-3
    u, f = viscous_loop(k, c, w, A, n=720, phase0=0.37 * 2 * np.pi / 720)
    assert peak_strain_energy(u, f) == pytest.approx(0.5 * k * A**2, rel=1e-6)


@pytest.mark.parametrize("eta", [0.01, 0.05, 0.3])
def test_paper002_ratio_is_the_loss_factor_for_a_viscous_loop(eta):
    """xi = E_d/(pi theta_max M_max) = eta / sqrt(1 + eta^2): the loss factor to O(eta^3).

    Exact with the analytic E_d and M_max; with M_max from the samples, to the sampling
    error (pi/N)^2/2 = 4e-7 relative.
    """
    k, w, th = 50.0, 2 * np.pi * 30.0, 2e-4  # N m/rad, rad/s (30 Hz as in paper 002), rad
    c = eta * k / w
    theta, moment = viscous_loop(k, c, w, th)
    e_d = np.pi * c * w * th**2
    h = 2 * np.pi / N
    assert loop_area(theta, moment) == pytest.approx(e_d * np.sin(h) / h, rel=1e-12)
    m_max_exact = th * np.hypot(k, c * w)
    xi = paper002_damping_ratio(e_d, th, m_max_exact)
    assert xi == pytest.approx(eta / np.sqrt(1 + eta**2), rel=1e-12)
    assert loss_factor(e_d, peak_strain_energy(theta, moment)) == pytest.approx(eta, rel=1e-12)
    xi_samples = paper002_damping_ratio(e_d, np.max(np.abs(theta)), np.max(np.abs(moment)))
    assert xi_samples == pytest.approx(xi, rel=1e-6)
    # to first order it is the loss factor, not the damping ratio zeta = eta / 2
    assert abs(xi / eta - 1) <= 0.5 * eta**2 + 1e-12


def test_paper002_supplied_energy_is_eight_peak_strain_energies():
    """002 (27) E_s = 4 theta_max M_max is the bounding rectangle: 8 x (theta_max M_max / 2)."""
    k, th = 50.0, 2e-4
    theta, moment = viscous_loop(k, 0.0, 1.0, th)
    e_peak = peak_strain_energy(theta, moment, method="peak")
    assert paper002_supplied_energy(th, k * th) == pytest.approx(8 * e_peak, rel=1e-12)


def test_log_decrement_conversions_against_viscous_peaks():
    """Peaks of exp(-zeta w_n t) cos(w_d t) one damped period apart: ratio exp(delta)."""
    zeta = np.array([1e-3, 0.01, 0.05, 0.3])
    wn = 7.0
    td = 2 * np.pi / (wn * np.sqrt(1 - zeta**2))
    delta = zeta * wn * td  # ln(x(t) / x(t + T_d))
    np.testing.assert_allclose(zeta_from_log_decrement(delta), zeta, rtol=1e-14)
    np.testing.assert_allclose(log_decrement_from_zeta(zeta), delta, rtol=1e-14)
    assert isinstance(zeta_from_log_decrement(0.1), float)
    with pytest.raises(ModelError, match="zeta"):
        log_decrement_from_zeta(1.0)


def test_coulomb_equivalent_ratio_from_a_friction_loop():
    """Spring k plus a Coulomb slider F sgn(u'), u = A cos: loop area 4 F A, E_s = k A^2/2
    (from the spring alone) and E_d / (4 pi E_s) = 2F/(pi k A). The slider force jumps at the
    tips (theta = 0, pi), where the samples carry sgn(0) = 0: the two half-height trapezoids
    next to each tip miss F A h^2 / 2 in all, i.e. E_d = 4 F A (1 - h^2/4) + O(h^4)."""
    k, F, A = 1e4, 2.0, 1e-3
    theta = 2 * np.pi * np.arange(N) / N
    u = A * np.cos(theta)
    f_slider = F * np.sign(-np.sin(theta))
    e_d = loop_area(u, f_slider)
    h = 2 * np.pi / N
    assert e_d == pytest.approx(4 * F * A * (1 - h**2 / 4), rel=1e-10)
    zeta = energy_damping_ratio(4 * F * A, 0.5 * k * A**2)
    assert zeta == pytest.approx(coulomb_equivalent_ratio(F, k, A), rel=1e-12)
    assert zeta == pytest.approx(2 * F / (np.pi * k * A), rel=1e-14)
    amps = np.array([1e-3, 2e-3, 4e-3])
    np.testing.assert_allclose(coulomb_equivalent_ratio(F, k, amps) * amps,
                               2 * F / (np.pi * k))


def test_ratios_never_mixed():
    """The same loop gives zeta, eta = 2 zeta and xi ~ eta: distinct numbers, distinct names."""
    e_d, k, A = 1e-4, 1e3, 1e-2
    e_s = 0.5 * k * A**2
    z = energy_damping_ratio(e_d, e_s)
    assert loss_factor(e_d, e_s) == pytest.approx(2 * z, rel=1e-14)
    assert paper002_damping_ratio(e_d, A, k * A) == pytest.approx(2 * z, rel=1e-14)


def test_vectorised_and_errors():
    e_d = np.array([1.0, 2.0, 3.0])
    np.testing.assert_allclose(energy_damping_ratio(e_d, 2.0), e_d / (8 * np.pi))
    with pytest.raises(ModelError, match="strain_energy"):
        energy_damping_ratio(1.0, 0.0)
    with pytest.raises(ModelError, match="dissipated_energy"):
        loss_factor(-1.0, 1.0)
    assert loss_factor(-1e-9, 1.0, allow_negative=True) < 0
    with pytest.raises(ModelError, match="theta_max"):
        paper002_damping_ratio(1.0, -1.0, 1.0)
    with pytest.raises(ModelError, match="amplitude"):
        coulomb_equivalent_ratio(1.0, 1.0, 0.0)
    with pytest.raises(ModelError, match="stiffness"):
        coulomb_equivalent_ratio(1.0, -5.0, 1.0)
    with pytest.raises(ModelError, match="finite"):
        zeta_from_log_decrement(np.nan)
