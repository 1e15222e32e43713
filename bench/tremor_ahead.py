"""Tremor ahead (issue 32): predictors of the tremor h samples ahead, their oracle, and gates, by measurement.

    python bench/tremor_ahead.py            # PADS (if found) and the synthetic set, every table (about 1.5 min)
    python bench/tremor_ahead.py --quick    # 3 PADS recordings and 3 synthetic signals
    python bench/tremor_ahead.py --no-baselines   # without the baselines' extrapolation (the slow part)

The tables and the design they chose are in docs/studies/design.md, "Tremor ahead (issue 32)", "The design study": an 8-tap
direct least-squares predictor from WAKE's estimate to each HPA window's truth, behind a gate that is the
previous model's held-out gain on the samples the new window adds, clipped to [0, 1], and 0 while the window
has no tremor peak, with a 0.3 s first-order ramp.

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
    """The direct Wiener predictor (WAKE estimate -> window truth) and the iterated AR at every order of
    :data:`ORDERS`, and the issue's sketch (AR(20) on WAKE's own past estimate, refitted every 0.5 s)."""
    out = {f"direct LS, WAKE estimate -> window truth, {p} taps":
           {h: ahead.predictor_direct_wiener(case.y, case.windows, h, p) for h in HORIZONS} for p in ORDERS}
    out.update({f"AR({p}) Yule-Walker on the window truth, iterated":
                {h: ahead.predictor_ar(case.y, case.windows, h, p) for h in HORIZONS} for p in ORDERS})
    out["the issue's sketch: AR(20) on WAKE's past estimate (last 5 s), refitted every 0.5 s, iterated"] = {
        h: ahead.predictor_ar_on_estimate(case.y, h) for h in HORIZONS}
    return out


def oracles(case, p=P_MAIN):
    rows = {f"oracle: hindsight {p}-tap LS on the true tremor, fed the true past": {},
            "oracle coefficients fed WAKE's estimate": {},
            f"hindsight {p}-tap Wiener, WAKE estimate -> truth": {}}
    names = list(rows)
    for h in HORIZONS:
        for name, P in zip(names, ahead.oracle(case.T, case.y, h, p)):
            rows[name][h] = P
    return rows


def gate_targets(case, P, h, p=P_MAIN):
    """{gate name: target in [0, 1] per sample} for the chosen predictor's predictions ``P`` (before the ramp)."""
    W, N, fs = case.windows, len(case.y), case.fs
    fallback = np.array([0.0 if w.fallback else 1.0 for w in W])
    coefs = [ahead.ls_direct(case.y[w.start:w.index], w.truth, h, p) for w in W]
    skill_in = ahead.in_sample_skill(case.y, W, coefs, h, p)
    gain_ho, skill_ho = ahead.held_out_gain(P, W, h)
    ratio = ahead.running_ratio(case.y, P, h, fs)
    on = ahead.step_target(W, N, np.ones(len(W)))
    t = {}
    t["none (on from the first HPA)"] = on
    t["off on a fallback cut-off flag"] = ahead.step_target(W, N, fallback)
    t["in-sample skill, clipped to [0, 1]"] = ahead.step_target(W, N, np.clip(skill_in, 0, 1))
    for th in (0.3, 0.5):
        t[f"in-sample skill > {th:g}"] = ahead.step_target(W, N, (skill_in > th).astype(float))
    t["held-out gain, clipped to [0, 1]"] = ahead.step_target(W, N, np.clip(np.nan_to_num(gain_ho), 0, 1))
    t["held-out skill, clipped to [0, 1]"] = ahead.step_target(W, N, np.clip(np.nan_to_num(skill_ho), 0, 1))
    for th in (0.0, 0.2):
        t[f"held-out skill > {th:g}"] = ahead.step_target(W, N, (np.nan_to_num(skill_ho, nan=-1) > th).astype(float))
    t["1 - running error ratio, clipped"] = on * np.clip(1 - ratio, 0, 1)
    split = np.clip(ahead.split_gain(case.y, W, h, p), 0, 1)
    first = np.isnan(gain_ho)
    t["split gain (fit on the window's first 70 %, gain on its last 30 %)"] = ahead.step_target(W, N, split)
    for f in (1.0, 0.5, 0.25):
        t[f"held-out gain; first window {f:g} x split gain"] = ahead.step_target(
            W, N, np.where(first, f * split, np.clip(np.nan_to_num(gain_ho), 0, 1)))
    peak = np.array([0.0 if w.flag in ahead.NO_TREMOR_FLAGS else 1.0 for w in W])
    t["held-out gain x tremor peak (0 on no_tremor_peak)"] = (t["held-out gain, clipped to [0, 1]"]
                                                             * ahead.step_target(W, N, peak))
    t["held-out gain x fallback flag"] = t["held-out gain, clipped to [0, 1]"] * t["off on a fallback cut-off flag"]
    t["held-out gain x in-sample skill"] = (t["held-out gain, clipped to [0, 1]"]
                                            * t["in-sample skill, clipped to [0, 1]"])
    t["held-out gain x (1 - running ratio)"] = (t["held-out gain, clipped to [0, 1]"]
                                                * t["1 - running error ratio, clipped"])
    return t


