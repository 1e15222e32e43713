"""CPU time of one ``wake evaluate`` cohort task, as a ratio to five ``scipy.signal.lfilter`` calls in one process.

    python bench/cohort_task.py                     # JSON: seconds per signal, lfilter seconds, their ratio
    python bench/cohort_task.py --signals 4 --repeat 5 --end-to-end

A cohort task is what ``wake evaluate --synthetic N`` computes for each
signal (:func:`wake.eval.compute.compute_task`): the signal generated, WAKE
on every backend the default ``--backend both`` runs (the float reference,
and the C core when it is built), BMFLC, E-BMFLC and WFLC, and every metric
and slice of the report's rows.  The reference is five ``lfilter`` calls of
a 32-tap FIR over the same samples, timed in the same process and
interleaved with the tasks (round by round), so load that comes and goes on
a shared machine falls on both; the ratio of the medians is what carries
from machine to machine.  Times are CPU seconds of this process
(``time.process_time``): other processes' load does not count.

:func:`cohort_task_seconds` and :func:`cohort_task_ratio` are the API a
speed gate calls; the CLI prints :func:`cohort_task_ratio`'s dict as JSON.
``--end-to-end`` also runs ``wake evaluate OUT --synthetic N
--synthetic-only --jobs 1`` in a fresh process and reports its CPU time
(imports, figures and the store included) and CPU time per signal.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: Taps of the reference FIR (the scale of the RTP's filter bank at level 5).
LFILTER_TAPS = 32
#: lfilter calls in the reference.
LFILTER_CALLS = 5


def cohort_tasks(signals=2, duration_s=50.0):
    """The tasks of ``wake evaluate --synthetic N`` for the first ``signals`` signals (default backends)."""
    from wake.eval.compute import WAKE_PARAMS, Task
    from wake.eval.sources import cohort_sources
    from wake.rtp import c_backend_available

    backends = ("reference", "c") if c_backend_available() else ("reference",)
    return [Task(source, tuple(WAKE_PARAMS.items()), backends) for source in cohort_sources(signals, duration_s=duration_s)]


def _cpu(fn, *args):
    t0 = time.process_time()
    fn(*args)
    return time.process_time() - t0


def cohort_task_seconds(signals=2, duration_s=50.0, repeat=3):
    """Median CPU seconds of one cohort task (over ``signals`` signals, ``repeat`` times each, after one warm-up).

    Examples
    --------
    >>> seconds = cohort_task_seconds(signals=1, duration_s=12.0, repeat=1)  # doctest: +SKIP
    """
    from wake.eval.compute import compute_task

    tasks = cohort_tasks(signals, duration_s)
    _check(compute_task(tasks[0]))  # warm-up: imports, cached constants
    return statistics.median(_cpu(compute_task, t) for _ in range(repeat) for t in tasks)


def lfilter_seconds(n):
    """CPU seconds of :data:`LFILTER_CALLS` ``scipy.signal.lfilter`` calls of a :data:`LFILTER_TAPS`-tap FIR
    over ``n`` samples."""
    from scipy.signal import lfilter

    x = np.random.default_rng(0).standard_normal(n)
    b = np.full(LFILTER_TAPS, 1.0 / LFILTER_TAPS)

    def five():
        for _ in range(LFILTER_CALLS):
            lfilter(b, 1.0, x)

    return _cpu(five)


def _check(rows):
    errors = [r["error"] for r in rows if r["error"]]
    if errors:
        raise RuntimeError(f"the cohort task failed: {errors[0]}")


def cohort_task_ratio(signals=2, duration_s=50.0, repeat=3, fs=100.0):
    """Median CPU seconds per cohort task, of the lfilter reference over the same samples, and their ratio.

    Tasks and references alternate, ``repeat`` rounds over ``signals`` signals.

    Returns
    -------
    dict
        ``task_s`` (median per signal), ``lfilter_s`` (median of the reference), ``ratio`` (task / lfilter),
        ``signals``, ``repeat``, ``samples`` (per signal), ``backends``, ``loadavg`` (before the run).
    """
    from wake.eval.compute import compute_task

    load = os.getloadavg()
    tasks = cohort_tasks(signals, duration_s)
    n = int(round(duration_s * fs))
    _check(compute_task(tasks[0]))
    lfilter_seconds(n)
    task_s, ref_s = [], []
    for _ in range(repeat):
        for t in tasks:
            task_s.append(_cpu(compute_task, t))
            ref_s.append(lfilter_seconds(n))
    task, ref = statistics.median(task_s), statistics.median(ref_s)
    return {"task_s": task, "lfilter_s": ref, "ratio": task / ref, "signals": signals, "repeat": repeat,
            "samples": n, "backends": list(tasks[0].backends), "loadavg": [round(v, 2) for v in load]}


def end_to_end(signals=4):
    """CPU seconds (user + system) of ``wake evaluate OUT --synthetic N --synthetic-only --jobs 1`` in a fresh
    process, and the report it wrote (its run-time line left out)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
        subprocess.run([sys.executable, "-m", "wake", "evaluate", str(out), "--synthetic", str(signals),
                        "--synthetic-only", "--jobs", "1", "--no-progress"], check=True, env=env, cwd=tmp,
                       stdout=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        report = "\n".join(line for line in (out / "report.md").read_text().splitlines()
                           if not line.startswith("_Run time:") and not line.startswith("Command:"))
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"cpu_s": cpu, "cpu_s_per_signal": cpu / signals, "signals": signals, "report": report}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--signals", type=int, default=2, help="cohort signals per round (default 2)")
    parser.add_argument("--duration", type=float, default=50.0, help="seconds per signal (default 50)")
    parser.add_argument("--repeat", type=int, default=3, help="rounds (default 3)")
    parser.add_argument("--end-to-end", type=int, default=0, metavar="N",
                        help="also time `wake evaluate --synthetic N --synthetic-only --jobs 1` in a fresh process")
    parser.add_argument("--report", metavar="FILE", help="with --end-to-end: write its report (run time left out)")
    args = parser.parse_args(argv)
    result = cohort_task_ratio(args.signals, args.duration, args.repeat)
    if args.end_to_end:
        e2e = end_to_end(args.end_to_end)
        if args.report:
            Path(args.report).write_text(e2e["report"] + "\n")
        result["end_to_end"] = {k: v for k, v in e2e.items() if k != "report"}
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
