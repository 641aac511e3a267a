"""Bounded optimisation of one scalar result over design parameters, on the sweep machinery.

:func:`optimize` minimises (or maximises) one result of ``fn(**params)`` over a box of
parameters with SciPy, evaluating the function exactly as :func:`~fricdamp.studies.sweep`
does: through :func:`~fricdamp.studies.sweep.run_points`, so points run in parallel on a Dask
cluster (local by default), every finished evaluation is stored at once when ``store`` is given,
and a failing evaluation does not stop the search (it counts as +inf). Every evaluation is kept
in the history.

Methods:

* ``"differential_evolution"`` (default): SciPy's global, derivative-free search. Each
  generation (``popsize * n_params`` candidates) is one batch evaluated in parallel
  (``vectorized=True``, deferred updating); no gradient is needed, which suits friction
  responses (kinks where contacts change between stick and slip). With a fixed ``seed`` a
  rerun asks for the same points, so an interrupted optimisation resumes from its store: the
  stored evaluations are replayed and only the missing ones computed.
* ``"nelder-mead"``: SciPy's bounded simplex, one evaluation at a time (cheap local
  refinement; run serially unless a client is given).

Parameters are scaled to the unit box internally, so parameters of very different magnitudes
(a mass in kg and an angle in degrees) are treated alike.
"""

from __future__ import annotations

import inspect
import json
import math
import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fricdamp.errors import CaseError
from fricdamp.results import ResultMixin
from fricdamp.studies.grid import check_bounds
from fricdamp.studies.sweep import (
    RESERVED,
    PointRecord,
    PointStore,
    StudyError,
    _check_signature,
    _ClientSlot,
    _Progress,
    function_fingerprint,
    run_points,
)

__all__ = ["OptimizationResult", "optimize", "resolve_result_name", "save_optimization"]

METHODS = {"differential_evolution": "differential_evolution", "de": "differential_evolution",
           "nelder-mead": "nelder-mead", "nelder_mead": "nelder-mead", "nm": "nelder-mead"}


