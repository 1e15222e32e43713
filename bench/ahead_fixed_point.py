"""Tremor ahead on the C core (issue 32): the command of FixedPointRTP against its float twin, per horizon.

    python bench/ahead_fixed_point.py          # the paper's ten synthetic signals, 30 s each (about 1 min)

The float twin is the contract's per-sample rule (wake.ahead.AheadStep beside ReferenceRTP, fed
e(n) = m(n) - y(n-1); ``FloatTwin`` in tests/rtp/test_fixed_ahead.py).  For each signal: weights and R
from run_hpa on the first 5 s window, the full scale FullScalePolicy's for that window, the 8-tap
predictor fitted (wake.ahead.fit_predictor) on the twin's estimate over that window against the true
tremor, the gate's goal 1.  Two figures, whole recording and after the first window, worst over the
signals:

* direct: NRMSE of the C command against the twin's, both fed the C core's Q15 samples;
* versus truth: relative difference of the two commands' NRMSE against the true tremor h samples ahead
  (the twin fed the float samples), the reading tests/rtp/test_fixed_point.py uses for the voluntary output.

docs/studies/fixed_point.md, "The tremor ahead", quotes the table.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "rtp"), str(ROOT / "tests"), str(ROOT)]

from test_fixed_ahead import _errors_on_signal  # noqa: E402

from wake.config import WakeConfig  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402


def main():
    config, data = WakeConfig(), paper_dataset(duration=30.0)
    print("| h | direct NRMSE, whole | direct, after 5 s | versus truth, whole | versus truth, after 5 s |")
    print("|---:|---:|---:|---:|---:|")
    for h in (1, 2, 5, 10):
        worst = np.array([_errors_on_signal(sig, h, config) for sig in data]).max(axis=0)  # (whole/after, kind)
        print(f"| {h} | {worst[0, 0]:.2%} | {worst[1, 0]:.2%} | {worst[0, 1]:.3%} | {worst[1, 1]:.3%} |")


if __name__ == "__main__":
    main()
