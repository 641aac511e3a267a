"""Bladed wheel with tie-boss friction contacts between neighbouring blades, paper 003.

The physical model (003 section 1.1, Figs 1-3): 30 prismatic blades on a disk clamped at
its hub; each blade carries a tip mass and, at the radius r = 0.44 m, a tie-boss whose two
shoulders touch the shoulders of the neighbouring blades on planes cut at 45 degrees.
The paper's FE model (89,000 SOLID85 elements) is not available; this module builds a
beam model of the same structure (3D Rayleigh beams, 6 DOF per node,
:mod:`fricdamp.structure.beam3d`) whose open-contact eigenfrequencies by nodal diameter
match the paper's Table 1 within 1 %.

Frames and geometry
-------------------
The wheel axis is z; sector 0 is the blade along +x (``e_r = x, e_t = y, e_z = z``), sector j
is sector 0 rotated by ``j alpha``, ``alpha = 2 pi / N`` (12 degrees for N = 30). Each sector
holds (node coordinates in its frame, ``h = alpha / 2``):

* the **hub** (disk web): a radial beam clamped at ``hub_inner_radius_m`` and reaching the
  blade root at ``hub_radius_m``, a rectangle ``hub_thickness_m`` (axial) x ``hub_width_m``
  (tangential);
* the **rim**: two straight beams from the root node to the cut nodes at angles -h and +h on
  the hub radius, a rectangle ``rim_thickness_m`` (axial) x ``rim_height_m`` (radial). The cut
  nodes are the left and right cuts of the cyclic sector; the rim couples the sectors and
  makes the frequencies depend on the nodal diameter (ND). Hub and rim are an equivalent
  beam model of the disk, tuned to Table 1 (the paper gives no disk dimensions);
* the **blade**: a radial beam from the root to ``tip_radius_m``, a rectangle ``blade_width_m``
  x ``blade_thickness_m`` whose plane contains the radius and makes the angle
  ``blade_angle_deg`` with the wheel plane (the 45-degree consoles of 003 section 1.1), so the
  flexural direction (normal to the blade plane, the plane alpha_0 of the paper) is
  ``d = sin(beta_b) e_t + cos(beta_b) e_z``; a node at ``tieboss_radius_m``;
* the **tie-boss**: a point mass at that node and two shoulders, beams of diameter
  ``shoulder_diameter_m`` along -e_t and +e_t, ending on the radials at -h and +h (the axes
  zeta_A, zeta_B of 003 Fig. 2, 12 degrees apart) at ``(r_tb, -/+ r_tb tan h, 0)``: the left
  and right **contact nodes**;
* the **tip mass**: a point mass (with rotary inertia) at the blade tip.

Contacts (003 Fig. 2 and section 2.4). The right contact node of blade j and the left one of
blade j+1 coincide. The cutting plane beta is the plane alpha (perpendicular to the wheel,
through the mid radial zeta = e_r(h)) turned by ``contact_plane_angle_deg`` (beta_c) about
zeta; its unit normal (pointing from blade j to blade j+1) and in-plane tangents are::

    n  = cos(beta_c) e_t(h) - sin(beta_c) e_z
    t1 = e_r(h) = zeta                     (radial sliding)
    t2 = sin(beta_c) e_t(h) + cos(beta_c) e_z   (sliding along the flexural direction)

With ``beta_c = beta_b`` the flexural motions of both blades lie (up to the 12-degree pitch)
in the contact plane, "to allow the blade to move freely during flexural vibrations"
(003 section 1.1); normal motion comes from blade twist, the pitch and the shoulders'
rotations, as the paper's non-parallel contact-node trajectories show (Figs 15-16). The
relative displacement ``u = Lambda (x_R^(j) - x_L^(j+1))`` (rows n, t1, t2; ``u_n > 0``
closes) drives one :class:`~fricdamp.contact.element3d.Contact3D` per blade pair: normal
penalty with the offset ``contact_offset_m`` (1e-5 m, the paper's contact-surface offset),
separation and re-contact, 2D Coulomb friction with 003 (2), ``mu_s = 0.4, mu_d = 0.2,
DC = 4 s/m``. The paper's offset of 1e-5 m gives 2.4 N of normal force *in the assembled
wheel*: the interference is taken up by the penalty in series with the structure (the
blades twist and the shoulders compress; the axial component of the contact forces twists
each blade, which slides the contacts along t2 until friction holds them on its static
cone), so the penalty ``normal_stiffness_N_per_m`` is
calibrated (:func:`calibrate_normal_stiffness`) such that the static prestress of the wheel
is ``contact_preload_N`` = 2.4 N; the tangential penalty equals the normal one (the ANSYS
default FKT = 1).

Material damping: Rayleigh ``D = a M + b K`` with the ratio ``damping_ratio`` (0.1 %, 003
section 2.4) at the two frequencies ``damping_band_hz`` bracketing the first blade family
(so it is within a few % of 0.1 % over 40-60 Hz and grows in the high modes). Being
Rayleigh, it survives the Craig-Bampton projection unchanged.

Cyclic symmetry and reduction: :func:`build_sector` gives a
:class:`~fricdamp.structure.cyclic.CyclicSector` in Cartesian frames (``frame="cartesian"``,
axis z, the cut DOFs are the rim nodes' displacement and rotation triples) with the named
DOF groups ``contact_left``, ``contact_right`` (translations of the contact nodes) and
``tieboss`` (translations of the tie-boss node, where the paper applies its modal forces).
:func:`build_wheel` assembles the full wheel (30 x 96 = 2880 DOFs by default: 102 sector
DOFs less the 6 of the right cut, shared with the next sector) or, with
``n_modes``, the wheel of Craig-Bampton sectors keeping the cuts, the contact nodes and
the tie-boss node plus ``n_modes`` fixed-interface modes (30 x (15 + n_modes) DOFs). A
user's FE sector (Matrix Market or ANSYS ``.full`` through
:func:`fricdamp.structure.io.read_sector`) with those named DOF groups runs the same
pipeline: :func:`sector_from_cyclic`.

Tuned parameters (:func:`tune_parameters`, Table 1, FEM column, pair means at 2-6 ND and
50.3 Hz at 15 ND; the defaults below are its result): ``hub_thickness_m = 10.04 mm``,
``rim_height_m = 24.78 mm``, ``tip_mass_kg = 0.4189 kg`` with the other dimensions fixed at
the documented values; largest error 0.5 % (5ND/6ND: 48.19/48.81 Hz against 48.16/48.56 Hz;
0ND and 1ND, not in the table, are 41.9 and 42.6 Hz). The normal penalty calibrated for
2.4 N is ``normal_stiffness_N_per_m = 4.654e5 N/m`` (k_t the same). Checked by
``tests/validation/test_tieboss_modal.py``.
"""

