"""The HPA's tremor ground truth with and without the window's end-point line taken out first.

    python bench/truth_detrend.py          # PADS (if found) and the synthetic set

The HPA's tremor ground truth is a sharp FFT high-pass of the window
(:func:`wake.hpa.sharp.sharp_highpass`).  The FFT treats the window as one
period, so a window that ends higher than it starts (a voluntary movement in
progress) has a jump at its seam, and the jump's high-frequency content lands
in the "tremor" truth at both ends of the window: where the causal fit's
newest rows are.  The shipped HPA (:func:`wake.hpa.sharp.detrended_highpass`)
subtracts the line through the window's first and last samples before the
high-pass (the line is voluntary by definition); the paper's truth is the
plain high-pass (:func:`wake.hpa.sharp.sharp_highpass`).  Scores: mean NRMSE
per slice of time since start, as in ``bench/warmup_slices.py`` (PADS:
tremor against the independent truth; synthetic: voluntary), with the
Python HPA and the default RTP backend (docs/studies/design.md, "Tremor ground
truth of a window").
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wake.hpa.run as hpa_run  # noqa: E402
from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import SLICES, independent_ground_truth, mean_slices, slice_nrmse  # noqa: E402
from wake.hpa.sharp import sharp_highpass  # noqa: E402

SHIPPED = hpa_run.detrended_highpass


def scores(pads, synthetic):
    p_rows, s_rows = [], []
    for rec in pads:
        res = WakeFilter(fs=rec.fs).run(rec.samples)
        for c in range(rec.samples.shape[1]):
            _, tremor, _ = independent_ground_truth(rec.samples[:, c], rec.fs)
            p_rows.append(slice_nrmse(tremor, res.tremor[:, c], rec.fs))
    for s in synthetic:
        s_rows.append(slice_nrmse(s.voluntary, WakeFilter(fs=s.fs).run(s.measurement).voluntary, s.fs))
    return (mean_slices(p_rows) if p_rows else None), mean_slices(s_rows)


def main():
    folder = default_pads_dir(cwd=ROOT)
    pads = load_pads_folder(folder) if folder is not None and Path(folder).is_dir() else []
    synthetic = paper_dataset()
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, f in (("paper: FFT high-pass of the window", sharp_highpass),
                        ("shipped: end-point line taken out first", SHIPPED)):
            hpa_run.detrended_highpass = f
            try:
                out[name] = scores(pads, synthetic)
            finally:
                hpa_run.detrended_highpass = SHIPPED
    for k, title in ((0, "PADS, 60 recording-axes (tremor NRMSE)"), (1, "synthetic, 10 signals (voluntary NRMSE)")):
        if out[next(iter(out))][k] is None:
            print("PADS not found: its table is skipped")
            continue
        print(f"\n{title}\n\n| truth | " + " | ".join(SLICES) + " |\n|---|" + "---:|" * len(SLICES))
        for name, v in out.items():
            print(f"| {name} | " + " | ".join(f"{v[k][s]:.4f}" for s in SLICES) + " |")


if __name__ == "__main__":
    main()
