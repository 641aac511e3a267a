"""The contact-law protocol shared by every solver.

A contact law acts on ``n_contacts`` contacts at once. Each contact has ``n_dir`` local
relative displacement components (1 for a 1D slider; 3 for the "3D contact element":
normal, tangential 1, tangential 2) and ``n_state`` internal state variables (slider
positions, Masing turning points, ...). The state is explicit: a law never keeps hidden
history, so a Newton iteration can call :meth:`ContactLaw.step` repeatedly from the last
converged state and commit the new state only once it has converged.

Sign convention
---------------
``u`` is the relative displacement seen by the contact (``u = P q`` through the contact
element's projection matrix ``P``) and ``force`` is the force the contact *resists* it with,
so the equations of motion read ``M q'' + D q' + K q + P^T f(u) = F(t)``. A linear spring
of stiffness k is the law ``f = k u``. For normal directions ``u_n > 0`` means approach
(closing the gap, increasing interference) and ``f_n >= 0`` is compressive.

Shapes
------
``u``, ``v``, ``force``: ``(n_contacts, n_dir)``; ``stiffness`` and ``damping`` (the
consistent tangents dF/du and dF/dv): ``(n_contacts, n_dir, n_dir)``; ``state``:
``(n_contacts, n_state)``. Histories add a leading time axis ``(n_t, ...)``.
"""

from __future__ import annotations

import abc
from typing import NamedTuple

import numpy as np

from fricdamp.errors import ModelError, as_finite_array


class LawStep(NamedTuple):
    """What one return-map step gives.

    Attributes
    ----------
    force : ndarray, shape (n_contacts, n_dir)
        Contact force [N] (or moment [N m] for rotational laws).
    stiffness : ndarray, shape (n_contacts, n_dir, n_dir)
        Consistent tangent dF/du [N/m] of the return map from the given state.
    damping : ndarray or None, shape (n_contacts, n_dir, n_dir)
        dF/dv [N s/m]; ``None`` when the law does not depend on the velocity.
    state : ndarray, shape (n_contacts, n_state)
        The state after the step (commit it only once the step has converged).
    """

    force: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray | None
    state: np.ndarray


class PeriodicResponse(NamedTuple):
    """Steady periodic response of a law to one period of relative displacement samples.

    Attributes
    ----------
    force : ndarray, shape (n_t, n_contacts, n_dir)
        Force samples [N] over the periodic period (the last period marched).
    jacobian : ndarray or None, shape (n_t, n_contacts, n_dir, n_dir, n_basis)
        ``jacobian[i, c, d, e, j]`` = d force[i, c, d] / d x[c, e, j], the exact (or finite
        difference) derivative of the periodic force with respect to the coefficients x of
        the displacement history ``u[:, c, e] = basis @ x[c, e, :]`` (and, for velocity
        dependent laws, ``v[:, c, e] = velocity_basis @ x[c, e, :]``). ``None`` when no
        basis was given.
    state : ndarray, shape (n_contacts, n_state)
        State at the start (= end) of the periodic period.
    periods : int
        Number of periods marched (the largest over the contacts).
    converged : bool
        True when every contact's state repeated within the tolerance.
    """

    force: np.ndarray
    jacobian: np.ndarray | None
    state: np.ndarray
    periods: int
    converged: bool


class HarmonicResponse(NamedTuple):
    """Steady periodic response in harmonic coefficients (:meth:`ContactLaw.harmonic_response`).

    Attributes
    ----------
    force : ndarray, shape (..., n_contacts, n_dir, n_basis)
        Coefficients of the periodic force samples projected by the basis' analysis matrix
        (leading axes: those of the coefficients given).
    jacobian : ndarray or None, shape (..., n_contacts, n_dir n_basis, n_dir n_basis)
        d force coefficients / d displacement coefficients of each contact (row and column
        index ``d * n_basis + j``); None if not requested.
    u_time, force_time : ndarray, shape (n_t, ..., n_contacts, n_dir)
        Displacement and periodic force samples.
    state : ndarray, shape (..., n_contacts, n_state)
        State at the start (= end) of the periodic period.
    periods : int
    converged : bool
    """

    force: np.ndarray
    jacobian: np.ndarray | None
    u_time: np.ndarray
    force_time: np.ndarray
    state: np.ndarray
    periods: int
    converged: bool


