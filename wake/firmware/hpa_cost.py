"""What the on-device HPA (csrc/wake_hpa*.c) costs on a Cortex-M: instructions, RAM, stack.

The HPA and a small harness (``csrc/profile/hpa_harness.c``) are built for
a Cortex-M4F (hard float, ``-mfpu=fpv4-sp-d16``) and a Cortex-M0+ (soft
float) at ``-O2`` with the struct sized for WakeConfig's defaults
(``-DWAKE_HPA_MAX_WINDOW=500 -DWAKE_HPA_MAX_LEVEL=5 -DWAKE_HPA_MAX_ORDER=17
-DWAKE_HPA_MAX_PSD_BINS=64``), and run in unicorn with the block-hook
counter of :mod:`wake.firmware.profile` on a set of 5 s windows: one whole
HPA (``wake_hpa_run``), and every ``wake_hpa_slice`` call of a sliced run.
The largest slice is a measured maximum over those windows; the slicing's
cost model bounds it by design (docs/studies/hpa_c.md).  ``--functions`` attributes
every instruction of a whole HPA to its function and with ``--ahead`` to the
parts of the tremor-ahead fit (:mod:`wake.firmware.hpa_functions`).

    python -m wake.firmware.hpa_cost [--json OUT] [--ahead] [--functions] [--ridge-scale centred] [--gate-cutoff 4]
    python -m wake.firmware.hpa_cost --calibrate [--write | --check]

The slice cost model's constants live in one table, :data:`wake.firmware.hpa_costs.COSTS`;
``--calibrate --write`` measures one piece of every step (budget-1 builds, with and without the tremor-ahead fit) and writes the table, each value
with that measurement beside it, as ``csrc/internal/wake_hpa_costs.h``; ``--calibrate --check`` fails when the
header is not what the table gives (a value edited in one place only).
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["HPA_TARGETS", "HPA_DEFS", "HPA_GOALS", "STEP_NAMES", "AHEAD_STEPS", "build_hpa_image",
           "profile_windows", "measure_hpa", "step_breakdown", "calibrate"]

HPA_TARGETS = {
    "m4f-O2": ("Cortex-M4F, -O2, hard float", ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
                                                "-mfpu=fpv4-sp-d16", "-O2"]),
    "m0plus-O2": ("Cortex-M0+, -O2, soft float", ["-mcpu=cortex-m0plus", "-mthumb", "-O2"]),
}
HPA_DEFS = ["-DWAKE_HPA_MAX_WINDOW=500", "-DWAKE_HPA_MAX_LEVEL=5", "-DWAKE_HPA_MAX_ORDER=17",
            "-DWAKE_HPA_MAX_PSD_BINS=64", "-DWAKE_RTP_MAX_LEVEL=5"]
#: Targets of the issue at L = 500, p = 17, J = 5 (Cortex-M4F): one whole HPA, RTP step + largest slice, RAM.
HPA_GOALS = {"whole": 400_000, "step_plus_slice": 3_000, "ram": 6 * 1024}
#: The steps of the C HPA (csrc/internal/wake_hpa_internal.h), in the order of its enum (wake_hpa_t::phase indexes this).
STEP_NAMES = ("idle", "sums", "lags", "lag end", "Rxx diagonal", "Levinson", "AR spectrum", "cut-off",
              "bin count", "DFT passes", "bin start", "bin slide", "ramp", "Gram", "solve", "ahead start",
              "ahead pass", "ahead solve")
#: The tremor-ahead fit's steps (built with -DWAKE_HPA_AHEAD=1).
AHEAD_STEPS = ("ahead start", "ahead pass", "ahead solve")
#: The HPA's C sources, by concern (csrc/internal/wake_hpa_internal.h); the tremor-ahead fit's module is linked
#: only into a build that uses it (-DWAKE_HPA_AHEAD=1).
HPA_AHEAD_SOURCE = "wake_hpa_ahead.c"

def hpa_sources(src, defs=()) -> tuple:
    """The HPA's sources in ``src`` (every ``wake_hpa*.c``) that a build with the ``-D`` options ``defs`` links."""
    ahead = "-DWAKE_HPA_AHEAD=1" in defs
    return tuple(sorted(p.name for p in Path(src).glob("wake_hpa*.c") if ahead or p.name != HPA_AHEAD_SOURCE))



