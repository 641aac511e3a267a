"""Sweep machinery on a local Dask cluster: parallel efficiency and overhead per point.

100 grid points of a CPU-bound task of about 0.5 s (repeated 40x40 dense solves, the kind of
small linear algebra a friction solver does; one BLAS thread) run through
:func:`fricdamp.studies.sweep` on a local cluster of 2 single-threaded worker processes, with
the point store on (each finished point written atomically, as a real study does).

* parallel efficiency ``E = T_serial / (n_workers * T_parallel)``, with ``T_serial`` 100 times
  the task's mean wall time run serially in this process (one BLAS thread, as in the workers);
* the *ceiling* ``E_plain``: the same efficiency of two plain processes (``subprocess``, no
  Dask, started once and kept warm) running the same task: what any multi-process scheme can
  reach here and now. It is below 1 when the two cores are not independent (shared caches,
  CPU frequency with both cores busy, a virtual machine's host) or other processes use them.
  On Linux with ``kernel.sched_autogroup_enabled = 1`` the scheduler shares the cores equally
  between *sessions*: one busy process started from another shell takes a whole core from
  this session, so two processes here get one core between them (``E_plain`` about 50 %)
  while the serial reference still runs at full speed;
* the judged figure ``E / E_plain``: what the Dask machinery keeps of that ceiling (the ratio
  of the two throughputs: it does not depend on the serial reference);
* scheduling overhead per point ``(n_workers * T_parallel - sum of task times) / n_points``:
  the worker time not spent in the task (submission, scheduling, transfer of results, idle
  tail), with each task's time measured inside the worker, and the same on 200 points that do
  no work;
* the share of the two cores the Dask workers and the plain processes really got (their CPU
  time over the wall time of the run): below 1, other processes were using the cores.

The 100 points run as 5 sweeps of 20 points (one store, one cluster), interleaved with blocks
of 10 points on the plain processes and single serial points: plain, serial, sweep, plain,
serial, sweep, ..., plain, serial. A change of the machine's load during the benchmark then
hits the references and the Dask sweeps alike (the idle cluster stays up during the plain
blocks; with the settings of :func:`~fricdamp.studies.open_client` it uses about 2 % of the two
cores, which lowers the ceiling by as much). The cluster's start-up (worker processes,
imports) and a warm-up point per worker are excluded from ``T_parallel``: they are paid once
per study, not per point.
Targets: ``E / E_plain >= 85 %`` and overhead <= 50 ms per point (on an idle machine where two
processes scale perfectly, ``E_plain = 1`` and the target is ``E >= 85 %``).
"""

from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

N_POINTS = 100
N_WORKERS = 2
N_BLOCKS = 5  # the Dask sweep runs in blocks of N_POINTS / N_BLOCKS points ...
N_PLAIN = 10  # ... between blocks of N_PLAIN points on the plain processes
N_NOOP = 200
TASK_SECONDS = 0.5
TARGET_RELATIVE = 0.85
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
    """Number of solves that takes about ``seconds`` here (one BLAS thread, best of 3)."""
    busy_task(0, 200)  # warm up
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        busy_task(0, 2000)
        best = min(best, time.perf_counter() - t0)
    return max(1, int(seconds * 2000 / best))


def _plain_worker(n_solves: int) -> None:
    """A plain benchmark process: warm up, say ready, then run each list of points it is sent.

    Reads lines of comma-separated point indices on stdin (an empty line ends it) and answers
    each with one JSON line: the task times, the CPU time and the wall time of the list.
    """
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1)
    busy_task(0, 200)
    print("ready", flush=True)
    for line in sys.stdin:
        if not line.strip():
            break
        cpu0, t0 = time.process_time(), time.perf_counter()
        times = []
        for i in map(int, line.split(",")):
            t = time.perf_counter()
            busy_task(i, n_solves)
            times.append(time.perf_counter() - t)
        print(json.dumps({"times": times, "cpu": time.process_time() - cpu0,
                          "wall": time.perf_counter() - t0}), flush=True)


