"""Blade damper (paper 000): CPU per forcing period, compiled event loop vs the paths before.

The stick-slip response is integrated for ``periods`` forcing periods from the same state
(reached after 4 periods from rest) by the event-driven solver (DOP853 phases, rtol 1e-8,
200 samples per period) in this run, three times per point:

* **before**: ``BladeDamperSystem(params, compiled_phases=False)`` -- SciPy's DOP853 calling
  the compiled right-hand side, event roots by ``scipy.optimize.brentq`` through Python, the
  generic projection onto the constraints (the code as of 2026-11-27);
* **middle**: ``BladeDamperSystem(params, compiled_loop=False)`` -- whole DOP853 steps
  (SciPy's step-size control and dense output), the event screening, the root refinement
  (Brent) and the projection in compiled code (:mod:`fricdamp.models.blade_damper.
  _compiled`); the switching decision and the bookkeeping per event in Python (the path of
  2026-11-28);
* **after**: ``BladeDamperSystem(params)`` -- the compiled event loop
  (:mod:`fricdamp.models.blade_damper._fastloop`): phases, switching decisions and samples
  in one kernel call, Python only for the switches the kernel leaves to it (an ambiguous
  switch, a singular system, chattering).

Points: **away from resonance** 58 Hz, F_e = 8 N, gamma = 50 deg (the case's time response,
4-6 switches per period) and **at the friction-damped resonance** 51 Hz, F_e = 8 N,
gamma = 65 deg (the 1 g optimum of the design study, ~16 switches per period). The paths
must give the same response (same switching sequence, final state within 1e-6 of the
motion's range; after and middle within 1e-8, the tolerance of
``tests/unit/test_blade_damper_fastloop.py``) before a time is reported. Times are CPU
(``time.process_time``), best of ``repeats``, one BLAS thread, compilation excluded (a
warm-up run first). Target:
**<= 5 ms CPU per forcing period** (issue 14).

``--release`` also times the released damper (``release=True``: lift-off and plastic impacts)
beyond lift-off (gamma = 80 deg, 52 Hz, F_e = 8 N: it rattles, ~40 lift-offs and impacts per
period), 20 periods from the state after 40: the generic path (``compiled=False``), the
compiled DOP853 phases with every lift-off and impact through the Python event loop
(``compiled_loop=False``) and the compiled event loop (default), same events required.

``--design`` also times one design of the design study (stepped sine on 5 frequencies + the
fine sweep at the resonance, steady states by shooting; 1 g, 65 deg), both paths (about
4 minutes). ``--grid`` also runs the paper-size design grid
(5 masses x 6 angles x 3 parabolas and the lift-off bisections, 000 Fig. 12) as a user
would, ``design_study(..., workers=2)``, and reports its wall time (target <= 10 minutes)
and CPU; ``--grid-subset N`` runs only the N lightest masses and extrapolates, labelled as
such.
"""

from __future__ import annotations

import sys
import time

import numpy as np

TARGET_MS = 5.0
GRID_TARGET_S = 600.0
POINTS = {"away": (58.0, 50.0), "resonance": (51.0, 65.0)}
# the paper-size grid: 000 Fig. 12 (masses, angles) and three contours (flat to steep)
GRID_MASSES = (0.25e-3, 0.5e-3, 1e-3, 2e-3, 4e-3)
GRID_GAMMAS = (40.0, 50.0, 60.0, 65.0, 70.0, 80.0)
GRID_PARABOLAS = ((-40.0, 2e-3), (-80.0, 2e-3), (-160.0, 2e-3))


def _timed(fn, repeats):
    best, out = np.inf, None
    for _ in range(repeats):
        c0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - c0)
    return best, out


