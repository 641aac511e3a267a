"""The blade damper's contact configurations (stick/slip/open of each contact) and the cached
system of a parameter set, shared by its studies (:mod:`fricdamp.models.blade_damper.studies`,
which re-exports them) and its periodic orbits (:mod:`fricdamp.models.blade_damper.orbits`).
"""

from __future__ import annotations

import numpy as np

from fricdamp.errors import ModelError
from fricdamp.models.blade_damper.model import BladeDamperParameters, BladeDamperSystem
from fricdamp.solvers.event_switch import OPEN

#: Names of the four configurations of the no-separation model (000 (1)-(4)), indexed by
#: :func:`configuration_codes` 0-3.
CONFIGURATIONS = ("stick/stick", "stick/slip", "slip/stick", "slip/slip")

#: :data:`CONFIGURATIONS` followed by those with a lifted-off contact (``release=True``;
#: contact mode ``OPEN``), indexed by :func:`configuration_codes` 4-8 (K1/K2).
RELEASED_CONFIGURATIONS = CONFIGURATIONS + ("open/stick", "open/slip", "stick/open",
                                            "slip/open", "open/open")

#: A released system's normal forces are compressive or zero (open); below this [N] they
#: are reported as a violation (the event location leaves round-off at a lift-off).
RELEASED_NORMAL_FORCE_TOL_N = 1e-6

#: Indices into :data:`RELEASED_CONFIGURATIONS` with at least one contact open.
OPEN_CONFIGURATIONS = (4, 5, 6, 7, 8)

# configuration index by (state of K1, state of K2), state 0 stick, 1 slip, 2 open
_TABLE = np.array([[0, 1, 6], [2, 3, 7], [4, 5, 8]])


def _system(params, *, release: bool | None = None,
            restitution: float | None = None) -> BladeDamperSystem:
    """The system of ``params`` (a :class:`BladeDamperSystem` is taken as it is).

    ``release`` and ``restitution`` (None: the system's own, bilateral for parameters) set
    the unilateral contacts; a system with other settings is rebuilt with them, keeping its
    other options.
    """
    if isinstance(params, BladeDamperSystem):
        s = params
        rel = s.release if release is None else bool(release)
        e = s.restitution if restitution is None else restitution
        if rel == s.release and e == s.restitution:
            return s
        return _rebuild(s, s.params, release=rel, restitution=e)
    if params is None:
        params = BladeDamperParameters()
    if not isinstance(params, BladeDamperParameters):
        raise ModelError(f"params must be BladeDamperParameters, got {type(params).__name__}")
    return BladeDamperSystem(params, release=bool(release),
                             restitution=0.0 if restitution is None else restitution)


def _rebuild(system: BladeDamperSystem, params: BladeDamperParameters, *,
             release: bool | None = None, restitution: float | None = None
             ) -> BladeDamperSystem:
    """A new system of ``params`` with the options of ``system`` (contacts released or not,
    restitution, compiled paths), ``release``/``restitution`` overriding when given. (Not
    ``dataclasses.replace``: it would share the system's cache.)"""
    return BladeDamperSystem(
        params, compiled=system.compiled, compiled_phases=system.compiled_phases,
        release=system.release if release is None else bool(release),
        restitution=system.restitution if restitution is None else restitution,
        compiled_loop=system.compiled_loop)


# ===================================================================== time response
def configuration_codes(modes) -> np.ndarray:
    """Configuration index from contact modes (n_t, 2).

    0 stick/stick (3 DOF), 1 stick K1 / slip K2, 2 slip K1 / stick K2, 3 slip/slip (5 DOF)
    (:data:`CONFIGURATIONS`); with a lifted-off contact (mode ``OPEN``, ``release=True``)
    4 open/stick, 5 open/slip, 6 stick/open, 7 slip/open, 8 open/open
    (:data:`RELEASED_CONFIGURATIONS`).
    """
    m = np.asarray(modes)
    if m.size == 0:
        return np.zeros(m.shape[:1], dtype=int)
    state = np.where(m == OPEN, 2, (m != 0).astype(int))
    return _TABLE[state[:, 0], state[:, 1]].astype(int)


def time_in_configuration(t, modes, *, release: bool = False) -> dict:
    """Time [s] spent in each configuration of a run sampled at ``t`` (n_t,) with contact
    modes (n_t, 2) (the mode of a sample holds until the next one): keys
    :data:`CONFIGURATIONS`, and with ``release`` (or when a contact opened) all of
    :data:`RELEASED_CONFIGURATIONS`."""
    conf = configuration_codes(modes)
    dt = np.diff(np.asarray(t, dtype=float))
    names = (RELEASED_CONFIGURATIONS if release or (conf.size and conf.max() > 3)
             else CONFIGURATIONS)
    return {name: float(dt[conf[:-1] == k].sum()) for k, name in enumerate(names)}


def open_fraction(tic: dict) -> float:
    """Fraction of the time of ``tic`` (a :func:`time_in_configuration` dict) during which a
    contact is open (0 when no open configuration is listed; NaN for no time)."""
    total = sum(v for v in tic.values() if np.isfinite(v))
    if not total > 0:
        return float("nan") if not tic else 0.0
    return float(sum(tic.get(RELEASED_CONFIGURATIONS[k], 0.0)
                     for k in OPEN_CONFIGURATIONS) / total)
