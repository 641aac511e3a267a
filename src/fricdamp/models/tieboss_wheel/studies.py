"""Analyses of the tie-boss wheel of paper 003: modes by ND, Campbell, damping strategy.

* :func:`modal_by_nd` -- open-contact eigenfrequencies by nodal diameter from one sector
  with the complex cyclic constraint (003 Table 1), and :func:`full_wheel_frequencies`, the
  same from the assembled wheel (both must agree).
* :func:`campbell_by_nd` and :func:`critical_speeds_by_nd` -- the rotating wheel's ND
  frequencies over 60-450 rpm (stress stiffening and spin softening of the sector; the
  Coriolis coupling of these flexural modes is neglected) and the crossings with the
  engine-order lines of ``p = 8`` electromagnet pulses, 003 (1) ``s = 60 f_R / (p o)``
  (Table 2: o = 1 with the 2ND mode near 334 rpm, o = 3 with the 6ND mode near 123 rpm).
* :func:`free_decay` -- the paper's damping strategy (003 section 3): (1) the open-contact
  mode of the chosen ND gives "affinity" forces at the tie-boss nodes of every blade, (2) the
  static solution of the prestressed wheel with its contacts under those forces, (3) the free
  attenuation from that deformation with zero velocity (implicit Newmark with the contact
  return maps), (4) the envelope of the probe displacement and the damping ratio from its
  logarithmic decrement, and the amplitude-dependent ratio along the decay.
* :func:`reduction_comparison` -- the same decay on the full-order wheel (the general
  :func:`~fricdamp.solvers.timestep.simulate`) and on the Craig-Bampton wheel (the compiled
  :func:`~fricdamp.solvers.fast_transient.integrate_contact3d`): DOFs, damping ratios and
  their relative difference, run times and their ratio.
* :func:`run_tieboss_case` -- all of them as the ``summary.json`` contract of
  ``examples/cases/tieboss_wheel.toml``.

Conventions. The decay signal is the displacement of blade 0's right contact node (the
paper's node in the midst of contact B) along blade 0's flexural direction, measured from
the prestressed equilibrium at rest; blade 0 sits on an antinode of the standing wave (the
mode's phase is chosen so). ``damping_ratio`` is the record-average ratio from the first and
last envelope peaks, ``zeta = delta / sqrt(4 pi^2 + delta^2)`` with ``delta`` the mean
logarithmic decrement per cycle (:func:`fricdamp.signals.decay.decay_damping`), i.e. what
003 reports (its 0.1 % material damping included).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError, as_finite_array, check_positive
from fricdamp.models.tieboss_wheel.model import (
    TABLE1_FEM_HZ,
    TiebossSector,
    TiebossWheel,
    TiebossWheelParameters,
    build_sector,
    build_wheel,
    table1_targets,
)
from fricdamp.signals.decay import DecayResult, decay_damping
from fricdamp.solvers.fast_transient import integrate_contact3d, solve_static
from fricdamp.structure.cyclic import CyclicSector, nodal_diameter_modes

__all__ = [
    "CampbellByND",
    "DecayRun",
    "campbell_by_nd",
    "critical_speeds_by_nd",
    "free_decay",
    "full_wheel_frequencies",
    "initial_deformation",
    "modal_by_nd",
    "modal_force",
    "reduction_comparison",
    "run_tieboss_case",
]

log = logging.getLogger(__name__)

#: 003 Table 2: excitation order o of the p = 8 pulses and the ND of the mode it excites.
TABLE2_ORDERS = ((1, 2), (3, 6))
TABLE2_RPM = {1: 334.0, 3: 123.0}
TABLE2_FREQUENCY_HZ = {1: 44.53, 3: 49.20}


def _sector(obj) -> TiebossSector:
    if obj is None:
        return build_sector()
    if isinstance(obj, TiebossWheelParameters):
        return build_sector(obj)
    if isinstance(obj, TiebossWheel):
        return obj.sector
    if isinstance(obj, TiebossSector):
        return obj
    raise ModelError(f"expected TiebossWheelParameters, TiebossSector or TiebossWheel, got "
                     f"{type(obj).__name__}")


def _int(name: str, v, low: int) -> int:
    if isinstance(v, bool) or int(v) != v or v < low:
        raise ModelError(f"{name} must be an integer >= {low}, got {v!r}")
    return int(v)


# =============================================================================== modal
def modal_by_nd(model=None, *, n_modes: int = 1, cyclic: CyclicSector | None = None) -> dict:
    """Open-contact eigenfrequencies by nodal diameter (cyclic symmetry, one sector).

    Parameters
    ----------
    model : TiebossWheelParameters, TiebossSector or TiebossWheel, optional
        Default: the tuned wheel. For a reduced wheel the reduced sector is used.
    n_modes : int
        Modes per ND (the first is the blade family of Table 1).
    cyclic : CyclicSector, optional
        Sector to analyse instead (any cyclic sector).

    Returns
    -------
    dict
        ``nd`` [0 .. N/2], ``frequency_hz`` (first mode of each ND), ``families_hz``
        (``n_modes`` per ND), ``table1`` (ND, paper FEM pair, model, relative error to the
        pair mean) and ``max_table1_error`` (largest |relative error|).
    """
    if cyclic is None:
        cyclic = model.cyclic if isinstance(model, TiebossWheel) else _sector(model).cyclic
    n_modes = _int("n_modes", n_modes, 1)
    fam = np.array([nodal_diameter_modes(cyclic, int(nd), n_modes).frequencies
                    for nd in cyclic.nodal_diameters])
    out = {"nd": cyclic.nodal_diameters.tolist(), "frequency_hz": fam[:, 0].tolist(),
           "families_hz": fam.tolist()}
    if cyclic.n_sectors == 30:
        tg = table1_targets()
        rows = [{"nd": nd, "paper_fem_hz": list(TABLE1_FEM_HZ[nd]), "model_hz": fam[nd, 0],
                 "relative_error": fam[nd, 0] / tg[nd] - 1.0} for nd in sorted(tg)]
        out["table1"] = rows
        out["max_table1_error"] = max(abs(r["relative_error"]) for r in rows)
    return out


def full_wheel_frequencies(wheel: TiebossWheel, n_modes: int | None = None) -> np.ndarray:
    """Lowest eigenfrequencies [Hz] of the assembled open-contact wheel (contacts ignored).

    ``n_modes`` defaults to N (the whole first family). Computed by shift-invert ARPACK on
    the sparse (full) or dense (reduced) assembled matrices.
    """
    from fricdamp.solvers.modal import modes

    n = wheel.n_blades if n_modes is None else _int("n_modes", n_modes, 1)
    return modes(wheel.system, n, kind="undamped", contacts="open").frequencies


# =============================================================================== Campbell
@dataclass(frozen=True)
class CampbellByND:
    """First-family frequencies of the rotating wheel by ND.

    Attributes
    ----------
    rpm : ndarray, shape (n_speeds,)
    nd : ndarray of int, shape (n_nd,)
    frequency_hz : ndarray, shape (n_speeds, n_nd)
        Frequencies [Hz] in the rotating frame.
    """

    rpm: np.ndarray
    nd: np.ndarray
    frequency_hz: np.ndarray

    def plot(self, orders=(1, 2, 3), pulses: int = 8, ax=None):
        """Campbell diagram with the excitation lines ``p o n / 60``; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4.5))
        cmap = plt.get_cmap("viridis")
        for k, nd in enumerate(self.nd):
            ax.plot(self.rpm, self.frequency_hz[:, k], color=cmap(k / max(len(self.nd) - 1, 1)),
                    lw=1.2, label=f"{nd}ND" if nd in (0, 2, 6, self.nd.max()) else None)
        fmin, fmax = self.frequency_hz.min(), self.frequency_hz.max()
        for o in orders:
            f = pulses * o * self.rpm / 60.0
            ax.plot(self.rpm, f, "k--", lw=0.8)
            inside = np.flatnonzero((f > 0.9 * fmin) & (f < 1.05 * fmax))
            if inside.size:
                i = inside[inside.size // 2]
                ax.annotate(f"o={o}", (self.rpm[i], f[i]), fontsize=8)
        ax.set_ylim(0.9 * fmin, 1.05 * fmax)
        ax.set_xlabel("speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_title(f"Campbell diagram, p = {pulses} pulses per revolution")
        ax.legend(fontsize="small", loc="lower right")
        ax.grid(alpha=0.3)
        return ax


def _sector_at_speed(sector: TiebossSector, omega: float) -> CyclicSector:
    r = sector.rotation
    if r is None:
        raise ModelError("the sector has no rotation terms (imported sectors do not); "
                         "build it with build_sector(params, rotation=True)")
    K = sector.cyclic.K
    if r.stress_stiffening is not None:
        K = K + omega**2 * r.stress_stiffening
    if r.spin_softening is not None:
        K = K - omega**2 * r.spin_softening
    return replace(sector.cyclic, K=sp.csr_matrix(0.5 * (K + K.T)))


def campbell_by_nd(model=None, rpm=None, nds=None) -> CampbellByND:
    """First-family frequencies by ND of the rotating wheel over ``rpm``.

    At spin speed Omega the sector stiffness is ``K + Omega^2 (K_w - K_d)`` (stress
    stiffening from the centrifugal prestress of the sector, spin softening); the Coriolis
    (gyroscopic) coupling is neglected (it is O(Omega / w) ~ 2 % of these flexural modes at
    450 rpm and shifts their frequencies by its square). Contacts open, as Table 1.

    Parameters
    ----------
    model : TiebossWheelParameters or TiebossSector, optional
    rpm : array_like, optional
        Speeds [rpm] >= 0; default 60 to 450 rpm in 40 steps (003 Fig. 6).
    nds : sequence of int, optional
        Nodal diameters; default all (0 .. N/2).
    """
    sector = _sector(model)
    if sector.rotation is None and isinstance(model, TiebossWheel):
        sector = build_sector(sector.parameters)
    rpm = np.linspace(60.0, 450.0, 40) if rpm is None else np.atleast_1d(
        as_finite_array("rpm", rpm)).astype(float)
    if rpm.ndim != 1 or rpm.size == 0 or np.any(rpm < 0):
        raise ModelError(f"rpm must be a non-empty list of speeds >= 0, got {rpm!r}")
    nds = sector.cyclic.nodal_diameters if nds is None else np.asarray(
        [sector.cyclic._check_nd(nd) for nd in np.atleast_1d(nds)])
    F = np.empty((rpm.size, len(nds)))
    for i, n in enumerate(rpm):
        cyc = _sector_at_speed(sector, n * np.pi / 30.0)
        F[i] = [nodal_diameter_modes(cyc, int(nd), 1).frequencies[0] for nd in nds]
    return CampbellByND(rpm=rpm, nd=np.asarray(nds, dtype=int), frequency_hz=F)


def critical_speeds_by_nd(model=None, *, orders=TABLE2_ORDERS, pulses: int = 8,
                          rpm_range=(60.0, 450.0)) -> list[dict]:
    """Critical speeds 003 (1): crossings of ND branches with the lines ``p o n / 60``.

    For each (order o, nodal diameter nd) the speed n [rpm] solving
    ``f_nd(n) = p o n / 60`` is found by Brent's method on the rotating-wheel frequency
    (:func:`campbell_by_nd` at single speeds), so ``n = 60 f_R / (p o)`` holds exactly with
    ``f_R = f_nd(n)``.

    Parameters
    ----------
    model : TiebossWheelParameters or TiebossSector, optional
    orders : sequence of (int, int)
        Pairs (o, nd); default 003 Table 2: (1, 2ND) and (3, 6ND).
    pulses : int
        Pulses per revolution p (003: 8).
    rpm_range : (float, float)
        Search interval [rpm].

    Returns
    -------
    list of dict
        ``order``, ``nd``, ``frequency_hz`` (f_R), ``rpm`` (s) and, for the Table 2 orders,
        ``paper_rpm``, ``paper_frequency_hz`` and ``paper_formula_rpm`` (003 (1) applied to
        the paper's f_R: 333.98 and 123.0 rpm); ``rpm`` is None if there is no crossing in
        the range.
    """
    from scipy.optimize import brentq

    from fricdamp.solvers.modal import critical_speeds

    sector = _sector(model)
    p = _int("pulses", pulses, 1)
    lo, hi = (float(v) for v in as_finite_array("rpm_range", rpm_range))
    if not 0 <= lo < hi:
        raise ModelError(f"rpm_range must be (low, high) with 0 <= low < high, got "
                         f"{rpm_range!r}")
    out = []
    for o, nd in orders:
        o = _int("order", o, 1)

        def f_nd(n, nd=nd):
            cyc = _sector_at_speed(sector, n * np.pi / 30.0)
            return nodal_diameter_modes(cyc, int(nd), 1).frequencies[0]

        def g(n, o=o, f_nd=f_nd):
            return f_nd(n) - p * o * n / 60.0

        entry = {"order": o, "nd": int(nd), "pulses": p}
        if g(lo) * g(hi) > 0:
            entry.update(frequency_hz=None, rpm=None)
        else:
            n = brentq(g, lo, hi, xtol=1e-9)
            f = f_nd(n)
            entry.update(frequency_hz=float(f),
                         rpm=float(critical_speeds(f, o, p)))
        if o in TABLE2_RPM:
            entry.update(paper_rpm=TABLE2_RPM[o], paper_frequency_hz=TABLE2_FREQUENCY_HZ[o],
                         paper_formula_rpm=float(critical_speeds(TABLE2_FREQUENCY_HZ[o], o,
                                                                 p)))
        out.append(entry)
    return out


# =============================================================================== decay
def _nd_shape(wheel: TiebossWheel, nd: int) -> np.ndarray:
    """Real standing-wave ND mode (open contacts) on the wheel DOFs, blade 0 at an antinode."""
    cyc = wheel.cyclic
    nd = cyc._check_nd(nd)
    modes = nodal_diameter_modes(cyc, nd, 1)
    shape = modes.full_shapes(cyc)[:, 0]
    probe = wheel.group_dofs("probe", 0)
    z = wheel.sector.flexural_direction @ shape[probe]
    if abs(z) == 0.0:
        raise ModelError(f"the {nd}ND mode does not move the probe of blade 0")
    return np.real(shape * (np.conj(z) / abs(z)))


FORCINGS = ("tieboss", "modal")


def modal_force(wheel: TiebossWheel, nd: int, *, scale: float = 1.0,
                forcing: str = "tieboss") -> np.ndarray:
    """Affinity force vector of the ``nd`` mode (003 section 3 step 1), shape (n_dof,).

    ``phi`` is the open-contact standing wave of ``nd`` nodal diameters (blade 0 at an
    antinode).

    * ``forcing="tieboss"`` (the paper's): at the translations of every blade's tie-boss
      node the force is ``scale * phi`` there [N per unit modal displacement], zero
      elsewhere. Point forces also excite the higher modes of the same ND a little (on
      the open wheel the probe then beats, and a log decrement over 0.1 s reads about
      0.14 % for the 0.098 % of the Rayleigh damping);
    * ``forcing="modal"``: ``scale * M phi`` on all DOFs, whose static response on the open
      wheel is exactly ``phi / w^2`` (a pure modal start; the decay of the open wheel then
      gives the Rayleigh ratio exactly).
    """
    if forcing not in FORCINGS:
        raise ModelError(f"forcing must be one of {FORCINGS}, got {forcing!r}")
    phi = _nd_shape(wheel, nd)
    if forcing == "modal":
        return scale * np.asarray(wheel.system.M @ phi).ravel()
    F = np.zeros(wheel.n_dof)
    dofs = wheel.group_dofs_all("tieboss").ravel()
    F[dofs] = scale * phi[dofs]
    return F


def _probe_signal(wheel: TiebossWheel, q) -> np.ndarray:
    """Probe displacement along blade 0's flexural direction, for q (n_dof,) or (n_t, n_dof)."""
    q = np.asarray(q)
    return q[..., wheel.group_dofs("probe", 0)] @ wheel.sector.flexural_direction


@dataclass(frozen=True)
class InitialDeformation:
    """Prestressed rest state and the statically deformed start of a free decay.

    Attributes
    ----------
    q_rest, q0 : ndarray, shape (n_dof,)
        Prestressed equilibrium at rest and the static solution under the modal force [m].
    states0 : list of ndarray
        Contact states of the static solution (the decay starts from them).
    force : ndarray, shape (n_dof,)
        The modal force [N].
    amplitude_m : float
        Initial probe displacement from rest [m].
    normal_force_rest_N : float
        Mean contact normal force at rest [N].
    """

    q_rest: np.ndarray
    q0: np.ndarray
    states0: list
    force: np.ndarray
    amplitude_m: float
    normal_force_rest_N: float


def initial_deformation(wheel: TiebossWheel, nd: int, amplitude_m: float = 5e-4, *,
                        forcing: str = "tieboss", rel_tol: float = 0.01,
                        max_iter: int = 8) -> InitialDeformation:
    """Steps 1-2 of the paper's strategy: modal force and static solution with contacts.

    The force scale is found by a secant iteration so that the probe displacement of the
    static solution (from the prestressed rest state) equals ``amplitude_m`` within
    ``rel_tol``. Both static problems are solved from the virgin contact state in one
    return-map step (a proportional, monotonic load path), the convention
    :func:`~fricdamp.solvers.timestep.simulate` uses for its initial state, so the full-order
    check runs from exactly the same state. ``forcing``: see :func:`modal_force`.
    """
    amp = float(check_positive("amplitude_m", amplitude_m, unit="m"))
    rest = solve_static(wheel.system, np.zeros(wheel.n_dof))
    x_rest = _probe_signal(wheel, rest.q)
    shape = modal_force(wheel, nd, forcing=forcing)
    from fricdamp.solvers.fast_transient import _factor_solver

    q_lin = _factor_solver(wheel.system.K)(shape)
    a_lin = _probe_signal(wheel, q_lin)
    if a_lin == 0.0:
        raise ModelError(f"the {nd}ND modal force does not move the probe")
    scales = [amp / a_lin]
    amps = []
    res = None
    for _ in range(max_iter):
        res = solve_static(wheel.system, scales[-1] * shape)
        amps.append(_probe_signal(wheel, res.q) - x_rest)
        if abs(amps[-1] / amp - 1.0) <= rel_tol:
            break
        if len(amps) == 1:
            scales.append(scales[-1] * amp / amps[-1])
        else:
            slope = (amps[-1] - amps[-2]) / (scales[-1] - scales[-2])
            nxt = scales[-1] + (amp - amps[-1]) / slope if slope > 0 else \
                scales[-1] * amp / amps[-1]
            scales.append(nxt)
    return InitialDeformation(q_rest=rest.q, q0=res.q, states0=res.states,
                              force=scales[len(amps) - 1] * shape, amplitude_m=float(amps[-1]),
                              normal_force_rest_N=float(np.mean(
                                  rest.contact_force[0][:, 0])))


@dataclass(frozen=True)
class DecayRun:
    """A free attenuation of the wheel from the paper's initial deformation.

    Attributes
    ----------
    nd : int
    t : ndarray, shape (n_t,)
        Time [s].
    signal : ndarray, shape (n_t,)
        Probe displacement from rest along blade 0's flexural direction [m].
    decay : DecayResult or None
        Peak envelope (one point per half cycle) and the record-average ratio (None if
        too few peaks).
    amplitude_decay : DecayResult or None
        Hilbert envelope: the amplitude-dependent ratio cycle by cycle (smoother than the
        half-cycle peaks, whose alternate values differ by the drift of the friction-locked
        rest position); None when the record holds fewer than 4 cycles.
    damping_ratio : float
        Record-average ratio (``decay.mean_damping_ratio``) [-].
    initial_amplitude_m : float
    runtime_s : float
        Time of the transient (the time loop) [s].
    solver : str
        ``"fast"`` (compiled path) or ``"simulate"`` (general solver).
    contact_status : ndarray of int8, shape (n_t, N) or None
        0 open, 1 stick, 2 slip (fast solver only).
    contact_displacement, contact_force : ndarray, shape (n_t, N, 3)
        Relative displacement [m] and force [N] of every contact (n, t1, t2).
    nodes : dict of str -> ndarray (n_t, 3)
        Displacements [m] from rest of the contact nodes of blades N-1, 0, 1 in sector-0
        components (``"B0.right"``, ``"B1.left"``: contact 0, the paper's contact B;
        ``"B29.right"``, ``"B0.left"``: the contact before it, contact A).
    energy_balance_error : float
    normal_force_rest_N : float
    n_dof : int
    meta : dict
    """

    nd: int
    t: np.ndarray
    signal: np.ndarray
    decay: DecayResult | None
    amplitude_decay: DecayResult | None
    damping_ratio: float
    initial_amplitude_m: float
    runtime_s: float
    solver: str
    contact_status: np.ndarray | None
    contact_displacement: np.ndarray
    contact_force: np.ndarray
    nodes: dict
    energy_balance_error: float
    normal_force_rest_N: float
    n_dof: int
    meta: dict = field(default_factory=dict, compare=False)

    def summary(self) -> dict:
        """The contract entry: nd, damping_ratio, initial_amplitude_m, runtime_s (+ extras)."""
        out = {"nd": self.nd, "damping_ratio": self.damping_ratio,
               "initial_amplitude_m": self.initial_amplitude_m, "runtime_s": self.runtime_s,
               "solver": self.solver, "n_dof": self.n_dof,
               "normal_force_rest_N": self.normal_force_rest_N,
               "energy_balance_error": self.energy_balance_error}
        if self.decay is not None:
            out["frequency_hz"] = self.decay.mean_frequency_hz
            out["envelope_model"] = self.decay.model
            amp = self.amplitude_decay if self.amplitude_decay is not None else self.decay
            out["amplitude_m"] = amp.amplitude.tolist()
            out["amplitude_damping_ratio"] = amp.damping_ratio.tolist()
            out["amplitude_method"] = amp.method
        if self.contact_status is not None:
            st = self.contact_status
            out["state_fractions"] = {"open": float(np.mean(st == 0)),
                                      "stick": float(np.mean(st == 1)),
                                      "slip": float(np.mean(st == 2))}
        out.update(self.meta)
        return out


def _node_keys(wheel: TiebossWheel) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(name, wheel DOFs, rotation to sector-0 components) of the contact nodes of
    contacts A (blades N-1 | 0) and B (blades 0 | 1)."""
    N = wheel.n_blades
    return [(f"B{b}.{side}", wheel.group_dofs(f"contact_{side}", b), wheel.blade_rotation(b))
            for b, side in ((N - 1, "right"), (0, "left"), (0, "right"), (1, "left"))]


def _node_histories(wheel: TiebossWheel, q, q_rest) -> dict:
    return {key: (np.asarray(q[:, dofs]) - q_rest[dofs]) @ R.T
            for key, dofs, R in _node_keys(wheel)}


def decay_estimates(t, x, label: str = "the decay"):
    """Damping of a free-decay signal: (peak-envelope DecayResult or None, Hilbert
    DecayResult or None, record-average damping ratio or NaN).

    The peak envelope (one point per half cycle) gives the record average; the Hilbert
    envelope, the ratio cycle by cycle, when the record holds at least 4 cycles."""
    try:
        dec = decay_damping(t, x, method="peaks")
        zeta = float(dec.mean_damping_ratio)
    except ModelError as exc:
        log.warning("no damping estimate for %s: %s", label, exc)
        return None, None, float("nan")
    hil = None
    if dec.mean_frequency_hz * (t[-1] - t[0]) >= 4.0:
        try:
            hil = decay_damping(t, x, method="hilbert", trim_cycles=1.0)
        except ModelError:
            hil = None
    return dec, hil, zeta


def free_decay(wheel: TiebossWheel, nd: int, *, amplitude_m: float = 5e-4,
               duration_s: float = 0.1, dt: float = 1e-5, solver: str = "auto",
               method: str = "newmark", save_every: int = 1, forcing: str = "tieboss",
               initial: InitialDeformation | None = None) -> DecayRun:
    """The paper's damping strategy for one ND (003 section 3; module docstring).

    Parameters
    ----------
    wheel : TiebossWheel
        Full or reduced wheel.
    nd : int
        Nodal diameter of the mode (003: 2 and 6).
    amplitude_m : float
        Initial probe displacement [m] (003: up to 0.5 mm).
    duration_s : float
        Length of the free attenuation [s] (003: 0.1 s).
    dt : float
        Time step [s] (003: 5e-6 s; 1e-5 s changes the ratios by < 1 %).
    solver : {"auto", "fast", "simulate"}
        ``fast``: :func:`~fricdamp.solvers.fast_transient.integrate_contact3d` (reduced
        wheels); ``simulate``: the general solver (what the full-order check uses);
        ``auto``: fast for reduced wheels, simulate for full ones.
    method : {"newmark", "hht"}
        Newmark average acceleration (003: gamma = 0.5) or HHT-alpha (alpha = -0.05).
    save_every : int
        Store every k-th step.
    forcing : {"tieboss", "modal"}
        Modal forces at the tie-boss nodes (the paper's) or mass-weighted on all DOFs
        (:func:`modal_force`).
    initial : InitialDeformation, optional
        Reuse a static solution (:func:`initial_deformation`).

    Returns
    -------
    DecayRun
    """
    if solver not in ("auto", "fast", "simulate"):
        raise ModelError(f"solver must be 'auto', 'fast' or 'simulate', got {solver!r}")
    if solver == "auto":
        solver = "fast" if wheel.is_reduced else "simulate"
    dur = float(check_positive("duration_s", duration_s, unit="s"))
    h = float(check_positive("dt", dt, unit="s"))
    init = initial_deformation(wheel, nd, amplitude_m, forcing=forcing) if initial is None \
        else initial
    N = wheel.n_blades
    probe = wheel.group_dofs("probe", 0)
    if solver == "fast":
        out_dofs = np.concatenate([probe] + [d for _, d, _ in _node_keys(wheel)])
        res = integrate_contact3d(wheel.system, dur, h, q0=init.q0, states0=init.states0,
                                  method=method, save_every=save_every, output_dofs=out_dofs)
        t = res.t
        qo = np.zeros((t.size, wheel.n_dof))
        qo[:, out_dofs] = res.q
        status = res.contact_status
        cu, cf = res.contact_displacement, res.contact_force
        runtime, ebal = res.runtime_s, res.energy_balance_error
        extra = {"n_newton": res.n_newton, "setup_s": res.setup_s}
    else:
        from fricdamp.solvers.timestep import simulate

        res = simulate(wheel.system, dur, h, q0=init.q0, method=method, save_every=save_every,
                       progress=False)
        t, qo = res.t, res.q
        status = None
        cu, cf = res.contact_displacement[0], res.contact_force[0]
        runtime, ebal = res.runtime_s, res.energy_balance_error
        extra = {"n_newton": res.n_newton}
    x = _probe_signal(wheel, qo) - _probe_signal(wheel, init.q_rest)
    dec, hil, zeta = decay_estimates(t, x, f"{nd}ND")
    nodes = _node_histories(wheel, qo, init.q_rest)
    return DecayRun(nd=int(nd), t=t, signal=x, decay=dec, amplitude_decay=hil,
                    damping_ratio=float(zeta),
                    initial_amplitude_m=float(x[0]), runtime_s=float(runtime), solver=solver,
                    contact_status=status, contact_displacement=cu, contact_force=cf,
                    nodes=nodes, energy_balance_error=float(ebal),
                    normal_force_rest_N=init.normal_force_rest_N, n_dof=wheel.n_dof,
                    meta={"dt_s": h, "duration_s": dur, "n_blades": N, "method": method,
                          "offset_m": wheel.parameters.contact_offset_m,
                          "forcing": forcing if initial is None else "given", **extra})


# =============================================================================== reduction
def reduction_comparison(params: TiebossWheelParameters | None = None, *, nd: int = 2,
                         n_modes: int = 10, amplitude_m: float = 5e-4,
                         duration_s: float = 0.1, dt: float = 1e-5,
                         method: str = "newmark") -> dict:
    """Full-order (``simulate``) against Craig-Bampton (fast path) free decays of one ND.

    Returns
    -------
    dict
        ``full_dof``, ``reduced_dof``, ``n_modes``, ``damping_ratio_full``,
        ``damping_ratio_reduced``, ``damping_ratio_difference`` (relative, |zr/zf - 1|),
        ``initial_amplitude_full_m`` / ``_reduced_m``, ``runtime_full_s``,
        ``runtime_reduced_s``, ``speed_ratio`` (full / reduced run time of the transients)
        and the largest probe difference relative to the initial amplitude.
    """
    sector = build_sector(params, rotation=False)
    full = build_wheel(sector)
    red = build_wheel(sector, n_modes=n_modes)
    kw = {"amplitude_m": amplitude_m, "duration_s": duration_s, "dt": dt, "method": method}
    rf = free_decay(full, nd, solver="simulate", **kw)
    rr = free_decay(red, nd, solver="fast", **kw)
    n = min(rf.t.size, rr.t.size)
    dev = float(np.max(np.abs(rf.signal[:n] - rr.signal[:n])) / abs(rf.signal[0]))
    return {"nd": int(nd), "full_dof": full.n_dof, "reduced_dof": red.n_dof,
            "n_modes": int(n_modes), "damping_ratio_full": rf.damping_ratio,
            "damping_ratio_reduced": rr.damping_ratio,
            "damping_ratio_difference": abs(rr.damping_ratio / rf.damping_ratio - 1.0),
            "initial_amplitude_full_m": rf.initial_amplitude_m,
            "initial_amplitude_reduced_m": rr.initial_amplitude_m,
            "runtime_full_s": rf.runtime_s, "runtime_reduced_s": rr.runtime_s,
            "speed_ratio": rf.runtime_s / rr.runtime_s,
            "max_signal_difference": dev, "duration_s": duration_s, "dt_s": dt}


# =============================================================================== case
def run_tieboss_case(params: TiebossWheelParameters | None = None, *, nds=(2, 6),
                     amplitude_m: float = 5e-4, duration_s: float = 0.1, dt: float = 1e-5,
                     n_modes: int = 10, pulses: int = 8, orders=TABLE2_ORDERS,
                     rpm_range=(60.0, 450.0), compare_full: bool = True,
                     compare_nd: int = 2) -> dict:
    """All 003 analyses; the dict of the ``summary.json`` contract.

    Returns
    -------
    dict
        ``modal`` (:func:`modal_by_nd`), ``decay`` (one :meth:`DecayRun.summary` per ND, on
        the reduced wheel, with the paper's tie-boss forcing, plus
        ``damping_ratio_modal_forcing`` from a pure-mode start), ``critical_speeds_rpm``
        (:func:`critical_speeds_by_nd`), ``reduction`` (:func:`reduction_comparison`, or
        only the DOF counts with ``compare_full=False``), ``parameters`` and ``runtime_s``.
    """
    t0 = time.perf_counter()
    p = TiebossWheelParameters() if params is None else params
    sector = build_sector(p)
    out = {"modal": modal_by_nd(sector)}
    out["critical_speeds_rpm"] = critical_speeds_by_nd(sector, orders=orders, pulses=pulses,
                                                       rpm_range=rpm_range)
    red = build_wheel(sector, n_modes=n_modes)
    out["decay"] = []
    for nd in nds:
        kw = {"amplitude_m": amplitude_m, "duration_s": duration_s, "dt": dt}
        entry = free_decay(red, int(nd), **kw).summary()
        entry["damping_ratio_modal_forcing"] = free_decay(red, int(nd), forcing="modal",
                                                          **kw).damping_ratio
        out["decay"].append(entry)
    if compare_full:
        out["reduction"] = reduction_comparison(p, nd=compare_nd, n_modes=n_modes,
                                                amplitude_m=amplitude_m,
                                                duration_s=duration_s, dt=dt)
    else:
        out["reduction"] = {"full_dof": p.n_blades * sector.cyclic.n_independent,
                            "reduced_dof": red.n_dof, "n_modes": int(n_modes),
                            "damping_ratio_difference": None}
    out["parameters"] = p.to_dict()
    out["runtime_s"] = time.perf_counter() - t0
    return out
