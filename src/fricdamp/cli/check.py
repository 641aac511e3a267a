"""``fricdamp check CASE.toml``: validate a case file without running it.

Checks keys, types and ranges, and builds the model (matrices, DOF numbers); prints one
``ok:`` line describing the case, or one error line naming the key (exit code 2).
"""

from __future__ import annotations

import sys

from fricdamp.cli._common import EXIT_OK, _describe, _out, add_common_options

__all__ = ["add_subparsers", "handle_check", "main"]


def add_subparsers(subparsers) -> None:
    """Add the ``check`` command to an argparse subparsers object (``func`` = handle_check)."""
    c = subparsers.add_parser("check", help="validate a case file without running it",
                              description="Validate a case file (keys, types, ranges, the "
                                          "model's matrices and DOF numbers) without running "
                                          "it.")
    c.add_argument("case", help="TOML case file")
    add_common_options(c)
    c.set_defaults(func=handle_check)


def handle_check(args) -> int:
    """``fricdamp check``: load and build the case; return the exit code."""
    from fricdamp.runner import build_system, load_case

    case = load_case(args.case)
    system = build_system(case)
    _out(f"ok: {args.case}: {_describe(case, system)}")
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """Run ``check`` without the other commands (``python -m fricdamp.cli.check check ...``)."""
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