def build_hpa_image(target="m4f-O2", *, build_dir=None, csrc=None, defs=()):
    """Cross-compile the HPA's sources (one relocatable object), wake_rtp.c and the harness; an :class:`~wake.firmware.profile.build.Image`.

    ``defs`` are extra ``-D`` options (the calibration builds with a slice budget of 1).
    """
    from wake.firmware.profile.build import WARN_FLAGS, Image, run_tool, toolchain
    from wake.firmware.sources import csrc_dir

    if target not in HPA_TARGETS:
        raise ValueError(f"unknown target {target!r}; valid choices: {', '.join(HPA_TARGETS)}")
    src = csrc_dir(csrc, need=("wake_hpa.c", "profile/hpa_harness.c"))
    prof = src / "profile"
    gcc = toolchain()["gcc"]
    out = Path(build_dir) if build_dir else Path(tempfile.mkdtemp(prefix="wake-hpa-"))
    out = out / f"hpa-{target}"
    out.mkdir(parents=True, exist_ok=True)
    flags = HPA_TARGETS[target][1] + ["-ffreestanding", "-g", *HPA_DEFS, *defs]

    def run(cmd):
        run_tool(cmd, out)

    objects = []
    for name in hpa_sources(src, flags):
        obj = name.replace(".c", ".o").replace("wake_hpa", "part_hpa", 1)
        run([gcc, *WARN_FLAGS, "-Wdouble-promotion", "-ffp-contract=off", *flags, "-fstack-usage",
             "-c", str(src / name), "-o", obj])
        objects.append(obj)
    # the HPA as one object (its code size is this object's .text + .rodata)
    run([gcc, *HPA_TARGETS[target][1], "-nostdlib", "-r", *objects, "-o", "wake_hpa.o"])
    run([gcc, *WARN_FLAGS, *flags, "-nostdlib", "-r", *map(str, sorted(src.glob("wake_rtp*.c"))), "-o", "wake_rtp.o"])
    hflags = ["-std=c99", "-Wall", "-Wextra", *flags, "-I", str(src)]
    run([gcc, *hflags, "-c", str(prof / "hpa_harness.c"), "-o", "harness.o"])
    run([gcc, *hflags, "-c", str(prof / "startup.c"), "-o", "startup.o"])
    elf = out / "hpa.elf"
    run([gcc, *HPA_TARGETS[target][1], "-nostdlib", "-ffreestanding", "-T", str(prof / "generic_m.ld"),
         "-L", str(prof), "startup.o", "harness.o", "wake_hpa.o", "wake_rtp.o", "-lc", "-lgcc", "-o", str(elf)])
    # the RTP's cycle model stands in for the integer part; the HPA is reported in instructions
    return Image.read(elf, out / "wake_hpa.o", "m4-O2" if target.startswith("m4") else "m0plus-O2")


def profile_windows(n_synthetic=10):
    """Named 5 s windows at 100 Hz, int16 Q15: the paper's synthetic signals and two degenerate ones."""
    from wake.eval.synthetic import paper_dataset
    from wake.hpa.c_port import quantize_window
    from wake.rtp.full_scale import power_of_two_at_least, robust_peak

    def q15(x):
        return quantize_window(x, power_of_two_at_least(16 * robust_peak(x)))

    out = {}
    for i, s in enumerate(paper_dataset()[:n_synthetic]):
        out[f"synthetic {i + 1}"] = q15(s.measurement[2000:2500])
    rng = np.random.default_rng(0)
    out["white noise, full range"] = rng.integers(-32768, 32768, 500).astype(np.int16)
    t = np.arange(500) / 100.0
    out["tremor at 14 Hz, full range"] = np.rint(32000 * np.sin(2 * np.pi * 14 * t)).astype(np.int16)
    return out


def measure_hpa(target="m4f-O2", *, windows=None, build_dir=None, csrc=None, defs=()) -> dict:
    """Instructions of one whole HPA and of every slice, RAM and stack, on ``target`` (``defs``: extra ``-D``
    options, e.g. ``-DWAKE_HPA_AHEAD=1`` for the tremor-ahead fit)."""
    img = build_hpa_image(target, build_dir=build_dir, csrc=csrc, defs=defs)
    emu = _loaded(img)
    windows = profile_windows() if windows is None else windows
    hpa = img.addr("g_hpa")
    rows = []
    stack = 0
    for name, x in windows.items():
        _start(emu, img, x)
        _, whole, depth = emu.call("wake_hpa_run", hpa, stack=True, limit=50_000_000)
        stack = max(stack, depth)
        # the same window in slices, after a fresh init
        slices, depths = [], []
        _sliced_run(emu, img, x, lambda _step, n, d: (slices.append(n), depths.append(d)), stack=True)
        stack = max(stack, *depths)
        _, apply_n, _ = emu.call("wake_hpa_apply", hpa, img.addr("g_rtp"))
        rows.append({"window": name, "whole": whole, "slices": len(slices), "max_slice": max(slices),
                     "sliced_total": sum(slices), "apply": apply_n})
    size = img.symbols
    return {
        "target": target, "label": HPA_TARGETS[target][0], "rows": rows,
        "whole_max": max(r["whole"] for r in rows), "whole_median": float(np.median([r["whole"] for r in rows])),
        "max_slice": max(r["max_slice"] for r in rows), "slices_max": max(r["slices"] for r in rows),
        "apply_max": max(r["apply"] for r in rows),
        "ram_hpa": size["g_hpa"][1], "ram_rtp": size["g_rtp"][1], "stack": stack,
        "code_hpa": _code_size(img),
    }


