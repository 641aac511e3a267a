"""Unit tests of the event-driven stick-slip solver (fricdamp.solvers.event*).

Each test names what it checks against: an independent brute-force enumeration, a closed
form, the other integration path, or the documented error behaviour.
"""

import itertools
import logging

import numpy as np
import pytest

from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers.event import (
    ConstrainedSystem,
    CoulombSystem,
    EventResult,
    simulate_events,
)
from fricdamp.solvers.event_switch import lemke, solve_friction_lcp
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem, TimeLoad


# ---------------------------------------------------------------- complementarity
def _lcp_by_enumeration(A, q):
    """All solutions of w = A z + q >= 0, z >= 0, w.z = 0 over the 2^n complementary bases."""
    n = q.size
    sols = []
    for basis in itertools.product([0, 1], repeat=n):
        zi = np.flatnonzero(basis)  # z basic, w = 0 there
        z = np.zeros(n)
        if zi.size:
            try:
                z[zi] = np.linalg.solve(A[np.ix_(zi, zi)], -q[zi])
            except np.linalg.LinAlgError:
                continue
        w = A @ z + q
        if np.all(z >= -1e-10) and np.all(w >= -1e-10):
            sols.append(z)
    return sols


@pytest.mark.parametrize("seed", range(6))
def test_lemke_matches_enumeration_on_positive_definite_lcp(seed):
    """A positive definite (non-symmetric) A is a P-matrix: exactly one LCP solution, which
    Lemke must find (1e-10)."""
    rng = np.random.default_rng(seed)
    n = 2 + seed % 4
    R = rng.normal(size=(n, n))
    S = rng.normal(size=(n, n))
    A = R @ R.T + 0.1 * np.eye(n) + (S - S.T)  # symmetric part positive definite
    q = rng.normal(size=n)
    sols = _lcp_by_enumeration(A, q)
    z = lemke(A, q)
    w = A @ z + q
    assert np.all(z >= 0) and np.all(w >= -1e-10) and abs(z @ w) < 1e-10
    assert any(np.allclose(z, s, atol=1e-10) for s in sols)


def _friction_by_enumeration(G, b, nmag, mu):
    """Consistent (lambda, a) of the friction problem found by trying all 3^k modes."""
    k = b.size
    out = []
    for modes in itertools.product([0, 1, -1], repeat=k):
        modes = np.array(modes)
        lam = np.where(modes != 0, -mu * nmag * modes, 0.0)
        S = np.flatnonzero(modes == 0)
        if S.size:
            rest = b + G[:, modes != 0] @ lam[modes != 0]
            lam[S] = np.linalg.solve(G[np.ix_(S, S)], -rest[S])
        a = G @ lam + b
        ok = np.all(np.abs(lam[S]) <= mu[S] * nmag[S] + 1e-12)
        ok &= np.all(modes[modes != 0] * a[modes != 0] > 0)
        if ok:
            out.append((modes, lam, a))
    return out


@pytest.mark.parametrize("seed", range(8))
def test_friction_lcp_matches_brute_force(seed):
    """Friction problem with fixed normal forces and a positive definite Delassus matrix: the
    solution is unique (it minimises lambda.G.lambda/2 + b.lambda over the friction box) and
    equals the one found by trying every stick/slip combination."""
    rng = np.random.default_rng(100 + seed)
    k = 1 + seed % 4
    R = rng.normal(size=(k, k))
    G = R @ R.T + 0.2 * np.eye(k)
    b = 2 * rng.normal(size=k)
    nmag = rng.uniform(0.2, 2.0, size=k)
    mu = rng.uniform(0.1, 1.0, size=k)
    lam, a = solve_friction_lcp(G, b, np.zeros((k, k)), nmag, mu)
    brute = _friction_by_enumeration(G, b, nmag, mu)
    assert len(brute) == 1
    np.testing.assert_allclose(lam, brute[0][1], atol=1e-10)
    np.testing.assert_allclose(a, brute[0][2], atol=1e-10)


def test_friction_lcp_with_normal_force_depending_on_friction():
    """Normal force n = H lambda + c (a wedge): the solution satisfies the friction law."""
    G = np.array([[2.0, 0.3], [0.3, 1.0]])
    b = np.array([3.0, -0.2])
    H = np.array([[0.2, 0.0], [0.0, -0.1]])
    c = np.array([1.0, 1.0])
    mu = np.array([0.5, 0.8])
    lam, a = solve_friction_lcp(G, b, H, c, mu)
    n = H @ lam + c
    assert np.all(np.abs(lam) <= mu * n + 1e-12)
    for i in range(2):
        if abs(a[i]) > 1e-10:  # slipping: force at the limit, opposing the acceleration
            assert lam[i] == pytest.approx(-mu[i] * n[i] * np.sign(a[i]), abs=1e-12)
    np.testing.assert_allclose(a, G @ lam + b, atol=1e-14)


