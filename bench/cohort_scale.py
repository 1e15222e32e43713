"""Throughput and memory of ``wake evaluate`` on a generated cohort: serial, joblib and Dask side by side.

    python bench/cohort_scale.py                       # 2,000 signals of 50 s at 100 Hz, and 200 for memory
    python bench/cohort_scale.py --count 400 --rss-count 2000 --small 200   # throughput on 400 signals

Every run is ``wake evaluate OUT --synthetic N --backend c`` (WAKE on the C
core and the three baselines, one configuration) in a fresh process, into a
fresh folder, so each computes every task.  The table gives wall time from
start to report, throughput (signals per second) and the peak RSS of the
parent process (``ru_maxrss`` of that process alone: workers are not
counted).  Targets (docs/evaluation.md, "At cohort scale"): ``--jobs 2`` at
>= 1.7x the throughput of ``--jobs 1``; a Dask LocalCluster of 2 workers
within 15 % of joblib's throughput; peak RSS for N signals within 1.5x of
that for N/10.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Runs the command in this process and prints its own peak RSS (kB on Linux) as the last line.
_CHILD = ("import json, resource, sys; from wake.eval.evaluate import cli; status = cli(sys.argv[1:]); "
          "print(json.dumps({'status': status, 'maxrss_kb': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}))")


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


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=2000, help="cohort size of the throughput runs")
    p.add_argument("--rss-count", type=int, default=None,
                   help="cohort size whose peak RSS is compared with --small's (default: --count)")
    p.add_argument("--small", type=int, default=200, help="cohort size the peak RSS is compared with")
    p.add_argument("--duration", type=float, default=50.0, help="seconds per signal (100 Hz)")
    p.add_argument("--no-dask", action="store_true", help="skip the Dask LocalCluster run")
    args = p.parse_args(argv)
    big = args.count if args.rss_count is None else args.rss_count
    runs = [("--jobs 2", args.small, ["--jobs", "2"])] + ([("--jobs 2", big, ["--jobs", "2"])] if big != args.count
                                                          else [])
    runs += [("--jobs 1", args.count, ["--jobs", "1"]), ("--jobs 2", args.count, ["--jobs", "2"])]
    if not args.no_dask:
        runs.append(("--scheduler local --jobs 2 (Dask)", args.count, ["--scheduler", "local", "--jobs", "2"]))
    print(f"{os.cpu_count()} cores, load average at start {os.getloadavg()[0]:.2f}; "
          f"signals of {args.duration:g} s at 100 Hz; WAKE (C core) + BMFLC, E-BMFLC, WFLC", flush=True)
    print("| run | signals | wall s | signals / s | parent peak RSS MB |\n|---|---:|---:|---:|---:|", flush=True)
    results = {}
    for label, count, extra in runs:
        out = Path(tempfile.mkdtemp(prefix="wake-cohort-"))
        try:
            wall, rss = run(out, count, extra, args.duration)
        finally:
            shutil.rmtree(out, ignore_errors=True)
        results[(label, count)] = (count / wall, rss)
        print(f"| {label} | {count} | {wall:.1f} | {count / wall:.2f} | {rss:.0f} |", flush=True)
    print(f"\nload average at end {os.getloadavg()[0]:.2f}")
    one, two = results[("--jobs 1", args.count)][0], results[("--jobs 2", args.count)][0]
    print(f"--jobs 2 / --jobs 1 throughput: {two / one:.2f}x (target >= 1.7x)")
    dask = results.get(("--scheduler local --jobs 2 (Dask)", args.count))
    if dask:
        print(f"Dask / joblib throughput: {dask[0] / two:.2f} (target within 15 %: >= 0.85)")
    rss_big, rss_small = results[("--jobs 2", big)][1], results[("--jobs 2", args.small)][1]
    print(f"parent peak RSS, {big} vs {args.small} signals: {rss_big / rss_small:.2f}x (target <= 1.5x)")


if __name__ == "__main__":
    main()
