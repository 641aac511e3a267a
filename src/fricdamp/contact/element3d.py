"""The "3D contact element": unilateral normal penalty + 2D tangential Jenkins friction.

Each contact has three local relative displacements: ``u[:, 0]`` the normal approach
``u_n`` (> 0 closes the gap) and ``u[:, 1:3]`` the tangential displacement ``u_t``. The
normal force is a unilateral penalty with an offset ``g0``::

    N = k_n max(u_n + g0, 0)

(``g0 > 0``: interference, prestress ``N0 = k_n g0`` at ``u_n = 0``, the contact-surface
offset of paper 003 -- 1e-5 m giving 2.4 N; ``g0 < 0``: an initial gap). The tangential
force is a 2D Jenkins element (isotropic Coulomb friction with a penalty spring ``k_t``)
with slider position ``w`` (2-vector, the state), solved by the radial return:

    f* = k_t (u_t - w)
    |f*| <= mu N  ->  stick:  f_t = f*
    |f*| >  mu N  ->  slip:   f_t = mu N f*/|f*|,   w = u_t - f_t / k_t
    N == 0        ->  separated: f_t = 0, w = u_t (the spring is unloaded on re-contact)

Consistent tangent dF/du (3x3, rows force ``(N, f_t1, f_t2)``, columns ``(u_n, u_t1, u_t2)``):

* separated: 0;
* stick: ``diag(k_n, k_t, k_t)``;
* slip, ``d = f*/|f*|``: ``dN/du_n = k_n``; ``df_t/du_t = (mu N / |f*|) k_t (I - d d^T)``
  (the slider only turns, it does not give force along d); ``df_t/du_n = mu k_n d``.

Accuracy: the radial return is exact when the slip direction is fixed (it is the 1D
Jenkins map then) but only first order in the *change* of slip direction (it is the
backward-Euler step of the flow rule): on a circular orbit sampled n times per cycle the
slider circle (radius ``rho = sqrt(R^2 - delta^2)``, ``delta = mu N / k_t``) is too small
by ``delta sin(pi / n)``, so the dissipated energy is low by about ``pi delta / (n rho)``.
Sample 2D orbits finely (AFT: many time samples) when ``delta`` is not small compared
with the orbit.

Static/kinetic friction with the velocity-dependent coefficient of paper 003 eq. (2)
(``mu_sliding`` given and different from ``mu``): the state gains a slip flag ``s``
(0 stuck, 1 slipping) and the cone depends on it, as in :class:`fricdamp.contact.coulomb.Coulomb`::

    stuck (s = 0):     |f*| <= mu_s N        -> stick;  else break away: f_t = mu(v) N d, s = 1
    slipping (s = 1):  |f*| >  mu(v) N       -> slip on: f_t = mu(v) N d;  else re-stick, s = 0
    mu(v) = mu_d + (mu_s - mu_d) exp(-DC |v_t|)          (003 (2), FACT = mu_s / mu_d)

with ``v_t`` the relative tangential velocity (the sliding velocity up to ``d f_t/dt / k_t``,
small for a stiff penalty) and ``mu_s = mu``. ``decay = 0`` means a constant sliding
coefficient ``mu_d`` (the ``DC -> inf`` limit; eq. (2) read literally with DC = 0 would give
``mu_s`` throughout, which is ``mu_sliding = mu``). In slip the tangent gains
``df_t/du_n = mu(v) k_n d`` and the velocity tangent ``df_t/dv_t = N d (dmu/d|v|) e_v^T``
(``e_v = v_t / |v_t|``, ``dmu/d|v| = -(mu_s - mu_d) DC exp(-DC |v_t|)``). A separated contact
re-closes stuck. With ``mu_sliding`` omitted (or equal to ``mu``) the law, its state
``(w1, w2)`` and its compiled kernel are the constant-mu ones above.

Energy: the normal penalty is conservative (potential ``k_n max(u_n + g0, 0)^2 / 2``); all
dissipation happens in the slider, ``f_t . dw = mu N |dw|`` per step (the return moves w
along the force), so a closed path dissipates ``mu N`` times the slider path length
(tests/validation/test_element3d_energy.py).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from fricdamp.contact.base import ContactLaw, LawStep, broadcast_parameter, common_size
from fricdamp.errors import ModelError, as_finite_array

__all__ = ["Contact3D", "contact3d_kinetic_march_kernel", "contact3d_march_kernel"]


@njit(cache=True, nogil=True)
def contact3d_march_kernel(u, kn, kt, mu, g0, w0, f_out):  # pragma: no cover - compiled
    """March 3D contact elements along u (n_t, n_c, 3); write forces to f_out, return w.

    kn, kt, mu, g0: (n_c,) normal and tangential stiffness, friction coefficient, offset;
    w0: (n_c, 2) initial slider positions. Same branches and operations as
    :meth:`Contact3D.step`.
    """
    nt, nc, _ = u.shape
    w = w0.copy()
    for i in range(nt):
        for j in range(nc):
            gap = u[i, j, 0] + g0[j]
            if gap <= 0.0:
                w[j, 0] = u[i, j, 1]
                w[j, 1] = u[i, j, 2]
                f_out[i, j, 0] = 0.0
                f_out[i, j, 1] = 0.0
                f_out[i, j, 2] = 0.0
                continue
            nf = kn[j] * gap
            f1 = kt[j] * (u[i, j, 1] - w[j, 0])
            f2 = kt[j] * (u[i, j, 2] - w[j, 1])
            nrm = np.sqrt(f1 * f1 + f2 * f2)
            lim = mu[j] * nf
            if nrm > lim:
                scale = lim / nrm
                f1 = f1 * scale
                f2 = f2 * scale
                w[j, 0] = u[i, j, 1] - f1 / kt[j]
                w[j, 1] = u[i, j, 2] - f2 / kt[j]
            f_out[i, j, 0] = nf
            f_out[i, j, 1] = f1
            f_out[i, j, 2] = f2
    return w


@njit(cache=True, nogil=True)
def contact3d_kinetic_march_kernel(u, v, kn, kt, mus, mud, dc, g0, w0, s0,
                                   f_out):  # pragma: no cover - compiled
    """March static/kinetic 3D contacts along u, v (n_t, n_c, 3); write forces to f_out.

    kn, kt, mus, mud, dc, g0: (n_c,) stiffnesses, static and sliding coefficients, decay
    DC [s/m] (0: constant mu_d while sliding) and offset; w0 (n_c, 2) sliders, s0 (n_c,)
    slip flags. Returns the final (w, s). Same branches and operations as
    :meth:`Contact3D.step`.
    """
    nt, nc, _ = u.shape
    w = w0.copy()
    s = s0.copy()
    for i in range(nt):
        for j in range(nc):
            gap = u[i, j, 0] + g0[j]
            if gap <= 0.0:
                w[j, 0] = u[i, j, 1]
                w[j, 1] = u[i, j, 2]
                s[j] = 0.0
                f_out[i, j, 0] = 0.0
                f_out[i, j, 1] = 0.0
                f_out[i, j, 2] = 0.0
                continue
            nf = kn[j] * gap
            f1 = kt[j] * (u[i, j, 1] - w[j, 0])
            f2 = kt[j] * (u[i, j, 2] - w[j, 1])
            nrm = np.sqrt(f1 * f1 + f2 * f2)
            if dc[j] > 0.0:
                vt = np.sqrt(v[i, j, 1] * v[i, j, 1] + v[i, j, 2] * v[i, j, 2])
                mu_v = mud[j] + (mus[j] - mud[j]) * np.exp(-dc[j] * vt)
            else:
                mu_v = mud[j]
            lim = (mus[j] if s[j] == 0.0 else mu_v) * nf
            if nrm > lim:
                scale = mu_v * nf / nrm
                f1 = f1 * scale
                f2 = f2 * scale
                w[j, 0] = u[i, j, 1] - f1 / kt[j]
                w[j, 1] = u[i, j, 2] - f2 / kt[j]
                s[j] = 1.0
            else:
                s[j] = 0.0
            f_out[i, j, 0] = nf
            f_out[i, j, 1] = f1
            f_out[i, j, 2] = f2
    return w, s


class Contact3D(ContactLaw):
    """Unilateral normal penalty with offset and isotropic 2D Jenkins friction.

    See the module docstring for the return map and its consistent tangent.

    Parameters
    ----------
    normal_stiffness : float or array_like, shape (n_contacts,)
        Normal penalty stiffness k_n [N/m], > 0.
    tangential_stiffness : float or array_like, shape (n_contacts,)
        Tangential stick stiffness k_t [N/m], > 0.
    mu : float or array_like, shape (n_contacts,)
        Friction coefficient [-], >= 0; the static coefficient mu_s when ``mu_sliding`` is
        given.
    offset : float or array_like, shape (n_contacts,), optional
        Normal offset g0 [m]: > 0 interference (prestress ``k_n g0``), < 0 gap. Default 0.
    mu_sliding : float or array_like, shape (n_contacts,), optional
        Sliding (dynamic) coefficient mu_d [-], ``0 <= mu_d <= mu``. Omitted (default) or
        equal to ``mu``: constant-mu law with state ``(w1, w2)``. Otherwise the static/kinetic
        law of paper 003 with state ``(w1, w2, slipping)`` (module docstring).
    decay : float or array_like, shape (n_contacts,), optional
        Decay coefficient DC [s/m] of 003 (2), >= 0; 0 (default) gives a constant ``mu_d``
        while sliding. Only used with ``mu_sliding``.
    n_contacts : int, optional
        Number of contacts when all parameters are scalars (default 1).

    Raises
    ------
    ModelError
        Naming the parameter for a non-positive stiffness, a negative mu, a non-finite
        value, ``mu_sliding > mu`` or inconsistent per-contact lengths.

    Examples
    --------
    >>> import numpy as np
    >>> law = Contact3D.from_preload(1e5, 2.0, tangential_stiffness=1e4, mu=0.5)
    >>> u = np.array([[0.0, 0.0, 0.0], [0.0, 5e-5, 0.0], [0.0, 2e-4, 0.0], [-3e-5, 0.0, 0.0]])
    >>> law.drive(u).round(6).tolist()
    [[2.0, 0.0, 0.0], [2.0, 0.5, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.0]]

    Paper 003 friction (mu_s = 0.4, mu_d = 0.2, DC = 4 s/m): break-away at 0.4 N, then the
    kinetic level at the sliding speed (here 0.25 m/s: 0.2 (1 + 1/e) N = 0.2736 N):

    >>> law = Contact3D.from_preload(1e5, 1.0, 1e4, 0.4, mu_sliding=0.2, decay=4.0)
    >>> u = np.array([[0.0, 3e-5, 0.0], [0.0, 1e-4, 0.0]])
    >>> law.drive(u, v_history=np.full((2, 3), [0.0, 0.25, 0.0])).round(4).tolist()
    [[1.0, 0.3, 0.0], [1.0, 0.2736, 0.0]]
    """

    n_dir = 3
    n_state = 2

    def __init__(self, normal_stiffness, tangential_stiffness, mu, offset=0.0, *,
                 mu_sliding=None, decay=0.0, n_contacts: int | None = None):
        kn = broadcast_parameter("normal_stiffness", normal_stiffness, n_contacts, unit="N/m")
        kt = broadcast_parameter("tangential_stiffness", tangential_stiffness, n_contacts,
                                 unit="N/m")
        mu_a = broadcast_parameter("mu", mu, n_contacts, unit="", allow_zero=True)
        mud = mu_a if mu_sliding is None else broadcast_parameter(
            "mu_sliding", mu_sliding, n_contacts, unit="", allow_zero=True)
        dc = broadcast_parameter("decay", decay, n_contacts, unit="s/m", allow_zero=True)
        g0 = np.atleast_1d(as_finite_array("offset", offset))
        if g0.ndim != 1:
            raise ModelError(f"offset must be a scalar or a 1-D array [m], got shape {g0.shape}")
        n = (common_size(normal_stiffness=kn, tangential_stiffness=kt, mu=mu_a, offset=g0,
                         mu_sliding=mud, decay=dc)
             if n_contacts is None else int(n_contacts))
        if n < 1:
            raise ModelError(f"n_contacts must be >= 1, got {n_contacts!r}")
        if g0.size not in (1, n):
            raise ModelError(f"offset must be a scalar or have {n} entries, got {g0.size}")
        self.n_contacts = n
        self.normal_stiffness = np.broadcast_to(kn, (n,)).copy()
        self.tangential_stiffness = np.broadcast_to(kt, (n,)).copy()
        self.mu = np.broadcast_to(mu_a, (n,)).copy()
        self.offset = np.broadcast_to(g0, (n,)).astype(float)
        self.mu_sliding = np.broadcast_to(mud, (n,)).copy()
        self.decay = np.broadcast_to(dc, (n,)).copy()
        if np.any(self.mu_sliding > self.mu):
            raise ModelError(f"mu_sliding must be <= mu (the static coefficient, 0 <= mu_d <= "
                             f"mu_s), got mu_sliding={mu_sliding!r}, mu={mu!r}")
        #: True for the static/kinetic law (state with a slip flag).
        self.kinetic = bool(np.any(self.mu_sliding != self.mu))
        self.n_state = 3 if self.kinetic else 2
        #: True when the sliding coefficient depends on the velocity (decay > 0).
        self.velocity_dependent = self.kinetic and bool(np.any(
            (self.decay > 0.0) & (self.mu_sliding != self.mu)))

    @property
    def mu_static(self) -> np.ndarray:
        """Static coefficient mu_s [-] (the ``mu`` parameter), shape (n_contacts,)."""
        return self.mu

    @classmethod
    def from_preload(cls, normal_stiffness, preload, tangential_stiffness, mu, *,
                     mu_sliding=None, decay=0.0, n_contacts: int | None = None) -> Contact3D:
        """Element whose normal force at ``u_n = 0`` is ``preload`` [N] (>= 0).

        The offset is ``g0 = preload / normal_stiffness`` (paper 003: offset 1e-5 m for
        2.4 N, i.e. k_n = 2.4e5 N/m). Other parameters as in the constructor.
        """
        kn = broadcast_parameter("normal_stiffness", normal_stiffness, n_contacts, unit="N/m")
        p = broadcast_parameter("preload", preload, n_contacts, unit="N", allow_zero=True)
        return cls(normal_stiffness, tangential_stiffness, mu, offset=p / kn,
                   mu_sliding=mu_sliding, decay=decay, n_contacts=n_contacts)

    def __repr__(self) -> str:
        extra = ""
        if self.kinetic:
            extra = (f", mu_sliding={self.mu_sliding.tolist()}, "
                     f"decay={self.decay.tolist()}")
        return (f"Contact3D(n_contacts={self.n_contacts}, "
                f"normal_stiffness={self.normal_stiffness.tolist()}, "
                f"tangential_stiffness={self.tangential_stiffness.tolist()}, "
                f"mu={self.mu.tolist()}, offset={self.offset.tolist()}{extra})")

    def initial_state(self) -> np.ndarray:
        """Virgin state: sliders at the origin (and stuck), shape (n_contacts, n_state)."""
        return np.zeros((self.n_contacts, self.n_state))

    def normal_force(self, u) -> np.ndarray:
        """Normal force ``k_n max(u_n + g0, 0)`` [N], shape (n_contacts,)."""
        u = self._check_u(u)
        return self.normal_stiffness * np.maximum(u[:, 0] + self.offset, 0.0)

    def sliding_coefficient(self, v) -> np.ndarray:
        """Coefficient while sliding at tangential velocity ``v`` [m/s], shape (n_contacts,).

        ``v`` is the relative velocity (n_contacts, 3) (the normal component is ignored)
        or the tangential speed (n_contacts,). Constant-mu law: ``mu``.
        """
        if not self.kinetic:
            return self.mu.copy()
        v = np.asarray(v, dtype=float)
        speed = (np.abs(v.reshape(self.n_contacts)) if v.size == self.n_contacts
                 else np.hypot(*v.reshape(self.n_contacts, 3)[:, 1:3].T))
        mud, dc = self.mu_sliding, self.decay
        return np.where(dc > 0.0, mud + (self.mu - mud) * np.exp(-dc * speed), mud)

    def _velocity(self, v) -> np.ndarray:
        if v is None:
            if self.velocity_dependent:
                raise ModelError("v (relative velocity [m/s], shape (n_contacts, 3)) is "
                                 "required: this Contact3D has decay > 0, so its sliding "
                                 "force depends on the velocity")
            return np.zeros((self.n_contacts, 3))
        v = as_finite_array("v", v)
        if v.size != 3 * self.n_contacts:
            raise ModelError(f"v must have shape ({self.n_contacts}, 3), got {v.shape}")
        return v.reshape(self.n_contacts, 3)

    def step(self, state, u, v=None) -> LawStep:
        """One radial-return step (module docstring); ``v`` is used by the kinetic law."""
        u = self._check_u(u)
        st = np.asarray(state, dtype=float).reshape(self.n_contacts, self.n_state)
        w = st[:, :2]
        kn, kt = self.normal_stiffness, self.tangential_stiffness
        gap = u[:, 0] + self.offset
        contact = gap > 0.0
        nf = np.where(contact, kn * gap, 0.0)
        ut = u[:, 1:3]
        ftr = kt[:, None] * (ut - w)
        nrm = np.sqrt(ftr[:, 0] * ftr[:, 0] + ftr[:, 1] * ftr[:, 1])
        if self.kinetic:
            vv = self._velocity(v)
            speed = np.hypot(vv[:, 1], vv[:, 2])
            mu_v = self.sliding_coefficient(speed)
            lim = np.where(st[:, 2] == 0.0, self.mu, mu_v) * nf
        else:
            mu_v = self.mu
            lim = mu_v * nf
        slip = contact & (nrm > lim)
        safe = np.where(slip, nrm, 1.0)
        scale = np.where(slip, mu_v * nf / safe, 1.0)
        ft = np.where(contact[:, None], ftr * scale[:, None], 0.0)
        w_new = np.where(slip[:, None], ut - ft / kt[:, None],
                         np.where(contact[:, None], w, ut))
        force = np.concatenate([nf[:, None], ft], axis=1)

        d = ftr / safe[:, None]                      # slip direction (used only in slip)
        eye = np.eye(2)
        k_tt = np.where(slip[:, None, None],
                        (scale * kt)[:, None, None] * (eye - d[:, :, None] * d[:, None, :]),
                        kt[:, None, None] * eye)
        K = np.zeros((self.n_contacts, 3, 3))
        K[:, 0, 0] = kn
        K[:, 1:, 1:] = k_tt
        K[:, 1:, 0] = np.where(slip[:, None], (mu_v * kn)[:, None] * d, 0.0)
        K[~contact] = 0.0
        damping = None
        if self.kinetic:
            new_state = np.concatenate([w_new, slip[:, None].astype(float)], axis=1)
            if self.velocity_dependent:
                dc = self.decay
                dmu = -(self.mu - self.mu_sliding) * dc * np.exp(-dc * speed)
                ev = vv[:, 1:3] / np.where(speed > 0.0, speed, 1.0)[:, None]
                c = np.where(slip, nf * dmu, 0.0)
                damping = np.zeros((self.n_contacts, 3, 3))
                damping[:, 1:, 1:] = c[:, None, None] * d[:, :, None] * ev[:, None, :]
        else:
            new_state = w_new
        return LawStep(force, K, damping, new_state)

    def contact_status(self, state, force) -> np.ndarray:
        """Status code per contact after a step: 0 open, 1 stick, 2 slip, shape (n_contacts,).

        Slip is read from the slip flag of the kinetic law; for the constant-mu law a closed
        contact whose tangential force lies on the cone (to 1e-9 relative) is slipping.
        """
        f = np.asarray(force, dtype=float).reshape(self.n_contacts, 3)
        st = np.asarray(state, dtype=float).reshape(self.n_contacts, self.n_state)
        closed = f[:, 0] > 0.0
        if self.kinetic:
            slip = st[:, 2] != 0.0
        else:
            slip = np.hypot(f[:, 1], f[:, 2]) >= (1.0 - 1e-9) * self.mu * f[:, 0]
            slip &= self.mu > 0.0
        return np.where(closed, np.where(slip, 2, 1), 0).astype(np.int8)

    def stored_energy(self, state, u) -> np.ndarray:
        """Normal penalty plus tangential spring energy [J], shape (n_contacts,).

        ``k_n max(u_n + g0, 0)^2 / 2 + k_t |u_t - w|^2 / 2`` with ``w`` the state after the
        step to ``u`` (with a prestress this is ``k_n g0^2 / 2`` at ``u = 0``).
        """
        u = self._check_u(u)
        w = np.asarray(state, dtype=float).reshape(self.n_contacts, self.n_state)[:, :2]
        gap = np.maximum(u[:, 0] + self.offset, 0.0)
        et = u[:, 1:3] - w
        return 0.5 * self.normal_stiffness * gap**2 + 0.5 * self.tangential_stiffness * np.sum(
            et * et, axis=1)

    def dissipation(self, state_old, state_new, force_new) -> np.ndarray:
        """Energy [J] dissipated by a step in each contact, shape (n_contacts,).

        ``f_t . (w_new - w_old)``: the tangential force times the slider increment (>= 0 for
        the radial return, which moves the slider along the force; 0 in stick and for an
        open contact, whose force is zero).
        """
        ns = self.n_state
        w0 = np.asarray(state_old, dtype=float).reshape(self.n_contacts, ns)[:, :2]
        w1 = np.asarray(state_new, dtype=float).reshape(self.n_contacts, ns)[:, :2]
        f = np.asarray(force_new, dtype=float).reshape(self.n_contacts, 3)
        return np.sum(f[:, 1:3] * (w1 - w0), axis=1)

    def march(self, u_history, state=None, v_history=None):
        """Compiled march (see :meth:`ContactLaw.march`).

        ``v_history`` (n_t, n_contacts, 3) is needed by the velocity-dependent kinetic law
        and ignored otherwise.
        """
        u = np.asarray(u_history, dtype=float)
        if u.ndim != 3 or u.shape[1:] != (self.n_contacts, 3):
            raise ModelError(f"u_history must have shape (n_t, {self.n_contacts}, 3), got "
                             f"{u.shape}")
        u = np.ascontiguousarray(u)
        st = self.initial_state() if state is None else np.asarray(state, dtype=float)
        st = np.ascontiguousarray(st, dtype=float).reshape(self.n_contacts, self.n_state)
        f = np.empty_like(u)
        if not self.kinetic:
            w = contact3d_march_kernel(u, self.normal_stiffness, self.tangential_stiffness,
                                       self.mu, self.offset, st, f)
            return f, w
        if v_history is None:
            if self.velocity_dependent:
                raise ModelError("v_history (relative velocities, shape (n_t, n_contacts, 3)) "
                                 "is required: this Contact3D has decay > 0")
            v = np.zeros_like(u)
        else:
            v = np.ascontiguousarray(np.asarray(v_history, dtype=float))
            if v.shape != u.shape:
                raise ModelError(f"v_history must have the shape of u_history {u.shape}, got "
                                 f"{v.shape}")
        w, s = contact3d_kinetic_march_kernel(
            u, v, self.normal_stiffness, self.tangential_stiffness, self.mu, self.mu_sliding,
            self.decay, self.offset, np.ascontiguousarray(st[:, :2]),
            np.ascontiguousarray(st[:, 2]), f)
        return f, np.concatenate([w, s[:, None]], axis=1)
