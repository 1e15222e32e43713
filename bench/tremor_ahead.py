"""Tremor ahead (issue 32): predictors of the tremor h samples ahead, their oracle, and gates, by measurement.

    python bench/tremor_ahead.py            # PADS (if found) and the synthetic set, every table
    python bench/tremor_ahead.py --quick    # 3 PADS recordings and 3 synthetic signals

Truth: PADS, the independent sharp high-pass of the whole recording at its Welch valley between 1.5 and 5 Hz
(``wake.eval.warmup.independent_ground_truth``, as ``bench/warmup_slices.py``); synthetic, the paper's tremor
component ``s_t`` alone (``SyntheticSignal.tremor``): the white noise ``s_w`` is unpredictable and an actuator
must not chase it.  The command an actuator plays at sample ``m`` is the prediction made at ``m - h`` from
WAKE's causal tremor estimate ``x - voluntary`` up to ``m - h`` (C core, default settings); it is scored
against the truth at ``m`` with the paper's NRMSE per slice of time since start (``wake.eval.warmup``), mean
over recording-axes / signals.  "zero" sends nothing.  Helpers and definitions: ``bench/ahead.py``.
The PADS folder is ../shared/data/pads next to the checkout or $WAKE_PADS_DIR.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import ahead  # noqa: E402
from ahead import HORIZONS  # noqa: E402
from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import SLICES, independent_ground_truth, mean_slices, slice_nrmse  # noqa: E402
from wake.rtp import c_backend_available  # noqa: E402

BACKEND = "c" if c_backend_available() else "reference"
ORDERS = (4, 8, 12, 20)
P_MAIN = 8


class Case:
    """One channel: measurement, WAKE's estimate, truth, HPA windows."""

    def __init__(self, x, y, T, windows, fs, name):
        self.x, self.y, self.T, self.windows, self.fs, self.name = x, y, T, windows, fs, name


def pads_cases(folder, limit=None):
    recs = load_pads_folder(folder)[:limit]
    cases, raw = [], []
    for rec in recs:
        filt = WakeFilter(fs=rec.fs, backend=BACKEND)
        res = filt.run(rec.samples)
        first = len(cases)
        for c in range(rec.samples.shape[1]):
            x = rec.samples[:, c].astype(float)
            _, T, _ = independent_ground_truth(x, rec.fs)
            y = x - res.voluntary[:, c]
            cases.append(Case(x, y, T, ahead.hpa_windows(x, res.hpa[c], rec.fs, filt.window_samples), rec.fs,
                              f"{rec.name}:{c}"))
        raw.append((rec.samples, rec.fs, first))
    return cases, raw


def synthetic_cases(limit=None):
    cases, raw = [], []
    for i, s in enumerate(paper_dataset()[:limit]):
        filt = WakeFilter(fs=s.fs, backend=BACKEND)
        res = filt.run(s.measurement)
        y = s.measurement - res.voluntary
        cases.append(Case(s.measurement, y, s.tremor, ahead.hpa_windows(s.measurement, res.hpa[0], s.fs,
                                                                         filt.window_samples), s.fs, f"signal {i + 1}"))
        raw.append((s.measurement[:, None], s.fs, i))
    return cases, raw


# -- predictors ------------------------------------------------------------------------------------------------


def predictions(case, p=P_MAIN, extra=True):
    """{name: {h: P}} of every candidate for one case."""
    y, W, fs = case.y, case.windows, case.fs
    out = {}
    out[f"AR({p}) Yule-Walker on the window truth, iterated"] = {h: ahead.predictor_ar(y, W, h, p) for h in HORIZONS}
    out[f"direct {p}-tap LS, window truth -> truth"] = {h: ahead.predictor_direct_truth(y, W, h, p)
                                                       for h in HORIZONS}
    out[f"direct {p}-tap LS, WAKE estimate -> window truth"] = {h: ahead.predictor_direct_wiener(y, W, h, p)
                                                               for h in HORIZONS}
    if extra:
        for bw in (0.5, 1.0, 2.0):
            out[f"Kalman oscillator, bandwidth {bw:g} Hz"] = ahead.predictor_oscillator(y, W, fs, HORIZONS, bw)
    return out


