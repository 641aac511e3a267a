"""Physical check of examples/cases/rotational_joint_paper_load.toml (paper 002's load case).

References computed here with numpy only: the Greenwood-Williamson joint of
check_rotational_joint.py (slip moment ``mu P <r>`` over the rig's cells, initial stiffness
``k0``), and the rig linearised about rest with the joint stuck (stiffness ``k0``), as
docs/cases_rotational_joint.md writes it::

    M(0) = [[I1 + m2 d3^2, m2 d3 d5, m2 d3], [m2 d3 d5, I2 + m2 d5^2, m2 d5],
            [m2 d3, m2 d5, m1 + m2]]
    K = diag(k_t + m2 g d3, m2 g d5, k_x) + k0 P P^T,  D = diag(c_t, 0, c_x),  P = [1, -1, 0]
    X = (K - w^2 M + i w D)^-1 [d_F, 0, 1] F0

Checks: the stuck modes of the summary are the eigenvalues of (K, M) (1e-6); the paper's
500 N lands below gross slip, at 80-95 % of the slip moment, and the simulated torque
amplitude is within 3 % of the linear stuck estimate k0 |X1 - X2| (partial slip softens the
joint by less than that at 85 % of the slip moment); xi between the micro-slip limit 0.1 and
its gross-slip value 4/pi; the accelerometer identification within 1 % of the model's loop.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

_spec = importlib.util.spec_from_file_location(
    "_check_rotational_joint_ref", Path(__file__).with_name("check_rotational_joint.py"))
_ref = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_ref)

#: the rig's documented defaults (RigParameters), used where the case leaves a key out
RIG = {"beam1_mass_kg": 0.4396, "beam2_mass_kg": 0.4396, "beam1_length_m": 0.2,
       "beam2_length_m": 0.2, "sensor_mass_kg": 0.00994, "sensor_a_m": -0.09,
       "sensor_b_m": 0.0, "sensor_c_m": 0.09, "shaker_arm_m": -0.1, "gravity_m_per_s2": 9.81}


def check(summary: dict, case: dict) -> None:
    m = {**_ref.DEFAULTS, **case["model"]}
    r = {**RIG, **{k: v for k, v in case["model"].items() if k in RIG}}
    joint = _ref.joint_reference({**m, "joint_cells": m["rig_joint_cells"]})
    k0, ms = joint["initial_stiffness"], joint["slip_moment_rig"]
    h = m["contact_height_m"] / 2
    m1, m2 = r["beam1_mass_kg"], r["beam2_mass_kg"]
    d3, d5 = r["beam1_length_m"] / 2 - h, r["beam2_length_m"] / 2 - h
    i1 = m1 * r["beam1_length_m"] ** 2 / 12 + r["sensor_mass_kg"] * (
        r["sensor_a_m"] ** 2 + r["sensor_b_m"] ** 2)                       # 002 (9)
    i2 = m2 * r["beam2_length_m"] ** 2 / 12 + r["sensor_mass_kg"] * r["sensor_c_m"] ** 2
    g = r["gravity_m_per_s2"]
    M = np.array([[i1 + m2 * d3 * d3, m2 * d3 * d5, m2 * d3],
                  [m2 * d3 * d5, i2 + m2 * d5 * d5, m2 * d5],
                  [m2 * d3, m2 * d5, m1 + m2]])
    P = np.array([1.0, -1.0, 0.0])
    mod = case["model"]
    K = np.diag([mod["suspension_torsional_stiffness_Nm_per_rad"] + m2 * g * d3, m2 * g * d5,
                 mod["suspension_stiffness_N_per_m"]]) + k0 * np.outer(P, P)
    D = np.diag([mod["suspension_torsional_damping_Nms_per_rad"], 0.0,
                 mod["suspension_damping_Ns_per_m"]])
    lam = np.linalg.eigvals(np.linalg.solve(M, K))
    freqs = np.sort(np.sqrt(lam.real)) / (2 * np.pi)
    np.testing.assert_allclose(summary["model"]["natural_frequencies_stuck_hz"], freqs,
                               rtol=1e-6)

    ident = summary["identification"]
    spec = case["analysis"]["identification"]
    f0, w = spec["force_amplitude_N"], 2 * np.pi * spec["frequency_hz"]
    X = np.linalg.solve(K - w * w * M + 1j * w * D, np.array([r["shaker_arm_m"], 0, 1]) * f0)
    linear_torque = k0 * abs(X[0] - X[1])
    assert ident["slip_moment_Nm"] == pytest.approx(ms, rel=1e-9)
    assert 0.8 < linear_torque / ms < 0.95
    torque = ident["torque_amplitude_Nm_model"]
    assert torque == pytest.approx(linear_torque, rel=0.03)
    assert torque < 0.99 * ms                       # below gross slip (docs' definition)
    assert 0.1 < ident["damping_ratio_identified"] < 4 / np.pi
    assert ident["relative_error"] < 0.01
