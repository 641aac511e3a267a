"""Study points: their records, the task that evaluates one, and the resumable store.

* :class:`PointRecord` is the outcome of one evaluation ``fn(**params)``;
  :func:`evaluate_point` computes it (the task sent to Dask workers) and turns an exception
  into a failed record, so one bad point never stops a study.
* :class:`PointStore` keeps every finished point in ``DIR/<key>.json``, written atomically;
  ``<key>`` (:func:`point_key`) hashes the point's parameters and a *fingerprint* of the study
  (:func:`function_fingerprint`: the function's name and bound arguments, or the case file's
  content), so a changed study never reuses a stale point.
* :class:`StudyError` and :class:`StudyInterrupted` are the errors of the studies.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import functools
import hashlib
import json
import logging
import math
import os
import pickle
import time
import traceback as _tb
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fricdamp.errors import FricdampError

log = logging.getLogger(__name__)

__all__ = [
    "RESERVED",
    "PointRecord",
    "PointStore",
    "StudyError",
    "StudyInterrupted",
    "evaluate_point",
    "function_fingerprint",
    "point_key",
]

#: Variables that :func:`~fricdamp.studies.sweep.sweep` adds to every Dataset; a function may
#: not return these names.
RESERVED = ("wall_time_s", "failed")


class StudyError(FricdampError, RuntimeError):
    """A study cannot run (scheduler unreachable, every evaluation failed, ...)."""


class StudyInterrupted(KeyboardInterrupt):
    """Ctrl-C (or SIGTERM turned into it) stopped a study; finished points are stored.

    Attributes
    ----------
    counts : dict
        ``points_total``, ``points_computed``, ``points_reused`` and ``points_failed`` (a
        list) at the time of the interruption.
    """

    def __init__(self, counts: dict):
        self.counts = counts
        done = counts["points_computed"] + counts["points_reused"]
        super().__init__(f"study interrupted after {done} of {counts['points_total']} points; "
                         "run it again to compute only the missing ones")


# ----------------------------------------------------------------------------- records
@dataclass(frozen=True)
class PointRecord:
    """The outcome of one evaluation.

    Attributes
    ----------
    key : str
        Hash of the fingerprint and the parameters (the file name in a store).
    params : dict of str -> float
        The point.
    status : {"ok", "failed"}
    results : dict of str -> float
        Scalar results (empty when failed).
    error : str or None
        ``"ExceptionType: message"`` of a failed point.
    traceback : str or None
        The failed point's traceback (kept in its file, for debugging).
    wall_time_s : float
        Wall time of the call ``fn(**params)`` [s] where it ran.
    ignored : tuple of str
        Returned names that were not scalars (arrays, strings), left out of the results.
    reused : bool
        Loaded from a store rather than computed in this run.
    """

    key: str
    params: dict
    status: str
    results: dict = field(default_factory=dict)
    error: str | None = None
    traceback: str | None = None
    wall_time_s: float = math.nan
    ignored: tuple = ()
    reused: bool = False

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_json(self, fingerprint: str) -> dict:
        return {"key": self.key, "fingerprint": fingerprint, "params": self.params,
                "status": self.status,
                "results": {k: (v if math.isfinite(v) else None) for k, v in
                            self.results.items()},
                "error": self.error, "traceback": self.traceback,
                "wall_time_s": self.wall_time_s if math.isfinite(self.wall_time_s) else None,
                "ignored": list(self.ignored),
                "finished": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")}

    @classmethod
    def from_json(cls, data: Mapping) -> PointRecord:
        def num(v):
            return math.nan if v is None else float(v)

        return cls(key=str(data["key"]), params=dict(data["params"]),
                   status=str(data["status"]),
                   results={str(k): num(v) for k, v in data.get("results", {}).items()},
                   error=data.get("error"), traceback=data.get("traceback"),
                   wall_time_s=num(data.get("wall_time_s")),
                   ignored=tuple(data.get("ignored", ())), reused=True)


def _scalar(value) -> float | None:
    if isinstance(value, (bool, np.bool_, int, float, np.integer, np.floating)):
        return float(value)
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "biuf":
        return float(value)
    return None


def evaluate_point(fn: Callable, key: str, params: Mapping, reserved: Sequence[str] = ()
                   ) -> PointRecord:
    """Call ``fn(**params)`` and return its record; an exception becomes a failed record.

    This is the task sent to Dask workers (a top-level function, so it pickles by reference).

    Parameters
    ----------
    fn : callable
        ``fn(**params) -> Mapping[str, float]``.
    key : str
        The point's key.
    params : mapping
        Keyword arguments.
    reserved : sequence of str
        Names the results may not use (the grid's parameters and :data:`RESERVED`).
    """
    t0 = time.perf_counter()
    try:
        out = fn(**params)
        if not isinstance(out, Mapping):
            raise TypeError(f"the study function must return a mapping result name -> number, "
                            f"got {type(out).__name__}")
        results, ignored = {}, []
        for name, value in out.items():
            x = _scalar(value)
            if x is None:
                ignored.append(str(name))
                continue
            if str(name) in reserved:
                raise ValueError(f"result name {name!r} is reserved (it is a grid parameter or "
                                 f"one of {', '.join(RESERVED)}); rename it")
            results[str(name)] = x
    except Exception as exc:  # a failing point must not stop the study
        return PointRecord(key=key, params=dict(params), status="failed",
                           error=f"{type(exc).__name__}: {exc}",
                           traceback="".join(_tb.format_exception(exc))[-4000:],
                           wall_time_s=time.perf_counter() - t0)
    return PointRecord(key=key, params=dict(params), status="ok", results=results,
                       wall_time_s=time.perf_counter() - t0, ignored=tuple(ignored))


# ------------------------------------------------------------------------------- store
def _canonical(obj) -> bytes:
    """Stable bytes of ``obj`` for hashing (JSON with sorted keys, else pickle)."""
    from fricdamp.iofiles import to_jsonable

    try:
        return json.dumps(to_jsonable(obj), sort_keys=True, allow_nan=True).encode()
    except (TypeError, ValueError):
        return pickle.dumps(obj, protocol=4)


def function_fingerprint(fn: Callable) -> str:
    """Identity of a study function for the point keys.

    ``fn.fingerprint`` if the callable defines it (case runners do: a hash of the case), else
    ``module.qualname`` plus a hash of the bound arguments of a :func:`functools.partial`.
    The code of ``fn`` is not hashed: pass ``fingerprint=`` to
    :func:`~fricdamp.studies.sweep.sweep` (e.g. a version string) when a changed function must
    not reuse stored points.
    """
    fp = getattr(fn, "fingerprint", None)
    if isinstance(fp, str):
        return fp
    if isinstance(fn, functools.partial):
        inner = function_fingerprint(fn.func)
        digest = hashlib.sha256(_canonical([list(fn.args), dict(fn.keywords)])).hexdigest()
        return f"{inner}|{digest[:16]}"
    module = getattr(fn, "__module__", None) or type(fn).__module__
    name = getattr(fn, "__qualname__", None)
    if name is None:  # a callable instance: its class and its state
        name = type(fn).__qualname__
        with contextlib.suppress(Exception):
            name += "|" + hashlib.sha256(pickle.dumps(fn, protocol=4)).hexdigest()[:16]
    return f"{module}.{name}"


def point_key(fingerprint: str, params: Mapping) -> str:
    """Stable hash of a study fingerprint and a point (values compared to 12 digits)."""
    norm = {str(k): format(float(v), ".12g") for k, v in params.items()}
    text = json.dumps({"fingerprint": fingerprint, "params": norm}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


class PointStore:
    """A folder of finished points, one JSON file each, written atomically.

    Parameters
    ----------
    directory : path
        Created if needed.
    fingerprint : str
        Identity of the study; part of every key.
    """

    def __init__(self, directory: str | os.PathLike, fingerprint: str):
        self.directory = Path(directory)
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise StudyError(f"cannot create the point store {str(self.directory)!r}: "
                             f"{exc}") from None
        self.fingerprint = fingerprint

    def key(self, params: Mapping) -> str:
        return point_key(self.fingerprint, params)

    def path(self, key: str) -> Path:
        return self.directory / f"{key}.json"

    def load(self, key: str) -> PointRecord | None:
        """The stored record of ``key``, or None (missing, unreadable or another study's)."""
        path = self.path(key)
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            log.warning("ignoring unreadable point file %s (%s); it will be computed again",
                        path, exc)
            return None
        if data.get("fingerprint") != self.fingerprint or data.get("key") != key:
            return None
        try:
            return PointRecord.from_json(data)
        except (KeyError, TypeError, ValueError) as exc:
            log.warning("ignoring malformed point file %s (%s)", path, exc)
            return None

    def save(self, record: PointRecord) -> Path:
        """Write ``record`` atomically (temporary file, fsync, rename)."""
        from fricdamp.iofiles import write_json

        return write_json(self.path(record.key), record.to_json(self.fingerprint), indent=1)

    def __len__(self) -> int:
        return sum(1 for _ in self.directory.glob("*.json"))

