"""Paper 002's test structure: two rigid beams, a rotational friction joint, three accelerometers.

Bouchaala et al. (2014) measure the damping of a lap joint rotating about its bolt: beam 1
(the upper beam, suspended, driven by a shaker at D, carrying accelerometers A and B) and
beam 2 (hanging from the joint O, carrying C). Three coordinates describe the motion
(002 §3.2, Fig. 6): the rotations ``theta1``, ``theta2`` of the beams and the horizontal
displacement ``x1`` of the centre of mass G1 of beam 1, which moves horizontally only
(002 (2)). Positions along the beams follow :mod:`fricdamp.analysis.identify` (on beam 1 from
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
"""

from __future__ import annotations

import logging
import math
import time as _time
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace

import numpy as np
from numba import njit

from fricdamp.analysis.damping import paper002_damping_ratio
from fricdamp.analysis.energy import loop_area
from fricdamp.analysis.identify import (
    JointIdentification,
    JointRigGeometry,
    identify_joint,
)
from fricdamp.analysis.signals import SignalTable
from fricdamp.contact.base import ContactLaw
from fricdamp.errors import ConvergenceError, ModelError, as_finite_array, check_positive
from fricdamp.structure.system import ContactElement, HarmonicLoad, MechanicalSystem

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


# ============================================================================ parameters
@dataclass(frozen=True)
class RigParameters:
    """Parameters of paper 002's test structure (SI units).

    From the paper: the accelerometer mass ``m_c = 9.94 g`` (§3.2), the inertias
    002 (9)-(10) (with B at G1, ``d2 = 0``, (9) is the formula below), the excitation
    frequency 30 Hz and force range 60-500 N (§3.4, used by :meth:`RotationalJointRig.simulate`
    callers), the nominal contact 28 x 18 mm (which sets the 18 mm overlap, ``h = 9 mm``).
    The paper's Fig. 3 (the beams' dimensions) and Fig. 6 (the sensor positions) are not
    legible in the text; **assumed**: steel beams (7850 kg/m^3) 200 mm long, 28 mm wide and
    10 mm thick (0.4396 kg each; the first free bending mode of such a beam is near 3.7 kHz,
    so rigid beams at 30 Hz), A 10 mm from the top end of beam 1, B at G1, C 10 mm from the
    bottom end of beam 2, the shaker at the top end of beam 1, and an elastic suspension of
    beam 1 (strings and stinger; with the stuck joint the rig's modes are then 3.9 Hz,
    8.5 Hz and 1.4 kHz, the last one the joint's).

    Parameters
    ----------
    beam1_mass, beam2_mass : float
        m1, m2 [kg], > 0. Default 0.4396 (assumed).
    beam1_length, beam2_length : float
        l1, l2 [m], > 0. Default 0.2 (assumed).
    joint_offset : float
        h, distance of the joint axis from the end of each beam [m], in [0, l/2). Default
        0.009 (half the 18 mm overlap of the paper's 28 x 18 mm contact).
    sensor_mass : float
        m_c, mass of one accelerometer [kg], >= 0. Default 9.94e-3 (paper).
    sensor_a, sensor_b : float
        d1, d2: positions of A and B on beam 1 from G1 towards the joint [m], within the
        beam (|d| <= l1/2), d1 != d2. Default -0.09 and 0 (assumed).
    sensor_c : float
        d4: position of C on beam 2 from G2 away from the joint [m], |d4| <= l2/2,
        d4 + d5 != 0. Default 0.09 (assumed).
    shaker_arm : float
        d_F: position of the shaker's point D on beam 1 from G1 towards the joint [m],
        |d_F| <= l1/2. Default -0.1, the top end (assumed).
    gravity : float
        g [m/s^2], >= 0. Default 9.81.
    suspension_stiffness : float
        k_x, horizontal stiffness of the suspension of beam 1 [N/m], >= 0. Default 870.
    suspension_damping : float
        c_x [N s/m], >= 0. Default 16.6.
    suspension_torsional_stiffness : float
        k_t, rotational stiffness of the suspension of beam 1 [N m/rad], >= 0. Default 17.4.
    suspension_torsional_damping : float
        c_t [N m s/rad], >= 0. Default 0.33.

    Examples
    --------
    >>> p = RigParameters()
    >>> round(p.joint_arm1, 4), round(p.inertia2 * 1e3, 4)   # d3 [m], I2 [g m^2]
    (0.091, 1.5458)
    """

    beam1_mass: float = 0.4396
    beam2_mass: float = 0.4396
    beam1_length: float = 0.200
    beam2_length: float = 0.200
    joint_offset: float = 0.009
    sensor_mass: float = 9.94e-3
    sensor_a: float = -0.090
    sensor_b: float = 0.0
    sensor_c: float = 0.090
    shaker_arm: float = -0.100
    gravity: float = 9.81
    suspension_stiffness: float = 870.0
    suspension_damping: float = 16.6
    suspension_torsional_stiffness: float = 17.4
    suspension_torsional_damping: float = 0.33

    def __post_init__(self):
        for f in fields(self):
            v = as_finite_array(f.name, getattr(self, f.name), ndim=0)
            object.__setattr__(self, f.name, float(v))
        for name in ("beam1_mass", "beam2_mass"):
            check_positive(name, getattr(self, name), unit="kg")
        for name in ("beam1_length", "beam2_length"):
            check_positive(name, getattr(self, name), unit="m")
        for name, unit in (("sensor_mass", "kg"), ("gravity", "m/s^2"),
                           ("suspension_stiffness", "N/m"), ("suspension_damping", "N s/m"),
                           ("suspension_torsional_stiffness", "N m/rad"),
                           ("suspension_torsional_damping", "N m s/rad")):
            check_positive(name, getattr(self, name), unit=unit, allow_zero=True)
        half = 0.5 * min(self.beam1_length, self.beam2_length)
        if not 0.0 <= self.joint_offset < half:
            raise ModelError(f"joint_offset (h) must lie in [0, {half:g}) m (half the shorter "
                             f"beam), got {self.joint_offset!r}")
        for name, length in (("sensor_a", self.beam1_length), ("sensor_b", self.beam1_length),
                             ("shaker_arm", self.beam1_length),
                             ("sensor_c", self.beam2_length)):
            if abs(getattr(self, name)) > 0.5 * length * (1 + 1e-12):
                raise ModelError(f"{name} must lie on its beam, in [{-0.5 * length:g}, "
                                 f"{0.5 * length:g}] m, got {getattr(self, name)!r}")
        self.geometry()  # d1 != d2, d4 + d5 != 0

    @property
    def joint_arm1(self) -> float:
        """d3 = l1/2 - h [m], 002 (7)."""
        return 0.5 * self.beam1_length - self.joint_offset

    @property
    def joint_arm2(self) -> float:
        """d5 = l2/2 - h [m], 002 (7)."""
        return 0.5 * self.beam2_length - self.joint_offset

    @property
    def inertia1(self) -> float:
        """I1 = m1 l1^2/12 + m_c (d1^2 + d2^2) [kg m^2], 002 (9) (B at G1 in the paper)."""
        return (self.beam1_mass * self.beam1_length ** 2 / 12.0
                + self.sensor_mass * (self.sensor_a ** 2 + self.sensor_b ** 2))

    @property
    def inertia2(self) -> float:
        """I2 = m2 l2^2/12 + m_c d4^2 [kg m^2], 002 (10)."""
        return self.beam2_mass * self.beam2_length ** 2 / 12.0 + self.sensor_mass * \
            self.sensor_c ** 2

    def geometry(self) -> JointRigGeometry:
        """What the identification needs (:class:`~fricdamp.analysis.identify.JointRigGeometry`)."""
        return JointRigGeometry(self.sensor_a, self.sensor_b, self.joint_arm1, self.sensor_c,
                                self.joint_arm2, self.beam2_mass, self.inertia2, self.gravity)

    def with_(self, **changes) -> RigParameters:
        """Copy with some parameters changed (validated again)."""
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            raise ModelError(f"unknown rig parameter(s) {sorted(unknown)}; known: "
                             f"{[f.name for f in fields(self)]}")
        return replace(self, **changes)


