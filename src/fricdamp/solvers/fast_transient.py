"""Fast transients of small (reduced) models with 3D friction contacts, and static contact.

:func:`integrate_contact3d` is the ``modal`` strategy of
:func:`fricdamp.solvers.timestep.simulate` (``simulate(..., strategy="modal")`` calls it; the
step is :class:`~fricdamp.solvers.newmark.NewmarkScheme`, shared by every transient solver)
for systems whose contacts are all :class:`~fricdamp.contact.element3d.Contact3D` elements
(constant or static/kinetic mu(v) friction) and whose damping is diagonal in the undamped
modes (Rayleigh or modal damping; Craig-Bampton models of Rayleigh-damped structures
are). It integrates **the same discrete equations** as ``simulate`` -- Newmark / HHT-alpha
with Newton condensed on the contact relative displacements and the same convergence test
-- so both agree to the Newton tolerance (tests/validation/test_tieboss_fast_transient.py),
but:

* the linear part is written in its mass-normalised undamped modes ``q = Phi eta``
  (``Phi^T M Phi = I``, ``Phi^T K Phi = diag(lambda)``, ``Phi^T D Phi = diag(c)``), so the
  effective stiffness ``S = c0 I + (1 + alpha)(c1 diag(c) + diag(lambda))`` is diagonal and
  a step costs two products with ``B = P Phi`` (m x n) instead of a factorised solve;
* the whole time loop, the contact return maps (with their consistent tangents, the velocity
  tangent of 003 (2) included) and the m x m Newton solves run in one compiled numba
  kernel, without the ~100 us of Python per step of the general solver.

Condensation (as in ``simulate``): ``eta_1 = eta_lin - (1 + alpha) S^-1 B^T f(u_1)`` and
Newton on ``g(u) = u - B eta_lin + (1 + alpha) C f(u) = 0`` with ``C = B S^-1 B^T``, the
contact velocity from the Newmark relation ``v = c1 (u - u_n) + c4 v_n + c5 a_n``.

:func:`solve_static` solves ``K q + sum P^T f(P q) = F`` for any contact laws, condensed on
the contacts with a damped Newton iteration, optionally in load increments with the contact
states committed after each (quasi-static loading; with ``increments=1`` the contacts go
from the given state to the solution in one return-map step, which is what ``simulate`` does
with its initial displacement).

Energy bookkeeping: as ``simulate`` (input work, kinetic and strain energy, viscous
dissipation, contact work, stored energy and the contacts' own dissipation
``f_t . dw``); for Newmark (alpha = 0) the balance of the linear part is exact, so
:attr:`FastTransientResult.energy_balance_error` measures how well the contacts are
integrated.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numba import njit

from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.limits import check_time_memory
from fricdamp.results import ResultMixin
from fricdamp.solvers.newmark import NewmarkScheme
from fricdamp.solvers.timestep import EnergyBalance, check_time_span
from fricdamp.structure.system import MechanicalSystem

__all__ = ["FastTransientResult", "StaticContactResult", "integrate_contact3d",
           "solve_static"]

ENERGY_KEYS = ("input_work", "kinetic", "strain", "viscous_dissipation", "contact_work",
               "contact_stored", "contact_dissipation")


def _blas1():
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


def _stack_projection(system: MechanicalSystem):
    blocks = [c.projection for c in system.contacts]
    if not blocks:
        return np.zeros((0, system.n_dof))
    if any(sp.issparse(b) for b in blocks):
        return sp.vstack([sp.csr_matrix(b) for b in blocks]).tocsr()
    return np.vstack(blocks)


# ================================================================================ static
@dataclass(frozen=True, repr=False)
class StaticContactResult(ResultMixin):
    """Static equilibrium with contacts from :func:`solve_static`.

    Attributes
    ----------
    q : ndarray, shape (n_dof,)
        Displacements [m].
    states : list of ndarray
        Contact states after the last increment, one per contact element.
    contact_displacement, contact_force : list of ndarray, each (n_contacts, n_dir)
        Relative displacements [m] and forces [N] per contact element.
    iterations : int
        Newton iterations over all increments.
    residual : float
        Final ``max |g|`` of the condensed equation [m].
    """

    q: np.ndarray
    states: list
    contact_displacement: list
    contact_force: list
    iterations: int
    residual: float

    def _judge(self):
        from fricdamp.results import status_verdict

        return status_verdict(True, "", {"residual_m": float(self.residual),
                                         "iterations": int(self.iterations)})

    def to_xarray(self):
        """``xarray.Dataset``: displacements per DOF and, per contact element ``k``, its
        relative displacements ``contact{k}_u`` and forces ``contact{k}_f``."""
        import xarray as xr

        ds = xr.Dataset({"q": (("dof",), self.q, {"units": "m"})},
                        attrs={"iterations": int(self.iterations),
                               "residual_m": float(self.residual)})
        for k, (u, f) in enumerate(zip(self.contact_displacement, self.contact_force,
                                       strict=True)):
            dims = (f"contact{k}", f"contact{k}_dir")
            ds[f"contact{k}_u"] = (dims, np.asarray(u), {"units": "m"})
            ds[f"contact{k}_f"] = (dims, np.asarray(f), {"units": "N"})
        return ds

    def plot(self, ax=None):
        """Static displacement of every DOF [m]; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 3.5), layout="constrained")
        ax.plot(np.arange(self.q.size), self.q, "o-", ms=3)
        ax.set_xlabel("DOF index")
        ax.set_ylabel("static displacement [m]")
        ax.grid(alpha=0.3)
        return ax


