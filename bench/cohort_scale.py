"""Throughput and memory of ``wake evaluate`` on a generated cohort: serial, joblib and Dask, interleaved.

    python bench/cohort_scale.py                       # 2,000 signals of 50 s at 100 Hz, 3 rounds, RSS vs 200
    python bench/cohort_scale.py --count 400 --repeat 3 --rss-count 2000 --small 200

Every run is ``wake evaluate OUT --synthetic N --backend c`` (WAKE on the C
core and the three baselines, one configuration) in a fresh process, into a
fresh folder, so each computes every task.  The three throughput
configurations (``--jobs 1``, ``--jobs 2``, ``--scheduler local --jobs 2``)
run in rounds, one of each per round, ``--repeat`` rounds: on a machine
whose cores are shared, load that comes and goes falls on every
configuration alike, and the summary gives the median of each and the
ratios of the medians.  The table gives wall time from start to report,
throughput (signals per second) and the peak RSS of the parent process
(``ru_maxrss`` of that process alone: workers are not counted), with the
load average before each run.  Targets (docs/studies/evaluation.md, "At cohort
scale"): ``--jobs 2`` at >= 1.7x the throughput of ``--jobs 1``; a Dask
LocalCluster of 2 workers within 15 % of joblib's throughput; peak RSS for
``--rss-count`` signals within 1.5x of that for ``--small``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Runs the command in this process and prints its own peak RSS (kB on Linux) as the last line.
_CHILD = ("import json, resource, sys; from wake.eval.evaluate import cli; status = cli(sys.argv[1:]); "
          "print(json.dumps({'status': status, 'maxrss_kb': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}))")

JOBS1, JOBS2, DASK = "--jobs 1", "--jobs 2", "--scheduler local --jobs 2 (Dask)"
EXTRA = {JOBS1: ["--jobs", "1"], JOBS2: ["--jobs", "2"], DASK: ["--scheduler", "local", "--jobs", "2"]}
#: ``--configs`` names of the throughput configurations
CONFIGS = {"jobs1": JOBS1, "jobs2": JOBS2, "dask": DASK}


def run(out, count, extra, duration):
    """One ``wake evaluate`` in a fresh process: (wall s, parent peak RSS MB)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    cmd = [sys.executable, "-c", _CHILD, str(out), "--synthetic", str(count), "--duration", str(duration),
           "--backend", "c", "--no-progress", *extra]
    t0 = time.perf_counter()
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    last = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else ""
    if done.returncode != 0 or not last.startswith("{"):
        raise SystemExit(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    info = json.loads(last)
    if info["status"] != 0:
        raise SystemExit(f"wake evaluate returned {info['status']}:\n{done.stderr[-2000:]}")
    return wall, info["maxrss_kb"] / 1024


def plan(count, repeat, rss_count, small, configs=tuple(CONFIGS)):
    """The runs in order: ``repeat`` rounds of the throughput configurations, then the memory pair.

    Examples
    --------
    >>> [f"{label}@{n}" for _, label, n in plan(400, 2, 2000, 200, configs=("jobs1", "jobs2"))]
    ['--jobs 1@400', '--jobs 2@400', '--jobs 2@400', '--jobs 1@400', '--jobs 2@200', '--jobs 2@2000']
    >>> [f"{label}@{n}" for _, label, n in plan(200, 0, 2000, 200)]
    ['--jobs 2@200', '--jobs 2@2000']
    >>> [f"{label}@{n}" for _, label, n in plan(2000, 1, None, None, configs=("jobs2", "dask"))]
    ['--jobs 2@2000', '--scheduler local --jobs 2 (Dask)@2000']
    """
    labels = [CONFIGS[c] for c in CONFIGS if c in configs]
    runs = []
    for r in range(repeat):
        # alternate the order too, so no configuration always follows the same one
        for label in (labels if r % 2 == 0 else labels[::-1]):
            runs.append((r, label, count))
    memory = [n for n in (small, rss_count) if n is not None and (n != count or not repeat)]
    runs += [("rss", JOBS2, n) for n in memory]
    return runs


def summary(results, count, rss_count, small):
    """Lines of medians and ratios of medians (throughput), and the RSS ratio.

    ``results``: ``(label, signals, wall s, peak RSS MB, round)`` per run (round ``"rss"``: the memory pair).
    """
    rounds = [r for r in results if r[4:] != ("rss",)]     # the memory pair is not a throughput round
    rate = {label: statistics.median(count / w for (lbl, n, w, *_) in rounds if lbl == label and n == count)
            for label in EXTRA if any(lbl == label and n == count for (lbl, n, *_) in rounds)}
    lines = [f"median signals / s over the rounds, {count} signals: "
             + ", ".join(f"{label} {v:.2f}" for label, v in rate.items())] if rate else []
    if JOBS1 in rate and JOBS2 in rate:
        lines.append(f"--jobs 2 / --jobs 1 (ratio of medians): {rate[JOBS2] / rate[JOBS1]:.2f}x (target >= 1.7x)")
    if DASK in rate and JOBS2 in rate:
        lines.append(f"Dask / joblib (ratio of medians): {rate[DASK] / rate[JOBS2]:.2f} (target >= 0.85)")
    rss = {n: statistics.median(m for (lbl, k, _, m, *_) in results if lbl == JOBS2 and k == n)
           for n in {small, rss_count or count} if any(lbl == JOBS2 and k == n for (lbl, k, *_) in results)}
    if len(rss) == 2:
        big = rss_count or count
        lines.append(f"parent peak RSS (median of the --jobs 2 runs), {big} vs {small} signals: "
                     f"{rss[big]:.0f} / {rss[small]:.0f} MB = {rss[big] / rss[small]:.2f}x (target <= 1.5x)")
    return lines


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=2000, help="cohort size of the throughput runs")
    p.add_argument("--repeat", type=int, default=3,
                   help="rounds of the throughput runs (medians over them); 0: the memory pair only")
    p.add_argument("--rss-count", type=int, default=None,
                   help="cohort size whose peak RSS is compared with --small's (default: --count)")
    p.add_argument("--small", type=int, default=200, help="cohort size the peak RSS is compared with")
    p.add_argument("--duration", type=float, default=50.0, help="seconds per signal (100 Hz)")
    p.add_argument("--no-dask", action="store_true", help="skip the Dask LocalCluster runs (drops dask from --configs)")
    p.add_argument("--configs", default=",".join(CONFIGS),
                   help=f"the throughput configurations, comma-separated among {', '.join(CONFIGS)} (default: all)")
    args = p.parse_args(argv)
    configs = [c.strip() for c in args.configs.split(",") if c.strip()]
    if not configs or set(configs) - set(CONFIGS):
        p.error(f"--configs takes a comma-separated choice of {', '.join(CONFIGS)}, got {args.configs!r}")
    if args.no_dask:
        configs = [c for c in configs if c != "dask"]
    if args.repeat < 0:
        p.error(f"--repeat needs 0 rounds or more, got {args.repeat}")
    print(f"{os.cpu_count()} cores; signals of {args.duration:g} s at 100 Hz; WAKE (C core) + BMFLC, E-BMFLC, WFLC",
          flush=True)
    print("| round | run | signals | load before | wall s | signals / s | parent peak RSS MB |\n"
          "|---|---|---:|---:|---:|---:|---:|", flush=True)
    results = []
    for rnd, label, count in plan(args.count, args.repeat, args.rss_count, args.small, configs):
        load = os.getloadavg()[0]
        out = Path(tempfile.mkdtemp(prefix="wake-cohort-"))
        try:
            wall, rss = run(out, count, EXTRA[label], args.duration)
        finally:
            shutil.rmtree(out, ignore_errors=True)
        results.append((label, count, wall, rss, rnd))
        print(f"| {rnd if rnd == 'rss' else rnd + 1} | {label} | {count} | {load:.1f} | {wall:.1f} | "
              f"{count / wall:.2f} | {rss:.0f} |", flush=True)
    print(f"\nload average at end {os.getloadavg()[0]:.2f}")
    for line in summary(results, args.count, args.rss_count, args.small):
        print(line)


if __name__ == "__main__":
    main()