# ---------------------------------------------------------------- multi-contact decision
def test_initial_decision_of_coupled_contacts_matches_enumeration():
    """Two coupled contacts at rest under a static load: the solver's first configuration is
    the unique consistent one found by trying all 9 stick/slip combinations (equations of
    motion solved independently here with the stick constraints)."""
    M = np.diag([1.0, 2.0])
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    W = np.array([[1.0, 1.0], [0.0, 1.0]])  # contact 1 on x1, contact 2 on x1 + x2
    f = np.array([1.0, 0.4])
    N = np.array([0.5, 2.0])
    mu = np.array([1.0, 0.6])
    s = MechanicalSystem(M=M, K=K, static_load=f)
    cs = CoulombSystem(s, directions=W.T, normal_load=N, mu_static=mu)
    consistent = []
    for modes in itertools.product([0, 1, -1], repeat=2):
        modes = np.array(modes)
        S = np.flatnonzero(modes == 0)
        fl = f + W[:, modes != 0] @ (-mu * N * modes)[modes != 0]
        nS = S.size
        A = np.block([[M, -W[:, S]], [W[:, S].T, np.zeros((nS, nS))]])
        x = np.linalg.solve(A, np.concatenate([fl, np.zeros(nS)]))
        acc, lamS = x[:2], x[2:]
        a = W.T @ acc
        ok = np.all(np.abs(lamS) <= mu[S] * N[S]) and np.all(
            modes[modes != 0] * a[modes != 0] > 0)
        if ok:
            consistent.append(tuple(modes))
    assert len(consistent) == 1
    res = simulate_events(cs, (0.0, 0.05), [0, 0, 0, 0], t_eval=[0.0, 0.05])
    assert tuple(res.modes[0]) == consistent[0]
    assert 0 in consistent[0] and any(m != 0 for m in consistent[0])  # one sticks, one slips


# ---------------------------------------------------------------- general systems (DOP853)
class Bead(ConstrainedSystem):
    """Bead of mass m on a fixed horizontal circular wire of radius R (no gravity).

    q = (x, y); bilateral normal constraint g_N = -(|q| - R) (inward normal, so the
    centripetal normal force is compressive) or its opposite (``outward``: the same force is
    then reported as tension). Friction mu |lambda_N| along the tangent.
    """

    n_dof = 2
    n_contacts = 1
    constant_mass = True

    def __init__(self, m=1.0, R=1.0, mu=0.2, outward=False):
        self.m, self.R = m, R
        self.mu_static = np.array([mu])
        self.mu_sliding = np.array([mu])
        self.normal_constrained = np.array([True])
        self.sgn = 1.0 if outward else -1.0

    def mass(self, q):
        return self.m * np.eye(2)

    def h(self, t, q, qd):
        return np.zeros(2)

    def normal_gap(self, q):
        return np.array([self.sgn * (np.hypot(*q) - self.R)])

    def normal_jacobian(self, q):
        return (self.sgn * q / np.hypot(*q))[:, None]

    def normal_wbar(self, q, qd):
        r = np.hypot(*q)
        rd = q @ qd / r
        return np.array([self.sgn * (qd @ qd - rd**2) / r])

    def tangent_jacobian(self, q):
        return (np.array([-q[1], q[0]]) / np.hypot(*q))[:, None]

    def tangent_wbar(self, q, qd):
        r = np.hypot(*q)
        rd = q @ qd / r
        gam = (-q[1] * qd[0] + q[0] * qd[1]) / r
        return np.array([-gam * rd / r])

    def potential_energy(self, q):
        return 0.0

    def input_power(self, t, q, qd):
        return 0.0

    def viscous_power(self, t, q, qd):
        return 0.0


