"""Command line of ``wake profile``."""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import tempfile
from pathlib import Path

from .build import (
    CLOCKS_MHZ,
    DEFAULT_LEVEL,
    DEFAULT_TARGET,
    DEFAULT_WAVELET,
    FOOTPRINT_VARIANTS,
    LEAN_BUILD,
    SAMPLE_RATE_HZ,
    CEILING_LIMITS,
    TARGET_LIMITS,
    TARGETS,
    ProfileUnavailable,
    _emulator_modules,
    build_image,
    toolchain,
)
from .emulator import Emulator
from .report import check_targets, footprint, markdown_tables, qemu_crosscheck
from .scenarios import hotspots, profile_configuration


def _parse_levels(text):
    out = []
    for part in text.split(","):
        if "-" in part or ".." in part:
            lo, hi = re.split(r"-|\.\.", part)
            out.extend(range(int(lo), int(hi) + 1))
        else:
            out.append(int(part))
    return out


def build_parser():
    p = argparse.ArgumentParser(
        prog="wake profile",
        description="Worst-case Cortex-M instructions per sample, footprint and stack of the fixed-point core "
                    "(cross-compiled with arm-none-eabi-gcc, counted in unicorn).")
    p.add_argument("--targets", default=",".join(TARGETS),
                   help=f"comma-separated targets (default: all of {', '.join(TARGETS)})")
    p.add_argument("--levels", default="3-6", help="levels J, e.g. 3-6 or 5 (default: 3-6)")
    p.add_argument("--wavelets", default="sym3,db5", help="comma-separated wavelets (default: sym3,db5)")
    p.add_argument("--samples", type=int, default=None,
                   help="samples per input kind (default: max(128, 4 * 2**J); --quick: 2 * 2**J + 16)")
    p.add_argument("--quick", action="store_true",
                   help="the default configuration only (J=5, sym3) on every target, shorter inputs")
    p.add_argument("--check", action="store_true",
                   help="exit with status 1 when a measured step exceeds its static bound or the default "
                        "configuration regresses past the ceilings CI holds (static bound, Cortex-M4 -O2: "
                        f"{CEILING_LIMITS['bound_m4_active']:,} active / {CEILING_LIMITS['bound_m4_inert']:,} inert "
                        f"instructions; Cortex-M0+ -O2: {CEILING_LIMITS['bound_m0plus_active']:,} active; "
                        f"{CEILING_LIMITS['code_bytes']:,} B code at -Os, {CEILING_LIMITS['state_bytes']} B state, "
                        f"{CEILING_LIMITS['stack_bytes']} B stack; without the tremor ahead "
                        f"{CEILING_LIMITS['lean_bound_m4_active']:,} / {CEILING_LIMITS['lean_bound_m4_inert']:,}, "
                        f"{CEILING_LIMITS['lean_bound_m0plus_active']:,}, {CEILING_LIMITS['lean_code_bytes']:,} B)")
    p.add_argument("--check-goals", action="store_true",
                   help="exit with status 1 when a goal is missed (static bound, Cortex-M4 -O2, Kalman active, "
                        f"with the tremor ahead: {TARGET_LIMITS['bound_m4_active']:,} instructions, its state "
                        f"{TARGET_LIMITS['ahead_state_bytes']} B; without it: {TARGET_LIMITS['lean_bound_m4_active']:,} "
                        f"active / {TARGET_LIMITS['lean_bound_m4_inert']:,} inert, Cortex-M0+ -O2: "
                        f"{TARGET_LIMITS['lean_bound_m0plus_active']:,} active, {TARGET_LIMITS['lean_code_bytes']:,} B "
                        f"code at -Os; bounds within {100 * TARGET_LIMITS['bound_gap']:g} %% of the measured worst; "
                        f"{TARGET_LIMITS['state_bytes']} B state, {TARGET_LIMITS['stack_bytes']} B stack)")
    p.add_argument("--hotspots", action="store_true",
                   help="instructions per (inlined) source function for the worst step of the default configuration")
    p.add_argument("--qemu", action="store_true", help="cross-check the unicorn count against QEMU (mps2-an386)")
    p.add_argument("--hpa", action="store_true",
                   help="also the on-device HPA (wake_hpa.c): instructions of one whole HPA and of the largest "
                        "slice on Cortex-M4F (hard float) and Cortex-M0+ (soft float), RAM, stack (about a minute)")
    p.add_argument("--fs", type=float, default=None, metavar="HZ",
                   help="also the cost at this input rate: the front end's push (csrc/wake_rate.c) beside the "
                        "RTP step, unsplit and split (WAKE_RTP_SPLIT=1: wake_rate_step), the worst input sample and "
                        "the instructions per second, with and without the tremor ahead (J = 5)")
    p.add_argument("--json", metavar="PATH", help="write every number as JSON")
    p.add_argument("--markdown", metavar="PATH", help="write the tables as Markdown")
    p.add_argument("--define", action="append", default=[], metavar="NAME=VALUE",
                   help="build every image with -DNAME=VALUE too (repeatable), e.g. WAKE_RTP_VOLUNTARY_AHEAD=1 for "
                        "the cost of the voluntary motion ahead; --check and the goals still hold the default "
                        "build's figures")
    p.add_argument("--build-dir", metavar="DIR", help="keep the objects and images here (default: a temp dir)")
    p.add_argument("--csrc", metavar="DIR", help="the csrc/ directory (default: next to the package)")
    return p


