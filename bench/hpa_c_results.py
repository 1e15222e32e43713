"""Every result of the C HPA on the synthetic set and PADS, saved bit for bit, and compared with an earlier save.

A change to csrc/wake_hpa.c that should not move any result (a guard that never fires on a real
window) is checked by saving the results before and after and comparing them:

    python bench/hpa_c_results.py --save before.npz          (on the old code)
    python bench/hpa_c_results.py --save after.npz --compare before.npz

Windows: on each of the paper's ten synthetic signals and, when present, each PADS axis, the
warm-up windows of 100, 200, 300 and 400 samples from the start and then a window of L samples
every ``--hop`` samples (default 5), each run by the C HPA (wake.hpa.c_port.run_hpa_c) alone;
then the fixed-point pipeline driven by the C HPA (its voluntary motion, every sample).  The
comparison prints how many windows differ in any field (weights, R, e_L, ridge, cut-off, flags)
and by how much, and how many pipeline samples differ.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.hpa.c_port import run_hpa_c  # noqa: E402

FIELDS = ("weights", "measurement_noise", "fit_error", "ridge", "cutoff")


def signals(pads_dir):
    """(name, samples (n, channels), fs) of every synthetic signal and PADS recording."""
    for i, s in enumerate(paper_dataset()):
        yield f"synthetic {i + 1}", s.measurement[:, None], s.fs
    folder = default_pads_dir(pads_dir)
    if folder is not None and Path(folder).is_dir():
        for rec in load_pads_folder(folder):
            yield rec.name, rec.samples, rec.fs


def windows(n, L, hop):
    """(start, end) of the warm-up windows and of every full window hop samples apart."""
    out = [(0, m) for m in range(L // 5, L, L // 5)]
    out += [(e - L, e) for e in range(L, n + 1, hop)]
    return out


def collect(pads_dir, hop):
    rows, names, pipeline = [], [], {}
    for name, x, fs in signals(pads_dir):
        filt = WakeFilter(fs=fs, backend="c", hpa_backend="c")
        cfg, taps = filt.config, filt.taps
        res = filt.run(x)
        pipeline[name] = np.asarray(res.voluntary, dtype=np.float64)
        for c in range(x.shape[1]):
            for a, b in windows(x.shape[0], cfg.window_samples, hop):
                u = run_hpa_c(x[a:b, c], cfg, taps=taps, full_scale=float(res.full_scale[c]))
                rows.append(np.concatenate([np.asarray(u.weights, dtype=np.float64),
                                            [u.measurement_noise, u.fit_error, u.ridge, u.cutoff]]))
                names.append(f"{name} ch{c} {a}:{b} {u.cutoff_flag} {','.join(u.flags)}")
    return np.array(rows), np.array(names), pipeline


def compare(now, before):
    rows, names = now["rows"], now["names"]
    if rows.shape != before["rows"].shape:
        print(f"different window sets: {rows.shape} now, {before['rows'].shape} before")
        return 1
    differ = np.any(rows != before["rows"], axis=1) | (names != before["names"])
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(rows - before["rows"]) / np.maximum(np.abs(before["rows"]), 1e-30)
    print(f"windows: {len(rows)}, differing in any field: {int(differ.sum())}, "
          f"largest relative change {float(np.nanmax(rel)) if differ.any() else 0.0:.3g}")
    for i in np.flatnonzero(differ)[:20]:
        print(f"  {names[i]} (before: {before['names'][i]})")
    samples = changed = 0
    for key in now["pipeline"]:
        a, b = now["pipeline"][key], before["pipeline"][key]
        samples += a.size
        changed += int(np.sum(a != b)) if a.shape == b.shape else a.size
    print(f"pipeline samples: {samples}, differing: {changed}")
    return int(bool(differ.any() or changed))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pads", help="PADS folder (default: the usual places)")
    ap.add_argument("--hop", type=int, default=5, help="samples between full windows (default 5)")
    ap.add_argument("--save", required=True, help="write the results here (.npz)")
    ap.add_argument("--compare", help="an earlier --save to compare with")
    args = ap.parse_args(argv)
    rows, names, pipeline = collect(args.pads, args.hop)
    np.savez(args.save, rows=rows, names=names, **{f"pipeline {k}": v for k, v in pipeline.items()})
    print(f"saved {len(rows)} windows of {len(pipeline)} recordings to {args.save}")
    if not args.compare:
        return 0
    old = np.load(args.compare)
    before = {"rows": old["rows"], "names": old["names"],
              "pipeline": {k[len("pipeline "):]: old[k] for k in old.files if k.startswith("pipeline ")}}
    return compare({"rows": rows, "names": names, "pipeline": pipeline}, before)


if __name__ == "__main__":
    sys.exit(main())