from __future__ import annotations

import logging
from dataclasses import asdict, dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from fricdamp.contact.element3d import Contact3D
from fricdamp.errors import ModelError, check_positive, check_range
from fricdamp.structure.beam3d import BeamModel, BeamSection, beam_model
from fricdamp.structure.cyclic import (
    CyclicSector,
    assemble_full,
    nodal_diameter_modes,
)
from fricdamp.structure.reduction import ReducedSector, craig_bampton_sector
from fricdamp.structure.system import ContactElement, MechanicalSystem, RotationTerms

__all__ = [
    "TABLE1_FEM_HZ",
    "TiebossSector",
    "TiebossWheel",
    "TiebossWheelParameters",
    "build_sector",
    "build_wheel",
    "calibrate_normal_stiffness",
    "contact_frame",
    "prestress_normal_force",
    "sector_from_cyclic",
    "table1_targets",
    "tune_parameters",
]

log = logging.getLogger(__name__)

#: Paper 003 Table 1, FEM column: open-contact eigenfrequency pairs [Hz] by nodal diameter
#: (the pairs are the split double modes of the slightly mistuned FE model), and the limit
#: 50.3 Hz quoted for 15 ND.
TABLE1_FEM_HZ = {2: (44.32, 44.39), 3: (46.14, 46.20), 4: (47.37, 47.42), 5: (48.10, 48.22),
                 6: (48.54, 48.58), 15: (50.3,)}
#: Paper 003 Table 1, experiment column (``None`` where the paper has a dash).
TABLE1_EXPERIMENT_HZ = {2: (43.51, None), 3: (45.43, 45.65), 4: (46.59, None),
                        5: (47.08, 47.67), 6: (48.21, 48.66)}

_DOF6 = ("u", "v", "w", "phi", "theta", "psi")


def table1_targets() -> dict[int, float]:
    """Target frequency [Hz] per ND: the mean of each FEM pair of Table 1 (and 50.3 at 15)."""
    return {nd: float(np.mean(v)) for nd, v in TABLE1_FEM_HZ.items()}


