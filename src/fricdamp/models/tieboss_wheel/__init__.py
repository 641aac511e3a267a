"""The tieboss-wheel system:
paper 003, bladed wheel with tie-boss friction contacts (beam and solid).

Its model is :mod:`fricdamp.models.tieboss_wheel.model` (every name of it is available here,
so ``from fricdamp.models.tieboss_wheel import ...`` works as before the move); its
studies, case-file section (``case``) and private helpers are the other modules.
"""

import importlib as _importlib


def __getattr__(name: str):
    # the model's names, imported on first use (the case-file section does not
    # need the model to register itself)
    model = _importlib.import_module(f"{__name__}.model")
    try:
        return getattr(model, name)
    except AttributeError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
