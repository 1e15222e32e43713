"""Where the on-device HPA's instructions go, per function and per part of the tremor-ahead fit.

Every instruction a Cortex-M4F image of the C HPA (csrc/wake_hpa*.c) executes (built and run as
:mod:`wake.firmware.hpa_cost` does, counted with a block hook and a disassembler so that
condition-failed instructions of an IT block count) is attributed to the innermost function of its
inline chain (``addr2line -i``) and, with the tremor-ahead fit built in, to a part of that fit
(:data:`AHEAD_PARTS`).  The per-function and the per-part counts each sum to the whole run's count.

    python -m wake.firmware.hpa_cost --functions [--ahead] [--sliced] [--json OUT]
"""

from __future__ import annotations

import numpy as np

from wake.firmware.hpa_cost import AHEAD_STEPS, STEP_NAMES, _loaded, _start, build_hpa_image, profile_windows

__all__ = ["AHEAD_PARTS", "function_profile", "function_report"]

#: The parts of the tremor-ahead fit, by function: an instruction counts for the part of the innermost
#: function of its inline chain listed here (the small functions inlined into them count with them:
#: int64_to_float with the FIR, ring_back with the rows).  Any other instruction run while the instance is in one of
#: AHEAD_STEPS is those steps' dispatch ("ahead steps' dispatch": the run loop, the slice cost model,
#: the instance check); the rest is "the HPA's other steps".
AHEAD_PARTS = {
    "ahead_estimate2": "pass: the estimate's 2^J-tap FIR",
    "ahead_estimate1": "pass: the estimate's 2^J-tap FIR",
    "ahead_voluntary8": "pass: the low-bin oscillators",
    "ahead_voluntary4": "pass: the low-bin oscillators",
    "ahead_voluntary2": "pass: the low-bin oscillators",
    "ahead_voluntary1": "pass: the low-bin oscillators",
    "ahead_voluntary": "pass: the low-bin oscillators",
    "ahead_rows": "pass: the row sums",
    "wake_hpa_step_ahead_pass": "pass: the truth, the ring, the blocks",
    "wake_hpa_step_ahead_start": "ahead start: the FIR's taps, the sums cleared",
    "ahead_assemble": "ahead solve: G's rows, the ridge, the held-out sums",
    "ahead_factor": "ahead solve: L D L'",
    "ahead_substitute": "ahead solve: the substitution, the clip",
    "wake_hpa_step_ahead_solve": "ahead solve: the gain, the goal, publish",
}


def function_profile(target="m4f-O2", *, windows=None, build_dir=None, csrc=None, defs=(), sliced=False) -> dict:
    """Where the instructions of one HPA go, per window: per function and per part of the tremor-ahead fit.

    Every executed instruction is attributed to the innermost function of its inline chain
    (``addr2line -i`` on the image's debug information; out-of-line callees such as ``memset`` count
    under their own name) and to a part (:data:`AHEAD_PARTS`, else by the step the instance is in when
    its block starts).  A whole HPA (``wake_hpa_run``), or with ``sliced`` every ``wake_hpa_slice``
    call of a sliced run summed.  Returns ``{"target", "sliced", "rows"}``, a row per window with ``whole``,
    ``samples`` (the window's), ``bins`` (the DFT bins below f_d: the low bins the fit's oscillators
    run), ``functions`` and ``parts`` (name -> instructions; each sums to ``whole``).
    """
    import struct

    from wake.firmware.profile.build import _emulator_modules
    from wake.firmware.profile.scenarios import _inline_chains

    unicorn, capstone = _emulator_modules()
    img = build_hpa_image(target, build_dir=build_dir, csrc=csrc, defs=defs)
    emu = _loaded(img)
    hpa = img.addr("g_hpa")
    phase_at = hpa + emu.read_words(img.addr("g_hpa_phase_offset"), 1)[0]
    bins_at = hpa + emu.read_words(img.addr("g_hpa_bins_offset"), 1)[0]

    def u16(addr):
        return struct.unpack("<H", bytes(emu.uc.mem_read(addr, 2)))[0]

    hits = {}

    def on_block(uc, address, size, _user):
        key = (u16(phase_at), address, size)
        hits[key] = hits.get(key, 0) + 1

    runs = []
    windows = profile_windows() if windows is None else windows
    handle = emu.uc.hook_add(unicorn.UC_HOOK_BLOCK, on_block)
    try:
        for name, x in windows.items():
            _start(emu, img, x)
            hits.clear()  # the counted calls only
            if sliced:
                whole, st = 0, 1
                while st == 1:  # WAKE_HPA_RUNNING
                    st, n, _ = emu.call("wake_hpa_slice", hpa)
                    whole += n
            else:
                _, whole, _ = emu.call("wake_hpa_run", hpa, limit=50_000_000)
            runs.append((name, len(x), whole, u16(bins_at), dict(hits)))
    finally:
        emu.uc.hook_del(handle)
    md = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
    blocks = {}
    for *_, h in runs:
        for _phase, address, size in h:
            if (address, size) not in blocks:
                code = bytes(emu.uc.mem_read(address, size))
                blocks[(address, size)] = [a for a, *_ in md.disasm_lite(code, address)]
    chains = _inline_chains(img, sorted({a for v in blocks.values() for a in v}))
    rows = []
    for name, n, whole, bins, h in runs:
        functions, parts = {}, {}
        for (phase, address, size), count in h.items():
            step = STEP_NAMES[phase] if phase < len(STEP_NAMES) else "?"
            for a in blocks[(address, size)]:
                chain = [f for f, _line in chains.get(a) or [("?", "?")]]
                part = next((AHEAD_PARTS[f] for f in chain if f in AHEAD_PARTS),
                            "ahead steps' dispatch" if step in AHEAD_STEPS else "the HPA's other steps")
                functions[chain[0]] = functions.get(chain[0], 0) + count
                parts[part] = parts.get(part, 0) + count
        rows.append({"window": name, "whole": whole, "samples": n, "bins": bins, "functions": functions,
                     "parts": parts})
    return {"target": target, "sliced": bool(sliced), "rows": rows}


