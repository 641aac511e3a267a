"""Paper 002's test structure: two rigid beams, a rotational friction joint, three accelerometers.

Bouchaala et al. (2014) measure the damping of a lap joint rotating about its bolt: beam 1
(the upper beam, suspended, driven by a shaker at D, carrying accelerometers A and B) and
beam 2 (hanging from the joint O, carrying C). Three coordinates describe the motion
(002 §3.2, Fig. 6): the rotations ``theta1``, ``theta2`` of the beams and the horizontal
displacement ``x1`` of the centre of mass G1 of beam 1, which moves horizontally only
(002 (2)). Positions along the beams follow :mod:`fricdamp.signals.identify` (on beam 1 from
G1 towards O; on beam 2 from O, G2 at ``d5``, C at ``d5 + d4``), ``Z0`` points down.

Equations of motion
-------------------
With the kinetic energy 002 (4) and the potential 002 (5), Lagrange's equations (A.1) give
002 (6) / (A.2)::

    M(q) q'' + h(q, q') + g(q) + s(q, q') + P^T f_joint(theta1 - theta2) = Q(t, q)

    M(q) = [[I1 + m2 d3^2,           m2 d3 d5 cos(t1 - t2),  m2 d3 cos t1],
            [m2 d3 d5 cos(t1 - t2),  I2 + m2 d5^2,           m2 d5 cos t2],
            [m2 d3 cos t1,           m2 d5 cos t2,           m1 + m2     ]]
    h = [ m2 d3 d5 t2'^2 sin(t1 - t2),
         -m2 d3 d5 t1'^2 sin(t1 - t2),
         -m2 d5 t2'^2 sin t2 - m2 d3 t1'^2 sin t1]
    g = [m2 g d3 sin t1, m2 g d5 sin t2, 0]

for ``q = (theta1, theta2, x1)``. (The velocity term of the second line of (A.2) lacks the
factor d3 that (6) and (8) have; tests/unit/test_rotational_joint_lagrange.py derives the
equations from the positions with sympy.) The joint torque acts between the beams through
``P = [1, -1, 0]``: ``f_joint`` is any :class:`~fricdamp.contact.base.ContactLaw` with one
direction (e.g. :class:`~fricdamp.contact.rough.RoughRotationalJoint`, the paper's extended
Greenwood model, or a :class:`~fricdamp.contact.jenkins.Jenkins` element), and the second
line is then exactly 002 (8) with ``M = f_joint``.

Where the shaker acts. 002 (8) has the joint torque as the only generalised force of
``theta2``: the shaker must therefore drive beam 1 (the text's "shaker attached to the upper
beam" and (2)'s "x1 ... due to the driving force" agree; (B.3)'s "P1 (lower beam)" does not).
A horizontal force F at D, at position ``d_F`` on beam 1, does the virtual work
``F (delta x1 + d_F cos(theta1) delta theta1)``, so ``Q = F(t) [d_F cos theta1, 0, 1]``.

Beam 1 hangs in an elastic suspension (strings and the shaker's stinger) that the paper does
not model; ``s = [k_t theta1 + c_t theta1', 0, k_x x1 + c_x x1']`` keeps the free-free
structure from drifting under the shaker and damps the start-up transient. It acts on beam 1
only, so it does not enter (8) nor the identification.

Integration: Newmark's average-acceleration rule on the full nonlinear equations, with a
Newton iteration on the three coordinates at each step (the contact law's consistent tangent
in the Jacobian, the angle-derivatives of the mass matrix omitted: they are of the order of
the angles). The law is stepped from the converged state of the previous step, as the
contact protocol requires. :meth:`RotationalJointRig.linearised_system` gives the small-angle
:class:`~fricdamp.structure.MechanicalSystem` for the generic solvers.

Layout: the rig (:class:`RigParameters`, :class:`RigResponse`, :class:`RotationalJointRig`,
:func:`paper002_joint`) is in :mod:`fricdamp.models.rotational_joint._rig`, its compiled
equations and the Newmark integrator in :mod:`fricdamp.models.rotational_joint._dynamics`, the
joint curves (:func:`symmetric_cycle`, :func:`joint_curves`, :class:`JointCurves`) in
:mod:`fricdamp.models.rotational_joint._curves`; this module holds the closed-loop
identification (:func:`closed_loop_identification`, :func:`paper002_results`) and re-exports
the others.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from fricdamp.contact.base import ContactLaw
from fricdamp.models.rotational_joint._curves import (
    JointCurves,
    joint_curves,
    masing_descent_kernel,  # noqa: F401 - re-exported
    symmetric_cycle,
)
from fricdamp.models.rotational_joint._rig import (
    RigParameters,
    RigResponse,
    RotationalJointRig,
    paper002_joint,
)
from fricdamp.signals.identify import JointIdentification, identify_joint

log = logging.getLogger(__name__)

__all__ = [
    "ClosedLoopResult",
    "JointCurves",
    "RigParameters",
    "RigResponse",
    "RotationalJointRig",
    "closed_loop_identification",
    "joint_curves",
    "paper002_joint",
    "paper002_results",
    "symmetric_cycle",
]


# ============================================================================ closed loop
@dataclass(frozen=True)
class ClosedLoopResult:
    """Rig simulated with a joint law, accelerometers sampled, pipeline run (002 Fig. 7).

    Attributes
    ----------
    response : RigResponse
    identification : JointIdentification
    model_energy : float
        Loop area of the joint law over the analysed periods, per cycle [J].
    identified_energy : float
        The pipeline's dissipated energy per cycle [J].
    relative_error : float
        ``|identified - model| / model``.
    noise : float
        Noise level of the accelerometers (fraction of each channel's RMS).
    """

    response: RigResponse
    identification: JointIdentification
    model_energy: float
    identified_energy: float
    relative_error: float
    noise: float = 0.0

    def to_dict(self) -> dict:
        """The ``identification`` block of the results contract (+ context)."""
        ident = self.identification
        r, _ = self.response.steady_loop(ident.n_periods)
        return {"dissipated_energy_J_model": float(self.model_energy),
                "dissipated_energy_J_identified": float(self.identified_energy),
                "relative_error": float(self.relative_error),
                "force_amplitude_N": float(self.response.force_amplitude),
                "frequency_hz": float(self.response.frequency_hz),
                "rotation_amplitude_rad_model": 0.5 * float(np.ptp(r)),
                "rotation_amplitude_rad_identified": float(ident.rotation_amplitude),
                "damping_ratio_identified": float(ident.damping_ratio),
                "noise_fraction": float(self.noise),
                "n_periods": int(ident.n_periods),
                "kinematics": ident.kinematics,
                **(ident.force_check.to_dict() if ident.force_check is not None else {})}

    def plot(self, ax=None):
        """Model loop and identified loop on one axes; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5.5, 4.2))
        r, f = self.response.steady_loop(1)
        r0 = r - r.mean()
        ax.plot(1e3 * np.append(r0, r0[0]), np.append(f, f[0]) - f.mean(), "k-", lw=2.2,
                alpha=0.4, label=f"model, E_d = {self.model_energy:.4g} J")
        self.identification.plot(ax, label=f"identified, E_d = {self.identified_energy:.4g} J")
        ax.set_title(f"closed loop, F0 = {self.response.force_amplitude:g} N, noise "
                     f"{100 * self.noise:g} %")
        return ax