def _factor_solver(K):
    if sp.issparse(K):
        try:
            lu = spla.splu(sp.csc_matrix(K))
        except RuntimeError as exc:
            raise ModelError("the stiffness matrix is singular: support the structure "
                             "before a static solution") from exc
        return lambda b: lu.solve(np.asarray(b, dtype=float))
    try:
        lu = sla.lu_factor(np.asarray(K, dtype=float), check_finite=False)
    except (sla.LinAlgError, ValueError) as exc:  # pragma: no cover - LAPACK path
        raise ModelError(f"the stiffness matrix cannot be factorised: {exc}") from exc
    d = np.abs(np.diag(lu[0]))
    if d.size and d.min() <= 1e-14 * d.max():
        raise ModelError("the stiffness matrix is singular: support the structure before a "
                         "static solution")
    return lambda b: sla.lu_solve(lu, b, check_finite=False)


def solve_static(system: MechanicalSystem, load=None, *, states=None, increments: int = 1,
                 tol: float = 1e-10, max_iter: int = 50) -> StaticContactResult:
    """Static equilibrium ``K q + sum_c P_c^T f_c(P_c q) = F`` with contact return maps.

    Parameters
    ----------
    system : MechanicalSystem
        Structure with contact elements (any laws); K must be non-singular.
    load : array_like, shape (n_dof,), optional
        External load F [N]; default ``system.static_load``.
    states : list of ndarray, optional
        Contact states to start from (default: virgin).
    increments : int
        The load is applied in ``increments`` equal steps, the contact states being
        committed after each (quasi-static path); 1 applies it at once.
    tol : float
        Convergence: ``max |g| <= tol * max(|u|, |u_lin|)`` on the condensed equation.
    max_iter : int
        Newton iterations per increment.

    Returns
    -------
    StaticContactResult

    Raises
    ------
    ConvergenceError
        If an increment does not converge (try more increments).

    Notes
    -----
    Velocity-dependent laws are evaluated at zero velocity (static friction). Newton
    steps are damped by halving until ``max |g|`` decreases (friction makes g only
    piecewise smooth).
    """
    if not isinstance(system, MechanicalSystem):
        raise ModelError(f"system must be a MechanicalSystem, got {type(system).__name__}")
    n = system.n_dof
    F = system.static_load if load is None else np.asarray(load, dtype=float).reshape(-1)
    if F.shape != (n,) or not np.all(np.isfinite(F)):
        raise ModelError(f"load must be a finite vector of length {n}")
    if isinstance(increments, bool) or int(increments) != increments or increments < 1:
        raise ModelError(f"increments must be an integer >= 1, got {increments!r}")
    with _blas1():
        solve = _factor_solver(system.K)
        P = _stack_projection(system)
        m = P.shape[0]
        st = [np.array(s, dtype=float) for s in (system.initial_states() if states is None
                                                 else states)]
        if len(st) != len(system.contacts):
            raise ModelError(f"states must hold one array per contact element "
                             f"({len(system.contacts)}), got {len(st)}")
        if m == 0:
            q = solve(F)
            return StaticContactResult(q, st, [], [], 0, 0.0)
        PT = P.T.toarray() if sp.issparse(P) else np.asarray(P.T)
        Z = solve(PT) if not sp.issparse(system.K) else np.column_stack(
            [solve(PT[:, j]) for j in range(m)])
        C = np.asarray(P @ Z)
        slices, r0 = [], 0
        for c in system.contacts:
            slices.append(slice(r0, r0 + c.n_contacts * c.n_dir))
            r0 += c.n_contacts * c.n_dir
        q_unit = solve(F)
        u = np.zeros(m)
        total_it = 0
        res = 0.0

        def evaluate(states_, uu):
            f = np.empty(m)
            J = np.zeros((m, m))
            new = []
            for c, sl, s in zip(system.contacts, slices, states_, strict=True):
                nc, nd = c.n_contacts, c.n_dir
                uc = uu[sl].reshape(nc, nd)
                r = c.law.step(s, uc, np.zeros_like(uc) if c.law.velocity_dependent else None)
                f[sl] = r.force.reshape(-1)
                base = sl.start + nd * np.arange(nc)
                for a in range(nd):
                    for b in range(nd):
                        J[base + a, base + b] = r.stiffness[:, a, b]
                new.append(r.state)
            return f, J, new

        eye = np.eye(m)
        for k in range(1, int(increments) + 1):
            u_lin = np.asarray(P @ (q_unit * k / increments))
            converged = False
            for _ in range(max_iter + 1):
                f, Kc, st_new = evaluate(st, u)
                g = u - u_lin + C @ f
                res = float(np.max(np.abs(g)))
                scale = max(float(np.max(np.abs(u))), float(np.max(np.abs(u_lin))), 1e-300)
                if res <= tol * scale:
                    converged = True
                    break
                du = np.linalg.solve(eye + C @ Kc, g)
                step = 1.0
                for _ls in range(30):
                    trial = u - step * du
                    ft = evaluate(st, trial)[0]
                    if np.max(np.abs(trial - u_lin + C @ ft)) < res or step < 1e-6:
                        break
                    step *= 0.5
                u = u - step * du
                total_it += 1
            if not converged:
                raise ConvergenceError(
                    f"static contact solution: increment {k}/{increments} did not converge "
                    f"in {max_iter} Newton iterations (residual {res:.3g} m); use more "
                    "increments")
            st = st_new
        q = q_unit - Z @ f
    cu = [u[sl].reshape(c.n_contacts, c.n_dir) for c, sl in zip(system.contacts, slices,
                                                               strict=True)]
    cf = [f[sl].reshape(c.n_contacts, c.n_dir) for c, sl in zip(system.contacts, slices,
                                                               strict=True)]
    return StaticContactResult(q, st, cu, cf, total_it, res)


