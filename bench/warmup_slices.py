"""Error by time since start (issue: the HPA on real wear), for WAKE and every baseline.

    python bench/warmup_slices.py                  # PADS (if found) and the synthetic set
    python bench/warmup_slices.py --variants       # also WAKE's warm-up variants (docs/studies/design.md)
    python bench/warmup_slices.py --cutoff-rule paper     # WAKE with another cut-off rule

PADS: tremor NRMSE of each method against a ground truth independent of
WAKE (sharp FFT high-pass at the Welch-spectrum valley between 1.5 and 5 Hz
of the whole recording, :mod:`wake.eval.warmup`), mean over the 60
recording-axes, per slice of time since start.  Synthetic (the paper's ten
signals): voluntary NRMSE against the known voluntary motion, mean over the
ten signals.  "zero tremor estimate" scores the trivial estimate 0 (voluntary = x):
its NRMSE is the RMS of the truth over its range, the level any method must beat.
The PADS folder is ../shared/data/pads next to the checkout or $WAKE_PADS_DIR.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeConfig, WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.evaluate import baseline_methods  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import SLICES, independent_ground_truth, mean_slices, slice_nrmse  # noqa: E402
from wake.registry import cutoff_rule_names  # noqa: E402
from wake.rtp import c_backend_available  # noqa: E402

#: WAKE variants compared in docs/studies/design.md ("Warm-up"): settings passed to WakeFilter.
VARIANTS = {
    "WAKE (first release: no progressive HPA, deepest approximation)": dict(warmup_hpa_s=(), initial_weights="deepest"),
    "WAKE, prior only": dict(warmup_hpa_s=()),
    "WAKE, progressive HPA only": dict(initial_weights="deepest"),
}


def _methods(fs, variants, rule=None):
    rule = WakeConfig.cutoff_rule if rule is None else rule
    backend = "c" if c_backend_available() else "reference"
    out = {f"WAKE ({backend})": lambda x: WakeFilter(fs=fs, backend=backend, cutoff_rule=rule).run(x).voluntary}
    if variants:
        for name, settings in VARIANTS.items():
            out[name] = (lambda s: lambda x: WakeFilter(fs=fs, backend=backend, cutoff_rule=rule,
                                                        **s).run(x).voluntary)(settings)
    for name, m in baseline_methods(fs).items():
        out[name] = (lambda m: lambda x: m.run(x).voluntary)(m)
    out["zero tremor estimate (voluntary = x)"] = lambda x: np.asarray(x, dtype=float)
    return out


def pads_table(folder, variants=False, rule=None):
    recs = load_pads_folder(folder)
    scores = {}
    for rec in recs:
        x = rec.samples
        methods = _methods(rec.fs, variants, rule)
        vols = {name: f(x) for name, f in methods.items()}
        for c in range(x.shape[1]):
            _, tremor, _ = independent_ground_truth(x[:, c], rec.fs)
            for name, v in vols.items():
                est = x[:, c] - np.reshape(v, x.shape)[:, c]
                scores.setdefault(name, []).append(slice_nrmse(tremor, est, rec.fs))
    return scores, f"PADS, {sum(r.samples.shape[1] for r in recs)} recording-axes (tremor NRMSE)"


def synthetic_table(variants=False, rule=None):
    data = paper_dataset()
    scores = {}
    for s in data:
        for name, f in _methods(s.fs, variants, rule).items():
            scores.setdefault(name, []).append(slice_nrmse(s.voluntary, f(s.measurement), s.fs))
    return scores, f"synthetic, {len(data)} signals (voluntary NRMSE)"


def print_table(scores, title):
    names = list(SLICES)
    print(f"\n{title}, mean per slice of time since start\n")
    print("| method | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for method, rows in scores.items():
        means = mean_slices(rows)
        print(f"| {method} | " + " | ".join(f"{means[n]:.3f}" for n in names) + " |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", action="store_true", help="also WAKE's warm-up variants")
    ap.add_argument("--pads", help="PADS folder (default: next to the checkout or $WAKE_PADS_DIR)")
    ap.add_argument("--cutoff-rule", default=WakeConfig.cutoff_rule, choices=cutoff_rule_names(),
                    help=f"WAKE's cut-off rule (default: {WakeConfig.cutoff_rule}, the library's)")
    args = ap.parse_args(argv)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = default_pads_dir(args.pads, cwd=ROOT)
        if folder is not None and Path(folder).is_dir():
            print_table(*pads_table(folder, args.variants, args.cutoff_rule))
        else:
            print("PADS not found (../shared/data/pads or $WAKE_PADS_DIR): real-recording table skipped")
        print_table(*synthetic_table(args.variants, args.cutoff_rule))


if __name__ == "__main__":
    main()
