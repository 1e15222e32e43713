"""The host speed gate: WAKE's batch, per-sample and cohort paths as ratios to a fixed unit, measured in one process.

    python bench/speed_gate.py                 # CI: the table; exit status 1 when a ratio exceeds its ceiling
    python bench/speed_gate.py --markdown      # the same table in Markdown, with the machine and its load
    python bench/speed_gate.py --update-docs   # that Markdown written into README.md and docs/studies/profiling.md
    python bench/speed_gate.py --repeats 9     # more repeats (default 7; the cohort task: half as many, at least 3)

A ratio, not a time, is what carries from machine to machine and from a quiet run to a loaded one: every figure is
the median over repeats of (the path's CPU time) / (its unit's CPU time), the two timed one right after the other
in this process (CPU time, not wall time: on a loaded machine a long call is preempted far more often than a short
one). The units:

* ``lfilter x5``: five ``scipy.signal.lfilter`` calls of a 32-tap FIR over the same 50 s at 100 Hz (5,000 samples);
* ``step``: one ``FixedPointRTP.step`` call from Python (the C core's step through cffi, nothing else).

The measures (:data:`CEILINGS`, the one table of ceilings):

* ``run``: ``WakeFilter(backend="c").run`` on a 50 s, 100 Hz recording, HPA included, over ``lfilter x5``;
* ``run, hpa_backend="c"``: the same with the HPA in C;
* ``update``: ``WakeFilter(backend="c").update`` per sample (the HPA every window included) over one ``step``;
* ``cohort task``: one task of ``wake evaluate --synthetic 1 --synthetic-only --jobs 1`` (a 50 s cohort signal:
  WAKE on both backends, BMFLC, E-BMFLC, WFLC; :func:`wake.eval.compute.compute_task`) over ``lfilter x5``.

The ceilings are regression guards set from what issue 44's changes reached, plus a margin of about a third over
the highest of three runs at a load average of 7.5 on 2 cores (run 22.5-24.3, with the C HPA 12.2-13.1, update
10.3-11.4, between HPA windows 3.2-3.3, cohort task 402-429; the Python HPA's windows analysed in batches, the C
HPA's glue cut, the float reference's tremor ahead one matmul per block). The C HPA's ceiling was then set again
from what its batch driver reached (wake/native/wake_batch.c: the HPA windows of a block in one C call), 6.6-7.5
at a load average of 1.5, plus a third: 10 (the code before the driver measured 10.3-13.1, so the ceiling fails
on it). Issue 44's fourth pass (the Python HPA's stretches and installs in one C call, wake_batch_install; the
cut-off search, robust peaks and outlier tests of a block's windows at once; the float warm-up's filter bank in
two numpy calls) measured, in three runs at a load average of 4.4 on 2 cores, run 17.4-18.5, with the C HPA
7.0-7.8, update 7.8-8.4, between HPA windows 3.1-3.2 and the cohort task 424-431: the ceilings of run and update
follow (24 and 11), the others stay. Issue 44's fifth pass (a block's windows of every length analysed in one
call, their cut-off search, Levinson recursions and solves at once; the windows' preparation and the schedule
without a call per window; the decimating front end without a step per input sample) measured, in three runs at
a load average of 7.3-7.5, run 12.9-15.1 and with the C HPA 5.7-6.8 (and 12.1-12.2, 5.3-5.6 in two at 6.2): the
ceilings of run and of the C HPA follow (20 and 9), the others stay. With a per-sample Python loop put back into the block path
(``AdaptiveRTP.run_outputs`` stepping ``step()`` sample by sample, the batch paths off) the gate measured run
62.5, with the C HPA 56.8 and the cohort task 797, and failed. Before those changes the same script
measured run 81.5, with the C HPA 57.0, update 11.1 and a cohort task 1,478 (the per-sample Python loop of the C
backend's block path), and at the previous ceilings run 33-39, with the C HPA 14-16: the run ceilings fail on
either. The unit here (a 32-tap ``firwin`` FIR over this recording) measures 0.28-0.33 ms where
bench/run_ratio.py's (a Hann FIR over its own recording, the figures issue 44's targets were set with) measures
0.36-0.42 ms, so the same run is a larger ratio here; docs/studies/profiling.md, "Host speed", gives both and says
where the time goes.

Exit status: 0 every ratio within its ceiling, 1 one above it, 2 a usage error, 3 the C core not built.
"""

import argparse
import os
import platform
import re
import statistics
import sys
import time
from pathlib import Path

# one thread: a BLAS pool's threads would add their CPU time (and spin) to a single-threaded path's
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

