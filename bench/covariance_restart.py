"""What P does at a weight change, measured with the Kalman filter live.

    python bench/covariance_restart.py [--pads DIR]

The float reference (``wake.rtp.reference``) restarts the covariance at every
weight change as ``P = (w'Pw / w'w) I``, its variance along the old ``w``.
This script runs the same filters with two other rules patched in: ``carry``
(P kept whole, the first release) and ``prior`` (P back to ``p0 I``), on the
paper's ten synthetic signals (voluntary NRMSE) and, when found, the PADS
recordings (``wake.eval.datasets.load_pads_folder``: every axis on a uniform
100 Hz grid; tremor NRMSE against the offline ground truth at the mean f_d of
the default filter, as ``bench/design_choices.py``), each after the first
HPA window (5 s) and from 0.5 s.  The default filter keeps the Kalman inert
(P = 0), where the three rules coincide; the rows are live settings.
Takes about 5 minutes on one core.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from a checkout without installing

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.metrics import nrmse, offline_ground_truth  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.rtp.reference import ReferenceRTP  # noqa: E402

SETTINGS = [
    dict(process_noise_ratio=1e-5),
    dict(process_noise_ratio=1e-4),
    dict(process_noise_ratio=1e-3),
    dict(initial_covariance=0.05),
    dict(initial_covariance=1.0),
    dict(process_noise_ratio=1e-4, initial_covariance=0.05),
]
ISOTROPIC = ReferenceRTP._restarted_covariance
RULES = {
    "isotropic (default)": ISOTROPIC,
    "carry": lambda self: self.covariance.copy(),
    "prior": lambda self: self.initial_covariance * np.eye(self.level).reshape(-1),
}
FS = 100.0


def pads_axes(folder):
    """Every axis of every PADS recording, on the loader's uniform 100 Hz grid."""
    out = []
    for rec in load_pads_folder(folder):
        if rec.fs != FS:
            raise SystemExit(f"{rec.name}: expected {FS:g} Hz after loading, got {rec.fs:g} Hz")
        out.extend(rec.samples[:, c] for c in range(rec.samples.shape[1]))
    return out


def score(kw, synth, real, truths):
    row = []
    for start in (500, 50):
        row.append(np.mean([nrmse(s.voluntary, WakeFilter(backend="reference", **kw).run(s.measurement).voluntary, start)
                            for s in synth]))
    for start in (500, 50):
        row.append(np.mean([nrmse(t, x - WakeFilter(backend="reference", **kw).run(x).voluntary, start)
                            for x, t in zip(real, truths)]) if real else float("nan"))
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pads", help="the PADS folder (default: $WAKE_PADS_DIR, else ../shared/data/pads)")
    args = ap.parse_args(argv)
    synth = paper_dataset()
    folder = default_pads_dir(args.pads, cwd=ROOT)
    real = pads_axes(folder) if folder is not None and folder.is_dir() else []
    if not real:
        print("PADS recordings not found: the PADS columns are NaN (pass --pads DIR)", file=sys.stderr)
    cutoffs = [WakeFilter(backend="reference").run(x).mean_cutoff[0] for x in real]
    truths = [offline_ground_truth(x, FS, fd)[1] for x, fd in zip(real, cutoffs)]
    print("| setting | rule | synthetic after 5 s | synthetic from 0.5 s | PADS after 5 s | PADS from 0.5 s |")
    print("|---|---|---:|---:|---:|---:|")
    try:
        for kw in SETTINGS:
            name = ", ".join(f"{k}={v:g}" for k, v in kw.items())
            for rule, fn in RULES.items():
                ReferenceRTP._restarted_covariance = fn
                cells = " | ".join(f"{v:.4f}" for v in score(kw, synth, real, truths))
                print(f"| {name} | {rule} | {cells} |", flush=True)
    finally:
        ReferenceRTP._restarted_covariance = ISOTROPIC


if __name__ == "__main__":
    main()
