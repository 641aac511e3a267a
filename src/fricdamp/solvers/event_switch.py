"""Equations of motion of one stick/slip configuration and the switching decision.

Configuration solve (000 (37)-(40), re-derived)
-----------------------------------------------
With the contacts split into constrained normals C, stuck contacts S, slipping contacts L
(direction ``s_i = +-1``) and "given" contacts G (tangential force prescribed, used to build
the switching problem), the accelerations and multipliers satisfy

    M q'' = h + W_N,C lambda_N,C + W_T,S lambda_T,S + sum_{i in L} W_T,i lambda_T,i
            + W_T,G lambda_T,G
    W_N,C^T q'' + wbar_N,C = 0,      W_T,S^T q'' + wbar_T,S = 0
    lambda_T,i = -mu_sliding,i |lambda_N,i| s_i                    (i in L)

For a slipping contact with a constrained normal, ``|lambda_N,i| = sigma_i lambda_N,i`` with
the tracked sign ``sigma_i`` makes the friction force linear in the unknown normal force, so
its column in the force matrix is ``W_N,i - mu_sliding,i sigma_i s_i W_T,i`` (the paper's
``W + W_S`` of 000 (37)). Eliminating q'' gives the small (n_C + n_S) system 000 (39)
(``(C M^-1 B) x = -(wbar + C M^-1 f)``) and q'' from 000 (40). The extracted text of (39)
lacks the signs of the ``w_0`` terms; they follow from differentiating the constraints twice
(000 (32)) and are checked by tests/unit/test_event_solver.py (a bead on a ring, whose normal
force is m v^2 / R).

Switching decision (000 (41)-(46) generalised to simultaneous switches)
-----------------------------------------------------------------------
At an event the contacts with zero slip velocity (the candidates) must each be given a mode
such that the configuration is consistent:

* stick: ``a_i = 0`` and ``|lambda_T,i| <= mu_static,i |lambda_N,i|`` (000 (42));
* slip ``s_i``: ``lambda_T,i = -mu_sliding,i |lambda_N,i| s_i`` and ``s_i a_i >= 0`` (the
  relative acceleration ``a_i = gamma_T,i'`` points into the slip direction, 000 (43)-(44)).

With the other contacts fixed, ``a = G lambda + b`` and ``|lambda_N| = H lambda + c`` are affine
in the candidates' tangential forces. With the reserves ``r+ = m|lambda_N| + lambda`` and
``r- = m|lambda_N| - lambda`` (``m = mu_static``), and ``a = a+ - a-``, the conditions are the
linear complementarity problem (Glocker & Pfeiffer's friction LCP)

    w = [a+, r-] = A [r+, a-] + q >= 0,  [r+, a-] >= 0,  w . [r+, a-] = 0
    A = [[G E, I], [(m H - I) E, 0]],  E = (I + m H)^-1,
    q = [b - G E m c, m c - (m H - I) E m c],

solved by Lemke's complementary pivoting (lexicographic ratio test). For fixed normal
loads (H = 0) and a positive definite Delassus matrix G, A is positive semi-definite, so
Lemke's method terminates with the (unique) solution. When ``mu_sliding < mu_static`` the
contacts found at the static limit start slipping with the smaller sliding force; the
problem is then solved again with their bound lowered to the sliding force (a breakaway
cascade: a contact that breaks away may let another one stick), until no further contact
breaks away; the result is consistent by construction when the normal forces do not depend
on the friction forces, and is verified. If the verification fails (strongly coupled normal
forces), the candidates' modes are enumerated (at most 6 contacts, 3^6 trials), preferring
the configuration with most contacts stuck; otherwise ConvergenceError.

With ``mu_static > mu_sliding`` several configurations can be consistent (the normal forces
of the blade damper depend on the friction forces). Then the consistent configurations of 2
to 4 candidates are enumerated and scored by (contacts stuck, contacts stuck before the event
that stay stuck): 000 (41)-(46) switch one contact at a time, a stuck contact only when its
own friction saturation reaches zero, so a neighbour that holds with a positive saturation
is not made to break away by a contact whose slip velocity vanished (``_select``). Only a
tie of both keys (a symmetric system) is left to the breakaway cascade, with a warning.
"""

from __future__ import annotations

