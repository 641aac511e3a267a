"""Rotating-frame inertia operators of a rigid slice or body (used by :mod:`beam3d`).

A body spins at constant speed Omega about a fixed axis (unit vector ``e`` through the point
``o``). Its motion is described in the frame rotating with it: a material point sits at
``r0 + u`` (``r0`` measured from ``o``) and the body's orientation is perturbed by a small
rotation vector ``theta``. The kinetic energy in the inertial frame is

    T = 1/2 m |u' + Omega e x (r0 + u)|^2 + 1/2 (Omega e + w)^T R J R^T (Omega e + w)

with ``R = exp(S(theta))``, ``w = theta' + theta x theta' / 2 + O(theta^2)`` the angular
velocity of the body relative to the rotating frame, ``J`` the inertia tensor [kg m^2] about
the centre of mass in the reference orientation and ``S(a) b = a x b``. Expanding T to second
order in (u, theta) and applying Lagrange's equations gives the linear terms of 001 (2) and
(5) (the paper lists them without derivation; this module derives them)::

    M q'' + Omega G q' + (K - Omega^2 K_d) q = Omega^2 f_c + ...

    translations (mass m):   G = 2 m S(e)         K_d = m (I - e e^T)     f_c = m (I - e e^T) r0
    rotations (inertia J):   G = S(e) J + J S(e) - S(J e)
                             K_d = sym(S(e) S(J e) - S(e) J S(e))          f_c = (J e) x e

G is the Coriolis (gyroscopic) matrix per unit Omega (skew-symmetric), K_d the spin-softening
matrix per unit Omega^2 (symmetric; for rotations it can stiffen, e.g. the "propeller moment"
that turns a flat blade section back into the plane of rotation), and f_c the centrifugal
force and moment per unit Omega^2. Checks: a rotor spinning about its own axis (J = diag(Ip,
Id, Id)) gets ``Id theta'' + Omega (Ip - 2 Id) S theta' + Omega^2 (Ip - Id) theta = 0``, whose
frequencies are the inertial ones (0 and Omega Ip / Id) shifted by Omega; the test suite also
compares every term with the numerical linearisation of the exact kinetic energy above.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fricdamp.errors import ModelError, as_finite_array, check_positive

__all__ = ["RigidBodyTerms", "rigid_body_terms", "rotary_operators", "skew", "spin_axis_unit",
           "translational_operators"]


def skew(a: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``S(a)`` with ``S(a) b = a x b``; a (..., 3) -> (..., 3, 3)."""
    a = np.asarray(a, dtype=float)
    S = np.zeros(a.shape + (3,))
    S[..., 0, 1], S[..., 0, 2] = -a[..., 2], a[..., 1]
    S[..., 1, 0], S[..., 1, 2] = a[..., 2], -a[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -a[..., 1], a[..., 0]
    return S


def spin_axis_unit(spin_axis) -> np.ndarray:
    """Validate a spin axis direction and return it as a unit vector, shape (3,)."""
    e = as_finite_array("spin_axis", spin_axis)
    if e.shape != (3,):
        raise ModelError(f"spin_axis must be a 3-vector, got shape {e.shape}")
    n = float(np.linalg.norm(e))
    if n == 0.0:
        raise ModelError("spin_axis must be a non-zero 3-vector (direction of the spin axis)")
    return e / n


def translational_operators(e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per unit mass: gyroscopic ``2 S(e)`` and spin-softening ``I - e e^T``.

    Parameters
    ----------
    e : ndarray, shape (..., 3)
        Unit spin axis, in whatever frame the displacements are expressed.

    Returns
    -------
    G, Kd : ndarray, shape (..., 3, 3)
        Multiply by the mass [kg] (or mass per length [kg/m]).
    """
    e = np.asarray(e, dtype=float)
    P = np.eye(3) - e[..., :, None] * e[..., None, :]
    return 2.0 * skew(e), P


def rotary_operators(e: np.ndarray, J: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gyroscopic, spin-softening and centrifugal-moment terms of a rotary inertia J.

    Parameters
    ----------
    e : ndarray, shape (..., 3)
        Unit spin axis, in the frame of ``J``.
    J : ndarray, shape (..., 3, 3)
        Inertia tensor about the centre of mass [kg m^2] (or per length [kg m]), symmetric.

    Returns
    -------
    G : ndarray, shape (..., 3, 3)
        ``S(e) J + J S(e) - S(J e)``, skew-symmetric, per unit Omega.
    Kd : ndarray, shape (..., 3, 3)
        ``sym(S(e) S(J e) - S(e) J S(e))``, symmetric, per unit Omega^2 (enters as
        ``-Omega^2 Kd``).
    moment : ndarray, shape (..., 3)
        Centrifugal moment ``(J e) x e`` per unit Omega^2 (zero when e is a principal axis).
    """
    e = np.asarray(e, dtype=float)
    J = np.asarray(J, dtype=float)
    Se = skew(e)
    Je = np.einsum("...ij,...j->...i", J, e)
    SJe = skew(Je)
    G = Se @ J + J @ Se - SJe
    A = Se @ SJe - Se @ J @ Se
    Kd = 0.5 * (A + np.swapaxes(A, -1, -2))
    return G, Kd, np.cross(Je, e)


@dataclass(frozen=True)
class RigidBodyTerms:
    """Rotating-frame matrices of a rigid body with DOFs (u, v, w, phi, theta, psi).

    Attributes
    ----------
    M : ndarray, shape (6, 6)
        Mass matrix [kg, kg m^2].
    G : ndarray, shape (6, 6)
        Gyroscopic matrix per unit spin speed (skew-symmetric) [kg, kg m^2].
    Kd : ndarray, shape (6, 6)
        Spin-softening matrix per unit Omega^2 [kg, kg m^2].
    fc : ndarray, shape (6,)
        Centrifugal force [kg m] and moment [kg m^2] per unit Omega^2.
    """

    M: np.ndarray
    G: np.ndarray
    Kd: np.ndarray
    fc: np.ndarray


def inertia_tensor(name: str, inertia) -> np.ndarray:
    """Validate an inertia given as a scalar, 3 principal values or a 3x3 tensor [kg m^2]."""
    J = as_finite_array(name, inertia)
    if J.ndim == 0:
        J = float(J) * np.eye(3)
    elif J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3):
        raise ModelError(f"{name} must be a scalar, 3 principal values or a 3x3 tensor "
                         f"[kg m^2], got shape {J.shape}")
    if np.abs(J - J.T).max() > 1e-12 * max(np.abs(J).max(), 1e-300):
        raise ModelError(f"{name} must be a symmetric 3x3 tensor")
    lam = np.linalg.eigvalsh(J)
    if lam[0] < -1e-12 * max(lam[-1], 0.0):
        raise ModelError(f"{name} must be positive semi-definite, smallest principal value "
                         f"{lam[0]:.3g} kg m^2")
    return J


def rigid_body_terms(mass_kg: float, inertia_kg_m2, position_m, *, spin_axis,
                     spin_origin=(0.0, 0.0, 0.0)) -> RigidBodyTerms:
    """Mass, gyroscopic, spin-softening and centrifugal terms of a rigid body, 001 (5).

    DOFs are the displacement of the centre of mass and the small rotation vector, both in
    the axes of the rotating frame: ``(u, v, w, phi, theta, psi)``.

    Parameters
    ----------
    mass_kg : float
        Mass m [kg], > 0.
    inertia_kg_m2 : float, (3,) or (3, 3)
        Inertia tensor about the centre of mass in the rotating axes [kg m^2] (a scalar is
        isotropic, 3 values are principal moments along the axes); positive semi-definite.
    position_m : (3,)
        Centre of mass [m] in the rotating frame.
    spin_axis : (3,)
        Direction of the spin axis (normalised here).
    spin_origin : (3,)
        A point on the spin axis [m].

    Returns
    -------
    RigidBodyTerms
        ``M q'' + Omega G q' - Omega^2 Kd q = Omega^2 fc`` (plus any elastic coupling).

    Examples
    --------
    >>> t = rigid_body_terms(2.0, 0.0, [0.5, 0.0, 0.0], spin_axis=[0, 0, 1])
    >>> t.fc[:3].tolist()   # m r per unit Omega^2, radially outward
    [1.0, 0.0, 0.0]
    """
    m = float(check_positive("mass_kg", mass_kg, unit="kg"))
    J = inertia_tensor("inertia_kg_m2", inertia_kg_m2)
    r = as_finite_array("position_m", position_m)
    o = as_finite_array("spin_origin", spin_origin)
    if r.shape != (3,) or o.shape != (3,):
        raise ModelError("position_m and spin_origin must be 3-vectors [m]")
    e = spin_axis_unit(spin_axis)
    Gt, Pt = translational_operators(e)
    Gr, Kr, mom = rotary_operators(e, J)
    M = np.zeros((6, 6))
    G = np.zeros((6, 6))
    Kd = np.zeros((6, 6))
    M[:3, :3], M[3:, 3:] = m * np.eye(3), J
    G[:3, :3], G[3:, 3:] = m * Gt, Gr
    Kd[:3, :3], Kd[3:, 3:] = m * Pt, Kr
    fc = np.concatenate([m * Pt @ (r - o), mom])
    return RigidBodyTerms(M=M, G=G, Kd=Kd, fc=fc)
