"""Command line: ``fricdamp run CASE.toml``, ``fricdamp check CASE.toml``, ``fricdamp demo``.

Exit codes (the same for every command; the "Case files" page of the documentation):

* 0 -- ok: every analysis finished and its error estimates are within their limits;
* 1 -- failed: a solver did not finish what was asked (an FRF that stopped short of its
  range, a time integration that stopped), a result could not be written (disk full,
  permission: the message names the file), or an internal error (``--traceback`` shows it);
* 2 -- bad input: invalid case, key or argument (one line on stderr naming the key and what
  is allowed, never a traceback); nothing is computed;
* 3 -- computed but unreliable: the results are written, but an error estimate exceeds its
  limit (energy balance, time-step or harmonic-truncation error, ...;
  ``summary.json["verdict"]`` says which and what to do);
* 130 -- interrupted (Ctrl-C or SIGTERM): temporary files are removed, complete files kept.

Progress bars appear only when stderr is a terminal and the ``CI`` environment variable is
not set.

The command line owns all terminal output; the library only logs.
"""

from __future__ import annotations

import argparse
import importlib.util
import logging
import os
import sys
import time
from pathlib import Path

from fricdamp._version import __version__
from fricdamp.errors import CaseError, ConvergenceError, ModelError, OutputError

__all__ = ["main"]

EXIT_OK, EXIT_FAILURE, EXIT_INVALID, EXIT_UNRELIABLE, EXIT_INTERRUPTED = 0, 1, 2, 3, 130


def _progress_wanted(disabled: bool) -> bool:
    """Progress bars only on a terminal, never in CI."""
    if disabled or os.environ.get("CI"):
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


_EPILOG = """\
Case files are documented key by key on the "Case files" page of the fricdamp documentation
(source: docs/cases.md of the source tree; build the site with `mkdocs build`). An annotated
case ships with the package: {demo}
`fricdamp check CASE.toml` names any key it rejects and what is allowed.
Also: python -m fricdamp ..."""


def _demo_case_path() -> str:
    """Path of the built-in annotated case (``fricdamp demo``) inside the installed package."""
    from importlib import resources

    return str(resources.files("fricdamp") / "data" / "demo.toml")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="fricdamp",
        description="Dry-friction damping of blades and joints: run TOML case files.",
        epilog=_EPILOG.format(demo=_demo_case_path()),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"fricdamp {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    def common(sp):
        sp.add_argument("--traceback", action="store_true",
                        help="show the Python traceback of internal errors")
        sp.add_argument("-v", "--verbose", action="store_true", help="log what happens")

    r = sub.add_parser("run", help="run the analyses of a case file",
                       description="Run the analyses of a case file and write summary.json, "
                                   "the results file, PNG figures and report.html.")
    r.add_argument("case", help="TOML case file")
    r.add_argument("--out", metavar="DIR",
                   help="output folder (default: ./fricdamp-out/<case name>)")
    r.add_argument("--format", choices=("nc", "npz"), default="nc",
                   help="results file format: netCDF (default) or numpy .npz")
    r.add_argument("--no-progress", action="store_true", help="never show progress bars")
    common(r)
    r.set_defaults(func=_cmd_run)

    c = sub.add_parser("check", help="validate a case file without running it",
                       description="Validate a case file (keys, types, ranges, the model's "
                                   "matrices and DOF numbers) without running it.")
    c.add_argument("case", help="TOML case file")
    common(c)
    c.set_defaults(func=_cmd_check)

    d = sub.add_parser("demo", help="run the built-in showcase (a few seconds)",
                       description="Run the built-in showcase: a 2-DOF oscillator with a "
                                   "Jenkins friction contact (free decay, forced response, "
                                   "hysteresis), and print where its report is.")
    d.add_argument("--out", metavar="DIR", help="output folder (default: ./fricdamp-out/demo)")
    d.add_argument("--format", choices=("nc", "npz"), default="nc",
                   help="results file format")
    d.add_argument("--no-progress", action="store_true", help="never show progress bars")
    common(d)
    d.set_defaults(func=_cmd_demo)

    # design studies (fricdamp sweep / optimize) and measurement post-processing
    # (fricdamp identify, fricdamp fit) live in their own modules
    for name in ("cli.studies", "cli.identify", "cli.fit"):
        if importlib.util.find_spec(f"fricdamp.{name}") is not None:
            importlib.import_module(f"fricdamp.{name}").add_subparsers(sub)
    return p


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


