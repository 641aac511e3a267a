"""Friction and contact laws, vectorised over contacts.

Every law follows one protocol (:class:`fricdamp.contact.base.ContactLaw`): explicit state,
``step(state, u, v) -> LawStep(force, stiffness, damping, state)`` and ``drive(u_history)``
to trace a hysteresis loop from the virgin state. The same code serves time stepping,
event-driven integration and the AFT step of harmonic balance.

The laws load on first use of their name (a Jenkins-only analysis does not load the
Mindlin or Greenwood-Williamson kernels).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

#: Public name -> module that defines it (imported on first use).
_LAZY = {
    "ContactLaw": "base", "LawStep": "base",
    "Coulomb": "coulomb", "ForceSet": "coulomb", "coulomb_force_set": "coulomb",
    "friction_coefficient": "coulomb",
    "CubicSpring": "cubic",
    "Contact3D": "element3d",
    "Iwan": "iwan",
    "Jenkins": "jenkins",
    "CattaneoMindlin": "mindlin", "RotationalMindlin": "mindlin",
    "effective_modulus": "mindlin", "hertz_radius": "mindlin", "shear_modulus": "mindlin",
    "tangential_compliance": "mindlin",
    "GreenwoodWilliamson": "rough", "RoughRotationalJoint": "rough", "gw_integral": "rough",
    "height_classes": "rough",
}

__all__ = sorted(_LAZY)

if TYPE_CHECKING:  # for type checkers and IDEs; at run time the names load lazily
    from fricdamp.contact.base import ContactLaw, LawStep  # noqa: F401
    from fricdamp.contact.coulomb import (  # noqa: F401
        Coulomb,
        ForceSet,
        coulomb_force_set,
        friction_coefficient,
    )
    from fricdamp.contact.cubic import CubicSpring  # noqa: F401
    from fricdamp.contact.element3d import Contact3D  # noqa: F401
    from fricdamp.contact.iwan import Iwan  # noqa: F401
    from fricdamp.contact.jenkins import Jenkins  # noqa: F401
    from fricdamp.contact.mindlin import (  # noqa: F401
        CattaneoMindlin,
        RotationalMindlin,
        effective_modulus,
        hertz_radius,
        shear_modulus,
        tangential_compliance,
    )
    from fricdamp.contact.rough import (  # noqa: F401
        GreenwoodWilliamson,
        RoughRotationalJoint,
        gw_integral,
        height_classes,
    )


def __getattr__(name: str):
    if name.startswith("__"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    if name in _LAZY:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
        globals()[name] = value          # later look-ups skip __getattr__
        return value
    try:        # submodules as attributes (``fricdamp.contact.jenkins``)
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