# ================================================================================ transient
@dataclass(frozen=True, repr=False)
class FastTransientResult(ResultMixin, EnergyBalance):
    """Time history from :func:`integrate_contact3d`.

    Attributes
    ----------
    t : ndarray, shape (n_save,)
        Saved instants [s].
    q : ndarray, shape (n_save, n_out)
        Displacements [m] of the requested output DOFs.
    contact_displacement, contact_force : ndarray, shape (n_save, n_contacts, 3)
        Relative displacement [m] and force [N] of all contacts (all elements stacked).
    contact_status : ndarray of int8, shape (n_save, n_contacts)
        0 open, 1 stick, 2 slip.
    energy : dict of ndarray, each (n_save,)
        Cumulative energies [J] (keys as :data:`ENERGY_KEYS`).
    q_final, v_final : ndarray, shape (n_dof,)
        Displacements and velocities at the last step.
    states_final : list of ndarray
        Contact states at the last step, one per contact element (their own layout).
    output_dofs : ndarray of int
    success, status, message
        ``status`` 0 finished, 1 Newton failure (with ``throw=False``).
    n_steps, n_newton : int
        Steps, and iterations (chord or Newton) over all steps.
    runtime_s : float
        Wall time of the time loop (set-up excluded; see ``setup_s``).
    setup_s : float
        Time of the modal transformation and compilation-free set-up.
    method : str
    """

    t: np.ndarray
    q: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    contact_status: np.ndarray
    energy: dict
    q_final: np.ndarray
    v_final: np.ndarray
    states_final: list
    output_dofs: np.ndarray
    success: bool = True
    status: int = 0
    message: str = "finished"
    n_steps: int = 0
    n_newton: int = 0
    runtime_s: float = 0.0
    setup_s: float = 0.0
    method: str = "newmark"
    meta: dict = field(default_factory=dict, compare=False)

    def to_xarray(self):
        """``xarray.Dataset``: output displacements over time, contact status, cumulative
        energies [J] and the stored contact fields (their own time axis)."""
        import xarray as xr

        ds = xr.Dataset(
            {"q": (("time", "output"), self.q, {"units": "m", "long_name": "displacement"}),
             "contact_status": (("time", "contact"), self.contact_status,
                                {"long_name": "0 open, 1 stick, 2 slip"}),
             "contact_displacement": (("time", "contact", "direction"),
                                      self.contact_displacement, {"units": "m"}),
             "contact_force": (("time", "contact", "direction"), self.contact_force,
                               {"units": "N"})},
            coords={"time": ("time", self.t, {"units": "s"}),
                    "output": np.asarray(self.output_dofs),
                    "direction": ["n", "t1", "t2"]},
            attrs={"method": self.method, "success": int(self.success), "status": self.status,
                   "message": self.message, "n_steps": self.n_steps,
                   "energy_balance_error": self.energy_balance_error})
        for k, arr in self.energy.items():
            ds[f"energy_{k}"] = (("time",), np.asarray(arr), {"units": "J"})
        return ds

    def plot(self, outputs=None, ax=None):
        """Displacement histories of the outputs (indices, default all) [mm]; returns the
        axes."""
        from fricdamp.results import plot_histories

        return plot_histories(self.t, self.q, outputs, ax)