def paper002_joint(*, n_cells=(14, 9), n_heights: int = 24, **overrides):
    """Paper 002's rough rotational joint (Table 2, 100 N) with a coarser grid of cells.

    :meth:`fricdamp.contact.rough.RoughRotationalJoint.paper_002` with 14 x 9 cells instead
    of 28 x 18 for time simulations of the rig (each time step steps every summit class):
    its loop energy is within 1.2 % of the full grid's from 1e-7 to 0.1 rad and within
    0.3 % above 1e-5 rad (tests/unit/test_rotational_joint.py). Fewer height classes are
    not advisable: 12 classes are 40 % off below 1e-6 rad.
    """
    from fricdamp.contact.rough import RoughRotationalJoint

    return RoughRotationalJoint.paper_002(n_cells=n_cells, n_heights=n_heights, **overrides)


# ============================================================================ response
@dataclass(frozen=True)
class RigResponse:
    """Time history of the rig from :meth:`RotationalJointRig.simulate`.

    Attributes
    ----------
    t : ndarray, shape (n_t,)
        Times [s], one per step (``steps_per_period`` per excitation period).
    q, v, a : ndarray, shape (n_t, 3)
        Coordinates ``(theta1 [rad], theta2 [rad], x1 [m])``, their velocities and
        accelerations.
    rotation : ndarray, shape (n_t,)
        Relative rotation ``theta1 - theta2`` of the joint [rad].
    torque : ndarray, shape (n_t,)
        Joint torque from the contact law [N m] (resisting the relative rotation).
    force : ndarray, shape (n_t,)
        Shaker force F(t) [N].
    energy : dict of ndarray, each (n_t,)
        Cumulative ``input_work``, ``joint_work``, ``suspension_dissipation`` and the
        instantaneous ``kinetic``, ``potential`` [J].
    frequency_hz, force_amplitude : float
        Excitation [Hz], [N].
    steps_per_period : int
    params : RigParameters
    n_newton : int
        Total Newton iterations.
    runtime_s : float
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    rotation: np.ndarray
    torque: np.ndarray
    force: np.ndarray
    energy: dict
    frequency_hz: float
    force_amplitude: float
    steps_per_period: int
    params: RigParameters
    n_newton: int = 0
    runtime_s: float = 0.0
    meta: dict = field(default_factory=dict, compare=False)

    @property
    def energy_balance_error(self) -> float:
        """max |input - d(kinetic + potential) - suspension - joint work| / max |input| [-]."""
        e = self.energy
        mech = e["kinetic"] + e["potential"]
        res = e["input_work"] - (mech - mech[0]) - e["suspension_dissipation"] - e["joint_work"]
        scale = max(float(np.max(np.abs(e["input_work"]))), 1e-300)
        return float(np.max(np.abs(res)) / scale)

    def _window(self, n_cycles: int) -> slice:
        if int(n_cycles) != n_cycles or n_cycles < 1:
            raise ModelError(f"n_cycles must be an integer >= 1, got {n_cycles!r}")
        m = int(n_cycles) * self.steps_per_period
        if m > self.t.size - 1:
            raise ModelError(f"the response holds {(self.t.size - 1) // self.steps_per_period} "
                             f"periods, {n_cycles} asked for")
        return slice(self.t.size - m, self.t.size)

    def steady_loop(self, n_cycles: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Relative rotation [rad] and joint torque [N m] over the last ``n_cycles`` periods."""
        w = self._window(n_cycles)
        return self.rotation[w], self.torque[w]

    def dissipated_energy(self, n_cycles: int = 1) -> float:
        """Energy the joint dissipates per cycle [J]: loop area over the last periods / n."""
        r, f = self.steady_loop(n_cycles)
        return loop_area(r, f) / n_cycles

    def accelerometers(self, *, noise: float = 0.0, seed: int | None = 0,
                       gravity_sensing: bool = False) -> SignalTable:
        """Readings of the accelerometers A, B, C (and the shaker force) at every step.

        The tangential (beam-fixed) accelerations of the exact kinematics
        (:mod:`fricdamp.analysis.identify`)::

            gamma_A = x1'' cos t1 + d1 t1'',  gamma_B = x1'' cos t1 + d2 t1''
            gamma_C = x1'' cos t2 + d3 (t1'' cos(t1 - t2) - t1'^2 sin(t1 - t2)) + (d4 + d5) t2''

        Parameters
        ----------
        noise : float, optional
            Standard deviation of white Gaussian noise added to each channel, as a fraction
            of that channel's RMS [-], >= 0; default 0.
        seed : int, optional
            Seed of the noise generator.
        gravity_sensing : bool, optional
            Add the tangential component of gravity ``g sin(theta)`` (what piezoelectric
            accelerometers read at the excitation frequency); default False.

        Returns
        -------
        SignalTable
            ``time`` [s], ``A``, ``B``, ``C`` [m/s^2] and ``force`` [N].
        """
        noise = float(check_positive("noise", noise, allow_zero=True))
        p = self.params
        t1, t2 = self.q[:, 0], self.q[:, 1]
        w1 = self.v[:, 0]
        a1, a2, ax = self.a[:, 0], self.a[:, 1], self.a[:, 2]
        rel = t1 - t2
        ga = ax * np.cos(t1) + p.sensor_a * a1
        gb = ax * np.cos(t1) + p.sensor_b * a1
        gc = (ax * np.cos(t2) + p.joint_arm1 * (a1 * np.cos(rel) - w1 * w1 * np.sin(rel))
              + (p.sensor_c + p.joint_arm2) * a2)
        if gravity_sensing:
            ga = ga + p.gravity * np.sin(t1)
            gb = gb + p.gravity * np.sin(t1)
            gc = gc + p.gravity * np.sin(t2)
        chans = {"A": ga, "B": gb, "C": gc}
        if noise > 0:
            rng = np.random.default_rng(seed)
            for k, x in chans.items():
                rms = float(np.sqrt(np.mean(x * x)))
                chans[k] = x + noise * rms * rng.standard_normal(x.size)
        data = {"time": self.t.copy(), **chans, "force": self.force.copy()}
        units = {"time": "s", "A": "m/s^2", "B": "m/s^2", "C": "m/s^2", "force": "N"}
        return SignalTable(data, units=units, path="<simulated rig>", time_column="time")

    def write_csv(self, path, **accelerometer_options) -> None:
        """Write the accelerometer signals as a CSV with units in the header."""
        from fricdamp.iofiles import write_text

        tab = self.accelerometers(**accelerometer_options)
        names = list(tab)
        head = ",".join(f"{n} [{tab.units[n]}]" for n in names)
        body = np.column_stack([tab[n] for n in names])
        lines = [head] + [",".join(f"{x:.12e}" for x in row) for row in body]
        write_text(path, "\n".join(lines) + "\n")


