"""Tie-boss wheel model (paper 003): parameters, geometry, contact kinematics, reduction.

References: 003 section 1.1 and Fig. 2 (30 blades, tie-boss at r = 0.44 m, contact planes
through the mid radials 12 degrees apart, turned by 45 degrees); rigid-body kinematics (a
rigid motion of the whole wheel must not move any contact); Craig-Bampton's Rayleigh-Ritz
property (reduced frequencies lie above the full ones).
"""

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import (
    TiebossWheelParameters,
    build_sector,
    build_wheel,
    contact_frame,
)
from fricdamp.structure.cyclic import nodal_diameter_modes


@pytest.fixture(scope="module")
def sector():
    return build_sector(rotation=False)


@pytest.fixture(scope="module")
def full(sector):
    return build_wheel(sector)


@pytest.mark.parametrize("kwargs, word", [
    ({"tieboss_radius_m": 0.25}, "radii"),
    ({"tip_radius_m": 0.40}, "radii"),
    ({"blade_angle_deg": 95.0}, "blade_angle_deg"),
    ({"contact_plane_angle_deg": 90.0}, "contact_plane_angle_deg"),
    ({"mu_sliding": 0.5}, "mu_sliding"),
    ({"n_blades": 2}, "n_blades"),
    ({"damping_band_hz": (60.0, 40.0)}, "damping_band_hz"),
    ({"tip_mass_kg": -1.0}, "tip_mass_kg"),
    ({"contact_offset_m": 0.1}, "contact_offset_m"),
    ({"n_blade_elements": 1}, "n_blade_elements"),
])
def test_bad_parameters_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        TiebossWheelParameters(**kwargs)


def test_rayleigh_damping_gives_the_ratio_at_both_band_ends():
    """zeta(w) = a / 2w + b w / 2 equals 0.1 % at 40 and 60 Hz and is below it between."""
    p = TiebossWheelParameters()
    a, b = p.rayleigh()
    for f in p.damping_band_hz:
        w = 2 * np.pi * f
        assert a / (2 * w) + b * w / 2 == pytest.approx(1e-3, rel=1e-12)
    w = 2 * np.pi * 48.0
    assert 0.96e-3 < a / (2 * w) + b * w / 2 < 1e-3


def test_contact_frame_is_the_45_degree_cut_through_the_mid_radial():
    """003 Fig. 2: the plane alpha (perpendicular to the wheel, through the mid radial zeta)
    turned by 45 degrees about zeta. Rows orthonormal; t1 = zeta; n has equal tangential and
    axial parts; beta_c = 0 gives the plane alpha (normal tangential)."""
    h = np.pi / 30
    L = contact_frame(2 * h, 45.0)
    np.testing.assert_allclose(L @ L.T, np.eye(3), atol=1e-15)
    zeta = np.array([np.cos(h), np.sin(h), 0.0])
    et = np.array([-np.sin(h), np.cos(h), 0.0])
    np.testing.assert_allclose(L[1], zeta, atol=1e-15)
    assert L[0] @ et == pytest.approx(np.sqrt(0.5)) and L[0][2] == pytest.approx(-np.sqrt(0.5))
    np.testing.assert_allclose(contact_frame(2 * h, 0.0)[0], et, atol=1e-15)


def test_sector_geometry(sector):
    """Contact nodes of neighbouring blades coincide on the mid radial at the tie-boss
    radius; the blade's flexural direction lies in the contact plane at the mid radial."""
    p = sector.parameters
    beam = sector.beam
    nodes = beam.nodes
    dof_node = {beam.dof_index(k, "u"): k for k in range(beam.n_nodes)
                if k != 0}  # node 0 is clamped
    right = nodes[dof_node[sector.cyclic.named_dofs["contact_right"][0]]]
    left = nodes[dof_node[sector.cyclic.named_dofs["contact_left"][0]]]
    R = sector.cyclic.rotation_matrix()
    np.testing.assert_allclose(R @ left, right, atol=1e-15)          # next blade's left node
    assert np.hypot(right[0], right[1]) * np.cos(np.pi / 30) == pytest.approx(
        p.tieboss_radius_m)
    tb = nodes[dof_node[sector.cyclic.named_dofs["tieboss"][0]]]
    assert tb.tolist() == pytest.approx([0.44, 0.0, 0.0])
    # flexural direction of a blade turned to the mid radial is in the contact plane
    h = np.pi / 30
    d_mid = np.array([[np.cos(h), -np.sin(h), 0], [np.sin(h), np.cos(h), 0], [0, 0, 1]]
                     ) @ sector.flexural_direction
    assert abs(sector.frame[0] @ d_mid) < 1e-14
    assert sector.cyclic.n_dof == 102


