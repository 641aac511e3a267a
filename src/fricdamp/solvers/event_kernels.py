"""Compiled event location for exact phases: event functions that are sums of exponentials.

In an exact phase every event function reads ``g_i(t) = Re(sum_j alpha_ij exp(mu_j dt)) +
gamma_i`` with ``dt = t - t0`` (see :class:`fricdamp.solvers.event_phase.ExactPhase`), and its
derivative has coefficients ``alpha_ij mu_j``. :func:`spectral_first_event` samples all of
them on a grid of step h, finds the earliest change from positive to non-positive (or a
grazing dip between samples, located from the derivative) and refines it with Brent's method
(a port of SciPy's ``brentq``) to round-off, returning the right end of the final bracket.
"""

from __future__ import annotations

import numpy as np

from fricdamp._numba_cache import njit

_EPS = np.finfo(np.float64).eps


@njit(cache=True)
def _sval(a, g0, mu, dt):
    s = g0
    for j in range(mu.size):
        e = np.exp(mu[j] * dt)
        s += a[j].real * e.real - a[j].imag * e.imag
    return s


@njit(cache=True)
def _brent(a, g0, mu, t0, xa, xb, xtol):
    """Bracket end with g <= 0 of the root of g in [xa, xb], g(xa) > 0 >= g(xb)."""
    rtol = 4.0 * _EPS
    xpre, xcur = xa, xb
    fpre = _sval(a, g0, mu, xpre - t0)
    fcur = _sval(a, g0, mu, xcur - t0)
    if fcur == 0.0:
        return xcur
    xblk, fblk, spre, scur = xpre, fpre, 0.0, 0.0
    for _ in range(200):
        if fpre != 0.0 and fcur != 0.0 and ((fpre < 0.0) != (fcur < 0.0)):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (xtol + rtol * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            break
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre, scur = sbis, sbis
        else:
            spre, scur = sbis, sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = _sval(a, g0, mu, xcur - t0)
    # the bracket [xcur, xblk] has a sign change: return its end where g <= 0 (the right one)
    if fcur <= 0.0:
        return xcur
    return xblk


@njit(cache=True)
def _root_in(a, g0, mu, t0, ta, tb, scale):
    xtol = 4.0 * _EPS * max(abs(ta), abs(tb), scale)
    if tb - ta <= xtol:
        return tb
    return _brent(a, g0, mu, t0, ta, tb, xtol)


@njit(cache=True)
def spectral_first_event(alpha, alpha_d, gamma, mu, t0, h, t_end, tol, first):
    """First event of sum-of-exponential event functions in (t0, t_end].

    Same rules as :func:`fricdamp.solvers.event_phase.first_event`: function i fires when
    it falls below ``-tol[i]``; roots within round-off of the earliest are one event.

    Parameters
    ----------
    alpha, alpha_d : complex ndarray, shape (n_ev, n_mu)
        Coefficients of the functions and of their derivatives.
    gamma : ndarray, shape (n_ev,)
        Constant parts.
    mu : complex ndarray, shape (n_mu,)
        Exponents [1/s].
    t0, h, t_end : float
        Phase start, sampling step and end [s].
    tol : ndarray, shape (n_ev,)
        Round-off level of each function.
    first : bool
        A function already below ``-tol`` at t0 fires immediately.

    Returns
    -------
    kind : int
        0 no event, 1 event, 2 immediate event at t0.
    t : float
        Event time (right end of the final bracket of the latest grouped root).
    fired : bool ndarray, shape (n_ev,)
    """
    n_ev = alpha.shape[0]
    fired = np.zeros(n_ev, np.bool_)
    zero = 0.0
    gs = gamma + tol  # shifted: fires when <= 0
    g_a = np.empty(n_ev)
    gd_a = np.empty(n_ev)
    g_b = np.empty(n_ev)
    gd_b = np.empty(n_ev)
    roots = np.empty(n_ev)
    for i in range(n_ev):
        g_a[i] = _sval(alpha[i], gs[i], mu, 0.0)
        gd_a[i] = _sval(alpha_d[i], zero, mu, 0.0)
        if first and g_a[i] <= 0.0:
            fired[i] = True
    if fired.any():
        return 2, t0, fired
    t_a = t0
    j = 0
    while t_a < t_end:
        t_b = t0 + (j + 1) * h
        if t_b >= t_end - 1e-9 * h:
            t_b = t_end
        any_root = False
        for i in range(n_ev):
            g_b[i] = _sval(alpha[i], gs[i], mu, t_b - t0)
            gd_b[i] = _sval(alpha_d[i], zero, mu, t_b - t0)
            roots[i] = np.inf
            if g_a[i] > 0.0 and g_b[i] <= 0.0:
                roots[i] = _root_in(alpha[i], gs[i], mu, t0, t_a, t_b, t_b - t_a)
                any_root = True
            elif g_a[i] > 0.0 and gd_a[i] < 0.0 and gd_b[i] > 0.0:
                # grazing dip: minimum where the derivative changes sign
                tm = _root_neg_to_pos(alpha_d[i], mu, t0, t_a, t_b)
                if _sval(alpha[i], gs[i], mu, tm - t0) <= 0.0:
                    roots[i] = _root_in(alpha[i], gs[i], mu, t0, t_a, tm, t_b - t_a)
                    any_root = True
        if any_root:
            best = roots.min()
            lim = best + 1e3 * _EPS * max(abs(best), t_b - t_a)
            t_ev = best
            for i in range(n_ev):
                if roots[i] <= lim:
                    fired[i] = True
                    t_ev = max(t_ev, roots[i])
            return 1, t_ev, fired
        t_a = t_b
        g_a[:] = g_b
        gd_a[:] = gd_b
        j += 1
    return 0, t_end, fired


@njit(cache=True)
def _root_neg_to_pos(ad, mu, t0, ta, tb):
    """Root of the derivative (negative at ta, positive at tb) by bisection to round-off."""
    lo, hi = ta, tb
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _sval(ad, 0.0, mu, mid - t0) < 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def _matvec(A, x, out):
    for i in range(A.shape[0]):
        acc = 0.0
        for j in range(A.shape[1]):
            acc += A[i, j] * x[j]
        out[i] = acc


@njit(cache=True)
def spectral_energy(P, xc, mu, t0, times, h, gx, gw, Fx, Eqd, D, ElamT, Egam):
    """Input, viscous and friction work from ``times[0]`` to each of ``times`` (exact phase).

    ``X(t) = Re(P exp(mu (t - t0))) + xc``; powers ``Fx X . Eqd X``, ``(Eqd X)^T D (Eqd X)``,
    ``ElamT X . Egam X``, integrated by the Gauss-Legendre rule (nodes ``gx``, weights ``gw``
    on [-1, 1]) on sub-intervals no longer than ``h``.

    Returns
    -------
    ndarray, shape (3, n_times)
        Cumulative input work, viscous dissipation and friction work (<= 0) [J].
    """
    n_t = times.size
    out = np.zeros((3, n_t))
    N = xc.size
    n = Eqd.shape[0]
    nc = ElamT.shape[0]
    n_mu = mu.size
    X = np.empty(N)
    qd = np.empty(n)
    f = np.empty(n)
    dq = np.empty(n)
    lam = np.empty(nc)
    gam = np.empty(nc)
    acc0 = 0.0
    acc1 = 0.0
    acc2 = 0.0
    for k in range(n_t - 1):
        a, b = times[k], times[k + 1]
        if b > a:
            nsub = 1
            if np.isfinite(h) and h > 0:
                nsub = max(1, int(np.ceil((b - a) / h)))
            d = (b - a) / nsub
            for s in range(nsub):
                lo = a + s * d
                for g in range(gx.size):
                    dt = lo + 0.5 * d * (gx[g] + 1.0) - t0
                    for r in range(N):
                        X[r] = xc[r]
                    for j in range(n_mu):
                        e = np.exp(mu[j] * dt)
                        er, ei = e.real, e.imag
                        for r in range(N):
                            X[r] += P[r, j].real * er - P[r, j].imag * ei
                    _matvec(Eqd, X, qd)
                    _matvec(Fx, X, f)
                    _matvec(D, qd, dq)
                    _matvec(ElamT, X, lam)
                    _matvec(Egam, X, gam)
                    p_in = 0.0
                    p_visc = 0.0
                    for i in range(n):
                        p_in += f[i] * qd[i]
                        p_visc += dq[i] * qd[i]
                    p_fric = 0.0
                    for i in range(nc):
                        p_fric += lam[i] * gam[i]
                    w = 0.5 * d * gw[g]
                    acc0 += w * p_in
                    acc1 += w * p_visc
                    acc2 += w * p_fric
        out[0, k + 1] = acc0
        out[1, k + 1] = acc1
        out[2, k + 1] = acc2
    return out


@njit(cache=True)
def small_lu_solve(A, B):
    """Solve ``A X = B`` for a small dense A by LU with partial pivoting (A, B unchanged).

    Returns ``(X, ratio)`` with ``ratio = min |u_ii| / max |u_ii|`` of the U factor, the
    caller's test for (numerically) redundant constraints; X is undefined when ratio is 0.
    The configuration solves of the event solver are 1-10 unknowns; this avoids the
    per-call overhead of the LAPACK wrappers, which dominates at that size.
    """
    n = A.shape[0]
    LU = A.copy()
    X = B.copy()
    for k in range(n):
        p = k
        big = abs(LU[k, k])
        for i in range(k + 1, n):
            if abs(LU[i, k]) > big:
                big = abs(LU[i, k])
                p = i
        if p != k:
            for j in range(n):
                LU[k, j], LU[p, j] = LU[p, j], LU[k, j]
            for j in range(X.shape[1]):
                X[k, j], X[p, j] = X[p, j], X[k, j]
        if LU[k, k] == 0.0:
            continue
        for i in range(k + 1, n):
            f = LU[i, k] / LU[k, k]
            LU[i, k] = f
            for j in range(k + 1, n):
                LU[i, j] -= f * LU[k, j]
            for j in range(X.shape[1]):
                X[i, j] -= f * X[k, j]
    umin, umax = np.inf, 0.0
    for k in range(n):
        u = abs(LU[k, k])
        umin = min(umin, u)
        umax = max(umax, u)
    if umin == 0.0:
        return X, 0.0
    for k in range(n - 1, -1, -1):
        for j in range(X.shape[1]):
            s = X[k, j]
            for i in range(k + 1, n):
                s -= LU[k, i] * X[i, j]
            X[k, j] = s / LU[k, k]
    return X, umin / umax


@njit(cache=True)
def lemke_kernel(A, q, max_iter):
    """:func:`fricdamp.solvers.event_switch.lemke` compiled (same tableau, covering vector,
    lexicographic ratio test and tolerances). Returns ``(z, status)``: 0 solved, 1 ended on
    a ray, 2 iteration limit."""
    n = q.size
    z = np.zeros(n)
    if n == 0:
        return z, 0
    allpos = True
    for i in range(n):
        if not q[i] >= 0:
            allpos = False
    if allpos:
        return z, 0
    nc = 2 * n + 2
    T = np.zeros((n, nc))
    amax = 0.0
    for i in range(n):
        T[i, i] = 1.0
        for j in range(n):
            T[i, n + j] = -A[i, j]
            amax = max(amax, abs(A[i, j]))
        T[i, 2 * n] = -1.0
        T[i, nc - 1] = q[i]
    basis = np.arange(n)
    tol = 1e-13 * max(1.0, amax)
    col = np.empty(n)
    r = 0
    for i in range(1, n):
        if q[i] < q[r]:
            r = i

    def _pivot(T, r, e, col):
        piv = T[r, e]
        for j in range(T.shape[1]):
            T[r, j] /= piv
        for i in range(T.shape[0]):
            col[i] = T[i, e]
        col[r] = 0.0
        for i in range(T.shape[0]):
            if col[i] != 0.0:
                for j in range(T.shape[1]):
                    T[i, j] -= col[i] * T[r, j]

    _pivot(T, r, 2 * n, col)
    leaving = basis[r]
    basis[r] = 2 * n
    cand = np.empty(n, dtype=np.int64)
    keys = np.empty((n, n + 1))
    for _ in range(max_iter):
        entering = leaving + n if leaving < n else leaving - n
        nr = 0
        for i in range(n):
            if T[i, entering] > tol:
                cand[nr] = i
                for j in range(n + 1):
                    src = nc - 1 if j == 0 else j - 1
                    keys[nr, j] = T[i, src] / T[i, entering]
                nr += 1
        if nr == 0:
            return z, 1
        for j in range(n + 1):
            best = np.inf
            for a in range(nr):
                best = min(best, keys[a, j])
            lim = best + 1e-12 * max(1.0, abs(best))
            m = 0
            for a in range(nr):
                if keys[a, j] <= lim:
                    cand[m] = cand[a]
                    for jj in range(n + 1):
                        keys[m, jj] = keys[a, jj]
                    m += 1
            nr = m
            if nr == 1:
                break
            if j == 0:
                has = False
                for a in range(nr):
                    if basis[cand[a]] == 2 * n:
                        has = True
                if has:
                    m = 0
                    for a in range(nr):
                        if basis[cand[a]] == 2 * n:
                            cand[m] = cand[a]
                            m += 1
                    nr = m
                    break
        r = cand[0]
        _pivot(T, r, entering, col)
        leaving = basis[r]
        basis[r] = entering
        if leaving == 2 * n:
            for i in range(n):
                if basis[i] >= n and basis[i] < 2 * n:
                    z[basis[i] - n] = max(T[i, nc - 1], 0.0)
            return z, 0
    return z, 2
