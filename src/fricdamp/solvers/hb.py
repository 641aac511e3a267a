"""Multi-harmonic balance with AFT contact forces, frequency response by continuation.

The steady periodic response of ``M q'' + D q' + K q + P^T f(P q) = F_static + F(t)`` at
excitation frequency Omega is sought as ``q(tau) = Q_0 + sum_{k=1..H} a_k cos k tau +
b_k sin k tau`` (``tau = Omega t``, real coefficients ``[c0, a1, b1, ..., aH, bH]``, see
:mod:`fricdamp.solvers.aft`). Galerkin projection onto the harmonics gives, per harmonic k,

    (K - k^2 Omega^2 M) a_k + k Omega D b_k + F^nl_{a,k} = F_{a,k}
    (K - k^2 Omega^2 M) b_k - k Omega D a_k + F^nl_{b,k} = F_{b,k}

(and ``K Q_0 + F^nl_0 = F_static`` for the static term), with the contact-force harmonics
``F^nl`` from the AFT step. Two equivalent formulations are solved:

* ``"full"``: unknowns are the harmonics of all DOFs; the Jacobian ``S(Omega) + (P^T x I)
  J_nl (P x I)`` is assembled into a fixed sparsity pattern (dense below ~200 unknowns) —
  one sparse LU per Newton step; this is the choice when every DOF carries a contact (ring
  of oscillators) or K is singular (a structure held only by its contacts).
* ``"condensed"``: the linear DOFs are eliminated harmonic by harmonic through the dynamic
  compliance ``R_k(Omega) = P Z_k^{-1} P^T`` with ``Z_k = K - k^2 Omega^2 M + i k Omega D``
  (exactly, by modal superposition when D is classically damped, else by direct solves);
  the unknowns are the contact relative-displacement harmonics u and the residual
  ``u - u_lin(Omega) + R(Omega) F^nl(u) = 0`` [m]. It pays whenever the contacts see fewer
  coordinates than the structure has DOFs (``method="auto"`` picks it then).

Frequency response curves (:func:`frequency_response`) are continued in Omega, and
response-vs-load curves (:func:`load_response`) in the excitation level, by the
problem-agnostic :func:`fricdamp.solvers.continuation.solve_and_continue`. Every steady
state carries its energy balance over one period: work of the external force = viscous
dissipation + dissipation of each contact (``oint f du``); with converged harmonic balance
this identity holds to the Newton tolerance (a consistency check of residual and
post-processing, not an accuracy estimate: for that compare harmonics H and 2H).

Accuracy and limits: the AFT samples the force at N instants, so a stick-slip transition is
located to within one sample (force error ~(2 pi / N)^2 for Jenkins kinks; on a cyclic
assembly the discrete AFT is shift invariant only if the inter-sector phase is a whole number
of samples). Laws with a discontinuous return map (static > kinetic friction) make the
residual discontinuous; Newton may then stall, and the result says so.

References
----------
Cameron & Griffin (1989), J. Appl. Mech. 56, 149-154 (AFT).
Krack & Gross (2019), *Harmonic Balance for Nonlinear Vibration Problems*, Springer.
Petrov & Ewins (2003), J. Turbomach. 125, 364-371 (analytic Jacobians for friction HB).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers.aft import HarmonicBasis, aft, cycle_work, element_rows
from fricdamp.solvers.continuation import blas_threads, newton, solve_and_continue
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem, TimeLoad

__all__ = [
    "FrequencyResponse",
    "SteadyState",
    "engine_order_load",
    "frequency_response",
    "harmonic_balance",
    "load_response",
]

logger = logging.getLogger(__name__)

#: Below this number of unknowns the full formulation uses dense LU (measured crossover
#: with SuperLU on this class of machine: dense 330 x 330 ~1 ms, sparse ~0.5 ms).
DENSE_LIMIT = 200


# ============================================================================ set-up
def _dense(A):
    return A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)


def excitation_coefficients(system: MechanicalSystem, harmonics: int) -> np.ndarray:
    """Real harmonic coefficients (n_dof, 2H+1) of the static and harmonic loads [N].

    ``HarmonicLoad(amplitude A, harmonic k)`` contributes ``Re(A e^{i k tau})``, i.e.
    ``a_k += Re A`` and ``b_k += -Im A``; its ``omega`` field is ignored (the solver's
    Omega replaces it).
    """
    n = system.n_dof
    F = np.zeros((n, 2 * harmonics + 1))
    F[:, 0] = system.static_load
    for ld in system.loads:
        if isinstance(ld, TimeLoad):
            raise ModelError("harmonic balance needs periodic loads: replace TimeLoad by "
                             "HarmonicLoad (amplitude, harmonic) entries")
        if not isinstance(ld, HarmonicLoad):
            raise ModelError(f"unsupported load {ld!r}")
        k = int(ld.harmonic)
        if k == 0:
            F[:, 0] += ld.amplitude.real
        elif k <= harmonics:
            F[:, 2 * k - 1] += ld.amplitude.real
            F[:, 2 * k] += -ld.amplitude.imag
        else:
            raise ModelError(f"a HarmonicLoad acts at harmonic {k} but harmonics={harmonics}: "
                             f"use harmonics >= {k}")
    return F


class _Setup:
    """System data shared by the formulations (built once per analysis)."""

    def __init__(self, system: MechanicalSystem, harmonics: int, samples: int | None):
        if not isinstance(system, MechanicalSystem):
            raise ModelError(f"system must be a MechanicalSystem, got {type(system).__name__}")
        if system.rotation is not None:
            raise ModelError("the system has speed-dependent rotation terms: evaluate them "
                             "first with system.at_speed(spin_speed_rad_s)")
        self.system = system
        self.basis = HarmonicBasis.create(harmonics, samples)
        self.H = self.basis.harmonics
        self.nh = self.basis.n_coeff
        self.n = system.n_dof
        self.contacts = system.contacts
        self.rows = element_rows(self.contacts)
        self.n_rows = self.rows[-1].stop if self.rows else 0
        if self.contacts:
            self.P = sp.vstack([sp.csr_matrix(c.projection) for c in self.contacts]).tocsr()
        else:
            self.P = sp.csr_matrix((0, self.n))
        self.PT = self.P.T.tocsr()
        self.F_ex = excitation_coefficients(system, self.H)
        self.sparse = system.is_sparse
        self.M, self.D, self.K = system.M, system.D, system.K
        self.hn = self.basis.harmonic_number.astype(float)
        self.em = -self.hn**2                       # coefficient of Omega^2 M
        self.ED = np.zeros((self.nh, self.nh))      # coefficient of Omega D
        k = np.arange(1, self.H + 1)
        self.ED[2 * k - 1, 2 * k] = k
        self.ED[2 * k, 2 * k - 1] = -k
        self.EDT = self.ED.T.copy()
        nd = [c.n_dir for c in self.contacts]
        self.contact_names = tuple(
            f"{c.name}[{i}]" if c.n_contacts > 1 else c.name
            for c in self.contacts for i in range(c.n_contacts))
        self.contact_of_row = np.concatenate(
            [np.repeat(np.arange(c.n_contacts), d) + off for c, d, off in zip(
                self.contacts, nd, np.cumsum([0] + [c.n_contacts for c in self.contacts])[:-1],
                strict=True)]) if self.contacts else np.zeros(0, int)
        self.n_contacts = len(self.contact_names)

    # ---------------------------------------------------------------- linear estimates
    def tangent_contact_stiffness(self):
        """Contact stiffness at the virgin state and zero displacement, sparse (n, n)."""
        if not self.contacts:
            return sp.csr_matrix((self.n, self.n))
        blocks = []
        for c in self.contacts:
            st = c.law.initial_state()
            k = c.law.step(st, np.zeros((c.n_contacts, c.n_dir)),
                           np.zeros((c.n_contacts, c.n_dir))
                           if c.law.velocity_dependent else None).stiffness
            blocks.append(sp.block_diag(list(np.asarray(k, float)), format="csr"))
        Kc = sp.block_diag(blocks, format="csr")
        return (self.PT @ Kc @ self.P).tocsr()

    def linear_response(self, omega: float, K_extra=None) -> np.ndarray | None:
        """Harmonic coefficients (n, nh) of the linear response with K + K_extra, or None."""
        K = self.K
        if K_extra is not None:
            K = (K + K_extra).tocsr() if sp.issparse(K) else K + _dense(K_extra)
        X = np.zeros((self.n, self.nh))
        F = self.F_ex
        try:
            for k in range(self.H + 1):
                cols = [0] if k == 0 else [2 * k - 1, 2 * k]
                if not np.any(F[:, cols]):
                    continue
                Z = K - (k * omega) ** 2 * self.M + 1j * k * omega * self.D
                rhs = F[:, 0].astype(complex) if k == 0 else F[:, 2 * k - 1] - 1j * F[:, 2 * k]
                if sp.issparse(Z):
                    import scipy.sparse.linalg as spla

                    Qk = spla.spsolve(sp.csc_matrix(Z), rhs)
                else:
                    Qk = np.linalg.solve(np.asarray(Z), rhs)
                if not np.all(np.isfinite(Qk)):
                    return None
                if k == 0:
                    X[:, 0] = Qk.real
                else:
                    X[:, 2 * k - 1] = Qk.real
                    X[:, 2 * k] = -Qk.imag
        except (np.linalg.LinAlgError, RuntimeError, ValueError):
            return None
        return X


# ============================================================================ full formulation
class _Full:
    """Residual of all DOF harmonics with a fixed-pattern Jacobian (dense or sparse)."""

    def __init__(self, s: _Setup, *, dense: bool | None = None, nma: bool = False):
        self.s = s
        n, nh = s.n, s.nh
        Nn = n * nh
        self.N = Nn
        self.nma = nma
        terms = [(s.K, np.eye(nh)), (s.M, np.diag(s.em)), (s.D, s.ED)]
        if nma:
            terms.append((s.M, s.ED))
        rows, cols, vals, which = [], [], [], []
        for t, (A, E) in enumerate(terms):
            C = sp.kron(sp.csr_matrix(A), sp.csr_matrix(E), format="coo")
            rows.append(C.row.astype(np.int64))
            cols.append(C.col.astype(np.int64))
            vals.append(C.data)
            which.append(np.full(C.nnz, t))
        # nonlinear pattern: pairs of projection entries of the same contact
        nl_rows, nl_cols, nl_coef, nl_src = [], [], [], []
        offset = 0
        self.block_sizes = []
        for c, rs in zip(s.contacts, s.rows, strict=True):
            Pc = s.P[rs].tocoo()
            nc, nd = c.n_contacts, c.n_dir
            m = nd * nh
            self.block_sizes.append(nc * m * m)
            if Pc.nnz:
                con = Pc.row // nd
                drn = Pc.row % nd
                order = np.argsort(con, kind="stable")
                con, drn, col, val = con[order], drn[order], Pc.col[order], Pc.data[order]
                counts = np.bincount(con, minlength=nc)
                starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
                pos = np.arange(con.size) - starts[con]
                grid = np.full((nc, counts.max()), -1)
                grid[con, pos] = np.arange(con.size)
                ga = np.broadcast_to(grid[:, :, None], (nc, grid.shape[1], grid.shape[1]))
                gb = np.broadcast_to(grid[:, None, :], ga.shape)
                mask = (ga >= 0) & (gb >= 0)
                ia, ib = ga[mask], gb[mask]
                h = np.arange(nh)
                r = (col[ia][:, None, None] * nh + h[None, :, None])
                cc = (col[ib][:, None, None] * nh + h[None, None, :])
                src = (offset + con[ia][:, None, None] * m * m
                       + (drn[ia][:, None, None] * nh + h[None, :, None]) * m
                       + drn[ib][:, None, None] * nh + h[None, None, :])
                coef = np.broadcast_to((val[ia] * val[ib])[:, None, None], src.shape)
                r, cc = np.broadcast_arrays(r, cc)
                nl_rows.append(r.ravel())
                nl_cols.append(cc.ravel())
                nl_src.append(src.ravel())
                nl_coef.append(coef.ravel())
            offset += nc * m * m
        self.n_jac = offset
        all_r = np.concatenate(rows + nl_rows) if (rows + nl_rows) else np.zeros(0, np.int64)
        all_c = np.concatenate(cols + nl_cols) if (cols + nl_cols) else np.zeros(0, np.int64)
        # always include the diagonal (keeps the pattern non-empty and LU-friendly)
        all_r = np.concatenate([all_r, np.arange(Nn)])
        all_c = np.concatenate([all_c, np.arange(Nn)])
        key = all_c * Nn + all_r
        ukey, inv = np.unique(key, return_inverse=True)
        self.nnz = ukey.size
        self.indices = (ukey % Nn).astype(np.int32)
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(ukey // Nn, minlength=Nn))]
                                     ).astype(np.int32)
        self.lin_index = (ukey % Nn) * Nn + ukey // Nn     # row-major position (dense)
        n_lin = sum(v.size for v in vals)
        inv_lin, self.inv_nl = inv[:n_lin], inv[n_lin: n_lin + sum(x.size for x in nl_rows)]
        w = np.concatenate(which) if which else np.zeros(0, int)
        v = np.concatenate(vals) if vals else np.zeros(0)
        self.base = [np.bincount(inv_lin[w == t], weights=v[w == t], minlength=self.nnz)
                     for t in range(len(terms))]
        self.nl_src = np.concatenate(nl_src) if nl_src else np.zeros(0, np.int64)
        self.nl_coef = np.concatenate(nl_coef) if nl_coef else np.zeros(0)
        if dense is None:
            dense = Nn <= DENSE_LIMIT or self.nnz > 0.3 * Nn * Nn
        self.dense = bool(dense)

    # --------------------------------------------------------------------------
    def linear_terms(self, X, omega, xi=0.0):
        """S(Omega, xi) X, dS/dOmega X, dS/dxi X for X (n, nh)."""
        s = self.s
        KX = s.K @ X
        MX = s.M @ X
        DX = s.D @ X
        DXE = DX @ s.EDT
        SX = KX + (omega**2) * MX * s.em + omega * DXE
        dSX = 2.0 * omega * MX * s.em + DXE
        dxi = None
        if self.nma:
            MXE = MX @ s.EDT
            SX -= xi * omega * MXE
            dSX -= xi * MXE
            dxi = -omega * MXE
        return np.asarray(SX), np.asarray(dSX), dxi

    def evaluate(self, x, omega, *, xi=0.0, jacobian=True, scale=1.0, x_scale=1.0,
                 load_scale=1.0):
        """Residual r (N,) [N * scale], Jacobian wrt x (scaled), dr/dOmega, dr/dxi, AFT.

        ``load_scale`` multiplies the harmonic loads (k >= 1); the static load is kept.
        """
        s = self.s
        X = (x * x_scale).reshape(s.n, s.nh)
        SX, dSX, dxi = self.linear_terms(X, omega, xi)
        r = SX - _static_only(s.F_ex)
        if load_scale != 0.0:
            r[:, 1:] -= load_scale * s.F_ex[:, 1:]
        res = None
        if s.contacts:
            U = s.P @ X
            res = aft(s.contacts, U, omega, s.basis, jacobian=jacobian)
            r = r + s.PT @ res.force
            if res.d_omega is not None:
                dSX = dSX + s.PT @ res.d_omega
        J = None
        if jacobian:
            data = self.base[0] + (omega**2) * self.base[1] + omega * self.base[2]
            if self.nma:
                data = data - (xi * omega) * self.base[3]
            if res is not None and self.nl_src.size:
                Jflat = np.concatenate([b.ravel() for b in res.jacobian])
                data = data + np.bincount(self.inv_nl, weights=self.nl_coef * Jflat[self.nl_src],
                                          minlength=self.nnz)
            data *= scale * x_scale
            if self.dense:
                J = np.zeros(self.N * self.N)
                J[self.lin_index] = data
                J = J.reshape(self.N, self.N)
            else:
                # one CSC object per formulation, its data replaced at each call (building
                # a scipy matrix costs ~0.1 ms of format checks): callers use J before the
                # next evaluation, as Newton and the continuation do
                J = getattr(self, "_J", None)
                if J is None:
                    J = sp.csc_matrix((data, self.indices, self.indptr),
                                      shape=(self.N, self.N))
                    J.has_sorted_indices = True
                    self._J = J
                else:
                    J.data = data
        dxi_out = None if dxi is None else dxi.ravel() * scale
        return r.ravel() * scale, J, dSX.ravel() * scale, dxi_out, res

    def to_dofs(self, x, omega, x_scale=1.0, load_scale=1.0):
        return (x * x_scale).reshape(self.s.n, self.s.nh)


def _static_only(F):
    G = np.zeros_like(F)
    G[:, 0] = F[:, 0]
    return G


# ============================================================================ condensation
class _Condensed:
    """Dynamic compliance of the contact coordinates, exact per harmonic.

    ``modal``: ``Z_k^{-1} = Phi diag(1 / (w_j^2 - k^2 W^2 + i k W c_j)) Phi^T`` with mass
    normalised modes Phi and modal damping c_j (requires Phi^T D Phi diagonal: classical
    damping, e.g. Rayleigh). ``direct``: per-harmonic solves with Z_k.
    """

    def __init__(self, s: _Setup, kind: str, modal=None):
        self.s = s
        self.kind = kind
        self.m = s.n_rows
        self.N = self.m * s.nh
        H = s.H
        self.k = np.arange(H + 1)
        Fc = np.zeros((H + 1, s.n), complex)
        Fc[0] = s.F_ex[:, 0]
        Fc[1:] = (s.F_ex[:, 1::2] - 1j * s.F_ex[:, 2::2]).T
        self.Fc = Fc
        self.ia = 2 * np.arange(1, H + 1) - 1
        self.ib = self.ia + 1
        if kind == "modal":
            if modal is None:
                w2, Phi = sla.eigh(_dense(s.K), _dense(s.M))
                C = Phi.T @ _dense(s.D) @ Phi
            else:
                w2, Phi, C = modal
            self.w2 = w2
            self.c = np.diag(C).copy()
            self.Phic = np.asarray(s.P @ Phi)          # (m, n_modes)
            self.PhicT = self.Phic.T.astype(complex)
            self.g = Fc @ Phi                           # (H+1, n_modes) modal forces
            self.Phi = Phi
        elif kind == "direct":
            self.Pd = s.P.toarray()
            self.sym = all(_is_symmetric(A) for A in (s.M, s.D, s.K))
        else:
            raise ModelError(f"unknown condensation kind {kind!r}")

    # -------------------------------------------------------------------------
    def compliance(self, omega, xi=0.0):
        """R_k (H+1, m, m), dR_k/dOmega, u_lin,k (H+1, m), du_lin/dOmega (complex)."""
        k = self.k[:, None]
        if self.kind == "modal":
            d = self.w2[None, :] - (k * omega) ** 2 + 1j * k * omega * self.c[None, :]
            dd = -2.0 * k**2 * omega + 1j * k * self.c[None, :]
            inv = 1.0 / d
            dinv = -dd * inv**2
            Pc = self.Phic
            R = (Pc[None, :, :] * inv[:, None, :]) @ self.PhicT
            dR = (Pc[None, :, :] * dinv[:, None, :]) @ self.PhicT
            u = (self.g * inv) @ self.PhicT
            du = (self.g * dinv) @ self.PhicT
            return R, dR, u, du
        return self._direct(omega)

    def _direct(self, omega):
        s = self.s
        H = s.H
        m = self.m
        R = np.empty((H + 1, m, m), complex)
        dR = np.empty_like(R)
        u = np.empty((H + 1, m), complex)
        du = np.empty_like(u)
        rhs = np.concatenate([s.PT.toarray().astype(complex), self.Fc.T], axis=1)  # (n, m+H+1)
        for kk in range(H + 1):
            Z = s.K - (kk * omega) ** 2 * s.M + 1j * kk * omega * s.D
            Zp = -2.0 * kk**2 * omega * s.M + 1j * kk * s.D
            b = rhs[:, list(range(m)) + [m + kk]]
            if sp.issparse(Z):
                import scipy.sparse.linalg as spla

                lu = spla.splu(sp.csc_matrix(Z))
                G = lu.solve(b)
                W = lu.solve(np.asarray(Zp @ G))
            else:
                lu = sla.lu_factor(np.asarray(Z), check_finite=False)
                G = sla.lu_solve(lu, b, check_finite=False)
                W = sla.lu_solve(lu, np.asarray(Zp) @ G, check_finite=False)
            PG = self.Pd @ G
            PW = self.Pd @ W
            R[kk], u[kk] = PG[:, :m], PG[:, m]
            dR[kk], du[kk] = -PW[:, :m], -PW[:, m]
        return R, dR, u, du

    def _real_blocks(self, R):
        """Real (m nh, m nh) matrix of the complex per-harmonic compliance R (H+1, m, m)."""
        s = self.s
        nh, m = s.nh, self.m
        T = np.zeros((nh, nh, m, m))
        T[0, 0] = R[0].real
        Rr, Ri = R[1:].real, R[1:].imag
        T[self.ia, self.ia] = Rr
        T[self.ia, self.ib] = Ri
        T[self.ib, self.ia] = -Ri
        T[self.ib, self.ib] = Rr
        return T.transpose(2, 0, 3, 1).reshape(m * nh, m * nh)

    def _to_complex(self, Y):
        """(m, nh) real coefficients -> (H+1, m) phasors."""
        C = np.empty((self.s.H + 1, Y.shape[0]), complex)
        C[0] = Y[:, 0]
        C[1:] = (Y[:, 1::2] - 1j * Y[:, 2::2]).T
        return C

    def _to_real(self, C):
        s = self.s
        Y = np.empty((C.shape[1], s.nh))
        Y[:, 0] = C[0].real
        Y[:, 1::2] = C[1:].real.T
        Y[:, 2::2] = -C[1:].imag.T
        return Y

    def evaluate(self, y, omega, *, jacobian=True, scale=1.0, x_scale=1.0, load_scale=1.0):
        s = self.s
        Y = (y * x_scale).reshape(self.m, s.nh)
        R, dR, ul, dul = self.compliance(omega)
        if load_scale != 1.0:
            ul = ul.copy()
            dul = dul.copy()
            ul[1:] *= load_scale
            dul[1:] *= load_scale
        res = aft(s.contacts, Y, omega, s.basis, jacobian=jacobian)
        Fc = self._to_complex(res.force)
        rc = (R @ Fc[:, :, None])[:, :, 0] - ul
        drc = (dR @ Fc[:, :, None])[:, :, 0] - dul
        r = Y + self._to_real(rc)
        dr = self._to_real(drc)
        J = None
        Rr = None
        if jacobian or res.d_omega is not None:
            Rr = self._real_blocks(R)
        if res.d_omega is not None:
            dr = dr + (Rr @ res.d_omega.ravel()).reshape(dr.shape)
        if jacobian:
            nh = s.nh
            J = np.eye(self.N)
            for blk, rows in zip(res.jacobian, s.rows, strict=True):
                nc, mm = blk.shape[0], blk.shape[1]
                c0, c1 = rows.start * nh, rows.stop * nh
                Rb = Rr[:, c0:c1].reshape(self.N, nc, mm)
                J[:, c0:c1] += np.einsum("icj,cjk->ick", Rb, blk).reshape(self.N, c1 - c0)
            J *= scale * x_scale
        return r.ravel() * scale, J, dr.ravel() * scale, None, res

    def to_dofs(self, y, omega, x_scale=1.0, load_scale=1.0):
        """All-DOF harmonics (n, nh) from contact coordinates (one AFT, no Jacobian)."""
        s = self.s
        Y = (y * x_scale).reshape(self.m, s.nh)
        res = aft(s.contacts, Y, omega, s.basis, jacobian=False)
        Fnl = self._to_complex(res.force)                     # (H+1, m)
        Fc = self.Fc.copy()
        Fc[1:] *= load_scale
        rhs = Fc - np.asarray(s.PT @ Fnl.T).T                 # (H+1, n)
        k = self.k[:, None]
        if self.kind == "modal":
            d = self.w2[None, :] - (k * omega) ** 2 + 1j * k * omega * self.c[None, :]
            Q = ((rhs @ self.Phi) / d) @ self.Phi.T
        else:
            Q = np.empty_like(rhs)
            for kk in range(s.H + 1):
                Z = s.K - (kk * omega) ** 2 * s.M + 1j * kk * omega * s.D
                if sp.issparse(Z):
                    import scipy.sparse.linalg as spla

                    Q[kk] = spla.spsolve(sp.csc_matrix(Z), rhs[kk])
                else:
                    Q[kk] = np.linalg.solve(np.asarray(Z), rhs[kk])
        return self._to_real(Q)


def _is_symmetric(A) -> bool:
    d = A - A.T
    scale = abs(A).max() if A.shape[0] else 0.0
    mx = abs(d).max() if (d.nnz if sp.issparse(d) else d.size) else 0.0
    return bool(mx <= 1e-12 * max(scale, 1e-300))


def _choose(s: _Setup, method: str):
    """Pick the formulation: ("full"|"condensed", kind) for method auto/full/condensed."""
    if method not in ("auto", "full", "condensed"):
        raise ModelError(f"method must be 'auto', 'full' or 'condensed', got {method!r}")
    if method == "full" or not s.contacts:
        return _Full(s)
    can_condense = s.n_rows < s.n or method == "condensed"
    if can_condense:
        kind = None
        modal = None
        if s.n <= 2000:
            Md, Kd, Dd = _dense(s.M), _dense(s.K), _dense(s.D)
            if _is_symmetric(Kd) and _is_symmetric(Dd):
                w2, Phi = sla.eigh(Kd, Md)
                C = Phi.T @ Dd @ Phi
                modal = (w2, Phi, C)
                off = np.abs(C - np.diag(np.diag(C))).max() if s.n > 1 else 0.0
                if w2.min() > 1e-10 * max(w2.max(), 1e-300) and off <= 1e-9 * max(
                        np.abs(C).max(), 1e-300):
                    kind = "modal"
                elif w2.min() <= 1e-10 * max(w2.max(), 1e-300):
                    kind = "singular"
        if kind is None:
            try:
                if sp.issparse(s.K):
                    import scipy.sparse.linalg as spla

                    spla.splu(sp.csc_matrix(s.K))
                else:
                    sla.lu_factor(_dense(s.K), check_finite=False)
                    if np.linalg.cond(_dense(s.K)) > 1e13:
                        raise np.linalg.LinAlgError
                kind = "direct"
            except (RuntimeError, np.linalg.LinAlgError, ValueError):
                kind = "singular"
        if kind != "singular":
            return _Condensed(s, kind, modal if kind == "modal" else None)
        if method == "condensed":
            raise ModelError("method='condensed' needs a non-singular stiffness matrix K (the "
                             "static compliance K^-1); this structure is held by its contacts "
                             "only: use method='full'")
    return _Full(s)


# ============================================================================ results
def _postprocess(s: _Setup, X: np.ndarray, omega: np.ndarray, xi=None, load_scale=None):
    """Contact forces, energies and amplitudes of steady states X (n_p, n, nh)."""
    n_p = X.shape[0]
    nh = s.nh
    U = np.zeros((n_p, s.n_rows, nh))
    for p in range(n_p):
        U[p] = s.P @ X[p]
    Fn = np.zeros_like(U)
    for p in range(n_p):
        if s.n_rows:
            Fn[p] = aft(s.contacts, U[p], float(omega[p]), s.basis, jacobian=False).force
    Wrow = cycle_work(U, Fn)                                         # (n_p, n_rows)
    Wc = np.zeros((n_p, s.n_contacts))
    if s.n_rows:
        np.add.at(Wc.T, s.contact_of_row, Wrow.T)
    W_ext = cycle_work(X, np.broadcast_to(s.F_ex, X.shape)).sum(axis=1)
    if load_scale is not None:     # the work of the static load over a cycle is zero
        W_ext = W_ext * np.asarray(load_scale, dtype=float)
    # viscous: Omega * pi * sum_k k^2 (a^T D a + b^T D b)
    Dd = s.D
    dX = X @ s.basis.d_dtau.T                                       # coefficients of dq/dtau
    DdX = np.stack([np.asarray(Dd @ dX[p]) for p in range(n_p)]) if n_p else dX
    W_visc = omega * np.pi * np.einsum("pnh,pnh->p", dX[:, :, 1:], DdX[:, :, 1:])
    MdX = np.stack([np.asarray(s.M @ dX[p]) for p in range(n_p)]) if n_p else dX
    # 2 pi x mean kinetic energy over the cycle [J]: the floor of the balance error
    E_kin = omega**2 * np.pi * np.einsum("pnh,pnh->p", dX[:, :, 1:], MdX[:, :, 1:])
    W_neg = None if xi is None else xi / omega * E_kin
    amp = peak_amplitude(X)
    return dict(U=U, F=Fn, W_contact=Wc, W_ext=W_ext, W_visc=W_visc, W_neg=W_neg, amp=amp,
                E_kin=E_kin)


def peak_amplitude(X: np.ndarray, n_grid: int = 128) -> np.ndarray:
    """``max_tau |x(tau) - c0|`` of signals with coefficients X (..., 2H+1), shape (...).

    Grid search on ``n_grid`` phases, then three Newton steps on dx/dtau = 0 from the best
    sample (the extremum of a trigonometric polynomial to machine precision).
    """
    X = np.asarray(X, dtype=float)
    shape = X.shape[:-1]
    C = X.reshape(-1, X.shape[-1]).copy()
    C[:, 0] = 0.0
    H = (C.shape[1] - 1) // 2
    if C.shape[0] == 0:
        return np.zeros(shape)
    xs = C @ _fine_synthesis(H, n_grid).T                       # (m, n_grid)
    i = np.argmax(np.abs(xs), axis=1)
    sgn = np.sign(xs[np.arange(C.shape[0]), i])
    tau = 2 * np.pi * i / n_grid
    k = np.arange(1, H + 1)
    a, b = C[:, 1::2], C[:, 2::2]
    for _ in range(3):
        ck, sk = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
        d1 = np.sum(k * (-a * sk + b * ck), axis=1)
        d2 = np.sum(-(k**2) * (a * ck + b * sk), axis=1)
        ok = d2 * sgn < 0
        tau = np.where(ok, tau - d1 / np.where(ok, d2, 1.0), tau)
    ck, sk = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
    val = np.abs(np.sum(a * ck + b * sk, axis=1))
    return np.maximum(val, np.abs(xs).max(axis=1)).reshape(shape)


_FINE: dict[int, np.ndarray] = {}


def _fine_synthesis(H: int, n_t: int = 256) -> np.ndarray:
    key = (H, n_t)
    if key not in _FINE:
        tau = 2 * np.pi * np.arange(n_t) / n_t
        kt = np.outer(tau, np.arange(1, H + 1))
        S = np.empty((n_t, 2 * H + 1))
        S[:, 0] = 1.0
        S[:, 1::2] = np.cos(kt)
        S[:, 2::2] = np.sin(kt)
        _FINE[key] = S
    return _FINE[key]


def _balance_error(W_in, W_out, E_ref):
    """|W_in - W_out| / max(|W_in|, |W_out|, 1e-8 E_ref): 0 for a conservative cycle."""
    den = np.maximum(np.maximum(np.abs(W_in), np.abs(W_out)), 1e-8 * np.abs(E_ref))
    return np.abs(W_in - W_out) / np.maximum(den, 1e-300)


@dataclass(frozen=True, eq=False)
class SteadyState:
    """One periodic steady state from :func:`harmonic_balance`.

    Attributes
    ----------
    omega : float
        Excitation (fundamental) angular frequency [rad/s].
    coefficients : ndarray, shape (n_dof, 2H+1)
        Real harmonic coefficients ``[c0, a1, b1, ..., aH, bH]`` of every DOF [m].
    amplitude : ndarray, shape (n_dof,)
        Largest excursion from the mean over the period, ``max_t |q(t) - c0|`` [m].
    contact_displacement, contact_force : ndarray, shape (n_rows, 2H+1)
        Harmonics of the local relative displacements [m] and contact forces [N].
    dissipated_energy : ndarray, shape (n_contacts,)
        ``oint f . du`` per contact per cycle [J].
    external_work, viscous_dissipation : float
        Work of the loads and of the viscous damping per cycle [J].
    energy_balance_error : float
        ``|W_ext - W_visc - sum W_contact| / max(...)``.
    success : bool
    status : int
        0 converged; 1 Newton failed: every array is then NaN (no solution is returned).
    message : str
    iterations : int
    residual_norm : float
        Max-norm of the scaled residual.
    harmonics, samples : int
    method : str
    """

    omega: float
    coefficients: np.ndarray
    amplitude: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    dissipated_energy: np.ndarray
    external_work: float
    viscous_dissipation: float
    energy_balance_error: float
    success: bool
    status: int
    message: str
    iterations: int
    residual_norm: float
    harmonics: int
    samples: int
    method: str
    dof_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()

    def time_history(self, n_samples: int = 256) -> tuple[np.ndarray, np.ndarray]:
        """One period: times t [s] shape (n_samples,) and q(t) shape (n_samples, n_dof)."""
        S = _fine_synthesis(self.harmonics, int(n_samples))
        t = 2 * np.pi * np.arange(n_samples) / n_samples / self.omega
        return t, S @ self.coefficients.T


@dataclass(frozen=True, eq=False)
class FrequencyResponse:
    """Frequency response curve from :func:`frequency_response` (converged points only).

    Attributes
    ----------
    omega : ndarray, shape (n_points,)
        Excitation angular frequency [rad/s] along the path (not monotone past folds).
    coefficients : ndarray, shape (n_points, n_dof, 2H+1)
        Harmonic coefficients of the DOFs [m] (see :mod:`fricdamp.solvers.aft`).
    amplitude : ndarray, shape (n_points, n_dof)
        ``max_t |q(t) - mean|`` [m].
    fundamental : ndarray, shape (n_points, n_dof)
        Amplitude of the first harmonic ``sqrt(a1^2 + b1^2)`` [m].
    contact_displacement, contact_force : ndarray, shape (n_points, n_rows, 2H+1)
        Harmonics of the contact relative displacements [m] and forces [N].
    dissipated_energy : ndarray, shape (n_points, n_contacts)
        Energy dissipated per cycle by each contact [J].
    external_work, viscous_dissipation : ndarray, shape (n_points,)
        Per cycle [J].
    energy_balance_error : ndarray, shape (n_points,)
        Relative energy balance error of each point.
    iterations : ndarray, shape (n_points,)
        Newton iterations per point.
    turning_points : tuple of int
        Indices of points after which Omega turns back (folds).
    status : int
        0 success; 1 max points; 2 stalled; 3 turned back; 4 callback; -1 no start point.
    message : str
    harmonics, samples : int
    method : str
        Formulation used ("full-dense", "full-sparse", "condensed-modal", ...).
    wall_time : float
        Seconds spent in the continuation.
    n_evaluations, n_factorizations : int
    dof_names, contact_names : tuple of str
    load_scale : ndarray, shape (n_points,)
        Factor on the harmonic loads (1 for a frequency response; the continued parameter
        of :func:`load_response`).
    parameter : str
        The continued parameter: "omega" or "load".
    """

    omega: np.ndarray
    coefficients: np.ndarray
    amplitude: np.ndarray
    fundamental: np.ndarray
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    dissipated_energy: np.ndarray
    external_work: np.ndarray
    viscous_dissipation: np.ndarray
    energy_balance_error: np.ndarray
    iterations: np.ndarray
    turning_points: tuple[int, ...]
    status: int
    message: str
    harmonics: int
    samples: int
    method: str
    wall_time: float
    n_evaluations: int
    n_factorizations: int
    dof_names: tuple[str, ...] = ()
    contact_names: tuple[str, ...] = ()
    load_scale: np.ndarray | None = None
    parameter: str = "omega"

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def n_points(self) -> int:
        return int(self.omega.size)

    def steady_state(self, i: int) -> SteadyState:
        """Point ``i`` as a :class:`SteadyState`."""
        return SteadyState(float(self.omega[i]), self.coefficients[i], self.amplitude[i],
                           self.contact_displacement[i], self.contact_force[i],
                           self.dissipated_energy[i], float(self.external_work[i]),
                           float(self.viscous_dissipation[i]),
                           float(self.energy_balance_error[i]), True, 0, "converged",
                           int(self.iterations[i]), 0.0, self.harmonics, self.samples,
                           self.method, self.dof_names, self.contact_names)

    def peak(self, dof: int = 0, *, refine: bool = True) -> tuple[float, float]:
        """(Omega [rad/s], amplitude [m]) of the largest ``amplitude`` of ``dof``.

        With ``refine`` the vertex of the parabola through the largest point and its two
        neighbours (when they bracket it in Omega) is returned instead of the point itself.
        """
        A = self.amplitude[:, dof]
        i = int(np.argmax(A))
        w, a = float(self.omega[i]), float(A[i])
        if refine and 0 < i < A.size - 1:
            x = self.omega[i - 1: i + 2]
            y = A[i - 1: i + 2]
            if (x[1] - x[0]) * (x[2] - x[1]) > 0:
                c2, c1, c0 = np.polyfit(x - x[1], y, 2)
                if c2 < 0:
                    xv = -c1 / (2 * c2)
                    if min(x[0], x[2]) - x[1] <= xv <= max(x[0], x[2]) - x[1]:
                        w, a = float(x[1] + xv), float(c0 - c1**2 / (4 * c2))
        return w, a

    def to_xarray(self):
        """``xarray.Dataset`` with dimensions point, dof, coefficient, row, contact."""
        import xarray as xr

        H = self.harmonics
        coef = ["c0"] + [f"{ab}{k}" for k in range(1, H + 1) for ab in ("a", "b")]
        dofs = list(self.dof_names) or [f"q{i + 1}" for i in range(self.coefficients.shape[1])]
        contacts = list(self.contact_names) or [
            f"c{i}" for i in range(self.dissipated_energy.shape[1])]
        ds = xr.Dataset(
            {
                "coefficients": (("point", "dof", "coefficient"), self.coefficients,
                                 {"units": "m"}),
                "amplitude": (("point", "dof"), self.amplitude, {"units": "m"}),
                "fundamental": (("point", "dof"), self.fundamental, {"units": "m"}),
                "contact_displacement": (("point", "row", "coefficient"),
                                         self.contact_displacement, {"units": "m"}),
                "contact_force": (("point", "row", "coefficient"), self.contact_force,
                                  {"units": "N"}),
                "dissipated_energy": (("point", "contact"), self.dissipated_energy,
                                      {"units": "J"}),
                "external_work": (("point",), self.external_work, {"units": "J"}),
                "viscous_dissipation": (("point",), self.viscous_dissipation, {"units": "J"}),
                "energy_balance_error": (("point",), self.energy_balance_error),
                "iterations": (("point",), self.iterations),
                "load_scale": (("point",), np.ones(self.omega.size) if self.load_scale is None
                               else self.load_scale),
            },
            coords={"omega": (("point",), self.omega, {"units": "rad/s"}),
                    "dof": dofs, "coefficient": coef, "contact": contacts},
            attrs={"harmonics": H, "samples": self.samples, "status": self.status,
                   "message": self.message, "method": self.method},
        )
        return ds

    def plot(self, dof: int = 0, ax=None, **kwargs):
        """Amplitude of ``dof`` vs excitation frequency [Hz] (or load scale); returns axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        name = self.dof_names[dof] if self.dof_names else f"q{dof + 1}"
        if self.parameter == "load":
            ax.plot(self.load_scale, self.amplitude[:, dof], **kwargs)
            ax.set_xlabel("load scale [-]")
        else:
            ax.plot(self.omega / (2 * np.pi), self.amplitude[:, dof], **kwargs)
            ax.set_xlabel("excitation frequency [Hz]")
        ax.set_ylabel(f"amplitude of {name} [m]")
        if not self.success:
            ax.set_title(f"incomplete: {self.message}", fontsize="small")
        return ax


