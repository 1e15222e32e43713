"""Cut-off rules on real wear: how often each falls back to the default, and what it does to the scores.

    python bench/cutoff_rules.py            # PADS (when found) and the paper's synthetic set

For each rule: the share of HPA windows per cut-off flag, the PADS tremor
NRMSE against the independent ground truth (``wake.eval.warmup``) over the
whole recording from 0.5 s and after 5 s, and the synthetic voluntary NRMSE
(whole and after 5 s).  The rules (``wake.hpa.cutoff``; each variant is registered as a cut-off rule of its own, ``wake.registry``; every WAKE run uses the C core):

* ``floor`` - the library's default: ``shallow`` (below), with both dips
  compared to the noise floor, the lowest PSD above the tremor band: a
  shallow dip less than ``floor_margin_db`` = 15 dB above it gives the
  default, a valley less than 15 dB above it moves to the floor's low edge
  (where the PSD comes within ``edge_db`` = 3 dB of it); ``floor margin D``
  and ``floor edge E`` vary the two; ``floor shallow-test only`` and
  ``floor edge-test only`` take one half of it (the other half off);
* ``paper`` - the valley counts only if it lies ``min_depth_db`` = 3 dB below
  both the tremor peak and the largest PSD value to its left (the paper's rule);
* ``depth 1 dB`` - the same with a 1 dB depth;
* ``no left test`` - 3 dB below the tremor peak only;
* ``shallow`` - the library's option (``cutoff_rule="shallow"``): where ``paper`` finds a tremor peak
  but no valley, the PSD minimum between ``cutoff_range[0]`` and the lower
  of the peak and ``shallow_max`` = 4 Hz, however shallow (``shallow max F``:
  the cap at F Hz; 6 Hz, the top of ``cutoff_range``, is no cap);
* ``shallow D`` - the uncapped minimum, only if it lies at least D dB below
  the peak;
* ``default F`` - the paper's rule with the fallback at F Hz instead of 2 Hz
  (is a gain only a higher cut-off?);
* ``shallow floor`` - as ``shallow``, but never below ``default_cutoff``;
* ``flank`` - as ``paper``, and when that finds no valley but there is a
  tremor peak, the frequency on the peak's left flank where the PSD is 3 dB
  below the peak.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import re  # noqa: E402
from dataclasses import replace  # noqa: E402

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth, slice_nrmse  # noqa: E402
from wake.hpa import cutoff as cutoff_mod  # noqa: E402
from wake.hpa.cutoff import Spectrum, floor_rule, paper_rule, shallow_rule  # noqa: E402
from wake.registry import register_cutoff_rule, unregister_cutoff_rule  # noqa: E402


def make_rule(kind):
    """The variant ``kind`` as a cut-off rule: a function of the window's :class:`Spectrum` (wake.registry)."""
    def find(s: Spectrum):
        if kind == "paper":
            return paper_rule(s)
        if "+default" in kind:  # "shallow+default 3": the shallow rule with the fallback at 3 Hz
            base, fallback = kind.split("+default")
            return make_rule(base)(replace(s, default_cutoff=float(fallback)))
        if kind.startswith("default "):  # the fallback at F Hz (not the setting: the prior stays at 2 Hz)
            return paper_rule(replace(s, default_cutoff=float(kind.split()[1])))
        if kind.startswith("floor"):
            if kind.startswith("floor margin "):
                s = replace(s, floor_margin_db=float(kind.split()[2]))
            if kind.startswith("floor edge "):
                s = replace(s, edge_db=float(kind.split()[2]))
            fd, flag = floor_rule(s)
            half = {"floor shallow-test only": "floor_valley", "floor edge-test only": "shallow_valley"}.get(kind)
            if flag == half:  # that half off: the paper's answer for this window
                return paper_rule(s)
            return fd, flag
        if kind == "shallow":  # the library's option (WakeConfig(cutoff_rule="shallow"), shallow_max = 4 Hz)
            return shallow_rule(s)
        if kind.startswith("shallow max "):  # the library's rule with another shallow_max
            return shallow_rule(replace(s, shallow_max=float(kind.split()[2])))
        if kind == "depth 1 dB":
            return paper_rule(replace(s, min_depth_db=1.0))
        fd, flag = paper_rule(s)
        if flag != "no_valley" or s.fallback is not None:
            return fd, flag
        freqs, db, peak = s.freqs, s.db, s.peak
        lo, hi = s.cutoff_range
        search = np.flatnonzero((freqs >= lo) & (freqs <= min(hi, freqs[peak])))
        if kind == "no left test":
            valley = search[np.argmin(db[search])]
            return (float(freqs[valley]), "valley") if db[valley] <= db[peak] - 3.0 else (fd, flag)
        if kind == "shallow floor":  # the shallow minimum, never below the default cut-off
            valley = search[np.argmin(db[search])]
            return max(float(freqs[valley]), float(s.default_cutoff)), "shallow_valley"
        if kind.startswith("shallow "):
            valley = search[np.argmin(db[search])]
            need = float(kind.split()[1])  # "shallow 1": 1 dB below the peak ("shallow 1 floor": >= default)
            if db[valley] > db[peak] - need:
                return fd, flag
            f = float(freqs[valley])
            return (max(f, float(s.default_cutoff)) if kind.endswith(" floor") else f), "shallow_valley"
        if kind == "flank":
            below = search[db[search] <= db[peak] - 3.0]
            if below.size == 0:
                return fd, flag
            return float(freqs[below[-1]]), "peak_flank"
        raise ValueError(kind)
    return find