@njit(cache=True, nogil=True)
def _eval_contacts(u, v, w0, s0, kn, kt, mus, mud, dc, g0, f, Ku, Kv, w1, s1,
                   code):  # pragma: no cover - compiled
    """Return maps of all contacts (Contact3D, kinetic form) at (u, v) from (w0, s0).

    u, v, f: (3 nc,); Ku, Kv: (nc, 3, 3); w0, w1: (nc, 2); s0, s1, code: (nc,).
    Same branches and operations as :meth:`Contact3D.step`.
    """
    nc = kn.size
    for j in range(nc):
        for a in range(3):
            for b in range(3):
                Ku[j, a, b] = 0.0
                Kv[j, a, b] = 0.0
        un = u[3 * j]
        ut1 = u[3 * j + 1]
        ut2 = u[3 * j + 2]
        gap = un + g0[j]
        if gap <= 0.0:
            f[3 * j] = 0.0
            f[3 * j + 1] = 0.0
            f[3 * j + 2] = 0.0
            w1[j, 0] = ut1
            w1[j, 1] = ut2
            s1[j] = 0.0
            code[j] = 0
            continue
        nf = kn[j] * gap
        f1 = kt[j] * (ut1 - w0[j, 0])
        f2 = kt[j] * (ut2 - w0[j, 1])
        nrm = np.sqrt(f1 * f1 + f2 * f2)
        vt = np.sqrt(v[3 * j + 1] * v[3 * j + 1] + v[3 * j + 2] * v[3 * j + 2])
        if dc[j] > 0.0:
            ex = np.exp(-dc[j] * vt)
            mu_v = mud[j] + (mus[j] - mud[j]) * ex
        else:
            ex = 0.0
            mu_v = mud[j]
        lim = (mus[j] if s0[j] == 0.0 else mu_v) * nf
        Ku[j, 0, 0] = kn[j]
        if nrm > lim:
            d1 = f1 / nrm
            d2 = f2 / nrm
            sc = mu_v * nf / nrm
            f1 *= sc
            f2 *= sc
            w1[j, 0] = ut1 - f1 / kt[j]
            w1[j, 1] = ut2 - f2 / kt[j]
            s1[j] = 1.0
            code[j] = 2
            k = sc * kt[j]
            Ku[j, 1, 1] = k * (1.0 - d1 * d1)
            Ku[j, 1, 2] = -k * d1 * d2
            Ku[j, 2, 1] = -k * d2 * d1
            Ku[j, 2, 2] = k * (1.0 - d2 * d2)
            Ku[j, 1, 0] = mu_v * kn[j] * d1
            Ku[j, 2, 0] = mu_v * kn[j] * d2
            if dc[j] > 0.0 and vt > 0.0:
                c = nf * (-(mus[j] - mud[j]) * dc[j] * ex)
                e1 = v[3 * j + 1] / vt
                e2 = v[3 * j + 2] / vt
                Kv[j, 1, 1] = c * d1 * e1
                Kv[j, 1, 2] = c * d1 * e2
                Kv[j, 2, 1] = c * d2 * e1
                Kv[j, 2, 2] = c * d2 * e2
        else:
            w1[j, 0] = w0[j, 0]
            w1[j, 1] = w0[j, 1]
            s1[j] = 0.0
            code[j] = 1
            Ku[j, 1, 1] = kt[j]
            Ku[j, 2, 2] = kt[j]
        f[3 * j] = nf
        f[3 * j + 1] = f1
        f[3 * j + 2] = f2


