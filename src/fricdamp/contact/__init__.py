"""Friction and contact laws, vectorised over contacts.

Every law follows one protocol (:class:`fricdamp.contact.base.ContactLaw`): explicit state,
``step(state, u, v) -> LawStep(force, stiffness, damping, state)`` and ``drive(u_history)``
to trace a hysteresis loop from the virgin state. The same code serves time stepping,
event-driven integration and the AFT step of harmonic balance.
"""

from fricdamp.contact.base import ContactLaw, LawStep
from fricdamp.contact.coulomb import Coulomb, ForceSet, coulomb_force_set, friction_coefficient
from fricdamp.contact.cubic import CubicSpring
from fricdamp.contact.element3d import Contact3D
from fricdamp.contact.iwan import Iwan
from fricdamp.contact.jenkins import Jenkins
from fricdamp.contact.mindlin import (
    CattaneoMindlin,
    RotationalMindlin,
    effective_modulus,
    hertz_radius,
    shear_modulus,
    tangential_compliance,
)
from fricdamp.contact.rough import (
    GreenwoodWilliamson,
    RoughRotationalJoint,
    gw_integral,
    height_classes,
)

__all__ = [
    "CattaneoMindlin",
    "GreenwoodWilliamson",
    "RotationalMindlin",
    "RoughRotationalJoint",
    "effective_modulus",
    "gw_integral",
    "height_classes",
    "hertz_radius",
    "shear_modulus",
    "tangential_compliance",
    "Contact3D",
    "ContactLaw",
    "Coulomb",
    "CubicSpring",
    "ForceSet",
    "Iwan",
    "Jenkins",
    "LawStep",
    "coulomb_force_set",
    "friction_coefficient",
]
