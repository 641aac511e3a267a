"""Contact patches between neighbouring sectors (structure/contact_patch.py)."""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.structure.contact_patch import patch_from_faces, rotation_about

ALPHA = 2 * np.pi / 30


def _faces(rng, n=25):
    """A square face on the cutting plane of 003 Fig. 2 (normal cos45 e_t(h) - sin45 e_z)."""
    h = ALPHA / 2
    er = np.array([np.cos(h), np.sin(h), 0.0])
    et = np.array([-np.sin(h), np.cos(h), 0.0])
    nrm = np.cos(np.pi / 4) * et - np.sin(np.pi / 4) * np.array([0, 0, 1.0])
    t2 = np.cross(nrm, er)
    s = np.linspace(-5e-3, 5e-3, int(np.sqrt(n)))
    a, b = np.meshgrid(s, s)
    right = 0.44 * er + a.reshape(-1, 1) * er + b.reshape(-1, 1) * t2
    left = (rotation_about("z", -ALPHA) @ right.T).T
    perm = rng.permutation(right.shape[0])
    return right, left[perm], nrm, perm


def test_pairs_frames_and_areas():
    rng = np.random.default_rng(0)
    right, left, nrm, perm = _faces(rng)
    areas = np.full(right.shape[0], 1e-4 / right.shape[0])
    p = patch_from_faces(right, left, right_areas=areas, right_normals=np.tile(nrm, (25, 1)),
                         sector_angle=ALPHA, element_size=2.5e-3)
    # partner p.left[i] of right node i is the left node that was right node i
    np.testing.assert_array_equal(perm[p.left], np.arange(25))
    F = p.frames
    np.testing.assert_allclose(np.einsum("pab,pcb->pac", F, F), np.tile(np.eye(3), (25, 1, 1)),
                               atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(F), 1.0)
    assert np.allclose(F[:, 0], nrm)
    assert p.area == pytest.approx(1e-4)
    # penalty k = factor E A / h
    np.testing.assert_allclose(p.normal_stiffness(2e11, 10.0), 10 * 2e11 * areas / 2.5e-3)
    law = p.law(youngs_modulus=2e11, penalty_factor=1.0, offset=1e-6, mu_static=0.4,
                mu_sliding=0.2, decay=4.0, n_sectors=30)
    assert law.n_contacts == 750


def test_wheel_rows_vanish_for_a_rigid_translation_and_close_along_the_normal():
    rng = np.random.default_rng(1)
    right, left, nrm, _ = _faces(rng)
    p = patch_from_faces(right, left, right_areas=np.ones(25), right_normals=np.tile(nrm, (25, 1)),
                         sector_angle=ALPHA, element_size=1e-3)
    N = 30
    R = rotation_about("z", ALPHA)
    c = np.array([1.0, -2.0, 0.5])
    # a global translation c, in every sector's own components: R^-j c
    own = np.stack([np.linalg.matrix_power(R.T, j) @ c for j in range(N)])
    G = np.repeat(own[:, None, :], 25, axis=1).reshape(N, 75, 1)
    rows = p.wheel_rows(G, G)
    assert np.abs(rows).max() < 1e-14
    # only sector 0's right face moves along its normal: contact 0 closes by that amount
    Gr = np.zeros((N, 75, 1))
    Gr[0, :, 0] = np.tile(nrm, 25) * 1e-6
    rows = p.wheel_rows(Gr, np.zeros((N, 75, 1))).reshape(N, 25, 3)
    np.testing.assert_allclose(rows[0, :, 0], 1e-6)
    assert np.abs(rows[1:]).max() == 0 and np.abs(rows[0, :, 1:]).max() < 1e-20


def test_non_conformal_faces_are_rejected():
    rng = np.random.default_rng(2)
    right, left, nrm, _ = _faces(rng)
    left[3] += 1e-4
    with pytest.raises(ModelError, match="node to node"):
        patch_from_faces(right, left, right_areas=np.ones(25),
                         right_normals=np.tile(nrm, (25, 1)), sector_angle=ALPHA,
                         element_size=1e-3)
    right, left, nrm, _ = _faces(rng)
    with pytest.raises(ModelError, match="right_areas"):
        patch_from_faces(right, left, right_areas=-np.ones(25),
                         right_normals=np.tile(nrm, (25, 1)), sector_angle=ALPHA,
                         element_size=1e-3)
