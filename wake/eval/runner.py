"""Running the tasks of ``wake evaluate``: in this process, on local cores (joblib) or on a Dask cluster.

Whatever runs them, each finished task is written to the result store at
once (so an interrupted run keeps everything that finished), a failing
recording is reported in one line and recorded, and a progress bar (tqdm,
when installed) shows tasks done, rate and time left.  Completion order
does not matter: the report reads the store in task order.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys

from wake.eval.compute import compute_task

__all__ = ["run_tasks", "require"]

#: The optional extra that brings each optional package (pyproject.toml).
EXTRAS = {"joblib": "cohort", "tqdm": "cohort", "pyarrow": "cohort", "distributed": "dask", "dask": "dask"}


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


def _pair(task):
    return task, compute_task(task)


def _serial(tasks):
    for task in tasks:
        yield _pair(task)


def _joblib(tasks, jobs):
    joblib = require("joblib", "--jobs")
    parallel = joblib.Parallel(n_jobs=jobs, backend="loky", return_as="generator_unordered")
    yield from parallel(joblib.delayed(_pair)(t) for t in tasks)


def _dask(tasks, scheduler, jobs):
    distributed = require("distributed", "--scheduler")
    if scheduler == "local":
        workers = os.cpu_count() if jobs in (None, -1) else jobs
        # the dashboard needs bokeh (the dask extra brings it); without it, no dashboard
        dashboard = ":0" if importlib.util.find_spec("bokeh") is not None else None
        cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                           dashboard_address=dashboard)
        client = distributed.Client(cluster)
    else:
        cluster, client = None, distributed.Client(scheduler)
    if client.dashboard_link and (scheduler != "local" or dashboard):
        print(f"wake evaluate: Dask dashboard at {client.dashboard_link}", file=sys.stderr)
    try:
        futures = client.map(_pair, tasks, pure=False)
        for future in distributed.as_completed(futures):
            yield future.result()
            future.release()
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


def run_tasks(tasks, store, *, jobs=None, scheduler=None, progress=True):
    """Compute every task ``store`` does not hold yet; returns ``(computed, failed)`` task counts.

    Parameters
    ----------
    tasks : list of wake.eval.compute.Task
    store : wake.eval.store.ResultStore
    jobs : int, optional
        Worker processes (joblib, loky); ``-1``: every core; ``None`` or 1: this process.
        With ``scheduler="local"``: the number of Dask workers.
    scheduler : str, optional
        A Dask scheduler address, or ``"local"`` for a ``LocalCluster`` on this machine.
    progress : bool
        Show a tqdm progress bar.

    Examples
    --------
    >>> import tempfile
    >>> from wake.eval.compute import ROW_COLUMNS, Task, WAKE_PARAMS
    >>> from wake.eval.runner import run_tasks
    >>> from wake.eval.sources import cohort_sources
    >>> from wake.eval.store import ResultStore
    >>> store = ResultStore(tempfile.mkdtemp(), ROW_COLUMNS, format="csv")
    >>> tasks = [Task(s, tuple(WAKE_PARAMS.items()), ("reference",), baselines=False)
    ...          for s in cohort_sources(2, duration_s=8.0)]
    >>> run_tasks(tasks, store, progress=False), run_tasks(tasks, store, progress=False)
    ((2, 0), (0, 0))
    """
    if jobs is not None and (int(jobs) == 0 or int(jobs) < -1):
        raise ValueError(f"--jobs must be a positive number of processes or -1 (every core), got {jobs}")
    done = store.done()
    pending = [t for t in tasks if t.key not in done]
    bar = _Progress(len(tasks), len(tasks) - len(pending), progress)
    failed = 0
    if scheduler:
        results = _dask(pending, scheduler, jobs)
    elif jobs in (None, 1) or not pending:
        results = _serial(pending)
    else:
        results = _joblib(pending, jobs)
    try:
        for task, rows in results:
            store.add(task.key, rows)
            if rows[0]["error"]:
                failed += 1
                bar.write(f"wake evaluate: {rows[0]['recording']}: {rows[0]['error']}")
            bar.update()
    finally:
        bar.close()
        close = getattr(results, "close", None)
        if close is not None:
            close()
    return len(pending), failed
