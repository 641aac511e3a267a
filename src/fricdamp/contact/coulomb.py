"""Coulomb friction: the velocity-dependent coefficient of paper 003 and a 1D penalty law.

Three things live here:

* :func:`friction_coefficient` -- the velocity-dependent friction coefficient of paper
  003 eq. (2) (the ANSYS ``TB,FRIC`` exponential law)::

      mu(v) = mu_d * (1 + (FACT - 1) * exp(-DC * |v|)),   FACT = mu_s / mu_d

  evaluated as the algebraically identical ``mu_d + (mu_s - mu_d) exp(-DC |v|)`` so that
  ``mu_d = 0`` is allowed. The extracted text writes ``exp(-DC v_rel)`` without a modulus;
  ``v_rel`` is the *magnitude* of the sliding velocity (the curve of the paper's Fig. 10 is
  drawn for v_rel >= 0 and the friction force must be odd in v), so ``|v|`` is used.
* :func:`coulomb_force_set` -- the exact, set-valued Coulomb law (force ``mu N sign(v)``
  for ``v != 0``, any force in ``[-mu N, mu N]`` for ``v == 0``), for the event-driven
  solver, which handles exact stick itself.
* :class:`Coulomb` -- a 1D regularised Coulomb contact for time stepping and harmonic
  balance: a tangential penalty spring ``stiffness`` in series with a slider that breaks
  away at ``mu_s N`` and slides at ``mu(v) N``.

Sign convention (see :mod:`fricdamp.contact.base`): the force is the force the contact
resists the relative motion with, ``f = k_t (u - w)``, positive for a positive stretch.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from fricdamp.contact.base import ContactLaw, LawStep, broadcast_parameter, common_size
from fricdamp.errors import ModelError, as_finite_array, check_positive

__all__ = ["Coulomb", "ForceSet", "coulomb_force_set", "coulomb_march_kernel",
           "friction_coefficient"]


def friction_coefficient(v, mu_static, mu_sliding, decay):
    """Velocity-dependent friction coefficient, paper 003 eq. (2).

    ``mu(v) = mu_d (1 + (FACT - 1) exp(-DC |v|))`` with ``FACT = mu_s / mu_d``, evaluated as
    ``mu_d + (mu_s - mu_d) exp(-DC |v|)``. It equals ``mu_s`` at ``v = 0`` and tends to
    ``mu_d`` for ``|v| >> 1/DC``. ``decay = 0`` gives ``mu_s`` at every speed, exactly as
    the formula says (the :class:`Coulomb` law reads ``decay = 0`` differently, see there).

    Parameters
    ----------
    v : float or array_like
        Relative sliding velocity [m/s] (its magnitude is used).
    mu_static : float or array_like
        Static coefficient mu_s [-], >= 0.
    mu_sliding : float or array_like
        Dynamic (sliding) coefficient mu_d [-], >= 0.
    decay : float or array_like
        Decay coefficient DC [s/m], >= 0.

    Returns
    -------
    mu : ndarray
        Friction coefficient [-], the broadcast shape of the inputs.

    Raises
    ------
    ModelError
        If a coefficient or the decay is negative or not finite, or ``v`` is not finite.

    References
    ----------
    Paper 003 eq. (2): mu_s = 0.4, mu_d = 0.2, DC = 4 s/m for the tie-boss wheel.

    Examples
    --------
    >>> float(friction_coefficient(0.0, 0.4, 0.2, 4.0))
    0.4
    >>> round(float(friction_coefficient(0.25, 0.4, 0.2, 4.0)), 6)  # 0.2 (1 + 1/e)
    0.273576
    """
    v = as_finite_array("v", v)
    mus = check_positive("mu_static", mu_static, allow_zero=True)
    mud = check_positive("mu_sliding", mu_sliding, allow_zero=True)
    dc = check_positive("decay", decay, unit="s/m", allow_zero=True)
    return mud + (mus - mud) * np.exp(-dc * np.abs(v))


class ForceSet(NamedTuple):
    """Admissible friction forces ``lower <= f <= upper`` [N] (equal when sliding)."""

    lower: np.ndarray
    upper: np.ndarray


def coulomb_force_set(v, normal_load, mu) -> ForceSet:
    """The exact set-valued Coulomb law ``f in mu N Sign(v)``.

    For ``v != 0`` the friction force is ``mu N sign(v)`` (``lower == upper``); for
    ``v == 0`` (stick) any force in ``[-mu N, mu N]`` is admissible, the actual one being
    whatever the constraint ``v = 0`` needs. The force is the one the contact resists the
    motion with (it does negative work on the moving body: ``f v >= 0`` is dissipated).

    For static/kinetic friction pass ``mu = friction_coefficient(v, mu_s, mu_d, DC)``: it
    equals ``mu_s`` at ``v == 0``, so the stick interval is the static one.

    Parameters
    ----------
    v : float or array_like
        Relative sliding velocity [m/s].
    normal_load : float or array_like
        Normal load N [N], >= 0.
    mu : float or array_like
        Friction coefficient [-], >= 0 (broadcast with ``v``).

    Returns
    -------
    ForceSet
        ``lower`` and ``upper`` [N], arrays of the broadcast shape of the inputs.

    Raises
    ------
    ModelError
        If ``normal_load`` or ``mu`` is negative, or any input is not finite.

    Examples
    --------
    >>> fs = coulomb_force_set([-0.1, 0.0, 0.2], 10.0, 0.3)
    >>> fs.lower.tolist(), fs.upper.tolist()
    ([-3.0, -3.0, 3.0], [-3.0, 3.0, 3.0])
    """
    v = as_finite_array("v", v)
    n = check_positive("normal_load", normal_load, unit="N", allow_zero=True)
    mu = check_positive("mu", mu, allow_zero=True)
    fmax = mu * n
    s = np.sign(v)
    lower = np.where(v == 0.0, -fmax, s * fmax)
    upper = np.where(v == 0.0, fmax, s * fmax)
    lower, upper = np.broadcast_arrays(lower, upper)
    return ForceSet(np.array(lower, dtype=float), np.array(upper, dtype=float))


@njit(cache=True, nogil=True)
def coulomb_march_kernel(u, v, kt, nl, mus, mud, dc, w0, s0, f_out):  # pragma: no cover
    """March 1D Coulomb contacts along (u, v), both (n_t, n_c); write forces to f_out.

    kt, nl, mus, mud, dc: (n_c,) stiffness, normal load, static and sliding coefficients,
    decay (0: constant mu_d while sliding); w0, s0: (n_c,) initial slider positions and slip
    flags (0.0 stuck, 1.0 slipping). Returns the final (w, s). Same branches and operations
    as :meth:`Coulomb.step`.
    """
    nt, nc = u.shape
    w = w0.copy()
    s = s0.copy()
    for i in range(nt):
        for j in range(nc):
            ft = kt[j] * (u[i, j] - w[j])
            if dc[j] > 0.0:
                mu_v = mud[j] + (mus[j] - mud[j]) * np.exp(-dc[j] * abs(v[i, j]))
            else:
                mu_v = mud[j]
            if s[j] == 0.0:
                lim = mus[j] * nl[j]
            else:
                lim = mu_v * nl[j]
            if abs(ft) <= lim:
                f_out[i, j] = ft
                s[j] = 0.0
            else:
                fs = mu_v * nl[j]
                f = fs if ft > 0.0 else -fs
                w[j] = u[i, j] - f / kt[j]
                s[j] = 1.0
                f_out[i, j] = f
    return w, s


class Coulomb(ContactLaw):
    """1D Coulomb friction with a tangential penalty spring, static/kinetic and mu(v).

    The contact is a spring ``stiffness`` k_t in series with a slider at position ``w``
    pressed by a constant ``normal_load`` N. State per contact: ``(w, slipping)``.

    Return map from ``(w, s)`` to ``(u, v)``, with trial force ``f* = k_t (u - w)``:

    * stuck (``s = 0``): if ``|f*| <= mu_s N`` the contact stays stuck, ``f = f*``;
      otherwise it breaks away: ``f = mu(v) N sign(f*)``, ``w = u - f / k_t``, ``s = 1``
      (the force drops from ``mu_s N`` to the kinetic level: the static peak).
    * slipping (``s = 1``): the kinetic cone is ``|f| <= mu(v) N``. If ``|f*| > mu(v) N``
      sliding goes on at ``f = mu(v) N sign(f*)``; otherwise (unloading, or a cone that
      grew as the slip slowed down) the contact re-sticks with ``f = f*``, ``s = 0``, and
      must then reach ``mu_s N`` again to break away.

    ``mu(v)`` is :func:`friction_coefficient` (paper 003 eq. (2)) with ``decay > 0``; with
    ``decay = 0`` (the default) the sliding coefficient is the constant ``mu_sliding``
    (the ``DC -> inf`` limit of eq. (2) for ``v != 0``: the classic static/kinetic law;
    eq. (2) taken literally with DC = 0 would give ``mu_s`` throughout, which is obtained
    here with ``mu_sliding = mu_static``). The velocity ``v`` is the contact's relative
    velocity, used as the sliding velocity (they differ by ``d f / dt / k_t``, small for a
    stiff penalty).

    Consistent tangent: stick ``dF/du = k_t``, ``dF/dv = 0``; slip ``dF/du = 0``,
    ``dF/dv = sign(f*) N dmu/dv = -sign(f*) sign(v) N (mu_s - mu_d) DC exp(-DC |v|)``
    (negative in steady sliding: velocity weakening; 0 at ``v = 0``, where mu(v) has a
    kink).

    Parameters
    ----------
    stiffness : float or array_like, shape (n_contacts,)
        Tangential stick (penalty) stiffness k_t [N/m], > 0.
    normal_load : float or array_like, shape (n_contacts,)
        Normal load N [N], >= 0.
    mu_static : float or array_like, shape (n_contacts,)
        Static friction coefficient mu_s [-], >= 0.
    mu_sliding : float or array_like, shape (n_contacts,), optional
        Sliding (dynamic) coefficient mu_d [-], 0 <= mu_d <= mu_s; default ``mu_static``.
    decay : float or array_like, shape (n_contacts,), optional
        Decay coefficient DC [s/m] of eq. (2), >= 0; default 0 (constant ``mu_sliding``).
    n_contacts : int, optional
        Number of contacts when all parameters are scalars (default 1).

    Raises
    ------
    ModelError
        Naming the parameter for a negative/non-finite value, ``mu_sliding > mu_static``
        (velocity strengthening is not supported: the break-away would raise the force
        above the trial force) or inconsistent per-contact lengths.

    Examples
    --------
    >>> import numpy as np
    >>> law = Coulomb(stiffness=1000.0, normal_load=10.0, mu_static=0.2, mu_sliding=0.1)
    >>> law.drive(np.array([0.0, 0.001, 0.002, 0.0025, 0.002])).round(6).tolist()
    [0.0, 1.0, 2.0, 1.0, 0.5]
    """

    n_dir = 1
    n_state = 2

    def __init__(self, stiffness, normal_load, mu_static, mu_sliding=None, decay=0.0, *,
                 n_contacts: int | None = None):
        kt = broadcast_parameter("stiffness", stiffness, n_contacts, unit="N/m")
        nl = broadcast_parameter("normal_load", normal_load, n_contacts, unit="N",
                                 allow_zero=True)
        mus = broadcast_parameter("mu_static", mu_static, n_contacts, unit="", allow_zero=True)
        mud = mus if mu_sliding is None else broadcast_parameter(
            "mu_sliding", mu_sliding, n_contacts, unit="", allow_zero=True)
        dc = broadcast_parameter("decay", decay, n_contacts, unit="s/m", allow_zero=True)
        n = (common_size(stiffness=kt, normal_load=nl, mu_static=mus, mu_sliding=mud, decay=dc)
             if n_contacts is None else int(n_contacts))
        if n < 1:
            raise ModelError(f"n_contacts must be >= 1, got {n_contacts!r}")
        self.n_contacts = n
        self.stiffness = np.broadcast_to(kt, (n,)).copy()
        self.normal_load = np.broadcast_to(nl, (n,)).copy()
        self.mu_static = np.broadcast_to(mus, (n,)).copy()
        self.mu_sliding = np.broadcast_to(mud, (n,)).copy()
        self.decay = np.broadcast_to(dc, (n,)).copy()
        if np.any(self.mu_sliding > self.mu_static):
            raise ModelError(
                f"mu_sliding must be <= mu_static (0 <= mu_d <= mu_s), got mu_sliding="
                f"{mu_sliding!r}, mu_static={mu_static!r}"
            )
        #: True when any contact has a velocity-dependent sliding coefficient (decay > 0).
        self.velocity_dependent = bool(np.any(self.decay > 0.0))

    def __repr__(self) -> str:
        return (f"Coulomb(n_contacts={self.n_contacts}, stiffness={self.stiffness.tolist()}, "
                f"normal_load={self.normal_load.tolist()}, mu_static={self.mu_static.tolist()}, "
                f"mu_sliding={self.mu_sliding.tolist()}, decay={self.decay.tolist()})")

    def initial_state(self) -> np.ndarray:
        """Virgin state: slider at 0, stuck; shape (n_contacts, 2) = (w [m], slipping)."""
        return np.zeros((self.n_contacts, 2))

    def sliding_coefficient(self, v) -> np.ndarray:
        """Coefficient used while sliding at velocity ``v`` [m/s], shape (n_contacts,)."""
        v = np.asarray(v, dtype=float).reshape(self.n_contacts)
        mud, dc = self.mu_sliding, self.decay
        return np.where(dc > 0.0, mud + (self.mu_static - mud) * np.exp(-dc * np.abs(v)), mud)

    def _velocity(self, v, n_t: int | None = None) -> np.ndarray:
        shape = (self.n_contacts,) if n_t is None else (n_t, self.n_contacts)
        if v is None:
            if self.velocity_dependent:
                raise ModelError(
                    "v (relative velocity [m/s]) is required: this Coulomb law has decay > 0, "
                    "so its sliding force depends on the velocity")
            return np.zeros(shape)
        v = as_finite_array("v", v)
        if v.size != int(np.prod(shape)):
            raise ModelError(f"v must have {shape + (1,)} entries for this law, got {v.shape}")
        return v.reshape(shape)

    def step(self, state, u, v=None) -> LawStep:
        """One return-map step (see the class docstring); shapes as in the protocol."""
        u = self._check_u(u)[:, 0]
        vv = self._velocity(v)
        st = np.asarray(state, dtype=float)
        w, s = st[:, 0], st[:, 1]
        kt, nl = self.stiffness, self.normal_load
        ft = kt * (u - w)
        mu_v = self.sliding_coefficient(vv)
        lim = np.where(s == 0.0, self.mu_static * nl, mu_v * nl)
        slip = np.abs(ft) > lim
        sgn = np.where(ft > 0.0, 1.0, -1.0)
        f = np.where(slip, sgn * mu_v * nl, ft)
        w_new = np.where(slip, u - f / kt, w)
        s_new = slip.astype(float)
        k = np.where(slip, 0.0, kt)
        dmu = -(self.mu_static - self.mu_sliding) * self.decay * np.exp(
            -self.decay * np.abs(vv)) * np.sign(vv)
        c = np.where(slip, sgn * nl * dmu, 0.0)
        damping = c[:, None, None] if self.velocity_dependent else None
        return LawStep(f[:, None], k[:, None, None], damping, np.stack([w_new, s_new], axis=1))

    def stored_energy(self, state, u) -> np.ndarray:
        """Spring energy ``k_t (u - w)^2 / 2`` [J], shape (n_contacts,)."""
        u = self._check_u(u)[:, 0]
        w = np.asarray(state, dtype=float)[:, 0]
        return 0.5 * self.stiffness * (u - w) ** 2

    def dissipation(self, state_old, state_new, force_new) -> np.ndarray:
        """Friction work ``f (w_new - w_old)`` [J]: the slider moves only while the force is on
        the friction limit, so this is the energy the step dissipates."""
        dw = np.asarray(state_new, float)[:, 0] - np.asarray(state_old, float)[:, 0]
        return np.asarray(force_new, float).reshape(self.n_contacts) * dw

    def march(self, u_history, state=None, v_history=None):
        """Compiled march (see :meth:`ContactLaw.march`); ``v_history`` needed if decay > 0."""
        u3 = np.asarray(u_history, dtype=float)
        if u3.ndim != 3 or u3.shape[1:] != (self.n_contacts, 1):
            raise ModelError(f"u_history must have shape (n_t, {self.n_contacts}, 1), got "
                             f"{u3.shape}")
        nt = u3.shape[0]
        u = np.ascontiguousarray(u3[:, :, 0])
        v = np.ascontiguousarray(self._velocity(v_history, nt) if v_history is not None
                                 or self.velocity_dependent else np.zeros_like(u))
        st = self.initial_state() if state is None else np.asarray(state, dtype=float)
        f = np.empty_like(u)
        w, s = coulomb_march_kernel(u, v, self.stiffness, self.normal_load, self.mu_static,
                                    self.mu_sliding, self.decay,
                                    np.ascontiguousarray(st[:, 0]),
                                    np.ascontiguousarray(st[:, 1]), f)
        return f[:, :, None], np.stack([w, s], axis=1)
