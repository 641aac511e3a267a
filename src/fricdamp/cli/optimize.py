"""``fricdamp optimize CASE.toml --minimize RESULT --over ...``: the best parameters of a case.

::

    fricdamp optimize CASE.toml --minimize amplitude_m --over "damper_mass_kg=0.5e-3:3e-3,..."
                   [--method differential_evolution] [--scheduler ... | --serial] --out DIR

A bounded SciPy optimiser evaluates the case as a sweep does (in parallel, each point stored at
once, resumable); the goal and bounds may also come from the case file's ``[optimize]`` table.
Writes ``optimum.json``, ``history.nc``, ``history.csv`` and figures. What the studies share
(the case as a study function, where the points run, exit codes) is in
:mod:`fricdamp.cli._studies`.
"""

from __future__ import annotations

import itertools
import sys

from fricdamp._version import __version__
from fricdamp.cli._common import _progress_wanted
from fricdamp.cli._studies import (
    EXIT_FAILURE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_UNRELIABLE,
    _add_where,
    _check_points,
    _client_kwargs,
    _err,
    _out,
    _out_dir,
    _run_guarded,
    _where,
    load_study_case,
)
from fricdamp.errors import CaseError

__all__ = ["add_subparsers", "handle_optimize", "main"]


def add_subparsers(subparsers) -> None:
    """Add the ``optimize`` command to an argparse subparsers object (``func`` and ``handler``
    = handle_optimize, which takes the parsed arguments and returns the exit code)."""
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



def main(argv: list[str] | None = None) -> int:
    """Run ``optimize`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli.optimize optimize CASE.toml ...``
    """
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
