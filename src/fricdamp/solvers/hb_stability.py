"""Stability of harmonic-balance solutions (Hill's method) and bifurcations along a branch.

Floquet exponents from the Hill matrix
--------------------------------------
A perturbation ``q = q_p(t) + e^{lambda t} p(t)`` of a periodic solution ``q_p`` with ``p``
periodic, expanded in the same harmonics as ``q_p`` (coefficients P, shape (n, 2H+1)),
turns the linearised equations of motion into the quadratic eigenvalue problem

    (J_0 + lambda Delta_1 + lambda^2 Delta_2) P = 0

with ``J_0`` the harmonic-balance Jacobian dR/dX at the solution (the structure's dynamic
stiffness plus the AFT contact tangent), ``Delta_1 = 2 Omega M (x) nabla + D (x) I + C_nl``
(``nabla`` the tau-derivative of the coefficients, ``C_nl`` the AFT tangent to the velocity
of velocity-dependent laws) and ``Delta_2 = M (x) I``. It is solved as the standard
eigenproblem of size 2 n (2H+1) of ``[[0, I], [-Delta_2^-1 J_0, -Delta_2^-1 Delta_1]]`` (dense
LAPACK ``geev``; the mass matrix must be invertible).

Each of the 2n Floquet exponents of the exact problem appears in the infinite Hill matrix
together with its copies ``lambda + i k Omega`` (k any integer), whose eigenvectors are the
exponent's eigenvector shifted by k harmonics. The truncated matrix has 2n (2H+1)
eigenvalues, of which those whose eigenvectors are "central" in the harmonic spectrum are
the best approximations (the copies near the truncation edge are spurious). The 2n retained
exponents are chosen by the **eigenvector criterion** of Lazarus & Thomas (2010): the
harmonic weights ``w_j = sum_dof |p_j|^2`` of the eigenvector in complex-exponential form
(j = -H..H) have a centre ``sum j w_j / sum w_j``; the 2n eigenvalues with the smallest
|centre| are kept. Near ties (|centre| within 0.1 of the last kept one; with H = 1 the
static block is exactly central too) are broken by the **imaginary-part criterion** (Moore
2005: smallest |Im lambda|), which is also available on its own (``sorting="imaginary"``).
A solution is stable when every retained exponent has ``Re lambda <= tol Omega``
(multipliers ``mu = exp(lambda 2 pi / Omega)`` inside the unit circle).

Laws with memory (Jenkins, Iwan, Coulomb: ``n_state > 0``): a perturbation reaches the force
at t_i through the history since the last slip, ``sum_k S_ik p(t_k) e^{lambda (t_k - t_i)}``.
The AFT tangent is its value at lambda = 0; its first-order term ``lambda K_1`` (the damping
that friction gives to perturbations) is added to ``Delta_1`` (:meth:`_Hill._memory_tangent`);
higher orders in ``lambda T`` are neglected. Without K_1 a friction-damped resonance would
show only the structural decay rate (measured on the Jenkins oscillator: -0.020 1/s instead
of the -0.054 1/s of time integration, which K_1 reproduces within about 1 %). Folds and branch
points (lambda = 0) are exact either way.

Accuracy: the exponents converge with H like the solution; :func:`hill_stability` compares
them (modulo i Omega) with those of the solution re-solved with ``H + 1`` harmonics
(``exponent_error``).

Bifurcations along a branch (:func:`branch_stability`)
------------------------------------------------------
* **fold** (turning point, a real multiplier through +1): the parameter component of the
  path tangent changes sign; located by regula falsi on it;
* **branch point** (a real multiplier through +1 with a second branch crossing): the sign of
  det of the bordered Jacobian ``[[J, R_lambda], [t^T]]`` changes; located on that determinant;
* **Neimark-Sacker** (a complex pair of multipliers crosses the unit circle) and **period
  doubling** (a real multiplier through -1): the number of unstable exponents changes between
  two points without a fold or branch point; located on the largest real part of the
  exponents of that kind.

Each is located between the two continuation points that bracket it with
:func:`fricdamp.solvers.continuation.locate_on_branch` (trial points corrected onto the path).

References
----------
Hill (1886), Acta Math. 8, 1-36.
Moore (2005), Floquet theory as a computational tool, SIAM J. Numer. Anal. 42(6), 2522-2568.
Lazarus & Thomas (2010), A harmonic-based method for computing the stability of periodic
solutions of dynamical systems, C. R. Mécanique 338, 510-517.
Peletan, Baguet, Torkhani & Jacquet-Richardet (2013), A comparison of stability
computational methods for periodic solution of nonlinear problems with application to
rotordynamics, Nonlinear Dyn. 72, 671-682.
Krack & Gross (2019), *Harmonic Balance for Nonlinear Vibration Problems*, Springer
(stability analysis by Hill's method).
Seydel (2010), *Practical Bifurcation and Stability Analysis*, Springer, ch. 5 and 7.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from fricdamp.errors import ModelError
from fricdamp.results import ResultMixin
from fricdamp.solvers._hb_formulations import _dense, _Full, _Setup
from fricdamp.solvers._hb_results import Bifurcation, SteadyState, peak_amplitude
from fricdamp.solvers.continuation import blas_threads, locate_on_branch
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem

__all__ = ["FloquetResult", "hill_stability"]

logger = logging.getLogger(__name__)

#: Largest Hill eigenproblem (2 n (2H+1)) solved densely.
MAX_HILL_SIZE = 6000
#: Near-tie width of the eigenvector centrality (in harmonics).
_TIE = 0.1
#: Multiplier angles within this fraction of pi of 0 or pi count as real.
_REAL_ANGLE = 0.04


# ============================================================================ Hill matrix
class _Hill:
    """The Hill eigenproblem of one system at H harmonics (built once, used per point)."""

    def __init__(self, s: _Setup):
        self.s = s
        n, nh = s.n, s.nh
        self.n, self.nh, self.N = n, nh, n * nh
        if 2 * self.N > MAX_HILL_SIZE:
            raise ModelError(f"Hill stability needs a dense eigenproblem of size 2 n_dof (2H+1) "
                             f"= {2 * self.N} > {MAX_HILL_SIZE}: reduce the model or harmonics")
        Md = _dense(s.M)
        cond = np.linalg.cond(Md) if n else 1.0
        if not np.isfinite(cond) or cond > 1e12:
            raise ModelError(f"Hill stability needs a non-singular mass matrix (condition "
                             f"number {cond:.3g} > 1e12): give every DOF a mass")
        self.Minv = np.linalg.inv(Md)
        self.full = _Full(s, dense=True)
        eye_h = np.eye(nh)
        self.MinvD = np.kron(self.Minv @ _dense(s.D), eye_h)
        self.Nabla = np.kron(np.eye(n), s.ED)           # d/dtau of the coefficients
        self.vel_dep = any(c.law.velocity_dependent and c.law.n_state == 0
                           for c in s.contacts)
        self.memory = any(c.law.n_state > 0 for c in s.contacts)

    def _minv(self, A):
        """(M^-1 (x) I) A for A (N, N)."""
        return np.einsum("ij,jhk->ihk", self.Minv, A.reshape(self.n, self.nh, -1)
                         ).reshape(self.N, -1)

    def _velocity_tangent(self, X, omega):
        """(M^-1 (x) I) C_nl: AFT tangent of the contact forces to the velocity coefficients."""
        s = self.s
        basis = s.basis
        U = s.P @ X
        u_time = basis.synthesis @ U.T
        v_time = omega * (basis.derivative @ U.T)
        Nt, nh = basis.samples, s.nh
        C = np.zeros((self.N, self.N))
        Pd = s.P.toarray()
        zero = np.zeros_like(basis.synthesis)
        for c, rows in zip(s.contacts, s.rows, strict=True):
            if not c.law.velocity_dependent or c.law.n_state > 0:
                continue      # laws with memory: in _memory_tangent
            nc, nd = c.n_contacts, c.n_dir
            res = c.law.periodic_response(u_time[:, rows].reshape(Nt, nc, nd),
                                          v_time[:, rows].reshape(Nt, nc, nd), basis=zero,
                                          velocity_basis=basis.synthesis)
            J = (basis.analysis @ res.jacobian.reshape(Nt, -1)).reshape(nh, nc, nd, nd, nh)
            G = sla.block_diag(*J.transpose(1, 2, 0, 3, 4).reshape(nc, nd * nh, nd * nh))
            Pk = np.kron(Pd[rows], np.eye(nh))
            C += Pk.T @ G @ Pk
        return self._minv(C)

    def _memory_tangent(self, X, omega):
        """(M^-1 (x) I) K_1: first-order lambda term of the tangent of laws with memory.

        A perturbation ``e^{lambda t} p(t)`` reaches the force at t_i through the history
        samples t_k <= t_i as ``sum_k S_ik p(t_k) e^{lambda (t_k - t_i)}``; the AFT tangent is
        its value at lambda = 0 and ``K_1 = sum_k S_ik (t_k - t_i) p(t_k)`` the first-order
        term. It is obtained by marching the law over two periods from its periodic state
        with the input perturbed by ``t b_j(t)`` (velocity ``t b_j' + b_j``), t in [-T, T),
        central differences, and subtracting ``t_i`` times the AFT tangent; memory older than
        one period (a slider that never slips keeps none) is not seen.
        """
        s = self.s
        basis = s.basis
        Nt, nh = basis.samples, s.nh
        T = 2 * np.pi / omega
        dt = T / Nt
        t2 = (np.arange(2 * Nt) - Nt) * dt
        t1 = np.arange(Nt) * dt
        B2 = np.vstack([basis.synthesis, basis.synthesis])
        dB2 = omega * np.vstack([basis.derivative, basis.derivative])
        U = s.P @ X
        u_time = basis.synthesis @ U.T
        v_time = omega * (basis.derivative @ U.T)
        Pd = s.P.toarray()
        K1 = np.zeros((self.N, self.N))
        for c, rows in zip(s.contacts, s.rows, strict=True):
            law = c.law
            if law.n_state == 0:
                continue
            nc, nd = c.n_contacts, c.n_dir
            u3 = u_time[:, rows].reshape(Nt, nc, nd)
            v3 = v_time[:, rows].reshape(Nt, nc, nd) if law.velocity_dependent else None
            vb = omega * basis.derivative if law.velocity_dependent else None
            res = law.periodic_response(u3, v3, basis=basis.synthesis, velocity_basis=vb)
            u2 = np.concatenate([u3, u3])
            v2 = None if v3 is None else np.concatenate([v3, v3])
            umax = np.max(np.abs(u3), axis=(0, 2))
            h = 1e-6 * np.maximum(umax, max(1e-3 * float(umax.max(initial=0.0)), 1e-12)) / T
            G = np.zeros((Nt, nc, nd, nd, nh))
            for d in range(nd):
                for j in range(nh):
                    fs = []
                    for sgn in (1.0, -1.0):
                        du = np.zeros_like(u2)
                        du[:, :, d] = sgn * (t2 * B2[:, j])[:, None] * h[None, :]
                        dv = None
                        if v2 is not None:
                            dv = np.zeros_like(v2)
                            dv[:, :, d] = sgn * ((t2 * dB2[:, j] + B2[:, j])[:, None]
                                                 * h[None, :])
                        f, _ = law.march(u2 + du, state=res.state,
                                         v_history=None if v2 is None else v2 + dv)
                        fs.append(f[Nt:])
                    G[:, :, :, d, j] = (fs[0] - fs[1]) / (2 * h[None, :, None])
            G -= t1[:, None, None, None, None] * res.jacobian
            J = (basis.analysis @ G.reshape(Nt, -1)).reshape(nh, nc, nd, nd, nh)
            Gb = sla.block_diag(*J.transpose(1, 2, 0, 3, 4).reshape(nc, nd * nh, nd * nh))
            Pk = np.kron(Pd[rows], np.eye(nh))
            K1 += Pk.T @ Gb @ Pk
        return self._minv(K1)

    def eig(self, X, omega, load_scale=1.0):
        """All eigenvalues (2N,) and the displacement part of the eigenvectors (N, 2N)."""
        J0, _ = self.jacobian(X, omega, load_scale)
        N = self.N
        A = np.zeros((2 * N, 2 * N))
        A[:N, N:] = np.eye(N)
        A[N:, :N] = -self._minv(J0)
        D1 = 2.0 * omega * self.Nabla + self.MinvD
        if self.vel_dep:
            D1 = D1 + self._velocity_tangent(X, omega)
        if self.memory:
            D1 = D1 + self._memory_tangent(X, omega)
        A[N:, N:] = -D1
        lam, V = sla.eig(A, check_finite=False, overwrite_a=True)
        return lam, V[:N]

    def jacobian(self, X, omega, load_scale=1.0):
        _, J, dr, _, _ = self.full.evaluate(np.asarray(X, float).ravel(), omega,
                                            load_scale=load_scale)
        return J, dr


def _centre(V, n, nh):
    """Centre ``sum j w_j / sum w_j`` of the harmonic weights of eigenvectors V (n nh, m)."""
    P = V.reshape(n, nh, -1)
    a, b = P[:, 1::2], P[:, 2::2]
    wp = np.sum(np.abs(a - 1j * b) ** 2, axis=0) / 4.0           # e^{+i k tau}, (H, m)
    wm = np.sum(np.abs(a + 1j * b) ** 2, axis=0) / 4.0
    w0 = np.sum(np.abs(P[:, 0]) ** 2, axis=0)
    k = np.arange(1, wp.shape[0] + 1)[:, None]
    tot = w0 + wp.sum(axis=0) + wm.sum(axis=0)
    return np.sum(k * (wp - wm), axis=0) / np.maximum(tot, 1e-300)


def _select(lam, V, n, nh, n_keep, sorting):
    """Indices of the retained exponents and the sorting margin (see the module docstring)."""
    finite = np.isfinite(lam)
    if sorting == "imaginary":
        key = np.where(finite, np.abs(lam.imag), np.inf)
        order = np.argsort(key, kind="stable")
        keep = order[:n_keep]
        c = np.abs(_centre(V, n, nh))
        rest = order[n_keep:]
        margin = (float(np.min(np.abs(lam[rest].imag)) - np.max(np.abs(lam[keep].imag)))
                  if rest.size else np.inf)
        return keep, margin, c
    c = np.where(finite, np.abs(_centre(V, n, nh)), np.inf)
    order = np.lexsort((np.abs(lam.imag), c))
    cut = c[order[n_keep - 1]]
    sure = order[c[order] < cut - _TIE]
    tied = order[np.abs(c[order] - cut) <= _TIE]
    tied = tied[np.argsort(np.abs(lam[tied].imag), kind="stable")]
    keep = np.concatenate([sure, tied[: n_keep - sure.size]])
    rest = np.setdiff1d(np.arange(lam.size), keep)
    margin = float(np.min(c[rest]) - np.max(c[keep])) if rest.size else np.inf
    return keep, margin, c


def _exponents(hill: _Hill, X, omega, load_scale=1.0, sorting="eigenvector"):
    """Retained Floquet exponents (2n,), sorted by decreasing real part, and the margin."""
    lam, V = hill.eig(X, omega, load_scale)
    keep, margin, _ = _select(lam, V, hill.n, hill.nh, 2 * hill.n, sorting)
    ex = lam[keep]
    ex = ex[np.lexsort((-ex.imag, -ex.real))]
    return ex, margin


def _angle(ex, omega):
    """Multiplier angle |arg mu| / pi in [0, 1] of exponents ex at Omega."""
    ph = np.mod(ex.imag * 2 * np.pi / omega + np.pi, 2 * np.pi) - np.pi
    return np.abs(ph) / np.pi


def _is_stable(ex, omega, tol):
    return bool(ex.size == 0 or np.max(ex.real) <= tol * omega)


# ============================================================================ one point
def _exponent_vars(ex: np.ndarray, dims: tuple) -> dict:
    """Real part [1/s] and imaginary part [rad/s] and [Hz] of Floquet exponents as Dataset
    variables."""
    return {"exponent_real": (dims, np.real(ex), {"units": "1/s",
                                                  "long_name": "growth rate Re(lambda)"}),
            "exponent_imag": (dims, np.imag(ex), {"units": "rad/s",
                                                  "long_name": "Im(lambda)"}),
            "exponent_imag_hz": (dims, np.imag(ex) / (2 * np.pi),
                                 {"units": "Hz", "long_name": "Im(lambda) / 2 pi"})}


@dataclass(frozen=True, eq=False, repr=False)
class FloquetResult(ResultMixin):
    """Stability of one periodic solution by Hill's method (:func:`hill_stability`).

    Attributes
    ----------
    exponents : ndarray, shape (2 n_dof,), complex
        Retained Floquet exponents lambda [1/s], by decreasing real part.
    multipliers : ndarray, shape (2 n_dof,), complex
        Floquet multipliers ``exp(lambda 2 pi / Omega)`` [-].
    stable : bool
        Every retained exponent has ``Re lambda <= tol Omega``.
    max_real : float
        Largest real part [1/s] (the growth rate of the fastest growing perturbation).
    omega : float
        Fundamental angular frequency [rad/s].
    harmonics : int
        H of the Hill matrix.
    sorting : str
        "eigenvector" or "imaginary" (see the module docstring).
    sorting_margin : float
        Gap between the retained and the rejected eigenvalues in the sorting key (harmonics
        for "eigenvector", rad/s for "imaginary"); small or negative means an ambiguous choice.
    check_harmonics : int or None
        H of the convergence check (None if not made).
    exponent_error : float
        Largest distance [1/s] between the retained exponents at H and at ``check_harmonics``
        (matched pairwise); NaN without a check.
    verdict_agrees : bool or None
        The check gives the same stability verdict.
    """

    exponents: np.ndarray
    multipliers: np.ndarray
    stable: bool
    max_real: float
    omega: float
    harmonics: int
    sorting: str
    sorting_margin: float
    check_harmonics: int | None = None
    exponent_error: float = float("nan")
    verdict_agrees: bool | None = None

    @property
    def frequency_hz(self) -> float:
        """Fundamental frequency [Hz]."""
        return self.omega / (2 * np.pi)

    def _judge(self):
        from fricdamp.results import status_verdict

        reasons = []
        if self.verdict_agrees is False:
            reasons.append(f"the stability verdict changes with {self.check_harmonics} "
                           f"harmonics instead of {self.harmonics}: raise harmonics")
        if self.sorting_margin <= 0:
            reasons.append(f"the choice of the Floquet exponents is ambiguous (sorting margin "
                           f"{self.sorting_margin:.3g}): raise harmonics or try "
                           f"sorting='imaginary'")
        est = {"exponent_error_relative": float(self.exponent_error / self.omega)
               if self.omega > 0 and np.isfinite(self.exponent_error) else None,
               "sorting_margin": float(self.sorting_margin)}
        return status_verdict(True, "", est, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` over the retained exponents: ``exponent_real`` [1/s],
        ``exponent_imag`` [rad/s] (``exponent_imag_hz`` [Hz]), ``multiplier_real`` and
        ``multiplier_imag`` [-]; the frequency in Hz (``frequency_hz``) and [rad/s]
        (``omega_rad_s``) as attributes."""
        import xarray as xr

        dims = ("exponent",)
        data = _exponent_vars(self.exponents, dims)
        data["multiplier_real"] = (dims, np.real(self.multipliers), {"units": "1"})
        data["multiplier_imag"] = (dims, np.imag(self.multipliers), {"units": "1"})
        data["multiplier_modulus"] = (dims, np.abs(self.multipliers), {"units": "1"})
        return xr.Dataset(data, attrs={
            "stable": int(self.stable), "max_real_1_per_s": float(self.max_real),
            "frequency_hz": float(self.frequency_hz), "omega_rad_s": float(self.omega),
            "harmonics": int(self.harmonics), "sorting": self.sorting,
            "sorting_margin": float(self.sorting_margin),
            "check_harmonics": -1 if self.check_harmonics is None else
            int(self.check_harmonics),
            "exponent_error_1_per_s": float(self.exponent_error)})

    def plot(self, ax=None):
        """Floquet multipliers in the complex plane with the unit circle (outside:
        unstable); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(4.6, 4.4))
        phi = np.linspace(0.0, 2 * np.pi, 361)
        ax.plot(np.cos(phi), np.sin(phi), "k-", lw=0.8, label="|mu| = 1")
        out = np.abs(self.multipliers) > 1.0 + 1e-12
        ax.plot(self.multipliers.real[~out], self.multipliers.imag[~out], "o", color="C0",
                mfc="none", label="stable side")
        if np.any(out):
            ax.plot(self.multipliers.real[out], self.multipliers.imag[out], "x", color="C3",
                    ms=8, label="outside: unstable")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("Re(mu)")
        ax.set_ylabel("Im(mu)")
        ax.set_title(f"Floquet multipliers at {self.frequency_hz:.4g} Hz "
                     f"({'stable' if self.stable else 'unstable'})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
        return ax


def _match_error(a, b, omega):
    """Largest distance modulo i Omega (exponents are defined modulo i Omega: equal
    multipliers) over the optimal pairing of two exponent sets [1/s]."""
    from scipy.optimize import linear_sum_assignment

    if a.size == 0:
        return 0.0
    d = a[:, None] - b[None, :]
    dim = np.mod(d.imag + omega / 2, omega) - omega / 2
    cost = np.hypot(d.real, dim)
    i, j = linear_sum_assignment(cost)
    return float(np.max(cost[i, j]))


def _check_sorting(sorting):
    if sorting not in ("eigenvector", "imaginary"):
        raise ModelError(f"sorting must be 'eigenvector' or 'imaginary', got {sorting!r}")


def _pad(X, H_new):
    X = np.asarray(X, dtype=float)
    out = np.zeros(X.shape[:-1] + (2 * H_new + 1,))
    m = min(X.shape[-1], out.shape[-1])
    out[..., :m] = X[..., :m]
    return out


def _scaled_system(system: MechanicalSystem, load_scale: float) -> MechanicalSystem:
    if load_scale == 1.0:
        return system
    loads = [HarmonicLoad(ld.amplitude * load_scale, omega=ld.omega, harmonic=ld.harmonic)
             if isinstance(ld, HarmonicLoad) and ld.harmonic != 0 else ld
             for ld in system.loads]
    return system.with_loads(*loads)


def _check_at(system, X, omega, H, samples, H_check, sorting, tol, ex_H, load_scale=1.0):
    """Exponents of the solution re-solved with H_check harmonics: (error, agrees)."""
    from fricdamp.solvers.hb import harmonic_balance

    N = samples if samples is not None and samples >= 2 * H_check + 1 else None
    ss = harmonic_balance(_scaled_system(system, load_scale), omega, harmonics=H_check,
                          samples=N, initial_guess=_pad(X, H_check), blas=None)
    if not ss.success:
        return np.nan, None
    hill = _Hill(_Setup(system, H_check, ss.samples))
    ex2, _ = _exponents(hill, ss.coefficients, omega, sorting=sorting)
    agrees = _is_stable(ex2, omega, tol) == _is_stable(ex_H, omega, tol)
    return _match_error(ex_H, ex2, omega), agrees


def hill_stability(system: MechanicalSystem, state: SteadyState, *,
                   sorting: str = "eigenvector", check_harmonics: int | None = -1,
                   tol: float = 1e-6, blas: int | None = 1) -> FloquetResult:
    """Floquet exponents and stability of a harmonic-balance solution by Hill's method.

    Parameters
    ----------
    system : MechanicalSystem
        The system ``state`` was computed for (same loads).
    state : SteadyState
        A converged solution of :func:`fricdamp.solvers.hb.harmonic_balance` (or
        ``FrequencyResponse.steady_state(i)``).
    sorting : {"eigenvector", "imaginary"}
        Criterion choosing the 2 n_dof exponents among the 2 n_dof (2H+1) eigenvalues.
    check_harmonics : int or None
        Re-solve with this many harmonics and compare the exponents (-1: H + 1; None: no
        check).
    tol : float
        Stable when ``max Re lambda <= tol * Omega`` (marginal exponents count as stable).
    blas : int or None
        BLAS threads (default 1).

    Returns
    -------
    FloquetResult

    Raises
    ------
    ModelError
        If the state did not converge, the mass matrix is singular or the eigenproblem is
        larger than :data:`MAX_HILL_SIZE`.

    Examples
    --------
    >>> from fricdamp.contact import CubicSpring
    >>> from fricdamp.solvers.hb import harmonic_balance
    >>> from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem
    >>> duffing = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
    ...     contacts=(ContactElement(CubicSpring(0.5), [[1.0]]),),
    ...     loads=(HarmonicLoad([0.03], omega=1.0),))
    >>> fl = hill_stability(duffing, harmonic_balance(duffing, 0.8, harmonics=5))
    >>> fl.stable, round(float(fl.exponents.real.sum()), 6)  # trace: -c/m
    (True, -0.02)
    """
    _check_sorting(sorting)
    if not state.success:
        raise ModelError("state did not converge: no stability without a solution")
    if not (0 < tol < 1):
        raise ModelError(f"tol must lie in (0, 1) (fraction of Omega), got {tol!r}")
    H = int(state.harmonics)
    if check_harmonics == -1:
        check_harmonics = H + 1
    if check_harmonics is not None and (int(check_harmonics) != check_harmonics
                                        or check_harmonics < 1 or check_harmonics == H):
        raise ModelError(f"check_harmonics must be an integer >= 1 other than H = {H}, got "
                         f"{check_harmonics!r}")
    omega = float(state.omega)
    with blas_threads(blas):
        hill = _Hill(_Setup(system, H, state.samples))
        ex, margin = _exponents(hill, state.coefficients, omega, sorting=sorting)
        err, agrees = np.nan, None
        if check_harmonics is not None:
            err, agrees = _check_at(system, state.coefficients, omega, H, state.samples,
                                    int(check_harmonics), sorting, tol, ex)
    T = 2 * np.pi / omega
    return FloquetResult(ex, np.exp(ex * T), _is_stable(ex, omega, tol),
                         float(ex.real.max()) if ex.size else -np.inf, omega, H, sorting,
                         margin, check_harmonics, err, agrees)


# ============================================================================ branches
@dataclass(frozen=True, eq=False, repr=False)
class BranchStability(ResultMixin):
    """Stability of every point of a continued branch (filled into FrequencyResponse).

    Attributes
    ----------
    exponents : ndarray, shape (n_points, 2 n_dof), complex
        Floquet exponents [1/s] of every point.
    stable : ndarray, shape (n_points,), bool
    bifurcations : tuple of Bifurcation
    exponent_error : float
        [1/s], largest change of the exponents with one more harmonic over the checked
        points (NaN without a check).
    verdict_agrees : bool or None
        The check with one more harmonic gives the same verdicts.
    checked_points : tuple of int
        Indices of the points checked.
    """

    exponents: np.ndarray              # (n_points, 2 n_dof) complex [1/s]
    stable: np.ndarray                 # (n_points,) bool
    bifurcations: tuple[Bifurcation, ...]
    exponent_error: float              # [1/s], largest over the checked points
    verdict_agrees: bool | None
    checked_points: tuple[int, ...]

    def _judge(self):
        from fricdamp.results import status_verdict

        reasons = []
        if self.verdict_agrees is False:
            reasons.append("the stability verdicts change with one more harmonic: raise "
                           "harmonics")
        return status_verdict(True, "", {}, reasons=reasons)

    def to_xarray(self):
        """``xarray.Dataset`` over (point, exponent): ``exponent_real`` [1/s],
        ``exponent_imag`` [rad/s] (and [Hz]), ``max_real`` [1/s], ``stable`` (int8); the bifurcation
        types and points as attributes."""
        import xarray as xr

        ex = np.asarray(self.exponents)
        data = _exponent_vars(ex, ("point", "exponent"))
        data["max_real"] = ("point", ex.real.max(axis=1) if ex.size else
                            np.zeros(ex.shape[0]), {"units": "1/s"})
        data["stable"] = ("point", np.asarray(self.stable, np.int8))
        return xr.Dataset(data, attrs={
            "bifurcation_types": ",".join(b.type for b in self.bifurcations),
            "bifurcation_frequency_hz": ",".join(f"{b.omega / (2 * np.pi):.12g}"
                                                 for b in self.bifurcations),
            "exponent_error_1_per_s": float(self.exponent_error),
            "checked_points": ",".join(str(int(i)) for i in self.checked_points)})

    def plot(self, ax=None):
        """Largest real part of the Floquet exponents along the branch; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5.5, 3.8))
        ex = np.asarray(self.exponents)
        mr = ex.real.max(axis=1) if ex.size else np.zeros(ex.shape[0])
        i = np.arange(mr.size)
        st = np.asarray(self.stable, bool)
        ax.plot(i, mr, "-", color="0.6", lw=0.8)
        ax.plot(i[st], mr[st], ".", color="C0", label="stable")
        if np.any(~st):
            ax.plot(i[~st], mr[~st], ".", color="C3", label="unstable")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xlabel("branch point")
        ax.set_ylabel("max Re(lambda) [1/s]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
        return ax


def _kind(ex_u, omega):
    """Kind of the crossing exponent of the unstable side: 'real+', 'real-' or 'complex'."""
    i = int(np.argmax(ex_u.real))
    ang = _angle(ex_u[i:i + 1], omega)[0]
    if ang <= _REAL_ANGLE:
        return "real+"
    if ang >= 1 - _REAL_ANGLE:
        return "real-"
    return "complex"


def branch_stability(system, s: _Setup, form, residual, cres, X, omegas, scales, param, *,
                     x_ref=1.0, sorting="eigenvector", tol=1e-6, check_harmonics=-1,
                     n_checks=5, locate=True, corrector_tol=1e-9) -> BranchStability:
    """Floquet exponents at every point of a branch, bifurcations detected and located.

    ``cres`` is the ContinuationResult of the branch (``test_functions=True``), ``residual``
    the continued residual, ``X`` (n_points, n, 2H+1), ``omegas``/``scales`` the frequency and
    load scale of each point, ``param`` "omega" or "load"; ``form.to_dofs`` maps the
    continued unknowns back to the DOFs.
    """
    _check_sorting(sorting)
    hill = _Hill(s)
    n_p = X.shape[0]
    n = s.n
    ex = np.zeros((n_p, 2 * n), complex)
    for p in range(n_p):
        ex[p], _ = _exponents(hill, X[p], float(omegas[p]), float(scales[p]), sorting)
    stable = np.array([_is_stable(ex[p], omegas[p], tol) for p in range(n_p)], dtype=bool)
    n_unst = np.array([int(np.sum(ex[p].real > tol * omegas[p])) for p in range(n_p)])
    lam_scale = cres.lam_scale
    x_scale = cres.x_scale if cres.x_scale is not None else 1.0
    tng = cres.tangents
    dets = cres.det_sign
    nx = cres.x.shape[1]
    bifs: list[Bifurcation] = []

    def point_from(pt):
        lam = pt.lam
        w = lam if param == "omega" else float(omegas[0])
        ls = 1.0 if param == "omega" else lam
        Xd = form.to_dofs(pt.x, w, x_ref, load_scale=ls)
        return Xd, w, ls

    def record(kind, i, loc, critical):
        if loc is not None and loc.point is not None:
            Xd, w, ls = point_from(loc.point)
            e, _ = _exponents(hill, Xd, w, ls, sorting)
            located = bool(loc.converged)
        else:     # not located: report the nearer end point
            j = i if abs(_crit(ex[i], omegas[i], critical)) <= abs(
                _crit(ex[i + 1], omegas[i + 1], critical)) else i + 1
            Xd, w, ls, e, located = X[j], float(omegas[j]), float(scales[j]), ex[j], False
        mu = _critical_multiplier(e, w, critical)
        bifs.append(Bifurcation(kind, float(w), float(ls), peak_amplitude(Xd), Xd, int(i),
                                complex(mu), located))

    def locate_with(i, test):
        if not locate:
            return None
        return locate_on_branch(residual, cres.x[i], cres.lam[i], cres.x[i + 1],
                                cres.lam[i + 1], tng[i], test, x_scale=x_scale,
                                lam_scale=lam_scale, tol=corrector_tol, xtol=1e-10,
                                max_trials=40)

    for i in range(n_p - 1):
        fold = tng is not None and tng[i][nx] * tng[i + 1][nx] < 0
        bp = dets is not None and dets[i] * dets[i + 1] < 0
        if fold:
            record("fold", i, locate_with(i, lambda pt: pt.tangent[-1]), "real+")
        if bp:
            ref = {}

            def det_test(pt, ref=ref):
                ref.setdefault("log", pt.log_abs_det)
                return pt.det_sign * np.exp(np.clip(pt.log_abs_det - ref["log"], -700, 700))

            record("branch_point", i, locate_with(i, det_test), "real+")
        if n_unst[i] != n_unst[i + 1]:
            j = i if n_unst[i] > n_unst[i + 1] else i + 1
            kind = _kind(ex[j], omegas[j])
            if kind == "real+":
                if not (fold or bp):
                    logger.debug("a real multiplier crosses +1 between points %d and %d "
                                 "without a fold or branch-point test change", i, i + 1)
                continue
            name = "neimark_sacker" if kind == "complex" else "period_doubling"

            def crit_test(pt, kind=kind):
                Xd, w, ls = point_from(pt)
                e, _ = _exponents(hill, Xd, w, ls, sorting)
                return _crit(e, w, kind)

            record(name, i, locate_with(i, crit_test), kind)

    # convergence in H at a few points (and on both sides of every bifurcation)
    err, agrees, checked = np.nan, None, ()
    if check_harmonics is not None and n_p:
        H2 = s.H + 1 if check_harmonics == -1 else int(check_harmonics)
        idx = set(np.unique(np.linspace(0, n_p - 1, min(n_checks, n_p)).round().astype(int)))
        for b in bifs:
            idx |= {b.after_point, min(b.after_point + 1, n_p - 1)}
        checked = tuple(sorted(int(i) for i in idx))
        errs, agr = [], []
        for i in checked:
            e_i, a_i = _check_at(system, X[i], float(omegas[i]), s.H, s.basis.samples, H2,
                                 sorting, tol, ex[i], float(scales[i]))
            errs.append(e_i)
            agr.append(a_i)
        errs = np.asarray(errs, float)
        err = float(np.nanmax(errs)) if np.any(np.isfinite(errs)) else np.nan
        agrees = None if any(a is None for a in agr) else bool(all(agr))
    return BranchStability(ex, stable, tuple(bifs), err, agrees, checked)


def _crit(ex, omega, kind):
    """Largest real part [1/s] among the exponents of one kind ('real+', 'real-', 'complex')."""
    ang = _angle(ex, omega)
    if kind == "real+":
        sel = ang <= _REAL_ANGLE
    elif kind == "real-":
        sel = ang >= 1 - _REAL_ANGLE
    else:
        sel = (ang > _REAL_ANGLE) & (ang < 1 - _REAL_ANGLE)
    return float(np.max(ex.real[sel])) if np.any(sel) else float(np.max(ex.real))


def _critical_multiplier(ex, omega, kind):
    """The multiplier of the given kind closest to the unit circle."""
    mu = np.exp(ex * 2 * np.pi / omega)
    ang = _angle(ex, omega)
    if kind == "real+":
        sel = ang <= _REAL_ANGLE
    elif kind == "real-":
        sel = ang >= 1 - _REAL_ANGLE
    else:
        sel = (ang > _REAL_ANGLE) & (ang < 1 - _REAL_ANGLE)
    cand = mu[sel] if np.any(sel) else mu
    return cand[np.argmin(np.abs(np.abs(cand) - 1.0))]