class ContactLaw(abc.ABC):
    """Base class of all contact laws (see the module docstring for the protocol).

    Subclasses set ``n_dir``, ``n_state`` and ``n_contacts`` and implement
    :meth:`initial_state`, :meth:`step` and :meth:`stored_energy`. They may override
    :meth:`march` with a compiled kernel; the default marches :meth:`step` in Python.
    """

    n_dir: int = 1
    n_state: int = 1
    n_contacts: int = 1
    #: True when the force depends on the velocity (step needs ``v``).
    velocity_dependent: bool = False

    @abc.abstractmethod
    def initial_state(self) -> np.ndarray:
        """Virgin state, shape (n_contacts, n_state)."""

    @abc.abstractmethod
    def step(self, state: np.ndarray, u: np.ndarray, v: np.ndarray | None = None) -> LawStep:
        """Return map from ``state`` to the relative displacement ``u`` (and velocity ``v``)."""

    @abc.abstractmethod
    def stored_energy(self, state: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Elastic energy [J] stored in each contact at (state, u), shape (n_contacts,).

        ``state`` is the state *after* the step to ``u``. Used for energy balances:
        dissipated energy = work done on the contact - change of stored energy.
        """

    def dissipation(self, state_old: np.ndarray, state_new: np.ndarray,
                    force_new: np.ndarray) -> np.ndarray | None:
        """Energy [J] dissipated in each contact by a step, shape (n_contacts,), or None.

        Laws that know their dissipation mechanism (slider displacement times friction force)
        return it, so that energy balances check the solver instead of restating it; the
        default ``None`` tells solvers to use work done minus change of stored energy.
        """
        return None

    # ------------------------------------------------------------------ histories
    def march(self, u_history: np.ndarray, state: np.ndarray | None = None,
              v_history: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Drive the law along a history; return (force history, final state).

        Parameters
        ----------
        u_history : ndarray, shape (n_t, n_contacts, n_dir)
            Relative displacements [m].
        state : ndarray, shape (n_contacts, n_state), optional
            Starting state; the virgin state if omitted.
        v_history : ndarray, shape (n_t, n_contacts, n_dir), optional
            Relative velocities [m/s], needed by velocity-dependent laws.

        Returns
        -------
        force : ndarray, shape (n_t, n_contacts, n_dir)
        state : ndarray, shape (n_contacts, n_state)
        """
        u_history = np.asarray(u_history, dtype=float)
        st = self.initial_state() if state is None else np.array(state, dtype=float)
        out = np.empty_like(u_history)
        for i in range(u_history.shape[0]):
            v = None if v_history is None else v_history[i]
            res = self.step(st, u_history[i], v)
            out[i] = res.force
            st = res.state
        return out, st

    def periodic_response(self, u: np.ndarray, v: np.ndarray | None = None, *,
                          basis: np.ndarray | None = None,
                          velocity_basis: np.ndarray | None = None,
                          state: np.ndarray | None = None, max_periods: int = 50,
                          tol: float = 1e-10) -> PeriodicResponse:
        """Periodic force along a periodic displacement history (the AFT time march).

        The law is marched over the period, again and again, starting from ``state`` (the
        virgin state by default), until its state at the end of a period equals the state
        at its start: the forces of that last period are the steady periodic forces. This
        generic version marches :meth:`march` and differentiates by forward finite
        differences (one march per basis function and direction, all contacts perturbed at
        once since contacts are independent); laws with a known exact sensitivity override
        it (see :class:`fricdamp.contact.jenkins.Jenkins`).

        Parameters
        ----------
        u : ndarray, shape (n_t, n_contacts, n_dir)
            Relative displacement samples [m] over one period, equally spaced in time,
            without repeating the first sample at the end.
        v : ndarray, shape (n_t, n_contacts, n_dir), optional
            Relative velocities [m/s]; required by velocity-dependent laws.
        basis : ndarray, shape (n_t, n_basis), optional
            If given, the Jacobian with respect to coefficients ``x`` of
            ``u[:, c, e] = basis @ x[c, e, :]`` is returned too (for harmonic balance the
            basis holds 1, cos k tau, sin k tau sampled at the time samples).
        velocity_basis : ndarray, shape (n_t, n_basis), optional
            ``v[:, c, e] = velocity_basis @ x[c, e, :]`` (Omega times the tau-derivative of
            ``basis``); needed for the Jacobian of velocity-dependent laws.
        state : ndarray, shape (n_contacts, n_state), optional
            State at the start of the first period (the virgin state by default). The
            result is a deterministic function of (u, v, state), as Newton needs.
        max_periods : int
            Largest number of periods marched before giving up (``converged=False``).
        tol : float
            Periodicity test: ``max |state_end - state_start| <= tol * scale`` with
            ``scale`` the largest magnitude of the state.

        Returns
        -------
        PeriodicResponse
        """
        u = self._as_history(np.asarray(u, dtype=float), "u")
        v = None if v is None else self._as_history(np.asarray(v, dtype=float), "v")
        if self.velocity_dependent and v is None:
            raise ModelError(f"{type(self).__name__} is velocity dependent: pass v (the "
                             "relative velocity samples) to periodic_response")
        st0 = self.initial_state() if state is None else np.array(state, dtype=float)
        f, st, periods, conv = self._march_to_periodic(u, v, st0, max_periods, tol)
        jac = None
        if basis is not None:
            basis = np.asarray(basis, dtype=float)
            if basis.ndim != 2 or basis.shape[0] != u.shape[0]:
                raise ModelError(f"basis must have shape (n_t={u.shape[0]}, n_basis), got "
                                 f"{basis.shape}")
            vb = None
            if v is not None and velocity_basis is not None:
                vb = np.asarray(velocity_basis, dtype=float)
            jac = self._fd_periodic_jacobian(u, v, basis, vb, f, st0, periods)
        return PeriodicResponse(f, jac, st, periods, conv)

    def harmonic_response(self, coeffs: np.ndarray, synthesis: np.ndarray,
                          analysis: np.ndarray, *, jacobian: bool = True,
                          state: np.ndarray | None = None,
                          max_periods: int = 50) -> HarmonicResponse | None:
        """The AFT step in one call: coefficients in, force coefficients and Jacobian out.

        Optional: a rate-independent law with a compiled kernel for the whole step
        (synthesis of the samples, periodic march, projection of the force and of its exact
        sensitivity) overrides it; the default returns None and harmonic balance uses
        :meth:`periodic_response` with the projections done by the caller. The result must
        equal that route's to rounding.

        Parameters
        ----------
        coeffs : ndarray, shape (..., n_contacts, n_dir, n_basis)
            Coefficients of the relative displacements, ``u[:, c, d] = synthesis @
            coeffs[c, d]``; leading axes are independent copies of the contacts (e.g. the
            points of a frequency response), with the results shaped alike.
        synthesis : ndarray, shape (n_t, n_basis)
        analysis : ndarray, shape (n_basis, n_t)
            Projection of samples onto the coefficients.
        jacobian, state, max_periods
            As for :meth:`periodic_response` (``jacobian``: return the Jacobian).

        Returns
        -------
        HarmonicResponse or None
        """
        return None

    def _march_to_periodic(self, u, v, st0, max_periods, tol):
        st = st0
        for p in range(1, max(int(max_periods), 1) + 1):
            f, st_end = self.march(u, state=st, v_history=v)
            scale = max(float(np.max(np.abs(st_end), initial=0.0)),
                        float(np.max(np.abs(st), initial=0.0)))
            if np.max(np.abs(st_end - st), initial=0.0) <= tol * scale:
                return f, st, p, True
            st = st_end
        return f, st, int(max_periods), False

    def _march_periods(self, u, v, st0, n_periods):
        """Forces of the last of exactly ``n_periods`` marches from ``st0``."""
        st = st0
        for _ in range(n_periods):
            f, st = self.march(u, state=st, v_history=v)
        return f

    def _fd_periodic_jacobian(self, u, v, basis, vb, f0, st0, n_periods):
        """Forward finite differences of the periodic force, all contacts at once.

        Each perturbed history is marched from the same start state for exactly as many
        periods as the unperturbed one took to become periodic: the difference quotient is
        then that of one smooth map (a varying period count would add the periodicity
        tolerance divided by the step to it). For laws that become periodic in finitely
        many periods (Jenkins, Masing laws in gross slip) this is the derivative of the
        periodic force; for laws that only approach periodicity (2D friction on an
        elliptic orbit) it converges with the march.
        """
        n_t, nc, nd = u.shape
        m = basis.shape[1]
        umax = np.max(np.abs(u), axis=(0, 2))  # (nc,)
        floor = max(float(umax.max(initial=0.0)) * 1e-3, 1e-12)
        h = np.sqrt(np.finfo(float).eps) * np.maximum(umax, floor)  # (nc,)
        jac = np.zeros((n_t, nc, nd, nd, m))
        for e in range(nd):
            for j in range(m):
                up = u.copy()
                up[:, :, e] += basis[:, j, None] * h[None, :]
                vp = v
                if v is not None and vb is not None:
                    vp = v.copy()
                    vp[:, :, e] += vb[:, j, None] * h[None, :]
                fp = self._march_periods(up, vp, st0, n_periods)
                jac[:, :, :, e, j] = (fp - f0) / h[None, :, None]
        return jac

    def drive(self, u_history, v_history=None, state=None) -> np.ndarray:
        """Force history along a relative-displacement history, from the virgin state.

        Accepts ``u_history`` of shape ``(n_t,)`` (one contact, one direction),
        ``(n_t, n_contacts)`` (one direction) or ``(n_t, n_contacts, n_dir)``, and returns the
        force with the same shape. This is the three-line way to a hysteresis loop::

            u = 1e-5 * np.sin(np.linspace(0, 4 * np.pi, 400))
            f = Jenkins(stiffness=1e6, slip_force=5.0).drive(u)
            plt.plot(u, f)

        If ``v_history`` is omitted for a velocity-dependent law, it is estimated from
        ``u_history`` by finite differences with unit sample spacing, so pass it explicitly
        whenever the velocity matters.
        """
        u = as_finite_array("u_history", u_history)
        shape = u.shape
        u3 = self._as_history(u, "u_history")
        v3 = None
        if v_history is not None:
            v3 = self._as_history(as_finite_array("v_history", v_history), "v_history")
            if v3.shape != u3.shape:
                raise ModelError(
                    f"v_history must have the shape of u_history {shape}, got {np.shape(v_history)}"
                )
        elif self.velocity_dependent:
            v3 = np.gradient(u3, axis=0) if u3.shape[0] > 1 else np.zeros_like(u3)
        f, _ = self.march(u3, state=state, v_history=v3)
        return f.reshape(shape)

    def _as_history(self, u: np.ndarray, name: str) -> np.ndarray:
        nc, nd = self.n_contacts, self.n_dir
        if u.ndim == 1 and nc == 1 and nd == 1:
            return u.reshape(-1, 1, 1)
        if u.ndim == 2 and nd == 1 and u.shape[1] == nc:
            return u.reshape(u.shape[0], nc, 1)
        if u.ndim == 2 and nc == 1 and u.shape[1] == nd:
            return u.reshape(u.shape[0], 1, nd)
        if u.ndim == 3 and u.shape[1:] == (nc, nd):
            return u
        raise ModelError(
            f"{name} must have shape (n_t, {nc}, {nd}) for this {type(self).__name__} "
            f"({nc} contact(s), {nd} direction(s)), got {u.shape}"
        )

    def _check_u(self, u: np.ndarray) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n_contacts, self.n_dir):
            u = u.reshape(self.n_contacts, self.n_dir)
        return u