# ------------------------------------------------------------------------------ parameters
@dataclass(frozen=True)
class TiebossWheelParameters:
    """Parameters of the tie-boss wheel (SI units; angles in degrees where the name says so).

    Defaults: the paper's data (30 blades, tie-boss radius 0.44 m, 45-degree contact planes,
    offset 1e-5 m for 2.4 N, mu_s = 0.4, mu_d = 0.2, DC = 4 s/m, 0.1 % damping) and, for
    what the paper does not give, documented choices (steel, blade 200 mm x 40 mm x 6 mm
    from r = 0.30 m to 0.50 m, 10 mm shoulders, 30 g tie-boss) with the hub, rim and tip
    mass tuned to Table 1 (:func:`tune_parameters`) and the normal penalty calibrated to
    2.4 N of prestress (:func:`calibrate_normal_stiffness`).

    Attributes
    ----------
    n_blades : int
        Number of blades (sectors) N >= 3 (003: 30).
    hub_inner_radius_m, hub_radius_m : float
        Clamped radius of the disk web and radius of the rim / blade roots [m].
    tieboss_radius_m, tip_radius_m : float
        Radius of the tie-boss (003: 0.44 m) and of the blade tip [m];
        ``hub_radius < tieboss_radius < tip_radius``.
    blade_width_m, blade_thickness_m : float
        Blade cross-section [m] (width in the blade plane, thickness along the flexural
        direction).
    blade_angle_deg : float
        Angle of the blade plane to the wheel plane [deg] in [0, 90] (003: consoles at 45).
    contact_plane_angle_deg : float
        Angle beta_c [deg] in [0, 90) by which the plane through the mid radial,
        perpendicular to the wheel, is turned to give the contact plane (003: 45).
    shoulder_diameter_m : float
        Diameter of the tie-boss shoulders [m] (circular beams).
    hub_thickness_m, hub_width_m : float
        Axial thickness and tangential width of the disk web beam [m].
    rim_thickness_m, rim_height_m : float
        Axial thickness and radial height of the rim beams [m].
    tip_mass_kg, tip_inertia_kg_m2 : float
        Tip mass [kg] and its rotary inertia about its centre [kg m^2] (isotropic).
    tieboss_mass_kg, tieboss_inertia_kg_m2 : float
        Mass [kg] and rotary inertia [kg m^2] of the tie-boss prism (the shoulders are beams).
    young_modulus_Pa, density_kg_m3, poisson_ratio : float
        Material (steel).
    n_hub_elements, n_blade_elements : int
        Beam elements along the hub web and the blade (the tie-boss is always a node).
    damping_ratio : float
        Material damping ratio [-] (003: 0.1 %), Rayleigh at ``damping_band_hz``.
    damping_band_hz : (float, float)
        The two frequencies [Hz] where the Rayleigh damping equals ``damping_ratio``.
    contact_offset_m : float
        Contact-surface offset g0 [m]: > 0 interference (003: 1e-5 m), < 0 a gap; |g0| below
        1 % of the tie-boss radius.
    contact_preload_N : float
        Target static normal force of the prestressed wheel [N] (003: 2.4 N); used by
        :func:`calibrate_normal_stiffness`.
    normal_stiffness_N_per_m : float
        Normal contact penalty k_n [N/m], calibrated for ``contact_preload_N``.
    tangential_stiffness_N_per_m : float or None
        Tangential penalty k_t [N/m]; None: equal to ``normal_stiffness_N_per_m``.
    mu_static, mu_sliding, decay_s_per_m : float
        Friction law 003 (2): mu_s, mu_d <= mu_s and DC [s/m].
    """

    n_blades: int = 30
    hub_inner_radius_m: float = 0.10
    hub_radius_m: float = 0.30
    tieboss_radius_m: float = 0.44
    tip_radius_m: float = 0.50
    blade_width_m: float = 0.040
    blade_thickness_m: float = 0.006
    blade_angle_deg: float = 45.0
    contact_plane_angle_deg: float = 45.0
    shoulder_diameter_m: float = 0.010
    hub_thickness_m: float = 0.01004
    hub_width_m: float = 0.100
    rim_thickness_m: float = 0.005
    rim_height_m: float = 0.02478
    tip_mass_kg: float = 0.4189
    tip_inertia_kg_m2: float = 1.0e-4
    tieboss_mass_kg: float = 0.030
    tieboss_inertia_kg_m2: float = 2.0e-6
    young_modulus_Pa: float = 2.1e11
    density_kg_m3: float = 7850.0
    poisson_ratio: float = 0.3
    n_hub_elements: int = 3
    n_blade_elements: int = 10
    damping_ratio: float = 1.0e-3
    damping_band_hz: tuple[float, float] = (40.0, 60.0)
    contact_offset_m: float = 1.0e-5
    contact_preload_N: float = 2.4
    normal_stiffness_N_per_m: float = 4.654e5
    tangential_stiffness_N_per_m: float | None = None
    mu_static: float = 0.4
    mu_sliding: float = 0.2
    decay_s_per_m: float = 4.0

    def __post_init__(self):
        if isinstance(self.n_blades, bool) or int(self.n_blades) != self.n_blades or \
                self.n_blades < 3:
            raise ModelError(f"n_blades must be an integer >= 3, got {self.n_blades!r}")
        object.__setattr__(self, "n_blades", int(self.n_blades))
        for name in ("hub_inner_radius_m", "hub_radius_m", "tieboss_radius_m", "tip_radius_m",
                     "blade_width_m", "blade_thickness_m", "shoulder_diameter_m",
                     "hub_thickness_m", "hub_width_m", "rim_thickness_m", "rim_height_m",
                     "tip_mass_kg", "tieboss_mass_kg", "young_modulus_Pa", "density_kg_m3",
                     "normal_stiffness_N_per_m"):
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name))))
        for name in ("tip_inertia_kg_m2", "tieboss_inertia_kg_m2", "contact_preload_N",
                     "mu_static", "mu_sliding", "decay_s_per_m"):
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name),
                                                                allow_zero=True)))
        if not (self.hub_inner_radius_m < self.hub_radius_m < self.tieboss_radius_m
                < self.tip_radius_m):
            raise ModelError(
                "radii must satisfy hub_inner_radius_m < hub_radius_m < tieboss_radius_m < "
                f"tip_radius_m, got {self.hub_inner_radius_m}, {self.hub_radius_m}, "
                f"{self.tieboss_radius_m}, {self.tip_radius_m} m")
        object.__setattr__(self, "blade_angle_deg", float(check_range(
            "blade_angle_deg", self.blade_angle_deg, 0.0, 90.0, unit="deg")))
        object.__setattr__(self, "contact_plane_angle_deg", float(check_range(
            "contact_plane_angle_deg", self.contact_plane_angle_deg, 0.0, 90.0, unit="deg",
            high_open=True)))
        object.__setattr__(self, "poisson_ratio", float(check_range(
            "poisson_ratio", self.poisson_ratio, -1.0, 0.5, low_open=True)))
        for name in ("n_hub_elements", "n_blade_elements"):
            v = getattr(self, name)
            if isinstance(v, bool) or int(v) != v or v < (1 if name == "n_hub_elements" else 2):
                raise ModelError(f"{name} must be an integer >= "
                                 f"{1 if name == 'n_hub_elements' else 2}, got {v!r}")
            object.__setattr__(self, name, int(v))
        object.__setattr__(self, "damping_ratio", float(check_range(
            "damping_ratio", self.damping_ratio, 0.0, 1.0, high_open=True)))
        band = np.asarray(self.damping_band_hz, dtype=float).reshape(-1)
        if band.size != 2 or not np.all(np.isfinite(band)) or not 0 < band[0] < band[1]:
            raise ModelError(f"damping_band_hz must be two frequencies 0 < f1 < f2 [Hz], got "
                             f"{self.damping_band_hz!r}")
        object.__setattr__(self, "damping_band_hz", (float(band[0]), float(band[1])))
        if self.tangential_stiffness_N_per_m is not None:
            object.__setattr__(self, "tangential_stiffness_N_per_m", float(check_positive(
                "tangential_stiffness_N_per_m", self.tangential_stiffness_N_per_m)))
        if self.mu_sliding > self.mu_static:
            raise ModelError(f"mu_sliding must be <= mu_static (0 <= mu_d <= mu_s), got "
                             f"mu_sliding={self.mu_sliding}, mu_static={self.mu_static}")
        g0 = float(check_range("contact_offset_m", self.contact_offset_m,
                               -0.01 * self.tieboss_radius_m, 0.01 * self.tieboss_radius_m,
                               unit="m (a small interference > 0 or gap < 0)"))
        object.__setattr__(self, "contact_offset_m", g0)

    @property
    def sector_angle_rad(self) -> float:
        """Blade pitch ``2 pi / N`` [rad]."""
        return 2.0 * np.pi / self.n_blades

    @property
    def tangential_stiffness(self) -> float:
        """k_t [N/m] actually used (the normal penalty when not given)."""
        t = self.tangential_stiffness_N_per_m
        return self.normal_stiffness_N_per_m if t is None else t

    def rayleigh(self) -> tuple[float, float]:
        """Rayleigh coefficients ``(a [1/s], b [s])`` giving ``damping_ratio`` at the band.

        ``zeta(w) = a / (2 w) + b w / 2`` equals zeta at ``w1`` and ``w2``:
        ``a = 2 zeta w1 w2 / (w1 + w2)``, ``b = 2 zeta / (w1 + w2)``.
        """
        w1, w2 = (2.0 * np.pi * f for f in self.damping_band_hz)
        z = self.damping_ratio
        return 2.0 * z * w1 * w2 / (w1 + w2), 2.0 * z / (w1 + w2)

    def with_(self, **changes) -> TiebossWheelParameters:
        """Copy with some parameters changed (validated again)."""
        return replace(self, **changes)

    def to_dict(self) -> dict:
        """Plain dict (JSON-ready) of all parameters."""
        d = asdict(self)
        d["damping_band_hz"] = list(self.damping_band_hz)
        return d


