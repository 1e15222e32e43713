"""``WakeFilter(backend="c").run`` against five ``scipy.signal.lfilter`` calls, as ratios in one process (issue 44).

    python bench/run_ratio.py [--repeats 9] [--profile]

On 50 s of a synthetic recording at 100 Hz: ``run`` with the default settings, with ``horizon=5`` and with
``hpa_backend="c"``, each against five ``lfilter`` calls of a 32-tap FIR over the same samples (what a
plain filter bank of that length costs through numpy).  Medians over ``--repeats`` alternating runs of the
process's CPU time (another process's time slice is not counted); the load average is printed with them (the ratio is what carries from run to run, not the times).  The
issue's targets: <= 12x with the default HPA, <= 5x with ``hpa_backend="c"``.  ``--profile`` prints
cProfile's top entries of one default ``run`` on 200 s (where the remaining time goes).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.synthetic import make_signal  # noqa: E402

CASES = {"default": {}, "horizon=5": {"horizon": 5}, 'hpa_backend="c"': {"hpa_backend": "c"}}
FIR = np.hanning(32) / np.hanning(32).sum()


def five_lfilter(x):
    for _ in range(5):
        lfilter(FIR, 1.0, x)


def timed(fn, *args):
    """CPU time of the process (not wall time: on a shared machine another process's slice is not ours)."""
    t = time.process_time()
    fn(*args)
    return time.process_time() - t


def measure(repeats=9, seconds=50.0, fs=100.0):
    x = make_signal(10.0, seed=4, fs=fs, duration=seconds).measurement
    filters = {name: WakeFilter(fs=fs, backend="c", **kw) for name, kw in CASES.items()}
    for f in filters.values():
        f.run(x)                                  # warm: imports, caches
    times = {name: [] for name in CASES}
    base = []
    for _ in range(repeats):
        base.append(timed(five_lfilter, x))
        for name, f in filters.items():
            times[name].append(timed(f.run, x))
    ref = float(np.median(base))
    return ref, {name: float(np.median(t)) for name, t in times.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    ref, res = measure(args.repeats)
    print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}, {os.cpu_count()} cores")
    print(f"five lfilter (32 taps), 5,000 samples: {ref * 1e3:.3f} ms")
    for name, t in res.items():
        print(f"run, {name:18s} {t * 1e3:8.2f} ms  {t / ref:6.1f}x five lfilter")
    if args.profile:
        x = make_signal(10.0, seed=4, duration=200.0).measurement
        for name in ("default", 'hpa_backend="c"'):
            f = WakeFilter(backend="c", **CASES[name])
            f.run(x)
            prof = cProfile.Profile(time.process_time)
            prof.runcall(f.run, x)
            print(f"cProfile (CPU time) of run, {name}, on 200 s:")
            pstats.Stats(prof).sort_stats("cumulative").print_stats(25)
    return ref, res


if __name__ == "__main__":
    main()
