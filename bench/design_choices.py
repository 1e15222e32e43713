"""Measure the choices where the paper is vague (the numbers in docs/studies/design.md).

    python bench/design_choices.py [--pads DIR]

Synthetic: mean voluntary NRMSE over the paper's ten signals (warm-up left
out).  Real (PADS, when found): mean tremor NRMSE against the offline
ground truth at the mean f_d of the default filter, over every axis.
"""

import argparse
import os
from pathlib import Path

import numpy as np

from wake import WakeFilter
from wake.eval.metrics import nrmse, offline_ground_truth
from wake.eval.synthetic import PAPER_WAKE, paper_dataset

VARIANTS = [
    ("default (causal fit, constant mode, q = 0)", {}),
    ("fit='paper' (full-window approximations)", dict(fit="paper")),
    ("mode='symmetric'", dict(mode="symmetric")),
    ("mode='periodization'", dict(mode="periodization")),
    ("mode='smooth'", dict(mode="smooth")),
    ("process_noise_ratio=1e-6", dict(process_noise_ratio=1e-6)),
    ("process_noise_ratio=1e-5", dict(process_noise_ratio=1e-5)),
    ("process_noise_ratio=1e-4", dict(process_noise_ratio=1e-4)),
    ("process_noise_ratio=1e-3", dict(process_noise_ratio=1e-3)),
    ("initial_covariance=0.05", dict(initial_covariance=0.05)),
    ("level=4", dict(level=4)),
    ("level=6", dict(level=6)),
    ("wavelet='db3'", dict(wavelet="db3")),
    ("window_s=9", dict(window_s=9.0)),
]


def pads_recordings(folder):
    out = []
    for path in sorted(Path(folder).glob("*.txt")):
        data = np.loadtxt(path, delimiter=",")
        for c in range(1, 7):
            out.append(data[:, c])
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pads", default=os.environ.get("WAKE_PADS_DIR",
                                                     str(Path(__file__).resolve().parents[1].parent / "shared" / "data" / "pads")))
    args = ap.parse_args()
    synth = paper_dataset()
    real = pads_recordings(args.pads) if Path(args.pads).is_dir() else []
    cutoffs = [WakeFilter(backend="reference").run(x).mean_cutoff[0] for x in real]
    truths = [offline_ground_truth(x, 100.0, fd)[1] for x, fd in zip(real, cutoffs)]
    paper = np.mean(PAPER_WAKE["nrmse"])
    print(f"| variant | synthetic NRMSE (mean) | / paper | worst signal / paper | PADS tremor NRMSE (mean, {len(real)} axes) |")
    print("|---|---|---|---|---|")
    for name, kw in VARIANTS:
        s = np.array([nrmse(sig.voluntary, WakeFilter(backend="reference", **kw).run(sig.measurement).voluntary, 500)
                      for sig in synth])
        r = [nrmse(t, x - WakeFilter(backend="reference", **kw).run(x).voluntary, 500) for x, t in zip(real, truths)]
        rtxt = f"{np.mean(r):.4f}" if r else "n/a"
        print(f"| {name} | {s.mean():.4f} | {s.mean() / paper:.3f} | {np.max(s / PAPER_WAKE['nrmse']):.3f} | {rtxt} |")


if __name__ == "__main__":
    main()
