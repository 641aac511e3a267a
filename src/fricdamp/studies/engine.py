"""The evaluation engine of sweeps and optimisers: run points on Dask or here, reuse stored ones.

:func:`run_points` evaluates ``fn`` at a list of points, in this process or on a
``distributed.Client``, loads the points already in a
:class:`~fricdamp.studies.points.PointStore` and saves each new one as soon as it is finished;
a progress bar or a callback follows it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
from collections.abc import Callable, Mapping, Sequence

from fricdamp.studies.cluster import _ClientSlot
from fricdamp.studies.points import (
    PointRecord,
    PointStore,
    StudyError,
    StudyInterrupted,
    evaluate_point,
    point_key,
)

log = logging.getLogger(__name__)

__all__ = ["run_points"]


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


#: Seconds a study waits with no Dask worker alive before it gives up (the points finished
#: before are stored; rerun to continue). Override with ``FRICDAMP_NO_WORKER_TIMEOUT``.
NO_WORKER_TIMEOUT_S = 60.0


def _no_worker_timeout() -> float:
    import os

    try:
        return float(os.environ.get("FRICDAMP_NO_WORKER_TIMEOUT", NO_WORKER_TIMEOUT_S))
    except ValueError:
        return NO_WORKER_TIMEOUT_S


def _n_workers(client) -> int:
    """Workers the scheduler knows; raises StudyError if the scheduler cannot be asked."""
    status = str(getattr(client, "status", "running"))
    if status in ("closed", "closing", "failed"):
        raise StudyError(f"lost the Dask scheduler (client {status})")
    try:
        info = client.scheduler_info()
    except Exception as exc:  # noqa: BLE001 - any comm failure means the scheduler is gone
        raise StudyError(f"lost the Dask scheduler ({type(exc).__name__}: {exc})") from None
    return len(info.get("workers", {}))


def _run_on_dask(client, fn, jobs, reserved, finish) -> None:
    """Submit the jobs, store each finished point; infrastructure failures are not stored.

    A point whose task was lost (its worker died, the scheduler went away, the task was
    cancelled) is *not* a physics failure: it is not stored, so a rerun computes it. The
    study then ends with :class:`StudyError` saying how many points were lost. With no worker
    alive for :data:`NO_WORKER_TIMEOUT_S` seconds, or the scheduler gone, it ends the same way.
    """
    import time

    from distributed import as_completed

    if not jobs:
        return
    futures = {}
    lost: list[str] = []
    timeout = _no_worker_timeout()
    try:
        try:
            for key, params in jobs:
                fut = client.submit(evaluate_point, fn, key, params, tuple(reserved),
                                    pure=False)
                futures[fut] = (key, params)
            ac = as_completed(list(futures))
            no_worker_since = None
            last_check = 0.0
            while not ac.is_empty():
                batch = ac.next_batch(block=False)
                if not batch:
                    time.sleep(0.05)
                    now = time.monotonic()
                    if now - last_check < 1.0:
                        continue
                    last_check = now
                    if _n_workers(client) == 0:
                        no_worker_since = no_worker_since or now
                        if now - no_worker_since > timeout:
                            raise StudyError(
                                f"no Dask worker has been alive for {timeout:g} s; start "
                                "workers (dask worker SCHEDULER) or use --serial")
                    else:
                        no_worker_since = None
                    continue
                for fut in batch:
                    key, params = futures[fut]
                    try:
                        rec = fut.result()
                    except Exception as exc:  # noqa: BLE001 - the task was lost, not the point
                        text = f"{type(exc).__name__}: {exc}".splitlines()[0]
                        lost.append(text if len(text) <= 160 else text[:157] + "...")
                        log.info("point %s lost on Dask (%s); not stored", params, exc)
                        continue
                    finish(rec)
                    fut.release()
        except StudyError:
            raise
        except (KeyboardInterrupt, StudyInterrupted):
            raise
        except Exception as exc:  # noqa: BLE001 - comm errors of a dead scheduler
            raise StudyError(f"lost the Dask scheduler ({type(exc).__name__}: {exc})") from None
    except StudyError as exc:
        n_left = sum(1 for f in futures if not f.done()) + len(lost)
        raise StudyError(f"{exc}: the finished points are stored, {n_left} point(s) were not "
                         "computed and are not stored; rerun the same command to compute "
                         "them") from None
    finally:
        pending = [f for f in futures if not f.done()]
        if pending:
            with contextlib.suppress(Exception):
                client.cancel(pending)
    if lost:
        why = ("the connection to the Dask scheduler was lost"
               if any("scheduler-connection-lost" in x for x in lost) else f"first: {lost[0]}")
        raise StudyError(f"{len(lost)} point(s) were lost on Dask ({why}): they are not stored "
                         "as failures; rerun the same command to compute them")