@njit(cache=True, nogil=True)
def _contact_energy(u, w, kn, kt, g0):  # pragma: no cover - compiled
    e = 0.0
    for j in range(kn.size):
        gap = u[3 * j] + g0[j]
        if gap > 0.0:
            e += 0.5 * kn[j] * gap * gap
            d1 = u[3 * j + 1] - w[j, 0]
            d2 = u[3 * j + 2] - w[j, 1]
            e += 0.5 * kt[j] * (d1 * d1 + d2 * d2)
    return e


@njit(cache=True, nogil=True)
def _march(n_steps, save_every, coef, lam, cdmp, s_inv, B, BT, C, J0inv, chord, Fm,
           Phi_out, eta, vel, acc, u, f, w, s, code0, kn, kt, mus, mud, dc, g0, tol, max_iter,
           T, Q, U, Fo, S, E, Vo, Ao):  # pragma: no cover - compiled
    """Time loop; returns (status, n_newton, steps done, saved count)."""
    h, alpha, gamma, c0, c1, c2, c3, c4, c5, t0 = (coef[0], coef[1], coef[2], coef[3],
                                                  coef[4], coef[5], coef[6], coef[7],
                                                  coef[8], coef[9])
    ap = 1.0 + alpha
    n = lam.size
    m = u.size
    nc = kn.size
    eye = np.eye(m)
    Ku = np.zeros((nc, 3, 3))
    Kv = np.zeros((nc, 3, 3))
    w1 = np.zeros((nc, 2))
    s1 = np.zeros(nc)
    code = np.zeros(nc, dtype=np.int8)
    fnew = np.zeros(m)
    J = np.zeros((m, m))
    BTf = BT @ f
    uv = B @ vel
    ua = B @ acc
    # energies at start
    acc_in = 0.0
    acc_visc = 0.0
    acc_cw = 0.0
    acc_cd = 0.0
    stored = _contact_energy(u, w, kn, kt, g0)
    full_state = Vo.shape[0] > 0
    T[0] = t0
    Q[0] = Phi_out @ eta
    if full_state:
        Vo[0] = Phi_out @ vel
        Ao[0] = Phi_out @ acc
    U[0] = u
    Fo[0] = f
    S[0] = code0
    E[0, 0] = 0.0
    E[0, 1] = 0.5 * np.sum(vel * vel)
    E[0, 2] = 0.5 * np.sum(lam * eta * eta)
    E[0, 3] = 0.0
    E[0, 4] = 0.0
    E[0, 5] = stored
    E[0, 6] = 0.0
    k_save = 1
    n_newton = 0
    un = u.copy()
    b = np.zeros(n)
    for step in range(1, n_steps + 1):
        for k in range(n):
            b[k] = (Fm[k] + alpha * (cdmp[k] * vel[k] + lam[k] * eta[k] + BTf[k])
                    + c0 * eta[k] + c2 * vel[k] + c3 * acc[k]
                    + ap * cdmp[k] * (c1 * eta[k] - c4 * vel[k] - c5 * acc[k]))
        eta_lin = b * s_inv
        u_lin = B @ eta_lin
        for i in range(m):
            un[i] = u[i]
        converged = False
        newton = not chord
        res_prev = np.inf
        for _it in range(max_iter + 1):
            vv = c1 * (un - u) + c4 * uv + c5 * ua
            _eval_contacts(un, vv, w, s, kn, kt, mus, mud, dc, g0, fnew, Ku, Kv, w1, s1,
                           code)
            g = un - u_lin + ap * (C @ fnew)
            res = np.max(np.abs(g))
            scale = max(np.max(np.abs(un)), np.max(np.abs(u_lin)), 1e-300)
            if res <= tol * scale:
                converged = True
                break
            n_newton += 1
            if not newton and res > 0.25 * res_prev:
                newton = True           # the chord iteration is slow here: full Newton
            res_prev = res
            if not newton:
                un = un - J0inv @ g
                continue
            for i in range(m):
                for jj in range(m):
                    J[i, jj] = eye[i, jj]
            for j in range(nc):
                for a in range(3):
                    for bb in range(3):
                        kk = ap * (Ku[j, a, bb] + c1 * Kv[j, a, bb])
                        if kk != 0.0:
                            col = 3 * j + bb
                            row = 3 * j + a
                            for i in range(m):
                                J[i, col] += C[i, row] * kk
            un = un - np.linalg.solve(J, g)
        if not converged:
            return 1, n_newton, step - 1, k_save
        BTf_new = BT @ fnew
        eta1 = eta_lin - ap * s_inv * BTf_new
        acc1 = c0 * (eta1 - eta) - c2 * vel - c3 * acc
        vel1 = vel + h * ((1.0 - gamma) * acc + gamma * acc1)
        deta = eta1 - eta
        acc_in += np.sum(deta * Fm)
        acc_visc += 0.5 * np.sum(deta * cdmp * (vel + vel1))
        acc_cw += 0.5 * np.sum((un - u) * (f + fnew))
        for j in range(nc):
            acc_cd += (fnew[3 * j + 1] * (w1[j, 0] - w[j, 0])
                       + fnew[3 * j + 2] * (w1[j, 1] - w[j, 1]))
        eta[:] = eta1          # in place: the caller reads the final state from these
        vel[:] = vel1
        acc[:] = acc1
        uv = B @ vel
        ua = B @ acc
        for i in range(m):
            u[i] = un[i]
            f[i] = fnew[i]
        for j in range(nc):
            w[j, 0] = w1[j, 0]
            w[j, 1] = w1[j, 1]
            s[j] = s1[j]
        BTf = BTf_new
        if step % save_every == 0:
            T[k_save] = t0 + step * h
            Q[k_save] = Phi_out @ eta
            if full_state:
                Vo[k_save] = Phi_out @ vel
                Ao[k_save] = Phi_out @ acc
            U[k_save] = u
            Fo[k_save] = f
            S[k_save] = code
            E[k_save, 0] = acc_in
            E[k_save, 1] = 0.5 * np.sum(vel * vel)
            E[k_save, 2] = 0.5 * np.sum(lam * eta * eta)
            E[k_save, 3] = acc_visc
            E[k_save, 4] = acc_cw
            E[k_save, 5] = _contact_energy(u, w, kn, kt, g0)
            E[k_save, 6] = acc_cd
            k_save += 1
    return 0, n_newton, n_steps, k_save