def function_report(*, defs=(), sliced=False, windows=None, build_dir=None, raw=None) -> list[str]:
    """The tables of ``--functions``: per function, and with the tremor-ahead fit per part of it (each part's
    max and median over the windows, per window and per sample of the window), beside the build without it.
    ``raw`` (a dict), if given, receives the :func:`function_profile` results (``"build"``, and with the fit
    ``"without fit"``) with every window's counts."""
    res = function_profile(defs=defs, sliced=sliced, windows=windows, build_dir=build_dir)
    raw = {} if raw is None else raw
    raw["build"] = res
    rows = res["rows"]
    run = "sliced run" if sliced else "whole HPA"

    def stats(key, name):
        v = [r[key].get(name, 0) for r in rows]
        return max(v), float(np.median(v))

    def per_sample(key, name):
        v = [r[key].get(name, 0) / r["samples"] for r in rows]
        return max(v), float(np.median(v))

    names = {f for r in rows for f in r["functions"]}
    lines = [f"| function ({run}, Cortex-M4F, {len(rows)} windows) | max | median |", "|---|---:|---:|"]
    for name in sorted(names, key=lambda f: -stats("functions", f)[0]):
        hi, med = stats("functions", name)
        lines.append(f"| {name} | {hi:,} | {med:,.0f} |")
    whole = [r["whole"] for r in rows]
    lines.append(f"| all | {max(whole):,} | {np.median(whole):,.0f} |")
    if "-DWAKE_HPA_AHEAD=1" not in defs:
        return lines
    parts = [p for p in dict.fromkeys(AHEAD_PARTS.values())] + ["ahead steps' dispatch"]
    worst = max(rows, key=lambda r: r["whole"])
    lines += ["", f"| part of the tremor-ahead fit ({run}, Cortex-M4F) | per window, max / median | "
                  "per sample of the window, max / median |", "|---|---:|---:|"]
    for name in parts:
        hi, med = stats("parts", name)
        s_hi, s_med = per_sample("parts", name)
        lines.append(f"| {name} | {hi:,} / {med:,.0f} | {s_hi:.1f} / {s_med:.1f} |")
    fit = [r["whole"] - r["parts"].get("the HPA's other steps", 0) for r in rows]
    fit_s = [f / r["samples"] for f, r in zip(fit, rows)]
    lines.append(f"| the fit's steps | {max(fit):,} / {np.median(fit):,.0f} | "
                 f"{max(fit_s):.1f} / {np.median(fit_s):.1f} |")
    raw["without fit"] = function_profile(sliced=sliced, windows=windows, build_dir=build_dir)
    plain = {r["window"]: r["whole"] for r in raw["without fit"]["rows"]}
    diff = [r["whole"] - plain[r["window"]] for r in rows]
    rest = [d - f for d, f in zip(diff, fit)]
    lines.append(f"| the HPA's other steps, more than in the build without the fit | {max(rest):,} / "
                 f"{np.median(rest):,.0f} | |")
    lines.append(f"| the fit (with - without) | {max(diff):,} / {np.median(diff):,.0f} | "
                 f"{max(d / r['samples'] for d, r in zip(diff, rows)):.1f} / "
                 f"{np.median([d / r['samples'] for d, r in zip(diff, rows)]):.1f} |")
    lines += ["", f"{run}, with the fit: {max(whole):,} / {np.median(whole):,.0f} (max / median); without: "
                  f"{max(plain.values()):,} / {np.median(list(plain.values())):,.0f}. The largest window "
                  f"({worst['window']}): {worst['whole']:,} instructions, {worst['samples']} samples, "
                  f"{worst['bins']} low bins (DFT bins below f_d); low bins over the windows: "
                  f"{min(r['bins'] for r in rows)} to {max(r['bins'] for r in rows)}."]
    return lines
