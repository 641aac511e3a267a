"""Cached numba kernels that load without numba's registry refresh (issue 13, a fast start).

``numba.njit(cache=True)`` loads a kernel's machine code from the on-disk cache on its first
call, but first "refreshes" its typing and target contexts: it imports and installs every
registry of numba (unicode, typed containers, random generators, jitclass, datetime, ...)
whether the cached code needs them or not. On the reference VM that refresh costs ~0.45 s of
CPU, the loading of a small cached kernel itself ~3 ms: for a harmonic-balance run from a
fresh process it was a quarter of the whole process.

The refresh is needed to *compile* (lowering looks up implementations in the registries),
not to rebuild cached machine code: :func:`njit` returns numba's dispatcher whose cache
loads the object code directly, after initialising numba's runtime (NRT: the allocation
symbols that the cached code links to). A cache miss (first run, changed source, other
CPU) falls through to numba's ordinary compilation, which refreshes the contexts itself, so
the compiled result is the same. If a numba version lacks the internals used here, the
dispatcher is left as numba made it (slower first call, same results).
"""

from __future__ import annotations

import numba

__all__ = ["fast_load", "njit"]


def _runtime_initialised(target_context) -> None:
    from numba.core.runtime import nrt

    nrt.rtsys.initialize(target_context)


def fast_load(dispatcher):
    """Make ``dispatcher`` (an ``njit(cache=True)`` function) load its cache without the
    registry refresh; returns it. Idempotent; a no-op for dispatchers without a cache."""
    cache = getattr(dispatcher, "_cache", None)
    load = getattr(cache, "_load_overload", None)
    guard = getattr(cache, "_guard_against_spurious_io_errors", None)
    if load is None or guard is None or getattr(cache, "_fricdamp_fast", False):
        return dispatcher

    def load_overload(sig, target_context):
        _runtime_initialised(target_context)
        with guard():
            return load(sig, target_context)
        return None     # the guard swallowed an I/O error: numba compiles

    cache.load_overload = load_overload
    cache._fricdamp_fast = True
    return dispatcher


def njit(*args, **options):
    """``numba.njit`` (``cache=True`` by default) with :func:`fast_load` applied."""
    options.setdefault("cache", True)
    if args and callable(args[0]):
        return fast_load(numba.njit(**options)(args[0]))

    def wrap(fn):
        return fast_load(numba.njit(*args, **options)(fn))

    return wrap
