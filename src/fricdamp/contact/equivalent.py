"""Equivalent viscous damping of dry friction from a harmonic slip orbit, 001 (19)-(34).

A contact point slipping harmonically in its contact plane, ``xi(t) = Re(xi~ e^{i w t})``,
``eta(t) = Re(eta~ e^{i w t})`` (complex amplitudes xi~, eta~ [m], excitation frequency
``w`` [rad/s]), traces an ellipse 001 (19)-(25). Its semi-axes follow from
``|r(tau)|^2 = (A + B)/2 + (A - B)/2 cos 2 tau - C sin 2 tau`` (``tau = w t``) with
``A = xi'^2 + eta'^2``, ``B = xi''^2 + eta''^2``, ``C = xi' xi'' + eta' eta''`` (one prime the
real, two primes the imaginary part, 001 (22)); the extremes are at
``tan 2 tau_1 = 2 C / (B - A)`` (001 (25), solved here with ``atan2`` so the branch is the
maximum) and ``tau_2 = tau_1 + pi/2``::

    a^2 = (A + B)/2 + sqrt(((A - B)/2)^2 + C^2),   b^2 = (A + B)/2 - sqrt(...)

and the major axis is inclined by ``delta = atan2(eta(tau_1), xi(tau_1))`` to the xi axis
001 (24), reported in [0, pi).

Friction is replaced by two viscous dampers along the ellipse axes 001 (26)
``T' = diag(c_a, c_b) v'`` and turned back to the (xi, eta) axes with the rotation by delta
001 (29)-(30) (the extracted text of (30) is garbled; it is the rotation matrix
``[[cos, sin], [-sin, cos]]``). Two rules for the coefficients are offered:

``rule="coulomb"`` (default)
    The exact first harmonic of Coulomb friction ``T = -f N v/|v|`` (constant normal load N)
    on the ellipse. With ``xi' = a cos tau``, ``eta' = b sin tau`` in the ellipse axes the
    force has no component in phase with the displacement nor any coupling between the
    axes (the integrands are odd), so the describing function *is* diagonal in the axes,
    as 001 (26) assumes, with::

        c_a = f N / (pi w) int_0^{2 pi} sin^2 / sqrt(a^2 sin^2 + b^2 cos^2) dtau
            = f N / (pi w) (4/3) b^2 R_D(0, a^2, b^2)
        c_b = f N / (pi w) (4/3) a^2 R_D(0, b^2, a^2)

    (R_D Carlson's symmetric elliptic integral; the forms avoid the cancellation of
    ``(E - (1 - m) K)/m``). Limits: a straight orbit (b -> 0) gives ``c_a = 4 f N/(pi a w)``,
    001 (27) with p = 1, and dissipates ``4 f N a`` per cycle; a circle gives
    ``c = f N/(a w)`` and ``2 pi a f N`` per cycle. In general the dissipation per cycle is
    ``pi w (c_a a^2 + c_b b^2) = f N x (perimeter of the ellipse)`` -- Coulomb's work.
``rule="paper"``
    001 (27) literally: each axis as an independent one-dimensional slip,
    ``c_a = 4 f N/(pi a w)``, ``c_b = 4 f N/(pi b w)``; it dissipates ``4 f N (a + b)`` per
    cycle, exact for a straight orbit, 4/pi = 27 % too much for a circle. Its minor-axis
    coefficient grows like 1/b (the Coulomb rule's only like log(a/b)), which makes the
    equivalent-linearisation fixed point stiff: on the 001 model a few per cent of the
    speeds do not converge with it (the solver flags them).

The paper's exponent p (fitted to measurements, 001 (27), (32)) multiplies each coefficient
by ``(w a_i)^(1 - p)`` with the slip velocity amplitude ``w a_i`` in m/s (SI, as in the
paper; p = 1, the default, is Coulomb's law and dimensionally clean).

Friction torque 001 (31)-(33): the relative rotation about the contact normal, amplitude
phi [rad], is damped by ``b_e = 4 M_0/(pi (phi w)^p)``. The paper does not define the
friction torque M_0; here it is the full-slip torque of a uniformly loaded effective
rectangle ``a_ef x h_ef`` (the one of 001 (17)): ``M_0 = f N rho`` with rho the mean distance
of the rectangle's points from its centre (:func:`rectangle_mean_radius`).

The equivalent coefficients diverge as the slip amplitude vanishes (a stuck contact). They
are evaluated at ``max(a, min_amplitude)`` and ``max(b, min_amplitude, min_ratio a)``: a
contact whose orbit falls below the floor is reported as stuck.

References
----------
Pesek, Pust et al. (paper 001): (19)-(34).
Carlson (1995), Numer. Algorithms 10, 13-26 (R_D).
Griffin (1980), J. Eng. Power 102, 329-333 (friction damper describing functions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import elliprd

from fricdamp.errors import ModelError, as_finite_array, check_positive

__all__ = [
    "RULES",
    "EllipseFrictionDamping",
    "JenkinsEllipseDamping",
    "SlipEllipse",
    "ellipse_damping",
    "ellipse_perimeter",
    "friction_torque",
    "orbit_damping_matrix",
    "rectangle_mean_radius",
    "rectangle_twist_stiffness",
    "slip_ellipse",
    "torsional_damping",
]

#: Rules for the equivalent damping coefficients along the ellipse axes.
RULES = ("coulomb", "paper")


@dataclass(frozen=True)
class SlipEllipse:
    """Elliptical slip orbit of contact points, 001 (23)-(25); arrays of one shape (...).

    Attributes
    ----------
    major, minor : ndarray
        Semi-axes a >= b >= 0 [m].
    inclination : ndarray
        Angle of the major axis from the xi axis towards eta [rad], in [0, pi).
    phase : ndarray
        ``w t_1`` [rad]: the phase at which the point is at the end of the major axis.
    """

    major: np.ndarray
    minor: np.ndarray
    inclination: np.ndarray
    phase: np.ndarray

    def points(self, n: int = 101) -> tuple[np.ndarray, np.ndarray]:
        """Closed orbit in the (xi, eta) axes: two arrays of shape (..., n) [m]."""
        tau = np.linspace(0.0, 2 * np.pi, int(n))
        c, s = np.cos(self.inclination)[..., None], np.sin(self.inclination)[..., None]
        x1 = self.major[..., None] * np.cos(tau)
        x2 = self.minor[..., None] * np.sin(tau)
        return c * x1 - s * x2, s * x1 + c * x2


def slip_ellipse(xi, eta) -> SlipEllipse:
    """Semi-axes and inclination of the orbit of complex amplitudes ``(xi, eta)``.

    Parameters
    ----------
    xi, eta : array_like of complex, broadcastable shapes (...)
        Complex amplitudes of the slip along xi and eta [m], ``xi(t) = Re(xi e^{i w t})``.

    Returns
    -------
    SlipEllipse
        001 (23)-(25) with the branch of (25) chosen so that ``a >= b``.

    Examples
    --------
    >>> e = slip_ellipse(2e-6, 1e-6j)       # xi = 2 cos, eta = -sin: a = 2, b = 1 um
    >>> float(e.major), float(e.minor), float(e.inclination)
    (2e-06, 1e-06, 0.0)
    """
    xi = np.asarray(xi, dtype=complex)
    eta = np.asarray(eta, dtype=complex)
    xr, xs, er, es = xi.real, xi.imag, eta.real, eta.imag
    A = xr**2 + er**2
    B = xs**2 + es**2
    C = xr * xs + er * es
    half = 0.5 * (A - B)
    rad = np.hypot(half, C)
    mean = 0.5 * (A + B)
    a = np.sqrt(mean + rad)
    b = np.sqrt(np.maximum(mean - rad, 0.0))
    tau1 = 0.5 * np.arctan2(-C, half)                          # 001 (25)
    x1 = xr * np.cos(tau1) - xs * np.sin(tau1)                 # 001 (22) at t_1
    y1 = er * np.cos(tau1) - es * np.sin(tau1)
    incl = np.mod(np.arctan2(y1, x1), np.pi)                   # 001 (24)
    incl = np.where(incl >= np.pi * (1 - 1e-15), 0.0, incl)
    return SlipEllipse(major=a, minor=b, inclination=incl, phase=tau1)


def ellipse_perimeter(major, minor) -> np.ndarray:
    """Perimeter of ellipses with semi-axes a >= b >= 0 [m].

    ``(4/3) a^2 b^2 (R_D(0, a^2, b^2) + R_D(0, b^2, a^2))`` (= ``4 a E(1 - b^2/a^2)``), the
    sum ``a^2 I_a + b^2 I_b`` of the two integrals of the Coulomb rule; 4a for b = 0.
    """
    a = np.asarray(major, dtype=float)
    b = np.asarray(minor, dtype=float)
    ok = b > 0
    bs, as_ = np.where(ok, b, 1.0), np.where(ok, a, 1.0)
    out = 4.0 / 3.0 * as_**2 * bs**2 * (_rd(bs, as_) + _rd(as_, bs))
    return np.where(ok, out, 4.0 * a)


def _rd(x, y):
    """``R_D(0, x^2, y^2)`` with the convention that a zero first argument is allowed."""
    return elliprd(0.0, np.asarray(x, float) ** 2, np.asarray(y, float) ** 2)


def _check_rule(rule: str) -> None:
    if rule not in RULES:
        raise ModelError(f"rule must be one of {RULES}, got {rule!r}")


def _floors(major, minor, min_amplitude, min_ratio):
    a = np.maximum(major, min_amplitude)
    b = np.minimum(np.maximum(np.maximum(minor, min_amplitude), min_ratio * a), a)
    return a, b


def ellipse_damping(major, minor, normal_load, friction_coefficient, omega, *,
                    exponent: float = 1.0, rule: str = "coulomb",
                    min_amplitude: float = 1e-12, min_ratio: float = 1e-6
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Equivalent viscous damping along the ellipse axes, 001 (26)-(27).

    Parameters
    ----------
    major, minor : array_like
        Semi-axes a >= b >= 0 of the slip orbit [m].
    normal_load : array_like
        Normal force N >= 0 [N] (constant over the cycle, 001 (6)).
    friction_coefficient : array_like
        f >= 0 [-].
    omega : array_like
        Excitation angular frequency > 0 [rad/s].
    exponent : float
        The paper's p > 0 (1: Coulomb).
    rule : {"coulomb", "paper"}
        See the module docstring.
    min_amplitude : float
        Floor of the semi-axes [m] (> 0) where the coefficients are evaluated.
    min_ratio : float
        Floor of b/a, in (0, 1].

    Returns
    -------
    c_major, c_minor : ndarray
        Damping coefficients [N s/m] along the major and minor axes (broadcast shape).

    Examples
    --------
    >>> ca, cb = ellipse_damping(1e-6, 1e-6, 100.0, 0.1, 1000.0)   # circle: f N/(a w)
    >>> round(float(ca), 6), round(float(cb), 6)
    (10000.0, 10000.0)
    """
    _check_rule(rule)
    p = float(check_positive("exponent", exponent))
    check_positive("min_amplitude", min_amplitude, unit="m")
    if not 0 < min_ratio <= 1:
        raise ModelError(f"min_ratio must lie in (0, 1], got {min_ratio!r}")
    N = check_positive("normal_load", normal_load, unit="N", allow_zero=True)
    f = check_positive("friction_coefficient", friction_coefficient, allow_zero=True)
    w = check_positive("omega", omega, unit="rad/s")
    return _ellipse_damping(as_finite_array("major", major), as_finite_array("minor", minor),
                            f * N, w, p, rule, float(min_amplitude), float(min_ratio))