class _PlainProcesses:
    """``n`` plain Python processes (no Dask) that run the task, started once, kept warm."""

    def __init__(self, n: int, n_solves: int):
        env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
                   MKL_NUM_THREADS="1")
        self.procs = [subprocess.Popen([sys.executable, os.path.abspath(__file__),
                                        "--plain-worker", str(n_solves)],
                                       stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                       env=env) for _ in range(n)]
        for p in self.procs:
            if p.stdout.readline().strip() != "ready":
                self.close()
                raise RuntimeError("a plain benchmark process did not start")

    def run(self, points: list[int]) -> dict:
        """Run ``points`` shared out over the processes, all starting together."""
        n = len(self.procs)
        t0 = time.perf_counter()
        for k, p in enumerate(self.procs):
            p.stdin.write(",".join(map(str, points[k::n])) + "\n")
            p.stdin.flush()
        out = [json.loads(p.stdout.readline()) for p in self.procs]
        return {"wall": time.perf_counter() - t0,
                "times": [t for o in out for t in o["times"]],
                "cpu": sum(o["cpu"] for o in out)}

    def close(self) -> None:
        for p in self.procs:
            p.kill()
            p.wait()


def _worker_cpu():
    import psutil  # a dependency of distributed

    t = psutil.Process().cpu_times()
    return t.user + t.system


