"""What ``fricdamp sweep`` (:mod:`fricdamp.cli.sweep`) and ``fricdamp optimize``
(:mod:`fricdamp.cli.optimize`) share: the case as a study function, the case file's study
tables, the options saying where the points run, and the guard that turns a study's runtime
problems into exit codes. The commands:

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
import json
import os
import signal
from collections.abc import Mapping
from pathlib import Path

from fricdamp._version import __version__
from fricdamp.cli._common import (  # noqa: F401 - the exit codes are shared by the studies
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_INVALID,
    EXIT_OK,
    EXIT_UNRELIABLE,
    _err,
    _out,
)
from fricdamp.errors import CaseError

__all__ = ["CasePoint", "load_study_case"]

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


# ------------------------------------------------------------------ running a study
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

