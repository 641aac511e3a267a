"""3D contact element: tangents vs finite differences, unilateral normal law, separation."""

import numpy as np
import pytest

from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ModelError

KN, KT, MU = 1e5, 1e4, 0.5


def _random_history(n_t=600, n_c=4, seed=0):
    """Random walk in (u_n, u_t1, u_t2) crossing separation (u_n + g0 < 0) now and then."""
    rng = np.random.default_rng(seed)
    u = np.cumsum(rng.normal(scale=[4e-6, 3e-5, 3e-5], size=(n_t, n_c, 3)), axis=0)
    u[:, :, 0] -= u[:, :, 0].mean(axis=0)
    return u


def test_step_matches_compiled_march():
    law = Contact3D([KN, 2 * KN, KN, KN], [KT, KT, 3 * KT, KT], [0.5, 0.3, 0.2, 0.0],
                    offset=[2e-5, 1e-5, 3e-5, 1e-5])
    u = _random_history()
    f_march, w_march = law.march(u)
    st = law.initial_state()
    seen = set()
    for i in range(u.shape[0]):
        r = law.step(st, u[i])
        np.testing.assert_allclose(r.force, f_march[i], rtol=0, atol=1e-12)
        gap = u[i, :, 0] + law.offset
        ftr = KT * np.linalg.norm(u[i, :, 1:] - st, axis=1)
        seen |= {"sep" if g <= 0 else ("slip" if t > lim else "stick")
                 for g, t, lim in zip(gap, ftr, law.mu * law.normal_force(u[i]), strict=True)}
        st = r.state
    np.testing.assert_allclose(st, w_march, rtol=0, atol=1e-15)
    assert seen == {"sep", "slip", "stick"}   # all three branches exercised


def _state_for(kind):
    """(law, state, u) in the requested regime, with a non-trivial slider position."""
    law = Contact3D(KN, KT, MU, offset=1e-4)                     # N0 = 10 N, mu N0 = 5 N
    st = np.array([[1e-4, -2e-4]])
    if kind == "stick":
        return law, st, np.array([[2e-5, 1e-4 + 1e-4, -2e-4 + 1.5e-4]])   # |f*| = 1.8 N < 6 N
    if kind == "slip":
        return law, st, np.array([[-3e-5, 1e-4 + 3e-4, -2e-4 - 4e-4]])    # |f*| = 5 N > 3.5 N
    return law, st, np.array([[-1.5e-4, 3e-4, 1e-4]])                      # separated


@pytest.mark.parametrize("kind", ["stick", "slip", "separated"])
def test_tangent_matches_finite_differences(kind):
    """Full 3x3 dF/du against central differences (h = 1e-10 m): the map is smooth inside
    each regime, so agreement to 1e-6 relative of k_n (rounding of f/h dominates)."""
    law, st, u0 = _state_for(kind)
    r = law.step(st, u0)
    h = 1e-10
    fd = np.empty((3, 3))
    for j in range(3):
        du = np.zeros((1, 3))
        du[0, j] = h
        fd[:, j] = (law.step(st, u0 + du).force - law.step(st, u0 - du).force)[0] / (2 * h)
    np.testing.assert_allclose(r.stiffness[0], fd, rtol=0, atol=1e-6 * KN)
    if kind == "slip":   # the coupling term of a varying normal load: mu k_n d
        d = r.force[0, 1:] / np.linalg.norm(r.force[0, 1:])
        np.testing.assert_allclose(r.stiffness[0, 1:, 0], MU * KN * d, rtol=1e-12)
        assert np.linalg.norm(r.stiffness[0, 1:, 0]) > 0.1 * KN
    if kind == "separated":
        assert not r.stiffness.any() and not r.force.any()


def test_normal_force_never_negative_and_zero_when_open():
    law = Contact3D(KN, KT, MU, offset=[1e-5, 0.0, -1e-5, 2e-5], n_contacts=4)
    u = _random_history(n_t=3000, seed=3)
    f, _ = law.march(u)
    assert (f[:, :, 0] >= 0).all()
    open_ = u[:, :, 0] + law.offset <= 0
    assert open_.mean() > 0.2 and (~open_).mean() > 0.2
    assert not f[open_].any()                       # no force of any kind when open
    # Coulomb cone holds everywhere (rounding slack 1e-12 relative)
    ft = np.linalg.norm(f[:, :, 1:], axis=2)
    assert (ft <= MU * f[:, :, 0] * (1 + 1e-12)).all()