def _ellipse_damping(major, minor, fN, w, p, rule, min_amplitude, min_ratio):
    """Unchecked kernel of :func:`ellipse_damping` (fN = f N)."""
    a, b = _floors(major, minor, min_amplitude, min_ratio)
    if rule == "coulomb":
        ca = fN / (np.pi * w) * (4.0 / 3.0) * b**2 * _rd(a, b)
        cb = fN / (np.pi * w) * (4.0 / 3.0) * a**2 * _rd(b, a)
    else:
        ca = 4.0 * fN / (np.pi * w * a)
        cb = 4.0 * fN / (np.pi * w * b)
    if p != 1.0:
        ca = ca * (w * a) ** (1.0 - p)
        cb = cb * (w * b) ** (1.0 - p)
    return ca, cb


def orbit_damping_matrix(c_major, c_minor, inclination) -> np.ndarray:
    """2x2 damping matrices in the (xi, eta) axes, 001 (29)-(30), shape (..., 2, 2).

    ``C = c_a e e^T + c_b e_perp e_perp^T`` with ``e = (cos delta, sin delta)``.
    """
    ca = np.asarray(c_major, float)
    cb = np.asarray(c_minor, float)
    d = np.asarray(inclination, float)
    c, s = np.cos(d), np.sin(d)
    shape = np.broadcast_shapes(ca.shape, cb.shape, d.shape)
    out = np.empty(shape + (2, 2))
    out[..., 0, 0] = ca * c * c + cb * s * s
    out[..., 1, 1] = ca * s * s + cb * c * c
    out[..., 0, 1] = out[..., 1, 0] = (ca - cb) * c * s
    return out


