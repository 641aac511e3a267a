"""Physical check of examples/cases/tieboss_wheel_solid.toml (paper 003 on solid sectors,
issue 12).

References, computed here independently of the case's analyses where a computation is
involved:

* Paper 003 Table 1 (FEM column, typed in below from the paper): the open-contact first
  family within 1 % of each pair's mean at 2-6 ND, and 15ND within 1 % of the 50.3 Hz the
  paper quotes as the limit; the family rises with ND.
* The paper's mesh density: >= 3,000 elements per sector (89,000 for the 30-sector wheel) and
  >= 25 node pairs per contact face.
* The prestress of every tie-boss is the paper's 2.4 N (003 section 2.4), reached through the
  structure's compliance by the calibrated interference.
* Paper 003 section 3.2: the 6ND mode is damped more than the 2ND mode; the log decrement
  recomputed here from the reported envelope peaks, ``delta = ln(A_first / A_last) / cycles``,
  agrees with the reported ratio to 30 % (the decay is Coulomb-like, nearly linear, so a
  two-point decrement and the record average differ by up to that much).
* Paper 003 Table 2: critical speeds 334 rpm (o = 1, 2ND) and 123 rpm (o = 3, 6ND) within
  2.5 % (n = 60 f / (p o) inherits the frequencies' error: Table 1 within 1 %, and the
  paper's measured f_R differ from its own FEM by up to 1.3 %, 49.20 against 48.56 Hz at 6ND);
  each solves f = p o n / 60 and the Ritz branches equal a direct solution there (1e-6); the
  blades stiffen with speed.
* Damping converged in the penalty factor: between the two largest factors (10 and 100 E A / h,
  at the same prestress) the ratios move by less than 5 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

#: 003 Table 1, FEM column: pairs of split eigenfrequencies [Hz] by ND
TABLE1 = {2: (44.32, 44.39), 3: (46.14, 46.20), 4: (47.37, 47.42), 5: (48.10, 48.22),
          6: (48.54, 48.58)}


def check(summary: dict, case: dict) -> None:
    m = summary["model"]
    assert m["element_type"] == "tet10"
    assert m["n_elements_sector"] >= 3000
    assert 30 * m["n_elements_sector"] >= 89000
    assert m["contact_pairs_per_tieboss"] >= 25
    assert m["prestress_normal_force_N"] == pytest.approx(2.4, rel=1e-3)
    f = np.asarray(summary["modal"]["frequency_hz"])
    for nd, pair in TABLE1.items():
        assert f[nd] == pytest.approx(np.mean(pair), rel=0.01), nd
    assert f[15] == pytest.approx(50.3, rel=0.01)
    assert np.all(np.diff(f[2:]) > 0)
    assert summary["modal"]["reduction_max_error"] < 1e-3
    decay = {e["nd"]: e for e in summary["decay"]}
    for e in decay.values():
        assert e["initial_amplitude_m"] == pytest.approx(5e-4, rel=0.02)
        assert e["energy_balance_error"] < 5e-3
        env_t, env = np.asarray(e["envelope_time_s"]), np.abs(e["envelope_m"])
        cycles = (env_t[-1] - env_t[0]) * e["frequency_hz"]
        delta = math.log(env[0] / env[-1]) / cycles
        zeta = delta / math.sqrt(4 * math.pi ** 2 + delta ** 2)
        assert e["damping_ratio"] == pytest.approx(zeta, rel=0.3)
        assert sum(e["state_fractions"].values()) == pytest.approx(1.0)
    assert decay[6]["damping_ratio"] > decay[2]["damping_ratio"]
    pc = summary["penalty_convergence"]
    assert pc["penalty_factor"][-1] / pc["penalty_factor"][0] >= 100
    for key in ("damping_ratio_2nd", "damping_ratio_6nd"):
        z = np.asarray(pc[key])
        assert abs(z[-1] / z[-2] - 1.0) < 0.05, (key, z)
    camp = summary["campbell_by_nd"]
    assert camp["ritz_error"] < 1e-6
    assert np.all(np.asarray(camp["frequency_change_hz"]) > 0)
    crit = {c["nd"]: c for c in summary["critical_speeds_rpm"]}
    assert crit[2]["rpm"] == pytest.approx(334.0, rel=0.025)
    assert crit[6]["rpm"] == pytest.approx(123.0, rel=0.025)
    for c in crit.values():
        assert c["frequency_hz"] == pytest.approx(8 * c["order"] * c["rpm"] / 60, rel=1e-8)
