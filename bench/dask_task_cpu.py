"""CPU time of one ``wake evaluate`` task where each runner runs it: serially, in a loky worker, in a Dask worker.

    python bench/dask_task_cpu.py serial
    python bench/dask_task_cpu.py loky
    python bench/dask_task_cpu.py dask              # Dask's defaults (the workers' profiler on)
    python bench/dask_task_cpu.py dask-noprofile    # as `--scheduler local` starts its workers
    python bench/dask_task_cpu.py dask-notick       # also the event loop's tick and system monitor slowed

The task is one signal of the generated cohort (50 s at 100 Hz; WAKE on the C core and the three
baselines); each worker times it five times after a warm-up and reports the median process time
(docs/studies/evaluation.md, "At cohort scale", run E).  A Dask worker runs the task in its executor thread;
``client.run`` runs it outside that thread, for comparison.
"""
import argparse
import time

MODES = ("serial", "loky", "dask", "dask-noprofile", "dask-notick")


def timed(_=None):
    """Median process time of one task over five runs, after one warm-up run (the worker's imports)."""
    from wake.eval.compute import WAKE_PARAMS, Task, compute_task
    from wake.eval.sources import cohort_sources

    task = Task(cohort_sources(3)[1], tuple(sorted(WAKE_PARAMS.items())), ("c",))
    compute_task(task)
    out = []
    for _ in range(5):
        t0 = time.process_time()
        compute_task(task)
        out.append(time.process_time() - t0)
    return sorted(out)[2]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("mode", choices=MODES, help="where the task runs")
    mode = p.parse_args(argv).mode
    if mode == "serial":
        print(mode, timed())
    elif mode == "loky":
        import joblib

        print(mode, joblib.Parallel(n_jobs=2)(joblib.delayed(timed)(i) for i in range(2)))
    else:
        import dask
        import distributed

        from wake.eval.runner import LOCAL_CLUSTER_CONFIG

        if mode == "dask-noprofile":        # as `wake evaluate --scheduler local` starts its workers
            dask.config.set(LOCAL_CLUSTER_CONFIG)
        if mode == "dask-notick":
            dask.config.set({**LOCAL_CLUSTER_CONFIG, "distributed.admin.tick.interval": "1s",
                             "distributed.admin.system-monitor.interval": "5s"})
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = distributed.Client(cluster)
        try:
            futures = [client.submit(timed, i, pure=False) for i in range(2)]
            print(mode, "(executor thread)", client.gather(futures))
            print(mode, "(client.run, outside the executor thread)", client.run(timed))
        finally:
            client.close()
            cluster.close()


if __name__ == "__main__":
    main()