def run(verbose: bool = True) -> dict:
    """Measure E, the plain-process ceiling and the overhead per point; return the result."""
    import functools

    from threadpoolctl import threadpool_limits

    from fricdamp.studies import open_client, sweep

    load0 = os.getloadavg()[0]
    with threadpool_limits(limits=1):
        n_solves = _calibrate(TASK_SECONDS)
    fn = functools.partial(busy_task, n_solves=n_solves)
    per_block = N_POINTS // N_BLOCKS
    blocks = [list(range(b * per_block, (b + 1) * per_block)) for b in range(N_BLOCKS)]
    serial_times, plain, par_blocks = [], [], []
    t_parallel = busy = cpu_dask = 0.0

    def serial_point(i):  # the serial reference, one point between blocks
        with threadpool_limits(limits=1):
            ds = sweep(fn, {"i": [i]}, serial=True)
        serial_times.append(float(ds["wall_time_s"].values[0]))
        return ds

    plain_procs = _PlainProcesses(N_WORKERS, n_solves)
    try:
        t0 = time.perf_counter()
        with open_client(None, n_workers=N_WORKERS) as client:
            t_start = time.perf_counter() - t0
            # warm-up: one real point per worker (imports, first calls)
            sweep(fn, {"i": [N_POINTS, N_POINTS + 1]}, client=client)
            with tempfile.TemporaryDirectory() as store:
                # plain, serial, Dask, plain, serial, Dask, ..., plain, serial: a change of the
                # machine's load hits the references and the Dask sweep alike
                for b in range(N_BLOCKS + 1):
                    plain.append(plain_procs.run(list(range(b * N_PLAIN, (b + 1) * N_PLAIN))))
                    ser = serial_point(b)
                    if b == 0:
                        reference = ser
                    if b == N_BLOCKS:
                        break
                    cpu0 = client.run(_worker_cpu)
                    t0 = time.perf_counter()
                    par = sweep(fn, {"i": blocks[b]}, client=client, store=store)
                    t_parallel += time.perf_counter() - t0
                    cpu1 = client.run(_worker_cpu)
                    cpu_dask += sum(cpu1[w] - cpu0[w] for w in cpu1)
                    busy += float(np.sum(par["wall_time_s"].values))
                    par_blocks.append(par)
                    if par.attrs["points_failed"]:
                        raise RuntimeError(f"benchmark points failed: {par.attrs['failures']}")
            # the machinery alone: points of no work at all (submission, scheduling, results,
            # atomic store writes), worker time per point
            with tempfile.TemporaryDirectory() as store:
                t0 = time.perf_counter()
                sweep(noop_task, {"i": list(range(N_NOOP))}, client=client, store=store)
                t_noop = time.perf_counter() - t0
    finally:
        plain_procs.close()
    load1 = os.getloadavg()[0]
    # the same numbers whichever process computed them
    np.testing.assert_allclose(par_blocks[0]["norm"].values[:1], reference["norm"].values,
                               rtol=1e-12)

    task_mean = statistics.mean(serial_times)
    t_serial = N_POINTS * task_mean
    efficiency = t_serial / (N_WORKERS * t_parallel)
    n_plain = N_PLAIN * len(plain)
    t_plain = sum(p["wall"] for p in plain)
    ceiling = n_plain * task_mean / (N_WORKERS * t_plain)
    relative = efficiency / ceiling  # = (N_POINTS / t_parallel) / (n_plain / t_plain)
    overhead = (N_WORKERS * t_parallel - busy) / N_POINTS
    overhead_noop = N_WORKERS * t_noop / N_NOOP
    # the share of the workers' time spent in tasks (the machinery alone)
    busy_share = busy / (N_WORKERS * t_parallel)
    # the share of the cores the processes really got (below 1: other load on the machine)
    cpu_share_dask = cpu_dask / (N_WORKERS * t_parallel)
    cpu_share_plain = sum(p["cpu"] for p in plain) / (N_WORKERS * t_plain)
    task_plain = statistics.mean(t for p in plain for t in p["times"])
    passed = bool(relative >= TARGET_RELATIVE and overhead <= TARGET_OVERHEAD_S)
    figure = (f"efficiency {100 * efficiency:.1f} % on {N_WORKERS} workers = "
              f"{100 * relative:.1f} % of the plain-process ceiling {100 * ceiling:.1f} %, "
              f"overhead {1e3 * overhead:.1f} ms/point ({N_POINTS} points of {task_mean:.2f} s)")
    details = {
        "n_points": N_POINTS, "n_workers": N_WORKERS, "cores": os.cpu_count(),
        "task_s_serial_mean": task_mean,
        "task_s_serial_spread (max/min)": max(serial_times) / min(serial_times),
        "task_s_plain_processes_mean": task_plain,
        "task_s_dask_workers_mean": busy / N_POINTS,
        "t_serial_s (100 x serial task time)": t_serial,
        "t_parallel_s": t_parallel,
        "ideal_parallel_s": t_serial / N_WORKERS,
        "efficiency": efficiency,
        "plain_process_ceiling": ceiling,
        "plain_process_blocks_points_per_s": [N_PLAIN / p["wall"] for p in plain],
        "efficiency_relative_to_ceiling": relative,
        "workers_busy_share": busy_share,
        "cpu_share_dask_workers": cpu_share_dask,
        "cpu_share_plain_processes": cpu_share_plain,
        "overhead_ms_per_point": 1e3 * overhead,
        "overhead_ms_per_point_noop_tasks": 1e3 * overhead_noop,
        "cluster_startup_s (excluded)": t_start,
        "load_average_1min_before_after": [load0, load1],
    }
    if verbose:
        print(f"sweep benchmark: {N_POINTS} points x {task_mean:.3f} s, {N_WORKERS} local "
              f"workers (cluster start-up {t_start:.1f} s, excluded)")
        print(f"  serial {t_serial:.1f} s ({N_POINTS} x mean of {len(serial_times)}), parallel "
              f"{t_parallel:.1f} s ({N_BLOCKS} sweeps of {per_block} points), ideal "
              f"{t_serial / N_WORKERS:.1f} s")
        print(f"  parallel efficiency {100 * efficiency:.1f} % (raw); two plain processes: "
              f"{100 * ceiling:.1f} % (the ceiling here, {n_plain} points in {len(plain)} "
              "blocks between the sweeps)")
        print(f"  Dask efficiency relative to the ceiling {100 * relative:.1f} % (target >= "
              f"{100 * TARGET_RELATIVE:.0f} %)")
        print(f"  scheduling overhead {1e3 * overhead:.1f} ms per point (target <= "
              f"{1e3 * TARGET_OVERHEAD_S:.0f} ms); workers busy {100 * busy_share:.1f} % of "
              "their time")
        print(f"  {N_NOOP} points of no work: {t_noop:.2f} s, i.e. "
              f"{1e3 * overhead_noop:.1f} ms of worker time per point")
        print(f"  task time: serial {task_mean:.3f} s, plain processes {task_plain:.3f} s, "
              f"Dask workers {busy / N_POINTS:.3f} s")
        print(f"  share of the {N_WORKERS} cores really obtained: Dask workers "
              f"{100 * cpu_share_dask:.0f} %, plain processes {100 * cpu_share_plain:.0f} %; "
              f"1-min load average {load0:.1f} -> {load1:.1f} on {os.cpu_count()} cores")
        if min(cpu_share_dask, cpu_share_plain) < 0.85:
            print("  other processes were using the cores (with Linux's autogroup scheduling "
                  "one busy process\n  in another session takes a whole core from this one): "
                  "judge the Dask machinery by\n  its efficiency relative to the plain-process "
                  "ceiling, or rerun on an idle machine")
    return {"name": "sweep", "figure": figure, "value": relative,
            "target": TARGET_RELATIVE, "passed": passed, "unit": "efficiency / ceiling",
            "details": details}


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--plain-worker":
        _plain_worker(int(sys.argv[2]))
    else:
        res = run()
        print("PASS" if res["passed"] else "MISS", res["figure"])
