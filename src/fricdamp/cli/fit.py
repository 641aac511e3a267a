"""Command line of the joint-model fit: ``fricdamp fit LOOPS --model MODEL --out DIR``.

::

    fricdamp fit loops.csv [more.csv | identify-folder ...] --model jenkins|iwan|rough
                 --out DIR [--target loops|energy|both] [--preload N]
                 [--fixed KEY=VALUE ...] [--initial NAME=VALUE ...]

Fits a Jenkins element, a four-parameter Iwan joint or paper 002's rough rotational joint
(:func:`fricdamp.signals.fit.fit_joint`) to measured hysteresis loops and/or dissipated
energy against amplitude, and writes ``fit.json`` (``parameters`` named with their units as in
case files, ``confidence_95``, ``derived``, ``residual``, ``conditioning``, ``status``,
``warnings``) and ``fit.png`` (measured and fitted loops, and energies) into ``DIR``.
The page "Fit a contact law to loops" of the fricdamp
documentation explains every key.

LOOPS are CSV files -- one loop each, columns ``time [s],displacement [m],force [N]`` or
``rotation [rad],torque [N m]`` (time or phase columns ignored; mm, um, mrad, deg, kN, N mm
converted), whole periods -- or tables ``amplitude [rad],energy [J]``, or output folders of
``fricdamp identify`` (their ``loop.csv``).

Exit codes: 0 success; 3 fitted but **unreliable** (fit.json written; a parameter's 95 %
interval wider than +-50 %, a residual above 20 % of the force amplitude or an
ill-conditioned fit); 2 invalid input (one line on stderr); 1 the fit failed or an internal
error.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from fricdamp._version import __version__
from fricdamp.errors import CaseError

__all__ = ["add_subparsers", "handle_fit", "main"]

EXIT_OK, EXIT_FAILURE, EXIT_INVALID, EXIT_UNRELIABLE = 0, 1, 2, 3


def add_subparsers(subparsers) -> None:
    """Add the ``fit`` command to an argparse subparsers object (``func`` = handle_fit)."""
    s = subparsers.add_parser(
        "fit", help="fit a Jenkins, Iwan or rough-contact joint model to measured loops",
        description="Fit a joint model (Jenkins element, four-parameter Iwan, or paper 002's "
                    "rough rotational joint) to hysteresis loops and/or dissipated energy "
                    "against amplitude, with 95 % confidence intervals. Writes fit.json "
                    "and fit.png.",
        epilog="Exit codes: 0 fitted; 3 fitted but unreliable (warnings say why); 2 invalid "
               "input; 1 the fit failed or internal error. Keys: the page \"Fit a contact "
               "law to loops\" of the fricdamp documentation.")
    s.add_argument("loops", nargs="+", metavar="LOOPS",
                   help="loop CSV files, energy tables or fricdamp identify output folders")
    s.add_argument("--model", required=True, choices=("jenkins", "iwan", "rough"),
                   help="joint model to fit")
    s.add_argument("--out", metavar="DIR",
                   help="output folder (default: ./fricdamp-out/fit-<model>)")
    s.add_argument("--target", choices=("loops", "energy", "both"),
                   help="fit the loops (default when loops are given), the energies, or both")
    s.add_argument("--preload", type=float, metavar="N",
                   help="rough model: bolt preload [N] (default 100, paper 002)")
    s.add_argument("--fixed", action="append", default=[], metavar="KEY=VALUE",
                   help="rough model: fixed parameter (preload_N, contact_width_m, "
                        "contact_height_m, summit_radius_m, youngs_modulus_Pa, poisson_ratio, "
                        "joint_cells=14,9, height_classes); repeatable")
    s.add_argument("--initial", action="append", default=[], metavar="NAME=VALUE",
                   help="starting value of a fitted parameter (e.g. slip_force_N=10); "
                        "repeatable")
    s.add_argument("--traceback", action="store_true",
                   help="show the Python traceback of internal errors")
    s.add_argument("-v", "--verbose", action="store_true", help="log what happens")
    s.set_defaults(func=handle_fit, handler=handle_fit)


def _pairs(items, option: str, *, ints=()) -> dict:
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        key = key.strip()
        try:
            if not sep or not key:
                raise ValueError
            if key in ints:
                parts = [int(v) for v in value.split(",")]
                val = tuple(parts) if len(parts) > 1 else parts[0]
            else:
                val = float(value)
        except ValueError:
            raise CaseError(f"--{option} must be KEY=VALUE with a number (e.g. "
                            f"{'preload_N=100' if option == 'fixed' else 'slip_force_N=10'}), "
                            f"got {item!r}") from None
        out[key] = val
    return out


def _out(msg: str) -> None:
    print(msg, flush=True)


def _warn(msg: str) -> None:
    print(f"fricdamp: warning: {msg}", file=sys.stderr)


def handle_fit(args) -> int:
    """``fricdamp fit``: read the loops, fit, write fit.json and fit.png; the exit code."""
    import numpy as np

    from fricdamp.iofiles import OutputLock, prepare_output_folder
    from fricdamp.signals.fit import read_fit_input

    fixed = _pairs(args.fixed, "fixed", ints=("joint_cells", "height_classes"))
    initial = _pairs(args.initial, "initial")
    if args.preload is not None:
        if not args.preload > 0:
            raise CaseError(f"--preload must be > 0 N, got {args.preload:g}")
        fixed["preload_N"] = args.preload
    if fixed and args.model != "rough":
        raise CaseError(f"--fixed and --preload apply to the rough model, not {args.model!r}")
    loops, amps, energies, rot = [], [], [], set()
    for path in args.loops:
        got = read_fit_input(path)
        if isinstance(got, tuple):
            amps.append(got[0])
            energies.append(got[1])
            rot.add(got[2])
        else:
            loops.extend(got)
            rot.update(lp.rotational for lp in got)
    if len(rot) > 1:
        raise CaseError("the inputs mix rotation/torque and displacement/force")
    energy = None
    if amps:
        energy = (np.concatenate(amps), np.concatenate(energies), rot.pop())
    target = args.target or ("both" if loops and energy is not None else None)
    out = Path(args.out) if args.out else Path("fricdamp-out") / f"fit-{args.model}"
    # the folder is created, write-tested and locked before anything is computed
    prepare_output_folder(out)
    with OutputLock(out, "fit"):
        return _fit(args, loops, energy, target, initial, fixed, out)


def _fit(args, loops, energy, target, initial, fixed, out: Path) -> int:
    from fricdamp.cli.app import say_verdict
    from fricdamp.iofiles import save_figure, write_json
    from fricdamp.signals.fit import fit_joint
    from fricdamp.verdict import OK, UNRELIABLE, Verdict, exit_code, verdict_block

    t0 = time.perf_counter()
    res = fit_joint(loops, energy=energy, model=args.model, target=target,
                    initial=initial or None, fixed=fixed or None)
    elapsed = time.perf_counter() - t0
    d = res.to_dict()
    est = {"rms_relative": d.get("residual", {}).get("rms_relative"),
           "raw_condition_number": d.get("conditioning", {}).get("raw_condition_number")}
    verdict = verdict_block({"fit": Verdict(UNRELIABLE, tuple(res.warnings), est)
                             if res.status == "unreliable" else Verdict(OK, (), est)})
    code = exit_code(verdict["overall"])
    write_json(out / "fit.json", {"verdict": verdict, "fricdamp_version": __version__,
                                  "inputs": [str(p) for p in args.loops],
                                  "target": target or ("loops" if loops else "energy"),
                                  "fixed": {k: list(v) if isinstance(v, tuple) else v
                                            for k, v in fixed.items()},
                                  **d, "exit_code": code, "runtime_s": elapsed})
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig = res.plot()
    save_figure(fig, out / "fit.png")
    plt.close(fig)
    _out(f"fricdamp {__version__}: fitted the {args.model} model to {len(loops)} loop(s)"
         + (f" and {energy[0].size} energies" if energy is not None else "")
         + f" in {elapsed:.2f} s")
    for name, value in res.parameters.items():
        lo, hi = res.confidence_95[name]
        _out(f"  {name} = {value:.6g}   (95 %: {lo:.6g} .. {hi:.6g})")
    _out(f"RMS residual {100 * res.residual['rms_relative']:.3g} % of the force amplitude; "
         f"status {res.status}")
    said_last = 1 if verdict["overall"] != "ok" else 0   # the verdict's reason, said last
    for w in res.warnings[said_last:]:
        _warn(w)
    _out(f"wrote fit.json and fit.png to {out}")
    return say_verdict(verdict)


def main(argv: list[str] | None = None) -> int:
    """Run ``fit`` without the main ``fricdamp`` parser (tests, scripts).

    ``python -m fricdamp.cli.fit fit LOOPS --model jenkins --out DIR``
    """
    from fricdamp.cli.app import main_for

    return main_for(add_subparsers, argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
