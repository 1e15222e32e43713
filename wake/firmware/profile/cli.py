"""Command line of ``wake profile``."""


import argparse
import json
import re
import sys
import tempfile
from pathlib import Path

from .build import (
    CLOCKS_MHZ,
    CPI_RANGE,
    DEFAULT_LEVEL,
    DEFAULT_TARGET,
    DEFAULT_WAVELET,
    SAMPLE_RATE_HZ,
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
                   help=f"exit with status 1 when a target of the default configuration is missed "
                        f"({TARGET_LIMITS['instructions']:,} instructions, {TARGET_LIMITS['state_bytes']} B state, "
                        f"{TARGET_LIMITS['code_bytes']} B code)")
    p.add_argument("--hotspots", action="store_true",
                   help="instructions per (inlined) source function for the worst step of the default configuration")
    p.add_argument("--qemu", action="store_true", help="cross-check the unicorn count against QEMU (mps2-an386)")
    p.add_argument("--json", metavar="PATH", help="write every number as JSON")
    p.add_argument("--markdown", metavar="PATH", help="write the tables as Markdown")
    p.add_argument("--build-dir", metavar="DIR", help="keep the objects and images here (default: a temp dir)")
    p.add_argument("--csrc", metavar="DIR", help="the csrc/ directory (default: next to the package)")
    return p


def cli(argv: list[str] | None = None) -> int:
    """``wake profile``: print the cost and memory tables; see ``--help``."""
    args = build_parser().parse_args(argv)
    targets = [t.strip() for t in args.targets.split(",") if t.strip()]
    for t in targets:
        if t not in TARGETS:
            raise ValueError(f"unknown target {t!r}; valid choices: {', '.join(TARGETS)}")
    levels = [DEFAULT_LEVEL] if args.quick else _parse_levels(args.levels)
    wavelets = [DEFAULT_WAVELET] if args.quick else [w.strip() for w in args.wavelets.split(",") if w.strip()]
    try:
        toolchain()
        _emulator_modules()
        build_root = Path(args.build_dir) if args.build_dir else Path(tempfile.mkdtemp(prefix="wake-profile-"))
        profiles, footprints = [], {}
        for t in targets:
            image = build_image(t, build_dir=build_root, csrc=args.csrc)
            emu = Emulator(image)
            footprints[t] = footprint(image, emu)
            for level in levels:
                if level > emu.max_level:
                    print(f"skipping J={level}: the core is built for levels up to {emu.max_level}", file=sys.stderr)
                    continue
                n = args.samples or ((2 * 2**level + 16) if args.quick else None)
                for w in wavelets:
                    for kalman in (True, False):
                        prof = profile_configuration(emu, w, level, kalman=kalman, n=n)
                        profiles.append(prof)
                        print(f"  {t:9s} J={level} {w:5s} Kalman {'active' if kalman else 'inert '}: "
                              f"max {prof.max:6,} median {prof.median:8,.0f} min {prof.min:6,}",
                              file=sys.stderr)
        hot = None
        if args.hotspots and DEFAULT_TARGET in targets:
            emu = Emulator(build_image(DEFAULT_TARGET, build_dir=build_root, csrc=args.csrc))
            hot = hotspots(emu, DEFAULT_WAVELET, DEFAULT_LEVEL, kalman=True, n=args.samples)
        qemu = None
        if args.qemu:
            qemu = qemu_crosscheck(DEFAULT_LEVEL, DEFAULT_WAVELET, build_dir=build_root, csrc=args.csrc)
    except ProfileUnavailable as exc:
        print(f"wake profile: {exc}", file=sys.stderr)
        return 3
    cost, mem = markdown_tables(profiles, footprints)
    cpi = f"{CPI_RANGE[0]:g}–{CPI_RANGE[1]:g}"
    notes = [
        "Instructions per call of wake_rtp_step, counted in unicorn (Cortex-M4 model; Cortex-M0+ images run "
        "on it, Thumb-1 being a subset of Thumb-2). 'max' includes the first (priming) sample of a stream, "
        "'steady max' leaves it out.",
        f"Microseconds assume {cpi} cycles per instruction (zero-wait-state memory); the budget is one "
        f"sample period at {SAMPLE_RATE_HZ:g} Hz (10 ms).",
        "floor (MAC) = multiply-accumulates per sample: J 2^J + J^2 + J + J + J(J+1)/2 + J.",
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
    fails = check_targets(profiles, footprints)
    if any(p.target == DEFAULT_TARGET and p.level == DEFAULT_LEVEL and p.wavelet == DEFAULT_WAVELET
           for p in profiles):
        text += ["Targets (Cortex-M4 -O2, J=5, sym3): " + ("all met." if not fails else "MISSED: " + "; ".join(fails)),
                 ""]
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
            "cpi_range": CPI_RANGE, "clocks_mhz": CLOCKS_MHZ, "targets": TARGET_LIMITS, "failed": fails,
        }, indent=2))
    if args.check and fails:
        print("wake profile: target missed: " + "; ".join(fails), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli())
