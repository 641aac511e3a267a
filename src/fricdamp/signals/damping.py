"""Damping ratios, each with its own name: never mix them.

Five quantities are in use in the friction-damping literature and in fricdamp; they differ by
factors of 2, 4 and pi, so each has its own function and the docstring says what it is:

- :func:`energy_damping_ratio` (zeta) = ``E_d / (4 pi E_s)``, E_s the peak strain energy of
  the loop (``k A^2 / 2``); viscous 1-DOF value ``c w / (2 k)``.
- :func:`loss_factor` (eta) = ``E_d / (2 pi E_s)`` = 2 zeta; viscous value ``c w / k``.
- :func:`paper002_damping_ratio` (xi) = ``E_d / (pi theta_max M_max)``, 002 (26)-(27);
  viscous value ``eta / sqrt(1 + eta^2)``, i.e. about the loss factor, not zeta.
- :func:`zeta_from_log_decrement` = ``delta / sqrt(4 pi^2 + delta^2)`` (linear free decay).
- :func:`coulomb_equivalent_ratio` = ``2 F_f / (pi k A)`` (Coulomb free decay or loop).

For a linear viscous oscillator ``m x'' + c x' + k x = F cos(w t)`` whose loop is the ellipse
``f = k u + c u'`` with ``u = A cos(w t)``: ``E_d = pi c w A^2``, ``E_s = k A^2 / 2``, so the
energy ratio is ``c w / (2 k)``, which equals the modal ratio ``zeta = c / (2 sqrt(k m))`` at
``w = w_n`` (tests/unit/test_damping_ratios.py).

References
----------
REFERENCES.md, "Damping ratios" and "Coulomb oscillator". Paper 002 (Bouchaala et al. 2014),
eqs (26)-(27).
"""

from __future__ import annotations

import numpy as np

from fricdamp.errors import ModelError, as_finite_array, check_positive


def _out(value: np.ndarray):
    """Return a Python float for 0-d results, the array otherwise."""
    value = np.asarray(value, dtype=float)
    return float(value) if value.ndim == 0 else value


def _dissipated(name: str, value, allow_negative: bool) -> np.ndarray:
    if allow_negative:
        return as_finite_array(name, value)
    arr = as_finite_array(name, value)
    if np.any(arr < 0):
        raise ModelError(
            f"{name} must be >= 0 J (energy dissipated per cycle by a passive element), got "
            f"{value!r}; a negative loop area usually means the force drives the motion "
            "instead of resisting it (swap the sign of f) or that the loop is noise only "
            "(pass allow_negative=True to accept it)")
    return arr


def energy_damping_ratio(dissipated_energy, strain_energy, *, allow_negative: bool = False):
    """Energy-based equivalent viscous damping ratio ``zeta = E_d / (4 pi E_s)`` [-].

    ``E_s`` is the **peak strain energy** of the cycle (``k A^2 / 2`` for a linear spring of
    stiffness k at amplitude A; see :func:`fricdamp.signals.energy.peak_strain_energy`). For
    a linear viscous loop at the natural frequency this is the modal damping ratio zeta.

    Parameters
    ----------
    dissipated_energy : float or array_like
        E_d, energy dissipated per cycle [J] (loop area, ``loop_area(u, f)``), >= 0.
    strain_energy : float or array_like
        E_s, peak strain energy [J], > 0. Broadcasts against ``dissipated_energy``.
    allow_negative : bool, optional
        Accept E_d < 0 (noisy near-elastic measured loops); default False.

    Returns
    -------
    float or ndarray
        zeta [-], same shape as the broadcast inputs.

    Raises
    ------
    ModelError
        If E_s <= 0, E_d < 0 (unless allowed) or any input is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> k, c, w, A = 100.0, 0.4, 10.0, 1e-3   # w = w_n for m = 1 kg
    >>> round(energy_damping_ratio(np.pi * c * w * A**2, 0.5 * k * A**2), 12)
    0.02
    """
    e_d = _dissipated("dissipated_energy", dissipated_energy, allow_negative)
    e_s = check_positive("strain_energy", strain_energy, unit="J")
    return _out(e_d / (4.0 * np.pi * e_s))


