"""Pull-off amplitude of the paper-000 blade damper (000 section 3.1, Figs 9-11).

References: Pfeiffer & Hajek (1992): the pull-off amplitude F_e,limit is the excitation
amplitude at which a contact first slips (switching condition 000 (43)); it rises with the
centrifugal force F_Z, falls with the block angle gamma, and dips at the eigenfrequencies
of the blocked 3-DOF system (000 (4), (22)).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import argrelmin, peak_prominences

from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.models.blade_damper.studies import (
    confirm_pulloff,
    pulloff_curve,
    pulloff_curves,
    stuck_constraint_forces,
    stuck_steady_state,
)

F = np.linspace(10.0, 250.0, 4801)


def _reserve_max(p, f, amplitude, n=20000):
    """Largest (|lambda_T| - mu_s lambda_N) over one period of the stuck steady state, from
    the time-domain force balance W lambda = M q'' - h(t, q, q') at each sample (independent
    of the phasor algebra of the closed form)."""
    s = BladeDamperSystem(p.with_(excitation_amplitude=amplitude, excitation_frequency=f))
    w = 2 * np.pi * f
    st = s.static_equilibrium()
    Q = stuck_constraint_forces(s, [f])["Q"][0] * amplitude
    W = np.hstack([s.normal_jacobian(st.q), s.tangent_jacobian(st.q)])
    Wp = np.linalg.pinv(W)
    t = np.linspace(0, 1 / f, n, endpoint=False)
    e = np.exp(1j * w * t)
    q = st.q[:, None] + (Q[:, None] * e).real
    qd = (1j * w * Q[:, None] * e).real
    qdd = (-(w**2) * Q[:, None] * e).real
    h = (s._cache["F0"][:, None] + s.excitation(t) - s.K @ q - s.D @ qd)
    lam = Wp @ (s.M @ qdd - h)
    return np.max(np.abs(lam[2:]) - p.mu_static * lam[:2])


@pytest.mark.parametrize("f", [20.0, 51.0, 62.7, 100.0, 200.0])
def test_closed_form_limit_matches_time_domain_bisection(f):
    """F_e,limit from the phasor formula equals the amplitude at which the time-sampled
    stuck contact forces first touch the friction cone (bisection to 1e-10). Tolerance
    1e-6 relative: sampling the maximum over 20000 points per period misses it by
    ~(2 pi / 20000)^2 / 2 = 5e-8 of the force amplitude."""
    p = BladeDamperParameters()
    lim = pulloff_curve(p, [f]).F_e_limit_N[0]
    lo, hi = 0.5 * lim, 2.0 * lim
    assert _reserve_max(p, f, lo) < 0 < _reserve_max(p, f, hi)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if _reserve_max(p, f, mid) < 0:
            lo = mid
        else:
            hi = mid
    assert 0.5 * (lo + hi) == pytest.approx(lim, rel=1e-6)


def test_constraint_force_balance_is_consistent():
    """The 7 force equations of the stuck system are solved exactly by 4 contact forces
    (the motion satisfies the reduced equations): residual at round-off (1e-12)."""
    r = stuck_constraint_forces(BladeDamperParameters(), F[::100])
    assert r["residual"] < 1e-12
    p = BladeDamperParameters()
    assert np.allclose(r["lambda_N0"], p.centrifugal_force / (2 * np.sin(p.gamma)),
                       rtol=1e-10)
    assert np.allclose(r["lambda_T0"], 0.0, atol=1e-9)


def test_pulloff_is_proportional_to_centrifugal_force():
    """000 Fig. 10: rises with F_Z. In the stuck (linear) system the contact-force response
    does not depend on F_Z and the static normal force is F_Z / (2 sin gamma), so
    F_e,limit is exactly proportional to F_Z (tolerance 1e-10, round-off)."""
    curves = pulloff_curves(gammas_deg=(50.0,), frequency_hz=F[::10])
    lims = np.array([c["F_e_limit_N"] for c in curves])
    fz = np.array([c["F_Z_N"] for c in curves])
    assert list(fz) == [60.0, 100.0, 140.0]
    assert np.allclose(lims / fz[:, None], lims[0] / fz[0], rtol=1e-10)
    assert np.all(np.diff(lims, axis=0) > 0)


def test_pulloff_falls_with_block_angle():
    """000 Fig. 9: the pull-off amplitude decreases with gamma (flatter platforms) at every
    frequency, for gamma = 40, 50, 60, 65 degrees (the paper's range)."""
    lims = [pulloff_curve(BladeDamperParameters().with_(gamma_deg=g), F).F_e_limit_N
            for g in (40.0, 50.0, 60.0, 65.0)]
    for a, b in zip(lims[:-1], lims[1:], strict=True):
        assert np.all(b < a)


def test_pulloff_dips_at_stuck_eigenfrequencies():
    """000 Fig. 11: the minima of F_e,limit lie at the eigenfrequencies of the blocked
    3-DOF system. Every local minimum lies within 1 % of a stuck eigenfrequency and every
    stuck eigenfrequency has a minimum within 1 % (the modal damping of ~1 % makes the
    half-power band 2 % wide, and the neighbouring modes' background may move a minimum
    inside it); each dip is pronounced: the curve rises by a factor of at least 1.5 on both
    sides before it falls again (prominence of the minimum of log F_e,limit)."""
    p = BladeDamperParameters()
    c = pulloff_curve(p, F)
    fs = c.stuck_eigenfrequencies_hz
    imin = argrelmin(c.F_e_limit_N)[0]
    fmin = F[imin]
    assert fmin.size == 3
    for f0 in fmin:
        assert np.min(np.abs(fs - f0) / fs) < 1e-2
    for f0 in fs:
        assert np.min(np.abs(fmin - f0) / f0) < 1e-2
    prominence = np.exp(peak_prominences(-np.log(c.F_e_limit_N), imin)[0])
    assert np.all(prominence > 1.5)


def test_contract_of_pulloff_curves():
    curves = pulloff_curves(frequency_hz=[30.0, 60.0])
    assert len(curves) == 9
    assert {(c["gamma_deg"], c["F_Z_N"]) for c in curves} == {
        (g, fz) for g in (40.0, 50.0, 60.0) for fz in (60.0, 100.0, 140.0)}
    for c in curves:
        assert set(c) >= {"gamma_deg", "F_Z_N", "frequency_hz", "F_e_limit_N",
                          "stuck_eigenfrequencies_hz"}
        assert len(c["F_e_limit_N"]) == 2 and len(c["stuck_eigenfrequencies_hz"]) == 3
        assert all(c["normal_force_ok"])


@pytest.mark.parametrize("f", [30.0, 51.1, 100.3])
def test_event_driven_runs_confirm_the_limit(f):
    """Event-driven runs started on the stuck steady state: 2 % below the closed-form limit
    no contact ever slips (and the smallest friction reserve is the expected 2 % of the
    limit's reserve); 2 % above, a contact slips within the first period."""
    chk = confirm_pulloff(BladeDamperParameters(), f, margin=0.02, periods=1.5)
    assert chk.confirmed, chk
    assert chk.first_slip_time_s[1] < 1.0 / f
    p = BladeDamperParameters()
    N0 = p.centrifugal_force / (2 * np.sin(p.gamma))
    assert chk.min_reserve_N[0] > 0
    assert chk.min_reserve_N[0] < 0.03 * p.mu_static * N0 * 2


def test_stuck_steady_state_is_a_periodic_stuck_solution():
    """The event-driven solver started on the stuck steady state below the limit reproduces
    the closed-form stuck motion (tolerance 1e-7 of the amplitude: DOP853 at rtol 1e-10)."""
    from fricdamp.models.blade_damper.studies import time_response

    p = BladeDamperParameters()
    lim = pulloff_curve(p, [45.0]).F_e_limit_N[0]
    pp = p.with_(excitation_amplitude=0.9 * lim, excitation_frequency=45.0)
    y0 = np.concatenate(stuck_steady_state(pp, 0.0))
    tr = time_response(pp, 1.0, y0=y0, samples_per_period=20, rtol=1e-10)
    r = tr.result
    assert np.all(r.modes == 0) and tr.ok
    ref = np.array([stuck_steady_state(pp, t)[0] for t in r.t])
    amp = np.max(np.abs(ref - ref.mean(axis=0)))
    assert np.max(np.abs(r.q - ref)) < 1e-7 * amp
