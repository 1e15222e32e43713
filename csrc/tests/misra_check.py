"""MISRA C:2012 check of the C core: cppcheck's MISRA addon against the listed deviations.

    python tests/misra_check.py            (from csrc/; or: make -C csrc misra)

Runs ``cppcheck --addon=misra`` over wake_rtp.c, wake_hpa.c and wake_rate.c (their headers come in through the
includes), counts the findings per rule and per unit (wake_rtp = wake_rtp.c + wake_rtp.h + wake_ahead.h + wake_voluntary_ahead.h + wake_fixed.h, its
integer helpers; wake_hpa = wake_hpa.c + wake_hpa.h), and compares them with the deviation table in
docs/studies/verification.md
("MISRA C:2012 deviations"), the one place the deviations are listed with their reasons. A rule
that is not in the table, or a unit with more findings of a rule than the table allows, is an
unlisted deviation: exit status 1. Fewer findings than listed are reported, so that the table can be
tightened. Exit status 3: cppcheck is missing (Debian: apt-get install cppcheck).

The counts are those of cppcheck 2.10 (Debian 12); another version may find more or fewer.
"""

import collections
import re
import shutil
import subprocess
import sys
from pathlib import Path

CSRC = Path(__file__).resolve().parents[1]
TABLE = CSRC.parent / "docs" / "studies" / "verification.md"
#: the RTP's modules (wake_rtp*.c), the HPA's (wake_hpa*.c) and the rate adapter (wake_rate: no deviation listed,
#: so none allowed)
SOURCES = [*sorted(p.name for p in CSRC.glob("wake_rtp*.c")), *sorted(p.name for p in CSRC.glob("wake_hpa*.c")),
           "wake_rate.c"]
UNITS = ["wake_rtp", "wake_hpa"]
#: files whose findings count in another file's unit: the RTP's integer helpers (moved out of wake_rtp.c) and
#: internal headers count in wake_rtp (as every wake_rtp_*.c module does); the HPA's files and internal headers,
#: and the analyser's bounds (mostly the HPA's), in wake_hpa
UNIT_OF = {"wake_fixed": "wake_rtp", "wake_rtp_internal": "wake_rtp", "wake_rtp_sample": "wake_rtp", "wake_ahead": "wake_rtp",
           "wake_voluntary_ahead": "wake_rtp",
           **{p.stem: "wake_hpa" for p in CSRC.glob("wake_hpa_*.c")},
           **{f: "wake_hpa" for f in ("wake_hpa_internal", "wake_bounds", "wake_hpa_costs")}}
FINDING = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+):\w+:misra-c2012-(?P<rule>\d+\.\d+):")
# | 10.4 | Required | 7 | 34 | reason |
ROW = re.compile(r"^\|\s*(?P<rule>\d+\.\d+)\s*\|\s*(?P<cat>\w+)\s*\|\s*(?P<rtp>\d+)\s*\|\s*(?P<hpa>\d+)\s*\|")


def listed_deviations(text: str) -> dict:
    """{(unit, rule): allowed count} from the deviation table's rows."""
    allowed = {}
    for line in text.splitlines():
        m = ROW.match(line)
        if m:
            allowed[("wake_rtp", m["rule"])] = int(m["rtp"])
            allowed[("wake_hpa", m["rule"])] = int(m["hpa"])
    return allowed


def findings(output: str) -> collections.Counter:
    """Counter of (unit, rule) over cppcheck's template output."""
    found = collections.Counter()
    for line in output.splitlines():
        m = FINDING.match(line)
        if m:
            stem = Path(m["file"]).stem
            unit = "wake_rtp" if stem.startswith("wake_rtp_") else UNIT_OF.get(stem, stem)
            found[(unit, m["rule"])] += 1
    return found


def run_cppcheck() -> str:
    # --max-configs: every preprocessor configuration of the RTP's modules (cppcheck's default, 12, leaves some
    # out, e.g. the GNU C branch of the window fill)
    cmd = ["cppcheck", "--addon=misra", "--std=c99", "-q", "--inline-suppr", "--max-configs=40",
           "--template={file}:{line}:{severity}:{id}:{message}", "-I", str(CSRC)]
    proc = subprocess.run(cmd + [str(CSRC / s) for s in SOURCES], capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"misra_check: cppcheck failed:\n{proc.stdout}{proc.stderr}")
    return proc.stdout + proc.stderr


def main() -> int:
    if shutil.which("cppcheck") is None:
        print("misra_check: cppcheck not found (Debian: apt-get install cppcheck)", file=sys.stderr)
        return 3
    allowed = listed_deviations(TABLE.read_text())
    if not allowed:
        print(f"misra_check: no deviation table found in {TABLE}", file=sys.stderr)
        return 1
    found = findings(run_cppcheck())
    unlisted = {k: n for k, n in found.items() if n > allowed.get(k, 0)}
    print("| rule | wake_rtp found / listed | wake_hpa found / listed |")
    print("|---|---:|---:|")
    for rule in sorted({r for _, r in set(found) | set(allowed)}, key=lambda r: tuple(map(int, r.split(".")))):
        cells = [f"{found[(u, rule)]} / {allowed.get((u, rule), 0)}" for u in UNITS]
        print(f"| {rule} | {cells[0]} | {cells[1]} |")
    total = sum(found.values())
    print(f"\n{total} findings over {len({r for _, r in found})} rules")
    for (unit, rule), n in sorted(allowed.items()):
        if found[(unit, rule)] < n:
            print(f"note: {unit} has {found[(unit, rule)]} findings of rule {rule}, {n} listed: "
                  f"lower the count in {TABLE.name}")
    if unlisted:
        for (unit, rule), n in sorted(unlisted.items()):
            print(f"error: {unit}: {n} findings of MISRA C:2012 rule {rule}, {allowed.get((unit, rule), 0)} "
                  f"listed in {TABLE.name}: fix them or list the deviation with its reason", file=sys.stderr)
        return 1
    print("misra: OK (no unlisted deviation)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
