"""``fricdamp sweep CASE.toml --grid ...``: run a case over a grid of parameters.

::

    fricdamp sweep CASE.toml --grid "damper_mass_kg=0.5e-3:3e-3:11" --grid "gamma_deg=40:70:7"
                   [--scheduler tcp://HOST:PORT | --serial] [--workers N] --out DIR

Each grid point runs every ``[analysis.*]`` of the case with the parameters written into the
case; the grid may also come from the case file's ``[sweep.grid]`` table. Writes ``points/``
(resumable), ``sweep.nc``, ``summary.json``, figures, ``report.html`` and ``report.md``. What
the studies share (the case as a study function, where the points run, exit codes) is in
:mod:`fricdamp.cli._studies`.
"""

from __future__ import annotations

import itertools
import sys
import time
from pathlib import Path

from fricdamp._version import __version__
from fricdamp.cli._common import _progress_wanted
from fricdamp.cli._studies import (
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_UNRELIABLE,
    CasePoint,
    _add_where,
    _check_points,
    _client_kwargs,
    _err,
    _out,
    _out_dir,
    _run_guarded,
    _where,
    load_study_case,
)
from fricdamp.errors import CaseError

__all__ = ["add_subparsers", "handle_sweep", "main"]


def add_subparsers(subparsers) -> None:
    """Add the ``sweep`` command to an argparse subparsers object (``func`` and ``handler`` =
    handle_sweep, which takes the parsed arguments and returns the exit code)."""
    s = subparsers.add_parser(
        "sweep", help="run a case over a grid of parameters (locally or on a Dask cluster)",
        description="Run the analyses of a case at every point of a parameter grid and write "
                    "sweep.nc (one dimension per parameter), summary.json, figures and "
                    "report.md. Finished points are stored at once: rerun the same command "
                    "after an interruption to compute only the missing ones.")
    s.add_argument("case", help="TOML case file")
    s.add_argument("--grid", action="append", metavar="NAME=START:STOP:NUM|NAME=V1,V2,...",
                   help="one grid axis (repeat for more); replaces the case file's "
                        "[sweep.grid]. NAME is a key of the case (gamma_deg) or a dotted "
                        "path (contacts.1.mu)")
    _add_where(s)
    s.set_defaults(func=handle_sweep, handler=handle_sweep)


def _write_html_report(out: Path, summary: dict, point: CasePoint, dims) -> None:
    """report.html in the style of ``fricdamp run`` (fricdamp.report), next to report.md."""
    import datetime as dt

    import numpy as np

    from fricdamp.report import write_report

    def at(p):
        return ", ".join(f"{k}={v:g}" for k, v in p.items())

    results = {}
    for name, r in summary["results"].items():
        if r.get("min") is None:
            results[name] = {"min": None, "max": None}
        else:
            results[name] = {"min": r["min"], "at min": at(r["at_min"]), "max": r["max"],
                             "at max": at(r["at_max"])}
    failures = {at(f["params"]): {"error": f["error"]} for f in summary["points_failed"][:50]}
    ebe = [r["max"] for n, r in summary["results"].items()
           if n.endswith("energy_balance_error") and r.get("max") is not None]
    section = {"points_total": summary["points_total"],
               "points_computed": summary["points_computed"],
               "points_reused": summary["points_reused"],
               "points_failed": len(summary["points_failed"]),
               "grid": {k: list(v) for k, v in summary["grid"].items()},
               "results": results}
    if failures:
        section["failed_points"] = failures
    # the study's verdict: the worst of its points' (failed points, then '<analysis>__verdict')
    worst = {name.removesuffix("__verdict"): r.get("max") for name, r in
             summary["results"].items() if name.endswith("__verdict")}
    word = {0: "ok", 1: "unreliable", 2: "failed"}
    analyses = {name: {"verdict": word.get(int(m or 0), "ok"),
                       "reasons": ([f"unreliable or failed at some points (max "
                                    f"{name}__verdict = {int(m)})"] if m else []),
                       "estimates": {}} for name, m in worst.items()}
    overall = "failed" if summary["points_failed"] else word.get(
        int(max((m or 0 for m in worst.values()), default=0)), "ok")
    html_summary = {
        "verdict": {"overall": overall, "analyses": analyses},
        "fricdamp_version": __version__,
        "case": {"name": f"{point.name} (sweep over {' x '.join(dims)})",
                 "file": point.source, "analysis": {}},
        "created": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
        "runtime_s": summary.get("elapsed_s"),
        "energy_balance_error": float(np.max(ebe)) if ebe else None,
        "sweep": section,
        "files": {"summary": "summary.json", "results": "sweep.nc"},
    }
    figures = {"sweep": [(f, f.removeprefix("sweep_").removesuffix(".png") + " over "
                          + " x ".join(dims)) for f in summary["files"]["figures"]]}
    write_report(out / "report.html", summary=html_summary, case_text=point.text,
                 figures=figures)


