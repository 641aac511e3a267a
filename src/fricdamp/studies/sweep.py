"""Parameter sweeps: evaluate a function over a grid, locally or on a Dask cluster, resumably.

:func:`sweep` calls ``fn(**params)`` at every point of a :class:`~fricdamp.studies.grid.Grid`
and gathers the scalar results into an :class:`xarray.Dataset` with one dimension per grid
parameter. Where the points run:

* ``serial=True``: one after the other in this process (no Dask needed);
* ``client=None`` (default): a local ``dask.distributed`` cluster of processes, one
  single-threaded worker per core (BLAS and OpenMP pools limited to one thread), closed at the
  end;
* ``client="tcp://host:port"`` or a ``distributed.Client``: the user's running cluster.

With ``store=DIR`` every finished point is written at once, atomically, to ``DIR/<key>.json``
where ``<key>`` is a hash of the point's parameters and of a *fingerprint* of the study
(the function's name and bound arguments, or the case file's content). Running the same study
again after a crash or Ctrl-C loads the stored points and computes only the missing ones; a
changed case changes the fingerprint, so no stale result is ever reused.

A point whose function raises does not stop the study: the exception's message is recorded
(``failed`` is 1 and the results are NaN at that point) and the other points go on. Failed
points are computed again on the next run unless ``retry_failed=False``.

Dask is imported only when a cluster is used, never at ``import fricdamp``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime as _dt
import functools
import hashlib
import inspect
import json
import logging
import math
import os
import pickle
import time
import traceback as _tb
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fricdamp.errors import CaseError, FricdampError
from fricdamp.studies.grid import Grid

log = logging.getLogger(__name__)

__all__ = [
    "PointRecord",
    "PointStore",
    "StudyError",
    "StudyInterrupted",
    "evaluate_point",
    "function_fingerprint",
    "open_client",
    "plot_sweep",
    "plot_variable",
    "plotted_variables",
    "point_key",
    "run_points",
    "save_sweep",
    "summarize",
    "sweep",
]

#: Variables that :func:`sweep` adds to every Dataset; a function may not return these names.
RESERVED = ("wall_time_s", "failed")

#: Environment of local Dask workers: one BLAS / OpenMP thread per single-threaded worker, so
#: two workers on two cores do not fight over four BLAS threads.
WORKER_ENV = {"OMP_NUM_THREADS": 1, "OPENBLAS_NUM_THREADS": 1, "MKL_NUM_THREADS": 1,
              "VECLIB_MAXIMUM_THREADS": 1, "NUMEXPR_NUM_THREADS": 1}


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
    The code of ``fn`` is not hashed: pass ``fingerprint=`` to :func:`sweep` (e.g. a version
    string) when a changed function must not reuse stored points.
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


# ------------------------------------------------------------------------------ clients
def _require_distributed():
    try:
        import distributed
    except ImportError:
        raise ImportError(
            "running a study on Dask needs the 'distributed' package, which is not installed: "
            "pip install 'fricdamp[dask]' (or pip install 'dask[distributed]'), or run the "
            "study serially (serial=True in Python, --serial on the command line)") from None
    return distributed


@contextlib.contextmanager
def open_client(client=None, *, serial: bool = False, n_workers: int | None = None
                ) -> Iterator:
    """Yield the ``distributed.Client`` a study runs on, or None for a serial run.

    Parameters
    ----------
    client : None, str or distributed.Client
        None starts a local cluster of ``n_workers`` processes (default ``os.cpu_count()``),
        one thread each, BLAS limited to one thread, on the loopback interface, without a
        dashboard, and closes it at the end. A string is a scheduler address
        (``tcp://host:port``): a client is connected to it and closed at the end (the cluster
        is left running). A Client is used as it is.
    serial : bool
        Yield None (no Dask at all).
    n_workers : int, optional
        Size of the local cluster.

    Raises
    ------
    ImportError
        ``distributed`` is not installed (the message says what to install).
    StudyError
        The scheduler cannot be reached.
    """
    if serial:
        if client is not None:
            raise StudyError("give either serial=True or a client / scheduler, not both")
        yield None
        return
    if client is not None and not isinstance(client, str):
        yield client
        return
    distributed = _require_distributed()
    if isinstance(client, str):
        try:
            c = distributed.Client(client, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise StudyError(f"cannot reach the Dask scheduler at {client!r}: {exc}. Is it "
                             "running (dask scheduler) and is the address right?") from None
        try:
            yield c
        finally:
            c.close()
        return
    import dask

    n = int(n_workers or os.cpu_count() or 1)
    if n < 1:
        raise StudyError(f"n_workers must be >= 1, got {n_workers}")
    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {})
    env.update(WORKER_ENV)
    with dask.config.set({"distributed.nanny.pre-spawn-environ": env}):
        cluster = distributed.LocalCluster(
            n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
            dashboard_address=None, silence_logs=logging.ERROR)
    try:
        c = distributed.Client(cluster)
        try:
            yield c
        finally:
            c.close()
    finally:
        cluster.close()


class _ClientSlot:
    """Opens the client (and a local cluster) only when a point must really be computed."""

    def __init__(self, client, serial: bool, n_workers: int | None):
        self.args = (client, serial, n_workers)
        self.stack = contextlib.ExitStack()
        self.opened = False
        self.client = None

    def get(self):
        if not self.opened:
            client, serial, n_workers = self.args
            self.client = self.stack.enter_context(open_client(client, serial=serial,
                                                               n_workers=n_workers))
            self.opened = True
        return self.client

    def __enter__(self):
        client, serial, _ = self.args
        if serial and client is not None:
            raise StudyError("give either serial=True or a client / scheduler, not both")
        return self

    def __exit__(self, *exc):
        return self.stack.__exit__(*exc)


# ----------------------------------------------------------------------------- running
class _Progress:
    """Progress over points: nothing, a tqdm bar (``True``) or a callback."""

    def __init__(self, progress, total: int | None, desc: str):
        self.callback = None
        self.bar = None
        self.done = 0
        self.total = total
        self.failed = 0
        if progress is True:
            import sys

            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, desc=desc, unit="point", file=sys.stderr,
                            dynamic_ncols=True)
        elif callable(progress):
            self.callback = progress
        elif progress not in (None, False):
            raise TypeError(f"progress must be None, True or a callable, got {progress!r}")

    def update(self, record: PointRecord) -> None:
        self.done += 1
        self.failed += not record.ok
        if self.bar is not None:
            self.bar.update(1)
            if self.failed:
                self.bar.set_postfix(failed=self.failed, refresh=False)
        if self.callback is not None:
            self.callback(record, self.done, self.total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _counts(records: Sequence[PointRecord | None], total: int) -> dict:
    done = [r for r in records if r is not None]
    return {
        "points_total": total,
        "points_computed": sum(not r.reused for r in done),
        "points_reused": sum(r.reused for r in done),
        "points_failed": [{"params": r.params, "error": r.error} for r in done if not r.ok],
    }


def run_points(fn: Callable, points: Sequence[Mapping], *, client=None,
               store: PointStore | None = None, fingerprint: str = "",
               progress=None, reserved: Sequence[str] = (), retry_failed: bool = True,
               desc: str = "points") -> list[PointRecord]:
    """Evaluate ``fn`` at ``points`` (reusing stored ones); the engine of sweeps and optimisers.

    Parameters
    ----------
    fn : callable
        ``fn(**point) -> Mapping[str, float]``.
    points : sequence of mapping
        The points, in order; repeated points are evaluated once.
    client : distributed.Client or None
        None evaluates in this process, one point after the other. (Internally also a lazy
        slot that starts a cluster only if some point is not stored.)
    store : PointStore, optional
        Stored points are reused; each new one is saved as soon as it is finished.
    fingerprint : str
        Study identity for the keys when there is no store.
    progress : None, True or callable
        ``True`` shows a tqdm bar; a callable receives ``(record, done, total)``.
    reserved : sequence of str
        Result names that are not allowed.
    retry_failed : bool
        Compute stored failures again (default) or reuse them.

    Returns
    -------
    list of PointRecord
        One per point, in the order of ``points``.

    Raises
    ------
    StudyInterrupted
        On Ctrl-C; every point finished before it is stored.
    """
    fp = store.fingerprint if store is not None else fingerprint
    keys = [point_key(fp, p) for p in points]
    records: list[PointRecord | None] = [None] * len(points)
    bar = _Progress(progress, len(points), desc)
    todo: dict[str, list[int]] = {}
    try:
        for i, key in enumerate(keys):
            if key in todo:
                todo[key].append(i)
                continue
            rec = store.load(key) if store is not None else None
            if rec is not None and (rec.ok or not retry_failed):
                records[i] = rec
                bar.update(rec)
            else:
                todo[key] = [i]

        def finish(rec: PointRecord) -> None:
            if store is not None:
                store.save(rec)
            for j in todo[rec.key]:
                records[j] = rec
                bar.update(rec)

        jobs = [(key, dict(points[idx[0]])) for key, idx in todo.items()]
        if isinstance(client, _ClientSlot):
            client = client.get() if jobs else None
        if client is None:
            for key, params in jobs:
                finish(evaluate_point(fn, key, params, reserved))
        else:
            _run_on_dask(client, fn, jobs, reserved, finish)
    except KeyboardInterrupt:
        log.warning("study interrupted; finished points are stored")
        raise StudyInterrupted(_counts(records, len(points))) from None
    finally:
        bar.close()
    # duplicates inside a batch count once as computed, the copies as reused
    out, seen = [], set()
    for rec in records:
        if rec.key in seen and not rec.reused:
            rec = dataclasses.replace(rec, reused=True)
        seen.add(rec.key)
        out.append(rec)
    return out


def _run_on_dask(client, fn, jobs, reserved, finish) -> None:
    from distributed import as_completed

    if not jobs:
        return
    futures = {}
    try:
        for key, params in jobs:
            fut = client.submit(evaluate_point, fn, key, params, tuple(reserved), pure=False)
            futures[fut] = (key, params)
        for fut in as_completed(list(futures)):
            key, params = futures[fut]
            try:
                rec = fut.result()
            except Exception as exc:  # the task itself was lost (worker died, cancelled...)
                rec = PointRecord(key=key, params=params, status="failed",
                                  error=f"{type(exc).__name__}: {exc}")
            finish(rec)
            fut.release()
    finally:
        pending = [f for f in futures if not f.done()]
        if pending:
            with contextlib.suppress(Exception):
                client.cancel(pending)


# ------------------------------------------------------------------------------- sweep
def _check_signature(fn: Callable, names: Sequence[str]) -> None:
    """Grid names must be parameters of ``fn`` and cover its required ones."""
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return
    params = sig.parameters.values()
    if any(p.kind is p.VAR_KEYWORD for p in params):
        return
    accepted = [p.name for p in params if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    Grid(tuple((n, np.zeros(1)) for n in names)).check_names(
        accepted, what=f"{getattr(fn, '__name__', 'the function')}()")
    missing = [p.name for p in params
               if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
               and p.default is p.empty and p.name not in names]
    if missing:
        raise CaseError(f"{getattr(fn, '__name__', 'the function')}() needs the parameter(s) "
                        f"{', '.join(missing)}, which the grid does not give")


def sweep(fn: Callable, grid, *, client=None, store: str | os.PathLike | None = None,
          serial: bool = False, progress=None, fingerprint: str | None = None,
          retry_failed: bool = True, n_workers: int | None = None):
    """Evaluate ``fn`` at every point of ``grid``; return the results as a Dataset.

    Parameters
    ----------
    fn : callable
        ``fn(**params) -> Mapping[str, float]``, a top-level (picklable) function for Dask.
        Non-scalar returned values are left out (their names are listed in the attribute
        ``ignored_results``).
    grid : Grid, mapping name -> values, or list of ``"name=start:stop:num"`` strings
        The parameters; see :mod:`fricdamp.studies.grid`.
    client : None, str or distributed.Client
        Where to run (see :func:`open_client`); ignored with ``serial=True``.
    store : path, optional
        Folder of finished points (resume); see :class:`PointStore`.
    serial : bool
        Run in this process, one point after the other, without Dask.
    progress : None, True or callable
        ``True`` for a progress bar on stderr; a callable gets ``(record, done, total)``.
    fingerprint : str, optional
        Study identity in the point keys (default :func:`function_fingerprint`).
    retry_failed : bool
        Compute again points that failed in an earlier run (default), or reuse the failure.
    n_workers : int, optional
        Size of the local cluster (default: the number of cores).

    Returns
    -------
    xarray.Dataset
        Dimensions: the grid parameters (coordinates: their values), in grid order. One float
        variable per scalar result (NaN where a point failed or did not return it),
        ``wall_time_s`` (time of each evaluation where it ran) and ``failed`` (int8, 1 where
        the point failed). Attributes: ``points_total``, ``points_computed``,
        ``points_reused``, ``points_failed`` (a count), ``failures`` (JSON list of
        ``{"params", "error"}``), ``fingerprint``, ``function``, ``elapsed_s``,
        ``ignored_results``, ``created``. :func:`summarize` turns them into a dict.

    Raises
    ------
    CaseError
        Bad grid, or grid names that are not parameters of ``fn``.
    ImportError
        Dask is needed (no ``serial=True``) but ``distributed`` is not installed.
    StudyInterrupted
        Ctrl-C; finished points are stored, run again to finish.

    Examples
    --------
    >>> def square(x):
    ...     return {"y": x * x}
    >>> ds = sweep(square, ["x=0:2:3"], serial=True)
    >>> ds["y"].values.tolist()
    [0.0, 1.0, 4.0]
    """
    grid = Grid.coerce(grid)
    _check_signature(fn, grid.names)
    fp = fingerprint if fingerprint is not None else function_fingerprint(fn)
    st = PointStore(store, fp) if store is not None else None
    points = list(grid.points())
    t0 = time.perf_counter()
    with _ClientSlot(client, serial, n_workers) as c:  # no cluster if every point is stored
        records = run_points(fn, points, client=c, store=st, fingerprint=fp, progress=progress,
                             reserved=(*grid.names, *RESERVED), retry_failed=retry_failed,
                             desc="sweep")
    elapsed = time.perf_counter() - t0
    name = getattr(fn, "__qualname__", None) or type(fn).__qualname__
    return _to_dataset(grid, records, fingerprint=fp, function=name, elapsed_s=elapsed)


def _to_dataset(grid: Grid, records: Sequence[PointRecord], **attrs):
    import xarray as xr

    shape = grid.shape
    names: list[str] = []
    ignored: list[str] = []
    for rec in records:
        for n in rec.results:
            if n not in names:
                names.append(n)
        ignored.extend(n for n in rec.ignored if n not in ignored)
    data = {n: np.full(shape, np.nan) for n in names}
    wall = np.full(shape, np.nan)
    failed = np.zeros(shape, dtype=np.int8)
    for flat, rec in enumerate(records):
        idx = np.unravel_index(flat, shape)
        for n, v in rec.results.items():
            data[n][idx] = v
        wall[idx] = rec.wall_time_s
        failed[idx] = not rec.ok
    dims = grid.names
    variables = {n: (dims, a) for n, a in data.items()}
    variables["wall_time_s"] = (dims, wall, {"units": "s",
                                             "long_name": "wall time of the evaluation"})
    variables["failed"] = (dims, failed, {"long_name": "1 where the evaluation failed"})
    counts = _counts(records, grid.size)
    ds = xr.Dataset(variables, coords={n: (n, v) for n, v in grid.axes})
    ds.attrs.update({
        "study": "sweep",
        "points_total": counts["points_total"],
        "points_computed": counts["points_computed"],
        "points_reused": counts["points_reused"],
        "points_failed": len(counts["points_failed"]),
        "failures": json.dumps(counts["points_failed"]),
        "ignored_results": json.dumps(ignored),
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        **attrs,
    })
    return ds


def summarize(ds) -> dict:
    """The summary of a sweep Dataset (what ``summary.json`` holds).

    Returns
    -------
    dict
        ``points_total``, ``points_computed``, ``points_reused`` (ints), ``points_failed``
        (list of ``{"params", "error"}``, one per failed point), ``elapsed_s``,
        ``grid`` (name -> list of values), ``results`` (name -> min, max and the point of
        the minimum and maximum), ``fingerprint``, ``function``.
    """
    a = ds.attrs
    results = {}
    for name, var in ds.data_vars.items():
        if name == "failed":
            continue
        vals = np.asarray(var.values, float)
        if not np.any(np.isfinite(vals)):
            results[name] = {"min": None, "max": None}
            continue
        entry = {}
        for what, fn in (("min", np.nanargmin), ("max", np.nanargmax)):
            idx = np.unravel_index(fn(vals), vals.shape)
            entry[what] = float(vals[idx])
            entry[f"at_{what}"] = {d: float(ds[d].values[i]) for d, i in zip(var.dims, idx,
                                                                               strict=True)}
        results[name] = entry
    return {
        "study": a.get("study", "sweep"),
        "function": a.get("function"),
        "fingerprint": a.get("fingerprint"),
        "points_total": int(a.get("points_total", 0)),
        "points_computed": int(a.get("points_computed", 0)),
        "points_reused": int(a.get("points_reused", 0)),
        "points_failed": json.loads(a.get("failures", "[]")),
        "elapsed_s": a.get("elapsed_s"),
        "grid": {d: ds[d].values.tolist() for d in ds.dims},
        "ignored_results": json.loads(a.get("ignored_results", "[]")),
        "results": results,
    }


# ------------------------------------------------------------------------------ output
def plotted_variables(ds, *, max_figures: int = 40) -> list[str]:
    """Results worth a figure: every variable but ``failed`` that varies over the grid."""
    names = []
    for name in ds.data_vars:
        if name == "failed":
            continue
        vals = np.asarray(ds[name].values, float)
        finite = vals[np.isfinite(vals)]
        if finite.size and (np.ptp(finite) > 0 or finite.size < vals.size):
            names.append(str(name))
    return names[:max_figures]


def plot_variable(ds, name: str):
    """Figure of one result: a line over 1 parameter, heat maps over 2 or more.

    With more than two parameters, one heat map over the first two is drawn for each
    combination of the others (at most 9 panels). Failed points are marked in red, the
    minimum with a star.

    Returns
    -------
    matplotlib.figure.Figure or None
        None when more than 9 panels would be needed.
    """
    import matplotlib.pyplot as plt

    dims = [str(d) for d in ds[name].dims]
    var = ds[name]
    failed = np.asarray(ds["failed"].transpose(*dims).values, bool)
    if len(dims) == 1:
        fig, ax = plt.subplots(figsize=(6, 4))
        x = ds[dims[0]].values
        ax.plot(x, var.values, "o-")
        for xf in x[failed]:  # failed points: red vertical lines
            ax.axvline(xf, color="r", alpha=0.3, lw=1)
        ax.set_xlabel(dims[0])
        ax.set_ylabel(name)
        ax.ticklabel_format(style="sci", scilimits=(-3, 4))
        ax.grid(True, alpha=0.3)
    else:
        rest = dims[2:]
        combos = list(np.ndindex(*[ds.sizes[d] for d in rest])) if rest else [()]
        if len(combos) > 9:
            log.info("no figure of %s: %d panels would be needed", name, len(combos))
            return None
        ncol = min(3, len(combos))
        nrow = math.ceil(len(combos) / ncol)
        fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 4.2 * nrow), squeeze=False)
        vals_all = np.asarray(var.values, float)
        finite = vals_all[np.isfinite(vals_all)]
        vmin, vmax = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
        x, y = ds[dims[1]].values, ds[dims[0]].values
        for ax, combo in zip(axes.flat, combos, strict=False):
            sel = (slice(None), slice(None), *combo)
            z = vals_all[sel]
            mesh = ax.pcolormesh(x, y, z, shading="nearest", vmin=vmin, vmax=vmax,
                                 cmap="viridis")
            fz = failed[sel]
            if fz.any():
                yy, xx = np.nonzero(fz)
                ax.plot(x[xx], y[yy], "rx", ms=8, label="failed")
            if np.isfinite(z).any():
                iy, ix = np.unravel_index(np.nanargmin(z), z.shape)
                ax.plot(x[ix], y[iy], "w*", ms=12, mec="k", label="minimum")
            ax.set_xlabel(dims[1])
            ax.set_ylabel(dims[0])
            ax.ticklabel_format(style="sci", scilimits=(-3, 4))
            ax.legend(loc="best", fontsize=8, framealpha=0.6)
            if rest:
                ax.set_title(", ".join(f"{d}={ds[d].values[i]:g}"
                                       for d, i in zip(rest, combo, strict=True)), fontsize=9)
            fig.colorbar(mesh, ax=ax, label=name)
        for ax in list(axes.flat)[len(combos):]:
            ax.set_visible(False)
    fig.suptitle(f"{name}\nover {' x '.join(dims)}", fontsize=10)
    fig.tight_layout()
    return fig


def plot_sweep(ds, *, max_figures: int = 40) -> list:
    """Figures of a sweep: one per result that varies (:func:`plotted_variables`).

    Returns
    -------
    list of (filename, title, matplotlib.figure.Figure)
    """
    figs = []
    for name in plotted_variables(ds, max_figures=max_figures):
        fig = plot_variable(ds, name)
        if fig is not None:
            figs.append((f"sweep_{name}.png", f"{name} over {' x '.join(ds[name].dims)}", fig))
    return figs


def _report_markdown(summary: dict, figures: Sequence[tuple[str, str]], title: str) -> str:
    lines = [f"# {title}", ""]
    lines += ["| | |", "|---|---|"]
    lines += [f"| points | {summary['points_total']} |",
              f"| computed in this run | {summary['points_computed']} |",
              f"| reused from earlier runs | {summary['points_reused']} |",
              f"| failed | {len(summary['points_failed'])} |"]
    if summary.get("elapsed_s") is not None:
        lines.append(f"| elapsed | {summary['elapsed_s']:.3g} s |")
    lines += ["", "## Grid", ""]
    for name, vals in summary["grid"].items():
        shown = ", ".join(f"{v:g}" for v in vals[:12]) + (" ..." if len(vals) > 12 else "")
        lines.append(f"- `{name}` ({len(vals)} values): {shown}")
    lines += ["", "## Results", "", "| result | min | at | max | at |", "|---|---|---|---|---|"]
    for name, r in summary["results"].items():
        if r.get("min") is None:
            lines.append(f"| `{name}` | - | - | - | - |")
            continue
        def at(p):
            return ", ".join(f"{k}={v:g}" for k, v in p.items())
        lines.append(f"| `{name}` | {r['min']:.6g} | {at(r['at_min'])} | {r['max']:.6g} | "
                     f"{at(r['at_max'])} |")
    if summary["points_failed"]:
        lines += ["", "## Failed points", ""]
        for f in summary["points_failed"][:50]:
            p = ", ".join(f"{k}={v:g}" for k, v in f["params"].items())
            lines.append(f"- {p}: {f['error']}")
        if len(summary["points_failed"]) > 50:
            lines.append(f"- ... and {len(summary['points_failed']) - 50} more (summary.json)")
    if figures:
        lines += ["", "## Figures", ""]
        lines += [f"![{t}]({f})" for f, t in figures]
    return "\n".join(lines) + "\n"


def save_sweep(ds, out_dir: str | os.PathLike, *, figures: bool = True,
               extra: Mapping | None = None, title: str = "Parameter sweep") -> dict:
    """Write a sweep's ``sweep.nc``, ``summary.json``, figures and ``report.md`` into a folder.

    Every file is written atomically. ``extra`` entries are added to ``summary.json``.

    Returns
    -------
    dict
        The summary written (with ``files``: the names written in ``out_dir``).
    """
    from fricdamp.iofiles import save_figure, write_json, write_results, write_text

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary = summarize(ds)
    if extra:
        summary.update(extra)
    written = []
    if figures:
        import matplotlib.pyplot as plt

        for name in plotted_variables(ds):  # one at a time: never many figures open
            fig = plot_variable(ds, name)
            if fig is None:
                continue
            filename = f"sweep_{name}.png"
            save_figure(fig, out / filename)
            plt.close(fig)
            written.append((filename, f"{name} over {' x '.join(ds[name].dims)}"))
    write_results(out / "sweep.nc", ds)
    summary["files"] = {"results": "sweep.nc", "summary": "summary.json",
                        "report": "report.md", "figures": [f for f, _ in written]}
    write_json(out / "summary.json", summary)
    write_text(out / "report.md", _report_markdown(summary, written, title))
    return summary
