"""Command line: ``fricdamp run CASE.toml``, ``fricdamp check CASE.toml``, ``fricdamp demo``.

Exit codes: 0 success; 2 invalid case or bad input (one line on stderr naming the key and
what is allowed, never a traceback); 1 a solver failed (its message on stderr) or an
internal error (``--traceback`` shows it). Progress bars appear only when stderr is a
terminal and the ``CI`` environment variable is not set.

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
from fricdamp.errors import CaseError, ConvergenceError, ModelError

__all__ = ["main"]

EXIT_OK, EXIT_FAILURE, EXIT_INVALID = 0, 1, 2


def _progress_wanted(disabled: bool) -> bool:
    """Progress bars only on a terminal, never in CI."""
    if disabled or os.environ.get("CI"):
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="fricdamp",
        description="Dry-friction damping of blades and joints: run TOML case files.",
        epilog="Case files are documented key by key in docs/cases.md.")
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
    for name in ("cli_studies", "cli_identify", "cli_fit"):
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
    outcome = run_case(case, out_dir, progress=_progress_wanted(args.no_progress),
                       results_format=args.format, echo=_out)
    files = outcome.files
    _out(f"wrote {len(files['figures'])} figures, {files['results']} and {files['summary']} "
         f"to {out_dir} in {time.perf_counter() - t0:.1f} s")
    _out(f"report: {outcome.report.resolve()}")
    return EXIT_OK


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


def run_parsed(args: argparse.Namespace) -> int:
    """Run a parsed subcommand (``args.func``) and map its errors to exit codes: 2 invalid
    input (one line), 1 solver failure or internal error, 130 interrupted."""
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="fricdamp: %(levelname)s: %(name)s: %(message)s")
    try:
        return args.func(args)
    except (CaseError, ModelError) as exc:
        _err(str(exc))
        return EXIT_INVALID
    except ConvergenceError as exc:
        _err(f"the solver failed: {exc}")
        return EXIT_FAILURE
    except KeyboardInterrupt:
        _err("interrupted")
        return 130
    except Exception as exc:  # a bug: say so in one line unless asked for the traceback
        if args.traceback:
            raise
        _err(f"internal error: {type(exc).__name__}: {exc} (run again with --traceback for "
             "details, and please report it)")
        return EXIT_FAILURE


def main_for(add_subparsers, argv: list[str] | None = None) -> int:
    """Run subcommands added by ``add_subparsers(subparsers)`` without the other commands
    (``python -m fricdamp.cli_studies ...``, scripts and tests)."""
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
