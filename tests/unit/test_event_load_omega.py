"""simulate_events needs the frequency of every harmonic load (HarmonicLoad.omega is optional
for harmonic balance): a load without it is a ModelError naming the load, raised before any
integration; with the frequency set the same system runs."""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.solvers.event import CoulombSystem, simulate_events
from fricdamp.structure import HarmonicLoad, MechanicalSystem


def _system(*loads):
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=loads)
    return CoulombSystem(s, directions=[1.0], normal_load=0.5, mu_static=1.0)


def test_harmonic_load_without_omega_is_named():
    cs = _system(HarmonicLoad([1.0], 0.8), HarmonicLoad([0.3]))
    with pytest.raises(ModelError, match=r"system\.loads\[1\].*has no omega.*rad/s"):
        simulate_events(cs, (0.0, 1.0), [0.0, 0.0])


def test_same_load_with_omega_runs():
    cs = _system(HarmonicLoad([1.0], 0.8), HarmonicLoad([0.3]).with_omega(0.8))
    res = simulate_events(cs, (0.0, 2.0), [0.0, 0.0], t_eval=np.linspace(0.0, 2.0, 11))
    assert res.success and res.t[-1] == pytest.approx(2.0)
