"""The papers' systems, ready to run.

* :mod:`fricdamp.models.blade_damper` -- paper 000, planar blade-damper stick-slip model
  (:class:`BladeDamperParameters`, :class:`BladeDamperSystem`); its analyses (pull-off
  curves, eigenfrequencies, time response, design study) are in
  :mod:`fricdamp.models.blade_damper_analyses`.
"""

from fricdamp.models.blade_damper import BladeDamperParameters, BladeDamperSystem

__all__ = ["BladeDamperParameters", "BladeDamperSystem"]
