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
from fricdamp.results import ResultMixin
from fricdamp.solvers.fast_transient import (
    ENERGY_KEYS,
    _blas1,
    _contact_energy,
    _eval_contacts,
)
from fricdamp.solvers.newmark import NewmarkScheme
from fricdamp.solvers.timestep import EnergyBalance, _progress_default, check_time_span

__all__ = ["ModalBasis", "ModalStaticResult", "ModalTransientResult", "contact_law_arrays",
           "integrate_modal", "solve_static_modal", "transient_compliance", "CyclicRows"]

log = logging.getLogger(__name__)


class _DenseRows:
    """Contact rows as a dense matrix B (m x n_modes)."""

    def __init__(self, B: np.ndarray):
        self.B = B
        self.m, self.n = B.shape
        self.block_rows = None

    def rows(self, eta):
        return self.B @ eta

    def rows_T(self, f):
        return self.B.T @ f

    def compliance(self, s) -> _DenseCompliance:
        return _DenseCompliance(np.ascontiguousarray((self.B * s) @ self.B.T))


class _DenseCompliance:
    """``C = B diag(s) B^T`` as a dense matrix."""

    def __init__(self, C: np.ndarray):
        self.C = C
        self.m = C.shape[0]

    def apply(self, f):
        return self.C @ f

    def diagonal_block(self, sl: slice):
        return self.C[sl, sl]

    def submatrix(self, idx):
        return self.C[np.ix_(idx, idx)]

    def dense(self):
        return self.C

    def chord(self, kdiag, ap):
        lu = sla.lu_factor(np.eye(self.m) + ap * self.C * kdiag[None, :], check_finite=False)
        return lambda g: sla.lu_solve(lu, g, check_finite=False)