# ------------------------------------------------------------------------------ sector
def contact_frame(sector_angle_rad: float, contact_plane_angle_deg: float) -> np.ndarray:
    """Rows ``(n, t1, t2)`` of the contact frame at the right contact of sector 0, (3, 3).

    ``n = cos(b) e_t(h) - sin(b) e_z``, ``t1 = e_r(h)``, ``t2 = sin(b) e_t(h) + cos(b) e_z``
    with ``h`` half the pitch and ``b`` the contact-plane angle (module docstring). The rows
    are orthonormal and ``n`` points from blade j towards blade j+1.

    Examples
    --------
    >>> L = contact_frame(2 * np.pi / 30, 45.0)
    >>> bool(np.allclose(L @ L.T, np.eye(3)))
    True
    """
    h = 0.5 * float(sector_angle_rad)
    b = np.deg2rad(float(contact_plane_angle_deg))
    er = np.array([np.cos(h), np.sin(h), 0.0])
    et = np.array([-np.sin(h), np.cos(h), 0.0])
    ez = np.array([0.0, 0.0, 1.0])
    return np.stack([np.cos(b) * et - np.sin(b) * ez, er, np.sin(b) * et + np.cos(b) * ez])


@dataclass(frozen=True, eq=False)
class TiebossSector:
    """One sector of a tie-boss wheel ready for the cyclic, contact and reduction pipeline.

    Attributes
    ----------
    cyclic : CyclicSector
        The sector (``frame`` Cartesian or cylindrical) with named DOF groups
        ``contact_left`` and ``contact_right`` (3 translations each, in the frame of the
        sector's DOFs, the contact frame's components) and optionally ``tieboss``
        (translations where the modal forces act) and ``probe`` (3 translations whose
        motion is reported).
    frame : ndarray, shape (3, 3)
        Rows ``(n, t1, t2)`` of the contact frame at the right contact, expressed in the
        components of the ``contact_right`` DOFs. The left contact of the next sector uses
        the same physical frame (``R^T`` of it in that sector's components).
    parameters : TiebossWheelParameters
        Contact law, damping and (for the built-in model) geometry.
    rotation : RotationTerms or None
        Per-sector rotation terms (spin softening, stress stiffening, ...) about the wheel
        axis, for Campbell diagrams; None for imported sectors.
    beam : BeamModel or None
        The beam model of the built-in sector (node coordinates for plots).
    flexural_direction : ndarray, shape (3,)
        Unit flexural direction of the blade of sector 0 (for the amplitude of the decay).
    """

    cyclic: CyclicSector
    frame: np.ndarray
    parameters: TiebossWheelParameters
    rotation: RotationTerms | None = None
    beam: BeamModel | None = None
    flexural_direction: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))

    def __post_init__(self):
        if not isinstance(self.cyclic, CyclicSector):
            raise ModelError(f"cyclic must be a CyclicSector, got {type(self.cyclic).__name__}")
        for key in ("contact_left", "contact_right"):
            dofs = self.cyclic.named_dofs.get(key)
            if dofs is None or len(dofs) != 3:
                raise ModelError(
                    f"the sector needs a named DOF group {key!r} with the 3 translations of "
                    f"its contact node (got {None if dofs is None else list(dofs)}); name them "
                    "with read_sector(named_nodes=...) or named_dofs=...")
        F = np.asarray(self.frame, dtype=float)
        if F.shape != (3, 3) or not np.allclose(F @ F.T, np.eye(3), atol=1e-9):
            raise ModelError("frame must be a 3 x 3 matrix with orthonormal rows (n, t1, t2)")
        object.__setattr__(self, "frame", F)
        d = np.asarray(self.flexural_direction, dtype=float).reshape(3)
        if not np.isfinite(d).all() or np.linalg.norm(d) == 0:
            raise ModelError("flexural_direction must be a non-zero 3-vector")
        object.__setattr__(self, "flexural_direction", d / np.linalg.norm(d))

    @property
    def n_sectors(self) -> int:
        return self.cyclic.n_sectors

    def contact_rows(self, cyclic: CyclicSector | None = None,
                     dofs: dict | None = None) -> sp.csr_matrix:
        """Projection of the contact of this sector with the next, shape (3, 2 n).

        Columns ``0..n-1`` act on this sector's DOFs (the right contact node), ``n..2n-1`` on
        the next sector's (its left contact node, rotated into this sector's components):
        ``u = Lambda (x_R - R x_L')`` (module docstring). ``cyclic`` and ``dofs`` select
        another numbering of the same sector (the reduced one).
        """
        cyc = self.cyclic if cyclic is None else cyclic
        named = cyc.named_dofs if dofs is None else dofs
        n = cyc.n_dof
        R = cyc.rotation_matrix()
        P = np.zeros((3, 2 * n))
        P[:, np.asarray(named["contact_right"])] = self.frame
        P[:, n + np.asarray(named["contact_left"])] = -self.frame @ R
        return sp.csr_matrix(P)


