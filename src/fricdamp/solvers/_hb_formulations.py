"""Harmonic-balance formulations: the residuals and Jacobians of :mod:`fricdamp.solvers.hb`.

* ``_Setup``: the system data shared by the formulations (harmonic basis, stacked contact
  projection, excitation coefficients :func:`excitation_coefficients`, linear estimates with
  stuck or free contacts);
* ``_Full``: the residual of the harmonics of all DOFs, its Jacobian assembled into a fixed
  sparsity pattern (dense below :data:`DENSE_LIMIT` unknowns);
* ``_Condensed``: the residual in the contact coordinates through the exact per-harmonic
  dynamic compliance (modal superposition or direct solves);
* ``_choose``: the formulation for ``method="auto" | "full" | "condensed"``.

The equations and the choice between the formulations are described in
:mod:`fricdamp.solvers.hb`, whose drivers are the public entry points.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from fricdamp._numba_cache import njit
from fricdamp.errors import ModelError
from fricdamp.solvers.aft import HarmonicBasis, aft, element_rows
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem, TimeLoad

#: Below this number of unknowns the full formulation uses dense LU (measured crossover
#: with SuperLU on this class of machine: dense 330 x 330 ~1 ms, sparse ~0.5 ms).
DENSE_LIMIT = 200


# ============================================================================ set-up
@njit(cache=True, nogil=True)
def _jacobian_values(out, pos, base0, base1, base2, c1, c2, dest, coef, src, jflat,
                     scale):  # pragma: no cover - compiled
    """``out = scale * (lin + scatter(coef * jflat[src] -> dest))``, ``lin[pos] = base0 +
    c1 base1 + c2 base2`` and zero elsewhere.

    The values of the Jacobian in its fixed pattern: the linear part ``K + Omega^2 M E_M +
    Omega D E_D`` at its own entries ``pos`` (a sixth of the pattern of the ring of Jenkins
    contacts, H = 5: the contact blocks are dense in the harmonics, the linear part couples
    a harmonic with itself) and the contact blocks ``(P^T x I) J_nl (P x I)`` scattered by
    precomputed (destination, source, coefficient) triples, sorted by destination. No
    temporaries (replaces a gather, a product and ``np.bincount`` over all entries). The
    entries outside ``pos`` would be ``0 + c1 0 + c2 0 = 0``: the same bits as a pass of
    the linear formula over the whole pattern, which read three arrays of its size.
    """
    for i in range(out.size):
        out[i] = 0.0
    for i in range(pos.size):
        out[pos[i]] = base0[i] + c1 * base1[i] + c2 * base2[i]
    for i in range(dest.size):
        out[dest[i]] += coef[i] * jflat[src[i]]
    for i in range(out.size):
        out[i] *= scale


@njit(cache=True, nogil=True)
def _linear_residual(x, ptr, col, v0, v1, v2, omega, rhs, r, dr):  # pragma: no cover
    """``r = S(Omega) x - rhs`` and ``dr = dS/dOmega x`` with ``S = V0 + Omega^2 V1 + Omega
    V2`` (CSR rows ``ptr``, columns ``col``, the values of K, M and D expanded over the
    harmonics)."""
    w2 = omega * omega
    for i in range(ptr.size - 1):
        a = 0.0
        b = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            xj = x[col[p]]
            a += (v0[p] + w2 * v1[p] + omega * v2[p]) * xj
            b += (2.0 * omega * v1[p] + v2[p]) * xj
        r[i] = a - rhs[i]
        dr[i] = b


@njit(cache=True, nogil=True)
def _csr_times(ptr, idx, val, X, out, add):  # pragma: no cover - compiled
    """``out (+)= A @ X`` for A in CSR form and X (n, m) dense."""
    m = X.shape[1]
    for i in range(ptr.size - 1):
        if not add:
            for h in range(m):
                out[i, h] = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            a = val[p]
            j = idx[p]
            for h in range(m):
                out[i, h] += a * X[j, h]


@njit(cache=True, nogil=True)
def _jenkins_linear_part(x, x_scale, ptr, col, v0, v1, v2, omega, rhs, p_ptr, p_idx, p_val,
                         X, xf, rf, drf, U):  # pragma: no cover - compiled
    """``X = x_scale x`` (``xf``: the flat view of ``X`` (n, nh)), :func:`_linear_residual`
    into ``rf``, ``drf`` (N,) and ``U = P X`` (:func:`_csr_times`): the steps of an
    evaluation before the AFT step, in one call (the same operations in the same order).
    The flat views are passed, not made here: no reshape, so loading the cached code needs
    no numba array modules (``tests/unit/test_hb_fast_path.py``)."""
    for i in range(x.size):
        xf[i] = x[i] * x_scale
    _linear_residual(xf, ptr, col, v0, v1, v2, omega, rhs, rf, drf)
    _csr_times(p_ptr, p_idx, p_val, X, U, False)


@njit(cache=True, nogil=True)
def _jenkins_contact_part(pt_ptr, pt_idx, pt_val, F, r, rf, drf, scale, r_out,
                          dr_out):  # pragma: no cover - compiled
    """``r += P^T F`` (:func:`_csr_times`; ``r`` (n, nh), ``rf`` its flat view), then
    ``r_out = scale r``, ``dr_out = scale dr`` (flat): the steps of an evaluation after the
    AFT step, in one call."""
    _csr_times(pt_ptr, pt_idx, pt_val, F, r, True)
    for i in range(rf.size):
        r_out[i] = rf[i] * scale
        dr_out[i] = drf[i] * scale


def _csr_arrays(A):
    A = sp.csr_matrix(A)
    A.sort_indices()
    return (A.indptr.astype(np.int64), A.indices.astype(np.int64),
            np.ascontiguousarray(A.data, dtype=float))


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
        """Contact stiffness at the virgin state and zero displacement, sparse (n, n).

        Computed once per set-up (the same object is returned again)."""
        Kc = getattr(self, "_Kc", None)
        if Kc is None:
            Kc = self._Kc = self._tangent_contact_stiffness()
        return Kc

    def _tangent_contact_stiffness(self):
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
        """Harmonic coefficients (n, nh) of the linear response with K + K_extra, or None.

        Small systems (n <= :data:`DENSE_LIMIT`) are solved densely: the sparse solver's
        set-up costs ~1 ms per call there, against ~20 us.
        """
        K, M, D = self.K, self.M, self.D
        if self.n <= DENSE_LIMIT and (sp.issparse(K) or sp.issparse(M) or sp.issparse(D)):
            if getattr(self, "_dense_kmd", None) is None:
                self._dense_kmd = (_dense(K), _dense(M), _dense(D))
            K, M, D = self._dense_kmd
        aligned = None
        if sp.issparse(K) and sp.issparse(M) and sp.issparse(D):
            aligned = self._aligned(K_extra)
        elif K_extra is not None:
            # K + K_extra once per K_extra object (the step scaling asks at 17 frequencies)
            kept = getattr(self, "_k_plus", None)
            if kept is not None and kept[0] is K_extra and kept[1] is K:
                K = kept[2]
            else:
                Ks = (K + K_extra).tocsr() if sp.issparse(K) else K + _dense(K_extra)
                self._k_plus = (K_extra, K, Ks)
                K = Ks
        X = np.zeros((self.n, self.nh))
        F = self.F_ex
        kept = getattr(self, "_loaded_harmonics", None)
        if kept is not None and kept[0] is F:
            loaded = kept[1]
        else:                       # the harmonics with a load
            loaded = [k for k in range(self.H + 1)
                      if np.any(F[:, [0] if k == 0 else [2 * k - 1, 2 * k]])]
            self._loaded_harmonics = (F, loaded)
        try:
            for k in loaded:
                rhs = F[:, 0].astype(complex) if k == 0 else F[:, 2 * k - 1] - 1j * F[:, 2 * k]
                if aligned is not None:
                    import scipy.sparse.linalg as spla

                    Z, Kd, Md, Dd = aligned
                    Z.data = Kd - (k * omega) ** 2 * Md + (1j * k * omega) * Dd
                    Qk = spla.spsolve(Z, rhs)
                else:
                    Z = K - (k * omega) ** 2 * M + 1j * k * omega * D
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

    def _aligned(self, K_extra):
        """(Z, K, M, D data) on the union pattern of K + K_extra, M, D (CSC): the dynamic
        stiffness of any frequency is then one vector expression (no sparse arithmetic,
        ~1 ms per call at 480 DOFs). Cached for the last two ``K_extra`` objects."""
        cache = getattr(self, "_aligned_cache", None)
        if cache is None:
            cache = self._aligned_cache = []
        for key, out in cache:
            if key is K_extra:
                return out
        K = self.K if K_extra is None else self.K + K_extra
        mats = [sp.coo_matrix(A) for A in (K, self.M, self.D)]
        n = self.n
        keys = np.unique(np.concatenate([m.col.astype(np.int64) * n + m.row for m in mats]))
        data = []
        for m in mats:
            d = np.zeros(keys.size)
            np.add.at(d, np.searchsorted(keys, m.col.astype(np.int64) * n + m.row), m.data)
            data.append(d)
        indptr = np.concatenate([[0], np.cumsum(np.bincount(keys // n, minlength=n))])
        Z = sp.csc_matrix((data[0].astype(complex), (keys % n).astype(np.int32),
                           indptr.astype(np.int32)), shape=(n, n))
        Z.has_sorted_indices = True
        out = (Z, *data)
        cache.insert(0, (K_extra, out))
        del cache[2:]
        return out


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
        # the compiled scatter walks the destinations in order (cache-friendly writes)
        order = np.argsort(self.inv_nl, kind="stable")
        # 32-bit indices where they fit: the scatter streams (destination, source,
        # coefficient) triples, ~40 % fewer bytes (ring of 480 Jenkins contacts: 2.3e5)
        itype = np.int32 if max(self.nnz, self.nl_src.size and int(self.nl_src.max()) + 1
                                ) < 2**31 else np.int64
        self.nl_dest = np.ascontiguousarray(self.inv_nl[order], dtype=itype)
        self.nl_src_sorted = np.ascontiguousarray(self.nl_src[order], dtype=itype)
        self.nl_coef_sorted = np.ascontiguousarray(self.nl_coef[order], dtype=float)
        if dense is None:
            dense = Nn <= DENSE_LIMIT or self.nnz > 0.3 * Nn * Nn
        self.dense = bool(dense)
        # the linear part alone as CSR rows (compiled residual, no scipy.sparse products)
        keep = (self.base[0] != 0) | (self.base[1] != 0) | (self.base[2] != 0)
        pos = np.flatnonzero(keep)
        row = self.indices[pos].astype(np.int64)
        col = np.repeat(np.arange(Nn), np.diff(self.indptr))[pos]
        order = np.lexsort((col, row))
        self.lin_ptr = np.concatenate([[0], np.cumsum(np.bincount(row, minlength=Nn))]
                                      ).astype(np.int64)
        self.lin_col = np.ascontiguousarray(col[order], dtype=np.int64)
        self.lin_val = [np.ascontiguousarray(self.base[t][pos][order]) for t in range(3)]
        # the same entries in the order of the pattern, for the Jacobian values
        self.lin_entries = (pos.astype(np.int64),
                            *(np.ascontiguousarray(self.base[t][pos]) for t in range(3)))
        self.P_csr = _csr_arrays(s.P)
        self.PT_csr = _csr_arrays(s.PT)
        self.F_static = _static_only(s.F_ex).ravel()
        F_h = s.F_ex.copy()
        F_h[:, 0] = 0.0
        self.F_harmonic = F_h.ravel()

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

    def _jenkins_step(self):
        """Buffers of the direct Jenkins AFT step, or None if another law acts.

        When every contact element is a :class:`~fricdamp.contact.Jenkins` law (one
        direction), :meth:`evaluate` with ``aft_result=False`` calls the compiled AFT step
        :func:`~fricdamp.contact.jenkins.jenkins_harmonic_step` for all contacts at once
        with the buffers kept here, instead of :func:`~fricdamp.solvers.aft.aft` and
        :meth:`Jenkins.harmonic_response` (their per-call Python overhead, ~0.1 ms, was a
        third of an evaluation on the ring of 30 contacts). Same kernel, same inputs, same
        order of operations: the same floating-point results.
        """
        st = getattr(self, "_jstep", False)
        if st is not False:
            return st
        from fricdamp.contact.jenkins import Jenkins, _prefix_sums, jenkins_harmonic_step

        st = None
        s = self.s
        # the exact type: a subclass may change the law
        if (s.contacts and not self.nma
                and all(type(c.law) is Jenkins and c.n_dir == 1
                        and not c.law.velocity_dependent for c in s.contacts)):

            syn = np.ascontiguousarray(s.basis.synthesis, dtype=float)
            ana = np.ascontiguousarray(s.basis.analysis, dtype=float)
            N, m = syn.shape
            nc = s.n_rows
            pre = _prefix_sums(syn, ana)
            st = dict(
                step=jenkins_harmonic_step,
                kt=np.ascontiguousarray(np.concatenate([c.law.stiffness for c in s.contacts]),
                                        dtype=float),
                fs=np.ascontiguousarray(np.concatenate([c.law.slip_force
                                                        for c in s.contacts]), dtype=float),
                w0=np.zeros(nc), syn=syn, pre=pre,
                U=np.empty((nc, m)), F=np.empty((nc, m)), Jb=np.empty((nc, m, m)),
                u_t=np.empty((nc, N)), f_t=np.empty((nc, N)), w=np.empty(nc),
                anchor=np.empty(N, np.int64), u=np.empty(N), fc=np.empty(pre[3].shape[1]),
                X=np.empty((s.n, s.nh)), r=np.empty((s.n, s.nh)), drf=np.empty(s.n * s.nh))
            st["xf"] = st["X"].reshape(-1)          # flat views of the same buffers
            st["rf"] = st["r"].reshape(-1)
            st["PS_rows"] = st["pre"][0].reshape(N + 1, m * m)
            st["Jb_rows"] = st["Jb"].reshape(nc, m * m)
        self._jstep = st
        return st

    def evaluate(self, x, omega, *, xi=0.0, jacobian=True, scale=1.0, x_scale=1.0,
                 load_scale=1.0, aft_result=True, deferred=False):
        """Residual r (N,) [N * scale], Jacobian wrt x (scaled), dr/dOmega, dr/dxi, AFT.

        ``load_scale`` multiplies the harmonic loads (k >= 1); the static load is kept.
        ``aft_result=False``: the AFT result is not returned (None), which lets systems
        whose contacts are all Jenkins elements take the direct compiled AFT step
        (:meth:`_jenkins_step`; same results). ``deferred`` (with ``aft_result=False``):
        the Jacobian may come as a zero-argument callable that assembles it when called
        (the deferred Jacobians of :mod:`fricdamp.solvers.continuation`).
        """
        s = self.s
        if not aft_result and jacobian:
            js = self._jenkins_step()
            if js is not None:
                return self._evaluate_jenkins(js, x, omega, scale, x_scale, load_scale,
                                              deferred)
        X = (x * x_scale).reshape(s.n, s.nh)
        if self.nma:
            SX, dSX, dxi = self.linear_terms(X, omega, xi)
            r = SX - _static_only(s.F_ex)
            if load_scale != 0.0:
                r[:, 1:] -= load_scale * s.F_ex[:, 1:]
        else:
            # compiled: S(Omega) X - F and dS/dOmega X in one pass over the linear entries
            dxi = None
            rhs = (self.F_static + load_scale * self.F_harmonic if load_scale != 0.0
                   else self.F_static)
            r = np.empty((s.n, s.nh))
            dSX = np.empty((s.n, s.nh))
            _linear_residual(np.ascontiguousarray(X).ravel(), self.lin_ptr, self.lin_col,
                             self.lin_val[0], self.lin_val[1], self.lin_val[2], float(omega),
                             rhs, r.ravel(), dSX.ravel())
        res = None
        if s.contacts:
            U = np.empty((s.n_rows, s.nh))
            _csr_times(*self.P_csr, np.ascontiguousarray(X), U, False)
            res = aft(s.contacts, U, omega, s.basis, jacobian=jacobian)
            _csr_times(*self.PT_csr, res.force, r, True)
            if res.d_omega is not None:
                _csr_times(*self.PT_csr, res.d_omega, dSX, True)
        J = None
        if jacobian:
            # a fresh array per call: callers may keep the previous Jacobian (its values)
            data = np.empty(self.nnz)
            if res is not None and self.nl_src.size:
                Jflat = (res.jacobian[0].ravel() if len(res.jacobian) == 1 else
                         np.concatenate([b.ravel() for b in res.jacobian]))
            else:
                Jflat = np.zeros(1)
            dest = self.nl_dest if res is not None else self.nl_dest[:0]
            _jacobian_values(data, *self.lin_entries, omega**2, omega,
                             dest, self.nl_coef_sorted, self.nl_src_sorted, Jflat,
                             scale * x_scale)
            if self.nma:
                data -= (xi * omega * scale * x_scale) * self.base[3]
            J = self._jacobian_from(data)
        dxi_out = None if dxi is None else dxi.ravel() * scale
        return r.ravel() * scale, J, dSX.ravel() * scale, dxi_out, res

    def _evaluate_jenkins(self, js, x, omega, scale, x_scale, load_scale, deferred=False):
        """:meth:`evaluate` (not NMA, with the Jacobian) for Jenkins contacts only: the same
        compiled kernels called in the same order with the same data, no AFT result.

        ``deferred``: the Jacobian is returned as a callable that assembles it from the
        contact Jacobian blocks of this evaluation (kept in the buffers of
        :meth:`_jenkins_step`) when called: a Newton corrector needs no Jacobian at the
        iterate where it stops (on the ring of 30 Jenkins contacts one evaluation in three;
        the assembly is a third of an evaluation). Called after a later evaluation
        overwrote the buffers, it evaluates again at the same point (same values).
        """
        if js.get("load_scale") != load_scale:      # the right-hand side of this load scale
            js["rhs"] = (self.F_static + load_scale * self.F_harmonic if load_scale != 0.0
                         else self.F_static)
            js["load_scale"] = load_scale
        U, F, Jb, r, rf, drf = js["U"], js["F"], js["Jb"], js["r"], js["rf"], js["drf"]
        # S(Omega) X - F, dS/dOmega X and U = P X; the AFT step; r += P^T F and the scaling:
        # three compiled calls (work arrays kept in js; the returned arrays are new)
        _jenkins_linear_part(np.asarray(x, dtype=float), float(x_scale), self.lin_ptr,
                             self.lin_col, *self.lin_val, float(omega), js["rhs"],
                             *self.P_csr, js["X"], js["xf"], rf, drf, U)
        _, PA, synT, anaT = js["pre"]
        js["step"](U, js["kt"], js["fs"], js["w0"], js["syn"], synT, anaT, js["PS_rows"], PA,
                   50, True, F, js["Jb_rows"], js["u_t"], js["f_t"], js["w"], js["anchor"],
                   js["u"], js["fc"])      # jenkins_harmonic_step
        r_out = np.empty(self.N)
        dr_out = np.empty(self.N)
        _jenkins_contact_part(*self.PT_csr, F, r, rf, drf, float(scale), r_out, dr_out)
        self._n_jenkins = token = getattr(self, "_n_jenkins", 0) + 1

        def jacobian():
            if self._n_jenkins != token:        # the blocks are another point's now
                return self._evaluate_jenkins(js, x, omega, scale, x_scale, load_scale)[1]
            data = np.empty(self.nnz)
            Jflat = Jb.ravel() if self.nl_src.size else np.zeros(1)
            _jacobian_values(data, *self.lin_entries, omega**2, omega,
                             self.nl_dest, self.nl_coef_sorted, self.nl_src_sorted, Jflat,
                             scale * x_scale)
            return self._jacobian_from(data)

        if deferred:
            x = np.array(x, dtype=float)     # the point, should the blocks be overwritten
        return r_out, jacobian if deferred else jacobian(), dr_out, None, None

    def _jacobian_from(self, data):
        if self.dense:
            J = np.zeros(self.N * self.N)
            J[self.lin_index] = data
            return J.reshape(self.N, self.N)
        # one CSC object per formulation, its data replaced at each call (building a scipy
        # matrix costs ~0.1 ms of format checks): callers use J before the next evaluation,
        # as Newton and the continuation do
        J = getattr(self, "_J", None)
        if J is None:
            from fricdamp.solvers.continuation import mark_fixed_pattern

            J = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.N, self.N))
            J.has_sorted_indices = True
            self._J = mark_fixed_pattern(J)
        else:
            J.data = data
        return J

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

    def evaluate(self, y, omega, *, jacobian=True, scale=1.0, x_scale=1.0, load_scale=1.0,
                 aft_result=True, deferred=False):
        """Residual in the contact coordinates (``aft_result`` and ``deferred`` are accepted
        for the common interface with :meth:`_Full.evaluate`; the AFT result is always
        returned, the Jacobian always assembled)."""
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
