"""Long gaps in a stream: interpolated for the HPA, or the HPA restarted on the samples after them.

    python bench/gap_policy.py [--backend reference|c]

The paper's ten synthetic signals, each streamed sample by sample
(``WakeFilter.update``) with a run of missing samples (NaN) from 10 s on, of
0.5, 1, 3, 4.5 and 7 s.  For each gap and each long-gap share
(``wake.schedule.GAP_SHARE``: a run of missing samples at least this share of
the HPA window is a long gap; "off" interpolates every gap, the behaviour
before the policy): the mean voluntary NRMSE over the 5 s after the gap and
from the gap to the end, and whether ``run`` gives the stream's predictions
bit for bit (docs/studies/design.md, "Missing samples").
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import wake.hpa.schedule as schedule  # noqa: E402
from wake import WakeFilter  # noqa: E402
from wake.eval.metrics import nrmse  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402

GAPS_S = (0.5, 1.0, 3.0, 4.5, 7.0)
SHARES = {"off": 1e9, "10 %": 0.1, "20 % (default)": 0.2, "40 %": 0.4}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--backend", choices=("reference", "c"), default="reference")
    args = ap.parse_args(argv)
    data = paper_dataset()
    shipped = schedule.GAP_SHARE
    print("| gap | " + " | ".join(SHARES) + " |")
    print("|---|" + "---:|" * len(SHARES))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for gap in GAPS_S:
            cells = []
            for share in SHARES.values():
                schedule.GAP_SHARE = share
                first, rest, same = [], [], True
                try:
                    for s in data:
                        x = s.measurement.copy()
                        a, b = int(10.0 * s.fs), int(round((10.0 + gap) * s.fs))
                        x[a:b] = np.nan
                        f = WakeFilter(fs=s.fs, backend=args.backend)
                        pred = np.array([f.update(v) for v in x])
                        same &= np.array_equal(pred, WakeFilter(fs=s.fs, backend=args.backend).run(x).prediction,
                                               equal_nan=True)
                        vol = np.concatenate([[0.0], pred[:-1]])
                        first.append(nrmse(s.voluntary[b:b + 500], vol[b:b + 500], 0))
                        rest.append(nrmse(s.voluntary[b:], vol[b:], 0))
                finally:
                    schedule.GAP_SHARE = shipped
                cells.append(f"{np.mean(first):.4f} / {np.mean(rest):.4f}" + ("" if same else " (run differs!)"))
            print(f"| {gap:g} s | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
