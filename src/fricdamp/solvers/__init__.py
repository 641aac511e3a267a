"""Solvers: time stepping, exact event-driven stick-slip, modal analysis, harmonic balance,
continuation and nonlinear modes.

Names load on first use (module-level ``__getattr__``): ``from fricdamp.solvers import
frequency_response`` imports the harmonic-balance modules only, not the event-driven stack,
``scipy.integrate`` or the time steppers, and numba loads the cached kernels of what is called.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

#: Public name -> module that defines it (imported on first use).
_LAZY = {
    "ContinuationResult": "continuation", "newton": "continuation",
    "solve_and_continue": "continuation",
    "ConstrainedSystem": "event", "CoulombSystem": "event", "EventResult": "event",
    "LinearForm": "event", "SwitchEvent": "event", "simulate_events": "event",
    "FrequencyResponse": "hb", "SteadyState": "hb", "engine_order_load": "hb",
    "frequency_response": "hb", "harmonic_balance": "hb", "load_response": "hb",
    "campbell": "modal", "critical_speeds": "modal", "modes": "modal",
    "NonlinearModes": "nma", "nonlinear_modes": "nma",
    "TimeResult": "timestep", "simulate": "timestep",
}

__all__ = sorted(_LAZY)

if TYPE_CHECKING:  # for type checkers and IDEs; at run time the names load lazily
    from fricdamp.solvers.continuation import (  # noqa: F401
        ContinuationResult,
        newton,
        solve_and_continue,
    )
    from fricdamp.solvers.event import (  # noqa: F401
        ConstrainedSystem,
        CoulombSystem,
        EventResult,
        LinearForm,
        SwitchEvent,
        simulate_events,
    )
    from fricdamp.solvers.hb import (  # noqa: F401
        FrequencyResponse,
        SteadyState,
        engine_order_load,
        frequency_response,
        harmonic_balance,
        load_response,
    )
    from fricdamp.solvers.modal import campbell, critical_speeds, modes  # noqa: F401
    from fricdamp.solvers.nma import NonlinearModes, nonlinear_modes  # noqa: F401
    from fricdamp.solvers.timestep import TimeResult, simulate  # noqa: F401


def __getattr__(name: str):
    if name.startswith("__"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    if name in _LAZY:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
        globals()[name] = value          # later look-ups skip __getattr__
        return value
    try:        # submodules as attributes (``fricdamp.solvers.hb``), as when imported eagerly
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
