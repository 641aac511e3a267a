"""Joint-model fitting (fricdamp.signals.fit): input files, the rough joint's
reparameterisation, the fit's intervals and verdicts.

References: the laws' own loops (exact, noise-free) or with white noise of a known level;
the rough joint's load and stiffness integrals (Greenwood-Williamson, 002 (11)-(14)).
"""

import json
import math

import numpy as np
import pytest

from fricdamp.contact import Jenkins
from fricdamp.contact.rough import RoughRotationalJoint
from fricdamp.errors import ModelError
from fricdamp.signals.fit import Loop, fit_joint, read_fit_input, rough_joint


def loops_of(law, amps, *, n=160, noise=0.0, seed=0, rotational=False, phase=0.0):
    rng = np.random.default_rng(seed)
    out = []
    for a in amps:
        cyc = a * np.cos(2 * np.pi * np.arange(n) / n + phase)
        u = np.concatenate((a * np.sin(np.linspace(0, np.pi / 2, 40)), cyc, cyc))
        f = law.drive(u)[-n:]
        out.append(Loop(cyc, f + noise * 0.5 * np.ptp(f) * rng.standard_normal(n),
                        rotational=rotational))
    return out


# ----------------------------------------------------------------------------- input files
def _write(path, head, *cols):
    rows = np.column_stack(cols)
    path.write_text(head + "\n" + "\n".join(",".join(f"{x:.12e}" for x in r) for r in rows))
    return path


def test_read_loops_with_units(tmp_path):
    x = 1e-5 * np.cos(np.linspace(0, 2 * np.pi, 50, endpoint=False))
    f = Jenkins(1e6, 5.0).drive(np.concatenate((x, x)))[50:]
    t = np.arange(50) / 1500.0
    lp = read_fit_input(_write(tmp_path / "a.csv", "time [s],displacement [um],force [kN]",
                               t, 1e6 * x, 1e-3 * f))[0]
    np.testing.assert_allclose(lp.displacement, x, rtol=1e-11)
    np.testing.assert_allclose(lp.force, f, rtol=1e-11)
    assert not lp.rotational and lp.amplitude == pytest.approx(1e-5)
    rot = read_fit_input(_write(tmp_path / "b.csv", "phase [-],rotation [mrad],torque [N mm]",
                                t, 1e3 * x, 1e3 * f))[0]
    assert rot.rotational
    np.testing.assert_allclose(rot.force, f, rtol=1e-11)
    folder = tmp_path / "identify-out"
    folder.mkdir()
    _write(folder / "loop.csv", "phase [-],rotation [rad],torque [N m]", t, x, f)
    assert read_fit_input(folder)[0].rotational
    a, e, rotational = read_fit_input(_write(tmp_path / "e.csv",
                                             "amplitude [rad],energy [mJ]",
                                             [1e-5, 2e-5], [1.0, 3.0]))
    assert rotational and e.tolist() == [1e-3, 3e-3]


@pytest.mark.parametrize("head, message", [
    ("time [s],speed [m/s],force [N]", "needs a displacement or rotation column"),
    ("time [s],rotation [rad],force [N]", "do not match"),
])
def test_read_errors_are_named(tmp_path, head, message):
    p = _write(tmp_path / "x.csv", head, np.arange(20.0), np.sin(np.arange(20.0)),
               np.cos(np.arange(20.0)))
    with pytest.raises(ModelError, match=message):
        read_fit_input(p)
    with pytest.raises(ModelError, match="without loop.csv"):
        read_fit_input(tmp_path)


# ----------------------------------------------------------------------------- rough joint
def test_rough_joint_reparameterisation_reproduces_paper_002():
    """The joint built from (mu, K0, sigma) is the paper's: same summit density (eta R^1/2 is
    what K0 and the preload fix), same initial stiffness and slip moment (1e-8)."""
    ref = RoughRotationalJoint.paper_002(n_cells=(7, 5))
    k0 = ref.initial_stiffness
    j = rough_joint(0.15, k0, 0.45e-6, joint_cells=(7, 5))
    assert j.initial_stiffness == pytest.approx(k0, rel=1e-8)
    assert j.gw.summit_density == pytest.approx(2e9, rel=1e-8)
    assert j.slip_moment == pytest.approx(ref.slip_moment, rel=1e-12)
    # another radius: eta scales as R^-1/2 and nothing else changes
    j4 = rough_joint(0.15, k0, 0.45e-6, joint_cells=(7, 5), summit_radius_m=200e-6)
    assert j4.gw.summit_density == pytest.approx(1e9, rel=1e-8)
    th = 3e-6 * np.cos(np.linspace(0, 2 * np.pi, 64))
    np.testing.assert_allclose(j4.drive(th), j.drive(th), rtol=1e-9, atol=1e-12)
    with pytest.raises(ModelError, match="cannot be reached"):
        rough_joint(0.15, 1e-3, 0.45e-6)
    with pytest.raises(ModelError, match="unknown fixed"):
        rough_joint(0.15, k0, 0.45e-6, preload=100.0)


