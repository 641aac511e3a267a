"""The one Newmark/HHT scheme (fricdamp.solvers.newmark) shared by the transient solvers.

Reference: for Newmark's average acceleration the discrete frequency of an undamped mode
obeys ``tan(omega_h h / 2) = omega h / 2`` (the amplification matrix has unit-modulus
eigenvalues ``exp(+-i omega_h h)``; e.g. Hughes, *The Finite Element Method*, 9.3), so the
period grows by ``x / arctan(x) - 1``, ``x = omega h / 2``. Measured on ``simulate``'s
history of a 1 Hz oscillator the zero-crossing period agrees with it to the resolution of
the crossing interpolation (linear between samples: an error of order ``(omega h)^2`` of
the step, i.e. < 1e-3 of the period at 10 steps per period over 20 periods).
"""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.solvers.newmark import NewmarkScheme
from fricdamp.solvers.timestep import simulate
from fricdamp.structure import chain


def _period(t, x):
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))          # upward zero crossings
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return (tc[-1] - tc[0]) / (tc.size - 1)


@pytest.mark.parametrize("steps_per_period", [10.0, 25.0, 2.5])
def test_period_error_is_the_closed_form_of_the_scheme(steps_per_period):
    h = 1.0 / steps_per_period
    res = simulate(chain([1.0], [4 * np.pi ** 2]), 40.0, h, q0=[1.0], progress=False)
    measured = _period(res.t, res.q[:, 0]) - 1.0
    predicted = NewmarkScheme(h).period_error(2 * np.pi)
    # linear interpolation of the crossings: error ~ (omega h)^2 / 8 of a step per crossing,
    # divided by the ~40 periods between the first and last crossings
    tol = (2 * np.pi * h) ** 2 / 8 * h / 30 + 1e-9
    assert abs(measured - predicted) < max(tol, 2e-4 * predicted)
    if steps_per_period == 2.5:
        assert predicted > 0.39         # 40 % too long: what a verdict must flag
    if steps_per_period == 25.0:
        assert predicted == pytest.approx((2 * np.pi * h) ** 2 / 12, rel=0.03)


def test_coefficients_and_velocity_forms_agree():
    s = NewmarkScheme(2e-3, -0.1)
    assert s.beta == pytest.approx(0.3025) and s.gamma == pytest.approx(0.6)
    rng = np.random.default_rng(0)
    dq, v0, a0 = rng.normal(size=(3, 5))
    a1 = s.acceleration(dq, v0, a0)
    # the two velocity updates are the same relation
    np.testing.assert_allclose(s.velocity(v0, a0, a1), s.velocity_of(dq, v0, a0), rtol=1e-12)
    # the displacement update of the scheme: q1 = q0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1)
    np.testing.assert_allclose(dq, s.h * v0 + s.h ** 2 * ((0.5 - s.beta) * a0 + s.beta * a1),
                               rtol=1e-12)
    assert s.coefficients(1.5)[[0, 1, 2, 9]].tolist() == [2e-3, -0.1, 0.6, 1.5]
    assert NewmarkScheme(1e-3).method == "newmark" and s.method == "hht(alpha=-0.1)"
    with pytest.raises(ModelError, match="dt must be"):
        NewmarkScheme(0.0)
    with pytest.raises(ModelError, match="alpha must lie"):
        NewmarkScheme(1e-3, 0.2)
