"""Multi-harmonic stick-slip steady states of the 001 model, continued in spin speed.

The equivalent linearisation of paper 001 (slip ellipse, 001 (19)-(34)) replaces friction by
viscous dampers fitted to a harmonic orbit. Its reference here is the project's harmonic
balance engine (:func:`fricdamp.solvers.hb.harmonic_balance`, HB-AFT) on the *same* 78-DOF
model, each contact a true stick-slip law:

* the translation of contact X (rows normal, xi, eta of
  :attr:`~fricdamp.models.blade_pair.model.BladePairModel.contact_projection`) a
  :class:`~fricdamp.contact.Contact3D`: isotropic 2D Jenkins friction with stick stiffness
  ``k_t`` and slip limit ``f N_X``, with the constant normal load ``N_X`` of 001 (6) (a
  vanishing normal penalty with the matching offset, balanced by a static load) -- the load
  the equivalent damping assumes;
* the rotation about the normal a 1D :class:`~fricdamp.contact.Jenkins` element, stiffness
  ``k_t (a_ef^2 + h_ef^2) / 12`` (the polar moment of the effective rectangle of 001 (17)),
  slip torque ``M_0 = f N rho`` (the same torque as the equivalent damping, 001 (32)).

As ``k_t`` grows this is rigid-plastic Coulomb friction -- the law the equivalent damping
linearises -- with true stick. The wedge's axial translation, held only by friction, gets a
weak spring (``axial_support``, 10 N/m against a wedge of 15 g: 4 Hz, far below the
excitation) so that its mean position (the static harmonic) is defined.

Continuation in speed
---------------------
The spin speed Omega changes the excitation frequency ``k Omega`` *and* the matrices
(``Omega G``, ``Omega^2 (K_w - K_d)``), the normal loads (``N ~ Omega^2``, 001 (6)) and with
them the slip limits. The engine's continuation (:func:`~fricdamp.solvers.hb.
frequency_response`) follows the excitation frequency of a system with fixed matrices and
refuses speed-dependent terms, so the speed is followed here by a sequence of HB solves
warm-started along the speed (natural-parameter continuation) with step control:

* predictor: the secant through the last two converged speeds (the previous solution alone
  at the first step and after a rejected step);
* corrector: :func:`~fricdamp.solvers.hb.harmonic_balance` with that initial guess;
* step control: a speed interval whose Newton solve fails is halved, down to
  ``1 / 2**max_halvings`` of the grid step; where even that fails the point is solved from
  the engine's own cold starts (linear stuck, linear free, zero) and, failing that, reported
  as NaN with ``success`` False.

Natural-parameter continuation cannot pass a fold in speed; none occurs on the default model
(friction damping makes the response curves single-valued), and a fold would show as a
failed point, never as a wrong one.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace

import numpy as np

from fricdamp.errors import ModelError, as_finite_array
from fricdamp.models.blade_pair.model import BladePairModel, rpm_to_rad_s

__all__ = ["HBSpeedSweep", "bands", "compare_with_hb", "hb_entry", "hb_speed_sweep", "hb_system"]

logger = logging.getLogger(__name__)


def hb_system(model: BladePairModel, order: int, speed: float, friction_coefficient, *,
              tangential_stiffness: float = 1e8, axial_support: float = 10.0):
    """The 001 model at one spin speed with stick-slip contacts (module docstring).

    Parameters
    ----------
    model : BladePairModel
    order : int
        Excitation order k (load at ``k Omega``).
    speed : float
        Spin speed Omega [rad/s], > 0.
    friction_coefficient : float or (2,)
        f at A and B.
    tangential_stiffness : float
        Stick stiffness k_t [N/m] of the Jenkins elements, > 0.
    axial_support : float
        Spring on the wedge's axial DOF [N/m], >= 0.

    Returns
    -------
    MechanicalSystem
        Contacts ``"AB"`` (Contact3D, 2 contacts, rows normal/xi/eta) and ``"torsion"``
        (Jenkins, 2 contacts).
    """
    from fricdamp.contact import Contact3D, Jenkins
    from fricdamp.structure.system import ContactElement

    kt = float(tangential_stiffness)
    if not (np.isfinite(kt) and kt > 0):
        raise ModelError(f"tangential_stiffness must be > 0 N/m, got {tangential_stiffness!r}")
    if not (np.isfinite(axial_support) and axial_support >= 0):
        raise ModelError(f"axial_support must be >= 0 N/m, got {axial_support!r}")
    f = np.broadcast_to(np.asarray(friction_coefficient, float), (2,))
    if np.any(f < 0) or not np.all(np.isfinite(f)):
        raise ModelError(f"friction_coefficient must be >= 0, got {friction_coefficient!r}")
    P = model.contact_projection
    P3 = P[:, :3, :].reshape(6, model.n_dof)
    p = model.params
    a_ef, h_ef = np.array(p.contact_width), np.array(p.contact_height)
    N = model.normal_loads(float(speed))
    kn = 1e-6
    contacts = (ContactElement(Contact3D(kn, kt, f, offset=N / kn), P3, name="AB"),
                ContactElement(Jenkins(kt * (a_ef**2 + h_ef**2) / 12.0,
                                       f * N * model.torque_arms), P[:, 5, :],
                               name="torsion"))
    base = model.system(float(speed), order=order)
    K = np.array(base.K)
    iv = model.dof_index("damper", None, "v")
    K[iv, iv] += axial_support
    return replace(base, K=K, contacts=contacts,
                   static_load=P3.T @ np.array([N[0], 0, 0, N[1], 0, 0]))


@dataclass(frozen=True, eq=False)
class HBSpeedSweep:
    """HB steady states along the spin speed (:func:`hb_speed_sweep`).

    Attributes
    ----------
    rpm : ndarray, shape (n,)
        The requested speeds [rpm].
    success : ndarray of bool, shape (n,)
    coefficients : ndarray, shape (n, n_dof, 2H+1)
        Harmonics of every DOF [m] (NaN where not converged).
    tip_amplitude : ndarray, shape (n, 2)
        Largest excursion from the mean of the tangential tip (shroud) displacement
        ``max_t |w(t) - w_0|`` of blade 1 and blade 2 [m] (all harmonics).
    tip_fundamental : ndarray, shape (n, 2)
        Amplitude of the first harmonic of the same [m].
    contact_energy : ndarray, shape (n, 2)
        Friction energy per period of contact A and B (translation + torsion) [J]; exactly
        0 where the contact sticks (:attr:`stuck`).
    stuck : ndarray of bool, shape (n, 2)
        The contact's dissipation is below ``1e-6 (f N)^2 / k_t`` (the work of a slip of a
        millionth of the stick displacement): it sticks.
    semi_axes : ndarray, shape (n, 2, 2)
        ``[a, b]`` of the fundamental-harmonic orbit of the relative displacement at A, B [m].
    normal_force_ratio : ndarray, shape (n, 2)
        Not computed by HB (constant normal load); see the equivalent-linear entry.
    energy_balance_error : ndarray, shape (n,)
    iterations : ndarray of int, shape (n,)
        Newton iterations per requested speed (including the intermediate speeds).
    n_solves : int
        HB solves in all (requested + intermediate speeds + cold restarts).
    runtime_s : float
    harmonics, samples : int
    tangential_stiffness : float
    """

    rpm: np.ndarray
    success: np.ndarray
    coefficients: np.ndarray
    tip_amplitude: np.ndarray
    tip_fundamental: np.ndarray
    contact_energy: np.ndarray
    stuck: np.ndarray
    semi_axes: np.ndarray
    energy_balance_error: np.ndarray
    iterations: np.ndarray
    n_solves: int
    runtime_s: float
    harmonics: int
    samples: int
    tangential_stiffness: float

    @property
    def dissipated_energy(self) -> np.ndarray:
        """Friction energy per period of both contacts [J], shape (n,)."""
        return self.contact_energy.sum(axis=1)


class _SpeedProblem:
    """The condensed HB residual of the 001 model at one spin speed.

    Unknowns: the real harmonics ``Y`` (m, 2H+1) of the m = 8 contact coordinates (A, B:
    normal, xi, eta; then the two rotations about the normals), scaled by ``x_ref``. Residual
    (the engine's condensed formulation, :mod:`fricdamp.solvers.hb`)::

        u_k - u_lin,k + R_k f_k(u) = 0,   R_k = P Z_k^{-1} P^T,   u_lin,k = P Z_k^{-1} F_k

    per harmonic k, with the contact forces f and their exact Jacobian from the engine's AFT
    (:func:`fricdamp.solvers.aft.aft`). ``Z_k`` is factorised once per speed (the matrices
    depend on the speed, not on the iterate).
    """

    def __init__(self, system, omega: float, basis, x_ref: float | None = None):
        import scipy.linalg as sla

        self.system = system
        self.omega = float(omega)
        self.basis = basis
        H = basis.harmonics
        self.H, self.nh = H, basis.n_coeff
        self.contacts = system.contacts
        P = np.vstack([np.asarray(c.projection, float) for c in self.contacts])
        self.P = P
        m, n = P.shape
        self.m = m
        F = np.zeros((H + 1, n), complex)
        F[0] = system.static_load
        for load in system.loads:
            F[int(getattr(load, "harmonic", 1))] += np.asarray(load.amplitude, complex)
        K, M, D = (np.asarray(a, float) for a in (system.K, system.M, system.D))
        self.G = np.empty((H + 1, n, m), complex)          # Z_k^{-1} P^T
        self.X0 = np.empty((H + 1, n), complex)            # Z_k^{-1} F_k
        for k in range(H + 1):
            Z = K - (k * omega) ** 2 * M + 1j * k * omega * D
            sol = sla.solve(Z, np.column_stack([P.T, F[k]]), check_finite=False)
            self.G[k], self.X0[k] = sol[:, :m], sol[:, m]
        self.R = P @ self.G                                  # (H+1, m, m)
        self.u_lin = self.X0 @ P.T                           # (H+1, m)
        R = self.R
        N = m * self.nh
        Rr = np.zeros((m, self.nh, m, self.nh))
        Rr[:, 0, :, 0] = R[0].real
        for k in range(1, H + 1):
            a, b = 2 * k - 1, 2 * k
            Rr[:, a, :, a] = R[k].real
            Rr[:, a, :, b] = R[k].imag
            Rr[:, b, :, a] = -R[k].imag
            Rr[:, b, :, b] = R[k].real
        self.Rr = Rr.reshape(N, N)
        self.ulin_real = self.to_real(self.u_lin)
        self.x_ref = float(x_ref) if x_ref else max(float(np.abs(self.u_lin[1:]).max()),
                                                      1e-12)
        self.N = N

    def to_real(self, C):
        """Complex harmonics (H+1, m) -> real coefficients (m, 2H+1)."""
        Y = np.empty((C.shape[1], self.nh))
        Y[:, 0] = C[0].real
        Y[:, 1::2] = C[1:].real.T
        Y[:, 2::2] = -C[1:].imag.T
        return Y

    def to_complex(self, Y):
        C = np.empty((self.H + 1, Y.shape[0]), complex)
        C[0] = Y[:, 0]
        C[1:] = (Y[:, 1::2] - 1j * Y[:, 2::2]).T
        return C

    def forces(self, Y, jacobian: bool):
        from fricdamp.solvers.aft import aft

        return aft(self.contacts, Y, self.omega, self.basis, jacobian=jacobian)

    def residual(self, y, jacobian: bool = True):
        """Scaled residual (N,) and Jacobian (N, N) at scaled unknowns y."""
        Y = (y * self.x_ref).reshape(self.m, self.nh)
        res = self.forces(Y, jacobian)
        r = Y - self.ulin_real + (self.Rr @ res.force.ravel()).reshape(Y.shape)
        J = None
        if jacobian:
            Jf = np.zeros((self.N, self.N))
            nh = self.nh
            r0 = 0
            for c, blk in zip(self.contacts, res.jacobian, strict=True):
                mm = c.n_dir * nh
                for j in range(c.n_contacts):
                    sl = slice((r0 + j * c.n_dir) * nh, (r0 + j * c.n_dir) * nh + mm)
                    Jf[sl, sl] = blk[j]
                r0 += c.n_contacts * c.n_dir
            J = np.eye(self.N) + self.Rr @ Jf
        return r.ravel() / self.x_ref, J

    def solve(self, y0, *, tol: float, max_iter: int):
        """Newton with backtracking (trial steps without the Jacobian); (y, ok, iterations)."""
        import scipy.linalg as sla

        y = np.array(y0, float)
        r, J = self.residual(y)
        rn = np.abs(r).max()
        for it in range(max_iter + 1):
            if not np.isfinite(rn):
                return y, False, it
            if rn <= tol:
                return y, True, it
            if it == max_iter:
                break
            try:
                dy = -sla.solve(J, r, check_finite=False)
            except (np.linalg.LinAlgError, ValueError):
                return y, False, it
            lam = 1.0
            for _ in range(10):
                yt = y + lam * dy
                rt, _ = self.residual(yt, jacobian=False)
                rtn = np.abs(rt).max()
                if np.isfinite(rtn) and rtn < rn:
                    break
                lam *= 0.5
            else:
                yt = y + dy                        # kinks can trap a monotone search
            y = yt
            r, J = self.residual(y)
            rn = np.abs(r).max()
        return y, False, max_iter

    def outputs(self, y, tip_dofs):
        """Coefficients (n, 2H+1), per-row work, contact displacement/force harmonics."""
        Y = (y * self.x_ref).reshape(self.m, self.nh)
        res = self.forces(Y, False)
        from fricdamp.solvers.aft import cycle_work

        W = cycle_work(Y, res.force)                                  # (m,)
        Fc = self.to_complex(res.force)                               # (H+1, m)
        Q = self.X0 - np.einsum("knm,km->kn", self.G, Fc)              # (H+1, n)
        X = np.empty((Q.shape[1], self.nh))
        X[:, 0] = Q[0].real
        X[:, 1::2] = Q[1:].real.T
        X[:, 2::2] = -Q[1:].imag.T
        return X, W, Y, res.force


def _fine(H: int, n: int = 256) -> np.ndarray:
    tau = 2 * np.pi * np.arange(n) / n
    k = np.arange(1, H + 1)
    S = np.empty((n, 2 * H + 1))
    S[:, 0] = 0.0                                   # excursion from the mean
    S[:, 1::2] = np.cos(np.outer(tau, k))
    S[:, 2::2] = np.sin(np.outer(tau, k))
    return S


def hb_speed_sweep(model: BladePairModel, order: int, rpm, friction_coefficient, *,
                   tangential_stiffness: float = 1e8, harmonics: int = 5,
                   samples: int | None = 64, axial_support: float = 10.0,
                   max_halvings: int = 3, max_iter: int = 30,
                   tol: float = 1e-8, guide=None) -> HBSpeedSweep:
    """HB-AFT steady states at the speeds ``rpm``, continued along the speed.

    Parameters
    ----------
    model : BladePairModel
    order : int
        Excitation order k.
    rpm : array_like, shape (n,)
        Spin speeds > 0 [rpm], strictly monotonic (the continuation follows their order).
    friction_coefficient : float or (2,)
        f at A and B, > 0.
    tangential_stiffness : float
        Stick stiffness k_t [N/m] (default 1e8: stick displacement ``f N / k_t`` of 1-100 nm
        at 100-2500 rpm, f = 0.1).
    harmonics, samples : int
        HB harmonics H and AFT samples per period (default 5 and 64).
    axial_support : float
        Spring on the wedge's axial DOF [N/m].
    max_halvings : int
        Halvings of a speed step whose Newton solve fails, before a cold restart.
    max_iter : int
        Newton iterations per solve (a cold restart gets twice as many).
    tol : float
        Newton tolerance on the max-norm of the residual [m] relative to the largest
        contact displacement of the free linear response (``x_ref``).
    guide : array_like of complex, shape (n, n_dof), optional
        First-harmonic responses ``q~`` of an approximation at the same speeds (the
        equivalent linearisation): the predictor may then add its change between two
        speeds to the last HB solution (the candidate predictor with the smallest residual
        is taken, see the module docstring).

    Returns
    -------
    HBSpeedSweep
    """
    from fricdamp.contact.equivalent import slip_ellipse
    from fricdamp.solvers.aft import HarmonicBasis
    from fricdamp.solvers.continuation import blas_threads

    t0 = time.perf_counter()
    r = np.atleast_1d(as_finite_array("rpm", rpm)).astype(float)
    if r.ndim != 1 or r.size == 0 or np.any(r <= 0):
        raise ModelError(f"rpm must be a non-empty list of spin speeds > 0 rpm, got {rpm!r}")
    if r.size > 1 and not (np.all(np.diff(r) > 0) or np.all(np.diff(r) < 0)):
        raise ModelError("rpm must be strictly monotonic (the continuation follows it)")
    f = np.broadcast_to(np.asarray(friction_coefficient, float), (2,))
    if not np.all(f > 0):
        raise ModelError(f"friction_coefficient must be > 0 for stick-slip HB, got "
                         f"{friction_coefficient!r}")
    for name, v, low in (("harmonics", harmonics, 1), ("max_halvings", max_halvings, 0),
                         ("max_iter", max_iter, 1)):
        if isinstance(v, bool) or int(v) != v or v < low:
            raise ModelError(f"{name} must be an integer >= {low}, got {v!r}")
    kt = float(tangential_stiffness)
    basis = HarmonicBasis.create(int(harmonics), samples)
    nh = basis.n_coeff
    tips = [model.dof_index(b, model.tip_node, "w") for b in ("blade1", "blade2")]
    fine = _fine(basis.harmonics)
    n, nd = r.size, model.n_dof
    X = np.full((n, nd, nh), np.nan)
    tip = np.full((n, 2), np.nan)
    tip1 = np.full((n, 2), np.nan)
    W = np.full((n, 2), np.nan)
    axes = np.full((n, 2, 2), np.nan)
    err = np.full(n, np.nan)
    iters = np.zeros(n, int)
    ok = np.zeros(n, bool)
    counters = {"solves": 0}

    def problem(rpm_value):
        w = float(rpm_to_rad_s(rpm_value))
        sysm = hb_system(model, order, w, f, tangential_stiffness=kt,
                         axial_support=axial_support)
        return _SpeedProblem(sysm, order * w, basis)

    def solve(prob, Yguess, n_iter):
        counters["solves"] += 1
        y, good, it = prob.solve(Yguess.ravel() / prob.x_ref, tol=tol, max_iter=n_iter)
        return (y * prob.x_ref).reshape(prob.m, nh), good, it

    hist: list = []                                    # last converged (rpm, Y)

    P8 = np.vstack([model.contact_projection[:, :3, :].reshape(6, nd),
                    model.contact_projection[:, 5, :]])
    g_u = None
    if guide is not None:
        g = np.asarray(guide, complex)
        if g.shape != (n, nd):
            raise ModelError(f"guide must have shape ({n}, {nd}), got {g.shape}")
        g_u = g @ P8.T                                  # (n, 8) contact coordinates
    guide_at = {}                                       # rpm -> first-harmonic u (8,)

    def guide_u(rpm_value):
        if g_u is None:
            return None
        if rpm_value in guide_at:
            return guide_at[rpm_value]
        # between grid speeds: linear interpolation of the guide
        j = int(np.clip(np.searchsorted(r if r[-1] > r[0] else r[::-1], rpm_value) - 1, 0,
                        max(n - 2, 0)))
        if r[-1] < r[0]:
            j = n - 2 - j if n > 1 else 0
        if n == 1:
            return g_u[0]
        t = (rpm_value - r[j]) / (r[j + 1] - r[j])
        return (1 - t) * g_u[j] + t * g_u[j + 1]

    for j_, rv in enumerate(r):
        if g_u is not None:
            guide_at[rv] = g_u[j_]

    def candidates(target, hist):
        """Predictors at ``target``: secant (or previous) and, with a guide, the previous
        solution shifted by the guide's change, and the guide's harmonic itself."""
        out = []
        r1, y1 = hist[-1]
        if len(hist) == 2:
            r0, y0 = hist[-2]
            out.append(y1 + (y1 - y0) * (target - r1) / (r1 - r0))
        out.append(y1)
        gt, g1 = guide_u(target), guide_u(r1)
        if gt is not None and g1 is not None:
            d = gt - g1
            y = y1.copy()
            y[:, 1] += d.real
            y[:, 2] -= d.imag
            out.append(y)
            y = y1.copy()
            y[:, 1], y[:, 2] = gt.real, -gt.imag
            out.append(y)
        return out

    def predict(prob, target, hist):
        best, best_r = None, np.inf
        for c in candidates(target, hist):
            rr, _ = prob.residual(c.ravel() / prob.x_ref, jacobian=False)
            v = float(np.abs(rr).max())
            if np.isfinite(v) and v < best_r:
                best, best_r = c, v
        return best

    def advance(hist, target, i):
        """Continue from the last converged point(s) in ``hist`` to ``target``, halving
        the step on failure; returns (Y or None, hist)."""
        prob_t = problem(target)
        pos = hist[-1][0]
        full = target - pos
        step = full
        while True:
            nxt = target if abs(step) >= abs(target - pos) * (1 - 1e-12) else pos + step
            prob = prob_t if nxt == target else problem(nxt)
            Yt, good, it = solve(prob, predict(prob, nxt, hist), max_iter)
            iters[i] += it
            if good:
                hist = (hist + [(nxt, Yt)])[-2:]
                pos = nxt
                if nxt == target:
                    return Yt, hist, prob_t
                continue
            hist = hist[-1:]                          # the secant is no longer trusted
            step = 0.5 * step
            if abs(step) < abs(full) / 2**max_halvings:
                return None, hist, prob_t

    def cold(target, i):
        prob_t = problem(target)
        guesses = _cold_guesses(prob_t)
        gt = guide_u(target)
        if gt is not None:                            # the guide's harmonic on the stuck mean
            y = guesses[0].copy()
            y[:, 1], y[:, 2] = gt.real, -gt.imag
            guesses.insert(0, y)
        for guess in guesses:
            Yt, good, it = solve(prob_t, guess, 2 * max_iter)
            iters[i] += it
            if good:
                return Yt, prob_t
        return None, prob_t

    found: dict[int, tuple] = {}
    with blas_threads(1):
        # forward along the speeds
        for i, target in enumerate(r):
            Y = None
            if hist:
                Y, hist, prob_t = advance(hist, target, i)
            if Y is None:                             # first point, or continuation failed
                Y, prob_t = cold(target, i)
                hist = [(target, Y)] if Y is not None else hist
            if Y is not None:
                found[i] = (Y, prob_t)
        # backward from the next converged speed into the speeds that failed
        for i in range(n - 2, -1, -1):
            if i in found or (i + 1) not in found:
                continue
            back = [(r[i + 2], found[i + 2][0])] if (i + 2) in found else []
            Y, _, prob_t = advance(back + [(r[i + 1], found[i + 1][0])], r[i], i)
            if Y is not None:
                found[i] = (Y, prob_t)
        for i in range(n):
            if i not in found:
                logger.warning("HB did not converge at %.6g rpm (k = %d, f = %s)", r[i],
                               order, f.tolist())
                continue
            Y, prob_t = found[i]
            Xi, Wr, Yc, _ = prob_t.outputs(Y.ravel() / prob_t.x_ref, tips)
            ok[i] = True
            X[i] = Xi
            tip1[i] = np.hypot(Xi[tips, 1], Xi[tips, 2])
            tip[i] = np.abs(fine @ Xi[tips].T).max(axis=0)
            W[i] = [Wr[0:3].sum() + Wr[6], Wr[3:6].sum() + Wr[7]]
            for c_ in range(2):
                e = slip_ellipse(Yc[3 * c_ + 1, 1] - 1j * Yc[3 * c_ + 1, 2],
                                 Yc[3 * c_ + 2, 1] - 1j * Yc[3 * c_ + 2, 2])
                axes[i, c_] = [float(e.major), float(e.minor)]
            # energy balance: work of the load = viscous + contact dissipation
            sysm = prob_t.system
            Fk = prob_t.to_real(np.stack([np.asarray(sysm.static_load, complex)]
                                         + [sum(np.asarray(ld.amplitude, complex)
                                                for ld in sysm.loads)]
                                         + [np.zeros(nd, complex)] * (basis.harmonics - 1)))
            from fricdamp.solvers.aft import cycle_work

            w_ext = float(cycle_work(Xi, Fk).sum())
            Dm = np.asarray(sysm.D, float)
            Ds = 0.5 * (Dm + Dm.T)
            kk = np.arange(1, basis.harmonics + 1)
            a_, b_ = Xi[:, 1::2], Xi[:, 2::2]
            w_visc = float(np.pi * prob_t.omega * np.sum(
                kk**2 * (np.einsum("ik,ij,jk->k", a_, Ds, a_)
                         + np.einsum("ik,ij,jk->k", b_, Ds, b_))))
            w_out = w_visc + float(Wr.sum())
            err[i] = abs(w_ext - w_out) / max(abs(w_ext), abs(w_out), 1e-300)
    fN = f[None, :] * model.normal_loads(rpm_to_rad_s(r))
    stuck = ok[:, None] & (np.abs(W) <= 1e-6 * fN**2 / kt)
    W = np.where(stuck, 0.0, W)
    return HBSpeedSweep(rpm=r, success=ok, coefficients=X, tip_amplitude=tip,
                        tip_fundamental=tip1, contact_energy=W, stuck=stuck, semi_axes=axes,
                        energy_balance_error=err, iterations=iters,
                        n_solves=counters["solves"], runtime_s=time.perf_counter() - t0,
                        harmonics=basis.harmonics, samples=basis.samples,
                        tangential_stiffness=kt)


def _cold_guesses(prob: _SpeedProblem):
    """Starting points without a neighbour: the linear responses with stuck contacts
    (stick springs, rigid rotations), then free contacts, then zero."""
    out = []
    # stuck: u = u_lin - R K_stick u  ->  (I + R K) u = u_lin, per harmonic
    kdiag = []
    for c in prob.contacts:
        law = c.law
        st = law.initial_state()
        k = law.step(st, np.zeros((c.n_contacts, c.n_dir)), None).stiffness
        kdiag.append(np.asarray(k, float).reshape(c.n_contacts, c.n_dir, c.n_dir))
    Kc = np.zeros((prob.m, prob.m))
    r0 = 0
    for blk in kdiag:
        for j in range(blk.shape[0]):
            d = blk.shape[1]
            Kc[r0:r0 + d, r0:r0 + d] = blk[j]
            r0 += d
    U = np.stack([np.linalg.solve(np.eye(prob.m) + prob.R[k] @ Kc, prob.u_lin[k])
                  for k in range(prob.H + 1)])
    out.append(prob.to_real(U))
    out.append(prob.ulin_real.copy())
    out.append(np.zeros_like(prob.ulin_real))
    return out


def _json_list(a) -> list:
    """Floats with NaN and infinities as None (JSON has neither)."""
    return [float(v) if np.isfinite(v) else None for v in np.asarray(a, float)]


def bands(rpm, flagged) -> list[list[float]]:
    """Contiguous runs of flagged grid speeds as ``[[lo, hi], ...]`` [rpm] (a lone speed:
    ``[r, r]``)."""
    r = np.asarray(rpm, float)
    m = np.asarray(flagged, bool)
    out, start = [], None
    for i, b in enumerate(m):
        if b and start is None:
            start = i
        if start is not None and (not b or i == m.size - 1):
            stop = i if b else i - 1
            out.append([float(r[start]), float(r[stop])])
            start = None
    return out


def compare_with_hb(rpm, energy_eqlin, tip_eqlin, energy_hb, tip_hb, hb_success, *,
                    threshold: float = 0.1, negligible: float = 1e-3) -> dict:
    """Ratios eqlin / HB and the speed bands where they disagree by more than ``threshold``.

    Parameters
    ----------
    rpm : array_like, shape (n,)
    energy_eqlin, energy_hb : array_like, shape (n,)
        Friction energy per period [J] (exactly 0 where every contact sticks).
    tip_eqlin, tip_hb : array_like, shape (n,)
        Tip amplitudes [m].
    hb_success : array_like of bool, shape (n,)
    threshold : float
        Relative disagreement flagged (0.1: 10 %).
    negligible : float
        Energies (tip amplitudes) below ``negligible`` times the largest energy (tip
        amplitude) of the two sweeps are negligible: their ratio is reported but not
        flagged (nanometre motions of stuck contacts, set by the stick stiffness that the
        paper's law does not have, are not a disagreement of the linearisation that matters
        for the response).

    Returns
    -------
    dict
        ``eqlin_over_hb_energy`` and ``eqlin_over_hb_tip_amplitude`` (per speed; 1 where
        both energies are 0, None where HB's is 0 and eqlin's not, or HB failed),
        ``disagreement`` (per speed, bool), ``disagreement_band_rpm`` (``[[lo, hi], ...]``).
    """
    We, Wh = np.asarray(energy_eqlin, float), np.asarray(energy_hb, float)
    te, th = np.asarray(tip_eqlin, float), np.asarray(tip_hb, float)
    ok = np.asarray(hb_success, bool) & np.isfinite(Wh) & np.isfinite(th)
    with np.errstate(divide="ignore", invalid="ignore"):
        rW = np.where(Wh > 0, We / Wh, np.where(We > 0, np.inf, 1.0))
        rt = np.where(th > 0, te / th, np.where(te > 0, np.inf, 1.0))
    rW = np.where(ok, rW, np.nan)
    rt = np.where(ok, rt, np.nan)
    def relevant(a, b):
        b = np.where(ok, b, 0.0)
        scale = negligible * max(float(np.nanmax(a, initial=0.0)),
                                 float(np.nanmax(b, initial=0.0)))
        return np.maximum(a, b) > scale

    bad_W = ok & relevant(We, Wh) & ~(np.abs(rW - 1.0) <= threshold)
    bad_t = ok & relevant(te, th) & ~(np.abs(rt - 1.0) <= threshold)
    bad = bad_W | bad_t
    return {"eqlin_over_hb_energy": _json_list(rW),
            "eqlin_over_hb_tip_amplitude": _json_list(rt),
            "disagreement": bad.tolist(),
            "disagreement_band_rpm": bands(rpm, bad)}


def hb_entry(sweep: HBSpeedSweep) -> dict:
    """The ``hb`` table of a ``steady_state`` entry (results contract)."""
    s = sweep
    return {"rpm": s.rpm.tolist(),
            "tip_amplitude_m": _json_list(s.tip_amplitude.max(axis=1)),
            "dissipated_energy_J": _json_list(s.dissipated_energy),
            "dissipated_energy_A_J": _json_list(s.contact_energy[:, 0]),
            "dissipated_energy_B_J": _json_list(s.contact_energy[:, 1]),
            "tip_tangential_amplitude_m": [_json_list(v) for v in s.tip_amplitude],
            "tip_fundamental_amplitude_m": _json_list(s.tip_fundamental.max(axis=1)),
            "semi_axes_A_m": [_json_list(v) for v in s.semi_axes[:, 0]],
            "semi_axes_B_m": [_json_list(v) for v in s.semi_axes[:, 1]],
            "stuck_A": s.stuck[:, 0].tolist(), "stuck_B": s.stuck[:, 1].tolist(),
            "success": s.success.tolist(),
            "energy_balance_error": float(np.nanmax(s.energy_balance_error, initial=0.0)),
            "harmonics": s.harmonics, "samples": s.samples,
            "tangential_stiffness_N_per_m": s.tangential_stiffness,
            "newton_iterations": int(s.iterations.sum()), "solves": int(s.n_solves),
            "runtime_s": float(s.runtime_s)}