def loss_factor(dissipated_energy, strain_energy, *, allow_negative: bool = False):
    """Loss factor ``eta = E_d / (2 pi E_s)`` = 2 zeta [-], with E_s the peak strain energy.

    Parameters
    ----------
    dissipated_energy : float or array_like
        E_d, energy dissipated per cycle [J], >= 0.
    strain_energy : float or array_like
        E_s, peak strain energy [J] (``k A^2 / 2`` for a linear spring), > 0.
    allow_negative : bool, optional
        Accept E_d < 0; default False.

    Returns
    -------
    float or ndarray
        eta [-]; for a linear viscous loop ``eta = c w / k``.

    Raises
    ------
    ModelError
        If E_s <= 0, E_d < 0 (unless allowed) or any input is not finite.
    """
    e_d = _dissipated("dissipated_energy", dissipated_energy, allow_negative)
    e_s = check_positive("strain_energy", strain_energy, unit="J")
    return _out(e_d / (2.0 * np.pi * e_s))


def paper002_supplied_energy(theta_max, moment_max):
    """Paper 002's "supplied energy" ``E_s = 4 theta_max M_max`` [J], 002 (27).

    This is the area of the rectangle that bounds the torque-rotation loop, i.e. 8 times the
    peak strain energy ``theta_max M_max / 2`` of a linear spring; it is *not* the E_s of
    :func:`energy_damping_ratio`.

    Parameters
    ----------
    theta_max : float or array_like
        Amplitude of the relative rotation (theta_1 - theta_2)_max [rad], > 0.
    moment_max : float or array_like
        Amplitude of the joint torque M_max [N m], > 0.

    Returns
    -------
    float or ndarray
        ``4 theta_max M_max`` [J].
    """
    th = check_positive("theta_max", theta_max, unit="rad")
    mm = check_positive("moment_max", moment_max, unit="N m")
    return _out(4.0 * th * mm)


def paper002_damping_ratio(dissipated_energy, theta_max, moment_max, *,
                           allow_negative: bool = False):
    """Paper 002's damping ratio ``xi = E_d / (pi theta_max M_max)`` [-], 002 (26)-(27).

    The paper (Bouchaala et al. 2014, section 5.2, after Bouchaala et al. 2013) writes
    ``xi = (4 / pi) E_d / E_s`` (26) with the "supplied energy" ``E_s = 4 (theta_1 -
    theta_2)_max M_max`` (27) -- the bounding rectangle of the loop -- hence
    ``xi = E_d / (pi theta_max M_max)``. The extracted text of (26) is legible; we checked it
    by re-deriving its meaning: for a linear spring ``M = k theta``, ``theta_max M_max =
    2 E_strain`` and xi becomes ``E_d / (2 pi E_strain)``, the **loss factor** eta = 2 zeta,
    not the damping ratio zeta. For the viscous loop ``M = k theta + c theta'`` the peak
    torque includes the damping torque, ``M_max = theta_max sqrt(k^2 + (c w)^2)``, so exactly
    ``xi = eta / sqrt(1 + eta^2)`` with ``eta = c w / k`` (equal to eta to O(eta^3);
    tests/unit/test_damping_ratios.py).

    Parameters
    ----------
    dissipated_energy : float or array_like
        E_d, loop area of the torque-rotation loop [J], >= 0.
    theta_max : float or array_like
        Amplitude of the relative rotation [rad], > 0.
    moment_max : float or array_like
        Amplitude of the joint torque [N m], > 0.
    allow_negative : bool, optional
        Accept E_d < 0; default False.

    Returns
    -------
    float or ndarray
        xi [-] (comparable with the loss factor eta, i.e. twice a damping ratio zeta).

    Raises
    ------
    ModelError
        If theta_max <= 0, moment_max <= 0, E_d < 0 (unless allowed) or inputs not finite.
    """
    e_d = _dissipated("dissipated_energy", dissipated_energy, allow_negative)
    e_s = paper002_supplied_energy(theta_max, moment_max)  # 002 (27)
    return _out(4.0 / np.pi * e_d / e_s)  # 002 (26)


