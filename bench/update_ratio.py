"""``WakeFilter.update`` against one bare ``FixedPointRTP.step``, as a ratio measured in one process (issue 44).

    python bench/update_ratio.py [--fs 100] [--repeats 7]

A C-backend filter is warmed up on 20 s of a synthetic recording (so the C core runs, with HPA weights,
a tremor-ahead predictor and the full scale set); then the next 30 s are fed by ``update()`` in chunks of
100 samples, each chunk timed.  A ``FixedPointRTP`` with the same taps is stepped over the same samples,
timed the same way.  The ratio is of the medians of the per-sample times over the chunks: a chunk that
holds an HPA point (one in five at 100 Hz) is an outlier the median leaves out, so the ratio is that of the
per-sample path, the HPA's own cost apart (the mean over all chunks, HPA included, is printed beside it).  Printed with each layer in between (``Channel.update``,
``AdaptiveRTP.step``), so that a slow layer shows.  The issue's target: ``update`` <= 4x ``step``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.synthetic import make_signal  # noqa: E402

CHUNK = 100


def chunk_times(fn, values):
    """Median and mean over chunks of CHUNK samples of the time per sample of ``fn(v)``."""
    out = []
    clock = time.perf_counter
    for k in range(0, len(values) - CHUNK + 1, CHUNK):
        part = values[k:k + CHUNK]
        t = clock()
        for v in part:
            fn(v)
        out.append((clock() - t) / CHUNK)
    return float(np.median(out)), float(np.mean(out))


def measure(fs=100.0, repeats=7, warm_s=20.0, run_s=30.0):
    x = make_signal(10.0, seed=3, fs=fs, duration=warm_s + run_s).measurement
    warm = int(warm_s * fs)
    rest = [float(v) for v in x[warm:]]
    rows = {"WakeFilter.update": [], "Channel.update": [], "AdaptiveRTP.step": [], "FixedPointRTP.step": []}
    for _ in range(repeats):
        filt = WakeFilter(fs=fs, backend="c")
        filt.update_block(x[:warm])
        rows["WakeFilter.update"].append(chunk_times(filt.update, rest))
        filt = WakeFilter(fs=fs, backend="c")
        filt.update_block(x[:warm])
        ch = filt._channels[0]
        rows["Channel.update"].append(chunk_times(lambda v: ch.update(v, filt._executor), rest))
        rtp = ch.rtp
        rows["AdaptiveRTP.step"].append(chunk_times(rtp.step, rest))
        core = rtp.core
        rows["FixedPointRTP.step"].append(chunk_times(core.step, rest))
    return {k: tuple(float(m) for m in np.median(np.array(v), axis=0)) for k, v in rows.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fs", type=float, default=100.0)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    res = measure(args.fs, args.repeats)
    base = res["FixedPointRTP.step"][0]
    print(f"load average {os.getloadavg()[0]:.2f} (1 min), {os.cpu_count()} cores; fs {args.fs:g} Hz")
    print(f"{'':20s} {'median per chunk':>22s} {'mean (HPA included)':>24s}")
    for name, (med, mean) in res.items():
        print(f"{name:20s} {med * 1e6:9.3f} us {med / base:6.2f}x {mean * 1e6:11.3f} us {mean / base:7.2f}x")
    return res


if __name__ == "__main__":
    main()
