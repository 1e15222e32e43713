"""How closely the single-precision C HPA (csrc/wake_hpa.c) agrees with the Python HPA.

Two measurements, on the paper's ten synthetic signals and, when present, on
every PADS axis:

* per window: both HPAs on the same window (every window the Python-HPA
  pipeline analysed, quantised with that channel's full scale for the C one):
  the share of windows with the same cut-off flag, and where the flags agree
  the largest ``|f_d(C) - f_d(Python)|`` in PSD grid steps (fs / 1022);
* per pipeline: the fixed-point RTP driven by the C HPA against the same RTP
  driven by the Python HPA: NRMSE of the voluntary motion (synthetic, against
  the known truth) and of the tremor (PADS, against the offline sharp
  high-pass at the Python run's mean cut-off), after the warm-up (the paper's
  score) and over the whole recording from 0.5 s.

Targets (issue "Standalone firmware"): the same flag in >= 98 % of windows,
f_d within one grid step, pipeline NRMSE within 1 % on every synthetic signal
and on the PADS mean.

    python bench/hpa_c_agreement.py [--pads DIR] [--json OUT]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.metrics import nrmse, offline_ground_truth  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.hpa import run_hpa  # noqa: E402
from wake.hpa.c_port import run_hpa_c  # noqa: E402

WHOLE_FROM_S = 0.5


def window_agreement(x, res, cfg, taps):
    """Both HPAs on every window the Python-HPA run analysed: (same flag?, grid steps apart) per window."""
    L = cfg.window_samples
    out = []
    for c, updates in enumerate(res.hpa):
        fs_scale = float(res.full_scale[c])
        for upd in updates:
            window = x[max(0, upd.index - L): upd.index, c]
            py = run_hpa(window, cfg, taps=taps)
            cc = run_hpa_c(window, cfg, taps=taps, full_scale=fs_scale)
            steps = abs(cc.cutoff - py.cutoff) / (cfg.fs / 1022)
            out.append((py.cutoff_flag == cc.cutoff_flag, steps, py.cutoff_flag, cc.cutoff_flag))
    return out


def run_pair(x, fs):
    """The fixed-point pipeline with the Python HPA and with the C HPA."""
    py = WakeFilter(fs=fs, backend="c", hpa_backend="python").run(x)
    cc = WakeFilter(fs=fs, backend="c", hpa_backend="c").run(x)
    return py, cc


def _summarise(windows):
    same = np.array([w[0] for w in windows])
    steps = np.array([w[1] for w in windows if w[0]])
    return {"windows": len(windows), "same_flag_share": float(same.mean()),
            "max_grid_steps_when_same": float(steps.max()) if steps.size else 0.0,
            "within_one_step_share": float((steps <= 1.0 + 1e-9).mean()) if steps.size else 1.0}


def synthetic():
    rows, windows = [], []
    for i, s in enumerate(paper_dataset()):
        x = s.measurement[:, None]
        py, cc = run_pair(x, s.fs)
        filt = WakeFilter(fs=s.fs, backend="c")
        cfg = filt.config
        windows += window_agreement(x, py, cfg, filt.taps)
        start = cfg.window_samples
        w0 = int(WHOLE_FROM_S * s.fs)
        row = {"signal": i + 1}
        for name, res in (("python", py), ("c", cc)):
            v = res.voluntary[:, 0]
            row[name] = {"after_warmup": nrmse(s.voluntary, v, start), "whole": nrmse(s.voluntary, v, w0)}
        row["rel_change_after_warmup"] = row["c"]["after_warmup"] / row["python"]["after_warmup"] - 1
        row["rel_change_whole"] = row["c"]["whole"] / row["python"]["whole"] - 1
        rows.append(row)
    return {"rows": rows, "windows": _summarise(windows)}


def pads(folder):
    rows, windows = [], []
    for rec in load_pads_folder(folder):
        x = rec.samples
        py, cc = run_pair(x, rec.fs)
        filt = WakeFilter(fs=rec.fs, backend="c")
        windows += window_agreement(x, py, filt.config, filt.taps)
        start = filt.config.window_samples
        w0 = int(WHOLE_FROM_S * rec.fs)
        for c, axis in enumerate(rec.channels):
            _, gt = offline_ground_truth(x[:, c], rec.fs, float(py.mean_cutoff[c]))
            row = {"recording": rec.name, "axis": axis}
            for name, res in (("python", py), ("c", cc)):
                est = x[:, c] - res.voluntary[:, c]
                row[name] = {"after_warmup": nrmse(gt, est, start), "whole": nrmse(gt, est, w0)}
            rows.append(row)
    mean = {name: {k: float(np.mean([r[name][k] for r in rows])) for k in ("after_warmup", "whole")}
            for name in ("python", "c")}
    return {"rows": rows, "mean": mean, "windows": _summarise(windows),
            "rel_change_mean_after_warmup": mean["c"]["after_warmup"] / mean["python"]["after_warmup"] - 1,
            "rel_change_mean_whole": mean["c"]["whole"] / mean["python"]["whole"] - 1}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pads", help="PADS folder (default: the usual places)")
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args(argv)
    out = {"synthetic": synthetic()}
    syn = out["synthetic"]
    print("synthetic: voluntary NRMSE, C HPA vs Python HPA (both on the fixed-point RTP)")
    print(f"{'signal':>6} {'python':>8} {'c':>8} {'change':>8}   {'whole py':>8} {'whole c':>8} {'change':>8}")
    for r in syn["rows"]:
        print(f"{r['signal']:>6} {r['python']['after_warmup']:8.5f} {r['c']['after_warmup']:8.5f} "
              f"{100 * r['rel_change_after_warmup']:+7.2f}%   {r['python']['whole']:8.5f} {r['c']['whole']:8.5f} "
              f"{100 * r['rel_change_whole']:+7.2f}%")
    print("synthetic windows:", syn["windows"])
    folder = default_pads_dir(args.pads)
    if folder is not None:
        out["pads"] = p = pads(folder)
        print(f"PADS ({len(p['rows'])} axes) mean tremor NRMSE after warm-up: python {p['mean']['python']['after_warmup']:.5f}"
              f"  c {p['mean']['c']['after_warmup']:.5f}  ({100 * p['rel_change_mean_after_warmup']:+.2f}%)")
        print(f"PADS mean tremor NRMSE whole: python {p['mean']['python']['whole']:.5f}  c {p['mean']['c']['whole']:.5f}"
              f"  ({100 * p['rel_change_mean_whole']:+.2f}%)")
        print("PADS windows:", p["windows"])
    else:
        print("PADS: not found (pass --pads DIR)")
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
