"""The blade-damper time response judges itself through the Python API (issue 15, item 5b).

The case file's ``time_response`` already ends ``failed`` when Lemke's method stops on a
ray and lists the negative normal force (tests/cli/test_cli_verdict.py). The same run
through ``time_response`` used to return ``ok=False`` with the errors as strings only; its
``verdict`` must say the same as the case: ``failed`` on the solver stop, with the tension
as a reason and the smallest normal force as an estimate. A normal run at 8 N is ``ok``.
"""

from __future__ import annotations

import numpy as np

from fricdamp.models.blade_damper.model import BladeDamperParameters
from fricdamp.models.blade_damper.studies import time_response

LIFTOFF = dict(masses=(0.30, 0.15, 0.30, 0.165), stiffnesses=(7.2e4, 2.3e4, 8.6e4, 2.6e4),
               dampings=(2.9, 1.2, 3.2, 1.3), damper_mass=1.0e-3, gamma=np.deg2rad(50.0),
               p1=-80.0, p2=2.0e-3, mu_static=0.35, mu_sliding=0.30, centrifugal_force=1.0,
               excitation_phase=np.deg2rad(90.0), excitation_frequency=58.0)


def test_solver_stop_with_tension_is_failed():
    tr = time_response(BladeDamperParameters(excitation_amplitude=2000.0, **LIFTOFF),
                       periods=3)
    v = tr.verdict
    assert not tr.ok
    assert v.status == "failed"
    assert v.reasons[0].startswith("solver:")
    assert any("negative normal force" in r for r in v.reasons)
    assert v.estimates["min_normal_force_N"] < 0


def test_normal_run_is_ok():
    tr = time_response(BladeDamperParameters(excitation_amplitude=8.0,
                                             excitation_frequency=58.0), periods=3)
    assert tr.ok and tr.verdict.status == "ok"
    assert tr.verdict.estimates["min_normal_force_N"] > 0