# ============================================================================ drivers
def _scales(s: _Setup, form, omegas) -> tuple[float, float]:
    """Typical unknown magnitude (from linear stuck / free responses) and force scale."""
    Kc = s.tangent_contact_stiffness()
    stuck, free = [], []
    for w in omegas:
        Xs = s.linear_response(w, Kc)
        if Xs is not None:
            stuck.append(np.abs(s.P @ Xs).max() if isinstance(form, _Condensed)
                         else np.abs(Xs).max())
        Xf = s.linear_response(w)
        if Xf is not None:
            free.append(np.abs(s.P @ Xf).max() if isinstance(form, _Condensed)
                        else np.abs(Xf).max())
    cand = [np.max(stuck) if stuck else 0.0, np.median(free) if free else 0.0]
    x_ref = max(cand)
    if not np.isfinite(x_ref) or x_ref <= 0:
        x_ref = 1.0
    f_ref = float(np.abs(s.F_ex).max())
    if f_ref <= 0:
        f_ref = 1.0
    return float(x_ref), f_ref


def _initial_guess(s: _Setup, form, omega, initial_guess):
    """Candidate starting points (unscaled unknowns of ``form``)."""
    if initial_guess is not None:
        g = np.asarray(initial_guess, dtype=float)
        if g.shape == (s.n, s.nh):
            return [g.ravel() if isinstance(form, _Full) else (s.P @ g).ravel()]
        if g.size == form.N:
            return [g.ravel()]
        raise ModelError(f"initial_guess must have shape (n_dof, 2H+1) = ({s.n}, {s.nh}), got "
                         f"{g.shape}")
    out = []
    for Kx in (s.tangent_contact_stiffness(), None):
        X = s.linear_response(omega, Kx)
        if X is not None:
            out.append(X.ravel() if isinstance(form, _Full) else (s.P @ X).ravel())
    out.append(np.zeros(form.N))
    return out


