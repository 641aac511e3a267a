"""Analyses of the two-blade model of paper 001: steady states, Campbell diagram, modes.

* :func:`steady_state_sweep` -- the equivalent-linearisation steady state (001 section 3)
  over spin speeds for one excitation order k and several friction coefficients: ellipse
  semi-axes and inclinations at A and B (001 Figs 6-8), energy dissipated by friction per
  period ``T_k = 2 pi / (k Omega)`` (Figs 9-11), energy balance, iterations. The linear
  part is factorised once per speed and reused for every friction coefficient.
* :func:`campbell_diagram` -- complex eigenvalues of the linearised model 001 (8) including
  the equivalent damping B_e of the steady state at each speed (001 section 4.1; Figs 3-4):
  imaginary parts [Hz] of the first modes, counts of complex pairs and of real
  (over-damped) eigenvalues.
* :func:`complex_modes` -- complex mode shapes at one speed (Fig. 5).
* :func:`orbits` -- the elliptical orbits of A and B at chosen speeds (Figs 12-14).
* :func:`run_blade_pair_case` -- all of the above as the ``summary.json`` contract.

Eigenvalues are those of the first-order form ``z' = A z``, ``A = [[0, I], [-M^-1 K,
-M^-1 D]]`` (156 states for 78 DOFs), solved densely by LAPACK with one BLAS thread (small
dense problems run ~100 times slower with a contended thread pool on 2 cores).
"""

from __future__ import annotations

import logging
import time

import numpy as np
import scipy.linalg as sla

from fricdamp.errors import ModelError, as_finite_array
from fricdamp.models.blade_pair.model import (
    BladePairModel,
    BladePairParameters,
    build_blade_pair,
    rpm_to_rad_s,
)
from fricdamp.solvers.eqlin import (
    EqLinResult,
    condense,
    dynamic_stiffness,
    equivalent_linearisation,
)

__all__ = [
    "campbell_diagram",
    "complex_modes",
    "crossing_speeds",
    "equivalent_damping_matrix",
    "harmonic_balance_cross_check",
    "normal_force_ratio",
    "orbits",
    "peak_crossing",
    "run_blade_pair_case",
    "solve_steady_states",
    "steady_state_sweep",
    "stick_masks",
]

logger = logging.getLogger(__name__)


def _blas1():
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


def _rpm(rpm, name: str = "rpm") -> np.ndarray:
    r = np.atleast_1d(as_finite_array(name, rpm)).astype(float)
    if r.ndim != 1 or r.size == 0 or np.any(r <= 0):
        raise ModelError(f"{name} must be a non-empty list of spin speeds > 0 rpm, got {rpm!r}")
    return r


def _order(k) -> int:
    if isinstance(k, bool) or int(k) != k or k < 1:
        raise ModelError(f"excitation order k must be an integer >= 1, got {k!r}")
    return int(k)


def _model(model) -> BladePairModel:
    if model is None:
        return build_blade_pair()
    if isinstance(model, BladePairParameters):
        return build_blade_pair(model)
    if not isinstance(model, BladePairModel):
        raise ModelError(f"model must be a BladePairModel or BladePairParameters, got "
                         f"{type(model).__name__}")
    return model


def _condensed(model: BladePairModel, order: int, speeds: np.ndarray):
    omega = order * speeds
    Z = dynamic_stiffness(model.M, model.damping(speeds), model.stiffness(speeds), omega)
    return condense(Z, model.load(order), model.friction_projection, omega,
                    dissipation_matrix=model.dissipative_damping())


def solve_steady_states(model: BladePairModel, order: int, rpm, friction_coefficients=None,
                        *, rule: str | None = None, tol: float = 1e-8,
                        max_iter: int = 2000) -> list[tuple[float, EqLinResult, object]]:
    """Equivalent-linear steady states at the speeds ``rpm`` for each friction coefficient.

    Returns
    -------
    list of (f, EqLinResult, EllipseFrictionDamping)
        One entry per friction coefficient (``params.friction_coefficient`` if None).
    """
    model = _model(model)
    k = _order(order)
    r = _rpm(rpm)
    speeds = rpm_to_rad_s(r)
    fcs = [model.params.friction_coefficient] if friction_coefficients is None else list(
        np.atleast_1d(friction_coefficients))
    out = []
    with _blas1():
        cs = _condensed(model, k, speeds)
        for f in fcs:
            damp = model.friction_damping(speeds, f, rule=rule)
            res = equivalent_linearisation(cs, damp, tol=tol, max_iter=max_iter)
            out.append((f, res, damp))
    return out


