"""Iwan model: Jenkins elements in parallel with Segalman's four-parameter slip density.

An Iwan model (Iwan 1966) is a continuum of Jenkins elements (unit spring in series with a
slider) in parallel, all driven by the same displacement ``u``; the element that slips at
displacement ``phi`` carries the density ``rho(phi)``::

    F(u) = int_0^inf rho(phi) (u - x(phi)) dphi,   |u - x(phi)| <= phi   (slider x)

Segalman's four-parameter density (Segalman 2005, J. Appl. Mech. 72, 752) is a truncated
power law plus a Dirac at the cut::

    rho(phi) = R phi^chi [H(phi) - H(phi - phi_max)] + S delta(phi - phi_max)

parameterised by the joint's stiffness ``K_T = int rho``, its slip force
``F_S = int rho phi`` (the force of macro-slip), the exponent ``chi`` and
``beta = S / (R phi_max^(chi+1) / (chi+1))``::

    phi_max = F_S (1 + beta) / (K_T (beta + (chi+1)/(chi+2)))
    R = F_S (chi+1) / (phi_max^(chi+2) (beta + (chi+1)/(chi+2))),   S = K_T beta / (1 + beta)

Micro-slip: for a symmetric cycle of displacement amplitude ``A <= phi_max`` every element
with ``phi < A`` slides and dissipates ``4 phi (A - phi)`` per unit density, so::

    E_d(A) = 4 R A^(chi+3) / ((chi+2)(chi+3))                 (the 3 + chi power law)

and in general :meth:`Iwan.continuum_energy`. Segalman's range is ``-1 < chi <= 0``
(``chi = -1/2`` gives a Cattaneo-Mindlin-like slope 2.5); this module accepts
``-1 < chi <= 1``.

Discretisation
--------------
The power-law part is cut at the edges ``0, e_1, ..., e_(n-1), phi_max`` with ``e_j``
logarithmically spaced from ``min_ratio phi_max``; each interval becomes one Jenkins
element whose stiffness is the interval's mass ``int rho`` and whose slip force is its first
moment ``int rho phi`` (so its slip displacement is the interval's mean ``phi``), and the Dirac
is one more element of stiffness ``S`` and slip displacement ``phi_max``. The discrete law
therefore has exactly ``K_T`` and ``F_S``. Its micro-slip energy is piecewise linear in
``A`` between the elements' slip displacements, within 0.2-0.5 % of the closed form (default
100 elements, ``chi`` from -0.8 to 0) for ``A`` from ``30 min_ratio phi_max`` to ``phi_max``,
and its least-squares exponent over those decades is ``3 + chi`` to 1e-5
(tests/unit/test_iwan.py). Below ``min_ratio phi_max`` everything sticks: the energy there
is 0, not the power law.

Protocol
--------
One direction, ``n_contacts`` contacts, state = the slider positions ``(n_contacts,
n_elements + 1)``. :meth:`Iwan.step` is the vectorised return map, :meth:`Iwan.march` a
compiled kernel, :meth:`Iwan.periodic_response` the steady periodic force with its exact
sensitivity (every element is a Jenkins element), so time stepping, the event-driven
solver's smooth phases and harmonic balance (AFT) all use it like any other law.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from fricdamp.contact.base import (
    ContactLaw,
    LawStep,
    PeriodicResponse,
    broadcast_parameter,
    common_size,
)
from fricdamp.contact.jenkins import jenkins_periodic_kernel
from fricdamp.errors import ModelError, as_finite_array

__all__ = ["Iwan", "segalman_density"]


def segalman_density(stiffness, slip_force, chi, beta):
    """``(phi_max, R, S)`` of Segalman's density from ``(K_T, F_S, chi, beta)`` (module doc).

    Parameters
    ----------
    stiffness : float or ndarray
        K_T [N/m], > 0.
    slip_force : float or ndarray
        F_S [N], > 0.
    chi : float or ndarray
        Exponent, in (-1, 1].
    beta : float or ndarray
        Dirac weight ratio, >= 0.

    Returns
    -------
    phi_max : ndarray
        Largest slip displacement [m].
    R : ndarray
        Coefficient of the power law [N m^-(chi+2)].
    S : ndarray
        Stiffness of the Dirac element [N/m].
    """
    k, f, x, b = (np.asarray(v, dtype=float) for v in (stiffness, slip_force, chi, beta))
    c = (x + 1.0) / (x + 2.0)
    phi_max = f * (1.0 + b) / (k * (b + c))
    R = f * (x + 1.0) / (phi_max ** (x + 2.0) * (b + c))
    S = k * b / (1.0 + b)
    return phi_max, R, S


@njit(cache=True, nogil=True)
def iwan_march_kernel(u, k, fs, w, f_out):  # pragma: no cover - compiled
    """March Iwan contacts along u (n_t, n_c): elements k, fs, sliders w (n_c, n_e), in place.

    Writes the total forces into f_out (n_t, n_c).
    """
    nt, nc = u.shape
    ne = k.shape[1]
    for i in range(nt):
        for c in range(nc):
            total = 0.0
            uc = u[i, c]
            for j in range(ne):
                f = k[c, j] * (uc - w[c, j])
                if f > fs[c, j]:
                    f = fs[c, j]
                    w[c, j] = uc - fs[c, j] / k[c, j]
                elif f < -fs[c, j]:
                    f = -fs[c, j]
                    w[c, j] = uc + fs[c, j] / k[c, j]
                total += f
            f_out[i, c] = total


@njit(cache=True, nogil=True)
def iwan_jacobian_kernel(anchor, k, basis, jac):  # pragma: no cover - compiled
    """jac[i, c, :] = sum_j d f_j[i, c] / d x from the Jenkins anchors (n_t, n_c, n_e)."""
    nt, nc, ne = anchor.shape
    m = basis.shape[1]
    for i in range(nt):
        for c in range(nc):
            for q in range(m):
                jac[i, c, q] = 0.0
            for j in range(ne):
                s = anchor[i, c, j]
                if s == -1:
                    continue
                kj = k[c, j]
                if s == -2:
                    for q in range(m):
                        jac[i, c, q] += kj * basis[i, q]
                else:
                    for q in range(m):
                        jac[i, c, q] += kj * (basis[i, q] - basis[s, q])


class Iwan(ContactLaw):
    """Four-parameter Iwan joint (Segalman): parallel Jenkins elements, power-law density.

    Parameters
    ----------
    stiffness : float or array_like, shape (n_contacts,)
        K_T, the stiffness of the stuck joint [N/m] (or [N m/rad] for a rotation), > 0.
    slip_force : float or array_like, shape (n_contacts,)
        F_S, the force of macro-slip [N] (or moment [N m]), > 0.
    chi : float or array_like, shape (n_contacts,)
        Exponent of the slip density, in (-1, 1]; the micro-slip energy grows as
        ``A^(3 + chi)``. Typical joints: -0.8 to -0.3.
    beta : float or array_like, shape (n_contacts,)
        Weight of the Dirac at ``phi_max`` relative to the power-law part's stiffness, >= 0.
    n_elements : int, optional
        Jenkins elements of the power-law part, >= 2 (one more carries the Dirac); default
        100.
    min_ratio : float, optional
        Smallest edge of the discretisation / phi_max, in (0, 1); default 1e-4 (power law
        from ~3e-3 phi_max).
    n_contacts : int, optional
        Number of contacts when every parameter is a scalar (default 1).

    Attributes
    ----------
    phi_max, density_coefficient, dirac_stiffness : ndarray, shape (n_contacts,)
        Segalman's ``phi_max`` [m], ``R``, ``S`` [N/m].
    element_stiffness, element_slip_force : ndarray, shape (n_contacts, n_elements + 1)
        The discrete Jenkins elements [N/m], [N].

    References
    ----------
    Iwan (1966) J. Appl. Mech. 33, 893; Segalman (2005) J. Appl. Mech. 72, 752-760.

    Examples
    --------
    >>> import numpy as np
    >>> law = Iwan(stiffness=1e6, slip_force=10.0, chi=-0.5, beta=0.2)
    >>> round(float(law.element_stiffness.sum()), 6), round(float(law.element_slip_force.sum()), 9)
    (1000000.0, 10.0)
    >>> u = 2e-6 * np.cos(np.linspace(0, 2 * np.pi, 2001))
    >>> bool(law.drive(u).max() < 2.0)          # micro-slip: far below F_S
    True
    """

    n_dir = 1

    def __init__(self, stiffness, slip_force, chi, beta, *, n_elements: int = 100,
                 min_ratio: float = 1e-4, n_contacts: int | None = None):
        kt = broadcast_parameter("stiffness", stiffness, n_contacts, unit="N/m")
        fs = broadcast_parameter("slip_force", slip_force, n_contacts, unit="N")
        x = np.atleast_1d(as_finite_array("chi", chi)).astype(float)
        if x.ndim != 1 or np.any(x <= -1.0) or np.any(x > 1.0):
            raise ModelError(f"chi must lie in (-1, 1] (Segalman: (-1, 0]), got {chi!r}")
        b = broadcast_parameter("beta", beta, n_contacts, unit="", allow_zero=True)
        n = (common_size(stiffness=kt, slip_force=fs, chi=x, beta=b) if n_contacts is None
             else int(n_contacts))
        if x.size not in (1, n):
            raise ModelError(f"chi must be a scalar or have {n} entries, got {x.size}")
        if int(n_elements) != n_elements or n_elements < 2:
            raise ModelError(f"n_elements must be an integer >= 2, got {n_elements!r}")
        mr = float(as_finite_array("min_ratio", min_ratio, ndim=0))
        if not 0.0 < mr < 1.0:
            raise ModelError(f"min_ratio must lie in (0, 1), got {min_ratio!r}")
        self.n_contacts = n
        self.n_elements = int(n_elements)
        self.min_ratio = mr
        self.n_state = self.n_elements + 1
        self.stiffness, self.slip_force, self.chi, self.beta = (
            np.broadcast_to(v, (n,)).astype(float).copy() for v in (kt, fs, x, b))
        self.phi_max, self.density_coefficient, self.dirac_stiffness = segalman_density(
            self.stiffness, self.slip_force, self.chi, self.beta)
        # edges 0, e_1 .. e_(n-1), phi_max (per contact); interval masses and first moments
        ne = self.n_elements
        ratios = np.concatenate(([0.0], np.geomspace(mr, 1.0, ne)))  # (ne + 1,)
        e = self.phi_max[:, None] * ratios[None, :]
        a1, a2 = self.chi[:, None] + 1.0, self.chi[:, None] + 2.0
        R = self.density_coefficient[:, None]
        mass = R * np.diff(e ** a1, axis=1) / a1
        moment = R * np.diff(e ** a2, axis=1) / a2
        self.element_stiffness = np.concatenate((mass, self.dirac_stiffness[:, None]), axis=1)
        self.element_slip_force = np.concatenate(
            (moment, (self.dirac_stiffness * self.phi_max)[:, None]), axis=1)
        # a Dirac of zero weight (beta = 0) is an element of zero stiffness: keep it inert
        self._k = np.where(self.element_stiffness > 0, self.element_stiffness, 1.0)
        self._fs = np.where(self.element_stiffness > 0, self.element_slip_force, 0.0)
        self._active = self.element_stiffness > 0

    def __repr__(self) -> str:
        return (f"Iwan(n_contacts={self.n_contacts}, stiffness={self.stiffness.tolist()}, "
                f"slip_force={self.slip_force.tolist()}, chi={self.chi.tolist()}, "
                f"beta={self.beta.tolist()}, n_elements={self.n_elements})")

    # ----------------------------------------------------------------- closed forms
    def continuum_energy(self, amplitude) -> np.ndarray:
        """Energy per symmetric cycle of the continuous model [J], shape (..., n_contacts).

        ``4 R A^(chi+3)/((chi+2)(chi+3))`` for ``A <= phi_max``; beyond, every power-law
        element and the Dirac slide: ``4 R phi_max^(chi+2) (A/(chi+2) - phi_max/(chi+3))
        + 4 S phi_max (A - phi_max)``.
        """
        A = np.asarray(as_finite_array("amplitude", amplitude), dtype=float)[..., None]
        if np.any(A < 0):
            raise ModelError(f"amplitude must be >= 0, got {amplitude!r}")
        x, R, pm, S = self.chi, self.density_coefficient, self.phi_max, self.dirac_stiffness
        Am = np.minimum(A, pm)
        e = 4.0 * R * (A * Am ** (x + 2.0) / (x + 2.0) - Am ** (x + 3.0) / (x + 3.0))
        return e + 4.0 * S * pm * np.maximum(A - pm, 0.0)

    def discrete_energy(self, amplitude) -> np.ndarray:
        """Energy per symmetric cycle of this discretised law [J], shape (..., n_contacts).

        Each Jenkins element of stiffness k and slip force f dissipates
        ``4 f (A - f/k)`` once ``A > f/k`` (den Hartog); the law's loop area, exactly.
        """
        A = np.asarray(as_finite_array("amplitude", amplitude), dtype=float)[..., None, None]
        phi = np.where(self._active, self.element_slip_force / self._k, np.inf)
        return np.sum(4.0 * self._fs * np.maximum(A - phi, 0.0), axis=-1)

    # ----------------------------------------------------------------- protocol
    def initial_state(self) -> np.ndarray:
        return np.zeros((self.n_contacts, self.n_state))

    def _sliders(self, state) -> np.ndarray:
        w = np.asarray(state, dtype=float)
        if w.shape != (self.n_contacts, self.n_state):
            raise ModelError(f"state must have shape ({self.n_contacts}, {self.n_state}), got "
                             f"{w.shape}")
        return w

    def step(self, state, u, v=None) -> LawStep:
        u = self._check_u(u)[:, 0]
        w = self._sliders(state)
        f = self._k * (u[:, None] - w)
        slip = np.abs(f) > self._fs
        f = np.where(slip, np.sign(f) * self._fs, f)
        w_new = np.where(slip, u[:, None] - f / self._k, w)
        k = np.sum(np.where(slip | ~self._active, 0.0, self._k), axis=1)
        return LawStep(f.sum(axis=1)[:, None], k[:, None, None], None, w_new)

    def stored_energy(self, state, u) -> np.ndarray:
        u = self._check_u(u)[:, 0]
        w = self._sliders(state)
        return 0.5 * np.sum(np.where(self._active, self._k * (u[:, None] - w) ** 2, 0.0),
                            axis=1)

    def dissipation(self, state_old, state_new, force_new) -> np.ndarray:
        """Friction work ``sum_j F_j |w_new - w_old|`` [J]: exact for the return map."""
        dw = np.abs(self._sliders(state_new) - self._sliders(state_old))
        return np.sum(self._fs * dw, axis=1)

    def march(self, u_history, state=None, v_history=None):
        u = np.ascontiguousarray(np.asarray(u_history, dtype=float)[:, :, 0])
        w = np.array(self.initial_state() if state is None else self._sliders(state),
                     dtype=float, order="C")
        f = np.empty_like(u)
        iwan_march_kernel(u, np.ascontiguousarray(self._k), np.ascontiguousarray(self._fs),
                          w, f)
        return f[:, :, None], w

    def periodic_response(self, u, v=None, *, basis=None, velocity_basis=None, state=None,
                          max_periods: int = 50, tol: float = 1e-10) -> PeriodicResponse:
        """Periodic force and its exact sensitivity: every element is a Jenkins element.

        Each element is marched to its periodic state (:func:`jenkins_periodic_kernel`,
        at most three periods, bit-exact), its force and anchors summed over the elements
        (:func:`iwan_jacobian_kernel`). See :meth:`ContactLaw.periodic_response`.
        """
        u3 = self._as_history(np.asarray(u, dtype=float), "u")
        nt, nc = u3.shape[0], self.n_contacts
        ne = self.n_state
        w0 = self.initial_state() if state is None else self._sliders(state)
        uu = np.ascontiguousarray(np.repeat(u3[:, :, 0], ne, axis=1))  # (nt, nc * ne)
        f = np.empty((nt, nc * ne))
        anchor = np.empty((nt, nc * ne), dtype=np.int64)
        w, periods = jenkins_periodic_kernel(
            uu, np.ascontiguousarray(self._k.ravel()), np.ascontiguousarray(self._fs.ravel()),
            np.ascontiguousarray(w0.ravel(), dtype=float), max(int(max_periods), 1), f,
            anchor)
        force = f.reshape(nt, nc, ne).sum(axis=2)
        jac = None
        if basis is not None:
            B = np.asarray(basis, dtype=float)
            if B.ndim != 2 or B.shape[0] != nt:
                raise ModelError(f"basis must have shape (n_t={nt}, n_basis), got {B.shape}")
            # inert elements (zero Dirac) never contribute: mark them as slipping
            anc = np.where(self._active.ravel()[None, :], anchor, -1).reshape(nt, nc, ne)
            jac = np.empty((nt, nc, B.shape[1]))
            iwan_jacobian_kernel(np.ascontiguousarray(anc), np.ascontiguousarray(self._k),
                                 np.ascontiguousarray(B), jac)
            jac = jac[:, :, None, None, :]
        return PeriodicResponse(force[:, :, None], jac, w.reshape(nc, ne),
                                int(np.max(np.abs(periods))), bool(np.all(periods > 0)))
