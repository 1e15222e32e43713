"""Running the tasks of ``wake evaluate``: in this process, on local cores (joblib) or on a Dask cluster.

One task model for every backend: the tasks (a recording under one
configuration; they carry a path or a synthetic seed, never samples) are
read lazily, grouped into batches of a few (:func:`batches`, sized by
:func:`batch_size`), and each batch is one unit of work that returns
``(task key, rows)`` pairs.  At most a few batches per worker are in flight
(joblib's ``pre_dispatch``; on Dask a window refilled as each batch
completes, ``as_completed``), so the parent holds neither the task list nor
the results: each finished batch is written to the result store at once (an
interrupted run keeps everything that finished) and dropped.  A failing
recording is reported in one line and recorded, and a progress bar (tqdm,
when installed) shows tasks done, rate and time left.  Completion order
does not matter: the report reads the store in task order.
"""

from __future__ import annotations

import importlib
import importlib.util
import itertools
import os
import sys

from wake.eval.compute import Task, compute_task

__all__ = ["run_tasks", "require", "TaskList", "batches", "batch_size", "compute_batch"]

#: The optional extra that brings each optional package (pyproject.toml).
EXTRAS = {"joblib": "cohort", "tqdm": "cohort", "pyarrow": "cohort", "distributed": "dask", "dask": "dask"}

#: Largest batch: with tasks of about half a second, 4 is 2 s of work, enough to make the
#: dispatch, transfer and store write of a batch (milliseconds) negligible, and short enough
#: that the last batches leave no core idle for long.
MAX_BATCH = 4

#: Batches in flight per worker: one running, one queued behind it.
IN_FLIGHT = 2


