"""Run the benchmarks: every ``benchmarks/bench_*.py`` exposing ``run() -> dict``.

Usage::

    python benchmarks/run.py                      # all benchmarks
    python benchmarks/run.py --only contact_kernel [--only ...]
    python benchmarks/run.py --json results.json  # also save every result dict
    python benchmarks/run.py -v                   # also print each result's details
    python benchmarks/run.py --quick              # quick modes (smoke test) where offered

Each ``run()`` returns at least ``name``, ``figure`` (the headline, e.g. "ratio 85x"),
``value``, ``target`` and ``passed``; one line is printed per benchmark::

    PASS  contact_kernel   Jenkins 3e+08 contact-steps/s (ratio 40x ...)  [value 3e+08, ...]

A result's ``table`` (e.g. the scaling table of ``hb_scaling``: contacts 30 -> 3,000,
harmonics 5 -> 21) is printed under its line. A benchmark whose ``run`` takes a ``quick``
argument (e.g. ``solid_wheel``, ~20 minutes in full) runs its smoke-test mode with
``--quick``.

The exit status is 0 when every selected benchmark ran and met its target, 1 otherwise
(a benchmark that raises is reported as ERROR and the others still run).
"""

from __future__ import annotations

import argparse
import importlib.util
import inspect
import json
import sys
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
REQUIRED = ("name", "figure", "value", "target", "passed")


def discover(directory: Path = HERE) -> dict[str, Path]:
    """Benchmark scripts by short name (file stem without the ``bench_`` prefix)."""
    return {p.stem.removeprefix("bench_"): p for p in sorted(directory.glob("bench_*.py"))}


def load(path: Path):
    spec = importlib.util.spec_from_file_location(f"fricdamp_benchmarks.{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _fmt(x) -> str:
    return f"{x:.3g}" if isinstance(x, int | float) and not isinstance(x, bool) else str(x)


def run_one(short: str, path: Path, quick: bool = False) -> dict:
    """Import and run one benchmark; never raises (errors come back as a result)."""
    t0 = time.perf_counter()
    try:
        module = load(path)
        kwargs = {"quick": True} if quick and "quick" in inspect.signature(
            module.run).parameters else {}
        res = dict(module.run(**kwargs))
        missing = [k for k in REQUIRED if k not in res]
        if missing:
            raise KeyError(f"run() result lacks {missing}")
        res["status"] = "PASS" if res["passed"] else "MISS"
    except Exception as exc:  # report it and go on with the others
        res = {"name": short, "figure": f"{type(exc).__name__}: {exc}", "value": None,
               "target": None, "passed": False, "status": "ERROR",
               "traceback": traceback.format_exc()}
    res["seconds"] = time.perf_counter() - t0
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", action="append", metavar="NAME",
                    help="run only this benchmark (file stem, with or without 'bench_'); "
                         "repeatable")
    ap.add_argument("--json", type=Path, metavar="PATH", help="write all results to PATH")
    ap.add_argument("-v", "--verbose", action="store_true", help="print details")
    ap.add_argument("--quick", action="store_true",
                    help="run the quick (smoke-test) mode of benchmarks that have one")
    args = ap.parse_args(argv)

    found = discover()
    if args.only:
        wanted = [n.removeprefix("bench_").removesuffix(".py") for n in args.only]
        unknown = [n for n in wanted if n not in found]
        if unknown:
            print(f"unknown benchmark(s) {unknown}; available: {sorted(found)}",
                  file=sys.stderr)
            return 2
        found = {n: found[n] for n in wanted}
    if not found:
        print(f"no bench_*.py found in {HERE}", file=sys.stderr)
        return 2

    results = []
    ok = True
    for short, path in found.items():
        res = run_one(short, path, quick=args.quick)
        results.append(res)
        ok &= res["status"] == "PASS"
        print(f"{res['status']:<5} {res['name']:<24} {res['figure']}  "
              f"[value {_fmt(res['value'])}, target {_fmt(res['target'])}, "
              f"{res['seconds']:.1f} s]", flush=True)
        if res.get("table"):
            print(res["table"], flush=True)
        if args.verbose:
            for k, v in res.get("details", {}).items():
                print(f"      {k}: {_fmt(v)}")
        if res["status"] == "ERROR":
            print(res["traceback"], file=sys.stderr)
    if args.json:
        args.json.write_text(json.dumps(results, indent=2, default=str))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
