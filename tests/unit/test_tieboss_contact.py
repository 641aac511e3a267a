"""Contact3D with static/kinetic friction and the velocity-dependent coefficient 003 (2).

References: paper 003 eq. (2) (mu = mu_d (1 + (FACT - 1) exp(-DC v)), mu_s = 0.4, mu_d = 0.2,
DC = 4 s/m); the 1D law :class:`fricdamp.contact.coulomb.Coulomb`, which the 3D element must
reproduce exactly for motion along one tangential axis at constant normal load.
"""

import numpy as np
import pytest

from fricdamp.contact.coulomb import Coulomb, friction_coefficient
from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ModelError

KN, KT = 2e5, 1e5
MUS, MUD, DC = 0.4, 0.2, 4.0


def _law(n=1, **kw):
    args = {"offset": 1e-5, "mu_sliding": MUD, "decay": DC, "n_contacts": n} | kw
    return Contact3D(KN, KT, MUS, **args)


def _history(n_t=1500, n_c=3, seed=0, sep=True):
    """Random walk (u_n, u_t1, u_t2) that opens now and then, with its velocities."""
    rng = np.random.default_rng(seed)
    u = np.cumsum(rng.normal(scale=[2e-6, 3e-6, 3e-6], size=(n_t, n_c, 3)), axis=0)
    u[:, :, 0] -= u[:, :, 0].mean(axis=0)
    if not sep:
        u[:, :, 0] = np.abs(u[:, :, 0]) * 0.1
    v = rng.normal(scale=0.2, size=(n_t, n_c, 3))          # independent speeds [m/s]
    return u, v


def test_constant_mu_law_and_state_unchanged():
    """Without mu_sliding (or with mu_sliding == mu) the law is the original one: 2 state
    columns, no velocity dependence, identical forces on a random path."""
    u, v = _history()
    base = Contact3D(KN, KT, 0.3, offset=1e-5, n_contacts=3)
    same = Contact3D(KN, KT, 0.3, offset=1e-5, mu_sliding=0.3, decay=4.0, n_contacts=3)
    for law in (base, same):
        assert law.n_state == 2 and not law.kinetic and not law.velocity_dependent
    f0, w0 = base.march(u)
    f1, w1 = same.march(u, v_history=v)
    np.testing.assert_array_equal(f0, f1)
    np.testing.assert_array_equal(w0, w1)


@pytest.mark.parametrize("decay", [0.0, DC])
def test_reduces_to_1d_coulomb_law(decay):
    """Closed contact at constant N, motion along a fixed tangential axis e: the tangential
    force along e equals Coulomb(k_t, N, mu_s, mu_d, DC) driven by (u.e, v.e), exactly (the
    same return map), and nothing acts across e."""
    N0 = 2.0
    law = Contact3D.from_preload(KN, N0, KT, MUS, mu_sliding=MUD, decay=decay)
    th = np.linspace(0, 8 * np.pi, 3001)
    s = 2e-5 * np.sin(th) * (1 + 0.5 * np.sin(0.3 * th))
    sv = np.gradient(s, th) * 300.0                     # a velocity history [m/s]
    e = np.array([np.cos(0.4), np.sin(0.4)])
    u = np.zeros((th.size, 3))
    v = np.zeros((th.size, 3))
    u[:, 1:] = s[:, None] * e
    v[:, 1:] = sv[:, None] * e
    f = law.drive(u, v_history=v)
    ref = Coulomb(KT, N0, MUS, MUD, decay).drive(s, v_history=sv)
    np.testing.assert_allclose(f[:, 1:] @ e, ref, rtol=0, atol=1e-12)
    np.testing.assert_allclose(f[:, 1:] @ [-e[1], e[0]], 0.0, atol=1e-12)
    np.testing.assert_allclose(f[:, 0], N0, rtol=1e-14)
    assert np.abs(ref).max() > 0.99 * MUS * N0 * 0.5     # friction actually engaged