def torsional_damping(amplitude, friction_torque_Nm, omega, *, exponent: float = 1.0,
                      min_amplitude: float = 1e-12) -> np.ndarray:
    """Equivalent rotational damping ``4 M_0 / (pi (phi w)^p)`` [N m s/rad], 001 (32).

    Parameters
    ----------
    amplitude : array_like
        Amplitude phi of the relative rotation about the contact normal [rad], 001 (33).
    friction_torque_Nm : array_like
        Full-slip friction torque M_0 >= 0 [N m].
    omega : array_like
        Excitation angular frequency > 0 [rad/s].
    exponent : float
        p > 0.
    min_amplitude : float
        Floor of phi [rad].
    """
    p = float(check_positive("exponent", exponent))
    M0 = check_positive("friction_torque_Nm", friction_torque_Nm, unit="N m", allow_zero=True)
    w = check_positive("omega", omega, unit="rad/s")
    phi = np.maximum(as_finite_array("amplitude", amplitude), min_amplitude)
    return 4.0 * M0 / (np.pi * (phi * w) ** p)


def rectangle_mean_radius(side_a, side_h) -> np.ndarray:
    """Mean distance [m] of the points of an ``a x h`` rectangle from its centre.

    ``rho = 4 I(a/2, h/2) / (a h)`` with ``I(c, d) = int_0^c int_0^d sqrt(x^2 + y^2) dy dx =
    (2 c d D + c^3 ln((d + D)/c) + d^3 ln((c + D)/d)) / 6``, ``D = sqrt(c^2 + d^2)``.
    A square of side s gives ``rho = s (sqrt 2 + ln(1 + sqrt 2))/6 = 0.38260 s``.

    Examples
    --------
    >>> round(float(rectangle_mean_radius(1.0, 1.0)), 6)
    0.382598
    """
    a = check_positive("side_a", side_a, unit="m")
    h = check_positive("side_h", side_h, unit="m")
    c, d = 0.5 * a, 0.5 * h
    D = np.hypot(c, d)
    integral = (2 * c * d * D + c**3 * np.log((d + D) / c) + d**3 * np.log((c + D) / d)) / 6
    return 4.0 * integral / (a * h)


