"""Friction and contact laws, vectorised over contacts.

Every law follows one protocol (:class:`fricdamp.contact.base.ContactLaw`): explicit state,
``step(state, u, v) -> LawStep(force, stiffness, damping, state)`` and ``drive(u_history)``
to trace a hysteresis loop from the virgin state. The same code serves time stepping,
event-driven integration and the AFT step of harmonic balance.
"""

from fricdamp.contact.base import ContactLaw, LawStep
from fricdamp.contact.jenkins import Jenkins

__all__ = ["ContactLaw", "LawStep", "Jenkins"]
