"""Compiled linearisation of blade-damper phases for shooting (monodromy matrices).

Shooting's Newton iteration needs, for every phase of a traced flow, the transition matrix of
the variational equation ``Phi' = J(t) Phi`` along the phase's DOP853 dense output, and the
Jacobian of the projection at its start (:class:`fricdamp.solvers.shooting._Linearizer`).
Through Python each Magnus step costs two dense-output evaluations, two central-difference
Jacobians (28 right-hand sides each), the state scaling and ``scipy.linalg.expm``: about
half of a Newton iteration on the blade damper and most of a light-damper design's time.

The kernels below (generated into the same module as ``phase_run``, source :data:`VAR_SRC`)
do the same arithmetic in one call per phase:

* ``transition``: the fourth-order Magnus integrator of ``_Linearizer.transition`` -- on each
  half of each DOP853 step of the phase, ``Omega = h/2 (J1 + J2) + sqrt(3)/12 h^2 [J2, J1]``
  with J at the two Gauss points, and ``exp(Omega)``; the product over whole steps
  (``coarse``) for the error estimate;
* ``expm_pade13``: the matrix exponential by the [13/13] Pade approximant with scaling and
  squaring. The number of squarings s comes from the norms of A's powers,
  ``min(max(d6, d8), max(d8, d10)) <= theta_13 = 5.37`` with ``d_k = ||A^k||_1^(1/k)``
  (Al-Mohy & Higham, SIAM J. Matrix Anal. Appl. 31 (2009) 970-989; the powers are formed
  exactly, not estimated), plus the squarings their backward-error bound asks for from
  ``||(|A| / 2^s)^27||_1`` with the approximant's leading error coefficient
  ``(13!)^2 / (26! 27!)``. Scaling by ``||A||_1`` alone (Higham 2005) over-squares a Magnus
  step's matrix: ``h [[0, I], [-K, -C]]`` with the damper's rocking at 784 Hz has
  ``||A||_1 ~ 1e4`` but a spectral radius below 1, and the needless squarings lost 2e-9
  of ``||exp(A)||`` (measured against a 40-digit reference); with the powers' norms the
  error is round-off (tests/unit/test_blade_damper_variational.py), as SciPy's ``expm``;
* ``projection_jacobian``: the central-difference Jacobian of the projection (``project``)
  with the step sizes of ``_Linearizer._steps``.

A singular constraint solve anywhere (pivot ratio <= 1e-13) returns its ratio and the caller
takes the Python path, whose minimum-norm multipliers handle redundant constraints.
"""

from __future__ import annotations

