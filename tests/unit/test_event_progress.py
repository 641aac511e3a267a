"""Progress bar of simulate_events (issue 18): shown when asked, silent by default off a
terminal, results bit for bit the same, and the bar touched at most once per interval."""

from __future__ import annotations

import functools
import time

import numpy as np

from fricdamp.solvers import event
from fricdamp.solvers.event import CoulombSystem, simulate_events
from fricdamp.structure import HarmonicLoad, MechanicalSystem


def _forced():
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]], loads=(HarmonicLoad([1.0], 0.8),))
    return CoulombSystem(s, directions=[1.0], normal_load=0.5, mu_static=1.0)


def test_bar_when_asked_and_same_result(capsys, monkeypatch):
    kw = dict(t_eval=np.linspace(0.0, 200.0, 401))
    quiet = simulate_events(_forced(), (0.0, 200.0), [0.0, 0.0], **kw)   # stderr no tty
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(event, "_EventProgress",
                        functools.partial(event._EventProgress, interval=0.0, delay=0.0))
    shown = simulate_events(_forced(), (0.0, 200.0), [0.0, 0.0], progress=True, **kw)
    err = capsys.readouterr().err
    assert "event-driven" in err and "events, t =" in err
    assert shown.n_events == quiet.n_events > 40
    np.testing.assert_array_equal(shown.q, quiet.q)
    np.testing.assert_array_equal(shown.t, quiet.t)


def test_bar_is_refreshed_at_most_every_interval(monkeypatch):
    """A 2 ms interval, so that even a fast run (~0.1-0.3 s wall for ~500 phases) updates
    the bar a few times while the bound wall/interval + 1 stays far below once per phase."""
    made, real, interval = [], event._EventProgress, 0.002

    def spy(*args, **kwargs):
        made.append(real(*args, **kwargs, interval=interval, delay=60.0))
        return made[-1]

    monkeypatch.setattr(event, "_EventProgress", spy)
    wall = time.perf_counter()
    res = simulate_events(_forced(), (0.0, 2000.0), [0.0, 0.0], progress=True,
                          t_eval=np.linspace(0.0, 2000.0, 2001))
    wall = time.perf_counter() - wall
    assert res.n_events > 400
    assert wall > 5 * interval, "the run is too short to test the refresh interval"
    assert 1 <= made[0].n_updates <= wall / interval + 1