def _method_name(form) -> str:
    if isinstance(form, _Full):
        return "full-dense" if form.dense else "full-sparse"
    return f"condensed-{form.kind}"


def harmonic_balance(system: MechanicalSystem, omega: float, *, harmonics: int = 5,
                     samples: int | None = None, initial_guess=None, method: str = "auto",
                     tol: float = 1e-10, max_iter: int = 100, blas: int | None = 1,
                     throw: bool = False) -> SteadyState:
    """Periodic steady state at one excitation frequency by harmonic balance with AFT.

    Parameters
    ----------
    system : MechanicalSystem
        Structure with contacts; loads must be :class:`HarmonicLoad` (their ``omega`` is
        replaced by ``omega``) plus the static load.
    omega : float
        Excitation angular frequency Omega [rad/s], > 0.
    harmonics : int
        Highest harmonic H (>= 1; >= 7 for friction responses to ~1 %).
    samples : int, optional
        AFT time samples N per period (>= 2H + 1; default the power of two >= 16 H).
    initial_guess : ndarray, shape (n_dof, 2H+1), optional
        Starting coefficients; by default the linear responses with stuck, then free,
        contacts and zero are tried in turn.
    method : {"auto", "full", "condensed"}
        Formulation (see the module docstring).
    tol : float
        Newton tolerance on the max-norm of the residual scaled by the load (full) or by
        the typical contact displacement (condensed).
    max_iter : int
        Newton iterations (with backtracking) per starting guess.
    blas : int or None
        BLAS threads during the solve (default 1; None leaves the pools alone).
    throw : bool
        Raise ConvergenceError when Newton fails instead of returning ``success=False``.

    Returns
    -------
    SteadyState

    Examples
    --------
    >>> import numpy as np
    >>> from fricdamp.contact import Jenkins
    >>> from fricdamp.structure import ContactElement, HarmonicLoad, MechanicalSystem
    >>> sys = MechanicalSystem(M=[[1.0]], K=[[1.0]], D=[[0.02]],
    ...     contacts=(ContactElement(Jenkins(1.0, 0.05), [[1.0]]),),
    ...     loads=(HarmonicLoad([0.1], omega=1.0),))
    >>> ss = harmonic_balance(sys, 1.2, harmonics=7)
    >>> bool(ss.success), ss.energy_balance_error < 1e-6
    (True, True)
    """
    if not (np.isfinite(omega) and omega > 0):
        raise ModelError(f"omega must be > 0 rad/s, got {omega!r}")
    s = _Setup(system, harmonics, samples)
    with blas_threads(blas):
        form = _choose(s, method)
        x_ref, f_ref = _scales(s, form, [omega])
        scale = 1.0 / (f_ref if isinstance(form, _Full) else x_ref)

        def fun(x):
            r, J, _, _, _ = form.evaluate(x, omega, scale=scale, x_scale=x_ref)
            return r, J

        best = None
        for g in _initial_guess(s, form, omega, initial_guess):
            res = newton(fun, g / x_ref, tol=tol, max_iter=max_iter)
            if best is None or res.residual_norm < best.residual_norm:
                best = res
            if res.success:
                break
        X = form.to_dofs(best.x, omega, x_ref) if best.success else None
    if not best.success:
        msg = (f"Newton failed at omega = {omega:g} rad/s: {best.message} (residual "
               f"{best.residual_norm:.3g}); no solution is returned (NaN): try another "
               "initial_guess, more samples, or frequency_response to approach it by "
               "continuation")
        if throw:
            raise ConvergenceError(msg)
        nan = np.full
        return SteadyState(float(omega), nan((s.n, s.nh), np.nan), nan(s.n, np.nan),
                           nan((s.n_rows, s.nh), np.nan), nan((s.n_rows, s.nh), np.nan),
                           nan(s.n_contacts, np.nan), np.nan, np.nan, np.nan, False, 1, msg,
                           best.iterations, best.residual_norm, s.H, s.basis.samples,
                           _method_name(form), system.names, s.contact_names)
    pp = _postprocess(s, X[None], np.array([omega]))
    err = _balance_error(pp["W_ext"], pp["W_visc"] + pp["W_contact"].sum(axis=1), pp["E_kin"])
    return SteadyState(float(omega), X, pp["amp"][0], pp["U"][0], pp["F"][0],
                       pp["W_contact"][0], float(pp["W_ext"][0]), float(pp["W_visc"][0]),
                       float(err[0]), True, 0, best.message, best.iterations,
                       best.residual_norm, s.H, s.basis.samples, _method_name(form),
                       system.names, s.contact_names)