import itertools
import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from fricdamp.errors import ConvergenceError, ModelError
from fricdamp.solvers.event_kernels import lemke_kernel, small_lu_solve

log = logging.getLogger(__name__)

STICK, SLIP_POS, SLIP_NEG = 0, 1, -1
GIVEN = 2  # internal: tangential force prescribed (building the switching problem)
OPEN = 3  # a unilateral contact that has lifted off: no normal or tangential force
MODE_NAMES = {STICK: "stick", SLIP_POS: "slip+", SLIP_NEG: "slip-", OPEN: "open"}
_EPS = np.finfo(float).eps


@dataclass
class Point:
    """Everything the configuration solve needs at one (t, q, q')."""

    t: float
    q: np.ndarray
    qd: np.ndarray
    mass_factor: object  # callable X -> M^-1 X
    h: np.ndarray
    WN: np.ndarray
    WT: np.ndarray
    wbN: np.ndarray
    wbT: np.ndarray
    N_presc: np.ndarray


class Evaluator:
    """Evaluates a :class:`ConstrainedSystem` at (t, q, q'), caching a constant mass factor."""

    def __init__(self, system):
        self.system = system
        self.n = int(system.n_dof)
        self.nc = int(system.n_contacts)
        self.constrained = np.asarray(system.normal_constrained, dtype=bool).copy()
        self.mu_s = np.asarray(system.mu_static, dtype=float).copy()
        self.mu_d = np.asarray(system.mu_sliding, dtype=float).copy()
        # no friction events (their tangential force is zero in any mode: kept in slip+)
        self.frictionless = (self.mu_s == 0) & (self.mu_d == 0)
        self._mfac = None
        self._plans: dict = {}
        self.n_solves = 0
        self.n_singular = 0
        #: switches with several equally valid configurations (see decide_modes)
        self.ambiguities: list = []
        #: compiled phase kernels of the system (None: the generic path)
        hook = getattr(system, "compiled_kernels", None)
        self.compiled = hook() if hook is not None else None
        #: contacts whose constrained normal may open and close (lift-off, impacts)
        uni = getattr(system, "unilateral_contacts", None)
        self.unilateral = (np.zeros(self.nc, dtype=bool) if uni is None
                           else np.asarray(uni(), dtype=bool).copy())
        res = getattr(system, "restitution_coefficients", None)
        self.restitution = (np.zeros(self.nc) if res is None
                            else np.asarray(res(), dtype=float).copy())
        if self.unilateral.any() and not getattr(self.compiled, "open_contacts", False):
            self.compiled = None  # these compiled kernels know no open contacts
        #: kernels for the switching and projection solves too (all normals constrained)
        self._fused = (self.compiled if getattr(self.compiled, "fused_phases", False)
                       and self.constrained.all() and hasattr(self.compiled, "solve_point")
                       else None)

    def mass_factor(self, q):
        """A solver ``X -> M(q)^-1 X`` (the explicit inverse is cached for a constant mass)."""
        if self._mfac is not None:
            return self._mfac
        M = np.asarray(self.system.mass(q), dtype=float)
        try:
            fac = sla.cho_factor(M, check_finite=False)
        except np.linalg.LinAlgError:
            raise ModelError("the mass matrix is not positive definite at q = "
                             f"{np.array2string(np.asarray(q), precision=4)}") from None
        if self.system.constant_mass:
            Minv = sla.cho_solve(fac, np.eye(M.shape[0]), check_finite=False)
            self._mfac = Minv.__matmul__
            return self._mfac
        return lambda X: sla.cho_solve(fac, X, check_finite=False)

    def point(self, t, q, qd) -> Point:
        s = self.system
        WN, WT, wbN, wbT = s.kinematics(q, qd)
        return Point(t, q, qd, self.mass_factor(q), np.asarray(s.h(t, q, qd), dtype=float),
                     np.asarray(WN, dtype=float), np.asarray(WT, dtype=float),
                     np.asarray(wbN, dtype=float), np.asarray(wbT, dtype=float),
                     np.asarray(s.prescribed_normal_load(t, q, qd), dtype=float))

    def _plan(self, modes, sigma):
        key = (np.asarray(modes, dtype=np.int64).tobytes(), np.asarray(sigma).tobytes())
        plan = self._plans.get(key)
        if plan is None:
            cons = self.constrained
            slip = (modes == SLIP_POS) | (modes == SLIP_NEG)
            s = np.where(slip, modes, 0).astype(float)
            ci = np.flatnonzero(cons & (modes != OPEN))
            plan = dict(
                ci=ci, si=np.flatnonzero(modes == STICK), sl=np.flatnonzero(slip),
                op=np.flatnonzero(modes == OPEN),
                ps=np.flatnonzero(slip & ~cons), gi=np.flatnonzero(modes == GIVEN),
                s=s, fric_ci=(self.mu_d * sigma * s)[ci],
                fric_ps=-self.mu_d[slip & ~cons] * s[slip & ~cons],
                fric_sl=(-self.mu_d * s)[slip])
            if len(self._plans) > 512:
                self._plans.clear()
            self._plans[key] = plan
        return plan

    # ------------------------------------------------------------ configuration solve
    def solve(self, pt: Point, modes, sigma, given=None):
        """Accelerations and contact forces of configuration ``modes`` at ``pt``.

        Parameters
        ----------
        modes : ndarray of int, shape (n_contacts,)
            STICK, SLIP_POS, SLIP_NEG or GIVEN per contact.
        sigma : ndarray, shape (n_contacts,)
            Assumed sign of the constrained normal forces (+1 compressive).
        given : ndarray, shape (n_contacts, k), optional
            Tangential forces of the GIVEN contacts, one column per right-hand side.

        Returns
        -------
        qdd : ndarray, shape (n_dof, k)
        lam_N, lam_T : ndarray, shape (n_contacts, k)
        """
        self.n_solves += 1
        ck = self._fused
        if ck is not None:
            ok, qdd, lamN, lamT = ck.solve_point(
                pt.h, pt.WN, pt.WT, pt.wbN, pt.wbT, np.asarray(modes, dtype=np.int64),
                np.asarray(sigma, dtype=float), given)
            if ok:
                return qdd, lamN, lamT
        p = self._plan(modes, sigma)
        ci, si, sl, ps, gi = p["ci"], p["si"], p["sl"], p["ps"], p["gi"]
        k = 1 if given is None else given.shape[1]
        F = np.empty((self.n, k))
        F[:] = pt.h[:, None]
        if ps.size:
            F += (pt.WT[:, ps] @ (p["fric_ps"] * np.abs(pt.N_presc[ps])))[:, None]
        if given is not None and gi.size:
            F += pt.WT[:, gi] @ given[gi]
        MiF = pt.mass_factor(F)
        lamN = np.empty((self.nc, k))
        lamN[:] = pt.N_presc[:, None]
        lamN[p["op"]] = 0.0
        lamT = np.zeros((self.nc, k))
        if ci.size + si.size:
            B = np.hstack([pt.WN[:, ci] - pt.WT[:, ci] * p["fric_ci"], pt.WT[:, si]])
            C = np.hstack([pt.WN[:, ci], pt.WT[:, si]]).T
            wb = np.concatenate([pt.wbN[ci], pt.wbT[si]])
            MiB = pt.mass_factor(B)
            x = self._solve_small(C @ MiB, -(wb[:, None] + C @ MiF))
            qdd = MiF + MiB @ x
            lamN[ci] = x[:ci.size]
            lamT[si] = x[ci.size:]
        else:
            qdd = MiF
        if sl.size:
            lamT[sl] = p["fric_sl"][:, None] * np.abs(lamN[sl])
        if given is not None and gi.size:
            lamT[gi] = given[gi]
        return qdd, lamN, lamT

    def _solve_small(self, A, rhs):
        d = np.abs(np.diag(A))
        if A.shape[0] == 1:
            if d[0] > 0:
                return rhs / A[0, 0]
        else:
            x, ratio = small_lu_solve(np.ascontiguousarray(A, dtype=float),
                                      np.ascontiguousarray(rhs, dtype=float))
            if ratio > 1e-13:
                return x
        # redundant constraints (e.g. two stuck contacts fixing the same motion): the
        # multipliers are not unique; take the minimum-norm set (q'' is still unique).
        self.n_singular += 1
        return np.linalg.lstsq(A, rhs, rcond=1e-12)[0]

    # ------------------------------------------------------------ constraints
    def tangent_velocity(self, t, q, qd):
        """Slip velocities (n_c,) and their magnitude scale |W_T|^T |q'| (n_c,)."""
        WT = np.asarray(self.system.tangent_jacobian(q), dtype=float)
        return WT.T @ qd, np.abs(WT).T @ np.abs(qd)

    def project(self, t, q, qd, modes):
        """Put (q, q') on the constraints of configuration ``modes``.

        Positions: Gauss-Newton on the closed normal gaps (M-weighted). Velocities: the
        M-orthogonal projection onto ``W_N^T q' = 0`` and ``W_T,S^T q' = 0`` (the velocity
        after a perfectly inelastic impulse, which removes the least kinetic energy). Open
        contacts (mode ``OPEN``) are not constrained.

        Returns
        -------
        q, qd : ndarray
        dE : float
            |kinetic energy change| of the velocity projection [J].
        """
        cons = self.constrained & (np.asarray(modes) != OPEN)
        ck = self.compiled
        if ck is not None and getattr(ck, "fused_phases", False) and (
                cons.all() or (self.constrained.all() and getattr(ck, "open_contacts", False))):
            ok, q_new, qd_new, de = ck.project(q, qd, modes)
            if ok:
                return q_new, qd_new, de
        if cons.any():
            for _ in range(5):
                g = np.asarray(self.system.normal_gap(q), float)[cons]
                if np.all(np.abs(g) <= 1e-15 * (1 + np.abs(q).max())):
                    break
                pt = self.point(t, q, qd)
                WN = pt.WN[:, cons]
                MiW = pt.mass_factor(WN)
                q = q - MiW @ np.linalg.lstsq(WN.T @ MiW, g, rcond=1e-12)[0]
        stick = modes == STICK
        if not (cons.any() or stick.any()):
            return q, qd, 0.0
        WN, WT, _, _ = self.system.kinematics(q, qd)
        W = np.hstack([np.asarray(WN, float)[:, cons], np.asarray(WT, float)[:, stick]])
        Msolve = self.mass_factor(q)
        MiW = Msolve(W)
        corr = MiW @ np.linalg.lstsq(W.T @ MiW, W.T @ qd, rcond=1e-12)[0]
        M = np.asarray(self.system.mass(q), float)
        qd_new = qd - corr
        return q, qd_new, abs(0.5 * qd @ M @ qd - 0.5 * qd_new @ M @ qd_new)

    # ------------------------------------------------------------ switching decision
    def decide_at(self, t, q, qd, modes, candidates, must_slip, sigma):
        """:meth:`decide` at (t, q, q')."""
        return self.decide(self.point(t, q, qd), modes, candidates, must_slip, sigma)

    def decide(self, pt: Point, modes, candidates, must_slip, sigma):
        """New modes after an event (see :func:`decide_modes`)."""

        def affine(new, cand):
            kc = cand.size
            given = np.zeros((self.nc, kc + 1))
            given[cand, 1:] = np.eye(kc)
            qdd, lamN, _ = self.solve(pt, new, sigma, given)
            acc = pt.WT[:, cand].T @ qdd + pt.wbT[cand, None]
            sg = np.where(self.constrained[cand], sigma[cand], np.sign(lamN[cand, 0]) + (
                lamN[cand, 0] == 0))
            nrm = sg[:, None] * lamN[cand]
            return acc[:, 1:] - acc[:, :1], acc[:, 0], nrm[:, 1:] - nrm[:, :1], nrm[:, 0]

        def verify(new):
            qdd, lamN, lamT = self.solve(pt, new, sigma)
            a = pt.WT.T @ qdd[:, 0] + pt.wbT
            parts = pt.mass_factor(np.column_stack([pt.h, pt.WT @ lamT[:, 0],
                                                    pt.WN @ lamN[:, 0]]))
            ascale = np.abs(pt.WT.T @ parts).sum(axis=1) + np.abs(pt.wbT)
            return a, ascale, lamT[:, 0], lamN[:, 0]

        return decide_modes(pt.t, modes, candidates, must_slip, self.mu_s, self.mu_d, affine,
                            verify, self.ambiguities, compiled_lcp=self._fused is not None)