def test_break_away_then_kinetic_level_then_restick():
    """Stuck up to mu_s N, then the force drops to mu(v) N (003 (2)); a slipping contact
    that unloads re-sticks and must reach mu_s N again to break away."""
    law = _law()
    N0 = KN * 1e-5                                       # 2 N
    st = law.initial_state()
    v = np.array([[0.0, 0.1, 0.0]])
    r = law.step(st, [[0.0, 0.79e-5, 0.0]], v)          # 0.79 N < mu_s N = 0.8 N
    assert r.force[0, 1] == pytest.approx(0.79) and r.state[0, 2] == 0.0
    r = law.step(r.state, [[0.0, 0.81e-5, 0.0]], v)     # break away
    mu_v = MUD + (MUS - MUD) * np.exp(-DC * 0.1)
    assert r.force[0, 1] == pytest.approx(mu_v * N0, rel=1e-12) and r.state[0, 2] == 1.0
    r = law.step(r.state, [[0.0, 0.70e-5, 0.0]], v)     # unload: re-stick
    assert r.state[0, 2] == 0.0 and r.force[0, 1] < mu_v * N0
    f_prev = r.force[0, 1]
    r2 = law.step(r.state, [[0.0, 0.70e-5 + (MUS * N0 - f_prev) / KT * 0.99, 0.0]], v)
    assert r2.state[0, 2] == 0.0                        # still stuck just below mu_s N
    assert r2.force[0, 1] > mu_v * N0


def test_sliding_coefficient_is_003_eq2():
    law = _law(n=4)
    v = np.array([0.0, 0.05, 0.25, 2.0])
    np.testing.assert_allclose(law.sliding_coefficient(v),
                               friction_coefficient(v, MUS, MUD, DC), rtol=1e-15)
    vv = np.zeros((4, 3))
    vv[:, 1], vv[:, 2] = 0.6 * v, 0.8 * v                # |v_t| = v; normal part ignored
    vv[:, 0] = 7.0
    np.testing.assert_allclose(law.sliding_coefficient(vv),
                               friction_coefficient(v, MUS, MUD, DC), rtol=1e-14)


def test_step_matches_compiled_march_all_branches():
    law = Contact3D([KN, 2 * KN, KN], [KT, KT, 3 * KT], [0.4, 0.3, 0.5], offset=[1e-5, 5e-6, 2e-5],
                    mu_sliding=[0.2, 0.3, 0.1], decay=[4.0, 4.0, 0.0])
    u, v = _history()
    f_m, st_m = law.march(u, v_history=v)
    st = law.initial_state()
    codes = set()
    breakaway = 0
    for i in range(u.shape[0]):
        r = law.step(st, u[i], v[i])
        np.testing.assert_allclose(r.force, f_m[i], rtol=0, atol=1e-12)
        code = law.contact_status(r.state, r.force)
        codes |= set(code.tolist())
        breakaway += int(np.sum((st[:, 2] == 0) & (r.state[:, 2] == 1)))
        st = r.state
    np.testing.assert_allclose(st, st_m, rtol=0, atol=1e-15)
    assert codes == {0, 1, 2} and breakaway > 10


@pytest.mark.parametrize("which", ["u", "v"])
def test_slip_tangents_match_finite_differences(which):
    """dF/du (3x3, with the mu(v) k_n d coupling) and dF/dv (the velocity-weakening
    tangent N d dmu/d|v| e_v^T) against central differences; smooth inside the slip regime,
    so agreement to 1e-6 of the scale."""
    law = _law()
    st = np.array([[1e-5, -2e-5, 1.0]])                 # slipping slider
    u0 = np.array([[3e-6, 3e-5, 1e-5]])
    v0 = np.array([[0.0, 0.08, -0.05]])
    r = law.step(st, u0, v0)
    assert r.state[0, 2] == 1.0
    h = 1e-10 if which == "u" else 1e-7
    fd = np.empty((3, 3))
    for j in range(3):
        d = np.zeros((1, 3))
        d[0, j] = h
        if which == "u":
            fp, fm = law.step(st, u0 + d, v0).force, law.step(st, u0 - d, v0).force
        else:
            fp, fm = law.step(st, u0, v0 + d).force, law.step(st, u0, v0 - d).force
        fd[:, j] = (fp - fm)[0] / (2 * h)
    tangent = r.stiffness[0] if which == "u" else r.damping[0]
    scale = KN if which == "u" else np.abs(fd).max()
    np.testing.assert_allclose(tangent, fd, rtol=0, atol=1e-6 * scale)
    if which == "v":
        assert np.abs(tangent[1:, 1:]).max() > 0.1       # N (mu_s - mu_d) DC e^(-DC v) ~ 0.5


