"""Frama-C Eva over every public function of the C core and the C HPA (make -C csrc prove).

    python tests/prove/eva_check.py              (from csrc/)
    python tests/prove/eva_check.py --timeout 120 --only rtp --jobs 2
    python tests/prove/eva_check.py --only hpa_steps   (the steps of one HPA run)
    python tests/prove/eva_check.py --hpa-report     (also analyse wake_hpa_run, never failing on it)
    python tests/prove/eva_check.py --entry wake_rtp_prepare --entry wake_rtp_finish   (some entries only)
    python tests/prove/eva_check.py --only rtp --entry wake_rtp_step --config "m0split K1"   (some configurations only)
    python tests/prove/eva_check.py --only hpa_ahead   (the HPA entries in the tremor-ahead build)
    python tests/prove/eva_check.py --only rtp_voluntary   (set_weights and load_state with WAKE_RTP_VOLUNTARY_AHEAD 1)

Runs ``frama-c -eva`` once per analysis entry (tests/prove/eva_rtp.c, tests/prove/eva_hpa.c: one ``eva_<function>``
per public function, inputs ranged as the API allows; tests/prove/eva_hpa_steps.c: one ``eva_step_<step>`` per step
of an HPA run, from its precondition, asserting its postcondition, the loop steps' chunks from any index, and
the dispatch ``eva_dispatch_slice``, ``eva_dispatch_run`` with run_step's contract; the HPA entries again in the
tremor-ahead build, WAKE_HPA_AHEAD 1) and per configuration (the 64-bit multiply and
the Cortex-M0+ split arithmetic, WAKE_RTP_KALMAN 1 and 0; the -O2 and -Os source paths), each bounded
by ``--timeout`` seconds and run ``--jobs`` at a time, on the ILP32 data model of a Cortex-M (machdep gcc_x86_32). It prints a
Markdown table of the alarms per entry and configuration, then compares the distinct alarms
(file and assertion) with the justified ones listed in docs/studies/verification.md ("Eva alarms"), the one
place they are listed. Exit status: 0 every alarm is listed; 1 an unlisted alarm, an analysis that
did not finish (timeout or error) or a degeneration; 3 frama-c is missing (Debian: apt-get install
frama-c-base).
"""

import argparse
import collections
import concurrent.futures
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

CSRC = Path(__file__).resolve().parents[2]
DOC = CSRC.parent / "docs" / "studies" / "verification.md"
#: the RTP's modules (csrc/wake_rtp*.c), the core step first: every analysis links them all
RTP_SOURCES = sorted((p.name for p in CSRC.glob("wake_rtp*.c")), key=lambda n: (n != "wake_rtp.c", n))
RTP_ENTRIES = ["wake_rtp_init", "wake_rtp_set_weights", "wake_rtp_reset", "wake_rtp_step",
               "wake_rtp_step_missing", "wake_rtp_run", "wake_rtp_load_state", "wake_rtp_get_state",
               "wake_rtp_reciprocal", "wake_rtp_set_ahead", "wake_rtp_set_ahead_ramp", "wake_rtp_ahead_output",
               "wake_rtp_load_ahead_state", "wake_rtp_get_ahead_state"]
#: the tremor ahead's own instance (wake_ahead.h): its per-sample functions and the setters that take arrays, on an
#: instance of any content, in every configuration (its module compiles in every one)
AHEAD_INSTANCE_ENTRIES = ["wake_ahead_step", "wake_ahead_step_missing", "wake_ahead_prepare", "wake_ahead_finish",
                          "wake_ahead_set_model", "wake_ahead_load", "wake_ahead_history"]