def closed_loop_identification(rig: RotationalJointRig, force_amplitude: float, *,
                               frequency_hz: float = 30.0, periods: int = 30,
                               analysed_periods: int = 10, steps_per_period: int = 400,
                               noise: float = 0.0, seed: int | None = 0,
                               gravity_sensing: bool = False,
                               response: RigResponse | None = None,
                               use_force: bool = False,
                               **identify_options) -> ClosedLoopResult:
    """Simulate the rig, sample the accelerometers, run the pipeline, compare loop energies.

    Parameters
    ----------
    rig : RotationalJointRig
    force_amplitude : float
        Shaker force amplitude [N].
    frequency_hz : float, optional
        Excitation frequency [Hz]; default 30.
    periods : int, optional
        Simulated periods (the first ones are the start-up transient); default 30.
    analysed_periods : int, optional
        Last periods given to the pipeline and used for the model's loop energy; default 10.
    steps_per_period : int, optional
        Time steps (= samples) per period; default 400.
    noise : float, optional
        Accelerometer noise, fraction of each channel's RMS; default 0.
    seed : int, optional
        Noise seed.
    gravity_sensing : bool, optional
        The synthetic sensors read gravity's tangential component (pass
        ``kinematics="exact", gravity_sensing=True`` to the pipeline to account for it).
    response : RigResponse, optional
        Reuse a simulation instead of running one.
    use_force : bool, optional
        Give the pipeline the simulated shaker force and the rig's beam 1
        (:meth:`RigParameters.driven_beam`): the second torque estimate and the energy
        balance (:class:`~fricdamp.signals.identify.ForceCheck`); default False.
    **identify_options
        Passed to :func:`fricdamp.signals.identify.identify_joint` (``kinematics``,
        ``filter``, ...).

    Returns
    -------
    ClosedLoopResult
    """
    if response is None:
        response = rig.simulate(force_amplitude, frequency_hz=frequency_hz, periods=periods,
                                steps_per_period=steps_per_period)
    tab = response.accelerometers(noise=noise, seed=seed, gravity_sensing=gravity_sensing)
    if gravity_sensing and identify_options.get("kinematics") == "exact":
        identify_options.setdefault("gravity_sensing", True)
    if use_force:
        identify_options.setdefault("force", tab["force"])
        identify_options.setdefault("driven_beam", rig.params.driven_beam())
    ident = identify_joint(tab["time"], tab["A"], tab["B"], tab["C"], rig.params.geometry(),
                           frequency_hz=response.frequency_hz, periods=analysed_periods,
                           source="simulated rig", **identify_options)
    e_model = response.dissipated_energy(ident.n_periods)
    e_id = ident.dissipated_energy
    err = abs(e_id - e_model) / abs(e_model) if e_model else float("inf")
    return ClosedLoopResult(response, ident, e_model, e_id, err, float(noise))


