"""Parameter sweeps: evaluate a function over a grid, locally or on a Dask cluster, resumably.

:func:`sweep` calls ``fn(**params)`` at every point of a :class:`~fricdamp.studies.grid.Grid`
and gathers the scalar results into an :class:`xarray.Dataset` with one dimension per grid
parameter. Where the points run:

* ``serial=True``: one after the other in this process (no Dask needed);
* ``client=None`` (default): a local ``dask.distributed`` cluster of processes, one
  single-threaded worker per core (BLAS and OpenMP pools limited to one thread, no profiler),
  closed at the end;
* ``client="tcp://host:port"`` or a ``distributed.Client``: the user's running cluster.

With ``store=DIR`` every finished point is written at once, atomically, to ``DIR/<key>.json``
where ``<key>`` is a hash of the point's parameters and of a *fingerprint* of the study
(the function's name and bound arguments, or the case file's content). Running the same study
again after a crash or Ctrl-C loads the stored points and computes only the missing ones; a
changed case changes the fingerprint, so no stale result is ever reused.

A point whose function raises does not stop the study: the exception's message is recorded
(``failed`` is 1 and the results are NaN at that point) and the other points go on. Failed
points are computed again on the next run unless ``retry_failed=False``.

The machinery lives in sibling modules, and every name is importable from here too:
:mod:`~fricdamp.studies.points` (records, the evaluation task, the point store),
:mod:`~fricdamp.studies.cluster` (:func:`open_client`), :mod:`~fricdamp.studies.engine`
(:func:`run_points`) and :mod:`~fricdamp.studies.figures` (:func:`plot_sweep`). This module
holds :func:`sweep`, :func:`summarize` and :func:`save_sweep`.

Dask is imported only when a cluster is used, never at ``import fricdamp``.
"""

from __future__ import annotations

import datetime as _dt
import inspect
import json
import os
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from fricdamp.errors import CaseError
from fricdamp.studies.cluster import WORKER_ENV, open_client
from fricdamp.studies.cluster import _ClientSlot as _ClientSlot
from fricdamp.studies.engine import _counts, run_points
from fricdamp.studies.engine import _Progress as _Progress
from fricdamp.studies.figures import plot_sweep, plot_variable, plotted_variables
from fricdamp.studies.grid import Grid
from fricdamp.studies.points import (
    RESERVED,
    PointRecord,
    PointStore,
    StudyError,
    StudyInterrupted,
    evaluate_point,
    function_fingerprint,
    point_key,
)

__all__ = [
    "RESERVED",
    "WORKER_ENV",
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