#: the voluntary motion ahead's own instance (wake_voluntary_ahead.h): its output entry, on an instance of any
#: content, in every configuration (it compiles in every one)
VOLUNTARY_INSTANCE_ENTRIES = ["wake_voluntary_ahead_output"]
#: entries of the split step, analysed in every configuration with WAKE_RTP_SPLIT 1 added
SPLIT_ENTRIES = ["wake_rtp_prepare", "wake_rtp_finish", "wake_rtp_finish_missing"]
SPLIT_DEFS = " -DWAKE_RTP_SPLIT=1"
#: entries of the voluntary motion at n + h, analysed in every configuration with WAKE_RTP_VOLUNTARY_AHEAD 1 added
#: (wake_rtp_step with it on: --entry wake_rtp_step --voluntary-ahead)
VOLUNTARY_ENTRIES = ["wake_rtp_set_voluntary_ahead", "wake_rtp_voluntary_ahead_output", "wake_rtp_run_outputs"]
VOLUNTARY_DEFS = " -DWAKE_RTP_VOLUNTARY_AHEAD=1"
#: the entries whose code runs the voluntary motion's restart (its gain k = w_h' w / |w|^2 by long division and its
#: FIR build), analysed again in the build with WAKE_RTP_VOLUNTARY_AHEAD 1 (unit rtp_voluntary), every configuration
VOLUNTARY_BUILD_ENTRIES = ["wake_rtp_set_weights", "wake_rtp_load_state"]
#: extra Eva options per entry in a build with WAKE_RTP_VOLUNTARY_AHEAD 1 (unit rtp_voluntary, or --voluntary-ahead)
#: and WAKE_RTP_KALMAN 1 (the functions named exist only there). The voluntary restart runs once per state the
#: restart's FIR build leaves (hundreds), and with 100 states per statement each of its calls reached the long
#: division for k about 14 times, each of those 66 turns of up to 100 states: 90 % of the analysis (-eva-show-perf).
#: Joining inside the voluntary restart and the division (one state per call; the division's quotient is clamped
#: to +-2^50 whatever the states) gives the same result (no alarm) in a tenth of the time or less
VOLUNTARY_ENTRY_OPTIONS = {e: ("-eva-slevel-function", "divide_wide:0,wake_rtpi_voluntary_restart_on:0")
                           for e in VOLUNTARY_BUILD_ENTRIES}
#: seconds per entry in that build whatever --timeout says: 9 to 33 s per configuration at a load average of 1 to 2
#: on a 2-core machine, beyond EVA_TIMEOUT's 120 s on a busier one
VOLUNTARY_ENTRY_TIMEOUT = {e: 300 for e in VOLUNTARY_BUILD_ENTRIES}
#: HPA entries whose analysis is checked (every alarm listed and justified)
HPA_ENTRIES = ["wake_hpa_default_config", "wake_hpa_init", "wake_hpa_push", "wake_hpa_push_missing",
               "wake_hpa_start", "wake_hpa_slice", "wake_hpa_take", "wake_hpa_to_rtp", "wake_hpa_apply",
               "wake_hpa_set_previous_ahead"]
#: configurations of the HPA entries: the HPA's own code does not depend on the RTP's arithmetic or Kalman
#: switches, so two configurations cover both values of each; apply, which calls wake_rtp_set_weights, runs
#: in all of them
HPA_CONFIGS = ["mul64 K1", "m0split K0"]
HPA_ALL_CONFIG_ENTRIES = {"wake_hpa_apply"}
#: the tremor-ahead build (off by default; docs/studies/verification.md, "The tremor-ahead build"): WAKE_HPA_AHEAD 1
#: and the RTP's WAKE_RTP_AHEAD it needs (on by default, stated so that the unit does not depend on that
#: default). Every HPA entry again, with the ahead counters, fields and steps compiled in, and the entry
#: that exists only there; the same configurations as above
AHEAD_DEFS = " -DWAKE_HPA_AHEAD=1 -DWAKE_RTP_AHEAD=1"
AHEAD_HPA_ENTRIES = HPA_ENTRIES + ["wake_hpa_ahead_to_rtp"]
#: the steps of one HPA run, each from its precondition (tests/prove/eva_hpa_steps.c, through the internal header:
#: the steps are internal functions), each checking the postcondition the next assumes (docs/studies/verification.md, "A whole HPA
#: run"); the HPA's own code, so one configuration
STEP_ENTRIES = ["step_sums", "step_lags", "step_lag_end", "step_diag", "step_levinson", "step_psd", "step_psd_chunk",
                "step_cutoff", "step_bins", "step_dft", "step_dft_chunk", "step_bin", "step_ramp", "step_ramp_chunk",
                "step_diag_chunk", "step_bin_end_chunk",
                "step_gram", "step_solve", "step_sums_chunk", "step_lags_chunk", "dispatch_slice", "dispatch_run"]
