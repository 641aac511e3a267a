"""Exact phases of linear systems (:class:`~fricdamp.solvers.event_system.LinearForm`).

Exact phases
------------
For a :class:`~fricdamp.solvers.event_system.LinearForm` in a fixed configuration (stuck set
S, slip directions s), the stuck directions are removed by an orthonormal split
``q = T z + U p`` with ``range(U) = range(W_S)`` and ``W_S^T T = 0``: p is constant while the
contacts stick and z obeys the regular linear system

    T^T M T z'' + T^T D T z' + T^T K T z = T^T (f_static + f_slip - K U p + F(t)),

``f_slip = -sum_slip w_i mu_sliding,i N_i s_i``. The augmented state
``X = [z, z', 1, cos W_k t, sin W_k t, p]`` obeys ``X' = A X`` exactly, and every output (q,
q', friction forces, event functions) is a linear functional of X. The stick forces follow
from ``M q'' = h + f_slip + W_S lambda_S`` as ``lambda_S = W_S^+ (M T z'' - h - f_slip)``.

X(t) is evaluated as homogeneous plus particular solution: ``[z, z'](t) = V exp(L (t - t0))
V^-1 ([z, z'](t0) - Y_p(t0)) + Y_p(t)`` with the eigen-decomposition of the (z, z') block and
the closed-form particular solutions of the constant and harmonic loads. When that is ill
conditioned (undamped resonance ``W_k`` = a natural frequency, a rigid-body mode under a
constant load, a defective block) the phase falls back to the matrix exponential of A, which
is exact in every case. Either way the phase is exact up to round-off: no time step.

Events are located by :func:`fricdamp.solvers.event_kernels.spectral_first_event` (eigen
tier) or by sampling the matrix-exponential solution (fallback tier), see
:mod:`fricdamp.solvers.event_phase`.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from fricdamp.solvers.event_kernels import spectral_energy, spectral_first_event
from fricdamp.solvers.event_phase import Hit, event_list, first_event
from fricdamp.solvers.event_switch import STICK

_EPS = np.finfo(float).eps
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_TINY = np.finfo(float).tiny


def expm_batch(A, dts):
    """``exp(A dt)`` for every dt in ``dts`` (n_t,), shape (n_t, N, N).

    Scaling and squaring with a degree-18 Taylor polynomial on ``||A dt|| 2^-s <= 1/2``
    (truncation below 1e-22), all time points at once (small N, many t).
    """
    dts = np.atleast_1d(np.asarray(dts, dtype=float))
    N = A.shape[0]
    nrm = float(np.abs(A).sum(axis=0).max()) * float(np.abs(dts).max(initial=0.0))
    s = max(0, int(np.ceil(np.log2(nrm / 0.5)))) if nrm > 0.5 else 0
    B = A[None] * (dts / 2.0**s)[:, None, None]
    eye = np.eye(N)
    E = np.broadcast_to(eye, B.shape).copy()
    for k in range(18, 0, -1):
        E = eye + (B @ E) / k
    for _ in range(s):
        E = E @ E
    return E


class LinearConfig:
    """Configuration-level data of an exact phase (cached per mode tuple)."""

    def __init__(self, lf, modes, mu_s, mu_d):
        n = lf.M.shape[0]
        nc = lf.tangent.shape[1]
        modes = np.asarray(modes, dtype=int)
        self.modes = modes
        S = modes == STICK
        s = np.where(S, 0, modes).astype(float)
        WT = lf.tangent
        WS = WT[:, S]
        if S.any():
            Uf, sv, _ = np.linalg.svd(WS, full_matrices=True)
            rank = int(np.sum(sv > 1e-12 * sv.max()))
            U, T = Uf[:, :rank], Uf[:, rank:]
        else:
            U, T = np.zeros((n, 0)), np.eye(n)
        self.T, self.U = T, U
        m, r = T.shape[1], U.shape[1]
        nf = lf.frequencies.size
        self.m, self.r, self.nf = m, r, nf
        N = 2 * m + 1 + 2 * nf + r
        self.N = N
        iz, izd, ik = slice(0, m), slice(m, 2 * m), 2 * m
        ic = 2 * m + 1 + 2 * np.arange(nf)
        isn = ic + 1
        ip = slice(2 * m + 1 + 2 * nf, N)
        self.ik, self.ic, self.isn, self.ip = ik, ic, isn, ip
        M, D, K = lf.M, lf.D, lf.K
        f_slip = -WT[:, ~S] @ (mu_d * lf.normal_load * s)[~S]
        f_const = lf.static_load + f_slip
        self.f_slip = f_slip

        # h + f_slip as a functional of X (n x N)
        Hf = np.zeros((n, N))
        Hf[:, iz] = -K @ T
        Hf[:, izd] = -D @ T
        Hf[:, ik] = f_const
        Hf[:, ic] = lf.cos_loads.T
        Hf[:, isn] = lf.sin_loads.T
        Hf[:, ip] = -K @ U
        # external load as a functional (input power)
        Fx = np.zeros((n, N))
        Fx[:, ik] = lf.static_load
        Fx[:, ic] = lf.cos_loads.T
        Fx[:, isn] = lf.sin_loads.T
        self.Fx = Fx

        A = np.zeros((N, N))
        if m:
            Mr = T.T @ M @ T
            Mr_fac = sla.cho_factor(Mr)
            zdd = sla.cho_solve(Mr_fac, T.T @ Hf)  # (m, N)
            A[iz, izd] = np.eye(m)
            A[izd, :] = zdd
        else:
            zdd = np.zeros((0, N))
        for k, w in enumerate(lf.frequencies):
            A[ic[k], isn[k]] = -w
            A[isn[k], ic[k]] = w
        self.A = A

        # output functionals
        Eq = np.zeros((n, N))
        Eq[:, iz] = T
        Eq[:, ip] = U
        Eqd = np.zeros((n, N))
        Eqd[:, izd] = T
        self.Eq, self.Eqd = Eq, Eqd
        lamT = np.zeros((nc, N))
        lamT[~S, ik] = -mu_d[~S] * lf.normal_load[~S] * s[~S]
        if S.any():
            lamS = np.linalg.pinv(WS) @ (M @ T @ zdd - Hf)
            lamT[S] = lamS
        self.ElamT = lamT
        self.Egam = WT.T @ Eqd
        self.lamN = np.array(lf.normal_load, dtype=float)
        self.D = np.ascontiguousarray(D, dtype=float)

        # event functionals
        rows = []
        frictionless = (np.asarray(mu_s) == 0) & (np.asarray(mu_d) == 0)
        for i in range(nc):
            if frictionless[i]:
                continue
            if S[i]:
                lim = np.zeros(N)
                lim[ik] = mu_s[i] * lf.normal_load[i]
                rows += [lim - lamT[i], lim + lamT[i]]
            else:
                rows.append(s[i] * self.Egam[i])
        self.Eev = np.array(rows).reshape(-1, N)
        self.Eev_d = self.Eev @ A
        self.kinds, self.contacts = event_list(modes, np.zeros(nc, dtype=bool), frictionless)

        # homogeneous + particular (eigen tier) when well conditioned
        self.eigen = False
        self.omega_max = float(np.max(lf.frequencies)) if nf else 0.0
        if m:
            As = A[:2 * m, :2 * m]
            lam, V = np.linalg.eig(As)
            self.omega_max = max(self.omega_max, float(np.abs(lam).max()))
            ok = np.isfinite(V).all() and np.linalg.cond(V) < 1e7
            Kr = T.T @ K @ T
            ok = ok and np.linalg.cond(Kr) < 1e10
            Zs = []
            if ok:
                for k, w in enumerate(lf.frequencies):
                    R = 1j * w * np.eye(2 * m) - As
                    if np.linalg.cond(R) > 1e8:
                        ok = False
                        break
                    # forcing of [z, z'] by the cos/sin states: B (a - i b) e^{iwt}
                    rhs = A[:2 * m, ic[k]] - 1j * A[:2 * m, isn[k]]
                    Zs.append(np.linalg.solve(R, rhs))
            if ok:
                self.eigen = True
                self.lam, self.V = lam, V
                self.Z = np.array(Zs).reshape(nf, 2 * m)
                # constant particular solution: z = Kr^-1 (T^T f_const - T^T K U p)
                Pc = np.zeros((2 * m, 1 + r))
                Pc[:m, 0] = np.linalg.solve(Kr, T.T @ f_const)
                if r:
                    Pc[:m, 1:] = np.linalg.solve(Kr, -(T.T @ K @ U))
                self.Pc = Pc
        else:
            self.eigen = True
            self.lam = np.zeros(0, dtype=complex)
            self.V = np.zeros((0, 0), dtype=complex)
            self.Z = np.zeros((nf, 0), dtype=complex)
            self.Pc = np.zeros((0, 1 + r))
        self.freqs = np.array(lf.frequencies, dtype=float)
        self.TT = np.ascontiguousarray(T.T)
        self.UT = np.ascontiguousarray(U.T)
        # [q, q'] -> the z, z', p entries of X
        S0 = np.zeros((N, 2 * n))
        S0[iz, :n] = T.T
        S0[izd, n:] = T.T
        S0[ip, :n] = U.T
        self.S0 = S0
        if self.eigen:
            self._spectral_templates()

    def _spectral_templates(self):
        """Per-configuration parts of the spectral form X = Re(Pbase diag(w) e^{mu dt}) + xc."""
        m, N, nf, r = self.m, self.N, self.nf, self.r
        self.mu = np.concatenate([self.lam, 1j * self.freqs]).astype(complex)
        n_mu = self.mu.size
        Pb = np.zeros((N, n_mu), dtype=complex)
        Pb[:2 * m, :2 * m] = self.V
        Pb[:2 * m, 2 * m:] = self.Z.T
        k = np.arange(nf)
        Pb[self.ic, 2 * m + k] = 1.0
        Pb[self.isn, 2 * m + k] = -1j
        self.Pbase = Pb
        Xc = np.zeros((N, 1 + r))  # xc = Xc @ [1, p]
        Xc[:2 * m] = self.Pc
        Xc[self.ik, 0] = 1.0
        Xc[self.ip, 1:] = np.eye(r)
        self.Xc = Xc
        self.Vinv = np.linalg.inv(self.V) if m else np.zeros((0, 0), dtype=complex)
        self.ZT = np.ascontiguousarray(self.Z.T)
        self.EevP = np.ascontiguousarray(self.Eev @ Pb)
        self.EevP_d = np.ascontiguousarray(self.EevP * self.mu[None, :])
        self.absEevP = np.abs(self.EevP)
        self.EevXc = self.Eev @ Xc
        self.absEgamP = np.abs(self.Egam @ Pb)
        self.EgamXc = self.Egam @ Xc
        w = float(np.abs(self.mu).max()) if n_mu else 0.0
        self.h = np.pi / (4 * w) if w > 0 else np.inf


class ExactPhase:
    """One phase of a LinearForm integrated exactly (see the module docstring).

    In the eigen tier the augmented state is kept in spectral form
    ``X(t) = Re(P exp(mu (t - t0))) + x_c`` with ``mu`` the eigenvalues of the (z, z') block
    and ``i W_k``; event functions are then sums of exponentials evaluated in O(N).
    """

    def __init__(self, cfg: LinearConfig, t0, q0, qd0):
        self.cfg = c = cfg
        self.t0 = t0 = float(t0)
        m = c.m
        X0 = c.S0 @ np.concatenate([q0, qd0])
        X0[c.ik] = 1.0
        wt = c.freqs * t0
        X0[c.ic] = np.cos(wt)
        X0[c.isn] = np.sin(wt)
        self.X0 = X0
        self.kinds, self.contacts = c.kinds, c.contacts
        self.n_expm = 0
        if c.eigen:
            kp = np.concatenate([[1.0], X0[c.ip]])
            e0 = np.exp(1j * wt)
            if m:
                c0 = c.Vinv @ (X0[:2 * m] - c.Pc @ kp - (c.ZT @ e0).real)
                w = np.concatenate([c0, e0])
            else:
                w = e0
            self.mu = c.mu
            self.P = c.Pbase * w
            self.xc = c.Xc @ kp
            self.alpha = c.EevP * w
            self.alpha_d = c.EevP_d * w
            self.gamma = c.EevXc @ kp
            self._aw, self._kp = np.abs(w), kp
            self._scale = c.absEevP @ self._aw + np.abs(self.gamma)
            self.h = c.h
        else:
            self._scale = np.abs(c.Eev) @ np.abs(X0)
            w = c.omega_max
            self.h = np.pi / (4 * w) if w > 0 else np.inf

    @property
    def vel_scale(self):
        """Magnitude scale of the slip velocities over the phase [m/s], (n_c,)."""
        c = self.cfg
        if c.eigen:
            return c.absEgamP @ self._aw + np.abs(c.EgamXc @ self._kp)
        return np.abs(c.Egam) @ np.abs(self.X0)

    def X(self, t):
        """Augmented state at times t (n_t,), shape (N, n_t)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        c = self.cfg
        dt = t - self.t0
        if c.eigen:
            return (self.P @ np.exp(np.multiply.outer(self.mu, dt))).real + self.xc[:, None]
        self.n_expm += t.size
        return (expm_batch(c.A, dt) @ self.X0).T

    # ------------------------------------------------------------------ events
    def _g(self, X):
        return self.cfg.Eev @ X, self.cfg.Eev_d @ X

    def _gi(self, i, t):
        if self.cfg.eigen:
            return float((self.alpha[i] @ np.exp(self.mu * (t - self.t0))).real + self.gamma[i])
        return float(self.cfg.Eev[i] @ self.X(np.array([t]))[:, 0])

    def _gdi(self, i, t):
        if self.cfg.eigen:
            return float((self.alpha_d[i] @ np.exp(self.mu * (t - self.t0))).real)
        return float(self.cfg.Eev_d[i] @ self.X(np.array([t]))[:, 0])

    def advance(self, t_end) -> Hit | None:
        """First event in (t0, t_end], or None."""
        c = self.cfg
        if c.Eev.shape[0] == 0 or t_end <= self.t0:
            return None
        h = min(self.h, t_end - self.t0)
        if c.eigen:
            kind, t, fired = spectral_first_event(
                self.alpha, self.alpha_d, self.gamma, self.mu, self.t0, h,
                float(t_end), self._tol(), True)
            if kind == 0:
                return None
            return Hit(float(t), np.flatnonzero(fired), immediate=kind == 2)
        n_chunk = 8
        t_a = self.t0
        first = True
        propagate = None
        if not c.eigen:
            propagate = expm_batch(c.A, h)[0]
            self.n_expm += 1
        x_prev = self.X0
        while t_a < t_end:
            n_pts = max(1, int(min(n_chunk, np.ceil((t_end - t_a) / h - 1e-9))))
            ts = t_a + h * np.arange(1, n_pts + 1)
            if ts[-1] >= t_end - 1e-9 * h:
                ts[-1] = t_end
            if propagate is not None:
                Xs = np.empty((c.N, n_pts))
                x = x_prev
                for j in range(n_pts):
                    if j < n_pts - 1 or ts[j] == t_a + h * (j + 1):
                        x = propagate @ x
                    else:
                        x = self.X(np.array([ts[j]]))[:, 0]
                    Xs[:, j] = x
            else:
                Xs = self.X(ts)
            tt = np.concatenate([[t_a], ts])
            XX = np.concatenate([x_prev[:, None], Xs], axis=1)
            g, gd = self._g(XX)
            if not c.eigen:
                self._scale = np.maximum(self._scale, (np.abs(c.Eev) @ np.abs(XX)).max(axis=1))
            found = first_event(tt, g, self._gi, self._tol(), first, gd, self._gdi)
            first = False
            if found is not None:
                return Hit(found[0], found[1], immediate=found[2])
            t_a = ts[-1]
            x_prev = Xs[:, -1]
            n_chunk = min(2 * n_chunk, 256)
        return None

    def _tol(self):
        """Round-off level of the event functions over the phase, (n_ev,)."""
        return 1e2 * _EPS * self._scale + _TINY

    # ------------------------------------------------------------------ outputs
    def outputs(self, t):
        """q, qd (n_t, n_dof); lam_N, lam_T (n_t, n_c) at times t."""
        X = self.X(t)
        c = self.cfg
        nt = X.shape[1]
        return ((c.Eq @ X).T, (c.Eqd @ X).T, np.repeat(c.lamN[None], nt, axis=0),
                (c.ElamT @ X).T)

    def energy(self, times):
        """Cumulative input, viscous and friction work [J] from ``times[0]``, (3, n_times)."""
        c = self.cfg
        return spectral_energy(self.P, self.xc, self.mu, self.t0, np.asarray(times, float),
                               self.h, _GL_X, _GL_W, c.Fx, c.Eqd, c.D, c.ElamT, c.Egam)

    def powers(self, t):
        """Input, viscous and friction power [W] at times t, each (n_t,)."""
        X = self.X(t)
        c = self.cfg
        qd = c.Eqd @ X
        p_in = np.einsum("it,it->t", c.Fx @ X, qd)
        p_visc = np.einsum("it,it->t", c.D @ qd, qd)
        p_fric = np.einsum("it,it->t", c.ElamT @ X, c.Egam @ X)
        return p_in, p_visc, p_fric


__all__ = ["ExactPhase", "LinearConfig", "expm_batch"]