def rule_name(kind) -> str:
    """The registry name of variant ``kind`` ("floor margin 8" -> "bench_floor_margin_8")."""
    return "bench_" + re.sub(r"\W+", "_", kind).strip("_")


RULES = ("paper", "floor", "floor shallow-test only", "floor edge-test only", "floor margin 8", "floor margin 12",
         "floor margin 20", "floor margin 25", "floor edge 1", "floor edge 6", "floor edge 10", "default 2.5",
         "default 3", "default 3.5", "depth 1 dB", "no left test", "shallow", "shallow max 3",
         "shallow max 3.5", "shallow max 4.5", "shallow max 5", "shallow max 6", "shallow 0", "shallow 1",
         "shallow floor", "shallow 1 floor", "shallow 2 floor", "flank", "shallow+default 2.5", "shallow+default 3")


def evaluate(kind, pads, synthetic):
    name = rule_name(kind)
    register_cutoff_rule(name, c_name=name.upper(), description=f"bench/cutoff_rules.py: {kind}")(make_rule(kind))
    settings = dict(cutoff_rule=name)
    try:
        flags, pads_scores, syn_scores = [], [], []
        for rec in pads:
            x = rec.samples
            res = WakeFilter(fs=rec.fs, **settings).run(x)
            flags += [u.cutoff_flag for ch in res.hpa for u in ch]
            for c in range(x.shape[1]):
                _, tremor, _ = independent_ground_truth(x[:, c], rec.fs)
                pads_scores.append(slice_nrmse(tremor, res.tremor[:, c], rec.fs))
        for s in synthetic:
            res = WakeFilter(fs=s.fs, **settings).run(s.measurement)
            syn_scores.append(slice_nrmse(s.voluntary, res.voluntary, s.fs))
        return flags, pads_scores, syn_scores
    finally:
        unregister_cutoff_rule(name)


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rules", help=f"comma-separated subset of: {', '.join(RULES)}")
    args = ap.parse_args(argv)
    rules = RULES if not args.rules else [r.strip() for r in args.rules.split(",")]
    unknown = [r for r in rules if r not in RULES]
    if unknown:
        ap.error(f"unknown rule(s) {unknown}; valid choices: {', '.join(RULES)}")
    folder = default_pads_dir(cwd=Path(__file__).resolve().parents[1])
    pads = load_pads_folder(folder) if folder is not None and folder.is_dir() else []
    synthetic = paper_dataset()
    print(f"PADS: {len(pads)} recordings; synthetic: {len(synthetic)} signals\n")
    print("| rule | PADS windows on the default | PADS flags | PADS tremor NRMSE whole / after 5 s "
          "| synthetic voluntary NRMSE whole / after 5 s |")
    print("|---|---:|---|---:|---:|")
    for kind in rules:
        flags, ps, ss = evaluate(kind, pads, synthetic)
        share = {f: flags.count(f) / max(len(flags), 1) for f in sorted(set(flags))}
        default = sum(v for f, v in share.items() if f in cutoff_mod.FALLBACK_FLAGS)
        mean = lambda rows, k: np.nanmean([r[k] for r in rows]) if rows else float("nan")  # noqa: E731
        print(f"| {kind} | {100 * default:.0f} % | " + ", ".join(f"{f} {100 * v:.0f} %" for f, v in share.items())
              + f" | {mean(ps, 'whole (from 0.5 s)'):.5f} / {mean(ps, 'after 5 s'):.5f} "
              f"| {mean(ss, 'whole (from 0.5 s)'):.5f} / {mean(ss, 'after 5 s'):.5f} |")


if __name__ == "__main__":
    main()
