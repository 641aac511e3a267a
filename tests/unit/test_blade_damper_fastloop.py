"""The compiled event loop of the blade damper against the Python event loop.

``BladeDamperSystem(params)`` (default) runs the phases *and* the switches in one compiled
kernel (:mod:`fricdamp.models.blade_damper._fastloop`); ``compiled_loop=False`` takes the
same compiled phases through the Python loop of :func:`fricdamp.solvers.event.
simulate_events` (the reference). The kernel calls the same compiled phase kernels
(``phase_run``, ``refine_root``, ``project``) with the same inputs and re-codes the
switching decision (``decide_modes``) with the same operations, so the two paths agree to
round-off: the stated tolerances are switching times within 1e-9 s, the final state within
1e-8 of each coordinate's range of motion, samples within 1e-8 of the range, contact forces
within 1e-8 of their largest magnitude and energies within 1e-8 of the input work. They
leave room for the last bits of the decision's small products (loops here, BLAS there);
measured (2026-11-29): identical times, states and work, kinetic energy to 2e-16 (the
kinetic energy of a block of samples is summed at once).
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper._fastloop import FastLoop
from fricdamp.models.blade_damper.studies import time_response
from fricdamp.solvers.event import simulate_events


def _systems(f_hz, gamma_deg):
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=f_hz
                              ).with_(gamma_deg=gamma_deg)
    return BladeDamperSystem(p), BladeDamperSystem(p, compiled_loop=False)


def _start(sys, f_hz):
    """A state on the stick-slip motion: 4 periods from the static equilibrium at rest."""
    y0 = np.concatenate([sys.static_equilibrium().q, np.zeros(7)])
    r = time_response(sys, 4.0, y0=y0).result
    return np.concatenate([r.q[-1], r.qd[-1]]), 4.0 / f_hz


def _assert_same(a, b):
    assert a.success and b.success
    assert a.n_events == b.n_events
    assert [(e.contact, e.kind, e.from_mode, e.to_mode) for e in a.events] == [
        (e.contact, e.kind, e.from_mode, e.to_mode) for e in b.events]
    ta, tb = np.array([e.time for e in a.events]), np.array([e.time for e in b.events])
    assert np.all(np.abs(ta - tb) <= 1e-9)
    rq = np.ptp(b.q, axis=0) + 1e-300
    assert np.all(np.abs(a.q[-1] - b.q[-1]) <= 1e-8 * rq)
    assert np.all(np.abs(a.qd[-1] - b.qd[-1]) <= 1e-8 * (np.ptp(b.qd, axis=0) + 1e-300))
    assert a.t.shape == b.t.shape
    assert np.all(np.abs(a.t - b.t) <= 1e-9)
    assert np.all(np.abs(a.q - b.q) <= 1e-8 * rq)
    assert np.array_equal(a.modes, b.modes)
    for lam in ("lambda_N", "lambda_T"):
        x, y = getattr(a, lam), getattr(b, lam)
        assert np.all(np.abs(x - y) <= 1e-8 * np.max(np.abs(y)))
    w = np.max(np.abs(b.energy["input_work"]))
    for k, v in b.energy.items():
        assert np.all(np.abs(a.energy[k] - v) <= 1e-8 * w), k
    assert (a.n_phases, a.n_decisions, a.n_configurations) == (
        b.n_phases, b.n_decisions, b.n_configurations)
    assert a.n_rhs == b.n_rhs
    assert a.projection_energy == pytest.approx(b.projection_energy, rel=1e-6, abs=1e-20)


class _Records(logging.Handler):
    def __init__(self):
        super().__init__(logging.WARNING)
        self.messages = []

    def emit(self, record):
        self.messages.append(record.getMessage())


def _warnings(monkeypatch, fn):
    """``fn()`` and the ambiguity warnings of the switching decision it logged (a handler on
    the module's logger itself: other tests may configure the logging tree)."""
    logger = logging.getLogger("fricdamp.solvers.event_switch")
    monkeypatch.setattr(logger, "disabled", False)
    monkeypatch.setattr(logger, "level", logging.WARNING)
    logger.manager._clear_cache()
    rec = _Records()
    logger.addHandler(rec)
    try:
        out = fn()
    finally:
        logger.removeHandler(rec)
    return out, [m for m in rec.messages if "consistent configurations" in m]


@pytest.mark.parametrize("f_hz, gamma_deg", [(58.0, 50.0), (51.0, 65.0)])
def test_compiled_loop_equals_python_loop(f_hz, gamma_deg, monkeypatch):
    """Away from resonance (58 Hz, 50 deg) and at the resonance (51 Hz, 65 deg). Near
    t = 0.2228 s the resonance run has a switch of both contacts whose configurations with
    one stuck contact may both be consistent (mu_static > mu_sliding): whether round-off
    makes it ambiguous depends on the last bits of the state, so the test asks only that
    both paths log the same warnings and record the same ambiguities, and that the kernel
    left each ambiguous switch to the Python loop (reason 16)."""
    fast, ref = _systems(f_hz, gamma_deg)
    y0, t0 = _start(ref, f_hz)
    a, warned_fast = _warnings(monkeypatch, lambda: time_response(fast, 10.0, y0=y0,
                                                                   t_start=t0).result)
    b, warned_ref = _warnings(monkeypatch, lambda: time_response(ref, 10.0, y0=y0,
                                                                  t_start=t0).result)
    _assert_same(a, b)
    assert a.n_events >= 10 * 4
    assert len(warned_fast) == len(warned_ref)
    assert a.meta["ambiguous_switches"] == b.meta["ambiguous_switches"]
    if warned_ref:
        # an ambiguous switch was met: the kernel left it to the Python loop
        assert fast.compiled_kernels()._fastloop.stops.get(16, 0) >= len(warned_ref)
    # nearly all phases ran in the kernel
    assert fast.compiled_kernels()._fastloop is not None


def test_hand_over_in_the_middle(monkeypatch):
    """Forced hand-overs: the kernel is told to stop every 3 events (its ``max_events``),
    the Python loop takes the next phase and switch and hands back; the result is the
    Python loop's (same tolerances)."""
    fast, ref = _systems(51.0, 65.0)
    y0, t0 = _start(ref, 51.0)
    orig = FastLoop.advance
    calls = []

    def advance(self, run, max_events):
        calls.append(run.n_events)
        return orig(self, run, min(max_events, run.n_events + 3))

    monkeypatch.setattr(FastLoop, "advance", advance)
    a = time_response(fast, 4.0, y0=y0, t_start=t0).result
    monkeypatch.setattr(FastLoop, "advance", orig)
    b = time_response(ref, 4.0, y0=y0, t_start=t0).result
    _assert_same(a, b)
    assert len(calls) > a.n_events // 4  # the kernel was entered again after each stop
    assert fast.compiled_kernels()._fastloop.stops.get(14, 0) >= a.n_events // 4


def test_max_events_and_switch_off():
    """``max_events`` stops where the Python loop stops (status 1); ``compiled_loop=False``
    and a trace keep the Python loop."""
    fast, ref = _systems(51.0, 65.0)
    y0, t0 = _start(ref, 51.0)
    om = 2 * np.pi * 51.0
    span = (t0, t0 + 2 * 2 * np.pi / om)
    a = simulate_events(fast, span, y0, max_events=7, throw=False, rtol=1e-8, atol=1e-12)
    b = simulate_events(ref, span, y0, max_events=7, throw=False, rtol=1e-8, atol=1e-12)
    assert a.status == b.status == 1 and a.n_events == b.n_events == 7
    assert a.t[-1] == b.t[-1] and np.array_equal(a.q, b.q)
    assert ref.compiled_kernels().compiled_loop is False
    assert BladeDamperSystem(fast.params, compiled_phases=False).compiled_kernels(
    ).compiled_loop is False


@pytest.mark.parametrize("mu_static, mu_sliding, both", [(0.35, 0.30, False),
                                                          (0.6, 0.2, True)])
def test_decision_kernel_equals_decide_modes(mu_static, mu_sliding, both):
    """The kernel's switching decision (``_decide``) against :meth:`Evaluator.decide_at`
    (``decide_modes``) on random states, modes, candidates and must-slip contacts: where the
    kernel decides (code 0) the modes are the same; it leaves to Python exactly the
    decisions that are ambiguous there (code 16: Python warns and records them) and those
    whose cascade is inconsistent (code 17: Python enumerates or raises). With
    mu_static = 3 mu_sliding and both contacts candidates, ties of ``_select`` occur."""
    from fricdamp.errors import ConvergenceError
    from fricdamp.solvers.event_switch import Evaluator

    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=51.0).with_(
        gamma_deg=65.0, mu_static=mu_static, mu_sliding=mu_sliding)
    s = BladeDamperSystem(p, compiled_loop=False)
    ck = s.compiled_kernels()
    ev = Evaluator(s)
    rng = np.random.default_rng(7)
    q0 = s.static_equilibrium().q
    codes = {}
    logger = logging.getLogger("fricdamp.solvers.event_switch")
    old = logger.disabled
    logger.disabled = True  # the ties' warnings are expected here
    try:
        for trial in range(600):
            spread = 2e-4 if trial % 2 else 1e-5 * (np.abs(q0) + 1e-4)
            q = q0 + spread * rng.standard_normal(7)
            qd = 0.05 * rng.standard_normal(7)
            q, qd, _ = ev.project(0.0, q, qd, np.array([0, 0]))
            t = rng.uniform(0, 0.02)
            modes = rng.choice([-1, 0, 1], 2)
            cand = np.ones(2, bool) if both else rng.random(2) < 0.7
            must = np.where(~cand & (modes == 0), rng.choice([-1, 1], 2), 0)
            n_amb = len(ev.ambiguities)
            try:
                ref = ev.decide_at(t, q, qd, modes, cand, must, np.ones(2))
            except ConvergenceError:
                ref = None
            new = np.empty(2, np.int64)
            code = ck.mod._decide(t, q, qd, modes.astype(np.int64), cand,
                                  must.astype(np.int64), np.ones(2), ck.par, new)
            codes[code] = codes.get(code, 0) + 1
            amb = len(ev.ambiguities) > n_amb
            assert (code == 16) == amb
            if code == 0:
                assert ref is not None and np.array_equal(new, ref)
            else:
                assert code in (16, 17)
    finally:
        logger.disabled = old
    assert codes.get(0, 0) > 400
    if both:
        assert codes.get(16, 0) > 0