def broadcast_parameter(name: str, value, n_contacts: int | None, *, unit: str,
                        allow_zero: bool = False) -> np.ndarray:
    """Per-contact parameter array, checked finite and positive, shape (n_contacts,).

    The messages name the parameter, its unit and the allowed range, as the case file's
    schema does for the same key (``Positive`` / ``NonNegative``)."""
    rng = ">= 0" if allow_zero else "> 0"
    u = f" {unit}" if unit else ""
    if isinstance(value, (str, bytes)):
        raise ModelError(f"{name} must be a number {rng}{u}, got {value!r}")
    try:
        arr = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise ModelError(f"{name} must be a number {rng}{u} (or one per contact), got "
                         f"{value!r}") from None
    if arr.ndim != 1:
        raise ModelError(f"{name} must be a scalar or a 1-D array, got shape {arr.shape}")
    if arr.size == 0:
        raise ModelError(f"{name} must be a number {rng}{u} or a non-empty list, got []")
    if not np.all(np.isfinite(arr)):
        raise ModelError(f"{name} must be finite (no NaN or inf), got {value!r}")
    bad = arr < 0 if allow_zero else arr <= 0
    if np.any(bad):
        raise ModelError(f"{name} must be {rng}{u}, got {value!r}")
    if n_contacts is not None and arr.size not in (1, n_contacts):
        raise ModelError(f"{name} must be a scalar or have {n_contacts} entries, got {arr.size}")
    return arr


def common_size(**params: np.ndarray) -> int:
    """Number of contacts implied by per-contact parameter arrays (all sizes 1 or n)."""
    sizes = {a.size for a in params.values() if a.size != 1}
    if len(sizes) > 1:
        desc = ", ".join(f"{k}: {v.size}" for k, v in params.items())
        raise ModelError(f"per-contact parameters have inconsistent lengths ({desc})")
    return sizes.pop() if sizes else 1
