"""fricdamp: dry-friction damping in turbomachinery blades and mechanical joints.

Layers (imports point downward only)::

    cli, report          command line, TOML cases, HTML/PNG report
    studies              sweeps and optimisation
    models               the papers' systems, each a builder of a MechanicalSystem
    solvers              time stepping, event-driven stick-slip, harmonic balance, ...
    analysis             hysteresis & energy, damping identification, signals
    structure            MechanicalSystem, contact elements, matrix builders and import
    contact              friction and contact laws, vectorised over contacts

Importing fricdamp never imports matplotlib or dask; the subpackages load their modules on
first use of a name (``fricdamp.solvers.frequency_response`` imports the harmonic-balance
modules, not the event-driven or time-stepping ones), and ``__version__`` reads the package
metadata only when asked (``importlib.metadata`` costs ~0.1 s of CPU).

At interpreter exit, the objects still alive are moved out of the garbage collector's reach
(``gc.freeze()`` in an ``atexit`` handler): the collections of the interpreter's
finalisation then skip them. With numpy, SciPy and numba loaded those collections cost
0.1-0.3 s of CPU per process (measured on the shared VM: 0.27-0.30 s after a harmonic-balance
curve, 0.00-0.01 s with the freeze), a fifth of a short script's run time. Python does not
promise to run ``__del__`` of objects alive at exit; with the freeze, those in reference
cycles are left to the operating system like the rest of the process memory. Set the
environment variable ``FRICDAMP_EXIT_GC=1`` to keep the interpreter's collections at exit.
"""

import atexit as _atexit
import os as _os

from fricdamp.errors import CaseError, ConvergenceError, FricdampError, ModelError

__all__ = [
    "__version__",
    "CaseError",
    "ConvergenceError",
    "FricdampError",
    "ModelError",
]


def _freeze_at_exit() -> None:
    import gc

    gc.freeze()


if _os.environ.get("FRICDAMP_EXIT_GC", "") != "1":
    # registered first, so it runs after the exit handlers registered later (LIFO)
    _atexit.register(_freeze_at_exit)


def __getattr__(name: str):
    if name == "__version__":
        from fricdamp._version import __version__

        return __version__
    import importlib

    if name in ("analyses", "analysis", "cases", "cli", "contact", "models", "signals",
                "solvers", "structure",
                "studies"):
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'fricdamp' has no attribute {name!r}")


from fricdamp import _moved  # noqa: E402,F401  (old module paths, see _moved.py)