# ============================================================================ the rig
class RotationalJointRig:
    """Paper 002's 3-DOF test structure with a joint law between the beams.

    Parameters
    ----------
    joint : ContactLaw
        One contact, one direction: relative rotation ``theta1 - theta2`` [rad] in, joint
        torque [N m] out (e.g. :func:`paper002_joint`, or ``Jenkins(k, M_slip)``).
    params : RigParameters, optional
        Geometry, masses and suspension (default: the documented assumptions).

    Examples
    --------
    >>> from fricdamp.contact import Jenkins
    >>> rig = RotationalJointRig(Jenkins(stiffness=6e4, slip_force=0.13))
    >>> [round(float(f), 1) for f in rig.linear_frequencies()]  # suspension x2, joint [Hz]
    [3.9, 8.5, 1402.3]
    """

    def __init__(self, joint: ContactLaw, params: RigParameters | None = None):
        if not isinstance(joint, ContactLaw):
            raise ModelError(f"joint must be a ContactLaw, got {type(joint).__name__}")
        if joint.n_contacts != 1 or joint.n_dir != 1:
            raise ModelError(f"joint must have one contact and one direction (rotation in, "
                             f"torque out), got n_contacts={joint.n_contacts}, "
                             f"n_dir={joint.n_dir}")
        if joint.velocity_dependent:
            raise ModelError("velocity-dependent joint laws are not supported by the rig "
                             "integrator")
        self.joint = joint
        self.params = RigParameters() if params is None else params
        if not isinstance(self.params, RigParameters):
            raise ModelError(f"params must be RigParameters, got {type(self.params).__name__}")

    @classmethod
    def paper_002(cls, joint: ContactLaw | None = None, **param_overrides) -> RotationalJointRig:
        """The rig with paper 002's joint (:func:`paper002_joint`) unless another is given."""
        return cls(paper002_joint() if joint is None else joint,
                   RigParameters().with_(**param_overrides))

    def __repr__(self) -> str:
        return f"RotationalJointRig(joint={self.joint!r})"

    # ---------------------------------------------------------------- equations
    def _par(self) -> np.ndarray:
        p = self.params
        return np.array([p.inertia1, p.inertia2, p.beam1_mass, p.beam2_mass, p.joint_arm1,
                         p.joint_arm2, p.gravity, p.suspension_torsional_stiffness,
                         p.suspension_torsional_damping, p.suspension_stiffness,
                         p.suspension_damping, p.shaker_arm])

    def mass_matrix(self, q) -> np.ndarray:
        """M(q), shape (3, 3) [kg m^2, kg m, kg], 002 (A.2)."""
        return _rig_mass(_vec3("q", q), self._par())

    def internal_force(self, q, v) -> np.ndarray:
        """Velocity, gravity and suspension terms ``h + g + s`` of the equations, shape (3,)."""
        return _rig_internal(_vec3("q", q), _vec3("v", v), self._par())

    def excitation(self, q, force: float) -> np.ndarray:
        """Generalised force of the shaker ``F [d_F cos theta1, 0, 1]``, shape (3,)."""
        return _rig_excitation(_vec3("q", q), float(force), self._par())

    def kinetic_energy(self, q, v) -> float:
        """``v^T M(q) v / 2`` [J], 002 (4)."""
        return float(_rig_energies(_vec3("q", q), _vec3("v", v), self._par())[0])

    def potential_energy(self, q) -> float:
        """Gravity 002 (5) plus the suspension springs [J]."""
        return float(_rig_energies(_vec3("q", q), np.zeros(3), self._par())[1])

    # ---------------------------------------------------------------- linear model
    def joint_initial_stiffness(self) -> float:
        """Tangent stiffness of the joint law at zero rotation from its virgin state [N m/rad]."""
        r = self.joint.step(self.joint.initial_state(), np.zeros((1, 1)))
        return float(r.stiffness.reshape(-1)[0])

    def _linear_matrices(self):
        p = self.params
        M = self.mass_matrix(np.zeros(3))
        K = np.diag([p.suspension_torsional_stiffness + p.beam2_mass * p.gravity * p.joint_arm1,
                     p.beam2_mass * p.gravity * p.joint_arm2, p.suspension_stiffness])
        D = np.diag([p.suspension_torsional_damping, 0.0, p.suspension_damping])
        b = np.array([p.shaker_arm, 0.0, 1.0])
        return M, K, D, b

    def linearised_system(self, force_amplitude: float = 0.0,
                          frequency_hz: float = 30.0) -> MechanicalSystem:
        """The small-angle model as a MechanicalSystem, the joint as a ContactElement.

        ``M = M(0)``, ``K = diag(k_t + m2 g d3, m2 g d5, k_x)``, ``D = diag(c_t, 0, c_x)``,
        the joint through the projection ``[1, -1, 0]`` and the shaker load
        ``F0 sin(2 pi f t) [d_F, 0, 1]`` (a :class:`HarmonicLoad`). Exact to first order in the
        angles; usable with every generic solver (time stepping, harmonic balance).
        """
        M, K, D, b = self._linear_matrices()
        f0 = float(check_positive("force_amplitude", force_amplitude, unit="N",
                                  allow_zero=True))
        om = 2 * np.pi * float(check_positive("frequency_hz", frequency_hz, unit="Hz"))
        loads = (HarmonicLoad(-1j * f0 * b, om),) if f0 > 0 else ()
        return MechanicalSystem(M=M, K=K, D=D, loads=loads,
                                contacts=(ContactElement(self.joint, np.array([[1.0, -1.0, 0.0]]),
                                                         name="joint"),),
                                dof_names=("theta1", "theta2", "x1"),
                                name="paper 002 rig (linearised)")

    def linear_frequencies(self, joint_stiffness: float | None = None) -> np.ndarray:
        """Undamped eigenfrequencies [Hz] of the linearised rig with a linear joint.

        Parameters
        ----------
        joint_stiffness : float, optional
            Rotational stiffness of the joint [N m/rad]; default its initial stiffness
            (the stuck, micro-slip limit).
        """
        M, K, _, _ = self._linear_matrices()
        k = self.joint_initial_stiffness() if joint_stiffness is None else float(
            check_positive("joint_stiffness", joint_stiffness, unit="N m/rad", allow_zero=True))
        P = np.array([1.0, -1.0, 0.0])
        from scipy.linalg import eigh

        lam = eigh(K + k * np.outer(P, P), M, eigvals_only=True)
        return np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)

    def linear_response(self, force_amplitude: float, frequency_hz: float = 30.0,
                        joint_stiffness: float | None = None) -> np.ndarray:
        """Complex amplitudes X (3,) of the linearised steady state, ``q = Im(X e^{i w t})``.

        For the force ``F0 sin(w t)`` and a linear joint of ``joint_stiffness`` [N m/rad]
        (default the initial stiffness): ``X = (K - w^2 M + i w D)^-1 b F0``.
        """
        M, K, D, b = self._linear_matrices()
        k = self.joint_initial_stiffness() if joint_stiffness is None else float(
            check_positive("joint_stiffness", joint_stiffness, unit="N m/rad", allow_zero=True))
        P = np.array([1.0, -1.0, 0.0])
        om = 2 * np.pi * float(check_positive("frequency_hz", frequency_hz, unit="Hz"))
        Z = K + k * np.outer(P, P) - om * om * M + 1j * om * D
        return np.linalg.solve(Z, b * float(force_amplitude))

    # ---------------------------------------------------------------- simulation
    def simulate(self, force_amplitude: float, *, frequency_hz: float = 30.0,
                 periods: float = 40.0, steps_per_period: int = 400,
                 ramp_periods: float = 3.0, q0=None, v0=None, tol: float = 1e-10,
                 max_iter: int = 50) -> RigResponse:
        """Time simulation under the shaker force ``F0 r(t) sin(2 pi f t)``.

        ``r(t)`` rises smoothly from 0 to 1 over ``ramp_periods`` periods
        (``(1 - cos(pi t / T_r)) / 2``), which keeps the start-up transient of the
        suspension small. Newmark average acceleration with Newton iterations (module
        docstring).

        Parameters
        ----------
        force_amplitude : float
            F0 [N], >= 0 (paper 002: 60-500 N).
        frequency_hz : float, optional
            Excitation frequency [Hz], > 0; default 30 (paper 002).
        periods : float, optional
            Duration in excitation periods, > 0; default 40.
        steps_per_period : int, optional
            Time steps per period, >= 16; default 400.
        ramp_periods : float, optional
            Duration of the force ramp in periods, >= 0 (0: no ramp); default 3.
        q0, v0 : array_like, shape (3,), optional
            Initial coordinates and velocities (default rest); e.g. from
            :meth:`linear_response` for a start without transient.
        tol : float, optional
            Newton tolerance on the update, relative to the coordinates' scale.
        max_iter : int, optional
            Newton iterations per step before :class:`ConvergenceError`.

        Returns
        -------
        RigResponse
        """
        f0 = float(check_positive("force_amplitude", force_amplitude, unit="N",
                                  allow_zero=True))
        freq = float(check_positive("frequency_hz", frequency_hz, unit="Hz"))
        n_per = float(check_positive("periods", periods))
        if int(steps_per_period) != steps_per_period or steps_per_period < 16:
            raise ModelError(f"steps_per_period must be an integer >= 16, got "
                             f"{steps_per_period!r}")
        spp = int(steps_per_period)
        ramp = float(check_positive("ramp_periods", ramp_periods, allow_zero=True))
        q = np.zeros(3) if q0 is None else as_finite_array("q0", q0, ndim=1).copy()
        v = np.zeros(3) if v0 is None else as_finite_array("v0", v0, ndim=1).copy()
        if q.shape != (3,) or v.shape != (3,):
            raise ModelError("q0 and v0 must have 3 entries (theta1, theta2, x1)")
        h = 1.0 / (freq * spp)
        n_steps = int(round(n_per * spp))
        if n_steps < 1:
            raise ModelError(f"periods = {periods!r} is less than one step")
        om = 2 * np.pi * freq
        t_ramp = ramp / freq

        def force(t):
            r = 1.0 if t >= t_ramp else 0.5 * (1.0 - math.cos(math.pi * t / t_ramp))
            return f0 * r * math.sin(om * t)

        start = _time.perf_counter()
        out = _newmark(self, q, v, h, n_steps, force, tol, max_iter)
        return RigResponse(**out, frequency_hz=freq, force_amplitude=f0, steps_per_period=spp,
                           params=self.params, runtime_s=_time.perf_counter() - start)