def handle_sweep(args) -> int:
    """``fricdamp sweep``: run the case over the grid; return the exit code."""
    from fricdamp.iofiles import prepare_output_folder, write_json
    from fricdamp.studies.grid import Grid, resolve_parameter
    from fricdamp.studies.sweep import StudyInterrupted, save_sweep, sweep

    point, tables = load_study_case(args.case)
    if args.grid:
        grid = Grid.parse(args.grid)
    elif tables["sweep"].get("grid"):
        grid = Grid.from_mapping(tables["sweep"]["grid"])
    else:
        raise CaseError(f"no grid: give --grid NAME=START:STOP:NUM (repeatable) or a "
                        f"[sweep.grid] table in {args.case}")
    kwargs = _client_kwargs(args)
    for name in grid.names:  # unknown names first, listing the case's keys
        resolve_parameter(point.data, name)
    # a grid running out of range is an input error: check every point of a small grid, the
    # corners of a large one (the schema's bounds are per key, so corners find them)
    if grid.size <= 2000 or len(grid.names) > 10:
        _check_points(point, grid.points())
    else:
        _check_points(point, (dict(zip(grid.names, c, strict=True)) for c in
                              itertools.product(*((v.min(), v.max()) for _, v in grid.axes))))
    out = _out_dir(args, point, "sweep")
    prepare_output_folder(out)
    _out(f"fricdamp {__version__}: sweep of {args.case} over {grid.size} points "
         f"({' x '.join(f'{n} {len(v)}' for n, v in grid.axes)}) {_where(args)}")
    _out(f"points stored in {out / 'points'} (rerun the same command to resume)")

    def run() -> int:
        t0 = time.perf_counter()
        try:
            ds = sweep(point, grid, store=out / "points", progress=_progress_wanted(
                args.no_progress), retry_failed=not args.no_retry_failed, **kwargs)
        except StudyInterrupted as exc:
            write_json(out / "summary.json", {**exc.counts, "interrupted": True,
                                              "case": str(args.case)})
            _err(f"{exc} (stored in {out / 'points'})")
            return EXIT_INTERRUPTED
        ds.attrs["case"] = str(args.case)
        ds.attrs["case_toml"] = point.text
        summary = save_sweep(ds, out, figures=not args.no_figures,
                             extra={"case": str(args.case), "interrupted": False},
                             title=f"Sweep of {point.name}")
        _write_html_report(out, summary, point, grid.names)
        n_failed = len(summary["points_failed"])
        _out(f"{summary['points_total']} points: {summary['points_computed']} computed, "
             f"{summary['points_reused']} reused, {n_failed} failed, in "
             f"{time.perf_counter() - t0:.1f} s")
        for f in summary["points_failed"][:5]:
            p = ", ".join(f"{k}={v:g}" for k, v in f["params"].items())
            _out(f"  failed at {p}: {f['error']}")
        _out(f"wrote sweep.nc, summary.json, report.html, report.md and "
             f"{len(summary['files']['figures'])} figures to {out}")
        _out(f"report: {(out / 'report.html').resolve()}")
        # the verdict is the last line, as for fricdamp run
        if n_failed:
            _err(f"verdict: failed at {n_failed} of {summary['points_total']} points (listed "
                 "under points_failed in summary.json)")
            return EXIT_FAILURE
        worst = max((float(ds[v].max()) for v in ds.data_vars if v.endswith("__verdict")),
                    default=0.0)
        if worst >= 2:
            _err("verdict: failed at some points (the '<analysis>__verdict' result is 2)")
            return EXIT_FAILURE
        if worst >= 1:
            print("fricdamp: warning: verdict: unreliable at some points (the "
                  "'<analysis>__verdict' result is 1; run one of them with fricdamp run to "
                  "see why)", file=sys.stderr)
            return EXIT_UNRELIABLE
        _out("verdict: ok")
        return EXIT_OK

    return _run_guarded(run, args, out)



def main(argv: list[str] | None = None) -> int:
    """Run ``sweep`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli.sweep sweep CASE.toml ...``
    """
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
