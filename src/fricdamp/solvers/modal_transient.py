"""Transients and statics of large reduced models with thousands of 3D friction contacts.

The linear part is given by its mass-normalised undamped modes (a :class:`ModalBasis`),
typically the *complete* eigenbasis of a reduced wheel obtained sector by sector through
cyclic symmetry (:func:`fricdamp.structure.cyclic_reduction.wheel_modes`), so no dense
eigenproblem of the whole wheel is ever solved. The contacts are
:class:`~fricdamp.contact.element3d.Contact3D` elements, each a patch of node pairs
(:mod:`fricdamp.structure.contact_patch`), whose relative displacements are the rows
``u = B eta`` of the basis.

Scheme (the discrete equations of :func:`fricdamp.solvers.fast_transient.integrate_contact3d`,
Newmark average acceleration or HHT-alpha, so both agree to the Newton tolerance on a model
they can both run): with the diagonal effective stiffness ``S = c0 I + (1 + alpha)
(c1 diag(c) + diag(lambda))`` and the condensed compliance ``C = B S^-1 B^T`` (m x m, formed
once), each step solves

    g(u) = u - u_lin + (1 + alpha) C f(u, v(u)) = 0,     v = c1 (u - u_n) + c4 v_n + c5 a_n

on the m contact unknowns only. Strategies, switched automatically per iteration:

* **chord**: ``u <- u - J0^-1 g`` with ``J0 = I + (1 + alpha) C K_stick`` (every contact
  closed and stuck) factorised once; converges in a few iterations while the contacts stick;
* **Newton-Krylov**: when the chord contracts by less than 4x per iteration (slipping or
  opening contacts), ``J du = g`` with the consistent tangent ``J = I + (1 + alpha) C
  (K_u + c1 K_v)`` is solved by GMRES on matrix-vector products, preconditioned by the
  exact inverse of J's diagonal blocks, one block per contact element (patch): the
  effective compliance between different patches is small against a patch's own, so a
  few Krylov iterations suffice. Cost per iteration O(m^2), never an m x m factorisation.

The contact velocities and accelerations follow from the same Newmark relations as the modal
ones (they are linear maps of them), so a step costs two products with B (``B eta_lin`` and
``B^T f``) plus the iterations.

:func:`solve_static_modal` solves ``lambda eta + B^T f(B eta) = F`` condensed on the
contacts (``C_s = B diag(1/lambda) B^T``) with damped Newton steps.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers.fast_transient import (
    ENERGY_KEYS,
    _blas1,
    _contact_energy,
    _eval_contacts,
)
from fricdamp.solvers.timestep import _progress_default, energy_balance_error, energy_residual

__all__ = ["ModalBasis", "ModalStaticResult", "ModalTransientResult", "contact_law_arrays",
           "integrate_modal", "solve_static_modal", "transient_compliance"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ModalBasis:
    """Linear part of a model in mass-normalised undamped modes, seen from its contacts.

    Attributes
    ----------
    omega2 : ndarray, shape (n_modes,)
        Eigenvalues lambda = omega^2 [rad^2/s^2], all > 0 (a supported structure).
    damping : ndarray, shape (n_modes,)
        Modal damping ``c = Phi^T D Phi`` (diagonal) [1/s], e.g. ``a + b omega^2``.
    B : ndarray, shape (m, n_modes)
        Contact rows: ``u = B eta`` are the local relative displacements (n, t1, t2 of each
        contact, stacked) [m per unit modal coordinate].
    output : ndarray, shape (n_out, n_modes)
        Shapes at the output DOFs (probes) [m per unit modal coordinate].
    groups : tuple of (str, int)
        Contact elements (name, number of contacts) in the order of B's rows; used for
        the block preconditioner and for reporting.
    """

    omega2: np.ndarray
    damping: np.ndarray
    B: np.ndarray
    output: np.ndarray
    groups: tuple = ()

    def __post_init__(self):
        lam = np.asarray(self.omega2, dtype=float).reshape(-1)
        n = lam.size
        if n == 0 or not np.all(np.isfinite(lam)) or lam.min() <= 0:
            raise ModelError("omega2 must be finite eigenvalues > 0 rad^2/s^2 (a supported "
                             "structure)")
        c = np.broadcast_to(np.asarray(self.damping, dtype=float), (n,)).copy()
        if not np.all(np.isfinite(c)) or c.min() < 0:
            raise ModelError("damping must be finite modal damping values >= 0 1/s")
        B = np.ascontiguousarray(np.asarray(self.B, dtype=float))
        if B.ndim != 2 or B.shape[1] != n or B.shape[0] % 3:
            raise ModelError(f"B must have shape (3 n_contacts, {n}), got {B.shape}")
        out = np.ascontiguousarray(np.asarray(self.output, dtype=float).reshape(-1, n))
        groups = tuple((str(a), int(b)) for a, b in (self.groups or (("contacts",
                                                                       B.shape[0] // 3),)))
        if sum(b for _, b in groups) * 3 != B.shape[0]:
            raise ModelError(f"groups must count the {B.shape[0] // 3} contacts of B, got "
                             f"{sum(b for _, b in groups)}")
        object.__setattr__(self, "omega2", lam)
        object.__setattr__(self, "damping", c)
        object.__setattr__(self, "B", B)
        object.__setattr__(self, "output", out)
        object.__setattr__(self, "groups", groups)

    @property
    def n_modes(self) -> int:
        return self.omega2.size

    @property
    def n_contacts(self) -> int:
        return self.B.shape[0] // 3


def contact_law_arrays(laws):
    """Stacked parameters of Contact3D laws: (kn, kt, mu_s, mu_d, decay, offset)."""
    laws = list(laws)
    for lw in laws:
        if not isinstance(lw, Contact3D):
            raise ModelError(f"contact laws must be Contact3D, got {type(lw).__name__}")
    cat = np.concatenate
    return (cat([lw.normal_stiffness for lw in laws]),
            cat([lw.tangential_stiffness for lw in laws]),
            cat([lw.mu for lw in laws]), cat([lw.mu_sliding for lw in laws]),
            cat([np.where(lw.kinetic, lw.decay, 0.0) * np.ones(lw.n_contacts) for lw in laws]),
            cat([lw.offset for lw in laws]))


def _states(laws, states, nc):
    if states is None:
        return np.zeros((nc, 2)), np.zeros(nc)
    w, s = states
    w = np.ascontiguousarray(np.asarray(w, dtype=float).reshape(nc, 2))
    s = np.ascontiguousarray(np.asarray(s, dtype=float).reshape(nc))
    return w, s


class _Contacts:
    """Return maps of all contacts and their block tangents (compiled kernel)."""

    def __init__(self, laws, basis: ModalBasis):
        self.kn, self.kt, self.mus, self.mud, self.dc, self.g0 = contact_law_arrays(laws)
        nc = basis.n_contacts
        if self.kn.size != nc:
            raise ModelError(f"the contact laws hold {self.kn.size} contacts, the basis "
                             f"{nc}")
        self.nc = nc
        self.Ku = np.zeros((nc, 3, 3))
        self.Kv = np.zeros((nc, 3, 3))
        self.w1 = np.zeros((nc, 2))
        self.s1 = np.zeros(nc)
        self.code = np.zeros(nc, dtype=np.int8)
        bounds = np.cumsum([0] + [n for _, n in basis.groups])
        self.blocks = [slice(3 * a, 3 * b) for a, b in zip(bounds[:-1], bounds[1:],
                                                           strict=True)]

    def evaluate(self, u, v, w, s):
        f = np.zeros(u.size)
        _eval_contacts(u, v, w, s, self.kn, self.kt, self.mus, self.mud, self.dc, self.g0,
                       f, self.Ku, self.Kv, self.w1, self.s1, self.code)
        return f

    def energy(self, u, w):
        return _contact_energy(u, w, self.kn, self.kt, self.g0)

    def stick_diagonal(self):
        k = np.empty(3 * self.nc)
        k[0::3], k[1::3], k[2::3] = self.kn, self.kt, self.kt
        return k


def _block_apply(K, x):
    """Block-diagonal (nc, 3, 3) times x (3 nc,)."""
    return np.einsum("jab,jb->ja", K, x.reshape(-1, 3)).reshape(-1)


def _newton_krylov_step(C, K, g, blocks, ap, tol):
    """Solve ``(I + ap C K) du = g`` by GMRES, block-Jacobi preconditioned by patches."""
    m = g.size

    def matvec(x):
        return x + ap * (C @ _block_apply(K, x))

    inv_blocks = []
    for sl in blocks:
        idx = np.arange(sl.start, sl.stop)
        Kb = np.zeros((idx.size, idx.size))
        nb = idx.size // 3
        for j in range(nb):
            Kb[3 * j:3 * j + 3, 3 * j:3 * j + 3] = K[sl.start // 3 + j]
        Jb = np.eye(idx.size) + ap * (C[sl, sl] @ Kb)
        inv_blocks.append(sla.lu_factor(Jb, check_finite=False))

    def precond(x):
        y = np.empty_like(x)
        for sl, lu in zip(blocks, inv_blocks, strict=True):
            y[sl] = sla.lu_solve(lu, x[sl], check_finite=False)
        return y

    A = spla.LinearOperator((m, m), matvec=matvec, dtype=float)
    P = spla.LinearOperator((m, m), matvec=precond, dtype=float)
    du, info = spla.gmres(A, g, M=P, rtol=tol, atol=0.0, restart=60, maxiter=20)
    return du, info


# ====================================================================================== static
@dataclass(frozen=True)
class ModalStaticResult:
    """Static equilibrium with contacts from :func:`solve_static_modal`.

    Attributes
    ----------
    eta : ndarray, shape (n_modes,)
        Modal coordinates [m kg^0.5].
    u, f : ndarray, shape (n_contacts, 3)
        Contact relative displacements [m] and forces [N] (n, t1, t2).
    states : tuple (w, s)
        Contact states: slider positions (n_contacts, 2) [m] and slip flags (n_contacts,).
    status : ndarray of int8, shape (n_contacts,)
        0 open, 1 stick, 2 slip.
    iterations : int
    residual : float
        Final ``max |g|`` [m].
    """

    eta: np.ndarray
    u: np.ndarray
    f: np.ndarray
    states: tuple
    status: np.ndarray
    iterations: int
    residual: float


def _static_compliance(basis: ModalBasis) -> np.ndarray:
    B = basis.B
    return np.ascontiguousarray((B / basis.omega2) @ B.T)


def solve_static_modal(basis: ModalBasis, laws, load=None, *, states=None,
                       compliance: np.ndarray | None = None, tol: float = 1e-10,
                       max_iter: int = 60) -> ModalStaticResult:
    """Static equilibrium ``lambda eta + B^T f(B eta) = F`` from given contact states.

    Parameters
    ----------
    basis : ModalBasis
    laws : sequence of Contact3D
        One law per contact element, in the order of ``basis.groups``.
    load : array_like, shape (n_modes,), optional
        Modal load ``Phi^T F`` [N m kg^-0.5] (default zero: prestress only).
    states : tuple (w, s), optional
        Contact states to start from (default virgin); the contacts go to the solution in
        one return-map step (a proportional, monotonic load path).
    compliance : ndarray, shape (m, m), optional
        ``B diag(1/lambda) B^T`` if already formed (re-used across calls).
    tol, max_iter
        Convergence ``max |g| <= tol max(|u|, |u_lin|)``; Newton iterations.

    Raises
    ------
    ConvergenceError
        When Newton does not converge.
    """
    n = basis.n_modes
    F = np.zeros(n) if load is None else np.asarray(load, dtype=float).reshape(-1)
    if F.shape != (n,) or not np.all(np.isfinite(F)):
        raise ModelError(f"load must be a finite modal vector of length {n}")
    con = _Contacts(laws, basis)
    w0, s0 = _states(laws, states, con.nc)
    Cs = _static_compliance(basis) if compliance is None else compliance
    eta_lin = F / basis.omega2
    u_lin = basis.B @ eta_lin
    u = u_lin.copy()
    zero = np.zeros_like(u)
    eye = np.eye(u.size)
    res = np.inf
    it = 0
    with _blas1():
        for it in range(max_iter + 1):  # noqa: B007
            f = con.evaluate(u, zero, w0, s0)
            g = u - u_lin + Cs @ f
            res = float(np.max(np.abs(g)))
            scale = max(float(np.max(np.abs(u))), float(np.max(np.abs(u_lin))), 1e-300)
            if res <= tol * scale:
                break
            J = eye + Cs @ _block_matrix(con.Ku)
            du = np.linalg.solve(J, g)
            step = 1.0
            for _ in range(30):
                trial = u - step * du
                ft = con.evaluate(trial, zero, w0, s0)
                if np.max(np.abs(trial - u_lin + Cs @ ft)) < res or step < 1e-6:
                    break
                step *= 0.5
            u = u - step * du
        else:
            raise ConvergenceError(f"static contact solution did not converge in {max_iter} "
                                   f"Newton iterations (residual {res:.3g} m)")
    f = con.evaluate(u, zero, w0, s0)
    eta = eta_lin - (basis.B.T @ f) / basis.omega2
    return ModalStaticResult(eta=eta, u=u.reshape(-1, 3), f=f.reshape(-1, 3),
                             states=(con.w1.copy(), con.s1.copy()), status=con.code.copy(),
                             iterations=it, residual=res)


def _block_matrix(K):
    nc = K.shape[0]
    out = np.zeros((3 * nc, 3 * nc))
    for a in range(3):
        for b in range(3):
            out[3 * np.arange(nc) + a, 3 * np.arange(nc) + b] = K[:, a, b]
    return out


# =================================================================================== transient
def _newmark(basis: ModalBasis, h: float, alpha: float):
    """Newmark/HHT coefficients, gamma, 1 + alpha and the inverse effective stiffness."""
    beta = (1.0 - alpha) ** 2 / 4.0
    gamma = 0.5 - alpha
    c = (1.0 / (beta * h * h), gamma / (beta * h), 1.0 / (beta * h), 1.0 / (2.0 * beta) - 1.0,
         1.0 - gamma / beta, h * (1.0 - gamma / (2.0 * beta)))
    ap = 1.0 + alpha
    s_inv = 1.0 / (c[0] + ap * (c[1] * basis.damping + basis.omega2))
    return c, gamma, ap, s_inv


def transient_compliance(basis: ModalBasis, dt: float, *, method: str = "newmark",
                         alpha: float = -0.05) -> np.ndarray:
    """Condensed compliance ``C = B S^-1 B^T`` of the time step [m/N], shape (m, m).

    It depends on the modes, ``dt`` and the method only, not on the contacts: form it once
    and pass it to :func:`integrate_modal` for every run with the same step.
    """
    a = 0.0 if method == "newmark" else float(alpha)
    with _blas1():
        s_inv = _newmark(basis, float(dt), a)[3]
        return np.ascontiguousarray((basis.B * s_inv) @ basis.B.T)


@dataclass(frozen=True)
class ModalTransientResult:
    """Time history from :func:`integrate_modal`.

    Attributes
    ----------
    t : ndarray, shape (n_save,)
        Saved instants [s].
    output : ndarray, shape (n_save, n_out)
        Displacements at the basis' output DOFs [m].
    contact_status : ndarray of int8, shape (n_save, n_contacts)
        0 open, 1 stick, 2 slip, at every saved instant.
    t_contacts : ndarray, shape (n_contact_save,)
        Instants of the stored contact fields [s].
    contact_displacement, contact_force : ndarray, shape (n_contact_save, n_contacts, 3)
        Relative displacement [m] and force [N] (n, t1, t2), every ``contact_every`` steps.
    energy : dict of ndarray, each (n_save,)
        Cumulative energies [J] (keys :data:`~fricdamp.solvers.fast_transient.ENERGY_KEYS`).
    eta_final, vel_final : ndarray, shape (n_modes,)
    states_final : tuple (w, s)
    success, status, message
        ``status`` 0 finished, 1 Newton failure (with ``throw=False``).
    n_steps, n_iterations, n_krylov : int
        Steps; chord + Newton iterations; Newton-Krylov iterations among them.
    runtime_s, cpu_s : float
        Wall and CPU time of the time loop [s].
    setup_s : float
        Wall time of forming C and factorising the chord matrix [s].
    """

    t: np.ndarray
    output: np.ndarray
    contact_status: np.ndarray
    t_contacts: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    energy: dict
    eta_final: np.ndarray
    vel_final: np.ndarray
    states_final: tuple
    success: bool = True
    status: int = 0
    message: str = "finished"
    n_steps: int = 0
    n_iterations: int = 0
    n_krylov: int = 0
    runtime_s: float = 0.0
    cpu_s: float = 0.0
    setup_s: float = 0.0
    method: str = "newmark"
    meta: dict = field(default_factory=dict, compare=False)

    @property
    def energy_residual(self) -> np.ndarray:
        """``input_work - (d(T + V + stored) + viscous + contact dissipation)`` [J]."""
        return energy_residual(self.energy)

    @property
    def energy_balance_error(self) -> float:
        """Largest energy residual relative to the run's energy scale."""
        return energy_balance_error(self.energy)

    def state_fractions(self) -> dict:
        """Fractions of (contact, saved instant) samples open / stick / slip."""
        st = self.contact_status
        return {"open": float(np.mean(st == 0)), "stick": float(np.mean(st == 1)),
                "slip": float(np.mean(st == 2))}