FS = 100.0
DURATION_S = 50.0
FIR_TAPS = 32
#: measure -> (unit, ceiling of the ratio, what it times); the one place the ceilings live
CEILINGS = {
    "run": ("lfilter x5", 20.0, 'WakeFilter(backend="c").run, 50 s at 100 Hz, HPA included'),
    'run, hpa_backend="c"': ("lfilter x5", 9.0, 'the same with hpa_backend="c"'),
    "update": ("step", 11.0, "WakeFilter(backend=\"c\").update per sample, HPA included"),
    "update, between HPA windows": ("step", 4.5, "the same, the median 100-sample chunk (no HPA in it)"),
    "cohort task": ("lfilter x5", 570.0, "one task of wake evaluate --synthetic 1 --synthetic-only --jobs 1"),
}


#: samples per timed chunk of "update, between HPA windows"
CHUNK = 100
#: the measures that time themselves (they return their CPU time)
SELF_TIMED = {"update, between HPA windows"}


def recording():
    """The 50 s, 100 Hz synthetic recording of the benchmarks (signal of SNR 10 dB, seed 3)."""
    from wake.eval.synthetic import make_signal

    return make_signal(10.0, seed=3, duration=DURATION_S)


def lfilter_unit(x):
    """The unit ``lfilter x5``: a function running five 32-tap FIR ``lfilter`` calls over ``x``."""
    from scipy.signal import firwin, lfilter

    b = firwin(FIR_TAPS, 0.1)
    a = np.array([1.0])

    def unit():
        for _ in range(5):
            lfilter(b, a, x)
    return unit


def step_unit(x):
    """The unit ``step``: a function running ``FixedPointRTP.step`` once per sample of ``x`` (weights fitted)."""
    from wake import WakeFilter
    from wake.rtp.fixed import FixedPointRTP

    filt = WakeFilter(fs=FS, backend="reference")
    upd = filt.run(x).hpa[0][-1]
    full_scale = filt.headroom * float(np.max(np.abs(x[: filt.window_samples])))
    rtp = FixedPointRTP(filt.taps, upd.weights, upd.measurement_noise, 0.0, 0.0, full_scale=full_scale)
    samples = [float(v) for v in x]

    def unit():
        step = rtp.step
        for v in samples:
            step(v)
    return unit


def measures(x):
    """measure -> (a function running it once, a function making a fresh state before each run, samples per run)."""
    from wake import WakeFilter
    from wake.eval.compute import Task, compute_task
    from wake.eval.evaluate import parse_grid
    from wake.eval.sources import cohort_sources

    state = {}
    samples = [float(v) for v in x]

    def fresh_filter(**kw):
        def make():
            state["filt"] = WakeFilter(fs=FS, backend="c", **kw)
        return make

    def run():
        state["filt"].run(x)

    def update():
        u = state["filt"].update
        for v in samples:
            u(v)

    def update_between_windows():
        """The CPU time of the samples at the median chunk's rate: a chunk of 100 samples that holds an HPA (one in
        five at 100 Hz) is an outlier the median leaves out, so this is the per-sample path itself."""
        u = state["filt"].update
        chunks = []
        for start in range(0, len(samples), CHUNK):
            t = time.process_time()
            for v in samples[start:start + CHUNK]:
                u(v)
            chunks.append(time.process_time() - t)
        return statistics.median(chunks) * len(samples) / CHUNK

    task = Task(cohort_sources(1, duration_s=DURATION_S)[0], tuple(parse_grid(None)[0].items()), ("reference", "c"))

    def cohort():
        rows = compute_task(task)
        if any(r.get("error") for r in rows):
            raise RuntimeError(f"the cohort task failed: {[r['error'] for r in rows if r.get('error')]}")

    return {"run": (run, fresh_filter(), 1),
            'run, hpa_backend="c"': (run, fresh_filter(hpa_backend="c"), 1),
            "update": (update, fresh_filter(), len(samples)),
            "update, between HPA windows": (update_between_windows, fresh_filter(), len(samples)),
            "cohort task": (cohort, lambda: None, 1)}


def timed(fn):
    """The CPU time of the process while ``fn`` runs: unlike wall time, it does not grow with the machine's load
    (a long call is preempted by other processes far more often than a short one, which skews a wall-time ratio)."""
    t = time.process_time()
    fn()
    return time.process_time() - t