def test_flow_without_phase_records_takes_the_compiled_loop():
    """``flow(..., monodromy=False, keep_phases=False)`` (the return maps and transients of
    shooting) runs through the compiled loop and ends where the traced flow (Python loop,
    phase records kept) ends: 3 periods at the resonance, final state within 1e-8 of the
    range as above; the traced run takes no phase through the kernel."""
    from fricdamp.solvers.shooting import flow

    fast, _ = _systems(51.0, 65.0)
    y0, t0 = _start(fast, 51.0)
    T = 1.0 / 51.0
    calls = []
    loop = fast.compiled_kernels().event_loop

    def counting(run, max_events):
        calls.append(run.trace is None)
        return loop(run, max_events)

    fast.compiled_kernels().event_loop = counting
    try:
        a = flow(fast, (t0, t0 + 3 * T), y0, monodromy=False, keep_phases=False, rtol=1e-9)
        n_fast = len(calls)
        b = flow(fast, (t0, t0 + 3 * T), y0, t_eval=np.linspace(t0, t0 + 3 * T, 301),
                 monodromy=False, rtol=1e-9)
    finally:
        fast.compiled_kernels().event_loop = loop
    assert n_fast >= 1 and all(calls[:n_fast]) and len(calls) == n_fast
    assert a.trace == [] and len(b.trace) > 3
    rng = np.concatenate([np.ptp(b.result.q, axis=0), np.ptp(b.result.qd, axis=0)])
    assert np.all(np.abs(a.y_end - b.y_end) <= 1e-8 * rng + 1e-300)


