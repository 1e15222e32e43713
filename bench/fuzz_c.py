"""Run the C core's libFuzzer harnesses for a stated time each and report executions and coverage.

    python bench/fuzz_c.py                   # each harness 60 s, one after the other
    python bench/fuzz_c.py --seconds 30      # CI
    python bench/fuzz_c.py --seconds 600 --only fuzz_hpa

Builds the harnesses (``make -C csrc fuzz``: clang with ``-fsanitize=fuzzer,address,undefined``),
copies the committed seed corpus (csrc/tests/fuzz/seeds/*) into a working corpus under
csrc/build/fuzz/corpus/ (the repository's seeds are never written), runs each harness for
``--seconds`` on one core and prints a Markdown table: executions, executions per second, edges
covered (libFuzzer's ``cov``) out of the instrumented ones (harness, library and libFuzzer's own
hooks: an upper bound, not the library's reachable edges), features (``ft``) and the corpus size
at the end.

Exit status: 0 no finding, 1 a harness crashed, leaked or tripped a sanitizer or a property
(the input is saved as csrc/build/fuzz/crash-*; replay it with ``csrc/build/fuzz/<harness> FILE``),
3 clang or libFuzzer is missing.
"""

import argparse
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

CSRC = Path(__file__).resolve().parents[1] / "csrc"
OUT = CSRC / "build" / "fuzz"
#: harness -> seed folders (the RTP's three arithmetic / Kalman builds share the RTP seeds; the HPA with
#: the tremor-ahead fit reads the HPA's seeds and its own, which set the horizon)
HARNESSES = {
    "fuzz_rtp": ("rtp",),
    "fuzz_rtp_m0_arith": ("rtp",),
    "fuzz_rtp_no_kalman": ("rtp",),
    "fuzz_hpa": ("hpa",),
    "fuzz_rtp_split": ("rtp_split",),
    "fuzz_hpa_ahead": ("hpa", "hpa_ahead"),
}
COUNTERS = re.compile(r"Loaded \d+ modules\s+\((\d+) inline 8-bit counters\)")
STATS = re.compile(r"#(\d+)\s+DONE\s+cov: (\d+) ft: (\d+) corp: (\d+)/(\S+) .*?exec/s: (\d+)")


def build() -> None:
    """Build every harness; exit 3 naming the missing tool when clang or libFuzzer is absent."""
    if not (shutil.which("clang-14") or shutil.which("clang")):
        print("fuzz_c: clang not found (Debian: apt-get install clang-14 libfuzzer-14-dev)", file=sys.stderr)
        sys.exit(3)
    proc = subprocess.run(["make", "-s", "-C", str(CSRC), "fuzz"], capture_output=True, text=True)
    if proc.returncode != 0:
        print(proc.stdout + proc.stderr, file=sys.stderr)
        print("fuzz_c: building the harnesses failed (libFuzzer: apt-get install libfuzzer-14-dev)", file=sys.stderr)
        sys.exit(3)


def run(harness: str, seconds: int) -> dict:
    """One harness for ``seconds``; its final statistics and whether it found something."""
    corpus = OUT / "corpus" / harness
    corpus.mkdir(parents=True, exist_ok=True)
    for folder in HARNESSES[harness]:
        for seed in (CSRC / "tests" / "fuzz" / "seeds" / folder).iterdir():
            shutil.copy(seed, corpus / f"seed-{folder}-{seed.name}")
    cmd = [str(OUT / harness), f"-max_total_time={seconds}", "-print_final_stats=1",
           f"-artifact_prefix={OUT}/", str(corpus)]
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    elapsed = time.monotonic() - start
    log = proc.stderr
    (OUT / f"{harness}.log").write_text(log)
    m = STATS.search(log)
    row = {"harness": harness, "seconds": elapsed, "status": proc.returncode}
    counters = COUNTERS.search(log)
    row["edges"] = int(counters.group(1)) if counters else 0
    if m:
        row.update(runs=int(m.group(1)), cov=int(m.group(2)), ft=int(m.group(3)), corpus=int(m.group(4)),
                   corpus_size=m.group(5), per_second=int(m.group(6)))
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=int, default=60, help="time per harness (default 60)")
    parser.add_argument("--only", choices=sorted(HARNESSES), action="append", help="run only these harnesses")
    args = parser.parse_args(argv)
    if args.seconds < 1:
        parser.error("--seconds must be at least 1")
    build()
    rows = [run(h, args.seconds) for h in (args.only or HARNESSES)]
    print(f"## libFuzzer, {args.seconds} s per harness (ASan + UBSan)\n")
    print("| harness | wall s | executions | exec/s | edges covered (cov) | of instrumented | features (ft) | corpus | result |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    found = False
    for r in rows:
        result = "no finding" if r["status"] == 0 else f"FINDING (exit {r['status']}, see {OUT}/{r['harness']}.log)"
        found = found or r["status"] != 0
        print(f"| {r['harness']} | {r['seconds']:.0f} | {r.get('runs', 0):,} | {r.get('per_second', 0):,} | "
              f"{r.get('cov', 0)} | {r['edges']} | {r.get('ft', 0)} | {r.get('corpus', 0)} | {result} |")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