def rectangle_twist_stiffness(tangential_stiffness, side_a, side_h) -> np.ndarray:
    """Stick stiffness against rotation about the normal ``k_r = k_t (a^2 + h^2) / 12``
    [N m/rad] of an ``a x h`` rectangle whose tangential stiffness ``k_t`` [N/m] is spread
    uniformly over its area and twisted about its centre (the polar moment of the area over
    the area).

    Examples
    --------
    >>> round(float(rectangle_twist_stiffness(1.2e6, 0.01, 0.02)), 6)
    50.0
    """
    kt = check_positive("tangential_stiffness", tangential_stiffness, unit="N/m")
    a = check_positive("side_a", side_a, unit="m")
    h = check_positive("side_h", side_h, unit="m")
    return kt * (a**2 + h**2) / 12.0


def friction_torque(normal_load, friction_coefficient, side_a, side_h) -> np.ndarray:
    """Full-slip friction torque ``M_0 = f N rho(a_ef, h_ef)`` [N m] of a uniformly loaded
    rectangle rotating about its centre (the M_X,0 of 001 (32))."""
    N = check_positive("normal_load", normal_load, unit="N", allow_zero=True)
    f = check_positive("friction_coefficient", friction_coefficient, allow_zero=True)
    return f * N * rectangle_mean_radius(side_a, side_h)