def orders(case):
    """The direct Wiener predictor (WAKE estimate -> window truth) at every order of :data:`ORDERS`."""
    return {f"direct LS, WAKE estimate -> window truth, {p} taps": {h: ahead.predictor_direct_wiener(case.y, case.windows,
                                                                                                     h, p)
                                                                   for h in HORIZONS} for p in ORDERS}


def oracles(case, p=P_MAIN):
    rows = {f"oracle: hindsight {p}-tap LS on the true tremor, fed the true past": {},
            f"oracle coefficients fed WAKE's estimate": {},
            f"hindsight {p}-tap Wiener, WAKE estimate -> truth": {}}
    names = list(rows)
    for h in HORIZONS:
        for name, P in zip(names, ahead.oracle(case.T, case.y, h, p)):
            rows[name][h] = P
    return rows


def score(case, P, h):
    return slice_nrmse(case.T, ahead.command(P, h), case.fs)


def table_rows(cases, per_case):
    """per_case(case) -> {name: {h: P}}; returns {name: {h: [slice dicts]}}."""
    acc = {}
    for case in cases:
        for name, byh in per_case(case).items():
            for h, P in byh.items():
                acc.setdefault(name, {}).setdefault(h, []).append(score(case, P, h))
    return acc


def zero_rows(cases):
    return {"zero (the actuator stays off)": {h: [slice_nrmse(c.T, np.zeros_like(c.T), c.fs) for c in cases]
                                              for h in HORIZONS}}


def baseline_rows(raw, cases):
    acc = {}
    for x, fs, first in raw:
        P = ahead.baselines_ahead(x, fs, HORIZONS)
        for name, byh in P.items():
            for h, arr in byh.items():
                for c in range(x.shape[1]):
                    case = cases[first + c]
                    acc.setdefault(f"{name}, own extrapolation", {}).setdefault(h, []).append(
                        score(case, arr[:, c], h))
    return acc


def print_by_horizon(title, acc, slices=("after 5 s", "whole (from 0.5 s)")):
    print(f"\n{title}\n")
    head = " | ".join(f"h={h} {s.split(' (')[0]}" for s in slices for h in HORIZONS)
    print(f"| estimate of the tremor at n + h | {head} |")
    print("|---|" + "---:|" * (len(slices) * len(HORIZONS)))
    for name, byh in acc.items():
        vals = [mean_slices(byh[h])[s] for s in slices for h in HORIZONS]
        print(f"| {name} | " + " | ".join(f"{v:.3f}" for v in vals) + " |")


def print_slices(title, acc, h):
    names = list(SLICES)
    print(f"\n{title}, h = {h} ({h * 10} ms)\n")
    print("| command | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for name, byh in acc.items():
        m = mean_slices(byh[h])
        print(f"| {name} | " + " | ".join(f"{m[n]:.3f}" for n in names) + " |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="3 PADS recordings and 3 synthetic signals")
    ap.add_argument("--pads", help="PADS folder (default: next to the checkout or $WAKE_PADS_DIR)")
    ap.add_argument("--no-baselines", action="store_true", help="skip the baselines' extrapolation")
    args = ap.parse_args(argv)
    t0 = time.time()
    limit = 3 if args.quick else None
    sets = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = default_pads_dir(args.pads, cwd=ROOT)
        if folder is not None and Path(folder).is_dir():
            sets.append(("PADS", *pads_cases(folder, limit)))
        else:
            print("PADS not found (../shared/data/pads or $WAKE_PADS_DIR): real-recording tables skipped")
        sets.append(("synthetic", *synthetic_cases(limit)))
        for label, cases, raw in sets:
            acc = zero_rows(cases)
            acc.update(table_rows(cases, predictions))
            acc.update(table_rows(cases, oracles))
            if not args.no_baselines:
                acc.update(baseline_rows(raw, cases))
            print_by_horizon(f"{label}, {len(cases)} signals: predicted-tremor NRMSE (ungated), mean", acc)
            print_by_horizon(f"{label}: the direct Wiener predictor by order (ungated)", table_rows(cases, orders))
    print(f"\n({time.time() - t0:.0f} s)")


if __name__ == "__main__":
    main()