STEP_CONFIGS = ["mul64 K1"]
#: the tremor-ahead steps of a run (tests/prove/eva_hpa_ahead_steps.c, the build with WAKE_HPA_AHEAD 1), as the
#: steps above; the pass as a chunk from any sample with its invariant (docs/studies/verification.md, "The tremor-ahead build")
AHEAD_STEP_ENTRIES = ["step_sums_ahead", "step_ahead_start", "step_ahead_pass_chunk", "step_ahead_solve"]
#: every step entry: the window lengths (and, per entry, the lag or the order) are split into one Eva state each
#: (Frama_C_interval_split), kept through the calls and beyond the default limit of 100 splits; the window
#: loops (up to 500 samples) unrolled
STEP_OPTIONS = ("-eva-interprocedural-splits", "-eva-split-limit", "1000", "-eva-auto-loop-unroll", "600",
                "-eva-slevel", "400")
#: the chunk entries' states (eva_hpa_steps.c: start index x lag x budget class) kept apart
CHUNK_OPTIONS = ("-eva-slevel", "20000", "-eva-split-limit", "20000")
#: HPA entries analysed on request only (--hpa-report): a whole run's float loops over a window of any
#: samples widen to every float (docs/studies/verification.md, "What Eva does not yet cover")
HPA_REPORT_ENTRIES = [("hpa", "wake_hpa_run")]
#: entries whose inputs are floats of any bit pattern (NaN and infinities included): the code itself
#: tests them, so Eva's non-finite float alarms are off there (-warn-special-float none); everywhere
#: else a NaN or an infinity is an alarm
RAW_FLOAT_ENTRIES = {"wake_hpa_init", "wake_hpa_to_rtp", "wake_hpa_apply", "wake_hpa_ahead_to_rtp",
                     "wake_hpa_set_previous_ahead",
                     # the tremor ahead's solve tests what it divides by and clips what it produces, a NaN or an
                     # infinity on the way included (eva_hpa_ahead_steps.c)
                     "step_ahead_solve"}
