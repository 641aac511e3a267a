"""Structural models: MechanicalSystem, contact elements, loads, builders and matrix import."""

from fricdamp.structure.beam import cantilever_beam, euler_bernoulli_matrices, node_dof
from fricdamp.structure.beam3d import (
    BeamModel,
    BeamSection,
    beam_model,
    line_mesh,
)
from fricdamp.structure.beam3d_rotation import RigidBodyTerms, rigid_body_terms
from fricdamp.structure.builders import chain, from_matrices
from fricdamp.structure.cyclic import CyclicSector, assemble_full, nodal_diameter_modes
from fricdamp.structure.io import read_sector
from fricdamp.structure.reduction import craig_bampton, craig_bampton_sector
from fricdamp.structure.system import (
    ContactElement,
    HarmonicLoad,
    MechanicalSystem,
    RotationTerms,
    TimeLoad,
)

__all__ = [
    "cantilever_beam",
    "euler_bernoulli_matrices",
    "node_dof",
    "CyclicSector",
    "assemble_full",
    "craig_bampton",
    "craig_bampton_sector",
    "nodal_diameter_modes",
    "read_sector",
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