def _progress(t, level, w, prof):
    print(f"  {t:9s} J={level} {w:5s} Kalman {'active' if prof.kalman else 'inert '}{' ' + prof.build if prof.build else ''}: "
          f"max {prof.max:6,} median {prof.median:8,.0f} min {prof.min:6,} "
          f"static bound {prof.bound.instructions:6,} ({prof.bound.cycles:,} cycles)", file=sys.stderr)


def _measure(args, targets, levels, wavelets):
    """Build, emulate and bound every configuration asked for: (profiles, footprints, hotspots, QEMU
    cross-check, on-device HPA); ``ProfileUnavailable`` without the toolchain or the emulator."""
    toolchain()
    _emulator_modules()
    build_root = Path(args.build_dir) if args.build_dir else Path(tempfile.mkdtemp(prefix="wake-profile-"))
    profiles, footprints = [], {}
    extra = [f"-D{d}" for d in getattr(args, "define", [])]   # --define: every image below
    for t in targets:
        for level in levels:
            # a firmware for level J builds the core with WAKE_RTP_MAX_LEVEL=J (the struct's size)
            image = build_image(t, build_dir=Path(build_root) / f"J{level}", csrc=args.csrc,
                                defs=[f"-DWAKE_RTP_MAX_LEVEL={level}", *extra])
            emu = Emulator(image)
            if level == DEFAULT_LEVEL or t not in footprints:
                footprints[t] = footprint(image, emu)
                for key, (_label, base, defs) in FOOTPRINT_VARIANTS.items():
                    if base == t:  # the same target with some code left out: memory only
                        lean = build_image(t, build_dir=Path(build_root) / f"J{level}-{key}", csrc=args.csrc,
                                           defs=[f"-DWAKE_RTP_MAX_LEVEL={level}", *defs, *extra])
                        footprints[key] = footprint(lean)
            n = args.samples or ((2 * 2**level + 16) if args.quick else None)
            for w in wavelets:
                for kalman in (True, False):
                    prof = profile_configuration(emu, w, level, kalman=kalman, n=n)
                    profiles.append(prof)
                    _progress(t, level, w, prof)
            if level == DEFAULT_LEVEL and DEFAULT_WAVELET in wavelets and t != "m4-Os":
                # the core without the tremor ahead, held to the cost issue's goals
                lean = Emulator(build_image(t, build_dir=Path(build_root) / f"J{level}-lean", csrc=args.csrc,
                                            defs=[f"-DWAKE_RTP_MAX_LEVEL={level}", *LEAN_BUILD[1], *extra]))
                for kalman in (True, False):
                    prof = profile_configuration(lean, DEFAULT_WAVELET, level, kalman=kalman, n=n)
                    prof.build = LEAN_BUILD[0]
                    profiles.append(prof)
                    _progress(t, level, DEFAULT_WAVELET, prof)
    hot = None
    if args.hotspots and DEFAULT_TARGET in targets:
        emu = Emulator(build_image(DEFAULT_TARGET, build_dir=build_root, csrc=args.csrc))
        hot = hotspots(emu, DEFAULT_WAVELET, DEFAULT_LEVEL, kalman=True, n=args.samples)
    qemu = None
    if args.qemu:
        qemu = qemu_crosscheck(DEFAULT_LEVEL, DEFAULT_WAVELET, build_dir=build_root, csrc=args.csrc)
    rate = None
    if args.fs is not None:
        rate = _rate_bounds(args, targets, build_root)
    hpa = None
    if args.hpa:
        from wake.firmware.hpa_cost import HPA_TARGETS, measure_hpa

        hpa = {t: measure_hpa(t, build_dir=build_root, csrc=args.csrc) for t in HPA_TARGETS}
    return profiles, footprints, hot, qemu, hpa, rate