def _vec3(name, x) -> np.ndarray:
    arr = as_finite_array(name, x, ndim=1)
    if arr.shape != (3,):
        raise ModelError(f"{name} must have 3 entries (theta1, theta2, x1), got {arr.shape}")
    return arr


# par = [I1, I2, m1, m2, d3, d5, g, k_t, c_t, k_x, c_x, d_F]
@njit(cache=True, nogil=True)
def _rig_mass(q, par):  # pragma: no cover - compiled
    t1, t2 = q[0], q[1]
    m2, d3, d5 = par[3], par[4], par[5]
    c12 = m2 * d3 * d5 * math.cos(t1 - t2)
    c13 = m2 * d3 * math.cos(t1)
    c23 = m2 * d5 * math.cos(t2)
    M = np.empty((3, 3))
    M[0, 0], M[0, 1], M[0, 2] = par[0] + m2 * d3 * d3, c12, c13
    M[1, 0], M[1, 1], M[1, 2] = c12, par[1] + m2 * d5 * d5, c23
    M[2, 0], M[2, 1], M[2, 2] = c13, c23, par[2] + m2
    return M


@njit(cache=True, nogil=True)
def _rig_internal(q, v, par):  # pragma: no cover - compiled
    t1, t2, x1 = q[0], q[1], q[2]
    w1, w2, vx = v[0], v[1], v[2]
    m2, d3, d5, g = par[3], par[4], par[5], par[6]
    s12 = math.sin(t1 - t2)
    out = np.empty(3)
    out[0] = (m2 * d3 * d5 * w2 * w2 * s12 + m2 * g * d3 * math.sin(t1)
              + par[7] * t1 + par[8] * w1)
    out[1] = -m2 * d3 * d5 * w1 * w1 * s12 + m2 * g * d5 * math.sin(t2)
    out[2] = (-m2 * d5 * w2 * w2 * math.sin(t2) - m2 * d3 * w1 * w1 * math.sin(t1)
              + par[9] * x1 + par[10] * vx)
    return out