def _loaded(img):
    """An emulator on ``img`` with the default filter bank (sym3, J = 5) in ``g_taps``."""
    from wake.firmware.profile.emulator import Emulator
    from wake.rtp.qformat import quantize_taps
    from wake.wavelets import filter_bank_taps

    emu = Emulator(img)
    emu.uc.mem_write(img.addr("g_taps"), quantize_taps(filter_bank_taps("sym3", 5)).astype("<i2").tobytes())
    return emu


def _start(emu, img, x):
    """A fresh instance (default configuration) started on the window ``x``."""
    emu.uc.mem_write(img.addr("g_window"), np.asarray(x, dtype="<i2").tobytes())
    st, _, _ = emu.call("hpa_profile_init", count=False)
    if st != 0:
        raise RuntimeError(f"hpa_profile_init failed in the image (status {st})")
    emu.call("hpa_profile_start", len(x), count=False)


def _sliced_run(emu, img, x, record, *, stack=False):
    """Start on ``x`` and slice to the end; ``record(step, instructions, stack_bytes)`` per slice."""
    import struct

    hpa = img.addr("g_hpa")
    phase_at = hpa + emu.read_words(img.addr("g_hpa_phase_offset"), 1)[0]
    _start(emu, img, x)
    while True:
        step = struct.unpack("<H", bytes(emu.uc.mem_read(phase_at, 2)))[0]
        st, n, depth = emu.call("wake_hpa_slice", hpa, stack=stack)
        record(STEP_NAMES[step], n, depth)
        if st != 1:  # WAKE_HPA_RUNNING
            return


def step_breakdown(target="m4f-O2", window="synthetic 1", *, build_dir=None, csrc=None, defs=()) -> dict:
    """Where one sliced HPA goes: instructions and largest slice per step (a slice counts for the step it starts in)."""
    img = build_hpa_image(target, build_dir=build_dir, csrc=csrc, defs=defs)
    emu = _loaded(img)
    out = {}

    def record(step, n, _stack):
        row = out.setdefault(step, {"slices": 0, "instructions": 0, "max_slice": 0})
        row["slices"] += 1
        row["instructions"] += n
        row["max_slice"] = max(row["max_slice"], n)

    _sliced_run(emu, img, profile_windows()[window], record)
    return out


def calibrate(target="m4f-O2", *, windows=None, build_dir=None, csrc=None, defs=()) -> dict:
    """Instructions of single pieces of work, per step, for the slice cost model in wake_hpa.c.

    The HPA is built with a slice budget of 1, so each wake_hpa_slice() call
    does one loop item or one indivisible step; every count includes the
    slice's fixed entry cost (the instance check).
    """
    img = build_hpa_image(target, build_dir=build_dir, csrc=csrc, defs=["-DWAKE_HPA_SLICE_BUDGET=1", *defs])
    emu = _loaded(img)
    counts = {}
    windows = profile_windows() if windows is None else windows
    for x in windows.values():
        _sliced_run(emu, img, x, lambda step, n, _stack: counts.setdefault(step, []).append(n))
    return {step: {"pieces": len(v), "median": float(np.median(v)), "max": int(max(v))} for step, v in counts.items()}


def _code_size(img):
    from wake.firmware.profile.report import section_sizes

    sizes = section_sizes(img.core_object)
    return None if sizes is None else sizes[".text"] + sizes[".rodata"]