def _rate_bounds(args, targets, build_root) -> dict:
    """target -> {build: bounds for :func:`wake.firmware.rate_cost.rate_lines`} at J = 5, active Kalman.

    Two builds, like with like: the default one (with the tremor ahead) and WAKE_RTP_AHEAD=0.  Each is
    bounded as the 100 Hz firmware builds it (wake_rtp_step, wake_rate_push) and, when the rate needs the
    front end, with -DWAKE_RTP_SPLIT=1 (wake_rate_step, the worst input sample; prepare, finish)."""
    from wake.firmware.wcet import static_bound
    from wake.sampling import decimation_for

    def bound(image, function):
        return static_bound(image, DEFAULT_LEVEL, function=function).instructions

    out = {}
    for t in targets:
        out[t] = {}
        for label, key, extra in (("default", "ahead", []), (LEAN_BUILD[0], "lean", LEAN_BUILD[1])):
            defs = [f"-DWAKE_RTP_MAX_LEVEL={DEFAULT_LEVEL}", *extra]
            image = build_image(t, build_dir=Path(build_root) / "rate" / key, csrc=args.csrc, defs=defs)
            entry = {"step": bound(image, "wake_rtp_step"), "push": None, "split": None}
            if decimation_for(args.fs) > 1 and "wake_rate_push" in image.symbols:
                entry["push"] = bound(image, "wake_rate_push")
                split = build_image(t, build_dir=Path(build_root) / "rate" / f"{key}-split", csrc=args.csrc,
                                    defs=[*defs, "-DWAKE_RTP_SPLIT=1"])
                if "wake_rate_step" in split.symbols:
                    entry["split"] = {"push": bound(split, "wake_rate_push"), "prepare": bound(split, "wake_rtp_prepare"),
                                      "finish": max(bound(split, "wake_rtp_finish"),
                                                    bound(split, "wake_rtp_finish_missing")),
                                      "rate_step": bound(split, "wake_rate_step")}
            out[t][label] = entry
    return out


def _report(profiles, footprints, hot, qemu, hpa):
    """The Markdown lines of the report, the goals missed and the regression ceilings exceeded."""
    cost, mem = markdown_tables(profiles, footprints)
    clocks = ", ".join(f"{k} {v:g} MHz" for k, v in CLOCKS_MHZ.items())
    notes = [
        "measured: instructions per call of wake_rtp_step, counted in unicorn (block hook + capstone; Cortex-M0+ "
        "images run on the Cortex-M4 model, Thumb-1 being a subset of Thumb-2), worst over adversarial inputs; "
        "'steady max' leaves out the first (priming) sample of a stream.",
        "static bound: longest path through wake_rtp_step's control-flow graph and its callees, built from the "
        "image's disassembly, with loop trip counts from the source's `wcet-loop:` annotations (N = 2^J); "
        "inert = the Kalman update (wake_rtpi_kalman_update) not called. Valid for instances of level J.",
        f"cycles: per-instruction Cortex-M4 / Cortex-M0+ timing model, zero wait states (docs/studies/profiling.md), "
        f"applied to the bound's path and to every measured step; µs = bound cycles at {clocks}; the budget is "
        f"one sample period at {SAMPLE_RATE_HZ:g} Hz.",
        "Each level's image is built with -DWAKE_RTP_MAX_LEVEL=J (a firmware for that level).",
        "Memory: the core object alone (arm-none-eabi-size); the taps table (J 2^J int16) is caller-owned.",
    ]
    text = ["## Instructions per sample", "", cost, "", "## Memory (bytes)", "", mem, ""]
    text += ["Notes:", ""] + [f"- {n}" for n in notes] + [""]
    if hot:
        text += [f"## Hotspots of the worst step (Cortex-M4 -O2, J={DEFAULT_LEVEL}, {DEFAULT_WAVELET}, "
                 f"Kalman active, input {hot['input']}, sample {hot['index']}): {hot['total']:,} instructions", ""]
        for key, title in (("phase", "phase"), ("function", "innermost function"), ("line", "source line")):
            rows = hot[key][:12]
            text += [f"| {title} | instructions | share |", "|---|---:|---:|"]
            text += [f"| {name} | {cnt:,} | {100 * share:.1f} % |" for name, cnt, share in rows] + [""]
    if qemu:
        text += [f"QEMU cross-check ({qemu['n']} steps, J={qemu['level']}, {qemu['wavelet']}, input "
                 f"{qemu['input']}): unicorn total {sum(qemu['unicorn']):,}, QEMU total {sum(qemu['qemu']):,}, "
                 f"{'identical per step' if qemu['agree'] else 'DIFFERENT'}.", ""]
    if hpa:
        from wake.firmware.hpa_cost import HPA_GOALS
        from wake.firmware.hpa_cost import report as hpa_report

        m4_bound = max((p.bound.instructions for p in profiles
                        if p.target == DEFAULT_TARGET and p.level == DEFAULT_LEVEL), default=None)
        m4f = hpa["m4f-O2"]
        text += ["## On-device HPA (wake_hpa.c; L = 500, p = 17, J = 5; 5 s windows: the paper's 10 synthetic "
                 "signals, white noise, a 14 Hz full-range tremor)", ""] + hpa_report(hpa) + [""]
        if m4_bound:
            text += [f"RTP step static bound (Cortex-M4 -O2) + largest measured slice (Cortex-M4F): "
                     f"{m4_bound:,} + {m4f['max_slice']:,} = {m4_bound + m4f['max_slice']:,} instructions "
                     f"(goal {HPA_GOALS['step_plus_slice']:,}).", ""]
        text += [f"HPA goals (Cortex-M4F): whole HPA {m4f['whole_max']:,} (goal {HPA_GOALS['whole']:,}); "
                 f"RAM {m4f['ram_hpa']:,} B (goal {HPA_GOALS['ram']:,} B).", ""]
    fails = check_targets(profiles, footprints)
    regressions = check_targets(profiles, footprints, CEILING_LIMITS)
    if any(p.target == DEFAULT_TARGET and p.level == DEFAULT_LEVEL and p.wavelet == DEFAULT_WAVELET
           for p in profiles):
        text += [f"Goals (J={DEFAULT_LEVEL}, {DEFAULT_WAVELET}): "
                 + ("all met." if not fails else "MISSED: " + "; ".join(fails)), "",
                 "Regression ceilings (what --check holds): "
                 + ("all held." if not regressions else "EXCEEDED: " + "; ".join(regressions)), ""]
    return text, fails, regressions


