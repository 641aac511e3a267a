"""examples/periodic_orbits.py (the figure of docs/periodic_orbits.md) runs in its quick mode
and gives the numbers the documentation states.

* den Hartog: shooting = closed form to 1e-8 at every frequency (exact phases, Newton 1e-11);
* long event-driven integration (300 periods) = shooting to 1e-6 at its frequencies (the
  transient decays as max|mu|^300 <= 0.94^300 = 1e-8; the amplitude from 4001 samples of
  the last period is biased by at most (pi/4000)^2/2 = 3e-7);
* harmonic balance (H = 15, Jenkins contacts) within 3 % of shooting where both exist
  (H-truncation and penalty compliance; measured <= 1 % away from the resonance peaks,
  where the HB curve is interpolated between its points: the den Hartog panel only).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "periodic_orbits.py"


@pytest.fixture(scope="module")
def data():
    spec = importlib.util.spec_from_file_location("example_periodic_orbits", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.compute(quick=True)


def test_den_hartog_panel(data):
    d = data["den_hartog"]
    np.testing.assert_allclose(d["shooting"], d["closed"], rtol=1e-8)
    assert d["stable"].all()
    sh = np.interp(d["long_omega"], d["omega"], d["shooting"])
    np.testing.assert_allclose(d["long"], sh, rtol=1e-6)
    order = np.argsort(d["hb_omega"])
    hb = np.interp(d["omega"], d["hb_omega"][order], d["hb"][order])
    np.testing.assert_allclose(hb, d["shooting"], rtol=3e-2)


def test_two_dof_panel(data):
    d = data["two_dof"]
    assert np.isfinite(d["shooting"]).all() and d["stable"].all()
    sh = np.interp(d["long_omega"], d["omega"], d["shooting"])
    np.testing.assert_allclose(d["long"], sh, rtol=1e-6)
