"""Coulomb friction: paper 003 eq. (2), the set-valued law and the 1D penalty return map.

References: paper 003 eq. (2) (velocity-dependent mu); den Hartog / REFERENCES.md (Jenkins
loop W = 4 F (A - F/k)); the static/kinetic loop closed form derived in
``_static_kinetic_loop_energy`` below.
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.contact.coulomb import Coulomb, coulomb_force_set, friction_coefficient
from fricdamp.errors import ModelError
from fricdamp.signals.energy import loop_area

# ---------------------------------------------------------------- friction_coefficient


def test_friction_coefficient_matches_paper_form():
    """Paper 003 (2) written literally, mu_d [1 + (FACT - 1) exp(-DC v)], FACT = mu_s/mu_d.

    Same formula, different algebra: agreement to rounding (1e-15 relative).
    """
    mus, mud, dc = 0.4, 0.2, 4.0
    v = np.linspace(0.0, 3.0, 31)
    fact = mus / mud
    paper = mud * (1.0 + (fact - 1.0) * np.exp(-dc * v))
    np.testing.assert_allclose(friction_coefficient(v, mus, mud, dc), paper, rtol=1e-15)
    # odd force => even coefficient; limits mu_s at rest and mu_d at speed
    np.testing.assert_allclose(friction_coefficient(-v, mus, mud, dc), paper, rtol=1e-15)
    assert friction_coefficient(0.0, mus, mud, dc) == mus
    assert friction_coefficient(50.0, mus, mud, dc) == pytest.approx(mud, abs=1e-80)
    # at DC |v| = 1 the excess over mu_d has decayed by 1/e
    assert friction_coefficient(1 / dc, mus, mud, dc) == pytest.approx(mud + (mus - mud) / np.e,
                                                                       rel=1e-14)


def test_friction_coefficient_broadcasts_and_checks():
    mu = friction_coefficient(np.zeros((4, 1)), [0.3, 0.5], 0.1, 2.0)
    assert mu.shape == (4, 2)
    np.testing.assert_array_equal(mu[0], [0.3, 0.5])
    with pytest.raises(ModelError, match="decay"):
        friction_coefficient(0.0, 0.4, 0.2, -1.0)
    with pytest.raises(ModelError, match="mu_static"):
        friction_coefficient(0.0, -0.4, 0.2, 1.0)
    with pytest.raises(ModelError, match="v must be finite"):
        friction_coefficient(np.nan, 0.4, 0.2, 1.0)


# ---------------------------------------------------------------- set-valued law


def test_force_set_values_and_interval():
    fs = coulomb_force_set([-2.0, 0.0, 1e-12], 10.0, 0.3)
    np.testing.assert_allclose(fs.lower, [-3.0, -3.0, 3.0])
    np.testing.assert_allclose(fs.upper, [-3.0, 3.0, 3.0])
    # with mu(v) from eq. (2): the stick interval is the static one, sliding uses mu(v)
    v = np.array([0.0, 0.25])
    fs = coulomb_force_set(v, 10.0, friction_coefficient(v, 0.4, 0.2, 4.0))
    np.testing.assert_allclose([fs.lower[0], fs.upper[0]], [-4.0, 4.0])
    np.testing.assert_allclose(fs.lower[1], 2.0 * (1 + np.exp(-1.0)), rtol=1e-14)
    with pytest.raises(ModelError, match="normal_load"):
        coulomb_force_set(0.0, -1.0, 0.3)
    with pytest.raises(ModelError, match="mu"):
        coulomb_force_set(0.0, 1.0, -0.3)


def test_penalty_law_slip_force_is_set_valued_law():
    """Wherever the penalty law slips its force is the set-valued law's single value at v;
    everywhere it stays within the static interval. Rounding-level tolerance (1e-12 N)."""
    N, mus, mud, dc = 10.0, 0.4, 0.2, 4.0
    t = np.linspace(0.0, 2.0, 4001)
    om = 2 * np.pi * 1.5
    u, v = 0.02 * np.sin(om * t), 0.02 * om * np.cos(om * t)
    law = Coulomb(1e5, N, mus, mud, dc)
    st = law.initial_state()
    n_slip = n_against = 0
    for i in range(t.size):
        r = law.step(st, [u[i]], [v[i]])
        st = r.state
        f = r.force[0, 0]
        assert abs(f) <= mus * N + 1e-12
        if st[0, 1] == 1.0:
            n_slip += 1
            fs = coulomb_force_set(v[i], N, friction_coefficient(v[i], mus, mud, dc))
            assert abs(f) == pytest.approx(abs(fs.lower[()]), abs=1e-12)
            # the slip direction comes from the sampled displacement: at a sample just
            # past a velocity reversal u may still be moving the old way
            n_against += int(np.sign(f) != np.sign(v[i]))
    assert n_slip > t.size // 2  # gross slip most of the time: the check is not vacuous
    assert n_against <= 6        # at most one sample at each of the 6 reversals


# ---------------------------------------------------------------- the return map


def test_constant_mu_reduces_to_jenkins():
    """mu_s = mu_d, decay = 0: exactly the Jenkins element (same operations, 1e-14 N)."""
    rng = np.random.default_rng(1)
    u = np.cumsum(rng.normal(scale=5e-4, size=(500, 3)), axis=0)
    kt, N, mu = np.array([1e3, 2e3, 5e3]), np.array([5.0, 2.0, 10.0]), 0.3
    f_c = Coulomb(kt, N, mu).drive(u)
    f_j = Jenkins(kt, mu * N).drive(u)
    np.testing.assert_allclose(f_c, f_j, rtol=0, atol=1e-14)


def test_step_matches_compiled_march():
    law = Coulomb([1e3, 4e3], [10.0, 5.0], [0.4, 0.3], [0.2, 0.3], [4.0, 0.0])
    rng = np.random.default_rng(0)
    v = rng.normal(scale=0.2, size=(400, 2, 1))
    u = np.cumsum(v * 0.01, axis=0)
    f_march, st_march = law.march(u, v_history=v)
    st = law.initial_state()
    n_slip = 0
    for i in range(u.shape[0]):
        r = law.step(st, u[i], v[i])
        st = r.state
        n_slip += int(st[:, 1].sum())
        np.testing.assert_allclose(r.force, f_march[i], rtol=0, atol=1e-13)
    np.testing.assert_allclose(st, st_march, rtol=0, atol=1e-15)
    assert 50 < n_slip < 750  # both stick and slip visited


def _prepared(kind):
    """A law and a state in stick or in slip (with decay so that dF/dv != 0)."""
    law = Coulomb(1e3, 10.0, 0.4, 0.2, 4.0)
    st = law.initial_state()
    if kind == "stuck":
        return law, st, 1e-3, 0.1            # |f| = 1 N < mu_s N = 4 N
    if kind == "breakaway":
        return law, st, 6e-3, 0.3            # 6 N > 4 N: breaks away this step
    # keep sliding at v = 0.3 m/s: the slider sits at u - mu(v) N / k_t
    st = law.step(st, [6e-3], [0.3]).state
    assert st[0, 1] == 1.0
    return law, st, 6.5e-3, 0.3


@pytest.mark.parametrize("kind", ["stuck", "breakaway", "sliding"])
def test_tangents_match_finite_differences(kind):
    """Central differences, h = 1e-9 m and 1e-7 m/s: the map is piecewise linear in u and
    smooth in v away from the switches, so agreement to 1e-6 relative."""
    law, st, u0, v0 = _prepared(kind)
    r = law.step(st, [u0], [v0])
    hu, hv = 1e-9, 1e-7
    dfdu = (law.step(st, [u0 + hu], [v0]).force - law.step(st, [u0 - hu], [v0]).force) / (2 * hu)
    dfdv = (law.step(st, [u0], [v0 + hv]).force - law.step(st, [u0], [v0 - hv]).force) / (2 * hv)
    np.testing.assert_allclose(r.stiffness[0, 0, 0], dfdu[0, 0], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(r.damping[0, 0, 0], dfdv[0, 0], rtol=1e-6, atol=1e-9)
    if kind == "stuck":
        assert r.stiffness[0, 0, 0] == 1e3 and r.damping[0, 0, 0] == 0.0
    else:  # velocity weakening: dF/dv = -N (mu_s - mu_d) DC exp(-DC v) < 0
        assert r.damping[0, 0, 0] == pytest.approx(-10.0 * 0.2 * 4.0 * np.exp(-1.2), rel=1e-14)


def test_breakaway_at_static_limit_then_kinetic_force():
    """Monotone loading from rest: f = k u up to mu_s N, then the force drops to mu_d N."""
    law = Coulomb(1e3, 10.0, 0.4, 0.2)   # F_s = 4 N, F_d = 2 N
    u = np.array([0.0, 1e-3, 3.9e-3, 4.0e-3, 4.1e-3, 6e-3])
    f = law.drive(u)
    np.testing.assert_allclose(f, [0.0, 1.0, 3.9, 4.0, 2.0, 2.0], rtol=1e-12)


def test_restick_on_unloading_then_static_threshold_again():
    law = Coulomb(1e3, 10.0, 0.4, 0.2)   # F_s = 4 N, F_d = 2 N
    st = law.step(law.initial_state(), [8e-3]).state       # slipping, f = 2 N, w = 6e-3
    assert st[0, 1] == 1.0 and st[0, 0] == pytest.approx(6e-3)
    r = law.step(st, [7.5e-3])                              # unload by 0.5 mm
    assert r.force[0, 0] == pytest.approx(1.5) and r.state[0, 1] == 0.0
    assert r.stiffness[0, 0, 0] == 1e3
    # reversed loading: stuck until -F_s = -4 N (u = 2e-3), then slides at -F_d
    assert law.step(r.state, [2.0e-3]).force[0, 0] == pytest.approx(-4.0)
    assert law.step(r.state, [1.9e-3]).force[0, 0] == pytest.approx(-2.0)


def _static_kinetic_loop_energy(A, k, F_s, F_d):
    """Energy per cycle of the spring-slider with break-away F_s and sliding force F_d.

    Descending branch from (A, F_d): stick line f = F_d - k (A - u) down to f = -F_s at
    u_b = A - L, L = (F_s + F_d)/k, drop to -F_d, slide to -A; the ascending branch is its
    point reflection. W = -2 int_{-A}^{A} f_down du = 4 F_d A - 4 F_d L + k L^2
    = 4 F_d A - (3 F_d^2 + 2 F_d F_s - F_s^2)/k  (F_s = F_d = F: 4 F (A - F/k)).
    """
    return 4 * F_d * A - (3 * F_d**2 + 2 * F_d * F_s - F_s**2) / k


def test_static_kinetic_loop_closed_form():
    """Harmonic u = A cos(theta), n samples per cycle. The drop to F_d happens at the first
    sample past u_b and the trapezoidal rule spreads it over one step: each of the two drops
    per cycle errs by at most du_max (F_s - F_d + k du_max), du_max = A 2 pi / n."""
    k, N, mus, mud, A, n = 1e3, 10.0, 0.4, 0.2, 5e-3, 20000
    theta = np.linspace(0.0, 4 * np.pi, 2 * n + 1)
    u = A * np.cos(theta)
    f = Coulomb(k, N, mus, mud).drive(u)
    W = loop_area(u[n:], f[n:])
    du = A * 2 * np.pi / n
    bound = 2 * du * ((mus - mud) * N + k * du)
    W_exact = _static_kinetic_loop_energy(A, k, mus * N, mud * N)
    assert abs(W - W_exact) <= bound
    assert bound < 1e-3 * W_exact        # the check is sharp against the 0.4 % effect of F_s
    assert abs(W_exact - 4 * mud * N * (A - mud * N / k)) > 10 * bound


def test_velocity_dependent_loop_at_constant_speed():
    """Triangle wave at speed V: while sliding mu = mu(V) (paper 003 (2)), so the loop is the
    static/kinetic one with F_d = mu(V) N. Same error bound as above."""
    k, N, mus, mud, dc, A, V = 1e3, 10.0, 0.4, 0.2, 4.0, 5e-3, 0.1
    n = 20000                                        # samples per cycle
    s = np.arange(2 * n + 1) / n                     # cycles
    phase = np.mod(s, 1.0)
    u = A * (1 - 4 * np.minimum(phase, 1 - phase))   # A at integer s, -A at half-integer
    v = np.empty_like(u)
    v[1:] = V * np.sign(np.diff(u))                  # backward difference: arrival velocity
    v[0] = V
    law = Coulomb(k, N, mus, mud, dc)
    f = law.drive(u, v_history=v)
    W = loop_area(u[n:], f[n:])
    F_d = float(friction_coefficient(V, mus, mud, dc)) * N
    du = 4 * A / n
    bound = 2 * du * ((mus * N - F_d) + k * du)
    assert abs(W - _static_kinetic_loop_energy(A, k, mus * N, F_d)) <= bound
    np.testing.assert_allclose(np.abs(f).max(), mus * N, rtol=0, atol=k * du)


def test_stored_energy_gradient_is_force_in_stick():
    law = Coulomb(2e3, 10.0, 0.4, 0.2)
    st = law.step(law.initial_state(), [5e-3]).state       # slipped: w = 4e-3
    u0, h = 4.6e-3, 1e-8
    f = law.step(st, [u0]).force[0, 0]
    dE = (law.stored_energy(st, [u0 + h]) - law.stored_energy(st, [u0 - h])) / (2 * h)
    assert dE[0] == pytest.approx(f, rel=1e-7)
    assert law.stored_energy(st, [4e-3])[0] == 0.0


@pytest.mark.parametrize(
    "kwargs, word",
    [({"stiffness": 0.0, "normal_load": 1.0, "mu_static": 0.3}, "stiffness"),
     ({"stiffness": 1.0, "normal_load": -1.0, "mu_static": 0.3}, "normal_load"),
     ({"stiffness": 1.0, "normal_load": 1.0, "mu_static": -0.3}, "mu_static"),
     ({"stiffness": 1.0, "normal_load": 1.0, "mu_static": 0.3, "mu_sliding": 0.5},
      "mu_sliding must be <= mu_static"),
     ({"stiffness": 1.0, "normal_load": 1.0, "mu_static": 0.3, "decay": -2.0}, "decay"),
     ({"stiffness": [1.0, 2.0], "normal_load": [1.0, 2.0, 3.0], "mu_static": 0.3},
      "inconsistent")],
)
def test_bad_parameters_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        Coulomb(**kwargs)


def test_velocity_required_when_velocity_dependent():
    law = Coulomb(1e3, 1.0, 0.4, 0.2, decay=4.0)
    assert law.velocity_dependent
    assert not Coulomb(1e3, 1.0, 0.4, 0.2).velocity_dependent
    with pytest.raises(ModelError, match="v .relative velocity"):
        law.step(law.initial_state(), [0.0])
    with pytest.raises(ModelError, match="v .relative velocity"):
        law.march(np.zeros((3, 1, 1)))