def test_separation_then_recontact_unloads_tangential_spring():
    law = Contact3D.from_preload(KN, 5.0, KT, MU)   # g0 = 5e-5 m
    st = law.initial_state()
    r = law.step(st, [0.0, 5e-4, 0.0])              # slip: f_t = mu N = 2.5 N
    assert r.force[0].tolist() == pytest.approx([5.0, 2.5, 0.0])
    r = law.step(r.state, [-6e-5, 3e-4, 2e-4])      # open: nothing, slider follows u_t
    assert not r.force.any()
    np.testing.assert_array_equal(r.state[0], [3e-4, 2e-4])
    r = law.step(r.state, [0.0, 3.1e-4, 2e-4])      # re-contact: spring starts unstretched
    np.testing.assert_allclose(r.force[0], [5.0, 0.1, 0.0], rtol=1e-12)
    np.testing.assert_allclose(r.stiffness[0], np.diag([KN, KT, KT]))


def test_gap_offset_and_preload():
    """A negative offset is a gap; from_preload gives N(u_n = 0) = preload. Paper 003: an
    offset of 1e-5 m gives 2.4 N, i.e. k_n = 2.4e5 N/m."""
    law = Contact3D(KN, KT, MU, offset=-1e-5)
    np.testing.assert_allclose(law.normal_force([[0.9e-5, 0, 0]]), [0.0])
    np.testing.assert_allclose(law.normal_force([[1.5e-5, 0, 0]]), [0.5], rtol=1e-12)
    paper = Contact3D.from_preload(2.4e5, 2.4, 1e5, 0.2)
    np.testing.assert_allclose(paper.offset, [1e-5], rtol=1e-15)
    np.testing.assert_allclose(paper.normal_force([[0.0, 0.0, 0.0]]), [2.4], rtol=1e-15)


def test_isotropy_rotating_the_path_rotates_the_force():
    u = _random_history(n_t=800, n_c=1, seed=5)
    u[:, :, 0] = np.abs(u[:, :, 0])                 # stay closed: pure friction path
    law = Contact3D(KN, KT, MU, offset=1e-5)
    a = 0.7
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    ur = u.copy()
    ur[:, :, 1:] = u[:, :, 1:] @ R.T
    f, _ = law.march(u)
    fr, _ = law.march(ur)
    np.testing.assert_allclose(fr[:, :, 1:], f[:, :, 1:] @ R.T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fr[:, :, 0], f[:, :, 0], rtol=0, atol=1e-12)


def test_vectorised_contacts_match_single():
    kn, kt, mu, g0 = [1e5, 3e5], [1e4, 5e3], [0.5, 0.2], [1e-5, -1e-6]
    u = _random_history(n_t=500, n_c=2, seed=7)
    f, _ = Contact3D(kn, kt, mu, g0).march(u)
    for j in range(2):
        fj, _ = Contact3D(kn[j], kt[j], mu[j], g0[j]).march(u[:, j:j + 1])
        np.testing.assert_allclose(f[:, j], fj[:, 0], rtol=0, atol=1e-14)


def test_stored_energy_gradient_is_force_in_stick():
    """Elastic regime: the force derives from the stored energy (penalty + spring)."""
    law, st, u0 = _state_for("stick")
    f = law.step(st, u0).force[0]
    h = 1e-10
    for j in range(3):
        du = np.zeros((1, 3))
        du[0, j] = h
        g = (law.stored_energy(st, u0 + du) - law.stored_energy(st, u0 - du))[0] / (2 * h)
        assert g == pytest.approx(f[j], rel=1e-6)
    # separated: nothing stored (the slider followed u_t)
    law, st, u0 = _state_for("separated")
    assert law.stored_energy(law.step(st, u0).state, u0)[0] == 0.0


@pytest.mark.parametrize(
    "kwargs, word",
    [({"normal_stiffness": 0.0, "tangential_stiffness": 1.0, "mu": 0.3}, "normal_stiffness"),
     ({"normal_stiffness": 1.0, "tangential_stiffness": -1.0, "mu": 0.3},
      "tangential_stiffness"),
     ({"normal_stiffness": 1.0, "tangential_stiffness": 1.0, "mu": -0.3}, "mu"),
     ({"normal_stiffness": 1.0, "tangential_stiffness": 1.0, "mu": 0.3, "offset": np.inf},
      "offset"),
     ({"normal_stiffness": [1.0, 2.0], "tangential_stiffness": 1.0, "mu": [0.1, 0.2, 0.3]},
      "inconsistent")],
)
def test_bad_parameters_named(kwargs, word):
    with pytest.raises(ModelError, match=word):
        Contact3D(**kwargs)


def test_bad_history_shape_and_preload():
    law = Contact3D(KN, KT, MU)
    with pytest.raises(ModelError, match="u_history"):
        law.march(np.zeros((5, 1, 2)))
    with pytest.raises(ModelError, match="preload"):
        Contact3D.from_preload(KN, -1.0, KT, MU)
