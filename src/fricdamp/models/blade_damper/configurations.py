"""The blade damper's contact configurations (stick/slip of each contact) and the cached
system of a parameter set, shared by its studies (:mod:`fricdamp.models.blade_damper.studies`,
which re-exports them) and its periodic orbits (:mod:`fricdamp.models.blade_damper.orbits`).
"""

from __future__ import annotations

import numpy as np

from fricdamp.errors import ModelError
from fricdamp.models.blade_damper.model import BladeDamperParameters, BladeDamperSystem

#: Names of the four configurations, indexed by :func:`configuration_codes` (000 (1)-(4)).
CONFIGURATIONS = ("stick/stick", "stick/slip", "slip/stick", "slip/slip")


def _system(params) -> BladeDamperSystem:
    if isinstance(params, BladeDamperSystem):
        return params
    if params is None:
        params = BladeDamperParameters()
    if not isinstance(params, BladeDamperParameters):
        raise ModelError(f"params must be BladeDamperParameters, got {type(params).__name__}")
    return BladeDamperSystem(params)


# ===================================================================== time response
def configuration_codes(modes) -> np.ndarray:
    """Configuration index (into :data:`CONFIGURATIONS`) from contact modes (n_t, 2).

    0 stick/stick (3 DOF), 1 stick K1 / slip K2, 2 slip K1 / stick K2, 3 slip/slip (5 DOF).
    """
    m = np.asarray(modes)
    return (2 * (m[:, 0] != 0) + (m[:, 1] != 0)).astype(int)