class LinearDecider:
    """Switching decisions of a :class:`LinearForm` (constant M, W_T and normal loads).

    Same problem as :meth:`Evaluator.decide`, with the Delassus matrix
    ``W_T^T M^-1 W_T`` computed once, so a decision costs a few small matrix products.
    """

    def __init__(self, lf, mu_s, mu_d):
        self.lf = lf
        self.mu_s, self.mu_d = np.asarray(mu_s, float), np.asarray(mu_d, float)
        self.N = np.abs(np.asarray(lf.normal_load, float))
        Minv = np.linalg.inv(lf.M)
        self.MinvW = Minv @ lf.tangent
        self.WtMinv = lf.tangent.T @ Minv
        self.Del = self.WtMinv @ lf.tangent
        self.absWtMinv = np.abs(self.WtMinv)
        self.absWt = np.abs(lf.tangent.T)
        #: switches with several equally valid configurations (see decide_modes)
        self.ambiguities: list = []
        self._projectors: dict = {}

    def tangent_velocity(self, t, q, qd):
        return self.lf.tangent.T @ qd, self.absWt @ np.abs(qd)

    def projector(self, stuck) -> np.ndarray:
        """``M^-1 W_S (W_S^T M^-1 W_S)^+ W_S^T`` for the stuck set (bool mask), cached: the
        velocity part removed by the M-orthogonal projection (n_dof, n_dof)."""
        key = np.asarray(stuck, dtype=bool).tobytes()
        P = self._projectors.get(key)
        if P is None:
            S = np.flatnonzero(stuck)
            P = self.MinvW[:, S] @ np.linalg.pinv(self.Del[np.ix_(S, S)], rcond=1e-12) @ \
                self.lf.tangent[:, S].T
            if len(self._projectors) > 256:
                self._projectors.clear()
            self._projectors[key] = P
        return P

    def project(self, t, q, qd, modes):
        """M-orthogonal velocity projection onto the stuck constraints (see Evaluator)."""
        stuck = modes == STICK
        if not stuck.any():
            return q, qd, 0.0
        qd_new = qd - self.projector(stuck) @ qd
        M = self.lf.M
        return q, qd_new, abs(0.5 * qd @ M @ qd - 0.5 * qd_new @ M @ qd_new)

    def decide_at(self, t, q, qd, modes, candidates, must_slip, sigma):
        lf = self.lf
        h = lf.load(t) - lf.D @ qd - lf.K @ q
        bh = self.WtMinv @ h  # free tangential accelerations
        slipf = -self.mu_d * self.N  # friction of a slipping contact times its direction
        cand = np.flatnonzero(candidates)
        if cand.size == 1 and not np.any(must_slip):
            # one contact with zero slip velocity, the others slipping (see decide_modes)
            i = cand[0]
            new = np.array(modes, dtype=int)
            new[i] = 0
            b = bh[i] + self.Del[i] @ (slipf * new)
            g, lim = self.Del[i, i], self.mu_s[i] * self.N[i]
            if g > 0:
                new[i] = STICK if abs(b) <= g * lim * (1 + 1e3 * _EPS) else (1 if b > 0 else -1)
                return new

        def b_of(new):
            sl = (new == SLIP_POS) | (new == SLIP_NEG)
            return bh + self.Del[:, sl] @ (slipf[sl] * new[sl])

        def affine(new, cand):
            G = self.Del[np.ix_(cand, cand)]
            return G, b_of(new)[cand], np.zeros_like(G), self.N[cand]

        def verify(new):
            b = b_of(new)
            S = np.flatnonzero(new == STICK)
            lamT = np.where(new == STICK, 0.0, slipf * new)
            a = b
            if S.size:
                lamS = np.linalg.lstsq(self.Del[np.ix_(S, S)], -b[S], rcond=1e-12)[0]
                lamT[S] = lamS
                a = b + self.Del[:, S] @ lamS
            ascale = self.absWtMinv @ np.abs(h) + np.abs(self.Del) @ np.abs(lamT)
            return a, ascale, lamT, self.N

        return decide_modes(t, modes, candidates, must_slip, self.mu_s, self.mu_d, affine,
                            verify, self.ambiguities)


