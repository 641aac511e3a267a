"""Resultant force, moment and centre of pressure of a contact patch (ContactPatch.resultants).

References (rigid-body statics of a plane face with pair forces ``f_p`` at ``x_p``, areas
``A_p``, centroid ``c``, mean frame ``(n, t1, t2)``, in-plane coordinates ``s = (s1, s2)``):

* uniform pressure ``f_n = p A``: ``N = p sum A``, zero moment, centre of pressure at ``c``;
* linear pressure ``f_n = (p0 + g s1) A``: ``M . t2 = -g I_1`` with ``I_1 = sum A s1^2``
  (``r x n = -s1 t2 + s2 t1``), ``M . t1 = g sum A s1 s2`` (0 on a symmetric grid), centre of
  pressure ``s1 = g I_1 / (p0 sum A)``;
* rigid twist ``f_t = k A (n x r)``: no net force, ``M . n = k J`` with ``J = sum A |r|^2``.

All sums are exact: tolerances are round-off (1e-12 relative). Resultants in the patch's own
frame do not change when the whole patch is rotated (checked for random rotations).
"""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.structure.contact_patch import ContactPatch, rotation_about


def _plane_patch(rot=None, shift=(0.3, -0.1, 0.2), n1=7, n2=5, a=0.012, b=0.008):
    """Grid of n1 x n2 nodes on an a x b rectangle, tributary areas (trapezoid weights),
    frames (n, t1, t2) = rows of ``rot`` (default the identity) at every pair."""
    rot = np.eye(3) if rot is None else rot
    s1 = np.linspace(-a / 2, a / 2, n1)
    s2 = np.linspace(-b / 2, b / 2, n2)
    w1 = np.full(n1, a / (n1 - 1))
    w1[[0, -1]] /= 2
    w2 = np.full(n2, b / (n2 - 1))
    w2[[0, -1]] /= 2
    S1, S2 = (x.ravel() for x in np.meshgrid(s1, s2, indexing="ij"))
    A = np.outer(w1, w2).ravel()
    n, t1, t2 = rot
    pos = np.asarray(shift) + S1[:, None] * t1 + S2[:, None] * t2
    frames = np.repeat(rot[None], S1.size, axis=0)
    idx = np.arange(S1.size)
    patch = ContactPatch(right=idx, left=idx, positions=pos, frames=frames, areas=A,
                         element_size=a / (n1 - 1), sector_angle=2 * np.pi / 30)
    return patch, S1, S2, A


def _random_rotation(seed):
    rng = np.random.default_rng(seed)
    return rotation_about(rng.normal(size=3), rng.uniform(0, 2 * np.pi))


def test_uniform_pressure_has_no_moment_and_acts_at_the_centroid():
    patch, s1, s2, A = _plane_patch()
    f = np.zeros((s1.size, 3))
    f[:, 0] = 2e5 * A
    r = patch.resultants(f)
    assert r.normal_force == pytest.approx(2e5 * A.sum(), rel=1e-12)
    np.testing.assert_allclose(r.tangential_force, 0, atol=1e-12 * r.normal_force)
    np.testing.assert_allclose(r.moment, 0, atol=1e-12 * r.normal_force * 0.012)
    np.testing.assert_allclose(r.center_of_pressure, 0, atol=1e-14)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_pressure_tilts_and_twist_turns_in_any_orientation(seed):
    patch, s1, s2, A = _plane_patch(rot=_random_rotation(seed))
    p0, g, k = 1e5, 4e6, 3e7
    I1, J = np.sum(A * s1 ** 2), np.sum(A * (s1 ** 2 + s2 ** 2))
    f = np.zeros((2, s1.size, 3))
    f[0, :, 0] = (p0 + g * s1) * A
    # rigid twist: n x r = s1 t2 - s2 t1 in the local (t1, t2) components
    f[1, :, 1] = -k * A * s2
    f[1, :, 2] = k * A * s1
    r = patch.resultants(f)
    scale = p0 * A.sum() * 0.012
    assert r.moment[0, 2] == pytest.approx(-g * I1, rel=1e-12)
    assert abs(r.moment[0, 1]) < 1e-12 * scale and abs(r.moment[0, 0]) < 1e-12 * scale
    assert r.center_of_pressure[0, 0] == pytest.approx(g * I1 / (p0 * A.sum()), rel=1e-12)
    assert abs(r.center_of_pressure[0, 1]) < 1e-15
    assert r.moment[1, 0] == pytest.approx(k * J, rel=1e-12)
    np.testing.assert_allclose(r.tangential_force[1], 0, atol=1e-12 * k * J / 0.012)
    assert abs(r.normal_force[1]) < 1e-12 * k * J / 0.012
    assert np.all(np.isnan(r.center_of_pressure[1]))
    # the same forces on the patch in another orientation: the same resultants
    other, *_ = _plane_patch(rot=_random_rotation(seed + 10), shift=(-1.0, 2.0, 0.5))
    r2 = other.resultants(f)
    np.testing.assert_allclose(r2.moment, r.moment, rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(r2.normal_force, r.normal_force, rtol=1e-12, atol=1e-12)


def test_wrong_force_shape_is_a_one_line_error():
    patch, *_ = _plane_patch()
    with pytest.raises(ModelError, match=r"forces must have shape \(\.\.\., 35, 3\)"):
        patch.resultants(np.zeros((34, 3)))
