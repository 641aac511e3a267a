"""Physical check of examples/cases/den_hartog_orbit.toml (tests/examples/test_cases.py).

den Hartog (1931), REFERENCES.md: ``X / (F0/k) = sqrt(V^2 - beta^2 U^2)``, ``V = 1/(1 - r^2)``,
``U = tan(pi/(2r))/r``, the turning point x = X at ``w t = phi = atan2(-beta U/V, X/V)``.
Shooting is exact up to its Newton tolerance: amplitude to 1e-8. The multipliers follow from
the saltation matrices at the two slip reversals (tests/validation/test_shooting.py): the
phases conserve phase-space area (no viscous damping) and each reversal scales it by the ratio
of the accelerations after and before it, ``a+/a- = (F0 cos phi - k X + F_f) / (F0 cos phi -
k X - F_f)``, the same at both by symmetry; so ``|mu_1 mu_2| = (a+/a-)^2`` (1e-9).
"""

from __future__ import annotations

import numpy as np
import pytest


def check(summary: dict, case: dict) -> None:
    m = case["model"]["masses_kg"][0]
    k = case["model"]["springs_N_per_m"][0]
    c = case["contacts"][0]
    Ff = c["mu_static"] * c["normal_load_N"]
    spec = case["analysis"]["periodic_orbit"]
    F0 = spec["force_amplitude_N"][0]
    r = 2 * np.pi * spec["frequency_hz"] / np.sqrt(k / m)
    beta = Ff / F0
    V = 1 / (1 - r**2)
    U = np.tan(np.pi / (2 * r)) / r
    Xh = np.sqrt(V**2 - beta**2 * U**2)
    X = Xh * F0 / k
    phi = np.arctan2(-beta * U / V, Xh / V)

    po = summary["periodic_orbit"]
    assert po["converged"] and po["period_multiple"] == 1 and po["stable"]
    assert po["amplitude_m"][0] == pytest.approx(X, rel=1e-8)
    ratio = (F0 * np.cos(phi) - k * X + Ff) / (F0 * np.cos(phi) - k * X - Ff)
    mu = np.asarray(po["floquet_multipliers_abs"])
    assert mu.size == 2
    assert np.prod(mu) == pytest.approx(ratio**2, rel=1e-9)
    assert po["switches_per_orbit"] == 2  # two slip reversals, no stop