@njit(cache=True, nogil=True)
def _rig_excitation(q, force, par):  # pragma: no cover - compiled
    out = np.empty(3)
    out[0] = force * par[11] * math.cos(q[0])
    out[1] = 0.0
    out[2] = force
    return out


@njit(cache=True, nogil=True)
def _rig_energies(q, v, par):  # pragma: no cover - compiled
    """(kinetic, potential) [J]."""
    M = _rig_mass(q, par)
    kin = 0.0
    for i in range(3):
        for j in range(3):
            kin += 0.5 * v[i] * M[i, j] * v[j]
    m2, d3, d5, g = par[3], par[4], par[5], par[6]
    pot = (m2 * g * (d5 * (1.0 - math.cos(q[1])) + d3 * (1.0 - math.cos(q[0])))
           + 0.5 * par[7] * q[0] * q[0] + 0.5 * par[9] * q[2] * q[2])
    return kin, pot


@njit(cache=True, nogil=True)
def _rig_newton(q, v, a, q1, f1, kt, force1, h, par):  # pragma: no cover - compiled
    """Newton update dq of the Newmark step equation at q1 (joint force f1, tangent kt).

    Residual ``M(q1) a1 + h + g + s + P^T f1 - Q`` with the Newmark a1, v1 of q1; Jacobian
    with the mass, the velocity terms' and dampers' derivatives, gravity, suspension and
    joint stiffness (the angle derivatives of M(q) a1 omitted). Returns (dq, a1, v1).
    """
    c0, c1, c2 = 4.0 / (h * h), 2.0 / h, 4.0 / h
    a1 = c0 * (q1 - q) - c2 * v - a
    v1 = v + 0.5 * h * (a + a1)
    M = _rig_mass(q1, par)
    R = M @ a1 + _rig_internal(q1, v1, par) - _rig_excitation(q1, force1, par)
    R[0] += f1
    R[1] -= f1
    m2, d3, d5, g = par[3], par[4], par[5], par[6]
    s12 = math.sin(q1[0] - q1[1])
    J = c0 * M
    J[0, 0] += c1 * par[8] + par[7] + m2 * g * d3 * math.cos(q1[0]) + kt
    J[0, 1] += c1 * 2.0 * m2 * d3 * d5 * v1[1] * s12 - kt
    J[1, 0] += -c1 * 2.0 * m2 * d3 * d5 * v1[0] * s12 - kt
    J[1, 1] += m2 * g * d5 * math.cos(q1[1]) + kt
    J[2, 0] += -c1 * 2.0 * m2 * d3 * v1[0] * math.sin(q1[0])
    J[2, 1] += -c1 * 2.0 * m2 * d5 * v1[1] * math.sin(q1[1])
    J[2, 2] += c1 * par[10] + par[9]
    dq = np.linalg.solve(J, -R)
    return dq, a1, v1