def frequency_response(system: MechanicalSystem, omega_start: float, omega_end: float, *,
                       harmonics: int = 5, samples: int | None = None, step: float = 0.02,
                       min_step: float | None = None, max_step: float | None = None,
                       max_points: int = 2000, method: str = "auto", tol: float = 1e-9,
                       initial_guess=None, max_angle_deg: float = 25.0,
                       blas: int | None = 1, throw: bool = False) -> FrequencyResponse:
    """Frequency response curve through resonance by HB-AFT and arclength continuation.

    Parameters
    ----------
    system : MechanicalSystem
        Structure, contacts and harmonic loads (their ``omega`` is the continued Omega).
        For engine-order forcing of a cyclic assembly use :func:`engine_order_load`.
    omega_start, omega_end : float
        Excitation frequency interval [rad/s] (either direction), > 0.
    harmonics : int
        Highest harmonic H.
    samples : int, optional
        AFT samples N per period (default the power of two >= 16 H).
    step : float
        Initial arclength step in scaled variables: Omega is scaled by
        ``|omega_end - omega_start|`` and the unknowns by the largest linear (stuck
        contacts) response over the interval, so 0.02 is about 1/50 of the interval.
    min_step, max_step : float, optional
        Step bounds (default ``step / 1000`` and ``5 * step``).
    max_points : int
        Largest number of points.
    method : {"auto", "full", "condensed"}
        Formulation (see the module docstring).
    tol : float
        Newton tolerance (scaled residual, see :func:`harmonic_balance`).
    initial_guess : ndarray, shape (n_dof, 2H+1), optional
        Starting coefficients at ``omega_start``.
    max_angle_deg : float
        Steps whose tangent turns more than this are refined.
    blas : int or None
        BLAS threads (default 1: faster for these small factorisations).
    throw : bool
        Raise ConvergenceError if the curve could not be completed.

    Returns
    -------
    FrequencyResponse
        Converged points only; ``status``/``message`` say whether ``omega_end`` was
        reached and, if not, why.
    """
    for name, v in (("omega_start", omega_start), ("omega_end", omega_end)):
        if not (np.isfinite(v) and v > 0):
            raise ModelError(f"{name} must be > 0 rad/s, got {v!r}")
    if omega_start == omega_end:
        raise ModelError("omega_start and omega_end must differ")
    out = _curve(system, harmonics, samples, method, "omega", omega_start, omega_end,
                 omega_start, 1.0, step, min_step, max_step, max_points, tol, initial_guess,
                 max_angle_deg, blas)
    if throw and not out.success:
        raise ConvergenceError(f"frequency response incomplete: {out.message}")
    return out