@pytest.mark.parametrize("outward", [False, True])
def test_bead_on_ring_closed_form(outward, caplog):
    """m v' = -mu m v^2/R gives v = v0/(1 + mu v0 t/R) and arc length
    s = (R/mu) ln(1 + mu v0 t/R); the normal force m v^2/R checks the normal constraint's
    wbar term (000 (32)-(33)). DOP853 at rtol 1e-10: 1e-8 relative. With the normal written
    outward the same force is reported as tension (negative) with a warning."""
    mu, v0, R = 0.2, 2.0, 1.0
    with caplog.at_level(logging.WARNING, logger="fricdamp.solvers.event"):
        res = simulate_events(Bead(mu=mu, outward=outward), (0.0, 5.0), [R, 0, 0, v0],
                              t_eval=np.linspace(0, 5, 11))
    assert res.method == "dop853"
    v = np.hypot(res.qd[:, 0], res.qd[:, 1])
    v_ex = v0 / (1 + mu * v0 * res.t / R)
    np.testing.assert_allclose(v, v_ex, rtol=1e-8)
    s_ex = R / mu * np.log1p(mu * v0 * res.t / R)
    theta = np.unwrap(np.arctan2(res.q[:, 1], res.q[:, 0]))
    np.testing.assert_allclose(R * theta, s_ex, rtol=1e-8, atol=1e-9)
    sign = -1.0 if outward else 1.0
    np.testing.assert_allclose(res.lambda_N[:, 0], sign * v_ex**2 / R, rtol=1e-7)
    np.testing.assert_allclose(res.lambda_T[:, 0], -mu * v_ex**2 / R, rtol=1e-7)
    assert res.energy_balance_error < 1e-8
    assert ("tension" in caplog.text) == outward


def test_exact_and_dop853_agree_on_non_proportionally_damped_system():
    """2-DOF, non-proportional damping, two harmonic loads, a ground contact and a contact
    between the masses, mu_static > mu_sliding: the exact phases (eigen-decomposition of a
    non-symmetric block) and DOP853 at rtol 1e-11 give the same history (1e-8) and the same
    events - stick, slip and a simultaneous switch in which one contact breaks away and thereby
    lets the other one stick (the breakaway cascade of the switching decision)."""
    M = np.diag([1.0, 2.0])
    K = np.array([[3.0, -1.0], [-1.0, 2.0]])
    D = np.array([[0.1, 0.0], [0.0, 0.02]])
    loads = (HarmonicLoad([1.0, 0.5j], 1.3), HarmonicLoad([0.3, 0.0], 0.4))
    s = MechanicalSystem(M=M, K=K, D=D, loads=loads)
    cs = CoulombSystem(s, directions=[[1.0, 0.0], [1.0, -1.0]], normal_load=[1.0, 0.5],
                       mu_static=[0.8, 0.6], mu_sliding=[0.6, 0.5])
    t_eval = np.linspace(0, 12, 49)
    ex = simulate_events(cs, (0.0, 12.0), [0.0, 0.0, 0.0, 0.0], t_eval=t_eval)
    nu = simulate_events(cs, (0.0, 12.0), [0.0, 0.0, 0.0, 0.0], t_eval=t_eval,
                         method="dop853", rtol=1e-11, atol=1e-13)
    assert ex.method == "exact" and nu.method == "dop853"
    assert len(ex.events) > 20 and len(ex.event_times(to_mode="stick")) > 5
    # at t ~ 8.534 contact 1 stops while contact 0 is stuck; sticking both would need more
    # than mu_s N at both, so contact 0 breaks away (slides with mu_d) and contact 1 sticks
    tb = ex.event_times(contact=0, to_mode="slip+")
    assert np.any(np.isin(tb, ex.event_times(contact=1, to_mode="stick")))
    assert [(e.contact, e.to_mode) for e in ex.events] == [(e.contact, e.to_mode)
                                                          for e in nu.events]
    np.testing.assert_allclose(nu.event_times(), ex.event_times(), atol=1e-8)
    on_e, on_n = np.isin(ex.t, t_eval), np.isin(nu.t, t_eval)
    np.testing.assert_allclose(nu.q[on_n], ex.q[on_e], atol=1e-8)
    assert ex.energy_balance_error < 1e-11
    assert nu.energy_balance_error < 1e-8


