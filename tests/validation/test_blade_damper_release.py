"""The paper-000 blade damper with lift-off and impacts (``BladeDamperSystem(release=True)``):
a design beyond the no-separation boundary (gamma = 80 deg, 1 g damper, F_Z = 100 N,
F_e = 8 N at 52 Hz; the bilateral model turns its normal force tensile there) is integrated
through lift-off and re-impacts, and the energy balance closes."""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.solvers.event import simulate_events

PARAMS = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=52.0).with_(
    gamma_deg=80.0)


def test_release_defaults_and_input():
    s = BladeDamperSystem(PARAMS)
    assert s.release is False and not s.unilateral_contacts().any()
    assert np.all(s.restitution_coefficients() == 0.0)
    for bad in (-0.2, 1.01, float("nan")):
        with pytest.raises(ModelError, match=r"restitution must be a number in \[0, 1\]"):
            BladeDamperSystem(PARAMS, release=True, restitution=bad)


@pytest.mark.parametrize("e, max_step", [(0.0, 2e-4), pytest.param(0.5, 5e-5,
                                                                     marks=pytest.mark.slow)])
def test_design_beyond_lift_off_is_computed(e, max_step):
    """Twelve excitation periods from the static state with release on: the damper lifts off
    (the first time when a normal force reaches zero, about 6.9 periods in) and re-impacts
    the platforms (bursts of impacts: a plastic impact on one platform throws the wedged
    damper off the other; they end at the Zeno velocity). Checks: normal forces never
    tensile (>= -1e-6 N), open gaps never negative beyond the gap tolerance (1e-9 m), a
    bilateral run from the state just before the first lift-off turns its normal force
    tensile (so the design is beyond lift-off and would be discarded without release), every
    impact loses energy (>= -1e-12 J), and the energy balance
    ``input work = friction + viscous + impact loss + change of mechanical energy`` closes to
    1e-6 of the input work (DOP853 at rtol 1e-8; the work integrals are not error-controlled,
    so the step is bounded: e = 0 at max_step 2e-4 s closes to 4e-8, while at the default
    step of a quarter of the excitation's half period the balance closes to about 1e-5;
    e = 0.5, whose bursts bring many more lift-offs, where the friction power of a slipping
    contact falls to zero within a step, closes to 1.1e-6 at 2e-4 s and to 8e-9 at 5e-5 s,
    the bound used)."""
    T = 1.0 / PARAMS.excitation_frequency
    s = BladeDamperSystem(PARAMS, release=True, restitution=e)
    y0 = np.concatenate([s.static_equilibrium().q, np.zeros(7)])
    t1 = 12 * T
    r = simulate_events(s, (0.0, t1), y0, t_eval=np.linspace(0.0, t1, 2401), rtol=1e-8,
                        atol=1e-12, max_step=max_step, max_events=40_000, progress=False)
    assert r.success
    lo, ti = r.lift_off_times(), r.impact_times()
    assert lo.size >= 1 and ti.size >= 1 and lo[0] < ti[0]
    assert 6 * T < lo[0] < 8 * T
    assert np.any(r.modes == 3)
    assert r.lambda_N.min() >= -1e-6
    gaps = np.array([s.normal_gap(q) for q in r.q])
    assert gaps[r.modes == 3].min() >= -1e-9
    assert all(im.energy_loss >= -1e-12 for im in r.impacts)
    loss = r.energy["impact_loss"][-1]
    assert loss > 0
    assert np.abs(r.energy_residual).max() <= 1e-6 * r.energy["input_work"][-1]
    # the same design without release: from just before the first lift-off the normal
    # force of the bilateral model becomes tensile
    i = int(np.searchsorted(r.t, lo[0])) - 1
    b = BladeDamperSystem(PARAMS, compiled=False)
    rb = simulate_events(b, (r.t[i], lo[0] + 2e-3), np.concatenate([r.q[i], r.qd[i]]),
                         rtol=1e-8, atol=1e-12, progress=False)
    assert rb.lambda_N.min() < -1.0