def decide_modes(t, modes, candidates, must_slip, mu_s, mu_d, affine, verify,
                 ambiguities: list | None = None, compiled_lcp: bool = False):
    """Consistent modes of the contacts with zero slip velocity after an event.

    Parameters
    ----------
    t : float
        Event time [s] (for messages).
    modes : ndarray of int, shape (n_contacts,)
        Current modes; non-candidates keep theirs (they slip).
    candidates : ndarray of bool, shape (n_contacts,)
        Contacts with zero slip velocity whose mode is to be decided.
    must_slip : ndarray of int, shape (n_contacts,)
        +-1 for stuck contacts whose friction saturation reached zero (they slip in that
        direction, 000 (43)); 0 otherwise.
    mu_s, mu_d : ndarray, shape (n_contacts,)
        Static and sliding friction coefficients.
    affine : callable (modes, cand) -> (G, b, H, c)
        With the candidates ``cand`` (indices) marked GIVEN in ``modes``: their relative
        accelerations ``a = G lambda + b`` and normal-force magnitudes ``H lambda + c`` as
        functions of their tangential forces.
    verify : callable (modes) -> (a, a_scale, lambda_T, lambda_N)
        Relative accelerations, their magnitude scale, and contact forces of a configuration.
    ambiguities : list, optional
        When given and 2 to 4 candidates with ``mu_static > mu_sliding`` are decided, every
        consistent configuration is enumerated; if several share the largest number of
        stuck contacts (the rule "stick whenever consistent" does not single one out: in a
        symmetric system round-off would pick which contact breaks away) a warning is
        logged and ``(t, [modes, ...])`` appended.
    compiled_lcp : bool
        Solve the friction LCPs with the compiled Lemke kernel (same algorithm).

    Returns
    -------
    ndarray of int, shape (n_contacts,)

    Raises
    ------
    ConvergenceError
        If no consistent configuration is found (Painleve-type paradox).
    """
    new = np.array(modes, dtype=int)
    ms = np.asarray(must_slip, dtype=int)
    new[ms != 0] = ms[ms != 0]
    todo = np.asarray(candidates, dtype=bool) & (ms == 0)
    new[todo] = GIVEN
    decided = todo | (ms != 0)
    cand = np.flatnonzero(todo)
    if cand.size == 1 and not ms.any():
        # one contact, the others slipping: consistent by construction when the normal force
        # does not depend on its friction force (clipped stick force; slip with mu_d <= mu_s
        # keeps the sign of the acceleration)
        G, b, H, c = affine(new, cand)
        g, bb = G[0, 0], b[0]
        if H[0, 0] == 0 and g > 0:
            i = cand[0]
            lim = mu_s[i] * c[0]
            new[i] = STICK if abs(bb) <= g * lim * (1 + 1e3 * _EPS) else (1 if bb > 0 else -1)
            return new
    if cand.size:
        G, b, H, c = affine(new, cand)
        broke = np.zeros(cand.size, dtype=bool)  # breakaway set: bounded by mu_d
        for _ in range(cand.size + 1):
            mu_b = np.where(broke, mu_d[cand], mu_s[cand])
            lam, a = solve_friction_lcp(G, b, H, c, mu_b, compiled=compiled_lcp)
            scale = max(np.abs(b).max(), np.abs(G).max() * max(
                np.abs(mu_b * c).max(), np.abs(lam).max()), 1e-300)
            slipping = np.abs(a) > 1e3 * _EPS * scale
            newly = slipping & ~broke & (mu_d[cand] < mu_s[cand])
            if not newly.any():
                break
            broke |= newly
        new[cand] = np.where(slipping, np.sign(a), STICK).astype(int)
    if _consistent(new, decided, mu_s, verify) is None:
        if ambiguities is not None and 2 <= cand.size <= 4 and np.any(
                mu_s[cand] > mu_d[cand]):
            return _select(t, modes, new, cand, decided, mu_s, verify, ambiguities)
        return new
    # the cascade failed (normal forces coupled to the friction forces, or must-slip
    # contacts reversed by the others): enumerate the candidates' modes, most stick first
    if cand.size <= 6:
        best = None
        for combo in itertools.product((STICK, SLIP_POS, SLIP_NEG), repeat=cand.size):
            trial = new.copy()
            trial[cand] = combo
            n_stick = combo.count(STICK)
            if (best is None or n_stick > best[0]) and _consistent(
                    trial, decided, mu_s, verify) is None:
                best = (n_stick, trial)
        if best is not None:
            return best[1]
    bad = _consistent(new, decided, mu_s, verify)
    raise ConvergenceError(
        f"no consistent stick/slip configuration at t = {t:.17g} s (contacts {bad}): the "
        "friction problem has no solution here (Painleve-type paradox, or normal forces that "
        "depend strongly on the friction forces); check mu and the contact geometry")