def test_time_load_uses_dop853_and_matches_harmonic_load():
    """A TimeLoad has no linear form: 'auto' integrates it with DOP853 (max_step given, since
    the load's frequency is unknown to the solver) and matches the exact solution of the
    same cosine given as a HarmonicLoad (1e-8)."""
    base = MechanicalSystem(M=[[1.0]], K=[[1.0]])
    harm = CoulombSystem(base.with_loads(HarmonicLoad([1.0], 0.8)), directions=[1.0],
                         normal_load=0.9, mu_static=1.0)
    tl = CoulombSystem(base.with_loads(TimeLoad([1.0], lambda t: np.cos(0.8 * t))),
                       directions=[1.0], normal_load=0.9, mu_static=1.0)
    t_eval = np.linspace(0, 12, 25)
    ex = simulate_events(harm, (0, 12), [0.0, 0.0], t_eval=t_eval)
    nu = simulate_events(tl, (0, 12), [0.0, 0.0], t_eval=t_eval, max_step=0.5)
    assert nu.method == "dop853"
    assert len(ex.event_times(to_mode="stick")) >= 2
    np.testing.assert_allclose(nu.q[np.isin(nu.t, t_eval)], ex.q[np.isin(ex.t, t_eval)],
                               atol=1e-8)


def test_rigid_body_mode_uses_matrix_exponential():
    """A free mass (K = 0) under F0 cos(w t) with F0 > mu N slides from rest with
    v = (F0/w) sin(w t) - mu N t, x = F0 (1 - cos w t)/w^2 - mu N t^2/2 until v = 0. K = 0
    makes the constant particular solution singular, so the phase uses the matrix
    exponential; it is still exact (1e-12)."""
    F0, w, muN = 1.0, 1.0, 0.5
    s = MechanicalSystem(M=[[1.0]], K=[[0.0]], loads=(HarmonicLoad([F0], w),))
    cs = CoulombSystem(s, directions=[1.0], normal_load=muN, mu_static=1.0)
    res = simulate_events(cs, (0.0, 2.0), [0.0, 0.0], t_eval=np.linspace(0, 2.0, 21))
    assert res.n_expm > 0
    t_stop = res.events[0].time
    from scipy.optimize import brentq
    t_ex = brentq(lambda t: F0 / w * np.sin(w * t) - muN * t, 0.5, 3.0, xtol=1e-15)
    assert t_stop == pytest.approx(t_ex, rel=1e-12)
    sel = res.t <= t_stop
    t = res.t[sel]
    np.testing.assert_allclose(res.qd[sel, 0], F0 / w * np.sin(w * t) - muN * t, atol=1e-12)
    np.testing.assert_allclose(res.q[sel, 0], F0 * (1 - np.cos(w * t)) / w**2 - muN * t**2 / 2,
                               atol=1e-12)
    assert res.energy_balance_error < 1e-11


# ---------------------------------------------------------------- result object and errors
def _dh_system():
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], 0.8),),
                         dof_names=("x",))
    return CoulombSystem(s, directions=[1.0], normal_load=0.5, mu_static=1.0,
                         contact_names=("ground",))


def test_result_shapes_xarray_and_plot():
    res = simulate_events(_dh_system(), (0.0, 20.0), [0.0, 0.0], t_eval=np.linspace(0, 20, 41))
    assert isinstance(res, EventResult) and res.success and res.status == 0
    n_t = res.t.size
    assert n_t == 41 + len({e.time for e in res.events} - set(np.linspace(0, 20, 41)))
    assert np.all(np.diff(res.t) >= 0)
    assert res.q.shape == (n_t, 1) and res.lambda_T.shape == (n_t, 1)
    assert res.modes.dtype == np.int8
    ds = res.to_xarray()
    assert ds["q"].dims == ("time", "dof") and list(ds["dof"].values) == ["x"]
    assert list(ds["contact"].values) == ["ground"]
    assert ds.sizes["event"] == len(res.events)
    assert float(ds.attrs["energy_balance_error"]) < 1e-12
    import matplotlib.pyplot as plt

    axes = res.plot()
    assert len(axes) == 3
    plt.close("all")


def test_max_events_and_throw():
    cs = _dh_system()
    with pytest.raises(ConvergenceError, match="max_events"):
        simulate_events(cs, (0.0, 50.0), [0.0, 0.0], max_events=3)
    res = simulate_events(cs, (0.0, 50.0), [0.0, 0.0], max_events=3, throw=False)
    assert not res.success and res.status == 1 and res.n_events == 3
    assert res.t[-1] < 50.0


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"t_span": (1.0, 0.0)}, "t_span"),
    ({"y0": [0.0]}, "y0"),
    ({"t_eval": [5.0, 1.0]}, "t_eval"),
    ({"t_eval": [0.0, 99.0]}, "t_eval"),
    ({"method": "rk4"}, "method"),
    ({"rtol": 0.0}, "rtol"),
])
def test_bad_arguments(kwargs, match):
    args = {"t_span": (0.0, 10.0), "y0": [0.0, 0.0]}
    args.update(kwargs)
    with pytest.raises(ModelError, match=match):
        simulate_events(_dh_system(), args.pop("t_span"), args.pop("y0"), **args)


