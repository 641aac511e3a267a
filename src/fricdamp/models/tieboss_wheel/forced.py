"""Forced response of paper 003's friction-coupled wheel: cyclic HB by ND, ζ(A), mistuning.

* :func:`cyclic_problem` -- the travelling-wave problem of one (Craig-Bampton) sector of the
  beam wheel for :mod:`fricdamp.solvers.cyclic_hb`: the sector's tie-boss contact with its
  neighbour (the paper's law: penalty with offset, separation, 2D friction with mu(v)),
  the load at the tie-boss (or any named group) along the flexural direction, and, for a
  response against rotation speed, the speed stiffness ``K_sigma - K_d`` with the
  excitation locked to ``p o`` times the rotation frequency (003 (1)).
* :func:`forced_response_by_nd` -- the response around a critical speed, the entry of the
  ``forced_response`` contract (issue 17).
* :func:`damping_vs_amplitude` -- the damping ratio of the resonant state against its
  amplitude, ``zeta = W_d / (4 pi E_max)`` at the resonance peak of each load level
  (:class:`~fricdamp.solvers.cyclic_hb.CyclicForcedResponse`).
* :func:`wheel_load`, :func:`expand_to_wheel` -- the same load and a cyclic solution on the
  assembled wheel (the full-wheel HB reference of tests/validation/test_cyclic_hb.py).
* :func:`mistuned_amplification` -- the full-wheel HB of a wheel with per-blade stiffness
  scatter: the amplification factor (largest blade amplitude over the tuned amplitude).

Amplitude definition (003 section 3.1 and Fig. 19): ``amplitude_m`` is the largest
displacement over the period, from its mean, of blade 0's right contact node (the node in
the midst of contact B, N165136 in 003, whose envelopes Fig. 19 compares with the rig)
along the blade's flexural direction (normal to the blade plane, 003's plane alpha_0):
the ``probe`` group. The rig measured blade L1 through a strain gauge; the tip of the beam
blade moves ``tip_ratio`` times more (reported with the results) and the paper does not
say where its "blade displacement" is taken.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from fricdamp.errors import ModelError
from fricdamp.models.tieboss_wheel.model import (
    TiebossSector,
    TiebossWheel,
    _contact_law,
    build_wheel,
)
from fricdamp.solvers.cyclic_hb import (
    CyclicForcedResponse,
    CyclicHarmonicBalance,
    _real,
    cyclic_frequency_response,
)
from fricdamp.structure.system import ContactElement, HarmonicLoad

__all__ = ["cyclic_problem", "damping_vs_amplitude", "expand_to_wheel",
           "forced_response_by_nd", "mistuned_amplification", "wheel_load"]


def _dense(A) -> np.ndarray:
    return A.toarray() if sp.issparse(A) else np.asarray(A)


def _rotation_stiffness(sector: TiebossSector, wheel: TiebossWheel | None):
    r = sector.rotation
    if r is None:
        raise ModelError("the sector has no rotation terms: build it with "
                         "build_sector(params, rotation=True)")
    Kr = sp.csr_matrix(r.stress_stiffening) - sp.csr_matrix(r.spin_softening)
    Kr = 0.5 * (Kr + Kr.T)
    if wheel is not None and wheel.reduction is not None:
        Psi = np.asarray(wheel.reduction.reduction.transformation)
        Kr = Psi.T @ (Kr @ Psi)
        Kr = 0.5 * (Kr + Kr.T)
    return Kr


def cyclic_problem(sector: TiebossSector, nd: int, *, force_N: float = 1.0,
                   n_modes: int | None = 4, load_group: str = "tieboss",
                   harmonics: int = 5, samples: int = 120,
                   excitations_per_rev: float | None = None, law=None,
                   wheel: TiebossWheel | None = None, force_vector=None):
    """The cyclic HB problem of the beam wheel for a forward wave of ``nd`` ND.

    Parameters
    ----------
    sector : TiebossSector
        The physical sector (with rotation terms when ``excitations_per_rev`` is given).
    nd : int
        Nodal diameter of the travelling wave (forward; negative: backward).
    force_N : float
        Force [N] per blade at ``load_group``'s node along the flexural direction.
    n_modes : int or None
        Craig-Bampton modes per sector (None: the full-order sector; its arclength path
        crawls through the stick-slip transitions, see docs/cases_tieboss_wheel.md).
    load_group : str
        Named DOF group loaded (``tieboss``: where 003 puts its modal forces).
    harmonics, samples : int
        H and the AFT samples (a multiple of N / gcd(nd, N) keeps the full-wheel AFT
        shift-invariant: 120 for N = 30).
    excitations_per_rev : float, optional
        ``p o``: excitation frequency over rotation frequency; adds the speed stiffness.
    law : ContactLaw, optional
        One-contact law (default: the wheel's, 003 (2)).
    wheel : TiebossWheel, optional
        A prebuilt (reduced) wheel of ``sector`` with ``n_modes`` modes.
    force_vector : array_like, shape (n,), optional
        The load phasor on the (reduced) sector's DOFs [N], instead of ``force_N`` at
        ``load_group``.

    Returns
    -------
    problem : CyclicHarmonicBalance
    wheel : TiebossWheel
        The (reduced) wheel whose ``cyclic`` is the sector solved.
    """
    if wheel is None:
        wheel = build_wheel(sector, n_modes=n_modes)
    cyc = wheel.cyclic
    if load_group not in cyc.named_dofs:
        raise ModelError(f"load_group {load_group!r} is not a kept DOF group of the sector; "
                         f"choose one of {sorted(cyc.named_dofs)}")
    P = sector.contact_rows(cyc)
    law = _contact_law(sector.parameters, 1) if law is None else law
    if force_vector is not None:
        f = np.asarray(force_vector, complex).reshape(-1)
        if f.size != cyc.n_dof:
            raise ModelError(f"force_vector must have {cyc.n_dof} entries, got {f.size}")
    else:
        f = np.zeros(cyc.n_dof, complex)
        f[np.asarray(cyc.named_dofs[load_group])] = float(force_N) * sector.flexural_direction
    kw = {}
    if excitations_per_rev is not None:
        kw = {"rotation_stiffness": _rotation_stiffness(sector, wheel),
              "excitations_per_rev": float(excitations_per_rev)}
    pb = CyclicHarmonicBalance(cyc, [ContactElement(law, P, name="tieboss")], int(nd), f,
                               harmonics=harmonics, samples=samples, **kw)
    return pb, wheel


def _probe(wheel: TiebossWheel):
    return np.asarray(wheel.cyclic.named_dofs["probe"]), wheel.sector.flexural_direction


def _tip_ratio(res: CyclicForcedResponse, wheel: TiebossWheel, i: int) -> float | None:
    """Tip / probe amplitude ratio at point i (the tip is recovered through the reduction)."""
    named = wheel.sector.cyclic.named_dofs
    if "tip" not in named:
        return None
    x1 = res.sector_harmonics[i, 1]
    full = wheel.reduction.expand(x1) if wheel.reduction is not None else x1
    d = wheel.sector.flexural_direction
    tip = abs(d @ full[np.asarray(named["tip"])])
    pr = abs(d @ full[np.asarray(named["probe"])])
    return float(tip / pr) if pr > 0 else None


def _peak(res: CyclicForcedResponse, amp: np.ndarray) -> int:
    return int(np.argmax(amp)) if amp.size else -1


def forced_response_by_nd(sector: TiebossSector, nd: int, order: int, *, pulses: int = 8,
                          force_N: float = 2.0, frequency_range_hz=(40.0, 52.0),
                          n_modes: int | None = 4, harmonics: int = 5, samples: int = 120,
                          step: float = 0.01) -> dict:
    """Forced response of the rotating wheel around the critical speed of (order, nd).

    The excitation frequency is locked to the speed, ``f = p o n / 60`` (003 (1)), and the
    sector stiffness follows it, ``K + Omega^2 (K_sigma - K_d)``; the load is a forward
    wave of ``nd`` ND of ``force_N`` per blade at the tie-boss (the travelling-wave part of
    the rig's standing pattern, :mod:`fricdamp.models.tieboss_wheel.excitation`).

    Returns
    -------
    dict
        ``nd``, ``order``, ``pulses``, ``rpm``, ``frequency_hz``, ``amplitude_m`` (probe,
        module docstring), ``dissipated_energy_J`` (contact dissipation per period and
        sector), ``energy_balance_error`` (largest over the points), ``peak_rpm``,
        ``peak_frequency_hz``, ``peak_amplitude_m``, ``damping_ratio_at_peak``,
        ``tip_ratio``, ``force_N``, ``n_points``, ``status``, ``message``,
        ``time_per_point_s`` (CPU) and ``runtime_s``.
    """
    E = float(pulses) * int(order)
    pb, wheel = cyclic_problem(sector, nd, force_N=force_N, n_modes=n_modes,
                               harmonics=harmonics, samples=samples, excitations_per_rev=E)
    lo, hi = (2 * np.pi * float(f) for f in frequency_range_hz)
    res = cyclic_frequency_response(pb, lo, hi, step=step)
    dofs, d = _probe(wheel)
    amp = res.amplitude(dofs, d)
    i = _peak(res, amp)
    f_hz = res.omega / (2 * np.pi)
    rpm = 60.0 * f_hz / E
    return {
        "nd": int(nd), "order": int(order), "pulses": int(pulses), "force_N": float(force_N),
        "rpm": rpm.tolist(), "frequency_hz": f_hz.tolist(), "amplitude_m": amp.tolist(),
        "dissipated_energy_J": res.work_contact.tolist(),
        "energy_balance_error": float(res.energy_balance_error.max()) if res.n_points
        else None,
        "peak_rpm": float(rpm[i]), "peak_frequency_hz": float(f_hz[i]),
        "peak_amplitude_m": float(amp[i]),
        "damping_ratio_at_peak": float(res.damping_ratio[i]),
        "tip_ratio": _tip_ratio(res, wheel, i), "n_points": res.n_points,
        "status": res.status, "message": res.message, "n_modes": n_modes,
        "harmonics": res.harmonics, "samples": res.samples,
        "time_per_point_s": res.cpu_s / max(res.n_points, 1), "runtime_s": res.runtime_s,
    }


def damping_vs_amplitude(sector: TiebossSector, nd: int, forces_N, *, order: int | None = None,
                         pulses: int = 8, frequency_range_hz=(40.0, 52.0),
                         n_modes: int | None = 4, harmonics: int = 5, samples: int = 120,
                         step: float = 0.01, law=None, force_vector=None) -> dict:
    """Damping ratio of the resonant state against its amplitude (one sweep per load).

    For each load level the resonance peak of the frequency response (speed-locked with
    ``order``, else at rest) gives the amplitude (probe, module docstring) and the
    equivalent ratio ``zeta = (W_visc + W_contact) / (4 pi E_max)`` (0.1 % material
    damping included, as in 003's log decrements). Load levels whose largest response
    lies at an end of ``frequency_range_hz`` (no resonance inside: the contacts stay
    stuck and the stuck-wheel resonance lies above the range) are left out. ``law`` and
    ``force_vector`` (scaled by each level) as :func:`cyclic_problem`.

    Returns
    -------
    dict
        ``nd``, ``amplitude_m``, ``damping_ratio``, ``frequency_hz``, ``force_N`` (sorted by
        amplitude), ``contact_damping_ratio`` (W_contact alone), ``tip_ratio``,
        ``amplitude_definition``, ``method``.
    """
    E = None if order is None else float(pulses) * int(order)
    rows = []
    t0 = time.perf_counter()
    wheel = None
    for F in forces_N:
        pb, wheel = cyclic_problem(sector, nd, force_N=float(F), n_modes=n_modes,
                                   harmonics=harmonics, samples=samples,
                                   excitations_per_rev=E, wheel=wheel, law=law,
                                   force_vector=None if force_vector is None
                                   else float(F) * np.asarray(force_vector))
        lo, hi = (2 * np.pi * float(f) for f in frequency_range_hz)
        res = cyclic_frequency_response(pb, lo, hi, step=step)
        dofs, d = _probe(wheel)
        amp = res.amplitude(dofs, d)
        if not res.n_points:
            continue
        i = _peak(res, amp)
        if i in (0, res.n_points - 1):      # no resonance inside the interval (stuck wheel
            continue                        # resonating above it): not a peak
        rows.append((float(amp[i]), float(res.damping_ratio[i]),
                     float(res.work_contact[i] / (4 * np.pi * res.kinetic_energy[i])),
                     float(res.omega[i] / (2 * np.pi)), float(F), _tip_ratio(res, wheel, i),
                     res.status))
    rows.sort()
    cols = list(zip(*rows, strict=True)) if rows else [[]] * 7
    return {
        "nd": int(nd), "amplitude_m": list(cols[0]), "damping_ratio": list(cols[1]),
        "contact_damping_ratio": list(cols[2]), "frequency_hz": list(cols[3]),
        "force_N": list(cols[4]), "tip_ratio": list(cols[5]), "status": list(cols[6]),
        "order": order,
        "amplitude_definition": (
            "largest displacement over the period, from its mean, of blade 0's right contact "
            "node (003's node N165136 in the midst of contact B, Fig. 19) along the blade's "
            "flexural direction, at the resonance peak of a forward travelling wave"),
        "method": ("cyclic HB resonance peaks, zeta = (W_visc + W_contact) / (4 pi E_max), "
                   "E_max = Omega^2 x1^H M x1 / 2"),
        "runtime_s": time.perf_counter() - t0,
    }


# ------------------------------------------------------------------------------ full wheel
def wheel_load(wheel: TiebossWheel, nd: int, force_N: float, *, load_group: str = "tieboss",
               omega: float = 1.0) -> HarmonicLoad:
    """The forward wave of ``nd`` ND on the assembled wheel: blade j's ``load_group`` node
    carries ``force_N d exp(-2 pi i nd j / N)`` along its flexural direction ``d``."""
    N = wheel.n_blades
    a = np.zeros(wheel.n_dof, complex)
    d = wheel.sector.flexural_direction
    for j in range(N):
        a[wheel.group_dofs(load_group, j)] = force_N * d * np.exp(-2j * np.pi * nd * j / N)
    return HarmonicLoad(a, omega=omega)


def expand_to_wheel(res: CyclicForcedResponse, wheel: TiebossWheel, point: int) -> np.ndarray:
    """Real harmonic coefficients (n_dof, 2H+1) on the assembled wheel of a cyclic solution:
    sector j's independent DOFs are ``x_h exp(-i h j phi)`` (cyclic_hb module docstring)."""
    N = wheel.n_blades
    ind = wheel.cyclic.independent
    X = res.sector_harmonics[point][:, ind]                       # (H+1, n_ind)
    h = np.arange(X.shape[0])
    ph = np.exp(-2j * np.pi * res.nd * np.outer(np.arange(N), h) / N)   # (N, H+1)
    Xf = (ph[:, :, None] * X[None]).transpose(1, 0, 2).reshape(X.shape[0], -1)
    return _real(Xf)


def mistuned_amplification(wheel: TiebossWheel, nd: int, force_N: float, scatter,
                           *, seed: int = 1, frequency_range_hz=(42.0, 48.0),
                           harmonics: int = 3, samples: int = 120, friction: bool = True,
                           step: float = 0.02) -> dict:
    """Amplification factor of a wheel with per-blade stiffness scatter, by full-wheel HB.

    Sector j's stiffness is ``(1 + s delta_j) K`` (``delta_j`` standard normal, fixed seed,
    zero mean over the wheel), ``s`` each level of ``scatter``, with the Rayleigh damping
    ``a M + b K`` of the mistuned stiffness (so the HB condenses through the mistuned modes;
    the wheel must be small enough for a dense eigenproblem: Craig-Bampton sectors); the
    load is the forward
    ``nd`` wave; the amplification factor is the largest peak amplitude of any blade's
    probe over the tuned wheel's peak (the scatter level 0: by cyclic HB with friction,
    the same travelling-wave state as the full-wheel HB).
    ``friction=False``: the contacts are removed (open contacts, the linear wheel; its
    response is solved directly per frequency on a fine grid).

    Returns
    -------
    dict
        ``scatter``, ``amplification_factor``, ``peak_amplitude_m``, ``peak_frequency_hz``,
        ``blade_of_peak``, ``friction``, ``seed``, ``status``.
    """
    from fricdamp.solvers.hb import frequency_response

    rng = np.random.default_rng(seed)
    N = wheel.n_blades
    delta = rng.standard_normal(N)
    delta -= delta.mean()
    cyc = wheel.cyclic
    T = [cyc.transform(j) for j in range(N)]
    Ks = sp.csr_matrix(cyc.K)
    probes = wheel.group_dofs_all("probe")                            # (N, 3)
    d = wheel.sector.flexural_direction
    lo, hi = (2 * np.pi * float(f) for f in frequency_range_hz)
    levels = [0.0] + [float(s) for s in scatter if float(s) != 0.0]
    a_r, b_r = wheel.parameters.rayleigh()
    out = {"scatter": [], "peak_amplitude_m": [], "peak_frequency_hz": [],
           "blade_of_peak": [], "status": []}
    load = wheel_load(wheel, nd, force_N)
    from fricdamp.solvers.aft import HarmonicBasis

    syn = HarmonicBasis.create(harmonics, 256).synthesis
    for s in levels:
        K = sum(((1.0 + s * delta[j]) * (T[j].T @ Ks @ T[j]) for j in range(N)),
                sp.csr_matrix((wheel.n_dof, wheel.n_dof)))
        K = sp.csr_matrix(0.5 * (K + K.T))
        # Rayleigh damping of the mistuned blades (b K follows each blade's stiffness), so
        # the HB condenses through the mistuned modes
        D = a_r * wheel.system.M + b_r * K
        dense = not wheel.system.is_sparse
        sysm = replace(wheel.system, K=K.toarray() if dense else K,
                       D=_dense(D) if dense else sp.csr_matrix(D),
                       loads=(load,), contacts=wheel.system.contacts if friction else ())
        if friction and s == 0.0:
            # the tuned wheel: its travelling-wave response by cyclic HB (the same states
            # as the full-wheel HB, tests/validation/test_cyclic_hb.py), every blade alike
            pb, _ = cyclic_problem(wheel.sector, nd, force_N=force_N, harmonics=harmonics,
                                   samples=samples, wheel=wheel)
            cr = cyclic_frequency_response(pb, lo, hi, step=step)
            amp = cr.amplitude(np.asarray(cyc.named_dofs["probe"]), d)[:, None]
            om, status = cr.omega, cr.status
        elif friction:
            fr = frequency_response(sysm, lo, hi, harmonics=harmonics, samples=samples,
                                    step=step, max_step=20 * step)
            X = fr.coefficients[:, probes]                             # (n_p, N, 3, nh)
            sig = np.einsum("pjdh,d,sh->pjs", X, d, syn)
            amp = np.abs(sig - sig.mean(axis=2, keepdims=True)).max(axis=2)
            om = fr.omega
            status = fr.status
        else:
            # linear wheel: modal superposition on a fine grid (Rayleigh: diagonal)
            import scipy.linalg as sla

            lam, Phi = sla.eigh(_dense(K), _dense(wheel.system.M))
            c = a_r + b_r * lam
            g = Phi.T @ load.amplitude
            Pp = np.einsum("d,jdm->jm", d, Phi[probes])                 # (N, n_modes)
            om = np.linspace(lo, hi, 2000)
            den = lam[None, :] - om[:, None] ** 2 + 1j * om[:, None] * c[None, :]
            amp = np.abs((g[None, :] / den) @ Pp.T)                      # (n_om, N)
            status = 0
        p, j = np.unravel_index(int(np.argmax(amp)), amp.shape)
        out["scatter"].append(s)
        out["peak_amplitude_m"].append(float(amp[p, j]))
        out["peak_frequency_hz"].append(float(om[p] / (2 * np.pi)))
        out["blade_of_peak"].append(int(j))
        out["status"].append(int(status))
    tuned = out["peak_amplitude_m"][0]
    out["amplification_factor"] = [a / tuned for a in out["peak_amplitude_m"]]
    out.update(friction=bool(friction), seed=int(seed), nd=int(nd), force_N=float(force_N))
    return out


# ------------------------------------------------------------------------------ release
def release_decay(sector: TiebossSector, nd: int, order: int, *, force_N: float = 2.0,
                  pulses: int = 8, frequency_range_hz=(40.0, 52.0), n_modes: int = 4,
                  harmonics: int = 5, samples: int = 120, duration_s: float = 0.3,
                  dt: float = 1e-5) -> dict:
    """Resonance, release, decay -- as in the rig test (003 section 2.3).

    The speed-locked cyclic HB response is followed to its resonance peak; at that speed the
    travelling-wave state (expanded to the 30 Craig-Bampton sectors, displacement and
    velocity at ``tau = 0``) starts a free decay of the *rotating* wheel (stiffness
    ``K + Omega^2 (K_sigma - K_d)`` of every sector; the excitation switched off) by the
    compiled contact integrator; the contacts start from their virgin state loaded to the
    initial displacement (the sliders are not part of the HB unknowns), which perturbs the
    first cycles. The probe's Hilbert envelope gives zeta(A) along the decay.

    Returns
    -------
    dict
        ``nd``, ``order``, ``rpm``, ``start_amplitude_m`` (HB peak), ``amplitude_m`` and
        ``damping_ratio`` (Hilbert, cycle by cycle), ``record_damping_ratio`` (log
        decrement of the envelope peaks), ``frequency_hz``, ``energy_balance_error``,
        ``runtime_s``.
    """
    from fricdamp.models.tieboss_wheel.studies import decay_estimates
    from fricdamp.solvers.fast_transient import integrate_contact3d

    E = float(pulses) * int(order)
    pb, wheel = cyclic_problem(sector, nd, force_N=force_N, n_modes=n_modes,
                               harmonics=harmonics, samples=samples, excitations_per_rev=E)
    lo, hi = (2 * np.pi * float(f) for f in frequency_range_hz)
    res = cyclic_frequency_response(pb, lo, hi)
    dofs, d = _probe(wheel)
    amp = res.amplitude(dofs, d)
    i = _peak(res, amp)
    om = float(res.omega[i])
    spin = om / E
    # the rotating wheel at that speed
    N = wheel.n_blades
    Kr = sp.csr_matrix(_rotation_stiffness(sector, wheel))
    T = [wheel.cyclic.transform(j) for j in range(N)]
    Kw = sum((T[j].T @ Kr @ T[j] for j in range(N)), sp.csr_matrix((wheel.n_dof,) * 2))
    K = _dense(wheel.system.K) + spin**2 * _dense(0.5 * (Kw + Kw.T))
    a_r, b_r = wheel.parameters.rayleigh()
    # Rayleigh damping of the spinning stiffness (the compiled integrator needs it modal;
    # b Omega^2 K_rot changes the 0.1 % by < 1e-3 of itself)
    system = replace(wheel.system, K=K, D=a_r * _dense(wheel.system.M) + b_r * K, loads=())
    C = expand_to_wheel(res, wheel, i)                               # (n_dof, 2H+1)
    h = np.arange(1, pb.H + 1)
    q0 = C[:, 0] + C[:, 1::2].sum(axis=1)                            # tau = 0
    v0 = om * (C[:, 2::2] * h).sum(axis=1)
    out = integrate_contact3d(system, duration_s, dt, q0=q0, v0=v0, save_every=5,
                              output_dofs=wheel.group_dofs("probe", 0))
    x = out.q @ d
    x = x - np.mean(x[-max(x.size // 20, 10):])                     # rest position at the end
    dec, hil, zeta = decay_estimates(out.t, x, f"{nd}ND release")
    src = hil if hil is not None else dec
    return {"nd": int(nd), "order": int(order), "rpm": 60.0 * om / (2 * np.pi * E),
            "start_amplitude_m": float(amp[i]),
            "amplitude_m": [] if src is None else src.amplitude.tolist(),
            "damping_ratio": [] if src is None else src.damping_ratio.tolist(),
            "record_damping_ratio": zeta,
            "frequency_hz": None if dec is None else dec.mean_frequency_hz,
            "energy_balance_error": float(out.energy_balance_error),
            "duration_s": duration_s, "dt_s": dt, "runtime_s": float(out.runtime_s)}


def standing_wave_peaks(sector: TiebossSector, nd: int, forces_N, *, n_modes: int = 4,
                        harmonics: int = 3, samples: int = 120,
                        frequency_range_hz=(43.0, 46.5), step: float = 0.02) -> dict:
    """Resonance peaks of the wheel under a *standing* ND pattern (the rig's kind of load).

    Blade j carries ``F cos(2 pi nd j / N)`` at the tie-boss along its flexural direction
    (two counter-rotating waves of ``F / 2``; for the linear wheel its antinode response
    equals the travelling wave's of ``F``). The assembled Craig-Bampton wheel at rest is
    solved by the full-wheel HB (a standing state is not a one-sector problem); at each
    level's peak: the largest blade amplitude (an antinode, probe definition of the module
    docstring) and ``zeta = (W_visc + W_contact) / (4 pi E_max)`` over the whole wheel.

    Returns
    -------
    dict
        ``nd``, ``amplitude_m``, ``damping_ratio``, ``frequency_hz``, ``force_N`` (sorted by
        amplitude), ``status``.
    """
    from fricdamp.solvers.aft import HarmonicBasis
    from fricdamp.solvers.hb import frequency_response

    wheel = build_wheel(sector, n_modes=n_modes)
    d = wheel.sector.flexural_direction
    probes = wheel.group_dofs_all("probe")
    syn = HarmonicBasis.create(harmonics, 256).synthesis
    lo, hi = (2 * np.pi * float(f) for f in frequency_range_hz)
    M = wheel.system.M
    rows = []
    for F in forces_N:
        ld = wheel_load(wheel, nd, float(F))
        load = HarmonicLoad(ld.amplitude.real.astype(complex), omega=1.0)
        fr = frequency_response(replace(wheel.system, loads=(load,)), lo, hi,
                                harmonics=harmonics, samples=samples, step=step,
                                max_step=20 * step)
        if not len(fr.omega):
            continue
        sig = np.einsum("pjdh,d,sh->pjs", fr.coefficients[:, probes], d, syn)
        amp = np.abs(sig - sig.mean(axis=2, keepdims=True)).max(axis=2)
        p = int(np.argmax(amp.max(axis=1)))
        if p in (0, len(fr.omega) - 1):
            continue
        x1 = fr.coefficients[p][:, 1] - 1j * fr.coefficients[p][:, 2]
        e_max = 0.5 * fr.omega[p] ** 2 * float(np.real(np.vdot(x1, M @ x1)))
        w_d = float(fr.dissipated_energy[p].sum() + fr.viscous_dissipation[p])
        rows.append((float(amp[p].max()), w_d / (4 * np.pi * e_max),
                     float(fr.omega[p] / (2 * np.pi)), float(F), int(fr.status)))
    rows.sort()
    cols = list(zip(*rows, strict=True)) if rows else [[]] * 5
    return {"nd": int(nd), "amplitude_m": list(cols[0]), "damping_ratio": list(cols[1]),
            "frequency_hz": list(cols[2]), "force_N": list(cols[3]), "status": list(cols[4])}
