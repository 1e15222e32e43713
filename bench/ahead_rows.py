"""The tremor ahead's fit on fewer rows (issue 32): what the cost target of 60 k instructions would take.

    python bench/ahead_rows.py            # PADS (if found) and the paper's synthetic set, every variant
    python bench/ahead_rows.py --quick    # 3 PADS recordings, 3 synthetic signals, two variants

The C HPA's tremor-ahead fit costs 158 k Cortex-M4F instructions a window, and its arithmetic alone is
66 k on the largest window (docs/studies/hpa_c.md, "The tremor ahead", measured with ``python -m
wake.firmware.hpa_cost --ahead --functions``): the issue's 60 k cannot be met by computing the same fit more
cleverly.  What is left is to fit on less, and this script measures what that does to the gated command.
Each HPA fits the 8-tap predictor (``wake.ahead.fit_predictor``) and scores the previous one
(``wake.ahead.held_out_gain``) on

* ``last R``: only the newest ``R`` rows of its window (every part of the pass, the estimate's FIR
  included, would scale with ``R``);
* ``every S``: every ``S``-th row, the newest kept (the row sums and the truth's oscillators would scale
  with ``1 / S``; the FIR would not, every lag of the estimate is still read).

Both substitute the two functions where :mod:`wake.hpa.run` calls them, on the C core with the Python HPA,
default settings.  Scored as ``wake evaluate`` scores the tremor ahead (:func:`wake.eval.tremor_ahead.ahead_scores`):
the gated command's NRMSE after 5 s and its ratio to zero, and the largest ratio to zero over the slices
of time since start (above 1: the command harms in that slice).  Tables: docs/studies/design.md, "Tremor ahead",
"A fit on fewer rows".
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wake.ahead as ahead  # noqa: E402
import wake.hpa.run as hpa_run  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.tremor_ahead import GATED, ZERO, ahead_scores  # noqa: E402
from wake.eval.warmup import independent_ground_truth, mean_slices  # noqa: E402

VARIANTS = ("all rows", "last 240", "last 160", "last 120", "every 2", "every 3", "every 4")
QUICK_VARIANTS = ("all rows", "last 160")


def kept_rows(variant: str, count: int) -> np.ndarray:
    """Indices of the rows (oldest first) a variant keeps of ``count``."""
    rows = np.arange(count)
    if variant.startswith("last "):
        return rows[-int(variant.split()[1]):]
    if variant.startswith("every "):
        return rows[::-1][::int(variant.split()[1])][::-1]
    return rows


def fit_on(variant: str):
    """``fit_predictor`` restricted to the variant's rows (``wake.ahead.fit_rows``: the same solve)."""
    def fit(estimate, truth, horizon, taps=ahead.TAPS, ridge=ahead.RIDGE):
        y, t = np.asarray(estimate, dtype=float), np.asarray(truth, dtype=float)
        X = ahead.lagged(y, taps)[taps - 1:y.size - horizon]
        keep = kept_rows(variant, X.shape[0])
        return ahead.fit_rows(X[keep], t[taps - 1 + horizon:][keep], ridge)
    return fit


def held_out_on(variant: str):
    """``held_out_gain`` over the held-out targets the variant's rows keep (the C HPA scores the previous
    predictor from the fit's own sums, so it would see only those)."""
    def held(estimate, truth, previous, horizon, new_samples):
        pairs = ahead.held_out_pairs(estimate, truth, previous, horizon, new_samples)
        if pairs is None:
            return 0.0
        keep = kept_rows(variant, pairs[0].size)
        return ahead.scale_gain(pairs[0][keep], pairs[1][keep])
    return held


@contextlib.contextmanager
def variant_in_use(variant: str):
    """The HPA fits and scores on the variant's rows inside the block; as shipped outside it."""
    saved = hpa_run.fit_predictor, hpa_run.held_out_gain
    if variant != "all rows":
        hpa_run.fit_predictor, hpa_run.held_out_gain = fit_on(variant), held_out_on(variant)
    try:
        yield
    finally:
        hpa_run.fit_predictor, hpa_run.held_out_gain = saved


def recordings(pads, limit):
    """(set, x (n, channels), fs, true tremor) per recording: PADS (when found), then the synthetic set."""
    if pads is not None:
        for rec in load_pads_folder(pads)[:limit]:
            x = rec.samples.astype(float)
            truth = np.column_stack([independent_ground_truth(c, rec.fs)[1] for c in x.T])
            yield "PADS", x, rec.fs, truth
    for s in paper_dataset()[:limit]:
        yield "synthetic", s.measurement[:, None], s.fs, s.tremor[:, None]


def scores(variant, data):
    """{(set, ms): (after 5 s, ratio to zero after 5 s, largest ratio to zero over the slices)}."""
    rows = {}
    with variant_in_use(variant):
        for name, x, fs, truth in data:
            for ms, methods in ahead_scores(x, fs, truth, backend="c", baselines=False).items():
                acc = rows.setdefault((name, ms), ([], []))
                acc[0].extend(methods[GATED])
                acc[1].extend(methods[ZERO])
    out = {}
    for key, (gated, zero) in rows.items():
        g, z = mean_slices(gated), mean_slices(zero)
        worst = max(g[s] / z[s] for s in g if z[s] > 0)
        out[key] = (g["after 5 s"], g["after 5 s"] / z["after 5 s"], worst)
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pads", help="PADS folder (default: $WAKE_PADS_DIR or ../shared/data/pads)")
    parser.add_argument("--quick", action="store_true", help="3 recordings of each set, two variants")
    args = parser.parse_args(argv)
    pads = default_pads_dir(args.pads)
    if pads is None:
        print("PADS not found: the synthetic set only", file=sys.stderr)
    limit = 3 if args.quick else None
    data = list(recordings(pads, limit))
    print("| variant | set | 10 ms | 20 ms | 50 ms | 100 ms | largest slice / zero |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for variant in (QUICK_VARIANTS if args.quick else VARIANTS):
        start = time.monotonic()
        out = scores(variant, data)
        for name in dict.fromkeys(n for n, _ in out):
            cells = [f"{out[(name, ms)][0]:.4f} ({out[(name, ms)][1]:.3f})" for ms in sorted(m for n, m in out if n == name)]
            worst = max(out[(name, ms)][2] for n, ms in out if n == name)
            print(f"| {variant} | {name} | {' | '.join(cells)} | {worst:.3f} |", flush=True)
        print(f"  ({variant}: {time.monotonic() - start:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
