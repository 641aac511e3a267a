"""Two rotating shrouded blades with a wedge friction element between the shrouds, paper 001.

Frames and coordinates (001 Fig. 1, section 2)
----------------------------------------------
The wheel spins at Omega [rad/s] about the axial axis y through the origin. The global
rotating frame has x radial through the centre D of the friction element, y axial and
z = x cross y tangential; the wheel turns towards -z. Blade j is radial at the angle
``alpha_j`` about y (``x_j = R_y(alpha_j) x``), ``alpha_1 = -delta/2`` (blade 1 on the +z side,
trailing), ``alpha_2 = +delta/2`` (blade 2, leading), delta = 2 pi / n_blades the pitch
angle. As in 001 (1), each blade's DOFs ``(u, v, w, phi, theta, psi)`` are in its own frame
(x_j along the blade, y_j = y, z_j tangential); a rotation about the spin axis leaves the
rotating-frame matrices unchanged, so both blades share the matrices of one blade
(001 (9): ``M = diag(M_B, M_D, M_B)``), and ``q = [q_1, q_D, q_2]`` (001 (7)), 78 DOFs.

Blades (001 (2)): 3D Rayleigh beams (:mod:`fricdamp.structure.beam3d`) with material
damping ``B_B = beta K_s``, spin softening, stress stiffening, gyroscopic terms and
centrifugal load; the rigid shroud is a rigid body at the tip node C_j. The paper counts
six free nodes per blade (2 x 36 + 6 = 78 DOFs): here the blade root node is held by the
rigid disk through a short stiff root element (dovetail), clamped at the rim, so all six
blade nodes are free. The friction element is a rigid body (001 (5),
:func:`~fricdamp.structure.beam3d_rotation.rigid_body_terms`).

Contacts (001 (12)-(20)): point A joins blade 2's shroud to plane a of the wedge, point B
joins blade 1's shroud to plane b. In the global frame the normals pointing from the shroud
into the wedge and the in-plane tangents are::

    n_A = (-sin d_a, 0,  cos d_a)    xi_A = (cos d_a, 0,  sin d_a)    eta = (0, 1, 0)
    n_B = (-sin d_b, 0, -cos d_b)    xi_B = (cos d_b, 0, -sin d_b)

(d_x the angle of plane x to the radial direction, 001 (14), (20)). The relative
displacement of the contact point, shroud minus wedge, is
``R_j [E, -S(r_Cj,X)] q_Cj - [E, -S(r_D,X)] q_D`` (001 (13), (19); S the cross-product
matrix, ``R^T`` of the paper) and the relative rotation ``R_j phi_j - phi_D`` (001 (15),
(16)). Expressed in blade j's own frame, the plane angles are ``d_A = d_a + delta/2`` and
``d_B = d_b + delta/2`` (:attr:`BladePairModel.contact_angles`), so one set of vectors
gives the paper's four angles consistently. The deformation energy 001 (12) with the
rotational stiffnesses 001 (17) gives ``K_C`` (001 (18)); contact damping ``B_C = beta_C K_C``.
Only the normal direction and the rotations about the in-plane axes are elastic (as in
001 (12)); the tangential slip and the rotation about the normal carry friction only.

Normal loads (001 (6)), derived again: the wedge, pushed outward by ``F = m_D r_D Omega^2``,
is held by ``N_A n_A + N_B n_B + F x = 0``, whence::

    N_A = F cos d_b / sin(d_a + d_b),   N_B = F cos d_a / sin(d_a + d_b)

(the extracted 001 (6) reads ``cos d_X``; both agree for a symmetric wedge, and the force
balance -- tested -- fixes the general case: each load balances the tangential component
of the other).

Excitation (001 (3), (10), (11), Table 1): ``F_ax`` along y_j and ``-F_t`` along z_j at every
blade node, harmonic at ``w_k = k Omega``, blade 2 leading blade 1 by the phase ``k delta``
(``cos w_k (t + delta/Omega)``); the amplitudes of Table 1 for k = 15, 20, 30, otherwise
``F^(k) = F^(1)/k``.

Parameters the paper does not give (geometry and material of its blades, 001 ref. [17])
are chosen for a plausible steam-turbine stage and documented in
:class:`BladePairParameters`; they put the first coupled frequencies near 195 Hz, so the
resonances with 15, 20 and 30 Omega fall between about 400 and 2000 rpm, as the paper's
Campbell diagrams and resonance speeds (390, 595 rpm) imply.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np

from fricdamp.contact.equivalent import (  # JenkinsEllipseDamping: re-exported, it lived here
    EllipseFrictionDamping,
    JenkinsEllipseDamping,
    rectangle_mean_radius,
    rectangle_twist_stiffness,
)
from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.structure.beam3d import BeamModel, BeamSection, beam_model
from fricdamp.structure.beam3d_rotation import RigidBodyTerms, rigid_body_terms, skew
from fricdamp.structure.system import HarmonicLoad, MechanicalSystem

__all__ = [
    "TABLE_1",
    "BladePairModel",
    "BladePairParameters",
    "build_blade_pair",
    "rpm_to_rad_s",
]

#: 001 Table 1: excitation order k -> (F_t [N], F_ax [N]) per blade node.
TABLE_1: dict[int, tuple[float, float]] = {15: (1.33, 0.66), 20: (1.0, 0.5), 30: (0.63, 0.3)}

#: Contact names in the order used everywhere (A: blade 2 - plane a, B: blade 1 - plane b).
CONTACTS = ("A", "B")
#: Rows of a contact in :attr:`BladePairModel.contact_projection`.
CONTACT_ROWS = ("normal", "xi", "eta", "rot_xi", "rot_eta", "rot_normal")


def rpm_to_rad_s(rpm) -> np.ndarray:
    """Spin speed [rpm] -> [rad/s]."""
    return np.asarray(rpm, float) * np.pi / 30.0


def _rot_y(alpha: float) -> np.ndarray:
    c, s = np.cos(alpha), np.sin(alpha)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _pair(name: str, value, unit: str, allow_zero: bool = False) -> tuple[float, float]:
    arr = np.broadcast_to(as_finite_array(name, value), (2,)) if np.ndim(value) == 0 else (
        as_finite_array(name, value))
    if arr.shape != (2,):
        raise ModelError(f"{name} must be one value or a pair (contact A, contact B) [{unit}], "
                         f"got {value!r}")
    check_positive(name, arr, unit=unit, allow_zero=allow_zero)
    return float(arr[0]), float(arr[1])


def _triple(name: str, value) -> tuple[float, float, float]:
    arr = as_finite_array(name, value)
    if arr.shape != (3,):
        raise ModelError(f"{name} must hold 3 principal moments of inertia [kg m^2] along "
                         f"(x, y, z), got {value!r}")
    check_positive(name, arr, unit="kg m^2")
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class BladePairParameters:
    """Parameters of the two-blade model of 001, SI units, angles in rad.

    The paper gives the model and Table 1 but not its blades (001 ref. [17]); the defaults
    describe a plausible shrouded steam-turbine blade of 12 % Cr steel, with a first coupled
    frequency near 195 Hz (001: first resonances with 30 Omega at 390 rpm and 20 Omega at
    595 rpm).

    Parameters
    ----------
    hub_radius : float
        Radius of the blade root node [m]. Default 0.40.
    blade_length : float
        Root node to tip (shroud) node [m]. Default 0.20 (tip radius 0.60 m).
    n_elements : int
        Beam elements per blade (001: 5, so 6 nodes and 78 DOFs in all).
    chord, thickness : float
        Rectangular blade section [m]: chord along the stagger direction, thickness across
        it. Default 30 mm x 11 mm.
    stagger : float
        Angle of the chord from the axial direction y towards z [rad], in [0, pi/2].
        Default 35 degrees: the weak bending couples axial and tangential motion.
    youngs_modulus, density, poisson : float
        X20Cr13 steel: 2.16e11 Pa, 7700 kg/m^3, 0.3.
    blade_damping : float
        Stiffness-proportional material damping ``B_B = beta K_s`` [s], >= 0. Default 2e-6 s
        (0.12 % of critical at 195 Hz).
    root_length, root_chord, root_thickness : float
        The root (dovetail) element between the rigid disk rim and the blade root node
        [m]. Default 20 mm, 40 mm x 30 mm.
    shroud_mass : float
        Rigid shroud at the tip node [kg]. Default 0.07.
    shroud_inertia : (3,) float
        Principal moments of inertia of the shroud about the tip node along the blade's
        (x, y, z) [kg m^2]. Default for a 50 x 40 x 6 mm block.
    n_blades : int
        Blades on the wheel, >= 3: pitch angle ``delta = 2 pi / n_blades``. Default 60.
    damper_mass : float
        Friction element m_D [kg]. Default 0.015 (a steel wedge about 20 x 12 x 10 mm).
    damper_inertia : (3,) float
        Its principal moments of inertia about D along (x, y, z) [kg m^2].
    damper_radius : float
        r_D, radius of D [m], between the hub and the tip radius plus a shroud height.
        Default 0.595.
    contact_points : ((x_A, z_A), (x_B, z_B))
        Contact points A and B in the wedge frame, from D [m]; z_A < 0 < z_B (A towards
        blade 2), within the blade pitch. Default ((3, -6), (3, 6)) mm.
    delta_a, delta_b : float
        Angles of the contact planes a, b to the radial direction [rad], in (0, pi/2).
        Default 45 and 30 degrees (plane a steeper, so N_A > N_B, as 001 section 4.2
        describes).
    contact_stiffness : float or (2,) float
        Linearised normal contact stiffness k_A, k_B [N/m]. Default 2e8.
    contact_width : float or (2,) float
        Side of the effective contact rectangle along xi (a_ef, b_ef) [m]. Default 8 mm.
    contact_height : float or (2,) float
        Side along eta (h_a,ef, h_b,ef) [m]. Default 20 mm. 001 (17):
        ``k_xixi = k h^2/12``, ``k_etaeta = k a^2/12``.
    contact_damping : float
        beta_C of ``B_C = beta_C K_C`` [s], >= 0. Default 5e-6.
    friction_coefficient : float or (2,) float
        f_a, f_b [-], >= 0. Default 0.1.
    friction_exponent : float
        p of 001 (27), (32), > 0. Default 1 (Coulomb).
    damping_rule : {"coulomb", "paper"}
        Equivalent damping along the ellipse axes (:mod:`fricdamp.contact.equivalent`).
    tangential_force_order1, axial_force_order1 : float
        ``F_t^(1)``, ``F_ax^(1)`` [N] per node for orders not in Table 1:
        ``F^(k) = F^(1)/k``. Default 20 and 10 N (Table 1 times k).
    excitation_table : tuple of (k, F_t, F_ax)
        Explicit amplitudes per node [N]; default 001 Table 1.
    min_slip : float
        Slip amplitude [m] below which a contact counts as stuck (floor of the equivalent
        damping; rotations are floored at ``min_slip / rho``). Default 1 nm: well below the
        elastic tangential compliance of real contacts (``f N / k_t`` ~ 10-100 nm), which
        this Coulomb model without tangential stiffness does not resolve anyway. A stuck
        contact is reported with zero slip and zero dissipation, never with the floor.
    tangential_stiffness : float or None
        Stick stiffness k_t [N/m] of the contacts in the equivalent-damping law (a Jenkins
        element, :class:`JenkinsEllipseDamping`: a stuck contact acts as a spring), > 0;
        None (default) for the paper's law, friction as a damper only.

    Raises
    ------
    ModelError
        Any value outside its range, naming the parameter and the range.
    """

    hub_radius: float = 0.40
    blade_length: float = 0.20
    n_elements: int = 5
    chord: float = 0.030
    thickness: float = 0.011
    stagger: float = float(np.deg2rad(35.0))
    youngs_modulus: float = 2.16e11
    density: float = 7700.0
    poisson: float = 0.3
    blade_damping: float = 2.0e-6
    root_length: float = 0.020
    root_chord: float = 0.040
    root_thickness: float = 0.030
    shroud_mass: float = 0.07
    shroud_inertia: tuple[float, float, float] = (1.1e-5, 1.5e-5, 2.4e-5)
    n_blades: int = 60
    damper_mass: float = 0.015
    damper_inertia: tuple[float, float, float] = (3.1e-7, 2.6e-7, 6.8e-7)
    damper_radius: float = 0.595
    contact_points: tuple[tuple[float, float], tuple[float, float]] = (
        (0.003, -0.006), (0.003, 0.006))
    delta_a: float = float(np.deg2rad(45.0))
    delta_b: float = float(np.deg2rad(30.0))
    contact_stiffness: float | tuple[float, float] = 2.0e8
    contact_width: float | tuple[float, float] = 0.008
    contact_height: float | tuple[float, float] = 0.020
    contact_damping: float = 5.0e-6
    friction_coefficient: float | tuple[float, float] = 0.1
    friction_exponent: float = 1.0
    damping_rule: str = "coulomb"
    tangential_force_order1: float = 20.0
    axial_force_order1: float = 10.0
    excitation_table: tuple[tuple[int, float, float], ...] = tuple(
        (k, ft, fa) for k, (ft, fa) in TABLE_1.items())
    min_slip: float = 1e-9
    tangential_stiffness: float | None = None

    def __post_init__(self):
        pos = {"hub_radius": "m", "blade_length": "m", "chord": "m", "thickness": "m",
               "youngs_modulus": "Pa", "density": "kg/m^3", "root_length": "m",
               "root_chord": "m", "root_thickness": "m", "shroud_mass": "kg",
               "damper_mass": "kg", "damper_radius": "m", "friction_exponent": "",
               "min_slip": "m"}
        for name, unit in pos.items():
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name),
                                                                unit=unit)))
        for name in ("blade_damping", "contact_damping", "tangential_force_order1",
                     "axial_force_order1"):
            unit = "s" if "damping" in name else "N"
            object.__setattr__(self, name, float(check_positive(
                name, getattr(self, name), unit=unit, allow_zero=True)))
        for name in ("n_elements", "n_blades"):
            v = getattr(self, name)
            low = 1 if name == "n_elements" else 3
            if isinstance(v, bool) or int(v) != v or v < low:
                raise ModelError(f"{name} must be an integer >= {low}, got {v!r}")
            object.__setattr__(self, name, int(v))
        if not -1.0 < self.poisson <= 0.5:
            raise ModelError(f"poisson must lie in (-1, 0.5], got {self.poisson!r}")
        if not 0.0 <= self.stagger <= np.pi / 2:
            raise ModelError(f"stagger must lie in [0, pi/2] rad, got {self.stagger!r}")
        for name in ("delta_a", "delta_b"):
            v = float(as_finite_array(name, getattr(self, name)))
            if not 0.0 < v < np.pi / 2:
                raise ModelError(f"{name} must lie in (0, pi/2) rad (angle of the contact "
                                 f"plane to the radial direction), got {v!r}")
            object.__setattr__(self, name, v)
        object.__setattr__(self, "shroud_inertia", _triple("shroud_inertia",
                                                           self.shroud_inertia))
        object.__setattr__(self, "damper_inertia", _triple("damper_inertia",
                                                           self.damper_inertia))
        object.__setattr__(self, "contact_stiffness", _pair("contact_stiffness",
                                                            self.contact_stiffness, "N/m"))
        object.__setattr__(self, "contact_width", _pair("contact_width", self.contact_width,
                                                        "m"))
        object.__setattr__(self, "contact_height", _pair("contact_height",
                                                         self.contact_height, "m"))
        object.__setattr__(self, "friction_coefficient", _pair(
            "friction_coefficient", self.friction_coefficient, "", allow_zero=True))
        if self.tangential_stiffness is not None:
            kt = float(as_finite_array("tangential_stiffness", self.tangential_stiffness))
            if not kt > 0:
                raise ModelError(f"tangential_stiffness must be > 0 N/m (or None), got "
                                 f"{self.tangential_stiffness!r}")
            object.__setattr__(self, "tangential_stiffness", kt)
        if self.damping_rule not in ("coulomb", "paper"):
            raise ModelError(f"damping_rule must be 'coulomb' or 'paper', got "
                             f"{self.damping_rule!r}")
        cp = as_finite_array("contact_points", self.contact_points)
        if cp.shape != (2, 2):
            raise ModelError("contact_points must be ((x_A, z_A), (x_B, z_B)) [m]")
        if not cp[0, 1] < 0.0 < cp[1, 1]:
            raise ModelError(f"contact_points: need z_A < 0 < z_B (A on blade 2's side), got "
                             f"z_A = {cp[0, 1]}, z_B = {cp[1, 1]}")
        tip = self.hub_radius + self.blade_length
        if not self.hub_radius < self.damper_radius < tip + 0.5 * self.blade_length:
            raise ModelError(f"damper_radius must lie between hub_radius ({self.hub_radius} m) "
                             f"and the tip radius + half a blade length, got "
                             f"{self.damper_radius}")
        half_gap = (self.damper_radius + cp[:, 0]) * np.tan(np.pi / self.n_blades)
        if np.any(np.abs(cp[:, 1]) >= half_gap):
            raise ModelError(f"contact_points: |z| must be smaller than the half pitch at the "
                             f"contact radius ({half_gap.min():.4g} m), got {cp[:, 1].tolist()}")
        object.__setattr__(self, "contact_points",
                           tuple(tuple(float(v) for v in row) for row in cp))
        table = []
        for row in self.excitation_table:
            try:
                k, ft, fa = row
            except (TypeError, ValueError):
                raise ModelError(f"excitation_table rows must be (k, F_t [N], F_ax [N]), got "
                                 f"{row!r}") from None
            if int(k) != k or k < 1:
                raise ModelError(f"excitation_table: order k must be an integer >= 1, got {k!r}")
            check_positive("excitation_table F_t", ft, unit="N", allow_zero=True)
            check_positive("excitation_table F_ax", fa, unit="N", allow_zero=True)
            table.append((int(k), float(ft), float(fa)))
        object.__setattr__(self, "excitation_table", tuple(table))

    @property
    def pitch_angle(self) -> float:
        """delta = 2 pi / n_blades [rad]."""
        return 2.0 * np.pi / self.n_blades

    @property
    def tip_radius(self) -> float:
        return self.hub_radius + self.blade_length

    def nozzle_forces(self, order: int) -> tuple[float, float]:
        """``(F_t, F_ax)`` per blade node [N] for excitation order k (Table 1 or F^(1)/k)."""
        if isinstance(order, bool) or int(order) != order or order < 1:
            raise ModelError(f"excitation order k must be an integer >= 1, got {order!r}")
        for k, ft, fa in self.excitation_table:
            if k == order:
                return ft, fa
        return self.tangential_force_order1 / order, self.axial_force_order1 / order

    def with_(self, **changes) -> BladePairParameters:
        """Copy with some parameters changed (validated again)."""
        names = {f.name for f in fields(self)}
        bad = sorted(set(changes) - names)
        if bad:
            raise ModelError(f"unknown BladePairParameters field(s) {bad}; known: "
                             f"{sorted(names)}")
        return replace(self, **changes)


@dataclass(frozen=True, eq=False)
class BladePairModel:
    """Assembled 001 model (build it with :func:`build_blade_pair`).

    DOFs ``q = [q_1 (blade 1), q_D (wedge), q_2 (blade 2)]`` (001 (7)); blade DOFs in the
    blade's frame, wedge DOFs in the global rotating frame.

    Attributes
    ----------
    params : BladePairParameters
    blade : BeamModel
        One blade (root element + blade elements, shroud at the tip) in its own frame.
    damper : RigidBodyTerms
        The wedge's M, G, K_d, f_c.
    M, K_s, B, G, K_d, K_w : ndarray, shape (n, n)
        Mass, static stiffness, material damping, gyroscopic (per Omega), spin softening and
        stress stiffening (per Omega^2), 001 (8)-(9).
    f_c : ndarray, shape (n,)
        Centrifugal load per Omega^2 [N s^2].
    K_C : ndarray, shape (n, n)
        Contact stiffness 001 (18).
    contact_projection : ndarray, shape (2, 6, n)
        Rows per contact (A, B): normal approach [m], slip along xi and eta [m], relative
        rotations about xi, eta and the normal [rad] (shroud minus wedge).
    normals, tangents_xi : ndarray, shape (2, 3)
        Global unit vectors per contact.
    frames : ndarray, shape (3, 3, 3)
        Local-to-global rotations of blade 1, wedge, blade 2.
    contact_offsets_shroud, contact_offsets_damper : ndarray, shape (2, 3)
        r_Cj,X (in blade j's frame) and r_D,X (in the wedge frame) [m].
    torque_arms : ndarray, shape (2,)
        Friction-torque arm rho [m] of each contact (M_0 = f N rho).
    """

    params: BladePairParameters
    blade: BeamModel
    damper: RigidBodyTerms
    M: np.ndarray
    K_s: np.ndarray
    B: np.ndarray
    G: np.ndarray
    K_d: np.ndarray
    K_w: np.ndarray
    f_c: np.ndarray
    K_C: np.ndarray
    contact_projection: np.ndarray
    normals: np.ndarray
    tangents_xi: np.ndarray
    frames: np.ndarray
    contact_offsets_shroud: np.ndarray
    contact_offsets_damper: np.ndarray
    torque_arms: np.ndarray
    dof_names: tuple[str, ...] = field(default=())

    # ------------------------------------------------------------------ layout
    @property
    def n_dof(self) -> int:
        return int(self.M.shape[0])

    @property
    def n_blade_dof(self) -> int:
        return self.blade.n_dof

    @property
    def blade_slices(self) -> tuple[slice, slice]:
        nb = self.n_blade_dof
        return slice(0, nb), slice(nb + 6, 2 * nb + 6)

    @property
    def damper_slice(self) -> slice:
        nb = self.n_blade_dof
        return slice(nb, nb + 6)

    @property
    def tip_node(self) -> int:
        return self.blade.n_nodes - 1

    def dof_index(self, body: str, node: int | None, name: str) -> int:
        """Index of a DOF: body ``"blade1"``, ``"blade2"`` (node = beam node, 1..n_el+1 the
        blade nodes) or ``"damper"`` (node ignored); name ``u, v, w, phi, theta, psi``."""
        names = ("u", "v", "w", "phi", "theta", "psi")
        if body == "damper":
            if name not in names:
                raise ModelError(f"name must be one of {names}, got {name!r}")
            return self.damper_slice.start + names.index(name)
        if body not in ("blade1", "blade2"):
            raise ModelError(f"body must be 'blade1', 'blade2' or 'damper', got {body!r}")
        start = self.blade_slices[0 if body == "blade1" else 1].start
        return start + self.blade.dof_index(node, name)

    @property
    def friction_projection(self) -> np.ndarray:
        """Contact coordinates of the friction model, shape (6, n): per contact (A, B) the
        slip along xi, eta [m] and the rotation about the normal [rad]."""
        return self.contact_projection[:, [1, 2, 5], :].reshape(6, self.n_dof)

    @property
    def contact_angles(self) -> dict[str, float]:
        """Plane angles [rad]: ``delta_a, delta_b`` (wedge frame) and ``delta_A, delta_B``
        (blade 2 and blade 1 frames, ``+ delta/2``), 001 Fig. 1."""
        p = self.params
        half = 0.5 * p.pitch_angle
        return {"delta_a": p.delta_a, "delta_b": p.delta_b, "delta_A": p.delta_a + half,
                "delta_B": p.delta_b + half}

    # ------------------------------------------------------------------ speed dependence
    def centrifugal_damper_force(self, speed) -> np.ndarray:
        """``m_D r_D Omega^2`` [N] at spin speeds [rad/s]."""
        w = np.asarray(speed, float)
        return self.params.damper_mass * self.params.damper_radius * w**2

    def normal_loads(self, speed) -> np.ndarray:
        """Static normal loads (N_A, N_B) [N] from 001 (6) (derived form, module docstring),
        shape (..., 2)."""
        p = self.params
        F = self.centrifugal_damper_force(speed)[..., None]
        s = np.sin(p.delta_a + p.delta_b)
        return F * np.array([np.cos(p.delta_b), np.cos(p.delta_a)]) / s

    def stiffness(self, speed) -> np.ndarray:
        """``K_s - Omega^2 K_d + Omega^2 K_w + K_C`` (001 (8)), shape (n, n) or (n_b, n, n)."""
        w2 = np.asarray(speed, float)[..., None, None] ** 2
        return self.K_s + self.K_C + w2 * (self.K_w - self.K_d)

    def damping(self, speed, *, gyroscopic: bool = True) -> np.ndarray:
        """``Omega G + B + B_C`` (001 (8) without B_e), shape (n, n) or (n_b, n, n)."""
        p = self.params
        D = self.B + p.contact_damping * self.K_C
        if not gyroscopic:
            return np.broadcast_to(D, np.shape(speed) + D.shape).copy()
        return D + np.asarray(speed, float)[..., None, None] * self.G

    def dissipative_damping(self) -> np.ndarray:
        """``B + B_C`` (the part of the damping that dissipates), shape (n, n)."""
        return self.B + self.params.contact_damping * self.K_C

    def load(self, order: int) -> np.ndarray:
        """Complex load amplitude (n,) [N] of the nozzle excitation k (001 (10)-(11)).

        ``F(t) = Re(F~ e^{i k Omega t})``: ``F_ax`` along y_j and ``-F_t`` along z_j at every
        blade node, blade 2 with the phase ``exp(i k delta)`` (001 (3), delta_2 = delta).
        """
        ft, fa = self.params.nozzle_forces(order)
        fb = np.zeros(self.n_blade_dof)
        for node in range(1, self.blade.n_nodes):
            fb[self.blade.dof_index(node, "v")] = fa
            fb[self.blade.dof_index(node, "w")] = -ft
        F = np.zeros(self.n_dof, complex)
        s1, s2 = self.blade_slices
        F[s1] = fb
        F[s2] = fb * np.exp(1j * order * self.params.pitch_angle)
        return F

    def friction_damping(self, speed, friction_coefficient=None, *,
                         rule: str | None = None) -> EllipseFrictionDamping:
        """Equivalent friction damping model of the two contacts (A, B) at spin speeds.

        Parameters
        ----------
        speed : array_like, shape (n_b,)
            Spin speeds [rad/s] (normal loads 001 (6) per speed).
        friction_coefficient : float or (2,), optional
            Overrides ``params.friction_coefficient``.
        rule : {"coulomb", "paper"}, optional
            Overrides ``params.damping_rule``.
        """
        p = self.params
        f = p.friction_coefficient if friction_coefficient is None else friction_coefficient
        N = np.atleast_2d(self.normal_loads(np.atleast_1d(speed)))
        opts = dict(exponent=p.friction_exponent, rule=rule or p.damping_rule,
                    min_amplitude=p.min_slip)
        if p.tangential_stiffness is None:
            return EllipseFrictionDamping(N, f, self.torque_arms, **opts)
        return JenkinsEllipseDamping(N, f, self.torque_arms,
                                     tangential_stiffness=p.tangential_stiffness,
                                     rotational_stiffness=self.rotational_stick_stiffness(
                                         p.tangential_stiffness), **opts)

    def rotational_stick_stiffness(self, tangential_stiffness: float) -> np.ndarray:
        """``k_t (a_ef^2 + h_ef^2) / 12`` [N m/rad] of A and B: a uniform tangential
        stiffness per unit area over the effective rectangle, twisted about its centre."""
        p = self.params
        return rectangle_twist_stiffness(tangential_stiffness, np.array(p.contact_width),
                                         np.array(p.contact_height))

    def system(self, speed: float, *, order: int | None = None,
               extra_damping: np.ndarray | None = None) -> MechanicalSystem:
        """The linear system at one spin speed as a MechanicalSystem (dense).

        ``M, D = Omega G + B + B_C (+ extra_damping), K = K(Omega) + K_C``; with ``order`` a
        HarmonicLoad at ``k Omega``. No contacts are attached (add them with
        ``with_contacts``).
        """
        w = float(speed)
        D = self.damping(w)
        if extra_damping is not None:
            D = D + np.asarray(extra_damping, float)
        loads = ()
        if order is not None:
            loads = (HarmonicLoad(self.load(order), omega=max(order * w, 0.0)),)
        return MechanicalSystem(M=self.M, K=self.stiffness(w), D=D, loads=loads,
                                dof_names=self.dof_names, name="blade_pair",
                                meta={"spin_speed_rad_s": w})


# ---------------------------------------------------------------------------- builder
def _blade(p: BladePairParameters) -> BeamModel:
    n = p.n_elements
    r0, r1 = p.hub_radius - p.root_length, p.hub_radius
    x = np.concatenate([[r0], np.linspace(r1, p.tip_radius, n + 1)])
    nodes = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    els = np.column_stack([np.arange(n + 1), np.arange(1, n + 2)])
    mat = dict(E_Pa=p.youngs_modulus, rho_kg_m3=p.density, nu=p.poisson)
    blade_sec = BeamSection.rectangle(p.chord, p.thickness, **mat)
    root_sec = BeamSection.rectangle(p.root_chord, p.root_thickness, **mat)
    chord_dir = [0.0, np.cos(p.stagger), np.sin(p.stagger)]
    return beam_model(nodes, els, [root_sec] + [blade_sec] * n, orientation=chord_dir,
                      clamped_nodes=[0],
                      point_masses={n + 1: (p.shroud_mass, np.array(p.shroud_inertia))},
                      rayleigh=(0.0, p.blade_damping) if p.blade_damping > 0 else None,
                      spin_axis=[0.0, 1.0, 0.0], name="blade")


def _dense(A):
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A, float)


def _block_diag(b: np.ndarray, d: np.ndarray) -> np.ndarray:
    nb = b.shape[0]
    out = np.zeros((2 * nb + 6, 2 * nb + 6))
    out[:nb, :nb] = b
    out[nb:nb + 6, nb:nb + 6] = d
    out[nb + 6:, nb + 6:] = b
    return out


def build_blade_pair(params: BladePairParameters | None = None) -> BladePairModel:
    """Assemble the 001 model: two blades, wedge, contact coupling (module docstring).

    Parameters
    ----------
    params : BladePairParameters, optional
        Defaults as documented there.

    Returns
    -------
    BladePairModel

    Examples
    --------
    >>> model = build_blade_pair()
    >>> model.n_dof
    78
    """
    p = BladePairParameters() if params is None else params
    if not isinstance(p, BladePairParameters):
        raise ModelError(f"params must be BladePairParameters, got {type(p).__name__}")
    blade = _blade(p)
    rot = blade.rotation
    rD = np.array([p.damper_radius, 0.0, 0.0])
    damper = rigid_body_terms(p.damper_mass, np.array(p.damper_inertia), rD,
                              spin_axis=[0.0, 1.0, 0.0])
    M = _block_diag(_dense(blade.M), damper.M)
    Ks = _block_diag(_dense(blade.K), np.zeros((6, 6)))
    B = _block_diag(_dense(blade.D), np.zeros((6, 6)))
    G = _block_diag(_dense(rot.gyroscopic), damper.G)
    Kd = _block_diag(_dense(rot.spin_softening), damper.Kd)
    Kw = _block_diag(_dense(rot.stress_stiffening), np.zeros((6, 6)))
    nb = blade.n_dof
    fc = np.concatenate([rot.centrifugal_load, damper.fc, rot.centrifugal_load])
    n = 2 * nb + 6

    half = 0.5 * p.pitch_angle
    frames = np.stack([_rot_y(-half), np.eye(3), _rot_y(half)])
    da, db = p.delta_a, p.delta_b
    normals = np.array([[-np.sin(da), 0.0, np.cos(da)], [-np.sin(db), 0.0, -np.cos(db)]])
    xis = np.array([[np.cos(da), 0.0, np.sin(da)], [np.cos(db), 0.0, -np.sin(db)]])
    eta = np.array([0.0, 1.0, 0.0])
    cp = np.array(p.contact_points)
    r_damper = np.column_stack([cp[:, 0], np.zeros(2), cp[:, 1]])      # r_D,X (wedge frame)
    tip = blade.n_nodes - 1
    tip_dofs = np.array([blade.dof_index(tip, nm) for nm in
                         ("u", "v", "w", "phi", "theta", "psi")])
    body_start = {0: 0, 2: nb + 6}
    r_shroud = np.zeros((2, 3))
    P = np.zeros((2, 6, n))
    for c, body in enumerate((2, 0)):                  # A: blade 2, B: blade 1
        R = frames[body]
        point = rD + r_damper[c]                        # global contact point
        r_shroud[c] = R.T @ point - np.array([p.tip_radius, 0.0, 0.0])
        T = np.zeros((3, n))                            # relative displacement, global axes
        W = np.zeros((3, n))                            # relative rotation, global axes
        cols = body_start[body] + tip_dofs
        T[:, cols[:3]] = R
        T[:, cols[3:]] = -R @ skew(r_shroud[c])
        ds = slice(nb, nb + 6)
        T[:, ds] = -np.hstack([np.eye(3), -skew(r_damper[c])])
        W[:, cols[3:]] = R
        W[:, nb + 3:nb + 6] = -np.eye(3)
        P[c] = np.stack([normals[c] @ T, xis[c] @ T, eta @ T, xis[c] @ W, eta @ W,
                         normals[c] @ W])
    k = np.array(p.contact_stiffness)
    a_ef = np.array(p.contact_width)
    h_ef = np.array(p.contact_height)
    stiff = np.zeros((2, 6))
    stiff[:, 0] = k                                     # 001 (12)
    stiff[:, 3] = k * h_ef**2 / 12.0                    # 001 (17): about xi
    stiff[:, 4] = k * a_ef**2 / 12.0                    # about eta
    KC = np.einsum("cin,ci,cim->nm", P, stiff, P)       # 001 (18)
    KC = 0.5 * (KC + KC.T)
    names = tuple(f"b1.{s}" for s in blade.dof_names) + tuple(
        f"D.{s}" for s in ("u", "v", "w", "phi", "theta", "psi")) + tuple(
        f"b2.{s}" for s in blade.dof_names)
    return BladePairModel(params=p, blade=blade, damper=damper, M=M, K_s=Ks, B=B, G=G,
                          K_d=Kd, K_w=Kw, f_c=fc, K_C=KC, contact_projection=P,
                          normals=normals, tangents_xi=xis, frames=frames,
                          contact_offsets_shroud=r_shroud, contact_offsets_damper=r_damper,
                          torque_arms=np.asarray(rectangle_mean_radius(a_ef, h_ef)),
                          dof_names=names)
