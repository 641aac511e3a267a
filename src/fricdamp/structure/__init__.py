"""Structural models: MechanicalSystem, contact elements, loads, builders and matrix import."""

#: Names imported on first use: a solver that needs ``MechanicalSystem`` does not load the
#: beam elements, cyclic symmetry or ``scipy.io``; scikit-fem, meshio and gmsh load only
#: when a solid is built.
_LAZY = {
    "SolidMesh": "fricdamp.structure.solid", "SolidModel": "fricdamp.structure.solid",
    "assemble_solid": "fricdamp.structure.solid", "read_mesh": "fricdamp.structure.solid",
    "mesh_from_meshio": "fricdamp.structure.solid", "box_mesh": "fricdamp.structure.solid",
    "ContactPatch": "fricdamp.structure.contact_patch",
    "patch_from_faces": "fricdamp.structure.contact_patch",
    "reduce_sector": "fricdamp.structure.cyclic_reduction",
    "wheel_modes": "fricdamp.structure.cyclic_reduction",
    "cantilever_beam": "fricdamp.structure.beam",
    "euler_bernoulli_matrices": "fricdamp.structure.beam",
    "node_dof": "fricdamp.structure.beam",
    "BeamModel": "fricdamp.structure.beam3d", "BeamSection": "fricdamp.structure.beam3d",
    "beam_model": "fricdamp.structure.beam3d", "line_mesh": "fricdamp.structure.beam3d",
    "RigidBodyTerms": "fricdamp.structure.beam3d_rotation",
    "rigid_body_terms": "fricdamp.structure.beam3d_rotation",
    "chain": "fricdamp.structure.builders", "from_matrices": "fricdamp.structure.builders",
    "CyclicSector": "fricdamp.structure.cyclic",
    "assemble_full": "fricdamp.structure.cyclic",
    "nodal_diameter_modes": "fricdamp.structure.cyclic",
    "read_sector": "fricdamp.structure.io", "read_ansys_archive": "fricdamp.structure.io",
    "craig_bampton": "fricdamp.structure.reduction",
    "craig_bampton_sector": "fricdamp.structure.reduction",
    "ContactElement": "fricdamp.structure.system",
    "HarmonicLoad": "fricdamp.structure.system",
    "MechanicalSystem": "fricdamp.structure.system",
    "RotationTerms": "fricdamp.structure.system",
    "TimeLoad": "fricdamp.structure.system",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    if not name.startswith("__"):      # submodules as attributes (``structure.beam``)
        import importlib

        try:
            return importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
    raise AttributeError(f"module 'fricdamp.structure' has no attribute {name!r}")


__all__ = [
    *_LAZY,
]
