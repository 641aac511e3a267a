"""Paper 002's equations re-derived from the geometry with sympy (not copied from the paper).

References: Bouchaala et al. 2014, kinetic energy (4), potential (5), Lagrange equations
(A.1) -> (6)/(A.2), joint torque (8), kinematic relations (B.1)-(B.10). The extracted text has
two defects this file pins down: (A.2)'s velocity term of the theta2 equation lacks d3 (it is
``m2 d3 d5 theta1'^2 sin``, as in (6) and (8)), and (B.9) must read
``x2'' = x1'' + d3 theta1'' + d5 theta2''``.

Tolerances: the symbolic and the numerical expressions are the same formulas evaluated in
floating point, so they agree to ~1e-12 relative (rtol 1e-10).
"""

import numpy as np
import pytest
import sympy as sp

from fricdamp.contact import Jenkins
from fricdamp.models.rotational_joint.model import RigParameters, RotationalJointRig
from fricdamp.signals.identify import (
    JointRigGeometry,
    beam_accelerations,
    beam_accelerations_exact,
    joint_torque,
)

t = sp.symbols("t")
m1, m2, I1, I2, d1, d2, d3, d4, d5, g = sp.symbols("m1 m2 I1 I2 d1 d2 d3 d4 d5 g",
                                                    positive=True)
th1, th2, x1 = (sp.Function(n)(t) for n in ("theta1", "theta2", "x1"))
Q = (th1, th2, x1)


def _axis(theta):
    """Unit vector along a beam (towards the joint on beam 1, away from it on beam 2) in
    (X0, Z0), Z0 pointing down."""
    return sp.Matrix([sp.sin(theta), sp.cos(theta)])


def _tangent(theta):
    return sp.Matrix([sp.cos(theta), -sp.sin(theta)])


G1 = sp.Matrix([x1, 0])                       # 002 (2): G1 moves horizontally
O = G1 + d3 * _axis(th1)                      # joint, on beam 1
G2 = O + d5 * _axis(th2)                      # 002 (3)
A = G1 + d1 * _axis(th1)
B = G1 + d2 * _axis(th1)
C = G2 + d4 * _axis(th2)


def _lagrange():
    v1, v2 = G1.diff(t), G2.diff(t)
    T = (m1 * v1.dot(v1) + I1 * th1.diff(t) ** 2 + m2 * v2.dot(v2)
         + I2 * th2.diff(t) ** 2) / 2            # 002 (1)
    V = -m2 * g * (G2[1] - (d3 + d5))            # 002 (5): weight of beam 2, Z0 down
    eqs = [sp.diff(T.diff(q.diff(t)), t) - T.diff(q) + V.diff(q) for q in Q]
    return T, V, eqs


def _numeric(expr, params, state):
    """Substitute parameters and a state (q, q', q'') into an expression."""
    subs = dict(params)
    for q, (x, xd, xdd) in zip(Q, state, strict=True):
        subs[q.diff(t, 2)] = xdd
        subs[q.diff(t)] = xd
        subs[q] = x
    # derivatives first, then the functions
    e = expr.subs({k: v for k, v in subs.items() if isinstance(k, sp.Derivative)})
    return float(e.subs({k: v for k, v in subs.items() if not isinstance(k, sp.Derivative)}))


@pytest.fixture(scope="module")
def derived():
    return _lagrange()


@pytest.fixture(scope="module")
def rig():
    p = RigParameters(sensor_b=0.02)  # B off G1 so that I1 holds both sensors
    return RotationalJointRig(Jenkins(stiffness=5e4, slip_force=0.1), p)


def _params(p: RigParameters):
    return {m1: p.beam1_mass, m2: p.beam2_mass, I1: p.inertia1, I2: p.inertia2,
            d1: p.sensor_a, d2: p.sensor_b, d3: p.joint_arm1, d4: p.sensor_c,
            d5: p.joint_arm2, g: p.gravity}


STATES = [
    [(0.3, 1.7, -40.0), (-0.2, -2.1, 55.0), (1e-3, 0.4, -3.0)],
    [(-0.05, 0.6, 120.0), (0.11, 0.9, -80.0), (-2e-3, -0.1, 7.0)],
]


@pytest.mark.parametrize("state", STATES)
def test_equations_of_motion_match_lagrange(derived, rig, state):
    """M(q) q'' + h(q, q') + gravity = the Lagrange expressions of T (1)-(3) and V (5)."""
    _, _, eqs = derived
    p = rig.params
    params = _params(p)
    q = np.array([s[0] for s in state])
    v = np.array([s[1] for s in state])
    a = np.array([s[2] for s in state])
    free = RotationalJointRig(rig.joint, p.with_(suspension_stiffness=0.0,
                                                 suspension_damping=0.0,
                                                 suspension_torsional_stiffness=0.0,
                                                 suspension_torsional_damping=0.0))
    ours = free.mass_matrix(q) @ a + free.internal_force(q, v)
    ref = np.array([_numeric(e, params, state) for e in eqs])
    np.testing.assert_allclose(ours, ref, rtol=1e-10, atol=1e-12 * np.max(np.abs(ref)))