def integrate_modal(basis: ModalBasis, laws, t_end: float, dt: float, *, eta0=None,
                    vel0=None, states0=None, load=None, t0: float = 0.0,
                    method: str = "newmark", alpha: float = -0.05, save_every: int = 1,
                    contact_every: int | None = None, tol: float = 1e-10,
                    max_iter: int = 40, chord: bool = True,
                    compliance: np.ndarray | None = None, progress: bool | None = None,
                    throw: bool = True) -> ModalTransientResult:
    """Integrate a modal model with Contact3D patches (module docstring).

    Parameters
    ----------
    basis : ModalBasis
    laws : sequence of Contact3D
        One law per contact element, in the order of ``basis.groups``.
    t_end, dt : float
        End time and time step [s].
    eta0, vel0 : array_like, shape (n_modes,), optional
        Initial modal displacements and velocities (default zero).
    states0 : tuple (w, s), optional
        Initial contact states (e.g. ``solve_static_modal(...).states``); default: virgin
        states loaded to the initial displacement in one step.
    load : array_like, shape (n_modes,), optional
        Constant modal load [N m kg^-0.5] (default zero: a free decay).
    t0 : float
        Start time [s].
    method : {"newmark", "hht"}
        Average acceleration (003: Newmark, gamma = 0.5) or HHT-alpha with ``alpha``.
    save_every : int
        Store outputs, energies and contact status every k-th step.
    contact_every : int, optional
        Store contact displacements and forces every k-th step (default: ``save_every``).
    tol, max_iter
        Convergence ``max |g| <= tol max(|u|, |u_lin|)`` per step; iterations per step.
    chord : bool
        Start every step with chord iterations (default); ``False``: Newton-Krylov from the
        first iteration. Both stop on the same residual test.
    compliance : ndarray, shape (m, m), optional
        ``C`` of :func:`transient_compliance` for the same basis, ``dt`` and method, if
        already formed (it does not depend on the contacts: re-use it across runs).
    progress : bool, optional
        tqdm progress bar (default: on a terminal and outside CI).
    throw : bool
        Raise :class:`ConvergenceError` on failure (default) or return what was computed
        with ``success=False``.

    Returns
    -------
    ModalTransientResult
    """
    if not isinstance(basis, ModalBasis):
        raise ModelError(f"basis must be a ModalBasis, got {type(basis).__name__}")
    if not (np.isfinite(dt) and dt > 0):
        raise ModelError(f"dt must be a finite time step > 0 s, got {dt!r}")
    if not (np.isfinite(t_end) and t_end > t0):
        raise ModelError(f"t_end must be > t0 = {t0} s, got {t_end!r}")
    if method not in ("newmark", "hht"):
        raise ModelError(f"method must be 'newmark' or 'hht', got {method!r}")
    if method == "newmark":
        alpha = 0.0
    elif not (-1.0 / 3.0 <= alpha <= 0.0):
        raise ModelError(f"alpha must lie in [-1/3, 0] for HHT-alpha, got {alpha!r}")
    for name, k in (("save_every", save_every), ("contact_every", contact_every)):
        if k is not None and (isinstance(k, bool) or int(k) != k or k < 1):
            raise ModelError(f"{name} must be an integer >= 1, got {k!r}")
    save_every = int(save_every)
    contact_every = save_every if contact_every is None else int(contact_every)
    n, m = basis.n_modes, basis.B.shape[0]
    eta = np.zeros(n) if eta0 is None else np.asarray(eta0, dtype=float).reshape(-1).copy()
    vel = np.zeros(n) if vel0 is None else np.asarray(vel0, dtype=float).reshape(-1).copy()
    Fm = np.zeros(n) if load is None else np.asarray(load, dtype=float).reshape(-1)
    for name, x in (("eta0", eta), ("vel0", vel), ("load", Fm)):
        if x.shape != (n,) or not np.all(np.isfinite(x)):
            raise ModelError(f"{name} must be a finite vector of length {n}")
    con = _Contacts(laws, basis)
    w, s = _states(laws, states0, con.nc)
    lam, cd, B, out = basis.omega2, basis.damping, basis.B, basis.output

    tic = time.perf_counter()
    with _blas1():
        h = float(dt)
        (c0, c1, c2, c3, c4, c5), gamma, ap, s_inv = _newmark(basis, h, alpha)
        if compliance is None:
            C = np.ascontiguousarray((B * s_inv) @ B.T)
        else:
            C = np.asarray(compliance)
            if C.shape != (m, m):
                raise ModelError(f"compliance must have shape ({m}, {m}), got {C.shape}")
        chord_lu = sla.lu_factor(np.eye(m) + ap * C * con.stick_diagonal()[None, :],
                              check_finite=False)
        u = B @ eta
        uv = B @ vel
        f = con.evaluate(u, uv, w, s)
        code = con.code.copy()
        code[(code == 1) & (s == 1.0)] = 2   # a contact given as slipping stays "slip"
        w, s = con.w1.copy(), con.s1.copy()
        BTf = B.T @ f
        acc = Fm - cd * vel - lam * eta - BTf
        ua = B @ acc
    setup = time.perf_counter() - tic

    n_steps = int(np.ceil((t_end - t0) / dt - 1e-9))
    n_save = n_steps // save_every + 1
    n_csave = n_steps // contact_every + 1
    T = np.zeros(n_save)
    Q = np.zeros((n_save, out.shape[0]))
    S = np.zeros((n_save, con.nc), dtype=np.int8)
    E = np.zeros((n_save, len(ENERGY_KEYS)))
    TC = np.zeros(n_csave)
    U = np.zeros((n_csave, con.nc, 3))
    FO = np.zeros((n_csave, con.nc, 3))
    acc_in = acc_visc = acc_cw = acc_cd = 0.0

    def store(k, kc, t, step):
        if step % save_every == 0:
            T[k] = t
            Q[k] = out @ eta
            S[k] = con.code if step else code
            E[k] = (acc_in, 0.5 * vel @ vel, 0.5 * np.sum(lam * eta * eta), acc_visc, acc_cw,
                    con.energy(u, w), acc_cd)
            k += 1
        if step % contact_every == 0:
            TC[kc] = t
            U[kc] = u.reshape(-1, 3)
            FO[kc] = f.reshape(-1, 3)
            kc += 1
        return k, kc

    k, kc = store(0, 0, t0, 0)
    show = _progress_default() if progress is None else bool(progress)
    bar = None
    if show:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_steps, desc="time steps", unit="step", leave=False)
    n_it = n_kr = 0
    status, message, done = 0, "finished", n_steps
    cpu0 = time.process_time()
    tic = time.perf_counter()
    with _blas1():
        for step in range(1, n_steps + 1):
            b = (Fm + alpha * (cd * vel + lam * eta + BTf) + c0 * eta + c2 * vel + c3 * acc
                 + ap * cd * (c1 * eta - c4 * vel - c5 * acc))
            eta_lin = b * s_inv
            u_lin = B @ eta_lin
            un = u.copy()
            use_chord = bool(chord)
            res_prev = np.inf
            converged = False
            for _it in range(max_iter + 1):
                vv = c1 * (un - u) + c4 * uv + c5 * ua
                fnew = con.evaluate(un, vv, w, s)
                Cf = C @ fnew
                g = un - u_lin + ap * Cf
                res = float(np.max(np.abs(g)))
                scale = max(float(np.max(np.abs(un))), float(np.max(np.abs(u_lin))), 1e-300)
                if res <= tol * scale:
                    converged = True
                    break
                n_it += 1
                if use_chord and res > 0.25 * res_prev:
                    use_chord = False
                res_prev = res
                if use_chord:
                    un = un - sla.lu_solve(chord_lu, g, check_finite=False)
                    continue
                n_kr += 1
                du, _info = _newton_krylov_step(C, con.Ku + c1 * con.Kv, g, con.blocks, ap,
                                                1e-3)
                un = un - du
            if not converged:
                status, done = 1, step - 1
                message = (f"Newton did not converge at t = {t0 + step * h:.6g} s within "
                           f"{max_iter} iterations (residual {res:.3g} m); try a smaller dt")
                break
            BTf_new = B.T @ fnew
            eta1 = eta_lin - ap * s_inv * BTf_new
            acc1 = c0 * (eta1 - eta) - c2 * vel - c3 * acc
            vel1 = vel + h * ((1.0 - gamma) * acc + gamma * acc1)
            deta = eta1 - eta
            acc_in += float(deta @ Fm)
            acc_visc += 0.5 * float(np.sum(deta * cd * (vel + vel1)))
            u1 = u_lin - ap * Cf                     # = B eta1 exactly (up to round-off)
            acc_cw += 0.5 * float((u1 - u) @ (f + fnew))
            fr = fnew.reshape(-1, 3)
            acc_cd += float(np.sum(fr[:, 1] * (con.w1[:, 0] - w[:, 0])
                                   + fr[:, 2] * (con.w1[:, 1] - w[:, 1])))
            du_c = u1 - u
            ua_new = c0 * du_c - c2 * uv - c3 * ua
            uv = c1 * du_c + c4 * uv + c5 * ua
            ua = ua_new
            u = u1
            eta, vel, acc = eta1, vel1, acc1
            f = fnew
            BTf = BTf_new
            w, s = con.w1.copy(), con.s1.copy()
            if step % 512 == 0:            # no drift of the contact-space Newmark recursion
                uv, ua = B @ vel, B @ acc
            k, kc = store(k, kc, t0 + step * h, step)
            if bar is not None:
                bar.update(1)
    runtime = time.perf_counter() - tic
    cpu = time.process_time() - cpu0
    if bar is not None:
        bar.close()
    if status and throw:
        raise ConvergenceError(message)
    return ModalTransientResult(
        t=T[:k], output=Q[:k], contact_status=S[:k], t_contacts=TC[:kc],
        contact_displacement=U[:kc], contact_force=FO[:kc],
        energy={key: E[:k, i].copy() for i, key in enumerate(ENERGY_KEYS)},
        eta_final=eta, vel_final=vel, states_final=(w, s), success=status == 0,
        status=status, message=message, n_steps=int(done), n_iterations=int(n_it),
        n_krylov=int(n_kr), runtime_s=runtime, cpu_s=cpu, setup_s=setup,
        method="newmark" if alpha == 0 else f"hht(alpha={alpha:g})",
        meta={"n_modes": int(n), "n_contact_rows": int(m)})
