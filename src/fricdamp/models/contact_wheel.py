"""A cyclic wheel of FE sectors joined by contact patches: paper 003's damping strategy at scale.

This is the pipeline of paper 003 (section 3) for a wheel whose sector is a real finite
element model -- the parametric solid sector of :mod:`fricdamp.models.tieboss_wheel.solid` or a
user's own mesh -- with contact *surfaces* between neighbouring sectors:

1. **Reduction** (:func:`~fricdamp.structure.cyclic_reduction.reduce_sector`): Craig-Bampton
   of the sparse sector keeping every node of both contact patches and the probe/load nodes,
   the cyclic cut interface reduced to characteristic interface modes; then **all** modes of
   the reduced wheel by nodal diameter (:func:`~fricdamp.structure.cyclic_reduction.
   wheel_modes`): a complete eigenbasis of the reduced wheel, found sector by sector, never
   by a dense eigenproblem of the whole wheel.
2. **Contacts** (:class:`~fricdamp.structure.contact_patch.ContactPatch`): one
   :class:`~fricdamp.contact.element3d.Contact3D` per node pair of every patch, penalty
   ``k_n = factor E A / h`` from the solid, ``k_t = k_n`` (ANSYS FKT = 1), 2D Coulomb friction
   with mu(v) of 003 (2), separation and re-contact. The **prestress** is an interference
   offset, the same on every pair, calibrated (:meth:`ContactWheel.calibrate_offset`) so
   that the static normal force per contact, taken up *through the structure's compliance*,
   is the target (003: 2.4 N).
3. **Free attenuation** (:meth:`ContactWheel.free_decay`): the open-contact standing wave of
   the chosen ND (blade 0 at an antinode) gives modal forces at every sector's ``load``
   nodes (003: "two nodes of the tie-boss prism of each blade"); the static solution with the
   contacts under those forces is released (zero velocity, forces off) and integrated by
   :func:`~fricdamp.solvers.modal_transient.integrate_modal` (Newmark, 003: gamma = 0.5);
   the probe's envelope gives the damping ratio from the logarithmic decrement
   (:func:`~fricdamp.signals.decay.decay_damping`). Every node pair's state (open / stick /
   slip) is recorded at every saved instant (003 Figs 17-18).

The probe signal is the displacement of blade 0's ``probe`` node along ``probe_direction``
(the blade's flexural direction) from the prestressed rest state.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace

import numpy as np

from fricdamp.errors import ModelError, check_positive
from fricdamp.structure.contact_patch import ContactPatch
from fricdamp.structure.cyclic import CyclicSector

__all__ = ["ContactSettings", "ContactWheel", "SolidDecayRun", "WheelSector",
           "build_contact_wheel", "cyclic_contact_rows", "rayleigh_coefficients",
           "sector_from_solid"]

log = logging.getLogger(__name__)

GROUPS = ("contact_left", "contact_right", "probe")


@dataclass(frozen=True)
class ContactSettings:
    """Contact parameters of the wheel's patches (defaults: paper 003 section 2.4).

    Attributes
    ----------
    mu_static, mu_sliding : float
        Friction coefficients mu_s, mu_d [-] of 003 (2) (0.4, 0.2).
    decay_s_per_m : float
        DC [s/m] of 003 (2) (4).
    penalty_factor : float
        ``k_n = penalty_factor E A / h`` per node pair [-] (> 0; FE codes' default 1).
    tangential_ratio : float
        ``k_t / k_n`` (ANSYS FKT, default 1).
    prestress_N : float
        Static normal force per contact (whole patch) the offset is calibrated to [N]
        (003: 2.4 N).
    """

    mu_static: float = 0.4
    mu_sliding: float = 0.2
    decay_s_per_m: float = 4.0
    penalty_factor: float = 1.0
    tangential_ratio: float = 1.0
    prestress_N: float = 2.4

    def __post_init__(self):
        check_positive("mu_static", self.mu_static, allow_zero=True)
        check_positive("mu_sliding", self.mu_sliding, allow_zero=True)
        if self.mu_sliding > self.mu_static:
            raise ModelError(f"mu_sliding must be <= mu_static, got {self.mu_sliding} > "
                             f"{self.mu_static}")
        check_positive("decay_s_per_m", self.decay_s_per_m, unit="s/m", allow_zero=True)
        check_positive("penalty_factor", self.penalty_factor)
        check_positive("tangential_ratio", self.tangential_ratio)
        check_positive("prestress_N", self.prestress_N, unit="N")

    def with_(self, **changes) -> ContactSettings:
        return replace(self, **changes)


@dataclass(frozen=True)
class WheelSector:
    """A cyclic FE sector with its contact patch, ready for the pipeline.

    Attributes
    ----------
    cyclic : CyclicSector
        The sector (sparse M, K; Cartesian DOF frames; supports removed). Its
        ``named_dofs`` hold ``contact_left`` and ``contact_right`` (x, y, z triples of the
        face nodes, in the order of the patch's face-node lists), ``probe`` (the first
        triple is the probe node) and optionally ``load`` (nodes where the modal forces
        act; without it a pure-mode start is used).
    patch : ContactPatch
        Node pairs of the right face of a sector and the left face of the next.
    youngs_modulus : float
        E of the solid at the faces [Pa] (penalty stiffness).
    probe_direction : ndarray, shape (3,)
        Unit direction of the probe signal (blade 0's flexural direction).
    rayleigh : tuple of float
        ``(a, b)``: material damping ``D = a M + b K`` [1/s, s].
    info : dict
        Descriptive numbers for summary.json (element type, element count, ...).
    solid_dofs : ndarray of int, optional
        DOF of the solid model (:class:`~fricdamp.structure.solid.SolidModel`) behind each
        sector DOF (the supports removed); set by :func:`sector_from_solid`.
    """

    cyclic: CyclicSector
    patch: ContactPatch
    youngs_modulus: float
    probe_direction: np.ndarray
    rayleigh: tuple = (0.0, 0.0)
    info: dict = field(default_factory=dict)
    solid_dofs: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        if not isinstance(self.cyclic, CyclicSector):
            raise ModelError(f"cyclic must be a CyclicSector, got {type(self.cyclic).__name__}")
        for g in GROUPS:
            if g not in self.cyclic.named_dofs:
                raise ModelError(f"the sector needs the DOF group {g!r}; it has "
                                 f"{sorted(self.cyclic.named_dofs)}")
        n_face = self.cyclic.named_dofs["contact_right"].size
        if n_face != 3 * self.patch.n_pairs or \
                self.cyclic.named_dofs["contact_left"].size != n_face:
            raise ModelError(f"contact_left/contact_right must hold 3 DOFs for each of the "
                             f"patch's {self.patch.n_pairs} node pairs, got "
                             f"{self.cyclic.named_dofs['contact_left'].size} and {n_face}")
        d = np.asarray(self.probe_direction, dtype=float).reshape(3)
        object.__setattr__(self, "probe_direction", d / np.linalg.norm(d))


def rayleigh_coefficients(damping_ratio: float, band_hz=(40.0, 60.0)) -> tuple[float, float]:
    """(a, b) [1/s, s] of Rayleigh damping ``a M + b K`` with the ratio ``damping_ratio`` at
    the two frequencies of ``band_hz`` [Hz] (003: 0.1 %)."""
    z = float(check_positive("damping_ratio", damping_ratio, allow_zero=True))
    f1, f2 = (float(f) for f in band_hz)
    if not 0 < f1 < f2:
        raise ModelError(f"damping_band_hz must be two frequencies 0 < f1 < f2 [Hz], got "
                         f"{band_hz!r}")
    w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
    return 2 * z * w1 * w2 / (w1 + w2), 2 * z / (w1 + w2)


def sector_from_solid(solid, *, n_sectors: int, youngs_modulus: float,
                      probe_direction, rayleigh=(0.0, 0.0), axis="z", clamp: str = "clamp",
                      cut_left: str = "cut_left", cut_right: str = "cut_right",
                      contact_left: str = "contact_left", contact_right: str = "contact_right",
                      probe: str = "probe", load: str | None = "load",
                      info: dict | None = None) -> WheelSector:
    """A :class:`WheelSector` from an assembled solid sector and its named node sets.

    Parameters
    ----------
    solid : SolidModel
        The sector (:func:`fricdamp.structure.solid.assemble_solid`), in the frame of
        sector 0 of a wheel whose axis is ``axis``.
    n_sectors : int
        Sectors N of the wheel (sector angle 2 pi / N).
    youngs_modulus : float
        E at the contact faces [Pa] (penalty stiffness).
    probe_direction : array_like (3,)
        Direction of the probe signal (e.g. the blade's flexural direction).
    rayleigh : (float, float)
        Material damping ``a M + b K`` [1/s, s] (:func:`rayleigh_coefficients`).
    axis : {"x", "y", "z"} or array_like (3,)
        Wheel axis.
    clamp, cut_left, cut_right, contact_left, contact_right, probe, load : str
        Names of the node sets: supported nodes (all DOFs fixed), the cyclic cut faces
        (the right one is the left one rotated by +2 pi / N about the axis), the contact
        faces (likewise), the probe node (its first node) and the nodes of the modal
        forces (``None``: a pure-mode start).
    info : dict, optional
        Extra descriptive numbers.

    Raises
    ------
    ModelError
        A missing set, faces that do not match node to node, a contact face touching a cut
        or the clamp.
    """
    from fricdamp.structure.contact_patch import pair_faces, patch_from_faces

    N = int(n_sectors)
    if N < 2:
        raise ModelError(f"n_sectors must be an integer >= 2, got {n_sectors!r}")
    alpha = 2 * np.pi / N
    names = [clamp, cut_left, cut_right, contact_left, contact_right, probe] + (
        [load] if load else [])
    for name in names:
        if name not in solid.node_sets:
            raise ModelError(f"the mesh has no node set {name!r}; it has "
                             f"{sorted(solid.node_sets)}")
    fixed = np.zeros(solid.n_nodes, dtype=bool)
    fixed[solid.node_sets[clamp]] = True
    free_dofs = solid.dofs[~fixed].reshape(-1)
    free_dofs.sort()
    pos = np.full(solid.n_dof, -1, dtype=np.int64)
    pos[free_dofs] = np.arange(free_dofs.size)

    def dofs(nodes):
        return pos[solid.dofs[np.asarray(nodes, dtype=np.int64)].reshape(-1)]

    # cyclic cuts: right[k] is left[k] rotated; supported cut nodes leave both sides
    L, R = solid.node_sets[cut_left], solid.node_sets[cut_right]
    partner = pair_faces(solid.points[R], solid.points[L], alpha, axis=axis)
    Lp = L[partner]
    keep = ~fixed[R] & ~fixed[Lp]
    if np.any(fixed[R] != fixed[Lp]):
        raise ModelError("the clamp is not cyclically symmetric: a cut node is supported on "
                         "one side only")
    left, right = dofs(Lp[keep]), dofs(R[keep])
    # contact faces, pairs in the right face's order
    CR, CL = solid.node_sets[contact_right], solid.node_sets[contact_left]
    busy = np.zeros(solid.n_nodes, dtype=bool)
    busy[np.concatenate([L, R])] = True
    busy |= fixed
    if busy[CR].any() or busy[CL].any():
        raise ModelError("the contact faces must not touch the cut faces or the clamp")
    facets = solid.surface_facets(CR)
    ids, areas = solid.tributary_areas(facets)
    nid, normals = solid.node_normals(facets)
    a_of = dict(zip(ids.tolist(), areas.tolist(), strict=True))
    n_of = {int(i): v for i, v in zip(nid, normals, strict=True)}
    missing = [int(i) for i in CR if int(i) not in a_of]
    if missing:
        raise ModelError(f"contact_right nodes {missing[:5]} lie on no boundary facet of the "
                         "face")
    patch = patch_from_faces(solid.points[CR], solid.points[CL],
                             right_areas=[a_of[int(i)] for i in CR],
                             right_normals=np.array([n_of[int(i)] for i in CR]),
                             sector_angle=alpha, element_size=solid.element_size(CR),
                             axis=axis)
    CLp = CL[patch.left]
    patch = replace(patch, left=np.arange(patch.n_pairs))
    named = {"contact_left": dofs(CLp), "contact_right": dofs(CR),
             "probe": dofs(solid.node_sets[probe][:1])}
    if load:
        named["load"] = dofs(solid.node_sets[load])
    for key, d in named.items():
        if np.any(d < 0):
            raise ModelError(f"the {key} nodes must not be supported (clamp)")
    K = solid.K[free_dofs][:, free_dofs]
    M = solid.M[free_dofs][:, free_dofs]
    K = 0.5 * (K + K.T)
    M = 0.5 * (M + M.T)
    cyc = CyclicSector(M=M.tocsr(), K=K.tocsr(), left=left, right=right, n_sectors=N,
                       frame="cartesian", axis=axis, named_dofs=named, name="solid sector")
    meta = {"element_type": solid.element_type, "n_elements_sector": int(solid.n_elements),
            "sector_dof": int(free_dofs.size), "sector_nodes": int(solid.n_nodes),
            "wheel_dof": int(N * (free_dofs.size - right.size)),
            "contact_pairs_per_tieboss": int(patch.n_pairs),
            "contact_face_area_m2": patch.area, "contact_element_size_m": patch.element_size,
            "cut_dof": int(left.size)}
    meta.update(info or {})
    return WheelSector(cyc, patch, float(youngs_modulus), np.asarray(probe_direction),
                       rayleigh=tuple(rayleigh), info=meta, solid_dofs=free_dofs)


@dataclass(frozen=True, eq=False)
class SolidDecayRun:
    """A free attenuation of the contact wheel (:meth:`ContactWheel.free_decay`).

    Attributes
    ----------
    nd : int
    t : ndarray, shape (n_t,)
        Time [s].
    signal : ndarray, shape (n_t,)
        Probe displacement of blade 0 from rest along ``probe_direction`` [m].
    blades : ndarray, shape (n_t, N)
        The same for every blade [m].
    decay, amplitude_decay : DecayResult or None
        Peak envelope (half cycles) and Hilbert envelope.
    damping_ratio : float
        Record-average ratio from the log decrement of the envelope [-].
    initial_amplitude_m : float
    runtime_s, cpu_s : float
        Wall and CPU time of the time loop [s].
    energy_balance_error : float
    state_fractions : dict
        Fractions of (node pair, instant) samples open / stick / slip.
    status : ndarray of int8, shape (n_t, N, n_pairs)
        Node-pair states 0 open, 1 stick, 2 slip.
    t_contacts, contact_force : ndarray
        Instants [s] and forces [N] (n_tc, N, n_pairs, 3) stored every ``contact_every``.
    normal_force_rest_N : float
        Static normal force per contact at rest [N].
    offset_m : float
        Interference offset [m].
    meta : dict
    resultants : PatchResultants or None
        Resultant normal and tangential force, twisting and tilting moments and centre of
        pressure of every contact at ``t_contacts`` (leading shape (n_tc, N);
        :meth:`~fricdamp.structure.contact_patch.ContactPatch.resultants`).
    """

    nd: int
    t: np.ndarray
    signal: np.ndarray
    blades: np.ndarray
    decay: object
    amplitude_decay: object
    damping_ratio: float
    initial_amplitude_m: float
    runtime_s: float
    cpu_s: float
    energy_balance_error: float
    state_fractions: dict
    status: np.ndarray
    t_contacts: np.ndarray
    contact_force: np.ndarray
    normal_force_rest_N: float
    offset_m: float
    meta: dict = field(default_factory=dict)
    resultants: object = None

    def resultant_summary(self, contact: int = 0) -> dict | None:
        """Extremes over the record of one contact's resultants (default contact 0, between
        blades 0 and 1): normal force [N], tangential force magnitude [N], twisting moment
        about the face normal and tilting moment magnitude [N m], distance of the centre of
        pressure from the face centroid [m], and the share of samples with no normal force
        (the whole face open)."""
        r = self.resultants
        if r is None:
            return None
        fn = r.normal_force[:, contact]
        ft = np.hypot(*r.tangential_force[:, contact].T)
        mn = r.moment[:, contact, 0]
        mt = np.hypot(r.moment[:, contact, 1], r.moment[:, contact, 2])
        cp = np.hypot(*r.center_of_pressure[:, contact].T)
        closed = np.isfinite(cp)
        return {"contact": contact, "normal_force_N": [float(fn.min()), float(fn.max())],
                "tangential_force_max_N": float(ft.max()),
                "twisting_moment_max_Nm": float(np.abs(mn).max()),
                "tilting_moment_max_Nm": float(mt.max()),
                "center_of_pressure_offset_max_m": float(cp[closed].max()) if closed.any()
                else None,
                "open_fraction": float(1.0 - closed.mean())}

    def summary(self) -> dict:
        """The contract entry (nd, damping_ratio, initial_amplitude_m, runtime_s,
        energy_balance_error, state_fractions) plus extras."""
        out = {"nd": self.nd, "damping_ratio": self.damping_ratio,
               "initial_amplitude_m": self.initial_amplitude_m, "runtime_s": self.runtime_s,
               "cpu_s": self.cpu_s, "energy_balance_error": self.energy_balance_error,
               "state_fractions": self.state_fractions,
               "normal_force_rest_N": self.normal_force_rest_N, "offset_m": self.offset_m}
        if self.resultants is not None:
            out["contact_resultants"] = self.resultant_summary(0)
        if self.decay is not None:
            out["frequency_hz"] = self.decay.mean_frequency_hz
            amp = self.amplitude_decay if self.amplitude_decay is not None else self.decay
            out["amplitude_m"] = amp.amplitude.tolist()
            out["amplitude_damping_ratio"] = amp.damping_ratio.tolist()
            out["amplitude_method"] = amp.method
        out.update(self.meta)
        return out


def cyclic_contact_rows(modes, patch: ContactPatch, named_dofs):
    """Contact rows of the wheel modes by harmonic (:class:`~fricdamp.solvers.
    modal_transient.CyclicRows`) from the complex sector shapes of ``modes``.

    Contact j joins sector j's right face to sector j + 1's left face; with sector j moving
    as ``Re/Im(exp(i k j alpha) u~)`` (:class:`~fricdamp.structure.cyclic_reduction.
    WheelModes`), its relative displacement is ``Re/Im(exp(i k j alpha) X_k)`` with
    ``X_k = Lambda (u~_right - exp(i k alpha) R u~_left)`` per node pair.
    """
    from fricdamp.solvers.modal_transient import CyclicRows

    N = modes.n_sectors
    alpha = 2 * np.pi / N
    R = patch.rotation
    iR = np.asarray(named_dofs["contact_right"]).reshape(-1, 3)[patch.right].reshape(-1)
    iL = np.asarray(named_dofs["contact_left"]).reshape(-1, 3)[patch.left].reshape(-1)
    P = patch.n_pairs
    blocks, columns = [], []
    for k_idx, nd in enumerate(modes.nds):
        U = np.asarray(modes.sector_shapes[k_idx])
        m = U.shape[1]
        uR = U[iR].reshape(P, 3, m)
        uL = U[iL].reshape(P, 3, m)
        rel = uR - np.exp(1j * nd * alpha) * np.einsum("ab,pbm->pam", R, uL)
        blocks.append(np.einsum("pab,pbm->pam", patch.frames, rel).reshape(3 * P, m))
        columns.append(modes.columns(int(nd)))
    return CyclicRows(N, tuple(int(k) for k in modes.nds), tuple(blocks), tuple(columns))


class ContactWheel:
    """The reduced wheel of a :class:`WheelSector` with its modal basis (module docstring).

    Build it with :func:`build_contact_wheel`. Compliance matrices are formed once and
    cached per time step.
    """

    def __init__(self, sector: WheelSector, reduced, modes):
        self.sector = sector
        self.reduced = reduced
        self.modes = modes
        self.n_sectors = sector.cyclic.n_sectors
        self._cache: dict = {}
        from fricdamp.solvers.modal_transient import ModalBasis

        omega2 = np.asarray(modes.omega, dtype=float) ** 2
        a, b = sector.rayleigh
        rows = cyclic_contact_rows(modes, sector.patch, reduced.sector.named_dofs)
        Gp = modes.group_shapes("probe")[:, :3]                  # (N, 3, n_modes)
        out = np.einsum("a,jam->jm", sector.probe_direction, Gp)
        n_p = sector.patch.n_pairs
        self.basis = ModalBasis(omega2, a + b * omega2, rows, out,
                                groups=tuple((f"contact {j}", n_p)
                                             for j in range(self.n_sectors)))
        self.load_shapes = (modes.group_shapes("load")
                            if "load" in reduced.sector.named_dofs else None)

    # ------------------------------------------------------------------ sizes
    @property
    def n_pairs(self) -> int:
        return self.sector.patch.n_pairs

    @property
    def n_modes(self) -> int:
        return self.basis.n_modes

    @property
    def reduced_dof(self) -> int:
        """DOFs of the reduced wheel (= its number of modes)."""
        return self.basis.n_modes

    def static_compliance(self) -> np.ndarray:
        if "static" not in self._cache:
            from fricdamp.solvers.modal_transient import _static_compliance

            self._cache["static"] = _static_compliance(self.basis)
        return self._cache["static"]

    # ------------------------------------------------------------------ contacts
    def laws(self, settings: ContactSettings, offset: float):
        """One Contact3D law with every node pair of every contact (pairs fastest)."""
        return [self.sector.patch.law(
            youngs_modulus=self.sector.youngs_modulus, penalty_factor=settings.penalty_factor,
            offset=offset, mu_static=settings.mu_static, mu_sliding=settings.mu_sliding,
            decay=settings.decay_s_per_m, tangential_ratio=settings.tangential_ratio,
            n_sectors=self.n_sectors)]

    def static(self, settings: ContactSettings, offset: float, load=None):
        """Static solution with the contacts from the virgin state (modal load or None): in
        one return-map step, or -- when that does not converge (stiff penalties) -- along a
        quasi-static path of 8 or 32 increments."""
        from fricdamp.errors import ConvergenceError
        from fricdamp.solvers.modal_transient import solve_static_modal

        laws = self.laws(settings, offset)
        for increments in (1, 8, 32):
            try:
                return solve_static_modal(self.basis, laws, load, increments=increments,
                                          compliance=self.static_compliance())
            except ConvergenceError:
                # stiff penalties: the one-step return map cycles between contact states;
                # a quasi-static path of interference and load converges
                if increments == 32:
                    raise
                log.info("static solution did not converge in %d increment(s): retrying on "
                         "a finer quasi-static path", increments)

    def normal_force_per_contact(self, static) -> np.ndarray:
        """Static normal force of each contact (sum over its node pairs) [N], shape (N,)."""
        return static.f[:, 0].reshape(self.n_sectors, self.n_pairs).sum(axis=1)

    def calibrate_offset(self, settings: ContactSettings, *, rel_tol: float = 1e-3,
                         max_iter: int = 12) -> tuple[float, object]:
        """Interference offset [m] giving ``settings.prestress_N`` per contact at rest.

        The force grows with the offset (linearly while every pair stays closed; friction
        couples the directions a little): secant iteration from the estimate of the
        penalty alone. Returns (offset, static solution at rest).
        """
        target = settings.prestress_N
        kn = self.sector.patch.normal_stiffness(self.sector.youngs_modulus,
                                                settings.penalty_factor).sum()
        g = [target / kn]
        F = []
        st = None
        for _ in range(max_iter):
            st = self.static(settings, g[-1])
            F.append(float(np.mean(self.normal_force_per_contact(st))))
            if abs(F[-1] / target - 1.0) <= rel_tol:
                return g[-1], st
            if len(F) == 1 or F[-1] == F[-2]:
                g.append(g[-1] * target / max(F[-1], 1e-300))
            else:
                slope = (F[-1] - F[-2]) / (g[-1] - g[-2])
                g.append(g[-1] + (target - F[-1]) / slope if slope > 0
                         else g[-1] * target / F[-1])
        raise ModelError(f"could not calibrate the contact offset for {target} N per contact "
                         f"(last: {F[-1]:.4g} N at offset {g[-2]:.4g} m)")

    # ------------------------------------------------------------------ ND start
    def nd_mode(self, nd: int) -> np.ndarray:
        """Modal coordinates (unit mass-normalised) of the open-contact standing wave of the
        first mode of ``nd`` nodal diameters with blade 0's probe at an antinode."""
        modes = self.modes
        idx = np.flatnonzero(np.asarray(modes.nd) == int(nd))
        if idx.size == 0:
            raise ModelError(f"nd must be a nodal diameter in [0, {self.n_sectors // 2}], "
                             f"got {nd!r}")
        w = np.asarray(modes.omega)[idx]
        first = idx[np.isclose(w, w.min(), rtol=1e-9, atol=0.0)][:2]
        e = np.zeros(self.n_modes)
        a = self.basis.output[0, first]
        if np.all(a == 0):
            raise ModelError(f"the {nd}ND mode does not move blade 0's probe")
        e[first] = a / np.linalg.norm(a)
        return e

    def nd_load(self, nd: int, forcing: str = "tieboss") -> np.ndarray:
        """Modal load of the ND affinity forces for a unit scale.

        ``tieboss``: at every sector's ``load`` DOFs the force equals the mode shape there
        (003 section 3, step 1); ``modal``: ``M phi`` (a pure-mode start).
        """
        e = self.nd_mode(nd)
        if forcing == "modal" or self.load_shapes is None:
            return e
        if forcing != "tieboss":
            raise ModelError(f"forcing must be 'tieboss' or 'modal', got {forcing!r}")
        G = self.load_shapes                                   # (N, n_load, n_modes)
        v = G @ e                                              # (N, n_load)
        return np.einsum("jlm,jl->m", G, v)

    def initial_deformation(self, nd: int, amplitude_m: float, settings: ContactSettings,
                            offset: float, *, forcing: str = "tieboss", rel_tol: float = 0.01,
                            max_iter: int = 8):
        """Static solution under the ND forces whose probe displacement (blade 0, from
        rest) is ``amplitude_m`` within ``rel_tol`` (secant on the force scale).

        Returns (static solution, rest solution, amplitude reached).
        """
        amp = float(check_positive("amplitude_m", amplitude_m, unit="m"))
        rest = self.static(settings, offset)
        x_rest = float(self.basis.output[0] @ rest.eta)
        shape = self.nd_load(nd, forcing)
        a_lin = float(self.basis.output[0] @ (shape / self.basis.omega2))
        if a_lin == 0.0:
            raise ModelError(f"the {nd}ND forces do not move the probe")
        scales = [amp / a_lin]
        amps = []
        st = None
        for _ in range(max_iter):
            st = self.static(settings, offset, scales[-1] * shape)
            amps.append(float(self.basis.output[0] @ st.eta) - x_rest)
            if abs(amps[-1] / amp - 1.0) <= rel_tol:
                break
            if len(amps) == 1:
                scales.append(scales[-1] * amp / amps[-1])
            else:
                slope = (amps[-1] - amps[-2]) / (scales[-1] - scales[-2])
                scales.append(scales[-1] + (amp - amps[-1]) / slope if slope > 0
                              else scales[-1] * amp / amps[-1])
        return st, rest, amps[-1]

    # ------------------------------------------------------------------ decay
    def free_decay(self, nd: int, *, amplitude_m: float = 5e-4, duration_s: float = 0.1,
                   dt: float = 2e-5, settings: ContactSettings | None = None,
                   offset: float | None = None, forcing: str = "tieboss",
                   save_every: int = 1, contact_every: int = 50, method: str = "newmark",
                   progress: bool | None = None) -> SolidDecayRun:
        """The paper's strategy for one ND (module docstring, step 3).

        Parameters
        ----------
        nd : int
            Nodal diameter (003: 2 and 6).
        amplitude_m : float
            Initial probe displacement from rest [m] (003: up to 0.5 mm).
        duration_s, dt : float
            Length of the attenuation and time step [s] (003: 0.1 s, 5e-6 s).
        settings : ContactSettings, optional
            Friction, penalty factor and prestress (default: paper 003's).
        offset : float, optional
            Interference offset [m]; default: calibrated for ``settings.prestress_N``.
        forcing : {"tieboss", "modal"}
            ND forces at the ``load`` nodes (003) or a pure-mode start.
        save_every, contact_every : int
            Store outputs and states every k-th step, contact forces every k-th step.
        method : {"newmark", "hht"}
        progress : bool, optional
            Progress bar.
        """
        from fricdamp.models.tieboss_wheel.studies import decay_estimates
        from fricdamp.solvers.modal_transient import integrate_modal, transient_compliance

        settings = ContactSettings() if settings is None else settings
        dur = float(check_positive("duration_s", duration_s, unit="s"))
        h = float(check_positive("dt", dt, unit="s"))
        if offset is None:
            offset, _ = self.calibrate_offset(settings)
        st, rest, amp = self.initial_deformation(nd, amplitude_m, settings, offset,
                                                 forcing=forcing)
        key = ("transient", h, method)
        if key not in self._cache:
            self._cache[key] = transient_compliance(self.basis, h, method=method)
        laws = self.laws(settings, offset)
        res = integrate_modal(self.basis, laws, dur, h, eta0=st.eta, states0=st.states,
                              method=method, save_every=save_every,
                              contact_every=contact_every, progress=progress,
                              compliance=self._cache[key])
        x_rest = self.basis.output @ rest.eta
        blades = res.output - x_rest[None, :]
        t, x = res.t, blades[:, 0]
        dec, hil, zeta = decay_estimates(t, x, f"{nd}ND")
        N, npair = self.n_sectors, self.n_pairs
        forces = res.contact_force.reshape(-1, N, npair, 3)
        return SolidDecayRun(
            nd=int(nd), t=t, signal=x, blades=blades, decay=dec, amplitude_decay=hil,
            damping_ratio=zeta, initial_amplitude_m=float(x[0]), runtime_s=res.runtime_s,
            cpu_s=res.cpu_s, energy_balance_error=res.energy_balance_error,
            state_fractions=res.state_fractions(),
            status=res.contact_status.reshape(-1, N, npair), t_contacts=res.t_contacts,
            contact_force=forces, resultants=self.sector.patch.resultants(forces),
            normal_force_rest_N=float(np.mean(self.normal_force_per_contact(rest))),
            offset_m=float(offset),
            meta={"dt_s": h, "duration_s": dur, "method": method, "forcing": forcing,
                  "penalty_factor": settings.penalty_factor, "n_iterations": res.n_iterations,
                  "n_krylov": res.n_krylov, "setup_s": res.setup_s,
                  "n_halved_steps": res.meta["n_halved_steps"],
                  "n_loose_steps": res.meta["n_loose_steps"],
                  "largest_loose_residual": res.meta["largest_loose_residual"],
                  "static_amplitude_m": amp, "success": res.success})


def build_contact_wheel(sector: WheelSector, *, n_modes: int = 30,
                        n_interface_modes: int = 30) -> ContactWheel:
    """Reduce the sector and find every mode of the reduced wheel (module docstring).

    Parameters
    ----------
    sector : WheelSector
    n_modes : int
        Fixed-interface modes of the sector (Craig-Bampton).
    n_interface_modes : int
        Characteristic interface modes of the cyclic cut.
    """
    from fricdamp.structure.cyclic_reduction import reduce_sector, wheel_modes

    if not isinstance(sector, WheelSector):
        raise ModelError(f"sector must be a WheelSector, got {type(sector).__name__}")
    keep = {g: d for g, d in sector.cyclic.named_dofs.items()
            if g in GROUPS or g == "load"}
    red = reduce_sector(sector.cyclic, keep=keep, n_modes=int(n_modes),
                        n_interface_modes=int(n_interface_modes), method="auto",
                        rayleigh=tuple(sector.rayleigh))
    modes = wheel_modes(red.sector)
    return ContactWheel(sector, red, modes)