@pytest.mark.parametrize("state", STATES)
def test_paper_eq8_is_the_theta2_equation(derived, rig, state):
    """002 (8) (the identification's torque) is the Lagrange expression of theta2."""
    _, _, eqs = derived
    p = rig.params
    ref = _numeric(eqs[1], _params(p), state)
    (t1, w1, a1), (t2, _, a2), (_, _, ax) = state
    ours = joint_torque(p.geometry(), t1, t2, w1, a1, a2, ax)
    assert ours == pytest.approx(ref, rel=1e-10)


def test_energies_match_lagrangian(derived, rig):
    """kinetic_energy / potential_energy are T and V (suspension switched off)."""
    T, V, _ = derived
    p = rig.params.with_(suspension_stiffness=0.0, suspension_torsional_stiffness=0.0)
    r = RotationalJointRig(rig.joint, p)
    state = STATES[0]
    q = [s[0] for s in state]
    v = [s[1] for s in state]
    assert r.kinetic_energy(q, v) == pytest.approx(_numeric(T, _params(p), state), rel=1e-10)
    assert r.potential_energy(q) == pytest.approx(_numeric(V, _params(p), state), rel=1e-10)


def _tangential(point, theta):
    """Beam-fixed tangential acceleration of a point (what a glued accelerometer reads)."""
    return point.diff(t, 2).dot(_tangent(theta))


@pytest.mark.parametrize("state", STATES)
def test_sensor_kinematics_exact(rig, state):
    """The rig's synthetic readings and the exact inversion follow from the positions."""
    p = rig.params
    params = _params(p)
    ga = _numeric(_tangential(A, th1), params, state)
    gb = _numeric(_tangential(B, th1), params, state)
    gc = _numeric(_tangential(C, th2), params, state)
    (t1, w1, a1), (t2, _, a2), (_, _, ax) = state
    th1dd, th2dd, x1dd = beam_accelerations_exact(p.geometry(), ga, gb, gc, t1, t2, w1)
    assert th1dd == pytest.approx(a1, rel=1e-10)
    assert th2dd == pytest.approx(a2, rel=1e-10)
    assert x1dd == pytest.approx(ax, rel=1e-10)


def test_paper_kinematics_are_the_linearisation():
    """(B.1), (B.2), (B.5) with the corrected (B.9) are the first-order terms of the exact
    readings, and (B.6), (B.10) invert them exactly."""
    eps = sp.symbols("epsilon")
    lin = {}
    for name, pt, th in (("A", A, th1), ("B", B, th1), ("C", C, th2)):
        expr = _tangential(pt, th)
        # scale every coordinate by eps and keep the first order
        subs = {}
        for q in Q:
            for k in (2, 1):
                subs[q.diff(t, k)] = eps * sp.Symbol(f"{q.func.__name__}_{k}")
            subs[q] = eps * sp.Symbol(f"{q.func.__name__}_0")
        e = expr.subs({k: v for k, v in subs.items() if isinstance(k, sp.Derivative)})
        e = e.subs({k: v for k, v in subs.items() if not isinstance(k, sp.Derivative)})
        lin[name] = sp.expand(sp.series(e, eps, 0, 2).removeO() / eps)
    a1s, a2s, axs = (sp.Symbol(f"{n}_2") for n in ("theta1", "theta2", "x1"))
    assert sp.simplify(lin["A"] - (axs + d1 * a1s)) == 0            # (B.1)
    assert sp.simplify(lin["B"] - (axs + d2 * a1s)) == 0            # (B.2)
    x2dd = axs + d3 * a1s + d5 * a2s                                # (B.9), corrected
    assert sp.simplify(lin["C"] - (x2dd + d4 * a2s)) == 0           # (B.5)
    # (B.6) and (B.10) invert them
    geom = JointRigGeometry(-0.09, 0.02, 0.091, 0.09, 0.091, 0.44, 1.5e-3)
    vals = {a1s: 310.0, a2s: -120.0, axs: 25.0, d1: geom.sensor_a, d2: geom.sensor_b,
            d3: geom.joint_arm1, d4: geom.sensor_c, d5: geom.joint_arm2}
    gam = [float(lin[k].subs(vals)) for k in ("A", "B", "C")]
    th1dd, th2dd, x1dd = beam_accelerations(geom, *gam)
    assert (th1dd, th2dd, x1dd) == pytest.approx((310.0, -120.0, 25.0), rel=1e-12)


def test_accelerometers_of_a_simulation_match_the_exact_kinematics(rig):
    """RigResponse.accelerometers equals the symbolic readings at the simulated states."""
    res = rig.simulate(2.0, periods=1.0, steps_per_period=64)
    tab = res.accelerometers(gravity_sensing=True)
    p = rig.params
    params = _params(p)
    k = 37
    state = [(res.q[k, i], res.v[k, i], res.a[k, i]) for i in range(3)]
    grav = {"A": p.gravity * np.sin(state[0][0]), "B": p.gravity * np.sin(state[0][0]),
            "C": p.gravity * np.sin(state[1][0])}  # proper acceleration, Z0 down
    for name, pt, th in (("A", A, th1), ("B", B, th1), ("C", C, th2)):
        ref = _numeric(_tangential(pt, th), params, state) + grav[name]
        assert tab[name][k] == pytest.approx(ref, rel=1e-10)
