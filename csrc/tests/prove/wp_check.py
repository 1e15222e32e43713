"""Frama-C WP on the HPA's dispatch: run_pieces' loop ends (make -C csrc wp, part of make -C csrc prove).

    python tests/prove/wp_check.py              (from csrc/)
    python tests/prove/wp_check.py --timeout 60 --prover cvc4

Proves, with ``frama-c -wp -wp-rte`` on tests/prove/eva_hpa_steps.c and the HPA's sources (the driver gives run_step
and run_pieces their contracts), every goal of ``run_pieces``: its loop invariants, its loop variant ``left``
(positive where an iteration goes on, strictly lower after it), its loop assigns, run_step's and piece_cost's
preconditions at their calls, no signed overflow, and its postcondition; from run_step's and piece_cost's
contracts, which the Eva entries show (docs/studies/verification.md, "Termination").  The SMT prover is the first of
alt-ergo, z3, cvc4 that Why3 detects (a Why3 configuration of the installed provers is written to a temporary
folder when none is set).  Exit status: 0 every goal proved, the variant's two among them; 1 a goal not proved
or an error; 3 frama-c, why3 or every prover missing (Debian: apt-get install frama-c-base why3 cvc4).
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CSRC = Path(__file__).resolve().parents[2]
#: the functions whose goals are proved
FUNCTIONS = ["wake_hpa_run_pieces"]
#: the HPA's sources of the default build (the tremor-ahead fit's module is not part of it)
HPA_SOURCES = sorted(p.name for p in CSRC.glob("wake_hpa*.c") if p.name != "wake_hpa_ahead.c")
#: goals that must be among the proved ones: without them "every goal proved" would not say the loop ends
REQUIRED = ["loop_variant_positive", "loop_variant_decrease"]
PROVERS = ["alt-ergo", "z3", "cvc4"]
#: "[wp] [CVC4 1.8] Goal typed_run_pieces_loop_variant_decrease : Valid (Qed:283ms) (50ms) (15914)"
GOAL = re.compile(r"^\[wp\] \[(?P<prover>[^\]]+)\] Goal (?P<goal>\S+) : (?P<verdict>\w+)", re.M)
#: "[wp] Proved goals:   37 / 37"
PROVED = re.compile(r"^\[wp\] Proved goals:\s+(\d+)\s*/\s*(\d+)", re.M)
#: "[wp] Prover       CVC4 1.8    [cvc4|CVC4:1.8]"
DETECTED = re.compile(r"^\[wp\] Prover\s+.*\[(?P<name>[\w-]+)\|", re.M)


def parse(out: str) -> dict:
    """The goals of a WP log: each goal's verdict and prover, the summary's proved and total counts."""
    goals = {m["goal"]: (m["verdict"], m["prover"]) for m in GOAL.finditer(out)}
    summary = PROVED.search(out)
    proved, total = (int(summary[1]), int(summary[2])) if summary else (0, 0)
    return {"goals": goals, "proved": proved, "total": total}


def verdict(result: dict) -> list:
    """What keeps the log from proving the loop's end: [] when every goal, the variant's included, is proved."""
    problems = [f"{goal}: {v} ({prover})" for goal, (v, prover) in sorted(result["goals"].items()) if v != "Valid"]
    if result["total"] == 0 or result["proved"] != result["total"]:
        problems.append(f"proved {result['proved']} of {result['total']} goals")
    for name in REQUIRED:
        if not any(name in goal and v == "Valid" for goal, (v, _) in result["goals"].items()):
            problems.append(f"no proved goal {name} (the loop variant is gone?)")
    return problems


def pick_prover(env: dict, wanted: str) -> str:
    """The prover WP uses: the one asked for, else the first of PROVERS that WP detects ('' if none)."""
    out = subprocess.run(["frama-c", "-wp-detect"], capture_output=True, text=True, env=env).stdout
    found = {m["name"] for m in DETECTED.finditer(out)}
    if wanted:
        return wanted if wanted in found else ""
    return next((p for p in PROVERS if p in found), "")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=int, default=30, help="seconds per goal (default 30)")
    parser.add_argument("--prover", default="", help=f"a Why3 prover name (default: the first of {PROVERS} found)")
    args = parser.parse_args(argv)
    if shutil.which("frama-c") is None or shutil.which("why3") is None:
        print("wp_check: frama-c or why3 not found (Debian: apt-get install frama-c-base why3 cvc4)", file=sys.stderr)
        return 3
    with tempfile.TemporaryDirectory() as tmp:
        env = {**os.environ, "PWD": str(CSRC)}
        if "WHY3CONFIG" not in env and not Path.home().joinpath(".why3.conf").exists():
            env["WHY3CONFIG"] = str(Path(tmp) / "why3.conf")
            subprocess.run(["why3", "config", "detect"], capture_output=True, env=env)
        prover = pick_prover(env, args.prover)
        if not prover:
            print(f"wp_check: Why3 finds no prover ({args.prover or ', '.join(PROVERS)}; Debian: apt-get install "
                  "cvc4)", file=sys.stderr)
            return 3
        cmd = ["frama-c", "-machdep", "gcc_x86_32",
               "-cpp-extra-args=-I. -include tests/prove/eva_builtins.h -DWAKE_RTP_KALMAN=1",
               *sorted(p.name for p in CSRC.glob("wake_rtp*.c")), "tests/prove/eva_hpa_steps.c", *HPA_SOURCES,
               "-wp", "-wp-fct", ",".join(FUNCTIONS), "-wp-rte",
               "-wp-prover", prover, "-wp-timeout", str(args.timeout)]
        start = time.monotonic()
        proc = subprocess.run(cmd, cwd=CSRC, capture_output=True, text=True, env=env)
        seconds = time.monotonic() - start
    out = proc.stdout + proc.stderr
    result = parse(out)
    print(f"| function | prover | goals | proved | seconds |\n|---|---|---:|---:|---:|\n"
          f"| {', '.join(FUNCTIONS)} | Qed + {prover} | {result['total']} | {result['proved']} | {seconds:.1f} |")
    problems = verdict(result) + ([f"frama-c exited {proc.returncode}"] if proc.returncode != 0 else [])
    if problems:
        print(out[-3000:], file=sys.stderr)
        for p in problems:
            print(f"error: {p}", file=sys.stderr)
        return 1
    print(f"wp: OK (every goal of {', '.join(FUNCTIONS)} proved, its loop variant included)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
