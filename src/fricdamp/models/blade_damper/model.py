"""Planar blade-damper model of paper 000 (Pfeiffer & Hajek 1992): two blades, one damper.

Mechanical model (000 Fig. 2, section 2.1)::

    ground --k1,d1-- m1 (q1, platform 1) --k2,d2-- m2 (q2, blade 1)     F_E1 on m2
    ground --k3,d3-- m3 (q3, platform 2) --k4,d4-- m4 (q4, blade 2)     F_E2 on m4
    damper: mass m5, inertia I5 = m5 r_g^2, rotation q5, centre (xS, yS), F_Z along +y,
            contour eta = p1 xi^2 + p2 (or a circle) touching the platform lines at K1, K2

The generalised coordinates are those of 000 (30), ``q = (q1, q2, q3, q4, q5, xS, yS)``, with
the constant mass matrix ``diag(m1, m2, m3, m4, I5, m5, m5)``. By default the damper stays in
contact with both platforms (bilateral normal constraints, no separation, as in the paper); a
negative normal force is reported by the solver, never hidden. With ``release=True`` the
contacts are unilateral: the damper lifts off a platform when its normal force reaches zero and
re-impacts it with Newton's restitution coefficient ``restitution`` (frictionless impulses,
:mod:`fricdamp.solvers.event_impact`), so designs beyond lift-off can be computed. The contact
kinematics 000 (5)-(28) are derived symbolically in
:mod:`fricdamp.models.blade_damper._kinematics` (sympy, on first use).

The model implements :class:`fricdamp.solvers.event_system.ConstrainedSystem`, so the
event-driven solver integrates its four configurations (slip/slip 5 DOF, slip/stick and
stick/slip 4 DOF, stick/stick 3 DOF, 000 (1)-(4)) with the switching rules 000 (41)-(46).

Parameters the paper does not give are chosen for its laboratory rig (000 Figs 6-7: steel-plate
blades, a spring for the "centrifugal" force F_Z = 60/100/140 N, block angles gamma = 40-65
degrees, a damper of about 1 g) and listed in :class:`BladeDamperParameters`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from fricdamp.errors import ConvergenceError, ModelError, as_finite_array, check_positive
from fricdamp.models.blade_damper._kinematics import (
    CONTOURS,
    DOF_NAMES,
    kinematics,
    linearised_kinematics,
)
from fricdamp.solvers.event_system import ConstrainedSystem

__all__ = ["BladeDamperParameters", "BladeDamperSystem", "StaticState", "LinearSystem"]


def _four(name: str, value, unit: str, allow_zero: bool) -> tuple[float, ...]:
    arr = as_finite_array(name, value)
    if arr.shape != (4,):
        raise ModelError(f"{name} must hold 4 values (blade 1 platform, blade 1, blade 2 "
                         f"platform, blade 2) in {unit}, got {value!r}")
    check_positive(name, arr, unit=unit, allow_zero=allow_zero)
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class BladeDamperParameters:
    """Parameters of the blade-damper model, SI units (angles in rad).

    The defaults describe the laboratory rig of 000 section 3.1 (the paper gives no numbers
    besides F_Z = 60/100/140 N, gamma = 40-65 degrees and m_D of about 1 g); they are chosen to
    be physically plausible and are documented here and in the case file.

    Parameters
    ----------
    masses : tuple of 4 float
        ``(m1, m2, m3, m4)`` [kg]: platform and blade masses of blades 1 and 2. Default
        ``(0.30, 0.15, 0.30, 0.165)``: a two-mass reduction of a clamped steel plate with its
        supporting block at about mid-height, whose first bending mode (50 Hz) moves the
        platform by 0.29 of the tip. The two blades of the default rig are not identical
        (blade 2 is 10 % heavier and its springs 13-20 % stiffer, so that its first mode is
        3.5 % higher): with identical blades the in-phase modes of the stuck system load the
        damper only through its own 1 g inertia, and their pull-off dips vanish.
    stiffnesses : tuple of 4 float
        ``(k1, k2, k3, k4)`` [N/m]: ground-platform (k1, k3) and platform-blade (k2, k4)
        springs. Default ``(7.2e4, 2.3e4, 8.6e4, 2.6e4)``: stuck modes at 51.1, 62.7 and
        100.3 Hz; free-sliding modes at 50.1, 51.9, 96.9 and 103.6 Hz (and the damper's
        rocking at 784 Hz).
    dampings : tuple of 4 float
        ``(d1, d2, d3, d4)`` [N s/m] dashpots parallel to the springs (material and joint
        damping of the plates and their clamps). Default ``(2.9, 1.2, 3.2, 1.3)``: about 1 %
        modal damping.
    damper_mass : float
        ``m5`` [kg], > 0. Default 1 g (000 Fig. 12).
    damper_gyration_radius : float
        ``r_g`` [m], > 0: ``I5 = m5 r_g^2`` (a thin parabolic steel sheet of 12 mm width:
        about 4 mm). Scaling the mass keeps the shape, so I5 scales with it.
    gamma : float
        Block angle [rad] in (0, pi/2): the platform lines have slope +-cot(gamma)
        (000 (11)-(12)); larger gamma means flatter platforms. Default 50 degrees.
    p1 : float
        Parabola coefficient [1/m], < 0 (000 (10)); for the circular contour the radius is
        ``R = -1/(2 p1)`` (same apex curvature). Default -80 1/m (a flat parabola).
    p2 : float
        Apex height of the contour above the damper's centre of mass [m], > 0. Default 2 mm.
    contour : {"parabola", "circle"}
        Damper contour shape.
    mu_static, mu_sliding : float
        Static and sliding friction coefficients [-], ``0 <= mu_sliding <= mu_static``
        (dry steel on steel: 0.35 and 0.30 by default).
    centrifugal_force : float
        ``F_Z`` [N], > 0, pressing the damper outwards (+y). Default 100 N.
    excitation_amplitude : float
        Amplitude ``F_e`` [N] of ``F_E1 = F_e cos(Omega t)`` on m2, >= 0.
    excitation_ratio : float
        ``F_E2 = ratio F_e cos(Omega t + phase)`` on m4; ratio >= 0 [-]. Default 1.
    excitation_phase : float
        Phase of F_E2 relative to F_E1 [rad] (set by the phase shifter of the rig, 000 Fig. 7).
        Default pi/2, which excites all three stuck modes.
    excitation_frequency : float
        ``f_e = Omega / (2 pi)`` [Hz], > 0.

    Raises
    ------
    ModelError
        For any value outside its range, naming the parameter and the range.
    """

    masses: tuple[float, float, float, float] = (0.30, 0.15, 0.30, 0.165)
    stiffnesses: tuple[float, float, float, float] = (7.2e4, 2.3e4, 8.6e4, 2.6e4)
    dampings: tuple[float, float, float, float] = (2.9, 1.2, 3.2, 1.3)
    damper_mass: float = 1.0e-3
    damper_gyration_radius: float = 4.0e-3
    gamma: float = float(np.deg2rad(50.0))
    p1: float = -80.0
    p2: float = 2.0e-3
    contour: str = "parabola"
    mu_static: float = 0.35
    mu_sliding: float = 0.30
    centrifugal_force: float = 100.0
    excitation_amplitude: float = 1.0
    excitation_ratio: float = 1.0
    excitation_phase: float = float(np.pi / 2)
    excitation_frequency: float = 60.0

    def __post_init__(self):
        object.__setattr__(self, "masses", _four("masses", self.masses, "kg", False))
        object.__setattr__(self, "stiffnesses",
                           _four("stiffnesses", self.stiffnesses, "N/m", False))
        object.__setattr__(self, "dampings", _four("dampings", self.dampings, "N s/m", True))
        for name, unit, zero in (("damper_mass", "kg", False), ("damper_gyration_radius", "m",
                                 False), ("p2", "m", False), ("centrifugal_force", "N", False),
                                 ("excitation_amplitude", "N", True), ("excitation_ratio", "-",
                                 True), ("excitation_frequency", "Hz", False),
                                 ("mu_static", "-", True), ("mu_sliding", "-", True)):
            check_positive(name, getattr(self, name), unit=unit, allow_zero=zero)
            object.__setattr__(self, name, float(getattr(self, name)))
        g = float(as_finite_array("gamma", self.gamma))
        if not 0.0 < g < np.pi / 2:
            raise ModelError(f"gamma must lie in (0, pi/2) rad, i.e. (0, 90) degrees, got {g!r} "
                             f"rad ({np.rad2deg(g):.6g} degrees)")
        object.__setattr__(self, "gamma", g)
        p1 = float(as_finite_array("p1", self.p1))
        if not p1 < 0:
            raise ModelError(f"p1 must be < 0 1/m (the contour eta = p1 xi^2 + p2 is a cap "
                             f"whose apex faces the platforms, 000 (10)), got {p1!r}")
        object.__setattr__(self, "p1", p1)
        object.__setattr__(self, "excitation_phase",
                           float(as_finite_array("excitation_phase", self.excitation_phase)))
        if self.contour not in CONTOURS:
            raise ModelError(f"contour must be one of {CONTOURS}, got {self.contour!r}")
        if self.mu_sliding > self.mu_static:
            raise ModelError(f"mu_sliding must not exceed mu_static (0 <= mu_sliding <= "
                             f"mu_static), got mu_sliding={self.mu_sliding!r} > "
                             f"mu_static={self.mu_static!r}")

    # ------------------------------------------------------------------ derived
    @property
    def gamma_deg(self) -> float:
        """Block angle [degrees] (rounded to 10 decimals: 60, not 59.99999999999999)."""
        return round(float(np.rad2deg(self.gamma)), 10)

    @property
    def damper_inertia(self) -> float:
        """``I5 = m5 r_g^2`` [kg m^2]."""
        return self.damper_mass * self.damper_gyration_radius**2

    @property
    def omega(self) -> float:
        """Excitation circular frequency ``Omega = 2 pi f_e`` [rad/s]."""
        return 2.0 * np.pi * self.excitation_frequency

    def with_(self, **changes) -> BladeDamperParameters:
        """Copy with some fields changed (validated again); ``gamma_deg`` is accepted too."""
        if "gamma_deg" in changes:
            changes["gamma"] = float(np.deg2rad(changes.pop("gamma_deg")))
        return replace(self, **changes)


@dataclass(frozen=True)
class StaticState:
    """Frictionless static equilibrium under F_Z (no excitation).

    Attributes
    ----------
    q : ndarray, shape (7,)
        Coordinates [m, rad] (000 (30) order).
    normal_force : ndarray, shape (2,)
        Normal contact forces ``lambda_N`` [N] at K1, K2 (compressive > 0).
    """

    q: np.ndarray
    normal_force: np.ndarray


@dataclass(frozen=True)
class LinearSystem:
    """Linear(ised) system ``M z'' + D z' + K z = T^T F(t)`` in reduced coordinates z.

    Attributes
    ----------
    M, D, K : ndarray, shape (n, n)
        Mass [kg or kg m^2], damping and stiffness matrices.
    T : ndarray, shape (7, n)
        Map from the reduced coordinates to the full ones, ``dq = T dz``.
    names : tuple of str
        Names of the reduced coordinates.
    """

    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    T: np.ndarray
    names: tuple[str, ...]

    def eigenfrequencies(self) -> np.ndarray:
        """Undamped eigenfrequencies [Hz], ascending; NaN marks an unstable (K < 0) mode."""
        import scipy.linalg as sla

        lam = sla.eigh(self.K, self.M, eigvals_only=True)
        with np.errstate(invalid="ignore"):
            f = np.where(lam >= 0, np.sqrt(np.abs(lam)), np.nan) / (2 * np.pi)
        return np.sort(f)


@dataclass(frozen=True, eq=False)
class BladeDamperSystem(ConstrainedSystem):
    """The paper-000 blade-damper model as a :class:`ConstrainedSystem` (7 coordinates).

    Parameters
    ----------
    params : BladeDamperParameters
        Model parameters.
    compiled : bool
        Integrate DOP853 phases with the compiled kernels of
        :mod:`fricdamp.models.blade_damper._compiled` (default; generated from the sympy
        kinematics on first use and cached on disk). False: the generic path through the
        lambdified kinematics (the reference; 20-40 times slower).
    compiled_phases : bool
        With ``compiled``: take whole DOP853 steps, their dense output and the event
        screening in compiled code too (default; the same step-size control and event
        samples as SciPy's DOP853). False: SciPy's DOP853 calls the compiled right-hand side
        (the path before, kept for comparisons; about 3-10 times slower).
    release : bool
        Let the damper lift off the platforms and re-impact them (unilateral normal contacts;
        default False: bilateral, the paper's no-separation model). The compiled kernels
        know open contacts: the DOP853 phases with their gap events, and the compiled
        event loop takes the lift-offs and impacts too.
    restitution : float
        Newton's restitution coefficient ``e`` in [0, 1] of the damper-platform impacts
        (with ``release``; default 0: plastic impacts, the damper stays on the platform it
        hits when the contact force is compressive).
    compiled_loop : bool
        With ``compiled_phases``: the event solver takes whole runs of phases and switches
        in the compiled event loop (:mod:`fricdamp.models.blade_damper._fastloop`; default),
        leaving to its Python loop only what the kernel would not do identically (an
        ambiguous switch, a singular constraint system, chattering, ...). False: the Python
        loop for every event (the reference for the compiled loop).

    Examples
    --------
    >>> sys = BladeDamperSystem(BladeDamperParameters())
    >>> st = sys.static_equilibrium()
    >>> bool(np.allclose(st.normal_force, 100.0 / (2 * np.sin(sys.params.gamma))))
    True
    """

    params: BladeDamperParameters = field(default_factory=BladeDamperParameters)
    compiled: bool = True
    compiled_phases: bool = True
    release: bool = False
    restitution: float = 0.0
    compiled_loop: bool = True
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    n_dof = 7
    n_contacts = 2
    constant_mass = True

    def __post_init__(self):
        if not isinstance(self.params, BladeDamperParameters):
            raise ModelError(f"params must be BladeDamperParameters, got "
                             f"{type(self.params).__name__}")
        e = self.restitution
        if not (isinstance(e, (int, float, np.floating)) and np.isfinite(e) and 0 <= e <= 1):
            raise ModelError(f"restitution must be a number in [0, 1], got {e!r}")
        object.__setattr__(self, "restitution", float(e))
        object.__setattr__(self, "release", bool(self.release))
        p = self.params
        m1, m2, m3, m4 = p.masses
        k1, k2, k3, k4 = p.stiffnesses
        d1, d2, d3, d4 = p.dampings
        c = self._cache
        c["M"] = np.diag([m1, m2, m3, m4, p.damper_inertia, p.damper_mass, p.damper_mass])
        c["Minv"] = 1.0 / np.diag(c["M"])

        def chain(a, b):
            K = np.zeros((7, 7))
            K[0, 0] = a + b
            K[0, 1] = K[1, 0] = -b
            K[1, 1] = b
            return K

        def two(a1, b1, a2, b2):
            K = chain(a1, b1)
            K2 = chain(a2, b2)
            P = np.zeros((7, 7))
            P[[2, 2, 3, 3], [2, 3, 2, 3]] = K2[[0, 0, 1, 1], [0, 1, 0, 1]]
            return K + P

        c["K"] = two(k1, k2, k3, k4)
        c["D"] = two(d1, d2, d3, d4)
        F0 = np.zeros(7)
        F0[6] = p.centrifugal_force
        c["F0"] = F0
        c["kin"] = kinematics(p.contour)
        c["geo"] = (p.gamma, p.p1, p.p2)
        self.check()

    # ------------------------------------------------------------------ protocol
    @property
    def mu_static(self) -> np.ndarray:  # type: ignore[override]
        return np.full(2, self.params.mu_static)

    @property
    def mu_sliding(self) -> np.ndarray:  # type: ignore[override]
        return np.full(2, self.params.mu_sliding)

    @property
    def normal_constrained(self) -> np.ndarray:  # type: ignore[override]
        return np.ones(2, dtype=bool)

    def unilateral_contacts(self) -> np.ndarray:
        """Both contacts may lift off when ``release`` (else none)."""
        return np.full(2, self.release)

    def restitution_coefficients(self) -> np.ndarray:
        """``restitution`` at both contacts."""
        return np.full(2, self.restitution)

    @property
    def dof_names(self) -> tuple[str, ...]:
        return DOF_NAMES

    @property
    def contact_names(self) -> tuple[str, ...]:
        return ("K1", "K2")

    @property
    def M(self) -> np.ndarray:
        """Mass matrix (7, 7) [kg, kg m^2]."""
        return self._cache["M"]

    @property
    def K(self) -> np.ndarray:
        """Stiffness matrix of the blade springs (7, 7) [N/m]."""
        return self._cache["K"]

    @property
    def D(self) -> np.ndarray:
        """Damping matrix of the blade dashpots (7, 7) [N s/m]."""
        return self._cache["D"]

    def mass(self, q):
        return self._cache["M"]

    def max_frequency(self) -> float:
        """Excitation circular frequency ``Omega`` [rad/s]: the only explicit time dependence
        of :meth:`h` (DOP853 phases step at most a quarter of its half period)."""
        return float(self.params.omega)

    def compiled_kernels(self):
        """:class:`~fricdamp.models.blade_damper._compiled.BladeDamperKernels` (None when
        ``compiled`` is False)."""
        if not self.compiled:
            return None
        if "kernels" not in self._cache:
            from fricdamp.models.blade_damper._compiled import BladeDamperKernels

            self._cache["kernels"] = BladeDamperKernels(self)
        return self._cache["kernels"]

    def excitation(self, t) -> np.ndarray:
        """Excitation forces F_E1 (on q2) and F_E2 (on q4) [N], shape (7,) or (7, n_t)."""
        p = self.params
        t = np.asarray(t, dtype=float)
        wt = p.omega * t
        F = np.zeros((7,) + t.shape)
        F[1] = p.excitation_amplitude * np.cos(wt)
        F[3] = p.excitation_amplitude * p.excitation_ratio * np.cos(wt + p.excitation_phase)
        return F

    def excitation_phasor(self) -> np.ndarray:
        """Complex amplitude ``F_hat`` (7,) [N] with ``F_E(t) = Re(F_hat exp(i Omega t))``."""
        p = self.params
        F = np.zeros(7, dtype=complex)
        F[1] = p.excitation_amplitude
        F[3] = p.excitation_amplitude * p.excitation_ratio * np.exp(1j * p.excitation_phase)
        return F

    def h(self, t, q, qd):
        c = self._cache
        return c["F0"] + self.excitation(t) - c["K"] @ q - c["D"] @ qd

    def _terms(self, q, u5=0.0):
        return self._cache["kin"].terms(q[0], q[2], q[4], q[5], q[6], u5, *self._cache["geo"])

    def _kin(self, q, u5=0.0):
        """``(gap, W_N, W_T, wbar_N, wbar_T)``: compiled when ``compiled``, else lambdified."""
        ck = self.compiled_kernels()
        if ck is None:
            return self._terms(q, u5)[:5]
        return ck.kinematics(q, u5)

    def kinematics(self, q, qd):
        _, WN, WT, wN, wT = self._kin(q, qd[4])
        return WN, WT, wN, wT

    def normal_gap(self, q):
        return self._kin(q)[0]

    def normal_jacobian(self, q):
        return self._kin(q)[1]

    def normal_wbar(self, q, qd):
        return self._kin(q, qd[4])[3]

    def tangent_jacobian(self, q):
        return self._kin(q)[2]

    def tangent_wbar(self, q, qd):
        return self._kin(q, qd[4])[4]

    def contact_points(self, q) -> np.ndarray:
        """Contact points K1, K2 in frame 0 [m], shape (2, 2) (row i: x, y of K_i+1)."""
        return np.asarray(q[5:7]) + self._terms(q)[5]

    # ------------------------------------------------------------------ energy hooks
    def potential_energy(self, q):
        """Spring energy plus the potential ``-F_Z yS`` of the centrifugal force [J]."""
        return 0.5 * float(q @ (self._cache["K"] @ q)) - self.params.centrifugal_force * q[6]

    def input_power(self, t, q, qd):
        """Power of the excitation forces F_E1, F_E2 [W]."""
        return float(self.excitation(t) @ qd)

    def viscous_power(self, t, q, qd):
        return float(qd @ (self._cache["D"] @ qd))

    def mechanical_energy_many(self, q, qd):
        """Kinetic and potential energy [J] of the rows of q, qd (n_t, 7) (the vectorised
        form of :meth:`kinetic_energy` and :meth:`potential_energy`)."""
        q = np.asarray(q, dtype=float)
        qd = np.asarray(qd, dtype=float)
        kin = 0.5 * (qd * qd) @ np.diag(self._cache["M"])
        pot = 0.5 * np.einsum("ti,ij,tj->t", q, self._cache["K"], q) \
            - self.params.centrifugal_force * q[:, 6]
        return kin, pot

    def kinetic_energy(self, qd) -> float:
        """``0.5 q'^T M q'`` [J]."""
        return 0.5 * float(qd @ (self._cache["M"] @ qd))

    # ------------------------------------------------------------------ reduced geometry
    def damper_centre(self, q1, q3, q5):
        """Closed-form damper centre and its derivatives, 000 (13)-(15).

        Returns
        -------
        r_S : ndarray (2,) [m]; J : ndarray (2, 3); H : ndarray (2, 3, 3)
            ``(xS, yS)`` keeping both contacts closed, and its first and second derivatives
            with respect to ``(q1, q3, q5)``.
        """
        return self._cache["kin"].reduced(q1, q3, q5, *self._cache["geo"])

    def full_state(self, z, zd=None):
        """Full coordinates from the independent ones ``z = (q1, q2, q3, q4, q5)``.

        Parameters
        ----------
        z : array_like, shape (5,)
        zd : array_like, shape (5,), optional
            Velocities of z.

        Returns
        -------
        q : ndarray, shape (7,); qd : ndarray, shape (7,) (zeros if zd is None)
            A state with closed contacts (``g_N = 0``, ``g_N' = 0``).
        """
        z = np.asarray(z, dtype=float)
        rS, J, _ = self.damper_centre(z[0], z[2], z[4])
        q = np.concatenate([z, rS])
        qd = np.zeros(7)
        if zd is not None:
            zd = np.asarray(zd, dtype=float)
            qd = np.concatenate([zd, J @ zd[[0, 2, 4]]])
        return q, qd

    def slip_velocity(self, q, qd) -> np.ndarray:
        """Relative tangential velocities ``gamma_T`` (2,) [m/s], 000 (25)-(28)."""
        return self.tangent_jacobian(q).T @ qd

    def linearised_kinematics(self) -> dict:
        """The paper's linearised forms at q = 0 (see
        :func:`fricdamp.models.blade_damper._kinematics.linearised_kinematics`)."""
        p = self.params
        return linearised_kinematics(p.contour, p.gamma, p.p1, p.p2)

    # ------------------------------------------------------------------ statics
    def static_equilibrium(self, *, tol: float = 1e-12, max_iter: int = 50) -> StaticState:
        """Frictionless static equilibrium under F_Z (Newton on the reduced potential).

        ``V(z) = 0.5 z^T K z - F_Z yS(z)`` with the closed-form ``yS(q1, q3, q5)``; the
        tangential contact forces are zero there (symmetric damper), so the same state is an
        equilibrium with friction. Normal forces from ``W_N lambda_N = -h``.

        Raises
        ------
        ConvergenceError
            If Newton does not converge (e.g. an unstable damper, see
            :meth:`sliding_system`).
        """
        if "static" in self._cache:
            return self._cache["static"]
        p = self.params
        K5 = self._cache["K"][:5, :5]
        idx = [0, 2, 4]
        z = np.zeros(5)
        for _ in range(max_iter):
            _, J, H = self.damper_centre(z[0], z[2], z[4])
            grad = K5 @ z
            grad[idx] -= p.centrifugal_force * J[1]
            if np.max(np.abs(grad)) <= tol * p.centrifugal_force:
                break
            hess = K5.copy()
            hess[np.ix_(idx, idx)] -= p.centrifugal_force * H[1]
            z = z - np.linalg.solve(hess, grad)
        else:
            raise ConvergenceError(
                f"static equilibrium under F_Z = {p.centrifugal_force} N not found in "
                f"{max_iter} Newton steps (residual {np.max(np.abs(grad)):.3g} N); is the "
                "damper stable (see sliding_system().eigenfrequencies())?")
        q, _ = self.full_state(z)
        WN = self.normal_jacobian(q)
        h_static = self._cache["F0"] - self._cache["K"] @ q
        lamN = np.linalg.lstsq(WN, -h_static, rcond=None)[0]
        st = StaticState(q=q, normal_force=lamN)
        self._cache["static"] = st
        return st

    # ------------------------------------------------------------------ linear systems
    def stuck_system(self) -> LinearSystem:
        """The fully stuck system, 3 DOF ``z = (u, q2, q4)``, 000 (4), (22).

        With both contacts stuck, ``q1' = q3' = xS' = u'`` and ``q5' = yS' = 0``: platforms and
        damper move as one mass ``m1 + m3 + m5``. This parametrisation is exact (the gaps are
        invariant to a common horizontal translation), so the stuck system is linear and
        does not depend on gamma, the contour or F_Z.
        """
        T = np.zeros((7, 3))
        T[[0, 2, 5], 0] = 1.0
        T[1, 1] = 1.0
        T[3, 2] = 1.0
        c = self._cache
        return LinearSystem(M=T.T @ c["M"] @ T, D=T.T @ c["D"] @ T, K=T.T @ c["K"] @ T, T=T,
                            names=("u", "q2", "q4"))

    def sliding_system(self) -> LinearSystem:
        """Frictionless (free-sliding) linearisation at the static equilibrium, 5 DOF.

        Reduced coordinates ``z = (q1, q2, q3, q4, q5)``; ``(xS, yS)`` follow from the
        closed-form constraint solution. ``M = J^T M7 J`` and ``K = K_springs - F_Z d2yS/dz2``:
        the second-order kinematics turn the centrifugal force into the stiffness of the
        damper's rocking (and a coupling to the platforms).
        """
        st = self.static_equilibrium()
        q = st.q
        p = self.params
        _, J, H = self.damper_centre(q[0], q[2], q[4])
        idx = [0, 2, 4]
        T = np.zeros((7, 5))
        T[:5, :5] = np.eye(5)
        T[5:, idx] = J
        c = self._cache
        K = T[:5, :5].T @ c["K"][:5, :5] @ T[:5, :5]
        K[np.ix_(idx, idx)] -= p.centrifugal_force * H[1]
        return LinearSystem(M=T.T @ c["M"] @ T, D=T.T @ c["D"] @ T, K=K, T=T,
                            names=("q1", "q2", "q3", "q4", "q5"))
