"""Energy dissipated per cycle by the 3D contact element against closed forms.

References and derivations (u = displacement, f = force, theta = phase):

* 1D Jenkins (den Hartog 1931 / Iwan 1966, REFERENCES.md): motion along one tangential
  axis at constant normal load N gives W = 4 mu N (A - mu N / k_t).
* Circular orbit (derived here): u_t = R (cos theta, sin theta) at constant N, R > delta =
  mu N / k_t. In steady gross slip the slider runs on a circle of radius rho with the spring
  u_t - w (length delta) tangent to it, so R^2 = rho^2 + delta^2 and W = mu N 2 pi rho =
  mu N x (slider path length). The discrete radial return has an exact steady state too
  (``_circle_steady_state``), smaller by delta sin(pi/n): first-order convergence.
* Varying normal load in phase with u_t (derived here, a Jenkins element with a moving slip
  limit F(theta) = mu N0 (1 + eps cos theta), u_t = A cos theta, |eps| < 1, |eps| mu N0 <
  k_t A, mu N0 < k_t A): W = sum over the two slip phases of int f dw, see
  ``_w_varying_load``. With separation (slip limit mu k_n max(g0 + a cos theta, 0),
  |g0| < a) the contact re-closes unstretched and slips at once if P = mu k_n a < k_t A;
  see ``_w_with_separation``. Both were also checked by sampling refinement (second order).

Tolerances: for motion along one tangential direction the return map is exact and the
trapezoidal loop integral errs only at the kinks where slip starts or the contact opens,
O(dtheta^2) = (2 pi / 4000)^2 ~ 2.5e-6 relative at 4000 samples per cycle; measured errors
are 4e-7 to 6e-7, and the tests use rtol 5e-6. Identities of the discrete map (slider
dissipation, energy balance, steady circle) hold to rounding (1e-12 to 1e-10).
"""

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.contact.element3d import Contact3D
from fricdamp.signals.energy import loop_area

KN, KT, MU = 1e5, 1e4, 0.5
N_CYCLE = 4000
RTOL = 5e-6


def _two_cycles(n=N_CYCLE):
    return np.linspace(0.0, 4 * np.pi, 2 * n + 1)


def _work_per_cycle(u, f, n=N_CYCLE):
    """Loop work over the second (steady) cycle, summed over the three directions."""
    return sum(loop_area(u[n:, d], f[n:, d]) for d in range(3))


@pytest.mark.parametrize("angle", [0.0, 0.6])
@pytest.mark.parametrize("amplitude", [1e-3, 3e-3])
def test_reduces_to_1d_jenkins(angle, amplitude):
    """Motion along a fixed tangential axis at constant N: exactly a Jenkins element."""
    N0 = 10.0
    law = Contact3D.from_preload(KN, N0, KT, MU)
    th = _two_cycles()
    s = amplitude * np.cos(th)
    e = np.array([np.cos(angle), np.sin(angle)])
    u = np.zeros((th.size, 3))
    u[:, 1:] = s[:, None] * e
    f = law.drive(u)
    f_j = Jenkins(KT, MU * N0).drive(s)
    np.testing.assert_allclose(f[:, 1:] @ e, f_j, rtol=0, atol=1e-12)
    np.testing.assert_allclose(f[:, 0], N0, rtol=1e-15)
    np.testing.assert_allclose(f[:, 1:] @ np.array([-e[1], e[0]]), 0.0, atol=1e-12)
    W_exact = 4 * MU * N0 * (amplitude - MU * N0 / KT)
    assert _work_per_cycle(u, f) == pytest.approx(W_exact, rel=RTOL)


def _circle_steady_state(R, delta, n):
    """Discrete steady state of the radial return on a circle sampled n times per cycle.

    w_k, w_{k+1} and u_{k+1} are collinear (the return moves w towards u_{k+1}) and
    |u - w| = delta, so with s = sin(pi/n): R^2 = rho_h^2 + 2 rho_h delta s + delta^2.
    Returns the slider radius rho_h and its lag phi behind u (law of cosines).
    """
    s = np.sin(np.pi / n)
    rho_h = -delta * s + np.sqrt((delta * s) ** 2 + R**2 - delta**2)
    phi = np.arccos((R**2 + rho_h**2 - delta**2) / (2 * R * rho_h))
    return rho_h, phi


def _circle_work(law, R, n, N0):
    """Loop work over one cycle started on the discrete steady state; also the sliders."""
    delta = MU * N0 / KT
    rho_h, phi = _circle_steady_state(R, delta, n)
    th = np.linspace(0.0, 2 * np.pi, n + 1)
    u = np.zeros((th.size, 3))
    u[:, 1], u[:, 2] = R * np.cos(th), R * np.sin(th)
    w0 = rho_h * np.array([[np.cos(phi), -np.sin(phi)]])
    f = law.drive(u, state=w0)
    w = u[:, 1:] - f[:, 1:] / KT                      # slider positions (always in contact)
    return _work_per_cycle(u, f, n=0), u, f, w, rho_h


