"""The voluntary motion at n + h (issue 32): what fitting the weights h samples ahead buys, by measurement.

    python bench/voluntary_ahead.py            # PADS (if found) and the paper's synthetic set, h = 1, 2, 5, 10
    python bench/voluntary_ahead.py --quick    # 3 PADS recordings and 3 synthetic signals
    python bench/voluntary_ahead.py --cost     # what w_h costs: the HPA per window and the float RTP per sample

Three estimates of the voluntary motion at sample ``k`` made ``h`` samples before (from ``x[:k - h + 1]``),
each scored against the voluntary truth at ``k`` with the paper's NRMSE per slice of time since start
(``wake.eval.warmup.slice_nrmse``; "whole" is from 0.5 s), mean over recording-axes / signals:

(a) ``WakeResult.voluntary_ahead``: ``w_h' (a + d)``, the HPA's second weight vector fitted on the voluntary
    truth ``h`` samples ahead (float reference: the C core has no ``w_h``);
(b) holding the one-step prediction: the voluntary motion predicted for ``k - h + 1`` used for ``k``
    (``PredictionTarget(h - 1).voluntary_from(voluntary)``, ``voluntary`` itself at ``h = 1``);
(c) the truth itself delayed by ``h`` (``truth[k - h]``): no prediction at all, with a perfect estimate.

Beside them, the one-step ``voluntary`` scored at its own sample (what every horizon's one-step output is).
Truth: PADS, the independent sharp high-pass of the whole recording at its Welch valley between 1.5 and 5 Hz
(``wake.eval.warmup.independent_ground_truth``), its complement; synthetic, ``s_v``.  The PADS folder is
../shared/data/pads next to the checkout or $WAKE_PADS_DIR.  Tables: docs/studies/design.md, "Voluntary motion at
n + h".
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth, mean_slices, slice_nrmse  # noqa: E402
from wake.target import PredictionTarget  # noqa: E402

HORIZONS = (1, 2, 5, 10)
SLICES = {"after 5 s": (5.0, None), "whole (from 0.5 s)": (0.5, None)}
ROWS = ("a. w_h (voluntary_ahead)", "b. one-step prediction held", "c. truth delayed by h",
        "one-step voluntary at its own sample")


def estimates(x, fs, truth, h):
    """The four rows of :data:`ROWS` for one channel at horizon ``h`` (float reference)."""
    res = WakeFilter(fs=fs, backend="reference", horizon=h).run(x)
    held = res.voluntary if h == 1 else PredictionTarget(h - 1).voluntary_from(res.voluntary)
    return res.voluntary_ahead, held, PredictionTarget(h).voluntary_from(truth), res.voluntary


def channels(pads, limit):
    """(set name, x, fs, voluntary truth) of every channel: PADS (when found) and the synthetic set."""
    if pads is not None:
        for rec in load_pads_folder(pads)[:limit]:
            for c in range(rec.samples.shape[1]):
                x = rec.samples[:, c].astype(float)
                yield "PADS", x, rec.fs, independent_ground_truth(x, rec.fs)[0]
    for s in paper_dataset()[:limit]:
        yield "synthetic", s.measurement, s.fs, s.voluntary


def measure(pads, limit):
    """``scores[set][h][row]``: the mean slice NRMSE dictionaries, and the channel count of each set."""
    rows = {}
    counts = {}
    for name, x, fs, truth in channels(pads, limit):
        counts[name] = counts.get(name, 0) + 1
        for h in HORIZONS:
            for row, est in zip(ROWS, estimates(x, fs, truth, h)):
                rows.setdefault(name, {}).setdefault(h, {}).setdefault(row, []).append(
                    slice_nrmse(truth, est, fs, SLICES))
    scores = {name: {h: {row: mean_slices(v) for row, v in by_row.items()} for h, by_row in by_h.items()}
              for name, by_h in rows.items()}
    return scores, counts


def table(scores, counts):
    """Markdown tables: per set, one row per estimate, after 5 s then whole, at each horizon."""
    lines = []
    for name, by_h in scores.items():
        lines.append(f"\n{name} ({counts[name]} channels), voluntary NRMSE, mean (after 5 s | whole from 0.5 s):\n")
        head = [f"h={h} ({1000 * h / 100:g} ms at 100 Hz)" for h in HORIZONS]
        lines.append("| estimate of v(n + h) | " + " | ".join(head) + " |")
        lines.append("|---|" + "---:|" * len(HORIZONS))
        for row in ROWS:
            cells = [f"{by_h[h][row]['after 5 s']:.4f} / {by_h[h][row]['whole (from 0.5 s)']:.4f}"
                     for h in HORIZONS]
            lines.append(f"| {row} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def cost(repeats=31):
    """Median times of (i) one 5-s HPA window at h = 1 and h = 5 and (ii) the float RTP over 50 s at h = 1
    and h = 5 (``WakeFilter.run``, reference backend, HPA included), on synthetic signal 1 (50 s)."""
    from wake import WakeConfig
    from wake.hpa import run_hpa
    from wake.wavelets import filter_bank_taps

    s = paper_dataset()[0]
    lines = []
    for h in (1, 5):
        config = WakeConfig(backend="reference", horizon=h)
        taps = filter_bank_taps(config.wavelet, config.level, config.mode)
        window = s.measurement[:config.window_samples]
        hpa = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            run_hpa(window, config, taps=taps)
            hpa.append(time.perf_counter() - t0)
        runs = []
        for _ in range(7):
            t0 = time.perf_counter()
            WakeFilter(config=config).run(s.measurement)
            runs.append(time.perf_counter() - t0)
        lines.append(f"h={h}: run_hpa on one 5-s window {1e3 * np.median(hpa):.2f} ms (median of {repeats}); "
                     f"WakeFilter(backend='reference').run over {s.measurement.size} samples "
                     f"{1e3 * np.median(runs):.0f} ms (median of 7)")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="3 PADS recordings and 3 synthetic signals")
    p.add_argument("--cost", action="store_true", help="time the HPA and the float RTP at h = 1 and h = 5")
    p.add_argument("--pads", default=None, help="PADS folder (default ../shared/data/pads or $WAKE_PADS_DIR)")
    args = p.parse_args(argv)
    if args.cost:
        print(cost())
        return 0
    pads = default_pads_dir(args.pads, cwd=ROOT)
    if pads is None or not pads.is_dir():
        print("PADS not found: the synthetic set only")
        pads = None
    t0 = time.perf_counter()
    scores, counts = measure(pads, 3 if args.quick else None)
    print(table(scores, counts))
    print(f"\n{time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
