"""Friction and contact laws, vectorised over contacts.

Every law follows one protocol (:class:`fricdamp.contact.base.ContactLaw`): explicit state,
``step(state, u, v) -> LawStep(force, stiffness, damping, state)`` and ``drive(u_history)``
to trace a hysteresis loop from the virgin state. The same code serves time stepping,
event-driven integration and the AFT step of harmonic balance.
"""

from fricdamp.contact.base import ContactLaw, LawStep
from fricdamp.contact.coulomb import Coulomb, ForceSet, coulomb_force_set, friction_coefficient
from fricdamp.contact.element3d import Contact3D
from fricdamp.contact.jenkins import Jenkins

__all__ = [
    "Contact3D",
    "ContactLaw",
    "Coulomb",
    "ForceSet",
    "Jenkins",
    "LawStep",
    "coulomb_force_set",
    "friction_coefficient",
]
