"""Footprint, stack depth, the QEMU cross-check and the Markdown report."""

from __future__ import annotations

import functools
import re
import shutil
import subprocess
from pathlib import Path

from .build import (
    CLOCKS_MHZ,
    DEFAULT_LEVEL,
    DEFAULT_TARGET,
    DEFAULT_WAVELET,
    FOOTPRINT_VARIANTS,
    LEAN_BUILD,
    SAMPLE_RATE_HZ,
    TARGET_LIMITS,
    TARGETS,
    Image,
    ProfileUnavailable,
    _emulator_modules,
    build_image,
    toolchain,
)
from .emulator import Emulator
from .scenarios import adversarial_inputs, fitted_parameters

# ---------------------------------------------------------------------------
# Footprint
# ---------------------------------------------------------------------------

def section_sizes(obj) -> dict | None:
    """Bytes of ``.text``, ``.rodata``, ``.data`` and ``.bss`` of an object file (subsections summed);
    None without ``arm-none-eabi-size``."""
    tools = toolchain()
    if not tools["size"]:
        return None
    sizes = dict.fromkeys((".text", ".rodata", ".data", ".bss"), 0)
    proc = subprocess.run([tools["size"], "-A", str(obj)], capture_output=True, text=True, check=True)
    for line in proc.stdout.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].startswith(".") and parts[1].isdigit():
            base = "." + parts[0].split(".")[1]
            if base in sizes:
                sizes[base] += int(parts[1])
    return sizes


def footprint(image: Image, emu: Emulator | None = None):
    """Sizes of the core object and the worst-case stack of ``wake_rtp_step``."""
    sizes = section_sizes(image.core_object) or dict.fromkeys((".text", ".rodata", ".data", ".bss"), 0)
    emu = emu or Emulator(image)
    stack = stack_depth(image.callgraph, "wake_rtp_step") if image.callgraph else None
    return {
        "text": sizes[".text"], "rodata": sizes[".rodata"], "data": sizes[".data"], "bss": sizes[".bss"],
        "code": sizes[".text"] + sizes[".rodata"],
        "state": emu.sizeof_state, "max_level": emu.max_level, "p_frac": emu.p_frac,
        "stack_static": stack,
    }