def _select(t, modes, new, cand, decided, mu_s, verify, ambiguities):
    """The configuration taken when ``mu_static > mu_sliding`` makes several consistent.

    Every consistent assignment of the candidates' modes is scored by (number of stuck
    candidates, number of candidates stuck before the event that stay stuck) and the
    unique best is taken. The first key is the rule "stick whenever consistent". The second
    is 000 (43): a stuck contact leaves stick only when its own friction saturation
    ``mu_S |F_N| - |F_c|`` reaches zero (its event then makes it a must-slip contact, not a
    candidate), so a contact whose slip velocity vanished does not make a neighbour that was
    holding with a positive saturation break away when a configuration with the neighbour
    still stuck is consistent. Without the second key the choice was left to round-off in
    the breakaway cascade: at the blade damper's resonance nearly every switch had the two
    one-stuck configurations "stick/slip" and "slip/stick", taken at random, and the
    response never settled on a periodic orbit.

    When several configurations share the best score (e.g. two contacts stuck before the
    event, both at zero saturation reserve in a symmetric system) the breakaway cascade's
    result ``new`` is kept, a warning is logged and ``(t, [modes, ...])`` appended to
    ``ambiguities``: the stick-slip solution is not unique there.
    """
    was_stuck = np.asarray(modes)[cand] == STICK
    best, alts = (-1, -1), []
    for combo in itertools.product((STICK, SLIP_POS, SLIP_NEG), repeat=cand.size):
        stuck = np.asarray(combo) == STICK
        score = (int(stuck.sum()), int(np.sum(stuck & was_stuck)))
        if score < best:
            continue
        trial = new.copy()
        trial[cand] = combo
        if _consistent(trial, decided, mu_s, verify) is None:
            if score > best:
                best, alts = score, []
            alts.append(trial)
    if len(alts) == 1:
        return alts[0]
    if len(alts) > 1:
        names = ["/".join(MODE_NAMES[int(m)] for m in a[cand]) for a in alts]
        log.warning("switch at t = %.17g s has %d consistent configurations of contacts %s "
                    "with %d stuck (%s); %s was taken: the stick-slip solution is not unique "
                    "here (mu_static > mu_sliding), and round-off may decide it", t, len(alts),
                    cand.tolist(), best[0], ", ".join(names),
                    "/".join(MODE_NAMES[int(m)] for m in new[cand]))
        ambiguities.append((float(t), [a.copy() for a in alts]))
    return new