def _sections(p: TiebossWheelParameters):
    mat = {"E_Pa": p.young_modulus_Pa, "rho_kg_m3": p.density_kg_m3, "nu": p.poisson_ratio}
    hub = BeamSection.rectangle(p.hub_thickness_m, p.hub_width_m, **mat)
    rim = BeamSection.rectangle(p.rim_thickness_m, p.rim_height_m, **mat)
    blade = BeamSection.rectangle(p.blade_width_m, p.blade_thickness_m, **mat)
    shoulder = BeamSection.circle(p.shoulder_diameter_m, **mat)
    return hub, rim, blade, shoulder


def build_sector(params: TiebossWheelParameters | None = None, *,
                 rotation: bool = True) -> TiebossSector:
    """The beam-model sector of the tie-boss wheel (module docstring).

    Parameters
    ----------
    params : TiebossWheelParameters, optional
        Defaults: the tuned wheel.
    rotation : bool
        Also build the rotation terms about the wheel axis (for Campbell diagrams).

    Returns
    -------
    TiebossSector
        ``cyclic`` has 17 free nodes x 6 = 102 DOFs with the default mesh (the hub node at
        the inner radius is clamped), Cartesian frames about z, Rayleigh damping, and the
        named groups ``contact_left``, ``contact_right``, ``tieboss``, ``probe`` (the right
        contact node) and ``tip``.

    Examples
    --------
    >>> s = build_sector(rotation=False)
    >>> s.cyclic.n_dof, s.cyclic.n_sectors
    (102, 30)
    """
    p = TiebossWheelParameters() if params is None else params
    if not isinstance(p, TiebossWheelParameters):
        raise ModelError(f"params must be TiebossWheelParameters, got {type(p).__name__}")
    h = 0.5 * p.sector_angle_rad
    hub_s, rim_s, blade_s, sh_s = _sections(p)
    nodes: list[np.ndarray] = []
    els: list[tuple[int, int]] = []
    secs: list[BeamSection] = []
    ori: list[np.ndarray] = []
    ez = np.array([0.0, 0.0, 1.0])

    def node(xyz) -> int:
        nodes.append(np.asarray(xyz, dtype=float))
        return len(nodes) - 1

    def element(a, b, sec, o):
        els.append((a, b))
        secs.append(sec)
        ori.append(np.asarray(o, dtype=float))

    clamp = node([p.hub_inner_radius_m, 0.0, 0.0])
    prev = clamp
    for k in range(1, p.n_hub_elements + 1):
        r = p.hub_inner_radius_m + (p.hub_radius_m - p.hub_inner_radius_m) * k / p.n_hub_elements
        cur = node([r, 0.0, 0.0])
        element(prev, cur, hub_s, ez)
        prev = cur
    root = prev
    rim_l = node([p.hub_radius_m * np.cos(h), -p.hub_radius_m * np.sin(h), 0.0])
    rim_r = node([p.hub_radius_m * np.cos(h), p.hub_radius_m * np.sin(h), 0.0])
    element(rim_l, root, rim_s, ez)
    element(root, rim_r, rim_s, ez)
    beta_b = np.deg2rad(p.blade_angle_deg)
    d = np.array([0.0, np.sin(beta_b), np.cos(beta_b)])       # flexural direction
    width_dir = np.cross(d, [1.0, 0.0, 0.0])                   # local y: in the blade plane
    span = p.tip_radius_m - p.hub_radius_m
    n1 = int(np.clip(round(p.n_blade_elements * (p.tieboss_radius_m - p.hub_radius_m) / span),
                     1, p.n_blade_elements - 1))
    radii = np.concatenate([np.linspace(p.hub_radius_m, p.tieboss_radius_m, n1 + 1)[1:],
                            np.linspace(p.tieboss_radius_m, p.tip_radius_m,
                                        p.n_blade_elements - n1 + 1)[1:]])
    prev = root
    tieboss = tip = -1
    for r in radii:
        cur = node([r, 0.0, 0.0])
        element(prev, cur, blade_s, width_dir)
        if np.isclose(r, p.tieboss_radius_m):
            tieboss = cur
        prev = cur
    tip = prev
    y = p.tieboss_radius_m * np.tan(h)
    c_left = node([p.tieboss_radius_m, -y, 0.0])
    c_right = node([p.tieboss_radius_m, y, 0.0])
    element(tieboss, c_left, sh_s, ez)
    element(tieboss, c_right, sh_s, ez)

    a, b = p.rayleigh()
    spin = {"spin_axis": [0.0, 0.0, 1.0]} if rotation else {}
    beam = beam_model(np.array(nodes), np.array(els), secs, orientation=np.array(ori),
                      clamped_nodes=[clamp],
                      point_masses={tip: (p.tip_mass_kg, p.tip_inertia_kg_m2),
                                    tieboss: (p.tieboss_mass_kg, p.tieboss_inertia_kg_m2)},
                      rayleigh=(a, b), name="tie-boss sector", **spin)

    def dofs(nd, names=_DOF6[:3]):
        return [beam.dof_index(nd, nm) for nm in names]

    named = {"contact_left": dofs(c_left), "contact_right": dofs(c_right),
             "tieboss": dofs(tieboss), "probe": dofs(c_right), "tip": dofs(tip)}
    # probe == contact_right; tip is not a kept group (see build_wheel)
    cyc = CyclicSector(M=beam.M, K=beam.K, D=beam.D, left=dofs(rim_l, _DOF6),
                       right=dofs(rim_r, _DOF6), n_sectors=p.n_blades, frame="cartesian",
                       axis="z", named_dofs=named, dof_names=beam.dof_names,
                       name="tie-boss sector")
    return TiebossSector(cyclic=cyc, frame=contact_frame(p.sector_angle_rad,
                                                         p.contact_plane_angle_deg),
                         parameters=p, rotation=beam.rotation, beam=beam,
                         flexural_direction=d)


