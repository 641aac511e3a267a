"""Where a study runs: no Dask, a local ``dask.distributed`` cluster, or the user's scheduler.

:func:`open_client` yields the ``distributed.Client`` of a study (or None for a serial run).
A local cluster it starts is set up for CPU-bound, Python-heavy study points: one
single-threaded worker process per core, BLAS / OpenMP / numba pools of one thread
(:data:`WORKER_ENV`), no statistical profiler and quieter event loops
(:data:`LOCAL_CLUSTER_CONFIG`).
A scheduler address or a Client given by the user is used as it is.

Dask is imported only when a cluster is used.
"""

from __future__ import annotations

import contextlib
import copy
import logging
import os
from collections.abc import Iterator, Mapping

from fricdamp.studies.points import StudyError

__all__ = ["LOCAL_CLUSTER_CONFIG", "WORKER_ENV", "check_scheduler_address", "open_client"]


def check_scheduler_address(address: str) -> str:
    """``address`` must look like ``tcp://HOST:PORT`` (or tls://, ws://, inproc://, or
    ``HOST:PORT``); raises :class:`~fricdamp.errors.CaseError` (bad input, exit code 2)."""
    import re

    from fricdamp.errors import CaseError

    if not isinstance(address, str) or not re.fullmatch(
            r"((tcp|tls|ws|wss|ucx)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):\d{1,5}"
            r"|inproc://\S+", address.strip()):
        raise CaseError(f"--scheduler {address!r} is not a scheduler address: give "
                        "tcp://HOST:PORT (e.g. tcp://10.0.0.5:8786, as printed by "
                        "'dask scheduler')")
    return address.strip()

#: Environment of local Dask workers: one BLAS / OpenMP / numba thread per single-threaded
#: worker, so two workers on two cores do not fight over four BLAS threads. It is set before
#: the worker processes start (``distributed.nanny.pre-spawn-environ``) and wins over the same
#: variables in this process's environment.
WORKER_ENV = {"OMP_NUM_THREADS": 1, "OPENBLAS_NUM_THREADS": 1, "MKL_NUM_THREADS": 1,
              "VECLIB_MAXIMUM_THREADS": 1, "NUMEXPR_NUM_THREADS": 1, "NUMBA_NUM_THREADS": 1}

#: Dask configuration of a local cluster started by :func:`open_client` (not of a user's
#: scheduler or Client): the diagnostics of the Dask dashboard, which a local study cluster
#: does not start, are turned off or slowed down. A worker's statistical profiler samples its
#: task thread every 10 ms on the event-loop thread, which needs the GIL for it, and every
#: server (scheduler, nannies, workers) wakes its event loop every 20 ms to measure its own
#: latency ("tick"); the GIL contention monitor (active only if ``gilknocker`` is installed)
#: polls the GIL every millisecond. Measured on 2 workers running Python-bound points (many
#: small NumPy solves): the workers' threads other than the task's use 6.4 % of the task
#: thread's CPU with Dask's defaults and 2.5 % with these settings, and the client process
#: (scheduler, nannies, client) 7 % of a core instead of 4.5 %. Dask's own cluster tests use
#: the same two settings.
LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "500ms",
    "distributed.admin.system-monitor.gil.enabled": False,
}


def _require_distributed():
    try:
        import distributed
    except ImportError:
        raise ImportError(
            "running a study on Dask needs the 'distributed' package, which is not installed: "
            "pip install 'fricdamp[dask]' (or pip install 'dask[distributed]'), or run the "
            "study serially (serial=True in Python, --serial on the command line)") from None
    return distributed


def _restore_environ(saved: Mapping[str, str | None],
                     spawned: Mapping[str, str | None] | None = None) -> None:
    """Put back the variables of ``saved`` (None: the variable was not set).

    With ``spawned`` (the values Dask's nanny set), only the variables that still hold them.
    """
    for name, value in saved.items():
        if spawned is not None and os.environ.get(name) != spawned.get(name):
            continue  # changed since: not ours to undo
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value


@contextlib.contextmanager
def open_client(client=None, *, serial: bool = False, n_workers: int | None = None
                ) -> Iterator:
    """Yield the ``distributed.Client`` a study runs on, or None for a serial run.

    Parameters
    ----------
    client : None, str or distributed.Client
        None starts a local cluster of ``n_workers`` processes (default ``os.cpu_count()``),
        one thread each, on the loopback interface, without a dashboard, and closes it at the
        end. Its workers get the environment :data:`WORKER_ENV` (BLAS, OpenMP and numba pools
        of one thread, whatever this process's environment says) and the Dask settings
        :data:`LOCAL_CLUSTER_CONFIG`: the workers' statistical profiler is off and the event
        loops wake less often, which leaves a few percent more of the cores to the points;
        start your own ``LocalCluster`` and pass its Client to profile a study. The
        environment of this process is left as it was (Dask's nanny sets its worker variables
        here to spawn the workers; they are put back once the workers run).
        A string is a scheduler address (``tcp://host:port``): a client is connected to it and
        closed at the end (the cluster is left running). A Client is used as it is. Neither
        is configured: their workers keep their own settings.
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
        check_scheduler_address(client)
        try:
            c = distributed.Client(client, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
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
    env = {str(k): str(v) for k, v in
           (dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {}).items()
           if v is not None}
    env.update({k: str(v) for k, v in WORKER_ENV.items()})
    # the nanny sets these (and PYTHONHASHSEED) in os.environ before it spawns a worker, and
    # prefers values already there to its configuration: set ours, put the user's back after
    saved = {k: os.environ.get(k) for k in (*env, "PYTHONHASHSEED")}
    try:
        os.environ.update({k: v for k, v in env.items() if k in WORKER_ENV})
        with dask.config.set({"distributed.nanny.pre-spawn-environ": env,
                              **LOCAL_CLUSTER_CONFIG}):
            # the nanny keeps the configuration it gives its worker by reference to the
            # global one: a copy keeps ours for a worker it restarts after this block
            worker_config = {"distributed": copy.deepcopy(dask.config.get("distributed"))}
            cluster = distributed.LocalCluster(
                n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                dashboard_address=None, silence_logs=logging.ERROR, config=worker_config)
    finally:
        spawned = {k: os.environ.get(k) for k in saved}
        _restore_environ(saved)
    try:
        c = distributed.Client(cluster)
        try:
            yield c
        finally:
            c.close()
    finally:
        cluster.close()
        _restore_environ(saved, spawned)  # a worker restarted by its nanny set them again


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
