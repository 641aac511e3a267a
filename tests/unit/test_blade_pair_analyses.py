"""The results contract of the 001 analyses (models/blade_pair_analyses.py) and their
input checks. Physics is tested in tests/validation/test_blade_pair.py."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.blade_pair.model import BladePairParameters, build_blade_pair
from fricdamp.models.blade_pair.studies import (
    campbell_diagram,
    complex_modes,
    run_blade_pair_case,
    steady_state_sweep,
)


@pytest.fixture(scope="module")
def summary():
    return run_blade_pair_case(BladePairParameters(), rpm_range=(300.0, 1500.0),
                               n_campbell=3, n_sweep=4, orders=(20, 30),
                               friction_coefficients=(0.1, 0.2), n_modes=5,
                               orbit_rpm=[600.0])


def test_summary_follows_the_contract(summary):
    """n_dof 78; campbell {rpm, frequency_hz per mode, excitation_orders}; steady_state a
    list of {k, friction_coefficient, rpm, semi_axes_A_m, semi_axes_B_m,
    dissipated_energy_J, energy_balance_error}; JSON-serialisable."""
    assert summary["n_dof"] == 78
    c = summary["campbell"]
    assert c["rpm"] == pytest.approx([300.0, 900.0, 1500.0])
    assert len(c["frequency_hz"]) == 5 and all(len(f) == 3 for f in c["frequency_hz"])
    assert c["excitation_orders"] == [20, 30]
    ss = summary["steady_state"]
    assert [(s["k"], s["friction_coefficient"]) for s in ss] == [
        (20, 0.1), (20, 0.2), (30, 0.1), (30, 0.2)]
    for s in ss:
        assert len(s["rpm"]) == 4
        for key in ("semi_axes_A_m", "semi_axes_B_m"):
            ab = np.array(s[key])
            assert ab.shape == (4, 2) and np.all(ab[:, 0] >= ab[:, 1])
        assert len(s["dissipated_energy_J"]) == 4
        assert isinstance(s["energy_balance_error"], float) and s["energy_balance_error"] < 1e-8
        assert s["converged"]
    assert summary["all_converged"]
    assert summary["eqlin_iterations"] == sum(s["total_iterations"] for s in ss)
    assert len(summary["orbits"]) == 2
    json.dumps(summary)


def test_sweep_entries_are_consistent(summary):
    """Total dissipation = A + B; normal loads follow the speed squared."""
    for s in summary["steady_state"]:
        W = np.array(s["dissipated_energy_J"])
        assert W == pytest.approx(np.add(s["dissipated_energy_A_J"],
                                         s["dissipated_energy_B_J"]))
        N = np.array(s["normal_loads_N"])
        r = np.array(s["rpm"])
        assert N[:, 0] / r**2 == pytest.approx(np.full(4, N[0, 0] / r[0] ** 2))


def test_bad_arguments_name_the_parameter():
    model = build_blade_pair()
    with pytest.raises(ModelError, match="rpm"):
        steady_state_sweep(model, 30, [0.0, 100.0])
    with pytest.raises(ModelError, match="order"):
        steady_state_sweep(model, 0, [100.0])
    with pytest.raises(ModelError, match="damping_source"):
        campbell_diagram(model, [100.0], damping_source="paper")
    with pytest.raises(ModelError, match="n_modes"):
        campbell_diagram(model, [100.0], n_modes=0)
    with pytest.raises(ModelError, match="rpm_range"):
        run_blade_pair_case(rpm_range=(500.0, 100.0))
    with pytest.raises(ModelError, match="model"):
        complex_modes("blade", 1000.0)
