"""Rough-surface contact: Greenwood–Williamson (1966) and paper 002's rotational joint.

Greenwood–Williamson (GW)
-------------------------
A nominally flat rough surface of nominal area ``A_n`` carries ``eta`` spherical summits of
radius ``R`` per unit area; the summit heights are Gaussian with standard deviation ``sigma``
(of the summits, not the surface Rq). Against a flat at separation ``d`` from the mean
summit height, a summit of height ``z > d`` is a Hertz contact of interference ``z - d``
(paper 002 (11)–(14))::

    N_i = (4/3) E* R^(1/2) (z - d)^(3/2),    a_i = (R (z - d))^(1/2)

and, with ``h = d / sigma`` and ``F_n(h) = int_h^inf (s - h)^n phi(s) ds``::

    P   = (4/3) eta A_n E* R^(1/2) sigma^(3/2) F_{3/2}(h)
    A_r = pi eta A_n R sigma F_1(h),     n = eta A_n F_0(h)

``F_n(h) = Gamma(n+1)/sqrt(2 pi) e^(-h^2/4) D_{-(n+1)}(h)`` (parabolic cylinder function,
``scipy.special.pbdv``). Paper 002's Table 2 also gives the mean summit height
``m = 2.45 um``: it only shifts the origin of the separation (the paper's (11) is centred on
``m``; here ``d`` is measured from the mean summit height) and enters no result.

Rotational joint (paper 002 §4, "Extended Greenwood model")
-----------------------------------------------------------
The nominal rectangle is cut into cells; every cell carries ``eta A_cell`` summits with the
GW height distribution, all at the separation ``d`` that carries the preload (a rigid,
untilted flat: uniform nominal pressure). A summit at distance ``r`` from the joint axis
under the rotation ``theta`` slides by ``r theta`` and resists with ``r T`` where ``T`` is
the Cattaneo–Mindlin law under its constant Hertz load (002 (15)–(23), see
:class:`fricdamp.contact.mindlin.RotationalMindlin`); the joint moment is the sum
(002 (24)–(25)). Paper 002 assumes summits equiprobable in angle with an affine density in
``r`` (a uniform areal density), which the cell grid reproduces.

Discretisation of the heights: the interference ``y = (z - d)/sigma`` is integrated on
``[0, Y]`` (``Y`` such that ``phi(h + Y) < 1e-16 phi(max(h, 0))``) by Gauss–Jacobi
quadrature with the weight ``y^(-1/2)``: ``int_0^Y f(y) phi(h + y) dy = sum_j p_j f(y_j)``.
With that weight the integrands of the load (``y^(3/2)``), the initial stiffness and slip
force (``a ~ y^(1/2)``, ``mu N ~ y^(3/2)``) and of the small-amplitude micro-slip energy
(``~ y^(-1/2)``) are all ``y^(-1/2)`` times an analytic function: the quadrature converges
spectrally (24 classes reproduce ``F_{3/2}``, ``F_{1/2}`` and ``F_{-1/2}`` to ~1e-12; only the
asperity count ``F_0``, which enters no force, converges algebraically). Each (cell, class)
pair is one Cattaneo–Mindlin contact of multiplicity ``eta A_cell p_j``; cells at the same
distance from the axis (the symmetric images of a centred rectangle) are merged.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.optimize import brentq
from scipy.special import gamma, pbdv, roots_genlaguerre, roots_hermitenorm, roots_jacobi

from fricdamp.contact.base import ContactLaw, LawStep
from fricdamp.contact.mindlin import (
    RotationalMindlin,
    cm_moment_march_kernel,
    effective_modulus,
    shear_modulus,
    tangential_compliance,
)
from fricdamp.errors import ModelError, as_finite_array, check_positive

_SQRT2PI = np.sqrt(2.0 * np.pi)
#: above this h the pbdv route loses accuracy (1e-9 near h = 6): use quadrature
_H_QUAD = 4.0
#: below this h the pbdv route over/underflows (inf * 0 beyond h ~ -38): Gauss–Hermite
_H_HERMITE = -10.0
_N_LAGUERRE = 30
_N_HERMITE = 60


def _gw_integral_quadrature(n: float, h: np.ndarray) -> np.ndarray:
    """F_n(h) for h >= 4 by generalised Gauss–Laguerre in u = h y (rel. error ~1e-13).

    F_n(h) = phi(h) h^-(n+1) int_0^inf u^n e^-u e^(-u^2/(2 h^2)) du.
    """
    x, w = roots_genlaguerre(_N_LAGUERRE, n)
    hh = h[:, None]
    s = np.sum(w * np.exp(-(x ** 2) / (2.0 * hh ** 2)), axis=1)
    with np.errstate(under="ignore"):
        return np.exp(-0.5 * h ** 2 - (n + 1.0) * np.log(h)) / _SQRT2PI * s


def _gw_integral_hermite(n: float, h: np.ndarray) -> np.ndarray:
    """F_n(h) for h < -10 by 60-point Gauss–Hermite over the whole Gaussian (the mass below
    h is < 1e-23, and (s - h)^n is smooth where the weight lives): rel. error ~1e-15."""
    x, w = roots_hermitenorm(_N_HERMITE)
    w = w / _SQRT2PI
    dist = x[None, :] - h[:, None]
    pos = dist > 0.0
    powd = np.zeros_like(dist)
    powd[pos] = dist[pos] ** n
    return np.sum(w * powd, axis=1)


def gw_integral(n, h):
    """Greenwood–Williamson integral ``F_n(h) = int_h^inf (s - h)^n phi(s) ds``.

    ``phi`` is the standard normal density. Uses ``F_n(h) = Gamma(n+1)/sqrt(2 pi) e^(-h^2/4)
    D_{-(n+1)}(h)`` (``scipy.special.pbdv``) for ``-10 <= h < 4``, where it is accurate to
    ~3e-11; a 30-point generalised Gauss–Laguerre quadrature for ``h >= 4``, where ``pbdv``
    loses digits (1e-9 near h = 6, 1e-5 beyond h = 13), and a 60-point Gauss–Hermite
    quadrature for ``h < -10``, where it overflows; both quadratures checked against mpmath
    (``pcfd``) to 6e-14. Underflows to 0 beyond h ~ 38.

    Parameters
    ----------
    n : float
        Order, > -1 (e.g. 0, 1/2, 1, 3/2).
    h : float or array_like
        Normalised separation d / sigma (any real; ``np.inf`` gives 0).

    Returns
    -------
    float or ndarray
        ``F_n(h)``, shape of ``h``.

    Examples
    --------
    >>> round(float(gw_integral(1.5, 0.0)), 6)
    0.43002
    """
    n = float(n)
    if not np.isfinite(n) or n <= -1.0:
        raise ModelError(f"n must be a finite order > -1, got {n!r}")
    h_arr = np.asarray(h, dtype=float)
    if np.any(np.isnan(h_arr)) or np.any(h_arr == -np.inf):
        raise ModelError(f"h must be a real number or +inf, got {h!r}")
    hf = np.atleast_1d(h_arr).ravel()
    out = np.zeros_like(hf)
    neg = hf < _H_HERMITE
    if np.any(neg):
        out[neg] = _gw_integral_hermite(n, hf[neg])
    lo = (hf >= _H_HERMITE) & (hf < _H_QUAD)
    if np.any(lo):
        d, _ = pbdv(-(n + 1.0), hf[lo])
        out[lo] = gamma(n + 1.0) / _SQRT2PI * np.exp(-0.25 * hf[lo] ** 2) * d
    hi = (hf >= _H_QUAD) & np.isfinite(hf)
    if np.any(hi):
        out[hi] = _gw_integral_quadrature(n, hf[hi])
    return float(out[0]) if h_arr.ndim == 0 else out.reshape(h_arr.shape)


@dataclasses.dataclass(frozen=True)
class GreenwoodWilliamson:
    """Greenwood–Williamson statistical contact of a rough surface on a flat.

    Parameters
    ----------
    summit_density : float
        Summits per unit nominal area eta [1/m^2], > 0.
    nominal_area : float
        Nominal contact area A_n [m^2], > 0.
    summit_radius : float
        Summit radius R [m], > 0.
    summit_std : float
        Standard deviation of the summit heights sigma [m], > 0.
    E_star : float
        Contact modulus E* [Pa], > 0 (:func:`fricdamp.contact.mindlin.effective_modulus`).

    Examples
    --------
    >>> gw = GreenwoodWilliamson(2e9, 5.04e-4, 50e-6, 0.45e-6, 115.4e9)
    >>> d = gw.separation_for_load(100.0)
    >>> round(float(gw.load(d)), 9)
    100.0
    """

    summit_density: float
    nominal_area: float
    summit_radius: float
    summit_std: float
    E_star: float

    def __post_init__(self):
        for name, unit in (("summit_density", "1/m^2"), ("nominal_area", "m^2"),
                           ("summit_radius", "m"), ("summit_std", "m"), ("E_star", "Pa")):
            v = check_positive(name, getattr(self, name), unit=unit)
            if v.ndim != 0:
                raise ModelError(f"{name} must be a scalar, got shape {v.shape}")
            object.__setattr__(self, name, float(v))

    @property
    def load_scale(self) -> float:
        """``(4/3) eta A_n E* R^(1/2) sigma^(3/2)`` [N]: the load is this times F_{3/2}(h)."""
        return (4.0 / 3.0 * self.summit_density * self.nominal_area * self.E_star
                * np.sqrt(self.summit_radius) * self.summit_std ** 1.5)

    def _h(self, separation):
        d = as_finite_array("separation", separation)
        return d / self.summit_std

    def load(self, separation):
        """Total normal load P [N] at separation d [m] (float or array, shape of d)."""
        return self.load_scale * gw_integral(1.5, self._h(separation))

    def real_area(self, separation):
        """Real contact area A_r = pi eta A_n R sigma F_1(h) [m^2] at separation d [m]."""
        return (np.pi * self.summit_density * self.nominal_area * self.summit_radius
                * self.summit_std * gw_integral(1.0, self._h(separation)))

    def n_contacts(self, separation):
        """Expected number of summits in contact eta A_n F_0(h) at separation d [m]."""
        return self.summit_density * self.nominal_area * gw_integral(0.0, self._h(separation))

    def separation_for_load(self, load):
        """Separation d [m] (from the mean summit height) at which the contact carries ``load``.

        Parameters
        ----------
        load : float or array_like
            Normal load P [N], > 0 (a GW contact carries no load only at d = +inf).

        Raises
        ------
        ModelError
            If a load is <= 0, or so small (d > 37 sigma) or so large (d < -50 sigma) that
            the separation is outside the range where the model is meaningful.
        """
        p = as_finite_array("load", load)
        if np.any(p <= 0):
            raise ModelError(f"load must be > 0 N (zero load means infinite separation), "
                             f"got {load!r}")
        with np.errstate(divide="ignore", under="ignore"):
            target = np.log(np.atleast_1d(p).ravel() / self.load_scale)
        h_hi, h_lo = 37.0, -50.0
        f_hi = np.log(gw_integral(1.5, h_hi))
        f_lo = np.log(gw_integral(1.5, h_lo))
        out = np.empty_like(target)
        for i, (t, pi) in enumerate(zip(target, np.atleast_1d(p).ravel(), strict=True)):
            if t < f_hi:
                raise ModelError(f"load {pi:g} N is too small to resolve: the separation "
                                 f"would exceed 37 summit_std")
            if t > f_lo:
                raise ModelError(f"load {pi:g} N is too large: the separation would be below "
                                 f"-50 summit_std (GW invalid)")
            out[i] = brentq(lambda x, t=t: np.log(gw_integral(1.5, x)) - t, h_lo, h_hi,
                            xtol=1e-13, maxiter=200)
        d = out * self.summit_std
        return float(d[0]) if np.ndim(load) == 0 else d.reshape(np.shape(load))


def height_classes(h: float, n_heights: int):
    """Quadrature of the GW height distribution above the flat (module docstring).

    Parameters
    ----------
    h : float
        Normalised separation d / sigma.
    n_heights : int
        Number of classes (Gauss–Jacobi nodes), >= 2.

    Returns
    -------
    y : ndarray, shape (n_heights,)
        Normalised interferences (z - d)/sigma of the classes, > 0.
    p : ndarray, shape (n_heights,)
        Probability mass of each class (fraction of all summits), so that
        ``sum p f(y) ~ int_0^inf f(y) phi(h + y) dy``.
    """
    if int(n_heights) != n_heights or n_heights < 2:
        raise ModelError(f"n_heights must be an integer >= 2, got {n_heights!r}")
    y_max = np.sqrt(max(h, 0.0) ** 2 + 2.0 * np.log(1e16)) - h
    x, w = roots_jacobi(int(n_heights), 0.0, -0.5)
    y = 0.5 * y_max * (1.0 + x)
    p = w * np.sqrt(0.5 * y_max) * np.sqrt(y) * np.exp(-0.5 * (h + y) ** 2) / _SQRT2PI
    return y, p


class RoughRotationalJoint(ContactLaw):
    """Paper 002's rotational joint: GW rough contact with Cattaneo–Mindlin summits.

    One contact, one direction: ``u`` is the relative rotation theta [rad] of the two
    plates about the joint axis, the force is the friction moment [N m]. The construction
    (cells, height classes, separation from the preload) is in the module docstring.

    Parameters
    ----------
    summit_density : float
        eta [1/m^2], > 0.
    summit_radius : float
        R [m], > 0.
    summit_std : float
        sigma [m], > 0.
    E_star : float
        Contact modulus [Pa], > 0.
    compliance : float
        Tangential compliance C = (2-nu1)/G1 + (2-nu2)/G2 [1/Pa], > 0.
    mu : float
        Friction coefficient, > 0.
    preload : float
        Normal (bolt) load [N], > 0.
    width, height : float
        Sides of the nominal rectangle [m], > 0; it is centred on the origin.
    n_cells : tuple of int, optional
        Cells along (width, height), default (28, 18).
    n_heights : int, optional
        Height classes (Gauss–Jacobi nodes), default 24.
    hole_radius : float, optional
        Cells whose centre lies closer than this to the axis are removed (a bolt hole) [m].
    axis : tuple of float, optional
        Position of the rotation axis in the rectangle's frame [m], default the centre.
    memory : int, optional
        Masing memory depth of each summit class (:class:`CattaneoMindlin`).

    Attributes
    ----------
    gw : GreenwoodWilliamson
        The GW model of the whole nominal area.
    separation : float
        Separation d [m] carrying the preload.
    asperities : RotationalMindlin
        The (radius group x height class) summit contacts; ``asperities.arm`` [m],
        ``asperities.normal_load`` [N per summit], ``asperities.multiplicity``.
    """

    n_dir = 1
    n_contacts = 1

    def __init__(self, *, summit_density, summit_radius, summit_std, E_star, compliance, mu,
                 preload, width, height, n_cells=(28, 18), n_heights=24, hole_radius=0.0,
                 axis=(0.0, 0.0), memory=16):
        w = float(check_positive("width", width, unit="m"))
        hgt = float(check_positive("height", height, unit="m"))
        c = float(check_positive("compliance", compliance, unit="1/Pa"))
        mu_v = float(check_positive("mu", mu))
        p = float(check_positive("preload", preload, unit="N"))
        hole = float(check_positive("hole_radius", hole_radius, unit="m", allow_zero=True))
        ax = as_finite_array("axis", axis, ndim=1)
        if ax.shape != (2,):
            raise ModelError(f"axis must be a pair (x, y) [m], got {axis!r}")
        nc = np.asarray(n_cells)
        if nc.shape != (2,) or np.any(nc < 1) or np.any(nc != np.round(nc)):
            raise ModelError(f"n_cells must be a pair of integers >= 1, got {n_cells!r}")
        nx, ny = int(nc[0]), int(nc[1])
        xc = -0.5 * w + (np.arange(nx) + 0.5) * w / nx
        yc = -0.5 * hgt + (np.arange(ny) + 0.5) * hgt / ny
        r = np.hypot(*np.meshgrid(xc - ax[0], yc - ax[1], indexing="ij")).ravel()
        r = r[r >= hole] if hole > 0 else r
        if r.size == 0:
            raise ModelError(f"hole_radius {hole!r} m removes every cell of the rectangle")
        self.cell_area = w * hgt / (nx * ny)
        self.cell_radius = r
        # merge cells at equal distance from the axis (symmetric images)
        r_round = np.round(r / max(w, hgt), 12)
        _, first, counts = np.unique(r_round, return_index=True, return_counts=True)
        r_group = r[first]

        self.gw = GreenwoodWilliamson(summit_density, self.cell_area * r.size, summit_radius,
                                      summit_std, E_star)
        self.preload = p
        self.separation = self.gw.separation_for_load(p)
        h = self.separation / self.gw.summit_std
        y, prob = height_classes(h, n_heights)
        interference = y * self.gw.summit_std
        n_summit = 4.0 / 3.0 * self.gw.E_star * np.sqrt(self.gw.summit_radius) \
            * interference ** 1.5  # 002 (12)
        a_summit = np.sqrt(self.gw.summit_radius * interference)  # 002 (13)
        self.interference = interference
        self.class_probability = prob
        mult = self.gw.summit_density * self.cell_area * np.outer(counts, prob)
        self.asperities = RotationalMindlin(
            mu_v, np.tile(n_summit, r_group.size), np.tile(a_summit, r_group.size), c,
            np.repeat(r_group, y.size), multiplicity=mult.ravel(), memory=memory)
        self.n_state = self.asperities.n_contacts * self.asperities.n_state

    # ----------------------------------------------------------------- summaries
    @property
    def total_normal_load(self) -> float:
        """Sum of the summit normal loads [N] (002 (24)); equals the preload up to the
        quadrature error."""
        a = self.asperities
        return float(np.sum(a.multiplicity * a.normal_load))

    @property
    def slip_moment(self) -> float:
        """Gross-slip moment ``sum r mu N`` [N m]: the largest moment the joint carries."""
        return float(np.sum(self.asperities.slip_moment))

    @property
    def initial_stiffness(self) -> float:
        """Initial rotational stiffness ``sum r^2 8 a / C`` [N m/rad]."""
        return float(np.sum(self.asperities.initial_rotational_stiffness))

    @property
    def n_summits_in_contact(self) -> float:
        """Summits in contact from the GW formula ``eta A_n F_0(h)``."""
        return float(self.gw.n_contacts(self.separation))

    # ----------------------------------------------------------------- factory
    @classmethod
    def paper_002(cls, **overrides) -> RoughRotationalJoint:
        """The lap joint of paper 002 (Bouchaala et al. 2014) with its Table 2 parameters.

        From the paper: summit height standard deviation sigma = 0.45 um, mu = 0.15 and
        E1 = E2 = 210 GPa (Table 2); nominal contact 28 x 18 mm (§2); preload 100 N (§3.4,
        §5.1). Table 2's mean height m = 2.45 um only shifts the separation origin.

        Assumed (the paper does not give them; override as needed): nu = 0.3 (steel);
        summit radius R = 50 um and density eta = 2e9 m^-2, which give the product
        eta R sigma = 0.045 of the range 0.03-0.05 Greenwood & Williamson (1966) report for
        real surfaces. With them ~1500 summits touch under 100 N at d = 2.96 sigma.

        Parameters
        ----------
        **overrides
            Any keyword of the constructor (e.g. ``preload=200.0``, ``n_cells=(14, 9)``).
        """
        E, nu = 210e9, 0.3
        g = shear_modulus(E, nu)
        params = dict(summit_density=2e9, summit_radius=50e-6, summit_std=0.45e-6,
                      E_star=float(effective_modulus(E, nu, E, nu)),
                      compliance=float(tangential_compliance(g, nu, g, nu)), mu=0.15,
                      preload=100.0, width=28e-3, height=18e-3)
        unknown = set(overrides) - set(params) - {"n_cells", "n_heights", "hole_radius",
                                                   "axis", "memory"}
        if unknown:
            raise ModelError(f"unknown parameter(s) for RoughRotationalJoint: {sorted(unknown)}")
        params.update(overrides)
        return cls(**params)

    def __repr__(self) -> str:
        return (f"RoughRotationalJoint(preload={self.preload} N, separation="
                f"{self.separation:.4g} m, slip_moment={self.slip_moment:.4g} N m, "
                f"{self.asperities.n_contacts} summit classes)")

    # ----------------------------------------------------------------- protocol
    def _split(self, state):
        a = self.asperities
        st = np.asarray(state, dtype=float)
        if st.size != self.n_state:
            raise ModelError(f"state must have shape (1, {self.n_state}), got {st.shape}")
        return st.reshape(a.n_contacts, a.n_state)

    def initial_state(self) -> np.ndarray:
        return np.zeros((1, self.n_state))

    def step(self, state, u, v=None) -> LawStep:
        th = float(self._check_u(u)[0, 0])
        a = self.asperities
        r = a.step(self._split(state), np.full((a.n_contacts, 1), th))
        return LawStep(np.array([[r.force.sum()]]), np.array([[[r.stiffness.sum()]]]), None,
                       r.state.reshape(1, -1))

    def stored_energy(self, state, u) -> np.ndarray:
        th = float(self._check_u(u)[0, 0])
        a = self.asperities
        return np.array([a.stored_energy(self._split(state), np.full((a.n_contacts, 1),
                                                                     th)).sum()])

    def march(self, u_history, state=None, v_history=None):
        th = np.ascontiguousarray(np.asarray(u_history, dtype=float)[:, 0, 0])
        a = self.asperities
        st = a.initial_state() if state is None else np.array(self._split(state), order="C")
        m = np.empty_like(th)
        cm_moment_march_kernel(th, a.arm, st, a.slip_force, a.slip_displacement, a.memory, m)
        return m[:, None, None], st.reshape(1, -1)
