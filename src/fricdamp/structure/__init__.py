"""Structural models: MechanicalSystem, contact elements, loads, builders and matrix import."""

from fricdamp.structure.builders import chain, from_matrices
from fricdamp.structure.system import (
    ContactElement,
    HarmonicLoad,
    MechanicalSystem,
    RotationTerms,
    TimeLoad,
)

__all__ = [
    "ContactElement",
    "HarmonicLoad",
    "MechanicalSystem",
    "RotationTerms",
    "TimeLoad",
    "chain",
    "from_matrices",
]
