"""Mistuned wheels (structure/mistuning.py) on the reduced beam sector of paper 003.

References: (1) without scatter, the assembled wheel's modes are the cyclic ones
(``wheel_modes``) to the eigen-solver's tolerance; (2) first-order perturbation theory
(module docstring): a stiffness scatter ``d_j = eps cos(2 k j alpha)`` splits the ND-k doublet
by ``Delta lambda = 2 |x^T K x| |D_2k|``, ``D_2k = eps / 2``, computed here from the tuned
sector shape x; second-order terms are O(eps^2): with eps = 1e-3 the relative tolerance 2 %
is generous; other NDs stay doublets to O(eps^2).
"""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import build_sector
from fricdamp.structure.cyclic_reduction import reduce_sector, wheel_modes
from fricdamp.structure.mistuning import mistuned_modes, mistuned_wheel


@pytest.fixture(scope="module")
def reduced():
    sec = build_sector(rotation=False)
    red = reduce_sector(sec.cyclic, n_modes=6, n_interface_modes=6).sector
    return sec, red


def test_tuned_wheel_has_the_cyclic_modes(reduced):
    sec, red = reduced
    probe = red.named_dofs["probe"]
    mm = mistuned_modes(red, 12, probe_dofs=probe, probe_direction=sec.flexural_direction)
    wm = wheel_modes(red)
    ref = np.sort(wm.frequencies)[:12]
    np.testing.assert_allclose(mm.frequency_hz, ref, rtol=1e-9)
    # the two lowest are ND 0 and 1 (blade family rising with ND); tuned doublets: equal
    assert mm.doublet_split_hz(2) < 1e-9 * ref[0]


def test_harmonic_scatter_splits_only_its_doublet(reduced):
    sec, red = reduced
    N, k, eps = 30, 2, 1e-3
    alpha = 2 * np.pi / N
    d = eps * np.cos(2 * k * alpha * np.arange(N))
    probe = red.named_dofs["probe"]
    mm = mistuned_modes(red, 14, probe_dofs=probe, probe_direction=sec.flexural_direction,
                        stiffness_factors=1.0 + d)
    wm = wheel_modes(red, nds=[k], n_modes_per_nd=1)
    x = wm.sector_shapes[0][:, 0]
    lam = wm.omega[0] ** 2
    kappa = x @ (red.K @ x)           # x^T K x (no conjugate)
    dlam = 2 * abs(kappa) * eps / 2   # |D_2k| = eps / 2
    f = np.sqrt(lam) / (2 * np.pi)
    expected = f * dlam / (2 * lam)   # d f = f d lambda / (2 lambda)
    assert mm.doublet_split_hz(k) == pytest.approx(expected, rel=0.02)
    # ND 3 (not hit by harmonic 4 of the scatter): split O(eps^2) only
    assert mm.doublet_split_hz(3) < 0.05 * expected


def test_tip_mass_scatter_and_bad_input(reduced):
    sec, red = reduced
    tip = red.named_dofs["probe"]
    K, M = mistuned_wheel(red, added_mass=np.r_[1e-3, np.zeros(29)], mass_dofs=tip)
    K0, M0 = mistuned_wheel(red)
    assert abs((M - M0).sum() - 3e-3) < 1e-12
    with pytest.raises(ModelError, match="stiffness_factors"):
        mistuned_wheel(red, stiffness_factors=np.zeros(30))
    with pytest.raises(ModelError, match="mass_dofs"):
        mistuned_wheel(red, added_mass=np.ones(30))
