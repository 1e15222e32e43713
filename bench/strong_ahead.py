"""Tremor ahead where tremor is strong: today's predictor, the selectable ones and the 40-tap hindsight limit.

    python bench/strong_ahead.py             # pdkit, the strong synthetic set, PADS (when found), about 3 min
    python bench/strong_ahead.py --quick     # pdkit and 4 strong synthetic signals, 10 and 50 ms
    python bench/strong_ahead.py --diagnose  # pdkit and the strong set with the refit-often ceilings, 3 min
    python bench/strong_ahead.py --ridge-scale centred --gate-cutoff 4   # the same with issue 46's settings
    python bench/strong_ahead.py --sweep-nlms  # "nlms8"'s step size: pdkit's 13 axes and the strong set, 20/50 ms

Per dataset and horizon, the mean over axes of the NRMSE after 5 s (range of the truth after 5 s) of what an
actuator plays against the truth (pdkit and PADS: :func:`wake.eval.truth.tremor_truth` of the whole
recording; the strong synthetic set of :mod:`wake.eval.strong_tremor`: its tremor component), and its ratio to
zero (the actuator off) and to the hindsight 40-tap Wiener limit from WAKE's own estimate
(:func:`wake.eval.ahead_select.wiener_limit`):

* "command (C core)": ``WakeResult.command`` of the filter on the C core, default settings (predictor "fir8");
* "<predictor>, gated": :func:`wake.eval.ahead_select.command_with` of each predictor of
  :data:`wake.ahead_models.PREDICTORS` and of each per-sample adaptive one of :data:`wake.ahead_models.ADAPTIVE`
  on the same run (float);
* "no harm": per slice of time since start (``wake.eval.warmup.SLICES``), the largest ratio of the mean
  command to zero's; "axes < zero": on how many axes the command is strictly below zero after 5 s.

``--diagnose`` adds what a causal predictor could reach if it were refitted every 0.5 s on the last 5 s
instead of at each HPA (every 5 s): "refit 0.5 s, true truth, p taps" fits on the recording's own truth (a
ceiling no device has), "refit 0.5 s, window truth, 40 taps, gated" on the sharp high-pass of the last 5 s
at the last HPA's cut-off with its newest 0.5 s left out (what a device could compute), gated by the
held-out gain on the 0.5 s before.

``--ridge-scale`` and ``--gate-cutoff`` run the filter with those settings (``WakeConfig.ridge_scale``,
``WakeConfig.gate_cutoff``; issue 46): its command, every candidate and the limit (from the filter's own
estimate) follow.  The set "pdkit, all 39 axes" (every axis of the 13 recordings, tremor task or not: what
``wake evaluate`` reports) is scored for no harm.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeConfig, WakeFilter  # noqa: E402
from wake.ahead import fit_rows, gate_target, horizon_from_ms, lagged, ramp_step, scale_gain  # noqa: E402
from wake.ahead_models import ADAPTIVE, PREDICTORS  # noqa: E402
from wake.eval.tremor_ahead import aligned  # noqa: E402
from wake.hpa.sharp import detrended_highpass  # noqa: E402
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
        recs = load_pdkit_folder(folder)
        sets["pdkit, 13 tremor axes"] = [(r.recording.samples[:, c].astype(float), r.recording.fs, None)
                                         for r, c in tremor_axes(recs)]
        if not args.quick and not args.diagnose:
            sets["pdkit, all 39 axes"] = [(r.recording.samples[:, c].astype(float), r.recording.fs, None)
                                          for r in recs for c in range(r.recording.samples.shape[1])]
    sets["strong synthetic"] = [(s.measurement, s.fs, s.tremor)
                                for s in strong_tremor_dataset(4 if args.quick else 10)]
    folder = default_pads_dir(cwd=ROOT)
    if not args.quick and folder is not None and Path(folder).is_dir():
        sets["PADS, 60 axes"] = [(rec.samples[:, c].astype(float), rec.fs, None)
                                 for rec in load_pads_folder(folder) for c in range(rec.samples.shape[1])]
    return sets


def refit_often(x, y, truth, res, h, p, fs, window_truth, every_s=0.5, span_s=5.0, drop_s=0.5):
    """The diagnoses of ``--diagnose`` (module docstring): a p-tap predictor refitted every ``every_s``."""
    n, step, span = y.size, int(every_s * fs), int(span_s * fs)
    drop = int(drop_s * fs) if window_truth else 0
    X = lagged(y, p)
    P, goal, prev = np.zeros(n), np.zeros(n), None
    for a in range(int(fs), n, step):
        done = [u for u in res.hpa[0] if u.index <= a]
        if not done:
            continue
        lo = max(0, a - span)
        T = np.zeros(n)
        T[lo:a] = detrended_highpass(x[lo:a], fs, done[-1].cutoff) if window_truth else truth[lo:a]
        ks = np.arange(max(lo, p - 1), a - h - drop)
        if ks.size < 2 * p:
            continue
        gain = scale_gain(X[ks[-step:]] @ prev, T[ks[-step:] + h]) if prev is not None else 0.0
        prev = fit_rows(X[ks], T[ks + h])
        P[a:a + step] = X[a:a + step] @ prev
        goal[a:a + step] = gate_target(gain, done[-1].cutoff_flag) if window_truth else 1.0
    g, v, alpha = np.empty(n), 0.0, ramp_step(fs)
    for k in range(n):
        v += alpha * (goal[k] - v)
        g[k] = v
    return aligned(g * P, h)


def score_axis(x, fs, truth, ms, diagnose=False, settings=None):
    h = horizon_from_ms(ms, fs)
    if truth is None:
        truth = tremor_truth(x, fs)[1]
    cfg = WakeConfig(fs=fs, horizon=h, backend=BACKEND, **(settings or {}))
    res = WakeFilter(config=cfg).run(x)
    y = x - res.voluntary
    methods = {"zero": np.zeros_like(x), "command (C core)" if BACKEND == "c" else "command": res.command}
    for p in PREDICTORS + ADAPTIVE:
        methods[f"{p}, gated"] = command_with(x, res, cfg, h, p)[2]
    if diagnose:
        for p in (8, 40):
            methods[f"refit 0.5 s, true truth, {p} taps"] = refit_often(x, y, truth, res, h, p, fs, False)
        methods["refit 0.5 s, window truth, 40 taps, gated"] = refit_often(x, y, truth, res, h, 40, fs, True)
    methods["limit: hindsight 40-tap Wiener"] = wiener_limit(y, truth, h, 40)
    methods["hindsight 8-tap Wiener"] = wiener_limit(y, truth, h, 8)
    return {k: slice_nrmse(truth, v, fs) for k, v in methods.items()}


def sweep_nlms(sets, settings, steps=(0.02, 0.05, 0.1, 0.2)):
    """``"nlms8"`` gated at each step size of ``steps``: mean NRMSE after 5 s / the 40-tap limit, 20 and 50 ms."""
    import wake.ahead_models as models

    print("\n### nlms8's step size: x the 40-tap limit, 20 ms / 50 ms\n")
    print("| mu | " + " | ".join(sets) + " |")
    print("|---|" + "---:|" * len(sets))
    keep = models.NLMS_STEP
    try:
        for mu in steps:
            models.NLMS_STEP = mu
            cells = []
            for axes in sets.values():
                out = []
                for ms in (20, 50):
                    r = [nlms_vs_limit(x, fs, t, ms, settings) for x, fs, t in axes]
                    out.append(np.mean([a for a, _ in r]) / np.mean([b for _, b in r]))
                cells.append(f"{out[0]:.3f} / {out[1]:.3f}")
            print(f"| {mu:g} | " + " | ".join(cells) + " |")
    finally:
        models.NLMS_STEP = keep


def nlms_vs_limit(x, fs, truth, ms, settings):
    """(nlms8 gated, the 40-tap limit): NRMSE after 5 s of one axis."""
    h = horizon_from_ms(ms, fs)
    truth = tremor_truth(x, fs)[1] if truth is None else truth
    cfg = WakeConfig(fs=fs, horizon=h, backend=BACKEND, **settings)
    res = WakeFilter(config=cfg).run(x)
    cmd = command_with(x, res, cfg, h, "nlms8")[2]   # reads models.NLMS_STEP (wake.ahead_models.adaptive_predictor)
    return (slice_nrmse(truth, cmd, fs)["after 5 s"],
            slice_nrmse(truth, wiener_limit(x - res.voluntary, truth, h, 40), fs)["after 5 s"])


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--diagnose", action="store_true", help="also the refit-every-0.5-s ceilings (pdkit and the "
                                                              "strong set only)")
    p.add_argument("--sweep-nlms", action="store_true", help="only nlms8's step size (pdkit 13 axes, strong set)")
    p.add_argument("--ridge-scale", default="gram", help="WakeConfig.ridge_scale of the filter (default gram)")
    p.add_argument("--gate-cutoff", type=float, default=None, help="WakeConfig.gate_cutoff of the filter, Hz "
                                                                   "(default None: the HPA's cut-off)")
    args = p.parse_args(argv)
    settings = dict(ridge_scale=args.ridge_scale, gate_cutoff=args.gate_cutoff)
    WakeConfig(**settings)   # bad settings fail here, before any recording is read
    print(f"settings: {settings}")
    horizons = (10, 50) if args.quick else (10, 20, 50, 100)
    if args.sweep_nlms:
        args.quick, args.diagnose = False, True   # pdkit's 13 axes and 10 strong signals, no PADS needed
        sweep_nlms({k: v for k, v in axes_of(args).items() if not k.startswith("PADS")}, settings)
        return 0
    for name, axes in axes_of(args).items():
        print(f"\n### {name} ({len(axes)}), after 5 s: NRMSE, x zero, x the 40-tap limit\n")
        if args.diagnose and name.startswith("PADS"):
            continue
        rows = {ms: [score_axis(x, fs, t, ms, args.diagnose, settings) for x, fs, t in axes] for ms in horizons}
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
        for m in [k for k in methods if ("gated" in k or k.startswith("command")) and "refit" not in k]:
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
