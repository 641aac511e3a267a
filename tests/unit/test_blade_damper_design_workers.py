"""``design_study(workers=2)`` spreads the designs over processes with the same results.

Each design (stepped sine and peak search) starts from its own static state, and each
lift-off bracket's bisection runs in one process, so the results do not depend on where a
design ran: every array, the validity boundary and the error list are compared for
equality. The grid has one design that lifts off (80 deg), so the bracket path runs too.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.blade_damper.model import BladeDamperParameters
from fricdamp.models.blade_damper.studies import design_study

KW = dict(damper_masses_kg=[1e-3], gammas_deg=[65.0, 80.0],
          frequency_hz=np.linspace(47.0, 56.0, 3), centrifugal_acceleration=1e5,
          boundary_refinements=1)


def test_workers_give_the_serial_results():
    p = BladeDamperParameters(excitation_amplitude=8.0)
    serial = design_study(p, **KW)
    ticks = []
    par = design_study(p, workers=2, progress=lambda d, n: ticks.append((d, n)), **KW)
    assert par.to_dict() == serial.to_dict()
    assert par.errors == serial.errors and serial.errors  # 80 deg lifts off
    assert serial.boundary[0]["gamma_invalid_deg"] is not None
    assert len(serial.boundary[0]["refined"]) == 1
    for name in ("blade_amplitude_m", "peak_frequency_hz", "min_normal_force_N"):
        assert np.array_equal(getattr(par, name), getattr(serial, name), equal_nan=True)
    assert ticks[-1][0] == ticks[-1][1] == 3  # two grid designs and one bisection design


@pytest.mark.parametrize("bad", [0, -1, 1.5, True])
def test_workers_must_be_a_positive_integer(bad):
    with pytest.raises(ModelError, match="workers must be an integer >= 1"):
        design_study(BladeDamperParameters(), workers=bad, **KW)
