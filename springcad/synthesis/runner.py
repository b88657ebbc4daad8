"""Dask execution of a sweep: one task per batch of candidate ids, parts written as they land.

By default a :class:`distributed.LocalCluster` with one single-threaded worker
process per core (the screening is numpy on small arrays: processes, not
threads, give the parallelism); ``scheduler="tcp://host:8786"`` runs the same
tasks on an existing cluster, whose workers need springcad importable. Tasks
carry only (space, start, stop); the client writes each finished batch to the
:class:`~springcad.synthesis.store.ResultStore`, so workers need no shared
file system and a killed run loses at most the batches in flight. At most a few
batches per worker are in flight at once, so memory stays flat for any sweep size.
"""

from __future__ import annotations

import logging
import os
import time
from contextlib import contextmanager
from dataclasses import dataclass

from springcad.errors import SpringcadError
from springcad.progress import Count, Progress, no_progress
from springcad.synthesis.evaluate import evaluate_batch


@dataclass(frozen=True)
class SweepStats:
    """What a run did (counts) and how long it took (s)."""

    total: int
    batches: int
    skipped_batches: int
    evaluated_batches: int
    evaluated_candidates: int
    wall_s: float
    workers: int

    @property
    def candidates_per_s(self) -> float:
        return self.evaluated_candidates / self.wall_s if self.wall_s > 0 else float("nan")

    def to_dict(self) -> dict:
        return {**self.__dict__, "candidates_per_s": self.candidates_per_s}


@contextmanager
def dask_client(scheduler: str | None = None, n_workers: int | None = None,
                processes: bool = True):
    """A connected :class:`distributed.Client`: to ``scheduler`` or to a new LocalCluster.

    Args:
        scheduler: address of an existing scheduler, or None for a local cluster.
        n_workers: local workers (default: every core).
        processes: local workers as processes (default) or threads.
    """
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="5s")
        except (OSError, TimeoutError) as err:
            raise SpringcadError(f"cannot reach the Dask scheduler at {scheduler}: {err}") from err
        try:
            yield client
        finally:
            client.close()
        return
    cluster = LocalCluster(n_workers=n_workers or os.cpu_count() or 1, threads_per_worker=1,
                           processes=processes, dashboard_address=None,
                           silence_logs=logging.ERROR)
    client = Client(cluster)
    try:
        yield client
    finally:
        client.close()
        cluster.close()


def run_sweep(space, store, client, progress: Progress = no_progress,
              in_flight_per_worker: int = 3) -> SweepStats:
    """Evaluate every batch of ``store`` not yet written, on ``client``'s workers.

    Args:
        space: the :class:`~springcad.synthesis.candidates.CandidateSpace`.
        store: the :class:`~springcad.synthesis.store.ResultStore` (decides the batches).
        client: a :class:`distributed.Client`.
        progress: ``progress(message, fraction)`` (:class:`springcad.progress.Progress`)
            at the start and after every batch, the message a
            :class:`~springcad.progress.Count` of candidates (``done_before``: finished by
            an earlier run).
    """
    from distributed import as_completed

    t0 = time.perf_counter()
    pending = store.pending_batches()
    skipped = store.n_batches - len(pending)
    done_before = sum(store.batch_range(b)[1] - store.batch_range(b)[0]
                      for b in store.done_batches() if b < store.n_batches)
    workers = max(1, len(client.scheduler_info().get("workers", {})))
    window = max(2, in_flight_per_worker * workers)
    space_f = client.scatter(space, broadcast=True)
    queue = iter(pending)
    futures = {}

    def submit_next(ac=None):
        b = next(queue, None)
        if b is None:
            return False
        lo, hi = store.batch_range(b)
        f = client.submit(evaluate_batch, space_f, lo, hi, pure=False, key=f"batch-{b}-{time.time_ns()}")
        futures[f] = b
        if ac is not None:
            ac.add(f)
        return True

    for _ in range(window):
        if not submit_next():
            break
    done = done_before
    evaluated = 0

    def report(done: int) -> None:
        count = Count(done, store.total, "candidates", done_before)
        progress(count.message(), count.fraction)

    report(done)
    ac = as_completed(list(futures))
    for fut in ac:
        b = futures.pop(fut)
        cols = fut.result()
        store.write_part(b, cols)
        n = store.batch_range(b)[1] - store.batch_range(b)[0]
        done += n
        evaluated += n
        report(done)
        submit_next(ac)
    return SweepStats(total=store.total, batches=store.n_batches, skipped_batches=skipped,
                      evaluated_batches=len(pending), evaluated_candidates=evaluated,
                      wall_s=time.perf_counter() - t0, workers=workers)
