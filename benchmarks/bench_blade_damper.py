"""Blade damper (paper 000): CPU per forcing period, compiled kernels vs the generic path.

The stick-slip response at 58 Hz, F_e = 8 N (the case's time response: both contacts switch
about six times per period) is integrated for ``periods`` forcing periods from the same
state by the event-driven solver (DOP853 phases, rtol 1e-8, 200 samples per period) twice in
this run:

* **before**: ``BladeDamperSystem(params, compiled=False)`` -- the lambdified sympy
  kinematics and the generic configuration solve of the event solver (the path every
  ConstrainedSystem has);
* **after**: ``BladeDamperSystem(params)`` -- the compiled kernels generated from the same
  sympy kinematics (:mod:`fricdamp.models._blade_damper_compiled`), outputs from the dense
  state.

Both must give the same response (final state within 1e-6 of the motion's scale, same
number of events) before a time is reported. Times are CPU (``time.process_time``), best of
``repeats``, one BLAS thread, compilation excluded (a warm-up run first). Also reported: one
periodic orbit by shooting at the same point (Newton on the stroboscopic map with the
monodromy matrix, after 20 transient periods), both paths. Target: **<= 5 ms CPU per
forcing period** (DESIGN.md).
"""

from __future__ import annotations

import time

import numpy as np

TARGET_MS = 5.0


def _timed(fn, repeats):
    best, out = np.inf, None
    for _ in range(repeats):
        c0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - c0)
    return best, out


def run(repeats: int = 3, quick: bool = False, periods: float = 20.0) -> dict:
    from threadpoolctl import threadpool_limits

    from fricdamp.models.blade_damper import BladeDamperParameters, BladeDamperSystem
    from fricdamp.models.blade_damper_analyses import time_response
    from fricdamp.solvers.shooting import shoot

    if quick:
        periods, repeats = 5.0, 1
    p = BladeDamperParameters(excitation_amplitude=8.0, excitation_frequency=58.0)
    systems = {"before": BladeDamperSystem(p, compiled=False), "after": BladeDamperSystem(p)}
    rows = {}
    with threadpool_limits(1):
        y0 = np.concatenate([systems["after"].static_equilibrium().q, np.zeros(7)])
        # start on the stick-slip motion (10 periods in): every period switches
        y0 = time_response(systems["after"], 10.0, y0=y0).result
        y0 = np.concatenate([y0.q[-1], y0.qd[-1]])
        t0 = 10.0 / p.excitation_frequency
        for key, s in systems.items():
            time_response(s, 1.0, y0=y0, t_start=t0)  # warm-up (compilation, caches)
            cpu, tr = _timed(lambda s=s: time_response(s, periods, y0=y0, t_start=t0), repeats)
            rows[key] = dict(cpu_s=cpu, ms_per_period=1e3 * cpu / periods, result=tr.result)
        a, b = rows["after"]["result"], rows["before"]["result"]
        scale = np.abs(b.q).max(axis=0) + 1e-12
        agree = float(np.max(np.abs(a.q[-1] - b.q[-1]) / scale))
        same = a.n_events == b.n_events and agree < 1e-6
        shots = {}
        if not quick:
            for key, s in systems.items():
                cpu, orb = _timed(lambda s=s: shoot(s, 1 / p.excitation_frequency, y0,
                                                    t0=t0, transient_periods=20,
                                                    period_multiple=1, rtol=1e-9), 1)
                shots[key] = dict(cpu_s=cpu, amplitude_q4=float(orb.amplitude[3]),
                                  success=orb.success)
    after = rows["after"]["ms_per_period"]
    before = rows["before"]["ms_per_period"]
    ok = same and after <= TARGET_MS
    fig = (f"{after:.1f} ms CPU per forcing period (before {before:.1f} ms, "
           f"{before / after:.1f}x; {a.n_events / periods:.1f} events per period)")
    if shots:
        fig += (f"; shooting one orbit {shots['after']['cpu_s']:.2f} s (before "
                f"{shots['before']['cpu_s']:.2f} s)")
    if not same:
        fig += f"; RESULTS DIFFER ({agree:.1e})"
    details = {"periods": periods, "ms_per_period_before": before, "ms_per_period_after": after,
               "ratio": before / after, "events": a.n_events, "final_state_agreement": agree,
               "blas_threads": 1}
    for key, v in shots.items():
        details[f"shooting_cpu_s_{key}"] = v["cpu_s"]
        details[f"shooting_amplitude_q4_{key}"] = v["amplitude_q4"]
    return {"name": "blade_damper", "figure": fig, "value": after, "target": TARGET_MS,
            "unit": "ms/period", "passed": bool(ok), "details": details}


if __name__ == "__main__":
    out = run()
    for k, v in out["details"].items():
        print(f"{k:32s} {v}")
    print(("PASS " if out["passed"] else "MISS ") + out["figure"])