def _cmd_run(args) -> int:
    from fricdamp.runner import load_case

    case = load_case(args.case)
    out = Path(args.out) if args.out else Path("fricdamp-out") / case.name
    return _run(case, out, args)


def _cmd_check(args) -> int:
    from fricdamp.runner import build_system, load_case

    case = load_case(args.case)
    system = build_system(case)
    _out(f"ok: {args.case}: {_describe(case, system)}")
    return EXIT_OK


def _cmd_demo(args) -> int:
    from fricdamp.runner import load_builtin_case

    case = load_builtin_case("demo")
    out = Path(args.out) if args.out else Path("fricdamp-out") / case.name
    return _run(case, out, args)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``fricdamp`` command; returns the exit code.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name (default ``sys.argv[1:]``).
    """
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors (argparse exits with 2)
        code = exc.code
        return code if isinstance(code, int) else (EXIT_OK if code is None else EXIT_INVALID)
    if args.command is None:
        parser.print_help(sys.stderr)
        return EXIT_INVALID
    return run_parsed(args)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised as an interruption so that temporary files are cleaned up."""


def _on_sigterm(signum, frame):  # pragma: no cover - exercised in a subprocess test
    raise Terminated()


def run_parsed(args: argparse.Namespace) -> int:
    """Run a parsed subcommand (``args.func``) and map its errors to exit codes: 2 invalid
    input (one line), 1 solver failure, write failure or internal error, 130 interrupted
    (Ctrl-C or SIGTERM). A subcommand returns 0, 1 or 3 from its results' verdict."""
    import signal
    import threading

    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="fricdamp: %(levelname)s: %(name)s: %(message)s")
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        return args.func(args)
    except (CaseError, ModelError) as exc:
        _err(str(exc))
        return EXIT_INVALID
    except ConvergenceError as exc:
        _err(f"the solver failed: {exc}")
        return EXIT_FAILURE
    except OutputError as exc:
        _err(str(exc))
        return EXIT_FAILURE
    except KeyboardInterrupt:
        _err("interrupted")
        return EXIT_INTERRUPTED
    except MemoryError:
        _err("out of memory: the run needs more memory than the machine has; reduce its size "
             "(time steps, harmonics, DOFs)")
        return EXIT_FAILURE
    except OSError as exc:  # disk full or permission while writing somewhere we did not wrap
        if args.traceback:
            raise
        name = getattr(exc, "filename", None)
        _err(f"cannot write or read {name!r}: {exc.strerror or exc}" if name else
             f"input/output error: {exc}")
        return EXIT_FAILURE
    except Exception as exc:  # a bug: say so in one line unless asked for the traceback
        if args.traceback:
            raise
        _err(f"internal error: {type(exc).__name__}: {exc} (run again with --traceback for "
             "details, and please report it)")
        return EXIT_FAILURE


def main_for(add_subparsers, argv: list[str] | None = None) -> int:
    """Run subcommands added by ``add_subparsers(subparsers)`` without the other commands
    (``python -m fricdamp.cli.studies ...``, scripts and tests)."""
    parser = argparse.ArgumentParser(prog="fricdamp")
    add_subparsers(parser.add_subparsers(dest="command", metavar="COMMAND", required=True))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        code = exc.code
        return code if isinstance(code, int) else (EXIT_OK if code is None else EXIT_INVALID)
    return run_parsed(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
