"""The 78-DOF model of paper 001 (models/blade_pair.py): structure of the matrices, the
contact kinematics against the paper's own row vectors 001 (14)-(16), (20), (34), the
deformation energy 001 (12), (17), the nozzle excitation 001 (3), (10), (11), Table 1, and
parameter validation."""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models.blade_pair.model import (
    TABLE_1,
    BladePairParameters,
    build_blade_pair,
    rpm_to_rad_s,
)
from fricdamp.structure.beam3d_rotation import skew


@pytest.fixture(scope="module")
def model():
    return build_blade_pair()


def test_78_dofs_and_block_diagonal_structure_of_001_9(model):
    """q = [q1, qD, q2] with 2 x 36 + 6 = 78 DOFs (001 section 4); M, G, K_d block-diagonal
    with identical blade blocks (001 (9)); K_s, B, K_w zero on the wedge."""
    assert model.n_dof == 78 and model.n_blade_dof == 36
    s1, s2 = model.blade_slices
    d = model.damper_slice
    for A in (model.M, model.K_s, model.B, model.G, model.K_d, model.K_w):
        assert np.array_equal(A[s1, s1], A[s2, s2])
        assert not A[s1, s2].any() and not A[s1, d].any() and not A[d, s2].any()
    for A in (model.K_s, model.B, model.K_w):
        assert not A[d, d].any()
    assert np.allclose(model.M[d, d][:3, :3], model.params.damper_mass * np.eye(3))
    assert np.abs(model.G + model.G.T).max() <= 1e-14 * np.abs(model.G).max()    # skew
    for A in (model.M, model.K_s, model.K_d, model.K_w, model.K_C):
        assert np.abs(A - A.T).max() <= 1e-12 * np.abs(A).max()
    assert np.linalg.eigvalsh(model.M).min() > 0


def _rigid_motion(model, t, theta):
    """DOF vector of a rigid motion of the whole assembly (translation t, rotation theta
    about the origin, global axes), each body's DOFs in its own frame."""
    q = np.zeros(model.n_dof)
    for body, R in (("blade1", model.frames[0]), ("blade2", model.frames[2])):
        for node in range(model.blade.n_nodes):
            p = R @ model.blade.nodes[node]
            u = R.T @ (t + np.cross(theta, p))
            th = R.T @ theta
            for k, nm in enumerate(("u", "v", "w", "phi", "theta", "psi")):
                try:
                    q[model.dof_index(body, node, nm)] = np.concatenate([u, th])[k]
                except ModelError:          # the clamped rim node
                    pass
    pD = np.array([model.params.damper_radius, 0.0, 0.0])
    q[model.damper_slice] = np.concatenate([t + np.cross(theta, pD), theta])
    return q


def test_a_rigid_motion_of_the_assembly_does_not_load_the_contacts(model):
    """Frame consistency: moving every body together (3 translations, 3 rotations) gives no
    relative displacement or rotation at A and B (all 12 contact rows vanish, 1e-15 m)."""
    for j in range(6):
        t, th = np.zeros(3), np.zeros(3)
        (t if j < 3 else th)[j % 3] = 1e-3
        q = _rigid_motion(model, t, th)
        assert np.abs(model.contact_projection @ q).max() < 1e-15
        assert np.abs(model.K_C @ q).max() < 1e-15 * np.abs(model.K_C).max()


