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

#: Names imported on first use (scikit-fem, meshio and gmsh load only when a solid is built).
_LAZY = {
    "SolidMesh": "fricdamp.structure.solid", "SolidModel": "fricdamp.structure.solid",
    "assemble_solid": "fricdamp.structure.solid", "read_mesh": "fricdamp.structure.solid",
    "mesh_from_meshio": "fricdamp.structure.solid", "box_mesh": "fricdamp.structure.solid",
    "ContactPatch": "fricdamp.structure.contact_patch",
    "patch_from_faces": "fricdamp.structure.contact_patch",
    "reduce_sector": "fricdamp.structure.cyclic_reduction",
    "wheel_modes": "fricdamp.structure.cyclic_reduction",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'fricdamp.structure' has no attribute {name!r}")


__all__ = [
    *_LAZY,
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
