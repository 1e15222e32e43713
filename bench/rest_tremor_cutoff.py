"""Cut-off on rest tremor with little voluntary motion: which rule, measured.

    python bench/rest_tremor_cutoff.py            # rest-tremor set, the paper's synthetic set, PADS (when found)
    python bench/rest_tremor_cutoff.py --fixed     # also every window at a fixed f_d (what each cut-off is worth)
    python bench/rest_tremor_cutoff.py --c-hpa     # the C HPA against the Python HPA on the rest-tremor set

A window of rest tremor on slow 1/f drift (``wake.eval.synthetic.rest_tremor_dataset``)
has a spectrum that rises from 0.5 Hz into the tremor peak with no valley: the
``shallow_valley`` minimum sits on the lowest bin of the search, and the drift
above it is called tremor.  For each rule: the HPA's flags and mean ``f_d`` on
the rest-tremor set, WAKE's tremor NRMSE against the true tremor and voluntary
NRMSE against the true drift (whole recording from 0.5 s / after 5 s), and the
condition every earlier rule change met: the whole-recording error on the
paper's synthetic set (voluntary NRMSE) and on PADS (tremor NRMSE against the
independent truth of ``wake.eval.warmup``) must not get worse.  The rules
(every WAKE run uses the C RTP and the Python HPA):

* ``floor`` - the library's default (``wake.hpa.cutoff``): a shallow minimum
  on the lowest bin of the search (a monotone rise, not a dip) is no valley:
  the default 2 Hz, flag ``no_valley`` (a fallback);
* ``floor, before`` - the default before that: the lowest bin, flag
  ``shallow_valley`` (the cases below start from it);
* ``paper`` - the paper's rule: no 3 dB valley, the default 2 Hz;
* ``edge flank D`` - ``floor, before``, but on the lowest bin the tremor
  peak's left flank instead, the highest frequency below the peak where the
  PSD is D dB below it;
* ``shallow at least F`` - ``floor, before``, every ``shallow_valley`` raised
  to F Hz or more (a lower bound on a shallow f_d);
* ``shallow below default`` - ``floor, before``, but a ``shallow_valley``
  below the default 2 Hz gives the default (``no_valley``);
* ``shallow`` and ``shallow, before`` - the library's option
  ``cutoff_rule="shallow"`` with and without the lowest-bin test;
* ``fixed F`` (``--fixed``) - every window at F Hz, whatever its spectrum.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import wake.hpa.run as hpa_run  # noqa: E402
from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.eval.synthetic import paper_dataset, rest_tremor_dataset  # noqa: E402
from wake.eval.warmup import independent_ground_truth, slice_nrmse  # noqa: E402
from wake.hpa import cutoff as cutoff_mod  # noqa: E402
from cutoff_rules import _peak  # noqa: E402

SHIPPED = cutoff_mod.find_cutoff
WHOLE, AFTER = "whole (from 0.5 s)", "after 5 s"


def lowest_bin_dip(freqs, psd, *, rule, tremor_band=(2.5, 15.0), cutoff_range=(0.5, 6.0),
                   shallow_max=cutoff_mod.SHALLOW_MAX, **_):
    """The lowest search bin, where rules ``shallow`` and ``floor`` took it as a shallow dip before they
    fell back there; None elsewhere."""
    freqs = np.asarray(freqs, dtype=float)
    db = 10 * np.log10(np.maximum(psd, np.max(psd) * 1e-30))
    peak = _peak(freqs, db, tremor_band)
    if peak is None:
        return None
    low = np.flatnonzero((freqs >= cutoff_range[0]) & (freqs <= min(cutoff_range[1], shallow_max, freqs[peak])))
    if low.size < 3 or np.argmin(db[low]) != 0:
        return None
    above = np.flatnonzero(freqs > tremor_band[1])[::-1][::cutoff_mod.FLOOR_STRIDE]
    floor = db[above].min() if rule == "floor" and above.size else -np.inf
    return low[0] if db[low[0]] >= floor + cutoff_mod.FLOOR_MARGIN_DB else None


def make_rule(kind):
    """``find_cutoff`` for one rule of the module docstring."""
    def find(freqs, psd, **kw):
        kw.pop("rule", None)
        if kind.startswith("fixed "):
            return float(kind.split()[1]), "fixed"
        base = kind.split(",")[0] if kind.split(",")[0] in ("paper", "shallow", "floor") else "floor"
        fd, flag = SHIPPED(freqs, psd, **kw, rule=base)
        if kind in ("paper", "shallow", "floor"):
            return fd, flag
        edge = lowest_bin_dip(freqs, psd, rule=base, **kw) if flag == "no_valley" else None
        if edge is not None:  # the rule before the change: the lowest bin, flag shallow_valley
            fd, flag = float(freqs[edge]), "shallow_valley"
        if kind.endswith(", before") or flag != "shallow_valley":
            return fd, flag
        if kind.startswith("shallow at least "):
            return max(fd, float(kind.split()[3])), flag
        if kind == "shallow below default":
            default = float(kw.get("default_cutoff", 2.0))
            return (default, "no_valley") if fd < default else (fd, flag)
        if kind.startswith("edge flank ") and edge is not None:
            db = 10 * np.log10(np.maximum(psd, np.max(psd) * 1e-30))
            peak = _peak(np.asarray(freqs, dtype=float), db, kw.get("tremor_band", (2.5, 15.0)))
            below = np.flatnonzero((np.arange(db.size) >= edge) & (np.arange(db.size) < peak)
                                   & (db <= db[peak] - float(kind.split()[2])))
            return (float(freqs[below[-1]]), "shallow_valley") if below.size else (fd, flag)
        if kind.startswith("edge flank "):
            return fd, flag
        raise ValueError(kind)
    return find


RULES = ("paper", "floor, before", "floor", "edge flank 3", "edge flank 6", "edge flank 10",
         "shallow at least 1", "shallow at least 1.5", "shallow at least 2", "shallow below default",
         "shallow, before", "shallow")
FIXED = ("fixed 0.6", "fixed 1", "fixed 1.5", "fixed 2", "fixed 2.5", "fixed 3", "fixed 3.5")


def evaluate(kind, rest, pads, synthetic):
    """Flags, f_d and scores of one rule: rest flags, f_d, tremor and voluntary scores; PADS, synthetic; PADS flags."""
    hpa_run.find_cutoff = make_rule(kind)
    try:
        flags, cutoffs, tremor, voluntary = [], [], [], []
        for s in rest:
            res = WakeFilter(fs=s.fs).run(s.measurement)
            flags += [u.cutoff_flag for u in res.hpa[0]]
            cutoffs += [u.cutoff for u in res.hpa[0]]
            tremor.append(slice_nrmse(s.tremor, res.tremor, s.fs))
            voluntary.append(slice_nrmse(s.voluntary, res.voluntary, s.fs))
        pads_scores, syn_scores, pads_flags = [], [], []
        for rec in pads:
            res = WakeFilter(fs=rec.fs).run(rec.samples)
            pads_flags += [u.cutoff_flag for ch in res.hpa for u in ch]
            for c in range(rec.samples.shape[1]):
                _, truth, _ = independent_ground_truth(rec.samples[:, c], rec.fs)
                pads_scores.append(slice_nrmse(truth, res.tremor[:, c], rec.fs))
        for s in synthetic:
            res = WakeFilter(fs=s.fs).run(s.measurement)
            syn_scores.append(slice_nrmse(s.voluntary, res.voluntary, s.fs))
        return flags, cutoffs, tremor, voluntary, pads_scores, syn_scores, pads_flags
    finally:
        hpa_run.find_cutoff = SHIPPED


def _mean(rows, key):
    return np.nanmean([r[key] for r in rows]) if rows else float("nan")


def c_hpa_agreement(rest):
    """The shipped rule in both HPAs on every rest-tremor window, and the pipeline NRMSE each gives."""
    from hpa_c_agreement import _summarise, run_pair, window_agreement

    windows, scores = [], {"python": [], "c": []}
    for s in rest:
        x = s.measurement[:, None]
        py, cc = run_pair(x, s.fs)
        filt = WakeFilter(fs=s.fs, backend="c")
        windows += window_agreement(x, py, filt.config, filt.taps)
        for name, res in (("python", py), ("c", cc)):
            scores[name].append(slice_nrmse(s.tremor, res.tremor[:, 0], s.fs))
    print("rest tremor, C HPA vs Python HPA (both on the fixed-point RTP):", _summarise(windows))
    for key in (WHOLE, AFTER):
        py, cc = _mean(scores["python"], key), _mean(scores["c"], key)
        print(f"  tremor NRMSE {key}: python {py:.5f}  c {cc:.5f}  ({100 * (cc / py - 1):+.2f} %)")


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fixed", action="store_true", help="also every window at a fixed f_d")
    ap.add_argument("--per-signal", action="store_true", help="the rest-tremor scores of each signal")
    ap.add_argument("--c-hpa", action="store_true", help="only the C HPA against the Python HPA on the rest set")
    args = ap.parse_args(argv)
    if args.c_hpa:
        return c_hpa_agreement(rest_tremor_dataset())
    folder = default_pads_dir(cwd=Path(__file__).resolve().parents[1])
    pads = load_pads_folder(folder) if folder is not None and folder.is_dir() else []
    rest, synthetic = rest_tremor_dataset(), paper_dataset()
    print(f"rest tremor: {len(rest)} signals; paper's synthetic: {len(synthetic)}; PADS: {len(pads)} recordings\n")
    print("| rule | rest: flags | rest: mean f_d | rest: tremor NRMSE whole / after 5 s "
          "| rest: drift (voluntary) NRMSE whole / after 5 s | synthetic whole / after 5 s "
          "| PADS whole / after 5 s | PADS windows on the default |")
    print("|---|---|---:|---|---|---|---|---:|")
    for kind in RULES + (FIXED if args.fixed else ()):
        flags, cutoffs, tr, vo, ps, ss, pf = evaluate(kind, rest, [] if kind in FIXED else pads,
                                                  [] if kind in FIXED else synthetic)
        share = ", ".join(f"{f} {100 * flags.count(f) / len(flags):.0f} %" for f in sorted(set(flags)))
        print(f"| {kind} | {share} | {np.mean(cutoffs):.2f} Hz "
              f"| {_mean(tr, WHOLE):.5f} / {_mean(tr, AFTER):.5f} | {_mean(vo, WHOLE):.5f} / {_mean(vo, AFTER):.5f} "
              f"| {_mean(ss, WHOLE):.5f} / {_mean(ss, AFTER):.5f} | {_mean(ps, WHOLE):.5f} / {_mean(ps, AFTER):.5f} "
              f"| {100 * np.mean([f in cutoff_mod.FALLBACK_FLAGS for f in pf]) if pf else np.nan:.0f} % |")
        if args.per_signal:
            print("|  | " + " ".join(f"{r[WHOLE]:.4f}" for r in tr) + " |")


if __name__ == "__main__":
    main()