#: extra Eva options per entry of the tremor-ahead build, after ENTRY_OPTIONS'. apply: its driver ranges the RTP's
#: predictor and goal (docs/studies/verification.md, "The tremor-ahead build"), so more states pass the RTP's check, and
#: with the default 100 states per statement the refusal path of wake_hpa_to_rtp (outputs unset) is joined with
#: the others again (a false "uninitialized" at wake_rtp_set_weights, as without wake_hpa_round_clamp:0)
AHEAD_ENTRY_OPTIONS = {"wake_hpa_apply": ("-eva-slevel", "300")}
#: extra Eva options per entry. apply: wake_hpa_round_clamp's three branches, per weight, would exceed the slevel
#: inside wake_hpa_to_rtp's loop and merge states where fewer weights are written (a false "uninitialized"
#: at wake_rtp_set_weights); joining inside wake_hpa_round_clamp (slevel 0 there) keeps one state per call
ENTRY_OPTIONS = {"wake_hpa_apply": ("-eva-slevel-function", "wake_hpa_round_clamp:0"),
                 # lag_run's four-at-a-time loop (t + 4 <= t1) is not unrolled automatically: at most 125 turns
                 "step_lags": STEP_OPTIONS + ("-eva-min-loop-unroll", "130"),
                 # err (1 - k k): k k of k in [-1, 1] is [0, 1] only when Eva subdivides k
                 "step_levinson": STEP_OPTIONS + ("-eva-subdivide-non-linear", "20"),
                 # one state per window length is enough for the spectrum and the valley rule (a tenth of the time)
                 "step_psd": STEP_OPTIONS + ("-eva-slevel", "100"),
                 "step_cutoff": STEP_OPTIONS + ("-eva-slevel", "100"),
                 # a chunk of a DFT pass from any t: the Reinsch loops' states joined (their clamps bound them; the
                 # 3 branches of each clamp and the 16 exits of a block's loop would otherwise multiply them), and room
                 # in the entry and the step for one state per budget range and outcome (about 15,000)
                 "step_dft_chunk": STEP_OPTIONS + ("-eva-slevel-function",
                                                   "reinsch_run1:0,reinsch_run2:0,clamp_abs:0,reinsch_block:0,"
                                                   "eva_step_dft_chunk:20000,wake_hpa_step_dft:20000"),
                 # chunks of the spectrum and of the ramp: room for one state per budget range, item and outcome
                 "step_psd_chunk": STEP_OPTIONS + ("-eva-slevel-function", "eva_step_psd_chunk:20000,wake_hpa_step_psd:20000"),
                 "step_ramp_chunk": STEP_OPTIONS + ("-eva-slevel-function", "eva_step_ramp_chunk:20000,wake_hpa_step_ramp:20000"),
                 # a chunk of a lag's diagonal from any row: room in the entry for one state per window length, lag,
                 # budget range and side of the lag's end; the step's states joined (the clamp where a chunk loads
                 # diag bounds it whatever the join; with 20,000 there, the lag d = 0 alone ran past 12 minutes)
                 "step_diag_chunk": STEP_OPTIONS + ("-eva-slevel-function", "eva_step_diag_chunk:20000,wake_hpa_step_diag:0"),
                 # a chunk of a bin's slide from any row: room in the entry for one state per window length, pair, bin
                 # of the pass, budget range and side of the slide's end; the step's states joined (its clamps bound
                 # the carried state whatever the join; the block's loop of SLIDE_BLOCK rows is unrolled)
                 "step_bin_end_chunk": STEP_OPTIONS + ("-eva-slevel-function",
                                                       "eva_step_bin_end_chunk:20000,wake_hpa_step_bin_end:0,clamp_abs:0"),
                 # the chunk entries keep one Eva state per start index, lag and budget class (up to 20,000):
                 # the slevel and the split limit must not merge them
                 "step_sums_chunk": STEP_OPTIONS + CHUNK_OPTIONS,
                 "step_lags_chunk": STEP_OPTIONS + CHUNK_OPTIONS + ("-eva-min-loop-unroll", "130"),
                 # the dispatch with run_step's contract (eva_hpa_steps.c) instead of its body: the steps are shown
                 # by the step and chunk entries
                 "dispatch_slice": STEP_OPTIONS + ("-eva-use-spec", "wake_hpa_run_step"),
                 "dispatch_run": STEP_OPTIONS + ("-eva-use-spec", "wake_hpa_run_step"),
                 # a chunk of the tremor-ahead pass from any sample: each block's states kept apart inside
                 # ahead_block and joined between blocks (ahead_blocks: its loop reaches its invariant), the
                 # oscillators' clamped stores joined (the clamps' branches would multiply the states per bin)
                 "step_ahead_pass_chunk": STEP_OPTIONS + ("-eva-slevel-function",
                                                          "ahead_osc_store:0,clamp_abs:0,ahead_blocks:0")}
