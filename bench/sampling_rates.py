"""WAKE at sampling rates from 50 Hz to 1 kHz: which structure keeps the 100 Hz accuracy (issue 33).

    python bench/sampling_rates.py            # the structure comparison (docs/studies/design.md, "Sampling rates")
    python bench/sampling_rates.py --library  # WakeFilter(fs=...) as shipped, both RTP backends

Signals.  The paper's ten synthetic signals (:func:`wake.eval.synthetic.paper_dataset`, 50 s at
100 Hz) and the PADS recordings (``$WAKE_PADS_DIR`` or ``../shared/data/pads``, read at 100 Hz), each
taken to the test rate by band-limited resampling, ``scipy.signal.resample_poly(x, up, down)``
(polyphase FIR, Kaiser window beta 5, the default): every rate sees the same motion, so only the rate
differs.  The truth goes through the same resampler: on the synthetic set ``s_v``; on PADS the tremor
of :func:`wake.eval.warmup.independent_ground_truth` (a sharp FFT high-pass at a cut-off found from
the recording, not from WAKE) computed at 100 Hz.

Scores.  Synthetic: voluntary NRMSE (:func:`wake.eval.metrics.nrmse`), mean of the ten, after 5 s and
over the whole recording.  PADS: tremor NRMSE (``x - voluntary`` against the truth), mean of the 60
recording-axes, after 5 s and whole.

Structures (float64 reference RTP and Python HPA throughout):

- ``today``: level 5, ``ar_order`` 17, everything at the input rate (what 0.x does);
- ``level``: the level from fs, ``J = 5 + round(log2(fs / 100))`` (bank ``2**J`` long, the same
  320 ms), ``ar_order = 17 fs / 100``, HPA at the input rate;
- ``box-hold`` / ``box-lin``: a causal boxcar of ``D = round(fs / 100)`` samples, WAKE at ``fs / D``,
  and the prediction carried back to the input rate held (``hold``) or along the slope of the last
  two predictions with the boxcar's delay accounted for (``lin``, :mod:`wake.rate`);
- ``cic2-lin``: two cascaded boxcars (triangle of ``2 D - 1`` taps, delay ``D - 1``), then as ``box-lin``;
- ``a-trous``: the level-5 bank dilated by ``D`` (zeros between the taps), i.e. ``D`` interleaved WAKEs
  at ``fs / D`` each fed every ``D``-th sample, the prediction of sample ``n + 1`` from the phase of
  ``n + 1`` (its newest sample is ``n + 1 - D``); no anti-alias filter.
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.signal import resample_poly

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wake.config  # noqa: E402
import wake.wavelets  # noqa: E402
from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.metrics import nrmse  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth  # noqa: E402
from wake.target import TARGET  # noqa: E402

RATES = {50: (1, 2), 100: (1, 1), 200: (2, 1), 250: (5, 2), 500: (5, 1), 1000: (10, 1)}
AFTER_S = 5.0


def _wake(x, fs, **kw):
    return WakeFilter(fs=float(fs), backend="reference", **kw).run(x).prediction


def today(x, fs):
    return _wake(x, fs)


def level_from_fs(x, fs):
    J = 5 + round(math.log2(fs / 100.0))
    p = min(512, round(17 * fs / 100.0))
    old = wake.config.MAX_LEVEL, wake.wavelets.MAX_LEVEL
    wake.config.MAX_LEVEL = wake.wavelets.MAX_LEVEL = 9  # the float reference only: measurement
    try:
        return _wake(x, fs, level=J, ar_order=p)
    finally:
        wake.config.MAX_LEVEL, wake.wavelets.MAX_LEVEL = old


def _carry_back(p, D, n, centre_shift, slope):
    """Input-rate predictions from the decimated ones: p[m] (after group m) predicts the front end's
    output of group m + 1, centred at input time (m + 1) D + D - 1 - centre_shift."""
    out = np.zeros(n)
    for m in range(p.size):
        prev = p[m - 1] if m else p[m]
        first = (m + 1) * D - 1            # the last sample of group m: p[m] is known after it
        for k in range(first, min(n, first + D)):
            t = k + 1                      # the sample predicted
            c = (m + 1) * D + D - 1 - centre_shift
            out[k] = p[m] + (slope * (p[m] - prev) * (t - c) / D)
    return out


def front_end(x, fs, *, D, kernel, slope):
    h = np.ones(D) / D if kernel == "box" else np.convolve(np.ones(D), np.ones(D)) / D**2
    y = np.convolve(x, h)[: x.size]        # causal
    d = y[D - 1 :: D]                       # group m ends at input sample m D + D - 1
    p = _wake(d, fs / D)
    return _carry_back(p, D, x.size, (h.size - 1) / 2, slope)


def a_trous(x, fs, *, D):
    out = np.zeros(x.size)
    for r in range(D):
        p = _wake(x[r::D], fs / D)         # p[i]: after x[r + i D], predicts x[r + (i + 1) D]
        idx = r + np.arange(p.size) * D + D - 1   # output index k predicts k + 1 = r + (i + 1) D
        keep = idx < x.size
        out[idx[keep]] = p[keep]
    return out


def structures(fs):
    D = max(1, round(fs / 100.0))
    out = {"today": today, "level": level_from_fs}
    if D > 1:
        out["box-hold"] = lambda x, f: front_end(x, f, D=D, kernel="box", slope=0.0)
        out["box-lin"] = lambda x, f: front_end(x, f, D=D, kernel="box", slope=1.0)
        out["cic2-lin"] = lambda x, f: front_end(x, f, D=D, kernel="cic2", slope=1.0)
        out["a-trous"] = lambda x, f: a_trous(x, f, D=D)
    if fs == 250:
        out["box-lin D=3"] = lambda x, f: front_end(x, f, D=3, kernel="box", slope=1.0)
    if fs == 50:
        out["level 4"] = lambda x, f: _wake(x, f, level=4)
        out["level 4, p 9"] = lambda x, f: _wake(x, f, level=4, ar_order=9)
        out["level 6"] = lambda x, f: _wake(x, f, level=6)
        for p in (9, 12, 25):
            out[f"p {p}"] = lambda x, f, p=p: _wake(x, f, ar_order=p)
        for w in (4.0, 6.0):
            out[f"window {w:g} s"] = lambda x, f, w=w: _wake(x, f, window_s=w)
    return out


def synthetic_scores(fs, method):
    up, down = RATES[fs]
    after, whole = [], []
    for s in paper_dataset():
        x, v = resample_poly(s.measurement, up, down), resample_poly(s.voluntary, up, down)
        est = TARGET.voluntary_from(method(x, fs))
        after.append(nrmse(v, est, int(AFTER_S * fs)))
        whole.append(nrmse(v, est))
    return float(np.mean(after)), float(np.mean(whole))


def pads_scores(fs, method, recordings):
    up, down = RATES[fs]
    after, whole = [], []
    for rec in recordings:
        for c in range(rec.samples.shape[1]):
            x100 = rec.samples[:, c]
            _, tremor, _ = independent_ground_truth(x100, rec.fs)
            x, truth = resample_poly(x100, up, down), resample_poly(tremor, up, down)
            est = x - TARGET.voluntary_from(method(x, fs))
            after.append(nrmse(truth, est, int(AFTER_S * fs)))
            whole.append(nrmse(truth, est))
    return float(np.mean(after)), float(np.mean(whole))


def cost(name, fs):
    """(multiply-adds per input sample in the RTP, worst sample / mean; state words per channel)."""
    D = int(name.split(" D=")[1]) if " D=" in name else max(1, round(fs / 100.0))
    J = 5 + round(math.log2(fs / 100.0)) if name == "level" else (4 if name.startswith("level 4") else
                                                                   6 if name == "level 6" else 5)
    N = 2**J
    step = J * N + J + 3 * J * J              # bank, w'(a+d), Kalman u, S, P
    state = N + J + J * J + J * N             # ring, d, P, taps (int16 words, roughly)
    if name in ("today", "level", "level 6") or name.startswith("level 4") or D == 1:
        return step, step, state
    if name == "a-trous":
        return step, step, D * N + J + J * J + J * N
    fe = 2 if name.startswith("cic2") else 1  # adds per input sample; + 2 for the group's mean and output
    return step + fe + 2, (step + D * (fe + 2)) / D, state + 2 * fe + 2


def compare(pads):
    print("| fs (Hz) | structure | synthetic voluntary NRMSE after 5 s | whole | PADS tremor NRMSE after 5 s "
          "| whole | MACs per input sample (worst / mean) | state words |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|")
    for fs in RATES:
        for name, method in structures(fs).items():
            sa, sw = synthetic_scores(fs, method)
            pa, pw = pads_scores(fs, method, pads) if pads else (math.nan, math.nan)
            worst, mean, state = cost(name, fs)
            print(f"| {fs} | {name} | {sa:.4f} | {sw:.4f} | {pa:.4f} | {pw:.4f} | {worst} / {mean:.0f} | {state} |",
                  flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--library", action="store_true", help="WakeFilter(fs=...) as shipped instead")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    folder = default_pads_dir()
    pads = load_pads_folder(folder) if folder is not None and Path(folder).is_dir() else []
    if not pads:
        print("(PADS not found: set WAKE_PADS_DIR; its columns are left NaN)")
    if args.library:
        library(pads)
    else:
        compare(pads)


def library(pads):
    print("| fs (Hz) | backend | synthetic voluntary NRMSE after 5 s | whole | PADS tremor NRMSE after 5 s | whole |")
    print("|---:|---|---:|---:|---:|---:|")
    for fs in RATES:
        for backend in ("reference", "c"):
            method = lambda x, f, b=backend: WakeFilter(fs=float(f), backend=b).run(x).prediction  # noqa: E731
            sa, sw = synthetic_scores(fs, method)
            pa, pw = pads_scores(fs, method, pads) if pads else (math.nan, math.nan)
            print(f"| {fs} | {backend} | {sa:.4f} | {sw:.4f} | {pa:.4f} | {pw:.4f} |", flush=True)


if __name__ == "__main__":
    main()
