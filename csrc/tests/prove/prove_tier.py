"""Frama-C in two tiers: the quick tier on every run, the full analysis whenever anything it analyses changed.

    python tests/prove/prove_tier.py choose            (from csrc/: which tier a run would take, and why)
    python tests/prove/prove_tier.py run --timeout 120  (make prove-tiered: CI)
    python tests/prove/prove_tier.py record --timeout 120   (make prove-record: the full analysis, then the record)
    python tests/prove/prove_tier.py quick --timeout 120    (make prove-quick: the quick tier alone)
    python tests/prove/prove_tier.py hash               (the inputs' hash and every input, one per line)

The full analysis is ``make prove`` (tests/prove/eva_check.py on every entry, configuration and step, then
tests/prove/wp_check.py): 17 to 40 minutes on a 2-core machine. The quick tier is every public entry of the C core
and the C HPA (eva_check.py's units ``rtp`` and ``hpa``, the split and voluntary-ahead entries included) in the
default configuration (``mul64 K1``: the 64-bit multiply, the Kalman update), with the same alarm check against
docs/studies/verification.md.

Which tier runs is decided from a SHA-256 over exactly the full analysis's inputs:

* every source and header its analyses read: the analysis drivers (tests/prove/eva_*.c), eva_builtins.h (included
  first), and every file they reach through ``#include "..."`` (wake_rtp.c, wake_rtp.h, wake_hpa.c, wake_hpa.h),
  found by following the includes, so a new one is hashed without a change here;
* the check scripts, eva_check.py and wp_check.py, whole (their entries, configurations and options, and
  the way they read a log);
* the justified alarms they accept (docs/studies/verification.md's "Eva alarms" rows, as eva_check.py reads them: an edit
  elsewhere in that file does not count);
* not the time limit per analysis (``--timeout``, make's ``EVA_TIMEOUT``): an analysis that ends has the same
  result whatever the limit, and one that does not end fails the run, so a limit can fail a run but never pass one
  (a record made with a longer limit on a busy machine holds for a shorter one);
* the Frama-C version string (``frama-c -version``) and Why3's (``why3 --version``; WP's provers are found by it).

tests/prove/full_prove_record.json holds the hash of the last passing full analysis beside its result (the tables
eva_check.py and wp_check.py printed). ``run`` takes the quick tier when the inputs' hash equals the record's, the
full analysis otherwise (a missing or unreadable record included), so no change to analysed code skips it; a
passing full analysis rewrites the record, which the developer commits (``make prove-record`` does the same on
request). Exit status: that of the analyses run (0 every alarm listed and every WP goal proved; 1 otherwise; 3
frama-c missing), 2 on a usage error.
"""

import argparse
import datetime
import hashlib
import importlib.util
import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

CSRC = Path(__file__).resolve().parents[2]
PROVE = CSRC / "tests" / "prove"
RECORD = PROVE / "full_prove_record.json"
#: the scripts whose text is an input (parameters and log reading); this script only selects, so it is not one
SCRIPTS = ["eva_check.py", "wp_check.py"]
#: the quick tier: eva_check.py's public-entry units in the default configuration
QUICK_UNITS = ["rtp", "hpa"]
QUICK_CONFIG = "mul64 K1"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def analysed_sources() -> list:
    """Every source and header the analyses read, as paths relative to csrc/ (sorted).

    The roots are the drivers in tests/prove (eva_*.c, eva_builtins.h) and the sources the check scripts pass to
    frama-c (wake_rtp.c, the HPA's wake_hpa*.c); each ``#include "..."`` is followed, looked up beside the including file and
    then in csrc/ (the analyses' ``-I.``). Frama-C's own headers (``__fc_builtin.h``, the libc) are covered by its
    version string."""
    roots = (sorted(PROVE.glob("eva_*.c")) + sorted(PROVE.glob("eva_*.h")) + sorted(CSRC.glob("wake_rtp*.c"))
             + sorted(CSRC.glob("wake_hpa*.c")))
    seen, todo = set(), list(roots)
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        for name in INCLUDE.findall(path.read_text(encoding="utf-8", errors="replace")):
            for where in (path.parent, CSRC):
                candidate = (where / name).resolve()
                if candidate.is_file():
                    todo.append(candidate)
                    break
    return sorted(str(p.relative_to(CSRC)) for p in seen)


def tool_version(cmd: list) -> str:
    """A tool's version line, or 'missing' when it is not on PATH."""
    if shutil.which(cmd[0]) is None:
        return "missing"
    proc = subprocess.run(cmd, capture_output=True, text=True)
    return (proc.stdout + proc.stderr).strip()


def listed_alarms() -> list:
    """docs/studies/verification.md's justified alarms, as eva_check.py reads them."""
    # loaded from this folder's file (not an `import`, which could return another checkout's cached module)
    spec = importlib.util.spec_from_file_location("prove_tier_eva_check", PROVE / "eva_check.py")
    eva_check = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(eva_check)
    return sorted(eva_check.listed_alarms())