def _newmark(rig: RotationalJointRig, q, v, h, n_steps, force, tol, max_iter) -> dict:
    """Newmark average acceleration with Newton on the 3 coordinates (module docstring).

    A step is accepted when the Newton update computed at the current iterate is below
    ``tol`` times the coordinates' scale; the iterate (not iterate + update) is kept, so the
    committed contact state is exactly the one of the accepted coordinates.
    """
    par = rig._par()
    law = rig.joint
    damp = np.array([par[8], 0.0, par[10]])
    u1 = np.zeros((1, 1))

    state = law.initial_state()
    u1[0, 0] = q[0] - q[1]
    r = law.step(state, u1)
    fj, state = float(r.force.reshape(-1)[0]), r.state
    F = force(0.0)
    Pf = np.array([fj, -fj, 0.0])
    a = np.linalg.solve(_rig_mass(q, par), _rig_excitation(q, F, par)
                        - _rig_internal(q, v, par) - Pf)

    n = n_steps + 1
    T = h * np.arange(n)
    Q, V, A = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    ROT, TOR, FRC = np.empty(n), np.empty(n), np.empty(n)
    E = {k: np.zeros(n) for k in ("input_work", "joint_work", "suspension_dissipation",
                                   "kinetic", "potential")}
    Q[0], V[0], A[0], ROT[0], TOR[0], FRC[0] = q, v, a, q[0] - q[1], fj, F
    E["kinetic"][0], E["potential"][0] = _rig_energies(q, v, par)
    w_in = w_joint = w_sus = 0.0
    n_newton = 0
    scale = max(float(np.max(np.abs(q))), 1e-12)
    for k in range(1, n):
        t1 = T[k]
        F1 = force(t1)
        q1 = q + h * v + 0.25 * h * h * a  # predictor: a1 = a
        converged = False
        for _ in range(max_iter + 1):
            u1[0, 0] = q1[0] - q1[1]
            rr = law.step(state, u1)
            f1 = float(rr.force.reshape(-1)[0])
            kt = float(rr.stiffness.reshape(-1)[0])
            dq, a1, v1 = _rig_newton(q, v, a, q1, f1, kt, F1, h, par)
            n_newton += 1
            scale = max(scale, float(np.max(np.abs(q1))))
            if float(np.max(np.abs(dq))) <= tol * scale:
                converged = True
                break
            q1 = q1 + dq
        if not converged:
            raise ConvergenceError(f"the rig's Newton iteration did not converge at t = {t1:.6g}"
                                   f" s within {max_iter} iterations (last update "
                                   f"{float(np.max(np.abs(dq))):.3g}); try more "
                                   "steps_per_period")
        dqs = q1 - q
        w_in += 0.5 * float((_rig_excitation(q, F, par) + _rig_excitation(q1, F1, par)) @ dqs)
        w_sus += 0.5 * float((damp * (v + v1)) @ dqs)
        w_joint += 0.5 * (fj + f1) * ((q1[0] - q1[1]) - (q[0] - q[1]))
        q, v, a, fj, F, state = q1, v1, a1, f1, F1, rr.state
        Q[k], V[k], A[k], ROT[k], TOR[k], FRC[k] = q, v, a, q[0] - q[1], fj, F
        E["input_work"][k], E["joint_work"][k], E["suspension_dissipation"][k] = (
            w_in, w_joint, w_sus)
        E["kinetic"][k], E["potential"][k] = _rig_energies(q, v, par)
    return dict(t=T, q=Q, v=V, a=A, rotation=ROT, torque=TOR, force=FRC, energy=E,
                n_newton=n_newton)