ENTRY_OPTIONS.update({e: STEP_OPTIONS for e in STEP_ENTRIES + AHEAD_STEP_ENTRIES if e not in ENTRY_OPTIONS})
#: configuration name -> preprocessor definitions
CONFIGS = {
    "mul64 K1": "-DWAKE_RTP_KALMAN=1",
    "mul64 K0": "-DWAKE_RTP_KALMAN=0",
    "m0split K1": "-DWAKE_RTP_KALMAN=1 -DWAKE_RTP_NO_LONG_MULTIPLY=1",
    "m0split K0": "-DWAKE_RTP_KALMAN=0 -DWAKE_RTP_NO_LONG_MULTIPLY=1",
    "Os K1": "-DWAKE_RTP_KALMAN=1 -D__OPTIMIZE_SIZE__=1",
}
#: the HPA's sources (by concern, csrc/internal/wake_hpa_internal.h); the tremor-ahead fit's module is added to the
#: units built with it (AHEAD_DEFS), the only ones that run it
HPA_AHEAD_SOURCE = "wake_hpa_ahead.c"
HPA_SOURCES = sorted(p.name for p in CSRC.glob("wake_hpa*.c") if p.name != HPA_AHEAD_SOURCE)
#: analysis unit -> (its entries' file in tests/prove, whether the HPA's sources are added to the sources (eva_hpa_steps.c
#: includes it: the steps are static), definitions added to every configuration's)
UNITS = {"rtp": ("eva_rtp.c", False, ""),
         "hpa": ("eva_hpa.c", True, ""),
         "hpa_ahead": ("eva_hpa.c", True, AHEAD_DEFS),
         "hpa_steps": ("eva_hpa_steps.c", True, ""),
         "hpa_ahead_steps": ("eva_hpa_ahead_steps.c", True, AHEAD_DEFS),
         "rtp_voluntary": ("eva_rtp.c", False, VOLUNTARY_DEFS)}
#: an alarm: Eva's assertion on the lines below the warning, or, when the warning fits on one line (a driver's
#: `//@ assert` not proven in a file of a short name, e.g. "[eva:alarm] tests/prove/eva_hpa.c:189: Warning: assertion
#: got status unknown."), its status on the warning's own line
ALARM = re.compile(r"^\[eva:alarm\] (?P<file>[\w./]+):(?P<line>\d+): Warning: "
                   r"(?:\n(?P<body>(?:  .*\n)+)|(?P<status>.*got status (?:unknown|invalid)\.)\n)", re.M)
#: the summary's counts, which the alarms read above must account for (a message of a shape the pattern above
#: does not know would otherwise pass unseen): "4 alarms generated by the analysis" and, per kind of logical
#: property, "Assertions   2 valid   0 unknown   0 invalid   2 total"
GENERATED = re.compile(r"^\s*(\d+) alarms? generated by the analysis", re.M)
PROPERTIES = re.compile(r"^\s+[A-Z][\w ]*?\s+\d+ valid\s+(\d+) unknown\s+(\d+) invalid\s+\d+ total", re.M)


def unproven_in_summary(out: str) -> int:
    """Alarms plus logical properties not proven (unknown or invalid), as Eva's summary counts them."""
    generated = sum(int(m[1]) for m in GENERATED.finditer(out))
    return generated + sum(int(m[1]) + int(m[2]) for m in PROPERTIES.finditer(out))
# | wake_rtp.c | invalid RHS operand for shift | `0 ≤ up < 64` | justification |
ROW = re.compile(r"^\|\s*(?P<file>wake_\w+\.[ch])\s*\|\s*(?P<kind>[^|]+?)\s*\|\s*`(?P<assert>[^`]+)`\s*\|")


def normalise(text: str) -> str:
    return " ".join(text.split())


def listed_alarms() -> set:
    rows = set()
    for line in DOC.read_text().splitlines():
        m = ROW.match(line)
        if m:
            rows.add((m["file"], normalise(m["assert"])))
    return rows


