"""Issue 15, faults of studies on Dask: a point whose worker dies is not stored as a physics
failure, no worker alive ends the study after a timeout, a bad scheduler address is bad input.
"""

from __future__ import annotations

import json
import os

import pytest

from fricdamp.errors import CaseError
from fricdamp.studies import sweep
from fricdamp.studies.cluster import check_scheduler_address
from fricdamp.studies.points import StudyError

distributed = pytest.importorskip("distributed")


def dies_at_two(x: float) -> dict:
    """A point function that kills its worker process at x = 2 (not a physics failure)."""
    if x == 2.0:
        os._exit(3)
    return {"f": 2.0 * x}


def raises_at_one(x: float) -> dict:
    if x == 1.0:
        raise ValueError("a physics failure")
    return {"f": x}


@pytest.mark.parametrize("address", ["notaurl", "http//x", "tcp://host", ""])
def test_bad_scheduler_address_is_bad_input(address):
    with pytest.raises(CaseError, match="is not a scheduler address: give tcp://HOST:PORT"):
        check_scheduler_address(address)


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:8786", "10.0.0.5:8786", "tls://h.x:1"])
def test_good_scheduler_addresses(address):
    assert check_scheduler_address(address) == address


def test_lost_worker_points_are_not_stored_as_failures(tmp_path):
    """The worker computing x = 2 dies (allowed-failures 0: no retry); the points queued on it
    die with it. The study ends with a StudyError counting the lost points; the points that
    finished are stored as successes, the lost ones are not stored at all (a rerun computes
    them) and none is stored as a failure."""
    import dask

    store = tmp_path / "points"
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), \
            distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                     dashboard_address=None, host="127.0.0.1",
                                     silence_logs=50) as cluster, \
            distributed.Client(cluster) as client:
        with pytest.raises(StudyError, match=r"point\(s\) were lost on Dask .*KilledWorker"
                                             r".*not stored as failures") as err:
            sweep(dies_at_two, {"x": [0.0, 1.0, 2.0, 3.0]}, client=client, store=store,
                  fingerprint="faults")
    n_lost = int(str(err.value).split()[0])
    assert 1 <= n_lost <= 3 and "\n" not in str(err.value)
    stored = [json.loads(p.read_text()) for p in store.glob("*.json")]
    assert len(stored) == 4 - n_lost
    assert all(r["params"]["x"] != 2.0 and r["status"] == "ok" for r in stored), stored


def test_physics_failures_are_still_stored(tmp_path):
    store = tmp_path / "points"
    ds = sweep(raises_at_one, {"x": [0.0, 1.0]}, serial=True, store=store,
               fingerprint="physics")
    assert bool(ds["failed"].values[1]) and not bool(ds["failed"].values[0])
    assert len(list(store.glob("*.json"))) == 2


def test_no_worker_alive_times_out(tmp_path, monkeypatch):
    monkeypatch.setenv("FRICDAMP_NO_WORKER_TIMEOUT", "2")
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=":0",
                                  silence_logs=50) as cluster, \
            distributed.Client(cluster) as client:
        with pytest.raises(StudyError, match="no Dask worker has been alive for 2 s"):
            sweep(raises_at_one, {"x": [0.0]}, client=client, store=tmp_path / "p",
                  fingerprint="noworker")
    assert not list((tmp_path / "p").glob("*.json"))


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_lost_scheduler_ends_the_cli_sweep_in_one_line(tmp_path):
    """A scheduler killed while the points run: the sweep ends with exit 1 and one line, no
    distributed traceback on stderr, and the lost points are not stored (about 30 s)."""
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    case = tmp_path / "case.toml"
    case.write_text('[model]\ntype = "chain"\nmasses_kg = [1.0]\nsprings_N_per_m = [1.0e4]\n'
                    "[analysis.free_decay]\ninitial_displacement_m = [1.0e-3]\n"
                    "duration_s = 60.0\ntime_step_s = 5.0e-4\n")
    port = _free_port()
    bindir = Path(sys.executable).parent
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "CI": "1"}
    sched = subprocess.Popen([str(bindir / "dask"), "scheduler", "--port", str(port),
                              "--no-dashboard"], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, env=env)
    worker = None
    try:
        time.sleep(3)
        worker = subprocess.Popen([str(bindir / "dask"), "worker", f"tcp://127.0.0.1:{port}",
                                   "--nthreads", "1", "--no-dashboard"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        time.sleep(3)
        out = tmp_path / "sw"
        run = subprocess.Popen([sys.executable, "-m", "fricdamp.cli", "sweep", str(case),
                                "--grid", "model.springs_N_per_m.1=1e4:2e4:3", "--scheduler",
                                f"tcp://127.0.0.1:{port}", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env=env)
        time.sleep(8)
        sched.send_signal(signal.SIGKILL)
        _, err = run.communicate(timeout=180)
    finally:
        for p in (sched, worker):
            if p is not None and p.poll() is None:
                p.kill()
                p.wait()
    assert run.returncode == 1, err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "lost" in lines[0] and "not stored" in lines[0], err
    assert not list((out / "points").glob("*.json"))