CHOSEN_GATE = "held-out gain x tremor peak (0 on no_tremor_peak)"


def chosen(case):
    """The chosen design at each ramp time constant, beside the same predictor ungated."""
    out = {}
    for h in HORIZONS:
        P = ahead.predictor_direct_wiener(case.y, case.windows, h, P_MAIN)
        target = gate_targets(case, P, h)[CHOSEN_GATE]
        out.setdefault("the predictor ungated (on from the first HPA)", {})[h] = P
        for tau in (0.1, 0.3, 1.0):
            out.setdefault(f"gated: {CHOSEN_GATE}, ramp {tau:g} s", {})[h] = ahead.ramp(target, case.fs, tau) * P
    return out


def gated_candidates(case, tau_s=0.3):
    """Every candidate predictor behind the chosen gate (held-out gain, ramp ``tau_s``)."""
    y, W, fs = case.y, case.windows, case.fs
    cands = {f"direct LS, WAKE estimate -> window truth, {p} taps":
             {h: ahead.predictor_direct_wiener(y, W, h, p) for h in HORIZONS} for p in (4, P_MAIN)}
    cands.update({
             f"AR({P_MAIN}) Yule-Walker on the window truth, iterated":
             {h: ahead.predictor_ar(y, W, h, P_MAIN) for h in HORIZONS},
             f"direct {P_MAIN}-tap LS, window truth -> truth":
             {h: ahead.predictor_direct_truth(y, W, h, P_MAIN) for h in HORIZONS}})
    for bw in (1.0, 2.0, 4.0):
        cands[f"Kalman oscillator, bandwidth {bw:g} Hz"] = ahead.predictor_oscillator(y, W, fs, HORIZONS, bw)
    cands["the issue's sketch: AR(20) on WAKE's past estimate, refitted every 0.5 s"] = {
        h: ahead.predictor_ar_on_estimate(y, h) for h in HORIZONS}
    out = {}
    for name, byh in cands.items():
        for h, P in byh.items():
            target = ahead.chosen_gate(P, W, h, len(y))
            out.setdefault(f"{name}, gated", {})[h] = ahead.ramp(target, fs, tau_s) * P
    return out


def fit_variants(case, tau_s=0.3):
    """The chosen predictor fitted without the window's edges or with a larger ridge, behind the chosen gate."""
    y, W, fs = case.y, case.windows, case.fs
    fits = {"as chosen (ridge 1e-3, whole window)": dict(trim=0, ridge=1e-3)}
    fits.update({f"window edges left out ({k} samples each end)": dict(trim=k, ridge=1e-3) for k in (10, 25)})
    fits.update({f"ridge {r:g}": dict(trim=0, ridge=r) for r in (1e-2, 1e-1)})
    out = {}
    for label, kw in fits.items():
        for h in HORIZONS:
            P = ahead.predictor_direct_wiener_trimmed(y, W, h, P_MAIN, kw["trim"], kw["ridge"])
            target = ahead.chosen_gate(P, W, h, len(y))
            out.setdefault(label, {})[h] = ahead.ramp(target, fs, tau_s) * P
    return out


def input_variants(case, tau_s=0.3):
    """Other inputs than WAKE's estimate for the direct least squares, ungated and behind the chosen gate."""
    y, x, W, fs = case.y, case.x, case.windows, case.fs
    dx = np.diff(x, prepend=x[0])
    out = {}
    for label, sig, taps in (("WAKE's estimate, 8 taps (the chosen input)", (y,), (8,)),
                             ("the measurement x, 8 taps", (x,), (8,)),
                             ("its first difference, 8 taps", (dx,), (8,)),
                             ("WAKE's estimate 8 + x 8 taps", (y, x), (8, 8)),
                             ("WAKE's estimate 4 + x 4 taps", (y, x), (4, 4)),
                             ("WAKE's estimate 8 + first difference 8 taps", (y, dx), (8, 8))):
        for h in HORIZONS:
            P = ahead.predictor_direct_inputs(sig, W, h, taps)
            target = ahead.chosen_gate(P, W, h, len(y))
            out.setdefault(f"{label}, ungated", {})[h] = P
            out.setdefault(f"{label}, gated", {})[h] = ahead.ramp(target, fs, tau_s) * P
    return out


def gated(case, tau_s=0.3, p=P_MAIN):
    """{gate: {h: g * P}} for the chosen predictor (direct Wiener, ``p`` taps) behind every gate target."""
    out = {}
    for h in HORIZONS:
        P = ahead.predictor_direct_wiener(case.y, case.windows, h, p)
        for name, target in gate_targets(case, P, h, p).items():
            out.setdefault(name, {})[h] = ahead.ramp(target, case.fs, tau_s) * P
    return out