def _rigid_field(wheel, translation, rotation_z):
    """Wheel DOFs of a rigid motion (translation [m], rotation about z [rad]) of everything,
    each sector's DOFs in its own frame (node coordinates from the beam model)."""
    beam = wheel.sector.beam
    ind = wheel.cyclic.independent
    q = np.zeros(wheel.n_dof)
    for j in range(wheel.n_blades):
        Rj = wheel.blade_rotation(j)
        sec = np.zeros(wheel.cyclic.n_dof)
        for node in range(1, beam.n_nodes):                 # node 0 is clamped
            x = Rj @ beam.nodes[node]
            disp = np.asarray(translation) + rotation_z * np.array([-x[1], x[0], 0.0])
            local = np.concatenate([Rj.T @ disp, Rj.T @ np.array([0.0, 0.0, rotation_z])])
            sec[[beam.dof_index(node, nm) for nm in ("u", "v", "w", "phi", "theta",
                                                      "psi")]] = local
        q[wheel.cyclic.full_dofs(ind, j)] = sec[ind]
    return q


def test_rigid_motion_does_not_move_the_contacts(full):
    """The contact projection (frame, next-sector rotation R) gives zero relative motion for
    a rigid translation and a rigid rotation about the wheel axis of the whole wheel."""
    P = full.system.contacts[0].projection
    for tr, rz in (([1e-3, -2e-3, 5e-4], 0.0), ([0.0, 0.0, 0.0], 1e-3)):
        u = np.asarray(P @ _rigid_field(full, tr, rz))
        assert np.abs(u).max() < 1e-15


def test_normal_approach_of_one_shoulder(full):
    """Moving blade 3's right contact node by delta along n closes contact 3 by delta and
    moves no other contact; moving blade 4's left node the same way opens it."""
    P = full.system.contacts[0].projection
    n_vec = full.sector.frame[0]
    q = np.zeros(full.n_dof)
    q[full.group_dofs("contact_right", 3)] = 2e-6 * n_vec
    u = np.asarray(P @ q).reshape(30, 3)
    assert u[3].tolist() == pytest.approx([2e-6, 0.0, 0.0], abs=1e-20)
    assert np.abs(np.delete(u, 3, axis=0)).max() == 0.0
    q[:] = 0.0
    R = full.cyclic.rotation_matrix()
    q[full.group_dofs("contact_left", 4)] = R.T @ (2e-6 * n_vec)   # same physical motion
    u = np.asarray(P @ q).reshape(30, 3)
    assert u[3].tolist() == pytest.approx([-2e-6, 0.0, 0.0], abs=1e-20)


def test_reduced_wheel_dofs_and_rayleigh_ritz_bound(sector):
    """CB keeps cuts (12), contact nodes (6) and the tie-boss (3) plus n_modes per sector:
    30 (15 + n_modes) independent DOFs; every reduced ND frequency lies above the full one
    and converges (10 modes: < 0.05 % on the first family)."""
    full_f = np.array([nodal_diameter_modes(sector.cyclic, nd, 2).frequencies
                       for nd in (0, 2, 6, 15)])
    prev = None
    for nm in (2, 10):
        red = build_wheel(sector, n_modes=nm)
        assert red.n_dof == 30 * (15 + nm) and red.law.n_contacts == 30
        f = np.array([nodal_diameter_modes(red.cyclic, nd, 2).frequencies
                      for nd in (0, 2, 6, 15)])
        assert (f >= full_f * (1 - 1e-12)).all()
        if prev is not None:
            assert (f <= prev * (1 + 1e-12)).all()
        prev = f
    assert np.abs(prev[:, 0] / full_f[:, 0] - 1).max() < 5e-4


def test_expansion_recovers_physical_sector_dofs(sector):
    """sector_displacement of the reduced wheel maps kept DOFs to themselves and fills the
    interior by the CB transformation (a static cut displacement expands statically)."""
    red = build_wheel(sector, n_modes=4)
    q = np.zeros(red.n_dof)
    dofs = red.group_dofs("tieboss", 5)
    q[dofs] = [1e-4, -2e-4, 3e-4]
    phys = red.sector_displacement(q, 5)
    np.testing.assert_allclose(phys[sector.cyclic.named_dofs["tieboss"]], [1e-4, -2e-4, 3e-4])
    assert np.abs(red.sector_displacement(q, 7)).max() == 0.0


def test_build_wheel_bad_input(sector):
    with pytest.raises(ModelError, match="n_modes"):
        build_wheel(sector, n_modes=-1)
    with pytest.raises(ModelError, match="sector"):
        build_wheel("wheel")