VAR_SRC = '''

from fricdamp.solvers.event_kernels import small_lu_solve

_PADE13 = np.array([64764752532480000.0, 32382376266240000.0, 7771770303897600.0,
                    1187353796428800.0, 129060195264000.0, 10559470521600.0, 670442572800.0,
                    33522128640.0, 1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0, 1.0])
_THETA13 = 5.371920351148152
# leading error coefficient of the [13/13] Pade approximant of exp: (13!)^2 / (26! 27!)
_PADE13_ERR = 8.829961602018678e-36


@njit(cache=True)
def _mm(A, B, C):
    """C = A B (square, same size)."""
    n = A.shape[0]
    for i in range(n):
        for j in range(n):
            C[i, j] = 0.0
        for k in range(n):
            a = A[i, k]
            if a != 0.0:
                for j in range(n):
                    C[i, j] += a * B[k, j]


@njit(cache=True)
def _norm1(A):
    n = A.shape[0]
    nrm = 0.0
    for j in range(n):
        s = 0.0
        for i in range(n):
            s += abs(A[i, j])
        nrm = max(nrm, s)
    return nrm


@njit(cache=True)
def expm_pade13(A, E):
    """E = exp(A) by the [13/13] Pade approximant with scaling and squaring; the number of
    squarings from the norms of the powers of A (Al-Mohy & Higham 2009)."""
    n = A.shape[0]
    b = _PADE13
    A2 = np.empty((n, n))
    A4 = np.empty((n, n))
    A6 = np.empty((n, n))
    T = np.empty((n, n))
    _mm(A, A, A2)
    _mm(A2, A2, A4)
    _mm(A4, A2, A6)
    _mm(A4, A4, T)
    d8 = _norm1(T) ** 0.125
    _mm(A4, A6, T)
    d10 = _norm1(T) ** 0.1
    d6 = _norm1(A6) ** (1.0 / 6.0)
    eta = min(max(d6, d8), max(d8, d10))
    sq = 0
    if eta > _THETA13:
        sq = int(np.ceil(np.log2(eta / _THETA13)))
    # more squarings where |A|^27 says the Pade approximant's backward error bound would
    # exceed the unit round-off (the "ell" correction of Al-Mohy & Higham, exact norms)
    nrm = _norm1(A) * 0.5 ** sq
    if nrm > 0.0:
        w = np.ones(n)
        v = np.empty(n)
        f = 0.5 ** sq
        for _ in range(27):
            for j in range(n):
                acc = 0.0
                for i in range(n):
                    acc += w[i] * abs(A[i, j]) * f
                v[j] = acc
            for j in range(n):
                w[j] = v[j]
        alpha = _PADE13_ERR * np.max(w) / nrm
        if alpha > 2.0 ** -53:
            sq += max(0, int(np.ceil(np.log2(alpha / 2.0 ** -53) / 26.0)))
    f = 0.5 ** sq
    X = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            X[i, j] = A[i, j] * f
            A2[i, j] *= f * f
            A4[i, j] *= f ** 4
            A6[i, j] *= f ** 6
    W = np.empty((n, n))
    U = np.empty((n, n))
    V = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            W[i, j] = b[13] * A6[i, j] + b[11] * A4[i, j] + b[9] * A2[i, j]
    _mm(A6, W, T)
    for i in range(n):
        for j in range(n):
            T[i, j] += b[7] * A6[i, j] + b[5] * A4[i, j] + b[3] * A2[i, j]
        T[i, i] += b[1]
    _mm(X, T, U)
    for i in range(n):
        for j in range(n):
            W[i, j] = b[12] * A6[i, j] + b[10] * A4[i, j] + b[8] * A2[i, j]
    _mm(A6, W, V)
    for i in range(n):
        for j in range(n):
            V[i, j] += b[6] * A6[i, j] + b[4] * A4[i, j] + b[2] * A2[i, j]
        V[i, i] += b[0]
    # (V - U) E = (V + U) by the event solver's small LU (partial pivoting)
    X, _ = small_lu_solve(V - U, V + U)
    for i in range(n):
        for j in range(n):
            E[i, j] = X[i, j]
    for _ in range(sq):
        _mm(E, E, T)
        for i in range(n):
            for j in range(n):
                E[i, j] = T[i, j]


@njit(cache=True)
def _state_at(TA, TB, YOLD, FF, m, t0, y0, t, out):
    """The phase's state at t from its stored steps (as ``NumericalPhase.y``)."""
    if m == 0 or t <= t0:
        for k in range(_NY):
            out[k] = y0[k]
        return
    lo = 0
    hi = m
    while lo < hi:
        mid = (lo + hi) // 2
        if TA[mid] <= t:
            lo = mid + 1
        else:
            hi = mid
    j = min(max(lo - 1, 0), m - 1)
    dense_eval(TA[j], TB[j] - TA[j], YOLD[j], FF[j], t, out)


@njit(cache=True)
def _fd_steps(y, steps):
    """Central-difference steps of ``_Linearizer._steps``: 6e-6 of the largest |q| for the
    positions and of the largest |q'| for the velocities."""
    sq = 1e-300
    sv = 1e-300
    for k in range(7):
        sq = max(sq, abs(y[k]))
        sv = max(sv, abs(y[7 + k]))
    for k in range(7):
        steps[k] = 6e-6 * sq
        steps[7 + k] = 6e-6 * sv


@njit(cache=True)
def _magnus(a, b, TA, TB, YOLD, FF, m, t0, y0, modes, sigma, par, E):
    """exp(Omega) of the fourth-order Magnus step over [a, b] into E; smallest pivot ratio."""
    h = b - a
    c = 0.5 * h / np.sqrt(3.0)
    mid = 0.5 * (a + b)
    ybuf = np.empty(_NY)
    y = np.empty(14)
    steps = np.empty(14)
    J1 = np.empty((14, 14))
    J2 = np.empty((14, 14))
    worst = 1.0
    for g in range(2):
        tg = mid - c if g == 0 else mid + c
        _state_at(TA, TB, YOLD, FF, m, t0, y0, tg, ybuf)
        for k in range(14):
            y[k] = ybuf[k]
        _fd_steps(y, steps)
        if g == 0:
            worst = min(worst, jacobian(tg, y, modes, sigma, par, steps, J1))
        else:
            worst = min(worst, jacobian(tg, y, modes, sigma, par, steps, J2))
    if worst <= 1e-13:
        return worst
    P12 = np.empty((14, 14))
    P21 = np.empty((14, 14))
    _mm(J2, J1, P21)
    _mm(J1, J2, P12)
    Om = np.empty((14, 14))
    w2 = (np.sqrt(3.0) / 12.0) * h * h
    for i in range(14):
        for j in range(14):
            Om[i, j] = 0.5 * h * (J1[i, j] + J2[i, j]) + w2 * (P21[i, j] - P12[i, j])
    expm_pade13(Om, E)
    return worst


@njit(cache=True)
def transition(TA, TB, YOLD, FF, m, t0, y0, t_start, t_end, modes, sigma, par, Phi, coarse):
    """Transition matrix (14, 14) of a DOP853 phase from t_start to t_end by Magnus steps on
    the halves of its stored steps (``Phi``) and on whole steps (``coarse``); smallest pivot
    ratio (<= 1e-13: singular, outputs undefined)."""
    nb = 2
    for j in range(m):
        if t_start < TA[j] < t_end:
            nb += 1
        if t_start < TB[j] < t_end:
            nb += 1
    bounds = np.empty(nb)
    bounds[0] = t_start
    bounds[1] = t_end
    nb = 2
    for j in range(m):
        if t_start < TA[j] < t_end:
            bounds[nb] = TA[j]
            nb += 1
        if t_start < TB[j] < t_end:
            bounds[nb] = TB[j]
            nb += 1
    bounds = np.unique(bounds)
    for i in range(14):
        for j in range(14):
            Phi[i, j] = 1.0 if i == j else 0.0
            coarse[i, j] = 1.0 if i == j else 0.0
    E1 = np.empty((14, 14))
    E2 = np.empty((14, 14))
    T1 = np.empty((14, 14))
    T2 = np.empty((14, 14))
    worst = 1.0
    for s in range(bounds.size - 1):
        a = bounds[s]
        b = bounds[s + 1]
        if not b > a:
            continue
        mid = 0.5 * (a + b)
        worst = min(worst, _magnus(a, mid, TA, TB, YOLD, FF, m, t0, y0, modes, sigma, par, E1))
        worst = min(worst, _magnus(mid, b, TA, TB, YOLD, FF, m, t0, y0, modes, sigma, par, E2))
        if worst <= 1e-13:
            return worst
        _mm(E2, E1, T1)
        _mm(T1, Phi, T2)
        for i in range(14):
            for j in range(14):
                Phi[i, j] = T2[i, j]
        worst = min(worst, _magnus(a, b, TA, TB, YOLD, FF, m, t0, y0, modes, sigma, par, E1))
        if worst <= 1e-13:
            return worst
        _mm(E1, coarse, T2)
        for i in range(14):
            for j in range(14):
                coarse[i, j] = T2[i, j]
    return worst


@njit(cache=True)
def projection_jacobian(y, modes, par, P):
    """Central-difference Jacobian (14, 14) of ``project`` (both normals closed, the stuck
    contacts of ``modes``) at y = [q, q']; smallest pivot ratio."""
    steps = np.empty(14)
    _fd_steps(y, steps)
    yy = np.empty(14)
    q = np.empty(7)
    qd = np.empty(7)
    qp = np.empty(7)
    qdp = np.empty(7)
    qm = np.empty(7)
    qdm = np.empty(7)
    worst = 1.0
    for j in range(14):
        for sgn in range(2):
            for k in range(14):
                yy[k] = y[k]
            yy[j] = y[j] + steps[j] if sgn == 0 else y[j] - steps[j]
            for k in range(7):
                q[k] = yy[k]
                qd[k] = yy[7 + k]
            if sgn == 0:
                r, _ = project(q, qd, modes, par, qp, qdp)
            else:
                r, _ = project(q, qd, modes, par, qm, qdm)
            worst = min(worst, r)
            if worst <= 1e-13:
                return worst
        for k in range(7):
            P[k, j] = (qp[k] - qm[k]) / (2.0 * steps[j])
            P[7 + k, j] = (qdp[k] - qdm[k]) / (2.0 * steps[j])
    return worst
'''
