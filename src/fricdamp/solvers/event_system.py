"""Systems for the event-driven stick-slip solver: the protocol and the Coulomb adapter.

The event-driven solver (:func:`fricdamp.solvers.event.simulate_events`) integrates

    M(q) q'' = h(t, q, q') + W_N(q) lambda_N + W_T(q) lambda_T                000 (29), (37)

where ``h`` holds every force that is not a contact constraint force, ``W_N`` and ``W_T``
(n_dof, n_contacts) are the normal and tangential Jacobians of the contacts (one tangential
direction per contact: planar contacts as in paper 000), ``lambda_N`` the normal and
``lambda_T`` the tangential contact forces [N]. The relative tangential velocity of contact i
is ``gamma_T,i = W_T[:, i] . q'`` and its time derivative
``gamma_T'' = W_T^T q'' + wbar_T`` with ``wbar_T = (dW_T/dt)^T q'``
(000 (32)-(33): ``w^T q'' + w_0 = 0``; here ``wbar`` plays the role of the paper's ``w_0``).

Per contact the normal direction is either

* **constrained** (``normal_constrained[i]`` true): the gap ``g_N,i(q) = 0`` is kept closed
  and ``lambda_N,i`` is a Lagrange multiplier found with the accelerations. A bilateral
  contact (the default) never separates: a negative value (tension) is reported, the
  friction limit uses ``|lambda_N,i|``. A *unilateral* contact
  (:meth:`ConstrainedSystem.unilateral_contacts`) lifts off when ``lambda_N,i`` reaches zero
  and closes again by an impact with restitution coefficient ``e_i``
  (:meth:`ConstrainedSystem.restitution_coefficients`, see
  :mod:`fricdamp.solvers.event_impact`); or
* **prescribed**: ``lambda_N,i`` is a given load (:meth:`ConstrainedSystem.prescribed_normal_load`)
  that does not act on the DOFs through ``W_N`` (include it in ``h`` if it does); it only
  sets the friction limit. This is the den Hartog oscillator's case.

In stick the tangential constraint ``gamma_T,i = 0`` holds and ``lambda_T,i`` is a multiplier
bounded by ``mu_static |lambda_N,i|``; in slip ``lambda_T,i = -mu_sliding |lambda_N,i|
sign(gamma_T,i)`` (000 (34)-(35), (41)-(44)). The power of the friction force on the system is
``lambda_T . gamma_T <= 0``.

:class:`CoulombSystem` wraps a linear :class:`~fricdamp.structure.system.MechanicalSystem`
with 1D friction contacts along fixed directions ``w`` and fixed normal loads; it also exposes
its :class:`LinearForm`, with which the solver integrates every stick/slip phase exactly.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError, as_finite_array
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem


@dataclass(frozen=True)
class LinearForm:
    """Linear time-invariant description of a system with fixed contact directions and loads.

    ``M q'' + D q' + K q = static_load + sum_k (cos_loads[k] cos(W_k t) + sin_loads[k] sin(W_k t))
    + W_T lambda_T`` with ``W_k = frequencies[k]``, and fixed normal loads (no normal
    constraint). Systems that can be written this way are integrated exactly, phase by phase.

    Attributes
    ----------
    M, D, K : ndarray, shape (n_dof, n_dof)
        Mass [kg], viscous damping [N s/m] and stiffness [N/m] matrices (dense).
    static_load : ndarray, shape (n_dof,)
        Constant load [N].
    frequencies : ndarray, shape (n_freq,)
        Distinct positive circular frequencies of the harmonic loads [rad/s].
    cos_loads, sin_loads : ndarray, shape (n_freq, n_dof)
        Cosine and sine load amplitudes [N] at each frequency.
    tangent : ndarray, shape (n_dof, n_contacts)
        Constant tangential directions ``W_T``.
    normal_load : ndarray, shape (n_contacts,)
        Normal loads [N] (>= 0).
    """

    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    static_load: np.ndarray
    frequencies: np.ndarray
    cos_loads: np.ndarray
    sin_loads: np.ndarray
    tangent: np.ndarray
    normal_load: np.ndarray

    def __post_init__(self):
        stack = np.column_stack([self.static_load, np.asarray(self.cos_loads).T,
                                 np.asarray(self.sin_loads).T])
        object.__setattr__(self, "_stack", stack)

    def load(self, t):
        """External load [N] at time(s) ``t``: shape (n_dof,) or (n_dof, n_t) for an array."""
        if np.ndim(t) == 0:
            wt = self.frequencies * float(t)
            return self._stack @ np.concatenate([[1.0], np.cos(wt), np.sin(wt)])
        wt = np.multiply.outer(self.frequencies, np.asarray(t, dtype=float))
        basis = np.concatenate([np.ones((1,) + wt.shape[1:]), np.cos(wt), np.sin(wt)])
        return self._stack @ basis


class ConstrainedSystem(abc.ABC):
    """Protocol of a mechanical system with stick-slip contacts (see the module docstring).

    Subclasses set the attributes below and implement :meth:`mass`, :meth:`h`,
    :meth:`tangent_jacobian` and :meth:`tangent_wbar`; contacts with a constrained normal
    also need :meth:`normal_gap`, :meth:`normal_jacobian` and :meth:`normal_wbar`. The energy
    hooks (:meth:`potential_energy`, :meth:`input_power`, :meth:`viscous_power`) are optional:
    without them the solver reports NaN for those energy terms.

    Attributes
    ----------
    n_dof : int
        Number of generalised coordinates.
    n_contacts : int
        Number of friction contacts.
    mu_static, mu_sliding : ndarray, shape (n_contacts,)
        Static and sliding friction coefficients, ``0 <= mu_sliding <= mu_static``.
    normal_constrained : ndarray of bool, shape (n_contacts,)
        True where the normal force is a Lagrange multiplier of ``g_N(q) = 0``.
    constant_mass : bool
        True when :meth:`mass` does not depend on q (its factorisation is then cached).
    """

    n_dof: int
    n_contacts: int
    mu_static: np.ndarray
    mu_sliding: np.ndarray
    normal_constrained: np.ndarray
    constant_mass: bool = False

    # ----------------------------------------------------------------- required
    @abc.abstractmethod
    def mass(self, q: np.ndarray) -> np.ndarray:
        """Mass matrix [kg] at ``q``, shape (n_dof, n_dof), symmetric positive definite."""

    @abc.abstractmethod
    def h(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """All non-constraint generalised forces [N] (external, elastic, damping, gyroscopic,
        quadratic velocity terms), shape (n_dof,)."""

    @abc.abstractmethod
    def tangent_jacobian(self, q: np.ndarray) -> np.ndarray:
        """``W_T(q)``, shape (n_dof, n_contacts): ``gamma_T = W_T^T q'`` [m/s]."""

    @abc.abstractmethod
    def tangent_wbar(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """``wbar_T = (dW_T/dt)^T q'`` [m/s^2], shape (n_contacts,)."""

    # ----------------------------------------------------------------- normal constraints
    def normal_gap(self, q: np.ndarray) -> np.ndarray:
        """Normal gaps ``g_N(q)`` [m], shape (n_contacts,) (0 for prescribed contacts)."""
        return np.zeros(self.n_contacts)

    def normal_jacobian(self, q: np.ndarray) -> np.ndarray:
        """``W_N(q) = (dg_N/dq)^T``, shape (n_dof, n_contacts) (columns of prescribed
        contacts are ignored)."""
        return np.zeros((self.n_dof, self.n_contacts))

    def normal_wbar(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """``wbar_N = (dW_N/dt)^T q'`` [m/s^2], shape (n_contacts,)."""
        return np.zeros(self.n_contacts)

    def unilateral_contacts(self) -> np.ndarray:
        """True where a constrained normal contact may open (lift-off when its normal force
        reaches zero) and close again by an impact, shape (n_contacts,) of bool. Default: no
        contact (bilateral constraints). Its gap ``g_N`` must then be the signed distance,
        positive when open, with ``W_N = (dg_N/dq)^T`` also away from contact."""
        return np.zeros(self.n_contacts, dtype=bool)

    def restitution_coefficients(self) -> np.ndarray:
        """Newton's restitution coefficients ``e`` in [0, 1] of the unilateral contacts,
        shape (n_contacts,): ``gamma_N+ = -e gamma_N-`` at an impact (0: plastic)."""
        return np.zeros(self.n_contacts)

    def prescribed_normal_load(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Normal loads [N] of the contacts whose normal is not constrained, (n_contacts,)."""
        return np.zeros(self.n_contacts)

    def kinematics(self, q: np.ndarray, qd: np.ndarray):
        """``(W_N, W_T, wbar_N, wbar_T)`` at (q, q'); override to share work between them."""
        return (self.normal_jacobian(q), self.tangent_jacobian(q), self.normal_wbar(q, qd),
                self.tangent_wbar(q, qd))

    # ----------------------------------------------------------------- energy hooks
    def potential_energy(self, q: np.ndarray) -> float:
        """Potential (strain + gravity) energy [J] at q; NaN if unknown."""
        return float("nan")

    def input_power(self, t: float, q: np.ndarray, qd: np.ndarray) -> float:
        """Power [W] of the external (non-conservative, non-dissipative) loads; NaN if unknown."""
        return float("nan")

    def viscous_power(self, t: float, q: np.ndarray, qd: np.ndarray) -> float:
        """Power [W] dissipated by viscous damping (>= 0); NaN if unknown."""
        return float("nan")

    # ----------------------------------------------------------------- optional
    def max_frequency(self) -> float:
        """Largest circular frequency [rad/s] of the explicit time dependence of ``h`` and of
        the prescribed normal loads (0 if none or unknown). The DOP853 phases limit their
        step to a quarter of the corresponding half period so that no event between two
        samples is missed while the state itself barely moves (e.g. all contacts stuck)."""
        return 0.0

    def linear_form(self) -> LinearForm | None:
        """The system's :class:`LinearForm` when it has one (exact phase integration)."""
        return None

    def compiled_kernels(self):
        """Compiled configuration kernels for DOP853 phases, or None (the generic path).

        An object with ``rhs(t, y, modes, sigma, out) -> ratio`` (fills ``out`` (2 n_dof + 3,)
        with ``[q', q'', input power, viscous power, friction power]``),
        ``solve_many(ts, Y, modes, sigma) -> (ratio, qdd, lambda_N, lambda_T, W_T)`` (columns
        of Y are states, outputs (n_dof, n_t), (n_c, n_t), (n_c, n_t), (n_dof, n_c, n_t)) and
        ``events_many(ts, Y, modes, sigma, kinds, contacts, lim, sgn, vel) -> (ratio, G, S)``
        (event functions and scales of :class:`~fricdamp.solvers.event_phase.NumericalPhase`,
        (n_ev, n_t)), all with the equations of the generic path; ``ratio`` is the smallest
        pivot ratio of the constraint solves: at or below ``SINGULAR`` the phase falls back
        to the generic path (minimum-norm multipliers of redundant constraints).
        """
        return None

    @property
    def dof_names(self) -> tuple[str, ...]:
        return tuple(f"q{i + 1}" for i in range(self.n_dof))

    @property
    def contact_names(self) -> tuple[str, ...]:
        return tuple(f"contact{i}" for i in range(self.n_contacts))

    def check(self) -> None:
        """Validate sizes and friction coefficients; raise ModelError naming the problem."""
        n, nc = int(self.n_dof), int(self.n_contacts)
        if n < 1:
            raise ModelError(f"n_dof must be >= 1, got {n}")
        if nc < 0:
            raise ModelError(f"n_contacts must be >= 0, got {nc}")
        for name in ("mu_static", "mu_sliding"):
            mu = np.asarray(getattr(self, name), dtype=float)
            if mu.shape != (nc,) or not np.all(np.isfinite(mu)) or np.any(mu < 0):
                raise ModelError(f"{name} must hold {nc} finite values >= 0, got {mu!r}")
        if np.any(np.asarray(self.mu_sliding) > np.asarray(self.mu_static) * (1 + 1e-12)):
            raise ModelError(
                "mu_sliding must not exceed mu_static (0 <= mu_sliding <= mu_static): a "
                "friction force that rises when slip starts has no consistent stick-slip switch")
        nc_mask = np.asarray(self.normal_constrained, dtype=bool)
        if nc_mask.shape != (nc,):
            raise ModelError(f"normal_constrained must be a boolean array of length {nc}")
        uni = np.asarray(self.unilateral_contacts(), dtype=bool)
        if uni.shape != (nc,):
            raise ModelError(f"unilateral_contacts() must return {nc} booleans, got {uni!r}")
        if np.any(uni & ~nc_mask):
            raise ModelError("a unilateral contact needs a constrained normal (normal_constrained "
                             f"true): contacts {np.flatnonzero(uni & ~nc_mask).tolist()}")
        e = np.asarray(self.restitution_coefficients(), dtype=float)
        if e.shape != (nc,) or not np.all(np.isfinite(e)) or np.any((e < 0) | (e > 1)):
            raise ModelError(f"restitution coefficients must be {nc} values in [0, 1], got "
                             f"{e!r}")
        if nc_mask.any() and type(self).normal_jacobian is ConstrainedSystem.normal_jacobian:
            raise ModelError(
                f"{type(self).__name__} has contacts with a constrained normal but does not "
                "implement normal_gap / normal_jacobian / normal_wbar")


def _dense(A) -> np.ndarray:
    return A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)


@dataclass(frozen=True, eq=False)
class CoulombSystem(ConstrainedSystem):
    """Linear structure with 1D Coulomb friction contacts at fixed normal loads.

    ``M q'' + D q' + K q = F(t) + sum_i w_i lambda_T,i`` with ``|lambda_T,i| <= mu_static,i N_i``
    in stick (``w_i . q' = 0``) and ``lambda_T,i = -mu_sliding,i N_i sign(w_i . q')`` in slip.

    Parameters
    ----------
    system : MechanicalSystem
        The linear structure (M, D, K, static load and loads). It must have no contact
        elements (their laws belong to the time-stepping solver) and no unevaluated rotation
        terms (use ``system.at_speed(omega)``).
    directions : array_like, shape (n_contacts, n_dof) or (n_dof,)
        Tangential direction ``w_i`` of each contact: ``gamma_T,i = w_i . q'`` is its slip
        velocity [m/s] and the friction force acts on the DOFs as ``w_i lambda_T,i``.
    normal_load : float or array_like, shape (n_contacts,)
        Normal load ``N_i`` [N], >= 0.
    mu_static : float or array_like, shape (n_contacts,)
        Static friction coefficient [-], >= 0.
    mu_sliding : float or array_like, optional
        Sliding friction coefficient [-], ``0 <= mu_sliding <= mu_static``; defaults to
        ``mu_static``.
    contact_names : sequence of str, optional
        Labels for results (default ``contact0``, ``contact1``, ...).

    Examples
    --------
    den Hartog's oscillator ``x'' + x + 0.3 sgn(x') = cos(0.8 t)``:

    >>> import numpy as np
    >>> from fricdamp.structure.system import MechanicalSystem, HarmonicLoad
    >>> s = MechanicalSystem(M=[[1.0]], K=[[1.0]], loads=(HarmonicLoad([1.0], 0.8),))
    >>> cs = CoulombSystem(s, directions=[1.0], normal_load=0.3, mu_static=1.0)
    >>> cs.n_contacts, cs.linear_form().frequencies
    (1, array([0.8]))
    """

    system: MechanicalSystem
    directions: np.ndarray
    normal_load: np.ndarray
    mu_static: np.ndarray
    mu_sliding: np.ndarray | None = None
    contact_names: tuple[str, ...] | None = None  # type: ignore[assignment]
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    constant_mass = True

    def __post_init__(self):
        s = self.system
        if not isinstance(s, MechanicalSystem):
            raise ModelError(f"system must be a MechanicalSystem, got {type(s).__name__}")
        if s.contacts:
            raise ModelError(
                "CoulombSystem: the MechanicalSystem must have no contact elements (the "
                "event-driven solver handles only the Coulomb contacts given by `directions`); "
                "use fricdamp.solvers.simulate for contact laws")
        if s.rotation is not None:
            raise ModelError("CoulombSystem: evaluate the rotation terms first with "
                             "system.at_speed(omega)")
        n = s.n_dof
        W = as_finite_array("directions", self.directions)
        if W.ndim == 1:
            W = W.reshape(1, -1)
        if W.ndim != 2 or W.shape[1] != n:
            raise ModelError(f"directions must have shape (n_contacts, {n}), got {W.shape}")
        nc = W.shape[0]
        if np.any(np.linalg.norm(W, axis=1) == 0):
            raise ModelError("directions: every contact needs a non-zero direction vector w")

        def per_contact(name, value, default=None):
            if value is None:
                value = default
            arr = as_finite_array(name, value)
            if arr.ndim == 0:
                arr = np.full(nc, float(arr))
            if arr.shape != (nc,):
                raise ModelError(f"{name} must be a scalar or have {nc} entries, got {arr.shape}")
            if np.any(arr < 0):
                raise ModelError(f"{name} must be >= 0, got {value!r}")
            return arr

        N = per_contact("normal_load", self.normal_load)
        mus = per_contact("mu_static", self.mu_static)
        mud = per_contact("mu_sliding", self.mu_sliding, mus)
        object.__setattr__(self, "directions", W)
        object.__setattr__(self, "normal_load", N)
        object.__setattr__(self, "mu_static", mus)
        object.__setattr__(self, "mu_sliding", mud)
        if self.contact_names is None:
            names = tuple(f"contact{i}" for i in range(nc))
        else:
            names = tuple(str(c) for c in self.contact_names)
            if len(names) != nc:
                raise ModelError(f"contact_names has {len(names)} names for {nc} contacts")
        object.__setattr__(self, "contact_names", names)
        self._cache["M"] = _dense(s.M)
        self._cache["D"] = _dense(s.D)
        self._cache["K"] = _dense(s.K)
        self._cache["WT"] = np.ascontiguousarray(W.T)
        self.check()

    # ----------------------------------------------------------------- protocol
    @property
    def n_dof(self) -> int:  # type: ignore[override]
        return self.system.n_dof

    @property
    def n_contacts(self) -> int:  # type: ignore[override]
        return self.directions.shape[0]

    @property
    def normal_constrained(self) -> np.ndarray:  # type: ignore[override]
        return np.zeros(self.n_contacts, dtype=bool)

    @property
    def dof_names(self) -> tuple[str, ...]:
        return self.system.names

    def mass(self, q):
        return self._cache["M"]

    def h(self, t, q, qd):
        c = self._cache
        return self.system.external_force(t) - c["D"] @ qd - c["K"] @ q

    def tangent_jacobian(self, q):
        return self._cache["WT"]

    def tangent_wbar(self, q, qd):
        return np.zeros(self.n_contacts)

    def prescribed_normal_load(self, t, q, qd):
        return self.normal_load

    def potential_energy(self, q):
        return 0.5 * float(q @ (self._cache["K"] @ q))

    def input_power(self, t, q, qd):
        return float(self.system.external_force(t) @ qd)

    def viscous_power(self, t, q, qd):
        return float(qd @ (self._cache["D"] @ qd))

    def max_frequency(self) -> float:
        w = [ld.harmonic * ld.omega for ld in self.system.loads if isinstance(ld, HarmonicLoad)]
        return float(max(w, default=0.0))

    def linear_form(self) -> LinearForm | None:
        """The LinearForm, or None when a load is not harmonic (e.g. a TimeLoad)."""
        if "linear" in self._cache:
            return self._cache["linear"]
        s = self.system
        n = s.n_dof
        static = np.array(s.static_load, dtype=float)
        freqs: list[float] = []
        cos_l: list[np.ndarray] = []
        sin_l: list[np.ndarray] = []
        form = None
        if all(isinstance(ld, HarmonicLoad) for ld in s.loads):
            for ld in s.loads:
                w = ld.harmonic * ld.omega
                a, b = ld.amplitude.real, -ld.amplitude.imag  # Re(A e^{iwt}) = a cos + b sin
                if w == 0:
                    static += a
                    continue
                for k, wk in enumerate(freqs):
                    if abs(wk - w) <= 1e-14 * w:
                        cos_l[k] = cos_l[k] + a
                        sin_l[k] = sin_l[k] + b
                        break
                else:
                    freqs.append(w)
                    cos_l.append(a.copy())
                    sin_l.append(b.copy())
            c = self._cache
            form = LinearForm(
                M=c["M"], D=c["D"], K=c["K"], static_load=static,
                frequencies=np.array(freqs, dtype=float),
                cos_loads=np.array(cos_l, dtype=float).reshape(len(freqs), n),
                sin_loads=np.array(sin_l, dtype=float).reshape(len(freqs), n),
                tangent=c["WT"], normal_load=self.normal_load)
        self._cache["linear"] = form
        return form
