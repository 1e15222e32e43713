"""One-step tremor extraction on strong real tremor: per axis, WAKE's estimate against zero and every baseline.

    python bench/strong_one_step.py                 # pdkit's 13 tremor axes and PADS's 60 axes (about 2 min)
    python bench/strong_one_step.py --pdkit-only    # about 30 s

Per axis, the NRMSE after 5 s (range of the truth after 5 s) of each method's one-step tremor estimate
``x - voluntary`` (``voluntary[k]`` predicted from ``x[:k]``) against the offline truth of the recording
(:func:`wake.eval.truth.tremor_truth`); "zero" estimates no tremor.  WAKE runs with the default settings on
the C core (the float reference when it is not built), the baselines with the parameters tuned once
(docs/studies/baselines.md).  The columns "WAKE, gravity out" and "WAKE from 3 s" are diagnoses, not methods: the same
filter fed the axis minus its median over the whole recording (gravity out, in hindsight), and fed the
recording from 3 s on (the start transient out), both scored on the same samples.  The last lines count the axes on which WAKE is below every
baseline and below zero.
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
    out["WAKE"] = score(truth, x - WakeFilter(fs=fs, backend=BACKEND).run(x).voluntary, fs)
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
    names = list(rows[0][1])
    print(f"\n{title}\n")
    print("| axis | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for label, r in rows:
        best = min(v for k, v in r.items() if k in BASELINES)
        cells = [f"**{v:.3f}**" if k == "WAKE" and v < best else f"{v:.3f}" for k, v in r.items()]
        print(f"| {label} | " + " | ".join(cells) + " |")
    mean = {k: float(np.mean([r[k] for _, r in rows])) for k in names}
    print("| mean | " + " | ".join(f"{v:.3f}" for v in mean.values()) + " |")
    wins = sum(r["WAKE"] < min(r[k] for k in BASELINES) for _, r in rows)
    below_zero = sum(r["WAKE"] < r["zero"] for _, r in rows)
    print(f"\nWAKE below every baseline on {wins} of {len(rows)} axes; below zero on {below_zero} of {len(rows)}.")
    if "WAKE, gravity out" in names:
        g = sum(r["WAKE, gravity out"] < min(r[k] for k in BASELINES) for _, r in rows)
        print(f"WAKE with gravity out (diagnosis) below every baseline on {g} of {len(rows)} axes.")
    return mean


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--pdkit-only", action="store_true")
    args = p.parse_args(argv)
    folder = default_pdkit_dir(cwd=ROOT)
    if folder is None or not folder.is_dir():
        print("pdkit recordings not found ($WAKE_PDKIT_DIR or ../shared/data/pdkit)")
    else:
        rows = [(f"{r.task.split('_')[0].lower()} {r.limb.lower()} {r.recording.channels[c]}",
                 axis_row(r.recording.samples[:, c].astype(float), r.recording.fs))
                for r, c in tremor_axes(load_pdkit_folder(folder))]
        table(rows, f"pdkit, 13 tremor axes, one-step tremor NRMSE after {START_S:g} s ({BACKEND} core)")
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