def report(results: dict, rtp_step_bound: int | None = None) -> list[str]:
    lines = ["| target | whole HPA (max / median) | slices | largest slice | apply | HPA RAM | RTP RAM | stack | HPA code |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results.values():
        lines.append(f"| {r['label']} | {r['whole_max']:,} / {r['whole_median']:,.0f} | {r['slices_max']} | "
                     f"{r['max_slice']:,} | {r['apply_max']:,} | {r['ram_hpa']:,} B | {r['ram_rtp']:,} B | "
                     f"{r['stack']} B | {r['code_hpa']:,} B |")
    return lines


def setting_defs(ahead=False, ridge_scale="gram", gate_cutoff=None) -> list:
    """The ``-D`` options of a build with the tremor-ahead fit (``ahead``) and the profiling harness's
    configuration at ``ridge_scale`` and ``gate_cutoff`` (csrc/profile/hpa_harness.c)."""
    from wake.config import RIDGE_SCALES

    defs = ["-DWAKE_HPA_AHEAD=1"] if ahead else []
    if ridge_scale != "gram":
        defs.append(f"-DHPA_PROFILE_RIDGE_SCALE={RIDGE_SCALES.index(ridge_scale)}")
    if gate_cutoff is not None:
        defs.append(f"-DHPA_PROFILE_GATE_CUTOFF={float(gate_cutoff)!r}f")
    return defs


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Cortex-M cost of the on-device HPA")
    ap.add_argument("--json", help="write the figures here (with --functions: every window's counts)")
    ap.add_argument("--check", action="store_true", help="exit 1 when a Cortex-M4F target is missed (with "
                    "--calibrate: when csrc/internal/wake_hpa_costs.h is not what COSTS gives)")
    ap.add_argument("--breakdown", metavar="WINDOW", nargs="?", const="synthetic 1",
                    help="print where one sliced HPA goes, per step, on Cortex-M4F (default window: synthetic 1)")
    ap.add_argument("--calibrate", action="store_true",
                    help="print the instructions of single pieces of work per step (budget-1 build), Cortex-M4F; "
                         "with --write: write them and the cost table (COSTS) as csrc/internal/wake_hpa_costs.h; "
                         "with --check: exit 1 when that header is not the table's")
    ap.add_argument("--write", action="store_true", help="with --calibrate: write csrc/internal/wake_hpa_costs.h")
    ap.add_argument("--ahead", action="store_true",
                    help="build the HPA with its tremor-ahead fit (-DWAKE_HPA_AHEAD=1)")
    ap.add_argument("--functions", action="store_true",
                    help="print the instructions of one whole HPA per function on Cortex-M4F, max / median over the "
                         "windows; with --ahead also per part of the tremor-ahead fit")
    ap.add_argument("--sliced", action="store_true",
                    help="with --functions: count a sliced run (every wake_hpa_slice call) instead of wake_hpa_run")
    ap.add_argument("--ridge-scale", choices=("gram", "centred"), default="gram",
                    help="the HPA's ridge_scale (WakeConfig.ridge_scale; default gram)")
    ap.add_argument("--gate-cutoff", type=float, default=None,
                    help="the HPA's gate_cutoff in Hz (WakeConfig.gate_cutoff; read with --ahead; default none)")
    args = ap.parse_args(argv)
    defs = setting_defs(args.ahead, args.ridge_scale, args.gate_cutoff)
    if args.functions:
        from wake.firmware.hpa_functions import function_report

        raw = {}
        print("\n".join(function_report(defs=defs, sliced=args.sliced, raw=raw)))
        if args.json:
            Path(args.json).write_text(json.dumps(raw, indent=1))
        return 0
    if args.calibrate and (args.check or args.write):
        from wake.firmware.hpa_costs import COSTS, COSTS_HEADER, check_costs_header, write_costs_header

        if args.write:
            print(f"wrote {write_costs_header()}")
        problems = check_costs_header()
        for p in problems:
            print(f"stale: {p}")
        print(f"{COSTS_HEADER}: {'stale' if problems else 'the cost table COSTS'} ({len(COSTS)} constants)")
        return 1 if problems else 0
    if args.breakdown or args.calibrate:
        if args.breakdown:
            rows = step_breakdown(window=args.breakdown, defs=defs)
            total = sum(r["instructions"] for r in rows.values())
            print(f"| step ({args.breakdown}, Cortex-M4F, sliced) | slices | instructions | share | largest slice |")
            print("|---|---:|---:|---:|---:|")
            for step, r in rows.items():
                print(f"| {step} | {r['slices']} | {r['instructions']:,} | {100 * r['instructions'] / total:.0f} % | "
                      f"{r['max_slice']:,} |")
            print(f"| all | {sum(r['slices'] for r in rows.values())} | {total:,} | 100 % | "
                  f"{max(r['max_slice'] for r in rows.values()):,} |")
        if args.calibrate:
            print("| step (one piece per slice, Cortex-M4F) | pieces | median | max |")
            print("|---|---:|---:|---:|")
            for step, r in calibrate(defs=defs).items():
                print(f"| {step} | {r['pieces']:,} | {r['median']:,.0f} | {r['max']:,} |")
        return 0
    res = {t: measure_hpa(t, defs=defs) for t in HPA_TARGETS}
    print("\n".join(report(res)))
    m4 = res["m4f-O2"]
    print(f"\nCortex-M4F targets: whole HPA {m4['whole_max']:,} <= {HPA_GOALS['whole']:,}; "
          f"HPA RAM {m4['ram_hpa']:,} B <= {HPA_GOALS['ram']:,} B; largest slice {m4['max_slice']:,} "
          f"(+ the RTP step's bound, see wake profile) vs {HPA_GOALS['step_plus_slice']:,}")
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=1))
    ok = m4["whole_max"] <= HPA_GOALS["whole"] and m4["ram_hpa"] <= HPA_GOALS["ram"]
    return 0 if ok or not args.check else 1


if __name__ == "__main__":
    raise SystemExit(main())
