"""Joint identification from three accelerometers: paper 002's Fig. 7 pipeline.

Bouchaala et al. (2014) measure the torque-rotation loop of a rotational friction joint with
accelerometers only. Beam 1 (driven by the shaker, carrying accelerometers A and B) and beam 2
(hanging from the joint O, carrying C) are rigid; ``theta1``, ``theta2`` are their rotations and
``x1`` the horizontal displacement of the centre of mass G1 of beam 1. The pipeline is

1. tangential accelerations ``gamma_A, gamma_B, gamma_C`` -> ``theta1''``, ``x1''``,
   ``theta2''`` by the kinematic relations 002 (B.1)-(B.10) (:func:`beam_accelerations`);
2. FFT / IFFT integration into velocities and rotations, on whole periods of the excitation
   (002 Fig. 7);
3. the joint torque from the Lagrange equation of beam 2, 002 (8) (:func:`joint_torque`);
4. the loop ``M`` vs ``theta1 - theta2``, its area (energy dissipated per cycle) and paper
   002's damping ratio (26)-(27).

Geometry and conventions
------------------------
Positions along a beam are measured on its axis: on beam 1 from G1 towards the joint O
(``d1`` for A, ``d2`` for B, ``d3 = l1/2 - h`` for O), on beam 2 from O away from beam 1
(``d5 = l2/2 - h`` for G2, ``d5 + d4`` for C, i.e. ``d4`` is C's position from G2). A
rotation ``theta`` moves a point at position ``s`` by ``s sin(theta)`` along ``X0``. The
accelerometers measure along the beam-fixed tangential direction ``t_i = (cos theta_i,
-sin theta_i)``. Differentiating the positions twice (tests/unit/test_identify_kinematics.py
does it symbolically) gives the exact readings::

    gamma_A = x1'' cos(theta1) + d1 theta1''                       (+ g sin(theta1))
    gamma_B = x1'' cos(theta1) + d2 theta1''                       (+ g sin(theta1))
    gamma_C = x1'' cos(theta2) + d3 theta1'' cos(theta1 - theta2)
              - d3 theta1'^2 sin(theta1 - theta2) + (d4 + d5) theta2''  (+ g sin(theta2))

(the bracketed terms are read by accelerometers that sense gravity, as piezoelectric ones do
at the excitation frequency; ``Z0`` points down, paper 002 (5)). Linearised in the angles
these are the paper's (B.1), (B.2) and (B.5) with ``x2'' = x1'' + d3 theta1'' + d5 theta2''``,
the acceleration of G2. The extracted text of (B.9) is garbled (it reads ``x2'' = x1'' + d3
theta1 + d5 theta2``, rotations instead of accelerations); the form above follows from (B.8)
and is what (B.10) needs: ``theta2'' = (gamma_C - gamma_O) / (d4 + d5)`` with
``gamma_O = x1'' + d3 theta1''`` (B.3). The ``"paper"`` kinematics of :func:`identify_joint`
use these linear relations (002 Fig. 7); the ``"exact"`` kinematics solve the relations above
with the rotations from a first pass (a fixed-point iteration; the corrections are of second
order in the angles), which matters only for rotations of several degrees.

Joint torque
------------
002 (8) is the Lagrange equation of ``theta2`` for the kinetic energy 002 (4) and potential
002 (5): its only generalised force is the joint torque ``M``, the moment that beam 1 applies
to beam 2 through the joint (the shaker drives beam 1). In the sign convention of
:mod:`fricdamp.contact.base` it is the moment with which the joint resists the relative
rotation ``theta1 - theta2``, so the loop area ``∮ M d(theta1 - theta2)`` is the energy the
joint dissipates, positive. Note that 002 (A.2) prints the velocity term of this equation as
``m2 d5 theta1'^2 sin(...)``: the factor ``d3`` is missing there but present in (6) and (8).

Damping ratio
-------------
:func:`fricdamp.signals.damping.paper002_damping_ratio`: ``xi = E_d / (pi theta_max
M_max)``, paper 002 (26)-(27), with the half peak-to-peak amplitudes of rotation and torque.
For a linear viscous loop this is (about) the **loss factor** ``eta = 2 zeta``, not the
damping ratio zeta of a mode. Peak-to-peak values depend on the sampling rate and on the
harmonics kept (the ringing of the rig's joint mode at each stick-slip transition adds
peaks), so the result also carries an energy-based ratio ``xi_E = E_d / (pi Theta_1 M_1)``
with the amplitudes of the fundamentals: ``E_d / (2 pi U_1)``, ``U_1 = Theta_1 M_1 / 2`` the
peak energy of the first-harmonic exchange. Integrals and fundamentals converge with the
sampling rate and the harmonic count; ``xi_E = xi`` for a linear loop and tends to 1 (not
4/pi) in gross slip.

Trust
-----
Every identification carries a verdict (:class:`TrustReport`, from
:mod:`fricdamp.signals._identify_trust`): block-wise energy scatter, conditioning, and a
Monte Carlo of the sensor positions, sensitivities, delays and noise giving 95 % intervals
of E_d and xi; ``status`` is "unreliable" when the interval is too wide (docs/identify.md).
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.results import ResultMixin
from fricdamp.signals._identify_core import (
    first_harmonic,
    kinematics_exact,
    kinematics_linear,
    process_window,
    torque_002,
)
from fricdamp.signals._identify_force import FORCE_UNITS, DrivenBeam, ForceCheck, force_check
from fricdamp.signals._identify_trust import (
    MeasurementUncertainty,
    TrustReport,
    TrustThresholds,
    assess,
)
from fricdamp.signals._identify_window import (
    check_time,
    estimate_frequency,
    refine_frequency,
    steady_start,
    whole_periods,
)
from fricdamp.signals.damping import paper002_damping_ratio

log = logging.getLogger(__name__)

__all__ = [
    "ACCELERATION_UNITS",
    "DrivenBeam",
    "FORCE_UNITS",
    "ForceCheck",
    "JointIdentification",
    "JointRigGeometry",
    "MeasurementUncertainty",
    "TrustReport",
    "TrustThresholds",
    "acceleration_scale",
    "beam_accelerations",
    "beam_accelerations_exact",
    "estimate_frequency",
    "identify_from_table",
    "identify_joint",
    "joint_torque",
]

#: Acceleration units understood in signal headers, and their factor to m/s^2.
ACCELERATION_UNITS: dict[str, float] = {
    "m/s^2": 1.0, "m/s2": 1.0, "m/s²": 1.0, "m s^-2": 1.0, "m*s^-2": 1.0, "m/s/s": 1.0,
    "ms^-2": 1.0, "ms-2": 1.0, "mm/s^2": 1e-3, "mm/s2": 1e-3, "mm/s²": 1e-3,
    "g": 9.80665, "g0": 9.80665, "gn": 9.80665, "ft/s^2": 0.3048, "ft/s2": 0.3048,
    "in/s^2": 0.0254, "in/s2": 0.0254,
}


def acceleration_scale(unit: str, *, channel: str = "") -> float:
    """Factor turning an acceleration in ``unit`` into m/s^2 (``"g"`` -> 9.80665).

    Raises
    ------
    ModelError
        For an empty or unknown unit (naming the channel and the units understood).
    """
    key = str(unit).strip().lower().replace(" ", "")
    key = {"m/s**2": "m/s^2", "mm/s**2": "mm/s^2"}.get(key, key)
    where = f"channel {channel!r}: " if channel else ""
    if not key:
        raise ModelError(f"{where}no acceleration unit: give it in the header (e.g. "
                         "'acc_A [m/s^2]' or '[g]') or set it explicitly; units understood: "
                         f"{', '.join(ACCELERATION_UNITS)}")
    if key not in ACCELERATION_UNITS:
        raise ModelError(f"{where}unknown acceleration unit {unit!r}; units understood: "
                         f"{', '.join(ACCELERATION_UNITS)}")
    return ACCELERATION_UNITS[key]


# ============================================================================ geometry
@dataclass(frozen=True)
class JointRigGeometry:
    """What the identification needs to know about the test structure (paper 002 Fig. 6).

    Positions follow the module docstring: on beam 1 from G1 towards the joint, on beam 2
    from G2 away from the joint.

    Parameters
    ----------
    sensor_a : float
        d1, position of accelerometer A on beam 1 [m].
    sensor_b : float
        d2, position of accelerometer B on beam 1 [m]; ``d1 != d2`` (B.6).
    joint_arm1 : float
        d3 = l1/2 - h, position of the joint O on beam 1 [m], > 0 (002 (7)).
    sensor_c : float
        d4, position of accelerometer C on beam 2, from G2 [m]; ``d4 + d5 != 0`` (B.10).
    joint_arm2 : float
        d5 = l2/2 - h, distance from O to G2 [m], > 0 (002 (7)).
    beam2_mass : float
        m2 [kg], > 0.
    beam2_inertia : float
        I2, moment of inertia of beam 2 about G2 [kg m^2], > 0 (002 (10)).
    gravity : float, optional
        g [m/s^2], >= 0; default 9.81.
    """

    sensor_a: float
    sensor_b: float
    joint_arm1: float
    sensor_c: float
    joint_arm2: float
    beam2_mass: float
    beam2_inertia: float
    gravity: float = 9.81

    def __post_init__(self):
        for name in ("sensor_a", "sensor_b", "sensor_c"):
            object.__setattr__(self, name, float(as_finite_array(name, getattr(self, name),
                                                                 ndim=0)))
        for name, unit in (("joint_arm1", "m"), ("joint_arm2", "m"), ("beam2_mass", "kg"),
                           ("beam2_inertia", "kg m^2")):
            v = check_positive(name, getattr(self, name), unit=unit)
            if v.ndim:
                raise ModelError(f"{name} must be a scalar, got shape {v.shape}")
            object.__setattr__(self, name, float(v))
        g = check_positive("gravity", self.gravity, unit="m/s^2", allow_zero=True)
        object.__setattr__(self, "gravity", float(g))
        scale = max(abs(self.sensor_a), abs(self.sensor_b), self.joint_arm1)
        if abs(self.sensor_a - self.sensor_b) <= 1e-6 * scale:
            raise ModelError(f"sensor_a (d1 = {self.sensor_a!r} m) and sensor_b (d2 = "
                             f"{self.sensor_b!r} m) must differ: theta1'' = (gamma_A - "
                             "gamma_B) / (d1 - d2), 002 (B.6)")
        if abs(self.sensor_c + self.joint_arm2) <= 1e-6 * self.joint_arm2:
            raise ModelError(f"accelerometer C must not sit on the joint: sensor_c + "
                             f"joint_arm2 (d4 + d5) must be != 0, got {self.sensor_c!r} + "
                             f"{self.joint_arm2!r} m (002 (B.10))")


def beam_accelerations(geometry: JointRigGeometry, gamma_a, gamma_b, gamma_c):
    """``theta1''``, ``theta2''``, ``x1''`` from the tangential accelerations, 002 (B.1)-(B.10).

    The paper's linear kinematics (module docstring)::

        theta1'' = (gamma_A - gamma_B) / (d1 - d2)                  (B.6)
        x1''     = (gamma_A + gamma_B - (d1 + d2) theta1'') / 2     (B.6)
        theta2'' = (gamma_C - x1'' - d3 theta1'') / (d4 + d5)       (B.3), (B.10)

    Parameters
    ----------
    geometry : JointRigGeometry
    gamma_a, gamma_b, gamma_c : array_like, shape (n,) (or broadcastable)
        Tangential accelerations at A, B, C [m/s^2].

    Returns
    -------
    theta1_dd, theta2_dd : ndarray
        Angular accelerations [rad/s^2].
    x1_dd : ndarray
        Acceleration of G1 [m/s^2].

    Examples
    --------
    G1 accelerating at 2 m/s^2, beam 1 at 10 rad/s^2, beam 2 not rotating:

    >>> geom = JointRigGeometry(-0.09, 0.0, 0.091, 0.09, 0.091, 0.44, 1.5e-3)
    >>> ga, gb = 2.0 - 0.09 * 10.0, 2.0          # (B.1), (B.2)
    >>> gc = 2.0 + 0.091 * 10.0                   # C moves with O: x1'' + d3 theta1''
    >>> [round(float(x), 12) for x in beam_accelerations(geom, ga, gb, gc)]
    [10.0, 0.0, 2.0]
    """
    ga, gb, gc = (np.asarray(x, dtype=float) for x in (gamma_a, gamma_b, gamma_c))
    return kinematics_linear(ga, gb, gc, geometry.sensor_a, geometry.sensor_b,
                             geometry.joint_arm1, geometry.sensor_c, geometry.joint_arm2)


def beam_accelerations_exact(geometry: JointRigGeometry, gamma_a, gamma_b, gamma_c, theta1,
                             theta2, theta1_dot, *, gravity_sensing: bool = False):
    """Angular and linear accelerations from the exact (nonlinear) sensor kinematics.

    Solves the relations of the module docstring for ``theta1''``, ``x1''`` and
    ``theta2''`` given the rotations and ``theta1'`` (from a first, linear pass).

    Parameters
    ----------
    geometry : JointRigGeometry
    gamma_a, gamma_b, gamma_c : array_like, shape (n,)
        Tangential accelerations at A, B, C [m/s^2].
    theta1, theta2 : array_like, shape (n,)
        Rotations of the beams [rad].
    theta1_dot : array_like, shape (n,)
        Angular velocity of beam 1 [rad/s].
    gravity_sensing : bool, optional
        The accelerometers also read the tangential component of gravity ``g sin(theta)``
        (true for piezoelectric sensors at the excitation frequency); default False.

    Returns
    -------
    theta1_dd, theta2_dd, x1_dd : ndarray
        As :func:`beam_accelerations`.
    """
    ga, gb, gc, t1, t2, w1 = (np.asarray(x, dtype=float) for x in
                              (gamma_a, gamma_b, gamma_c, theta1, theta2, theta1_dot))
    g = geometry.gravity if gravity_sensing else 0.0
    return kinematics_exact(ga, gb, gc, t1, t2, w1, geometry.sensor_a, geometry.sensor_b,
                            geometry.joint_arm1, geometry.sensor_c, geometry.joint_arm2, g)


def joint_torque(geometry: JointRigGeometry, theta1, theta2, theta1_dot, theta1_dd, theta2_dd,
                 x1_dd):
    """Joint torque from the Lagrange equation of beam 2, paper 002 (8) [N m].

    ``M = (I2 + m2 d5^2) theta2'' + m2 d5 x1'' cos(theta2) + m2 d3 d5 theta1'' cos(theta1 -
    theta2) - m2 d3 d5 theta1'^2 sin(theta1 - theta2) + m2 g d5 sin(theta2)``: the moment
    that beam 1 applies to beam 2 through the joint, i.e. the moment with which the joint
    resists the relative rotation ``theta1 - theta2``.

    Parameters
    ----------
    geometry : JointRigGeometry
    theta1, theta2, theta1_dot, theta1_dd, theta2_dd, x1_dd : array_like, shape (n,)
        Rotations [rad], angular velocity of beam 1 [rad/s], angular accelerations
        [rad/s^2] and acceleration of G1 [m/s^2].

    Returns
    -------
    ndarray, shape (n,)
        M [N m].
    """
    t1, t2, w1, a1, a2, ax = (np.asarray(x, dtype=float) for x in
                              (theta1, theta2, theta1_dot, theta1_dd, theta2_dd, x1_dd))
    return torque_002(t1, t2, w1, a1, a2, ax, geometry.beam2_mass, geometry.beam2_inertia,
                      geometry.gravity, geometry.joint_arm1, geometry.joint_arm2)



# ============================================================================ result
@dataclass(frozen=True, repr=False)
class JointIdentification(ResultMixin):
    """Torque-rotation loop of a joint identified from accelerometer signals.

    Attributes
    ----------
    time : ndarray, shape (m,)
        Times of the analysed window [s] (``n_periods`` whole periods, not closed).
    theta1, theta2 : ndarray, shape (m,)
        Rotations of beam 1 and beam 2 [rad] (zero mean: a constant is not measurable).
    x1 : ndarray, shape (m,)
        Displacement of G1 [m] (zero mean).
    rotation : ndarray, shape (m,)
        Relative rotation ``theta1 - theta2`` of the joint [rad].
    torque : ndarray, shape (m,)
        Joint torque M [N m], 002 (8).
    frequency_hz : float
        Excitation frequency [Hz] (given or estimated).
    n_periods : int
        Whole periods analysed.
    dissipated_energy : float
        Energy dissipated per cycle [J]: ``∮ M d(theta1 - theta2)`` over the window divided
        by ``n_periods``.
    cycle_energy : ndarray, shape (n_periods,)
        Loop area of each period [J] (split at the nearest samples when a period is not a
        whole number of samples). After the harmonic filter every period is alike, so
        their spread says nothing about noise: see ``trust.block_scatter``.
    rotation_amplitude : float
        ``theta_max`` = half the peak-to-peak relative rotation [rad].
    torque_amplitude : float
        ``M_max`` = half the peak-to-peak torque [N m].
    damping_ratio : float
        Paper 002's ``xi = E_d / (pi theta_max M_max)``, (26)-(27) [-]; this is (about) the
        loss factor 2 zeta of a viscous loop, not a modal damping ratio.
    kinematics, filter : str
        Options used (see :func:`identify_joint`).
    resampled : bool
        True when the window was resampled to a whole number of samples per period.
    filtered_fraction : float
        RMS of what the filter removed from the angular and linear accelerations (noise,
        transients, offsets, leakage) relative to their RMS without the mean [-]: a few
        percent for a clean steady record.
    source : str
        Where the signals came from.
    damping_ratio_energy : float
        Energy-based ``xi_E = E_d / (pi Theta_1 M_1)`` with the fundamentals' amplitudes
        [-] (module docstring): independent of sampling rate and harmonic count.
    skipped_periods : int
        Leading whole periods dropped as start-up transient.
    time_snapped : bool
        True when rounded time stamps were rebuilt on a uniform grid.
    trust : TrustReport or None
        The diagnostics and verdict (None when ``diagnostics=False``).
    checks : tuple of str
        Findings made even without the diagnostics: a given excitation frequency that is
        not the signals' strongest line, a negative loop area, the force channel's checks.
        Either makes the result ``unreliable`` with ``diagnostics=False`` too.
    force_check : ForceCheck or None
        With a force channel: the torque from the shaker force and the energy balance
        (:mod:`fricdamp.signals._identify_force`); their failures are among the warnings
        and make the result ``unreliable``.
    """

    time: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    x1: np.ndarray
    rotation: np.ndarray
    torque: np.ndarray
    frequency_hz: float
    n_periods: int
    dissipated_energy: float
    cycle_energy: np.ndarray
    rotation_amplitude: float
    torque_amplitude: float
    damping_ratio: float
    kinematics: str = "paper"
    filter: str = "harmonic"
    resampled: bool = False
    filtered_fraction: float = 0.0
    source: str = ""
    meta: dict = field(default_factory=dict, compare=False)
    damping_ratio_energy: float = float("nan")
    skipped_periods: int = 0
    time_snapped: bool = False
    trust: TrustReport | None = None
    checks: tuple[str, ...] = ()
    force_check: ForceCheck | None = None

    @property
    def samples_per_period(self) -> float:
        """Samples per period of the window (not always a whole number)."""
        return self.time.size / self.n_periods

    @property
    def status(self) -> str:
        """``"ok"``, ``"unreliable"`` (see ``warnings``) or ``"unchecked"`` (no diagnostics
        and none of the ``checks`` found anything)."""
        if self.trust is None:
            return "unreliable" if self.checks else "unchecked"
        return self.trust.status

    @property
    def warnings(self) -> tuple:
        """The diagnostics' findings (without diagnostics: the ``checks``)."""
        return self.checks if self.trust is None else self.trust.warnings

    def cycle(self, samples: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """One period of the loop (rotation [rad], torque [N m]): the synchronous average.

        The harmonics of the window's spectrum (bins at multiples of ``n_periods``) summed
        at ``samples`` equally spaced phases (default ``ceil(samples_per_period)``), starting
        at the window's first sample; the same as averaging the periods sample by sample
        when a period is a whole number of samples, and exact for any rate otherwise.
        """
        n, N = self.time.size, self.n_periods
        m = int(np.ceil(n / N - 1e-9)) if samples is None else int(samples)
        if m < 4:
            raise ModelError(f"samples must be >= 4, got {samples!r}")
        out = []
        for x in (self.rotation, self.torque):
            H = np.fft.rfft(x)[::N]
            k = min(H.size, (m + 1) // 2)  # harmonics strictly below the Nyquist of m
            C = np.zeros(m // 2 + 1, dtype=complex)
            C[:k] = H[:k] * (m / n)
            out.append(np.fft.irfft(C, n=m))
        return out[0], out[1]

    def to_dict(self) -> dict:
        """JSON-able key numbers (units in the key names) and, if checked, the verdict."""
        ce = self.cycle_energy
        spread = float(np.std(ce) / abs(np.mean(ce))) if ce.size > 1 and np.mean(ce) else 0.0
        out = {
            "dissipated_energy_J": float(self.dissipated_energy),
            "rotation_amplitude_rad": float(self.rotation_amplitude),
            "torque_amplitude_Nm": float(self.torque_amplitude),
            "damping_ratio": float(self.damping_ratio),
            "damping_ratio_definition": "paper 002 (26)-(27): xi = E_d / (pi theta_max M_max)"
                                        ", about the loss factor (2 zeta) of a viscous loop",
            "damping_ratio_energy": float(self.damping_ratio_energy),
            "damping_ratio_energy_definition": "xi_E = E_d / (pi Theta_1 M_1), amplitudes of "
                                               "the fundamentals (= xi for a linear loop, "
                                               "-> 1 in gross slip)",
            "frequency_hz": float(self.frequency_hz),
            "n_periods": int(self.n_periods),
            "samples_per_period": float(self.samples_per_period),
            "cycle_energy_relative_spread": spread,
            "filtered_fraction": float(self.filtered_fraction),
            "kinematics": self.kinematics,
            "filter": self.filter,
            "resampled": bool(self.resampled),
            "skipped_periods": int(self.skipped_periods),
            "time_snapped": bool(self.time_snapped),
            "source": self.source,
            "status": self.status,
            "warnings": list(self.warnings),
        }
        if self.trust is not None:
            out.update(self.trust.to_dict())
        if self.force_check is not None:
            out.update(self.force_check.to_dict())
        return out

    def _judge(self):
        from fricdamp.results import status_verdict

        est = {}
        if self.trust is not None:
            lo, hi = self.trust.energy_interval
            if self.dissipated_energy:
                est["energy_interval_relative"] = float(
                    0.5 * (hi - lo) / abs(self.dissipated_energy))
        if self.status == "ok":
            reasons = ()
        elif self.status == "unchecked":
            reasons = ("identified without diagnostics (diagnostics=False): its uncertainty is "
                       "unknown",)
        else:
            reasons = tuple(self.warnings) or ("the identification is unreliable",)
        return status_verdict(True, "", est, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` along ``time`` [s] of the analysed window: ``theta1``,
        ``theta2``, ``rotation`` [rad], ``x1`` [m], ``torque`` [N m]; ``cycle_energy`` [J]
        along ``period``; the key numbers of :meth:`to_dict` (units in their names, e.g.
        ``dissipated_energy_J``, ``frequency_hz``) as attributes."""
        import xarray as xr

        data = {"theta1": ("time", self.theta1, {"units": "rad"}),
                "theta2": ("time", self.theta2, {"units": "rad"}),
                "rotation": ("time", self.rotation, {"units": "rad"}),
                "x1": ("time", self.x1, {"units": "m"}),
                "torque": ("time", self.torque, {"units": "N m"}),
                "cycle_energy": ("period", np.asarray(self.cycle_energy, float),
                                 {"units": "J"})}
        attrs = {}
        for k, v in self.to_dict().items():
            if isinstance(v, bool):
                attrs[k] = int(v)
            elif isinstance(v, (int, float, str)):
                attrs[k] = v
            elif isinstance(v, (list, tuple)) and all(isinstance(x, str) for x in v):
                attrs[k] = "\n".join(v)
        return xr.Dataset(data, coords={"time": ("time", self.time, {"units": "s"})},
                          attrs=attrs)

    def plot(self, ax=None, *, label: str | None = None, all_periods: bool = False):
        """Torque vs relative rotation (mrad); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5.5, 4.2))
        r, f = (self.rotation, self.torque) if all_periods else self.cycle()
        r = np.append(r, r[0])
        f = np.append(f, f[0])
        if label is None:
            label = f"E_d = {self.dissipated_energy:.3g} J, xi = {self.damping_ratio:.3g}"
            if self.trust is not None:
                lo, hi = self.trust.energy_interval
                label += f"\n95 %: [{lo:.3g}, {hi:.3g}] J ({self.status})"
        ax.plot(1e3 * r, f, lw=1.2, label=label)
        ax.set_xlabel(r"relative rotation $\theta_1-\theta_2$ [mrad]")
        ax.set_ylabel("joint torque M [N m]")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize="small")
        return ax


# ============================================================================ pipeline
def identify_joint(time, gamma_a, gamma_b, gamma_c, geometry: JointRigGeometry, *,
                   frequency_hz: float | None = None, periods: int | None = None,
                   kinematics: Literal["paper", "exact"] = "paper",
                   gravity_sensing: bool = False,
                   filter: Literal["harmonic", "highpass"] = "harmonic",
                   n_harmonics: int | None = None, f_low_hz: float | None = None,
                   iterations: int = 3, source: str = "",
                   skip_periods: int | Literal["auto"] = "auto", diagnostics: bool = True,
                   uncertainty: MeasurementUncertainty | None = None,
                   thresholds: TrustThresholds | None = None, force=None,
                   driven_beam: DrivenBeam | None = None) -> JointIdentification:
    """Torque-rotation loop, dissipated energy and damping ratio from three accelerometers.

    Paper 002 Fig. 7: accelerations -> (B.1)-(B.10) -> FFT/IFFT integration -> torque (8)
    -> loop -> energy and (26)-(27). The care taken with the integration:

    * time stamps rounded by the acquisition software (e.g. written with 7 decimals) are
      rebuilt on a uniform grid (:func:`fricdamp.signals.records.uniform_time`);
    * the start-up transient is dropped (``skip_periods="auto"``: the leading periods whose
      fundamentals differ from the record's steady values,
      :func:`fricdamp.signals._identify_window.steady_start`);
    * the last ``periods`` **whole periods** of the excitation are analysed, with a whole
      number of samples per period (the record is resampled by a cubic spline when the
      sampling rate is not commensurate with the frequency), so the FFT sees a periodic
      signal and integrates it without leakage;
    * a linear drift of the angular and linear accelerations (estimated from the means of
      the first and last periods, which is exactly zero for a periodic signal) is removed;
    * ``filter="harmonic"`` (default) keeps only the harmonics of the excitation frequency
      (the spectral lines of a periodic steady state): it removes offsets and drifts of the
      sensors, slow transients and all noise between the lines (the synchronous average of
      the periods, in one FFT); ``filter="highpass"`` keeps every line above ``f_low_hz``
      (default half the excitation frequency) and removes the mean
      (:func:`fricdamp.signals.records.fft_integrate`).

    The constants of integration (mean rotations and displacement) are not measurable and
    are set to zero; they change neither the loop area nor the amplitudes. With
    ``diagnostics`` (default) the result carries a :class:`TrustReport`: block scatter,
    conditioning, 95 % intervals from a Monte Carlo of ``uncertainty`` and the status.

    Parameters
    ----------
    time : array_like, shape (n,)
        Uniform (or rounded uniform) sample times [s].
    gamma_a, gamma_b, gamma_c : array_like, shape (n,)
        Tangential accelerations at A, B (beam 1) and C (beam 2) [m/s^2].
    geometry : JointRigGeometry
        Positions, mass and inertia of beam 2.
    frequency_hz : float, optional
        Excitation frequency [Hz]; estimated from the strongest line of the accelerations
        when omitted (:func:`estimate_frequency`).
    periods : int, optional
        Whole periods to analyse, counted from the end of the record (the steady state);
        default every whole period after the start-up transient. A number reaching into
        the transient is honoured with a warning.
    kinematics : {"paper", "exact"}, optional
        The paper's linear relations (B.1)-(B.10) (default), or the exact sensor kinematics
        solved by ``iterations`` fixed-point passes (module docstring).
    gravity_sensing : bool, optional
        With ``kinematics="exact"``: the sensors read the tangential component of gravity.
    filter : {"harmonic", "highpass"}, optional
        See above; default "harmonic".
    n_harmonics : int, optional
        Highest harmonic kept by the harmonic filter (default: all below Nyquist).
    f_low_hz : float, optional
        Cut-off of the high-pass filter [Hz] (default ``frequency_hz / 2``).
    iterations : int, optional
        Fixed-point passes of the exact kinematics (default 3).
    source : str, optional
        Description of the signals' origin, kept in the result.
    skip_periods : int or "auto", optional
        Leading whole periods dropped as start-up transient; "auto" (default) detects them,
        0 keeps the whole record.
    diagnostics : bool, optional
        Compute the :class:`TrustReport` (default True; ~0.1-0.5 s).
    uncertainty : MeasurementUncertainty, optional
        Uncertainties of the measurement chain for the Monte Carlo (default: its defaults).
    thresholds : TrustThresholds, optional
        When the result is flagged unreliable (default: its defaults).
    force : array_like, shape (n,), optional
        The shaker force measured at D [N] (positive along X0, as the accelerations). With
        ``driven_beam``: a second joint torque from the ``theta1`` equation of 002 (6) and
        the energy balance of the rig (:class:`ForceCheck`); the result is unreliable when
        they disagree beyond ``thresholds.max_torque_discrepancy`` /
        ``max_energy_imbalance``.
    driven_beam : DrivenBeam, optional
        Beam 1 and its shaker and suspension; required with ``force``.

    Returns
    -------
    JointIdentification

    Raises
    ------
    ModelError
        Non-uniform or too short records, fewer than 8 samples per period, channels of
        different lengths or with NaN, bad options.

    References
    ----------
    Bouchaala et al. (2014), section 3, Fig. 7, eqs (8), (26)-(27), appendix B.
    """
    t, dt, snapped = check_time(time)
    chans = []
    for name, g in (("gamma_a", gamma_a), ("gamma_b", gamma_b), ("gamma_c", gamma_c)):
        arr = as_finite_array(name, g, ndim=1)
        if arr.size != t.size:
            raise ModelError(f"{name} has {arr.size} samples, time has {t.size}")
        chans.append(arr)
    if kinematics not in ("paper", "exact"):
        raise ModelError(f"kinematics must be 'paper' or 'exact', got {kinematics!r}")
    if filter not in ("harmonic", "highpass"):
        raise ModelError(f"filter must be 'harmonic' or 'highpass', got {filter!r}")
    if int(iterations) != iterations or iterations < 1:
        raise ModelError(f"iterations must be an integer >= 1, got {iterations!r}")
    if n_harmonics is not None and (int(n_harmonics) != n_harmonics or n_harmonics < 1):
        raise ModelError(f"n_harmonics must be an integer >= 1, got {n_harmonics!r}")
    if skip_periods != "auto" and (isinstance(skip_periods, str) or int(skip_periods)
                                   != skip_periods or skip_periods < 0):
        raise ModelError(f"skip_periods must be 'auto' or an integer >= 0, got "
                         f"{skip_periods!r}")
    if (force is None) != (driven_beam is None):
        raise ModelError("force and driven_beam go together: the torque from the shaker "
                         "force needs beam 1's mass, inertia, shaker position and suspension "
                         "(DrivenBeam), and the force samples [N]")
    if force is not None:
        if not isinstance(driven_beam, DrivenBeam):
            raise ModelError(f"driven_beam must be a DrivenBeam, got "
                             f"{type(driven_beam).__name__}")
        f_arr = as_finite_array("force", force, ndim=1)
        if f_arr.size != t.size:
            raise ModelError(f"force has {f_arr.size} samples, time has {t.size}")
    G = np.column_stack(chans)
    estimated = frequency_hz is None
    if estimated:
        strongest = int(np.argmax(np.std(G, axis=0)))
        frequency_hz = estimate_frequency(G[:, strongest], dt)
        if frequency_hz * dt < 0.125:  # refined on the second half, before the transient test
            frequency_hz = refine_frequency(G[t.size // 2:, strongest], dt, frequency_hz)
    frequency_hz = float(check_positive("frequency_hz", frequency_hz, unit="Hz"))
    mismatch = None
    if not estimated and frequency_hz < 0.5 / dt:
        # a given frequency that is not the signals' strongest line makes a loop of the wrong
        # period: its area (even its sign) is meaningless
        strongest = int(np.argmax(np.std(G, axis=0)))
        seen = float(estimate_frequency(G[:, strongest], dt))
        tol = max(FREQUENCY_MISMATCH * frequency_hz, 1.5 / (G.shape[0] * dt))  # 1.5 bins
        if abs(seen - frequency_hz) > tol:
            mismatch = (f"the given excitation frequency {frequency_hz:g} Hz is not the "
                        f"signals' strongest line ({seen:.4g} Hz, more than "
                        f"{100 * FREQUENCY_MISMATCH:g} % away): the loop is not one period; "
                        "check frequency_hz or leave it out to estimate it")
    if frequency_hz >= 0.5 / dt:
        raise ModelError(f"frequency_hz = {frequency_hz:g} Hz is above the Nyquist frequency "
                         f"{0.5 / dt:g} Hz of the record")
    f_low = 0.5 * frequency_hz if f_low_hz is None else float(f_low_hz)
    per = 1.0 / (frequency_hz * dt)
    if per < 8:
        raise ModelError(f"{per:.3g} samples per period of {frequency_hz:g} Hz: at least 8 "
                         "are needed (sample faster)")

    # start-up transient
    notes = []
    if skip_periods == "auto":
        a1, a2, ax = beam_accelerations(geometry, G[:, 0], G[:, 1], G[:, 2])
        skip, settled = steady_start(np.column_stack((a1, a2, ax, a1 - a2)), dt,
                                     frequency_hz)
        if not settled:
            notes.append("the record may not reach a steady state: the fundamentals of the "
                         "last two quarters differ")
    else:
        skip = int(skip_periods)
    if estimated:  # refined again on the whole steady part (the phase drift of its periods)
        frequency_hz = refine_frequency(G[int(round(skip * per)):, strongest], dt,
                                        frequency_hz)
        per = 1.0 / (frequency_hz * dt)
        log.info("estimated excitation frequency %.9g Hz", frequency_hz)
    start = int(round(skip * per))
    if start >= t.size:
        raise ModelError(f"skip_periods = {skip} leaves no samples of the record "
                         f"({int(t.size / per)} periods)")
    steady_avail = int(np.floor((t.size - start) / per + 1e-9))
    if periods is not None and int(periods) == periods and steady_avail < periods \
            <= int(np.floor(t.size / per + 1e-9)):
        notes.append(f"periods = {int(periods)} reach into the start-up transient (the first "
                     f"{skip} of the record's periods); analysing them anyway")
        start, skip = 0, 0
    t_s, G_s = t[start:], G[start:]
    if force is not None:  # windowed (and resampled) with the accelerations
        tw, Gfw, n_per, resampled, dtw = whole_periods(
            t_s, np.column_stack((G_s, f_arr[start:])), dt, frequency_hz, periods)
        Gw, f_w = Gfw[:, :3], Gfw[:, 3]
    else:
        tw, Gw, n_per, resampled, dtw = whole_periods(t_s, G_s, dt, frequency_hz, periods)
    del G
    options = dict(kinematics=kinematics, gravity_sensing=gravity_sensing, filter=filter,
                   n_harmonics=n_harmonics, f_low=f_low, iterations=iterations)
    loop = process_window(Gw, dtw, n_per, geometry, **options)
    theta1, theta2, x1 = loop.theta1, loop.theta2, loop.x1
    rotation, torque = loop.rotation, loop.torque

    inc = 0.5 * (torque + np.roll(torque, -1)) * (np.roll(rotation, -1) - rotation)
    e_d = float(loop.energy)
    csum = np.concatenate(([0.0], np.cumsum(inc)))
    bounds = np.round(np.arange(n_per + 1) * (tw.size / n_per)).astype(int)
    cycles = np.diff(csum[bounds])
    th_amp = 0.5 * float(np.ptp(rotation))
    m_amp = 0.5 * float(np.ptp(torque))
    if th_amp <= 0 or m_amp <= 0:
        raise ModelError("the identified rotation or torque does not vary: no loop")
    xi = paper002_damping_ratio(e_d, th_amp, m_amp, allow_negative=True)
    xi_e = e_d / (np.pi * float(first_harmonic(rotation, n_per))
                  * float(first_harmonic(torque, n_per)))
    checks = []
    fcheck = None
    if force is not None:
        thr = thresholds or TrustThresholds()
        fcheck = force_check(f_w, loop, dtw, n_per, geometry, driven_beam, filter=filter,
                             n_harmonics=n_harmonics, f_low=f_low,
                             max_torque_discrepancy=thr.max_torque_discrepancy,
                             max_energy_imbalance=thr.max_energy_imbalance)
    if not diagnostics:
        # what needs no diagnostics still judges the result (a wrong frequency makes a loop
        # of the wrong period, whose area, even its sign, is meaningless)
        if mismatch is not None:
            checks.append(mismatch)
        if e_d < 0:
            checks.append(f"the loop area E_d = {e_d:.3g} J is not positive: the loop runs the "
                          "wrong way (check the sign conventions and channel assignment) or "
                          "is noise only")
    trust = None
    if diagnostics:
        trust = assess(energy=e_d, damping_ratio=float(xi), damping_ratio_energy=float(xi_e),
                       Gw=Gw, n_periods=n_per, frequency=frequency_hz, loop=loop,
                       geometry=geometry, options=options, t_steady=t_s, G_steady=G_s, dt=dt,
                       unc=uncertainty or MeasurementUncertainty(),
                       thr=thresholds or TrustThresholds(), notes=notes)
        if mismatch is not None:
            trust = dataclasses.replace(trust, status="unreliable",
                                        warnings=(mismatch, *trust.warnings))
        if fcheck is not None and (fcheck.warnings or fcheck.notes):
            trust = dataclasses.replace(
                trust, status="unreliable" if fcheck.warnings else trust.status,
                warnings=(*fcheck.warnings, *trust.warnings, *fcheck.notes))
        if trust.status != "ok":  # the verdict travels with the result; callers report it
            log.info("identification unreliable: %s", "; ".join(trust.warnings))
    else:
        if fcheck is not None:
            checks.extend(fcheck.warnings)
            notes.extend(fcheck.notes)
        if notes:
            log.warning("%s", "; ".join(notes))
    return JointIdentification(
        time=tw, theta1=theta1, theta2=theta2, x1=x1, rotation=rotation, torque=torque,
        frequency_hz=frequency_hz, n_periods=n_per, dissipated_energy=e_d,
        cycle_energy=cycles, rotation_amplitude=th_amp, torque_amplitude=m_amp,
        damping_ratio=float(xi), kinematics=kinematics, filter=filter, resampled=resampled,
        filtered_fraction=loop.residual, source=source, damping_ratio_energy=float(xi_e),
        skipped_periods=skip, time_snapped=snapped, trust=trust, checks=tuple(checks),
        force_check=fcheck)


#: Largest relative distance between a given excitation frequency and the strongest line of
#: the signals (or 1.5 FFT bins, 1.5 / record length, if that is more: the line's resolution).
FREQUENCY_MISMATCH = 0.05


#: Voltage units of channels that a sensitivity [mV/g] turns into accelerations.
VOLTAGE_UNITS: dict[str, float] = {"mv": 1.0, "v": 1e3, "": 1.0}


def identify_from_table(table: Mapping, geometry: JointRigGeometry, *,
                        channels: Mapping[str, str] | None = None,
                        units: Mapping[str, str] | str | None = None,
                        sensitivity_mV_per_g: Mapping[str, float] | None = None,
                        driven_beam: DrivenBeam | None = None,
                        force_unit: str | None = None,
                        force_sensitivity_mV_per_N: float | None = None,
                        **options) -> JointIdentification:
    """Run :func:`identify_joint` on a table of signals (CSV or UFF reader output).

    Parameters
    ----------
    table : SignalTable or mapping
        ``"time"`` [s] and the channels (a :class:`~fricdamp.signals.records.SignalTable`
        from :func:`~fricdamp.signals.records.read_signals_csv`, or the UFF reader's table);
        its ``units`` attribute (name -> unit) gives each channel's unit.
    geometry : JointRigGeometry
    channels : mapping, optional
        ``{"A": name, "B": name, "C": name}``: the table columns of the three accelerometers;
        default the columns named A, B and C. An optional ``"force": name`` is the shaker's
        force channel (default the column ``force`` when ``driven_beam`` is given).
    units : str or mapping, optional
        Unit of every accelerometer channel (a string) or per role ``{"A": "g", ...}``;
        overrides the units of the table (needed when the file has none).
    sensitivity_mV_per_g : mapping, optional
        Per role ``{"A": 10.35, ...}`` [mV/g], > 0: those channels hold the sensors'
        voltages (unit mV, V, or none = mV), turned into accelerations by
        ``a = U / S * 9.80665`` m/s^2 (paper 002 §2 gives 10.35, 10.79, 10.29 mV/g).
    driven_beam : DrivenBeam, optional
        Beam 1, its shaker and suspension: with a force channel, the second torque estimate
        and the energy balance (:class:`ForceCheck`).
    force_unit : str, optional
        Unit of the force channel (N, kN, mN, lbf, kgf; or mV / V with
        ``force_sensitivity_mV_per_N``); overrides the table's.
    force_sensitivity_mV_per_N : float, optional
        Sensitivity of the force sensor [mV/N], > 0, for a voltage force channel.
    **options
        Passed to :func:`identify_joint`.

    Raises
    ------
    ModelError
        A missing channel (listing the columns), an unknown or missing unit, a sensitivity
        <= 0 or given for a channel already in acceleration units, a force channel without
        ``driven_beam``.
    """
    channels = dict(channels or {"A": "A", "B": "B", "C": "C"})
    force_col = channels.pop("force", None)
    if set(channels) != {"A", "B", "C"}:
        raise ModelError(f"channels must map exactly A, B and C (and optionally force) to "
                         f"column names, got {sorted(channels)}")
    sens = dict(sensitivity_mV_per_g or {})
    if not set(sens) <= {"A", "B", "C"}:
        raise ModelError(f"sensitivity_mV_per_g must map A, B or C to mV/g, got "
                         f"{sorted(sens)}")
    if "time" not in table:
        raise ModelError("the signal table has no 'time' column")
    table_units = dict(getattr(table, "units", {}) or {})
    data = []
    for role in ("A", "B", "C"):
        col = channels[role]
        if col not in table:
            cols = [c for c in table if c != "time"]
            raise ModelError(f"accelerometer {role}: no column {col!r} in the signals; "
                             f"columns: {cols}")
        if isinstance(units, str):
            unit = units
        elif units is not None and role in units:
            unit = units[role]
        else:
            unit = table_units.get(col, "")
        values = np.asarray(table[col], dtype=float)
        if role in sens:
            s = float(check_positive(f"sensitivity_mV_per_g[{role!r}]", sens[role],
                                     unit="mV/g"))
            key = str(unit).strip().lower()
            if key not in VOLTAGE_UNITS:
                raise ModelError(f"channel {col!r} is in {unit!r}, not a voltage (V, mV): a "
                                 "sensitivity [mV/g] applies to voltage channels; drop it "
                                 "for channels already in acceleration units")
            data.append(values * VOLTAGE_UNITS[key] / s * ACCELERATION_UNITS["g"])
        else:
            data.append(values * acceleration_scale(unit, channel=col))
    force = None
    if force_col is not None and driven_beam is None:
        raise ModelError(f"a force channel ({force_col!r}) needs the driven beam (beam 1's "
                         "mass, inertia, shaker position and suspension) for its checks")
    if driven_beam is not None:
        force_col = "force" if force_col is None else force_col
        if force_col not in table:
            cols = [c for c in table if c != "time"]
            raise ModelError(f"force channel: no column {force_col!r} in the signals; "
                             f"columns: {cols}")
        unit = force_unit if force_unit is not None else table_units.get(force_col, "")
        force = np.asarray(table[force_col], dtype=float) * force_scale(
            unit, force_sensitivity_mV_per_N, channel=force_col)
    source = options.pop("source", "") or str(getattr(table, "path", ""))
    return identify_joint(table["time"], *data, geometry, source=source, force=force,
                          driven_beam=driven_beam, **options)


def force_scale(unit: str, sensitivity_mV_per_N: float | None = None, *,
                channel: str = "") -> float:
    """Factor turning the force channel's values into N.

    ``unit`` is a force unit (:data:`FORCE_UNITS`), or a voltage (mV, V) with
    ``sensitivity_mV_per_N`` [mV/N] > 0.
    """
    key = str(unit).strip().lower()
    where = f"channel {channel!r}: " if channel else ""
    if sensitivity_mV_per_N is not None:
        s = float(check_positive("force_sensitivity_mV_per_N", sensitivity_mV_per_N,
                                 unit="mV/N"))
        if key not in VOLTAGE_UNITS:
            raise ModelError(f"{where}the force is in {unit!r}, not a voltage (V, mV): a "
                             "sensitivity [mV/N] applies to a voltage channel")
        return VOLTAGE_UNITS[key] / s
    if key not in FORCE_UNITS:
        raise ModelError(f"{where}unknown or missing force unit {unit!r}; units understood: "
                         f"{', '.join(FORCE_UNITS)} (or mV/V with a sensitivity in mV/N)")
    return FORCE_UNITS[key]
