"""Time stepper (Newmark / HHT-alpha with condensed Newton on the contacts).

References and tolerances are given per test.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fricdamp.contact import Jenkins
from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.signals.energy import loop_area
from fricdamp.solvers import simulate
from fricdamp.structure import ContactElement, HarmonicLoad, chain


def test_newmark_discrete_solution_exact():
    """Average-acceleration Newmark on x'' + w^2 x = 0 gives x_n = cos(n Phi) exactly with
    cos(Phi) = (1 - (wh/2)^2) / (1 + (wh/2)^2) (e.g. Hughes, The FEM, 9.3).
    Round-off only: 1e-12."""
    w, h = 2 * np.pi * 3.0, 0.01
    res = simulate(chain([2.0], [2.0 * w**2]), 2.0, h, q0=[1.0])
    r = (w * h / 2) ** 2
    phi = np.arccos((1 - r) / (1 + r))
    n = np.arange(res.t.size)
    np.testing.assert_allclose(res.q[:, 0], np.cos(n * phi), atol=1e-12)
    # undamped linear: energy conserved to round-off
    assert res.energy_balance_error < 1e-12


def test_forced_damped_steady_state_second_order():
    """Damped 1-DOF under F cos(wt), started on the exact steady state
    X = F / (k - m w^2 + i c w): the computed response must stay on it. Newmark is second
    order: the error (harmonic projection over the last period) falls ~4x when h halves and is
    below 1e-3 at 100 steps per period."""
    m, k, c, F0 = 1.0, (2 * np.pi) ** 2, 0.4, 1.0
    w = 2 * np.pi * 1.3
    X = F0 / (k - m * w**2 + 1j * c * w)
    T = 2 * np.pi / w
    errs = []
    for spp in (100, 200):
        sys_ = chain([m], [k], dampers=[c], loads=[HarmonicLoad([F0], w)])
        res = simulate(sys_, 10 * T, T / spp, q0=[X.real], v0=[(1j * w * X).real])
        last = slice(-spp - 1, -1)
        t, x = res.t[last], res.q[last, 0]
        Xh = 2 * np.mean(x * np.exp(-1j * w * t))
        errs.append(abs(Xh - X) / abs(X))
    assert errs[1] < 1e-3
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.05)


def _jenkins_2dof(**kw):
    law = Jenkins(stiffness=800.0, slip_force=2.0)
    return chain([1.0, 0.5], [1000.0, 500.0], dampers=[0.5, 0.2],
                 contacts=[ContactElement(law, [[0.0, 1.0]], "damper")], **kw)


def test_energy_balance_jenkins_free_decay():
    """Input work = dissipated + change of mechanical energy (issue: <= 0.5 %). The friction
    dissipation is measured independently (slider slip x force), so the check is on the
    integration of the stick-slip transitions: O(h) at each transition."""
    res = simulate(_jenkins_2dof(), 5.0, 5e-4, q0=[0.0, 0.05])
    assert res.energy["contact_dissipation"][-1] > 0.1 * res.energy["kinetic"].max()
    assert res.energy_balance_error < 5e-3


def test_energy_balance_jenkins_forced_steady_cycle():
    """Forced 2-DOF with Jenkins contact: over one steady cycle, input work = viscous +
    friction dissipation (issue: <= 0.5 %); the friction part equals the contact's loop area."""
    w = 2 * np.pi * 4.0
    T = 2 * np.pi / w
    sys_ = _jenkins_2dof(loads=[HarmonicLoad([0.0, 3.0], w)])
    res = simulate(sys_, 30 * T, T / 400)
    assert res.energy_balance_error < 5e-3
    last = res.t >= 29 * T - 1e-9
    e = res.energy
    i0, i1 = np.flatnonzero(last)[[0, -1]]
    w_in = e["input_work"][i1] - e["input_work"][i0]
    w_diss = (e["viscous_dissipation"][i1] - e["viscous_dissipation"][i0]
              + e["contact_dissipation"][i1] - e["contact_dissipation"][i0])
    assert w_in > 0
    assert w_diss == pytest.approx(w_in, rel=5e-3)
    u = res.contact_displacement[0][last, 0, 0][:-1]
    f = res.contact_force[0][last, 0, 0][:-1]
    friction = e["contact_dissipation"][i1] - e["contact_dissipation"][i0]
    assert loop_area(u, f) == pytest.approx(friction, rel=5e-3)


def test_coulomb_free_decay_with_stiff_jenkins():
    """1-DOF with a stiff Jenkins contact (k_t = 1e4 k) behaves as a Coulomb oscillator:
    peaks drop by 4 F/k per cycle (den Hartog; REFERENCES.md) and the mass stops inside
    |x| <= F/k. Stick-phase error O(F/k_t) = 1e-4 of F/k: tolerance 1 % on the drop."""
    k, m, Fs = 100.0, 1.0, 0.5
    law = Jenkins(stiffness=1e4 * k, slip_force=Fs)
    sys_ = chain([m], [k], contacts=[ContactElement(law, [[1.0]], "coulomb")])
    x0 = 0.1
    Tn = 2 * np.pi / np.sqrt(k / m)
    res = simulate(sys_, 7 * Tn, Tn / 1500, q0=[x0])
    x = res.q[:, 0]
    peaks = [x[i] for i in range(1, x.size - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1]
             and x[i] > 0.02]
    drops = -np.diff([x0] + peaks)
    assert len(drops) >= 3
    np.testing.assert_allclose(drops, 4 * Fs / k, rtol=1e-2)
    assert abs(x[-1]) <= Fs / k * (1 + 1e-3)
    assert np.max(np.abs(res.v[-200:, 0])) < 1e-3 * np.max(np.abs(res.v[:, 0]))


