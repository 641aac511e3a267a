"""Scaling of the HB continuation with the number of contacts and of harmonics (issue 13).

The ring of the peers' benchmark (:mod:`bench_hb_ring`: unit oscillators, coupling 0.05,
damping 0.005, Jenkins k_t = 0.5, mu N = 0.02 between neighbours, forcing 0.01 per sector)
with 30, 120, 480, 1,200 and 3,000 contacts at H = 5, N = 64, and with 30 contacts at
H = 5, 9, 13, 21 (N = the power of two >= 16 H). The engine order is n / 10 (3 for the
30-sector ring of the peers), so that the inter-sector phase (36 degrees) and hence the
motion of every sector and contact is the same at every size: the rings differ in size
only (with engine order 3 on 3,000 sectors the neighbours move together and the contacts
stay stuck: a linear problem). Each case runs the same window of the curve:
``max_points`` = 40 continuation points from Omega = 0.97 (inside the resonance, where the
contacts slip) with the default steps. Timed: CPU (``time.process_time``) and wall time of
the whole call, warm (a first run loads the numba caches and builds the orderings), one BLAS
thread; the cold time (first
call in the process, numba caches loaded) is printed for the first case. Ratios are against
the 30-contact case of the same run.

The table printed by ``benchmarks/run.py`` is copied in benchmarks/README.md. The
target is linear growth: the exponent p of ``ms/point ~ contacts^p`` (least squares over the
contact cases) <= 1.1.
"""

from __future__ import annotations

import time

import numpy as np
from bench_hb_ring import build

from fricdamp.solvers.hb import frequency_response

CONTACTS = (30, 120, 480, 1200, 3000)
HARMONICS = (5, 9, 13, 21)
WINDOW = dict(max_points=40)
TARGET_EXPONENT = 1.1


def _samples(h: int) -> int:
    return int(2 ** np.ceil(np.log2(16 * h)))


def _case(n, h, repeats):
    ring = build(n, eo=max(n // 10, 1))
    kw = dict(harmonics=h, samples=64 if h == 5 else _samples(h), **WINDOW)
    c0, w0 = time.process_time(), time.perf_counter()
    fr = frequency_response(ring, 0.97, 1.3, **kw)
    cold = (time.process_time() - c0, time.perf_counter() - w0)
    best = (np.inf, np.inf)
    for _ in range(repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        fr = frequency_response(ring, 0.97, 1.3, **kw)
        best = min(best, (time.process_time() - c0, time.perf_counter() - w0))
    if fr.n_points < 2 or np.max(fr.energy_balance_error) > 1e-3:
        raise RuntimeError(f"ring {n}, H = {h}: {fr.message}")
    p = fr.n_points
    return {"contacts": n, "harmonics": h, "unknowns": n * (2 * h + 1), "points": p,
            "cpu_ms_per_point": 1e3 * best[0] / p, "wall_ms_per_point": 1e3 * best[1] / p,
            "cold_cpu_s": cold[0], "factorizations_per_point": fr.n_factorizations / p,
            "evaluations_per_point": fr.n_evaluations / p}


def table(rows) -> str:
    head = ("| contacts | H | unknowns | points | CPU ms/point | wall ms/point | "
            "factorisations/point | evaluations/point |\n"
            "|---:|---:|---:|---:|---:|---:|---:|---:|")
    lines = [head] + [
        f"| {r['contacts']:,} | {r['harmonics']} | {r['unknowns']:,} | {r['points']} | "
        f"{r['cpu_ms_per_point']:.2f} | {r['wall_ms_per_point']:.2f} | "
        f"{r['factorizations_per_point']:.2f} | {r['evaluations_per_point']:.2f} |"
        for r in rows]
    return "\n".join(lines)


def run(repeats: int = 2, quick: bool = False, verbose: bool = False) -> dict:
    contacts = CONTACTS[:3] if quick else CONTACTS
    rows = [_case(n, 5, repeats) for n in contacts]
    rows += [_case(30, h, repeats) for h in HARMONICS[1:]]
    cr = [r for r in rows if r["harmonics"] == 5]
    x = np.log([r["contacts"] for r in cr])
    y = np.log([r["cpu_ms_per_point"] for r in cr])
    p = float(np.polyfit(x, y, 1)[0])
    base = cr[0]["cpu_ms_per_point"]
    figure = (f"exponent {p:.2f} (ms/point ~ contacts^p, {cr[0]['contacts']} -> "
              f"{cr[-1]['contacts']:,}); " + ", ".join(
                  f"{r['contacts']}: {r['cpu_ms_per_point']:.2f} ms "
                  f"({r['cpu_ms_per_point'] / base:.1f}x)" for r in cr))
    details = {"exponent": p, "cold_first_call_cpu_s": rows[0]["cold_cpu_s"]}
    if verbose:
        print(figure)
        print(table(rows))
    return {"name": "hb_scaling", "figure": figure, "value": p, "target": TARGET_EXPONENT,
            "passed": bool(p <= TARGET_EXPONENT), "unit": "exponent", "details": details,
            "table": table(rows)}


if __name__ == "__main__":
    run(verbose=True)