def run_grid(masses: int | None = None, workers: int = 2) -> dict:
    """Paper-size design grid by ``design_study(..., workers=2)`` (what a user runs on a
    2-core laptop); ``masses`` < 5: only the lightest ``masses`` damper masses (all angles
    and parabolas), wall time extrapolated in proportion to the designs (an overestimate:
    the light dampers cost the most). CPU is this process's and its workers'."""
    import os
    import resource

    from fricdamp.models.blade_damper.model import BladeDamperParameters
    from fricdamp.models.blade_damper.studies import design_study

    ms = GRID_MASSES if masses is None else GRID_MASSES[:int(masses)]
    load0 = os.getloadavg()[0]
    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    c0, w0 = time.process_time(), time.perf_counter()
    d = design_study(BladeDamperParameters(excitation_amplitude=8.0), damper_masses_kg=ms,
                     gammas_deg=GRID_GAMMAS, parabolas=GRID_PARABOLAS,
                     centrifugal_acceleration=1e5, workers=workers)
    wall = time.perf_counter() - w0
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (time.process_time() - c0 + ru1.ru_utime - ru0.ru_utime
           + ru1.ru_stime - ru0.ru_stime)
    frac = len(ms) / len(GRID_MASSES)
    n_ref = sum(len(b["refined"]) for b in d.boundary)
    return {"grid_masses_run": len(ms), "grid_designs": int(d.blade_amplitude_m.size),
            "grid_boundary_designs": n_ref, "grid_wall_s": wall, "grid_cpu_s": cpu,
            "grid_wall_s_full_estimate": wall / frac, "grid_extrapolated": frac < 1,
            "grid_designs_valid": int(np.sum(d.valid)),
            "grid_designs_converged": int(np.sum(d.converged)),
            "grid_nonperiodic_steady_states": int(d.n_nonperiodic),
            "grid_load_start": load0, "grid_load_end": os.getloadavg()[0],
            "grid_optimum": d.optimum,
            "grid_optimum_on_validity_boundary": bool(d.optimum_on_validity_boundary)}


def run_release(repeats: int = 1, periods: float = 20.0) -> dict:
    """CPU per period of the released damper rattling beyond lift-off: generic path, compiled
    phases with the Python loop, compiled loop (same events and lift-off times required)."""
    from threadpoolctl import threadpool_limits

    from fricdamp.models.blade_damper.model import BladeDamperParameters, BladeDamperSystem
    from fricdamp.solvers.event import simulate_events

    f = 52.0
    T = 1.0 / f
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=f).with_(
        gamma_deg=80.0)
    kw = dict(rtol=1e-9, atol=1e-12, max_events=200_000, progress=False)
    out: dict = {}
    res = {}
    with threadpool_limits(1):
        fast = BladeDamperSystem(p, release=True)
        y0 = np.concatenate([fast.static_equilibrium().q, np.zeros(7)])
        r = simulate_events(fast, (0.0, 40 * T), y0, **kw)
        y1 = np.concatenate([r.q[-1], r.qd[-1]])
        for key, s in (("before", BladeDamperSystem(p, release=True, compiled=False)),
                       ("middle", BladeDamperSystem(p, release=True, compiled_loop=False)),
                       ("after", fast)):
            simulate_events(s, (40 * T, 41 * T), y1, **kw)  # warm-up
            cpu, res[key] = _timed(lambda s=s: simulate_events(
                s, (40 * T, (40 + periods) * T), y1, **kw), repeats)
            out[f"release_ms_per_period_{key}"] = 1e3 * cpu / periods
    a = res["after"]
    out["release_events_per_period"] = a.n_events / periods
    out["release_same_events"] = all(
        a.n_events == b.n_events and a.lift_off_times().size == b.lift_off_times().size
        and np.max(np.abs(a.lift_off_times() - b.lift_off_times()), initial=0.0) <= 1e-8
        for b in (res["before"], res["middle"]))
    return out