# ============================================================================ joint curves
@njit(cache=True, nogil=True)
def masing_descent_kernel(theta, amplitude, arm, slip_force, slip_disp, out):  # pragma: no cover
    """Moment of Cattaneo–Mindlin asperities on the descending branch of a symmetric cycle.

    For the cycle ``0 -> A -> -A -> A`` from the virgin state, every asperity (translational
    slip ``r theta``) follows the Masing branch from its turning point ``(r A, T_A)``::

        T = T_A - 2 F_s (1 - (1 - y)^(3/2)),  y = r (A - theta) / (2 delta_s) < 1
        T = T_A - 2 F_s = -F_s                 otherwise (gross slip)

    with ``T_A = F_s (1 - (1 - r A / delta_s)^(3/2))`` (``F_s`` when ``r A >= delta_s``).
    Writes ``out[k] = sum_j r_j T_j(theta_k)`` [N m] for the samples ``theta`` (descending).
    """
    n_t = theta.shape[0]
    for k in range(n_t):
        out[k] = 0.0
    for j in range(arm.shape[0]):
        fs = slip_force[j]
        ds = slip_disp[j]
        r = arm[j]
        if fs <= 0.0 or ds <= 0.0 or r <= 0.0:
            continue
        xa = r * amplitude / ds
        if xa >= 1.0:
            ta = fs
        else:
            z = 1.0 - xa
            ta = fs * (1.0 - z * math.sqrt(z))
        inv = r / (2.0 * ds)
        for k in range(n_t):
            y = (amplitude - theta[k]) * inv
            if y >= 1.0:
                tt = ta - 2.0 * fs
            else:
                z = 1.0 - y
                tt = ta - 2.0 * fs * (1.0 - z * math.sqrt(z))
            out[k] += r * tt


def _asperities(law):
    """The RotationalMindlin summits of a law (itself or a rough joint's), or None."""
    from fricdamp.contact.mindlin import RotationalMindlin

    asp = getattr(law, "asperities", law)
    return asp if isinstance(asp, RotationalMindlin) else None


