"""Cubic spring: the Duffing nonlinearity ``f = k3 u^3`` on a relative displacement (1D).

The force is a function of the relative displacement only: the law has no state
(``n_state = 0``), dissipates nothing and its tangent ``df/du = 3 k3 u^2`` is exact, so the
same object serves time stepping (Newton on ``step``) and the AFT step of harmonic balance
(:meth:`CubicSpring.periodic_response` returns the exact sensitivity of the sampled force to
the displacement coefficients, ``3 k3 u(t_i)^2 basis[i, j]``).

With a linear spring k and a mass m it makes the Duffing oscillator
``m x'' + c x' + k x + k3 x^3 = F cos(Omega t)``, whose single-harmonic backbone is
``Omega^2 = k / m + 3/4 (k3 / m) a^2`` (tests/validation/test_hb_stability.py).
"""

from __future__ import annotations

import numpy as np

from fricdamp.contact.base import ContactLaw, LawStep, PeriodicResponse
from fricdamp.errors import ModelError

__all__ = ["CubicSpring"]


class CubicSpring(ContactLaw):
    """Cubic spring ``f = k3 u^3`` [N] on the relative displacement u [m] of each contact.

    Parameters
    ----------
    k3 : float or array_like, shape (n_contacts,)
        Cubic stiffness [N/m^3], finite; > 0 hardens, < 0 softens (a softening spring has no
        stable equilibrium beyond ``|u|`` where the structure's linear stiffness is overcome).
    n_contacts : int, optional
        Number of contacts when ``k3`` is a scalar (default 1).

    Raises
    ------
    ModelError
        If ``k3`` is not finite or its length does not match ``n_contacts``.

    Examples
    --------
    >>> import numpy as np
    >>> law = CubicSpring(2.0)
    >>> r = law.step(law.initial_state(), [[0.5]])
    >>> float(r.force[0, 0]), float(r.stiffness[0, 0, 0])
    (0.25, 1.5)
    """

    n_dir = 1
    n_state = 0

    def __init__(self, k3, *, n_contacts: int | None = None):
        arr = np.atleast_1d(np.asarray(k3, dtype=float))
        if arr.ndim != 1:
            raise ModelError(f"k3 must be a scalar or a 1-D array [N/m^3], got shape {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ModelError(f"k3 must be finite [N/m^3] (any sign), got {k3!r}")
        if n_contacts is not None:
            if int(n_contacts) != n_contacts or n_contacts < 1:
                raise ModelError(f"n_contacts must be an integer >= 1, got {n_contacts!r}")
            if arr.size not in (1, n_contacts):
                raise ModelError(f"k3 must be a scalar or have n_contacts = {n_contacts} "
                                 f"entries, got {arr.size}")
        n = arr.size if n_contacts is None else int(n_contacts)
        self.n_contacts = n
        self.k3 = np.broadcast_to(arr, (n,)).copy()

    def __repr__(self) -> str:
        return f"CubicSpring(n_contacts={self.n_contacts}, k3={self.k3.tolist()})"

    def initial_state(self) -> np.ndarray:
        return np.zeros((self.n_contacts, 0))

    def step(self, state, u, v=None) -> LawStep:
        u = self._check_u(u)[:, 0]
        f = self.k3 * u**3
        k = 3.0 * self.k3 * u**2
        return LawStep(f[:, None], k[:, None, None], None, np.zeros((self.n_contacts, 0)))

    def stored_energy(self, state, u) -> np.ndarray:
        """Potential ``k3 u^4 / 4`` [J] per contact."""
        u = self._check_u(u)[:, 0]
        return 0.25 * self.k3 * u**4

    def dissipation(self, state_old, state_new, force_new) -> np.ndarray:
        """A cubic spring is conservative: zero [J]."""
        return np.zeros(self.n_contacts)

    def march(self, u_history, state=None, v_history=None):
        u = np.asarray(u_history, dtype=float)
        return self.k3[None, :, None] * u**3, np.zeros((self.n_contacts, 0))

    def periodic_response(self, u, v=None, *, basis=None, velocity_basis=None, state=None,
                          max_periods: int = 50, tol: float = 1e-10) -> PeriodicResponse:
        """Force samples and their exact sensitivity (the law is memoryless: one period).

        ``jacobian[i, c, 0, 0, j] = 3 k3 u[i, c]^2 basis[i, j]``. See
        :meth:`ContactLaw.periodic_response` for the parameters.
        """
        u3 = self._as_history(np.asarray(u, dtype=float), "u")
        k3 = self.k3[None, :, None]
        f = k3 * u3**3
        jac = None
        if basis is not None:
            B = np.asarray(basis, dtype=float)
            if B.ndim != 2 or B.shape[0] != u3.shape[0]:
                raise ModelError(f"basis must have shape (n_t={u3.shape[0]}, n_basis), got "
                                 f"{B.shape}")
            kt = 3.0 * k3[:, :, 0] * u3[:, :, 0] ** 2                     # (n_t, nc)
            jac = (kt[:, :, None] * B[:, None, :])[:, :, None, None, :]
        return PeriodicResponse(f, jac, np.zeros((self.n_contacts, 0)), 1, True)