def run(repeats: int = 3, quick: bool = False, periods: float = 10.0, design: bool = False,
        grid: bool = False, grid_masses: int | None = None, release: bool = False) -> dict:
    from threadpoolctl import threadpool_limits

    from fricdamp.models.blade_damper.model import BladeDamperParameters, BladeDamperSystem
    from fricdamp.models.blade_damper.studies import resonance_amplitude, time_response

    if quick:
        periods, repeats, design = 4.0, 1, False
    details: dict = {"periods": periods, "blas_threads": 1}
    figs = []
    ok = True
    with threadpool_limits(1):
        for name, (f, g) in POINTS.items():
            p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=f
                                      ).with_(gamma_deg=g)
            systems = {"before": BladeDamperSystem(p, compiled_phases=False),
                       "middle": BladeDamperSystem(p, compiled_loop=False),
                       "after": BladeDamperSystem(p)}
            y0 = np.concatenate([systems["after"].static_equilibrium().q, np.zeros(7)])
            r = time_response(systems["before"], 4.0, y0=y0).result
            y0 = np.concatenate([r.q[-1], r.qd[-1]])
            t0 = 4.0 / f
            res = {}
            for key, s in systems.items():
                time_response(s, 1.0, y0=y0, t_start=t0)  # warm-up (compilation, caches)
                cpu, tr = _timed(lambda s=s, y0=y0, t0=t0: time_response(
                    s, periods, y0=y0, t_start=t0), repeats)
                res[key] = tr.result
                details[f"{name}_ms_per_period_{key}"] = 1e3 * cpu / periods
            a, b, mid = res["after"], res["before"], res["middle"]
            same = all([(e.contact, e.to_mode) for e in a.events]
                       == [(e.contact, e.to_mode) for e in x.events] for x in (b, mid))
            agree = float(np.max(np.abs(a.q[-1] - b.q[-1]) / (np.ptp(b.q, axis=0) + 1e-300)))
            agree_mid = float(np.max(np.abs(a.q[-1] - mid.q[-1])
                                     / (np.ptp(mid.q, axis=0) + 1e-300)))
            same = same and agree < 1e-6 and agree_mid < 1e-8
            details[f"{name}_final_state_agreement_middle"] = agree_mid
            ok = ok and same
            after = details[f"{name}_ms_per_period_after"]
            before = details[f"{name}_ms_per_period_before"]
            middle = details[f"{name}_ms_per_period_middle"]
            details[f"{name}_events_per_period"] = a.n_events / periods
            details[f"{name}_final_state_agreement"] = agree
            details[f"{name}_ratio"] = before / after
            figs.append(f"{name} ({f:g} Hz, {g:g} deg, {a.n_events / periods:.1f} switches/"
                        f"period): {after:.1f} ms (before {before:.1f} ms, "
                        f"compiled phases with the Python loop {middle:.1f} ms, "
                        f"{before / after:.1f}x)" + ("" if same else
                                                      f" RESULTS DIFFER ({agree:.1e})"))
        if design:
            from unittest import mock

            import fricdamp.models.blade_damper.studies as bda

            f = np.linspace(46.0, 58.0, 5)
            p = BladeDamperParameters(excitation_amplitude=8.0, damper_mass=1e-3,
                                      centrifugal_force=100.0).with_(gamma_deg=65.0)
            orig = bda._system

            def before(params):  # every system the sweep builds takes the path before
                s = orig(params)
                return BladeDamperSystem(s.params, compiled_phases=False)

            for key, patch in (("before", before), ("after", orig)):
                with mock.patch.object(bda, "_system", patch):
                    cpu, r = _timed(lambda: resonance_amplitude(p, f, resolution_hz=0.5), 1)
                details[f"design_cpu_s_{key}"] = cpu
                details[f"design_peak_amplitude_m_{key}"] = float(r["peak_amplitude_m"])
            figs.append(f"one design (1 g, 65 deg): {details['design_cpu_s_after']:.1f} s "
                        f"(before {details['design_cpu_s_before']:.1f} s)")
    if release:
        details.update(run_release(repeats))
        figs.append(f"released damper beyond lift-off "
                    f"({details['release_events_per_period']:.0f} events/period): "
                    f"{details['release_ms_per_period_after']:.0f} ms/period (generic path "
                    f"{details['release_ms_per_period_before']:.0f} ms, compiled phases with "
                    f"the Python loop {details['release_ms_per_period_middle']:.0f} ms)")
    if grid:
        details.update(run_grid(grid_masses))
        lab = " (estimated from a subset)" if details["grid_extrapolated"] else ""
        figs.append(f"paper grid on 2 processes: {details['grid_wall_s_full_estimate']:.0f} s "
                    f"wall{lab}, {details['grid_cpu_s']:.0f} s CPU (target "
                    f"{GRID_TARGET_S:.0f} s wall)")
    worst = max(details[f"{n}_ms_per_period_after"] for n in POINTS)
    passed = ok and worst <= TARGET_MS
    if release:
        passed = passed and details["release_same_events"]
    if grid and not details["grid_extrapolated"]:
        passed = passed and details["grid_wall_s"] <= GRID_TARGET_S
    return {"name": "blade_damper", "figure": "; ".join(figs), "value": worst,
            "target": TARGET_MS, "unit": "ms/period", "passed": bool(passed),
            "details": details}


if __name__ == "__main__":
    args = sys.argv[1:]
    masses = None
    if "--grid-subset" in args:
        masses = int(args[args.index("--grid-subset") + 1])
    out = run(grid="--grid" in args or masses is not None, grid_masses=masses,
              quick="--quick" in args, design="--design" in args,
              release="--release" in args)
    for k, v in out["details"].items():
        print(f"{k:40s} {v}")
    print(("PASS " if out["passed"] else "MISS ") + out["figure"])