def cli(argv: list[str] | None = None) -> int:
    """``wake profile``: print the cost and memory tables; see ``--help``."""
    args = build_parser().parse_args(argv)
    targets = [t.strip() for t in args.targets.split(",") if t.strip()]
    for t in targets:
        if t not in TARGETS:
            raise ValueError(f"unknown target {t!r}; valid choices: {', '.join(TARGETS)}")
    levels = [DEFAULT_LEVEL] if args.quick else _parse_levels(args.levels)
    wavelets = [DEFAULT_WAVELET] if args.quick else [w.strip() for w in args.wavelets.split(",") if w.strip()]
    if args.fs is not None and not (math.isfinite(args.fs) and 0 < args.fs <= 1e5):
        raise ValueError(f"--fs must lie in (0, 100000] Hz, got {args.fs}")
    try:
        profiles, footprints, hot, qemu, hpa, rate = _measure(args, targets, levels, wavelets)
    except ProfileUnavailable as exc:
        print(f"wake profile: {exc}", file=sys.stderr)
        return 3
    text, fails, regressions = _report(profiles, footprints, hot, qemu, hpa)
    if rate is not None:
        from wake.firmware.rate_cost import rate_lines

        text += rate_lines(args.fs, rate)
    report = "\n".join(text)
    print(report)
    if args.markdown:
        Path(args.markdown).write_text(report)
    if args.json:
        Path(args.json).write_text(json.dumps({
            "profiles": [p.as_dict() for p in profiles],
            "footprint": {t: {**f, "stack_static": f["stack_static"][0] if f["stack_static"] else None,
                              "stack_path": f["stack_static"][1] if f["stack_static"] else None}
                          for t, f in footprints.items()},
            "hotspots": hot,
            "qemu": qemu,
            "hpa": hpa,
            "rate": rate,
            "clocks_mhz": CLOCKS_MHZ, "targets": TARGET_LIMITS, "failed": fails,
            "ceilings": CEILING_LIMITS, "regressions": regressions,
        }, indent=2))
    if args.check and regressions:
        print("wake profile: ceiling exceeded: " + "; ".join(regressions), file=sys.stderr)
        return 1
    if args.check_goals and fails:
        print("wake profile: goal missed: " + "; ".join(fails), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli())
