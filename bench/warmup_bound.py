"""How low WAKE's warm-up error could go: weights fitted to the *true* voluntary motion.

    python bench/warmup_bound.py          # PADS (if found) and the synthetic set, about 1 minute

The issue on real wear asks that the 1-2 s error be within 1.5x of WAKE's
own after-5-s error and that WAKE be the lowest of all methods from 0.5 s on.
Between two HPAs WAKE predicts with fixed weights ``w`` on its filter bank;
an HPA estimates the voluntary motion of its window and fits ``w`` to it.
This script replaces that estimate by the truth (synthetic: the known
voluntary motion; PADS: the measurement minus the independent tremor truth
of ``wake.eval.warmup``) and fits ``w`` by least squares on every sample seen
so far (:func:`wake.eval.warmup.truth_fitted_prediction`):

* at the default warm-up schedule (1, 2, 3, 4 s): the best any cut-off rule
  or ground-truth estimate could do with today's HPA times;
* before every sample from 0.5 s on: the limit of any HPA schedule;
* the same, pulled towards the start-up weights (``pull``);
* a hindsight choice per signal among those and WAKE (not causal: a lower
  bound on what any rule choosing between them could reach).

Each row is the mean NRMSE per slice of time since start (PADS: tremor, 60
recording-axes; synthetic: voluntary, the paper's ten signals), printed
beside WAKE, BMFLC and WFLC and the issue's two limits.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeConfig, WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.evaluate import baseline_methods  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth, mean_slices, slice_nrmse, truth_fitted_prediction  # noqa: E402
from wake.rtp import c_backend_available  # noqa: E402

SLICE_NAMES = ("0.5-1 s", "1-2 s", "2-5 s", "after 5 s")
#: Truth-fitted variants: (label, refit times or None for every sample, pull towards the start-up weights).
BOUNDS = (
    ("truth-fitted at the default HPA times (1, 2, 3, 4 s, then every 5 s)",
     tuple(WakeConfig(fs=100.0).warmup_hpa_s) + tuple(range(5, 3600, 5)), 0.0),
    ("truth-fitted before every sample", None, 0.0),
    ("truth-fitted before every sample, pull 0.01", None, 0.01),
    ("truth-fitted before every sample, pull 0.1", None, 0.1),
)

HINDSIGHT = ("hindsight choice per signal (not causal): best of WAKE, the start-up weights and the truth fits "
             "before every sample, pull 0, 0.01, 0.1, 1")


def _methods(fs):
    backend = "c" if c_backend_available() else "reference"
    out = {f"WAKE ({backend})": lambda x: WakeFilter(fs=fs, backend=backend).run(x).voluntary}
    baselines = baseline_methods(fs)
    for name in ("BMFLC", "WFLC"):
        out[name] = (lambda m: lambda x: m.run(x).voluntary)(baselines[name])
    return out


def score_set(signals):
    """signals: (x, voluntary truth, score truth, to_score, fs) per channel -> {row: [slice dicts]}."""
    rows = {}
    for x, vol, truth, to_score, fs in signals:
        for name, f in _methods(fs).items():
            rows.setdefault(name, []).append(slice_nrmse(truth, to_score(f(x)), fs))
        for label, refit, pull in BOUNDS:
            p = truth_fitted_prediction(x, vol, fs, WakeConfig(fs=fs), refit_s=refit, pull=pull)
            rows.setdefault(label, []).append(slice_nrmse(truth, to_score(p), fs))
        # Not causal: per signal and slice, the best of WAKE, the start-up weights and truth fits.
        choices = [rows[name][-1] for name in rows if name.startswith(("WAKE", "truth-fitted before"))]
        choices += [slice_nrmse(truth, to_score(truth_fitted_prediction(x, vol, fs, WakeConfig(fs=fs), refit_s=r,
                                                                        pull=pull)), fs)
                    for r, pull in (((), 0.0), (None, 1.0))]
        rows.setdefault(HINDSIGHT, []).append({k: min(c[k] for c in choices) for k in choices[0]})
    return {name: mean_slices(r) for name, r in rows.items()}


def synthetic_signals():
    for s in paper_dataset():
        yield s.measurement, s.voluntary, s.voluntary, (lambda v: v), s.fs


def pads_signals(folder):
    for rec in load_pads_folder(folder):
        for c in range(rec.samples.shape[1]):
            x = rec.samples[:, c]
            _, tremor, _ = independent_ground_truth(x, rec.fs)
            yield x, x - tremor, tremor, (lambda v, x=x: x - v), rec.fs


def print_table(means, title):
    print(f"\n{title}\n")
    print("| | " + " | ".join(SLICE_NAMES) + " |")
    print("|---|" + "---:|" * len(SLICE_NAMES))
    for name, m in means.items():
        print(f"| {name} | " + " | ".join(f"{m[s]:.3f}" for s in SLICE_NAMES) + " |")
    wake = next(m for n, m in means.items() if n.startswith("WAKE"))
    best_bound = {s: min(m[s] for n, m in means.items() if n.startswith("truth")) for s in SLICE_NAMES}
    hindsight = means[HINDSIGHT]
    best_baseline = min(means["BMFLC"]["0.5-1 s"], means["WFLC"]["0.5-1 s"])
    limit = 1.5 * wake["after 5 s"]
    print(f"\n1-2 s limit (1.5 x WAKE after 5 s): {limit:.4f}; lowest truth-fitted 1-2 s: {best_bound['1-2 s']:.3f} "
          f"({'within' if best_bound['1-2 s'] <= limit else 'above'} the limit); "
          f"hindsight choice {hindsight['1-2 s']:.4f}")
    print(f"0.5-1 s: best of BMFLC/WFLC {best_baseline:.3f}; lowest truth-fitted {best_bound['0.5-1 s']:.3f} "
          f"({'below' if best_bound['0.5-1 s'] < best_baseline else 'not below'} the baselines); "
          f"hindsight choice {hindsight['0.5-1 s']:.3f}")


def main(argv=None) -> int:
    warnings.simplefilter("ignore")
    folder = default_pads_dir(cwd=ROOT)
    if folder is not None and folder.is_dir():
        print_table(score_set(pads_signals(folder)), "PADS, 60 recording-axes (tremor NRMSE), mean per slice")
    else:
        print("PADS recordings not found: synthetic set only (set WAKE_PADS_DIR)")
    print_table(score_set(synthetic_signals()), "synthetic, the paper's 10 signals (voluntary NRMSE), mean per slice")
    return 0


if __name__ == "__main__":
    sys.exit(main())