def stack_depth(ci_path, root):
    """Worst-case stack of ``root`` from a gcc ``-fcallgraph-info=su`` file.

    Sums the frames along every call path (the graph of the core has no
    recursion); an external callee (no frame size) counts as 0 and is
    listed in the result.  Returns ``(bytes, path, externals)``.
    """
    text = Path(ci_path).read_text()
    frames, edges = {}, {}

    def short(title):
        return title.rsplit(":", 1)[-1]

    for m in re.finditer(r'node: \{ title: "([^"]+)" label: "([^"]*)"', text):
        name = short(m.group(1))
        sz = re.search(r"\\n(\d+) bytes", m.group(2))
        if sz or name not in frames:       # a module's definition wins over another's external declaration
            frames[name] = int(sz.group(1)) if sz else None
    for m in re.finditer(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', text):
        edges.setdefault(short(m.group(1)), set()).add(short(m.group(2)))
    externals = set()

    @functools.lru_cache(maxsize=None)
    def worst(fn):
        own = frames.get(fn)
        if own is None:
            externals.add(fn)
            own = 0
        best, path = 0, ()
        for callee in sorted(edges.get(fn, ())):
            d, p = worst(callee)
            if d > best:
                best, path = d, p
        return own + best, (fn,) + path

    depth, path = worst(root)
    return depth, list(path), sorted(externals)


# ---------------------------------------------------------------------------
# Cross-check against QEMU
# ---------------------------------------------------------------------------

def qemu_crosscheck(level=5, wavelet="sym3", *, n=48, kind="random", build_dir=None, csrc=None,
                    qemu="qemu-system-arm", timeout=120):
    """Count the same steps in unicorn and in QEMU (mps2-an386, Cortex-M4).

    One image (Cortex-M4 -O2, linked for the AN386 memory map) runs
    stand-alone under QEMU with an instruction-per-block exec trace; the
    configuration block is loaded with ``-device loader``.  Instructions
    from the entry of ``wake_rtp_step`` to the instruction it returns to are
    counted per call and compared with the unicorn block-hook counts of the
    same image, parameters and inputs.  Returns a dict with both lists.
    """
    exe = shutil.which(qemu)
    if exe is None:
        raise ProfileUnavailable(f"{qemu} not found (Debian/Ubuntu: apt-get install qemu-system-arm)")
    image = build_image("m4-O2", board="mps2-an386", build_dir=build_dir, csrc=csrc)
    emu = Emulator(image)
    params = fitted_parameters(wavelet, level, kalman=True, formats=emu.formats)
    x = adversarial_inputs(level, n, measurement=params["measurement"])[kind]
    update_at = n // 2
    blob = emu.write_config(params, x, update_at)
    # unicorn
    emu.init()
    ours = []
    for i, sample in enumerate(x):
        if i == update_at:
            emu.set_weights()
        ours.append(emu.step(int(sample), out_index=i)[1])
    # QEMU
    work = image.elf.parent
    cfg = work / "config.bin"
    cfg.write_bytes(blob)
    log = work / "qemu-exec.log"
    version = _qemu_version(exe)
    one_insn = (["-accel", "tcg,one-insn-per-tb=on"] if version >= (8, 1) else ["-singlestep"])
    cmd = [exe, "-M", "mps2-an386", "-cpu", "cortex-m4", "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", "-kernel", str(image.elf),
           "-device", f"loader,file={cfg},addr={image.addr('g_profile_config'):#x}",
           *one_insn, "-d", "exec,nochain", "-D", str(log)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise RuntimeError(f"QEMU exited with status {proc.returncode}: {proc.stderr.strip()}")
    entry = image.addr("wake_rtp_step")
    returns = _call_return_addresses(image, "main", entry)
    theirs = []
    counting = False
    pat = re.compile(r"^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/")
    with open(log) as fh:
        for line in fh:
            m = pat.match(line)
            if not m:
                continue
            pc = int(m.group(1), 16)
            if pc == entry and not counting:
                counting, cnt = True, 0
            elif counting and pc in returns:
                theirs.append(cnt)
                counting = False
            if counting:
                cnt += 1
    return {"level": level, "wavelet": wavelet, "input": kind, "n": n, "unicorn": ours, "qemu": theirs,
            "qemu_version": ".".join(map(str, version)), "one_insn_option": one_insn[-1],
            "agree": ours == theirs}


def _qemu_version(exe):
    out = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout
    m = re.search(r"version (\d+)\.(\d+)", out)
    return (int(m.group(1)), int(m.group(2))) if m else (0, 0)


def _call_return_addresses(image: Image, caller, callee):
    """Addresses right after every ``bl callee`` in ``caller``."""
    _, capstone = _emulator_modules()
    start, size, _ = image.symbols[caller]
    data = None
    for name, addr, sz, _flags, off in image.sections:
        if addr <= start < addr + sz and name == ".text":
            raw = image.elf.read_bytes()
            data = raw[off + start - addr: off + start - addr + size]
    md = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
    out = set()
    for ins in md.disasm(data, start):
        if ins.mnemonic == "bl" and ins.op_str.lstrip("#").startswith("0x") and \
                int(ins.op_str.lstrip("#"), 16) == callee:
            out.add(ins.address + ins.size)
    if not out:
        raise RuntimeError(f"no call to {callee:#x} found in {caller}")
    return out


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

def _core(target):
    return "m0plus" if target.startswith("m0") else "m4"


def markdown_tables(profiles, footprints):
    """The cost table (measured beside the static bound) and the memory table, as Markdown."""
    budget_us = 1e6 / SAMPLE_RATE_HZ
    lines = [
        "| target | J | wavelet | Kalman | measured max | steady max | median | static bound | bound / measured "
        "| cycles measured max | cycles bound | clock | µs bound | % of 10 ms |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for p in profiles:
        b = p.bound
        mhz = CLOCKS_MHZ[_core(p.target)]
        us = b.cycles / mhz if b else float("nan")
        lines.append(
            f"| {TARGETS[p.target][0]}{', ' + p.build if getattr(p, 'build', '') else ''} | {p.level} | {p.wavelet} | {'active' if p.kalman else 'inert'} "
            f"| {p.max:,} | {p.steady_max:,} | {p.median:,.0f} | {b.instructions:,} | {b.instructions / p.max:.3f} "
            f"| {p.max_cycles:,} | {b.cycles:,} | {mhz:g} MHz | {us:.1f} | {100 * us / budget_us:.2f} |")
    mem = [
        "| target | .text | .rodata | .data | .bss | code total | sizeof(wake_rtp_t) | stack of step "
        "(call graph) | stack of step (measured) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for t, f in footprints.items():
        measured = max((p.stack_bytes for p in profiles if p.target == t), default=None)
        static = f["stack_static"][0] if f["stack_static"] else "n/a"
        label = TARGETS[t][0] if t in TARGETS else FOOTPRINT_VARIANTS[t][0]
        mem.append(f"| {label} | {f['text']:,} | {f['rodata']} | {f['data']} | {f['bss']} | "
                   f"{f['code']:,} | {f['state']} (MAX_LEVEL {f['max_level']}) | {static} | "
                   f"{measured if measured is not None else 'n/a'} |")
    return "\n".join(lines), "\n".join(mem)


#: Static bounds the limits name: key -> (build, target, Kalman active); "" is the default build.
BOUND_KEYS = {
    "bound_m4_active": ("", "m4-O2", True), "bound_m4_inert": ("", "m4-O2", False),
    "bound_m0plus_active": ("", "m0plus-O2", True),
    "lean_bound_m4_active": (LEAN_BUILD[0], "m4-O2", True), "lean_bound_m4_inert": (LEAN_BUILD[0], "m4-O2", False),
    "lean_bound_m0plus_active": (LEAN_BUILD[0], "m0plus-O2", True),
}
#: Code sizes the limits name: key -> footprint (Cortex-M4 -Os, with and without the tremor ahead).
CODE_KEYS = {"code_bytes": "m4-Os", "lean_code_bytes": "m4-Os-no-ahead"}


def _bound_fails(profiles, L):
    """The static-bound part of :func:`check_targets`."""
    fails = []
    dflt = {(getattr(p, "build", ""), p.target, p.kalman): p for p in profiles
            if p.level == DEFAULT_LEVEL and p.wavelet == DEFAULT_WAVELET}
    if ("", DEFAULT_TARGET, True) not in dflt:
        fails.append(f"the default configuration ({DEFAULT_TARGET}, J={DEFAULT_LEVEL}, {DEFAULT_WAVELET}) "
                     "was not profiled")
    for key, (build, target, kalman) in BOUND_KEYS.items():
        p = dflt.get((build, target, kalman))
        if p is None or key not in L:
            continue
        what = f"Kalman {'active' if kalman else 'inert'}" + (f", {build}" if build else "")
        core = "Cortex-M4" if target.startswith("m4") else "Cortex-M0+"
        if p.bound.instructions > L[key]:
            fails.append(f"{core} -O2 static bound, {what}: {p.bound.instructions:,} > {L[key]:,}")
        if target == DEFAULT_TARGET and p.bound.instructions > (1 + L["bound_gap"]) * p.max:
            fails.append(f"Cortex-M4 -O2, {what}: bound {p.bound.instructions:,} is more than "
                         f"{100 * L['bound_gap']:g} % above the measured worst {p.max:,}")
    return fails


def check_targets(profiles, footprints, limits=None):
    """Failed targets of the default configuration, as messages (empty: all met).

    Any configuration whose measured worst step exceeds its static bound fails too.

    Parameters
    ----------
    limits : dict, optional
        ``TARGET_LIMITS`` (the goals, default) or ``CEILING_LIMITS`` (the regression ceilings CI holds);
        a key it does not hold is not checked.
    """
    L = TARGET_LIMITS if limits is None else limits
    fails = []
    for p in profiles:
        if p.bound and (p.max > p.bound.instructions or p.max_cycles > p.bound.cycles):
            fails.append(f"{p.target} J={p.level} {p.wavelet} Kalman {'active' if p.kalman else 'inert'}: measured "
                         f"{p.max:,} instructions / {p.max_cycles:,} cycles exceed the static bound "
                         f"{p.bound.instructions:,} / {p.bound.cycles:,}")
    fails += _bound_fails(profiles, L)
    f = footprints.get(DEFAULT_TARGET)
    if f is not None:
        if f["state"] > L["state_bytes"]:
            fails.append(f"sizeof(wake_rtp_t) = {f['state']} B > {L['state_bytes']} B")
        stack = f["stack_static"][0] if f["stack_static"] else None
        if stack is not None and stack > L["stack_bytes"]:
            fails.append(f"stack of wake_rtp_step {stack} B > {L['stack_bytes']} B")
        lean = footprints.get("m4-O2-no-ahead")
        if lean is not None and f["state"] - lean["state"] > L["ahead_state_bytes"]:
            fails.append(f"state of the tremor ahead {f['state'] - lean['state']} B > {L['ahead_state_bytes']} B")
    for key, name in CODE_KEYS.items():
        f = footprints.get(name)
        if f is not None and key in L and f["code"] > L[key]:
            lean = footprints.get("m4-Os-no-kalman")
            note = (f" ({lean['code']:,} B built with WAKE_RTP_KALMAN=0, for firmware that keeps the Kalman inert)"
                    if lean is not None and key == "code_bytes" else "")
            build = ", WAKE_RTP_AHEAD=0" if key.startswith("lean") else ""
            fails.append(f"code (Cortex-M4 -Os{build}) {f['code']:,} B > {L[key]:,} B{note}")
    return fails