def _contact_parameters(system: MechanicalSystem):
    laws = [c.law for c in system.contacts]
    if not laws:
        raise ModelError("integrate_contact3d needs contact elements (use simulate for a "
                         "linear system)")
    for c in system.contacts:
        if not isinstance(c.law, Contact3D):
            raise ModelError(f"integrate_contact3d handles Contact3D laws only; contact "
                             f"{c.name!r} has {type(c.law).__name__} (use simulate)")
    cat = np.concatenate
    kn = cat([lw.normal_stiffness for lw in laws])
    kt = cat([lw.tangential_stiffness for lw in laws])
    mus = cat([lw.mu for lw in laws])
    mud = cat([lw.mu_sliding for lw in laws])
    dc = cat([np.where(lw.kinetic, lw.decay, 0.0) * np.ones(lw.n_contacts) for lw in laws])
    g0 = cat([lw.offset for lw in laws])
    return laws, kn, kt, mus, mud, dc, g0


def _split_states(laws, states):
    if states is None:
        states = [lw.initial_state() for lw in laws]
    if len(states) != len(laws):
        raise ModelError(f"states0 must hold one array per contact element ({len(laws)}), "
                         f"got {len(states)}")
    ws, ss = [], []
    for lw, st in zip(laws, states, strict=True):
        st = np.asarray(st, dtype=float).reshape(lw.n_contacts, lw.n_state)
        ws.append(st[:, :2])
        ss.append(st[:, 2] if lw.kinetic else np.zeros(lw.n_contacts))
    return np.ascontiguousarray(np.concatenate(ws)), np.ascontiguousarray(np.concatenate(ss))


def _join_states(laws, w, s):
    out, k = [], 0
    for lw in laws:
        sl = slice(k, k + lw.n_contacts)
        out.append(np.concatenate([w[sl], s[sl, None]], axis=1) if lw.kinetic else w[sl].copy())
        k += lw.n_contacts
    return out


