"""Why PADS tremor at 50 Hz scores above 100 Hz, and how far the 50 Hz settings can close it (issue 33).

    python bench/rate_50hz.py                  # offset 0 only (the rate table's setting), under a minute
    python bench/rate_50hz.py --offsets 20     # the recordings also started 0.05 .. 0.95 s later, about 5 min
    python bench/rate_50hz.py --whole          # whole recordings instead of after 5 s (with --offsets too)
    python bench/rate_50hz.py --sweep          # one setting at a time at 50 Hz, PADS and synthetic, about 2 min
    python bench/rate_50hz.py --sweep --at 100 # the same settings at 100 Hz
    python bench/rate_50hz.py --rates 50 55 60 75 --offsets 20   # the candidates at other low rates, about 8 min

Signals, truth and scores as in bench/sampling_rates.py: the PADS recordings read at 100 Hz and taken to
the test rate with ``scipy.signal.resample_poly``; the truth is the tremor of
:func:`wake.eval.warmup.independent_ground_truth` computed at 100 Hz and resampled the same way; PADS
tremor NRMSE after 5 s, mean of the 60 recording-axes; float64 reference RTP and Python HPA.

Columns of the decomposition (one row per start offset):

- ``100 Hz``: the shipped filter at 100 Hz, predicting 10 ms ahead (the rate table's 0.1133);
- ``100 Hz scored at 50 Hz``: the same tremor estimate taken to 50 Hz with the resampler the truth goes
  through, scored against the 50 Hz truth: what the 50 Hz scoring alone costs (the truth loses its
  25-50 Hz part, so its range, the NRMSE's denominator, shrinks);
- ``100 Hz, 20 ms``: the 100 Hz filter predicting 2 samples (20 ms) ahead, as a 50 Hz filter must: the
  HPA fits the weights to the voluntary truth 2 samples ahead, the start-up prior aims 2 samples ahead and
  the output is aligned 2 samples on (the Kalman is inert at the defaults, ``P = 0``, so nothing else
  reads the horizon); and that estimate scored at 50 Hz;
- ``50 Hz`` settings: today's (level 5, ``ar_order`` 17, ``mode`` constant) and the variants below;
  ``today, truth at 50 Hz``: today's estimate against the truth found on the 50 Hz signal itself
  (``independent_ground_truth`` at 50 Hz) instead of the resampled 100 Hz truth.

``--cutoffs``: today's 50 Hz filter with each HPA's cut-off found as at 100 Hz (AR(17) spectrum of the
same stretch of the 100 Hz recording, the 100 Hz cut-off rule), the rest of the HPA at 50 Hz: does the
50 Hz spectral analysis pick worse cut-offs?

``--offsets N`` drops the first 0, 5, .., 5 (N - 1) samples of every 100 Hz recording before anything
else: the same motion, the HPA windows falling elsewhere on it (the recordings last 10.3 s, so the
after-5-s score rests on one or two HPA windows).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np
from scipy.signal import resample_poly

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wake.filter  # noqa: E402
import wake.hpa.prior  # noqa: E402
import wake.hpa.run  # noqa: E402
import wake.target  # noqa: E402
from wake import WakeConfig, WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.metrics import nrmse  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth  # noqa: E402
from wake.hpa.spectrum import window_order  # noqa: E402
from wake.target import PredictionTarget  # noqa: E402

AFTER_S = 5.0
#: the 50 Hz settings compared (keyword arguments of WakeFilter on top of its defaults)
TODAY = "today (constant, p 17)"
VARIANTS = {
    TODAY: dict(mode="constant", ar_order=17),
    "symmetric": dict(mode="symmetric", ar_order=17),
    "p 15": dict(mode="constant", ar_order=15),
    "symmetric, p 14": dict(mode="symmetric", ar_order=14),
    "symmetric, p 15": dict(mode="symmetric", ar_order=15),
    "symmetric, p 16": dict(mode="symmetric", ar_order=16),
}
SWEEP = [dict(ar_order=p) for p in (8, 10, 14, 17, 20, 25, 34)] + \
        [dict(window_s=w) for w in (3.0, 4.0, 4.5, 5.5, 6.0, 8.0)] + \
        [dict(level=4), dict(level=6), dict(cutoff_rule="shallow"), dict(default_cutoff=2.5),
         dict(shallow_max=3.0), dict(tremor_band=(3.0, 15.0)), dict(ridge=1e-5), dict(wavelet="db4"),
         dict(mode="symmetric"), dict(mode="smooth")]


@contextlib.contextmanager
def horizon(h: int):
    """Every reader of :data:`wake.target.TARGET` sees a prediction ``h`` samples ahead (float reference only)."""
    target, modules = PredictionTarget(horizon=h), (wake.target, wake.hpa.run, wake.hpa.prior, wake.filter)
    old = wake.target.TARGET
    for m in modules:
        m.TARGET = target
    try:
        yield target
    finally:
        for m in modules:
            m.TARGET = old


def tremor(x, fs, h=1, **kw):
    """``x`` minus the voluntary motion WAKE predicted for each sample ``h`` samples before it."""
    with horizon(h) as target:
        return x - target.voluntary_from(WakeFilter(fs=float(fs), backend="reference", **kw).run(x).prediction)


def resample(x, fs):
    r = Fraction(int(fs), 100)
    return x if r == 1 else resample_poly(x, r.numerator, r.denominator)


def pads_axes(pads, offset):
    """(x at 100 Hz, tremor truth at 100 Hz) of every recording-axis, the first ``offset`` samples dropped."""
    for rec in pads:
        for c in range(rec.samples.shape[1]):
            x = rec.samples[offset:, c]
            yield x, independent_ground_truth(x, rec.fs)[1]


def decomposition(pads, offset, variants, after_s=AFTER_S):
    cols = {k: [] for k in ("100", "100 at 50", "100 20 ms", "100 20 ms at 50", *variants,
                            "today, truth at 50 Hz")}
    for x, truth in pads_axes(pads, offset):
        x50, t50 = resample(x, 50), resample(truth, 50)
        for h, name in ((1, "100"), (2, "100 20 ms")):
            est = tremor(x, 100, h)
            cols[name].append(nrmse(truth, est, int(after_s * 100)))
            cols[name + " at 50"].append(nrmse(t50, resample(est, 50), int(after_s * 50)))
        for name, kw in variants.items():
            cols[name].append(nrmse(t50, tremor(x50, 50, **kw), int(after_s * 50)))
        own = independent_ground_truth(x50, 50.0)[1]
        cols["today, truth at 50 Hz"].append(nrmse(own, tremor(x50, 50, **VARIANTS[TODAY]), int(after_s * 50)))
    return {k: float(np.mean(v)) for k, v in cols.items()}


def print_rows(rows, offsets):
    names = list(rows[0])
    print("| start offset (s) | " + " | ".join(names) + " |")
    print("|---:|" + "---:|" * len(names))
    for off, r in zip(offsets, rows):
        print(f"| {off / 100:.2f} | " + " | ".join(f"{r[k]:.4f}" for k in names) + " |", flush=True)
    if len(rows) > 1:
        A = np.array([[r[k] for k in names] for r in rows])
        rel = 100 * (A / A[:, :1] - 1)
        print("| mean | " + " | ".join(f"{v:.4f}" for v in A.mean(0)) + " |")
        print("| vs 100 Hz, mean (min, max) | " + " | ".join(
            f"{m:+.1f} % ({lo:+.1f}, {hi:+.1f})" for m, lo, hi in zip(rel.mean(0), rel.min(0), rel.max(0))) + " |")


def synthetic(fs, kw):
    after, whole = [], []
    for s in paper_dataset():
        x, v = resample(s.measurement, fs), resample(s.voluntary, fs)
        est = x - tremor(x, fs, **kw)
        after.append(nrmse(v, est, int(AFTER_S * fs)))
        whole.append(nrmse(v, est))
    return float(np.mean(after)), float(np.mean(whole))


def pads_at(pads, fs, kw, offset=0):
    after, whole = [], []
    for x, truth in pads_axes(pads, offset):
        xr, tr = resample(x, fs), resample(truth, fs)
        est = tremor(xr, fs, **kw)
        after.append(nrmse(tr, est, int(AFTER_S * fs)))
        whole.append(nrmse(tr, est))
    return float(np.mean(after)), float(np.mean(whole))


@contextlib.contextmanager
def cutoffs_as_at_100_hz(x100, x50):
    """Each 50 Hz HPA takes the cut-off the 100 Hz analysis finds on the same stretch of ``x100``."""
    config, psd, find = WakeConfig(fs=100.0, backend="reference"), wake.hpa.run.ar_psd, wake.hpa.run.find_cutoff
    seen = {}

    def spectrum(window, fs, order):
        seen["window"] = np.asarray(window)
        return psd(window, fs, order)

    def cutoff(freqs, density, **kw):
        w = seen["window"]
        end = next(e for e in range(w.size, x50.size + 1) if np.array_equal(x50[e - w.size:e], w))
        stretch = x100[2 * (end - w.size):2 * end]
        return find(*psd(stretch, 100.0, window_order(stretch.size, config.ar_order)), **kw)

    wake.hpa.run.ar_psd, wake.hpa.run.find_cutoff = spectrum, cutoff
    try:
        yield
    finally:
        wake.hpa.run.ar_psd, wake.hpa.run.find_cutoff = psd, find


def cutoffs(pads):
    native, at100 = [], []
    for x, truth in pads_axes(pads, 0):
        x50, t50 = resample(x, 50), resample(truth, 50)
        native.append(nrmse(t50, tremor(x50, 50, **VARIANTS[TODAY]), int(AFTER_S * 50)))
        with cutoffs_as_at_100_hz(x, x50):
            at100.append(nrmse(t50, tremor(x50, 50, **VARIANTS[TODAY]), int(AFTER_S * 50)))
    print(f"50 Hz PADS tremor after 5 s: cut-offs found at 50 Hz {np.mean(native):.4f}, "
          f"found as at 100 Hz {np.mean(at100):.4f}")


def sweep(pads, fs=50):
    print(f"| {fs} Hz setting | PADS tremor, after 5 s | PADS whole | synthetic voluntary, after 5 s | synthetic whole |")
    print("|---|---:|---:|---:|---:|")
    for kw in [dict(), *SWEEP, *VARIANTS.values()]:
        pa, pw = pads_at(pads, fs, kw)
        sa, sw = synthetic(fs, kw)
        name = ", ".join(f"{k} {v}" for k, v in kw.items()) or "defaults"
        print(f"| {name} | {pa:.4f} | {pw:.4f} | {sa:.4f} | {sw:.4f} |", flush=True)


def rates(pads, fss, offsets):
    base = [pads_at(pads, 100, {}, off)[0] for off in offsets]
    print("| fs (Hz) | settings | PADS after 5 s, offset 0 | PADS mean over offsets | vs 100 Hz, mean | "
          "offsets better than today | synthetic after 5 s |")
    print("|---:|---|---:|---:|---:|---:|---:|")
    for fs in fss:
        today = None
        for name in (TODAY, "symmetric", "symmetric, p 15"):
            v = np.array([pads_at(pads, fs, VARIANTS[name], off)[0] for off in offsets])
            today = v if today is None else today
            rel = 100 * np.mean(v / np.array(base) - 1)
            print(f"| {fs} | {name} | {v[0]:.4f} | {v.mean():.4f} | {rel:+.1f} % | {int(np.sum(v < today))}/"
                  f"{len(offsets)} | {synthetic(fs, VARIANTS[name])[0]:.4f} |", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--offsets", type=int, default=1, help="start offsets 0, 0.05, .. s (default 1: offset 0)")
    ap.add_argument("--at", type=int, default=50, help="the rate --sweep runs at (default 50 Hz)")
    ap.add_argument("--whole", action="store_true", help="score whole recordings instead of after 5 s")
    ap.add_argument("--sweep", action="store_true", help="one setting at a time at 50 Hz instead")
    ap.add_argument("--rates", type=int, nargs="*", help="the 50 Hz candidates at these rates instead")
    ap.add_argument("--cutoffs", action="store_true", help="50 Hz with the cut-offs found as at 100 Hz instead")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    folder = default_pads_dir()
    pads = load_pads_folder(folder) if folder is not None and Path(folder).is_dir() else []
    if not pads:
        sys.exit("PADS not found: set WAKE_PADS_DIR")
    offsets = [5 * k for k in range(args.offsets)]
    if args.sweep:
        sweep(pads, args.at)
    elif args.cutoffs:
        cutoffs(pads)
    elif args.rates:
        rates(pads, args.rates, offsets)
    else:
        after_s = 0.0 if args.whole else AFTER_S
        print_rows([decomposition(pads, off, VARIANTS, after_s) for off in offsets], offsets)


if __name__ == "__main__":
    main()
