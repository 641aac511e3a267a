"""Protocol checks of the contact laws: step agrees with march, tangent with finite differences."""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.errors import ModelError


def test_step_matches_compiled_march():
    law = Jenkins([1e3, 4e3], [1.0, 2.0])
    rng = np.random.default_rng(0)
    u = np.cumsum(rng.normal(scale=4e-4, size=(300, 2, 1)), axis=0)
    f_march, w_march = law.march(u)
    st = law.initial_state()
    for i in range(u.shape[0]):
        r = law.step(st, u[i])
        st = r.state
        np.testing.assert_allclose(r.force, f_march[i], atol=1e-13)
    np.testing.assert_allclose(st, w_march, atol=1e-15)


@pytest.mark.parametrize("u0", [2e-4, 3e-3, -3e-3])
def test_tangent_matches_finite_difference(u0):
    law = Jenkins(1e3, 1.0)
    st = law.step(law.initial_state(), [0.5e-3]).state  # some history
    h = 1e-9
    r = law.step(st, [u0])
    fd = (law.step(st, [u0 + h]).force - law.step(st, [u0 - h]).force) / (2 * h)
    np.testing.assert_allclose(r.stiffness[:, :, 0], fd, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize(
    "kwargs, word",
    [({"stiffness": -1.0, "slip_force": 1.0}, "stiffness"),
     ({"stiffness": 1.0, "slip_force": -1.0}, "slip_force"),
     ({"stiffness": np.nan, "slip_force": 1.0}, "stiffness"),
     ({"stiffness": [1.0, 2.0], "slip_force": [1.0, 2.0, 3.0]}, "inconsistent")],
)
def test_bad_parameters_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        Jenkins(**kwargs)


def test_drive_shape_error_names_parameter():
    with pytest.raises(ModelError, match="u_history"):
        Jenkins([1.0, 1.0], [1.0, 1.0]).drive(np.zeros((5, 3)))