def analyse(unit: str, entry: str, defs: str, timeout: int, slevel: int, extra=()) -> dict:
    driver, with_hpa, unit_defs = UNITS[unit]
    hpa = HPA_SOURCES + ([HPA_AHEAD_SOURCE] if "-DWAKE_HPA_AHEAD=1" in unit_defs else [])
    sources = RTP_SOURCES + [f"tests/prove/{driver}"] + (hpa if with_hpa else [])
    cmd = ["frama-c", "-machdep", "gcc_x86_32",
           "-cpp-extra-args=-I. -include tests/prove/eva_builtins.h " + defs + unit_defs, *sources,
           "-eva", "-main", f"eva_{entry}", "-eva-slevel", str(slevel), "-eva-auto-loop-unroll", "400",
           "-eva-split-return", "full", *extra,
           "-eva-msg-key=-initial-state,-final-states", "-eva-warn-key", "garbled-mix=active"]
    start = time.monotonic()
    try:
        # Frama-C resolves relative source names against $PWD, which `make -C csrc` leaves at the caller's folder
        proc = subprocess.run(cmd, cwd=CSRC, capture_output=True, text=True, timeout=timeout,
                              env={**os.environ, "PWD": str(CSRC)})
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "alarms": [], "seconds": timeout}
    out = proc.stdout + proc.stderr
    alarms = []
    for m in ALARM.finditer(out):
        body = normalise(m["body"] or m["status"])
        kind, _, assertion = body.partition(". assert ")
        assertion = assertion.split(";")[0]     # the assertion, without Eva's note on temporaries
        if m["status"] is not None or body.startswith("assertion got status"):
            # a driver's `//@ assert` (a step's postcondition) or a called function's precondition Eva could not
            # prove: never listed
            kind, assertion = "postcondition not shown", f"{body} (line {m['line']})"
        alarms.append((Path(m["file"]).name, kind, normalise(assertion), int(m["line"])))
    ok = proc.returncode == 0 and "ANALYSIS SUMMARY" in out and "degeneration" not in out.lower()
    status = "ok" if ok else f"error {proc.returncode}"
    counted = unproven_in_summary(out)
    if ok and len(alarms) < counted:
        status = f"error: the summary counts {counted} alarms and unproven properties, {len(alarms)} were read"
    return {"status": status, "alarms": alarms, "seconds": time.monotonic() - start, "log": out}


ARGS = argparse.Namespace(timeout=300, slevel=100, voluntary_ahead=False)


#: seconds a step entry may take whatever --timeout says: step_diag (160 states of 32 diagonal entries) takes about
#: 60 s on an idle core and 160 s on a 2-core machine at a load average of 13
STEP_TIMEOUT = 400
#: entries that need more on a loaded machine: step_solve's 16 ridge attempts (about 70 s of CPU; 4 min of wall
#: time at a load average of 8)
ENTRY_TIMEOUT = {"step_solve": 900,
                 # one state per start index, lag near its end and budget class: about 250 s of CPU, 6 min of wall
                 # time one at a time at a load average of 2 to 3
                 "step_lags_chunk": 900,
                 # one state per window length, lag, budget class and side of the lag's end: about 440 s of CPU,
                 # 14 min of wall time at a load average of about 3 to 4
                 "step_diag_chunk": 1500}
#: the tremor-ahead build's apply, with 300 states per statement: 34 to 72 s per configuration at a load average of
#: about 3 on a 2-core machine, beyond EVA_TIMEOUT's 120 s on a busier one
AHEAD_ENTRY_TIMEOUT = {"wake_hpa_apply": 400}


