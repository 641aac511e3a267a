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

__all__ = ["Contact3D", "contact3d_march_kernel"]


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
        Friction coefficient [-], >= 0.
    offset : float or array_like, shape (n_contacts,), optional
        Normal offset g0 [m]: > 0 interference (prestress ``k_n g0``), < 0 gap. Default 0.
    n_contacts : int, optional
        Number of contacts when all parameters are scalars (default 1).

    Raises
    ------
    ModelError
        Naming the parameter for a non-positive stiffness, a negative mu, a non-finite
        value or inconsistent per-contact lengths.

    Examples
    --------
    >>> import numpy as np
    >>> law = Contact3D.from_preload(1e5, 2.0, tangential_stiffness=1e4, mu=0.5)
    >>> u = np.array([[0.0, 0.0, 0.0], [0.0, 5e-5, 0.0], [0.0, 2e-4, 0.0], [-3e-5, 0.0, 0.0]])
    >>> law.drive(u).round(6).tolist()
    [[2.0, 0.0, 0.0], [2.0, 0.5, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.0]]
    """

    n_dir = 3
    n_state = 2

    def __init__(self, normal_stiffness, tangential_stiffness, mu, offset=0.0, *,
                 n_contacts: int | None = None):
        kn = broadcast_parameter("normal_stiffness", normal_stiffness, n_contacts, unit="N/m")
        kt = broadcast_parameter("tangential_stiffness", tangential_stiffness, n_contacts,
                                 unit="N/m")
        mu_a = broadcast_parameter("mu", mu, n_contacts, unit="", allow_zero=True)
        g0 = np.atleast_1d(as_finite_array("offset", offset))
        if g0.ndim != 1:
            raise ModelError(f"offset must be a scalar or a 1-D array [m], got shape {g0.shape}")
        n = (common_size(normal_stiffness=kn, tangential_stiffness=kt, mu=mu_a, offset=g0)
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

    @classmethod
    def from_preload(cls, normal_stiffness, preload, tangential_stiffness, mu, *,
                     n_contacts: int | None = None) -> Contact3D:
        """Element whose normal force at ``u_n = 0`` is ``preload`` [N] (>= 0).

        The offset is ``g0 = preload / normal_stiffness`` (paper 003: offset 1e-5 m for
        2.4 N, i.e. k_n = 2.4e5 N/m).
        """
        kn = broadcast_parameter("normal_stiffness", normal_stiffness, n_contacts, unit="N/m")
        p = broadcast_parameter("preload", preload, n_contacts, unit="N", allow_zero=True)
        return cls(normal_stiffness, tangential_stiffness, mu, offset=p / kn,
                   n_contacts=n_contacts)

    def __repr__(self) -> str:
        return (f"Contact3D(n_contacts={self.n_contacts}, "
                f"normal_stiffness={self.normal_stiffness.tolist()}, "
                f"tangential_stiffness={self.tangential_stiffness.tolist()}, "
                f"mu={self.mu.tolist()}, offset={self.offset.tolist()})")

    def initial_state(self) -> np.ndarray:
        """Virgin state: sliders at the origin, shape (n_contacts, 2) [m]."""
        return np.zeros((self.n_contacts, 2))

    def normal_force(self, u) -> np.ndarray:
        """Normal force ``k_n max(u_n + g0, 0)`` [N], shape (n_contacts,)."""
        u = self._check_u(u)
        return self.normal_stiffness * np.maximum(u[:, 0] + self.offset, 0.0)

    def step(self, state, u, v=None) -> LawStep:
        """One radial-return step (module docstring); ``v`` is ignored."""
        u = self._check_u(u)
        w = np.asarray(state, dtype=float).reshape(self.n_contacts, 2)
        kn, kt, mu = self.normal_stiffness, self.tangential_stiffness, self.mu
        gap = u[:, 0] + self.offset
        contact = gap > 0.0
        nf = np.where(contact, kn * gap, 0.0)
        ut = u[:, 1:3]
        ftr = kt[:, None] * (ut - w)
        nrm = np.sqrt(ftr[:, 0] * ftr[:, 0] + ftr[:, 1] * ftr[:, 1])
        lim = mu * nf
        slip = contact & (nrm > lim)
        safe = np.where(slip, nrm, 1.0)
        scale = np.where(slip, lim / safe, 1.0)
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
        K[:, 1:, 0] = np.where(slip[:, None], (mu * kn)[:, None] * d, 0.0)
        K[~contact] = 0.0
        return LawStep(force, K, None, w_new)

    def stored_energy(self, state, u) -> np.ndarray:
        """Normal penalty plus tangential spring energy [J], shape (n_contacts,).

        ``k_n max(u_n + g0, 0)^2 / 2 + k_t |u_t - w|^2 / 2`` with ``w`` the state after the
        step to ``u`` (with a prestress this is ``k_n g0^2 / 2`` at ``u = 0``).
        """
        u = self._check_u(u)
        w = np.asarray(state, dtype=float).reshape(self.n_contacts, 2)
        gap = np.maximum(u[:, 0] + self.offset, 0.0)
        et = u[:, 1:3] - w
        return 0.5 * self.normal_stiffness * gap**2 + 0.5 * self.tangential_stiffness * np.sum(
            et * et, axis=1)

    def march(self, u_history, state=None, v_history=None):
        """Compiled march (see :meth:`ContactLaw.march`); ``v_history`` is ignored."""
        u = np.asarray(u_history, dtype=float)
        if u.ndim != 3 or u.shape[1:] != (self.n_contacts, 3):
            raise ModelError(f"u_history must have shape (n_t, {self.n_contacts}, 3), got "
                             f"{u.shape}")
        u = np.ascontiguousarray(u)
        w0 = self.initial_state() if state is None else np.asarray(state, dtype=float)
        f = np.empty_like(u)
        w = contact3d_march_kernel(u, self.normal_stiffness, self.tangential_stiffness,
                                   self.mu, self.offset,
                                   np.ascontiguousarray(w0, dtype=float).reshape(-1, 2), f)
        return f, w