def sector_from_cyclic(cyclic: CyclicSector, frame, params: TiebossWheelParameters | None = None,
                       *, flexural_direction=(0.0, 0.0, 1.0)) -> TiebossSector:
    """Wrap a user's sector (e.g. from :func:`fricdamp.structure.io.read_sector`).

    Parameters
    ----------
    cyclic : CyclicSector
        The sector's M, K (and D) with named DOF groups ``contact_left`` and
        ``contact_right`` (the 3 translations of the two contact nodes) and optionally
        ``tieboss`` (where the modal forces act; default the contact nodes) and ``probe``.
        Without D, Rayleigh damping from ``params`` is added.
    frame : array_like, shape (3, 3)
        Rows ``(n, t1, t2)`` of the contact frame at the right contact node, in the
        components of its DOFs (``n`` pointing towards the next blade).
    params : TiebossWheelParameters, optional
        Contact law and damping parameters (geometry entries are ignored); its
        ``n_blades`` is replaced by the sector's.
    flexural_direction : array_like, shape (3,)
        Direction (in sector-0 components) along which the probe displacement is reported.

    Returns
    -------
    TiebossSector
    """
    if not isinstance(cyclic, CyclicSector):
        raise ModelError(f"cyclic must be a CyclicSector, got {type(cyclic).__name__}")
    p = TiebossWheelParameters() if params is None else params
    p = p.with_(n_blades=cyclic.n_sectors)
    named = dict(cyclic.named_dofs)
    named.setdefault("tieboss", np.concatenate([named.get("contact_left", []),
                                                named.get("contact_right", [])]).astype(int))
    named.setdefault("probe", named.get("contact_right"))
    D = cyclic.D
    if D is None or (sp.issparse(D) and D.nnz == 0) or (not sp.issparse(D) and not np.any(D)):
        a, b = p.rayleigh()
        D = a * cyclic.M + b * cyclic.K
    cyc = replace(cyclic, D=D, named_dofs=named)
    return TiebossSector(cyclic=cyc, frame=np.asarray(frame, dtype=float), parameters=p,
                         flexural_direction=flexural_direction)


