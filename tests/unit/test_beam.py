"""Euler-Bernoulli cantilever against closed forms.

- Bending frequencies f_n = (beta_n L)^2 sqrt(EI / (rho A L^4)) / (2 pi), beta_n L the roots
  of 1 + cos cosh = 0 (Blevins, *Formulas for Natural Frequency and Mode Shape*, table 8-1).
  Hermite cubics with consistent mass converge as h^4 (upper bounds, Rayleigh-Ritz).
- Tip deflection under a tip load P L^3 / (3 EI): Hermite elements are nodally exact.
- Rigid translation of the free-free beam carries the total mass rho A L.
"""

import numpy as np
import pytest
import scipy.linalg as sla

from fricdamp.errors import ModelError
from fricdamp.structure.beam import (
    CANTILEVER_BETA_L,
    cantilever_beam,
    euler_bernoulli_matrices,
    node_dof,
)

L, E, RHO, B, H = 2.0, 185e9, 7830.0, 0.3, 0.1
A, I = B * H, B * H**3 / 12


def _freqs(n_el):
    beam = cantilever_beam(n_el, L, E, RHO, A, I)
    return np.sqrt(sla.eigh(beam.K, beam.M, eigvals_only=True)) / (2 * np.pi)


def _exact(n_modes):
    return np.array(CANTILEVER_BETA_L[:n_modes]) ** 2 * np.sqrt(E * I / (RHO * A * L**4)) / (
        2 * np.pi)


def test_first_frequencies_closed_form():
    """8 elements: modes 1-3 within 5e-6, 2e-4, 2e-3 (error ~ (beta_n h)^4), from above."""
    f = _freqs(8)[:3]
    ex = _exact(3)
    rel = f / ex - 1
    assert np.all(rel >= -1e-9)       # Rayleigh-Ritz: never below the exact value
    np.testing.assert_array_less(rel, [5e-6, 2e-4, 2e-3])


def test_convergence_order_h4():
    """Halving h divides the mode-3 error by 2^4 = 16 (between 12 and 20)."""
    e8 = _freqs(8)[2] / _exact(3)[2] - 1
    e16 = _freqs(16)[2] / _exact(3)[2] - 1
    assert 12 < e8 / e16 < 20


def test_tip_deflection_exact():
    beam = cantilever_beam(5, L, E, RHO, A, I)
    F = np.zeros(beam.n_dof)
    F[node_dof(5, "w")] = 1000.0
    q = np.linalg.solve(beam.K, F)
    assert q[node_dof(5, "w")] == pytest.approx(1000.0 * L**3 / (3 * E * I), rel=1e-12)
    assert q[node_dof(5, "theta")] == pytest.approx(1000.0 * L**2 / (2 * E * I), rel=1e-12)


def test_total_mass_and_symmetry():
    M, K = euler_bernoulli_matrices(6, L, E, RHO, A, I)
    t = np.zeros(M.shape[0])
    t[0::2] = 1.0                      # rigid translation
    assert t @ M @ t == pytest.approx(RHO * A * L, rel=1e-12)
    np.testing.assert_allclose(K @ t, 0.0, atol=1e-6 * np.abs(K).max())
    np.testing.assert_allclose(M, M.T)
    np.testing.assert_allclose(K, K.T)


def test_rayleigh_damping_and_names():
    beam = cantilever_beam(4, L, E, RHO, A, I, rayleigh=(0.5, 1e-4), name="b")
    np.testing.assert_allclose(beam.D, 0.5 * beam.M + 1e-4 * beam.K)
    assert beam.n_dof == 8 and beam.names[:2] == ("w1", "theta1")
    assert beam.names[node_dof(4, "theta")] == "theta4"
    np.testing.assert_allclose(beam.meta["x_nodes_m"], np.linspace(0, L, 5))


@pytest.mark.parametrize("kwargs, word", [
    ({"n_elements": 0}, "n_elements"),
    ({"E_Pa": -1.0}, "E_Pa"),
    ({"inertia_m4": 0.0}, "inertia_m4"),
    ({"rayleigh": (-1.0, 0.0)}, "rayleigh alpha"),
    ({"rayleigh": 3.0}, "rayleigh"),
])
def test_bad_input_named(kwargs, word):
    args = dict(n_elements=4, length_m=L, E_Pa=E, rho_kg_m3=RHO, area_m2=A, inertia_m4=I)
    args.update(kwargs)
    with pytest.raises(ModelError, match=word):
        cantilever_beam(**args)


def test_node_dof_checks():
    assert node_dof(1) == 0 and node_dof(3, "theta") == 5
    with pytest.raises(ModelError, match="node"):
        node_dof(0)
    with pytest.raises(ModelError, match="kind"):
        node_dof(1, "u")
