"""The shaker's force channel in the joint identification (:mod:`fricdamp.signals.identify`).

Paper 002 measures the shaker force F at D (§2, Fig. 4) but its torque comes from the
accelerometers alone, through the Lagrange equation of beam 2, 002 (8). The other two
equations of 002 (6) / (A.2) are redundant once F is measured, and give two checks:

**Torque from the force** (the ``theta1`` equation, the first line of 002 (6) with the
joint torque that beam 2 returns to beam 1, and the suspension of beam 1)::

    M_F = F d_F cos(theta1)                                  (moment of F about G1's line)
          - (I1 + m2 d3^2) theta1'' - m2 d3 x1'' cos(theta1)
          - m2 d3 d5 (theta2'' cos(theta1 - theta2) + theta2'^2 sin(theta1 - theta2))
          - m2 g d3 sin(theta1) - k_t theta1 - c_t theta1'

It needs what beam 1 is (mass, inertia I1 about G1, the shaker's position d_F, its
suspension: :class:`DrivenBeam`), not beam 2's inertia, so it is a second, largely
independent estimate of the joint torque: a force-sensor calibration error e moves it by
``e F d_F``, a wrong I2 or m2 moves the other one. It is the small remainder of the
equation's terms when beam 1 is held by a stiff suspension (``amplification``, the largest
term over the joint torque: 2-4 for the default free-hanging rig, ~440 for
``RigParameters.paper_load_case()``, where even the simulated rig's own time-discretisation
error of 1e-4 leaves 7 % between the two torques and the check flags it).

The ``x1`` equation (the third line) gives the force the measured accelerations need; its
RMS difference from the measured force is reported too (``force_relative_rms_difference``).

**Energy balance** over whole periods of the steady state (every other term of the
equations is conservative and returns its energy each cycle)::

    W_in = ∮ F (dx1 + d_F cos(theta1) dtheta1)       work of the shaker at D
    E_rig = ∮ c_x x1' dx1 + ∮ c_t theta1' dtheta1   the suspension's known damping
    W_in = E_rig + E_d                               E_d the joint's loop area from (8)

Both are reported (``torque_from_force``, ``energy_balance`` in ``identification.json``)
and the result is unreliable when the two torques differ by more than
``max_torque_discrepancy`` (RMS of the difference over the RMS of the torque) or the
balance misses by more than ``max_energy_imbalance`` of the input work
(:class:`~fricdamp.signals._identify_trust.TrustThresholds`). Exact signals of the
simulated rig meet both to better than 1e-3 (tests/unit/test_identify_force.py).

The balance resolves E_d only where the joint takes a noticeable share of the input: in
micro-slip the suspension (or any rig damping) takes nearly all of it, and the balance then
checks the calibration of the force against the accelerometers, not E_d (the report says
so in ``joint_share_of_input`` and a note).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.signals._identify_core import first_harmonic, spectral

__all__ = ["DrivenBeam", "ForceCheck", "FORCE_UNITS", "force_check"]

#: Force units understood in signal headers, and their factor to N.
FORCE_UNITS: dict[str, float] = {"n": 1.0, "kn": 1e3, "mn": 1e-3, "lbf": 4.4482216152605,
                                 "kgf": 9.80665}


@dataclass(frozen=True)
class DrivenBeam:
    """Beam 1 of paper 002's rig and its shaker: what the force channel's checks need.

    Positions follow :mod:`fricdamp.signals.identify` (on beam 1 from G1 towards the
    joint). The suspension of beam 1 (strings, stinger) is the rig's known stiffness and
    damping; a free-free rig has zeros there.

    Parameters
    ----------
    beam1_mass : float
        m1 [kg], > 0 (with the sensors it carries).
    beam1_inertia : float
        I1, moment of inertia of beam 1 about G1 [kg m^2], > 0 (002 (9)).
    shaker_arm : float
        d_F, position of the shaker's point D on beam 1 [m] (the top end of a 200 mm beam:
        -0.1).
    suspension_stiffness, suspension_damping : float, optional
        k_x [N/m], c_x [N s/m] of the horizontal suspension of G1, >= 0; default 0.
    suspension_torsional_stiffness, suspension_torsional_damping : float, optional
        k_t [N m/rad], c_t [N m s/rad] of the rotational suspension of beam 1, >= 0;
        default 0.
    """

    beam1_mass: float
    beam1_inertia: float
    shaker_arm: float
    suspension_stiffness: float = 0.0
    suspension_damping: float = 0.0
    suspension_torsional_stiffness: float = 0.0
    suspension_torsional_damping: float = 0.0

    def __post_init__(self):
        for name, unit in (("beam1_mass", "kg"), ("beam1_inertia", "kg m^2")):
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name),
                                                                unit=unit)))
        object.__setattr__(self, "shaker_arm", float(as_finite_array(
            "shaker_arm", self.shaker_arm, ndim=0)))
        for f in fields(self)[3:]:
            object.__setattr__(self, f.name, float(check_positive(
                f.name, getattr(self, f.name), allow_zero=True)))


@dataclass(frozen=True)
class ForceCheck:
    """The force channel's two checks on one identification (module docstring).

    Attributes
    ----------
    torque : ndarray, shape (m,)
        M_F, the joint torque from the ``theta1`` equation and the force [N m].
    torque_discrepancy : float
        ``rms(M_F - M) / rms(M)`` over the window [-].
    force_discrepancy : float
        ``rms(F_acc - F) / rms(F)``, F_acc the force that the ``x1`` equation of 002 (6)
        needs for the measured accelerations (with k_x, c_x) [-]; reported, not judged.
    dissipated_energy : float
        Loop area of M_F against the joint rotation, per cycle [J].
    input_work, rig_dissipation, joint_dissipation : float
        W_in, E_rig and E_d per cycle [J].
    warnings : tuple of str
        Reasons for "unreliable" (limits exceeded).
    notes : tuple of str
        Findings that are not reasons (the balance cannot resolve E_d).
    amplification : float
        Conditioning of M_F: the largest term of the ``theta1`` equation over the joint
        torque (amplitudes of the fundamentals) [-]; a relative error e of that term moves
        M_F by about ``e x amplification`` of the torque.
    max_torque_discrepancy, max_energy_imbalance : float
        The limits used.
    """

    torque: np.ndarray
    torque_discrepancy: float
    force_discrepancy: float
    dissipated_energy: float
    input_work: float
    rig_dissipation: float
    joint_dissipation: float
    warnings: tuple = ()
    notes: tuple = ()
    amplification: float = float("nan")
    max_torque_discrepancy: float = 0.02
    max_energy_imbalance: float = 0.02

    @property
    def imbalance(self) -> float:
        """``W_in - E_rig - E_d`` per cycle [J]."""
        return self.input_work - self.rig_dissipation - self.joint_dissipation

    @property
    def imbalance_relative(self) -> float:
        """The imbalance over the input work [-]."""
        w = abs(self.input_work)
        return abs(self.imbalance) / w if w > 0 else float("inf")

    def to_dict(self) -> dict:
        """``{"torque_from_force": {...}, "energy_balance": {...}}`` for identification.json."""
        e_d = self.joint_dissipation
        rel_e = (abs(self.dissipated_energy - e_d) / abs(e_d)) if e_d else float("inf")
        share = e_d / self.input_work if self.input_work else float("nan")
        return {
            "torque_from_force": {
                "dissipated_energy_J": float(self.dissipated_energy),
                "energy_relative_difference": float(rel_e),
                "torque_relative_rms_difference": float(self.torque_discrepancy),
                "torque_amplitude_Nm": 0.5 * float(np.ptp(self.torque)),
                "force_relative_rms_difference": float(self.force_discrepancy),
                "amplification": float(self.amplification),
                "limit": float(self.max_torque_discrepancy),
                "definition": "theta1 equation of 002 (6) with the measured force; "
                              "rms(M_F - M) / rms(M)",
            },
            "energy_balance": {
                "input_work_J": float(self.input_work),
                "rig_dissipation_J": float(self.rig_dissipation),
                "joint_dissipation_J": float(e_d),
                "residual_J": float(self.imbalance),
                "residual_relative_to_input": float(self.imbalance_relative),
                "joint_share_of_input": float(share),
                "limit": float(self.max_energy_imbalance),
                "definition": "per cycle: W_in = E_rig + E_d; residual over W_in",
            },
        }


def force_check(force, loop, dt: float, n_periods: int, geometry, beam: DrivenBeam, *,
                filter: str = "harmonic", n_harmonics=None, f_low=None,
                max_torque_discrepancy: float = 0.02,
                max_energy_imbalance: float = 0.02) -> ForceCheck:
    """Second torque estimate and energy balance from the window's force samples.

    Parameters
    ----------
    force : ndarray, shape (m,)
        Shaker force on the window of whole periods that gave ``loop`` [N].
    loop : WindowLoop
        The processed window (:func:`fricdamp.signals._identify_core.process_window`).
    dt : float
        Sampling interval of the window [s].
    n_periods : int
    geometry : JointRigGeometry
    beam : DrivenBeam
    filter, n_harmonics, f_low
        The filter of the accelerations, applied to the force too (same phase, same lines).
    max_torque_discrepancy, max_energy_imbalance : float
        Limits of the two checks.
    """
    if not isinstance(beam, DrivenBeam):
        raise ModelError(f"driven_beam must be a DrivenBeam, got {type(beam).__name__}")
    f = np.asarray(force, dtype=float)
    n = loop.rotation.shape[0]
    if f.shape != (n,):
        raise ModelError(f"force window has shape {f.shape}, the accelerations' {(n,)}")
    f_low = 0.0 if f_low is None else f_low
    F, _, _, _ = spectral(f[:, None], dt, n_periods, filter, n_harmonics, f_low)
    F = F[:, 0]
    # velocities of the three coordinates from the filtered accelerations
    _, vel, _, _ = spectral(loop.acc, dt, n_periods, filter, n_harmonics, f_low)
    w1, w2, vx = vel[:, 0], vel[:, 1], vel[:, 2]
    a1, a2, ax = loop.acc[:, 0], loop.acc[:, 1], loop.acc[:, 2]
    t1, t2, x1 = loop.theta1, loop.theta2, loop.x1
    m2, d3, d5, g = geometry.beam2_mass, geometry.joint_arm1, geometry.joint_arm2, \
        geometry.gravity
    rel = t1 - t2
    dF = beam.shaker_arm
    terms = (F * dF * np.cos(t1),  # theta1 equation of 002 (6) / (A.2), solved for M
             -(beam.beam1_inertia + m2 * d3 * d3) * a1, -m2 * d3 * ax * np.cos(t1),
             -m2 * d3 * d5 * (a2 * np.cos(rel) + w2 * w2 * np.sin(rel)),
             -m2 * g * d3 * np.sin(t1),
             -beam.suspension_torsional_stiffness * t1 - beam.suspension_torsional_damping * w1)
    mf = sum(terms)
    # conditioning: the largest term of the equation over the joint torque (fundamentals)
    m1 = float(first_harmonic(loop.torque, n_periods))
    biggest = max(float(first_harmonic(x, n_periods)) for x in terms)
    amplification = biggest / m1 if m1 > 0 else float("inf")
    # x1 equation of 002 (6): the force the accelerations need (reported, not judged)
    f_acc = ((beam.beam1_mass + m2) * ax + m2 * d5 * (a2 * np.cos(t2) - w2 * w2 * np.sin(t2))
             + m2 * d3 * (a1 * np.cos(t1) - w1 * w1 * np.sin(t1))
             + beam.suspension_stiffness * x1 + beam.suspension_damping * vx)
    f_rms = float(np.sqrt(np.mean(F * F)))
    f_disc = float(np.sqrt(np.mean((f_acc - f_acc.mean() - F) ** 2)) / f_rms) if f_rms > 0 \
        else float("inf")
    M = loop.torque
    rms = float(np.sqrt(np.mean((M - M.mean()) ** 2)))
    diff = (mf - mf.mean()) - (M - M.mean())
    disc = float(np.sqrt(np.mean(diff ** 2)) / rms) if rms > 0 else float("inf")

    def circ(force_like, coord):  # ∮ force d(coord) per cycle, closed trapezoids
        inc = 0.5 * (force_like + np.roll(force_like, -1)) * (np.roll(coord, -1) - coord)
        return float(np.sum(inc)) / n_periods

    def circ_rate(force_like, rate):  # ∮ force(t) coord'(t) dt: exact for harmonics
        return float(np.sum(force_like * rate)) * dt / n_periods

    e_f = circ(mf, rel)
    w_in = circ_rate(F, vx + dF * np.cos(t1) * w1)
    e_rig = (beam.suspension_damping * circ_rate(vx, vx)
             + beam.suspension_torsional_damping * circ_rate(w1, w1))
    e_d = float(loop.energy)
    reasons, notes = [], []
    if not disc <= max_torque_discrepancy:
        reasons.append(f"the joint torque from the shaker force differs from the one of 002 "
                       f"(8) by {100 * disc:.3g} % RMS (limit {100 * max_torque_discrepancy:g}"
                       " %): check the force channel's calibration, the rig's beam-1 "
                       "parameters (m1, I1, d_F, suspension) and the accelerometers"
                       + (f"; the theta1 equation's largest term is {amplification:.3g} x the "
                          "joint torque, so relative errors of "
                          f"{max_torque_discrepancy / amplification:.2g} in it are enough"
                          if amplification > 10 else ""))
    imb = w_in - e_rig - e_d
    rel_imb = abs(imb) / abs(w_in) if w_in else float("inf")
    if not rel_imb <= max_energy_imbalance:
        reasons.append(f"energy balance: the shaker's work {w_in:.4g} J per cycle minus the "
                       f"rig's damping {e_rig:.4g} J and the joint's {e_d:.4g} J leaves "
                       f"{100 * rel_imb:.3g} % of the input (limit "
                       f"{100 * max_energy_imbalance:g} %): a calibration error of the force "
                       "or the accelerometers, or damping the rig file does not give")
    if w_in > 0 and abs(e_d) < max_energy_imbalance * abs(w_in):
        notes.append(f"the joint dissipates {100 * e_d / w_in:.3g} % of the shaker's work: "
                     "the energy balance checks the calibration but cannot confirm E_d")
    return ForceCheck(torque=mf, torque_discrepancy=disc, force_discrepancy=f_disc,
                      amplification=float(amplification),
                      dissipated_energy=e_f,
                      input_work=w_in, rig_dissipation=e_rig, joint_dissipation=e_d,
                      warnings=tuple(reasons), notes=tuple(notes),
                      max_torque_discrepancy=float(max_torque_discrepancy),
                      max_energy_imbalance=float(max_energy_imbalance))
