"""Command line of design studies: ``fricdamp sweep`` and ``fricdamp optimize``.

The two commands live in :mod:`fricdamp.cli.sweep` and :mod:`fricdamp.cli.optimize`, what
they share in :mod:`fricdamp.cli._studies`; this module adds both to a parser and re-exports
their names (``fricdamp.cli.studies.X`` and the old ``fricdamp.cli_studies.X`` keep working).

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

import sys

from fricdamp._version import __version__  # noqa: F401 - re-exported, as before the split
from fricdamp.cli import optimize as _optimize
from fricdamp.cli import sweep as _sweep
from fricdamp.cli._common import _progress_wanted  # noqa: F401
from fricdamp.cli._studies import (  # noqa: F401
    _OPTIMIZE_KEYS,
    _SWEEP_KEYS,
    DASK_LOG,
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_INVALID,
    EXIT_OK,
    EXIT_UNRELIABLE,
    STUDY_TABLES,
    CasePoint,
    _add_where,
    _check_points,
    _client_kwargs,
    _dask_log,
    _err,
    _file_digests,
    _flatten,
    _out,
    _out_dir,
    _run_guarded,
    _sigterm_as_interrupt,
    _where,
    load_study_case,
)
from fricdamp.cli.optimize import handle_optimize
from fricdamp.cli.sweep import _write_html_report, handle_sweep  # noqa: F401
from fricdamp.errors import CaseError  # noqa: F401

__all__ = ["CasePoint", "add_subparsers", "handle_optimize", "handle_sweep", "load_study_case",
           "main"]


def add_subparsers(subparsers) -> None:
    """Add the ``sweep`` and ``optimize`` commands to an argparse subparsers object.

    Each sets ``func`` (and ``handler``) to its handler, which takes the parsed arguments and
    returns the exit code.
    """
    _sweep.add_subparsers(subparsers)
    _optimize.add_subparsers(subparsers)


def main(argv: list[str] | None = None) -> int:
    """Run ``sweep`` or ``optimize`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli.studies sweep CASE.toml --grid ...``
    """
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
