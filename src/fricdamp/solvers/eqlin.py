"""Equivalent linearisation: steady harmonic response with amplitude-dependent damping.

The steady response ``q(t) = Re(q~ e^{i w t})`` of a linear structure whose friction
contacts are replaced by equivalent viscous dampers (paper 001 section 3) solves

    (Z(w) + P^T (K_eq(s~) + i w C(s~)) P) q~ = F~,      s~ = P q~,

with ``Z = K - w^2 M + i w D`` the dynamic stiffness of the linear part (gyroscopic terms
included in D), P the projection on the m contact coordinates, and C(s~) the equivalent
damping (m x m, symmetric) built from the contact orbits (:mod:`fricdamp.contact.equivalent`);
``K_eq`` an optional equivalent stiffness of the contacts (0 for the paper's law; the stick
spring of a Jenkins element otherwise, so that a stuck contact is a spring, not a damper).
Since C acts on the contact coordinates only, the problem is condensed once per frequency,

    q~ = X0 - X_P H s~,   X0 = Z^{-1} F~,   X_P = Z^{-1} P^T,   H = K_eq + i w C,
    (I + R H) s~ = s_lin,  R = P X_P,  s_lin = P X0,

and the fixed point ``s~ = S(s~)`` (the orbits reproduce the damping they were built from)
is iterated on m unknowns, vectorised over a batch of frequencies/speeds:

    s_{n+1} = s_n + r_n (S(s_n) - s_n),

starting (as 001 section 4.1 does) from the response without friction damping. The
relaxation r_n is either fixed or adapted by Aitken's Delta^2 rule for vectors (Irons and
Tuck; Kuettler and Wall 2008), ``r_n = -r_{n-1} <D_{n-1}, D_n - D_{n-1}> / |D_n - D_{n-1}|^2``
with ``D_n = S(s_n) - s_n``, computed per group g of contact coordinates (e.g. each
contact's slip and rotation) and clipped to [min_relaxation, max_relaxation]. Convergence:
``|D_g| / (1 - rho_g) <= tol |S(s)_g| + atol_g`` for every group, with the observed
contraction ``rho_g`` of successive changes (capped at 0.99) turning the last change into
an estimate of the distance to the fixed point: a small orbit is not judged against a
large one, a stuck contact (orbit tending to zero) against an absolute floor, and a slowly
converging group (a contact at the threshold of sticking) not by its small steps alone.
Points that the relaxed iteration has not settled after ``fixed_point_iter`` iterations
are finished by Newton's method on ``F(s) = S(s) - s`` (finite-difference Jacobian in the
real and imaginary parts, backtracking on the relative residual
``sum_g (|F_g| / (|S_g| + atol_g))^2``; a relaxed fixed-point step where no descent is
found).

The returned state is ``S(s_n)`` with the damping ``C(s_n)`` it was computed with, so
it satisfies the linear equations exactly and the energy balance per cycle

    W_in = -pi Im(F~^H q~) = pi w q~^H D_sym q~ + pi w s~^H C s~ = W_visc + W_eq

holds to rounding (checked and reported; it fails if the dissipation matrix does not match
the dynamic stiffness, e.g. a damping term missing from one of them).

References
----------
Caughey (1963), J. Acoust. Soc. Am. 35, 1706-1711 (equivalent linearisation).
Kuettler & Wall (2008), Comput. Mech. 43, 61-72 (Aitken relaxation of fixed points).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from fricdamp.errors import ConvergenceError, ModelError, as_finite_array
from fricdamp.results import ResultMixin

__all__ = [
    "CondensedSystem",
    "EqLinResult",
    "EquivalentDamping",
    "condense",
    "dynamic_stiffness",
    "equivalent_linearisation",
]

logger = logging.getLogger(__name__)


class EquivalentDamping(Protocol):
    """What the solver needs from a damping model (e.g. EllipseFrictionDamping).

    ``matrix(s, omega, batch_index)`` returns the real symmetric damping matrices
    (n_b, m, m) for contact coordinates s (n_b, m) at frequencies omega (n_b,);
    ``batch_index`` (n_b,) are the batch points they belong to. ``groups`` (m,) optional:
    convergence groups of the coordinates. ``stiffness(s, omega, batch_index)`` optional:
    real symmetric equivalent stiffness matrices (n_b, m, m) [N/m] of the same contacts
    (e.g. the stick spring of a Jenkins element); the contact impedance is then
    ``K_eq + i w C``.
    """

    def matrix(self, s: np.ndarray, omega: np.ndarray,
               batch_index: np.ndarray) -> np.ndarray: ...


def dynamic_stiffness(M, D, K, omega) -> np.ndarray:
    """``Z(w) = K - w^2 M + i w D`` for a batch of frequencies, shape (n_b, n, n).

    Parameters
    ----------
    M, D, K : array_like, shape (n, n) or (n_b, n, n)
        Mass [kg], damping [N s/m] (may hold a skew gyroscopic part) and stiffness [N/m].
    omega : array_like, shape (n_b,)
        Angular frequencies [rad/s].
    """
    w = np.atleast_1d(as_finite_array("omega", omega))
    M = np.asarray(M, float)
    D = np.asarray(D, float)
    K = np.asarray(K, float)
    ww = w[:, None, None]
    return K - ww**2 * M + 1j * ww * D


@dataclass(frozen=True, eq=False)
class CondensedSystem:
    """Linear part condensed on the contact coordinates (see the module docstring).

    Attributes
    ----------
    omega : ndarray, shape (n_b,)
        Angular frequencies [rad/s].
    force : ndarray of complex, shape (n_b, n)
        Load amplitudes F~ [N].
    projection : ndarray, shape (m, n)
        Contact coordinates ``s = P q``.
    free_response : ndarray of complex, shape (n_b, n)
        ``X0 = Z^{-1} F~``: the response without equivalent damping [m].
    influence : ndarray of complex, shape (n_b, n, m)
        ``X_P = Z^{-1} P^T`` [m/N].
    receptance : ndarray of complex, shape (n_b, m, m)
        ``R = P Z^{-1} P^T`` [m/N].
    contact_free : ndarray of complex, shape (n_b, m)
        ``s_lin = P X0`` [m].
    dissipation_matrix : ndarray, shape (n, n) or (n_b, n, n), or None
        Viscous damping D of the linear part for the energy balance [N s/m].
    dynamic_stiffness : ndarray of complex, shape (n_b, n, n)
        Z itself (the final response is solved with it, see
        :func:`equivalent_linearisation`).
    """

    omega: np.ndarray
    force: np.ndarray
    projection: np.ndarray
    free_response: np.ndarray
    influence: np.ndarray
    receptance: np.ndarray
    contact_free: np.ndarray
    dissipation_matrix: np.ndarray | None = None
    dynamic_stiffness: np.ndarray | None = None

    @property
    def n_batch(self) -> int:
        return int(self.omega.size)


def condense(dynamic_stiffness_matrix, force, projection, omega, *,
             dissipation_matrix=None) -> CondensedSystem:
    """Factorise ``Z`` once per frequency and condense on the contact coordinates.

    Parameters
    ----------
    dynamic_stiffness_matrix : array_like of complex, shape (n_b, n, n)
        ``Z(w)`` at each batch point (:func:`dynamic_stiffness`).
    force : array_like of complex, shape (n,) or (n_b, n)
        Load amplitudes F~ [N] (``F(t) = Re(F~ e^{i w t})``).
    projection : array_like, shape (m, n)
        Contact coordinates ``s = P q``.
    omega : array_like, shape (n_b,)
        Angular frequencies [rad/s], > 0.
    dissipation_matrix : array_like, shape (n, n) or (n_b, n, n), optional
        The D of ``Z`` (for the energy balance check of the result).

    Returns
    -------
    CondensedSystem

    Raises
    ------
    ModelError
        Inconsistent shapes, non-positive omega, or a singular Z (an undamped resonance of
        the linear part, or a free body without damping).
    """
    Z = np.asarray(dynamic_stiffness_matrix, dtype=complex)
    if Z.ndim == 2:
        Z = Z[None]
    w = np.atleast_1d(as_finite_array("omega", omega))
    if Z.ndim != 3 or Z.shape[1] != Z.shape[2] or Z.shape[0] != w.size:
        raise ModelError(f"dynamic_stiffness_matrix must have shape (n_b, n, n) with n_b = "
                         f"len(omega) = {w.size}, got {Z.shape}")
    if np.any(w <= 0):
        raise ModelError("omega must be > 0 rad/s at every batch point")
    n = Z.shape[1]
    P = np.atleast_2d(as_finite_array("projection", projection))
    if P.shape[1] != n:
        raise ModelError(f"projection must have {n} columns, got shape {P.shape}")
    F = np.asarray(force, dtype=complex)
    F = np.broadcast_to(F, (w.size, n)) if F.ndim == 1 else F
    if F.shape != (w.size, n) or not np.all(np.isfinite(F)):
        raise ModelError(f"force must be finite with shape ({n},) or ({w.size}, {n})")
    rhs = np.concatenate([F[:, :, None], np.broadcast_to(P.T, (w.size, n, P.shape[0]))],
                         axis=2)
    try:
        X = np.linalg.solve(Z, rhs)
    except np.linalg.LinAlgError:
        raise ModelError("the dynamic stiffness Z(w) is singular at some frequency (an "
                         "undamped resonance or a free, undamped body): add damping or "
                         "move the frequency") from None
    if not np.all(np.isfinite(X)):
        raise ModelError("the dynamic stiffness Z(w) is singular or ill-conditioned at some "
                         "frequency")
    X0, XP = X[:, :, 0], X[:, :, 1:]
    Dm = None if dissipation_matrix is None else np.asarray(dissipation_matrix, float)
    return CondensedSystem(omega=w, force=np.ascontiguousarray(F), projection=P,
                           free_response=X0, influence=XP, receptance=P @ XP,
                           contact_free=X0 @ P.T, dissipation_matrix=Dm, dynamic_stiffness=Z)


@dataclass(frozen=True, eq=False, repr=False)
class EqLinResult(ResultMixin):
    """Consistent equivalent-linear steady states, one per batch point.

    Attributes
    ----------
    omega : ndarray, shape (n_b,)
        Angular frequencies [rad/s] (kept for compatibility: ``frequency_hz`` [Hz],
        ``omega_rad_s``).
    response : ndarray of complex, shape (n_b, n)
        q~ [m].
    contact_response : ndarray of complex, shape (n_b, m)
        s~ = P q~ (the orbits) [m].
    damping : ndarray, shape (n_b, m, m)
        The equivalent damping C the response was computed with [N s/m].
    stiffness : ndarray, shape (n_b, m, m), or None
        The equivalent stiffness K_eq it was computed with [N/m] (None: the damping model
        has none).
    iterations : ndarray of int, shape (n_b,)
        Iterations (fixed-point steps plus Newton steps).
    newton_iterations : ndarray of int, shape (n_b,)
        Of which Newton steps.
    converged : ndarray of bool, shape (n_b,)
    residual : ndarray, shape (n_b,)
        Last relative change ``max_g |S(s)_g - s_g| / |S(s)_g|``.
    external_work : ndarray, shape (n_b,)
        Work of the load per cycle ``-pi Im(F^H q)`` [J].
    viscous_dissipation : ndarray, shape (n_b,)
        ``pi w q^H D q`` [J] (NaN without a dissipation matrix).
    equivalent_dissipation : ndarray, shape (n_b, n_groups)
        ``pi w Re(s_g^H (C s)_g)`` per convergence group [J].
    energy_balance_error : ndarray, shape (n_b,)
        ``|W_in - W_out| / max(|W_in|, |W_out|)``, ``W_out = W_visc + sum W_eq``
        (NaN without D).
    message : str
    """

    omega: np.ndarray
    response: np.ndarray
    contact_response: np.ndarray
    damping: np.ndarray
    iterations: np.ndarray
    newton_iterations: np.ndarray
    converged: np.ndarray
    residual: np.ndarray
    external_work: np.ndarray
    viscous_dissipation: np.ndarray
    equivalent_dissipation: np.ndarray
    energy_balance_error: np.ndarray
    message: str = ""
    stiffness: np.ndarray | None = None

    @property
    def success(self) -> bool:
        """True when every batch point converged."""
        return bool(np.all(self.converged))

    @property
    def total_iterations(self) -> int:
        return int(self.iterations.sum())

    @property
    def frequency_hz(self) -> np.ndarray:
        """Frequencies [Hz], shape (n_b,)."""
        return self.omega / (2 * np.pi)

    @property
    def omega_rad_s(self) -> np.ndarray:
        """Angular frequencies [rad/s] (the same as ``omega``), shape (n_b,)."""
        return self.omega

    def _judge(self):
        """``unreliable`` when some batch points did not converge (their response is the
        last iterate), or when the energy balance exceeds its limit."""
        from fricdamp.results import status_verdict

        est = {"residual": float(np.max(self.residual)) if self.residual.size else None}
        if self.energy_balance_error.size and np.any(np.isfinite(self.energy_balance_error)):
            est["energy_balance_error"] = float(np.nanmax(self.energy_balance_error))
        bad = int(np.sum(~np.asarray(self.converged, bool)))
        reasons = () if bad == 0 else (
            f"{bad} of {self.converged.size} points did not converge ({self.message}): "
            "increase max_iter or use method='hybrid'",)
        return status_verdict(True, self.message, est, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` over the batch points: |q~| and its phase, contact orbits,
        energies per cycle and the convergence record."""
        import xarray as xr

        return xr.Dataset(
            {"response_abs": (("point", "dof"), np.abs(self.response), {"units": "m"}),
             "response_phase": (("point", "dof"), np.angle(self.response), {"units": "rad"}),
             "contact_response_real": (("point", "row"), self.contact_response.real,
                                       {"units": "m"}),
             "contact_response_imag": (("point", "row"), self.contact_response.imag,
                                       {"units": "m"}),
             "external_work": (("point",), self.external_work, {"units": "J"}),
             "viscous_dissipation": (("point",), self.viscous_dissipation, {"units": "J"}),
             "equivalent_dissipation": (("point", "group"), self.equivalent_dissipation,
                                        {"units": "J"}),
             "energy_balance_error": (("point",), self.energy_balance_error, {"units": "1"}),
             "residual": (("point",), self.residual, {"units": "1"}),
             "iterations": (("point",), self.iterations),
             "converged": (("point",), np.asarray(self.converged, bool))},
            coords={"frequency": ("point", self.frequency_hz, {"units": "Hz"}),
                    "omega": ("point", self.omega, {"units": "rad/s"})},
            attrs={"message": self.message})

    def plot(self, dof: int = 0, ax=None, **kwargs):
        """|q~| of ``dof`` [m] vs frequency [Hz] (non-converged points marked x); returns
        the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4), layout="constrained")
        a = np.abs(self.response[:, dof])
        ax.plot(self.frequency_hz, a, **kwargs)
        bad = ~np.asarray(self.converged, bool)
        if np.any(bad):
            ax.plot(self.frequency_hz[bad], a[bad], "x", color="C3", label="not converged")
            ax.legend(fontsize="small")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(f"amplitude of DOF {dof} [m]")
        ax.grid(alpha=0.3)
        return ax


def _group_norms(x: np.ndarray, groups: np.ndarray, n_groups: int) -> np.ndarray:
    sq = np.abs(x) ** 2
    out = np.zeros(x.shape[:-1] + (n_groups,))
    for g in range(n_groups):
        out[..., g] = sq[..., groups == g].sum(axis=-1)
    return np.sqrt(out)


def equivalent_linearisation(system: CondensedSystem, damping, *, tol: float = 1e-8,
                             atol=None, max_iter: int = 2000,
                             relaxation: float = 0.7, acceleration: str = "aitken",
                             min_relaxation: float = 0.05, max_relaxation: float = 4.0,
                             method: str = "hybrid", fixed_point_iter: int = 20,
                             newton_iter: int = 20,
                             initial=None, throw: bool = False) -> EqLinResult:
    """Fixed point of the equivalent damping and the steady response (module docstring).

    Parameters
    ----------
    system : CondensedSystem
        From :func:`condense` (reusable for several damping models, e.g. friction
        coefficients).
    damping : EquivalentDamping or callable
        ``damping.matrix(s, omega, batch_index) -> (n_b, m, m)``, or a function with that
        signature; ``damping.groups`` (m,) ints, optional.
    tol : float
        Relative tolerance on the (estimated) distance of the contact coordinates to the
        fixed point, per group.
    atol : float or array_like, shape (n_groups,), optional
        Absolute tolerance per group (in the units of the group's coordinates): a group
        has converged when ``|D_g| / (1 - rho_g) <= tol |S(s)_g| + atol_g`` (module
        docstring). Default ``damping.atol`` if the model has it (e.g. the slip floor below
        which a contact counts as stuck), else 0.
    max_iter : int
        Largest number of iterations (fixed-point and Newton steps) per batch point.
    relaxation : float
        Initial (and, with ``acceleration="none"``, fixed) relaxation factor in (0, 1].
    acceleration : {"aitken", "none"}
        Aitken's dynamic relaxation or a fixed factor.
    min_relaxation, max_relaxation : float
        Bounds of the Aitken factor.
    method : {"hybrid", "fixed_point", "newton"}
        ``hybrid``: ``fixed_point_iter`` relaxed fixed-point iterations, then up to
        ``newton_iter`` Newton steps for the points not yet converged, then relaxation
        again; ``fixed_point``: relaxation only; ``newton``: one fixed-point step, then
        Newton.
    fixed_point_iter : int
        Fixed-point iterations before Newton takes over (hybrid).
    newton_iter : int
        Newton steps allowed per point (hybrid); a point not converged by then goes back
        to its fixed-point iterate at the hand-over and continues with relaxation.
    initial : array_like of complex, shape (n_b, m), optional
        Starting contact coordinates (default: the response without equivalent damping).
    throw : bool
        Raise ConvergenceError if a batch point does not converge (else flag it).

    Returns
    -------
    EqLinResult

    Examples
    --------
    Single DOF with Coulomb friction (equivalent damping ``4 mu N / (pi w a)``): the
    amplitude is ``F sqrt(1 - (4 mu N / (pi F))^2) / |k - m w^2|``.

    >>> import numpy as np
    >>> Z = dynamic_stiffness([[1.0]], [[0.0]], [[1.0]], [0.5])
    >>> cs = condense(Z, [1.0], [[1.0]], [0.5], dissipation_matrix=[[0.0]])
    >>> def coulomb(s, w, idx):
    ...     return (4 * 0.3 / (np.pi * w * np.abs(s[:, 0])))[:, None, None]
    >>> res = equivalent_linearisation(cs, coulomb)
    >>> bool(np.isclose(abs(res.response[0, 0]), np.sqrt(1 - (1.2 / np.pi) ** 2) / 0.75))
    True
    """
    if not isinstance(system, CondensedSystem):
        raise ModelError(f"system must be a CondensedSystem (from condense), got "
                         f"{type(system).__name__}")
    if method not in ("hybrid", "fixed_point", "newton"):
        raise ModelError(f"method must be 'hybrid', 'fixed_point' or 'newton', got {method!r}")
    if acceleration not in ("aitken", "none"):
        raise ModelError(f"acceleration must be 'aitken' or 'none', got {acceleration!r}")
    if not 0 < relaxation <= 1:
        raise ModelError(f"relaxation must lie in (0, 1], got {relaxation!r}")
    if not 0 < min_relaxation <= max_relaxation:
        raise ModelError("need 0 < min_relaxation <= max_relaxation")
    if not tol > 0:
        raise ModelError(f"tol must be > 0, got {tol!r}")
    if int(max_iter) != max_iter or max_iter < 1:
        raise ModelError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    fn = damping.matrix if hasattr(damping, "matrix") else damping
    if not callable(fn):
        raise ModelError("damping must have a matrix(s, omega, batch_index) method or be "
                         "callable")
    nb, m = system.n_batch, system.projection.shape[0]
    groups = getattr(damping, "groups", None)
    groups = np.zeros(m, int) if groups is None else np.asarray(groups, int)
    if groups.shape != (m,) or groups.min() < 0:
        raise ModelError(f"damping.groups must hold {m} non-negative ints")
    n_groups = int(groups.max()) + 1
    atol_g = getattr(damping, "atol", None) if atol is None else atol
    atol_g = np.broadcast_to(np.asarray(0.0 if atol_g is None else atol_g, float),
                             (n_groups,)).copy()
    if not np.all(np.isfinite(atol_g)) or np.any(atol_g < 0):
        raise ModelError("atol must be >= 0 (scalar or one value per group)")
    w = system.omega
    R, s_lin = system.receptance, system.contact_free
    eye = np.eye(m)
    onehot = (groups[:, None] == np.arange(n_groups)[None, :]).astype(float)   # (m, G)
    lin_scale = np.maximum(_group_norms(s_lin, groups, n_groups), atol_g[None, :])
    lin_scale = np.where(lin_scale > 0, lin_scale, 1.0)                           # (nb, G)

    kfn = getattr(damping, "stiffness", None)
    kfn = kfn if callable(kfn) else None

    def damping_of(s, idx):
        C = np.asarray(fn(s, w[idx], idx), dtype=float)
        if C.shape != (idx.size, m, m) or not np.all(np.isfinite(C)):
            raise ModelError(f"damping matrix must be finite with shape ({idx.size}, {m}, "
                             f"{m}), got {C.shape}")
        return C

    def impedance(s, idx):
        """C(s) and the contact impedance H = K_eq(s) + i w C(s)."""
        C = damping_of(s, idx)
        Hm = 1j * w[idx, None, None] * C
        if kfn is not None:
            Kq = np.asarray(kfn(s, w[idx], idx), dtype=float)
            if Kq.shape != C.shape or not np.all(np.isfinite(Kq)):
                raise ModelError(f"stiffness matrix must be finite with shape {C.shape}, "
                                 f"got {Kq.shape}")
            Hm = Hm + Kq
        return C, Hm

    def fixed_point_map(s, idx):
        """C(s) and S(s): the response to the damping built from s."""
        C, Hm = impedance(s, idx)
        A = eye + R[idx] @ Hm
        return C, np.linalg.solve(A, s_lin[idx][:, :, None])[:, :, 0]

    def residual(s, idx):
        """Fixed-point residual ``F(s) = S(s) - s`` and its relative size per point.

        The size ``phi = sum_g (|F_g| / (|S(s)_g| + atol_g))^2`` is the merit function of
        the Newton line search (a function of s alone, measured like the convergence test).
        """
        S = fixed_point_map(s, idx)[1]
        F = S - s
        rel = _group_norms(F, groups, n_groups) / (_group_norms(S, groups, n_groups)
                                                    + np.maximum(atol_g, 1e-300))
        return F, np.sum(rel**2, axis=1)

    prev_change = np.full((nb, n_groups), np.nan)

    def check(s, idx):
        """Convergence test of s; returns C(s), S(s), the change and the error estimate.

        The distance to the fixed point is estimated from the change ``|D_g|`` and the
        observed contraction ``rho_g = |D_g| / |D_g,prev|`` as ``|D_g| / (1 - rho_g)``
        (rho capped at 0.99), so that a slowly converging group (a contact at the
        threshold of sticking) is not declared converged by a small step alone.
        """
        C, s_new = fixed_point_map(s, idx)
        d = s_new - s
        change = _group_norms(d, groups, n_groups)
        with np.errstate(invalid="ignore", divide="ignore"):
            rho = np.where(prev_change[idx] > 0, change / prev_change[idx], 0.0)
        rho = np.clip(np.nan_to_num(rho, nan=0.0), 0.0, 0.99)
        prev_change[idx] = change
        est = change / (1.0 - rho)
        err = (np.maximum(est - atol_g, 0.0)
               / np.maximum(_group_norms(s_new, groups, n_groups), 1e-300)).max(axis=1)
        return C, s_new, d, err

    s = s_lin.copy() if initial is None else np.array(initial, dtype=complex)
    if s.shape != (nb, m):
        raise ModelError(f"initial must have shape ({nb}, {m}), got {s.shape}")
    s_out = np.zeros((nb, m), complex)
    C_out = np.zeros((nb, m, m))
    iters = np.zeros(nb, int)
    newton_iters = np.zeros(nb, int)
    conv = np.zeros(nb, bool)
    resid = np.full(nb, np.inf)

    def record(idx, C, s_new, err):
        iters[idx] += 1
        resid[idx] = err
        s_out[idx] = s_new
        C_out[idx] = C
        done = err <= tol
        conv[idx[done]] = True
        return done

    r = np.full((nb, n_groups), float(relaxation))
    d_prev = np.zeros((nb, m), complex)
    have_prev = np.zeros(nb, bool)

    def fixed_point_step(idx):
        """One relaxed (Aitken per group) fixed-point step; returns the converged mask."""
        C, s_new, d, err = check(s[idx], idx)
        done = record(idx, C, s_new, err)
        if acceleration == "aitken":
            dd = d - d_prev[idx]
            num = np.real(np.conj(d_prev[idx]) * dd) @ onehot                # (na, G)
            den = (np.abs(dd) ** 2) @ onehot
            ok = have_prev[idx][:, None] & (den > 0)
            rr = r[idx]
            rr[ok] = np.clip(-rr[ok] * num[ok] / den[ok], min_relaxation, max_relaxation)
            r[idx] = rr
            d_prev[idx] = d
            have_prev[idx] = True
        s[idx] = s[idx] + r[idx][:, groups] * d
        return done

    steps = 0.5 ** np.arange(7)
    pert = np.concatenate([np.eye(m), 1j * np.eye(m)])                         # (2m, m)

    def newton_step(idx):
        """One Newton step on F(s) = S(s) - s with backtracking; returns converged mask."""
        na = idx.size
        sa = s[idx]
        F0, phi0 = residual(sa, idx)
        h = 1e-7 * np.maximum(_group_norms(sa, groups, n_groups),
                              np.maximum(atol_g, 1e-7 * lin_scale[idx]))
        h = h[:, groups]                                                       # (na, m)
        trial = sa[:, None, :] + pert[None] * h[:, None, :]                    # (na, 2m, m)
        Fp, _ = residual(trial.reshape(-1, m), np.repeat(idx, 2 * m))
        dF = (Fp.reshape(na, 2 * m, m) - F0[:, None, :]) / np.concatenate(
            [h, h], axis=1)[:, :, None]
        J = np.concatenate([dF.real, dF.imag], axis=2).transpose(0, 2, 1)      # (na, 2m, 2m)
        rhs = -np.concatenate([F0.real, F0.imag], axis=1)
        try:
            dx = np.linalg.solve(J, rhs[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:         # a singular Jacobian somewhere: least squares
            dx = np.stack([np.linalg.lstsq(J[i], rhs[i], rcond=None)[0] for i in range(na)])
        ds = dx[:, :m] + 1j * dx[:, m:]
        cand = sa[:, None, :] + steps[None, :, None] * ds[:, None, :]         # (na, ns, m)
        _, phi = residual(cand.reshape(-1, m), np.repeat(idx, steps.size))
        phi = phi.reshape(na, steps.size)
        good = phi < (1.0 - 1e-4 * steps[None, :]) * phi0[:, None]
        first = np.argmax(good, axis=1)
        any_good = good.any(axis=1)
        s_new = sa + 0.5 * F0                # no descent: a relaxed fixed-point step
        s_new[any_good] = cand[any_good, first[any_good]]
        s[idx] = s_new
        newton_iters[idx] += 1
        C, S_new, _, err = check(s[idx], idx)
        return record(idx, C, S_new, err)

    # Each point: relaxed fixed point for fixed_point_iter iterations, then up to
    # newton_iter Newton steps; if Newton has not converged by then (a non-smooth point,
    # e.g. a contact switching between stick and slip), back to the fixed-point iterate
    # at the hand-over and on with the relaxed iteration until max_iter.
    n_fp = {"fixed_point": int(max_iter), "newton": 1}.get(method, int(fixed_point_iter))
    n_nt = 0 if method == "fixed_point" else (int(max_iter) if method == "newton"
                                              else int(newton_iter))
    mode = np.zeros(nb, int)                  # 0 fixed point, 1 Newton, 2 fixed point again
    handover = np.zeros((nb, m), complex)
    active = np.arange(nb)
    while active.size:
        fp = active[mode[active] != 1]
        nt = active[mode[active] == 1]
        done = np.zeros(nb, bool)
        if fp.size:
            done[fp[fixed_point_step(fp)]] = True
        if nt.size:
            done[nt[newton_step(nt)]] = True
        active = active[~done[active] & (iters[active] < max_iter)]
        to_newton = active[(mode[active] == 0) & (iters[active] >= n_fp) & (n_nt > 0)]
        mode[to_newton] = 1
        handover[to_newton] = s[to_newton]
        back = active[(mode[active] == 1) & (newton_iters[active] >= n_nt)]
        mode[back] = 2
        s[back] = handover[back]
        prev_change[back] = np.nan
    # Final response: solve (Z + P^T H P) q = F once. (The condensed form
    # q = X0 - X_P H s cancels catastrophically when a stuck contact's huge damping
    # nearly cancels the free response.)
    P = system.projection
    K_out = None
    H_out = 1j * w[:, None, None] * C_out
    if kfn is not None:
        # K_eq and C of the converged orbit (equal to those of the last iterate to the
        # tolerance); the response below is solved with exactly these, so the energy
        # balance holds to rounding
        K_out = np.asarray(kfn(s_out, w, np.arange(nb)), dtype=float)
        C_out = damping_of(s_out, np.arange(nb))
        H_out = K_out + 1j * w[:, None, None] * C_out
    if system.dynamic_stiffness is not None:
        Zt = system.dynamic_stiffness + np.einsum("mi,bmn,nj->bij", P, H_out, P)
        q = np.linalg.solve(Zt, system.force[:, :, None])[:, :, 0]
        s_out = q @ P.T
    else:
        q = (system.free_response
             - np.einsum("bnm,bm->bn", system.influence,
                         np.einsum("bij,bj->bi", H_out, s_out)))
    F = system.force
    W_in = -np.pi * np.imag(np.sum(np.conj(F) * q, axis=1))
    Cs = np.einsum("bij,bj->bi", C_out, s_out)
    per_row = np.pi * w[:, None] * np.real(np.conj(s_out) * Cs)
    W_eq = np.zeros((nb, n_groups))
    for g in range(n_groups):
        W_eq[:, g] = per_row[:, groups == g].sum(axis=1)
    if system.dissipation_matrix is not None:
        Dq = np.einsum("...ij,bj->bi", system.dissipation_matrix, q) if (
            system.dissipation_matrix.ndim == 2) else np.einsum(
            "bij,bj->bi", system.dissipation_matrix, q)
        W_visc = np.pi * w * np.real(np.sum(np.conj(q) * Dq, axis=1))
        W_out = W_visc + W_eq.sum(axis=1)
        scale = np.maximum(np.maximum(np.abs(W_in), np.abs(W_out)), 1e-300)
        err_bal = np.abs(W_in - W_out) / scale
    else:
        W_visc = np.full(nb, np.nan)
        err_bal = np.full(nb, np.nan)
    n_bad = int(np.sum(~conv))
    if n_bad:
        bad = np.flatnonzero(~conv)
        msg = (f"{n_bad} of {nb} points did not converge in {max_iter} iterations (first at "
               f"omega = {w[bad[0]]:.6g} rad/s, relative change {resid[bad[0]]:.3g}); the "
               "equivalent damping may have no fixed point there (friction unable to limit "
               "an undamped resonance): add damping, lower the load or raise max_iter")
        if throw:
            raise ConvergenceError(msg)
        logger.warning(msg)
    else:
        msg = (f"converged: {nb} points, {int(iters.sum())} iterations in all "
               f"({int(newton_iters.sum())} Newton)")
    return EqLinResult(omega=w, response=q, contact_response=s_out, damping=C_out,
                       iterations=iters, newton_iterations=newton_iters, converged=conv,
                       residual=resid, external_work=W_in,
                       viscous_dissipation=W_visc, equivalent_dissipation=W_eq,
                       energy_balance_error=err_bal, message=msg, stiffness=K_out)
