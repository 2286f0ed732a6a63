"""Independent, deterministic tasks run here, on worker processes, or on a Dask cluster — the same results,
to the bit, whatever runs them.  Used by the stability matrix (its cells) and by the work-precision
benchmark's error sweep (`bench --errors-only`); never by a timed run (two runs timed at once on these
cores would slow each other down).

    run_tasks(fn, tasks, workers=1, scheduler=None)  ->  (index, fn(task)) as each finishes

fn must be a module-level function (it is sent to the workers by name) and its result picklable.
"""
from __future__ import annotations

import sys

import numpy as np


def check_workers(workers) -> int:
    """workers: an integer >= 1 (the number of processes running tasks at once); ValueError otherwise."""
    if isinstance(workers, str):
        try:
            workers = int(workers)
        except ValueError:
            raise ValueError(f"workers (--workers) must be an integer >= 1, got {workers!r}") from None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers (--workers) must be an integer >= 1, got {workers!r}")
    return int(workers)


def default_workers() -> int:
    """Every core: os.cpu_count() (1 if unknown)."""
    import os
    return os.cpu_count() or 1


def connect(scheduler, timeout: float = 10.0):
    """A dask.distributed Client on the scheduler at `scheduler` ("tcp://host:port", "host:port", or an
    in-process LocalCluster's address); a Client is returned as it is.  ValueError naming the address if it
    cannot be reached within `timeout` s."""
    from dask.distributed import Client
    if isinstance(scheduler, Client):
        return scheduler
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise ValueError(f"scheduler must be a Dask scheduler address such as tcp://host:8786, got {scheduler!r}")
    try:
        return Client(scheduler, timeout=timeout)
    except (OSError, TimeoutError, ValueError, TypeError) as err:
        raise ValueError(f"scheduler: cannot reach a Dask scheduler at {scheduler!r} within {timeout:g} s "
                         f"({type(err).__name__}: {' '.join(str(err).split())[:200]})") from None


def run_tasks(fn, tasks, workers: int = 1, scheduler=None):
    """(i, fn(tasks[i])) for every task, yielded as each finishes: on the Dask cluster at `scheduler` (an
    address or a Client) if given, else on `workers` spawned processes if workers > 1, else here in order."""
    workers = check_workers(workers)
    if scheduler is not None:
        return _run_dask(fn, tasks, scheduler)
    if workers > 1:
        return _run_pool(fn, tasks, workers)
    return ((i, fn(task)) for i, task in enumerate(tasks))


def _ignore_sigint():
    """A worker leaves Ctrl-C to the parent, which writes what finished and then stops the workers."""
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)


QUIET_TRACKER = "ignore::UserWarning:multiprocessing.resource_tracker"


def _run_pool(fn, tasks, workers: int):
    """The tasks on `workers` spawned processes, yielded as they finish; on Ctrl-C (or any error) the
    pending tasks are cancelled and the workers this started are terminated.

    The pool's queues hold semaphores that multiprocessing's resource tracker (a process of its own) watches.
    A Ctrl-C that lands inside a semaphore's clean-up, between its unlink and its unregistering (CPython
    gh-109629), leaves the tracker a name already gone: it warned of it after the command's own last words
    ("interrupted after …").  The tracker is started with sys.warnoptions' -W flags: its warnings are ignored."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    if QUIET_TRACKER not in sys.warnoptions:
        sys.warnoptions.append(QUIET_TRACKER)
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=_ignore_sigint)
    futures = {pool.submit(fn, t): i for i, t in enumerate(tasks)}
    try:
        for f in as_completed(futures):
            yield futures[f], f.result()
    except BaseException:
        for f in futures:
            f.cancel()
        for p in list(getattr(pool, "_processes", {}).values()):     # the workers it started, by process
            p.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _run_dask(fn, tasks, scheduler):
    """The tasks on a Dask cluster (scheduler: an address or a Client), yielded as they finish."""
    from dask.distributed import as_completed
    client = connect(scheduler)
    futures = client.map(fn, tasks, pure=False)
    index = {f.key: i for i, f in enumerate(futures)}
    try:
        for f in as_completed(futures):
            yield index[f.key], f.result()
    except BaseException:
        client.cancel(futures)
        raise
    finally:
        if client is not scheduler:
            client.close()