def test_contact_rows_are_the_paper_vectors_in_the_blade_frames(model):
    """001 (14), (20), (15)-(16), (34) written in blade j's own frame with the plane angles
    delta_A = delta_a + delta/2, delta_B = delta_b + delta/2 and the wedge's in its frame
    (E R^T q = u + theta x r) equal the model's rows built from global vectors (up to the
    orientation of the normal, which the paper takes differently at A and B)."""
    ang = model.contact_angles
    tip = model.tip_node
    P = model.contact_projection

    def block(r):
        return np.hstack([np.eye(3), skew(r).T])          # [E R^T]: u + theta x r

    for c, (X, body, dX, dx, sgn) in enumerate((("A", "blade2", ang["delta_A"],
                                                ang["delta_a"], +1),
                                               ("B", "blade1", ang["delta_B"],
                                                ang["delta_b"], -1))):
        cols_C = [model.dof_index(body, tip, nm) for nm in
                  ("u", "v", "w", "phi", "theta", "psi")]
        cols_D = list(range(model.damper_slice.start, model.damper_slice.stop))
        rC, rD = model.contact_offsets_shroud[c], model.contact_offsets_damper[c]
        # 001 (14): zeta rows (the paper: [-sin, 0, cos] at A, [sin, 0, cos] at B)
        zC = np.array([-sgn * np.sin(dX), 0, np.cos(dX)]) @ block(rC)
        zD = np.array([-sgn * np.sin(dx), 0, np.cos(dx)]) @ block(rD)
        # 001 (20): xi rows ([cos, 0, +sin] at A, [cos, 0, -sin] at B) and eta rows
        xC = np.array([np.cos(dX), 0, sgn * np.sin(dX)]) @ block(rC)
        xD = np.array([np.cos(dx), 0, sgn * np.sin(dx)]) @ block(rD)
        eC, eD = np.array([0, 1.0, 0]) @ block(rC), np.array([0, 1.0, 0]) @ block(rD)
        # 001 (15)-(16): relative rotations about xi and eta; (34): about the normal
        rxC = np.concatenate([np.zeros(3), [np.cos(dX), 0, sgn * np.sin(dX)]])
        rxD = np.concatenate([np.zeros(3), [np.cos(dx), 0, sgn * np.sin(dx)]])
        reC = reD = np.array([0, 0, 0, 0, 1.0, 0])
        rnC = np.concatenate([np.zeros(3), [-sgn * np.sin(dX), 0, np.cos(dX)]])
        rnD = np.concatenate([np.zeros(3), [-sgn * np.sin(dx), 0, np.cos(dx)]])
        paper = [(zC, zD), (xC, xD), (eC, eD), (rxC, rxD), (reC, reD), (rnC, rnD)]
        for row, (vc, vd) in enumerate(paper):
            ref = np.zeros(model.n_dof)
            ref[cols_C] = vc
            ref[cols_D] = -vd
            mine = P[c, row]
            s = 1.0 if row not in (0, 5) else sgn            # normal orientation at B
            assert np.abs(mine - s * ref).max() < 1e-14, (X, row)


def test_contact_stiffness_is_the_deformation_energy_of_001_12(model):
    """q^T K_C q / 2 = 1/2 sum (k zeta^2 + k_xixi phi_xi^2 + k_etaeta phi_eta^2) with
    001 (17) k_xixi = k h^2/12, k_etaeta = k a^2/12 (random q, 1e-12)."""
    p = model.params
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = rng.normal(size=model.n_dof) * 1e-6
        E = 0.0
        for c in range(2):
            z, _, _, px, pe, _ = model.contact_projection[c] @ q
            k, a, h = p.contact_stiffness[c], p.contact_width[c], p.contact_height[c]
            E += 0.5 * (k * z**2 + k * h**2 / 12 * px**2 + k * a**2 / 12 * pe**2)
        assert 0.5 * q @ model.K_C @ q == pytest.approx(E, rel=1e-12)


def test_normal_loads_balance_the_centrifugal_force_of_the_wedge(model):
    """001 (6) derived again: N_A n_A + N_B n_B + m_D r_D Omega^2 x = 0 (1e-12); for a
    symmetric wedge both loads equal the paper's printed form F cos(d)/sin(2 d)."""
    p = model.params
    for rpm in (300.0, 1500.0):
        w = rpm_to_rad_s(rpm)
        N = model.normal_loads(w)
        F = p.damper_mass * p.damper_radius * w**2
        res = N[0] * model.normals[0] + N[1] * model.normals[1] + [F, 0, 0]
        assert np.abs(res).max() < 1e-12 * F
        assert N[0] > N[1]                      # plane a steeper: N_A > N_B (001 sec. 4.2)
    sym = build_blade_pair(p.with_(delta_b=p.delta_a))
    N = sym.normal_loads(100.0)
    F = p.damper_mass * p.damper_radius * 1e4
    assert N == pytest.approx(F * np.cos(p.delta_a) / np.sin(2 * p.delta_a) * np.ones(2))


