"""What P does at a weight change, measured with the Kalman filter live.

    python bench/covariance_restart.py [--pads DIR]

The float reference (``wake.rtp.reference``) restarts the covariance at every
weight change as ``P = (w'Pw / w'w) I``, its variance along the old ``w``.
This script runs the same filters with two other rules patched in: ``carry``
(P kept whole, the first release) and ``prior`` (P back to ``p0 I``), on the
paper's ten synthetic signals (voluntary NRMSE) and, when found, the PADS
recordings (tremor NRMSE against the offline ground truth at the mean f_d of
the default filter, as ``bench/design_choices.py``), each after the first
HPA window (5 s) and from 0.5 s.  The default filter keeps the Kalman inert
(P = 0), where the three rules coincide; the rows are live settings.
Takes about 15 minutes on one core.
"""

import argparse
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

from wake import WakeFilter  # noqa: E402
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
    out = []
    for path in sorted(Path(folder).glob("*.txt")):
        data = np.loadtxt(path, delimiter=",")
        out.extend(data[:, c] for c in range(1, 7))
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
    ap.add_argument("--pads", default=os.environ.get("WAKE_PADS_DIR",
                                                     str(Path(__file__).resolve().parents[2] / "shared" / "data" / "pads")))
    args = ap.parse_args(argv)
    synth = paper_dataset()
    real = pads_axes(args.pads) if Path(args.pads).is_dir() else []
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
