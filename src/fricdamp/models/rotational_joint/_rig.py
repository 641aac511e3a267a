"""Paper 002's test structure: its parameters, the rig model and its time response.

:class:`RigParameters` (geometry, masses, sensors, suspension), :func:`paper002_joint`,
:class:`RigResponse` (time history, energy balance, synthetic accelerometers) and
:class:`RotationalJointRig` (equations, linearised model, simulation). The equations and the
integration are described in :mod:`fricdamp.models.rotational_joint.model`, which re-exports these
names.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, field, fields, replace

import numpy as np

from fricdamp.contact.base import ContactLaw
from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.models.rotational_joint._dynamics import (
    _newmark,
    _rig_energies,
    _rig_excitation,
    _rig_internal,
    _rig_mass,
)
from fricdamp.signals.energy import loop_area
from fricdamp.signals.identify import DrivenBeam, JointRigGeometry
from fricdamp.signals.records import SignalTable
from fricdamp.structure.system import ContactElement, HarmonicLoad, MechanicalSystem


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
        """What the identification needs (:class:`~fricdamp.signals.identify.JointRigGeometry`)."""
        return JointRigGeometry(self.sensor_a, self.sensor_b, self.joint_arm1, self.sensor_c,
                                self.joint_arm2, self.beam2_mass, self.inertia2, self.gravity)

    @classmethod
    def paper_load_case(cls, **overrides) -> RigParameters:
        """The rig calibrated so that paper 002's load case lands in its regime.

        Paper 002 drives the joint (100 N preload) with 60-500 N and reports micro-slip
        loops with an elastic ("oblique") part (Fig. 8) and a damping ratio that keeps
        rising with the amplitude (Fig. 17): the whole range lies below gross slip. With
        the default soft suspension (rig modes 3.9 and 8.5 Hz, mass-controlled at 30 Hz)
        the joint transmits 0.052 N m per newton of shaker force and slips grossly from
        ~2.5 N. Beam 1 is mounted stiffly instead: both suspension stiffnesses are the
        defaults times 230 (``k_x = 2.0e5 N/m``, ``k_t = 4.0e3 N m/rad``), both dampings
        times sqrt(230) (the same modal damping ratios: ``c_x = 250 N s/m``,
        ``c_t = 5.0 N m s/rad``). The factor is the one for which the linearised rig with the
        joint stuck carries ~90 % of the slip moment at 500 N (with the rounded values it
        carries 2.3e-4 N m/N, 85 %); the rig's modes are then 59 Hz and 126 Hz (the paper's
        FE model, Table 1: 99.7 and 270.8 Hz, the same order) and 1.42 kHz (the joint).
        Simulated (docs/cases_rotational_joint.md, tests/unit/test_rotational_joint_regimes.py):
        60 N gives micro-slip (xi = 0.02, M_max = 10 % of the slip moment), 500 N partial slip
        (xi = 0.41, 85 %), gross slip from ~600 N. The preload stays 100 N.

        Parameters
        ----------
        **overrides
            Other parameters to change (see :meth:`with_`).
        """
        base = dict(suspension_stiffness=2.0e5, suspension_torsional_stiffness=4.0e3,
                    suspension_damping=250.0, suspension_torsional_damping=5.0)
        base.update(overrides)
        return cls().with_(**base)

    def driven_beam(self) -> DrivenBeam:
        """Beam 1, its shaker and suspension, for the force channel's checks
        (:class:`~fricdamp.signals.identify.DrivenBeam`)."""
        return DrivenBeam(self.beam1_mass, self.inertia1, self.shaker_arm,
                          self.suspension_stiffness, self.suspension_damping,
                          self.suspension_torsional_stiffness,
                          self.suspension_torsional_damping)

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
    0.4 % above 1e-5 rad (tests/unit/test_rotational_joint.py). Fewer height classes are
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
        (:mod:`fricdamp.signals.identify`)::

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
