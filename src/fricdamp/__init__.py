"""fricdamp: dry-friction damping in turbomachinery blades and mechanical joints.

Layers (imports point downward only)::

    cli, report          command line, TOML cases, HTML/PNG report
    studies              sweeps and optimisation
    models               the papers' systems, each a builder of a MechanicalSystem
    solvers              time stepping, event-driven stick-slip, harmonic balance, ...
    analysis             hysteresis & energy, damping identification, signals
    structure            MechanicalSystem, contact elements, matrix builders and import
    contact              friction and contact laws, vectorised over contacts

Importing fricdamp never imports matplotlib or dask.
"""

from fricdamp._version import __version__
from fricdamp.errors import CaseError, ConvergenceError, FricdampError, ModelError

__all__ = [
    "__version__",
    "CaseError",
    "ConvergenceError",
    "FricdampError",
    "ModelError",
]
