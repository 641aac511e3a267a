"""Unilateral normal contacts of the event-driven solver: lift-off and impacts.

A contact that a :class:`~fricdamp.solvers.event_system.ConstrainedSystem` declares
unilateral (:meth:`~fricdamp.solvers.event_system.ConstrainedSystem.unilateral_contacts`) is
either *closed* (``g_N = 0``, ``lambda_N`` a Lagrange multiplier, friction as for a bilateral
contact) or *open* (mode ``OPEN``: no normal and no tangential force, the gap ``g_N(q) > 0``
is an event function). The solver switches between the two (Glocker & Pfeiffer, *Multibody
Dynamics with Unilateral Contacts*, 1996, ch. 6-7; Leine & Nijmeijer 2004, ch. 7):

* **lift-off**: a closed contact opens when its normal force would become tensile (the event
  ``lambda_N = 0`` of the closed phase); the position and velocity are continuous there;
* **impact**: an open contact whose gap reaches zero with ``gamma_N = W_N^T q' < 0`` closes
  through an impulse (this module). All contacts that are closed at that instant, and the
  impacting ones, take part in one impulsive problem

      M (q'+ - q'-) = W_A Lambda,   gamma_N+ = W_A^T q'+,
      xi = gamma_N+ + e gamma_N-  >= 0,   Lambda >= 0,   xi . Lambda = 0   (unilateral)
      gamma_N+ = 0                                                        (bilateral)

  (Newton's impact law with restitution ``e``, written as a linear complementarity problem
  in the normal impulses ``Lambda`` [N s] and solved by Lemke's method after eliminating the
  bilateral ones by their Schur complement). Impacts are **frictionless**: the impulse acts
  along the contact normals only; a contact that was stuck before the impact slips afterwards
  if the impulse gave it a slip velocity, and the friction decision after the impact is the
  ordinary one. With ``0 <= e <= 1`` the impulse never adds kinetic energy; the loss
  ``T- - T+`` is reported as the ``impact_loss`` energy term.

After the impact a contact with ``gamma_N+`` at round-off (``e = 0``, or a contact already
closed that the impulse held) is closed, one with ``gamma_N+ > 0`` is open (it bounces).
Impacts slower than the *Zeno velocity* are taken as plastic (``e = 0``): the contact closes,
and a closed contact that the impulse would set separating slower than it is held closed
(a bilateral row of the impulsive problem, whose impulse may then be slightly negative, of
order the effective mass times that velocity). The default Zeno velocity is that of a
bounce whose apex height stays below the gap tolerance. This ends an accumulation of ever
shorter bounces (a ball coming to rest after infinitely many impacts in finite time; a damper
wedged between two platforms, where a plastic impact on one throws it off the other) with an
error of order that velocity times the remaining flight times (see
:func:`~fricdamp.solvers.event.simulate_events`, ``zeno_velocity``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fricdamp.solvers.event_switch import lemke

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class Impact:
    """One impact of an event-driven run.

    Attributes
    ----------
    time : float
        Impact time [s].
    contacts : tuple of int
        Contacts whose gap closed at this instant.
    velocity_before, velocity_after : ndarray, shape (n_contacts,)
        Normal relative velocities ``gamma_N = W_N^T q'`` [m/s] before and after (negative:
        approaching).
    impulse : ndarray, shape (n_contacts,)
        Normal impulses ``Lambda`` [N s] (zero for contacts not involved).
    energy_loss : float
        Kinetic energy lost ``T- - T+`` [J] (>= 0).
    plastic : tuple of int
        Contacts taken as plastic (impacting slower than the Zeno velocity) or held closed
        (set separating slower than it).
    """

    time: float
    contacts: tuple
    velocity_before: np.ndarray
    velocity_after: np.ndarray
    impulse: np.ndarray
    energy_loss: float
    plastic: tuple = ()


def close_gaps(ev, q, contacts, iterations: int = 5):
    """``q`` moved (M-weighted Gauss-Newton) so that the gaps of ``contacts`` are zero: the
    impact state of a gap event located at a round-off penetration."""
    idx = np.flatnonzero(contacts)
    if idx.size == 0:
        return q
    s = ev.system
    for _ in range(iterations):
        g = np.asarray(s.normal_gap(q), float)[idx]
        if np.all(np.abs(g) <= 1e-15 * (1 + np.abs(q).max())):
            break
        WN = np.asarray(s.normal_jacobian(q), float)[:, idx]
        MiW = ev.mass_factor(q)(WN)
        q = q - MiW @ np.linalg.lstsq(WN.T @ MiW, g, rcond=1e-12)[0]
    return q


def impulse(ev, q, qd, unilateral, bilateral, restitution):
    """Velocity after an impact (see the module docstring).

    Parameters
    ----------
    ev : Evaluator
    q, qd : ndarray, shape (n_dof,)
        Position at the impact and velocity before it.
    unilateral, bilateral : ndarray of bool, shape (n_contacts,)
        Contacts in the impulsive problem: closed-or-impacting unilateral contacts
        (complementarity) and closed bilateral ones (``gamma_N+ = 0``).
    restitution : ndarray, shape (n_contacts,)
        Restitution coefficients to use (0 for plastic).

    Returns
    -------
    qd_plus : ndarray, shape (n_dof,)
    Lambda : ndarray, shape (n_contacts,)
        Normal impulses [N s].
    """
    nc = unilateral.size
    u, b = np.flatnonzero(unilateral), np.flatnonzero(bilateral)
    WN = np.asarray(ev.system.normal_jacobian(q), float)
    Msolve = ev.mass_factor(q)
    Lam = np.zeros(nc)
    gm = WN.T @ qd
    if u.size + b.size == 0:
        return qd.copy(), Lam
    Wu, Wb = WN[:, u], WN[:, b]
    MiWu, MiWb = Msolve(Wu), Msolve(Wb)
    Guu = Wu.T @ MiWu
    qv = (1.0 + restitution[u]) * gm[u]
    A = Guu
    if b.size:
        Gbb = Wb.T @ MiWb
        Gbu = Wb.T @ MiWu
        P = np.linalg.pinv(Gbb, rcond=1e-12)
        A = Guu - Gbu.T @ P @ Gbu
        qv = qv - Gbu.T @ P @ gm[b]
    Lu = lemke(0.5 * (A + A.T), qv) if u.size else np.zeros(0)
    Lam[u] = Lu
    if b.size:
        Lam[b] = -P @ (gm[b] + Gbu @ Lu)
    return qd + MiWu @ Lu + (MiWb @ Lam[b] if b.size else 0.0), Lam


__all__ = ["Impact", "close_gaps", "impulse"]