def test_circular_orbit_gross_slip():
    """Continuum: W = mu N 2 pi sqrt(R^2 - delta^2) = mu N x slider path length. The radial
    return is exact in 1D but only first order in the slip direction: its steady slider
    circle is smaller by delta sin(pi/n) (derived in _circle_steady_state), so the loop work
    per cycle is W_h = n mu N 2 rho_h sin(pi/n) cos^2(pi/n) exactly (trapezoid on u: slider
    chords of length 2 rho_h sin(pi/n), f_k at angle 2 pi/n to the chord direction f_{k+1}),
    and W_h -> W at first order."""
    N0, R = 10.0, 1e-3
    delta = MU * N0 / KT                              # 5e-4 m: spring stretch in slip
    law = Contact3D.from_preload(KN, N0, KT, MU)
    n = N_CYCLE
    W_h, u, f, w, rho_h = _circle_work(law, R, n, N0)
    # 1. the discrete steady state is invariant under the return map (rounding: 1e-12)
    np.testing.assert_allclose(np.linalg.norm(w, axis=1), rho_h, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(f[:, 1:], axis=1), MU * N0, rtol=1e-12)
    # 2. slider dissipation = mu N x slider path length, step by step (exact identity)
    dw = np.diff(w, axis=0)
    path = np.sum(np.linalg.norm(dw, axis=1))
    assert np.sum(f[1:, 1:] * dw) == pytest.approx(MU * N0 * path, rel=1e-12)
    # 3. the exact discrete loop work
    a = np.pi / n
    assert W_h == pytest.approx(n * MU * N0 * 2 * rho_h * np.sin(a) * np.cos(a) ** 2,
                                rel=1e-10)
    # 4. first-order convergence to the continuum closed form (error ratio 2 +- 1 %)
    W = MU * N0 * 2 * np.pi * np.sqrt(R**2 - delta**2)
    err_n = W_h - W
    err_2n = _circle_work(law, R, 2 * n, N0)[0] - W
    assert err_n < 0 and err_n / err_2n == pytest.approx(2.0, rel=0.01)
    assert abs(err_n) < 1e-3 * W
    assert abs(W - MU * N0 * 2 * np.pi * R) > 0.1 * W          # not the naive 2 pi R
    # 5. from the virgin state the slider spirals out towards that circle (pursuit curve)
    th = np.linspace(0.0, 4 * np.pi, 2 * n + 1)
    uv = np.zeros((th.size, 3))
    uv[:, 1], uv[:, 2] = R * np.cos(th), R * np.sin(th)
    wv = uv[:, 1:] - law.drive(uv)[:, 1:] / KT
    gap = rho_h - np.linalg.norm(wv[::n // 4], axis=1)
    assert (gap > 0).all() and (np.diff(gap) < 0).all()


def test_slider_dissipation_is_mu_n_times_slip_on_any_path():
    """Per step, f_t . dw = mu N |dw| >= 0 (the return moves w along f_t); with the slider
    increments of a random history incl. separation (where f = 0). Rounding tolerance."""
    rng = np.random.default_rng(11)
    u = np.cumsum(rng.normal(scale=[5e-6, 2e-5, 2e-5], size=(3000, 1, 3)), axis=0)[:, 0]
    law = Contact3D(KN, KT, MU, offset=2e-5)
    st = law.initial_state()
    lhs = rhs = 0.0
    for i in range(u.shape[0]):
        r = law.step(st, u[i])
        dw = r.state[0] - st[0]
        lhs += float(r.force[0, 1:] @ dw)
        rhs += MU * r.force[0, 0] * float(np.linalg.norm(dw))
        st = r.state
    assert rhs > 0
    assert lhs == pytest.approx(rhs, rel=1e-12)


def _w_varying_load(A, kt, F0, eps):
    """W per cycle, u_t = A cos th, slip limit F0 (1 + eps cos th), no separation.

    Phase 1 (th: 0 -> pi): stuck from f = F0 (1 + eps) on f = F0(1+eps) - kt A (1 - cos th)
    until f = -F(th) at cos th1 = c1 = (kt A - 2 F0 - eps F0) / (kt A + eps F0); then slip
    f = -F(th), w = u - f/kt, dw = -(A + eps F0/kt) sin th dth, so
    W1 = F0 (A + eps F0/kt) [1 + c1 - (eps/2)(1 - c1^2)].
    Phase 2 is the same with eps -> -eps (u and the load variation change sign together).
    """
    def half(e):
        c = (kt * A - 2 * F0 - e * F0) / (kt * A + e * F0)
        return F0 * (A + e * F0 / kt) * (1 + c - 0.5 * e * (1 - c**2))
    return half(eps) + half(-eps)


@pytest.mark.parametrize("eps", [0.3, -0.6, 0.9])
def test_varying_normal_load_in_phase(eps):
    """u_n = a cos th, u_t = A cos th with preload N0: N = N0 (1 + eps cos th), eps = k_n a/N0
    (eps < 0: anti-phase). The slip-limit variation changes W by up to ~10 % relative to
    the constant-load Jenkins value, which the test also checks is not what we match."""
    N0, A = 10.0, 1e-3
    law = Contact3D.from_preload(KN, N0, KT, MU)
    th = _two_cycles()
    u = np.zeros((th.size, 3))
    u[:, 0] = eps * N0 / KN * np.cos(th)
    u[:, 1] = A * np.cos(th)
    f = law.drive(u)
    np.testing.assert_allclose(f[:, 0], N0 * (1 + eps * np.cos(th)), rtol=1e-12)
    W = _work_per_cycle(u, f)
    W_exact = _w_varying_load(A, KT, MU * N0, eps)
    assert W == pytest.approx(W_exact, rel=RTOL)
    W_const = 4 * MU * N0 * (A - MU * N0 / KT)
    assert abs(W_exact - W_const) > 0.02 * W_const
    # the normal penalty is conservative: no work around the loop
    assert abs(loop_area(u[N_CYCLE:, 0], f[N_CYCLE:, 0])) < 1e-12 * W


def _w_with_separation(A, kt, P, cc):
    """W per cycle, u_t = A cos th, slip limit P max(cos th - cc, 0), cc = -g0/a in (-1, 1).

    Re-contact at cos th = cc (th in (pi, 2 pi)) with an unstretched spring; the stuck force
    k_t A (cos th - cc) exceeds the cone P (cos th - cc) since P < k_t A, so it slips
    positively at once up to th = 2 pi: W2 = P (A - P/kt) (1 - cc)^2 / 2. Then stuck from
    f = P (1 - cc) until f = -P (cos th - cc) at cos th = c1 = (kt A - P (1 - 2 cc)) /
    (kt A + P), slip to separation at cos th = cc: W1 = P (A + P/kt) (c1 - cc)^2 / 2.
    Separated: f = 0, nothing dissipated.
    """
    c1 = (kt * A - P * (1 - 2 * cc)) / (kt * A + P)
    return 0.5 * P * ((A + P / kt) * (c1 - cc) ** 2 + (A - P / kt) * (1 - cc) ** 2)


@pytest.mark.parametrize("cc", [-0.5, 0.3])
def test_varying_normal_load_with_separation(cc):
    """Contact opens for part of each cycle (N = k_n max(g0 + a cos th, 0))."""
    A, a = 1e-3, 1e-4
    P = MU * KN * a                                   # 5 N < k_t A = 10 N
    law = Contact3D(KN, KT, MU, offset=-cc * a)
    th = _two_cycles()
    u = np.zeros((th.size, 3))
    u[:, 0] = a * np.cos(th)
    u[:, 1] = A * np.cos(th)
    f = law.drive(u)
    open_ = np.cos(th) <= cc
    assert open_.any() and not f[open_].any()
    assert _work_per_cycle(u, f) == pytest.approx(_w_with_separation(A, KT, P, cc), rel=RTOL)


def test_energy_balance_with_stored_energy():
    """Work done on the contact = change of stored energy + slider dissipation, on every
    step of a random history that stays closed. With the trapezoidal rule this is exact:
    the normal force and the spring force are linear in (u_n, u_t - w), so
    1/2 (f_k + f_{k+1}) . (u_{k+1} - u_k) = E_{k+1} - E_k + 1/2 (f_k + f_{k+1}) . (w_{k+1} - w_k).
    Checks stored_energy (penalty + spring) against the forces; rounding tolerance."""
    rng = np.random.default_rng(2)
    n_t = 2000
    u = np.cumsum(rng.normal(scale=[3e-6, 2e-5, 2e-5], size=(n_t, 3)), axis=0)
    u[:, 0] = 5e-5 * np.sin(np.linspace(0, 12, n_t)) + 1e-5 * np.tanh(u[:, 0] / 1e-5)
    law = Contact3D(KN, KT, MU, offset=7e-5)          # g0 > max |u_n|: always closed
    st = law.initial_state()
    f = np.empty((n_t, 3))
    w = np.empty((n_t, 2))
    E = np.empty(n_t)
    for i in range(n_t):
        r = law.step(st, u[i])
        st = r.state
        f[i], w[i] = r.force[0], st[0]
        E[i] = law.stored_energy(st, u[i])[0]
    fm = 0.5 * (f[1:] + f[:-1])
    work = np.sum(fm * np.diff(u, axis=0), axis=1)
    diss = np.sum(fm[:, 1:] * np.diff(w, axis=0), axis=1)
    np.testing.assert_allclose(work, np.diff(E) + diss, rtol=0, atol=1e-12 * np.abs(work).max())
    assert diss.sum() > 0.1 * np.abs(work).sum()      # plenty of slip: not a stick-only check
