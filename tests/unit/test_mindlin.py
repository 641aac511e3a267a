"""Unit checks of the Cattaneo–Mindlin laws: helpers, protocol, tangent, Masing memory, energy.

Closed forms: Johnson, Contact Mechanics (1985) §4.2, §7.2–7.3; Mindlin & Deresiewicz (1953);
REFERENCES.md. Paper 002 (12)–(14), (17)–(23).
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.contact.mindlin import (
    CattaneoMindlin,
    RotationalMindlin,
    cm_iwan,
    effective_modulus,
    hertz_radius,
    shear_modulus,
    tangential_compliance,
)
from fricdamp.errors import ModelError

MU, N, A, C = 0.3, 50.0, 2e-4, 4.2e-11  # slip force 15 N, delta_s = 3 mu N C/(16 a)
F = MU * N
DS = 3 * MU * N * C / (16 * A)


def virgin(x):
    """Virgin curve T(delta), Johnson (7.43) / paper 002 (17) with G* = C."""
    return np.sign(x) * F * (1 - (1 - np.minimum(np.abs(x) / DS, 1)) ** 1.5)


def branch(x, xr, tr, s):
    """Masing branch from the turning point (xr, tr) in direction s (Mindlin-Deresiewicz)."""
    y = np.clip(s * (x - xr) / (2 * DS), 0, 1)
    return tr + 2 * s * F * (1 - (1 - y) ** 1.5)


def law(**kw):
    return CattaneoMindlin(MU, N, A, C, **kw)


def random_history(rng, n_legs=120, scale=2.5, pts=(2, 30)):
    x = [0.0]
    for _ in range(n_legs):
        amp = rng.uniform(0, scale) * DS
        x.extend(np.linspace(x[-1], rng.uniform(-1, 1) * amp, rng.integers(*pts))[1:])
    return np.array(x)


# ----------------------------------------------------------------------------- helpers
def test_material_helpers_closed_forms():
    E, nu = 210e9, 0.3
    G = E / (2 * (1 + nu))
    assert shear_modulus(E, nu) == pytest.approx(G, rel=1e-15)
    # identical bodies: E* = E / (2 (1 - nu^2)); rigid flat: E* = E / (1 - nu^2)
    assert effective_modulus(E, nu, E, nu) == pytest.approx(E / (2 * (1 - nu**2)), rel=1e-15)
    assert effective_modulus(E, nu, np.inf, 0.3) == pytest.approx(E / (1 - nu**2), rel=1e-15)
    assert tangential_compliance(G, nu, G, nu) == pytest.approx(2 * (2 - nu) / G, rel=1e-15)
    assert tangential_compliance(G, nu, np.inf, nu) == pytest.approx((2 - nu) / G, rel=1e-15)


def test_hertz_radius_consistent_with_paper_002_eq_12_13():
    """002 (12)-(13): N = 4/3 E* R^1/2 d^3/2 and a = (R d)^1/2 imply a = (3NR/4E*)^1/3."""
    R, Es = 50e-6, 115e9
    d = np.array([1e-9, 1e-7, 3e-6])
    n_load = 4 / 3 * Es * np.sqrt(R) * d**1.5
    np.testing.assert_allclose(hertz_radius(n_load, R, Es), np.sqrt(R * d), rtol=1e-14)
    assert isinstance(hertz_radius(1.0, R, Es), float)


@pytest.mark.parametrize(
    "call, word",
    [(lambda: effective_modulus(-1.0, 0.3, 1.0, 0.3), "E1"),
     (lambda: effective_modulus(1.0, 0.7, 1.0, 0.3), "nu1"),
     (lambda: effective_modulus(np.inf, 0.3, np.inf, 0.3), "rigid"),
     (lambda: tangential_compliance(1.0, 0.3, 0.0, 0.3), "G2"),
     (lambda: hertz_radius(1.0, -1.0, 1.0), "radius"),
     (lambda: CattaneoMindlin(-0.1, N, A, C), "mu"),
     (lambda: CattaneoMindlin(MU, np.nan, A, C), "normal_load"),
     (lambda: CattaneoMindlin(MU, N, 0.0, C), "contact_radius"),
     (lambda: CattaneoMindlin(MU, N, A, 0.0), "compliance"),
     (lambda: CattaneoMindlin(MU, N, A, C, multiplicity=0.0), "multiplicity"),
     (lambda: CattaneoMindlin(MU, N, A, C, memory=3), "memory"),
     (lambda: CattaneoMindlin([MU, MU], N, [A, A, A], C), "inconsistent"),
     (lambda: RotationalMindlin(MU, N, A, C, arm=-1.0), "arm"),
     (lambda: RotationalMindlin(MU, [N, N], A, C, arm=[1.0, 2.0, 3.0]), "inconsistent")],
)
def test_bad_parameters_named(call, word):
    with pytest.raises(ModelError, match=word):
        call()


def test_state_shape_checked():
    with pytest.raises(ModelError, match="state"):
        law().step(np.zeros((1, 3)), [0.0])


# ----------------------------------------------------------------------------- protocol
def test_step_matches_compiled_march():
    cm = CattaneoMindlin([MU, 0.5, 0.0], [N, 20.0, N], [A, 1e-4, A], C, memory=6)
    rng = np.random.default_rng(0)
    x = random_history(rng, n_legs=60)
    u = np.stack([x, 0.7 * x, x], axis=1)[:, :, None]
    f_march, st_march = cm.march(u)
    st = cm.initial_state()
    for i in range(u.shape[0]):
        r = cm.step(st, u[i])
        st = r.state
        np.testing.assert_allclose(r.force, f_march[i], rtol=0, atol=1e-13)
    np.testing.assert_array_equal(st, st_march)
    assert np.all(f_march[:, 2] == 0.0)  # mu = 0: frictionless contact


def test_step_does_not_mutate_given_state():
    cm = law()
    st = cm.step(cm.initial_state(), [0.3 * DS]).state
    before = st.copy()
    cm.step(st, [-0.2 * DS])
    np.testing.assert_array_equal(st, before)


@pytest.mark.parametrize("path", [
    [0.4],                 # virgin curve
    [0.8, 0.1],            # unloading branch
    [0.8, -0.3, 0.2],      # nested reloading branch
    [0.9, -0.95, 0.6, 0.0],  # deeper nesting
    [1.5, 0.2],            # branch from a gross-slip point
])
def test_tangent_matches_finite_difference(path):
    cm = law()
    st = cm.initial_state()
    for x in path[:-1]:
        st = cm.step(st, [x * DS]).state
    prev = path[-2] if len(path) > 1 else 0.0
    # evaluate a bit beyond the last point, continuing in the same direction
    x0 = (path[-1] + 0.05 * np.sign(path[-1] - prev)) * DS
    st = cm.step(st, [path[-1] * DS]).state
    h = 1e-7 * DS
    r = cm.step(st, [x0])
    fd = (cm.step(st, [x0 + h]).force - cm.step(st, [x0 - h]).force) / (2 * h)
    # central difference error ~ h^2 f''' / 6 ~ 1e-14 relative: 1e-7 leaves room for rounding
    np.testing.assert_allclose(r.stiffness[:, :, 0], fd, rtol=1e-7)


def test_tangent_at_rest_is_initial_stiffness_and_zero_in_gross_slip():
    cm = law()
    r = cm.step(cm.initial_state(), [0.0])
    assert r.stiffness[0, 0, 0] == pytest.approx(8 * A / C, rel=1e-14)
    assert cm.initial_stiffness[0] == pytest.approx(8 * A / C, rel=1e-14)
    r = cm.step(cm.step(cm.initial_state(), [2 * DS]).state, [2.5 * DS])
    assert r.stiffness[0, 0, 0] == 0.0
    assert r.force[0, 0] == pytest.approx(F, rel=1e-15)


# ----------------------------------------------------------------------------- Masing memory
def test_virgin_curve_and_gross_slip():
    x = np.linspace(-2 * DS, 2 * DS, 81)
    for xi in x:  # every point from the virgin state (one monotone step)
        f = law().drive(np.array([0.0, xi]))[1]
        assert f == pytest.approx(virgin(xi), rel=1e-13, abs=1e-13 * F)


def test_unloading_from_gross_slip_reaches_opposite_slip_after_two_delta_s():
    x = np.concatenate([np.linspace(0, 1.5 * DS, 50), np.linspace(1.5 * DS, -1.5 * DS, 301)])
    f = law().drive(x)
    down = x[50:]
    np.testing.assert_allclose(f[50:], branch(down, 1.5 * DS, F, -1), rtol=0, atol=1e-12 * F)
    assert f[-1] == pytest.approx(-F, rel=1e-15)


def test_memory_rule_inner_loop_closes_and_rejoins_outer_curves():
    """Mindlin-Deresiewicz: after an inner loop the contact returns onto the older branch."""
    x1, x2, x3 = 0.7 * DS, -0.2 * DS, 0.4 * DS
    legs = [np.linspace(0, x1, 40), np.linspace(x1, x2, 60)[1:], np.linspace(x2, x3, 40)[1:],
            np.linspace(x3, -0.9 * DS, 120)[1:], np.linspace(-0.9 * DS, 0.95 * DS, 200)[1:]]
    x = np.concatenate(legs)
    f = law().drive(x)
    t1 = virgin(x1)
    t2 = branch(x2, x1, t1, -1)
    t3 = branch(x3, x2, t2, +1)
    expect = np.empty_like(x)
    i = 0
    for leg, fn in zip(legs, [
            virgin,
            lambda z: branch(z, x1, t1, -1),
            lambda z: branch(z, x2, t2, +1),
            # from x3 down: inner branch until x2, then the branch from x1, then past -x1
            # the virgin curve (memory erased twice)
            lambda z: np.where(z > x2, branch(z, x3, t3, -1),
                               np.where(z > -x1, branch(z, x1, t1, -1), virgin(z))),
            # final reload from -0.9 DS: past +0.9 DS it rejoins the virgin curve
            lambda z: np.where(z < 0.9 * DS, branch(z, -0.9 * DS, virgin(-0.9 * DS), +1),
                               virgin(z))], strict=True):
        expect[i:i + leg.size] = fn(leg)
        i += leg.size
    np.testing.assert_allclose(f, expect, rtol=0, atol=1e-12 * F)


def test_sinusoid_steady_state_uses_simple_masing_rule():
    """After the first quarter cycle the loop is the simple Masing loop (REFERENCES.md)."""
    q = 0.6
    amp = DS * (1 - (1 - q) ** (2 / 3))
    th = np.linspace(0, 6 * np.pi, 1201)
    x = amp * np.cos(th)
    f = law().drive(x)
    tstar = q * F
    down = np.sin(th) >= 0
    expect = np.where(down, branch(x, amp, tstar, -1), branch(x, -amp, -tstar, +1))
    np.testing.assert_allclose(f, expect, rtol=0, atol=1e-12 * F)


def test_overflowing_memory_keeps_current_loop_and_outer_envelope():
    """A slow free decay overflows a 4-point stack; the current loop stays the exact Masing
    loop and a final large excursion rejoins the virgin curve (outermost memory kept)."""
    t = np.linspace(0, 40 * 2 * np.pi, 40 * 200 + 1)
    x = 0.9 * DS * np.exp(-t / 80) * np.cos(t)
    ramp = x[-1] + (0.95 * DS - x[-1]) * np.linspace(0, 1, 400)[1:]
    cm = law(memory=4)
    f, st = cm.march(np.concatenate([x, ramp])[:, None, None])
    f = f[:, 0, 0]
    assert st[0, 2] <= 4
    # second-to-last peak (t = 39 periods, sample index len(t) - 201): branch exact
    i_peak = len(t) - 201
    assert x[i_peak] == pytest.approx(x[i_peak - 100:i_peak + 100].max(), rel=1e-15)
    seg = slice(i_peak, i_peak + 80)
    np.testing.assert_allclose(f[seg], branch(x[seg], x[i_peak], f[i_peak], -1), rtol=0,
                               atol=1e-12 * F)
    assert f[-1] == pytest.approx(virgin(0.95 * DS), rel=1e-12)


# ----------------------------------------------------------------------------- energy
def test_iwan_representation_reproduces_masing_force():
    """The stored-energy model (Iwan continuum) gives back the Masing force exactly."""
    cm = law(memory=64)
    x = random_history(np.random.default_rng(3), n_legs=200)
    st = cm.initial_state()
    err = 0.0
    for xi in x[1:]:
        r = cm.step(st, [xi])
        st = r.state
        assert st[0, 2] < 64  # no overflow: the representation is exact
        f_iwan, _ = cm_iwan(st[0], xi, cm.slip_force[0], DS, cm.memory)
        err = max(err, abs(f_iwan - r.force[0, 0]))
    assert err < 1e-12 * F  # closed-form segment integrals, rounding only


def test_stored_energy_matches_discrete_iwan_of_jenkins_elements():
    """Independent check: 4000 Jenkins elements with slip displacements z_i delta_s,
    z = 1 - u^2 (u uniform: the density (3/4)(1-z)^-1/2 dz = 1.5 du), stiffness
    1.5 F/(delta_s n). Midpoint rule in u: force and energy agree to O(1/n^2) ~ 1e-7."""
    n = 4000
    u_mid = (np.arange(n) + 0.5) / n
    z = 1 - u_mid**2
    k = 1.5 * F / (DS * n)
    jk = Jenkins(np.full(n, k), k * z * DS)
    cm = law()
    x = random_history(np.random.default_rng(5), n_legs=25, pts=(2, 8))
    fj, stj = jk.march(np.repeat(x[:, None, None], n, axis=1))
    fc, stc = cm.march(x[:, None, None])
    np.testing.assert_allclose(fj[:, :, 0].sum(axis=1), fc[:, 0, 0], rtol=0, atol=2e-6 * F)
    e_j = jk.stored_energy(stj, np.full((n, 1), x[-1])).sum()
    e_c = cm.stored_energy(stc, [x[-1]])[0]
    assert e_c == pytest.approx(e_j, rel=1e-5, abs=1e-7 * F * DS)


def test_dissipation_non_negative_at_every_step_and_virgin_split():
    cm = law()
    rng = np.random.default_rng(7)
    legs = [np.linspace(0.0, 0.6 * DS, 400)]
    for _ in range(40):
        legs.append(np.linspace(legs[-1][-1], rng.uniform(-1.6, 1.6) * DS, 400)[1:])
    x = np.concatenate(legs)
    st = cm.initial_state()
    f = np.zeros_like(x)
    e = np.zeros_like(x)
    for i in range(1, x.size):
        st = cm.step(st, [x[i]]).state
        f[i] = st[0, 4]
        e[i] = cm.stored_energy(st, [x[i]])[0]
    work = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(x))])
    dd = np.diff(work - e)
    # trapezoid error per step <= dx^3 max|f''| / 12; steps are ~DS/250 here
    assert dd.min() > -1e-9 * F * DS
    assert work[-1] - e[-1] > 0


def test_virgin_loading_to_gross_slip_energy_split():
    """Iwan split at gross slip: work 0.6 F ds = stored 0.4 F ds + dissipated 0.2 F ds."""
    cm = law()
    st = cm.step(cm.initial_state(), [DS]).state
    assert cm.stored_energy(st, [DS])[0] == pytest.approx(0.4 * F * DS, rel=1e-14)
    st0 = cm.initial_state()
    assert cm.stored_energy(st0, [0.0])[0] == 0.0
    # small displacement: elastic, E = k0 x^2 / 2
    x = 1e-6 * DS
    st = cm.step(st0, [x]).state
    assert cm.stored_energy(st, [x])[0] == pytest.approx(0.5 * 8 * A / C * x**2, rel=1e-5)


def test_multiplicity_scales_force_stiffness_energy():
    x = random_history(np.random.default_rng(2), n_legs=10)
    one, many = law(), law(multiplicity=7.5)
    f1, s1 = one.march(x[:, None, None])
    f7, s7 = many.march(x[:, None, None])
    np.testing.assert_allclose(f7, 7.5 * f1, rtol=1e-14)
    assert many.stored_energy(s7, [x[-1]])[0] == pytest.approx(
        7.5 * one.stored_energy(s1, [x[-1]])[0], rel=1e-13)


# ----------------------------------------------------------------------------- rotation
def test_rotational_law_is_paper_002_eq_21_22():
    """002 (21): M = r mu N (1 - (1 - 16 a r theta/(3 mu N G*))^3/2) with G* = C; (22) with
    the exponent 2/3 on (1 - T_max/mu N) (printed 3/2 in the extracted text)."""
    r = 8e-3
    rot = RotationalMindlin(MU, N, A, C, arm=r)
    th_s = DS / r
    tmax_q = 0.7
    th_max = th_s * (1 - (1 - tmax_q) ** (2 / 3))
    th = np.concatenate([np.linspace(0, th_max, 100), np.linspace(th_max, -th_max, 200)[1:]])
    m = rot.drive(th)
    xx = 16 * A * r * th / (3 * MU * N * C)
    m21 = r * MU * N * (1 - (1 - xx) ** 1.5)
    np.testing.assert_allclose(m[:100], m21[:100], rtol=0, atol=1e-12 * r * F)
    rtm = r * tmax_q * F  # (r T)_max
    m22 = 2 * r * MU * N * ((0.5 * (xx + (1 - tmax_q) ** (2 / 3) + 1)) ** 1.5 - 1) + rtm
    np.testing.assert_allclose(m[99:], m22[99:], rtol=0, atol=1e-12 * r * F)
    # the printed exponent 3/2 does not even start at the turning point
    wrong = 2 * r * MU * N * ((0.5 * (xx[99] + (1 - tmax_q) ** 1.5 + 1)) ** 1.5 - 1) + rtm
    assert abs(wrong - m[99]) > 0.05 * r * F


def test_rotational_law_is_arm_times_translational():
    r = np.array([2e-3, 9e-3])
    rot = RotationalMindlin(MU, N, A, C, arm=r)
    tr = CattaneoMindlin(MU, N, A, C, n_contacts=2)
    th = 0.5 * DS / 2e-3 * np.sin(np.linspace(0, 5 * np.pi, 300))[:, None] * np.ones(2)
    m, st_r = rot.march(th[:, :, None])
    f, st_t = tr.march((th * r)[:, :, None])
    np.testing.assert_allclose(m[:, :, 0], f[:, :, 0] * r, rtol=1e-15)
    res_r = rot.step(st_r, th[-1] * 1.001)
    res_t = tr.step(st_t, th[-1] * 1.001 * r)
    np.testing.assert_allclose(res_r.stiffness[:, 0, 0], res_t.stiffness[:, 0, 0] * r**2,
                               rtol=1e-14)
    np.testing.assert_allclose(rot.stored_energy(st_r, th[-1]),
                               tr.stored_energy(st_t, th[-1] * r), rtol=1e-14)
    np.testing.assert_allclose(rot.slip_moment, r * F, rtol=1e-15)


def test_periodic_history_state_repeats_exactly():
    """Sampled off its peaks, a two-harmonic periodic history nests turning points; after
    the first period the state (stack with unused slots zeroed) repeats bit for bit, so a
    periodicity test (AFT) stops after two periods."""
    t = np.arange(64) / 64 * 2 * np.pi + 0.1
    u = (0.5 * DS * np.cos(t) + 0.2 * DS * np.sin(3 * t))[:, None, None]
    cm = law()
    _, s1 = cm.march(u)
    f2, s2 = cm.march(u, state=s1)
    f3, s3 = cm.march(u, state=s2)
    assert s1[0, 2] >= 1
    np.testing.assert_array_equal(s2, s3)
    np.testing.assert_array_equal(f2, f3)
