"""Parameters, statics and linear sub-systems of the paper-000 blade-damper model."""

from __future__ import annotations

import numpy as np
import pytest

from fricdamp.errors import ModelError
from fricdamp.models import BladeDamperParameters, BladeDamperSystem
from fricdamp.solvers.event_system import ConstrainedSystem


@pytest.mark.parametrize(("changes", "name"), [
    ({"gamma": 0.0}, "gamma"),
    ({"gamma": np.pi / 2}, "gamma"),
    ({"gamma_deg": 95.0}, "gamma"),
    ({"masses": (0.4, -0.2, 0.4, 0.2)}, "masses"),
    ({"masses": (0.4, 0.2, 0.4)}, "masses"),
    ({"stiffnesses": (1e5, 0.0, 1e5, 1e4)}, "stiffnesses"),
    ({"dampings": (1.0, -1.0, 1.0, 1.0)}, "dampings"),
    ({"damper_mass": 0.0}, "damper_mass"),
    ({"damper_gyration_radius": -1e-3}, "damper_gyration_radius"),
    ({"p1": 10.0}, "p1"),
    ({"p2": -1e-3}, "p2"),
    ({"mu_static": -0.1}, "mu_static"),
    ({"mu_sliding": 0.5}, "mu_sliding"),
    ({"centrifugal_force": 0.0}, "centrifugal_force"),
    ({"excitation_frequency": 0.0}, "excitation_frequency"),
    ({"excitation_amplitude": float("nan")}, "excitation_amplitude"),
    ({"contour": "ellipse"}, "contour"),
])
def test_bad_parameters_name_the_parameter(changes, name):
    with pytest.raises(ModelError, match=name):
        BladeDamperParameters().with_(**changes)


def test_parameters_are_frozen_and_copied():
    p = BladeDamperParameters()
    q = p.with_(gamma_deg=60.0, centrifugal_force=140.0)
    assert p.gamma_deg == 50.0 and q.gamma_deg == 60.0 and q.centrifugal_force == 140.0
    with pytest.raises(AttributeError):
        p.damper_mass = 2e-3  # type: ignore[misc]
    assert p.damper_inertia == pytest.approx(1e-3 * 4e-3**2)


def test_system_implements_the_solver_protocol():
    s = BladeDamperSystem()
    assert isinstance(s, ConstrainedSystem)
    s.check()
    assert s.n_dof == 7 and s.n_contacts == 2 and s.normal_constrained.all()
    assert s.dof_names == ("q1", "q2", "q3", "q4", "q5", "xS", "yS")
    assert np.allclose(np.diag(s.mass(np.zeros(7))),
                       [0.3, 0.15, 0.3, 0.165, 1.6e-8, 1e-3, 1e-3])


def test_excitation_phasor_matches_time_function():
    """F_E(t) = Re(F_hat exp(i Omega t)) for F_E1 on q2 and F_E2 on q4."""
    p = BladeDamperParameters(excitation_amplitude=2.0, excitation_ratio=0.5,
                              excitation_phase=0.7, excitation_frequency=33.0)
    s = BladeDamperSystem(p)
    t = np.linspace(0, 0.1, 17)
    F = s.excitation(t)
    Fh = s.excitation_phasor()
    assert np.allclose(F, (Fh[:, None] * np.exp(1j * p.omega * t)).real, atol=1e-14)
    assert np.allclose(F[[0, 2, 4, 5, 6]], 0.0)


def test_static_equilibrium_closed_form():
    """Damper equilibrium: 2 lambda_N sin(gamma) = F_Z, so lambda_N = F_Z / (2 sin gamma);
    each platform is pushed outwards by lambda_N cos(gamma): k1 q1 = -lambda_N cos(gamma),
    k3 q3 = +lambda_N cos(gamma), blades follow (q2 = q1, q4 = q3). Tolerance 1e-10
    relative (Newton converged to 1e-12 of F_Z)."""
    for g in (40.0, 50.0, 65.0):
        p = BladeDamperParameters().with_(gamma_deg=g)
        s = BladeDamperSystem(p)
        st = s.static_equilibrium()
        N = p.centrifugal_force / (2 * np.sin(p.gamma))
        assert np.allclose(st.normal_force, N, rtol=1e-10)
        k1, _, k3, _ = p.stiffnesses
        assert st.q[0] == pytest.approx(-N * np.cos(p.gamma) / k1, rel=1e-10)
        assert st.q[2] == pytest.approx(N * np.cos(p.gamma) / k3, rel=1e-10)
        assert st.q[1] == pytest.approx(st.q[0], rel=1e-10)
        assert st.q[3] == pytest.approx(st.q[2], rel=1e-10)
        assert abs(st.q[4]) < 1e-12
        assert np.max(np.abs(s.normal_gap(st.q))) < 1e-15


def test_stuck_system_is_the_paper_three_dof_system():
    """000 (22): m1, m3 and the damper move as one mass on k1 + k3; blades on k2, k4."""
    p = BladeDamperParameters()
    L = BladeDamperSystem(p).stuck_system()
    m1, m2, m3, m4 = p.masses
    k1, k2, k3, k4 = p.stiffnesses
    assert np.allclose(L.M, np.diag([m1 + m3 + p.damper_mass, m2, m4]))
    assert np.allclose(L.K, [[k1 + k2 + k3 + k4, -k2, -k4], [-k2, k2, 0], [-k4, 0, k4]])
    assert L.eigenfrequencies().shape == (3,)


def test_sliding_system_rocking_stiffness_from_centrifugal_force():
    """The free-sliding damper rocks on its contour: the rocking stiffness is
    -F_Z d2yS/dq5^2, which at q = 0 is F_Z (4 p1 p2 + 1 - 1/s^2 + 2/s^4) / (4 |p1|)
    (series of the closed-form yS(q5), s = sin gamma). Compared at the static state, which
    differs from q = 0 by ~1e-4 m: tolerance 1e-3 relative."""
    p = BladeDamperParameters()
    s = BladeDamperSystem(p)
    L = s.sliding_system()
    sg = np.sin(p.gamma)
    k55 = p.centrifugal_force * (4 * p.p1 * p.p2 + 1 - 1 / sg**2 + 2 / sg**4) / (4 * abs(p.p1))
    assert L.K[4, 4] == pytest.approx(k55, rel=1e-3)
    f = L.eigenfrequencies()
    assert f.shape == (5,) and np.all(np.isfinite(f))


def test_unstable_damper_is_reported_as_nan_frequency():
    """A damper whose centre of mass lies too far below the apex (large p2) is unstable
    when sliding freely: the rocking stiffness is negative and its frequency is NaN."""
    p = BladeDamperParameters(p2=0.05)
    s = BladeDamperSystem(p)
    f = s.sliding_system().eigenfrequencies()
    assert np.isnan(f).sum() == 1
