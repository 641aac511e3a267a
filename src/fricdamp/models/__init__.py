"""The papers' systems, ready to run.

* :mod:`fricdamp.models.blade_damper.model` -- paper 000, planar blade-damper stick-slip model
  (:class:`BladeDamperParameters`, :class:`BladeDamperSystem`); its analyses (pull-off
  curves, eigenfrequencies, time response, design study) are in
  :mod:`fricdamp.models.blade_damper.studies`.
"""

from fricdamp.models.blade_damper.model import BladeDamperParameters, BladeDamperSystem

__all__ = ["BladeDamperParameters", "BladeDamperSystem"]