class EllipseFrictionDamping:
    """Equivalent damping of ``n_c`` friction contacts in contact coordinates (vectorised).

    Contact coordinates, per contact c: rows ``3c, 3c+1`` the slip along xi and eta [m],
    row ``3c+2`` the relative rotation about the normal [rad] (only when friction torques
    are given; otherwise 2 rows per contact). This is the damping model the
    equivalent-linearisation solver :func:`fricdamp.solvers.eqlin.equivalent_linearisation`
    iterates with.

    Parameters
    ----------
    normal_load : array_like, shape (n_c,) or (n_batch, n_c)
        Constant normal loads N [N] (per batch point, e.g. per spin speed).
    friction_coefficient : array_like, shape (n_c,) or scalar
        f >= 0 [-].
    torque_arm : array_like, shape (n_c,), optional
        Arm rho [m] of the full-slip friction torque ``M_0 = f N rho`` about the normal
        (:func:`rectangle_mean_radius` of the effective contact area); None: no torsional
        rows.
    exponent : float
        p > 0 of 001 (27), (32).
    rule : {"coulomb", "paper"}
        See the module docstring.
    min_amplitude : float
        Floor of slip amplitudes [m]; below it a contact is stuck. The floor of the rotation
        amplitudes is ``min_amplitude / torque_arm`` [rad] (the same slip at the arm).
    min_ratio : float
        Floor of b/a.

    Attributes
    ----------
    groups : ndarray of int, shape (m,)
        Convergence groups: ``2c`` the translation of contact c, ``2c+1`` its rotation
        (without torsion: ``c``).
    atol : ndarray, shape (n_groups,)
        Absolute convergence tolerance per group: the slip and rotation floors (an orbit
        below them is stuck, its further changes do not matter).
    """

    def __init__(self, normal_load, friction_coefficient, torque_arm=None, *,
                 exponent: float = 1.0, rule: str = "coulomb", min_amplitude: float = 1e-12,
                 min_ratio: float = 1e-6):
        _check_rule(rule)
        N = np.atleast_1d(check_positive("normal_load", normal_load, unit="N",
                                         allow_zero=True))
        if N.ndim > 2:
            raise ModelError(f"normal_load must have shape (n_c,) or (n_batch, n_c), got "
                             f"{N.shape}")
        self.n_contacts = int(N.shape[-1])
        f = np.atleast_1d(check_positive("friction_coefficient", friction_coefficient,
                                         allow_zero=True))
        if f.ndim != 1 or f.size not in (1, self.n_contacts):
            raise ModelError(f"friction_coefficient must be a scalar or have {self.n_contacts} "
                             f"entries, got {friction_coefficient!r}")
        self.normal_load = N
        self.friction_coefficient = np.broadcast_to(f, (self.n_contacts,)).copy()
        self.torsion = torque_arm is not None
        if self.torsion:
            rho = np.atleast_1d(check_positive("torque_arm", torque_arm, unit="m",
                                               allow_zero=True))
            if rho.ndim != 1 or rho.size not in (1, self.n_contacts):
                raise ModelError(f"torque_arm must be a scalar or have {self.n_contacts} "
                                 f"entries [m], got {torque_arm!r}")
            self.torque_arm = np.broadcast_to(rho, (self.n_contacts,)).copy()
        self.exponent = float(check_positive("exponent", exponent))
        self.rule = rule
        self.min_amplitude = float(check_positive("min_amplitude", min_amplitude))
        if not 0 < min_ratio <= 1:
            raise ModelError(f"min_ratio must lie in (0, 1], got {min_ratio!r}")
        self.min_ratio = float(min_ratio)
        self.rows_per_contact = 3 if self.torsion else 2
        self.n_rows = self.rows_per_contact * self.n_contacts
        self.min_rotation = None
        if self.torsion:
            g = np.repeat(2 * np.arange(self.n_contacts), 3)
            g[2::3] += 1
            # the rotation floor is the slip floor at the torque arm
            self.min_rotation = self.min_amplitude / np.maximum(self.torque_arm, 1e-300)
            atol = np.column_stack([np.full(self.n_contacts, self.min_amplitude),
                                    self.min_rotation]).ravel()
        else:
            g = np.repeat(np.arange(self.n_contacts), 2)
            atol = np.full(self.n_contacts, self.min_amplitude)
        self.groups = g
        self.atol = atol

    def _split(self, s):
        s = np.asarray(s, dtype=complex)
        if s.shape[-1] != self.n_rows:
            raise ModelError(f"contact coordinates must have {self.n_rows} entries, got "
                             f"shape {s.shape}")
        r = s.reshape(s.shape[:-1] + (self.n_contacts, self.rows_per_contact))
        return r[..., 0], r[..., 1], (r[..., 2] if self.torsion else None)

    def _load(self, batch_index):
        N = self.normal_load
        if N.ndim == 2 and batch_index is not None:
            N = N[batch_index]
        return N

    def orbits(self, s) -> SlipEllipse:
        """Slip ellipses of the contacts, arrays of shape (..., n_c)."""
        xi, eta, _ = self._split(s)
        return slip_ellipse(xi, eta)

    def coefficients(self, s, omega, batch_index=None):
        """``(c_major, c_minor, inclination, c_torsion)`` per contact, each (..., n_c)."""
        xi, eta, rot = self._split(s)
        e = slip_ellipse(xi, eta)
        w = np.asarray(omega, float)[..., None]
        N = self._load(batch_index)
        fN = self.friction_coefficient * N
        ca, cb = _ellipse_damping(e.major, e.minor, fN, w, self.exponent, self.rule,
                                  self.min_amplitude, self.min_ratio)
        ct = None
        if self.torsion:
            vphi = np.maximum(np.abs(rot), self.min_rotation) * w
            ct = 4.0 * fN * self.torque_arm / (np.pi * vphi**self.exponent)   # 001 (32)
        return ca, cb, e.inclination, ct

    def matrix(self, s, omega, batch_index=None) -> np.ndarray:
        """Damping matrices in contact coordinates, shape (..., m, m) [N s/m, N m s/rad].

        Parameters
        ----------
        s : ndarray of complex, shape (..., m)
            Contact coordinates (complex amplitudes).
        omega : ndarray, shape (...)
            Excitation angular frequencies [rad/s].
        batch_index : ndarray of int, optional
            Rows of a per-batch ``normal_load`` that ``s`` corresponds to (the solver passes
            the indices of the points still iterating).
        """
        ca, cb, incl, ct = self.coefficients(s, omega, batch_index)
        blocks = orbit_damping_matrix(ca, cb, incl)                  # (..., n_c, 2, 2)
        lead = blocks.shape[:-3]
        k = self.rows_per_contact
        C = np.zeros(lead + (self.n_contacts, k, self.n_contacts, k))
        for c in range(self.n_contacts):
            C[..., c, 0:2, c, 0:2] = blocks[..., c, :, :]
            if self.torsion:
                C[..., c, 2, c, 2] = ct[..., c]
        return C.reshape(lead + (self.n_rows, self.n_rows))

    def dissipation(self, s, omega, batch_index=None) -> np.ndarray:
        """Energy dissipated per cycle by each contact, ``pi w s^H C(s) s`` [J], (..., n_c).

        For ``rule="coulomb"``, p = 1, this equals ``f N`` times the orbit perimeter plus
        ``4 M_0 phi`` (Coulomb's work).
        """
        C = self.matrix(s, omega, batch_index)
        s = np.asarray(s, complex)
        w = np.asarray(omega, float)
        Cs = np.einsum("...ij,...j->...i", C, s)
        per_row = np.real(np.conj(s) * Cs)
        per = per_row.reshape(per_row.shape[:-1] + (self.n_contacts, self.rows_per_contact))
        return np.pi * w[..., None] * per.sum(axis=-1)

    def stuck(self, s) -> np.ndarray:
        """True where a contact does not slip, shape (..., n_c): its major semi-axis is
        below twice the floor (the floor is also the convergence tolerance of such an
        orbit, so anything up to twice it is indistinguishable from no slip)."""
        return self.orbits(s).major <= 2.0 * self.min_amplitude


