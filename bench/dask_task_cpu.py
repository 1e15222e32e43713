"""CPU time of one ``wake evaluate`` task where each runner runs it: serially, in a loky worker, in a Dask worker.

    python bench/dask_task_cpu.py serial
    python bench/dask_task_cpu.py loky
    python bench/dask_task_cpu.py dask              # Dask's defaults (the workers' profiler on)
    python bench/dask_task_cpu.py dask-noprofile    # as `--scheduler local` starts its workers
    python bench/dask_task_cpu.py dask-notick       # also the event loop's tick and system monitor slowed

The task is one signal of the generated cohort (50 s at 100 Hz; WAKE on the C core and the three
baselines); each worker times it five times after a warm-up and reports the median process time
(docs/evaluation.md, "At cohort scale", run E).  A Dask worker runs the task in its executor thread;
``client.run`` runs it outside that thread, for comparison.
"""
import time, sys
def timed(_=None):
    import time
    from wake.eval.compute import compute_task, Task, WAKE_PARAMS
    from wake.eval.sources import cohort_sources
    src = cohort_sources(3)[1]
    t = Task(src, tuple(sorted(WAKE_PARAMS.items())), ("c",))
    compute_task(t)
    out = []
    for _ in range(5):
        t0 = time.process_time(); compute_task(t); out.append(time.process_time() - t0)
    return sorted(out)[2]

def main():
    mode = sys.argv[1]
    if mode == "serial":
        print(mode, timed())
    elif mode == "loky":
        import joblib
        print(mode, joblib.Parallel(n_jobs=2)(joblib.delayed(timed)(i) for i in range(2)))
    else:
        import dask, distributed
        if mode == "dask-noprofile":
            dask.config.set({"distributed.worker.profile.enabled": False})
        if mode == "dask-notick":
            dask.config.set({"distributed.worker.profile.enabled": False, "distributed.admin.tick.interval": "1s",
                             "distributed.admin.system-monitor.interval": "5s"})
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = distributed.Client(cluster)
        futs = [client.submit(timed, i, pure=False) for i in range(2)]
        print(mode, client.gather(futs))
        print("run in worker main thread", client.run(timed))
        client.close(); cluster.close()

if __name__ == "__main__":
    main()