def measure(repeats: int) -> dict:
    """measure -> {ratio, path and unit medians (s), repeats}: the median of per-repeat ratios, each repeat timing
    the path once and its unit right before it (the unit as the median of 5 calls: it is short)."""
    x = recording().measurement
    units = {"lfilter x5": (lfilter_unit(x), 1), "step": (step_unit(x), len(x))}
    out = {}
    for name, (fn, setup, items) in measures(x).items():
        unit_name = CEILINGS[name][0]
        unit_fn, unit_items = units[unit_name]
        n = max(3, repeats // 2) if name == "cohort task" else repeats
        setup()
        fn()                                    # warm-up: imports, caches, the first HPA's one-off costs
        ratios, paths, unit_times = [], [], []
        for _ in range(n):
            u = statistics.median(timed(unit_fn) for _ in range(5)) / unit_items
            setup()
            p = (fn() if name in SELF_TIMED else timed(fn)) / items
            ratios.append(p / u)
            paths.append(p)
            unit_times.append(u)
        out[name] = {"ratio": statistics.median(ratios), "path_s": statistics.median(paths),
                     "unit_s": statistics.median(unit_times), "repeats": n}
    return out


ROOT = Path(__file__).resolve().parents[1]
#: the documents that carry the table: each has it once, from its header line to the note under it
DOCS = [ROOT / "README.md", ROOT / "docs" / "studies" / "profiling.md"]
#: the table (its lines from the header), what separates it from its note (blank lines, a tag), the note
TABLE_BLOCK = re.compile(r"^(?P<table>\| measure \| what \| unit \|.*\n(?:\|.*\n)*)(?P<sep>(?:\n|<!--.*-->\n)+)"
                         r"(?P<note>\S.*medians of \d+ repeats)$", re.M)


def update_doc(path: Path, table_md: str, note: str) -> None:
    """Replace the table and its note in ``path`` (exactly one of each) with ``table_md`` and ``note``; what lies
    between them (a blank line, a claim tag) is kept."""
    text = path.read_text(encoding="utf-8")
    found = TABLE_BLOCK.findall(text)
    if len(found) != 1:
        raise SystemExit(f"speed_gate: {path} has {len(found)} speed tables (a line '| measure | what | unit |' "
                         "then, after a blank line, 'medians of N repeats'), not one: put one there first")
    path.write_text(TABLE_BLOCK.sub(lambda m: f"{table_md}\n{m['sep']}{note}", text), encoding="utf-8")


def load_average() -> str:
    try:
        return ", ".join(f"{v:.1f}" for v in os.getloadavg())
    except OSError:
        return "unknown"


def _t(seconds):
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds / 1e-9:.3g} ns"


def table(results: dict, markdown: bool) -> str:
    rows = []
    for name, r in results.items():
        unit, ceiling, what = CEILINGS[name]
        per = " per sample" if name == "update" else ""
        verdict = "within" if r["ratio"] <= ceiling else "ABOVE"
        rows.append((name, what, unit, f"{r['ratio']:,.1f}", f"{ceiling:,g}", verdict,
                     f"{_t(r['path_s'])}{per} / {_t(r['unit_s'])}"))
    head = ("measure", "what", "unit", "ratio (median)", "ceiling", "verdict", "times (this run)")
    if markdown:
        lines = ["| " + " | ".join(head) + " |", "|---|---|---|---:|---:|---|---|"]
        lines += ["| " + " | ".join(f"`{c}`" if i == 0 else c for i, c in enumerate(row)) + " |" for row in rows]
    else:
        lines = [f"{name:<22} {ratio:>9} (ceiling {ceiling:>5}) {verdict:<6} {unit:<11} {times}"
                 for name, _, unit, ratio, ceiling, verdict, times in rows]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7, help="repeats per measure (default 7; the cohort task "
                        "half as many, at least 3)")
    parser.add_argument("--markdown", action="store_true", help="print the table in Markdown with the machine and "
                        "its load")
    parser.add_argument("--update-docs", action="store_true", help="also write that Markdown over the table in "
                        "README.md (host-speed-record) and docs/studies/profiling.md (Host speed)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats needs at least 1, got {args.repeats}")
    from wake.rtp import c_backend_available

    if not c_backend_available():
        print("speed_gate: the C core wake._rtp is not built (python build_ffi.py, or pip install .)", file=sys.stderr)
        return 3
    before = load_average()
    results = measure(args.repeats)
    note = (f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; load average "
            f"{before} before, {load_average()} after; medians of {args.repeats} repeats")
    table_md = table(results, True)
    print(f"{table_md}\n\n{note}" if args.markdown or args.update_docs else f"{table(results, False)}\n{note}")
    if args.update_docs:
        for doc in DOCS:
            update_doc(doc, table_md, note)
            print(f"speed_gate: wrote the table into {doc.relative_to(ROOT)}")
    above = [name for name, r in results.items() if r["ratio"] > CEILINGS[name][1]]
    if above:
        print(f"speed_gate: FAILED: {', '.join(above)} above the ceiling (CEILINGS in bench/speed_gate.py)",
              file=sys.stderr)
        return 1
    print("speed_gate: OK (every ratio within its ceiling)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
