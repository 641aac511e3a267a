"""Solvers: time stepping, exact event-driven stick-slip, modal analysis, harmonic balance,
continuation and nonlinear modes."""

from fricdamp.solvers.continuation import ContinuationResult, newton, solve_and_continue
from fricdamp.solvers.event import (
    ConstrainedSystem,
    CoulombSystem,
    EventResult,
    LinearForm,
    SwitchEvent,
    simulate_events,
)
from fricdamp.solvers.hb import (
    FrequencyResponse,
    SteadyState,
    engine_order_load,
    frequency_response,
    harmonic_balance,
    load_response,
)
from fricdamp.solvers.modal import campbell, critical_speeds, modes
from fricdamp.solvers.nma import NonlinearModes, nonlinear_modes
from fricdamp.solvers.timestep import TimeResult, simulate

__all__ = [
    "ContinuationResult",
    "FrequencyResponse",
    "NonlinearModes",
    "SteadyState",
    "engine_order_load",
    "frequency_response",
    "harmonic_balance",
    "load_response",
    "newton",
    "nonlinear_modes",
    "solve_and_continue",
    "ConstrainedSystem",
    "CoulombSystem",
    "EventResult",
    "LinearForm",
    "SwitchEvent",
    "TimeResult",
    "campbell",
    "critical_speeds",
    "modes",
    "simulate",
    "simulate_events",
]
