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
"""

from fricdamp.errors import CaseError, ConvergenceError, FricdampError, ModelError

__all__ = [
    "__version__",
    "CaseError",
    "ConvergenceError",
    "FricdampError",
    "ModelError",
]


def __getattr__(name: str):
    if name == "__version__":
        from fricdamp._version import __version__

        return __version__
    import importlib

    if name in ("analyses", "analysis", "contact", "models", "solvers", "structure",
                "studies"):
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'fricdamp' has no attribute {name!r}")
