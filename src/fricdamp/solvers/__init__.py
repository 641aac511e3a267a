"""Solvers: time stepping, exact event-driven stick-slip, modal analysis (harmonic balance next)."""

from fricdamp.solvers.event import (
    ConstrainedSystem,
    CoulombSystem,
    EventResult,
    LinearForm,
    SwitchEvent,
    simulate_events,
)
from fricdamp.solvers.modal import campbell, critical_speeds, modes
from fricdamp.solvers.timestep import TimeResult, simulate

__all__ = [
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