def paper002_results(*, amplitudes=None, force_amplitude: float = 5.0,
                     frequency_hz: float = 30.0, noise: float = 0.0, periods: int = 20,
                     steps_per_period: int = 200, analysed_periods: int = 8,
                     kinematics: str = "paper", joint: ContactLaw | None = None,
                     params: RigParameters | None = None):
    """Paper 002's results contract: joint curves (Figs 16-17) and one closed-loop check.

    Parameters
    ----------
    amplitudes : sequence of float, optional
        Rotation amplitudes of the joint curves [rad]; default 41 from 1e-7 to 0.1.
    force_amplitude : float, optional
        Shaker force of the closed-loop check [N]; default 5 (gross slip sets in at ~2.5 N
        with the default rig and joint).
    frequency_hz, noise, periods, steps_per_period, analysed_periods, kinematics
        See :func:`closed_loop_identification`.
    joint : ContactLaw, optional
        The joint law; default ``RoughRotationalJoint.paper_002()`` (28 x 18 cells) for the
        curves and :func:`paper002_joint` (14 x 9 cells) in the rig.
    params : RigParameters, optional
        The rig (default: the documented assumptions).

    Returns
    -------
    summary : dict
        ``{"joint": {"amplitude_rad", "dissipated_energy_J", "damping_ratio", ...},
        "identification": {"dissipated_energy_J_model", "dissipated_energy_J_identified",
        "relative_error", ...}}``.
    curves : JointCurves
        For the figures (``plot_loops``, ``plot_energy``, ``plot_damping``).
    closed_loop : ClosedLoopResult
        For the loop figure (``plot``).
    """
    from fricdamp.contact.rough import RoughRotationalJoint

    amps = np.logspace(-7, -1, 41) if amplitudes is None else amplitudes
    curves = joint_curves(RoughRotationalJoint.paper_002() if joint is None else joint, amps)
    rig = RotationalJointRig(paper002_joint() if joint is None else joint, params)
    cl = closed_loop_identification(rig, force_amplitude, frequency_hz=frequency_hz,
                                    periods=periods, analysed_periods=analysed_periods,
                                    steps_per_period=steps_per_period, noise=noise,
                                    kinematics=kinematics)
    return {"joint": curves.to_dict(), "identification": cl.to_dict()}, curves, cl
