"""Built-in time-domain analyses of a case: free decay, forced response, hysteresis.

Each is registered in :data:`fricdamp.runner.REGISTRY` under its ``[analysis.<name>]`` table.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from fricdamp.case import ForcedResponse, FreeDecay, Hysteresis
from fricdamp.errors import CaseError, ConvergenceError, ModelError
from fricdamp.limits import check_time_memory
from fricdamp.registry import AnalysisOutput, RunContext, register_analysis
from fricdamp.verdict import THRESHOLDS, judge, time_result_verdict

# ========================================================================== closed forms
#: Closed-form loop energies per law class, used by the hysteresis analysis.
_CLOSED_FORMS: dict[type, Callable] = {}


def register_closed_form(law_class: type, fn: Callable) -> None:
    """Register ``fn(law, amplitudes) -> (n_contacts, n_amplitudes)`` energy per cycle [J]
    for ``u = A sin(theta)``; shown next to the numerical loops of ``[analysis.hysteresis]``."""
    _CLOSED_FORMS[law_class] = fn


def jenkins_loop_energy(law, amplitudes) -> np.ndarray:
    """Energy per cycle of Jenkins elements, ``W = 4 F_s (A - F_s/k_t)`` for ``A > F_s/k_t``.

    Closed form of den Hartog / Iwan (docs REFERENCES.md, "Jenkins element"); 0 while stuck.
    Returns shape (n_contacts, n_amplitudes) [J].
    """
    A = np.asarray(amplitudes, float)[None, :]
    fs = law.slip_force[:, None]
    a_slip = fs / law.stiffness[:, None]
    return np.where(A > a_slip, 4.0 * fs * (A - a_slip), 0.0)


def coulomb_loop_energy(law, amplitudes) -> np.ndarray | None:
    """Energy per cycle of static/kinetic Coulomb sliders with constant sliding coefficient.

    Derived here for ``u = A sin(theta)`` (steady cycle): a reversal re-sticks the slider at
    ``+mu_d N``; it breaks away again after the travel ``L = (mu_s + mu_d) N / k_t`` at
    ``-mu_s N`` and slides at ``-mu_d N``. Integrating ``f du`` over both branches::

        W = 4 mu_d N A - (mu_s + mu_d)(3 mu_d - mu_s) N^2 / k_t    for A > mu_s N / k_t

    and 0 below (never breaks away). With mu_s = mu_d it is the Jenkins form
    ``4 mu N (A - mu N / k_t)``. Returns None when a contact has ``decay > 0``
    (velocity-dependent coefficient: no closed form), else (n_contacts, n_amplitudes) [J].
    """
    if np.any(law.decay > 0):
        return None
    A = np.asarray(amplitudes, float)[None, :]
    N, kt = law.normal_load[:, None], law.stiffness[:, None]
    mus, mud = law.mu_static[:, None], law.mu_sliding[:, None]
    W = 4 * mud * N * A - (mus + mud) * (3 * mud - mus) * N**2 / kt
    return np.where(A > mus * N / kt, W, 0.0)


def _register_default_closed_forms() -> None:
    from fricdamp.contact import Jenkins
    from fricdamp.contact.coulomb import Coulomb

    register_closed_form(Jenkins, jenkins_loop_energy)
    register_closed_form(Coulomb, coulomb_loop_energy)


_register_default_closed_forms()


# ================================================================================ analyses
def _contact_labels(system) -> list[tuple[int, int, str]]:
    """(element index, contact index, label) for every single contact of the system."""
    out = []
    for e, c in enumerate(system.contacts):
        for k in range(c.n_contacts):
            out.append((e, k, c.name if c.n_contacts == 1 else f"{c.name}[{k + 1}]"))
    return out


def _contact_rows(system) -> int:
    return sum(c.n_contacts * c.n_dir for c in system.contacts)


def _check_vector(values, n_dof: int, key: str) -> None:
    if values is not None and len(values) != n_dof:
        raise CaseError(f"{key} must have one entry per DOF ({n_dof}), got {len(values)}")


def _check_dof(dof, n_dof: int, key: str) -> None:
    if dof is not None and dof > n_dof:
        raise CaseError(f"{key} = {dof}: the model has {n_dof} DOFs, numbered 1 to {n_dof}")


# ------------------------------------------------------------------------- free decay
def _check_free_decay(system, spec: FreeDecay) -> None:
    n = system.n_dof
    _check_vector(spec.initial_displacement_m, n, "initial_displacement_m")
    _check_vector(spec.initial_velocity_m_per_s, n, "initial_velocity_m_per_s")
    _check_dof(spec.response_dof, n, "response_dof")


def _mechanical_energy(energy: Mapping) -> np.ndarray:
    return energy["kinetic"] + energy["strain"] + energy["contact_stored"]


def run_free_decay(system, spec: FreeDecay, ctx: RunContext) -> AnalysisOutput:
    """Free decay by time stepping; damping ratio and frequency vs amplitude from the peaks.

    The decay of ``response_dof`` is analysed by
    :func:`fricdamp.signals.decay.decay_damping` (peak method). The energy balance error is
    the time integrator's (:attr:`TimeResult.energy_balance_error`).
    """
    import xarray as xr

    from fricdamp.solvers.timestep import simulate

    n = system.n_dof
    q0 = np.zeros(n) if spec.initial_displacement_m is None else np.asarray(
        spec.initial_displacement_m, float)
    v0 = np.zeros(n) if spec.initial_velocity_m_per_s is None else np.asarray(
        spec.initial_velocity_m_per_s, float)
    if spec.response_dof is not None:
        dof = spec.response_dof - 1
    else:
        dof = int(np.argmax(np.abs(q0))) if np.any(q0) else int(np.argmax(np.abs(v0)))
    sys_ = system.with_loads()
    check_time_memory(spec.duration_s, spec.time_step_s, n, _contact_rows(system),
                      save_every=spec.save_every, param="time_step_s")
    res = simulate(sys_, spec.duration_s, spec.time_step_s, q0=q0, v0=v0,
                   save_every=spec.save_every, **ctx.simulate_kwargs())
    if not res.success:
        raise ConvergenceError(res.message)
    sd = _step_doubling_decay(sys_, res, spec, q0, v0, ctx)
    verdict = time_result_verdict(sys_, res, spec.time_step_s,
                                  estimates={"step_doubling_error": sd})

    notes = []
    x = res.q[:, dof]
    try:
        decay, center = _identify_decay(res.t, x)
        amp = np.asarray(decay.amplitude, float)
        zeta = np.asarray(decay.damping_ratio, float)
        freq = np.asarray(decay.frequency_hz, float)
    except ModelError as exc:
        notes.append(f"no damping could be identified from the decay of "
                     f"{system.names[dof]}: {exc}")
        decay, center = None, 0.0
        amp = zeta = freq = np.zeros(0)
    if decay is not None and not decay.verdict.ok:
        # e.g. two modes in the record: a decrement would mix both modes' damping
        for reason in decay.verdict.reasons:
            verdict = verdict.worse(decay.verdict.status, f"decay of {system.names[dof]}: "
                                                          f"{reason}")

    e = res.energy
    mech = _mechanical_energy(e)
    summary = {
        "response_dof": dof + 1,
        "response_dof_name": system.names[dof],
        "amplitude_m": amp,
        "damping_ratio": zeta,
        "frequency_hz": freq,
        "max_damping_ratio": float(np.nanmax(zeta)) if zeta.size else None,
        "amplitude_at_max_damping_m": float(amp[np.nanargmax(zeta)]) if zeta.size else None,
        "mean_damping_ratio": float(decay.mean_damping_ratio) if decay is not None else None,
        "envelope_model": decay.model if decay is not None else None,
        "second_mode_ratio": float(decay.second_mode_ratio) if decay is not None else None,
        "oscillation_center_m": float(center),
        "initial_energy_J": float(mech[0]),
        "final_energy_J": float(mech[-1]),
        "contact_dissipation_J": float(e["contact_dissipation"][-1] - e["contact_dissipation"][0]),
        "viscous_dissipation_J": float(e["viscous_dissipation"][-1] - e["viscous_dissipation"][0]),
        "energy_balance_error": float(res.energy_balance_error),
        "period_error": verdict.estimates.get("period_error"),
        "n_steps": int(res.n_steps),
        "solver_runtime_s": float(res.runtime_s),
    }
    decay_ds = xr.Dataset(
        {"amplitude": ("peak", amp, {"units": "m"}),
         "damping_ratio": ("peak", zeta, {"units": "1"}),
         "frequency": ("peak", freq, {"units": "Hz"})},
        attrs={"response_dof": dof + 1, "method": "peaks"})
    arrays = {"response": res.to_xarray(), "decay": decay_ds}
    headline = (f"{res.n_steps} steps in {res.runtime_s:.2f} s; "
                + (f"largest damping ratio {100 * summary['max_damping_ratio']:.3g} % at "
                   f"amplitude {summary['amplitude_at_max_damping_m']:.3g} m; " if zeta.size
                   else "")
                + f"energy balance error {res.energy_balance_error:.2e}")

    def figures():
        from fricdamp import plot

        names = list(system.names)
        figs = [("free_decay_response.png", "Free decay: displacement of each DOF",
                 plot.time_histories(res.t, res.q, names, title="Free decay")),
                ("free_decay_energy.png", "Free decay: energy balance",
                 plot.energy_partition(res.t, e, title="Free decay: where the energy goes"))]
        if zeta.size:
            figs.insert(1, ("free_decay_damping.png",
                            f"Free decay: damping ratio and frequency vs amplitude of "
                            f"{names[dof]}",
                            plot.damping_vs_amplitude(amp, zeta, freq,
                                                      title=f"Free decay of {names[dof]}")))
        loops = _loops_of(system, res.contact_displacement, res.contact_force, slice(None))
        if loops:
            figs.append(("free_decay_contacts.png", "Free decay: contact force vs relative "
                         "displacement", plot.hysteresis_loops(
                             loops, title="Contacts during the free decay")))
        return figs

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, verdict=verdict)


def _coarse_kwargs(ctx: RunContext) -> dict:
    kw = ctx.simulate_kwargs()
    kw.update(progress=False, throw=False)
    return kw


def _step_doubling_decay(sys_, res, spec: FreeDecay, q0, v0, ctx) -> float | None:
    """Richardson estimate of the time-step error of a free decay: the mechanical-energy
    history at 2 dt against dt, a third of the largest difference relative to the largest
    energy (None if the coarse run fails)."""
    from fricdamp.solvers.timestep import simulate

    coarse = simulate(sys_, spec.duration_s, 2 * spec.time_step_s, q0=q0, v0=v0,
                      **_coarse_kwargs(ctx))
    if not coarse.success:
        return None
    e_f, e_c = _mechanical_energy(res.energy), _mechanical_energy(coarse.energy)
    k = np.arange(e_f.size)
    idx = k * spec.save_every
    common = idx % 2 == 0
    j = idx[common] // 2
    ok = j < e_c.size
    diff = np.abs(e_f[common][ok] - e_c[j[ok]])
    scale = float(np.max(np.abs(e_f)))
    if diff.size == 0 or scale == 0:
        return None
    return float(np.max(diff) / (3.0 * scale))


def _step_doubling_forced(sys_, spec: ForcedResponse, amp, ctx) -> float | None:
    """Richardson estimate of the time-step error of a forced response: the amplitudes of the
    last period at steps_per_period / 2, a third of the largest difference relative to the
    largest amplitude (None for an odd steps_per_period or a failed coarse run)."""
    from fricdamp.solvers.timestep import simulate

    N = spec.steps_per_period
    if N % 2 or N < 8:
        return None
    period = 1.0 / spec.frequency_hz
    coarse = simulate(sys_, spec.periods * period, 2 * period / N, **_coarse_kwargs(ctx))
    if not coarse.success:
        return None
    q = coarse.q[coarse.t.size - N // 2 - 1:]
    amp_c = 0.5 * (q.max(axis=0) - q.min(axis=0))
    scale = float(np.max(amp))
    return float(np.max(np.abs(amp - amp_c)) / (3.0 * scale)) if scale > 0 else None


def _identify_decay(t, x):
    """Decay identification about the equilibrium the oscillation settles to.

    A friction contact that sticks leaves the structure oscillating about a shifted
    equilibrium (the slider stays where it stopped). Measured from zero, alternate half-cycle
    peaks then differ by twice that offset and the half-cycle decrements alternate in sign.
    When the record ends in a nearly stationary oscillation (last two envelope points within
    5 %), the decay is analysed again about the level ``((p1 + p3) / 2 + p2) / 2`` of its last
    three extrema (alternating maxima and minima; averaging the outer two cancels a linear
    decay of the amplitude). Returns (DecayResult, center [m]).
    """
    import warnings

    from fricdamp.signals.decay import decay_damping, find_peaks

    with warnings.catch_warnings():     # a two-mode record: said by the analysis verdict
        warnings.simplefilter("ignore", UserWarning)
        decay = decay_damping(t, x, method="peaks", kind="auto")
    env = decay.envelope.amplitude
    if env.size >= 3 and abs(env[-1] - env[-2]) < 0.05 * env[-1]:
        pk = find_peaks(t, x, negative=True)
        v, sg = pk.value[-3:], pk.sign[-3:]
        if v.size == 3 and sg[0] == sg[2] != sg[1]:
            center = 0.5 * (0.5 * (v[0] + v[2]) + v[1])
            if center != 0.0:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)
                    return decay_damping(t, x, method="peaks", kind="auto",
                                         center=center), center
    return decay, 0.0


def _plot_direction(n_dir: int) -> int:
    """Direction drawn in loop plots: the only one, or the first tangential (index 1)."""
    return 0 if n_dir == 1 else 1


def _loops_of(system, cu, cf, sl: slice) -> list[tuple[str, np.ndarray, np.ndarray]]:
    loops = []
    for e, k, label in _contact_labels(system):
        d = _plot_direction(system.contacts[e].n_dir)
        loops.append((label, cu[e][sl, k, d], cf[e][sl, k, d]))
    return loops


# --------------------------------------------------------------------- forced response
#: Largest relative change of the amplitudes over the last period of a forced response that
#: is called a steady state (a transient is never called one).
STEADY_STATE_LIMIT = 1e-2

def _check_forced(system, spec: ForcedResponse) -> None:
    _check_vector(spec.force_amplitude_N, system.n_dof, "force_amplitude_N")


def run_forced_response(system, spec: ForcedResponse, ctx: RunContext) -> AnalysisOutput:
    """Harmonic force ``F cos(2 pi f t)`` from rest, time stepping to a steady state.

    The last excitation period is taken as the steady state: amplitude per DOF (half the
    peak-to-peak), each contact's hysteresis loop and its area (energy dissipated per cycle,
    summed over the contact's directions), the input work per cycle and the viscous
    dissipation per cycle. ``cycle_energy_balance_error`` is
    ``|W_in - W_viscous - W_contacts - dE_mech| / W_in`` over that period (0 for an exact
    integration), ``steady_state_change`` the relative change of the amplitudes between the
    last two periods (small once the transient has died out).
    """
    import xarray as xr

    from fricdamp.signals.energy import loop_area
    from fricdamp.solvers.timestep import simulate
    from fricdamp.structure import HarmonicLoad

    f_hz = spec.frequency_hz
    N = spec.steps_per_period
    period = 1.0 / f_hz
    load = HarmonicLoad(np.asarray(spec.force_amplitude_N, float), 2 * np.pi * f_hz)
    sys_ = system.with_loads(load)
    check_time_memory(spec.periods * period, period / N, system.n_dof, _contact_rows(system),
                      param="steps_per_period", value=N)
    res = simulate(sys_, spec.periods * period, period / N, **ctx.simulate_kwargs())
    if not res.success:
        raise ConvergenceError(res.message)

    n_t = res.t.size
    last = slice(n_t - N - 1, n_t)  # N + 1 samples: one full period, both ends
    prev = slice(n_t - 2 * N - 1, n_t - N)
    q_last, q_prev = res.q[last], res.q[prev]
    amp = 0.5 * (q_last.max(axis=0) - q_last.min(axis=0))
    amp_prev = 0.5 * (q_prev.max(axis=0) - q_prev.min(axis=0))
    change = float(np.max(np.abs(amp - amp_prev)) / max(np.max(amp), 1e-300))

    e = res.energy
    mech = _mechanical_energy(e)

    def per_cycle(arr):
        return float(arr[-1] - arr[-N - 1])

    w_in = per_cycle(e["input_work"])
    w_visc = per_cycle(e["viscous_dissipation"])
    w_cont = per_cycle(e["contact_dissipation"])
    d_mech = per_cycle(mech)
    cycle_err = abs(w_in - w_visc - w_cont - d_mech) / abs(w_in) if w_in else None

    contacts = {}
    for el, k, label in _contact_labels(system):
        u = res.contact_displacement[el][last, k, :]
        f = res.contact_force[el][last, k, :]
        area = sum(loop_area(u[:, d], f[:, d]) for d in range(u.shape[1]))
        dd = _plot_direction(u.shape[1])
        contacts[label] = {
            "dissipated_energy_per_cycle_J": float(area),
            "relative_displacement_amplitude_m": float(0.5 * np.ptp(u[:, dd])),
            "force_amplitude_N": float(0.5 * np.ptp(f[:, dd])),
        }

    # energy per period over the whole run (convergence to the steady state)
    idx = np.arange(0, n_t, N)
    w_in_k = np.diff(e["input_work"][idx])
    w_d_k = np.diff(e["viscous_dissipation"][idx] + e["contact_dissipation"][idx])

    summary = {
        "frequency_hz": f_hz,
        "dof_names": list(system.names),
        "amplitude_m": amp,
        "steady_state_change": change,
        "input_work_per_cycle_J": w_in,
        "viscous_dissipation_per_cycle_J": w_visc,
        "contact_dissipation_per_cycle_J": w_cont,
        "cycle_energy_balance_error": cycle_err,
        "contacts": contacts,
        "energy_balance_error": float(res.energy_balance_error),
        "n_steps": int(res.n_steps),
        "solver_runtime_s": float(res.runtime_s),
    }
    notes = []
    reasons = []
    if change > STEADY_STATE_LIMIT:
        reasons.append(f"the response is not yet steady (amplitudes changed by "
                       f"{100 * change:.2g} % over the last period, limit "
                       f"{100 * STEADY_STATE_LIMIT:g} %): increase periods")
    if cycle_err is not None and cycle_err > THRESHOLDS["energy_balance_error"]:
        reasons.append(f"the energy balance of the last period is off by {cycle_err:.3g} "
                       f"(limit {THRESHOLDS['energy_balance_error']:g}): the last period is "
                       "not a steady cycle, or the time step is too large")
    negative = {k: v["dissipated_energy_per_cycle_J"] for k, v in contacts.items()
                if v["dissipated_energy_per_cycle_J"] < -1e-6 * max(abs(w_in), 1e-300)}
    if negative:
        k, v = next(iter(negative.items()))
        reasons.append(f"contact {k!r} gives energy back over the last period ({v:.3g} J): "
                       "a passive contact cannot; reduce the time step")
    sd = _step_doubling_forced(sys_, spec, amp, ctx)
    verdict = time_result_verdict(sys_, res, period / N, reasons=reasons, estimates={
        "step_doubling_error": sd, "steady_state_change": change,
        "cycle_energy_balance_error": cycle_err})
    summary["period_error"] = verdict.estimates.get("period_error")
    names = list(system.names)
    arrays = {
        "response": res.to_xarray(),
        "steady_state": xr.Dataset(
            {"amplitude": ("dof", amp, {"units": "m", "long_name": "amplitude, last period"})},
            coords={"dof": names}),
        "cycles": xr.Dataset(
            {"input_work": ("period", w_in_k, {"units": "J"}),
             "dissipated_energy": ("period", w_d_k, {"units": "J"})},
            coords={"period": np.arange(1, w_in_k.size + 1)}),
    }
    i_max = int(np.argmax(amp))
    headline = (f"{res.n_steps} steps in {res.runtime_s:.2f} s; amplitude of {names[i_max]} "
                f"{amp[i_max]:.3g} m at {f_hz:g} Hz; input work per cycle {w_in:.3g} J; "
                f"energy balance error {res.energy_balance_error:.2e}")

    def figures():
        from fricdamp import plot

        figs = [("forced_response_time.png",
                 f"Forced response at {f_hz:g} Hz: displacement of each DOF",
                 plot.time_histories(res.t, res.q, names, title=f"Forced response at "
                                     f"{f_hz:g} Hz"))]
        loops = _loops_of(system, res.contact_displacement, res.contact_force, last)
        if loops:
            figs.append(("forced_response_loops.png",
                         "Forced response: hysteresis loop of each contact over the last period",
                         plot.hysteresis_loops(loops, title="Contacts over the last period")))
        figs.append(("forced_response_energy.png",
                     "Forced response: input work and dissipated energy per period",
                     plot.cycle_energy(np.arange(1, w_in_k.size + 1), w_in_k, w_d_k,
                                       title="Energy per excitation period")))
        return figs

    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          notes=notes, verdict=verdict)


# -------------------------------------------------------------------------- hysteresis
def _hysteresis_elements(system, spec: Hysteresis):
    """The contacts to drive: those named in ``contacts``, or every one-directional one."""
    names = [c.name for c in system.contacts]
    if spec.contacts is not None:
        for n in spec.contacts:
            if n not in names:
                raise CaseError(f"contacts: there is no contact named {n!r}; the case has "
                                f"{', '.join(repr(x) for x in names) or 'no contacts'}")
        chosen = [c for c in system.contacts if c.name in spec.contacts]
        multi = [c for c in chosen if c.n_dir != 1]
        if multi:
            raise CaseError(f"contacts: {multi[0].name!r} has {multi[0].n_dir} directions; the "
                            "hysteresis analysis drives one-directional laws only")
        return chosen
    chosen = [c for c in system.contacts if c.n_dir == 1]
    if not chosen:
        raise CaseError("needs at least one one-directional contact (jenkins, coulomb) to "
                        "drive; the case has " + (", ".join(repr(x) for x in names) or "none"))
    return chosen


def _check_hysteresis(system, spec: Hysteresis) -> None:
    _hysteresis_elements(system, spec)


def run_hysteresis(system, spec: Hysteresis, ctx: RunContext) -> AnalysisOutput:
    """Drive each contact law with ``u = A sin(2 pi f t)``; loop energy vs amplitude.

    Each amplitude starts from the virgin state and runs ``cycles`` cycles; the last cycle
    is the loop, its area (:func:`fricdamp.signals.energy.loop_area`) the energy dissipated
    per cycle. Where a closed form is registered for the law (Jenkins:
    ``W = 4 F_s (A - F_s/k_t)``), it is given alongside with the largest deviation relative
    to the largest closed-form energy.
    """
    import xarray as xr

    from fricdamp.signals.energy import loop_area

    elements = _hysteresis_elements(system, spec)
    A = np.asarray(spec.amplitudes_m, float)
    n_s = spec.samples_per_cycle
    omega = 2 * np.pi * spec.frequency_hz
    t = np.arange(spec.cycles * n_s + 1) / (n_s * spec.frequency_hz)
    last = slice(t.size - n_s - 1, t.size)
    labels, energies, closed, loops_f = [], [], [], []
    for c in elements:
        law = c.law
        nc = c.n_contacts
        W = np.empty((nc, A.size))
        fu = np.empty((nc, A.size, n_s + 1))
        for j, a in enumerate(A):
            u = np.broadcast_to((a * np.sin(omega * t))[:, None, None], (t.size, nc, 1))
            v = np.broadcast_to((a * omega * np.cos(omega * t))[:, None, None], u.shape)
            f = law.drive(np.array(u), np.array(v))
            for k in range(nc):
                W[k, j] = loop_area(u[last, k, 0], f[last, k, 0])
                fu[k, j] = f[last, k, 0]
        cf = _closed_form(law, A)
        for k in range(nc):
            labels.append(c.name if nc == 1 else f"{c.name}[{k + 1}]")
            energies.append(W[k])
            closed.append(None if cf is None else cf[k])
            loops_f.append(fu[k])

    contacts = {}
    errors = []
    for label, W, Wc in zip(labels, energies, closed, strict=True):
        entry = {"loop_energy_J": W}
        if Wc is not None:
            scale = np.max(np.abs(Wc))
            err = float(np.max(np.abs(W - Wc)) / scale) if scale > 0 else float(np.max(np.abs(W)))
            entry.update(closed_form_J=Wc, closed_form_error=err)
            errors.append(err)
        contacts[label] = entry
    summary = {"amplitude_m": A, "frequency_hz": spec.frequency_hz, "cycles": spec.cycles,
               "samples_per_cycle": n_s, "contacts": contacts,
               "max_closed_form_error": max(errors) if errors else None}
    u_last = A[:, None] * np.sin(omega * t[last])[None, :]
    arrays = {"loops": xr.Dataset(
        {"u": (("amplitude", "sample"), u_last, {"units": "m"}),
         "force": (("contact", "amplitude", "sample"), np.array(loops_f), {"units": "N"}),
         "loop_energy": (("contact", "amplitude"), np.array(energies), {"units": "J"})},
        coords={"contact": labels, "amplitude": A})}
    if any(c is not None for c in closed):
        arrays["loops"]["closed_form_energy"] = (
            ("contact", "amplitude"),
            np.array([np.full(A.size, np.nan) if c is None else c for c in closed]),
            {"units": "J"})
    headline = f"{len(labels)} contact(s) x {A.size} amplitudes" + (
        f"; largest deviation from the closed form {max(errors):.2e}" if errors else "")

    def figures():
        from fricdamp import plot

        loops = [(f"A = {plot.format_si(a, 'm')}", u_last[j], loops_f[i][j])
                 for i, label in enumerate(labels) for j, a in enumerate(A)]
        return [
            ("hysteresis_loops.png", "Hysteresis: force vs imposed relative displacement",
             plot.hysteresis_loops(loops, title="Contact laws driven at each amplitude",
                                   group=[lab for lab in labels for _ in A])),
            ("hysteresis_energy.png", "Hysteresis: dissipated energy per cycle vs amplitude",
             plot.loop_energy_vs_amplitude(A, dict(zip(labels, energies, strict=True)),
                                           _closed_form_curves(elements, A),
                                           title="Energy dissipated per cycle")),
        ]

    worst = min((float(np.min(W)) / max(float(np.max(np.abs(W))), 1e-300), label)
                for label, W in zip(labels, energies, strict=True))
    verdict = judge({"negative_dissipation": max(0.0, -worst[0]),
                     "max_closed_form_error": summary["max_closed_form_error"]})
    if worst[0] < -THRESHOLDS["negative_dissipation"]:
        verdict = verdict.worse("unreliable", f"the loop of {worst[1]!r} has a negative area: "
                                "the law gives energy back over a closed cycle (not passive)")
    return AnalysisOutput(summary=summary, arrays=arrays, figures=figures, headline=headline,
                          verdict=verdict)


def _closed_form_curves(elements, A) -> dict:
    """Closed-form energy on a fine amplitude grid for each contact label (or None)."""
    a_fine = np.geomspace(A.min(), A.max(), 400) if A.size > 1 else A
    curves = {}
    for c in elements:
        cf = _closed_form(c.law, a_fine)
        for k in range(c.n_contacts):
            label = c.name if c.n_contacts == 1 else f"{c.name}[{k + 1}]"
            curves[label] = None if cf is None else (a_fine, cf[k])
    return curves


def _closed_form(law, amplitudes):
    for cls in type(law).__mro__:
        if cls in _CLOSED_FORMS:
            return _CLOSED_FORMS[cls](law, amplitudes)
    return None


register_analysis("free_decay", FreeDecay, run_free_decay, check=_check_free_decay,
                  description="release from initial conditions; damping ratio vs amplitude")
register_analysis("forced_response", ForcedResponse, run_forced_response, check=_check_forced,
                  description="harmonic force to a steady state; loops and energy per cycle")
register_analysis("hysteresis", Hysteresis, run_hysteresis, check=_check_hysteresis,
                  description="contact laws driven by a sine; loop energy vs amplitude")