def test_bad_systems():
    s = MechanicalSystem(M=[[1.0]], K=[[1.0]])
    with pytest.raises(ModelError, match="mu_sliding"):
        CoulombSystem(s, directions=[1.0], normal_load=1.0, mu_static=0.2, mu_sliding=0.3)
    with pytest.raises(ModelError, match="normal_load"):
        CoulombSystem(s, directions=[1.0], normal_load=-1.0, mu_static=0.2)
    with pytest.raises(ModelError, match="directions"):
        CoulombSystem(s, directions=[1.0, 0.0], normal_load=1.0, mu_static=0.2)
    with pytest.raises(ModelError, match="MechanicalSystem"):
        CoulombSystem("not a system", directions=[1.0], normal_load=1.0, mu_static=0.2)
    with pytest.raises(ModelError, match="ConstrainedSystem"):
        simulate_events(s, (0, 1), [0.0, 0.0])
    with pytest.raises(ModelError, match="exact"):
        tl = CoulombSystem(s.with_loads(TimeLoad([1.0], np.sin)), directions=[1.0],
                           normal_load=1.0, mu_static=0.2)
        simulate_events(tl, (0, 1), [0.0, 0.0], method="exact")


def test_identically_zero_reserves_do_not_chatter():
    """At rest with no load, or with a load the static friction holds (|f| <= mu_s N), the
    contacts stay stuck with no event: friction reserves that are identically zero (N = 0)
    or constant must not fire (an event needs a crossing below round-off level)."""
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    free = CoulombSystem(MechanicalSystem(M=np.eye(2), K=K), directions=np.eye(2),
                         normal_load=[0.0, 0.0], mu_static=0.8)
    res = simulate_events(free, (0.0, 30.0), np.zeros(4))
    assert res.success and len(res.events) == 0 and np.all(res.modes == 0)
    held = CoulombSystem(MechanicalSystem(M=np.eye(2), K=K, static_load=[0.1, 0.0]),
                         directions=np.eye(2), normal_load=[1.0, 0.0], mu_static=0.8)
    res = simulate_events(held, (0.0, 30.0), np.zeros(4))
    assert len(res.events) == 0
    np.testing.assert_array_equal(res.q, 0.0)
    np.testing.assert_allclose(res.lambda_T[-1], [-0.1, 0.0], atol=1e-15)


@pytest.mark.parametrize("method", ["exact", "dop853"])
def test_frictionless_contact_gives_the_linear_solution(method):
    """mu_static = mu_sliding = 0 on one of two contacts of a 2-DOF chain: that contact has
    no friction events and carries no force, so with the other contact frictionless too the
    free vibration is the linear one, q(t) = V cos(w t) V^T M q0 (closed form), to 1e-12
    (exact phases: round-off) or 1e-8 (DOP853 at rtol 1e-11), with zero friction work; with
    the other contact rough, only that contact has events."""
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    s = MechanicalSystem(M=np.eye(2), K=K)
    cs = CoulombSystem(s, directions=np.eye(2), normal_load=[1.0, 1.0], mu_static=0.0)
    q0 = np.array([1.0, -0.3])
    t = np.linspace(0.0, 20.0, 201)
    res = simulate_events(cs, (0.0, 20.0), np.r_[q0, 0.0, 0.0], t_eval=t, method=method,
                          rtol=1e-11, atol=1e-13)
    lam, V = np.linalg.eigh(K)
    w = np.sqrt(lam)
    ref = (V @ (np.cos(np.outer(w, res.t)) * (V.T @ q0)[:, None])).T
    tol = 1e-12 if method == "exact" else 1e-8
    np.testing.assert_allclose(res.q, ref, atol=tol)
    assert res.n_events == 0 and np.all(res.lambda_T == 0.0)
    assert res.energy["friction_dissipation"][-1] == 0.0
    rough = CoulombSystem(s, directions=np.eye(2), normal_load=[1.0, 1.0],
                          mu_static=[0.0, 0.05])
    res = simulate_events(rough, (0.0, 20.0), np.r_[q0, 0.0, 0.0], method=method,
                          rtol=1e-11, atol=1e-13)
    assert res.n_events > 0 and {e.contact for e in res.events} == {1}
    assert np.all(res.lambda_T[:, 0] == 0.0)
    assert res.energy_balance_error < 1e-8