def test_sparse_equals_dense():
    dense = _jenkins_2dof()
    from dataclasses import replace

    sparse = replace(dense, M=sp.csr_matrix(dense.M), K=sp.csr_matrix(dense.K),
                     D=sp.csr_matrix(dense.D))
    r1 = simulate(dense, 1.0, 1e-3, q0=[0.0, 0.05])
    r2 = simulate(sparse, 1.0, 1e-3, q0=[0.0, 0.05])
    np.testing.assert_allclose(r1.q, r2.q, atol=1e-12)


def test_hht_damps_high_frequency_and_stays_second_order():
    """HHT-alpha: algorithmic dissipation of a mode resolved with few steps (wh = 2),
    negligible for a well-resolved one (Hilber et al. 1977)."""
    w = 2 * np.pi
    sys_ = chain([1.0], [w**2])
    fast = simulate(sys_, 20.0, 2.0 / w, q0=[1.0], method="hht", alpha=-0.3)
    assert fast.energy["kinetic"][-1] + fast.energy["strain"][-1] < 0.5 * w**2 / 2
    slow = simulate(sys_, 1.0, 1e-3, q0=[1.0], method="hht", alpha=-0.3)
    assert slow.q[-1, 0] == pytest.approx(1.0, abs=1e-4)


def test_bad_input_named():
    s = _jenkins_2dof()
    with pytest.raises(ModelError, match="dt"):
        simulate(s, 1.0, -1e-3)
    with pytest.raises(ModelError, match="alpha"):
        simulate(s, 1.0, 1e-3, method="hht", alpha=0.5)
    with pytest.raises(ModelError, match="q0"):
        simulate(s, 1.0, 1e-3, q0=[1.0])
    with pytest.raises(ModelError, match="method"):
        simulate(s, 1.0, 1e-3, method="euler")


def test_newton_failure_reported_not_returned():
    s = _jenkins_2dof(loads=[HarmonicLoad([0.0, 50.0], 20.0)])
    with pytest.raises(ConvergenceError, match="Newton"):
        simulate(s, 0.5, 1e-3, max_iter=1, tol=1e-16)
    res = simulate(s, 0.5, 1e-3, max_iter=1, tol=1e-16, throw=False)
    assert not res.success and res.status == 1 and "Newton" in res.message
    assert res.t[-1] < 0.5


def test_save_and_xarray(tmp_path):
    res = simulate(_jenkins_2dof(), 0.2, 1e-3, q0=[0.0, 0.05], save_every=10)
    assert res.t.size == 21
    ds = res.to_xarray()
    assert ds["q"].shape == (21, 2) and ds["damper_f"].attrs["units"] == "N"
    res.save(tmp_path / "r.nc")
    res.save(tmp_path / "r.npz")
    import xarray as xr

    back = xr.open_dataset(tmp_path / "r.nc", engine="scipy")
    np.testing.assert_allclose(back["q"].values, res.q)
    assert not list(tmp_path.glob("*.tmp"))


def test_energy_balance_with_velocity_dependent_coulomb():
    """Forced 1-DOF with the Coulomb law of paper 003 (2) (mu_s = 0.4, mu_d = 0.2, DC = 4):
    the friction dissipation is booked from the slider slip (law.dissipation), independently
    of the trapezoidal contact work, so the balance checks the integration (<= 0.5 %, the
    issue's tolerance for the time stepper)."""
    from fricdamp.contact import Coulomb

    law = Coulomb(stiffness=2e4, normal_load=5.0, mu_static=0.4, mu_sliding=0.2, decay=4.0)
    w = 2 * np.pi * 6.0
    sys_ = chain([1.0], [1500.0], dampers=[0.5],
                 contacts=[ContactElement(law, [[1.0]], "coulomb")],
                 loads=[HarmonicLoad([6.0], w)])
    T = 2 * np.pi / w
    res = simulate(sys_, 20 * T, T / 1000)
    assert res.energy["contact_dissipation"][-1] > 0.2 * res.energy["input_work"][-1]
    assert res.energy_balance_error < 5e-3


def test_restart_from_states_equals_one_run():
    """A run split in two, the second started from the first's final displacement, velocity
    and contact states (``states0``), equals the uninterrupted run (Newmark is one-step, so
    only the stored acceleration differs: recomputed from equilibrium, it is the same)."""
    s = _jenkins_2dof(loads=[HarmonicLoad([0.0, 3.0], 25.0)])
    full = simulate(s, 0.4, 1e-3)
    first = simulate(s, 0.2, 1e-3)
    # final contact state of the first run: replay its contact history from virgin
    law = s.contacts[0].law
    _, st = law.march(first.contact_displacement[0])
    second = simulate(s, 0.4, 1e-3, t0=0.2, q0=first.q[-1], v0=first.v[-1], states0=[st])
    np.testing.assert_allclose(second.q[-1], full.q[-1], rtol=1e-8, atol=1e-12)
    with pytest.raises(ModelError, match="states0"):
        simulate(s, 0.4, 1e-3, states0=[])
