"""What the sub-commands of ``fricdamp`` share: exit codes, terminal output, the verdict line,
the options every command has, and running a case into an output folder (``run``, ``demo``).

The command line owns all terminal output; the library only logs.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from fricdamp._version import __version__

EXIT_OK, EXIT_FAILURE, EXIT_INVALID, EXIT_UNRELIABLE, EXIT_INTERRUPTED = 0, 1, 2, 3, 130


def _progress_wanted(disabled: bool) -> bool:
    """Progress bars only on a terminal, never in CI."""
    if disabled or os.environ.get("CI"):
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def add_common_options(sp) -> None:
    """``--traceback`` and ``-v/--verbose``, which ``run``, ``check`` and ``demo`` take."""
    sp.add_argument("--traceback", action="store_true",
                    help="show the Python traceback of internal errors")
    sp.add_argument("-v", "--verbose", action="store_true", help="log what happens")


def _err(msg: str) -> None:
    print(f"fricdamp: error: {msg}", file=sys.stderr)


def _out(msg: str) -> None:
    print(msg, flush=True)


def _describe(case, system) -> str:
    from fricdamp.structure.system import MechanicalSystem

    head = (f"case {case.name!r}: {case.model_type} model with {system.n_dof} DOF"
            f"{'s' if system.n_dof != 1 else ''}")
    if isinstance(system, MechanicalSystem):
        ncont = sum(c.n_contacts for c in system.contacts)
        laws = sorted({t for t, _ in case.contacts})
        head += (f", {ncont} contact{'s' if ncont != 1 else ''}"
                 + (f" ({', '.join(laws)})" if laws else ""))
    return head + f"; analyses: {', '.join(case.analyses)}"


def _run(case, out_dir: Path, args) -> int:
    from fricdamp.runner import build_system, run_case

    system = build_system(case)
    _out(f"fricdamp {__version__}: {_describe(case, system)}")
    t0 = time.perf_counter()
    existed = out_dir.is_dir()
    try:
        outcome = run_case(case, out_dir, progress=_progress_wanted(args.no_progress),
                           results_format=args.format, echo=_out)
    except KeyboardInterrupt:
        _err(f"interrupted: {_kept(out_dir, existed, t0)}")
        return EXIT_INTERRUPTED
    files = outcome.files
    _out(f"wrote {len(files['figures'])} figures, {files['results']} and {files['summary']} "
         f"to {out_dir} in {time.perf_counter() - t0:.1f} s")
    _out(f"report: {outcome.report.resolve()}")
    return say_verdict(outcome.summary["verdict"])


def say_verdict(verdict: dict) -> int:
    """Print the verdict of a command (``summary.json["verdict"]``: ``overall`` and
    ``analyses``) as its last line and return the exit code: ``verdict: ok`` on stdout (0),
    else one line on stderr naming the analyses and the first reason of each, as a warning
    for ``unreliable`` (3) and an error for ``failed`` (1)."""
    from fricdamp.verdict import exit_code

    if verdict["overall"] != "ok":
        bad = [n for n, v in verdict["analyses"].items() if v["verdict"] != "ok"]
        line = (f"verdict: {verdict['overall']} ({', '.join(bad)}): "
                + "; ".join(r for n in bad for r in verdict["analyses"][n]["reasons"][:1]))
        if verdict["overall"] == "failed":
            _err(line)
        else:   # computed, written, but not to be trusted: exit 3
            print(f"fricdamp: warning: {line}", file=sys.stderr)
    else:
        _out("verdict: ok")
    return exit_code(verdict["overall"])


def _kept(out_dir: Path, existed: bool, since: float) -> str:
    """What an interrupted run left in ``out_dir`` (temporary files are removed by the
    atomic writers; an empty folder this run created is removed)."""
    import contextlib

    if not out_dir.is_dir():
        return "nothing was written"
    wall = time.time() - (time.perf_counter() - since)
    new = sorted(p.name for p in out_dir.iterdir()
                 if p.is_file() and not p.name.startswith(".") and p.stat().st_mtime >= wall)
    if not new:
        if not existed:
            with contextlib.suppress(OSError):
                out_dir.rmdir()
        return f"nothing was written to {out_dir}"
    return (f"kept {len(new)} complete file{'s' if len(new) != 1 else ''} in {out_dir} "
            f"({', '.join(new)}); the run is incomplete")

