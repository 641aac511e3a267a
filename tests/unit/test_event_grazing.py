"""Grazing in DOP853 phases: dips of an event function between the samples of a step.

DOP853 phases screen their event functions at the start and the quarter points of each
step; a function that dips below zero and comes back between two samples has no sign
change there. Where the samples show a small local minimum, the dense output is searched
for the dip (:func:`fricdamp.solvers.event_phase.dip_windows`, :func:`~fricdamp.solvers.
event_phase.dip_search`; compiled copies in the blade damper's ``phase_run`` and event loop).

References: the exact phases (``method="exact"``, closed-form solution with the derivative's
roots, :mod:`fricdamp.solvers.event_kernels`) on the same linear systems; for the blade
damper, the compiled event loop against the Python loop over the same compiled phases (to
round-off) and SciPy's DOP853 (to the integration accuracy). Without the search (the code
before, or ``dip_windows`` switched off here) each dip below is stepped over.
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.solvers import event_phase
from fricdamp.solvers.event import CoulombSystem, simulate_events
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem


def _no_dip_search(monkeypatch):
    monkeypatch.setattr(event_phase, "dip_windows", lambda v, tol, sits=False: [])


def _events(res):
    return [(e.contact, e.from_mode, e.to_mode) for e in res.events]


def _reserve_dip(delta):
    """1 DOF (m = k = 1), stuck at q = 0 under F (1 + delta) sin(0.5 t) with mu N = 1: the
    friction reserve 1 - |lambda_T| = 1 - (1 + delta) |sin(0.5 t)| dips to -delta at
    t = pi for 2 sqrt(2 delta) / 0.5 s (0.018 s for delta = 1e-5; quarter samples every
    pi / 16 s): the contact slips briefly and sticks again."""
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]],
                         loads=(HarmonicLoad([-1j * (1.0 + delta)], 0.5),))  # Re(-i e^{iwt})
    return CoulombSystem(s, directions=[1.0], normal_load=1.0, mu_static=1.0,
                         mu_sliding=1.0)


def _slip_dip():
    """1 DOF (m = k = 1) slipping forward from q = 0 at q' = v0 under 3 cos(10 t), mu N =
    0.5: the slip velocity falls with ripples of the load. At v0* = 0.621007290290521 m/s
    (bisection on the exact phases: the first stop jumps from t = 0.497 s to 0.926 s) a
    ripple minimum touches zero at t = 0.49666 s; 1e-8 m/s less and it dips below zero: the
    contact sticks for 2.5e-8 s and slips on (mu_static = mu_sliding)."""
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([3.0], 10.0),))
    return CoulombSystem(s, directions=[1.0], normal_load=1.0, mu_static=0.5,
                         mu_sliding=0.5)


def test_stuck_contact_reserve_dip_dop853_equals_exact(monkeypatch):
    """Slip onset 1e-5 of the friction limit (the case of issue 14): DOP853 (rtol 1e-10)
    gives the exact phases' events, times within 1e-8 s (measured 2026-11-29: 7e-9 s for the
    stick-again time, whose root is shallow: the slip lasts 8.5e-3 s at 1e-7 m/s)."""
    cs = _reserve_dip(1e-5)
    ex = simulate_events(cs, (0.0, 8.0), [0.0, 0.0], method="exact")
    nu = simulate_events(cs, (0.0, 8.0), [0.0, 0.0], method="dop853", rtol=1e-10,
                         atol=1e-14)
    assert _events(ex) == [(0, "stick", "slip+"), (0, "slip+", "stick")]
    assert abs(ex.events[0].time - np.pi) < 0.01
    assert _events(nu) == _events(ex)
    np.testing.assert_allclose(nu.event_times(), ex.event_times(), rtol=0, atol=1e-8)
    # without the dip search the slip onset is stepped over
    _no_dip_search(monkeypatch)
    old = simulate_events(cs, (0.0, 8.0), [0.0, 0.0], method="dop853", rtol=1e-10,
                          atol=1e-14)
    assert old.events == ()


@pytest.mark.parametrize("delta", [1e-3, 1e-6])
def test_reserve_dips_of_other_depths(delta):
    """The same within 1e-8 s for a deeper (1e-3) and a shallower (1e-6) dip."""
    cs = _reserve_dip(delta)
    ex = simulate_events(cs, (0.0, 8.0), [0.0, 0.0], method="exact")
    nu = simulate_events(cs, (0.0, 8.0), [0.0, 0.0], method="dop853", rtol=1e-10,
                         atol=1e-14)
    assert _events(nu) == _events(ex) == [(0, "stick", "slip+"), (0, "slip+", "stick")]
    np.testing.assert_allclose(nu.event_times(), ex.event_times(), rtol=0, atol=1e-8)


def test_slip_velocity_dip_dop853_equals_exact(monkeypatch):
    """A slipping contact whose velocity dips 1e-8 m/s below zero between quarter samples:
    DOP853 (rtol 1e-10) stops it as the exact phases do, times within 2e-8 s (measured
    2026-11-29: 2e-9 s; the stop's root is shallow)."""
    cs = _slip_dip()
    y0 = [0.0, 0.621007290290521 - 1e-8]
    ex = simulate_events(cs, (0.0, 1.0), y0, method="exact")
    nu = simulate_events(cs, (0.0, 1.0), y0, method="dop853", rtol=1e-10, atol=1e-14)
    assert _events(ex)[:2] == [(0, "slip+", "stick"), (0, "stick", "slip+")]
    assert _events(nu) == _events(ex)
    np.testing.assert_allclose(nu.event_times(), ex.event_times(), rtol=0, atol=2e-8)
    _no_dip_search(monkeypatch)
    old = simulate_events(cs, (0.0, 1.0), y0, method="dop853", rtol=1e-10, atol=1e-14)
    assert _events(old) == [(0, "slip+", "slip-")]


def test_dip_windows_trigger():
    """Windows around small local minima of the samples only; none for a function that is
    far from its threshold, monotone, flat at round-off, or at zero at the phase start."""
    t = np.linspace(0.0, 1.0, 5)
    dip = 1.0 - np.cos(2.0 * (t - 0.6))  # minimum between samples 2 and 3
    tol = 1e-14
    assert event_phase.dip_windows(dip + 1e-6, tol) == [(1, 3)]
    assert event_phase.dip_windows(dip + 1.0, tol) == []  # far above: cannot dip below zero
    assert event_phase.dip_windows(1.0 + t, tol) == []
    assert event_phase.dip_windows(np.full(5, 1e-14), tol) == []
    noise = 1e-14 * np.array([1.0, 0.2, 1.1, 0.3, 0.9])  # curved by round-off only
    assert event_phase.dip_windows(noise, 2e-14) == []
    assert event_phase.dip_windows(noise, 1e-15) == [(0, 2), (2, 4)]
    rising = 1e-16 + t ** 2
    assert event_phase.dip_windows(rising, tol) == [(0, 1)]
    assert event_phase.dip_windows(rising, tol, sits=True) == []
    falling = (1.0 - t) ** 2 + 1e-9  # a local minimum at the step's end
    assert event_phase.dip_windows(falling, tol) == [(3, 4)]


def test_dip_search_finds_a_point_below_zero():
    """Brent's bounded minimisation: a point below zero of a dip 2.5e-9 deep and 1e-4 wide
    (of the window), none for a minimum 1e-9 above zero; at the window's edge, a dip 1e-10
    deep (the location tolerance is 1e-5 of the window: (1e-5)^2 = 1e-10)."""
    assert event_phase.dip_search(lambda t: (t - 0.3712) ** 2 - 2.5e-9, 0.0, 1.0) is not None
    assert event_phase.dip_search(lambda t: (t - 0.3712) ** 2 + 1e-9, 0.0, 1.0) is None
    tm = event_phase.dip_search(lambda t: (t - 1.0) ** 2 - 1e-10, 0.0, 1.0)
    assert tm is not None and (tm - 1.0) ** 2 <= 1e-10


def test_blade_damper_slip_onset_dip_caught_by_every_path(monkeypatch):
    """Blade damper (paper 000; 58 Hz, gamma = 50 deg) from the static equilibrium at rest:
    below F_e* = 3.7178965153871 N the damper sticks for 3 periods; 1e-5 above it, contact 1
    slips for 2 ms from t = 0.04757 s: its friction reserve dips 1e-5 of the limit below zero
    between quarter samples. The compiled event loop, the Python loop over the compiled
    phases (to round-off: times within 1e-9 s, as in test_blade_damper_fastloop) and SciPy's
    DOP853 (to the integration accuracy: 2e-7 of the period, as in test_blade_damper_fused)
    find the same switches; SciPy's DOP853 without the dip search steps over them. F_e*:
    bisection on the first slip with this search (2026-11-29)."""
    from fricdamp.models import BladeDamperParameters, BladeDamperSystem
    from fricdamp.models.blade_damper.studies import time_response

    f_hz = 58.0

    def run(amplitude, **kw):
        p = BladeDamperParameters(excitation_amplitude=amplitude, excitation_frequency=f_hz
                                  ).with_(gamma_deg=50.0)
        s = BladeDamperSystem(p, **kw)
        y0 = np.concatenate([s.static_equilibrium().q, np.zeros(7)])
        return time_response(s, 3.0, y0=y0).result

    amplitude = 3.7178965153871 * (1 + 1e-5)
    loop = run(amplitude)
    fused = run(amplitude, compiled_loop=False)
    scipy = run(amplitude, compiled_phases=False)
    assert _events(loop) == [(1, "stick", "slip-"), (1, "slip-", "stick")]
    assert abs(loop.events[0].time - 0.04757) < 1e-5
    assert _events(fused) == _events(scipy) == _events(loop)
    assert np.all(np.abs(loop.event_times() - fused.event_times()) <= 1e-9)
    assert np.all(np.abs(loop.event_times() - scipy.event_times()) <= 2e-7 / f_hz)
    assert run(3.7178965153871 * (1 - 1e-5)).events == ()
    _no_dip_search(monkeypatch)
    assert run(amplitude, compiled_phases=False).events == ()


def test_compiled_dip_kernels_equal_python():
    """The blade damper's compiled ``dip_windows`` and ``dip_search`` are the Python ones
    operation for operation: the same windows on random samples, the same point below the
    threshold (bit for bit) on the dense output of a stuck phase's steps."""
    from fricdamp.models import BladeDamperParameters, BladeDamperSystem
    from fricdamp.solvers.event_phase import NumericalPhase
    from fricdamp.solvers.event_switch import Evaluator

    s = BladeDamperSystem(BladeDamperParameters(excitation_amplitude=8.0,
                                                excitation_frequency=58.0))
    ev = Evaluator(s)
    ck = ev.compiled
    mod = ck.mod
    rng = np.random.default_rng(14)
    wa, wb = np.empty(5, dtype=np.int64), np.empty(5, dtype=np.int64)
    t5 = np.linspace(0.0, 1.0, 5)
    for _ in range(3000):
        v = (rng.uniform(-0.1, 1.0) + rng.uniform(-1.0, 1.0) * (t5 - rng.uniform(-0.5, 1.5)) ** 2
             + rng.choice([0.0, 1e-3]) * rng.standard_normal(5))
        tol = rng.choice([1e-14, 1e-3])
        for sits in (False, True):
            n = mod.dip_windows(v, tol, sits, wa, wb)
            assert [(int(a), int(b)) for a, b in zip(wa[:n], wb[:n], strict=True)] == \
                event_phase.dip_windows(v, tol, sits)
    q0 = s.static_equilibrium().q
    ph = NumericalPhase(ev, [0, 0], [1.0, 1.0], 0.0, q0, np.zeros(7), 1e-8, 1e-12, 1e-4)
    ph.advance(0.01)
    args = (ph._TA, ph._TB, ph._YOLD, ph._FF, ph._modes_c, ph.sigma, ph._kinds_c,
            ph._contacts_c, ph._lim_c, ph._sgn_c, ph.vel_scale)
    n_found = 0
    for j in range(0, ph._m, 3):
        ta, tb = float(ph._TA[j]), float(ph._TB[j])
        for i in range(ph.kinds.size):
            def g(t, i=i, j=j):
                return ck.refine_value(j, i, t, *args)
            ts = np.linspace(ta, tb, 9)
            gs = np.array([g(t) for t in ts])
            for shift in (-gs.min() - 1e-3 * np.ptp(gs), -gs.min() + 1e-1 * np.ptp(gs)):
                a = ck.dip_search(j, i, ta, tb, shift, *args)
                b = event_phase.dip_search(lambda t, g=g, shift=shift: g(t) + shift, ta, tb)
                assert (np.isnan(a) and b is None) or a == b
                n_found += b is not None
    assert n_found > 5