def integrate_contact3d(system: MechanicalSystem, t_end: float, dt: float, *, q0=None, v0=None,
                        states0=None, t0: float = 0.0, method: str = "newmark",
                        alpha: float = -0.05, save_every: int = 1, output_dofs=None,
                        tol: float = 1e-10, max_iter: int = 30, chord: bool = True,
                        throw: bool = True, full_state: bool = False) -> FastTransientResult:
    """Integrate a Contact3D system like :func:`~fricdamp.solvers.timestep.simulate`, fast.

    Parameters
    ----------
    system : MechanicalSystem
        Dense or sparse matrices (a few hundred to ~2000 DOFs: the modal transformation is
        a dense eigenproblem), contacts all :class:`~fricdamp.contact.element3d.Contact3D`,
        damping diagonal in the undamped modes (Rayleigh, modal), a constant
        ``static_load`` and no time-dependent loads.
    t_end, dt : float
        End time and time step [s].
    q0, v0 : array_like, shape (n_dof,), optional
        Initial displacements [m] and velocities [m/s] (default zero).
    states0 : list of ndarray, optional
        Initial contact states, one array per contact element (e.g. from
        :func:`solve_static`). Default: virgin states loaded to ``q0`` in one step, as
        ``simulate`` does.
    t0 : float
        Start time [s].
    method : {"newmark", "hht"}
        Average acceleration, or HHT-alpha with ``alpha`` in [-1/3, 0].
    alpha : float
        HHT parameter (``method="hht"`` only).
    save_every : int
        Store every k-th step.
    output_dofs : sequence of int, optional
        DOFs whose displacements are stored (default all).
    tol, max_iter
        Newton tolerance and iterations per step (as ``simulate``).
    chord : bool
        Iterate with the constant matrix of closed, stuck contacts (inverted once) and
        switch to full Newton only when that converges slowly (default); with small steps
        ``(1 + alpha) C K_c`` is small (inertia dominates the contact compliance) and the
        chord iteration gains ~2-3 digits per iteration at the cost of a matrix-vector
        product instead of an m x m factorisation. ``False``: full Newton at every
        iteration, the iterates of ``simulate``. Both stop on the same residual test.
    throw : bool
        Raise :class:`ConvergenceError` on a Newton failure (default) or return the
        history up to it with ``success=False``.
    full_state : bool
        Also store velocities and accelerations of ``output_dofs`` (in ``meta["v"]`` and
        ``meta["a"]``; what ``simulate(..., strategy="modal")`` returns).

    Returns
    -------
    FastTransientResult

    Raises
    ------
    ModelError
        Non-Contact3D laws, time-dependent loads, non-proportional damping, bad arguments.
    """
    if not isinstance(system, MechanicalSystem):
        raise ModelError(f"system must be a MechanicalSystem, got {type(system).__name__}")
    if system.loads:
        raise ModelError("integrate_contact3d handles a constant static_load only; use "
                         "simulate for time-dependent loads")
    alpha = check_time_span(t_end, dt, t0=t0, method=method, alpha=alpha)
    if isinstance(save_every, bool) or int(save_every) < 1:
        raise ModelError(f"save_every must be an integer >= 1, got {save_every!r}")
    save_every = int(save_every)
    n = system.n_dof
    q = np.zeros(n) if q0 is None else np.asarray(q0, dtype=float).reshape(-1).copy()
    v = np.zeros(n) if v0 is None else np.asarray(v0, dtype=float).reshape(-1).copy()
    for name, x in (("q0", q), ("v0", v)):
        if x.shape != (n,) or not np.all(np.isfinite(x)):
            raise ModelError(f"{name} must be a finite vector of length {n}")
    out = np.arange(n) if output_dofs is None else np.asarray(output_dofs, dtype=np.int64)
    if out.ndim != 1 or (out.size and (out.min() < 0 or out.max() >= n)):
        raise ModelError(f"output_dofs must be DOF indices in [0, {n - 1}]")
    # refuse before allocating the saved histories (dt = 1e-12: a MemoryError of TiB)
    check_time_memory(float(t_end) - float(t0), float(dt), int(out.size),
                      sum(c.n_contacts * c.n_dir for c in system.contacts),
                      save_every=save_every, value=dt)
    laws, kn, kt, mus, mud, dc, g0 = _contact_parameters(system)
    w, s = _split_states(laws, states0)

    tic = time.perf_counter()
    with _blas1():
        def dense(A):
            return A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)

        M, K, D = dense(system.M), dense(system.K), dense(system.D)
        lam, Phi = sla.eigh(0.5 * (K + K.T), 0.5 * (M + M.T), check_finite=False)
        Dm = Phi.T @ D @ Phi
        cd = np.diag(Dm).copy()
        off = np.abs(Dm - np.diag(cd)).max(initial=0.0)
        if off > 1e-8 * max(np.abs(cd).max(initial=0.0), 1e-300) and off > 1e-12 * max(
                np.sqrt(np.abs(lam).max()), 1e-300):
            raise ModelError("integrate_contact3d needs damping that is diagonal in the "
                             "undamped modes (Rayleigh or modal damping); use simulate")
        P = _stack_projection(system)
        B = np.ascontiguousarray(np.asarray(P @ Phi))
        scheme = NewmarkScheme(dt, alpha)
        h, ap = scheme.h, scheme.ap
        s_inv = scheme.modal_inverse(cd, lam)
        C = np.ascontiguousarray((B * s_inv) @ B.T)
        # chord matrix: the Newton matrix with every contact closed and stuck
        m = B.shape[0]
        kstick = np.zeros(m)
        kstick[0::3], kstick[1::3], kstick[2::3] = kn, kt, kt
        J0inv = np.ascontiguousarray(np.linalg.inv(np.eye(m) + ap * C * kstick[None, :]))
        BT = np.ascontiguousarray(B.T)
        Fm = Phi.T @ system.static_load
        eta = np.ascontiguousarray(Phi.T @ (M @ q))     # modal coordinates (Phi^T M Phi = I)
        vel = np.ascontiguousarray(Phi.T @ (M @ v))
        # initial contact evaluation (virgin or given states) and acceleration
        u = np.ascontiguousarray(B @ eta)
        uv = B @ vel
        f = np.zeros(u.size)
        nc = kn.size
        Ku, Kv = np.zeros((nc, 3, 3)), np.zeros((nc, 3, 3))
        w1, s1, code = np.zeros((nc, 2)), np.zeros(nc), np.zeros(nc, dtype=np.int8)
        _eval_contacts(u, uv, w, s, kn, kt, mus, mud, dc, g0, f, Ku, Kv, w1, s1, code)
        # a contact given as slipping stays "slip" at t0 (re-evaluated on its cone it would
        # read stick or slip by rounding)
        code[(code == 1) & (s == 1.0)] = 2
        w, s = w1.copy(), s1.copy()
        acc = Fm - cd * vel - lam * eta - B.T @ f
        n_steps = int(np.ceil((t_end - t0) / dt - 1e-9))
        n_save = n_steps // save_every + 1
        T = np.zeros(n_save)
        Phi_out = np.ascontiguousarray(Phi[out])
        Q = np.zeros((n_save, out.size))
        U = np.zeros((n_save, u.size))
        Fo = np.zeros((n_save, u.size))
        S = np.zeros((n_save, nc), dtype=np.int8)
        E = np.zeros((n_save, len(ENERGY_KEYS)))
        coef = scheme.coefficients(t0)
        n_full = n_save if full_state else 0
        Vo = np.zeros((n_full, out.size))
        Ao = np.zeros((n_full, out.size))
        setup = time.perf_counter() - tic
        tic = time.perf_counter()
        status, n_newton, done, k = _march(
            n_steps, save_every, coef, lam, cd, s_inv, B, BT, C, J0inv, bool(chord), Fm,
            Phi_out, eta, vel, acc,
            u, f, w, s, code, kn, kt, mus, mud, dc, g0, float(tol), int(max_iter), T, Q, U, Fo,
            S, E, Vo, Ao)
        runtime = time.perf_counter() - tic
    message = "finished"
    if status != 0:
        message = (f"Newton did not converge at t = {t0 + (done + 1) * h:.6g} s within "
                   f"{max_iter} iterations; try a smaller dt or a larger max_iter")
        if throw:
            raise ConvergenceError(message)
    nc3 = (nc, 3)
    return FastTransientResult(
        t=T[:k], q=Q[:k], contact_displacement=U[:k].reshape((k,) + nc3),
        contact_force=Fo[:k].reshape((k,) + nc3), contact_status=S[:k],
        energy={key: E[:k, i].copy() for i, key in enumerate(ENERGY_KEYS)},
        q_final=Phi @ eta, v_final=Phi @ vel, states_final=_join_states(laws, w, s),
        output_dofs=out, success=status == 0, status=int(status), message=message,
        n_steps=int(done), n_newton=int(n_newton), runtime_s=runtime, setup_s=setup,
        method=scheme.method,
        meta={"n_modes": int(lam.size), "n_contact_rows": int(u.size),
              **({"v": Vo[:k], "a": Ao[:k]} if full_state else {})})
