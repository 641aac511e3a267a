"""Jenkins element: a linear spring in series with a Coulomb slider (1D).

The tangential force is ``f = k_t (u - w)`` with slider position ``w`` (the state). The
return map predicts ``f_trial = k_t (u - w)``; if ``|f_trial| <= F_s`` the slider sticks,
otherwise it slides so that ``|f| = F_s`` and ``w = u - F_s sign(f_trial) / k_t``.
Consistent tangent: ``k_t`` in stick, 0 in slip.

Closed form (den Hartog / Iwan): for ``u = A cos(theta)`` and ``A > F_s / k_t`` the energy
dissipated per cycle is ``W = 4 F_s (A - F_s / k_t)`` (tests/validation/test_jenkins.py).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from fricdamp.contact.base import ContactLaw, LawStep, broadcast_parameter, common_size


@njit(cache=True, nogil=True)
def jenkins_march_kernel(u, kt, fs, w0, f_out):  # pragma: no cover - compiled
    """March 1D Jenkins elements along u (n_t, n_c); write forces, return final w.

    kt, fs: (n_c,) stiffness and slip force; w0: (n_c,) initial slider positions.
    """
    nt, nc = u.shape
    w = w0.copy()
    for i in range(nt):
        for j in range(nc):
            f = kt[j] * (u[i, j] - w[j])
            if f > fs[j]:
                f = fs[j]
                w[j] = u[i, j] - fs[j] / kt[j]
            elif f < -fs[j]:
                f = -fs[j]
                w[j] = u[i, j] + fs[j] / kt[j]
            f_out[i, j] = f
    return w


class Jenkins(ContactLaw):
    """Spring ``stiffness`` [N/m] in series with a Coulomb slider of limit ``slip_force`` [N].

    Parameters
    ----------
    stiffness : float or array_like, shape (n_contacts,)
        Tangential contact stiffness k_t [N/m], > 0.
    slip_force : float or array_like, shape (n_contacts,)
        Slip limit F_s = mu N [N], >= 0 (0 gives a force-free contact).
    n_contacts : int, optional
        Number of contacts when both parameters are scalars (default 1).

    Examples
    --------
    >>> import numpy as np
    >>> law = Jenkins(stiffness=1000.0, slip_force=1.0)
    >>> f = law.drive(np.array([0.0, 0.0005, 0.002, 0.001]))
    >>> f.round(6).tolist()
    [0.0, 0.5, 1.0, 0.0]
    """

    n_dir = 1
    n_state = 1

    def __init__(self, stiffness, slip_force, *, n_contacts: int | None = None):
        kt = broadcast_parameter("stiffness", stiffness, n_contacts, unit="N/m")
        fs = broadcast_parameter("slip_force", slip_force, n_contacts, unit="N", allow_zero=True)
        n = common_size(stiffness=kt, slip_force=fs) if n_contacts is None else int(n_contacts)
        self.n_contacts = n
        self.stiffness = np.broadcast_to(kt, (n,)).copy()
        self.slip_force = np.broadcast_to(fs, (n,)).copy()

    @classmethod
    def from_friction(cls, stiffness, mu, normal_load, **kw) -> Jenkins:
        """Jenkins element with ``slip_force = mu * normal_load`` (mu >= 0, N >= 0 [N])."""
        mu_a = broadcast_parameter("mu", mu, None, unit="", allow_zero=True)
        n_a = broadcast_parameter("normal_load", normal_load, None, unit="N", allow_zero=True)
        return cls(stiffness, mu_a * n_a, **kw)

    def __repr__(self) -> str:
        return (f"Jenkins(n_contacts={self.n_contacts}, stiffness={self.stiffness.tolist()}, "
                f"slip_force={self.slip_force.tolist()})")

    def initial_state(self) -> np.ndarray:
        return np.zeros((self.n_contacts, 1))

    def step(self, state, u, v=None) -> LawStep:
        u = self._check_u(u)[:, 0]
        w = np.asarray(state, dtype=float)[:, 0]
        kt, fs = self.stiffness, self.slip_force
        f = kt * (u - w)
        slip = np.abs(f) > fs
        f = np.where(slip, np.sign(f) * fs, f)
        w_new = np.where(slip, u - f / kt, w)
        k = np.where(slip, 0.0, kt)
        return LawStep(f[:, None], k[:, None, None], None, w_new[:, None])

    def stored_energy(self, state, u) -> np.ndarray:
        u = self._check_u(u)[:, 0]
        w = np.asarray(state, dtype=float)[:, 0]
        return 0.5 * self.stiffness * (u - w) ** 2

    def dissipation(self, state_old, state_new, force_new) -> np.ndarray:
        """Friction work ``f (w_new - w_old)`` [J]: exact for the return map (f = +-F_s in slip)."""
        dw = np.asarray(state_new, float)[:, 0] - np.asarray(state_old, float)[:, 0]
        return np.asarray(force_new, float).reshape(self.n_contacts) * dw

    def march(self, u_history, state=None, v_history=None):
        u = np.ascontiguousarray(np.asarray(u_history, dtype=float)[:, :, 0])
        w0 = (self.initial_state() if state is None else np.asarray(state, float))[:, 0]
        f = np.empty_like(u)
        w = jenkins_march_kernel(u, self.stiffness, self.slip_force,
                                 np.ascontiguousarray(w0, dtype=float), f)
        return f[:, :, None], w[:, None]
