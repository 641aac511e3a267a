"""Near-simultaneous switches and non-unique switching problems (issue 14, item 4).

Model: a rigid body (x, theta) on two friction contacts at +-L (slip velocities
x' +- L theta'), m = 1 kg, J = 0.25 kg m^2, L = 1 m, springs k_x = 1 N/m, k_theta = 4 N m,
force sin(0.5 t) on x, N = 0.2 N per contact, mu_static = 1, mu_sliding = 0.5. The Delassus
matrix W^T M^-1 W = [[5, -3], [-3, 5]] couples the contacts: when one slips the body can turn
about the other. Both-stuck limit: F = 2 mu_s N = 0.4 N. Just beyond it, three configurations
are consistent: both slip, and either one stuck while the other slips (derived in the
docstring of test_several_configurations_warn).
"""

import logging

import numpy as np

from fricdamp.solvers.event import CoulombSystem, simulate_events
from fricdamp.solvers.event_switch import STICK, LinearDecider
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem


def body(asymmetry=0.0):
    s = MechanicalSystem(M=np.diag([1.0, 0.25]), K=np.diag([1.0, 4.0]),
                         loads=(HarmonicLoad([-1j, 0.0], 0.5),))  # Re(-i e^{iwt}) = sin
    N = 0.2 * np.array([1.0 + asymmetry, 1.0])
    return CoulombSystem(s, directions=[[1.0, 1.0], [1.0, -1.0]], normal_load=N,
                         mu_static=1.0, mu_sliding=0.5)


def test_near_simultaneous_breakaway_is_one_event_in_dop853_phases():
    """Normal loads differing by 1e-10 (relative) make the two breakaways 1e-10 s apart: far
    more than round-off (1e-13 s) but far less than the DOP853 uncertainty of the roots
    (rtol 1e-8: ~2e-8 s). They must be one event: both contacts break away and the body
    keeps translating (|theta| <= 1e-6 |x| afterwards). Split into two events, the second
    contact would stay stuck (consistent with mu_s > mu_d) and the body would turn about it
    (|theta| ~ |x|)."""
    cs = body(asymmetry=1e-10)
    res = simulate_events(cs, (0.0, 2.0), np.zeros(4), method="dop853", rtol=1e-8,
                          atol=1e-14, t_eval=np.linspace(0, 2.0, 201))
    assert res.success
    breaks = [e for e in res.events if e.from_mode == "stick"]
    assert len(breaks) == 2 and breaks[0].time == breaks[1].time
    after = res.t > breaks[0].time + 0.1
    assert np.all(np.abs(res.q[after, 1]) <= 1e-6 * np.abs(res.q[after, 0]))


def test_several_configurations_warn(caplog):
    """At rest with F = 0.41 N (just above 2 mu_s N): with G = [[5, -3], [-3, 5]], b = F/m:
    both slipping (lambda = -mu_d N each) gives a = 2 (F - 0.2) > 0: consistent; contact 1
    stuck, 2 slipping: lambda_1 = -(F + 0.3)/5 = -0.142, |lambda_1| < mu_s N = 0.2, and
    a_2 = F - 0.5 + 0.426 > 0: consistent; the mirror image too. Two configurations with one
    stuck contact: the rule "stick whenever consistent" does not choose, so a warning is
    logged and the switch recorded (the breakaway cascade itself breaks both, symmetrically).
    Below the limit (F = 0.39 N) both stick: unique, silent."""
    cs = body()
    lf = cs.linear_form()
    for F, expect in ((0.41, 2), (0.39, 0)):
        dec = LinearDecider(lf, cs.mu_static, cs.mu_sliding)
        t = np.arcsin(F) / 0.5
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="fricdamp.solvers.event_switch"):
            new = dec.decide_at(t, np.zeros(2), np.zeros(2), np.array([STICK, STICK]),
                                np.array([True, True]), np.zeros(2, dtype=int), np.ones(2))
        if expect:
            assert len(dec.ambiguities) == 1 and len(dec.ambiguities[0][1]) == expect
            assert "consistent configurations" in caplog.text
            assert sorted(tuple(m) for m in dec.ambiguities[0][1]) == [(0, 1), (1, 0)]
            assert new.tolist() == [1, 1]  # the breakaway cascade treats both alike
        else:
            assert dec.ambiguities == [] and caplog.text == ""
            assert np.all(new == STICK)


def test_a_stuck_neighbour_stays_stuck_when_a_slipping_contact_stops():
    """Same body and load (F = 0.41 N at rest), but contact 1 was stuck before the event and
    contact 0 was slipping (in -) and has just stopped. The two one-stuck configurations
    (stick/slip+ and slip+/stick, derived above) are both consistent; 000 (43) lets a stuck
    contact break away only when its own friction saturation reaches zero, which has not
    happened to contact 1 (it is a candidate, not a must-slip contact). So contact 1 stays
    stuck and contact 0 reverses: slip+/stick, decided by the rule (no warning, no recorded
    ambiguity), not by round-off in the breakaway cascade (which breaks both). The mirror
    history (contact 0 stuck, contact 1 stopping) gives the mirror choice."""
    cs = body()
    lf = cs.linear_form()
    t = np.arcsin(0.41) / 0.5
    for before, expect in (((-1, STICK), [1, STICK]), ((STICK, -1), [STICK, 1])):
        dec = LinearDecider(lf, cs.mu_static, cs.mu_sliding)
        new = dec.decide_at(t, np.zeros(2), np.zeros(2), np.array(before),
                            np.array([True, True]), np.zeros(2, dtype=int), np.ones(2))
        assert new.tolist() == expect
        assert dec.ambiguities == []
