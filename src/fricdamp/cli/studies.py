"""Command line of design studies: ``fricdamp sweep`` and ``fricdamp optimize``.

::

    fricdamp sweep CASE.toml --grid "damper_mass_kg=0.5e-3:3e-3:11" --grid "gamma_deg=40:70:7"
                   [--scheduler tcp://HOST:PORT | --serial] [--workers N] --out DIR
    fricdamp optimize CASE.toml --minimize amplitude_m --over "damper_mass_kg=0.5e-3:3e-3,..."
                   [--method differential_evolution] [--scheduler ... | --serial] --out DIR

Each grid point (or optimiser evaluation) runs every ``[analysis.*]`` of the case with the
parameters written into the case (:func:`fricdamp.studies.grid.apply_overrides`: a key such as
``stiffness_N_per_m`` found once in the case, or a dotted path ``contacts.1.mu``); the modified
case is validated by the case schema as a case file is. The scalar entries of each analysis's
summary become the results, named ``<analysis>__<key>``.

The grid may also be given in the case file (the ``--grid`` options replace it as a whole)::

    [sweep.grid]
    damper_mass_kg = "0.5e-3:3e-3:11"      # or a list [..], a number, or {start, stop, num}
    gamma_deg = [40, 45, 50, 55, 60, 65, 70]

    [optimize]
    minimize = "amplitude_m"               # or maximize = "..."
    over = { damper_mass_kg = [0.5e-3, 3e-3], gamma_deg = "40:70" }
    method = "differential_evolution"      # optional: maxiter, popsize, seed, tol

Written into ``--out DIR``: ``points/`` (one file per finished point, reused by a rerun: an
interrupted study resumes where it stopped), ``sweep.nc``, ``summary.json``, one PNG per result
that varies, ``report.html`` and ``report.md`` (sweep); ``optimum.json``, ``history.nc``,
``history.csv`` and figures (optimize). Exit codes: 0 every point succeeded, 1 some points
failed (results still written) or the study could not run (no Dask worker alive, scheduler
lost: the finished points are stored, the lost ones are not), 2 invalid input (a bad
``--scheduler`` address included), 3 every point computed but some are unreliable (their
``<analysis>__verdict`` result is 1; optimize: the analyses at the optimum are), 130
interrupted (rerun the same command); the verdict is the last line, as for ``run``. A lock file
keeps two studies out of one folder; Dask's own messages go to ``dask.log`` there.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import itertools
import json
import os
import signal
import sys
import time
from collections.abc import Mapping
from pathlib import Path

from fricdamp._version import __version__
from fricdamp.cli.app import _progress_wanted
from fricdamp.errors import CaseError

__all__ = ["CasePoint", "add_subparsers", "handle_optimize", "handle_sweep", "load_study_case",
           "main"]

EXIT_OK, EXIT_FAILURE, EXIT_INVALID, EXIT_UNRELIABLE, EXIT_INTERRUPTED = 0, 1, 2, 3, 130

#: Top-level tables of a case file that belong to the study, not to the case schema.
STUDY_TABLES = ("sweep", "optimize")
_SWEEP_KEYS = {"grid"}
_OPTIMIZE_KEYS = {"minimize", "maximize", "over", "method", "maxiter", "popsize", "seed", "tol"}


# ------------------------------------------------------------------------ case points
def _flatten(prefix: str, summary: Mapping, out: dict) -> None:
    for key, value in summary.items():
        name = f"{prefix}__{key}"
        if isinstance(value, Mapping):
            _flatten(name, value, out)
        elif isinstance(value, bool):
            out[name] = float(value)
        elif isinstance(value, (int, float)) or (hasattr(value, "ndim") and value.ndim == 0
                                                 and hasattr(value, "dtype")
                                                 and value.dtype.kind in "biuf"):
            out[name] = float(value)


def _file_digests(node, base: Path, digest) -> None:
    """Feed the bytes of every file the case refers to (matrix files...) into ``digest``."""
    if isinstance(node, Mapping):
        for v in node.values():
            _file_digests(v, base, digest)
    elif isinstance(node, list):
        for v in node:
            _file_digests(v, base, digest)
    elif isinstance(node, str) and 0 < len(node) < 400:
        with contextlib.suppress(OSError, ValueError):
            path = base / node
            if path.is_file():
                digest.update(node.encode())
                digest.update(path.read_bytes())


class CasePoint:
    """The study function of a case: ``point(**params)`` runs the case's analyses there.

    Picklable (a module-level class holding plain data), so Dask workers can run it.

    Parameters
    ----------
    data : mapping
        The case as read from TOML, without its ``[sweep]`` / ``[optimize]`` tables.
    text : str
        The TOML text.
    source : path, optional
        The case file (relative paths in the case are resolved against its folder).
    name : str
        Default case name.

    Attributes
    ----------
    fingerprint : str
        Hash of the case content, of the files it refers to and of the fricdamp version: a
        changed case never reuses stored points.
    """

    def __init__(self, data: Mapping, *, text: str = "", source: str | Path | None = None,
                 name: str = "case"):
        self.data = {k: v for k, v in dict(data).items() if k not in STUDY_TABLES}
        self.text = text
        self.source = str(Path(source).resolve()) if source is not None else None
        self.name = name
        digest = hashlib.sha256()
        digest.update(json.dumps(self.data, sort_keys=True, default=str).encode())
        digest.update(__version__.encode())
        base = Path(self.source).parent if self.source else Path.cwd()
        _file_digests(self.data, base, digest)
        self.fingerprint = f"case:{name}:{digest.hexdigest()[:32]}"

    def case(self, params: Mapping):
        """The validated :class:`fricdamp.case.Case` at ``params`` (raises CaseError)."""
        from fricdamp.case import parse_case
        from fricdamp.runner import REGISTRY
        from fricdamp.studies.grid import apply_overrides

        data = apply_overrides(self.data, params)
        return parse_case(data, REGISTRY, text=self.text, source=self.source,
                          default_name=self.name)

    def check(self, params: Mapping) -> None:
        """Validate the case and its model at ``params``; CaseError names the point."""
        from fricdamp.runner import build_system

        try:
            build_system(self.case(params))
        except CaseError as exc:
            if not params:
                raise
            point = ", ".join(f"{k}={v:g}" for k, v in params.items())
            raise CaseError(f"at {point}: {exc}") from None

    def __call__(self, **params) -> dict[str, float]:
        from fricdamp.runner import compute_case

        results: dict[str, float] = {}
        for name, out in compute_case(self.case(params)).outputs.items():
            _flatten(name, out.summary, results)
            # the point's verdict: 0 ok, 1 unreliable, 2 failed (the study's exit code uses it)
            status = out.verdict.status if out.verdict is not None else "ok"
            results[f"{name}__verdict"] = float({"ok": 0, "unreliable": 1, "failed": 2}[status])
        return results


def load_study_case(path: str | Path) -> tuple[CasePoint, dict]:
    """Read a case file for a study.

    Returns
    -------
    point : CasePoint
        The study function.
    tables : dict
        The ``sweep`` and ``optimize`` tables of the file (empty dicts if absent), checked for
        unknown keys.

    Raises
    ------
    CaseError
        Unreadable file, or an invalid case (validated once with no parameter changed).
    """
    from fricdamp.case import read_case_file

    path = Path(path)
    data, text = read_case_file(path)
    tables = {}
    for name, allowed in (("sweep", _SWEEP_KEYS), ("optimize", _OPTIMIZE_KEYS)):
        table = data.get(name, {})
        if not isinstance(table, Mapping):
            raise CaseError(f"[{name}] must be a table, got {table!r}")
        unknown = sorted(set(table) - allowed)
        if unknown:
            raise CaseError(f"unknown key {unknown[0]!r} in [{name}]; allowed keys: "
                            f"{', '.join(sorted(allowed))}")
        tables[name] = dict(table)
    name = data.get("name") if isinstance(data.get("name"), str) else path.stem
    point = CasePoint(data, text=text, source=path, name=name)
    point.check({})
    return point, tables


# ------------------------------------------------------------------------------- parser
def _add_where(p: argparse.ArgumentParser) -> None:
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                       help="address of a running dask.distributed scheduler (default: a local "
                            "cluster of processes, one per core)")
    where.add_argument("--serial", action="store_true",
                       help="run the points one after the other in this process (no Dask)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="number of local worker processes (default: the number of cores)")
    p.add_argument("--out", metavar="DIR",
                   help="output folder (default: ./fricdamp-out/<case name>-<command>); "
                        "rerunning into the same folder reuses the finished points")
    p.add_argument("--no-retry-failed", action="store_true",
                   help="reuse stored failures instead of computing failed points again")
    p.add_argument("--no-figures", action="store_true", help="write no PNG figures")
    p.add_argument("--no-progress", action="store_true", help="never show a progress bar")
    p.add_argument("--traceback", action="store_true",
                   help="show the Python traceback of internal errors")
    p.add_argument("-v", "--verbose", action="store_true", help="log what happens")


def add_subparsers(subparsers) -> None:
    """Add the ``sweep`` and ``optimize`` commands to an argparse subparsers object.

    Each sets ``func`` (and ``handler``) to its handler, which takes the parsed arguments and
    returns the exit code.
    """
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

    o = subparsers.add_parser(
        "optimize", help="minimise or maximise a result of a case inside parameter bounds",
        description="Search the parameters of a case for the minimum (or maximum) of one "
                    "result with a bounded SciPy optimiser, evaluating points as a sweep does "
                    "(in parallel, stored at once, resumable). Writes optimum.json and the "
                    "evaluation history.")
    o.add_argument("case", help="TOML case file")
    goal = o.add_mutually_exclusive_group()
    goal.add_argument("--minimize", metavar="RESULT", help="result to minimise "
                      "(e.g. amplitude_m, or forced_response__amplitude_m)")
    goal.add_argument("--maximize", metavar="RESULT", help="result to maximise")
    o.add_argument("--over", action="append", metavar="NAME=LOW:HIGH,...",
                   help="parameters and bounds (replaces the case file's [optimize] over)")
    o.add_argument("--method", choices=("differential_evolution", "nelder-mead"),
                   help="optimiser (default differential_evolution)")
    o.add_argument("--maxiter", type=int, help="generations (differential evolution) or "
                                               "evaluations (Nelder-Mead)")
    o.add_argument("--popsize", type=int, help="differential evolution: candidates per "
                                               "generation per parameter (default 8)")
    o.add_argument("--seed", type=int, help="random seed (default 0)")
    _add_where(o)
    o.set_defaults(func=handle_optimize, handler=handle_optimize)


# ----------------------------------------------------------------------------- handlers
def _err(msg: str) -> None:
    print(f"fricdamp: error: {msg}", file=sys.stderr)


def _out(msg: str) -> None:
    print(msg, flush=True)


@contextlib.contextmanager
def _sigterm_as_interrupt():
    """Turn SIGTERM into KeyboardInterrupt so a killed study closes its local cluster."""
    def handler(signum, frame):
        raise KeyboardInterrupt

    try:
        old = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def _out_dir(args, point, command: str) -> Path:
    return Path(args.out) if args.out else Path("fricdamp-out") / f"{point.name}-{command}"


def _client_kwargs(args) -> dict:
    from fricdamp.studies.cluster import check_scheduler_address

    if args.workers is not None and args.workers < 1:
        raise CaseError(f"--workers must be >= 1, got {args.workers}")
    if args.scheduler is not None:
        check_scheduler_address(args.scheduler)
    return {"client": args.scheduler, "serial": args.serial, "n_workers": args.workers}


def _where(args) -> str:
    if args.serial:
        return "serially in this process"
    if args.scheduler:
        return f"on the Dask scheduler at {args.scheduler}"
    return f"on a local Dask cluster of {args.workers or os.cpu_count()} processes"


def _check_points(point: CasePoint, points) -> None:
    """Validate the case (schema: types and ranges) at each point; CaseError names it."""
    for params in points:
        try:
            point.case(params)
        except CaseError as exc:
            where = ", ".join(f"{k}={v:g}" for k, v in params.items())
            raise CaseError(f"at {where}: {exc}") from None


#: Log file of Dask's own messages in the output folder (never on the terminal).
DASK_LOG = "dask.log"


@contextlib.contextmanager
def _dask_log(out: Path, verbose: bool):
    """Send the ``distributed`` loggers to ``out/dask.log`` instead of stderr (a dead worker or
    scheduler makes Dask log tracebacks; the command line says what happened in one line)."""
    import logging

    if verbose:
        yield
        return
    with contextlib.suppress(ImportError):
        import distributed  # noqa: F401 - its import configures its loggers: do it first
    logger = logging.getLogger("distributed")
    try:
        handler = logging.FileHandler(out / DASK_LOG, encoding="utf-8", delay=True)
    except OSError:
        handler = logging.NullHandler()
    handler.setFormatter(logging.Formatter("%(asctime)s %(name)s %(levelname)s: %(message)s"))
    saved = (logger.handlers[:], logger.propagate, logger.level)
    # distributed's sub-loggers may carry their own stderr handlers: silence them too
    subs = [logging.getLogger(n) for n in list(logging.root.manager.loggerDict)
            if n.startswith("distributed.")]
    sub_saved = [(lg, lg.handlers[:], lg.propagate) for lg in subs]
    logger.handlers = [handler]
    logger.propagate = False
    logger.setLevel(logging.WARNING)
    for lg in subs:
        lg.handlers = []
        lg.propagate = True
    try:
        yield
    finally:
        handler.close()
        logger.handlers, logger.propagate, level = saved[0], saved[1], saved[2]
        logger.setLevel(level)
        for lg, hs, prop in sub_saved:
            lg.handlers, lg.propagate = hs, prop


def _run_guarded(fn, args, out: Path | None = None):
    """Run ``fn()`` holding the output folder's lock; turn the study's runtime problems into
    exit codes (one line each; Dask's messages go to ``dask.log`` in the folder)."""
    import logging

    from fricdamp.errors import OutputError
    from fricdamp.iofiles import OutputLock
    from fricdamp.studies.sweep import StudyError

    if not args.serial and not args.verbose and out is None:
        with contextlib.suppress(ImportError):
            import distributed  # noqa: F401 - its import configures its loggers: do it first
        logging.getLogger("distributed").setLevel(logging.ERROR)
    lock = OutputLock(out, args.command or "study") if out is not None else None
    try:
        with contextlib.ExitStack() as stack:
            if lock is not None:
                stack.enter_context(lock)
                if not args.serial:
                    stack.enter_context(_dask_log(out, args.verbose))
            stack.enter_context(_sigterm_as_interrupt())
            return fn()
    except ImportError as exc:
        _err(str(exc))
        return EXIT_FAILURE
    except StudyError as exc:
        _err(str(exc))
        return EXIT_FAILURE
    except OutputError as exc:
        _err(str(exc))
        return EXIT_FAILURE


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


def handle_optimize(args) -> int:
    """``fricdamp optimize``: search the bounds for the best value; return the exit code."""
    from fricdamp.iofiles import prepare_output_folder
    from fricdamp.studies.grid import parse_bounds, resolve_parameter
    from fricdamp.studies.optimize import optimize, save_optimization
    from fricdamp.studies.sweep import StudyInterrupted

    point, tables = load_study_case(args.case)
    opt = tables["optimize"]
    if args.minimize or args.maximize:
        goal = {"minimize": args.minimize} if args.minimize else {"maximize": args.maximize}
    elif "minimize" in opt or "maximize" in opt:
        if "minimize" in opt and "maximize" in opt:
            raise CaseError("[optimize] has both minimize and maximize; keep one")
        goal = {k: opt[k] for k in ("minimize", "maximize") if k in opt}
    else:
        raise CaseError(f"nothing to optimise: give --minimize RESULT or --maximize RESULT, "
                        f"or minimize = \"...\" in the [optimize] table of {args.case}")
    if args.over:
        bounds = parse_bounds(args.over)
    elif "over" in opt:
        bounds = parse_bounds(opt["over"])
    else:
        raise CaseError("no parameters to optimise over: give --over NAME=LOW:HIGH,... or an "
                        "[optimize] over table")
    for name in bounds:
        resolve_parameter(point.data, name)
    corners = [dict(zip(bounds, c, strict=True)) for c in itertools.product(*bounds.values())]
    _check_points(point, corners[:1024])
    settings = {k: opt[k] for k in ("method", "maxiter", "popsize", "seed", "tol") if k in opt}
    for k in ("method", "maxiter", "popsize", "seed"):
        if getattr(args, k) is not None:
            settings[k] = getattr(args, k)
    kwargs = _client_kwargs(args)
    out = _out_dir(args, point, "optimize")
    prepare_output_folder(out)
    sense, target = next(iter(goal.items()))
    _out(f"fricdamp {__version__}: {sense} {target} of {args.case} over "
         f"{', '.join(f'{n} in [{lo:g}, {hi:g}]' for n, (lo, hi) in bounds.items())} "
         f"{_where(args)}")

    def run() -> int:
        from fricdamp.iofiles import write_json

        try:
            result = optimize(point, bounds, store=out / "points",
                              progress=_progress_wanted(args.no_progress),
                              retry_failed=not args.no_retry_failed, **goal, **settings,
                              **kwargs)
        except StudyInterrupted as exc:
            write_json(out / "optimum.json", {**exc.counts, "interrupted": True,
                                              "case": str(args.case)})
            _err(f"{exc} (stored in {out / 'points'})")
            return EXIT_INTERRUPTED
        summary = save_optimization(result, out, figures=not args.no_figures)
        x = ", ".join(f"{k}={v:.6g}" for k, v in result.x.items())
        _out(f"{'converged' if result.success else 'NOT converged'} ({result.message}): "
             f"{result.objective} = {result.value:.6g} at {x}")
        _out(f"{result.n_evaluations} evaluations: {result.n_computed} computed, "
             f"{result.n_reused} reused, {result.n_failed} failed, in {result.elapsed_s:.1f} s")
        _out(f"wrote optimum.json, history.nc, history.csv and "
             f"{len(summary['files']['figures'])} figures to {out}")
        # the verdict is the last line, as for fricdamp run: the optimizer's, then the
        # verdicts of the analyses at the optimum
        if not result.success:
            _err(f"verdict: failed: the optimizer did not converge ({result.message})")
            return EXIT_FAILURE
        bad = {k.removesuffix("__verdict"): v for k, v in (result.results or {}).items()
               if k.endswith("__verdict") and isinstance(v, (int, float)) and v >= 1}
        if any(v >= 2 for v in bad.values()):
            _err(f"verdict: failed at the optimum ({', '.join(bad)})")
            return EXIT_FAILURE
        if bad:
            print(f"fricdamp: warning: verdict: unreliable at the optimum ({', '.join(bad)}): "
                  "run the case at the optimum with fricdamp run to see why", file=sys.stderr)
            return EXIT_UNRELIABLE
        _out("verdict: ok")
        return EXIT_OK

    return _run_guarded(run, args, out)


# ------------------------------------------------------------------------- standalone
def main(argv: list[str] | None = None) -> int:
    """Run ``sweep`` or ``optimize`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli.studies sweep CASE.toml --grid ...``
    """
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
