"""The blade-damper system:
paper 000, planar blade-damper stick-slip model.

Its model is :mod:`fricdamp.models.blade_damper.model` (every name of it is available here,
so ``from fricdamp.models.blade_damper import ...`` works as before the move); its
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
