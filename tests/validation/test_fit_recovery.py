"""Recovery of known joint parameters from synthetic noisy loops (issue 16, paper 002 part).

Each model's own law draws symmetric loops at amplitudes from micro- to macro-slip (after a
first loading), white noise of 1 % of each loop's force amplitude is added, and the fit
starts from its automatic guesses. Requirement (issue 16): the known parameters within 5 %.
Measured: Jenkins within 0.05 %; Iwan K_T, F_S, beta within 0.6 %, chi within 0.005;
paper 002's rough joint (Table 2: mu = 0.15, sigma = 0.45 um; eta = 2e9 / m^2, R = 50 um)
mu within 0.1 %, K0 within 0.05 %, sigma within 0.6 % (the derived eta is 8 % off, inside its
+-60 % interval: eta is the poorly determined one). The 95 % intervals hold the known
values.
"""

import numpy as np
import pytest

from fricdamp.contact import Iwan, Jenkins
from fricdamp.contact.rough import RoughRotationalJoint
from fricdamp.signals.fit import Loop, fit_joint

NOISE = 0.01


def noisy_loops(law, amps, *, n=200, seed=0, rotational=False):
    rng = np.random.default_rng(seed)
    out = []
    for a in amps:
        cyc = a * np.cos(2 * np.pi * np.arange(n) / n)
        u = np.concatenate((a * np.sin(np.linspace(0, np.pi / 2, 50)), cyc, cyc))
        f = law.drive(u)[-n:]
        out.append(Loop(cyc, f + NOISE * 0.5 * np.ptp(f) * rng.standard_normal(n),
                        rotational=rotational))
    return out


def _check(res, truth, tol=0.05):
    for name, value in truth.items():
        got = res.parameters[name]
        assert got == pytest.approx(value, rel=tol), (name, got, value)
        lo, hi = res.confidence_95[name]
        assert lo <= value <= hi, (name, lo, value, hi)


def test_jenkins_recovered():
    loops = noisy_loops(Jenkins(1e6, 10.0), [5e-6, 1e-5, 2e-5, 4e-5])
    res = fit_joint(loops, model="jenkins")
    _check(res, {"stiffness_N_per_m": 1e6, "slip_force_N": 10.0})
    assert res.status == "ok"


def test_iwan_recovered():
    law = Iwan(1e6, 10.0, -0.5, 0.5)
    loops = noisy_loops(law, law.phi_max[0] * np.array([0.05, 0.2, 0.5, 1.0, 2.0]))
    res = fit_joint(loops, model="iwan")
    _check(res, {"stiffness_N_per_m": 1e6, "slip_force_N": 10.0, "beta": 0.5})
    assert res.parameters["chi"] == pytest.approx(-0.5, abs=0.025)  # 5 % of chi
    assert res.status == "ok"


def test_rough_joint_recovered():
    """Paper 002's joint (14 x 9 cells as in the rig), rotation loops from 3e-7 rad (micro-
    slip) to 1e-4 rad (gross slip)."""
    truth = RoughRotationalJoint.paper_002(n_cells=(14, 9))
    loops = noisy_loops(truth, [3e-7, 1e-6, 3e-6, 1e-5, 3e-5, 1e-4], rotational=True)
    res = fit_joint(loops, model="rough")
    _check(res, {"mu": 0.15, "initial_stiffness_Nm_per_rad": truth.initial_stiffness,
                 "summit_std_m": 0.45e-6})
    # eta (for the known R) is derived, ~ sigma^-3/2 F_3/2(h)^-1: only its interval is checked
    lo, hi = res.derived_confidence_95["summit_density_per_m2"]
    assert lo <= 2e9 <= hi
    assert res.status == "ok"
    assert res.conditioning["fitted_condition_number"] < 100


def test_rig_identify_fit_chain():
    """The lab's chain: the rig (paper 002's joint, 100 N) at 1, 2, 2.5 and 3 N of shaker force,
    its accelerometers through identify (noise-free), the four loops fitted. Measured: mu
    1.4 % and K0 0.5 % off; sigma 64 % off but flagged (its interval, +-60 %, holds the
    truth): the rig's loops are not symmetric cycles of the law (slow drift of the mean
    rotation, harmonic truncation) and only the transition loop at 2.5 N carries sigma."""
    from fricdamp.models.rotational_joint.model import RotationalJointRig, paper002_joint
    from fricdamp.signals.identify import identify_joint

    joint = paper002_joint()
    rig = RotationalJointRig(joint)
    loops = []
    for force in (1.0, 2.0, 2.5, 3.0):
        tab = rig.simulate(force, periods=16, steps_per_period=200).accelerometers()
        ident = identify_joint(tab["time"], tab["A"], tab["B"], tab["C"],
                               rig.params.geometry(), frequency_hz=30.0, diagnostics=False)
        loops.append(Loop(*ident.cycle(), rotational=True))
    res = fit_joint(loops, model="rough")
    assert res.parameters["mu"] == pytest.approx(0.15, rel=0.03)
    assert res.parameters["initial_stiffness_Nm_per_rad"] == pytest.approx(
        joint.initial_stiffness, rel=0.03)
    lo, hi = res.confidence_95["summit_std_m"]
    assert lo <= 0.45e-6 <= hi
    assert res.status == "unreliable" and any("summit_std_m" in w for w in res.warnings)
