"""``fricdamp demo``: run the built-in showcase case and print where its report is.

The case (a 2-DOF oscillator with a Jenkins friction contact: free decay, forced response,
hysteresis) ships with the package, annotated key by key (:func:`_demo_case_path`).
"""

from __future__ import annotations

import sys
from pathlib import Path

from fricdamp.cli._common import _run, add_common_options

__all__ = ["add_subparsers", "handle_demo", "main"]


def _demo_case_path() -> str:
    """Path of the built-in annotated case (``fricdamp demo``) inside the installed package."""
    from importlib import resources

    return str(resources.files("fricdamp") / "data" / "demo.toml")


def add_subparsers(subparsers) -> None:
    """Add the ``demo`` command to an argparse subparsers object (``func`` = handle_demo)."""
    d = subparsers.add_parser("demo", help="run the built-in showcase (a few seconds)",
                              description="Run the built-in showcase: a 2-DOF oscillator with "
                                          "a Jenkins friction contact (free decay, forced "
                                          "response, hysteresis), and print where its report "
                                          "is.")
    d.add_argument("--out", metavar="DIR", help="output folder (default: ./fricdamp-out/demo)")
    d.add_argument("--format", choices=("nc", "npz"), default="nc",
                   help="results file format")
    d.add_argument("--no-progress", action="store_true", help="never show progress bars")
    add_common_options(d)
    d.set_defaults(func=handle_demo)


def handle_demo(args) -> int:
    """``fricdamp demo``: run the built-in case; return the exit code."""
    from fricdamp.runner import load_builtin_case

    case = load_builtin_case("demo")
    out = Path(args.out) if args.out else Path("fricdamp-out") / case.name
    return _run(case, out, args)


def main(argv: list[str] | None = None) -> int:
    """Run ``demo`` without the other commands (``python -m fricdamp.cli.demo demo``)."""
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
