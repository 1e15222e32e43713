"""One-step tremor extraction on strong real tremor: per axis, WAKE's estimate against zero and every baseline.

    python bench/strong_one_step.py                 # pdkit's 13 tremor axes and PADS's 60 axes (about 2 min)
    python bench/strong_one_step.py --pdkit-only    # about 30 s
    python bench/strong_one_step.py --synthetic     # the paper's set and the strong set (100 and 1000 Hz)

Per axis, the NRMSE after 5 s (range of the truth after 5 s) of each method's one-step tremor estimate
``x - voluntary`` (``voluntary[k]`` predicted from ``x[:k]``) against the offline truth of the recording
(:func:`wake.eval.truth.tremor_truth`); "zero" estimates no tremor.  WAKE runs with the default settings on
the C core (the float reference when it is not built), the baselines with the parameters tuned once
(docs/studies/baselines.md).  The columns "WAKE, gravity out" and "WAKE from 3 s" are diagnoses, not methods: the same
filter fed the axis minus its median over the whole recording (gravity out, in hindsight), and fed the
recording from 3 s on (the start transient out), both scored on the same samples.  The column "WAKE, ridge
centred" is the setting ``ridge_scale="centred"`` (the weight fit's ridge relative to the centred Gram matrix,
which gravity does not inflate; issue 46), beside the default.  The last lines count the axes on which WAKE
(and the setting) is below every baseline and below zero, and say how far the setting moves the one-step
voluntary prediction (its NRMSE against the voluntary truth ``x - truth``, mean over axes).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.baselines import BASELINES, baseline_methods  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.strong_tremor import strong_tremor_dataset  # noqa: E402
from wake.eval.pdkit import default_pdkit_dir, load_pdkit_folder, tremor_axes  # noqa: E402
from wake.eval.truth import tremor_truth  # noqa: E402
from wake.rtp import c_backend_available  # noqa: E402

BACKEND = "c" if c_backend_available() else "reference"
START_S = 5.0


def score(truth, est, fs, start_s=START_S):
    lo = int(start_s * fs)
    t, e = truth[lo:], est[lo:]
    ok = np.isfinite(t)
    return float(np.sqrt(np.mean((t[ok] - e[ok]) ** 2)) / np.ptp(t[ok]))


def axis_row(x, fs, diagnose=True):
    """{method: NRMSE after 5 s} of one axis."""
    _, truth, _ = tremor_truth(x, fs)
    out = {"zero": score(truth, np.zeros_like(x), fs)}
    vol = WakeFilter(fs=fs, backend=BACKEND).run(x).voluntary
    out["WAKE"] = score(truth, x - vol, fs)
    vol_c = WakeFilter(fs=fs, backend=BACKEND, ridge_scale="centred").run(x).voluntary
    out["WAKE, ridge centred"] = score(truth, x - vol_c, fs)
    # the one-step voluntary prediction against the voluntary truth, default and setting (not a column)
    out["_voluntary"] = score(x - truth, vol, fs)
    out["_voluntary, ridge centred"] = score(x - truth, vol_c, fs)
    out["_identical"] = bool(np.array_equal(vol, vol_c))
    for name, m in baseline_methods(fs).items():
        out[name] = score(truth, x - np.reshape(m.run(x).voluntary, x.shape), fs)
    if diagnose:
        d = x - np.median(x)
        out["WAKE, gravity out"] = score(truth, d - WakeFilter(fs=fs, backend=BACKEND).run(d).voluntary, fs)
        k = int(3 * fs)
        y = np.full_like(x, np.nan)
        y[k:] = x[k:] - WakeFilter(fs=fs, backend=BACKEND).run(x[k:]).voluntary
        out["WAKE from 3 s"] = score(truth, y, fs)
    return out


def table(rows, title):
    names = [k for k in rows[0][1] if not k.startswith("_")]
    print(f"\n{title}\n")
    print("| axis | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for label, r in rows:
        best = min(v for k, v in r.items() if k in BASELINES)
        cells = [f"**{r[k]:.3f}**" if k in ("WAKE", "WAKE, ridge centred") and r[k] < best else f"{r[k]:.3f}" for k in names]
        print(f"| {label} | " + " | ".join(cells) + " |")
    mean = {k: float(np.mean([r[k] for _, r in rows])) for k in names}
    print("| mean | " + " | ".join(f"{v:.3f}" for v in mean.values()) + " |")
    wins = sum(r["WAKE"] < min(r[k] for k in BASELINES) for _, r in rows)
    below_zero = sum(r["WAKE"] < r["zero"] for _, r in rows)
    print(f"\nWAKE below every baseline on {wins} of {len(rows)} axes; below zero on {below_zero} of {len(rows)}.")
    c = "WAKE, ridge centred"
    wins_c = sum(r[c] < min(r[k] for k in BASELINES) for _, r in rows)
    print(f"{c} (ridge_scale='centred') below every baseline on {wins_c} of {len(rows)} axes; below zero on "
          f"{sum(r[c] < r['zero'] for _, r in rows)} of {len(rows)}.")
    v0 = float(np.mean([r["_voluntary"] for _, r in rows]))
    v1 = float(np.mean([r["_voluntary, ridge centred"] for _, r in rows]))
    worst = max(abs(r["_voluntary, ridge centred"] / r["_voluntary"] - 1) for _, r in rows)
    same = sum(r["_identical"] for _, r in rows)
    print(f"One-step voluntary NRMSE (against x - truth), mean: default {v0:.4f}, ridge centred {v1:.4f} "
          f"({100 * (v1 / v0 - 1):+.2f} %; largest change on one axis {100 * worst:.2f} %; bit for bit on "
          f"{same} of {len(rows)} axes).")
    if "WAKE, gravity out" in names:
        g = sum(r["WAKE, gravity out"] < min(r[k] for k in BASELINES) for _, r in rows)
        print(f"WAKE with gravity out (diagnosis) below every baseline on {g} of {len(rows)} axes.")
    return mean


def ridge_inflation(axes, window=500):
    """Per full HPA window of each axis (after the first), the Gram scale of the weight fit's ridge over the centred
    one (:func:`wake.hpa.fit.ridge_scale_of`): how much an offset inflates the ridge. Percentiles 10, 50, 90."""
    from wake.hpa.fit import ridge_scale_of
    from wake.wavelets import filter_bank_outputs, filter_bank_taps

    taps = filter_bank_taps("sym3", 5, "constant")
    ratio = []
    for x in axes:
        for end in range(2 * window, x.size + 1, window):
            A = filter_bank_outputs(x[end - window:end], taps)
            ratio.append(ridge_scale_of(A, A.T @ A) / ridge_scale_of(A, A.T @ A, "centred"))
    return np.percentile(ratio, [10, 50, 90])


def synthetic_rows():
    """The ridge setting on the synthetic sets, whose tremor is known: {set: (default, centred, voluntary
    default, voluntary centred)}, mean NRMSE after 5 s of the one-step tremor estimate against the tremor
    component and of the voluntary prediction against ``x - tremor``."""
    sets = {"paper set (10, 100 Hz, gyroscope-like)": [(s.measurement, s.fs, s.tremor) for s in paper_dataset()],
            "strong set (10, 100 Hz, half accelerometer)": [(s.measurement, s.fs, s.tremor)
                                                            for s in strong_tremor_dataset(10)],
            "strong set (4, 1000 Hz, half accelerometer)": [(s.measurement, s.fs, s.tremor)
                                                            for s in strong_tremor_dataset(4, fs=1000.0)]}
    out = {}
    for name, signals in sets.items():
        cols = []
        for rule in ("gram", "centred"):
            t, v = [], []
            for x, fs, tremor in signals:
                vol = WakeFilter(fs=fs, backend=BACKEND, ridge_scale=rule).run(x).voluntary
                t.append(score(tremor, x - vol, fs))
                v.append(score(x - tremor, vol, fs))
            cols.append((float(np.mean(t)), float(np.mean(v))))
        out[name] = cols
    print("\nSynthetic sets, mean NRMSE after 5 s: tremor estimate / voluntary prediction\n")
    print("| set | ridge_scale='gram' (default) | ridge_scale='centred' |")
    print("|---|---:|---:|")
    for name, ((t0, v0), (t1, v1)) in out.items():
        print(f"| {name} | {t0:.4f} / {v0:.4f} | {t1:.4f} / {v1:.4f} |")
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--pdkit-only", action="store_true")
    p.add_argument("--synthetic", action="store_true", help="only the synthetic sets (the ridge setting's effect)")
    args = p.parse_args(argv)
    if args.synthetic:
        synthetic_rows()
        return 0
    folder = default_pdkit_dir(cwd=ROOT)
    if folder is None or not folder.is_dir():
        print("pdkit recordings not found ($WAKE_PDKIT_DIR or ../shared/data/pdkit)")
    else:
        rows = [(f"{r.task.split('_')[0].lower()} {r.limb.lower()} {r.recording.channels[c]}",
                 axis_row(r.recording.samples[:, c].astype(float), r.recording.fs))
                for r, c in tremor_axes(load_pdkit_folder(folder))]
        table(rows, f"pdkit, 13 tremor axes, one-step tremor NRMSE after {START_S:g} s ({BACKEND} core)")
        p10, p50, p90 = ridge_inflation([r.recording.samples[:, c].astype(float)
                                         for r, c in tremor_axes(load_pdkit_folder(folder))])
        print(f"The ridge's Gram scale over its centred scale, per HPA window (default settings' window): median "
              f"{p50:,.0f}, 10th-90th percentile {p10:,.0f} to {p90:,.0f}.")
    if args.pdkit_only:
        return 0
    folder = default_pads_dir(cwd=ROOT)
    if folder is None or not Path(folder).is_dir():
        print("PADS recordings not found ($WAKE_PADS_DIR or ../shared/data/pads)")
        return 0
    rows = [(f"{rec.name[:3]} {rec.channels[c]}", axis_row(rec.samples[:, c].astype(float), rec.fs, diagnose=False))
            for rec in load_pads_folder(folder) for c in range(rec.samples.shape[1])]
    table(rows, f"PADS, 60 axes, one-step tremor NRMSE after {START_S:g} s ({BACKEND} core)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