# ------------------------------------------------------------------------------ wheel
@dataclass(frozen=True, eq=False)
class TiebossWheel:
    """The assembled wheel (full or Craig-Bampton reduced) with its 30 tie-boss contacts.

    Attributes
    ----------
    system : MechanicalSystem
        The wheel with one :class:`~fricdamp.structure.system.ContactElement` ("tieboss")
        holding ``N`` Contact3D contacts (contact j joins blade j's right shoulder to blade
        j+1's left one). Full: sparse, ``N * n_independent`` DOFs; reduced: dense.
    sector : TiebossSector
        The physical sector.
    cyclic : CyclicSector
        The sector actually assembled (the reduced one for a reduced wheel).
    reduction : ReducedSector or None
        Craig-Bampton reduction of the sector (None for the full wheel).
    """

    system: MechanicalSystem
    sector: TiebossSector
    cyclic: CyclicSector
    reduction: ReducedSector | None = None

    @property
    def n_blades(self) -> int:
        return self.cyclic.n_sectors

    @property
    def n_dof(self) -> int:
        return self.system.n_dof

    @property
    def is_reduced(self) -> bool:
        return self.reduction is not None

    @property
    def law(self) -> Contact3D:
        return self.system.contacts[0].law

    @property
    def parameters(self) -> TiebossWheelParameters:
        return self.sector.parameters

    def group_dofs(self, name: str, blade: int = 0) -> np.ndarray:
        """Wheel DOF indices of the named group ``name`` of blade ``blade``."""
        if name not in self.cyclic.named_dofs:
            raise ModelError(f"unknown DOF group {name!r}; the sector has "
                             f"{sorted(self.cyclic.named_dofs)}")
        return self.cyclic.full_dofs(self.cyclic.named_dofs[name], int(blade) % self.n_blades)

    def group_dofs_all(self, name: str) -> np.ndarray:
        """``(N, k)`` wheel DOF indices of group ``name`` for every blade."""
        return np.stack([self.group_dofs(name, j) for j in range(self.n_blades)])

    def blade_rotation(self, blade: int) -> np.ndarray:
        """3 x 3 rotation from blade ``blade``'s DOF components to sector 0's."""
        R = self.cyclic.rotation_matrix()
        return np.linalg.matrix_power(R, int(blade) % self.n_blades)

    def sector_displacement(self, q, blade: int) -> np.ndarray:
        """Physical sector DOFs of blade ``blade`` (its own components) from wheel DOFs.

        ``q`` has shape (n_dof,) or (n_t, n_dof); the result (n_sector,) or (n_t, n_sector)
        on the DOFs of ``sector.cyclic`` (expanded through the reduction if any).
        """
        T = self.cyclic.transform(int(blade) % self.n_blades)
        qs = np.asarray(T @ np.asarray(q).T).T
        return self.reduction.expand(qs) if self.reduction is not None else qs


def _contact_law(p: TiebossWheelParameters, n: int) -> Contact3D:
    return Contact3D(p.normal_stiffness_N_per_m, p.tangential_stiffness, p.mu_static,
                     offset=p.contact_offset_m, mu_sliding=p.mu_sliding,
                     decay=p.decay_s_per_m, n_contacts=n)


def build_wheel(sector: TiebossSector | TiebossWheelParameters | None = None, *,
                n_modes: int | None = None, method: str = "auto") -> TiebossWheel:
    """Assemble the wheel with its tie-boss contacts, full or Craig-Bampton reduced.

    Parameters
    ----------
    sector : TiebossSector or TiebossWheelParameters, optional
        The sector (default: :func:`build_sector` of the default parameters).
    n_modes : int, optional
        Fixed-interface modes per sector. None: the full wheel (sparse). Otherwise each
        sector is reduced by :func:`~fricdamp.structure.reduction.craig_bampton_sector`
        keeping its cuts and its named DOF groups (contact nodes, tie-boss, probe) plus
        ``n_modes`` modes, and the wheel is assembled from the reduced sectors (dense).
    method : {"auto", "dense", "sparse"}
        Eigen-solver of the fixed-interface modes.

    Returns
    -------
    TiebossWheel

    Examples
    --------
    >>> w = build_wheel(n_modes=4)
    >>> w.n_dof, w.law.n_contacts
    (570, 30)
    """
    if sector is None or isinstance(sector, TiebossWheelParameters):
        sector = build_sector(sector, rotation=False)
    if not isinstance(sector, TiebossSector):
        raise ModelError(f"sector must be a TiebossSector or parameters, got "
                         f"{type(sector).__name__}")
    red = None
    cyc = sector.cyclic
    if n_modes is not None:
        if isinstance(n_modes, bool) or int(n_modes) != n_modes or n_modes < 0:
            raise ModelError(f"n_modes must be an integer >= 0 or None, got {n_modes!r}")
        named = dict(cyc.named_dofs)
        named.pop("tip", None)           # not kept: recovered by expansion
        red = craig_bampton_sector(replace(cyc, named_dofs=named), int(n_modes),
                                   method=method)
        cyc = red.sector
    P = sector.contact_rows(cyc)
    proj = cyc.contact_projection(P)
    law = _contact_law(sector.parameters, cyc.n_sectors)
    label = f"CB {n_modes} modes" if red is not None else "full"
    system = assemble_full(cyc, contacts=(ContactElement(law, proj, name="tieboss"),),
                           name=f"tie-boss wheel ({label})")
    if red is not None:
        system = system.dense()
    return TiebossWheel(system=system, sector=sector, cyclic=cyc, reduction=red)