def test_nozzle_excitation_of_001_10_11_and_table_1(model):
    """F_ax along y_j and -F_t along z_j at each of the six blade nodes, blade 2 leading by
    the phase k delta (001 (3), (10)); amplitudes from Table 1, F^(1)/k otherwise."""
    p = model.params
    for k, (ft, fa) in TABLE_1.items():
        F = model.load(k)
        s1, s2 = model.blade_slices
        f1 = F[s1].reshape(6, 6)
        assert np.allclose(f1[:, 1], fa) and np.allclose(f1[:, 2], -ft)
        assert np.count_nonzero(F[s1]) == 12 and not F[model.damper_slice].any()
        assert np.allclose(F[s2], F[s1] * np.exp(1j * k * p.pitch_angle))
    assert p.nozzle_forces(25) == (20.0 / 25, 10.0 / 25)
    with pytest.raises(ModelError, match="order"):
        p.nozzle_forces(0)


def test_matrices_at_speed_follow_001_8(model):
    """K(Omega) = K_s + K_C + Omega^2 (K_w - K_d); D(Omega) = B + beta_C K_C + Omega G; the
    MechanicalSystem carries them and the load at k Omega."""
    w = 150.0
    K = model.stiffness(w)
    assert np.allclose(K, model.K_s + model.K_C + w**2 * (model.K_w - model.K_d))
    assert np.allclose(model.stiffness([w, w])[1], K)
    D = model.damping(w)
    assert np.allclose(D, model.B + model.params.contact_damping * model.K_C + w * model.G)
    sys = model.system(w, order=20)
    assert sys.n_dof == 78 and sys.loads[0].omega == pytest.approx(20 * w)
    assert np.allclose(sys.loads[0].amplitude, model.load(20))


def test_blade_frame_angles_and_contact_geometry(model):
    """The contact point is one physical point: shroud tip + R_j r_C,X = D + r_D,X."""
    p = model.params
    half = p.pitch_angle / 2
    ang = model.contact_angles
    assert ang["delta_A"] == pytest.approx(p.delta_a + half)
    assert ang["delta_B"] == pytest.approx(p.delta_b + half)
    for c, body in enumerate((2, 0)):
        R = model.frames[body]
        tip = R @ np.array([p.tip_radius, 0, 0])
        assert np.allclose(tip + R @ model.contact_offsets_shroud[c],
                           [p.damper_radius, 0, 0] + model.contact_offsets_damper[c])
    assert model.torque_arms == pytest.approx([0.0056545] * 2, rel=1e-4)


@pytest.mark.parametrize("change, match", [
    (dict(damper_mass=-0.01), "damper_mass"),
    (dict(delta_a=0.0), "delta_a"),
    (dict(delta_b=np.pi / 2), "delta_b"),
    (dict(n_blades=2), "n_blades"),
    (dict(n_elements=0), "n_elements"),
    (dict(contact_points=((0.0, 0.01), (0.0, 0.02))), "z_A < 0"),
    (dict(contact_points=((0.0, -0.05), (0.0, 0.05))), "half pitch"),
    (dict(contact_stiffness=(1e8, -1.0)), "contact_stiffness"),
    (dict(friction_coefficient=-0.1), "friction_coefficient"),
    (dict(damping_rule="exact"), "damping_rule"),
    (dict(damper_radius=0.1), "damper_radius"),
    (dict(shroud_inertia=(1.0, 2.0)), "shroud_inertia"),
    (dict(excitation_table=((0, 1.0, 1.0),)), "order k"),
])
def test_bad_parameters_are_rejected_with_their_name(change, match):
    with pytest.raises(ModelError, match=match):
        BladePairParameters(**change)


def test_with_copies_and_rejects_unknown_fields():
    p = BladePairParameters()
    assert p.with_(friction_coefficient=0.3).friction_coefficient == (0.3, 0.3)
    with pytest.raises(ModelError, match="unknown"):
        p.with_(mu=0.3)
    with pytest.raises(ModelError, match="BladePairParameters"):
        build_blade_pair({"mu": 0.3})
