"""WAKE's defaults at sampling rates other than 100 Hz (the figures behind ``RateWarning``).

    python bench/sampling_rates.py

Synthetic signal 10 dB SNR (seed 3, 30 s) made at 100 Hz and resampled to
250 and 1000 Hz (``scipy.signal.resample_poly``); WAKE with the default
level 5 and AR orders 17, 17 fs/100 and 60; voluntary NRMSE after the first
HPA window and the HPA flags.
"""

import warnings

from scipy.signal import resample_poly

from wake import WakeFilter
from wake.eval.metrics import nrmse
from wake.eval.synthetic import make_signal


def main():
    warnings.simplefilter("ignore")
    s = make_signal(10.0, seed=3, duration=30.0)
    print("| fs (Hz) | ar_order | voluntary NRMSE | HPA flags |")
    print("|---:|---:|---:|---|")
    for fs, up, down in ((100, 1, 1), (250, 5, 2), (1000, 10, 1)):
        x, v = resample_poly(s.measurement, up, down), resample_poly(s.voluntary, up, down)
        for p in sorted({17, round(17 * fs / 100), 60}):
            r = WakeFilter(fs=float(fs), ar_order=p, backend="reference").run(x)
            flags = [u.flags[0] if u.flags else "ok" for u in r.hpa[0]]
            counts = ", ".join(f"{f} {flags.count(f)}" for f in sorted(set(flags)))
            print(f"| {fs} | {p} | {nrmse(v, r.voluntary, r.warmup):.4f} | {counts} |")


if __name__ == "__main__":
    main()
