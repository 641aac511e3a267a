"""Cubic spring law (Duffing nonlinearity): protocol conformance and exact tangents."""

import numpy as np
import pytest

from fricdamp.contact import CubicSpring
from fricdamp.contact.base import ContactLaw
from fricdamp.errors import CaseError, ModelError
from fricdamp.solvers.aft import HarmonicBasis, aft
from fricdamp.structure import ContactElement


def test_is_a_state_free_contact_law():
    law = CubicSpring([2.0, -1.0])
    assert isinstance(law, ContactLaw)
    assert (law.n_contacts, law.n_dir, law.n_state) == (2, 1, 0)
    assert law.initial_state().shape == (2, 0)
    r = law.step(law.initial_state(), [[0.5], [2.0]])
    np.testing.assert_allclose(r.force[:, 0], [0.25, -8.0], rtol=1e-15)
    np.testing.assert_allclose(r.stiffness[:, 0, 0], [1.5, -12.0], rtol=1e-15)
    assert r.damping is None and r.state.shape == (2, 0)


@pytest.mark.parametrize("u0", [-3e-3, 0.0, 1e-4, 2.5])
def test_tangent_matches_finite_difference(u0):
    """Central differences, h = 1e-6 max(|u|, 1): error ~ k3 h^2, relative 1e-7."""
    law = CubicSpring(3.0e5)
    h = 1e-6 * max(abs(u0), 1.0)
    r = law.step(law.initial_state(), [u0])
    fd = (law.step(law.initial_state(), [u0 + h]).force
          - law.step(law.initial_state(), [u0 - h]).force) / (2 * h)
    np.testing.assert_allclose(r.stiffness[:, :, 0], fd, rtol=1e-7, atol=3.0e5 * h * h * 2)


def test_step_matches_march_and_drive():
    law = CubicSpring([1.0, 4.0])
    u = np.random.default_rng(0).normal(size=(50, 2, 1))
    f, st = law.march(u)
    assert st.shape == (2, 0)
    for i in range(u.shape[0]):
        np.testing.assert_array_equal(law.step(law.initial_state(), u[i]).force, f[i])
    np.testing.assert_array_equal(law.drive(u[:, :, 0]), f[:, :, 0])


def test_energy_is_the_potential_of_the_force():
    """f = dE/du (central differences) and no dissipation."""
    law = CubicSpring(7.0)
    u, h = 0.3, 1e-6
    st = law.initial_state()
    dE = (law.stored_energy(st, [u + h]) - law.stored_energy(st, [u - h])) / (2 * h)
    np.testing.assert_allclose(dE, law.step(st, [u]).force[:, 0], rtol=1e-9)
    np.testing.assert_array_equal(law.dissipation(st, st, [1.0]), [0.0])


def test_periodic_response_jacobian_exact():
    """The exact AFT sensitivity equals the base class's generic finite-difference one."""
    law = CubicSpring([2.0, 0.5])
    basis = HarmonicBasis.create(3, 32)
    x = np.array([[0.1, 1.0, -0.3, 0.2, 0.0, 0.05, 0.01],
                  [0.0, -0.5, 0.8, 0.0, 0.1, 0.0, 0.02]])
    u = (basis.synthesis @ x.T)[:, :, None]
    exact = law.periodic_response(u, basis=basis.synthesis)
    generic = ContactLaw.periodic_response(law, u, basis=basis.synthesis)
    np.testing.assert_allclose(exact.force, generic.force, rtol=1e-15)
    np.testing.assert_allclose(exact.jacobian, generic.jacobian, rtol=1e-5, atol=1e-7)
    assert exact.converged and exact.periods == 1


def test_aft_first_harmonic_of_cubic():
    """x = a cos: the first harmonic of k3 x^3 is 3/4 k3 a^3, the third 1/4 k3 a^3 (exact
    with N >= 4H)."""
    basis = HarmonicBasis.create(3, 16)
    el = ContactElement(CubicSpring(2.0), [[1.0]])
    a = 0.7
    res = aft([el], np.array([[0.0, a, 0.0, 0.0, 0.0, 0.0, 0.0]]), 1.0, basis)
    np.testing.assert_allclose(res.force[0, [1, 5]], [0.75 * 2 * a**3, 0.25 * 2 * a**3],
                               rtol=1e-13)
    np.testing.assert_allclose(res.force[0, [0, 2, 3, 4, 6]], 0.0, atol=1e-14)


@pytest.mark.parametrize("kwargs, word", [({"k3": np.nan}, "k3"), ({"k3": np.inf}, "k3"),
                                          ({"k3": [1.0, 2.0], "n_contacts": 3}, "k3"),
                                          ({"k3": 1.0, "n_contacts": 0}, "n_contacts")])
def test_bad_parameters_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        CubicSpring(**kwargs)


def test_case_file_contact(tmp_path):
    from fricdamp.runner import build_system, load_case

    text = """
[model]
type = "chain"
masses_kg = [1.0, 1.0]
springs_N_per_m = [1.0, 1.0]

[[contacts]]
type = "cubic_spring"
name = "duffing"
between = [2, 1]
k3_N_per_m3 = 0.5

[analysis.frf]
force_amplitude_N = [0.1, 0.0]
frequency_start_hz = 0.05
frequency_end_hz = 0.3
"""
    p = tmp_path / "c.toml"
    p.write_text(text)
    system = build_system(load_case(p))
    (c,) = system.contacts
    assert isinstance(c.law, CubicSpring) and c.law.k3.tolist() == [0.5]
    np.testing.assert_array_equal(c.projection.toarray() if hasattr(c.projection, "toarray")
                                  else c.projection, [[-1.0, 1.0]])
    p.write_text(text.replace("k3_N_per_m3 = 0.5", "k3_N_per_m = 0.5"))
    with pytest.raises(CaseError, match="k3_N_per_m"):
        load_case(p)
