"""Tremor ahead at other input rates: the gated command's NRMSE after 5 s and whole (from 0.5 s) on the paper's
synthetic set resampled from 100 Hz with scipy.signal.resample_poly (the truth s_t likewise), C core;
docs/studies/design.md, "Tremor ahead", "At other input rates".

    python bench/rate_ahead.py 100 250 500 1000     # about 4 minutes
"""

import sys

import numpy as np
from scipy.signal import resample_poly

from wake import WakeFilter
from wake.eval.metrics import nrmse
from wake.eval.synthetic import paper_dataset

HORIZONS_MS = (10, 20, 50, 100)


def main(rates):
    for fs in rates:
        for ms in HORIZONS_MS:
            after, whole, zero = [], [], []
            for s in paper_dataset():
                x = resample_poly(s.measurement, fs, 100) if fs != 100 else s.measurement
                truth = resample_poly(s.tremor, fs, 100) if fs != 100 else s.tremor
                h = int(np.floor(ms * fs / 1000 + 0.5))
                command = WakeFilter(fs=float(fs), horizon=h, backend="c").run(x).command
                after.append(nrmse(truth, command, start=5 * fs))
                whole.append(nrmse(truth, command, start=fs // 2))
                zero.append(nrmse(truth, np.zeros_like(truth), start=5 * fs))
            print(f"fs {fs:5d} Hz, h {ms:3d} ms: gated after 5 s {np.mean(after):.4f}, "
                  f"whole (from 0.5 s) {np.mean(whole):.4f}, zero after 5 s {np.mean(zero):.4f}")


if __name__ == "__main__":
    main([int(r) for r in sys.argv[1:]] or [100, 250, 500, 1000])
