"""Unit tests of the 3D Rayleigh beam (structure/beam3d.py, beam3d_rotation.py).

Element matrices against Przemieniecki's closed forms, matrix properties (symmetry, rigid-body
modes, total mass), DOF bookkeeping, damping, the system at speed, and input errors.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl
from threadpoolctl import threadpool_limits

from fricdamp.errors import ModelError
from fricdamp.structure.beam3d import (
    BeamModel,
    BeamSection,
    beam_model,
    line_mesh,
    local_element_matrices,
)
from fricdamp.structure.beam3d_rotation import rigid_body_terms, rotary_operators, skew
from fricdamp.structure.system import MechanicalSystem

STEEL = dict(E_Pa=2.1e11, rho_kg_m3=7850.0, nu=0.3)


@pytest.fixture(autouse=True)
def _one_blas_thread():
    with threadpool_limits(limits=1):
        yield


def _bending(EI, l):
    return EI / l**3 * np.array([[12, 6 * l, -12, 6 * l], [6 * l, 4 * l**2, -6 * l, 2 * l**2],
                                 [-12, -6 * l, 12, -6 * l], [6 * l, 2 * l**2, -6 * l, 4 * l**2]])


def _consistent(rA, l):
    return rA * l / 420 * np.array([[156, 22 * l, 54, -13 * l], [22 * l, 4 * l**2, 13 * l,
                                                                  -3 * l**2],
                                    [54, 13 * l, 156, -22 * l], [-13 * l, -3 * l**2, -22 * l,
                                                                 4 * l**2]])


def _rotary(rI, l):
    return rI / (30 * l) * np.array([[36, 3 * l, -36, 3 * l], [3 * l, 4 * l**2, -3 * l, -l**2],
                                     [-36, -3 * l, 36, -3 * l], [3 * l, -l**2, -3 * l,
                                                                 4 * l**2]])


def test_local_element_matrices_match_przemieniecki():
    """Stiffness and consistent Rayleigh mass equal the closed forms (Przemieniecki 1968,
    ch. 5 and 11) to round-off (1e-12 of the largest entry): 4-point Gauss is exact here."""
    sec = BeamSection(area_m2=3e-4, Iy_m4=2e-9, Iz_m4=7e-9, J_m4=4e-9, E_Pa=2e11,
                      rho_kg_m3=7800.0, G_Pa=8e10, Ip_m4=9.5e-9)
    l = 0.13
    K, M = local_element_matrices(l, sec)
    Kref, Mref = np.zeros((12, 12)), np.zeros((12, 12))
    ax, tw = [0, 6], [3, 9]
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    Kref[np.ix_(ax, ax)] = sec.E_Pa * sec.area_m2 / l * bar
    Kref[np.ix_(tw, tw)] = sec.G_Pa * sec.J_m4 / l * bar
    rod = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6
    rho = sec.rho_kg_m3
    Mref[np.ix_(ax, ax)] = rho * sec.area_m2 * l * rod
    Mref[np.ix_(tw, tw)] = rho * sec.Ip_m4 * l * rod
    v_plane, w_plane = [1, 5, 7, 11], [2, 4, 8, 10]
    flip = np.diag([1.0, -1.0, 1.0, -1.0])              # theta_y = -w'
    Kref[np.ix_(v_plane, v_plane)] = _bending(sec.E_Pa * sec.Iz_m4, l)
    Kref[np.ix_(w_plane, w_plane)] = flip @ _bending(sec.E_Pa * sec.Iy_m4, l) @ flip
    rA = rho * sec.area_m2
    Mref[np.ix_(v_plane, v_plane)] = _consistent(rA, l) + _rotary(rho * sec.Iz_m4, l)
    Mref[np.ix_(w_plane, w_plane)] = flip @ (_consistent(rA, l)
                                             + _rotary(rho * sec.Iy_m4, l)) @ flip
    np.testing.assert_allclose(K, Kref, atol=1e-12 * np.abs(Kref).max())
    np.testing.assert_allclose(M, Mref, atol=1e-12 * np.abs(Mref).max())


SECS = [BeamSection.rectangle(0.03 - 0.004 * i, 0.004, **STEEL) for i in range(4)]


def _branched_model(**kw) -> BeamModel:
    """Staggered, bent blade with a side branch, a tip mass with a full inertia tensor and an
    inclined spin axis: no symmetry that could hide an error."""
    nodes = np.array([[0.3, 0, 0], [0.35, 0.0, 0.01], [0.4, 0.01, 0.02], [0.45, 0.02, 0.02],
                      [0.42, 0.05, 0.03]])
    els = np.array([[0, 1], [1, 2], [2, 3], [2, 4]])
    ori = np.array([[0, 1, 0.3], [0, 1, 0.5], [0, 1, 0.7], [1, 0, 0.9]])
    J = np.array([[2e-5, 3e-6, 0], [3e-6, 1e-5, 1e-6], [0, 1e-6, 2.5e-5]])
    kw.setdefault("clamped_nodes", [0])
    return beam_model(nodes, els, SECS, orientation=ori, point_masses={3: (0.03, J), 4: 0.01},
                      spin_axis=[0.1, 0.2, 1.0], spin_origin=[0.01, 0.0, 0.1], **kw)


def test_matrix_symmetries_of_a_general_structure():
    """M, K, K_d, K_w symmetric, G skew-symmetric (001 (2)); M positive definite."""
    model = _branched_model()
    r = model.rotation
    for name, A in (("M", model.M), ("K", model.K), ("Kd", r.spin_softening),
                    ("Kw", r.stress_stiffening)):
        A = A.toarray()
        assert np.abs(A - A.T).max() <= 1e-13 * np.abs(A).max(), name
        assert np.abs(A).max() > 0, name
    G = r.gyroscopic.toarray()
    assert np.abs(G + G.T).max() <= 1e-13 * np.abs(G).max()
    assert sl.eigvalsh(model.M.toarray())[0] > 0


def test_free_structure_has_six_rigid_body_modes_and_the_right_total_mass():
    """Unsupported: K has exactly 6 zero eigenvalues, whose null space holds the rigid
    translations and rotations; a unit translation t carries the total mass, t^T K_d t the
    mass off the axis (|t x e|^2 m), s^T G t = 2 m s . (e x t) (Coriolis of a rigid body)."""
    model = _branched_model(clamped_nodes=[], stress_stiffening=False)
    K, M = model.K.toarray(), model.M.toarray()
    lam = sl.eigvalsh(K, M)
    assert np.all(np.abs(lam[:6]) < 1e-8 * lam[6]) and lam[6] > 1.0
    x = model.nodes
    for k in range(3):
        t = np.zeros((model.n_nodes, 6))
        t[:, k] = 1.0
        assert np.abs(K @ t.ravel()).max() < 1e-6
        a = np.zeros(3)
        a[k] = 1.0
        rot = np.zeros((model.n_nodes, 6))
        rot[:, :3] = np.cross(a, x)                      # small rigid rotation about axis k
        rot[:, 3 + k] = 1.0
        assert np.abs(K @ rot.ravel()).max() < 1e-6 * np.abs(K).max()
    rA_len = sum(s.rho_kg_m3 * s.area_m2 * np.linalg.norm(x[j] - x[i])
                 for s, (i, j) in zip(SECS, model.elements, strict=True))
    m_total = rA_len + 0.03 + 0.01
    e = model.spin_axis
    Kd, G = model.rotation.spin_softening.toarray(), model.rotation.gyroscopic.toarray()
    trans = []
    for k in range(3):
        t = np.zeros((model.n_nodes, 6))
        t[:, k] = 1.0
        trans.append(t.ravel())
        assert t.ravel() @ M @ t.ravel() == pytest.approx(m_total, rel=1e-12)
        off_axis = 1.0 - e[k] ** 2
        assert t.ravel() @ Kd @ t.ravel() == pytest.approx(m_total * off_axis, rel=1e-12)
    s_, t_ = trans[0], trans[1]
    assert s_ @ G @ t_ == pytest.approx(2 * m_total * np.cross(e, [0, 1, 0])[0], rel=1e-12)


def test_rotary_operators_of_a_spinning_disk_and_a_flat_blade_section():
    """Rotor spinning about its own axis x (J = diag(Ip, Id, Id)): G couples the tilts with
    (Ip - 2 Id), K_d = diag(0, Id - Ip, Id - Ip) (rotating-frame rotor equations). A flat
    section (chord along y, in the plane of rotation; spin axis z) is stiffened in twist by
    the propeller moment: K_d[x, x] = Jyy - Jzz < 0 (enters as -Omega^2 K_d)."""
    Ip, Id = 2.0, 1.3
    G, Kd, mom = rotary_operators(np.array([1.0, 0, 0]), np.diag([Ip, Id, Id]))
    np.testing.assert_allclose(G, (Ip - 2 * Id) * np.array([[0, 0, 0], [0, 0, 1], [0, -1, 0]]),
                               atol=1e-15)
    np.testing.assert_allclose(Kd, np.diag([0.0, Id - Ip, Id - Ip]), atol=1e-15)
    np.testing.assert_allclose(mom, 0.0, atol=1e-15)
    Jyy, Jzz = 1e-3, 3e-2                      # thin in z, wide chord along y
    G, Kd, _ = rotary_operators(np.array([0, 0, 1.0]), np.diag([Jyy + Jzz, Jyy, Jzz]))
    assert Kd[0, 0] == pytest.approx(Jyy - Jzz) and Kd[0, 0] < 0
    assert Kd[1, 1] == pytest.approx(Jyy)      # flap slope: rotary inertia softening
    assert np.all(np.abs(G + G.T) < 1e-15)


def test_skew_matrix_is_the_cross_product():
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(2, 4, 3))
    np.testing.assert_allclose(np.einsum("kij,kj->ki", skew(a), b), np.cross(a, b))


def test_rigid_body_terms_of_a_point_mass():
    """A point mass m at radius r in the plane of rotation: f_c = m r (radial),
    K_d = m diag(1, 1, 0) for spin about z, G = 2 m S(e)."""
    t = rigid_body_terms(2.0, 0.0, [0.3, 0.4, 1.0], spin_axis=[0, 0, 5.0])
    np.testing.assert_allclose(t.fc[:3], [0.6, 0.8, 0.0])
    np.testing.assert_allclose(t.Kd[:3, :3], np.diag([2.0, 2.0, 0.0]))
    np.testing.assert_allclose(t.G[:3, :3], 4.0 * skew(np.array([0, 0, 1.0])))
    np.testing.assert_allclose(t.M, np.diag([2.0, 2, 2, 0, 0, 0]))


def test_dof_bookkeeping():
    nodes, els = line_mesh([0, 0, 0], [1, 0, 0], 3)
    sec = BeamSection.circle(0.01, **STEEL)
    model = beam_model(nodes, els, sec, clamped_nodes=[0], fixed_dofs=[(3, ("v", "rx"))])
    assert model.n_dof == 6 * 4 - 6 - 2
    assert model.dof_index(1, "u") == 0 and model.dof_index(1, "psi") == 5
    assert model.dof_index(3, "w") == 13 and model.dof_index(3, "uz") == 13
    assert model.full_dof_index(3, "w") == 20
    assert model.dof_names[model.dof_index(2, "theta")] == "theta2"
    with pytest.raises(ModelError, match="fixed"):
        model.dof_index(0, "u")
    with pytest.raises(ModelError, match="fixed"):
        model.dof_index(3, "phi")
    with pytest.raises(ModelError, match="DOF name"):
        model.dof_index(1, "x")
    with pytest.raises(ModelError, match="node"):
        model.dof_index(4, "u")
    q = np.arange(model.n_dof, dtype=float) + 1
    nodal = model.expand(q)
    assert nodal.shape == (4, 6) and np.all(nodal[0] == 0) and nodal[3, 1] == 0
    assert nodal[3, 2] == q[model.dof_index(3, "w")]
    with pytest.raises(ModelError, match="shape"):
        model.expand(q[:-1])


def test_default_element_frames():
    """Element along x: local axes = global; along y: local z = global z (x' = y, y' = -x)."""
    sec = BeamSection.rectangle(0.02, 0.005, **STEEL)     # Iz (width along local y) > Iy
    K_loc, _ = local_element_matrices(0.5, sec)
    for end, expect in (([0.5, 0, 0], {"v": 1, "w": 2}), ([0, 0.5, 0], {"v": 0, "w": 2})):
        model = beam_model(np.array([[0, 0, 0], end], float), np.array([[0, 1]]), sec,
                           clamped_nodes=[0])
        K = model.K.toarray()
        # transverse tip stiffness along local y is 12 EIz / l^3
        i = model.dof_index(1, "uvw"[expect["v"]])
        assert K[i, i] == pytest.approx(K_loc[7, 7], rel=1e-12)
        i = model.dof_index(1, "uvw"[expect["w"]])
        assert K[i, i] == pytest.approx(K_loc[8, 8], rel=1e-12)


def test_damping_options():
    nodes, els = line_mesh([0, 0, 0], [1, 0, 0], 4)
    sec = BeamSection.circle(0.01, **STEEL)
    m = beam_model(nodes, els, sec, clamped_nodes=[0], rayleigh=(2.0, 1e-5))
    np.testing.assert_allclose(m.D.toarray(), 2.0 * m.M.toarray() + 1e-5 * m.K.toarray())
    m = beam_model(nodes, els, sec, clamped_nodes=[0], loss_factor=(0.01, 500.0))
    np.testing.assert_allclose(m.D.toarray(), 0.01 / 500.0 * m.K.toarray())
    assert beam_model(nodes, els, sec, clamped_nodes=[0]).D.nnz == 0
    with pytest.raises(ModelError, match="either"):
        beam_model(nodes, els, sec, clamped_nodes=[0], rayleigh=(1, 0), loss_factor=(0.1, 1))
    with pytest.raises(ModelError, match="rayleigh"):
        beam_model(nodes, els, sec, clamped_nodes=[0], rayleigh=(-1.0, 0.0))
    with pytest.raises(ModelError, match="omega_ref"):
        beam_model(nodes, els, sec, clamped_nodes=[0], loss_factor=(0.1, 0.0))


def test_system_at_speed_follows_the_conventions_of_001_2():
    """to_system().at_speed(W): D + W G, K + W^2 (K_w - K_d), static load W^2 f_c; dense and
    sparse systems agree."""
    model = _branched_model(rayleigh=(1.0, 1e-6))
    W = 250.0
    sys_s = model.to_system(name="blade")
    sys_d = model.to_system(sparse=False)
    assert isinstance(sys_s, MechanicalSystem) and sys_s.is_sparse and not sys_d.is_sparse
    assert sys_s.dof_names == model.dof_names and sys_s.name == "blade"
    r = model.rotation
    at = sys_s.at_speed(W)
    np.testing.assert_allclose(at.D.toarray(), (model.D + W * r.gyroscopic).toarray())
    np.testing.assert_allclose(
        at.K.toarray(),
        (model.K + W**2 * (r.stress_stiffening - r.spin_softening)).toarray())
    np.testing.assert_allclose(at.static_load, W**2 * r.centrifugal_load)
    at_d = sys_d.at_speed(W)
    np.testing.assert_allclose(at_d.K, at.K.toarray(), rtol=1e-14, atol=1e-6)
    np.testing.assert_allclose(at_d.D, at.D.toarray(), rtol=1e-14, atol=1e-12)


def test_without_spin_axis_there_are_no_rotation_terms():
    nodes, els = line_mesh([0, 0, 0], [1, 0, 0], 2)
    m = beam_model(nodes, els, BeamSection.circle(0.01, **STEEL), clamped_nodes=[0])
    assert m.rotation is None and m.axial_force_per_omega2 is None
    s = m.to_system()
    assert s.at_speed(100.0) is s


def test_section_constructors():
    """Square torsion constant 0.1406 a^4, thin strip a b^3 / 3 (1 - 0.630 b / a) (Roark,
    Table 10.7); circle J = pi d^4 / 32; G from nu."""
    s = BeamSection.rectangle(0.01, 0.01, E_Pa=2e11, rho_kg_m3=7800.0, nu=0.25)
    assert s.J_m4 == pytest.approx(0.1406e-8, rel=2e-4)
    assert s.G_Pa == pytest.approx(8e10) and s.Ip_m4 == pytest.approx(2 * 0.01**4 / 12)
    c = BeamSection.circle(0.02, E_Pa=2e11, rho_kg_m3=7800.0, G_Pa=7.7e10)
    assert c.J_m4 == pytest.approx(np.pi * 0.02**4 / 32) and c.Iy_m4 == c.Iz_m4
    thin = BeamSection.rectangle(0.05, 0.002, E_Pa=2e11, rho_kg_m3=7800.0, nu=0.3)
    assert thin.J_m4 == pytest.approx(0.05 * 0.002**3 / 3 * (1 - 0.630 * 0.002 / 0.05),
                                      rel=1e-4)


@pytest.mark.parametrize("kwargs, match", [
    (dict(area_m2=-1.0), "area_m2"),
    (dict(G_Pa=None, nu=None), "shear modulus"),
    (dict(G_Pa=8e10, nu=0.1), "disagree"),
    (dict(G_Pa=None, nu=0.7), "nu"),
    (dict(rho_kg_m3=float("nan")), "rho_kg_m3"),
])
def test_section_errors(kwargs, match):
    base = dict(area_m2=1e-4, Iy_m4=1e-9, Iz_m4=2e-9, J_m4=2e-9, E_Pa=2e11, rho_kg_m3=7800.0,
                G_Pa=8e10)
    with pytest.raises(ModelError, match=match):
        BeamSection(**{**base, **kwargs})


def test_model_input_errors():
    sec = BeamSection.circle(0.01, **STEEL)
    nodes, els = line_mesh([0, 0, 0], [1, 0, 0], 2)
    with pytest.raises(ModelError, match="zero length"):
        beam_model(np.zeros((2, 3)), [[0, 1]], sec)
    with pytest.raises(ModelError, match="belongs to no element"):
        beam_model(np.vstack([nodes, [[2, 0, 0]]]), els, sec)
    with pytest.raises(ModelError, match="elements"):
        beam_model(nodes, [[0, 3]], sec)
    with pytest.raises(ModelError, match="elements"):
        beam_model(nodes, [[0.0, 1.0]], sec)
    with pytest.raises(ModelError, match="parallel"):
        beam_model(nodes, els, sec, orientation=[2.0, 0, 0])
    with pytest.raises(ModelError, match="sections"):
        beam_model(nodes, els, [sec])
    with pytest.raises(ModelError, match="spin_axis"):
        beam_model(nodes, els, sec, clamped_nodes=[0], spin_axis=[0, 0, 0])
    with pytest.raises(ModelError, match="singular"):
        beam_model(nodes, els, sec, spin_axis=[0, 0, 1])        # no support, prestress asked
    with pytest.raises(ModelError, match="point_masses"):
        beam_model(nodes, els, sec, point_masses={5: 1.0})
    with pytest.raises(ModelError, match="mass"):
        beam_model(nodes, els, sec, point_masses={2: -1.0})
    with pytest.raises(ModelError, match="inertia"):
        beam_model(nodes, els, sec, point_masses={2: (1.0, [[1, 2, 0], [0, 1, 0], [0, 0, 1]])})
    with pytest.raises(ModelError, match="clamped_nodes"):
        beam_model(nodes, els, sec, clamped_nodes=[7])
    with pytest.raises(ModelError, match="no DOFs"):
        beam_model(nodes, els, sec, clamped_nodes=[0, 1, 2])
    with pytest.raises(ModelError, match="n_elements"):
        line_mesh([0, 0, 0], [1, 0, 0], 0)