def _f_value(f):
    a = np.atleast_1d(np.asarray(f, float))
    return float(a[0]) if a.size == 1 or np.all(a == a[0]) else [float(v) for v in a]


def stick_masks(damp, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where each contact's slip and its rotation about the normal stick, (n_b, 2) each.

    Paper law (friction as a damper only): the orbit, or the rotation amplitude, is within
    twice its floor (``min_slip``, ``min_slip / rho``), where the floor is also the
    convergence tolerance -- indistinguishable from no slip. With a stick stiffness
    (:class:`~fricdamp.models.blade_pair.model.JenkinsEllipseDamping`): the spring force is
    within the slip limit (``k_t a <= f N``, ``k_r phi <= M_0``).
    """
    stuck_t = np.asarray(damp.stuck(s), bool)
    if hasattr(damp, "rotation_stuck"):
        stuck_r = np.asarray(damp.rotation_stuck(s), bool)
    else:
        rot = np.abs(np.asarray(s)[:, [2, 5]])
        stuck_r = rot <= 2.0 * np.asarray(damp.min_rotation)[None, :]
    return stuck_t, stuck_r


def normal_force_ratio(model: BladePairModel, response: np.ndarray, speeds,
                       omega) -> np.ndarray:
    """Amplitude of the normal-force oscillation over the static normal load, (n_b, 2).

    ``|k_X (1 + i w beta_C) zeta~_X| / N_X0`` with ``zeta~_X`` the normal approach of contact
    X (001 (13)) in the steady state: the constant-normal-load assumption of 001 (6) behind
    the equivalent damping holds while it is well below 1; at 1 the contact lifts off once
    per cycle.
    """
    p = model.params
    zeta = np.asarray(response) @ model.contact_projection[:, 0, :].T      # (n_b, 2)
    k = np.array(p.contact_stiffness)[None, :]
    w = np.asarray(omega, float)[:, None]
    dyn = np.abs(k * (1.0 + 1j * w * p.contact_damping) * zeta)
    N0 = model.normal_loads(np.asarray(speeds, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(N0 > 0, dyn / N0, np.inf)


def _sweep_entry(model: BladePairModel, k: int, r: np.ndarray, f, res: EqLinResult, damp
                 ) -> dict:
    s = res.contact_response
    e = damp.orbits(s)                                              # (n_b, 2)
    stuck, stuck_r = stick_masks(damp, s)
    # a stuck contact has no slip and dissipates nothing: report 0, never the floor of
    # the equivalent damping (whose product with the floored orbit is arbitrary)
    W = res.equivalent_dissipation.copy()                           # A-tr, A-rot, B-tr, B-rot
    W[:, 0::2] = np.where(stuck, 0.0, W[:, 0::2])
    W[:, 1::2] = np.where(stuck_r, 0.0, W[:, 1::2])
    W_A, W_B = W[:, 0] + W[:, 1], W[:, 2] + W[:, 3]
    major = np.where(stuck, 0.0, e.major)
    minor = np.where(stuck, 0.0, e.minor)
    incl = np.where(stuck, 0.0, e.inclination)
    tip = model.tip_node
    i1 = model.dof_index("blade1", tip, "w")
    i2 = model.dof_index("blade2", tip, "w")
    tip_amp = np.column_stack([np.abs(res.response[:, i1]), np.abs(res.response[:, i2])])
    speeds = rpm_to_rad_s(r)
    nfr = normal_force_ratio(model, res.response, speeds, res.omega)
    return {
        "k": int(k),
        "friction_coefficient": _f_value(f),
        "rpm": r.tolist(),
        "semi_axes_A_m": np.column_stack([major[:, 0], minor[:, 0]]).tolist(),
        "semi_axes_B_m": np.column_stack([major[:, 1], minor[:, 1]]).tolist(),
        "inclination_A_rad": incl[:, 0].tolist(),
        "inclination_B_rad": incl[:, 1].tolist(),
        "dissipated_energy_J": (W_A + W_B).tolist(),
        "dissipated_energy_A_J": W_A.tolist(),
        "dissipated_energy_B_J": W_B.tolist(),
        "external_work_J": res.external_work.tolist(),
        "tip_tangential_amplitude_m": tip_amp.tolist(),
        "tip_amplitude_m": tip_amp.max(axis=1).tolist(),
        "normal_force_ratio_A": nfr[:, 0].tolist(),
        "normal_force_ratio_B": nfr[:, 1].tolist(),
        "normal_loads_N": model.normal_loads(speeds).tolist(),
        "stuck_A": stuck[:, 0].tolist(),
        "stuck_B": stuck[:, 1].tolist(),
        "rotation_stuck_A": stuck_r[:, 0].tolist(),
        "rotation_stuck_B": stuck_r[:, 1].tolist(),
        "tangential_stiffness_N_per_m": model.params.tangential_stiffness,
        "energy_balance_error": float(np.max(res.energy_balance_error)),
        "iterations": res.iterations.tolist(),
        "total_iterations": res.total_iterations,
        "converged": bool(res.success),
        "damping_rule": damp.rule,
    }


def steady_state_sweep(model, order: int, rpm, friction_coefficients=None, *,
                       rule: str | None = None, tol: float = 1e-8,
                       max_iter: int = 2000) -> list[dict]:
    """Steady states vs spin speed for one order k and several friction coefficients.

    Parameters
    ----------
    model : BladePairModel or BladePairParameters or None
        The 001 model (defaults if None).
    order : int
        Excitation order k (``w_k = k Omega``; Table 1 amplitudes for 15, 20, 30).
    rpm : array_like
        Spin speeds > 0 [rpm].
    friction_coefficients : array_like, optional
        f values (each the same for A and B), default ``params.friction_coefficient``.
    rule : {"coulomb", "paper"}, optional
        Equivalent damping rule (default ``params.damping_rule``).
    tol, max_iter
        Fixed-point tolerance and iteration limit (:func:`equivalent_linearisation`).

    Returns
    -------
    list of dict
        One per friction coefficient with the keys of the results contract: ``k``,
        ``friction_coefficient``, ``rpm``, ``semi_axes_A_m`` / ``semi_axes_B_m`` ([a, b] per
        speed [m]), ``dissipated_energy_J`` (friction, per period T_k, both contacts [J]),
        ``energy_balance_error`` (largest over the speeds); and ``inclination_A_rad``,
        ``inclination_B_rad`` (major axis from xi_X, [0, pi)), ``dissipated_energy_A_J``,
        ``dissipated_energy_B_J``, ``external_work_J``, ``tip_tangential_amplitude_m``
        (blade 1, blade 2), ``normal_loads_N``, ``stuck_A``/``stuck_B``, ``iterations``,
        ``total_iterations``, ``converged``, ``damping_rule``.
    """
    model = _model(model)
    k = _order(order)
    r = _rpm(rpm)
    return [_sweep_entry(model, k, r, f, res, damp) for f, res, damp in
            solve_steady_states(model, k, r, friction_coefficients, rule=rule, tol=tol,
                                max_iter=max_iter)]


def equivalent_damping_matrix(model: BladePairModel, result: EqLinResult) -> np.ndarray:
    """``B_e = P^T C P`` (n_b, n, n) [N s/m] of converged steady states (001 (8))."""
    P = model.friction_projection
    return np.einsum("mi,bmn,nj->bij", P, result.damping, P)


def _state_matrix(Minv: np.ndarray, K: np.ndarray, D: np.ndarray) -> np.ndarray:
    n = Minv.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -Minv @ K
    A[n:, n:] = -Minv @ D
    return A


def _classify(lam: np.ndarray):
    scale = max(float(np.abs(lam).max()), 1e-300)
    real = np.abs(lam.imag) <= 1e-10 * scale
    upper = lam[(~real) & (lam.imag > 0)]
    return upper[np.argsort(upper.imag)], int(real.sum()), int(upper.size)


def _linearised(model: BladePairModel, order: int, rpm, friction_coefficient, friction: bool,
                damping_source: str, rule):
    """(speeds, D_total per speed) with the equivalent damping of the steady states."""
    r = _rpm(rpm)
    speeds = rpm_to_rad_s(r)
    D = model.damping(speeds)
    if friction:
        if damping_source == "converged":
            (_, res, _), = solve_steady_states(model, order, r, [friction_coefficient],
                                               rule=rule)
            D = D + equivalent_damping_matrix(model, res)
        else:
            # 001 section 4.1: B_e from the response computed without friction damping
            with _blas1():
                cs = _condensed(model, order, speeds)
                damp = model.friction_damping(speeds, friction_coefficient, rule=rule)
                C = damp.matrix(cs.contact_free, cs.omega, np.arange(speeds.size))
            P = model.friction_projection
            D = D + np.einsum("mi,bmn,nj->bij", P, C, P)
    return r, speeds, D


def campbell_diagram(model, rpm, *, order: int = 30, friction_coefficient: float = 0.1,
                     friction: bool = True, n_modes: int = 15,
                     damping_source: str = "linear", rule: str | None = None,
                     excitation_orders=(15, 20, 30)) -> dict:
    """Imaginary parts of the eigenvalues of the linearised 001 (8) vs spin speed.

    Parameters
    ----------
    model : BladePairModel or BladePairParameters or None
    rpm : array_like
        Spin speeds > 0 [rpm].
    order : int
        Excitation order k whose steady state sets the equivalent damping B_e (the
        eigenvalues depend on it, 001 section 4.1).
    friction_coefficient : float
        f of that steady state.
    friction : bool
        Include B_e (False: only material, contact and gyroscopic terms).
    n_modes : int
        Number of lowest complex pairs reported.
    damping_source : {"linear", "converged"}
        ``"linear"`` (default, 001 section 4.1): B_e from the steady response computed
        without friction damping; ``"converged"``: from the converged equivalent-linear
        steady state.
    rule : {"coulomb", "paper"}, optional
    excitation_orders : sequence of int
        Orders of the excitation lines ``f = k rpm / 60`` (for the plot and the contract).

    Returns
    -------
    dict
        ``rpm``; ``frequency_hz`` (n_modes lists over the speeds, ``Im(lambda)/2 pi``,
        ascending at each speed; None where fewer pairs exist); ``damping_ratio``
        (``-Re/|lambda|``, same layout); ``complex_pairs`` and ``real_eigenvalues`` per
        speed (001: about 47 and 62 for its model); ``excitation_orders``; ``k``;
        ``friction_coefficient``; ``friction``; ``damping_source``; ``n_states``;
        ``runtime_s``.
    """
    t0 = time.perf_counter()
    model = _model(model)
    k = _order(order)
    if damping_source not in ("converged", "linear"):
        raise ModelError(f"damping_source must be 'converged' or 'linear', got "
                         f"{damping_source!r}")
    if isinstance(n_modes, bool) or int(n_modes) != n_modes or n_modes < 1:
        raise ModelError(f"n_modes must be an integer >= 1, got {n_modes!r}")
    orders = [_order(o) for o in np.atleast_1d(excitation_orders)]
    r, speeds, D = _linearised(model, k, rpm, friction_coefficient, friction, damping_source,
                               rule)
    K = model.stiffness(speeds)
    n = model.n_dof
    freq = np.full((int(n_modes), r.size), np.nan)
    zeta = np.full((int(n_modes), r.size), np.nan)
    n_complex = np.zeros(r.size, int)
    n_real = np.zeros(r.size, int)
    with _blas1():
        Minv = np.linalg.inv(model.M)
        for i in range(r.size):
            lam = sla.eig(_state_matrix(Minv, K[i], D[i]), right=False, check_finite=False)
            up, n_real[i], n_complex[i] = _classify(lam)
            m = min(int(n_modes), up.size)
            freq[:m, i] = up[:m].imag / (2 * np.pi)
            zeta[:m, i] = -up[:m].real / np.abs(up[:m])

    def lists(a):
        return [[None if not np.isfinite(v) else float(v) for v in row] for row in a]

    return {"rpm": r.tolist(), "frequency_hz": lists(freq), "damping_ratio": lists(zeta),
            "complex_pairs": n_complex.tolist(), "real_eigenvalues": n_real.tolist(),
            "excitation_orders": orders, "k": k,
            "friction_coefficient": float(friction_coefficient), "friction": bool(friction),
            "damping_source": damping_source, "n_states": 2 * n,
            "runtime_s": time.perf_counter() - t0}


def crossing_speeds(rpm, frequency_hz, order: int) -> list[float]:
    """Speeds [rpm] where a branch ``f(rpm)`` [Hz] meets the line ``k rpm / 60``.

    Linear interpolation between grid points where ``f - k rpm / 60`` changes sign (NaN or
    missing points break the branch).
    """
    r = np.asarray(rpm, float)
    f = np.array([np.nan if v is None else v for v in frequency_hz], float)
    g = f - order * r / 60.0
    out = []
    for i in range(r.size - 1):
        a, b = g[i], g[i + 1]
        if not (np.isfinite(a) and np.isfinite(b)):
            continue
        if a == 0.0:
            out.append(float(r[i]))
        elif a * b < 0.0:
            out.append(float(r[i] + (r[i + 1] - r[i]) * a / (a - b)))
    if r.size and np.isfinite(g[-1]) and g[-1] == 0.0:
        out.append(float(r[-1]))
    return out


def peak_crossing(model, order: int, friction_coefficient, rpm, peak_index: int, *,
                  window: int = 3, n_modes: int = 15, damping_source: str = "linear",
                  rule: str | None = None) -> dict:
    """Is a steady-state peak at a Campbell crossing? (001 section 4.1, Figs 3-4.)

    The Campbell diagram of the same steady state (order k, friction coefficient f, B_e by
    ``damping_source``) is computed at the sweep's speeds within ``window`` grid steps of
    the peak; the peak is *at a crossing* when ``k rpm / 60`` meets one of the ``n_modes``
    lowest branches within one grid step of the peak speed.

    Returns
    -------
    dict
        ``peak_rpm``, ``crossings_rpm`` (in the window), ``nearest_crossing_rpm`` (None if
        none), ``at_crossing`` (bool), ``tolerance_rpm`` (one grid step).
    """
    r = _rpm(rpm)
    i = int(peak_index)
    lo, hi = max(i - int(window), 0), min(i + int(window) + 1, r.size)
    rw = r[lo:hi]
    step = float(np.max(np.diff(r))) if r.size > 1 else 0.0
    f = float(np.atleast_1d(np.asarray(friction_coefficient, float))[0])
    camp = campbell_diagram(model, rw, order=order, friction_coefficient=f,
                            n_modes=n_modes, damping_source=damping_source, rule=rule,
                            excitation_orders=[order])
    cr = sorted(c for row in camp["frequency_hz"] for c in crossing_speeds(rw, row, order))
    near = min(cr, key=lambda c: abs(c - r[i])) if cr else None
    return {"peak_rpm": float(r[i]), "crossings_rpm": cr, "nearest_crossing_rpm": near,
            "at_crossing": bool(near is not None and abs(near - r[i]) <= step * (1 + 1e-9)),
            "tolerance_rpm": step}


def complex_modes(model, rpm: float, *, order: int = 30, friction_coefficient: float = 0.1,
                  friction: bool = True, n_modes: int = 3, damping_source: str = "linear",
                  rule: str | None = None) -> dict:
    """Complex mode shapes of the linearised model at one speed (001 Fig. 5).

    Shapes are normalised on the translations: the translational DOF (u, v, w of a blade
    node or of the wedge) of largest modulus is 1 (rotations in rad would otherwise compete
    with displacements in m).

    Returns
    -------
    dict
        ``rpm``, ``eigenvalues`` (n_modes complex as [re, im] [1/s]), ``frequency_hz``,
        ``damping_ratio``, ``shapes`` (n_dof x n_modes complex as [re, im], largest
        translation 1), ``normalised_on`` (the DOF name per mode), ``blade_nodes_m`` (radii
        of the blade nodes), ``blade1`` / ``blade2``: per mode the complex (v, w) of each
        blade node (axial, tangential) as [re, im].
    """
    model = _model(model)
    k = _order(order)
    if damping_source not in ("converged", "linear"):
        raise ModelError(f"damping_source must be 'converged' or 'linear', got "
                         f"{damping_source!r}")
    r, speeds, D = _linearised(model, k, [rpm], friction_coefficient, friction,
                               damping_source, rule)
    K = model.stiffness(speeds)[0]
    n = model.n_dof
    with _blas1():
        lam, V = sla.eig(_state_matrix(np.linalg.inv(model.M), K, D[0]), check_finite=False)
    up, _, _ = _classify(lam)
    sel = [int(np.argmin(np.abs(lam - u))) for u in up[:int(n_modes)]]
    X = V[:n, sel]
    trans = np.array([nm.split(".")[-1][:1] in ("u", "v", "w") for nm in model.dof_names])
    if trans.size != n or not trans.any():
        trans = np.ones(n, bool)
    idx = np.flatnonzero(trans)[np.argmax(np.abs(X[trans]), axis=0)]
    X = X / X[idx, np.arange(X.shape[1])]
    nodes = range(1, model.blade.n_nodes)

    def blade(body):
        out = []
        for j in range(X.shape[1]):
            out.append([[[float(X[model.dof_index(body, nd, nm), j].real),
                          float(X[model.dof_index(body, nd, nm), j].imag)]
                         for nm in ("v", "w")] for nd in nodes])
        return out

    lam_sel = lam[sel]
    return {"rpm": float(r[0]), "eigenvalues": [[float(v.real), float(v.imag)] for v in lam_sel],
            "frequency_hz": (lam_sel.imag / (2 * np.pi)).tolist(),
            "damping_ratio": (-lam_sel.real / np.abs(lam_sel)).tolist(),
            "shapes": np.stack([X.real, X.imag], axis=-1).tolist(),
            "normalised_on": [model.dof_names[i] if model.dof_names else int(i) for i in idx],
            "blade_nodes_m": model.blade.nodes[1:, 0].tolist(),
            "blade1": blade("blade1"), "blade2": blade("blade2")}


def orbits(model, order: int, rpm, friction_coefficients=None, *, n_points: int = 101,
           rule: str | None = None) -> list[dict]:
    """Elliptical orbits of A and B at chosen speeds (001 Figs 12-14).

    Returns
    -------
    list of dict
        Per friction coefficient: ``k``, ``friction_coefficient``, ``rpm``, ``A`` and ``B``:
        per speed ``{"xi_m": [...], "eta_m": [...], "semi_axes_m": [a, b],
        "inclination_rad": ...}`` in the contact plane axes (xi, eta).
    """
    model = _model(model)
    k = _order(order)
    r = _rpm(rpm)
    out = []
    for f, res, damp in solve_steady_states(model, k, r, friction_coefficients, rule=rule):
        e = damp.orbits(res.contact_response)
        x, y = e.points(n_points)                                   # (n_b, 2, n_points)
        entry = {"k": k, "friction_coefficient": _f_value(f), "rpm": r.tolist()}
        for c, name in enumerate(("A", "B")):
            entry[name] = [{"xi_m": x[i, c].tolist(), "eta_m": y[i, c].tolist(),
                            "semi_axes_m": [float(e.major[i, c]), float(e.minor[i, c])],
                            "inclination_rad": float(e.inclination[i, c])}
                           for i in range(r.size)]
        out.append(entry)
    return out


def harmonic_balance_cross_check(model, order: int, rpm, friction_coefficient: float = 0.1,
                                 *, tangential_stiffness: float = 1e8, harmonics: int = 5,
                                 samples: int = 512, axial_support: float = 10.0) -> dict:
    """The same steady states by multi-harmonic balance with Jenkins contacts (HB-AFT).

    Each contact becomes a :class:`~fricdamp.contact.Contact3D` (isotropic 2D Jenkins
    friction, stick stiffness ``tangential_stiffness``, slip limit ``f N`` with the constant
    normal load of 001 (6): a vanishing normal penalty with the matching offset, balanced
    by a static load) on the rows (normal, xi, eta), plus a 1D Jenkins element on the
    rotation about the normal (stiffness ``k_t (a_ef^2 + h_ef^2)/12``, slip torque
    ``f N rho``). As ``k_t`` grows this is rigid-plastic Coulomb friction -- the law the
    equivalent damping linearises -- with true stick. The wedge's axial translation, held
    only by friction, gets a weak spring ``axial_support`` [N/m] so that its mean position
    (the static harmonic) is defined.

    Parameters
    ----------
    model : BladePairModel or BladePairParameters or None
    order : int
        Excitation order k.
    rpm : array_like
        Spin speeds > 0 [rpm] (each solved independently; ~0.05-0.5 s per speed).
    friction_coefficient : float
        f at both contacts.
    tangential_stiffness : float
        k_t [N/m] of the Jenkins elements (large: stick displacement f N / k_t small).
    harmonics, samples : int
        HB harmonics and AFT samples per period.
    axial_support : float
        Spring on the wedge's axial DOF [N/m] (>= 0; negligible against its inertia).

    Returns
    -------
    dict
        ``rpm``, ``k``, ``friction_coefficient``; per method (``"eqlin"``, ``"hb"``):
        ``semi_axes_A_m``, ``semi_axes_B_m`` ([a, b] per speed, fundamental harmonic for
        HB), ``dissipated_energy_J`` (friction, per period), ``tip_tangential_amplitude_m``
        (blade 1, first harmonic); and ``hb_success``, ``hb_energy_balance_error``.
    """
    from dataclasses import replace

    from fricdamp.contact import Contact3D, Jenkins
    from fricdamp.contact.equivalent import slip_ellipse
    from fricdamp.solvers.hb import harmonic_balance
    from fricdamp.structure.system import ContactElement

    model = _model(model)
    k = _order(order)
    r = _rpm(rpm)
    f = float(friction_coefficient)
    if not f > 0:
        raise ModelError(f"friction_coefficient must be > 0 for the cross-check, got {f!r}")
    kt = float(as_finite_array("tangential_stiffness", tangential_stiffness))
    if not kt > 0:
        raise ModelError(f"tangential_stiffness must be > 0 N/m, got {kt!r}")
    if not axial_support >= 0:
        raise ModelError(f"axial_support must be >= 0 N/m, got {axial_support!r}")
    eq = steady_state_sweep(model, k, r, [f])[0]
    P = model.contact_projection
    P3 = P[:, :3, :].reshape(6, model.n_dof)
    a_ef = np.array(model.params.contact_width)
    h_ef = np.array(model.params.contact_height)
    iv = model.dof_index("damper", None, "v")
    it = model.dof_index("blade1", model.tip_node, "w")
    kn = 1e-6
    out = {"A": [], "B": [], "W": [], "tip": [], "ok": [], "err": []}
    for speed in rpm_to_rad_s(r):
        N = model.normal_loads(speed)
        contacts = (ContactElement(Contact3D(kn, kt, f, offset=N / kn), P3, name="AB"),
                    ContactElement(Jenkins(kt * (a_ef**2 + h_ef**2) / 12.0,
                                           f * N * model.torque_arms), P[:, 5, :],
                                   name="torsion"))
        base = model.system(speed, order=k)
        K = np.array(base.K)
        K[iv, iv] += axial_support
        sysm = replace(base, K=K, contacts=contacts,
                       static_load=P3.T @ np.array([N[0], 0, 0, N[1], 0, 0]))
        ss = harmonic_balance(sysm, k * speed, harmonics=harmonics, samples=samples)
        U = ss.contact_displacement
        for c, name in enumerate(("A", "B")):
            xi = U[3 * c + 1, 1] - 1j * U[3 * c + 1, 2]
            eta = U[3 * c + 2, 1] - 1j * U[3 * c + 2, 2]
            e = slip_ellipse(xi, eta)
            out[name].append([float(e.major), float(e.minor)])
        out["W"].append(float(np.sum(ss.dissipated_energy)))
        out["tip"].append(float(np.hypot(ss.coefficients[it, 1], ss.coefficients[it, 2])))
        out["ok"].append(bool(ss.success))
        out["err"].append(float(ss.energy_balance_error))
    return {"rpm": r.tolist(), "k": k, "friction_coefficient": f,
            "tangential_stiffness_N_per_m": kt,
            "eqlin": {"semi_axes_A_m": eq["semi_axes_A_m"], "semi_axes_B_m": eq["semi_axes_B_m"],
                      "dissipated_energy_J": eq["dissipated_energy_J"],
                      "tip_tangential_amplitude_m": [v[0] for v in
                                                     eq["tip_tangential_amplitude_m"]]},
            "hb": {"semi_axes_A_m": out["A"], "semi_axes_B_m": out["B"],
                   "dissipated_energy_J": out["W"], "tip_tangential_amplitude_m": out["tip"]},
            "hb_success": out["ok"], "hb_energy_balance_error": out["err"]}


def run_blade_pair_case(params: BladePairParameters | None = None, *,
                        rpm_range=(100.0, 2500.0), n_campbell: int = 100,
                        n_sweep: int = 200, orders=(15, 20, 30),
                        friction_coefficients=(0.05, 0.1, 0.2, 0.3),
                        campbell_order: int = 30, campbell_friction: float = 0.1,
                        n_modes: int = 15, damping_source: str = "linear",
                        mode_rpm: float = 2000.0, orbit_rpm=None,
                        tol: float = 1e-8) -> dict:
    """All 001 analyses; the dict of the ``summary.json`` contract.

    Parameters
    ----------
    params : BladePairParameters, optional
    rpm_range : (float, float)
        Speed range [rpm] of the Campbell diagram and the sweeps, > 0.
    n_campbell, n_sweep : int
        Number of speeds of the Campbell diagram and of each steady-state sweep.
    orders : sequence of int
        Excitation orders k of the sweeps (001: 15, 20, 30).
    friction_coefficients : sequence of float
        f of the sweeps.
    campbell_order, campbell_friction : int, float
        Steady state whose equivalent damping enters the Campbell diagram (001 Fig. 3:
        k = 30, f = 0.1).
    n_modes : int
        Campbell branches reported.
    damping_source : {"converged", "linear"}
        See :func:`campbell_diagram`.
    mode_rpm : float
        Speed of the complex mode shapes (001 Fig. 5: 2000 rpm).
    orbit_rpm : sequence of float, optional
        Speeds of the orbit plots (default: the quartiles of rpm_range).
    tol : float
        Fixed-point tolerance.

    Returns
    -------
    dict
        ``n_dof``, ``campbell`` (see :func:`campbell_diagram`), ``steady_state`` (list of
        :func:`steady_state_sweep` entries over orders x friction coefficients),
        ``complex_modes``, ``orbits``, ``parameters``, ``contact_angles_rad``,
        ``energy_balance_error`` (largest), ``eqlin_iterations`` (total),
        ``all_converged``, ``runtime_s``.
    """
    from dataclasses import asdict

    t0 = time.perf_counter()
    model = build_blade_pair(params)
    lo, hi = (float(v) for v in as_finite_array("rpm_range", rpm_range))
    if not 0 < lo < hi:
        raise ModelError(f"rpm_range must be (low, high) with 0 < low < high rpm, got "
                         f"{rpm_range!r}")
    for name, v in (("n_campbell", n_campbell), ("n_sweep", n_sweep)):
        if isinstance(v, bool) or int(v) != v or v < 2:
            raise ModelError(f"{name} must be an integer >= 2, got {v!r}")
    rpm_c = np.linspace(lo, hi, int(n_campbell))
    rpm_s = np.linspace(lo, hi, int(n_sweep))
    orders = [_order(k) for k in np.atleast_1d(orders)]
    camp = campbell_diagram(model, rpm_c, order=campbell_order,
                            friction_coefficient=campbell_friction, n_modes=n_modes,
                            damping_source=damping_source, excitation_orders=orders)
    steady = []
    for k in orders:
        steady += steady_state_sweep(model, k, rpm_s, friction_coefficients, tol=tol)
    modes = complex_modes(model, mode_rpm, order=campbell_order,
                          friction_coefficient=campbell_friction,
                          damping_source=damping_source)
    o_rpm = np.quantile([lo, hi], [0.25, 0.5, 0.75]) if orbit_rpm is None else orbit_rpm
    orb = orbits(model, campbell_order, o_rpm, friction_coefficients, n_points=73)
    p = asdict(model.params)
    return {
        "n_dof": model.n_dof,
        "campbell": camp,
        "steady_state": steady,
        "complex_modes": modes,
        "orbits": orb,
        "parameters": p,
        "contact_angles_rad": model.contact_angles,
        "energy_balance_error": max(s["energy_balance_error"] for s in steady),
        "eqlin_iterations": int(sum(s["total_iterations"] for s in steady)),
        "all_converged": bool(all(s["converged"] for s in steady)),
        "runtime_s": time.perf_counter() - t0,
    }
