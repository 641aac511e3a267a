"""Solvers: time stepping (more to come: event-driven stick-slip, harmonic balance, modes)."""

from fricdamp.solvers.timestep import TimeResult, simulate

__all__ = ["TimeResult", "simulate"]