def load_response(system: MechanicalSystem, omega: float, scale_start: float,
                  scale_end: float, *, harmonics: int = 5, samples: int | None = None,
                  step: float = 0.02, min_step: float | None = None,
                  max_step: float | None = None, max_points: int = 2000,
                  method: str = "auto", tol: float = 1e-9, initial_guess=None,
                  max_angle_deg: float = 25.0, blas: int | None = 1,
                  throw: bool = False) -> FrequencyResponse:
    """Steady response vs excitation level at fixed frequency (continuation in the load).

    The harmonic loads (harmonics k >= 1) are multiplied by the continued factor
    ``load_scale`` from ``scale_start`` to ``scale_end`` (the static load is kept): the
    classic friction-damper curve of response against excitation level, through its
    stick-slip transition. Parameters as :func:`frequency_response`, with ``omega`` the fixed
    excitation frequency [rad/s] and the scale factors [-] (``scale_start`` >= 0).

    Returns
    -------
    FrequencyResponse
        With constant ``omega`` and the continued factor in ``load_scale``.
    """
    if not (np.isfinite(omega) and omega > 0):
        raise ModelError(f"omega must be > 0 rad/s, got {omega!r}")
    for name, v in (("scale_start", scale_start), ("scale_end", scale_end)):
        if not (np.isfinite(v) and v >= 0):
            raise ModelError(f"{name} must be >= 0, got {v!r}")
    if scale_start == scale_end:
        raise ModelError("scale_start and scale_end must differ")
    out = _curve(system, harmonics, samples, method, "load", scale_start, scale_end,
                 float(omega), scale_start, step, min_step, max_step, max_points, tol,
                 initial_guess, max_angle_deg, blas)
    if throw and not out.success:
        raise ConvergenceError(f"load response incomplete: {out.message}")
    return out


