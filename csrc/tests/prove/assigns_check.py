"""What the HPA's steps write, computed by Frama-C, against run_step's `assigns` list (make -C csrc assigns).

    python tests/prove/assigns_check.py              (from csrc/)
    python tests/prove/assigns_check.py --entry step_lag_end --jobs 2

run_step's contract (tests/prove/eva_hpa_steps.c, above its declaration) lists the fields of the instance the
steps write; the dispatch entries use that contract instead of the steps' bodies (docs/studies/verification.md, "The
dispatch and the integer chunks"). This script runs the step entries of eva_check.py (each step of a run from
its precondition, with the options eva_check.py gives it) with Frama-C's outputs analysis after Eva
(``-out-external``: an over-approximation of the locations a function writes, callees included, on the states
Eva reached), takes the outputs of every function run_step calls, and checks each written location of the
instance against the list: the field listed, and an array's written indices within the listed range.  Exit
status: 0 every write is listed; 1 a write not listed, a location not read, a step no entry reached, or an
analysis that did not finish; 3 frama-c is missing.
"""

import argparse
import concurrent.futures
import re
import shutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import eva_check  # noqa: E402

CSRC = eva_check.CSRC
#: the step entries whose analyses reach the steps' bodies (the chunk entries call the same functions from
#: other indices: --chunks adds them)
ENTRIES = ["step_sums", "step_lags", "step_lag_end", "step_diag", "step_levinson", "step_psd", "step_cutoff",
           "step_bins", "step_dft", "step_bin", "step_ramp", "step_gram", "step_solve"]
CHUNK_ENTRIES = ["step_sums_chunk", "step_lags_chunk", "step_psd_chunk", "step_dft_chunk", "step_ramp_chunk"]
#: the instance the entries run on (eva_hpa_steps.c: `static wake_hpa_t hpa`)
INSTANCE = "hpa"
#: "[inout] Out (external) for function step_lag_end:\n    hpa{.phase; .t; ...}" up to the next message
OUT = re.compile(r"^\[inout\] Out \(external\) for function (?P<fn>\w+):\n(?P<body>(?:    .*\n)*)", re.M)
#: one item of the run_step contract's assigns: h->name or h->name[lo .. hi]
LISTED = re.compile(r"h->(?P<name>\w+)(?:\[(?P<lo>[^\]]+?)\s*\.\.\s*(?P<hi>[^\]]+)\])?")


def header_values() -> dict:
    """The default value of every integer macro of the public headers (`#define NAME expr`; wake_rtp_types.h holds
    the RTP's sizes), as eval'd ints."""
    text = "".join((CSRC / h).read_text() for h in ("wake_rtp_types.h", "wake_rtp.h", "wake_hpa.h"))
    exprs = {}
    for m in re.finditer(r"^#define (WAKE_\w+) (.+?)\s*(?:/\*.*)?$", text, re.M):
        exprs.setdefault(m[1], m[2])
    values = {}
    for _ in range(5):   # macros defined from others: a few rounds
        for name, expr in exprs.items():
            value = evaluate(expr, values)
            if value is not None:
                values[name] = value
    return values


def evaluate(expr: str, values: dict):
    """An integer C expression of macros and literals (None when it names something unknown)."""
    text = re.sub(r"\b(\d+)[uUlL]+\b", r"\1", expr)
    text = re.sub(r"\b[A-Z_][A-Z0-9_]*\b", lambda m: str(values.get(m[0], m[0])), text)
    if not re.fullmatch(r"[\d\s()+\-*/<>]+", text):
        return None
    return int(eval(text.replace("/", "//")))   # noqa: S307 (digits and operators only)


def listed_assigns(values: dict) -> dict:
    """run_step's assigns as {field: (lo, hi) or None (the whole field)}."""
    source = (CSRC / "tests" / "prove" / "eva_hpa_steps.c").read_text()
    contract = source[:source.index("int32_t wake_hpa_run_step(wake_hpa_t *h, int32_t budget, int32_t fixed);")]
    clause = contract[contract.rindex("assigns"):]
    clause = clause[:clause.index(";")]
    out = {}
    for m in LISTED.finditer(clause):
        out[m["name"]] = None if m["lo"] is None else (evaluate(m["lo"], values), evaluate(m["hi"], values))
    return out


def split_items(text: str) -> list:
    """The items of `a; b{c; d}; e` at the top level."""
    items, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        depth += ch == "{"
        depth -= ch == "}"
        if ch == ";" and depth == 0:
            items.append(text[start:i].strip())
            start = i + 1
    items.append(text[start:].strip())
    return [item for item in items if item]


def locations(item: str, prefix: str = "") -> list:
    """The written locations of one printed item as (path, range or None): `.a[0..3]`, `{.a; .b}`, `.a{.b; .c}`.
    A shape not understood comes back as (the item, 'unparsed')."""
    if item.startswith("{") and item.endswith("}"):
        return [loc for sub in split_items(item[1:-1]) for loc in locations(sub, prefix)]
    m = re.fullmatch(r"\.(?P<name>\w+)(?:\[(?P<lo>\d+)(?:\.\.(?P<hi>\d+))?\])?(?P<rest>.*)", item, re.S)
    if m is None:
        return [(prefix + item, "unparsed")]
    path = prefix + m["name"]
    index = None if m["lo"] is None else (int(m["lo"]), int(m["hi"] or m["lo"]))
    rest = m["rest"].strip()
    if not rest:
        return [(path, index)]
    if index is None and rest.startswith("{") and rest.endswith("}"):
        return [loc for sub in split_items(rest[1:-1]) for loc in locations(sub, path + ".")]
    if index is None and rest.startswith("."):
        return locations(rest, path + ".")
    return [(path + rest, "unparsed")]