def analyse_and_print(unit: str, entry: str, config: str, args) -> dict:
    """One analysis with the options its entry needs; its table row printed."""
    timeout = max(args.timeout, ENTRY_TIMEOUT.get(entry, STEP_TIMEOUT)) if unit.endswith("_steps") else args.timeout
    if unit == "hpa_ahead":
        timeout = max(timeout, AHEAD_ENTRY_TIMEOUT.get(entry, 0))
    voluntary = voluntary_build(unit, entry, args)
    if voluntary:
        timeout = max(timeout, VOLUNTARY_ENTRY_TIMEOUT.get(entry, 0))
    defs = CONFIGS[config] + (SPLIT_DEFS if entry in SPLIT_ENTRIES else "") \
        + (VOLUNTARY_DEFS if voluntary and UNITS[unit][2] != VOLUNTARY_DEFS else "")
    r = analyse(unit, entry, defs, timeout, args.slevel,
                entry_options(entry, unit, voluntary and "-DWAKE_RTP_KALMAN=1" in CONFIGS[config]))
    label = config + {AHEAD_DEFS: " ahead", VOLUNTARY_DEFS: " voluntary"}.get(UNITS[unit][2], "")
    print(f"| {entry} | {label} | {len(r['alarms'])} | {r['seconds']:.1f} | {r['status']} |", flush=True)
    return r


def voluntary_build(unit: str, entry: str, args) -> bool:
    """Whether the analysis builds with WAKE_RTP_VOLUNTARY_AHEAD 1."""
    return unit == "rtp_voluntary" or entry in VOLUNTARY_ENTRIES or \
        (args.voluntary_ahead and unit == "rtp" and entry not in SPLIT_ENTRIES)


def entry_options(entry: str, unit: str = "", voluntary_kalman: bool = False) -> tuple:
    """The Eva options an entry adds to the common ones (voluntary_kalman: built with WAKE_RTP_VOLUNTARY_AHEAD 1
    and WAKE_RTP_KALMAN 1)."""
    raw = ("-warn-special-float", "none") if entry in RAW_FLOAT_ENTRIES else ()
    ahead = AHEAD_ENTRY_OPTIONS.get(entry, ()) if unit == "hpa_ahead" else ()
    vol = VOLUNTARY_ENTRY_OPTIONS.get(entry, ()) if voluntary_kalman else ()
    return raw + ENTRY_OPTIONS.get(entry, ()) + ahead + vol