def test_dissipation_is_friction_times_slider_path():
    """dissipation() = f_t . dw = mu(v) N |dw| >= 0 per step (the return map moves w along
    f_t); zero in stick and when open. The trapezoidal energy balance of a closed path
    (work = d stored + diss) then holds up to 1/2 (mu_s - mu_d)^2 N^2 / k_t per break-away
    (the force drop at break-away is not on the slider path): checked against that bound."""
    law = _law(n=3)
    u, v = _history(n_t=2000, seed=4, sep=False)
    u[:, :, 0] = 1e-6 * np.sin(np.linspace(0, 20, 2000))[:, None]    # closed throughout
    st = law.initial_state()
    work = diss = 0.0
    f_old = law.step(st, u[0], v[0]).force
    st = law.step(st, u[0], v[0]).state
    E0 = law.stored_energy(st, u[0]).sum()
    n_break = 0
    for i in range(1, u.shape[0]):
        r = law.step(st, u[i], v[i])
        d = law.dissipation(st, r.state, r.force)
        dw = np.linalg.norm(r.state[:, :2] - st[:, :2], axis=1)
        mu_v = np.where(r.state[:, 2] == 1, law.sliding_coefficient(v[i]), 0.0)
        np.testing.assert_allclose(d, mu_v * r.force[:, 0] * dw, rtol=1e-12, atol=1e-18)
        assert (d >= 0).all()
        n_break += int(np.sum((st[:, 2] == 0) & (r.state[:, 2] == 1)))
        work += np.sum(0.5 * (f_old + r.force) * (u[i] - u[i - 1]))
        diss += d.sum()
        st, f_old = r.state, r.force
    E1 = law.stored_energy(st, u[-1]).sum()
    N0 = KN * (1e-5)
    bound = n_break * 0.5 * (MUS - MUD) ** 2 * (N0 * 1.2) ** 2 / KT
    assert n_break > 20 and diss > 0.2 * abs(work)
    assert abs(work - (E1 - E0) - diss) <= bound


def test_contact_status_codes():
    law = _law(n=3)
    st = law.initial_state()
    u = np.array([[-2e-5, 0, 0], [0, 1e-6, 0], [0, 1e-4, 0]])   # open, stick, slip
    r = law.step(st, u, np.zeros((3, 3)))
    assert law.contact_status(r.state, r.force).tolist() == [0, 1, 2]
    const = Contact3D(KN, KT, 0.4, offset=1e-5, n_contacts=3)
    r = const.step(const.initial_state(), u)
    assert const.contact_status(r.state, r.force).tolist() == [0, 1, 2]


@pytest.mark.parametrize("kwargs, word", [
    ({"mu_sliding": 0.5}, "mu_sliding"),
    ({"mu_sliding": -0.1}, "mu_sliding"),
    ({"decay": -1.0}, "decay"),
    ({"mu_sliding": [0.1, 0.2], "n_contacts": 3}, "mu_sliding"),
])
def test_bad_kinetic_parameters_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        Contact3D(KN, KT, 0.4, **kwargs)


def test_velocity_required_when_velocity_dependent():
    law = _law()
    assert law.velocity_dependent and law.n_state == 3
    with pytest.raises(ModelError, match="v"):
        law.step(law.initial_state(), np.zeros((1, 3)))
    with pytest.raises(ModelError, match="v_history"):
        law.march(np.zeros((4, 1, 3)))
    # decay = 0: static/kinetic but velocity independent (constant mu_d in slip)
    law0 = _law(decay=0.0)
    assert law0.kinetic and not law0.velocity_dependent
    assert law0.step(law0.initial_state(), [[0.0, 1e-4, 0.0]]).force[0, 1] == pytest.approx(
        MUD * KN * 1e-5)
