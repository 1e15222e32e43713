"""99.9th-percentile latency of ``WakeFilter.update()``, HPA inline vs on a worker thread.

    python bench/streaming_latency.py [--seconds 600] [--backend c|reference]

Streams a synthetic recording sample by sample and times every ``update()``
call with ``time.perf_counter_ns``.  With ``hpa_mode="inline"`` the call that
completes a window also runs the HPA; with ``hpa_mode="thread"`` the HPA
runs on a worker thread and its weights are swapped in between two later
samples.  Prints median, p99, p99.9 and max in microseconds for both modes,
measured in one run.
"""

import argparse
import sys
import time

import numpy as np

from wake import WakeFilter
from wake.config import WakeConfig
from wake.eval.synthetic import make_signal


def latencies(x, **kwargs):
    f = WakeFilter(**kwargs)
    out = np.empty(x.size, dtype=np.int64)
    clock = time.perf_counter_ns
    update = f.update
    for i, v in enumerate(x):
        t0 = clock()
        update(v)
        out[i] = clock() - t0
    f.close()
    return out / 1000.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=600.0, help="stream length at 100 Hz (default 600 s)")
    ap.add_argument("--backend", default=None, choices=("c", "reference"))
    args = ap.parse_args()
    backend = WakeConfig(backend=args.backend).backend  # None: the C core when installed
    x = make_signal(10.0, seed=7, duration=args.seconds).measurement
    print(f"{x.size} samples, backend {backend}, HPA every 500 samples")
    print("| HPA mode | median (us) | p99 (us) | p99.9 (us) | max (us) |")
    print("|---|---|---|---|---|")
    default_interval = sys.getswitchinterval()
    for mode, interval in (("inline", default_interval), ("thread", default_interval), ("thread", 2e-4)):
        sys.setswitchinterval(interval)
        lat = latencies(x, backend=backend, hpa_mode=mode)
        sys.setswitchinterval(default_interval)
        p = np.percentile(lat, [50, 99, 99.9])
        label = f"{mode}, switch interval {interval * 1e3:g} ms"
        print(f"| {label} | {p[0]:.1f} | {p[1]:.1f} | {p[2]:.1f} | {lat.max():.1f} |")


if __name__ == "__main__":
    main()
