"""Structural models: MechanicalSystem, contact elements, loads, builders and matrix import."""

from fricdamp.structure.beam3d import (
    BeamModel,
    BeamSection,
    beam_model,
    line_mesh,
)
from fricdamp.structure.beam3d_rotation import RigidBodyTerms, rigid_body_terms
from fricdamp.structure.builders import chain, from_matrices
from fricdamp.structure.system import (
    ContactElement,
    HarmonicLoad,
    MechanicalSystem,
    RotationTerms,
    TimeLoad,
)

__all__ = [
    "BeamModel",
    "BeamSection",
    "RigidBodyTerms",
    "beam_model",
    "line_mesh",
    "rigid_body_terms",
    "ContactElement",
    "HarmonicLoad",
    "MechanicalSystem",
    "RotationTerms",
    "TimeLoad",
    "chain",
    "from_matrices",
]
