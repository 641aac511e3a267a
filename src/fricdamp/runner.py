"""Run a validated case: :mod:`fricdamp.registry` and the built-in analyses.

Importing this module registers every built-in case-file section: the generic analyses of
:mod:`fricdamp.cases` and the ``case``/``case_*`` modules of each system under
:mod:`fricdamp.models`. Every name of :mod:`fricdamp.registry` is available here too (the
registry, ``load_case``, ``run_case``, ...), so user code imports this module.
"""

from __future__ import annotations

import importlib as _importlib
import pkgutil as _pkgutil

import numpy as np

from fricdamp import registry as _registry
from fricdamp.registry import (  # noqa: F401 (re-exported)
    REGISTRY,
    AnalysisOutput,
    BuildContext,
    ComputedCase,
    Entry,
    ModelObject,
    NotAMechanicalSystemError,
    Registry,
    RunContext,
    RunOutcome,
    attachment_projection,
    build_system,
    compute_case,
    default_verdict,
    describe_system,
    load_builtin_case,
    load_case,
    register_analysis,
    register_contact,
    register_model,
    register_table,
    run_case,
    verdict_summary,
)

# the registry's private names too (``fricdamp.runner._x`` as before the split)
globals().update({_k: _v for _k, _v in vars(_registry).items()
                  if not (_k.startswith("__") and _k.endswith("__"))})
__all__ = [
    *_registry.__all__,
    "coulomb_loop_energy",
    "iwan_loop_energy",
    "jenkins_loop_energy",
    "register_closed_form",
    "run_forced_response",
    "run_free_decay",
    "run_hysteresis",
]


def builtin_case_modules() -> list[str]:
    """The modules that register the built-in case-file sections, in registration order:
    every public module of :mod:`fricdamp.cases` and every ``case``/``case_*`` module of a
    system subpackage of :mod:`fricdamp.models` (ordered by ``<system><suffix>``, the order
    of the former analyses package)."""
    import fricdamp.cases as cases
    import fricdamp.models as models

    found = []
    for info in _pkgutil.iter_modules(cases.__path__):
        if not info.name.startswith("_"):
            found.append((info.name, f"fricdamp.cases.{info.name}"))
    for system in _pkgutil.iter_modules(models.__path__):
        if not system.ispkg or system.name.startswith("_"):
            continue
        pkg = _importlib.import_module(f"fricdamp.models.{system.name}")
        for info in _pkgutil.iter_modules(pkg.__path__):
            if info.name == "case" or info.name.startswith("case_"):
                found.append((system.name + info.name[4:],
                              f"fricdamp.models.{system.name}.{info.name}"))
    return [mod for _, mod in sorted(found)]


def _import_analyses() -> None:
    """Import every module of :func:`builtin_case_modules` (each registers its tables)."""
    for mod in builtin_case_modules():
        _importlib.import_module(mod)


_import_analyses()
from fricdamp.cases.timedomain import (  # noqa: E402
    coulomb_loop_energy,
    jenkins_loop_energy,
    register_closed_form,
    run_forced_response,
    run_free_decay,
    run_hysteresis,
)


def iwan_loop_energy(law, amplitudes) -> np.ndarray:
    """Segalman's closed form of the Iwan joint's energy per symmetric cycle [J], shape
    (n_contacts, n_amplitudes): ``4 R A^(chi+3) / ((chi+2)(chi+3))`` in micro-slip
    (:meth:`fricdamp.contact.iwan.Iwan.continuum_energy`, the continuous density; the
    discretised law is within 0.5 % of it from ``30 min_ratio phi_max`` to ``phi_max``)."""
    return np.asarray(law.continuum_energy(np.asarray(amplitudes, float))).T


def _register_iwan_closed_form() -> None:
    from fricdamp.contact.iwan import Iwan

    register_closed_form(Iwan, iwan_loop_energy)


_register_iwan_closed_form()