def written(body: str) -> tuple:
    """The instance's locations an Out block lists, and the other bases it writes (globals beyond it)."""
    text = " ".join(body.split())
    if text in ("", "\\nothing"):
        return [], []
    locs, others = [], []
    for base in split_items(text):
        if base.startswith(INSTANCE + "{") and base.endswith("}"):
            locs += [loc for item in split_items(base[len(INSTANCE) + 1:-1]) for loc in locations(item)]
        elif base.startswith(INSTANCE + "."):
            locs += locations(base[len(INSTANCE):])
        elif base == INSTANCE:
            locs.append(("(the whole instance)", "unparsed"))
        else:
            others.append(base)
    return locs, others


def steps_of_run_step() -> list:
    """The functions run_step's body calls (csrc/wake_hpa_slice.c, the default build: the tremor-ahead fit's steps
    are reached through hooks that do nothing there)."""
    source = (CSRC / "wake_hpa_slice.c").read_text()
    body = source[source.index("int32_t wake_hpa_run_step(wake_hpa_t *h"):]
    body = body[:body.index("\n}\n")]
    return sorted(set(re.findall(r"\b(wake_hpa_step_\w+)\(h", body)))


def fields_written(logs: dict, steps: list) -> set:
    """The instance's fields the steps write in any entry (the first name of each location's path)."""
    return {path.split(".")[0] for log in logs.values() for m in OUT.finditer(log) if m["fn"] in steps
            for path, _ in written(m["body"])[0]}


def check(logs: dict, listed: dict, steps: list) -> list:
    """Every problem: a write not listed or beyond the listed range, an unparsed location, a step not reached."""
    problems, reached = [], set()
    for entry, log in logs.items():
        for m in OUT.finditer(log):
            if m["fn"] not in steps:
                continue
            reached.add(m["fn"])
            locs, others = written(m["body"])
            for base in others:
                if base != "Frama_C_entropy_source":
                    problems.append(f"{m['fn']} ({entry}) writes {base}, not the instance")
            for path, index in locs:
                field = path.split(".")[0]
                if index == "unparsed":
                    problems.append(f"{m['fn']} ({entry}): location not understood: {path}")
                elif field not in listed:
                    problems.append(f"{m['fn']} ({entry}) writes {path}, not in run_step's assigns")
                elif index is not None and "." not in path and listed[field] is not None and not (
                        listed[field][0] <= index[0] and index[1] <= listed[field][1]):
                    problems.append(f"{m['fn']} ({entry}) writes {path}[{index[0]}..{index[1]}], beyond the listed "
                                    f"[{listed[field][0]}..{listed[field][1]}]")
    problems += [f"{fn}: no entry reached it" for fn in steps if fn not in reached]
    return problems


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--entry", action="append", metavar="STEP", help="only this step entry (repeatable)")
    parser.add_argument("--chunks", action="store_true", help="also the chunk entries (several minutes more)")
    parser.add_argument("--jobs", type=int, default=1, help="analyses run at once (default 1)")
    parser.add_argument("--timeout", type=int, default=eva_check.STEP_TIMEOUT, help="seconds per analysis")
    args = parser.parse_args(argv)
    if shutil.which("frama-c") is None:
        print("assigns_check: frama-c not found (Debian: apt-get install frama-c-base)", file=sys.stderr)
        return 3
    entries = args.entry or ENTRIES + (CHUNK_ENTRIES if args.chunks else [])
    listed, steps = listed_assigns(header_values()), steps_of_run_step()

    def one(entry):
        timeout = max(args.timeout, eva_check.ENTRY_TIMEOUT.get(entry, 0))
        extra = eva_check.entry_options(entry, "hpa_steps") + ("-out-external",)
        return eva_check.analyse("hpa_steps", entry, eva_check.CONFIGS["mul64 K1"], timeout, 100, extra)

    print("| entry | seconds | status |\n|---|---:|---|")
    logs, problems = {}, []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for entry, r in zip(entries, pool.map(one, entries)):
            print(f"| {entry} | {r['seconds']:.1f} | {r['status']} |", flush=True)
            if r["status"] != "ok":
                problems.append(f"{entry}: {r['status']}")
            logs[entry] = r.get("log", "")
    if args.entry:   # some entries only: only the steps they reach are checked
        steps = [fn for fn in steps if any(re.search(rf"for function {fn}:", log) for log in logs.values())]
    problems += check(logs, listed, steps)
    if problems:
        for p in problems:
            print(f"error: {p}", file=sys.stderr)
        return 1
    unwritten = sorted(set(listed) - fields_written(logs, steps))
    print(f"listed but written by no step analysed: {', '.join(unwritten) or 'none'}")
    print(f"assigns: OK (every location {', '.join(steps)} write is in run_step's assigns list)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
