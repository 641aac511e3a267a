"""Sweep and optimisation machinery: results, failures, resume after a kill, Dask = serial.

The study functions here are analytic stand-ins used ONLY to test the machinery (their names
start with ``standin_``); physical studies run the case analyses (tests/cli/test_sweep_cli.py).
Every expected value is the stand-in's closed form evaluated independently with numpy.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from fricdamp.errors import CaseError
from fricdamp.studies import (
    Grid,
    PointStore,
    StudyError,
    optimize,
    save_optimization,
    save_sweep,
    summarize,
    sweep,
)
from fricdamp.studies.sweep import point_key

HERE = Path(__file__).resolve().parent


# ----------------------------------------------------------- analytic stand-ins (tests only)
def standin_quadratic(x, y):
    """Test stand-in: f = 1 + (x-1)^2 + 2 (y-3)^2 (minimum 1 at x=1, y=3), g = x y."""
    return {"f": 1.0 + (x - 1.0) * (x - 1.0) + 2.0 * (y - 3.0) * (y - 3.0), "g": x * y,
            "vector": np.arange(3), "label": "not a number"}


def standin_fails_above(x, y):
    """Test stand-in that raises for x > 2 (a solver failure at some grid points)."""
    if x > 2:
        raise ArithmeticError(f"no convergence at x={x:g}")
    return {"f": x + y}


def standin_logged(x, y, log_file, delay=0.0):
    """Test stand-in that records each evaluation in ``log_file`` (to count recomputations)."""
    time.sleep(delay)
    with open(log_file, "a", encoding="utf-8") as fh:
        fh.write(json.dumps({"x": x, "y": y}) + "\n")
        fh.flush()
    return {"f": x * 10.0 + y}


def standin_where(x, y):
    """Test stand-in reporting which process evaluated it (Dask workers differ from here)."""
    time.sleep(0.05)
    return {"f": math.sin(x) * math.exp(-y), "pid": float(os.getpid())}


def _logged(path: Path) -> list[tuple[float, float]]:
    if not path.exists():
        return []
    return [(d["x"], d["y"]) for d in map(json.loads, path.read_text().splitlines())]


# ------------------------------------------------------------------------------- sweep
def test_dataset_layout_and_values_match_closed_form():
    ds = sweep(standin_quadratic, ["x=-1:2:4", "y=2.5,3,4"], serial=True)
    assert ds["f"].dims == ("x", "y") and ds["f"].shape == (4, 3)
    X, Y = np.meshgrid(np.linspace(-1, 2, 4), [2.5, 3.0, 4.0], indexing="ij")
    # identical arithmetic on identical floats: exact equality is the right check
    np.testing.assert_array_equal(ds["f"].values, 1.0 + (X - 1) * (X - 1) + 2 * (Y - 3) * (Y - 3))
    np.testing.assert_array_equal(ds["g"].values, X * Y)
    np.testing.assert_array_equal(ds["x"].values, np.linspace(-1, 2, 4))
    assert set(ds.data_vars) == {"f", "g", "wall_time_s", "failed"}  # non-scalars left out
    assert json.loads(ds.attrs["ignored_results"]) == ["vector", "label"]
    assert np.all(ds["wall_time_s"].values >= 0) and not ds["failed"].values.any()
    s = summarize(ds)
    assert (s["points_total"], s["points_computed"], s["points_reused"]) == (12, 12, 0)
    assert s["points_failed"] == []
    assert s["results"]["f"]["min"] == 1.0 and s["results"]["f"]["at_min"] == {"x": 1.0,
                                                                              "y": 3.0}


def test_failing_points_do_not_stop_the_study():
    ds = sweep(standin_fails_above, {"x": [1, 2, 3, 4], "y": [0.5, 1.5]}, serial=True)
    f = ds["f"].values
    assert np.isnan(f[2:]).all() and np.array_equal(f[:2], [[1.5, 2.5], [2.5, 3.5]])
    np.testing.assert_array_equal(ds["failed"].values, [[0, 0], [0, 0], [1, 1], [1, 1]])
    failures = summarize(ds)["points_failed"]
    assert len(failures) == 4 and ds.attrs["points_failed"] == 4
    assert failures[0] == {"params": {"x": 3, "y": 0.5},
                           "error": "ArithmeticError: no convergence at x=3"}


def test_bad_return_values_are_point_failures():
    def standin_list(x):
        return [x]

    def standin_reserved(x):
        return {"wall_time_s": x}

    def standin_param_name(x):
        return {"x": x}

    for fn, words in ((standin_list, "must return a mapping"),
                      (standin_reserved, "'wall_time_s' is reserved"),
                      (standin_param_name, "'x' is reserved")):
        ds = sweep(fn, ["x=1,2"], serial=True)
        failures = summarize(ds)["points_failed"]
        assert len(failures) == 2 and words in failures[0]["error"]


def test_grid_names_must_match_the_function():
    with pytest.raises(CaseError, match="unknown grid parameter 'z'.*takes x, y"):
        sweep(standin_quadratic, ["x=1,2", "z=1,2"], serial=True)
    with pytest.raises(CaseError, match="needs the parameter.*y"):
        sweep(standin_quadratic, ["x=1,2"], serial=True)
    with pytest.raises(CaseError, match="empty range"):
        sweep(standin_quadratic, ["x=1:2:0", "y=1"], serial=True)
    with pytest.raises(CaseError, match="not a number"):
        sweep(standin_quadratic, ["x=1,two", "y=1"], serial=True)


def test_store_reuses_points_and_a_changed_study_does_not(tmp_path):
    import functools

    log = tmp_path / "calls.log"
    grid = Grid.parse(["x=0:1:3", "y=1,2"])
    fn = functools.partial(standin_logged, log_file=str(log))
    ds1 = sweep(fn, grid, serial=True, store=tmp_path / "points")
    assert len(_logged(log)) == 6 and ds1.attrs["points_computed"] == 6
    files = sorted(p.name for p in (tmp_path / "points").iterdir())
    assert len(files) == 6 and all(f.endswith(".json") for f in files)  # no temp file left

    ds2 = sweep(fn, grid, serial=True, store=tmp_path / "points")
    assert len(_logged(log)) == 6  # nothing computed again
    assert (ds2.attrs["points_computed"], ds2.attrs["points_reused"]) == (0, 6)
    np.testing.assert_array_equal(ds1["f"].values, ds2["f"].values)
    np.testing.assert_array_equal(ds1["wall_time_s"].values, ds2["wall_time_s"].values)

    # a different study (other bound arguments) never reuses these points
    fn2 = functools.partial(standin_logged, log_file=str(log), delay=0.0001)
    ds3 = sweep(fn2, grid, serial=True, store=tmp_path / "points")
    assert ds3.attrs["points_computed"] == 6 and len(_logged(log)) == 12
    # ... nor does an explicit new fingerprint (e.g. a new version of the model code)
    ds4 = sweep(fn, grid, serial=True, store=tmp_path / "points", fingerprint="v2")
    assert ds4.attrs["points_computed"] == 6


def test_failed_points_are_retried_unless_asked_not_to(tmp_path):
    grid = {"x": [1, 3], "y": [0.0]}
    ds = sweep(standin_fails_above, grid, serial=True, store=tmp_path)
    assert ds.attrs["points_failed"] == 1
    ds = sweep(standin_fails_above, grid, serial=True, store=tmp_path)
    assert (ds.attrs["points_computed"], ds.attrs["points_reused"]) == (1, 1)
    ds = sweep(standin_fails_above, grid, serial=True, store=tmp_path, retry_failed=False)
    assert (ds.attrs["points_computed"], ds.attrs["points_reused"]) == (0, 2)
    assert ds.attrs["points_failed"] == 1


def test_point_files_round_trip_and_keys_are_stable(tmp_path):
    def standin_nan(x):
        return {"a": math.nan, "b": x, "c": True}

    ds = sweep(standin_nan, ["x=0.1,0.2"], serial=True, store=tmp_path, fingerprint="fp")
    store = PointStore(tmp_path, "fp")
    key = point_key("fp", {"x": 0.1})
    assert store.path(key).exists()
    rec = store.load(key)
    assert rec.ok and rec.reused and math.isnan(rec.results["a"]) and rec.results["b"] == 0.1
    assert rec.results["c"] == 1.0
    assert np.isnan(ds["a"].values).all()
    # the key does not depend on the order of the parameters, nor on float noise below 12 digits
    assert point_key("fp", {"x": 1.0, "y": 2.0}) == point_key("fp", {"y": 2.0, "x": 1.0})
    assert point_key("fp", {"x": 0.1 + 0.2}) == point_key("fp", {"x": 0.3})
    assert point_key("fp", {"x": 0.3}) != point_key("fp", {"x": 0.30001})
    assert point_key("fp", {"x": 0.3}) != point_key("other", {"x": 0.3})
    # a corrupt file (not possible with atomic writes, but a disk can fail) is recomputed
    store.path(key).write_text("{not json")
    assert store.load(key) is None


def test_kill_mid_study_then_rerun_loses_and_recomputes_nothing(tmp_path):
    """Terminate a study process mid-way (SIGTERM, no clean-up), rerun: counts add up."""
    store, log = tmp_path / "points", tmp_path / "calls.log"
    script = textwrap.dedent(f"""
        import functools, sys
        sys.path.insert(0, {str(HERE)!r})
        from test_sweep import standin_logged
        from fricdamp.studies import sweep
        fn = functools.partial(standin_logged, log_file={str(log)!r}, delay=0.05)
        sweep(fn, ["x=0:1:6", "y=0:1:5"], serial=True, store={str(store)!r})
    """)
    proc = subprocess.Popen([sys.executable, "-c", script])
    try:
        deadline = time.monotonic() + 60
        while (not store.exists() or len(list(store.glob("*.json"))) < 5):
            assert proc.poll() is None, "the study ended before it could be interrupted"
            assert time.monotonic() < deadline
            time.sleep(0.02)
        proc.terminate()
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    stored = {json.loads(p.read_text())["key"] for p in store.glob("*.json")}
    n_stored = len(stored)
    assert 5 <= n_stored < 30, "the kill did not land mid-study"
    first_run = _logged(log)
    log.unlink()

    import functools

    # the same study (same function and bound arguments, hence the same fingerprint)
    fn = functools.partial(standin_logged, log_file=str(log), delay=0.05)
    ds = sweep(fn, ["x=0:1:6", "y=0:1:5"], serial=True, store=store)
    second_run = _logged(log)
    fp = ds.attrs["fingerprint"]
    all_points = {(x, y) for x in np.linspace(0, 1, 6).tolist()
                  for y in np.linspace(0, 1, 5).tolist()}
    stored_points = {p for p in all_points if point_key(fp, {"x": p[0], "y": p[1]}) in stored}
    assert len(stored_points) == n_stored  # every stored file is one of this study's points
    assert stored_points <= set(first_run)
    assert ds.attrs["points_reused"] == n_stored
    assert ds.attrs["points_computed"] == 30 - n_stored == len(second_run)
    assert ds.attrs["points_failed"] == 0 and not np.isnan(ds["f"].values).any()
    # none recomputed, none lost: the rerun evaluated exactly the missing points, once each
    assert len(set(second_run)) == len(second_run)
    assert set(second_run) == all_points - stored_points
    X, Y = np.meshgrid(np.linspace(0, 1, 6), np.linspace(0, 1, 5), indexing="ij")
    np.testing.assert_array_equal(ds["f"].values, X * 10.0 + Y)


def test_without_distributed_serial_works_and_dask_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    ds = sweep(standin_quadratic, ["x=1,2", "y=3"], serial=True)
    assert ds["f"].values.tolist() == [[1.0], [2.0]]
    with pytest.raises(ImportError, match=r"pip install 'fricdamp\[dask\]'.*serial=True"):
        sweep(standin_quadratic, ["x=1,2", "y=3"])


def test_import_fricdamp_studies_pulls_no_dask_nor_matplotlib():
    code = ("import sys, fricdamp, fricdamp.studies, fricdamp.cli.studies; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('dask', 'distributed', 'matplotlib')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_save_sweep_writes_netcdf_summary_figures_report(tmp_path):
    from fricdamp.iofiles import read_results

    ds = sweep(standin_fails_above, ["x=1:4:4", "y=0.5,1.5"], serial=True)
    summary = save_sweep(ds, tmp_path)
    back = read_results(tmp_path / "sweep.nc")
    np.testing.assert_array_equal(back["f"].values, ds["f"].values)
    on_disk = json.loads((tmp_path / "summary.json").read_text())
    assert on_disk["points_total"] == 8 and len(on_disk["points_failed"]) == 4
    assert on_disk["points_failed"][0]["error"].startswith("ArithmeticError")
    assert summary["files"]["figures"] == ["sweep_f.png", "sweep_wall_time_s.png"]
    assert (tmp_path / "sweep_f.png").stat().st_size > 1000
    report = (tmp_path / "report.md").read_text()
    assert "| failed | 4 |" in report and "no convergence at x=3" in report


# --------------------------------------------------------------------------------- dask
def _worker_setup(dask_worker):
    """Run on a Dask worker (``Client.run``): what the worker process was started with."""
    import dask
    from threadpoolctl import threadpool_info

    return {"OPENBLAS_NUM_THREADS": os.environ.get("OPENBLAS_NUM_THREADS"),
            "blas_threads": sorted({p["num_threads"] for p in threadpool_info()
                                    if p["user_api"] == "blas"}),
            "profile_config": dask.config.get("distributed.worker.profile.enabled"),
            "profiling": "profile" in dask_worker.periodic_callbacks}


#: Variables Dask's nanny sets in the parent to spawn workers, or that the cluster overrides.
SPAWN_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
                   "NUMBA_NUM_THREADS", "MALLOC_TRIM_THRESHOLD_", "PYTHONHASHSEED")


@pytest.fixture(scope="module")
def loopback_started():
    """A real dask.distributed scheduler and two worker processes on 127.0.0.1.

    Started by :func:`open_client` exactly as ``sweep(client=None)`` starts its local cluster,
    from a process whose environment asks for 3 OpenBLAS threads. Yields the client and this
    process's spawn variables before the start and once the cluster runs.
    """
    pytest.importorskip("distributed")
    from fricdamp.studies import open_client

    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("OPENBLAS_NUM_THREADS", "3")
        env = {"before": {k: os.environ.get(k) for k in SPAWN_VARIABLES}}
        with open_client(None, n_workers=2) as client:
            env["running"] = {k: os.environ.get(k) for k in SPAWN_VARIABLES}
            yield client, env


@pytest.fixture(scope="module")
def loopback_cluster(loopback_started):
    return loopback_started[0]


def test_local_cluster_is_on_loopback_with_single_threaded_blas(loopback_started):
    cluster, env = loopback_started
    info = cluster.scheduler_info()
    assert cluster.scheduler.address.startswith("tcp://127.0.0.1:")
    assert len(info["workers"]) == 2
    assert all(w["nthreads"] == 1 for w in info["workers"].values())
    # one BLAS thread in the workers although this process's environment asks for 3, and no
    # statistical profiler (it stalls Python-bound tasks for the GIL every 10 ms)
    expected = {"OPENBLAS_NUM_THREADS": "1", "blas_threads": [1], "profile_config": False,
                "profiling": False}
    assert list(cluster.run(_worker_setup).values()) == [expected, expected]
    # this process's environment is left as it was
    assert env["before"]["OPENBLAS_NUM_THREADS"] == "3"
    assert env["running"] == env["before"]
    # workers restarted by their nannies (after a crash, or on demand) are set up alike
    cluster.restart()
    assert list(cluster.run(_worker_setup).values()) == [expected, expected]


def test_a_user_client_is_used_as_it_is():
    """A Client given by the user is yielded unchanged: not reconfigured, not closed."""
    distributed = pytest.importorskip("distributed")
    from fricdamp.studies import open_client

    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        profiling = client.run(_worker_setup)
        with open_client(client) as got:
            assert got is client
        ds = sweep(standin_where, {"x": [0.0, 1.0], "y": [0.0]}, client=client)
        np.testing.assert_array_equal(ds["f"].values, [[0.0], [math.sin(1.0)]])
        assert client.status == "running"
        assert client.run(_worker_setup) == profiling  # its profiler is as it was (on)
        assert all(s["profiling"] for s in profiling.values())


def test_dask_sweep_equals_serial_sweep(loopback_cluster, tmp_path):
    address = loopback_cluster.scheduler.address
    grid = ["x=0:3:4", "y=0.5:1:3"]
    ser = sweep(standin_where, grid, serial=True)
    par = sweep(standin_where, grid, client=address, store=tmp_path)  # as --scheduler does
    np.testing.assert_array_equal(par["f"].values, ser["f"].values)
    np.testing.assert_array_equal(par["failed"].values, ser["failed"].values)
    pids = set(par["pid"].values.ravel().tolist())
    assert float(os.getpid()) not in pids and len(pids) == 2  # both workers took points
    # failures travel back from the workers with their message
    grid_f = {"x": [1, 3], "y": [0.0]}
    fpar = sweep(standin_fails_above, grid_f, client=loopback_cluster)  # a Client object
    assert summarize(fpar)["points_failed"] == summarize(
        sweep(standin_fails_above, grid_f, serial=True))["points_failed"]
    # the points the cluster stored are reused by a serial rerun (same keys everywhere)
    again = sweep(standin_where, grid, serial=True, store=tmp_path)
    assert again.attrs["points_reused"] == 12
    np.testing.assert_array_equal(again["pid"].values, par["pid"].values)


def test_dask_optimisation_equals_serial(loopback_cluster):
    bounds = {"x": (-2.0, 4.0), "y": (0.0, 5.0)}
    kw = {"minimize": "f", "maxiter": 5, "popsize": 4, "seed": 3}
    ser = optimize(standin_quadratic, bounds, serial=True, **kw)
    par = optimize(standin_quadratic, bounds, client=loopback_cluster, **kw)
    assert par.x == ser.x and par.value == ser.value
    np.testing.assert_array_equal(par.history["f"].values, ser.history["f"].values)


# ---------------------------------------------------------------------------- optimize
def test_nelder_mead_finds_the_closed_form_minimum():
    res = optimize(standin_quadratic, {"x": (-2.0, 4.0), "y": (0.0, 5.0)}, minimize="f",
                   method="nelder-mead", tol=1e-6)
    assert res.success
    # xatol = 1e-6 in the unit box is 6e-6 in x and 5e-6 in y; 1e-4 leaves room for the
    # simplex's last shrink
    assert abs(res.x["x"] - 1.0) < 1e-4 and abs(res.x["y"] - 3.0) < 1e-4
    assert res.value == pytest.approx(1.0, abs=1e-8)
    assert res.n_evaluations == res.history.sizes["evaluation"] == res.n_computed
    best = res.history["best_so_far"].values
    assert np.all(np.diff(best) <= 0) and best[-1] == res.value


def test_differential_evolution_global_minimum_and_bounds():
    res = optimize(standin_quadratic, {"x": (-2.0, 4.0), "y": (0.0, 5.0)}, minimize="f",
                   seed=1, maxiter=40, serial=True)
    # DE without polishing returns its best member; with 16 members and 40 generations it
    # lands within a few percent of the range: 0.05 is 1 % of the x-range
    assert abs(res.x["x"] - 1.0) < 0.05 and abs(res.x["y"] - 3.0) < 0.05
    assert res.value == min(res.history["f"].values)
    # an optimum on the boundary: x is held at its lower bound
    res = optimize(standin_quadratic, {"x": (2.0, 4.0), "y": (0.0, 5.0)}, minimize="f",
                   method="nelder-mead", tol=1e-7)
    assert res.x["x"] == pytest.approx(2.0, abs=1e-5) and res.x["y"] == pytest.approx(3.0,
                                                                                      abs=1e-3)
    # maximising g = x y over the box: the corner (4, 5)
    res = optimize(standin_quadratic, {"x": (-2.0, 4.0), "y": (0.0, 5.0)}, maximize="g",
                   method="nelder-mead", tol=1e-8)
    assert res.value == pytest.approx(20.0, rel=1e-5) and res.sense == "maximize"


def test_optimisation_resumes_from_its_store_and_survives_failures(tmp_path):
    bounds = {"x": (0.0, 4.0), "y": (0.0, 5.0)}
    r1 = optimize(standin_fails_above, bounds, minimize="f", store=tmp_path, serial=True,
                  maxiter=6, popsize=5, seed=7)
    assert r1.n_failed > 0 and all("no convergence" in f["error"] for f in r1.failures)
    assert r1.x["x"] <= 2 and r1.value == r1.x["x"] + r1.x["y"]
    r2 = optimize(standin_fails_above, bounds, minimize="f", store=tmp_path, serial=True,
                  maxiter=6, popsize=5, seed=7, retry_failed=False)
    assert r2.n_computed == 0 and r2.n_reused == r2.n_evaluations == r1.n_evaluations
    assert r2.x == r1.x
    summary = save_optimization(r1, tmp_path / "out")
    assert json.loads((tmp_path / "out" / "optimum.json").read_text())["x"] == r1.x
    csv = (tmp_path / "out" / "history.csv").read_text().splitlines()
    assert len(csv) == r1.n_evaluations + 1 and csv[0].startswith("evaluation,x,y,f")
    assert summary["files"]["figures"] == ["optimize_convergence.png", "optimize_points.png"]


def test_optimisation_input_errors():
    b = {"x": (0.0, 1.0), "y": (0.0, 1.0)}
    with pytest.raises(CaseError, match="no result 'h'"):
        optimize(standin_quadratic, b, minimize="h", serial=True, maxiter=1, popsize=1)
    with pytest.raises(CaseError, match="exactly one of minimize"):
        optimize(standin_quadratic, b, serial=True)
    with pytest.raises(CaseError, match="smaller than HIGH"):
        optimize(standin_quadratic, {"x": (1.0, 0.0), "y": (0.0, 1.0)}, minimize="f")
    with pytest.raises(CaseError, match="unknown optimisation method"):
        optimize(standin_quadratic, b, minimize="f", method="bfgs")
    with pytest.raises(StudyError, match="every one of the .* evaluations failed"):
        optimize(standin_fails_above, {"x": (3.0, 4.0), "y": (0.0, 1.0)}, minimize="f",
                 serial=True, maxiter=1, popsize=1)
