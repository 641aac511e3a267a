"""Command line: the ``fricdamp`` parser and :func:`main`.

One module per sub-command adds it to the parser (``add_subparsers``) and handles it:
:mod:`~fricdamp.cli.run`, :mod:`~fricdamp.cli.check`, :mod:`~fricdamp.cli.demo`,
:mod:`~fricdamp.cli.sweep`, :mod:`~fricdamp.cli.optimize`, :mod:`~fricdamp.cli.identify`,
:mod:`~fricdamp.cli.fit`; what they share is in :mod:`fricdamp.cli._common` (and, for the
studies, :mod:`fricdamp.cli._studies`). The names this module held before the split
(``_parser``, ``say_verdict``, ``_progress_wanted``, ...) are re-exported here.

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
import importlib
import importlib.util
import logging
import sys

from fricdamp._version import __version__
from fricdamp.cli import check as _check
from fricdamp.cli import demo as _demo
from fricdamp.cli import run as _run_command
from fricdamp.cli._common import (  # noqa: F401 - re-exported: the names of this module
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_INVALID,
    EXIT_OK,
    EXIT_UNRELIABLE,
    _describe,
    _err,
    _kept,
    _out,
    _progress_wanted,
    _run,
    say_verdict,
)
from fricdamp.cli.demo import _demo_case_path
from fricdamp.errors import CaseError, ConvergenceError, ModelError, OutputError

__all__ = ["main"]

#: The handlers under the names they had in this module before the split.
_cmd_run, _cmd_check, _cmd_demo = (_run_command.handle_run, _check.handle_check,
                                   _demo.handle_demo)

_EPILOG = """\
Case files are documented key by key on the "Case files" page of the fricdamp documentation
(source: docs/cases.md of the source tree; build the site with `mkdocs build`). An annotated
case ships with the package: {demo}
`fricdamp check CASE.toml` names any key it rejects and what is allowed.
Also: python -m fricdamp ..."""

#: Modules adding their sub-commands to the parser, in the order of ``fricdamp --help``; the
#: last four are looked up by name (design studies, measurement post-processing).
_COMMANDS = (_run_command, _check, _demo)
_OPTIONAL_COMMANDS = ("cli.sweep", "cli.optimize", "cli.identify", "cli.fit")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="fricdamp",
        description="Dry-friction damping of blades and joints: run TOML case files.",
        epilog=_EPILOG.format(demo=_demo_case_path()),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"fricdamp {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    for module in _COMMANDS:
        module.add_subparsers(sub)
    for name in _OPTIONAL_COMMANDS:
        if importlib.util.find_spec(f"fricdamp.{name}") is not None:
            importlib.import_module(f"fricdamp.{name}").add_subparsers(sub)
    return p


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