def _consistent(new, decided, mu_s, verify):
    """None if configuration ``new`` satisfies the friction law, else the offending contacts."""
    a, ascale, lamT, lamN = verify(new)
    lim = mu_s * np.abs(lamN)
    lt = np.abs(lamT)
    bad_slip = decided & (new != STICK) & (new * a < -1e-9 * ascale)
    bad_stick = decided & (new == STICK) & (lt > lim + 1e-9 * (lim + lt))
    bad = bad_slip | bad_stick
    return np.flatnonzero(bad).tolist() if bad.any() else None


# ---------------------------------------------------------------- friction LCP
def solve_friction_lcp(G, b, H, c, mu, compiled: bool = False):
    """Solve the friction complementarity problem of k contacts with zero slip velocity.

    Find tangential forces ``lambda`` (k,) and relative accelerations ``a = G lambda + b``
    with, per contact and ``n = H lambda + c`` (normal force magnitude):
    ``|lambda| <= mu n``; ``lambda = -mu n => a >= 0``; ``lambda = mu n => a <= 0``;
    ``a = 0`` in between.

    With ``compiled``, Lemke's method runs compiled (:func:`~fricdamp.solvers.event_kernels.
    lemke_kernel`, the same pivoting rules).

    Returns
    -------
    lam, a : ndarray, shape (k,)

    Raises
    ------
    ConvergenceError
        If Lemke's method ends on a secondary ray (no solution found).
    """
    k = b.size
    m = np.asarray(mu, dtype=float)
    if k == 1 and H[0, 0] == 0 and G[0, 0] > 0:
        # one contact, fixed normal force: clip the sticking force to the friction limit
        lim = m[0] * c[0]
        lam = np.clip(np.array([-b[0] / G[0, 0]]), -lim, lim)
        return lam, G @ lam + b
    E = np.linalg.inv(np.eye(k) + m[:, None] * H)
    mc = m * c
    GE = G @ E
    QE = (m[:, None] * H - np.eye(k)) @ E
    A = np.zeros((2 * k, 2 * k))
    A[:k, :k] = GE
    A[:k, k:] = np.eye(k)
    A[k:, :k] = QE
    q = np.concatenate([b - GE @ mc, mc - QE @ mc])
    if compiled:
        z, status = lemke_kernel(np.ascontiguousarray(A), np.ascontiguousarray(q),
                                 50 * (q.size + 1))
        if status == 1:
            raise ConvergenceError("Lemke's method ended on a ray: the friction complementarity "
                                   "problem has no solution (check mu and the contact geometry)")
        if status == 2:
            raise ConvergenceError(f"Lemke's method did not terminate in {50 * (q.size + 1)} "
                                   "pivots")
    else:
        z = lemke(A, q)
    r_plus = z[:k]
    lam = E @ (r_plus - mc)
    a = G @ lam + b
    return lam, a


