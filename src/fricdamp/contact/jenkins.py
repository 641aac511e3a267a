"""Jenkins element: a linear spring in series with a Coulomb slider (1D).

The tangential force is ``f = k_t (u - w)`` with slider position ``w`` (the state). The
return map predicts ``f_trial = k_t (u - w)``; if ``|f_trial| <= F_s`` the slider sticks,
otherwise it slides so that ``|f| = F_s`` and ``w = u - F_s sign(f_trial) / k_t``.
Consistent tangent: ``k_t`` in stick, 0 in slip.

Closed form (den Hartog / Iwan): for ``u = A cos(theta)`` and ``A > F_s / k_t`` the energy
dissipated per cycle is ``W = 4 F_s (A - F_s / k_t)`` (tests/validation/test_jenkins.py).
"""

from __future__ import annotations

import numpy as np

from fricdamp._numba_cache import njit
from fricdamp.contact.base import (
    ContactLaw,
    HarmonicResponse,
    LawStep,
    PeriodicResponse,
    broadcast_parameter,
    common_size,
)
from fricdamp.errors import ModelError


@njit(cache=True, nogil=True)
def jenkins_march_kernel(u, kt, fs, w0, f_out):  # pragma: no cover - compiled
    """March 1D Jenkins elements along u (n_t, n_c); write forces, return final w.

    kt, fs: (n_c,) stiffness and slip force; w0: (n_c,) initial slider positions.
    """
    nt, nc = u.shape
    w = w0.copy()
    for i in range(nt):
        for j in range(nc):
            f = kt[j] * (u[i, j] - w[j])
            if f > fs[j]:
                f = fs[j]
                w[j] = u[i, j] - fs[j] / kt[j]
            elif f < -fs[j]:
                f = -fs[j]
                w[j] = u[i, j] + fs[j] / kt[j]
            f_out[i, j] = f
    return w


@njit(cache=True, nogil=True)
def jenkins_periodic_kernel(u, kt, fs, w0, max_periods, f_out, anchor_out):  # pragma: no cover
    """March Jenkins elements over a periodic history until the slider state repeats.

    u: (n_t, n_c) one period of samples; kt, fs, w0: (n_c,). Writes the periodic forces
    into f_out (n_t, n_c) and into anchor_out (n_t, n_c) the sensitivity pattern of each
    sample: -1 if the sample slips (df = 0), -2 if the contact never slipped from w0
    (f = k_t (u - w0)), else the index s of the last slip sample, possibly from an earlier
    period (f = f_s + k_t (u - u_s) with f_s = +-F_s). Returns the periodic start state
    (n_c,) and the number of periods marched per contact (n_c,), negative if the state did
    not repeat within max_periods.
    """
    nt, nc = u.shape
    w_start = np.empty(nc)
    periods = np.empty(nc, dtype=np.int64)
    for j in range(nc):
        w = w0[j]
        last = -2
        k = kt[j]
        lim = fs[j]
        periods[j] = -max_periods
        for p in range(max_periods):
            w_begin = w
            for i in range(nt):
                f = k * (u[i, j] - w)
                if lim <= 0.0:
                    f = 0.0
                    w = u[i, j]
                    last = i
                    anchor_out[i, j] = -1
                elif f > lim:
                    f = lim
                    w = u[i, j] - lim / k
                    last = i
                    anchor_out[i, j] = -1
                elif f < -lim:
                    f = -lim
                    w = u[i, j] + lim / k
                    last = i
                    anchor_out[i, j] = -1
                else:
                    anchor_out[i, j] = last
                f_out[i, j] = f
            if w == w_begin:
                periods[j] = p + 1
                w_start[j] = w_begin
                break
        else:
            w_start[j] = w
    return w_start, periods