def require(module, purpose):
    """Import an optional package, or raise a ValueError naming the extra that installs it.

    Examples
    --------
    >>> from wake.eval.runner import require
    >>> require("no_such_package_xyz", "this")
    Traceback (most recent call last):
    ...
    ValueError: this needs no_such_package_xyz: pip install no_such_package_xyz
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        top = module.split(".")[0]
        extra = EXTRAS.get(top)
        hint = (f"pip install \"wake-tremor[{extra}]\" (or pip install \".[{extra}]\" in a wake source tree)"
                if extra else f"pip install {top}")
        raise ValueError(f"{purpose} needs {top}: {hint}") from None


class TaskList:
    """Every (configuration, source) task, made one at a time as it is iterated (never held as a list).

    Tasks run configuration by configuration, each over every source; only
    the first configuration runs the baselines (they do not depend on WAKE's
    settings).

    Parameters
    ----------
    sources : sequence of wake.eval.sources.Source
    configs : sequence of dict
        WakeFilter settings, one per configuration.
    backends : sequence of str
        WAKE backends (``"c"``, ``"reference"``).

    Examples
    --------
    >>> from wake.eval.compute import WAKE_PARAMS
    >>> from wake.eval.runner import TaskList
    >>> from wake.eval.sources import cohort_sources
    >>> tasks = TaskList(cohort_sources(3), [WAKE_PARAMS, {**WAKE_PARAMS, "level": 4}], ["c"])
    >>> len(tasks), [t.baselines for t in tasks]
    (6, [True, True, True, False, False, False])
    """

    def __init__(self, sources, configs, backends):
        self.sources, self.configs, self.backends = list(sources), [dict(c) for c in configs], tuple(backends)

    def __len__(self):
        return len(self.sources) * len(self.configs)

    def __iter__(self):
        for i, config in enumerate(self.configs):
            for source in self.sources:
                yield Task(source, tuple(config.items()), self.backends, baselines=(i == 0))


def batch_size(pending, workers):
    """Tasks per batch: enough batches to give each worker several, at most :data:`MAX_BATCH` tasks.

    Examples
    --------
    >>> from wake.eval.runner import batch_size
    >>> batch_size(2000, 2), batch_size(20, 2), batch_size(6, 2), batch_size(0, 2)
    (4, 2, 1, 1)
    """
    return max(1, min(MAX_BATCH, pending // (4 * max(1, workers))))


def batches(tasks, size):
    """Group an iterable of tasks into tuples of ``size`` (the last may be shorter), lazily.

    Examples
    --------
    >>> from wake.eval.runner import batches
    >>> list(batches(iter("abcde"), 2))
    [('a', 'b'), ('c', 'd'), ('e',)]
    """
    if int(size) < 1:
        raise ValueError(f"a batch needs at least one task, got size {size}")
    it = iter(tasks)
    while batch := tuple(itertools.islice(it, int(size))):
        yield batch


def compute_batch(batch):
    """What a worker runs: ``[(task key, rows), ...]`` for each task of ``batch``, in its order.

    Each task's rows are :func:`wake.eval.compute.compute_task`'s, whatever
    else is in the batch: a batch is a unit of transport, not of computing.
    """
    return [(task.key, compute_task(task)) for task in batch]


def _serial(groups):
    for batch in groups:
        yield compute_batch(batch)


def _joblib(groups, jobs):
    joblib = require("joblib", "--jobs")
    parallel = joblib.Parallel(n_jobs=jobs, backend="loky", return_as="generator_unordered", batch_size=1,
                               pre_dispatch=f"{IN_FLIGHT}*n_jobs")
    yield from parallel(joblib.delayed(compute_batch)(b) for b in groups)


#: Dask settings of the ``LocalCluster`` that ``--scheduler local`` starts (its workers are spawned with them).
LOCAL_CLUSTER_CONFIG = {"distributed.worker.profile.enabled": False}


def _start_dask(distributed, scheduler, jobs):
    """(cluster or None, client): a LocalCluster of ``jobs`` single-threaded worker processes, or a client."""
    if scheduler != "local":
        client = distributed.Client(scheduler)
        if client.dashboard_link:
            print(f"wake evaluate: Dask dashboard at {client.dashboard_link}", file=sys.stderr)
        return None, client
    workers = os.cpu_count() if jobs in (None, -1) else jobs
    # no dashboard: its server and bokeh's import cost the parent seconds of a core the workers need
    # (start a cluster yourself and pass its address to watch one); and so no statistical profiler in the
    # workers either, which only feeds the dashboard: sampling the task's stack every 10 ms made a task cost
    # 4-7 % more CPU than with it off (docs/studies/evaluation.md, "At cohort scale")
    with require("dask", "--scheduler").config.set(LOCAL_CLUSTER_CONFIG):
        cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                           dashboard_address=None)
    return cluster, distributed.Client(cluster)


def _dask(groups, scheduler, jobs):
    distributed = require("distributed", "--scheduler")
    cluster, client = _start_dask(distributed, scheduler, jobs)
    try:
        threads = max(1, sum(client.nthreads().values()))
        running = distributed.as_completed()
        for batch in itertools.islice(groups, IN_FLIGHT * threads):
            running.add(client.submit(compute_batch, batch, pure=False))
        for future in running:
            pairs = future.result()
            future.release()
            for batch in itertools.islice(groups, 1):   # refill the window as each batch completes
                running.add(client.submit(compute_batch, batch, pure=False))
            yield pairs
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


class _Progress:
    """A tqdm bar over the tasks when tqdm is installed and wanted, else silent."""

    def __init__(self, total, done, enabled):
        self.bar = None
        if enabled:
            try:
                from tqdm import tqdm
            except ImportError:
                print("wake evaluate: no progress bar (tqdm is not installed: pip install \"wake-tremor[cohort]\")",
                      file=sys.stderr)
            else:
                self.bar = tqdm(total=total, initial=done, unit="rec", desc="wake evaluate", file=sys.stderr)

    def update(self):
        if self.bar is not None:
            self.bar.update(1)

    def write(self, line):
        (self.bar.write if self.bar is not None else lambda s: print(s, file=sys.stderr))(line)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def run_tasks(tasks, store, *, jobs=None, scheduler=None, progress=True, batch=None):
    """Compute every task ``store`` does not hold yet; returns ``(computed, failed)`` task counts.

    Parameters
    ----------
    tasks : sized iterable of wake.eval.compute.Task
        A list, or a :class:`TaskList` (iterated twice: once to count what is done, once to run).
    store : wake.eval.store.ResultStore
    jobs : int, optional
        Worker processes (joblib, loky); ``-1``: every core; ``None`` or 1: this process.
        With ``scheduler="local"``: the number of Dask workers.
    scheduler : str, optional
        A Dask scheduler address, or ``"local"`` for a ``LocalCluster`` on this machine.
    progress : bool
        Show a tqdm progress bar.
    batch : int, optional
        Tasks per unit of work (default: :func:`batch_size`; a serial run always computes one at a time).
        Each batch is stored as it completes, so an interrupted run recomputes at most the batches in flight.

    Examples
    --------
    >>> import tempfile
    >>> from wake.eval.compute import ROW_COLUMNS, WAKE_PARAMS
    >>> from wake.eval.runner import TaskList, run_tasks
    >>> from wake.eval.sources import cohort_sources
    >>> from wake.eval.store import ResultStore
    >>> store = ResultStore(tempfile.mkdtemp(), ROW_COLUMNS, format="csv")
    >>> tasks = TaskList(cohort_sources(2, duration_s=8.0), [WAKE_PARAMS], ["reference"])
    >>> run_tasks(tasks, store, progress=False), run_tasks(tasks, store, progress=False)
    ((2, 0), (0, 0))
    """
    if jobs is not None and (int(jobs) == 0 or int(jobs) < -1):
        raise ValueError(f"--jobs must be a positive number of processes or -1 (every core), got {jobs}")
    if batch is not None and int(batch) < 1:
        raise ValueError(f"batch must be a positive number of tasks, got {batch}")
    done = store.done()
    total = len(tasks)
    pending_count = total - sum(1 for t in tasks if t.key in done)
    serial = not scheduler and (jobs in (None, 1) or not pending_count)
    workers = 1 if serial else (os.cpu_count() or 1) if jobs in (None, -1) else int(jobs)
    size = 1 if serial else int(batch) if batch is not None else batch_size(pending_count, workers)
    groups = batches((t for t in tasks if t.key not in done), size)
    bar = _Progress(total, total - pending_count, progress)
    if scheduler:
        results = _dask(groups, scheduler, jobs)
    elif serial:
        results = _serial(groups)
    else:
        results = _joblib(groups, jobs)
    try:
        failed = _store_results(results, store, bar)
    finally:
        bar.close()
        close = getattr(results, "close", None)
        if close is not None:
            close()
    return pending_count, failed


def _store_results(results, store, bar):
    """Write each batch's rows as it arrives, report its failures, drop it; returns the failed task count."""
    failed = 0
    for pairs in results:
        store.add_many(pairs)
        for _, rows in pairs:
            if rows[0]["error"]:
                failed += 1
                bar.write(f"wake evaluate: {rows[0]['recording']}: {rows[0]['error']}")
            bar.update()
    return failed