@pytest.mark.parametrize("restitution", [0.0, 0.5])
def test_released_damper_compiled_loop_equals_python_loop(restitution, monkeypatch):
    """The released damper beyond lift-off (gamma = 80 deg, 52 Hz, 8 N; lift-off 6.9 periods
    from the static state, then bursts of impacts between the platforms): the kernel takes
    the lift-offs and impacts too (Newton's impact law by Lemke, the Zeno velocity of the
    gap tolerance, the gap's zero by Brent on the step), and once more with a hand-over to
    the Python loop every 3 events. Same events, impacts and modes; event times within
    1e-8 s and samples, energies (impact loss included) within 1e-6 of their scales: the
    impulse and the gap closure differ from the Python loop's in the last bits (loops here,
    BLAS and ``lstsq`` there), which ~100 impacts in bursts amplify (measured over 30
    periods with e = 0: times 1.6e-10 s, states 6e-8 of the range). The work integrals are
    not error-controlled: a slipping contact's friction power falls to zero within a step
    at a lift-off, and round-off that changes one step size changes the friction work by
    its integration error, ~1e-5 of the input work at the default step and ~1e-6 at the
    2e-4 s used here (tests/validation/test_blade_damper_release.py): the friction work is
    held to 1e-5 (measured 1e-6 with e = 0.5, 1e-9 with e = 0)."""
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=52.0
                              ).with_(gamma_deg=80.0)
    fast = BladeDamperSystem(p, release=True, restitution=restitution)
    ref = BladeDamperSystem(p, release=True, restitution=restitution, compiled_loop=False)
    y0 = np.concatenate([ref.static_equilibrium().q, np.zeros(7)])
    T = 1.0 / 52.0
    kw = dict(t_eval=np.linspace(0.0, 10 * T, 1001), rtol=1e-9, atol=1e-12, max_step=2e-4,
              max_events=100_000, progress=False)
    b = simulate_events(ref, (0.0, 10 * T), y0, **kw)
    orig = FastLoop.advance
    runs = [simulate_events(fast, (0.0, 10 * T), y0, **kw)]
    assert fast.compiled_kernels()._fastloop.stops == {}  # no hand-over needed

    def advance(self, run, max_events):
        return orig(self, run, min(max_events, run.n_events + 3))

    monkeypatch.setattr(FastLoop, "advance", advance)
    runs.append(simulate_events(fast, (0.0, 10 * T), y0, **kw))
    assert len(b.impacts) >= 10 and b.lift_off_times().size >= 10
    for a in runs:
        assert a.success and a.n_events == b.n_events
        assert [(e.contact, e.kind, e.from_mode, e.to_mode) for e in a.events] == [
            (e.contact, e.kind, e.from_mode, e.to_mode) for e in b.events]
        ta, tb = np.array([e.time for e in a.events]), np.array([e.time for e in b.events])
        assert np.all(np.abs(ta - tb) <= 1e-8)
        assert [(i.contacts, i.plastic) for i in a.impacts] == [
            (i.contacts, i.plastic) for i in b.impacts]
        assert np.all(np.abs(a.t - b.t) <= 1e-8) and np.array_equal(a.modes, b.modes)
        assert np.all(np.abs(a.q - b.q) <= 1e-6 * (np.ptp(b.q, axis=0) + 1e-300))
        w = np.max(np.abs(b.energy["input_work"]))
        for k, v in b.energy.items():
            tol = 1e-5 if k == "friction_dissipation" else 1e-6
            assert np.all(np.abs(a.energy[k] - v) <= tol * w), k
        assert a.energy["impact_loss"][-1] > 0