def _curve(system, harmonics, samples, method, param, lam0, lam1, omega0, scale0, step,
           min_step, max_step, max_points, tol, initial_guess, max_angle_deg, blas):
    """Continue the HB solution in Omega (param "omega") or in the load scale ("load")."""
    s = _Setup(system, harmonics, samples)
    t0 = time.perf_counter()
    with blas_threads(blas):
        form = _choose(s, method)
        if param == "omega":
            grid = np.linspace(lam0, lam1, 17)
            s_grid = None
        else:
            grid = [omega0]
            s_grid = max(abs(lam0), abs(lam1))
        x_ref, f_ref = _scales(s, form, grid)
        if s_grid is not None:      # linear estimates were made at load scale 1
            x_ref *= max(s_grid, 1e-12) if np.any(s.F_ex[:, 1:]) else 1.0
            f_ref *= max(s_grid, 1e-12) if not np.any(s.F_ex[:, 0]) else 1.0
        scale = 1.0 / (f_ref if isinstance(form, _Full) else x_ref)
        d_load = None
        if param == "load":
            if isinstance(form, _Full):
                d_load = np.zeros_like(s.F_ex)
                d_load[:, 1:] = -s.F_ex[:, 1:]
                d_load = d_load.ravel() * scale
            else:
                _, _, ul, _ = form.compliance(omega0)
                ul = ul.copy()
                ul[0] = 0.0
                d_load = -form._to_real(ul).ravel() * scale

        def residual(x, lam):
            if param == "omega":
                r, J, dr, _, _ = form.evaluate(x, lam, scale=scale, x_scale=x_ref)
                return r, J, dr
            r, J, _, _, _ = form.evaluate(x, omega0, scale=scale, x_scale=x_ref,
                                          load_scale=lam)
            return r, J, d_load

        guesses = _initial_guess(s, form, omega0, initial_guess)
        if param == "load":
            guesses = [g * scale0 if np.any(s.F_ex[:, 1:]) else g for g in guesses]
        x0 = guesses[0] / x_ref
        for g in guesses:
            res = newton(lambda x: residual(x, lam0)[:2], g / x_ref, tol=tol, max_iter=100)
            if res.success:
                x0 = res.x
                break
        cres = solve_and_continue(
            x0, residual, lam0, lam1, step,
            ds_min=min_step if min_step is not None else step / 1000.0,
            ds_max=max_step if max_step is not None else 5.0 * step,
            x_scale=1.0, lam_scale=abs(lam1 - lam0), tol=tol,
            max_steps=max_points, max_angle_deg=max_angle_deg, blas=None)
        wall = time.perf_counter() - t0
        n_p = cres.n_points
        omegas = cres.lam if param == "omega" else np.full(n_p, omega0)
        scales = np.ones(n_p) if param == "omega" else cres.lam.copy()
        X = np.stack([form.to_dofs(x, w, x_ref, load_scale=ls) for x, w, ls in
                      zip(cres.x, omegas, scales, strict=True)]
                     ) if n_p else np.zeros((0, s.n, s.nh))
    pp = _postprocess(s, X, omegas, load_scale=scales)
    fund = np.hypot(X[:, :, 1], X[:, :, 2])
    err = _balance_error(pp["W_ext"], pp["W_visc"] + pp["W_contact"].sum(axis=1), pp["E_kin"])
    return FrequencyResponse(
        omegas, X, pp["amp"], fund, pp["U"], pp["F"], pp["W_contact"], pp["W_ext"],
        pp["W_visc"], err, cres.iterations, cres.turning_points,
        cres.status, cres.message, s.H, s.basis.samples, _method_name(form), wall,
        cres.n_evaluations, cres.n_factorizations, system.names, s.contact_names, scales,
        param)


