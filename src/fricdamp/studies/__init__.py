"""Design studies: parameter sweeps and bounded optimisation, locally or on a Dask cluster.

* :func:`sweep` evaluates ``fn(**params)`` over a grid and returns an ``xarray.Dataset`` with
  one dimension per parameter; :func:`save_sweep` writes ``sweep.nc``, ``summary.json``,
  figures and a report.
* :func:`optimize` minimises or maximises one result inside bounds (SciPy), on the same
  evaluation engine.
* Both run on a local Dask cluster by default, on the user's scheduler with
  ``client="tcp://host:port"``, or in this process with ``serial=True``; with ``store=DIR``
  each finished point is saved at once and a rerun computes only the missing points.

Dask is imported only when a study runs on it.
"""

from fricdamp.studies.grid import Grid, apply_overrides, parse_axis, parse_bounds, resolve_parameter
from fricdamp.studies.optimize import OptimizationResult, optimize, save_optimization
from fricdamp.studies.sweep import (
    PointRecord,
    PointStore,
    StudyError,
    StudyInterrupted,
    open_client,
    plot_sweep,
    run_points,
    save_sweep,
    summarize,
    sweep,
)

__all__ = [
    "Grid",
    "OptimizationResult",
    "PointRecord",
    "PointStore",
    "StudyError",
    "StudyInterrupted",
    "apply_overrides",
    "open_client",
    "optimize",
    "parse_axis",
    "parse_bounds",
    "plot_sweep",
    "resolve_parameter",
    "run_points",
    "save_optimization",
    "save_sweep",
    "summarize",
    "sweep",
]
