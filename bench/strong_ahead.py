"""Tremor ahead where tremor is strong: today's predictor, the selectable ones and the 40-tap hindsight limit.

    python bench/strong_ahead.py             # pdkit, the strong synthetic set, PADS (when found), about 3 min
    python bench/strong_ahead.py --quick     # pdkit and 4 strong synthetic signals, 10 and 50 ms

Per dataset and horizon, the mean over axes of the NRMSE after 5 s (range of the truth after 5 s) of what an
actuator plays against the truth (pdkit and PADS: :func:`wake.eval.truth.tremor_truth` of the whole
recording; the strong synthetic set of :mod:`wake.eval.strong_tremor`: its tremor component), and its ratio to
zero (the actuator off) and to the hindsight 40-tap Wiener limit from WAKE's own estimate
(:func:`wake.eval.ahead_select.wiener_limit`):

* "command (C core)": ``WakeResult.command`` of the filter on the C core, default settings (predictor "fir8");
* "<predictor>, gated": :func:`wake.eval.ahead_select.command_with` of each predictor of
  :data:`wake.ahead.PREDICTORS` on the same run (float);
* "no harm": per slice of time since start (``wake.eval.warmup.SLICES``), the largest ratio of the mean
  command to zero's; "axes < zero": on how many axes the command is strictly below zero after 5 s.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeConfig, WakeFilter  # noqa: E402
from wake.ahead import PREDICTORS, horizon_from_ms  # noqa: E402
from wake.eval.ahead_select import command_with, wiener_limit  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.pdkit import default_pdkit_dir, load_pdkit_folder, tremor_axes  # noqa: E402
from wake.eval.strong_tremor import strong_tremor_dataset  # noqa: E402
from wake.eval.truth import tremor_truth  # noqa: E402
from wake.eval.warmup import SLICES, slice_nrmse  # noqa: E402
from wake.rtp import c_backend_available  # noqa: E402

BACKEND = "c" if c_backend_available() else "reference"


def axes_of(args):
    sets = {}
    folder = default_pdkit_dir(cwd=ROOT)
    if folder is not None and folder.is_dir():
        sets["pdkit, 13 tremor axes"] = [(r.recording.samples[:, c].astype(float), r.recording.fs, None)
                                         for r, c in tremor_axes(load_pdkit_folder(folder))]
    sets["strong synthetic"] = [(s.measurement, s.fs, s.tremor)
                                for s in strong_tremor_dataset(4 if args.quick else 10)]
    folder = default_pads_dir(cwd=ROOT)
    if not args.quick and folder is not None and Path(folder).is_dir():
        sets["PADS, 60 axes"] = [(rec.samples[:, c].astype(float), rec.fs, None)
                                 for rec in load_pads_folder(folder) for c in range(rec.samples.shape[1])]
    return sets


def score_axis(x, fs, truth, ms):
    h = horizon_from_ms(ms, fs)
    if truth is None:
        truth = tremor_truth(x, fs)[1]
    cfg = WakeConfig(fs=fs, horizon=h, backend=BACKEND)
    res = WakeFilter(config=cfg).run(x)
    y = x - res.voluntary
    methods = {"zero": np.zeros_like(x), "command (C core)" if BACKEND == "c" else "command": res.command}
    for p in PREDICTORS:
        methods[f"{p}, gated"] = command_with(x, res, cfg, h, p)[2]
    methods["limit: hindsight 40-tap Wiener"] = wiener_limit(y, truth, h, 40)
    methods["hindsight 8-tap Wiener"] = wiener_limit(y, truth, h, 8)
    return {k: slice_nrmse(truth, v, fs) for k, v in methods.items()}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true")
    args = p.parse_args(argv)
    horizons = (10, 50) if args.quick else (10, 20, 50, 100)
    for name, axes in axes_of(args).items():
        print(f"\n### {name} ({len(axes)}), after 5 s: NRMSE, x zero, x the 40-tap limit\n")
        rows = {ms: [score_axis(x, fs, t, ms) for x, fs, t in axes] for ms in horizons}
        methods = list(rows[horizons[0]][0])
        print("| method | " + " | ".join(f"{ms} ms" for ms in horizons) + " |")
        print("|---|" + "---:|" * len(horizons))
        for m in methods:
            cells = []
            for ms in horizons:
                mean = {k: float(np.nanmean([r[k]["after 5 s"] for r in rows[ms]])) for k in methods}
                lim = mean["limit: hindsight 40-tap Wiener"]
                cells.append(f"{mean[m]:.4f} / {mean[m] / mean['zero']:.3f} / {mean[m] / lim:.3f}")
            print(f"| {m} | " + " | ".join(cells) + " |")
        print()
        for m in [k for k in methods if "gated" in k or k.startswith("command")]:
            worst, below = [], []
            for ms in horizons:
                ratio = max(float(np.nanmean([r[m][s] for r in rows[ms]])) /
                            float(np.nanmean([r["zero"][s] for r in rows[ms]])) for s in SLICES)
                worst.append(f"{ratio:.3f}")
                below.append(sum(r[m]["after 5 s"] < r["zero"]["after 5 s"] for r in rows[ms]))
            print(f"- {m}: no harm, largest slice mean / zero at " + ", ".join(
                f"{ms} ms {w}" for ms, w in zip(horizons, worst)) + "; axes < zero after 5 s: "
                + ", ".join(f"{b}/{len(axes)}" for b in below))
    return 0


if __name__ == "__main__":
    sys.exit(main())