def run_plan(plan: list, jobs: int) -> list:
    """Every analysis of the plan, `jobs` at a time; results in the plan's order, rows printed as they end."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(analyse_and_print, unit, entry, config, ARGS) for unit, entry, config in plan]
        return [f.result() for f in futures]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=int, default=300, help="seconds per analysis (default 300)")
    parser.add_argument("--slevel", type=int, default=100, help="Eva's -eva-slevel (default 100; loops with a "
                        "computable bound up to 400 iterations are unrolled)")
    parser.add_argument("--only", choices=list(UNITS), help="one unit only (hpa_ahead: the HPA entries with "
                        "WAKE_HPA_AHEAD 1; rtp_voluntary: set_weights and load_state with WAKE_RTP_VOLUNTARY_AHEAD 1)")
    parser.add_argument("--entry", action="append", metavar="FUNCTION",
                        help="only this public function (repeatable), e.g. --entry wake_rtp_finish")
    parser.add_argument("--config", action="append", choices=list(CONFIGS), metavar="NAME",
                        help="only this configuration (repeatable), e.g. --config 'm0split K1'")
    parser.add_argument("--voluntary-ahead", action="store_true",
                        help="build every RTP entry with WAKE_RTP_VOLUNTARY_AHEAD 1 (not with the split entries)")
    parser.add_argument("--hpa-report", action="store_true",
                        help="analyse the HPA entries not yet checked and report their alarms (never fails on them)")
    parser.add_argument("--jobs", type=int, default=2, help="analyses run at once (default 2)")
    args = parser.parse_args(argv)
    ARGS.timeout, ARGS.slevel, ARGS.voluntary_ahead = args.timeout, args.slevel, args.voluntary_ahead
    if shutil.which("frama-c") is None:
        print("eva_check: frama-c not found (Debian: apt-get install frama-c-base)", file=sys.stderr)
        return 3
    plan = []
    if args.only in (None, "rtp"):
        plan += [("rtp", e, c) for e in RTP_ENTRIES + AHEAD_INSTANCE_ENTRIES + VOLUNTARY_INSTANCE_ENTRIES + SPLIT_ENTRIES
                 + VOLUNTARY_ENTRIES for c in CONFIGS]
    if args.only in (None, "hpa"):
        plan += [("hpa", e, c) for e in HPA_ENTRIES
                 for c in (CONFIGS if e in HPA_ALL_CONFIG_ENTRIES else HPA_CONFIGS)]
    if args.only in (None, "hpa_steps"):
        plan += [("hpa_steps", e, c) for e in STEP_ENTRIES for c in STEP_CONFIGS]
    if args.only in (None, "hpa_ahead"):
        plan += [("hpa_ahead", e, c) for e in AHEAD_HPA_ENTRIES
                 for c in (CONFIGS if e in HPA_ALL_CONFIG_ENTRIES else HPA_CONFIGS)]
    if args.only in (None, "hpa_ahead_steps"):
        plan += [("hpa_ahead_steps", e, c) for e in AHEAD_STEP_ENTRIES for c in STEP_CONFIGS]
    if args.only in (None, "rtp_voluntary") and not args.voluntary_ahead:
        plan += [("rtp_voluntary", e, c) for e in VOLUNTARY_BUILD_ENTRIES for c in CONFIGS]
    if args.hpa_report:
        print("| HPA entry (report only) | configuration | alarms | seconds | status |")
        print("|---|---|---:|---:|---|")
        for unit, entry in HPA_REPORT_ENTRIES:
            if args.entry and entry not in args.entry:
                continue
            r = analyse_and_print(unit, entry, "mul64 K1", args)
            if len(r["alarms"]) <= 40:
                for file, kind, assertion, line in r["alarms"]:
                    print(f"  - {file}:{line} {kind}: `{assertion}`")
        print()
    if args.entry:
        unknown = set(args.entry) - {e for _, e, _ in plan} - \
            ({e for _, e in HPA_REPORT_ENTRIES} if args.hpa_report else set())
        if unknown:
            parser.error(f"--entry: not an analysed entry: {', '.join(sorted(unknown))}")
        plan = [p for p in plan if p[1] in args.entry]
    if args.config:
        plan = [p for p in plan if p[2] in args.config]
    listed = listed_alarms()
    failures, distinct = [], collections.defaultdict(set)
    print("| entry | configuration | alarms | seconds | status |")
    print("|---|---|---:|---:|---|")
    for (unit, entry, config), r in zip(plan, run_plan(plan, max(1, args.jobs))):
        if r["status"] != "ok":
            failures.append(f"{entry} ({config}, {unit}): {r['status']}")
            if "log" in r:
                print(r["log"][-3000:], file=sys.stderr)
        for file, kind, assertion, line in r["alarms"]:
            distinct[(file, assertion)].add((kind, line, f"{entry} ({config}, {unit})"))
    print(f"\n{len(distinct)} distinct alarms (file, assertion):")
    for (file, assertion), seen in sorted(distinct.items()):
        kinds = sorted({k for k, _, _ in seen})
        lines = sorted({ln for _, ln, _ in seen})
        mark = "listed" if (file, assertion) in listed else "UNLISTED"
        print(f"- {mark}: {file}:{','.join(map(str, lines))} {'/'.join(kinds)}: `{assertion}` "
              f"({len(seen)} runs)")
        if (file, assertion) not in listed:
            failures.append(f"unlisted alarm {file}: {assertion}")
    if failures:
        for f in failures:
            print(f"error: {f}", file=sys.stderr)
        return 1
    print("prove: OK (every alarm is listed and justified in docs/studies/verification.md)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
