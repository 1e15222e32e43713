"""The result file of a 10-minute, 2-channel recording at 100 Hz: size and writing time with ``%.17g`` (the
writer before issue 43) and with the shortest exact form (``wake.io.writers.exact_lines``), in one process.

The recording is a gyroscope written with 5 decimals (as a logger writes it); the filter's outputs are
full doubles.  Usage: ``python bench/write_exact.py`` (prints sizes, the median of 5 timings, and ratios).
"""

import io
import statistics
import time

import numpy as np

from wake import WakeFilter
from wake.io.writers import exact_lines

FS, SECONDS = 100.0, 600.0


def table():
    rng = np.random.default_rng(0)
    t = np.arange(int(FS * SECONDS)) / FS
    x = np.round(np.column_stack([40 * np.sin(2 * np.pi * 0.3 * t) + 8 * np.sin(2 * np.pi * 6 * t),
                                  30 * np.sin(2 * np.pi * 0.2 * t) + 5 * np.sin(2 * np.pi * 5 * t)])
                 + rng.normal(0, 0.5, (t.size, 2)), 5)
    res = WakeFilter(fs=FS).run(x)
    cols = [t]
    for c in range(2):
        cols += [x[:, c], res.voluntary[:, c], res.tremor[:, c]]
    return np.column_stack(cols)


def old(a):
    buf = io.StringIO()
    np.savetxt(buf, a, delimiter=",", fmt="%.17g")
    return buf.getvalue()


def timed(f, a, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        text = f(a)
        times.append(time.perf_counter() - t0)
    return text, statistics.median(times)


def main():
    a = table()
    before, t_before = timed(old, a)
    after, t_after = timed(exact_lines, a)
    back = np.array([[float(v) for v in line.split(",")] for line in after.splitlines()])
    assert np.array_equal(back, a, equal_nan=True), "the shortest form must read back bit for bit"
    print(f"{a.shape[0]} rows x {a.shape[1]} columns (10 min, 2 channels at {FS:g} Hz)")
    print(f"%.17g:        {len(before) / 1e6:.2f} MB in {t_before:.3f} s")
    print(f"shortest exact: {len(after) / 1e6:.2f} MB in {t_after:.3f} s (reads back bit for bit)")
    print(f"ratios after/before: size {len(after) / len(before):.3f}, time {t_after / t_before:.3f}")


if __name__ == "__main__":
    main()