def engine_order_load(n_sectors: int, engine_order: int, amplitude: float, *,
                      dofs_per_sector: int = 1, dof: int = 0, harmonic: int = 1,
                      omega: float = 1.0) -> HarmonicLoad:
    """Travelling-wave (engine-order) excitation of a cyclic assembly.

    Sector j (0-based) is loaded at DOF ``j * dofs_per_sector + dof`` by
    ``amplitude * cos(harmonic Omega t - 2 pi engine_order j / n_sectors)`` [N], i.e. a
    forward wave of ``engine_order`` nodal diameters.

    Parameters
    ----------
    n_sectors : int
        Number of sectors N_s >= 1.
    engine_order : int
        Engine order (integer; its alias modulo N_s sets the nodal diameter).
    amplitude : float
        Force amplitude per sector [N].
    dofs_per_sector : int
        DOFs of each sector (sector-major numbering).
    dof : int
        Loaded DOF within the sector.
    harmonic : int
        Harmonic of the load (1 = at Omega).
    omega : float
        Nominal angular frequency [rad/s] stored in the load (HB replaces it).

    Returns
    -------
    HarmonicLoad
    """
    if int(n_sectors) != n_sectors or n_sectors < 1:
        raise ModelError(f"n_sectors must be an integer >= 1, got {n_sectors!r}")
    if int(dofs_per_sector) != dofs_per_sector or dofs_per_sector < 1:
        raise ModelError(f"dofs_per_sector must be an integer >= 1, got {dofs_per_sector!r}")
    if not 0 <= dof < dofs_per_sector:
        raise ModelError(f"dof must lie in [0, {dofs_per_sector - 1}], got {dof!r}")
    if int(engine_order) != engine_order:
        raise ModelError(f"engine_order must be an integer, got {engine_order!r}")
    a = np.zeros(int(n_sectors) * int(dofs_per_sector), complex)
    j = np.arange(int(n_sectors))
    a[j * dofs_per_sector + dof] = amplitude * np.exp(-2j * np.pi * engine_order * j / n_sectors)
    return HarmonicLoad(a, omega=omega, harmonic=harmonic)