def inputs() -> dict:
    """Every input of the full analysis: file -> SHA-256 of its bytes, and the other inputs by name."""
    items = {}
    for rel in analysed_sources() + [f"tests/prove/{s}" for s in SCRIPTS]:
        items[rel] = hashlib.sha256((CSRC / rel).read_bytes()).hexdigest()
    items["docs/studies/verification.md: Eva alarms"] = hashlib.sha256(
        json.dumps(listed_alarms(), ensure_ascii=False).encode()).hexdigest()
    items["frama-c -version"] = tool_version(["frama-c", "-version"])
    items["why3 --version"] = tool_version(["why3", "--version"])
    return items


def digest(items: dict) -> str:
    return hashlib.sha256(json.dumps(items, sort_keys=True, ensure_ascii=False).encode()).hexdigest()


def read_record() -> dict:
    try:
        return json.loads(RECORD.read_text())
    except (OSError, ValueError):
        return {}


def choose() -> tuple:
    """('quick' or 'full', the reason, the inputs, their hash)."""
    items = inputs()
    h = digest(items)
    record = read_record()
    if not record.get("inputs_sha256"):
        return "full", f"no readable record ({RECORD.relative_to(CSRC)})", items, h
    if record["inputs_sha256"] == h:
        return "quick", f"the inputs' hash {h[:16]} equals the record's (full analysis passed {record.get('date')})", \
            items, h
    old = record.get("inputs", {})
    changed = sorted(k for k in set(items) | set(old) if items.get(k) != old.get(k))
    return "full", f"the inputs' hash {h[:16]} differs from the record's {record['inputs_sha256'][:16]}: " \
        f"changed {', '.join(changed) or '(the record is inconsistent)'}", items, h


def run(cmd: list) -> tuple:
    """A check script's exit status and output, the output echoed as it comes."""
    proc = subprocess.Popen(cmd, cwd=CSRC, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = []
    for line in proc.stdout:
        print(line, end="", flush=True)
        lines.append(line)
    return proc.wait(), "".join(lines)


def quick(timeout: int) -> int:
    """The quick tier: every public entry in the default configuration, the alarms checked as in the full one."""
    status = 0
    for unit in QUICK_UNITS:
        rc, _ = run([sys.executable, "tests/prove/eva_check.py", "--timeout", str(timeout), "--only", unit,
                     "--config", QUICK_CONFIG])
        status = status or rc
    return status


def full(timeout: int, items: dict, h: str) -> int:
    """The full analysis (make prove); the record rewritten when it passed on inputs unchanged meanwhile."""
    start = time.monotonic()
    rc, out = run([shutil.which("make") or "make", "--no-print-directory", "prove", f"PYTHON={sys.executable}",
                   f"EVA_TIMEOUT={timeout}"])
    if rc != 0:
        return rc
    if digest(inputs()) != h:
        print("prove_tier: an input changed while the analysis ran: the record is left as it was", file=sys.stderr)
        return 1
    write_record(items, h, round(time.monotonic() - start), out)
    print(f"prove_tier: the full analysis passed; {RECORD.relative_to(CSRC)} rewritten (inputs {h[:16]}): commit it "
          "so that later runs take the quick tier")
    return 0


def write_record(items: dict, h: str, seconds: int, out: str) -> None:
    """The record: the inputs and their hash beside the passing full analysis's result (its tables and verdicts)."""
    keep = [line for line in out.splitlines() if line.startswith(("|", "- ", "prove:", "wp:", "SKIPPED"))
            or "distinct alarms" in line]
    record = {"inputs_sha256": h, "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
              "seconds": seconds, "inputs": items, "result": keep}
    RECORD.write_text(json.dumps(record, indent=1, ensure_ascii=False) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("action", choices=["choose", "run", "quick", "record", "hash"],
                        help="choose: say which tier and why; run: that tier; quick: the quick tier; record: the full "
                             "analysis and, if it passes, the record; hash: the inputs and their hash")
    parser.add_argument("--timeout", type=int, default=120, help="seconds per Eva analysis (make's EVA_TIMEOUT, "
                        "default 120); not an input of the hash")
    args = parser.parse_args(argv)
    if args.action == "hash":
        items = inputs()
        for k, v in items.items():
            print(f"{k}: {v}")
        print(f"inputs_sha256: {digest(items)}")
        return 0
    if shutil.which("frama-c") is None and args.action != "choose":
        print("prove_tier: frama-c not found (Debian: apt-get install frama-c-base)", file=sys.stderr)
        return 3
    if args.action == "quick":
        return quick(args.timeout)
    tier, reason, items, h = choose()
    if args.action == "record":
        tier, reason = "full", "make prove-record"
    print(f"prove_tier: {tier} tier: {reason}", flush=True)
    if args.action == "choose":
        return 0
    return quick(args.timeout) if tier == "quick" else full(args.timeout, items, h)


if __name__ == "__main__":
    sys.exit(main())
