"""Progress bar of the HB continuation: shown when asked, off by default outside a terminal
(tests, CI, pipes), and the curve is the same with and without it."""

import numpy as np

from fricdamp.contact import CubicSpring
from fricdamp.solvers.hb import frequency_response, load_response
from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem

DUFFING = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
                           contacts=(ContactElement(CubicSpring(0.5), [[1.0]]),),
                           loads=(HarmonicLoad([0.03], omega=1.0),))


def test_progress_bar_when_asked_only(capsys):
    quiet = frequency_response(DUFFING, 0.8, 1.6, harmonics=3)
    assert capsys.readouterr().err == ""           # stderr is not a terminal here
    shown = frequency_response(DUFFING, 0.8, 1.6, harmonics=3, progress=True)
    err = capsys.readouterr().err
    assert "HB continuation" in err and f"{shown.n_points} points" in err
    assert "100%" in err                           # the end of the interval was reached
    assert np.array_equal(quiet.coefficients, shown.coefficients)
    load_response(DUFFING, 1.2, 0.1, 1.0, harmonics=3, progress=True)
    assert "load scale" in capsys.readouterr().err
    frequency_response(DUFFING, 0.8, 1.6, harmonics=3, progress=False)
    assert capsys.readouterr().err == ""
