"""``fricdamp run CASE.toml``: run the analyses of a case file and write its results.

Writes ``summary.json``, the results file (netCDF or ``.npz``), PNG figures and
``report.html`` into ``--out DIR`` (default ``./fricdamp-out/<case name>``); the verdict is
the last line and sets the exit code (:mod:`fricdamp.cli.app`).
"""

from __future__ import annotations

import sys
from pathlib import Path

from fricdamp.cli._common import _run, add_common_options

__all__ = ["add_subparsers", "handle_run", "main"]


def add_subparsers(subparsers) -> None:
    """Add the ``run`` command to an argparse subparsers object (``func`` = handle_run)."""
    r = subparsers.add_parser("run", help="run the analyses of a case file",
                              description="Run the analyses of a case file and write "
                                          "summary.json, the results file, PNG figures and "
                                          "report.html.")
    r.add_argument("case", help="TOML case file")
    r.add_argument("--out", metavar="DIR",
                   help="output folder (default: ./fricdamp-out/<case name>)")
    r.add_argument("--format", choices=("nc", "npz"), default="nc",
                   help="results file format: netCDF (default) or numpy .npz")
    r.add_argument("--no-progress", action="store_true", help="never show progress bars")
    add_common_options(r)
    r.set_defaults(func=handle_run)


def handle_run(args) -> int:
    """``fricdamp run``: run the case into its output folder; return the exit code."""
    from fricdamp.runner import load_case

    case = load_case(args.case)
    out = Path(args.out) if args.out else Path("fricdamp-out") / case.name
    return _run(case, out, args)


def main(argv: list[str] | None = None) -> int:
    """Run ``run`` without the other commands (``python -m fricdamp.cli.run run CASE.toml``)."""
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
