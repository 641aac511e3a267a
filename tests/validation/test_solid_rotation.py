"""Rotation terms of solid FE models (fricdamp.structure.solid_rotation) against Southwell.

Reference: a uniform cantilever spinning about an axis through its root, perpendicular to
it, has ``omega^2 = omega_0^2 + S Omega^2`` to first order with Southwell's coefficient
``S = 1.1933`` for the first flap (out-of-plane) mode and ``S - 1 = 0.1933`` for the first
lead-lag (in-plane) mode, whose spin softening removes one ``Omega^2``
(tests/validation/test_beam3d_closed_forms.py computes 1.19334 as the exact Rayleigh quotient).
Beam theory is uniaxial stress without Poisson coupling, so the like-for-like solid has
``nu = 0``: hex20, 40 x 4 x 2 elements, gives S within 1e-3 relative (measured 1e-4 flap,
6e-4 lead-lag; the piecewise-linear element stress of the quadratic prestress converges as
the element length squared). With ``nu = 0.3`` the flap coefficient of this b/h = 5 strip is
0.4 % higher (a plate effect beam theory does not have), which the test records.

Also checked: the centrifugal load's resultant is ``m Omega^2 r_cg`` (closed form), the
geometric stiffness is symmetric, and a compressive prestress softens (K_sigma of -u is
-K_sigma).
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from fricdamp.structure.solid import assemble_solid, box_mesh
from fricdamp.structure.solid_rotation import (
    centrifugal_load,
    geometric_stiffness,
    spin_softening,
)

S_FLAP = 1.19334


def _blade(nu):
    mesh = box_mesh((0.2, 0.02, 0.004), (40, 4, 2), cell_type="hexahedron20")
    s = assemble_solid(mesh, youngs_modulus=2.1e11, poisson_ratio=nu, density=7850.0)
    clamp = np.flatnonzero(np.isclose(s.points[:, 0], 0.0))
    free = np.setdiff1d(np.arange(s.n_dof), s.dofs[clamp].ravel())
    return s, free


def _southwell(s, free):
    K = s.K[free][:, free].tocsc()
    M = s.M[free][:, free].tocsc()
    f = centrifugal_load(s, "z")
    u = np.zeros(s.n_dof)
    u[free] = spla.spsolve(K, f[free])
    Kg = geometric_stiffness(s, u)
    K1 = (Kg - spin_softening(s, "z"))[free][:, free]
    lam0, X = spla.eigsh(K, 3, M, sigma=0, which="LM")
    order = np.argsort(lam0)
    lam0, X = lam0[order], X[:, order]
    Om2 = (0.05 ** 2) * lam0[0]
    lam1 = np.sort(spla.eigsh(K + Om2 * K1, 3, M, sigma=0, which="LM")[0])
    return (lam1 - lam0) / Om2, X, Kg, free, u


def test_southwell_coefficients_of_a_solid_blade():
    s, free = _blade(0.0)
    S, X, Kg, free, u = _southwell(s, free)
    # identify the modes by their displacement direction: the lowest mode moving mostly in
    # z is the first flap mode, the lowest moving mostly in y the first lead-lag mode (a
    # ratio argmax would compare two flap modes by the round-off of their y motion)
    full = np.zeros((s.n_dof, X.shape[1]))
    full[free] = X
    w = np.array([np.abs(full[2::3, k]).max() for k in range(3)])
    v = np.array([np.abs(full[1::3, k]).max() for k in range(3)])
    flap = int(np.flatnonzero(w > 10 * v)[0])
    lag = int(np.flatnonzero(v > 10 * w)[0])
    assert flap == 0 and lag != flap
    assert S[flap] == pytest.approx(S_FLAP, rel=1e-3)
    assert S[lag] == pytest.approx(S_FLAP - 1.0, rel=1e-3 * S_FLAP / (S_FLAP - 1.0))
    # symmetry; a compressive prestress gives the opposite geometric stiffness
    assert abs(Kg - Kg.T).max() <= 1e-12 * abs(Kg).max()
    assert abs(geometric_stiffness(s, -u) + Kg).max() <= 1e-12 * abs(Kg).max()
    # resultant of the centrifugal load: m r_cg per Omega^2 (r_cg = (0.1, 0.01) m)
    f = centrifugal_load(s, "z")
    m = 7850.0 * 0.2 * 0.02 * 0.004
    np.testing.assert_allclose([f[0::3].sum(), f[1::3].sum(), f[2::3].sum()],
                               [m * 0.1, m * 0.01, 0.0], rtol=1e-12, atol=1e-15)


def test_poisson_plate_effect_is_small_and_recorded():
    s, free = _blade(0.3)
    S = _southwell(s, free)[0]
    assert 1.002 < S[0] / S_FLAP < 1.006