# ------------------------------------------------------------------------------ prestress
def prestress_normal_force(wheel: TiebossWheel) -> float:
    """Mean static normal force [N] of the contacts of the prestressed wheel at rest.

    The static problem ``K q + P^T f(P q) = 0`` is solved from the virgin contact state in
    one return-map step (:func:`fricdamp.solvers.fast_transient.solve_static`): the
    interference twists the blades, which slides the contacts along t2 against friction
    (the friction force then sits on the static cone), so the problem is not linear.
    """
    from fricdamp.solvers.fast_transient import solve_static

    res = solve_static(wheel.system, np.zeros(wheel.n_dof))
    return float(np.mean(res.contact_force[0][:, 0]))


def calibrate_normal_stiffness(params: TiebossWheelParameters | None = None, *,
                               target_N: float | None = None) -> float:
    """Normal penalty [N/m] giving the static prestress ``target_N`` for the offset.

    The wheel's normal force at rest rises monotonically with the penalty, from 0 towards
    ``g0 / c`` (c: the structure's compliance to the uniform pattern of contact forces,
    friction included). Solved by Brent's method on :func:`prestress_normal_force` of the
    full wheel.

    Raises
    ------
    ModelError
        If ``target_N >= g0 / c`` (the structure is too soft to take 2.4 N from the
        offset whatever the penalty): stiffen the blades or shoulders.
    """
    from scipy.optimize import brentq

    p = TiebossWheelParameters() if params is None else params
    target = p.contact_preload_N if target_N is None else float(check_positive(
        "target_N", target_N, unit="N"))
    sector = build_sector(p, rotation=False)

    def force(log_kn):
        kn = float(np.exp(log_kn))
        q = p.with_(normal_stiffness_N_per_m=kn)
        return prestress_normal_force(build_wheel(replace(sector, parameters=q))) - target

    lo, hi = np.log(target / p.contact_offset_m), np.log(1e12)
    if force(hi) <= 0:
        raise ModelError(f"the structure cannot carry {target} N from an offset of "
                         f"{p.contact_offset_m} m even with a rigid penalty: it is too soft "
                         "(stiffen the blades, shoulders or hub, or lower contact_preload_N)")
    return float(np.exp(brentq(force, lo, hi, xtol=1e-10, rtol=1e-10)))


# ------------------------------------------------------------------------------ tuning
def _first_family(params: TiebossWheelParameters, nds) -> np.ndarray:
    s = build_sector(params, rotation=False)
    return np.array([nodal_diameter_modes(s.cyclic, int(nd), 1).frequencies[0] for nd in nds])


def tune_parameters(params: TiebossWheelParameters | None = None, *,
                    names=("hub_thickness_m", "rim_height_m", "tip_mass_kg"),
                    targets: dict[int, float] | None = None,
                    bounds=None) -> tuple[TiebossWheelParameters, dict]:
    """Tune geometry/mass parameters so the open-contact first family matches Table 1.

    Least squares (``scipy.optimize.least_squares``, log-parameters) on the relative errors
    ``f_model(nd) / f_target(nd) - 1`` of the first eigenfrequency of each nodal diameter
    (cyclic modal analysis of one sector), then the normal penalty is calibrated again
    for the prestress (:func:`calibrate_normal_stiffness`).

    Parameters
    ----------
    params : TiebossWheelParameters, optional
        Start values (default: the defaults).
    names : sequence of str
        Parameters tuned (positive floats of the dataclass).
    targets : dict nd -> Hz, optional
        Default :func:`table1_targets` (pair means at 2-6 ND, 50.3 Hz at 15 ND).
    bounds : (sequence, sequence), optional
        Lower and upper bounds of the tuned parameters (default: a factor 5 around the
        start values).

    Returns
    -------
    params : TiebossWheelParameters
    report : dict
        ``nd``, ``target_hz``, ``model_hz``, ``relative_error`` and ``tuned`` (the values).
    """
    from scipy.optimize import least_squares

    p = TiebossWheelParameters() if params is None else params
    tg = table1_targets() if targets is None else {int(k): float(v) for k, v in
                                                     targets.items()}
    nds = sorted(tg)
    if max(nds) > p.n_blades // 2:
        raise ModelError(f"targets hold nd = {max(nds)} > N/2 = {p.n_blades // 2}")
    names = tuple(names)
    for nm in names:
        if nm not in TiebossWheelParameters.__dataclass_fields__ or not isinstance(
                getattr(p, nm), float):
            raise ModelError(f"cannot tune {nm!r}: not a float parameter")
    x0 = np.log([getattr(p, nm) for nm in names])
    lo, hi = (x0 - np.log(5.0), x0 + np.log(5.0)) if bounds is None else (
        np.log(np.asarray(bounds[0], float)), np.log(np.asarray(bounds[1], float)))
    ft = np.array([tg[nd] for nd in nds])

    def make(x):
        return p.with_(**dict(zip(names, (float(v) for v in np.exp(x)), strict=True)))

    def residual(x):
        return _first_family(make(x), nds) / ft - 1.0

    sol = least_squares(residual, np.clip(x0, lo, hi), bounds=(lo, hi), diff_step=1e-4,
                        x_scale=1.0)
    tuned = make(sol.x)
    kn = calibrate_normal_stiffness(tuned)
    tuned = tuned.with_(normal_stiffness_N_per_m=kn)
    fm = _first_family(tuned, nds)
    report = {"nd": nds, "target_hz": ft.tolist(), "model_hz": fm.tolist(),
              "relative_error": (fm / ft - 1.0).tolist(),
              "tuned": {nm: getattr(tuned, nm) for nm in (*names, "normal_stiffness_N_per_m")}}
    return tuned, report