@dataclass(frozen=True)
class CyclicRows:
    """Contact rows of the real modes of a cyclic wheel, harmonic by harmonic.

    The wheel has ``N`` sectors and one contact of ``r`` rows per sector (rows
    ``j r .. (j + 1) r`` belong to contact j). For harmonic ``k`` the modes are the standing
    waves of the sector eigenvectors whose contact rows on contact ``j`` are
    ``w Re / Im(exp(2 pi i k j / N) X_k)`` (cos / sin, ``w = sqrt(2/N)``, interleaved
    cos, sin per eigenvector) or ``w exp(2 pi i k j / N) X_k`` (real, ``k = 0, N/2``,
    ``w = 1/sqrt(N)``). Then (derived in the module docstring of
    :mod:`fricdamp.solvers.modal_transient`)::

        u = irfft_j(U_k),  U_k = (N / 2 or N) X_k w (eta_cos - i eta_sin)
        (B^T f)_cos/sin = w Re / -Im (X_k^H f_k),  f_k = rfft_j(f)
        C f = irfft_j(H_k f_k),  H_k = X_k diag(s_k) X_k^H

    so products with B cost ``sum_k r n_k`` instead of ``N r n`` and the compliance is
    block-circulant: ``N/2 + 1`` blocks of ``r x r``.

    Attributes
    ----------
    n_sectors : int
    harmonics : tuple of int
        Harmonic index k of each block (0 <= k <= N/2, distinct).
    blocks : tuple of ndarray, each (r, n_k) complex
        ``X_k``.
    columns : tuple of slice
        The modal coordinates of harmonic k (``2 n_k`` for paired harmonics).
    """

    n_sectors: int
    harmonics: tuple
    blocks: tuple
    columns: tuple

    def __post_init__(self):
        N = int(self.n_sectors)
        r = {X.shape[0] for X in self.blocks}
        if len(r) != 1 or len(self.blocks) != len(self.harmonics) != len(self.columns):
            raise ModelError("CyclicRows: one block of equal row count per harmonic")
        object.__setattr__(self, "n_sectors", N)
        object.__setattr__(self, "blocks", tuple(np.ascontiguousarray(X, dtype=complex)
                                                 for X in self.blocks))
        for k, X, sl in zip(self.harmonics, self.blocks, self.columns, strict=True):
            if not 0 <= k <= N // 2:
                raise ModelError(f"harmonic {k} out of [0, {N // 2}]")
            if sl.stop - sl.start != X.shape[1] * (1 if self._real(k) else 2):
                raise ModelError(f"harmonic {k}: {sl.stop - sl.start} columns for "
                                 f"{X.shape[1]} sector modes")

    def _real(self, k) -> bool:
        return (2 * int(k)) % self.n_sectors == 0

    @property
    def r(self) -> int:
        return self.blocks[0].shape[0]

    @property
    def m(self) -> int:
        return self.n_sectors * self.r

    @property
    def n(self) -> int:
        return max(sl.stop for sl in self.columns)

    @property
    def block_rows(self) -> int:
        return self.r

    def rows(self, eta):
        N, r = self.n_sectors, self.r
        U = np.zeros((N // 2 + 1, r), dtype=complex)
        for k, X, sl in zip(self.harmonics, self.blocks, self.columns, strict=True):
            e = eta[sl]
            if self._real(k):
                U[k] = N / np.sqrt(N) * (X @ e)
            else:
                U[k] = (N / 2) * np.sqrt(2.0 / N) * (X @ (e[0::2] - 1j * e[1::2]))
        return np.fft.irfft(U, n=N, axis=0).reshape(-1)

    def rows_T(self, f):
        N = self.n_sectors
        fh = np.fft.rfft(np.asarray(f).reshape(N, self.r), axis=0)
        out = np.zeros(self.n)
        for k, X, sl in zip(self.harmonics, self.blocks, self.columns, strict=True):
            a = X.conj().T @ fh[k]
            if self._real(k):
                out[sl] = a.real / np.sqrt(N)
            else:
                w = np.sqrt(2.0 / N)
                seg = np.empty(2 * a.size)
                seg[0::2], seg[1::2] = w * a.real, -w * a.imag
                out[sl] = seg
        return out

    def compliance(self, s) -> _CyclicCompliance:
        H = {}
        for k, X, sl in zip(self.harmonics, self.blocks, self.columns, strict=True):
            sk = s[sl] if self._real(k) else s[sl][0::2]
            H[k] = (X * sk) @ X.conj().T
        return _CyclicCompliance(self.n_sectors, self.r, H)

    def dense(self) -> np.ndarray:
        """The equivalent dense B (m x n), for tests and small wheels."""
        eye = np.eye(self.n)
        return np.column_stack([self.rows(eye[:, i]) for i in range(self.n)])


class _CyclicCompliance:
    """Block-circulant ``C`` from its harmonic blocks ``H_k`` (r x r)."""

    def __init__(self, N: int, r: int, H: dict):
        self.N, self.r, self.H = N, r, H
        self.m = N * r

    def _spectral(self, f, fn):
        fh = np.fft.rfft(np.asarray(f).reshape(self.N, self.r), axis=0)
        out = np.zeros_like(fh)
        for k in self.H:
            out[k] = fn(k, fh[k])
        return np.fft.irfft(out, n=self.N, axis=0).reshape(-1)

    def apply(self, f):
        return self._spectral(f, lambda k, x: self.H[k] @ x)

    def circulant(self) -> np.ndarray:
        """``c(d)``, (N, r, r): the block coupling contact j to contact j - d."""
        if getattr(self, "_c", None) is None:
            Hs = np.zeros((self.N // 2 + 1, self.r, self.r), dtype=complex)
            for k, Hk in self.H.items():
                Hs[k] = Hk
            self._c = np.fft.irfft(Hs, n=self.N, axis=0)
        return self._c

    def submatrix(self, idx):
        c = self.circulant()
        idx = np.asarray(idx)
        j, p = np.divmod(idx, self.r)
        return c[(j[:, None] - j[None, :]) % self.N, p[:, None], p[None, :]]

    def diagonal_block(self, sl: slice):
        if sl.stop - sl.start != self.r or sl.start % self.r:
            raise ModelError("cyclic compliance: blocks must be whole contacts")
        c0 = np.zeros((self.r, self.r))
        for k, Hk in self.H.items():
            real = (2 * k) % self.N == 0
            c0 += (Hk.real if real else 2.0 * Hk.real)
        return c0 / self.N

    def dense(self):
        eye = np.eye(self.m)
        return np.column_stack([self.apply(eye[:, i]) for i in range(self.m)])

    def chord(self, kdiag, ap):
        kd = np.asarray(kdiag).reshape(self.N, self.r)
        if np.any(kd != kd[0]):
            raise ModelError("cyclic chord: the contacts must be the same on every sector")
        lus = {k: sla.lu_factor(np.eye(self.r) + ap * Hk * kd[0][None, :], check_finite=False)
               for k, Hk in self.H.items()}

        def solve(g):
            fh = np.fft.rfft(np.asarray(g).reshape(self.N, self.r), axis=0)
            out = fh.copy()        # harmonics without modes: identity
            for k, lu in lus.items():
                out[k] = sla.lu_solve(lu, fh[k], check_finite=False)
            return np.fft.irfft(out, n=self.N, axis=0).reshape(-1)

        return solve


@dataclass(frozen=True)
class ModalBasis:
    """Linear part of a model in mass-normalised undamped modes, seen from its contacts.

    Attributes
    ----------
    omega2 : ndarray, shape (n_modes,)
        Eigenvalues lambda = omega^2 [rad^2/s^2], all > 0 (a supported structure).
    damping : ndarray, shape (n_modes,)
        Modal damping ``c = Phi^T D Phi`` (diagonal) [1/s], e.g. ``a + b omega^2``.
    B : ndarray, shape (m, n_modes), or CyclicRows
        Contact rows: ``u = B eta`` are the local relative displacements (n, t1, t2 of each
        contact, stacked) [m per unit modal coordinate]; a :class:`CyclicRows` for a cyclic
        wheel (products by harmonic).
    output : ndarray, shape (n_out, n_modes)
        Shapes at the output DOFs (probes) [m per unit modal coordinate].
    groups : tuple of (str, int)
        Contact elements (name, number of contacts) in the order of B's rows; used for
        the block preconditioner and for reporting.
    """

    omega2: np.ndarray
    damping: np.ndarray
    B: object
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
        if isinstance(self.B, CyclicRows):
            rows = self.B
            if rows.n != n:
                raise ModelError(f"B (CyclicRows) has {rows.n} modal columns, omega2 {n}")
        else:
            B = np.ascontiguousarray(np.asarray(self.B, dtype=float))
            if B.ndim != 2 or B.shape[1] != n or B.shape[0] % 3:
                raise ModelError(f"B must have shape (3 n_contacts, {n}), got {B.shape}")
            object.__setattr__(self, "B", B)
            rows = _DenseRows(B)
        if rows.m % 3:
            raise ModelError(f"B must have 3 rows per contact, got {rows.m}")
        out = np.ascontiguousarray(np.asarray(self.output, dtype=float).reshape(-1, n))
        groups = tuple((str(a), int(b)) for a, b in (self.groups or (("contacts",
                                                                       rows.m // 3),)))
        if sum(b for _, b in groups) * 3 != rows.m:
            raise ModelError(f"groups must count the {rows.m // 3} contacts of B, got "
                             f"{sum(b for _, b in groups)}")
        object.__setattr__(self, "omega2", lam)
        object.__setattr__(self, "damping", c)
        object.__setattr__(self, "output", out)
        object.__setattr__(self, "groups", groups)
        object.__setattr__(self, "_rows", rows)

    @property
    def rows(self):
        """The contact-row operator (``rows(eta)``, ``rows_T(f)``, ``compliance(s)``)."""
        return self._rows

    @property
    def n_modes(self) -> int:
        return self.omega2.size

    @property
    def n_contacts(self) -> int:
        return self._rows.m // 3


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


def _times_block_diagonal(D, K, sl: slice) -> np.ndarray:
    """``D @ blockdiag(K[contacts of sl])`` for a dense (r x 3n) D, without forming the
    block-diagonal matrix."""
    Ks = K[sl.start // 3:sl.stop // 3]
    r, n = D.shape[0], Ks.shape[0]
    return np.matmul(D.reshape(r, n, 3).transpose(1, 0, 2), Ks).transpose(1, 0, 2).reshape(
        r, 3 * n)


#: A step at the finest bisection level whose Newton iteration cycles is accepted when its
#: residual is below this fraction of the displacement scale (counted in
#: ``meta["n_loose_steps"]``; the energy balance shows what it costs).
LOOSE_TOL = 1e-3

#: Largest active set (rows of closed contacts) solved by a dense LU in a Newton step.
DENSE_ACTIVE_MAX = 2400


def _active_newton_step(C, K, g, ap):
    """Solve ``(I + ap C K) du = g`` exactly through the closed contacts only.

    ``K`` (nc, 3, 3) vanishes on open contacts, so with ``A`` the rows of the closed ones:
    ``(I + ap C_AA K_AA) du_A = g_A`` and ``du_rest = g_rest - ap (C z)_rest`` with
    ``z_A = K_AA du_A``. Returns du, or None when the active set is too large."""
    closed = np.flatnonzero(np.any(K != 0.0, axis=(1, 2)))
    if closed.size == 0:
        return g.copy()
    if 3 * closed.size > DENSE_ACTIVE_MAX:
        return None
    A = (3 * closed[:, None] + np.arange(3)).reshape(-1)
    CAA = _cached_submatrix(C, closed, A)
    Kc = K[closed]                                             # (na, 3, 3)
    na = closed.size
    # C_AA K_AA without forming the block-diagonal K_AA: column block b times K_b
    CK = np.matmul(CAA.reshape(3 * na, na, 3).transpose(1, 0, 2), Kc)
    JA = ap * CK.transpose(1, 0, 2).reshape(3 * na, 3 * na)
    JA[np.diag_indices_from(JA)] += 1.0
    duA = np.linalg.solve(JA, g[A])
    z = np.zeros_like(g)
    z[A] = np.einsum("pab,pb->pa", Kc, duA.reshape(na, 3)).reshape(-1)
    du = g - ap * C.apply(z)
    du[A] = duA
    return du


def _cached_submatrix(C, closed, A):
    """``C_AA``, re-used while the set of closed contacts is the same (it changes far less
    often than the Newton iterate)."""
    key = closed.tobytes()
    cache = getattr(C, "_sub_cache", None)
    if cache is not None and cache[0] == key:
        return cache[1]
    CAA = np.ascontiguousarray(C.submatrix(A))
    C._sub_cache = (key, CAA)
    return CAA


def _newton_krylov_step(C, K, g, blocks, ap, tol):
    """Solve ``(I + ap C K) du = g`` by GMRES, block-Jacobi preconditioned by patches.

    ``C`` is a compliance operator (``apply``, ``diagonal_block``). Returns (du, info)."""
    m = g.size

    def matvec(x):
        return x + ap * C.apply(_block_apply(K, x))

    diag = getattr(C, "_diag_cache", None)
    if diag is None:
        diag = {}
        C._diag_cache = diag
    inv_blocks = []
    for sl in blocks:
        key = (sl.start, sl.stop) if not hasattr(C, "H") else (sl.stop - sl.start,)
        if key not in diag:
            diag[key] = np.asarray(C.diagonal_block(sl))
        Jb = np.eye(sl.stop - sl.start) + ap * _times_block_diagonal(diag[key], K, sl)
        inv_blocks.append(sla.lu_factor(Jb, check_finite=False))

    def precond(x):
        y = np.empty_like(x)
        for sl, lu in zip(blocks, inv_blocks, strict=True):
            y[sl] = sla.lu_solve(lu, x[sl], check_finite=False)
        return y

    A = spla.LinearOperator((m, m), matvec=matvec, dtype=float)
    P = spla.LinearOperator((m, m), matvec=precond, dtype=float)
    du, info = spla.gmres(A, g, M=P, rtol=tol, atol=0.0, restart=80, maxiter=50)
    return du, info


# ====================================================================================== static
@dataclass(frozen=True, repr=False)
class ModalStaticResult(ResultMixin):
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

    def _judge(self):
        from fricdamp.results import status_verdict

        return status_verdict(True, "", {"residual_m": float(self.residual),
                                         "iterations": int(self.iterations)})

    def to_xarray(self):
        """``xarray.Dataset``: modal coordinates, contact displacements and forces
        (n, t1, t2) and the contact status of every contact."""
        import xarray as xr

        return xr.Dataset(
            {"eta": (("mode",), self.eta, {"units": "m kg^0.5"}),
             "contact_displacement": (("contact", "direction"), self.u, {"units": "m"}),
             "contact_force": (("contact", "direction"), self.f, {"units": "N"}),
             "contact_status": (("contact",), np.asarray(self.status),
                                {"long_name": "0 open, 1 stick, 2 slip"})},
            coords={"direction": ["n", "t1", "t2"]},
            attrs={"iterations": int(self.iterations), "residual_m": float(self.residual)})

    def plot(self, ax=None):
        """Tangential against normal force of every contact, coloured by status; returns
        the axes."""
        return _plot_contact_forces(self.f, np.asarray(self.status), ax)


def _plot_contact_forces(f, status, ax=None):
    """Scatter of |tangential| vs normal contact force [N], one point per contact."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 4), layout="constrained")
    f = np.asarray(f, float).reshape(-1, 3)
    ft = np.hypot(f[:, 1], f[:, 2])
    for code, name in ((0, "open"), (1, "stick"), (2, "slip")):
        sel = status == code
        if np.any(sel):
            ax.plot(-f[sel, 0], ft[sel], "o", ms=3, label=name)
    ax.set_xlabel("normal force (compression) [N]")
    ax.set_ylabel("tangential force [N]")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    return ax


#: Contact rows up to which the static Newton step is a dense solve (above: GMRES).
DENSE_STATIC_MAX = 3000


def _static_compliance(basis: ModalBasis):
    """Compliance operator ``B diag(1/lambda) B^T``."""
    with _blas1():
        return basis.rows.compliance(1.0 / basis.omega2)


def _as_compliance(C):
    return _DenseCompliance(np.asarray(C)) if isinstance(C, np.ndarray) else C


def solve_static_modal(basis: ModalBasis, laws, load=None, *, states=None,
                       compliance: np.ndarray | None = None, increments: int = 1,
                       tol: float = 1e-10, max_iter: int = 60) -> ModalStaticResult:
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
    compliance : compliance operator or ndarray (m, m), optional
        ``B diag(1/lambda) B^T`` if already formed (re-used across calls).
    increments : int
        The load and the contacts' interference offsets are applied in this many equal
        steps, the contact states committed after each (a quasi-static path); 1: at once.
    tol, max_iter
        Convergence ``max |g| <= tol max(|u|, |u_lin|)``; Newton iterations (dense steps
        up to :data:`DENSE_STATIC_MAX` contact rows, block-preconditioned GMRES above).

    Raises
    ------
    ConvergenceError
        When Newton does not converge.
    """
    n = basis.n_modes
    F = np.zeros(n) if load is None else np.asarray(load, dtype=float).reshape(-1)
    if F.shape != (n,) or not np.all(np.isfinite(F)):
        raise ModelError(f"load must be a finite modal vector of length {n}")
    if isinstance(increments, bool) or int(increments) != increments or increments < 1:
        raise ModelError(f"increments must be an integer >= 1, got {increments!r}")
    con = _Contacts(laws, basis)
    w0, s0 = _states(laws, states, con.nc)
    Cs = _as_compliance(_static_compliance(basis) if compliance is None else compliance)
    g0_full = con.g0.copy()
    u = np.zeros(basis.rows.m)
    zero = np.zeros_like(u)
    dense = hasattr(Cs, "C") and u.size <= DENSE_STATIC_MAX
    res, it_total = np.inf, 0
    with _blas1():
        for k in range(1, int(increments) + 1):
            frac = k / int(increments)
            con.g0 = g0_full * frac              # interference and load ramped together
            eta_lin = frac * F / basis.omega2
            u_lin = basis.rows.rows(eta_lin)
            if k == 1:
                u = u_lin.copy()
            for _it in range(max_iter + 1):
                f = con.evaluate(u, zero, w0, s0)
                Cf = Cs.apply(f)
                g = u - u_lin + Cf
                res = float(np.max(np.abs(g)))
                scale = max(float(np.max(np.abs(u))), float(np.max(np.abs(u_lin))),
                            float(np.max(np.abs(Cf))), 1e-300)
                if res <= tol * scale:
                    break
                it_total += 1
                if dense:
                    du = np.linalg.solve(np.eye(u.size) + Cs.C @ _block_matrix(con.Ku), g)
                else:
                    du = _active_newton_step(Cs, con.Ku.copy(), g, 1.0)
                    if du is None:
                        du = _newton_krylov_step(Cs, con.Ku.copy(), g, con.blocks, 1.0,
                                                 1e-8)[0]
                step = 1.0
                for _ in range(30):
                    trial = u - step * du
                    ft = con.evaluate(trial, zero, w0, s0)
                    if np.max(np.abs(trial - u_lin + Cs.apply(ft))) < res or step < 1e-6:
                        break
                    step *= 0.5
                u = u - step * du
            else:
                raise ConvergenceError(
                    f"static contact solution did not converge in {max_iter} Newton "
                    f"iterations (increment {k}/{increments}, residual {res:.3g} m); use "
                    "more increments")
            if k < increments:                    # commit the contact states
                con.evaluate(u, zero, w0, s0)
                w0, s0 = con.w1.copy(), con.s1.copy()
        f = con.evaluate(u, zero, w0, s0)
        eta = eta_lin - basis.rows.rows_T(f) / basis.omega2
    return ModalStaticResult(eta=eta, u=u.reshape(-1, 3), f=f.reshape(-1, 3),
                             states=(con.w1.copy(), con.s1.copy()), status=con.code.copy(),
                             iterations=it_total, residual=res)


def _block_matrix(K):
    nc = K.shape[0]
    out = np.zeros((3 * nc, 3 * nc))
    for a in range(3):
        for b in range(3):
            out[3 * np.arange(nc) + a, 3 * np.arange(nc) + b] = K[:, a, b]
    return out


# =================================================================================== transient
def _newmark(basis: ModalBasis, h: float, alpha: float):
    """Newmark/HHT coefficients, gamma, 1 + alpha and the inverse effective stiffness (the
    scheme of :class:`~fricdamp.solvers.newmark.NewmarkScheme`)."""
    scheme = NewmarkScheme(h, alpha)
    return scheme.c, scheme.gamma, scheme.ap, scheme.modal_inverse(basis.damping,
                                                                   basis.omega2)


def transient_compliance(basis: ModalBasis, dt: float, *, method: str = "newmark",
                         alpha: float = -0.05):
    """Condensed compliance operator ``C = B S^-1 B^T`` of the time step [m/N] (m x m:
    dense, or block-circulant for :class:`CyclicRows`).

    It depends on the modes, ``dt`` and the method only, not on the contacts: form it once
    and pass it to :func:`integrate_modal` for every run with the same step.
    """
    a = 0.0 if method == "newmark" else float(alpha)
    with _blas1():
        s_inv = _newmark(basis, float(dt), a)[3]
        return basis.rows.compliance(s_inv)


@dataclass(frozen=True, repr=False)
class ModalTransientResult(ResultMixin, EnergyBalance):
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

    def state_fractions(self) -> dict:
        """Fractions of (contact, saved instant) samples open / stick / slip."""
        st = self.contact_status
        return {"open": float(np.mean(st == 0)), "stick": float(np.mean(st == 1)),
                "slip": float(np.mean(st == 2))}

    def to_xarray(self):
        """``xarray.Dataset``: output displacements over time, contact status, cumulative
        energies [J] and the stored contact fields (their own time axis)."""
        import xarray as xr

        n_out = self.output.shape[1]
        ds = xr.Dataset(
            {"q": (("time", "output"), self.output, {"units": "m", "long_name": "displacement"}),
             "contact_status": (("time", "contact"), self.contact_status,
                                {"long_name": "0 open, 1 stick, 2 slip"}),
             "contact_displacement": (("contact_time", "contact", "direction"),
                                      self.contact_displacement, {"units": "m"}),
             "contact_force": (("contact_time", "contact", "direction"), self.contact_force,
                               {"units": "N"})},
            coords={"time": ("time", self.t, {"units": "s"}),
                    "contact_time": ("contact_time", self.t_contacts, {"units": "s"}),
                    "output": np.arange(n_out),
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

        return plot_histories(self.t, self.output, outputs, ax)


class _State:
    """Modal and contact state after a step, with the cumulative energies."""

    __slots__ = ("eta", "vel", "acc", "u", "uv", "ua", "f", "BTf", "w", "s", "code", "e_in",
                 "e_visc", "e_cw", "e_cd")

    def copy(self) -> _State:
        new = _State()
        for name in self.__slots__:
            setattr(new, name, getattr(self, name))
        return new


class _Level:
    """Newmark/HHT coefficients, compliance and chord of one step size."""

    def __init__(self, basis, con, h, alpha, C=None):
        (self.c0, self.c1, self.c2, self.c3, self.c4, self.c5), self.gamma, self.ap, \
            self.s_inv = _newmark(basis, h, alpha)
        self.h = h
        self.C = basis.rows.compliance(self.s_inv) if C is None else C
        self._chord = None
        self._con = con

    @property
    def chord(self):
        if self._chord is None:
            self._chord = self.C.chord(self._con.stick_diagonal(), self.ap)
        return self._chord


class _Stepper:
    """One Newmark step condensed on the contacts, with bisection on failure."""

    def __init__(self, basis, con, dt, alpha, tol, max_iter, chord, max_halvings, C0):
        self.basis, self.con, self.dt, self.alpha = basis, con, dt, alpha
        self.tol, self.max_iter, self.use_chord = tol, max_iter, chord
        self.max_halvings = int(max_halvings)
        self.levels = {0: _Level(basis, con, dt, alpha, C0)}
        self.chord_ok = True
        self.since_chord = 0
        self.n_iterations = self.n_newton = self.n_halved = self.n_loose = 0
        self.loose_residual = 0.0
        self.last_residual = np.nan

    def level(self, i: int) -> _Level:
        if i not in self.levels:
            self.levels[i] = _Level(self.basis, self.con, self.dt / 2 ** i, self.alpha)
        return self.levels[i]

    def initial_state(self, eta, vel, w, s, Fm) -> _State:
        rows, con, b = self.basis.rows, self.con, self.basis
        st = _State()
        st.eta, st.vel = eta, vel
        st.u, st.uv = rows.rows(eta), rows.rows(vel)
        st.f = con.evaluate(st.u, st.uv, w, s)
        code = con.code.copy()
        code[(code == 1) & (s == 1.0)] = 2   # a contact given as slipping stays "slip"
        st.code = code
        st.w, st.s = con.w1.copy(), con.s1.copy()
        st.BTf = rows.rows_T(st.f)
        st.acc = Fm - b.damping * vel - b.omega2 * eta - st.BTf
        st.ua = rows.rows(st.acc)
        st.e_in = st.e_visc = st.e_cw = st.e_cd = 0.0
        self.Fm = Fm
        return st

    def advance(self, st: _State, lvl: int) -> _State | None:
        """The state one step of level ``lvl`` later, or None."""
        last = lvl >= self.max_halvings
        new = self._step(st, self.level(lvl), accept_loose=last)
        if new is not None or last:
            return new
        self.n_halved += 1
        half = self.advance(st, lvl + 1)
        return None if half is None else self.advance(half, lvl + 1)

    def _step(self, st: _State, L: _Level, accept_loose: bool = False) -> _State | None:
        con, rows, b = self.con, self.basis.rows, self.basis
        lam, cd, Fm, alpha, ap = b.omega2, b.damping, self.Fm, self.alpha, L.ap
        c0, c1, c2, c3, c4, c5 = L.c0, L.c1, L.c2, L.c3, L.c4, L.c5
        C = L.C
        eta, vel, acc, u, uv, ua = st.eta, st.vel, st.acc, st.u, st.uv, st.ua
        rhs = (Fm + alpha * (cd * vel + lam * eta + st.BTf) + c0 * eta + c2 * vel + c3 * acc
               + ap * cd * (c1 * eta - c4 * vel - c5 * acc))
        eta_lin = rhs * L.s_inv
        u_lin = rows.rows(eta_lin)
        un = u_lin - ap * C.apply(st.f)        # predictor: the contact forces unchanged
        # the chord (stuck, closed contacts) is tried again only every 64 steps after it
        # failed: with opening and slipping contacts it wastes iterations
        self.since_chord += 1
        use_chord = self.use_chord and (self.chord_ok or self.since_chord >= 64)
        res_prev = np.inf
        converged = False
        for _it in range(self.max_iter + 1):
            vv = c1 * (un - u) + c4 * uv + c5 * ua
            fnew = con.evaluate(un, vv, st.w, st.s)
            Cf = C.apply(fnew)
            g = un - u_lin + ap * Cf
            res = float(np.max(np.abs(g)))
            # the scale includes |C f|: g is a difference of the three, so its round-off is
            # relative to the largest (stiff penalties make |C f| >> |u|)
            scale = max(float(np.max(np.abs(un))), float(np.max(np.abs(u_lin))),
                        float(np.max(np.abs(ap * Cf))), 1e-300)
            if res <= self.tol * scale:
                converged = True
                break
            self.n_iterations += 1
            if log.isEnabledFor(logging.DEBUG):
                log.debug("h %.3g it %d res/scale %.3e chord %s states %s", L.h, _it,
                          res / scale, use_chord, np.bincount(con.code, minlength=3).tolist())
            if use_chord and res > 0.25 * res_prev:
                use_chord = self.chord_ok = False
                self.since_chord = 0
            res_prev = res
            if use_chord:
                un = un - L.chord(g)
                continue
            self.n_newton += 1
            Kt = con.Ku + c1 * con.Kv
            du = _active_newton_step(C, Kt, g, ap)
            if du is None:
                du = _newton_krylov_step(C, Kt, g, con.blocks, ap, 1e-6)[0]
            # backtracking on max|g|: stick/slip and open/closed switches make g only
            # piecewise smooth, and a full step can cycle between two contact states
            lam_s = 1.0
            for _ls in range(8):
                trial = un - lam_s * du
                vt = c1 * (trial - u) + c4 * uv + c5 * ua
                ft = con.evaluate(trial, vt, st.w, st.s)
                if np.max(np.abs(trial - u_lin + ap * C.apply(ft))) < res:
                    break
                lam_s *= 0.5
            un = trial
        self.last_residual = res
        if use_chord:
            self.chord_ok = True                       # the chord alone converged
        if not converged and accept_loose and res <= LOOSE_TOL * scale:
            # the smallest step still cycles between two contact states (stick/slip with
            # velocity-weakening friction): accept the last iterate, counted and reported
            self.n_loose += 1
            self.loose_residual = max(self.loose_residual, res / scale)
            converged = True
        if not converged:
            return None
        new = _State()
        new.BTf = rows.rows_T(fnew)
        new.eta = eta_lin - ap * L.s_inv * new.BTf
        new.acc = c0 * (new.eta - eta) - c2 * vel - c3 * acc
        new.vel = vel + L.h * ((1.0 - L.gamma) * acc + L.gamma * new.acc)
        deta = new.eta - eta
        new.e_in = st.e_in + float(deta @ Fm)
        new.e_visc = st.e_visc + 0.5 * float(np.sum(deta * cd * (vel + new.vel)))
        u1 = u_lin - ap * Cf                     # = B eta1 exactly (up to round-off)
        new.e_cw = st.e_cw + 0.5 * float((u1 - u) @ (st.f + fnew))
        fr = fnew.reshape(-1, 3)
        new.e_cd = st.e_cd + float(np.sum(fr[:, 1] * (con.w1[:, 0] - st.w[:, 0])
                                          + fr[:, 2] * (con.w1[:, 1] - st.w[:, 1])))
        du_c = u1 - u
        new.ua = c0 * du_c - c2 * uv - c3 * ua
        new.uv = c1 * du_c + c4 * uv + c5 * ua
        new.u = u1
        new.f = fnew
        new.w, new.s = con.w1.copy(), con.s1.copy()
        new.code = con.code.copy()
        return new


def integrate_modal(basis: ModalBasis, laws, t_end: float, dt: float, *, eta0=None,
                    vel0=None, states0=None, load=None, t0: float = 0.0,
                    method: str = "newmark", alpha: float = -0.05, save_every: int = 1,
                    contact_every: int | None = None, tol: float = 1e-10,
                    max_iter: int = 40, chord: bool = True, max_halvings: int = 5,
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
        Convergence ``max |g| <= tol max(|u|, |u_lin|, |(1 + alpha) C f|)`` per step;
        iterations per step.
    chord : bool
        Start every step with chord iterations (default); ``False``: Newton-Krylov from the
        first iteration. Both stop on the same residual test.
    max_halvings : int
        A step whose Newton iteration does not converge is redone as two half steps,
        recursively, at most this many times (time-step bisection, as FE codes do);
        outputs stay on the ``dt`` grid. At the finest level a step whose iterates cycle
        between contact states is accepted below :data:`LOOSE_TOL` of the displacement
        scale and counted (``meta["n_loose_steps"]``).
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
    alpha = check_time_span(t_end, dt, t0=t0, method=method, alpha=alpha)
    for name, k in (("save_every", save_every), ("contact_every", contact_every)):
        if k is not None and (isinstance(k, bool) or int(k) != k or k < 1):
            raise ModelError(f"{name} must be an integer >= 1, got {k!r}")
    save_every = int(save_every)
    contact_every = save_every if contact_every is None else int(contact_every)
    n, m = basis.n_modes, basis.rows.m
    eta = np.zeros(n) if eta0 is None else np.asarray(eta0, dtype=float).reshape(-1).copy()
    vel = np.zeros(n) if vel0 is None else np.asarray(vel0, dtype=float).reshape(-1).copy()
    Fm = np.zeros(n) if load is None else np.asarray(load, dtype=float).reshape(-1)
    for name, x in (("eta0", eta), ("vel0", vel), ("load", Fm)):
        if x.shape != (n,) or not np.all(np.isfinite(x)):
            raise ModelError(f"{name} must be a finite vector of length {n}")
    con = _Contacts(laws, basis)
    w, s = _states(laws, states0, con.nc)
    lam, rows, out = basis.omega2, basis.rows, basis.output

    tic = time.perf_counter()
    stepper = _Stepper(basis, con, float(dt), alpha, tol, max_iter, bool(chord), max_halvings,
                       None if compliance is None else _as_compliance(compliance))
    with _blas1():
        if stepper.level(0).C.m != m:
            raise ModelError(f"compliance must be m x m with m = {m} contact rows")
        st = stepper.initial_state(eta, vel, w, s, Fm)
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

    def store(k, kc, t, step):
        if step % save_every == 0:
            T[k] = t
            Q[k] = out @ st.eta
            S[k] = st.code
            E[k] = (st.e_in, 0.5 * st.vel @ st.vel, 0.5 * np.sum(lam * st.eta * st.eta),
                    st.e_visc, st.e_cw, con.energy(st.u, st.w), st.e_cd)
            k += 1
        if step % contact_every == 0:
            TC[kc] = t
            U[kc] = st.u.reshape(-1, 3)
            FO[kc] = st.f.reshape(-1, 3)
            kc += 1
        return k, kc

    k, kc = store(0, 0, t0, 0)
    show = _progress_default() if progress is None else bool(progress)
    bar = None
    if show:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_steps, desc="time steps", unit="step", leave=False)
    status, message, done = 0, "finished", n_steps
    cpu0 = time.process_time()
    tic = time.perf_counter()
    with _blas1():
        for step in range(1, n_steps + 1):
            new = stepper.advance(st, 0)
            if new is None:
                status, done = 1, step - 1
                message = (f"Newton did not converge at t = {t0 + step * dt:.6g} s, even with "
                           f"the step halved {max_halvings} times (residual "
                           f"{stepper.last_residual:.3g} m); try a smaller dt")
                break
            st = new
            if step % 512 == 0:            # no drift of the contact-space Newmark recursion
                st.uv, st.ua = rows.rows(st.vel), rows.rows(st.acc)
            k, kc = store(k, kc, t0 + step * dt, step)
            if bar is not None:
                bar.update(1)
    runtime = time.perf_counter() - tic
    cpu = time.process_time() - cpu0
    if bar is not None:
        bar.close()
    if status and throw:
        raise ConvergenceError(message)
    eta, vel, w, s = st.eta, st.vel, st.w, st.s
    n_it, n_kr = stepper.n_iterations, stepper.n_newton
    return ModalTransientResult(
        t=T[:k], output=Q[:k], contact_status=S[:k], t_contacts=TC[:kc],
        contact_displacement=U[:kc], contact_force=FO[:kc],
        energy={key: E[:k, i].copy() for i, key in enumerate(ENERGY_KEYS)},
        eta_final=eta, vel_final=vel, states_final=(w, s), success=status == 0,
        status=status, message=message, n_steps=int(done), n_iterations=int(n_it),
        n_krylov=int(n_kr), runtime_s=runtime, cpu_s=cpu, setup_s=setup,
        method="newmark" if alpha == 0 else f"hht(alpha={alpha:g})",
        meta={"n_modes": int(n), "n_contact_rows": int(m),
              "n_halved_steps": int(stepper.n_halved),
              "n_loose_steps": int(stepper.n_loose),
              "largest_loose_residual": float(stepper.loose_residual)})
