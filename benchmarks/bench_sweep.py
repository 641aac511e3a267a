"""Sweep machinery on a local Dask cluster: parallel efficiency and overhead per point.

100 grid points of a CPU-bound task of about 0.5 s (repeated 40x40 dense solves, the kind of
small linear algebra a friction solver does; one BLAS thread) run through
:func:`fricdamp.studies.sweep` on a local cluster of 2 single-threaded worker processes, with
the point store on (each finished point written atomically, as a real study does). The serial
reference is the task's mean wall time when run through ``sweep(serial=True)`` in this process
on 10 of the points, times 100.

* parallel efficiency ``E = T_serial / (n_workers * T_parallel)``;
* scheduling overhead per point ``(n_workers * T_parallel - sum of task times) / n_points``:
  the worker time not spent in the task (submission, scheduling, transfer of results, idle
  tail), with each task's time measured inside the worker;
* the same overhead measured directly on 200 points that do no work;
* the share of the workers' time spent in tasks ``sum of task times / (n_workers *
  T_parallel)``, which isolates the machinery from other load on the cores (on an idle machine
  it equals E).

The cluster's start-up (worker processes, imports) and a warm-up of two points are excluded
from ``T_parallel`` and reported separately: they are paid once per study, not per point.
Targets: E >= 85 % and overhead <= 50 ms per point. Run on an otherwise idle 2-core machine:
other processes competing for the cores lower E.
"""

from __future__ import annotations

import os
import tempfile
import time

import numpy as np

N_POINTS = 100
N_WORKERS = 2
N_SERIAL = 10
N_NOOP = 200
TASK_SECONDS = 0.5
TARGET_EFFICIENCY = 0.85
TARGET_OVERHEAD_S = 0.050


def busy_task(i, n_solves=1000):
    """CPU-bound stand-in of a study point: ``n_solves`` dense 40x40 solves (seeded by i)."""
    rng = np.random.default_rng(int(i))
    a = rng.standard_normal((40, 40)) + 40.0 * np.eye(40)
    b = rng.standard_normal(40)
    x = b
    for _ in range(int(n_solves)):
        x = np.linalg.solve(a, b + 1e-3 * x)
    return {"norm": float(np.linalg.norm(x))}


def noop_task(i):
    """A study point that does nothing: what is left is the machinery's cost."""
    return {"i2": float(i) * 2.0}


def _calibrate(seconds: float) -> int:
    """Number of solves that takes about ``seconds`` here (one BLAS thread)."""
    busy_task(0, 200)  # warm up
    t0 = time.perf_counter()
    busy_task(0, 2000)
    per_solve = (time.perf_counter() - t0) / 2000
    return max(1, int(seconds / per_solve))


def run(verbose: bool = True) -> dict:
    """Measure E and the overhead per point; return the benchmark result."""
    import functools

    from threadpoolctl import threadpool_limits

    from fricdamp.studies import open_client, sweep

    with threadpool_limits(limits=1):
        n_solves = _calibrate(TASK_SECONDS)
        fn = functools.partial(busy_task, n_solves=n_solves)
        # serial reference: the task itself, run here on 10 points, scaled to 100
        ser = sweep(fn, {"i": list(range(N_SERIAL))}, serial=True)
    task_mean = float(np.mean(ser["wall_time_s"].values))
    t_serial = N_POINTS * task_mean

    t0 = time.perf_counter()
    with open_client(None, n_workers=N_WORKERS) as client:
        t_start = time.perf_counter() - t0
        sweep(fn, {"i": [-1, -2]}, client=client)  # warm-up: imports in the workers
        with tempfile.TemporaryDirectory() as store:
            t0 = time.perf_counter()
            par = sweep(fn, {"i": list(range(N_POINTS))}, client=client, store=store)
            t_parallel = time.perf_counter() - t0
        # the machinery alone: points of no work at all (submission, scheduling, results,
        # atomic store writes), worker time per point
        with tempfile.TemporaryDirectory() as store:
            t0 = time.perf_counter()
            sweep(noop_task, {"i": list(range(N_NOOP))}, client=client, store=store)
            t_noop = time.perf_counter() - t0
    overhead_noop = N_WORKERS * t_noop / N_NOOP
    # the same numbers whichever process computed them
    np.testing.assert_allclose(par["norm"].values[:N_SERIAL], ser["norm"].values, rtol=1e-12)
    if par.attrs["points_failed"]:
        raise RuntimeError(f"benchmark points failed: {par.attrs['failures']}")

    busy = float(np.sum(par["wall_time_s"].values))
    efficiency = t_serial / (N_WORKERS * t_parallel)
    overhead = (N_WORKERS * t_parallel - busy) / N_POINTS
    # the share of the workers' time spent in tasks: the machinery alone, whatever else
    # competes for the cores (it equals `efficiency` on an idle machine)
    busy_share = busy / (N_WORKERS * t_parallel)
    passed = bool(efficiency >= TARGET_EFFICIENCY and overhead <= TARGET_OVERHEAD_S)
    figure = (f"parallel efficiency {100 * efficiency:.1f} % on {N_WORKERS} workers, "
              f"overhead {1e3 * overhead:.1f} ms/point, workers busy "
              f"{100 * busy_share:.1f} % ({N_POINTS} points of {task_mean:.2f} s)")
    details = {
        "n_points": N_POINTS, "n_workers": N_WORKERS, "cores": os.cpu_count(),
        "task_s_serial_mean": task_mean,
        "task_s_in_workers_mean": busy / N_POINTS,
        "t_serial_s (100 x serial task time)": t_serial,
        "t_parallel_s": t_parallel,
        "ideal_parallel_s": t_serial / N_WORKERS,
        "efficiency": efficiency,
        "workers_busy_share": busy_share,
        "overhead_ms_per_point": 1e3 * overhead,
        "overhead_ms_per_point_noop_tasks": 1e3 * overhead_noop,
        "cluster_startup_s (excluded)": t_start,
        "load_average_1min": os.getloadavg()[0],
    }
    if verbose:
        print(f"sweep benchmark: {N_POINTS} points x {task_mean:.3f} s, {N_WORKERS} local "
              f"workers (cluster start-up {t_start:.1f} s, excluded)")
        print(f"  serial {t_serial:.1f} s ({N_POINTS} x mean of {N_SERIAL}), parallel "
              f"{t_parallel:.1f} s, ideal {t_serial / N_WORKERS:.1f} s")
        print(f"  parallel efficiency {100 * efficiency:.1f} % (target >= "
              f"{100 * TARGET_EFFICIENCY:.0f} %)")
        print(f"  scheduling overhead {1e3 * overhead:.1f} ms per point (target <= "
              f"{1e3 * TARGET_OVERHEAD_S:.0f} ms); workers busy {100 * busy_share:.1f} % of "
              "their time")
        print(f"  {N_NOOP} points of no work: {t_noop:.2f} s, i.e. "
              f"{1e3 * overhead_noop:.1f} ms of worker time per point")
        print(f"  task time in the workers {busy / N_POINTS:.3f} s vs {task_mean:.3f} s serial; "
              f"1-min load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    return {"name": "sweep", "figure": figure, "value": efficiency,
            "target": TARGET_EFFICIENCY, "passed": passed, "unit": "efficiency",
            "details": details}


if __name__ == "__main__":
    res = run()
    print("PASS" if res["passed"] else "MISS", res["figure"])