def zeta_from_log_decrement(delta):
    """Damping ratio from the logarithmic decrement, ``zeta = delta / sqrt(4 pi^2 + delta^2)``.

    Exact for a linear viscous free decay ``x = A exp(-zeta w_n t) cos(w_d t + phi)``, whose
    successive peaks one damped period apart have the ratio ``exp(delta)`` with ``delta =
    2 pi zeta / sqrt(1 - zeta^2)``. For a Coulomb (linear-envelope) decay use
    :func:`coulomb_equivalent_ratio` instead.

    Parameters
    ----------
    delta : float or array_like
        Logarithmic decrement per cycle ``ln(x_n / x_{n+1})`` [-] (negative for a growing
        oscillation, which gives a negative ratio).

    Returns
    -------
    float or ndarray
        zeta [-], in (-1, 1).
    """
    d = as_finite_array("delta", delta)
    return _out(d / np.sqrt(4.0 * np.pi**2 + d * d))


def log_decrement_from_zeta(zeta):
    """Logarithmic decrement per cycle ``delta = 2 pi zeta / sqrt(1 - zeta^2)`` [-].

    Inverse of :func:`zeta_from_log_decrement`.

    Parameters
    ----------
    zeta : float or array_like
        Viscous damping ratio [-], in (-1, 1).

    Returns
    -------
    float or ndarray
        delta [-].

    Raises
    ------
    ModelError
        If |zeta| >= 1 (no oscillation, no decrement).
    """
    z = as_finite_array("zeta", zeta)
    if np.any(np.abs(z) >= 1.0):
        raise ModelError(f"zeta must lie in (-1, 1) (underdamped), got {zeta!r}")
    return _out(2.0 * np.pi * z / np.sqrt(1.0 - z * z))


def coulomb_equivalent_ratio(friction_force, stiffness, amplitude):
    """Equivalent damping ratio of a Coulomb oscillator, ``zeta_eq = 2 F_f / (pi k A)`` [-].

    Energy equivalence: a Coulomb slider dissipates ``E_d = 4 F_f A`` per cycle at amplitude
    A, and ``E_d / (4 pi k A^2 / 2)`` gives the ratio above; equivalently, a free decay loses
    ``dA = 4 F_f / k`` per cycle and ``zeta_eq = dA / (2 pi A)`` (den Hartog; REFERENCES.md).
    The ratio grows as the amplitude falls; the motion stops once ``A <= F_s / k``.

    Parameters
    ----------
    friction_force : float or array_like
        Sliding friction force F_f = mu N [N], >= 0.
    stiffness : float or array_like
        Spring stiffness k [N/m], > 0.
    amplitude : float or array_like
        Vibration amplitude A [m], > 0.

    Returns
    -------
    float or ndarray
        zeta_eq [-], broadcast shape of the inputs.

    Raises
    ------
    ModelError
        If F_f < 0, k <= 0, A <= 0 or inputs are not finite.

    Examples
    --------
    >>> round(coulomb_equivalent_ratio(1.0, 1000.0, 0.01), 10)
    0.0636619772
    """
    ff = check_positive("friction_force", friction_force, unit="N", allow_zero=True)
    k = check_positive("stiffness", stiffness, unit="N/m")
    a = check_positive("amplitude", amplitude, unit="m")
    return _out(2.0 * ff / (np.pi * k * a))


def equivalent_viscous_damping(dissipated_energy, omega, amplitude, *,
                               allow_negative: bool = False):
    """Equivalent viscous coefficient ``c_eq = E_d / (pi w A^2)`` [N s/m].

    The dashpot that dissipates the same energy per cycle as the loop at the same harmonic
    amplitude: a dashpot c dissipates ``pi c w A^2`` per cycle.

    Parameters
    ----------
    dissipated_energy : float or array_like
        E_d [J], >= 0.
    omega : float or array_like
        Angular frequency w [rad/s], > 0.
    amplitude : float or array_like
        Displacement amplitude A [m], > 0.
    allow_negative : bool, optional
        Accept E_d < 0; default False.

    Returns
    -------
    float or ndarray
        c_eq [N s/m].
    """
    e_d = _dissipated("dissipated_energy", dissipated_energy, allow_negative)
    w = check_positive("omega", omega, unit="rad/s")
    a = check_positive("amplitude", amplitude, unit="m")
    return _out(e_d / (np.pi * w * a * a))