def print_early(title, acc, zero):
    """The 1-2 s and 2-5 s slices, gated / zero, per horizon."""
    print(f"\n{title}\n")
    print("| gate | " + " | ".join(f"h={h} 1-2 s" for h in HORIZONS) + " | "
          + " | ".join(f"h={h} 2-5 s" for h in HORIZONS) + " |")
    print("|---|" + "---:|" * (2 * len(HORIZONS)))
    for name, byh in acc.items():
        cells = [mean_slices(byh[h])[sl] for sl in ("1-2 s", "2-5 s") for h in HORIZONS]
        print(f"| {name} | " + " | ".join(f"{v:.3f}" for v in cells) + " |")


def print_harm(title, acc, zero):
    """After 5 s and the worst slice (gated / zero) per horizon; "no harm" when every slice at every h <= 1."""
    names = [n for n in SLICES if n != "whole (from 0.5 s)"] + ["whole (from 0.5 s)"]
    print(f"\n{title}\n")
    print("| gate | " + " | ".join(f"h={h} after 5 s" for h in HORIZONS) + " | "
          + " | ".join(f"h={h} worst slice / zero" for h in HORIZONS) + " | no harm |")
    print("|---|" + "---:|" * (2 * len(HORIZONS)) + "---|")
    for name, byh in acc.items():
        after, worst = [], []
        for h in HORIZONS:
            m, z = mean_slices(byh[h]), mean_slices(zero[h])
            after.append(m["after 5 s"])
            worst.append(max((m[n] / z[n], n) for n in names))
        ok = all(w[0] <= 1.0 + 1e-12 for w in worst)
        print(f"| {name} | " + " | ".join(f"{a:.3f}" for a in after) + " | "
              + " | ".join(f"{w[0]:.4f} ({w[1].split(' (')[0]})" for w in worst) + f" | {'yes' if ok else 'no'} |")


def print_per_signal(label, best, zero):
    """How many signals the chosen design harms (NRMSE above zero's) per slice, and by how much at most."""
    rows = best[f"gated: {CHOSEN_GATE}, ramp 0.3 s"]
    names = [n for n in SLICES if n not in ("0.5-1 s",)]
    print(f"\n{label}: signals where the chosen design is above zero (count of {len(zero[1])}, largest ratio)\n")
    print("| h | " + " | ".join(names) + " |")
    print("|---:|" + "---|" * len(names))
    for h in HORIZONS:
        cells = []
        for n in names:
            r = np.array([g[n] / z[n] for g, z in zip(rows[h], zero[h])])
            worse = r > 1 + 1e-12
            cells.append(f"{int(worse.sum())} ({np.nanmax(r):.3f})")
        print(f"| {h} | " + " | ".join(cells) + " |")


def print_targets(label, acc, best):
    """The chosen design after 5 s against zero, the oracles and the baselines (ratios, 4 digits)."""
    def after(byh, h):
        return mean_slices(byh[h])["after 5 s"]

    mine = best[f"gated: {CHOSEN_GATE}, ramp 0.3 s"]
    refs = [n for n in acc if n.startswith(("zero", "oracle", "hindsight")) or "own extrapolation" in n]
    print(f"\n{label}: the chosen design after 5 s (8-tap direct Wiener, the chosen gate, ramp 0.3 s) "
          "divided by each reference\n")
    print("| reference | " + " | ".join(f"h={h}" for h in HORIZONS) + " |")
    print("|---|" + "---:|" * len(HORIZONS))
    print("| the chosen design itself (NRMSE) | " + " | ".join(f"{after(mine, h):.4f}" for h in HORIZONS) + " |")
    for n in refs:
        print(f"| / {n} | " + " | ".join(f"{after(mine, h) / after(acc[n], h):.3f}" for h in HORIZONS) + " |")


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
            print_by_horizon(f"{label}: predictors by order (ungated)", table_rows(cases, orders))
            z = zero_rows(cases)["zero (the actuator stays off)"]
            gates = table_rows(cases, gated)
            print_harm(f"{label}: gates on the direct Wiener predictor ({P_MAIN} taps), ramp 0.3 s", gates, z)
            print_early(f"{label}: the same gates in the first seconds (NRMSE)", {**zero_rows(cases), **gates}, z)
            print_harm(f"{label}: every predictor behind the chosen gate ({CHOSEN_GATE}, ramp 0.3 s)",
                       table_rows(cases, gated_candidates), z)
            print_harm(f"{label}: fitting variants of the chosen predictor, behind the chosen gate",
                       table_rows(cases, fit_variants), z)
            print_harm(f"{label}: inputs of the direct least-squares predictor (columns scaled to unit RMS)",
                       table_rows(cases, input_variants), z)
            best = zero_rows(cases)
            best.update(table_rows(cases, chosen))
            print_harm(f"{label}: the chosen gate by ramp time constant", best, z)
            for h in HORIZONS:
                print_slices(f"{label}: the chosen design per slice", best, h)
            print_targets(label, acc, best)
            print_per_signal(label, best, z)
    print(f"\n({time.time() - t0:.0f} s)")


if __name__ == "__main__":
    main()
