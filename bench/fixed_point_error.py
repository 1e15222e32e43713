"""Worst arithmetic error of the C core against the float reference (docs/studies/fixed_point.md, "Measured").

    python bench/fixed_point_error.py

For each Kalman configuration: 6000 samples of a smooth signal at 1.5/4 of
full scale, random unit-DC-gain weights, sym3/db4/haar at levels 3, 5 and
6; the C core (``FixedPointRTP``) against a ``ReferenceRTP`` with exactly its
quantised configuration and Q15-rounded input.  Prints a Markdown table in
Q15 LSB of full scale.  Needs the compiled core (``pip install -e .``).
"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "rtp"), str(ROOT / "tests"), str(ROOT)]

from test_fixed_point import FixedPointRTP, filter_bank_taps, make_weights, quantized, smooth_signal, twin  # noqa: E402

CONFIGS = [("inert (P = 0, q = 0)", 0.0, 0.0), ("q/R = 1e-2, p0 = R", 1e-2, 1.0), ("q/R = 1e-3, p0 = 0", 1e-3, 0.0),
           ("q/R = 1e-4, p0 = R", 1e-4, 1.0), ("q/R = 1e-5, p0 = R", 1e-5, 1.0), ("q = 0, p0 = 10 R", 0.0, 10.0)]


def worst_error_lsb(q_ratio, p0_ratio, n=6000, fs=4.0):
    worst = 0.0
    for level in (3, 5, 6):
        for wavelet in ("sym3", "db4", "haar"):
            rng = np.random.default_rng(level * 7 + len(wavelet))
            x = smooth_signal(n, rng, amp=1.5)
            r = (0.2 * 1.5) ** 2
            c = FixedPointRTP(filter_bank_taps(wavelet, level), make_weights(rng, level), r, q_ratio * r,
                              p0_ratio * r, full_scale=fs)
            ref = twin(c)
            y_ref = np.array([ref.step(v) for v in quantized(x, fs)])
            worst = max(worst, float(np.max(np.abs(c.run(x) - y_ref))) / fs * 32768)
    return worst


def main():
    print("| configuration | worst error |")
    print("|---|---|")
    for label, q_ratio, p0_ratio in CONFIGS:
        print(f"| {label} | {worst_error_lsb(q_ratio, p0_ratio):.3f} LSB |")


if __name__ == "__main__":
    main()