@dataclass(frozen=True, repr=False)
class OptimizationResult(ResultMixin):
    """Result of :func:`optimize`.

    Attributes
    ----------
    x : dict of str -> float
        Best point found.
    objective : str
        Name of the optimised result.
    value : float
        Its value at ``x`` (as returned by the function, not negated for maximisation).
    results : dict of str -> float
        Every scalar result at ``x``.
    success : bool
        The optimiser converged and ``value`` is finite.
    message : str
        The optimiser's message.
    method : str
    sense : {"minimize", "maximize"}
    n_evaluations, n_computed, n_reused, n_failed : int
        Evaluations asked for, computed in this run, loaded from the store, failed.
    history : xarray.Dataset
        Dimension ``evaluation`` (in the order asked): one variable per parameter, per scalar
        result, ``objective``, ``best_so_far``, ``wall_time_s``, ``failed``, ``reused`` and
        ``batch`` (generation of differential evolution, call number of Nelder-Mead).
    failures : list of dict
        ``{"params", "error"}`` of each failed evaluation.
    elapsed_s : float
        Wall time of the optimisation [s].
    """

    x: dict
    objective: str
    value: float
    results: dict
    success: bool
    message: str
    method: str
    sense: str
    n_evaluations: int
    n_computed: int
    n_reused: int
    n_failed: int
    history: object
    failures: list
    elapsed_s: float

    def to_xarray(self):
        """The evaluation history, every floating-point variable with a ``units`` attribute:
        the unit a parameter or result name implies by its suffix (``_m``, ``_N``, ``_hz``,
        ... as in case files; ``"1"`` without one), ``wall_time_s`` in s."""
        from fricdamp.case import unit_of

        ds = self.history.copy()
        obj_unit = unit_of(self.objective) or "1"
        for name in ds.variables:
            var = ds[name]
            if var.dtype.kind != "f" or "units" in var.attrs:
                continue
            unit = obj_unit if name in ("objective", "best_so_far") else (
                unit_of(str(name)) or "1")
            ds[name].attrs["units"] = unit
        return ds

    def _judge(self):
        from fricdamp.results import status_verdict

        reasons = ()
        if self.n_failed:
            reasons = (f"{self.n_failed} of {self.n_evaluations} evaluations failed (see "
                       f"failures): the optimum was searched around them",)
        return status_verdict(self.success, self.message, {}, reasons=reasons)

    def plot(self, ax=None):
        """Objective of every evaluation and the best so far; returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4))
        h = self.history
        ax.plot(h["evaluation"], h["objective"], ".", alpha=0.5, label="evaluations")
        ax.plot(h["evaluation"], h["best_so_far"], "-", label="best so far")
        ax.set_xlabel("evaluation")
        ax.set_ylabel(self.objective)
        ax.legend()
        ax.grid(True, alpha=0.3)
        return ax

    def summary(self) -> dict:
        """JSON-able summary (what ``optimum.json`` holds)."""
        return {"objective": self.objective, "sense": self.sense, "method": self.method,
                "x": self.x, "value": self.value, "results": self.results,
                "success": self.success, "message": self.message,
                "n_evaluations": self.n_evaluations, "n_computed": self.n_computed,
                "n_reused": self.n_reused, "n_failed": self.n_failed,
                "points_failed": self.failures, "elapsed_s": self.elapsed_s}


def resolve_result_name(name: str, available) -> str:
    """Find result ``name`` among ``available``: exact, or the one ending in ``__name``.

    Case studies prefix each result with its analysis (``forced_response__amplitude_m``); the
    bare key is accepted when only one analysis has it.
    """
    available = list(available)
    if name in available:
        return name
    hits = [a for a in available if a.endswith(f"__{name}")]
    if len(hits) == 1:
        return hits[0]
    if len(hits) > 1:
        raise CaseError(f"result {name!r} is ambiguous: {', '.join(hits)}; give the full name")
    import difflib

    close = difflib.get_close_matches(name, available, n=1, cutoff=0.5)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    raise CaseError(f"the study function returns no result {name!r}{hint}; results: "
                    f"{', '.join(available) or 'none'}")


class _StopSearch(Exception):
    """Carries an input error (CaseError is a ValueError) through SciPy, which would wrap it."""

    def __init__(self, error: Exception):
        super().__init__(str(error))
        self.error = error


class _Evaluator:
    """Objective on the unit box, evaluated through run_points; keeps the history."""

    def __init__(self, fn, bounds, objective, sign, client, store, fingerprint, bar,
                 retry_failed):
        self.fn = fn
        self.names = list(bounds)
        self.lo = np.array([b[0] for b in bounds.values()])
        self.hi = np.array([b[1] for b in bounds.values()])
        self.objective = objective
        self.key = None  # resolved result name
        self.sign = sign
        self.client = client
        self.store = store
        self.fingerprint = fingerprint
        self.bar = bar
        self.retry_failed = retry_failed
        self.history: list[tuple[int, PointRecord]] = []
        self.batch = 0

    def params(self, u) -> dict:
        x = self.lo + np.clip(u, 0.0, 1.0) * (self.hi - self.lo)
        return {n: float(v) for n, v in zip(self.names, x, strict=True)}

    def value(self, rec: PointRecord) -> float:
        if not rec.ok:
            return math.inf
        if self.key is None:
            self.key = resolve_result_name(self.objective, rec.results)
        v = rec.results.get(self.key, math.nan)
        return self.sign * v if math.isfinite(v) else math.inf

    def __call__(self, u):
        u = np.asarray(u, float)
        batch = u[:, None] if u.ndim == 1 else u  # (n_params, S)
        points = [self.params(batch[:, s]) for s in range(batch.shape[1])]
        records = run_points(self.fn, points, client=self.client, store=self.store,
                             fingerprint=self.fingerprint,
                             progress=lambda rec, done, total: self.bar.update(rec),
                             reserved=(*self.names, *RESERVED), retry_failed=self.retry_failed)
        self.history.extend((self.batch, r) for r in records)
        self.batch += 1
        try:
            vals = np.array([self.value(r) for r in records])
        except CaseError as exc:
            raise _StopSearch(exc) from None
        return vals if u.ndim > 1 else float(vals[0])


def optimize(fn: Callable, bounds: Mapping[str, tuple[float, float]], *,
             minimize: str | None = None, maximize: str | None = None,
             method: str = "differential_evolution", client=None,
             store: str | os.PathLike | None = None, serial: bool = False, progress=None,
             fingerprint: str | None = None, maxiter: int | None = None,
             popsize: int = 8, tol: float = 0.01, seed: int = 0,
             x0: Mapping[str, float] | None = None, n_workers: int | None = None,
             retry_failed: bool = True) -> OptimizationResult:
    """Minimise (or maximise) one scalar result of ``fn(**params)`` inside bounds.

    Parameters
    ----------
    fn : callable
        ``fn(**params) -> Mapping[str, float]`` as for :func:`~fricdamp.studies.sweep`.
    bounds : mapping name -> (low, high)
        The design parameters and their ranges (``low < high``).
    minimize, maximize : str
        Name of the result to minimise or maximise (exactly one of them). A bare key such as
        ``amplitude_m`` matches a prefixed result ``<analysis>__amplitude_m``.
    method : {"differential_evolution", "nelder-mead"}
        Optimiser (see the module doc).
    client, serial, n_workers : as for :func:`~fricdamp.studies.sweep`
        Nelder-Mead evaluates one point at a time, so without a client it runs serially.
    store : path, optional
        Folder of finished evaluations: a rerun reuses them (resume after an interruption).
    progress : None, True or callable
        ``True`` shows a progress bar over evaluations.
    fingerprint : str, optional
        Study identity in the point keys (default :func:`function_fingerprint`).
    maxiter : int, optional
        Generations of differential evolution (default 30) or evaluations of Nelder-Mead
        (default ``200 * n_params``).
    popsize : int
        Differential evolution: candidates per generation = ``popsize * n_params``.
    tol : float
        Relative convergence tolerance (differential evolution: spread of the population's
        values; Nelder-Mead: simplex size in the unit box and objective change).
    seed : int
        Random seed of differential evolution (a fixed seed makes a rerun replay its store).
    x0 : mapping name -> float, optional
        Starting point (Nelder-Mead: the start, default the centre of the box; differential
        evolution: one member of the first population).

    Returns
    -------
    OptimizationResult

    Raises
    ------
    CaseError
        Bad bounds, unknown method, names that are not parameters of ``fn``, an objective that
        ``fn`` does not return.
    StudyError
        Every evaluation failed (the first error is quoted).
    StudyInterrupted
        Ctrl-C; finished evaluations are stored.
    """
    import scipy.optimize as so

    if (minimize is None) == (maximize is None):
        raise CaseError("give exactly one of minimize= or maximize= (the name of a result)")
    objective = minimize if minimize is not None else maximize
    sign = 1.0 if minimize is not None else -1.0
    key = str(method).lower().replace(" ", "_")
    if key not in METHODS:
        raise CaseError(f"unknown optimisation method {method!r}; use differential_evolution "
                        "or nelder-mead")
    method = METHODS[key]
    bounds = check_bounds(bounds)
    names = list(bounds)
    _check_signature(fn, names)
    if popsize < 1:
        raise CaseError(f"popsize must be >= 1, got {popsize}")
    if not 0 < tol < 1:
        raise CaseError(f"tol must lie in (0, 1), got {tol}")
    if maxiter is not None and maxiter < 1:
        raise CaseError(f"maxiter must be >= 1, got {maxiter}")
    u0 = None
    if x0 is not None:
        unknown = set(x0) - set(names)
        if unknown or set(x0) != set(names):
            raise CaseError(f"x0 must give every parameter {names}, got {sorted(x0)}")
        u0 = np.array([(x0[n] - bounds[n][0]) / (bounds[n][1] - bounds[n][0]) for n in names])
        if np.any((u0 < 0) | (u0 > 1)):
            raise CaseError(f"x0 {dict(x0)} lies outside the bounds {bounds}")
    fp = fingerprint if fingerprint is not None else function_fingerprint(fn)
    st = PointStore(store, fp) if store is not None else None
    if method == "nelder-mead" and client is None:
        serial = True  # one point at a time: a local cluster would only add latency

    t0 = time.perf_counter()
    bar = _Progress(progress, None, "optimize")
    try:
        with _ClientSlot(client, serial, n_workers) as c:
            ev = _Evaluator(fn, bounds, objective, sign, c, st, fp, bar, retry_failed)
            with np.errstate(invalid="ignore", over="ignore"):
                if method == "differential_evolution":
                    kw = {"rng": seed} if "rng" in inspect.signature(
                        so.differential_evolution).parameters else {"seed": seed}
                    res = so.differential_evolution(
                        ev, [(0.0, 1.0)] * len(names), maxiter=maxiter or 30, popsize=popsize,
                        tol=tol, polish=False, vectorized=True, updating="deferred", x0=u0,
                        init="latinhypercube", **kw)
                else:
                    res = so.minimize(
                        ev, u0 if u0 is not None else np.full(len(names), 0.5),
                        method="Nelder-Mead", bounds=[(0.0, 1.0)] * len(names),
                        options={"maxfev": maxiter or 200 * len(names), "xatol": tol,
                                 "fatol": 0.0, "adaptive": len(names) > 2})
    except _StopSearch as stop:
        raise stop.error from None
    finally:
        bar.close()
    elapsed = time.perf_counter() - t0
    return _result(ev, res, method, "minimize" if sign > 0 else "maximize", elapsed)


def _result(ev: _Evaluator, res, method: str, sense: str, elapsed: float) -> OptimizationResult:
    import xarray as xr

    records = [r for _, r in ev.history]
    failures = [{"params": r.params, "error": r.error} for r in records if not r.ok]
    if not any(r.ok for r in records):
        first = failures[0]["error"] if failures else "no evaluation"
        raise StudyError(f"every one of the {len(records)} evaluations failed; the first: "
                         f"{first}")
    vals = np.array([ev.value(r) for r in records])
    if not np.any(np.isfinite(vals)):
        raise StudyError(f"no evaluation gave a finite {ev.objective!r}")
    best = int(np.argmin(vals))  # first evaluation of the best value
    rec = records[best]
    n = len(records)
    results = sorted({k for r in records for k in r.results}, key=lambda k: (k != ev.key, k))
    data = {p: ("evaluation", np.array([r.params[p] for r in records])) for p in ev.names}
    for k in results:
        data[k] = ("evaluation", np.array([r.results.get(k, np.nan) for r in records]))
    obj = np.array([r.results.get(ev.key, np.nan) if r.ok else np.nan for r in records])
    data["objective"] = ("evaluation", obj, {"result": ev.key, "sense": sense})
    data["best_so_far"] = ("evaluation", ev.sign * np.minimum.accumulate(vals))
    data["wall_time_s"] = ("evaluation", np.array([r.wall_time_s for r in records]),
                           {"units": "s"})
    data["failed"] = ("evaluation", np.array([not r.ok for r in records], np.int8))
    data["reused"] = ("evaluation", np.array([r.reused for r in records], np.int8))
    data["batch"] = ("evaluation", np.array([b for b, _ in ev.history], np.int32))
    history = xr.Dataset(data, coords={"evaluation": np.arange(n)},
                         attrs={"study": "optimize", "method": method, "objective": ev.key,
                                "sense": sense, "fingerprint": ev.fingerprint,
                                "bounds": json.dumps({k: [float(ev.lo[i]), float(ev.hi[i])]
                                                      for i, k in enumerate(ev.names)})})
    # reused: loaded from the store, or a repeat of a point already asked in this run
    reused = sum(r.reused for r in records)
    return OptimizationResult(
        x=dict(rec.params), objective=ev.key, value=float(rec.results[ev.key]),
        results=dict(rec.results), success=bool(res.success) and bool(np.isfinite(vals[best])),
        message=str(res.message), method=method, sense=sense, n_evaluations=n,
        n_computed=n - reused, n_reused=reused, n_failed=len(failures), history=history,
        failures=failures, elapsed_s=elapsed)


def save_optimization(result: OptimizationResult, out_dir: str | os.PathLike, *,
                      figures: bool = True) -> dict:
    """Write ``optimum.json``, ``history.nc``, ``history.csv`` and figures into ``out_dir``.

    Figures: the objective of every evaluation with the best so far, and (two parameters)
    the evaluated points coloured by the objective with the optimum marked.

    Returns
    -------
    dict
        The summary written to ``optimum.json`` (with ``files``).
    """
    from fricdamp.iofiles import save_figure, write_json, write_results, write_text

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    h = result.history
    write_results(out / "history.nc", h)
    cols = [str(c) for c in h.data_vars]
    lines = [",".join(["evaluation", *cols])]
    for i in range(h.sizes["evaluation"]):
        lines.append(",".join([str(i), *(repr(float(h[c].values[i])) for c in cols)]))
    write_text(out / "history.csv", "\n".join(lines) + "\n")
    written = []
    if figures:
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(h["evaluation"], h["objective"], ".", alpha=0.5, label="evaluations")
        ax.plot(h["evaluation"], h["best_so_far"], "-", label="best so far")
        ax.set_xlabel("evaluation")
        ax.set_ylabel(result.objective)
        ax.legend()
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        save_figure(fig, out / "optimize_convergence.png")
        plt.close(fig)
        written.append("optimize_convergence.png")
        names = list(result.x)
        if len(names) == 2:
            fig, ax = plt.subplots(figsize=(6, 4.5))
            sc = ax.scatter(h[names[1]], h[names[0]], c=h["objective"], cmap="viridis", s=18)
            ax.plot(result.x[names[1]], result.x[names[0]], "r*", ms=14, mec="k",
                    label="optimum")
            fig.colorbar(sc, ax=ax, label=result.objective)
            ax.ticklabel_format(style="sci", scilimits=(-3, 4))
            ax.set_xlabel(names[1])
            ax.set_ylabel(names[0])
            ax.legend()
            fig.tight_layout()
            save_figure(fig, out / "optimize_points.png")
            plt.close(fig)
            written.append("optimize_points.png")
    summary = result.summary()
    summary["files"] = {"optimum": "optimum.json", "history": ["history.nc", "history.csv"],
                        "figures": written}
    write_json(out / "optimum.json", summary)
    return summary
