"""``wake evaluate``: the paper's evaluation recomputed with our implementations, at any scale.

What :func:`cli` writes into ``OUT_DIR`` (docs/studies/evaluation.md explains the
protocol and the options):

* ``report.md``: Markdown tables.
  - Synthetic set (the paper's Table "results2"): PRF, SNR_out and NRMSE of
    the voluntary estimate for BMFLC, E-BMFLC, WFLC and WAKE (every
    available backend), beside the paper's numbers; the first
    ``window_s * fs`` samples (WAKE's warm-up) are left out for every method.
    With ``--synthetic N``: a generated cohort of N signals instead.
  - Real recordings (PADS, or any files :mod:`wake.io` reads): NRMSE of the
    predicted tremor per recording and axis against the offline ground truth
    (sharp high-pass at the mean ``f_d`` of WAKE's HPA runs on that axis;
    the same truth for every method), and the mean per method.
  - The delay (samples) maximising the cross-correlation between estimated
    and true tremor, per method.
  - Ablation: the paper's literal RTP (:mod:`wake.rtp.literal`) against
    WAKE's per-sample RTP: NRMSE, time and operations per sample.
  - Time since start: NRMSE per slice of time since switch-on and over the
    whole recording from 0.5 s (:mod:`wake.eval.warmup`), for WAKE, every
    baseline and the zero estimate; PADS against a truth independent of WAKE.
  - The cut-off's flags: their shares over the HPA windows, and (figure) the
    AR spectrum of sample windows of each flag with the chosen ``f_d``.
  - With ``--grid``: every configuration ranked by whole-recording and
    after-warm-up NRMSE with the spread across recordings.
  - Recordings that failed, one line each.
* ``store/``: the result store (:mod:`wake.eval.store`), one row per
  recording, channel, method and configuration; a rerun computes only what
  it lacks and rebuilds the report from it.
* ``results.json``: every number of the report.
* ``fig_*.png`` when matplotlib is installed.

The work is split by concern: :mod:`wake.eval.sources` (loading),
:mod:`wake.eval.compute` (computing), :mod:`wake.eval.runner` (running, in
parallel or not), :mod:`wake.eval.store` (storing), :mod:`wake.eval.tables`,
:mod:`wake.eval.report` and :mod:`wake.eval.figures` (reporting).
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
import time
from dataclasses import fields
from pathlib import Path

from wake.config import WakeConfig
from wake.eval.compute import (ROW_COLUMNS, WAKE_PARAMS, Task, ablation_literal_rtp, baseline_methods,
                               compute_task, config_label, wake_name)
from wake.eval.datasets import default_pads_dir
from wake.eval.figures import tremor_candidate, write_figures
from wake.eval.report import jsonable, markdown_report, recordings_label
from wake.eval.runner import TaskList, run_tasks
from wake.eval.pdkit import default_pdkit_dir
from wake.eval.sources import (cohort_sources, file_sources, pads_sources, paper_sources, pdkit_sources,
                               strong_sources)
from wake.eval.store import ResultStore
from wake.eval.suppression import suppression_figure
from wake.eval.synthetic import PAPER_SNR_DB
from wake.eval.tables import ahead_summary, compact_row, grid_ranking, real_summary, synthetic_summary
from wake.rtp import c_backend_available

__all__ = ["cli", "c_backend_available", "baseline_methods", "ablation_literal_rtp", "evaluate_synthetic", "evaluate_real",
           "parse_grid", "WAKE_PARAMS"]


def evaluate_synthetic(backends, quick=False):
    """The paper's synthetic set scored in this process, as the report's synthetic summary.

    Examples
    --------
    >>> from wake.eval.evaluate import evaluate_synthetic
    >>> syn = evaluate_synthetic(["reference"], quick=True)
    >>> [r["signal"] for r in syn["rows"]], sorted(syn["rows"][0]["methods"])
    ([1, 2], ['BMFLC', 'E-BMFLC', 'WAKE-ref', 'WFLC', 'eHWFLC-KF'])
    """
    tasks = [Task(s, tuple(WAKE_PARAMS.items()), tuple(backends)) for s in paper_sources(2 if quick else None)]
    return synthetic_summary([row for task in tasks for row in compute_task(task)])


def evaluate_real(folder, backends):
    """The PADS recordings in ``folder`` scored in this process, as the report's recordings summary.

    ``rows``: one per recording axis, tremor NRMSE per method against the paper's offline ground truth
    (samples before the first full HPA window left out), as the report's per-axis table.
    """
    tasks = [Task(s, tuple(WAKE_PARAMS.items()), tuple(backends)) for s in pads_sources(folder)]
    return real_summary([row for task in tasks for row in compute_task(task)])


def parse_grid(items):
    """``["level=4,5", "wavelet=sym3,db4"]`` -> every combination, as WakeFilter settings over the paper's.

    Values take the type of the setting's default (``window_s=3`` is 3.0).

    Examples
    --------
    >>> from wake.eval.evaluate import parse_grid
    >>> [c["level"] for c in parse_grid(["level=4,6"])], parse_grid(["window_s=3"])[0]["window_s"]
    ([4, 6], 3.0)
    >>> parse_grid(["levels=4"])
    Traceback (most recent call last):
    ...
    ValueError: --grid: unknown WakeFilter setting 'levels'; valid settings: ar_order, ...
    """
    defaults = {f.name: f.default for f in fields(WakeConfig)}
    axes = {}
    for item in items or ():
        name, sep, values = item.partition("=")
        if not sep or not values:
            raise ValueError(f"--grid: {item!r} is not NAME=VALUE[,VALUE...] (e.g. level=4,5,6)")
        if name in ("fs", "backend"):
            raise ValueError(f"--grid: {name} is set by the recording or by --backend, not by --grid")
        if name not in defaults:
            valid = ", ".join(sorted(set(defaults) - {"fs", "backend"}))
            raise ValueError(f"--grid: unknown WakeFilter setting {name!r}; valid settings: {valid}")
        axes[name] = [_typed(name, v.strip(), defaults[name]) for v in values.split(",")]
    configs = []
    for combo in itertools.product(*axes.values()):
        settings = {**WAKE_PARAMS, **dict(zip(axes, combo))}
        try:
            WakeConfig(**settings)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"--grid: {config_label(settings)}: {exc}") from None
        configs.append(settings)
    return configs or [dict(WAKE_PARAMS)]


def _typed(name, text, default):
    kind = type(default) if isinstance(default, (bool, int, float)) else str
    try:
        if kind is bool:
            return {"true": True, "false": False}[text.lower()]
        return kind(float(text)) if kind is int and float(text).is_integer() else kind(text)
    except (KeyError, ValueError):
        what = {bool: "true or false", int: "an integer", float: "a number"}.get(kind, "a name")
        raise ValueError(f"--grid: {name}={text} is not {what}") from None


def _parser():
    p = argparse.ArgumentParser(
        prog="wake evaluate",
        description="Recompute the paper's evaluation (synthetic table, real recordings, delay, literal-RTP "
                    "ablation) with WAKE and the BMFLC/E-BMFLC/WFLC/eHWFLC-KF baselines, over any number of recordings, "
                    "in parallel; write report.md, a result store and figures.")
    p.add_argument("out_dir", metavar="OUT_DIR", help="folder for report.md, results.json, store/ and the figures")
    p.add_argument("inputs", metavar="INPUT", nargs="*",
                   help="recordings: files (any format wake.io reads), folders or glob patterns (quoted)")
    p.add_argument("--fs", metavar="HZ", type=float, default=None,
                   help="sampling rate of INPUT files without a time column")
    p.add_argument("--pads", metavar="DIR", default=None,
                   help="PADS recordings folder (default when no INPUT: $WAKE_PADS_DIR, else ../shared/data/pads "
                        "relative to the current directory if present, else synthetic only)")
    p.add_argument("--pdkit", metavar="DIR", default=None,
                   help="pdkit's smartphone tremor-task recordings (default when no INPUT: $WAKE_PDKIT_DIR, else "
                        "../shared/data/pdkit relative to the current directory if present)")
    p.add_argument("--strong", metavar="N", type=int, default=0,
                   help="also N signals of the synthetic strong-tremor set (wake.eval.strong_tremor; default 0)")
    p.add_argument("--synthetic-only", action="store_true", help="skip the real recordings")
    p.add_argument("--synthetic", metavar="N", type=int, default=None,
                   help="a generated cohort of N synthetic signals instead of the paper's ten (seed and SNR "
                        "drawn per signal; 0: recordings only); no PADS folder unless given")
    p.add_argument("--duration", metavar="S", type=float, default=50.0, help="length of --synthetic signals (s)")
    p.add_argument("--backend", choices=("c", "reference", "both"), default="both",
                   help="WAKE RTP backend(s) (default: both; 'both' runs the C one only when it is built)")
    p.add_argument("--grid", metavar="NAME=V1,V2", nargs="+", default=None,
                   help="WAKE configurations: every combination, e.g. level=4,5,6 wavelet=sym3,db4 window_s=3,5")
    p.add_argument("--jobs", metavar="N", type=int, default=None,
                   help="worker processes (joblib, loky; -1: every core; default: this process)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="run on a Dask cluster at ADDRESS, or 'local' for a LocalCluster of --jobs workers")
    p.add_argument("--store-format", choices=("auto", "parquet", "csv"), default="auto",
                   help="result store format (default: Parquet when pyarrow is installed, else CSV)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--quick", action="store_true",
                   help="2 synthetic signals, 2 recordings, short timing: a smoke run, not the paper's numbers")
    return p


def _backends(choice, notes):
    have_c = c_backend_available()
    if choice == "c" and not have_c:
        raise ValueError("the C backend is not built (import wake._rtp failed); use --backend reference")
    if choice == "both" and not have_c:
        notes.append("The C backend is not built (`import wake._rtp` failed): WAKE ran on the float "
                     "reference only (column WAKE-ref).")
    return {"c": ["c"], "reference": ["reference"]}.get(choice) or (["reference", "c"] if have_c else ["reference"])


def _sources(args, notes):
    """(synthetic sources, recording sources, PADS folder or None) of the command line."""
    synthetic = (cohort_sources(args.synthetic, duration_s=args.duration) if args.synthetic is not None
                 else paper_sources(2 if args.quick else None))
    recordings, pads_dir = [], None
    if args.inputs:
        recordings += file_sources(args.inputs, fs=args.fs)
        if args.fs is None:
            _refuse_unknown_rates(recordings)
    if not args.synthetic_only and (args.pads or not (args.inputs or args.synthetic is not None)):
        pads_dir = default_pads_dir(args.pads)
        if pads_dir is not None:
            recordings += pads_sources(pads_dir)
        else:
            notes.append("No PADS folder (--pads, $WAKE_PADS_DIR or ../shared/data/pads): synthetic set only.")
    if not args.synthetic_only and (args.pdkit or not (args.inputs or args.synthetic is not None)):
        pdkit_dir = default_pdkit_dir(args.pdkit)
        if pdkit_dir is not None:
            recordings += pdkit_sources(pdkit_dir)
    synthetic = synthetic + strong_sources(args.strong)
    if args.synthetic_only:
        recordings = []
    if args.quick:
        recordings = recordings[:2]
    return synthetic, recordings, pads_dir


def _refuse_unknown_rates(sources):
    """ValueError naming the files that have no time column (their rate unknown), saying that ``--fs`` serves.

    Checked before the work, not found by each task: a file that reads into a signal (two samples or more)
    once a rate is given lacks only the rate.  A file that does not read either way, or holds a single
    sample, is left to its task (the report lists it as a failure).  Each INPUT is read once more for this,
    and only when ``--fs`` is not given.
    """
    from wake.io import read_recording

    unknown = []
    for source in sources:
        try:
            read_recording(source.path)
        except ValueError:
            try:
                if read_recording(source.path, fs=100.0).samples.shape[0] < 2:
                    continue
            except ValueError:
                continue
            unknown.append(Path(source.path).name)
    if unknown:
        names = ", ".join(unknown[:3]) + (f" and {len(unknown) - 3} more" if len(unknown) > 3 else "")
        raise ValueError(f"{names} {'has' if len(unknown) == 1 else 'have'} no time column, so the sampling rate "
                         "is unknown: give it with --fs HZ (the rate of every INPUT without a time column)")


def _summaries(rows, first):
    sel = [r for r in rows if r["config"] == first and not r["error"]]
    return {"synthetic": synthetic_summary([r for r in sel if r["set"] == "paper"]),
            "cohort": synthetic_summary([r for r in sel if r["set"] == "cohort"]),
            "real": real_summary([r for r in sel if r["set"] == "real"])}


def _rankings(rows, labels, backends):
    method = wake_name("c" if "c" in backends else "reference")
    titles = {"paper": "Synthetic set (voluntary NRMSE)", "cohort": "Synthetic cohort (voluntary NRMSE)",
              "real": "Recordings (tremor NRMSE, independent truth)"}
    out = []
    for key, title in titles.items():
        ranking = grid_ranking([r for r in rows if r["set"] == key and not r["error"]], labels, method)
        if ranking:
            out.append((title, method, ranking))
    return out


def _ablation(store_dir, quick):
    """The literal-RTP ablation, computed once per store (it does not depend on the recordings)."""
    path = Path(store_dir) / ("ablation-quick.json" if quick else "ablation.json")
    if path.is_file():
        return json.loads(path.read_text())
    result = jsonable(ablation_literal_rtp(quick))
    path.write_text(json.dumps(result))
    return result


def cli(argv: list[str] | None = None) -> int:
    """Entry point of ``wake evaluate``; returns the exit status (1 when a recording failed)."""
    args = _parser().parse_args(None if argv is None else [str(a) for a in argv])
    out_dir, notes = Path(args.out_dir), []
    try:
        backends = _backends(args.backend, notes)
        configs = parse_grid(args.grid)
        synthetic, recordings, pads_dir = _sources(args, notes)
        store = ResultStore(out_dir / "store", ROW_COLUMNS, format=args.store_format)
    except ValueError as exc:
        print(f"wake evaluate: {exc}", file=sys.stderr)
        return 2
    for n in notes:
        print(f"wake evaluate: {n}")
    tasks = TaskList(synthetic + recordings, configs, backends)    # made as iterated, not held
    t0 = time.perf_counter()
    try:
        computed, _ = run_tasks(tasks, store, jobs=args.jobs, scheduler=args.scheduler,
                                progress=not args.no_progress)
    except ValueError as exc:
        print(f"wake evaluate: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"wake evaluate: interrupted; finished tasks are kept in {out_dir / 'store'}: rerun the same command "
              "to compute the rest", file=sys.stderr)
        return 130
    store.compact()
    print(f"wake evaluate: {computed} of {len(tasks)} tasks computed, {len(tasks) - computed} from the store")
    return _write_outputs(args, argv, out_dir, store, tasks, configs, backends, notes, pads_dir, t0,
                          recordings_label(recordings))


def _write_outputs(args, argv, out_dir, store, tasks, configs, backends, notes, pads_dir, t0, real_name):
    rows = store.rows([t.key for t in tasks], convert=compact_row)
    labels = [config_label(c) for c in configs]
    parts = _summaries(rows, labels[0])
    ahead = ahead_summary([r for r in rows if r["config"] == labels[0] and not r["error"]])
    failures = [r for r in rows if r["error"]]
    abl = _ablation(store.folder, args.quick) if parts["synthetic"] else None
    real_rows = [r for r in rows if r["set"] == "real" and r["config"] == labels[0] and r["hpa"]]
    pick = tremor_candidate(real_rows)
    sources = {t.source.key: t.source for t in tasks}
    figs, fig_note = write_figures(out_dir, parts, pick and (pick, sources[pick["source"]], configs[0], backends),
                                   sources, real_name)
    if suppression_figure(ahead, out_dir / "fig_suppression.png"):
        figs = [*figs, "fig_suppression.png"]
    if fig_note:
        notes.append(fig_note)
        print(f"wake evaluate: {fig_note}")
    rankings = _rankings(rows, labels, backends) if len(configs) > 1 else []
    command = " ".join(str(a) for a in (argv if argv is not None else sys.argv[1:]))
    text = markdown_report(command=command, quick=args.quick, settings=configs[0], backends=backends, notes=notes,
                           parts=parts, ablation=abl, pads_dir=pads_dir, figures=figs, rankings=rankings,
                           failures=failures, run_time=time.perf_counter() - t0, ahead=ahead, real_name=real_name)
    (out_dir / "report.md").write_text(text)
    (out_dir / "results.json").write_text(json.dumps(jsonable(
        {"backends": backends, "synthetic": parts["synthetic"], "cohort": parts["cohort"], "real": parts["real"],
         "ablation": abl, "ahead": ahead, "notes": notes, "wake_params": configs[0], "paper_snr_db": PAPER_SNR_DB,
         "grid": [{**e, "method": m, "set": t} for t, m, ranking in rankings for e in ranking],
         "failures": [{"recording": r["recording"], "error": r["error"]} for r in failures]}), indent=1))
    for line in text.split("## Headline\n\n", 1)[-1].split("\n\n")[:2] if any(parts.values()) else ():
        print(line)
    print(f"wake evaluate: wrote {out_dir / 'report.md'}")
    return 1 if failures else 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli())
