"""Joint curves of paper 002: hysteresis loops, dissipated energy and damping ratio of a joint
law against the rotation amplitude (Figs 14, 16, 17).

:func:`symmetric_cycle` (one steady symmetric cycle, by closed-form Masing branches
:func:`masing_descent_kernel` for Cattaneo-Mindlin summits or by marching the law),
:class:`JointCurves` and :func:`joint_curves`; re-exported by
:mod:`fricdamp.models.rotational_joint.model`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from fricdamp.contact.base import ContactLaw
from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.signals.damping import paper002_damping_ratio
from fricdamp.signals.energy import loop_area


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
