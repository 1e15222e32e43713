"""``WakeFilter(backend="c").run`` against five ``scipy.signal.lfilter`` calls, as ratios in one process (issue 44).

    python bench/run_ratio.py [--repeats 9] [--profile]

On 50 s of a synthetic recording at 100 Hz: ``run`` with the default settings, with ``horizon=5`` and with
``hpa_backend="c"``, each against five ``lfilter`` calls of a 32-tap FIR over the same samples (what a
plain filter bank of that length costs through numpy).  Medians over ``--repeats`` alternating runs of the
process's CPU time (another process's time slice is not counted); the load average is printed with them (the ratio is what carries from run to run, not the times).  The
issue's targets: <= 12x with the default HPA, <= 5x with ``hpa_backend="c"``.  ``--profile`` prints
cProfile's top entries of one default ``run`` on 200 s (where the remaining time goes).  ``--c-calls`` times
every call into the C core inside ``run`` with ``hpa_backend="c"`` (the C HPA's set-up, run and result, the
RTP's blocks and installs) and prints their sum beside the whole run, both as ratios to five ``lfilter``: the
floor that a C loop over the HPA windows (no Python between them) would approach.
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


#: The C core's entries whose time --c-calls adds up (every call of run(hpa_backend="c") into C but cffi's own)
C_CALLS = ("wake_hpa_init", "wake_hpa_start", "wake_hpa_run", "wake_hpa_take", "wake_rtp_run_outputs",
           "wake_rtp_set_weights", "wake_rtp_set_ahead", "wake_rtp_set_ahead_ramp", "wake_rtp_load_state",
           "wake_batch_run")


def c_calls(repeats=15, seconds=50.0, fs=100.0):
    """(five lfilter, run with hpa_backend="c", the C calls inside that run): medians of CPU seconds."""
    import statistics

    import wake.hpa.c_batch as c_batch
    import wake.hpa.c_port as c_port
    import wake.rtp.fixed as fixed

    spent = [0.0]

    class Timed:
        """The cffi library with the calls of C_CALLS timed (everything else passed through)."""

        def __init__(self, lib):
            self._lib = lib

        def __getattr__(self, name):
            fn = getattr(self._lib, name)
            if name not in C_CALLS:
                return fn

            def timed_call(*args):
                t = time.process_time()
                try:
                    return fn(*args)
                finally:
                    spent[0] += time.process_time() - t
            return timed_call

    ffi, lib = c_port._core()
    saved = c_port._core, c_batch._core, fixed.lib
    c_port._core = c_batch._core = lambda: (ffi, Timed(lib))   # the batch driver's one call included
    fixed.lib = Timed(fixed.lib)
    try:
        x = make_signal(10.0, seed=4, fs=fs, duration=seconds).measurement
        f = WakeFilter(fs=fs, backend="c", hpa_backend="c")
        f.run(x)
        base, runs, inside = [], [], []
        for _ in range(repeats):
            base.append(timed(five_lfilter, x))
            spent[0] = 0.0
            runs.append(timed(f.run, x))
            inside.append(spent[0])
    finally:
        c_port._core, c_batch._core, fixed.lib = saved
    return statistics.median(base), statistics.median(runs), statistics.median(inside)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--profile", action="store_true")
    parser.add_argument("--c-calls", action="store_true", help='the C calls inside run(hpa_backend="c"), summed')
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    if args.c_calls:
        ref, whole, inside = c_calls(max(args.repeats, 15))
        print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}, {os.cpu_count()} cores")
        print(f'run, hpa_backend="c": {whole / ref:.1f}x five lfilter, of which its C calls {inside / ref:.1f}x '
              f"(timer overhead included); the Python around them {(whole - inside) / ref:.1f}x")
        return ref, {"c_calls": inside, "whole": whole}
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