@njit(cache=True, nogil=True)
def jenkins_periodic_jacobian(anchor, kt, basis, jac):  # pragma: no cover - compiled
    """jac[i, c, :] = d f[i, c] / d x[c, :] from the anchors of jenkins_periodic_kernel."""
    nt, nc = anchor.shape
    m = basis.shape[1]
    for i in range(nt):
        for c in range(nc):
            s = anchor[i, c]
            if s == -1:
                for j in range(m):
                    jac[i, c, j] = 0.0
            elif s == -2:
                for j in range(m):
                    jac[i, c, j] = kt[c] * basis[i, j]
            else:
                for j in range(m):
                    jac[i, c, j] = kt[c] * (basis[i, j] - basis[s, j])


@njit(cache=True, nogil=True)
def jenkins_harmonic_kernel(U, kt, fs, w0, syn, synT, anaT, PS, PA, max_periods, jacobian,
                            F, Jb, u_t, f_t, w_out):  # pragma: no cover - compiled
    """The AFT step of Jenkins elements from coefficients, all contacts in one call: the
    arrays of :func:`jenkins_harmonic_step` shaped as below, its work arrays allocated."""
    nc, m = U.shape
    N = syn.shape[0]
    nb = Jb.shape[0]
    return jenkins_harmonic_step(U, kt, fs, w0, syn, synT, anaT, PS.reshape(N + 1, m * m),
                                 PA, max_periods, jacobian, F, Jb.reshape(nb, m * m if nb else 0),
                                 u_t, f_t, w_out, np.empty(N, np.int64), np.empty(N),
                                 np.empty(anaT.shape[1]))


@njit(cache=True, nogil=True)
def jenkins_harmonic_step(U, kt, fs, w0, syn, synT, anaT, PS, PA, max_periods, jacobian,
                          F, Jb, u_t, f_t, w_out, anchor, u, fc):  # pragma: no cover
    """The AFT step of Jenkins elements from coefficients, all contacts in one call.

    Allocation-free (the work arrays anchor (N,) int64, u (N,) and fc (mp,) are passed):
    loading its cached machine code then needs none of numba's array-allocation modules
    (``numba.np.arrayobj`` and the ~10 modules it imports, ~0.06 s of CPU in a fresh
    process). PS and Jb come as flat rows: (N+1, m*m) and (n_c, m*m) (or (0, 1)).

    U: (n_c, m) displacement coefficients; syn (N, m) the synthesis, synT its transpose
    and anaT (N, mp) the transposed analysis (C-contiguous; mp >= m, the columns from m on
    zero: :func:`_prefix_sums` pads them to a multiple of 4); PS (N+1, m*m), PA (N+1, m)
    prefix sums over the samples of ``ana[:, i] syn[i, :]`` and
    ``ana[:, i]``. Writes the samples u_t, f_t (n_c, N), the force coefficients F (n_c, m),
    the Jacobian blocks Jb (n_c, m*m) if ``jacobian`` and the periodic start states w_out.
    The march is that of :func:`jenkins_periodic_kernel`; the Jacobian is ``ana @ jac`` with
    the sample sensitivities of :func:`jenkins_periodic_jacobian`, summed over the runs of
    samples that share an anchor: ``k_t (PS[j] - PS[i] - (PA[j] - PA[i]) syn[s])`` for the
    run [i, j) stuck since sample s, ``k_t (PS[j] - PS[i])`` for a run that never slipped,
    0 in slip (O(m^2) per run instead of O(N m^2) per contact). Returns (largest period
    count, all converged).
    """
    nc, m = U.shape
    N = syn.shape[0]
    mp = anaT.shape[1]
    worst = 0
    conv = True
    for c in range(nc):
        # u = syn @ U[c], as sums over h in order, vectorised over the samples
        a = U[c, 0]
        for i in range(N):
            u[i] = synT[0, i] * a
        for h in range(1, m):
            a = U[c, h]
            for i in range(N):
                u[i] += synT[h, i] * a
        ut = u_t[c]
        for i in range(N):
            ut[i] = u[i]
        ft = f_t[c]
        w = w0[c]
        last = -2
        k = kt[c]
        lim = fs[c]
        got = -max_periods
        for p in range(max_periods):
            w_begin = w
            for i in range(N):
                ui = u[i]
                f = k * (ui - w)
                if lim <= 0.0:
                    f = 0.0
                    w = ui
                    last = i
                    anchor[i] = -1
                elif f > lim:
                    f = lim
                    w = ui - lim / k
                    last = i
                    anchor[i] = -1
                elif f < -lim:
                    f = -lim
                    w = ui + lim / k
                    last = i
                    anchor[i] = -1
                else:
                    anchor[i] = last
                ft[i] = f
            if w == w_begin:
                got = p + 1
                w_out[c] = w_begin
                break
        else:
            w_out[c] = w
        if got < 0:
            conv = False
        if abs(got) > worst:
            worst = abs(got)
        # F[c] = ana @ f, as sums over the samples in order, vectorised over h (anaT's
        # rows may be padded with zeros to whole SIMD vectors: no scalar remainder)
        for h in range(mp):
            fc[h] = 0.0
        for i in range(N):
            fi = ft[i]
            for h in range(mp):
                fc[h] += anaT[i, h] * fi
        for h in range(m):
            F[c, h] = fc[h]
        if not jacobian:
            continue
        # flat rows of the blocks: the compiler vectorises these loops
        Jc = Jb[c]
        for q in range(m * m):
            Jc[q] = 0.0
        i = 0
        while i < N:
            s = anchor[i]
            j = i + 1
            while j < N and anchor[j] == s:
                j += 1
            if s != -1:
                Pj = PS[j]
                Pi = PS[i]
                for q in range(m * m):
                    Jc[q] += k * (Pj[q] - Pi[q])
                if s >= 0:
                    row = syn[s]
                    for a in range(m):
                        pa = k * (PA[j, a] - PA[i, a])
                        for b in range(m):
                            Jc[a * m + b] -= pa * row[b]
            i = j
    return worst, conv