def symmetric_cycle(law: ContactLaw, amplitude: float, n_steps: int = 1000, *,
                    method: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """One steady symmetric cycle ``theta = A cos(2 pi k / n)`` of a joint law, from virgin.

    The history ``0 -> A`` (a quarter sine) then the full cycle; the cycle returned is
    closed for Masing laws (Cattaneo–Mindlin, Jenkins) once the first loading is done.

    Parameters
    ----------
    law : ContactLaw
        One contact, one direction.
    amplitude : float
        A [rad], > 0.
    n_steps : int, optional
        Samples per cycle, even, >= 8; default 1000.
    method : {"auto", "kernel", "march"}, optional
        ``"kernel"``: closed-form Masing branches summed over the asperities of a
        :class:`~fricdamp.contact.mindlin.RotationalMindlin` (or a rough joint's
        ``asperities``), half a cycle computed and the other half by symmetry
        (:func:`masing_descent_kernel`); ``"march"``: :meth:`ContactLaw.march` along the
        history (any law); ``"auto"``: the kernel when it applies.

    Returns
    -------
    theta : ndarray, shape (n_steps,)
        Rotation samples [rad] (``A cos(2 pi k / n)``, not closed).
    moment : ndarray, shape (n_steps,)
        Torque [N m].
    """
    amp = float(check_positive("amplitude", amplitude, unit="rad"))
    if int(n_steps) != n_steps or n_steps < 8 or n_steps % 2:
        raise ModelError(f"n_steps must be an even integer >= 8, got {n_steps!r}")
    n = int(n_steps)
    if law.n_contacts != 1 or law.n_dir != 1:
        raise ModelError("the joint law must have one contact and one direction")
    theta = amp * np.cos(2 * np.pi * np.arange(n) / n)
    asp = _asperities(law)
    if method not in ("auto", "kernel", "march"):
        raise ModelError(f"method must be 'auto', 'kernel' or 'march', got {method!r}")
    if method == "kernel" and asp is None:
        raise ModelError(f"method='kernel' needs Cattaneo–Mindlin asperities; "
                         f"{type(law).__name__} has none (use method='march')")
    if asp is not None and method != "march":
        half = n // 2
        desc = np.empty(half + 1)
        masing_descent_kernel(np.ascontiguousarray(theta[:half + 1]), amp, asp.arm,
                              asp.slip_force, asp.slip_displacement, desc)
        moment = np.empty(n)
        moment[:half + 1] = desc
        # ascending half: M(theta_{n-k}) = -M_desc(-theta_k) = -desc[half - k]
        k = np.arange(half + 1, n)
        moment[k] = -desc[k - half]
        return theta, moment
    ramp = amp * np.sin(0.5 * np.pi * np.arange(1, n // 4 + 1) / (n // 4))
    hist = np.concatenate((ramp, theta))
    f = law.drive(hist.reshape(-1, 1, 1)).reshape(-1)
    return theta, f[ramp.size:]


@dataclass(frozen=True)
class JointCurves:
    """Hysteresis loops, dissipated energy and damping ratio of a joint vs rotation amplitude.

    Paper 002 Figs 14 (loops), 16 (energy) and 17 (damping ratio).

    Attributes
    ----------
    amplitude : ndarray, shape (n_a,)
        Rotation amplitudes theta_max [rad].
    rotation, torque : ndarray, shape (n_a, n_steps)
        One steady cycle per amplitude [rad], [N m].
    dissipated_energy : ndarray, shape (n_a,)
        Loop areas E_d [J].
    torque_amplitude : ndarray, shape (n_a,)
        M_max, half the peak-to-peak torque [N m].
    damping_ratio : ndarray, shape (n_a,)
        Paper 002's xi = E_d / (pi theta_max M_max), (26)-(27) [-] (about the loss factor,
        2 zeta, of a viscous loop; 4/pi in gross slip).
    slip_moment : float
        Gross-slip torque of the law [N m] if known, else NaN.
    """

    amplitude: np.ndarray
    rotation: np.ndarray
    torque: np.ndarray
    dissipated_energy: np.ndarray
    torque_amplitude: np.ndarray
    damping_ratio: np.ndarray
    slip_moment: float = float("nan")

    def to_dict(self) -> dict:
        """``{"amplitude_rad", "dissipated_energy_J", "damping_ratio"}`` lists (+ definition)."""
        return {"amplitude_rad": self.amplitude.tolist(),
                "dissipated_energy_J": self.dissipated_energy.tolist(),
                "damping_ratio": self.damping_ratio.tolist(),
                "torque_amplitude_Nm": self.torque_amplitude.tolist(),
                "damping_ratio_definition": "paper 002 (26)-(27): xi = E_d / (pi theta_max "
                                            "M_max), about the loss factor (2 zeta)"}

    def plot_loops(self, ax=None, *, every: int = 1):
        """Fig. 14: torque vs rotation for each amplitude; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5.5, 4.2))
        for i in range(0, self.amplitude.size, every):
            r = np.append(self.rotation[i], self.rotation[i, 0])
            f = np.append(self.torque[i], self.torque[i, 0])
            ax.plot(1e3 * r, f, lw=1)
        ax.set_xlabel("rotation [mrad]")
        ax.set_ylabel("torque [N m]")
        ax.set_title("hysteresis loops (002 Fig. 14)")
        ax.grid(alpha=0.3)
        return ax

    def plot_energy(self, ax=None, **kw):
        """Fig. 16: dissipated energy per cycle vs amplitude (log-log); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5.5, 4.2))
        ax.loglog(self.amplitude, self.dissipated_energy, "-", lw=1.5, **kw)
        ax.set_xlabel(r"rotation amplitude $\theta_{max}$ [rad]")
        ax.set_ylabel("dissipated energy per cycle [J]")
        ax.set_title("dissipated energy (002 Fig. 16)")
        ax.grid(alpha=0.3, which="both")
        return ax

    def plot_damping(self, ax=None, **kw):
        """Fig. 17: paper 002's damping ratio vs amplitude; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5.5, 4.2))
        ax.semilogx(self.amplitude, self.damping_ratio, "-", lw=1.5, **kw)
        ax.set_xlabel(r"rotation amplitude $\theta_{max}$ [rad]")
        ax.set_ylabel(r"$\xi = E_d / (\pi\,\theta_{max} M_{max})$ [-]")
        ax.set_title("damping ratio (002 Fig. 17)")
        ax.grid(alpha=0.3, which="both")
        return ax


def joint_curves(law: ContactLaw, amplitudes: Sequence[float], *, n_steps: int = 1000,
                 method: str = "auto") -> JointCurves:
    """Loops, dissipated energy and damping ratio of a joint law over rotation amplitudes.

    Each amplitude is a separate symmetric cycle from the virgin state
    (:func:`symmetric_cycle`), as in paper 002 §4 ("increasing the amplitude of the angular
    displacement"); from micro-slip (E_d ~ A^3 for Cattaneo–Mindlin summits) to gross slip
    (E_d -> 4 M_slip A, xi -> 4/pi).

    Parameters
    ----------
    law : ContactLaw
        One contact, one direction (rotation [rad] -> torque [N m]).
    amplitudes : sequence of float
        Rotation amplitudes [rad], > 0.
    n_steps : int, optional
        Samples per cycle (even); default 1000.
    method : str, optional
        See :func:`symmetric_cycle`.

    Returns
    -------
    JointCurves
    """
    amps = as_finite_array("amplitudes", amplitudes)
    amps = np.atleast_1d(amps).astype(float)
    if amps.ndim != 1 or amps.size == 0 or np.any(amps <= 0):
        raise ModelError(f"amplitudes must be a non-empty list of rotations > 0 rad, got "
                         f"{amplitudes!r}")
    rot = np.empty((amps.size, int(n_steps)))
    tor = np.empty_like(rot)
    for i, A in enumerate(amps):
        rot[i], tor[i] = symmetric_cycle(law, A, n_steps, method=method)
    e_d = np.array([loop_area(rot[i], tor[i]) for i in range(amps.size)])
    m_amp = 0.5 * (tor.max(axis=1) - tor.min(axis=1))
    xi = np.asarray(paper002_damping_ratio(np.maximum(e_d, 0.0), amps, m_amp))
    slip = getattr(law, "slip_moment", None)
    if slip is None and hasattr(law, "slip_force") and law.n_contacts == 1:
        slip = float(np.sum(law.slip_force))
    slip = float(np.sum(slip)) if slip is not None else float("nan")
    return JointCurves(amps, rot, tor, e_d, m_amp, np.atleast_1d(xi), slip)


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
                "kinematics": ident.kinematics}

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
    **identify_options
        Passed to :func:`fricdamp.analysis.identify.identify_joint` (``kinematics``,
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