def test_rough_fit_is_conditioned_by_the_reparameterisation():
    """(mu, sigma, eta, R): singular (eta and R only as eta sqrt(R)); (mu, K0, sigma):
    well conditioned on loops from micro- to macro-slip. Coarse joint (5 x 3 cells, 16
    classes) for speed; noise-free loops, so the parameters come back to 1e-4."""
    fixed = {"joint_cells": (5, 3), "height_classes": 16}
    truth = rough_joint(0.15, 5e4, 0.45e-6, **fixed)
    loops = loops_of(truth, [3e-7, 2e-6, 1e-5, 1e-4], n=100, rotational=True)
    res = fit_joint(loops, model="rough", fixed=fixed)
    assert res.parameters["mu"] == pytest.approx(0.15, rel=1e-4)
    assert res.parameters["initial_stiffness_Nm_per_rad"] == pytest.approx(5e4, rel=1e-4)
    assert res.parameters["summit_std_m"] == pytest.approx(0.45e-6, rel=1e-4)
    c = res.conditioning
    assert c["raw_condition_number"] > 1e6 > 1e3 > c["fitted_condition_number"]
    assert res.derived["slip_moment_Nm"] == pytest.approx(truth.slip_moment, rel=1e-4)
    assert res.derived["summit_density_per_m2"] == pytest.approx(truth.gw.summit_density,
                                                                 rel=1e-3)


# ----------------------------------------------------------------------------- fits
def test_jenkins_fit_exact_and_json():
    loops = loops_of(Jenkins(2e6, 7.0), [2e-6, 6e-6, 2e-5])
    res = fit_joint(loops, model="jenkins")
    assert res.parameters["stiffness_N_per_m"] == pytest.approx(2e6, rel=1e-7)
    assert res.parameters["slip_force_N"] == pytest.approx(7.0, rel=1e-7)
    assert res.residual["rms_relative"] < 1e-7 and res.status == "ok"
    d = json.loads(json.dumps(res.to_dict()))
    assert set(d) >= {"parameters", "confidence_95", "residual", "conditioning", "status"}
    fig = res.plot()
    assert len(fig.axes) == 1


def test_energy_only_fit():
    """E_d(A) of a Jenkins element, 4 F (A - F/k), from 5 amplitudes in slip: exact."""
    k, fs = 1e6, 10.0
    a = np.array([1.5, 2, 4, 8, 16]) * fs / k
    res = fit_joint(energy=(a, 4 * fs * (a - fs / k)), model="jenkins")
    assert res.parameters["stiffness_N_per_m"] == pytest.approx(k, rel=1e-6)
    assert res.parameters["slip_force_N"] == pytest.approx(fs, rel=1e-6)
    assert len(res.plot().axes) == 1


def test_gross_slip_loop_sampled_coarsely_is_flagged():
    """One loop 50x past the slip displacement, 64 samples: the stick phase at each reversal
    spans ~1 sample, so the stiffness rests on a handful of samples: unreliable."""
    law = Jenkins(1e6, 10.0)
    res = fit_joint(loops_of(law, [5e-4], n=64, noise=0.01), model="jenkins")
    assert res.status == "unreliable"
    assert any("stiffness_N_per_m rests on" in w for w in res.warnings)
    assert res.conditioning["samples_informing"]["slip_force_N"] > 20


def test_iwan_bounds_are_reported():
    """A Jenkins element's loops asked of an Iwan model: beta goes to its upper bound."""
    res = fit_joint(loops_of(Jenkins(1e6, 10.0), [5e-6, 2e-5, 4e-5]), model="iwan")
    assert res.parameters["stiffness_N_per_m"] == pytest.approx(1e6, rel=0.05)
    assert res.parameters["slip_force_N"] == pytest.approx(10.0, rel=0.01)
    assert res.status == "unreliable" and any("bound" in w for w in res.warnings)


@pytest.mark.parametrize("kwargs, message", [
    ({"model": "coulomb"}, "model must be one of"),
    ({"model": "jenkins", "initial": {"stiffness": 1.0}}, "unknown parameter"),
    ({"model": "jenkins", "initial": {"slip_force_N": -1.0}}, "must be > 0"),
    ({"model": "rough"}, "rotational joint"),
    ({"model": "jenkins", "target": "energies"}, "target must be"),
])
def test_bad_fit_requests(kwargs, message):
    loops = loops_of(Jenkins(1e6, 10.0), [2e-5])
    with pytest.raises(ModelError, match=message):
        fit_joint(loops, **kwargs)


def test_mixed_loops_are_refused():
    a = loops_of(Jenkins(1e6, 10.0), [2e-5])
    b = loops_of(Jenkins(1e6, 10.0), [2e-5], rotational=True)
    with pytest.raises(ModelError, match="mix"):
        fit_joint(a + b, model="jenkins")
    assert math.isfinite(a[0].energy)