#: Prefix sums and transposes of the AFT projections per (synthesis, analysis) pair.
_PREFIX: list[tuple[np.ndarray, ...]] = []


def _prefix_sums(syn: np.ndarray, ana: np.ndarray) -> tuple[np.ndarray, ...]:
    """``PS[i] = sum_{i' < i} ana[:, i'] syn[i', :]`` (N+1, m, m), ``PA[i] = sum ana[:, i']``
    and the C-contiguous transposes of ``syn`` and ``ana`` (the latter's rows padded with
    zeros to a multiple of 4: (N, mp))."""
    for s, a, *out in _PREFIX:
        if s is syn and a is ana and not (s.flags.writeable or a.flags.writeable):
            return out                  # the same read-only arrays (a HarmonicBasis)
    for s, a, *out in _PREFIX:
        if s.shape == syn.shape and np.array_equal(s, syn) and np.array_equal(a, ana):
            return out
    N, m = syn.shape
    PS = np.zeros((N + 1, m, m))
    np.cumsum(ana.T[:, :, None] * syn[:, None, :], axis=0, out=PS[1:])
    PA = np.zeros((N + 1, m))
    np.cumsum(ana.T, axis=0, out=PA[1:])
    keep = (syn, ana) if not (syn.flags.writeable or ana.flags.writeable) else (
        syn.copy(), ana.copy())
    anaT = np.zeros((N, -(-m // 4) * 4))     # rows padded to whole SIMD vectors
    anaT[:, :m] = ana.T
    out = (PS, PA, np.ascontiguousarray(syn.T), anaT)
    _PREFIX.insert(0, (*keep, *out))
    del _PREFIX[4:]
    return out


class Jenkins(ContactLaw):
    """Spring ``stiffness`` [N/m] in series with a Coulomb slider of limit ``slip_force`` [N].

    Parameters
    ----------
    stiffness : float or array_like, shape (n_contacts,)
        Tangential contact stiffness k_t [N/m], > 0.
    slip_force : float or array_like, shape (n_contacts,)
        Slip limit F_s = mu N [N], >= 0 (0 gives a force-free contact).
    n_contacts : int, optional
        Number of contacts when both parameters are scalars (default 1).

    Examples
    --------
    >>> import numpy as np
    >>> law = Jenkins(stiffness=1000.0, slip_force=1.0)
    >>> f = law.drive(np.array([0.0, 0.0005, 0.002, 0.001]))
    >>> f.round(6).tolist()
    [0.0, 0.5, 1.0, 0.0]
    """

    n_dir = 1
    n_state = 1

    def __init__(self, stiffness, slip_force, *, n_contacts: int | None = None):
        kt = broadcast_parameter("stiffness", stiffness, n_contacts, unit="N/m")
        fs = broadcast_parameter("slip_force", slip_force, n_contacts, unit="N", allow_zero=True)
        n = common_size(stiffness=kt, slip_force=fs) if n_contacts is None else int(n_contacts)
        self.n_contacts = n
        self.stiffness = np.broadcast_to(kt, (n,)).copy()
        self.slip_force = np.broadcast_to(fs, (n,)).copy()

    @classmethod
    def from_friction(cls, stiffness, mu, normal_load, **kw) -> Jenkins:
        """Jenkins element with ``slip_force = mu * normal_load`` (mu >= 0, N >= 0 [N])."""
        mu_a = broadcast_parameter("mu", mu, None, unit="", allow_zero=True)
        n_a = broadcast_parameter("normal_load", normal_load, None, unit="N", allow_zero=True)
        return cls(stiffness, mu_a * n_a, **kw)

    def __repr__(self) -> str:
        return (f"Jenkins(n_contacts={self.n_contacts}, stiffness={self.stiffness.tolist()}, "
                f"slip_force={self.slip_force.tolist()})")

    def initial_state(self) -> np.ndarray:
        return np.zeros((self.n_contacts, 1))

    def step(self, state, u, v=None) -> LawStep:
        u = self._check_u(u)[:, 0]
        w = np.asarray(state, dtype=float)[:, 0]
        kt, fs = self.stiffness, self.slip_force
        f = kt * (u - w)
        slip = np.abs(f) > fs
        f = np.where(slip, np.sign(f) * fs, f)
        w_new = np.where(slip, u - f / kt, w)
        k = np.where(slip, 0.0, kt)
        return LawStep(f[:, None], k[:, None, None], None, w_new[:, None])

    def stored_energy(self, state, u) -> np.ndarray:
        u = self._check_u(u)[:, 0]
        w = np.asarray(state, dtype=float)[:, 0]
        return 0.5 * self.stiffness * (u - w) ** 2

    def dissipation(self, state_old, state_new, force_new) -> np.ndarray:
        """Friction work ``f (w_new - w_old)`` [J]: exact for the return map (f = +-F_s in slip)."""
        dw = np.asarray(state_new, float)[:, 0] - np.asarray(state_old, float)[:, 0]
        return np.asarray(force_new, float).reshape(self.n_contacts) * dw

    def march(self, u_history, state=None, v_history=None):
        u = np.ascontiguousarray(np.asarray(u_history, dtype=float)[:, :, 0])
        w0 = (self.initial_state() if state is None else np.asarray(state, float))[:, 0]
        f = np.empty_like(u)
        w = jenkins_march_kernel(u, self.stiffness, self.slip_force,
                                 np.ascontiguousarray(w0, dtype=float), f)
        return f[:, :, None], w[:, None]

    def periodic_response(self, u, v=None, *, basis=None, velocity_basis=None, state=None,
                          max_periods: int = 50, tol: float = 1e-10) -> PeriodicResponse:
        """Periodic Jenkins force with its exact sensitivity (compiled, all contacts at once).

        After the last slip sample s the element sticks, ``f_k = f_s + k_t (u_k - u_s)``
        with ``f_s = +-F_s`` independent of u, so ``df_k/dx = k_t (basis[k] - basis[s])``;
        in slip ``df_k = 0``; a contact that never slipped from its start state w0 has
        ``f_k = k_t (u_k - w0)``. The slider state of a Jenkins element repeats exactly
        (bit for bit) once it is periodic, which takes at most three periods, so ``tol`` is
        not needed. See :meth:`ContactLaw.periodic_response` for the parameters.
        """
        u3 = self._as_history(np.asarray(u, dtype=float), "u")
        uu = np.ascontiguousarray(u3[:, :, 0])
        w0 = (self.initial_state() if state is None else np.asarray(state, float))[:, 0]
        nt, nc = uu.shape
        f = np.empty((nt, nc))
        anchor = np.empty((nt, nc), dtype=np.int64)
        w, periods = jenkins_periodic_kernel(uu, self.stiffness, self.slip_force,
                                             np.ascontiguousarray(w0, dtype=float),
                                             max(int(max_periods), 1), f, anchor)
        jac = None
        if basis is not None:
            B = np.asarray(basis, dtype=float)
            if B.ndim != 2 or B.shape[0] != nt:
                raise ModelError(f"basis must have shape (n_t={nt}, n_basis), got {B.shape}")
            jac = np.empty((nt, nc, B.shape[1]))
            jenkins_periodic_jacobian(anchor, self.stiffness, np.ascontiguousarray(B), jac)
            jac = jac[:, :, None, None, :]
        return PeriodicResponse(f[:, :, None], jac, w[:, None], int(np.max(np.abs(periods))),
                                bool(np.all(periods > 0)))

    def harmonic_response(self, coeffs, synthesis, analysis, *, jacobian=True, state=None,
                          max_periods: int = 50) -> HarmonicResponse:
        """The AFT step in one compiled call (:func:`jenkins_harmonic_kernel`); equal to
        :meth:`periodic_response` projected by ``analysis`` to rounding. See
        :meth:`ContactLaw.harmonic_response`."""
        c = np.ascontiguousarray(coeffs, dtype=float)
        batch = c.shape[:-3]
        syn = np.ascontiguousarray(synthesis, dtype=float)
        ana = np.ascontiguousarray(analysis, dtype=float)
        N, m = syn.shape
        if c.ndim < 3 or c.shape[-3:] != (self.n_contacts, 1, m) or ana.shape != (m, N):
            raise ModelError(f"coeffs (..., {self.n_contacts}, 1, {m}) and analysis ({m}, {N}) "
                             f"must match synthesis {syn.shape}; got {c.shape}, {ana.shape}")
        copies = int(np.prod(batch)) if batch else 1
        nc = self.n_contacts * copies
        U = c.reshape(nc, m)
        kt, fs = self.stiffness, self.slip_force
        if copies > 1:
            kt, fs = np.tile(kt, copies), np.tile(fs, copies)
        w0 = (np.zeros(nc) if state is None else
              np.ascontiguousarray(np.broadcast_to(np.asarray(state, float)[..., 0],
                                                   batch + (self.n_contacts,)).reshape(nc)))
        PS, PA, synT, anaT = _prefix_sums(syn, ana)
        Jb = np.empty((nc, m, m) if jacobian else (0, 1, 1))
        F = np.empty((nc, m))
        u_t = np.empty((nc, N))
        f_t = np.empty((nc, N))
        w = np.empty(nc)
        periods, conv = jenkins_harmonic_kernel(U, kt, fs, w0, syn, synT, anaT, PS, PA,
                                                max(int(max_periods), 1), bool(jacobian), F,
                                                Jb, u_t, f_t, w)
        shape = batch + (self.n_contacts,)
        return HarmonicResponse(F.reshape(shape + (1, m)),
                                Jb.reshape(shape + (m, m)) if jacobian else None,
                                u_t.T.reshape((N,) + shape + (1,)),
                                f_t.T.reshape((N,) + shape + (1,)), w.reshape(shape + (1,)),
                                int(periods), bool(conv))
