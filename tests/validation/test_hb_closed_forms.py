"""Harmonic balance against closed forms (REFERENCES.md).

1. den Hartog (1930/1931) Coulomb oscillator ``m x'' + k x + F_f sgn(x') = F_0 cos wt``,
   non-stop steady state ``X / (F_0/k) = sqrt(V^2 - beta^2 U^2)``, ``V = 1/(1 - r^2)``,
   ``U = tan(pi/(2r))/r``. The Coulomb slider is a Jenkins element with k_t = 1e6 k: its
   stick phases at the reversals change the amplitude by ~1e-3 relative (measured: the
   deviation scales like sqrt(k / k_t), 2.4 % at k_t = 1e3 k). The HB error then decreases
   with H roughly like 1/H (a non-smooth force); H = 1 is the describing-function estimate
   ``sqrt(1 - (4 beta/pi)^2)/|1 - r^2|`` (REFERENCES: "only an approximation").
2. Griffin-type blade-to-ground damper, one harmonic, c = 0: peak amplitude
   ``4 S^2 / (k_d (4 S - pi F))`` and, at ``S_opt = pi F / 2``, ``A_min = pi F / k_d`` at
   ``w^2 = (k + k_d/2)/m``: an exact property of the one-harmonic balance, checked through a
   continued frequency response (the sampled AFT force: 1e-5; the peak located by a parabola
   through the densest points of the curve: 2e-3).
3. Energy balance of every HB point (input work = viscous + contact dissipation) <= 0.1 %.
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.solvers.hb import frequency_response, harmonic_balance
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem


def den_hartog(r, beta):
    V = 1.0 / (1.0 - r * r)
    U = np.tan(np.pi / (2.0 * r)) / r
    return np.sqrt(V * V - beta * beta * U * U)


def coulomb_oscillator(beta, kt=1e6):
    return MechanicalSystem(M=[[1.0]], K=[[1.0]],
                            contacts=(ContactElement(Jenkins(kt, beta), [[1.0]]),),
                            loads=(HarmonicLoad([1.0], omega=1.0),))


@pytest.mark.parametrize("r, beta", [(0.6, 0.3), (2.0, 0.3)])
def test_den_hartog_error_decreases_with_harmonics(r, beta):
    """Non-stop regime (beta below the REFERENCES bound with S = 1): 0.53 at r = 0.6 and
    0.60 at r = 2. Errors at H = 1, 3, 7, 15, 31 decrease strictly; below 0.6 % at H = 31."""
    sysm = coulomb_oscillator(beta)
    X = den_hartog(r, beta)
    errors = []
    for H in (1, 3, 7, 15, 31):
        ss = harmonic_balance(sysm, r, harmonics=H, samples=2048)
        assert ss.success, ss.message
        assert ss.energy_balance_error < 1e-3
        errors.append(abs(ss.amplitude[0] / X - 1))
    assert all(b < a for a, b in zip(errors, errors[1:], strict=False)), errors
    assert errors[-1] < 6e-3
    assert errors[2] < 1.5e-2         # H = 7: the engineering default, ~1 %


@pytest.mark.parametrize("r", [0.6, 1.5, 2.0])
def test_one_harmonic_is_describing_function(r):
    """H = 1 with a Coulomb slider equals sqrt(1 - (4 beta/pi)^2)/|1 - r^2| (1e-3: k_t)."""
    beta = 0.3
    ss = harmonic_balance(coulomb_oscillator(beta), r, harmonics=1, samples=4096)
    X1 = np.sqrt(1 - (4 * beta / np.pi) ** 2) / abs(1 - r * r)
    assert ss.amplitude[0] == pytest.approx(X1, rel=1e-3)


@pytest.mark.parametrize("S", [0.1, np.pi * 0.1 / 2])
def test_griffin_damper_peak(S):
    m, k, kd, F = 1.0, 1.0, 1.0, 0.1
    sysm = MechanicalSystem(M=[[m]], K=[[k]],
                            contacts=(ContactElement(Jenkins(kd, S), [[1.0]]),),
                            loads=(HarmonicLoad([F], omega=1.0),))
    fr = frequency_response(sysm, 1.05, 1.6, harmonics=1, samples=1024, step=0.01)
    assert fr.success, fr.message
    assert np.all(fr.energy_balance_error < 1e-3)
    w_pk, A_pk = fr.peak(0)
    assert A_pk == pytest.approx(4 * S**2 / (kd * (4 * S - np.pi * F)), rel=2e-3)
    if S == pytest.approx(np.pi * F / 2):
        assert A_pk == pytest.approx(np.pi * F / kd, rel=2e-3)
        assert w_pk == pytest.approx(np.sqrt((k + kd / 2) / m), rel=2e-3)
