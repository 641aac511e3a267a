"""Physical checks of examples/cases/damper_sweep.toml (`fricdamp run`: the single design)."""

import numpy as np


def check(summary: dict, case: dict) -> None:
    """F_Z = m_D a_c (1e-3 kg x 1e5 m/s^2 = 100 N, exact); the resonant amplitude is the largest
    of the swept amplitudes or above it (refined peak), finite and positive; the peak frequency
    lies inside the swept band (the first two modes of the stuck and sliding systems)."""
    r = summary["blade_resonance"]
    m = case["model"]
    assert r["F_Z_N"] == m["damper_mass_kg"] * m["centrifugal_acceleration_m_per_s2"]
    a = np.asarray(r["amplitude_m"], float)
    assert np.isfinite(r["blade_amplitude_m"]) and r["blade_amplitude_m"] > 0
    assert r["blade_amplitude_m"] >= np.nanmax(a) * (1 - 1e-12)
    assert min(r["frequency_hz"]) <= r["peak_frequency_hz"] <= max(r["frequency_hz"])