def lemke(A, q, max_iter: int | None = None):
    """Lemke's complementary pivoting for ``w = A z + q >= 0, z >= 0, w . z = 0``.

    Lexicographic ratio test (no cycling on degenerate problems), covering vector of ones.

    Parameters
    ----------
    A : ndarray, shape (n, n)
    q : ndarray, shape (n,)

    Returns
    -------
    z : ndarray, shape (n,)

    Raises
    ------
    ConvergenceError
        On ray termination or when the iteration limit is hit.
    """
    q = np.asarray(q, dtype=float)
    n = q.size
    if n == 0 or np.all(q >= 0):
        return np.zeros(n)
    # tableau columns: w (0..n-1), z (n..2n-1), z0 (2n), rhs (2n+1)
    T = np.zeros((n, 2 * n + 2))
    T[:, :n] = np.eye(n)
    T[:, n:2 * n] = -A
    T[:, 2 * n] = -1.0
    T[:, -1] = q
    basis = np.arange(n)
    tol = 1e-13 * max(1.0, np.abs(A).max())
    max_iter = max_iter or 50 * (n + 1)

    def pivot(r, e):
        T[r] /= T[r, e]
        col = T[:, e].copy()
        col[r] = 0.0
        T[:] -= np.outer(col, T[r])

    r = int(np.argmin(q))
    pivot(r, 2 * n)
    leaving = basis[r]
    basis[r] = 2 * n
    for _ in range(max_iter):
        entering = leaving + n if leaving < n else leaving - n
        col = T[:, entering]
        rows = np.flatnonzero(col > tol)
        if rows.size == 0:
            raise ConvergenceError("Lemke's method ended on a ray: the friction complementarity "
                                   "problem has no solution (check mu and the contact geometry)")
        # lexicographic minimum ratio over [rhs, B^-1] / col
        keys = np.column_stack([T[rows, -1], T[rows, :n]]) / col[rows, None]
        cand = rows
        for j in range(keys.shape[1]):
            kj = keys[:, j]
            best = kj.min()
            sel = kj <= best + 1e-12 * max(1.0, abs(best))
            cand, keys = cand[sel], keys[sel]
            if cand.size == 1:
                break
            if j == 0 and np.any(basis[cand] == 2 * n):
                cand = cand[basis[cand] == 2 * n]
                break
        r = int(cand[0])
        pivot(r, entering)
        leaving = basis[r]
        basis[r] = entering
        if leaving == 2 * n:
            z = np.zeros(n)
            isz = (basis >= n) & (basis < 2 * n)
            z[basis[isz] - n] = np.maximum(T[isz, -1], 0.0)
            return z
    raise ConvergenceError(f"Lemke's method did not terminate in {max_iter} pivots")
