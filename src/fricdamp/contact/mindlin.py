"""Cattaneo–Mindlin sphere-on-flat contact under constant normal load, with Masing memory.

A sphere pressed by a constant normal load ``N`` and displaced tangentially by ``delta``
carries the tangential force (Cattaneo 1938, Mindlin 1949; Johnson, *Contact Mechanics*,
§7.2–7.3; REFERENCES.md)::

    virgin loading:  T = mu N [1 - (1 - delta/delta_s)^(3/2)],   |delta| <= delta_s
    gross slip:      |T| = mu N,                                   |delta| >= delta_s
    delta_s = 3 mu N C / (16 a),   a = (3 N R / (4 E*))^(1/3)     (Hertz radius)
    C = (2 - nu1)/G1 + (2 - nu2)/G2  [1/Pa]                        (tangential compliance)

so the initial tangential stiffness is ``dT/d delta (0) = 8 a / C``. Paper 002 (17) writes
``16 a delta / (3 mu N G*)`` with ``G*`` of its (20): ``G*`` is this compliance ``C`` (units
1/Pa), not a modulus; with that reading the constant 16/3 is right (a units check).

Unloading and reloading (Mindlin & Deresiewicz 1953) follow Masing's rule: from the last
turning point ``(delta_r, T_r)`` with the new direction ``s = +-1``::

    T = T_r + 2 s mu N [1 - (1 - s (delta - delta_r) / (2 delta_s))^(3/2)]

Paper 002 (18)–(19) print this branch as ``2 mu N ((0.5 (x + (1 - T_max/mu N)^(3/2) + 1))^(3/2)
- 1) + T_max`` with ``x = 16 a delta / (3 mu N G*)``; expanding the branch above with
``delta_r = delta_s (1 - (1 - T_max/mu N)^(2/3))`` (the inverse of (17)) gives the same
expression with the exponent **2/3**, not 3/2, on ``(1 - T_max/mu N)``: the printed exponent
is an extraction (or typesetting) error; this module implements the derived form.

Memory (nested reversals)
-------------------------
Under constant ``N`` the traction is a superposition of Hertz-like distributions whose
stick radii are nested; a reversal branch stays valid until it reaches the force of the
turning point it emanated from, where the two innermost distributions cancel and the contact
returns onto the older branch (Mindlin & Deresiewicz 1953). This is exactly the extended
Masing rule with memory (Pyke 1979; the "rainflow" memory of Iwan models):

* the state holds a stack of turning points ``(delta_k, T_k)``;
* a reversal pushes the last point; the branch from ``P_m`` is valid until ``delta``
  reaches ``delta_(m-1)`` (where by Masing symmetry ``T = T_(m-1)``); there ``P_m`` and
  ``P_(m-1)`` are erased and the branch from ``P_(m-2)`` continues;
* the first reversal from the virgin curve at ``P_1`` is valid until the mirror point
  ``-delta_1`` on the virgin curve, which then continues; after a gross slip, the branch
  from the slip point is valid until gross slip in the opposite direction (``2 delta_s``
  further), the loop of the Jenkins-like steady gross-slip cycle.

For a sinusoid sampled at its turning points the stack alternates between zero and one
point, and the simple Masing loop is reproduced exactly after the first quarter cycle
(tests/unit/test_mindlin.py); sampled off its peaks, successive sampled peaks differ
slightly and nest a few levels deep, which is the exact response to the sampled history.
The stack has a fixed depth ``memory`` (default 16 points); only histories with more than
``memory`` nested, still-open reversals (e.g. a long free decay) overflow it. On overflow
the pair of consecutive points whose removal moves a branch bound the least is forgotten
(never the outermost point nor the current loop): the loop being traced stays exact, a
later return to a forgotten older branch is approximated, and the stored energy below
(rebuilt from the stack) becomes approximate by the size of the forgotten loops.

Stored energy
-------------
The Cattaneo–Mindlin law under constant ``N`` is reproduced *exactly*, including Masing
memory, by a parallel Iwan model: a continuum of Jenkins elements (spring + slider) with
slip displacements ``z delta_s`` (0 < z < 1) and stiffness density
``(3/4) (mu N / delta_s) (1 - z)^(-1/2)``; the skeleton ``T'' = -k rho`` gives exactly
``mu N [1 - (1 - delta/delta_s)^(3/2)]`` and each element's slip history gives the Masing
branches. :meth:`CattaneoMindlin.stored_energy` returns the elastic energy of the springs of
that model, ``E = 1/2 sum k_i e_i^2`` computed in closed form from the turning-point stack.
With this definition the dissipation ``work - stored change`` is the slider work: it is
non-negative at every instant and, around any closed cycle, equals the loop area (the
Mindlin closed form W(q) for a symmetric cycle). It is the energy the contact would give
back if every element were unloaded elastically, not the strain energy of the two
half-spaces (which also holds the locked-in residual tractions and is not needed for the
balance).

Tangent
-------
``dT/d delta = (mu N / delta_s) (3/2) (1 - y)^(1/2)`` on the active branch (``y`` the
normalised distance from its origin), 0 in gross slip. When ``u`` equals the previous
displacement the tangent is the one of the current branch continued in the current
direction (``8 a / C`` from the virgin state).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from fricdamp.contact.base import ContactLaw, LawStep, broadcast_parameter, common_size
from fricdamp.errors import ModelError, as_finite_array

# state layout (per contact): fixed header, then the turning-point stack
_BASE, _DIR, _DEPTH, _XPREV, _FPREV = 0, 1, 2, 3, 4
_HEADER = 5


# ----------------------------------------------------------------------------- materials
def _check_nu(name, nu):
    arr = as_finite_array(name, nu)
    if np.any((arr <= -1.0) | (arr > 0.5)):
        raise ModelError(f"{name} must lie in (-1, 0.5], got {nu!r}")
    return arr


def _check_modulus(name, value, unit="Pa"):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{name} must be numeric, got {value!r}") from exc
    if np.any(np.isnan(arr)) or np.any(arr <= 0):
        raise ModelError(f"{name} must be > 0 {unit} (np.inf for a rigid body), got {value!r}")
    return arr


def _scalar_or_array(out, *inputs):
    return float(out) if all(np.ndim(v) == 0 for v in inputs) else np.asarray(out)


def shear_modulus(E, nu):
    """Shear modulus ``G = E / (2 (1 + nu))`` [Pa] of an isotropic material.

    Parameters
    ----------
    E : float or array_like
        Young's modulus [Pa], > 0 (``np.inf`` for a rigid body).
    nu : float or array_like
        Poisson's ratio, in (-1, 0.5].
    """
    return _scalar_or_array(_check_modulus("E", E) / (2.0 * (1.0 + _check_nu("nu", nu))), E, nu)


def effective_modulus(E1, nu1, E2, nu2):
    """Hertz contact modulus ``E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`` [Pa].

    Paper 002 (14); Johnson (1985) eq. (4.22). Pass ``E2 = np.inf`` for a rigid flat.

    Parameters
    ----------
    E1, E2 : float or array_like
        Young's moduli [Pa], > 0 (``np.inf`` for a rigid body).
    nu1, nu2 : float or array_like
        Poisson's ratios, in (-1, 0.5].

    Examples
    --------
    >>> round(effective_modulus(210e9, 0.3, 210e9, 0.3) / 1e9, 3)
    115.385
    """
    c = (1 - _check_nu("nu1", nu1) ** 2) / _check_modulus("E1", E1) \
        + (1 - _check_nu("nu2", nu2) ** 2) / _check_modulus("E2", E2)
    if np.any(c <= 0):
        raise ModelError("E1 and E2 cannot both be rigid (np.inf)")
    return _scalar_or_array(1.0 / c, E1, nu1, E2, nu2)


def tangential_compliance(G1, nu1, G2, nu2):
    """Mindlin tangential compliance ``C = (2 - nu1)/G1 + (2 - nu2)/G2`` [1/Pa].

    This is paper 002's ``G*`` of (20) (a compliance, not a modulus); Johnson (1985)
    eq. (7.42). The initial tangential stiffness of a Hertz contact of radius ``a`` is
    ``8 a / C``. Pass ``G2 = np.inf`` for a rigid flat.

    Parameters
    ----------
    G1, G2 : float or array_like
        Shear moduli [Pa], > 0 (``np.inf`` for a rigid body).
    nu1, nu2 : float or array_like
        Poisson's ratios, in (-1, 0.5].
    """
    c = (2 - _check_nu("nu1", nu1)) / _check_modulus("G1", G1) \
        + (2 - _check_nu("nu2", nu2)) / _check_modulus("G2", G2)
    if np.any(c <= 0):
        raise ModelError("G1 and G2 cannot both be rigid (np.inf)")
    return _scalar_or_array(c, G1, nu1, G2, nu2)


def hertz_radius(normal_load, radius, E_star):
    """Hertz contact radius ``a = (3 N R / (4 E*))^(1/3)`` [m] of a sphere on a flat.

    Parameters
    ----------
    normal_load : float or array_like
        Normal load N [N], >= 0.
    radius : float or array_like
        Sphere (summit) radius R [m], > 0.
    E_star : float or array_like
        Contact modulus E* [Pa], > 0 (see :func:`effective_modulus`).
    """
    n = broadcast_parameter("normal_load", normal_load, None, unit="N", allow_zero=True)
    r = broadcast_parameter("radius", radius, None, unit="m")
    e = broadcast_parameter("E_star", E_star, None, unit="Pa")
    try:
        out = np.cbrt(3.0 * n * r / (4.0 * e))
    except ValueError as exc:
        raise ModelError(f"normal_load, radius and E_star have incompatible lengths "
                         f"({n.size}, {r.size}, {e.size})") from exc
    return _scalar_or_array(out[0] if out.size == 1 else out, normal_load, radius, E_star)


# ----------------------------------------------------------------------------- kernels
@njit(cache=True, nogil=True, inline="always")
def _g(y):  # pragma: no cover - compiled
    """Normalised virgin curve 1 - (1 - y)^(3/2) on [0, 1] and its slope."""
    if y <= 0.0:
        return 0.0, 1.5
    if y >= 1.0:
        return 1.0, 0.0
    r = np.sqrt(1.0 - y)
    return 1.0 - (1.0 - y) * r, 1.5 * r


@njit(cache=True, nogil=True)
def _drop_pair(st, m, K):  # pragma: no cover - compiled
    """Forget the pair (P_k, P_k+1), 1 <= k <= m-3, that moves a branch bound the least."""
    xo, fo = _HEADER, _HEADER + K
    best, err = 1, np.inf
    for k in range(1, m - 2):
        e = abs(st[xo + k - 1] - st[xo + k + 1])
        if e < err:
            err, best = e, k
    for i in range(best, m - 2):
        st[xo + i] = st[xo + i + 2]
        st[fo + i] = st[fo + i + 2]
    for i in range(m - 2, m):  # keep unused slots zero: equal states behave equally
        st[xo + i] = 0.0
        st[fo + i] = 0.0
    return m - 2


@njit(cache=True, nogil=True)
def cm_update(st, x, F, ds, K):  # pragma: no cover - compiled
    """Advance one Cattaneo–Mindlin contact to displacement x; mutate its state row.

    st: state row (5 + 2K,); F: slip force [N] (> 0 or 0 for a force-free contact);
    ds: slip displacement delta_s [m]. Returns (force [N], tangent [N/m]).
    """
    if F <= 0.0 or ds <= 0.0:
        st[_XPREV] = x
        st[_FPREV] = 0.0
        return 0.0, 0.0
    xo, fo = _HEADER, _HEADER + K
    base = st[_BASE]
    s = st[_DIR]
    m = int(st[_DEPTH])
    xp = st[_XPREV]
    dx = x - xp
    if dx != 0.0:
        if m == 0 and base == 0.0:
            cur = np.sign(xp)  # on the virgin curve motion is outward (0 at the origin)
        else:
            cur = s
        if cur == 0.0:
            s = np.sign(dx)
        elif dx * cur < 0.0:  # reversal at the previous point: push it
            if m == K:
                m = _drop_pair(st, m, K)
            st[xo + m] = xp
            st[fo + m] = st[_FPREV]
            m += 1
            s = -cur
        else:
            s = cur
        # erase closed loops (Masing memory rule)
        while m >= 1:
            if m >= 2:
                xb = st[xo + m - 2]
            elif base == 0.0:
                xb = -st[xo]
            else:
                xb = st[xo] + 2.0 * s * ds
            if s * (x - xb) >= 0.0:
                mn = m - 2 if m >= 2 else 0
                for i in range(mn, m):  # keep unused slots zero (canonical state)
                    st[xo + i] = 0.0
                    st[fo + i] = 0.0
                m = mn
            else:
                break
    if m >= 1:
        y = s * (x - st[xo + m - 1]) / (2.0 * ds)
        gv, gp = _g(y)
        f = st[fo + m - 1] + 2.0 * s * F * gv
        k = F / ds * gp
    elif base == 0.0:
        xi = abs(x) / ds
        if xi >= 1.0:
            base = 1.0
            s = np.sign(x)
            f = s * F
            k = 0.0
        else:
            gv, gp = _g(xi)
            f = np.sign(x) * F * gv
            k = F / ds * gp
    else:
        f = s * F
        k = 0.0
    st[_BASE] = base
    st[_DIR] = s
    st[_DEPTH] = m
    st[_XPREV] = x
    st[_FPREV] = f
    return f, k


@njit(cache=True, nogil=True)
def cm_step_kernel(state, x, F, ds, K, f_out, k_out):  # pragma: no cover - compiled
    """Step every contact j from state[j] (mutated) to x[j]; write force and tangent."""
    for j in range(x.shape[0]):
        f, k = cm_update(state[j], x[j], F[j], ds[j], K)
        f_out[j] = f
        k_out[j] = k


@njit(cache=True, nogil=True)
def cm_march_kernel(x, state, F, ds, K, f_out):  # pragma: no cover - compiled
    """March contacts along x (n_t, n_c); state (n_c, 5 + 2K) is mutated; forces to f_out."""
    nt, nc = x.shape
    for i in range(nt):
        for j in range(nc):
            f, _ = cm_update(state[j], x[i, j], F[j], ds[j], K)
            f_out[i, j] = f


@njit(cache=True, nogil=True)
def cm_moment_march_kernel(theta, arm, state, F, ds, K, m_out):  # pragma: no cover
    """Rotational march summed over contacts: delta_j = arm_j theta, M = sum arm_j T_j."""
    nt = theta.shape[0]
    nc = arm.shape[0]
    for i in range(nt):
        acc = 0.0
        for j in range(nc):
            f, _ = cm_update(state[j], arm[j] * theta[i], F[j], ds[j], K)
            acc += arm[j] * f
        m_out[i] = acc


@njit(cache=True, nogil=True, inline="always")
def _w_moments(z):  # pragma: no cover - compiled
    """W_n(z) = int_0^z t^n (3/4)(1 - t)^(-1/2) dt, n = 0, 1, 2 (cancellation-free forms)."""
    if z <= 0.0:
        return 0.0, 0.0, 0.0
    if z >= 1.0:
        return 1.5, 1.0, 0.8
    r = np.sqrt(1.0 - z)
    om = z / (1.0 + r)  # 1 - sqrt(1 - z)
    return 1.5 * om, om * om * (1.0 + 0.5 * r), om ** 3 * (3.0 * r * r + 9.0 * r + 8.0) / 10.0


@njit(cache=True, nogil=True, inline="always")
def _segment(a, b, alpha, beta):  # pragma: no cover - compiled
    """(int w e, 1/2 int w e^2) over z in [a, b] for the elongation e = alpha z + beta."""
    if b <= a:
        return 0.0, 0.0
    a0, a1, a2 = _w_moments(a)
    b0, b1, b2 = _w_moments(b)
    m0, m1, m2 = b0 - a0, b1 - a1, b2 - a2
    return alpha * m1 + beta * m0, 0.5 * (alpha * alpha * m2 + 2.0 * alpha * beta * m1
                                          + beta * beta * m0)


@njit(cache=True, nogil=True)
def cm_iwan(st, x, F, ds, K):  # pragma: no cover - compiled
    """Force and stored energy of the equivalent Iwan model at x for the state row st.

    Normalised element slip levels z in [0, 1] with stiffness density (3/4)(1 - z)^(-1/2):
    the elongation profile e(z) is rebuilt from the turning-point stack. Returns
    (force [N], energy [J]); the force equals the Masing force (a consistency check).
    """
    if F <= 0.0 or ds <= 0.0:
        return 0.0, 0.0
    xo = _HEADER
    base = st[_BASE]
    s = st[_DIR]
    m = int(st[_DEPTH])
    xi = x / ds
    ft, et = 0.0, 0.0
    if m == 0:
        if base == 0.0:  # virgin curve: slipped below |xi|, elastic above
            sg = np.sign(xi)
            f1, e1 = _segment(0.0, min(abs(xi), 1.0), sg, 0.0)
            f2, e2 = _segment(min(abs(xi), 1.0), 1.0, 0.0, xi)
            return F * (f1 + f2), F * ds * (e1 + e2)
        f1, e1 = _segment(0.0, 1.0, s, 0.0)  # gross slip: every element slides
        return F * f1, F * ds * e1
    # current branch from P_m-1: elements below half the current span slide with s
    hi = min(0.5 * abs(xi - st[xo + m - 1] / ds), 1.0)
    f1, e1 = _segment(0.0, hi, s, 0.0)
    ft += f1
    et += e1
    lo = hi
    d = -s  # direction of the branch that led to P_k (alternates going back)
    for k in range(m - 1, -1, -1):
        xk = st[xo + k] / ds
        if k >= 1:
            top = 0.5 * abs(xk - st[xo + k - 1] / ds)
        elif base == 0.0:
            top = abs(xk)
        else:
            top = 1.0
        top = min(max(top, lo), 1.0)
        f1, e1 = _segment(lo, top, d, xi - xk)
        ft += f1
        et += e1
        lo = top
        d = -d
    if base == 0.0 and lo < 1.0:  # never slipped: elastic from the origin
        f1, e1 = _segment(lo, 1.0, 0.0, xi)
        ft += f1
        et += e1
    return F * ft, F * ds * et


@njit(cache=True, nogil=True)
def cm_energy_kernel(state, x, F, ds, K, e_out, f_out):  # pragma: no cover - compiled
    for j in range(x.shape[0]):
        f, e = cm_iwan(state[j], x[j], F[j], ds[j], K)
        e_out[j] = e
        f_out[j] = f


# ----------------------------------------------------------------------------- laws
class CattaneoMindlin(ContactLaw):
    """Cattaneo–Mindlin sphere on a flat under constant normal load, with Masing memory.

    One direction per contact (``n_dir = 1``): ``u`` is the tangential displacement
    ``delta`` [m] and the force is the tangential force ``T`` [N] (see the module docstring
    for the law, the memory rule and the stored-energy definition).

    Parameters
    ----------
    mu : float or array_like, shape (n_contacts,)
        Friction coefficient, >= 0.
    normal_load : float or array_like, shape (n_contacts,)
        Constant normal load N [N] per asperity, >= 0 (0: open contact, no force).
    contact_radius : float or array_like, shape (n_contacts,)
        Hertz contact radius a [m], > 0 where N > 0 (see :func:`hertz_radius`).
    compliance : float or array_like, shape (n_contacts,)
        Tangential compliance C [1/Pa] (see :func:`tangential_compliance`), > 0.
    multiplicity : float or array_like, shape (n_contacts,), optional
        Number of identical asperities a contact stands for (forces, stiffness and energy
        are multiplied by it; default 1); need not be an integer (statistical models).
    n_contacts : int, optional
        Number of contacts when every parameter is a scalar.
    memory : int, optional
        Depth of the turning-point stack (>= 4, default 16); see the module docstring.

    Attributes
    ----------
    slip_force : ndarray, shape (n_contacts,)
        ``multiplicity * mu * N`` [N].
    slip_displacement : ndarray, shape (n_contacts,)
        ``delta_s = 3 mu N C / (16 a)`` [m].
    initial_stiffness : ndarray, shape (n_contacts,)
        ``multiplicity * 8 a / C`` [N/m] (0 where mu N = 0).

    Examples
    --------
    >>> import numpy as np
    >>> law = CattaneoMindlin(mu=0.5, normal_load=10.0, contact_radius=1e-4,
    ...                       compliance=4e-11)
    >>> round(float(law.slip_displacement[0]), 14)  # 3 mu N C / (16 a) [m]
    3.75e-07
    >>> f = law.drive(np.array([0.0, 2e-7, 1e-6, 5e-7, 0.0]))  # micro-slip, gross slip, back
    >>> f.round(4).tolist()
    [0.0, 3.406, 5.0, -3.0755, -5.0]
    """

    n_dir = 1

    def __init__(self, mu, normal_load, contact_radius, compliance, *, multiplicity=1.0,
                 n_contacts: int | None = None, memory: int = 16):
        mu_a = broadcast_parameter("mu", mu, n_contacts, unit="", allow_zero=True)
        n_a = broadcast_parameter("normal_load", normal_load, n_contacts, unit="N",
                                  allow_zero=True)
        a_a = broadcast_parameter("contact_radius", contact_radius, n_contacts, unit="m",
                                  allow_zero=True)
        c_a = broadcast_parameter("compliance", compliance, n_contacts, unit="1/Pa")
        m_a = broadcast_parameter("multiplicity", multiplicity, n_contacts, unit="")
        n = common_size(mu=mu_a, normal_load=n_a, contact_radius=a_a, compliance=c_a,
                        multiplicity=m_a) if n_contacts is None else int(n_contacts)
        if int(memory) != memory or memory < 4:
            raise ModelError(f"memory must be an integer >= 4 turning points, got {memory!r}")
        bc = lambda v: np.broadcast_to(v, (n,)).astype(float)  # noqa: E731
        self.n_contacts = n
        self.mu, self.normal_load = bc(mu_a), bc(n_a)
        self.contact_radius, self.compliance = bc(a_a), bc(c_a)
        self.multiplicity = bc(m_a)
        if np.any((self.contact_radius == 0) & (self.normal_load > 0)):
            raise ModelError("contact_radius must be > 0 m where normal_load > 0, got "
                             f"{contact_radius!r}")
        self.memory = int(memory)
        self.n_state = _HEADER + 2 * self.memory
        active = self.mu * self.normal_load > 0
        self.slip_force = self.multiplicity * self.mu * self.normal_load
        a_safe = np.where(active, self.contact_radius, 1.0)
        self.slip_displacement = np.where(
            active, 3.0 * self.mu * self.normal_load * self.compliance / (16.0 * a_safe), 0.0)
        self.initial_stiffness = np.where(
            active, self.multiplicity * 8.0 * self.contact_radius / self.compliance, 0.0)

    # ----------------------------------------------------------------- factories
    @classmethod
    def from_sphere(cls, mu, normal_load, radius, E_star, compliance, **kw):
        """Contacts of spheres of ``radius`` R [m] on a flat, with the Hertz radius from
        ``normal_load`` N [N] and ``E_star`` [Pa]: ``a = (3 N R / (4 E*))^(1/3)``."""
        a = hertz_radius(np.atleast_1d(normal_load), radius, E_star)
        return cls(mu, normal_load, a, compliance, **kw)

    @classmethod
    def from_materials(cls, mu, normal_load, radius, E1, nu1, E2=None, nu2=None, **kw):
        """Sphere of ``radius`` R [m] and material (E1 [Pa], nu1) on a flat of (E2, nu2)
        (the same material if omitted; ``E2 = np.inf`` for a rigid flat)."""
        E2 = E1 if E2 is None else E2
        nu2 = nu1 if nu2 is None else nu2
        e_star = effective_modulus(E1, nu1, E2, nu2)
        c = tangential_compliance(shear_modulus(E1, nu1), nu1, shear_modulus(E2, nu2), nu2)
        return cls.from_sphere(mu, normal_load, radius, e_star, c, **kw)

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(n_contacts={self.n_contacts}, "
                f"slip_force={self.slip_force.tolist()}, "
                f"slip_displacement={self.slip_displacement.tolist()})")

    # ----------------------------------------------------------------- protocol
    def initial_state(self) -> np.ndarray:
        return np.zeros((self.n_contacts, self.n_state))

    def _state(self, state) -> np.ndarray:
        st = np.array(state, dtype=float, order="C")
        if st.shape != (self.n_contacts, self.n_state):
            raise ModelError(f"state must have shape ({self.n_contacts}, {self.n_state}) for "
                             f"this {type(self).__name__}, got {st.shape}")
        return st

    def _step_delta(self, state, delta):
        st = self._state(state)
        f = np.empty(self.n_contacts)
        k = np.empty(self.n_contacts)
        cm_step_kernel(st, np.ascontiguousarray(delta, dtype=float), self.slip_force,
                       self.slip_displacement, self.memory, f, k)
        return f, k, st

    def step(self, state, u, v=None) -> LawStep:
        f, k, st = self._step_delta(state, self._check_u(u)[:, 0])
        return LawStep(f[:, None], k[:, None, None], None, st)

    def _energy_delta(self, state, delta):
        st = self._state(state)
        e = np.empty(self.n_contacts)
        f = np.empty(self.n_contacts)
        cm_energy_kernel(st, np.ascontiguousarray(delta, dtype=float), self.slip_force,
                         self.slip_displacement, self.memory, e, f)
        return e, f

    def stored_energy(self, state, u) -> np.ndarray:
        """Elastic energy [J] of the equivalent Iwan model (module docstring), (n_contacts,)."""
        return self._energy_delta(state, self._check_u(u)[:, 0])[0]

    def march(self, u_history, state=None, v_history=None):
        u = np.ascontiguousarray(np.asarray(u_history, dtype=float)[:, :, 0])
        st = self.initial_state() if state is None else self._state(state)
        f = np.empty_like(u)
        cm_march_kernel(u, st, self.slip_force, self.slip_displacement, self.memory, f)
        return f[:, :, None], st


class RotationalMindlin(CattaneoMindlin):
    """Cattaneo–Mindlin asperities at radius ``arm`` from a joint axis, driven by a rotation.

    Paper 002 (15)–(16), (21)–(23): an asperity at distance ``r`` from the rotation axis
    slides by ``delta = r theta`` along the circle, carries the translational
    Cattaneo–Mindlin force ``T(delta)`` (tangent to the circle) and resists with the moment
    ``M = r T(r theta)``. This law is exactly that composition: (21) is ``r`` times the
    virgin curve (17) at ``delta = r theta`` and (22)–(23) are ``r`` times the Masing branches
    (18)–(19) (with the corrected exponent, see the module docstring). ``u`` is the rotation
    ``theta`` [rad] of each contact, the force is the moment [N m], the tangent
    ``r^2 dT/d delta`` [N m/rad]; the state is that of the translational law (displacements
    [m] and forces [N]).

    Parameters
    ----------
    mu, normal_load, contact_radius, compliance, multiplicity, n_contacts, memory
        As :class:`CattaneoMindlin`.
    arm : float or array_like, shape (n_contacts,)
        Distance r [m] of each asperity from the rotation axis, >= 0.
    """

    def __init__(self, mu, normal_load, contact_radius, compliance, arm, *, multiplicity=1.0,
                 n_contacts: int | None = None, memory: int = 16):
        r = broadcast_parameter("arm", arm, n_contacts, unit="m", allow_zero=True)
        if n_contacts is None:
            params = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in
                      dict(mu=mu, normal_load=normal_load, contact_radius=contact_radius,
                           compliance=compliance, multiplicity=multiplicity, arm=r).items()}
            n_contacts = common_size(**params)
        super().__init__(mu, normal_load, contact_radius, compliance,
                         multiplicity=multiplicity, n_contacts=n_contacts, memory=memory)
        self.arm = np.broadcast_to(r, (self.n_contacts,)).astype(float)
        #: gross-slip moment ``r mu N`` [N m] per contact
        self.slip_moment = self.arm * self.slip_force
        #: initial rotational stiffness ``r^2 8 a / C`` [N m/rad] per contact
        self.initial_rotational_stiffness = self.arm ** 2 * self.initial_stiffness

    def step(self, state, u, v=None) -> LawStep:
        th = self._check_u(u)[:, 0]
        f, k, st = self._step_delta(state, self.arm * th)
        return LawStep((self.arm * f)[:, None], (self.arm ** 2 * k)[:, None, None], None, st)

    def stored_energy(self, state, u) -> np.ndarray:
        return self._energy_delta(state, self.arm * self._check_u(u)[:, 0])[0]

    def march(self, u_history, state=None, v_history=None):
        th = np.asarray(u_history, dtype=float)[:, :, 0]
        u = np.ascontiguousarray(th * self.arm)
        st = self.initial_state() if state is None else self._state(state)
        f = np.empty_like(u)
        cm_march_kernel(u, st, self.slip_force, self.slip_displacement, self.memory, f)
        return (f * self.arm)[:, :, None], st