class JenkinsEllipseDamping(EllipseFrictionDamping):
    """Equivalent damping *and stiffness* of friction contacts with a stick spring.

    The contact is a Jenkins element: a tangential spring ``k_t`` [N/m] in series with the
    Coulomb slider of 001 (slip force ``F = f N``); the rotation about the normal a spring
    ``k_r = k_t (a_ef^2 + h_ef^2)/12`` [N m/rad] in series with the slider of torque
    ``M_0 = f N rho``. Its describing function for a harmonic relative displacement of
    amplitude a (the major semi-axis of the orbit; phi for the rotation) is the classic
    one-dimensional one (Griffin 1980):

    * stick, ``k a <= F``: stiffness ``k``, no damping -- a stuck contact is a spring, its
      dissipation exactly zero;
    * slip, ``beta = arccos(1 - 2 F/(k a))``: stiffness ``k (beta - sin(2 beta)/2)/pi``,
      dissipation ``4 F (a - F/k)`` per cycle.

    In slip the damping is the Coulomb rule of the parent class
    (:class:`EllipseFrictionDamping`) times ``1 - F/(k a)``, which is the Jenkins
    dissipation exactly for a straight orbit and tends to the Coulomb rule as ``k a / F``
    grows; the stiffness acts isotropically in the contact plane (the stick spring of a 2D
    Jenkins element is isotropic). As ``k_t -> inf`` this is the parent law.

    Parameters
    ----------
    tangential_stiffness : float
        k_t [N/m], > 0.
    rotational_stiffness : array_like, shape (n_c,)
        k_r [N m/rad], > 0 (:func:`rectangle_twist_stiffness` for a uniform rectangle).
    Other parameters as :class:`EllipseFrictionDamping`.
    """

    def __init__(self, normal_load, friction_coefficient, torque_arm, *,
                 tangential_stiffness: float, rotational_stiffness, **kwargs):
        super().__init__(normal_load, friction_coefficient, torque_arm, **kwargs)
        kt = float(check_positive("tangential_stiffness", tangential_stiffness, unit="N/m"))
        if kt <= 0:
            raise ModelError(f"tangential_stiffness must be > 0 N/m, got {kt!r}")
        kr = np.broadcast_to(np.asarray(rotational_stiffness, float), (self.n_contacts,))
        if np.any(~np.isfinite(kr)) or np.any(kr <= 0):
            raise ModelError(f"rotational_stiffness must be > 0 N m/rad, got "
                             f"{rotational_stiffness!r}")
        self.tangential_stiffness = kt
        self.rotational_stiffness = kr.copy()

    def _slip_forces(self, batch_index):
        fN = self.friction_coefficient * self._load(batch_index)
        return fN, fN * self.torque_arm

    @staticmethod
    def _jenkins(amplitude, k, F):
        """(stiffness, dissipation factor 1 - F/(k a), stuck) of the 1D describing function."""
        a = np.maximum(amplitude, 1e-300)
        r = F / (k * a)
        stuck = r >= 1.0
        beta = np.arccos(np.clip(1.0 - 2.0 * r, -1.0, 1.0))
        keq = np.where(stuck, k, k * (beta - 0.5 * np.sin(2.0 * beta)) / np.pi)
        return keq, np.where(stuck, 0.0, 1.0 - r), stuck

    def _split_amplitudes(self, s):
        xi, eta, rot = self._split(s)
        return self.orbits(s).major, np.abs(rot)

    def matrix(self, s, omega, batch_index=None) -> np.ndarray:
        C = super().matrix(s, omega, batch_index)
        a, phi = self._split_amplitudes(s)
        F, M0 = self._slip_forces(batch_index)
        _, gt, _ = self._jenkins(a, self.tangential_stiffness, F)
        _, gr, _ = self._jenkins(phi, self.rotational_stiffness, M0)
        g = np.stack([gt, gt, gr], axis=-1).reshape(gt.shape[:-1] + (self.n_rows,))
        return C * np.sqrt(g[..., :, None] * g[..., None, :])

    def stiffness(self, s, omega, batch_index=None) -> np.ndarray:
        """Equivalent stiffness in contact coordinates, shape (..., m, m) [N/m, N m/rad]."""
        a, phi = self._split_amplitudes(s)
        F, M0 = self._slip_forces(batch_index)
        kt, _, _ = self._jenkins(a, self.tangential_stiffness, F)
        kr, _, _ = self._jenkins(phi, self.rotational_stiffness, M0)
        d = np.stack([kt, kt, kr], axis=-1).reshape(kt.shape[:-1] + (self.n_rows,))
        return d[..., :, None] * np.eye(self.n_rows)

    def stuck(self, s, batch_index=None) -> np.ndarray:
        """True where the translation of a contact sticks (``k_t a <= f N``), (..., n_c)."""
        F, _ = self._slip_forces(batch_index)
        return self._jenkins(self.orbits(s).major, self.tangential_stiffness, F)[2]

    def rotation_stuck(self, s, batch_index=None) -> np.ndarray:
        """True where the rotation about the normal sticks (``k_r phi <= M_0``), (..., n_c)."""
        _, M0 = self._slip_forces(batch_index)
        return self._jenkins(np.abs(self._split(s)[2]), self.rotational_stiffness, M0)[2]
