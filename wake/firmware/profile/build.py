"""Cross-compilation of the core into a bare-metal image, and a minimal ELF reader."""

from __future__ import annotations

import shutil
import struct
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from wake.firmware import sources
from wake.firmware.sources import firmware_entries

TARGETS = {
    "m4-O2": ("Cortex-M4, -O2", ["-mcpu=cortex-m4", "-mthumb", "-O2"]),
    "m4-Os": ("Cortex-M4, -Os", ["-mcpu=cortex-m4", "-mthumb", "-Os"]),
    "m0plus-O2": ("Cortex-M0+, -O2", ["-mcpu=cortex-m0plus", "-mthumb", "-O2"]),
}
#: Builds whose memory is reported beside the targets': key -> (label, target, extra defines).
#: Firmware whose Kalman stays inert (the default) can leave the covariance code out.
FOOTPRINT_VARIANTS = {
    "m4-Os-no-kalman": ("Cortex-M4, -Os, WAKE_RTP_KALMAN=0", "m4-Os", ["-DWAKE_RTP_KALMAN=0"]),
    "m4-O2-no-ahead": ("Cortex-M4, -O2, WAKE_RTP_AHEAD=0", "m4-O2", ["-DWAKE_RTP_AHEAD=0"]),
    "m4-Os-no-ahead": ("Cortex-M4, -Os, WAKE_RTP_AHEAD=0", "m4-Os", ["-DWAKE_RTP_AHEAD=0"]),
}
#: The core without the tremor ahead (issue 32), ``(name, defines)``: the voluntary core the cost issue's
#: goals were set for (its object code is the one before the tremor ahead, byte for byte).  Its step is
#: profiled beside the default build's for the default configuration on the -O2 targets.
LEAN_BUILD = ("WAKE_RTP_AHEAD=0", ["-DWAKE_RTP_AHEAD=0"])
#: The configuration the targets apply to.
DEFAULT_TARGET, DEFAULT_LEVEL, DEFAULT_WAVELET = "m4-O2", 5, "sym3"
#: Targets for the default configuration (J = 5, sym3).  The default build (with the tremor ahead): the
#: static bound (instructions) of wake_rtp_step on Cortex-M4 -O2 with the Kalman active <= 650 and the
#: tremor ahead's state <= 256 B per channel (issue 32), sizeof(wake_rtp_t) and the stack of step.  The
#: build without it (``lean_*``, LEAN_BUILD): the cost issue's goals, bounds on Cortex-M4 -O2 (active /
#: inert) and Cortex-M0+ -O2 (active) and code at M4 -Os.  Both: the largest gap between the M4 bound and
#: the measured worst case.
TARGET_LIMITS = {"bound_m4_active": 650, "ahead_state_bytes": 256, "state_bytes": 512, "stack_bytes": 200,
                 "bound_gap": 0.05, "lean_bound_m4_active": 800, "lean_bound_m4_inert": 450,
                 "lean_bound_m0plus_active": 2000, "lean_code_bytes": 3072}
#: Regression ceilings that CI enforces with ``--check``: the figures of the current core (J=5, sym3) plus a
#: little room for compiler versions.  Default build: bound M4 -O2 599 active / 453 inert, M0+ -O2 2,031
#: active, 3,728 B at M4 -Os, 464 B state (88 B of it the tremor ahead), 128 B stack; without the tremor
#: ahead: 493 / 348, 1,429, 3,060 B (unchanged).  The goals above are reported as met or missed beside them
#: and fail the run only with ``--check-goals`` (all met; see docs/studies/profiling.md).
CEILING_LIMITS = {"bound_m4_active": 620, "bound_m4_inert": 475, "bound_m0plus_active": 2100, "code_bytes": 3850,
                  "ahead_state_bytes": 96, "state_bytes": 512, "stack_bytes": 200, "bound_gap": 0.07,
                  "lean_bound_m4_active": 520, "lean_bound_m4_inert": 375, "lean_bound_m0plus_active": 1500,
                  "lean_code_bytes": 3200}

#: Warning flags of csrc/Makefile: the core must build clean with them.
WARN_FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wsign-conversion", "-pedantic", "-Werror"]
#: Clock per core for the microsecond columns (cycles come from wake.firmware.wcet.CYCLE_MODELS).
CLOCKS_MHZ = {"m4": 64.0, "m0plus": 16.0}
SAMPLE_RATE_HZ = 100.0

PROFILE_MAGIC = 0x5052464C
INFO_MAGIC = 0x494E464F
NEVER = 0xFFFFFFFF
STACK_PAINT = 0xCD
STACK_PROBE = 4096

INPUT_KINDS = ("silence", "square_nyquist", "square_window", "steps", "spikes", "random", "synthetic")


class ProfileUnavailable(RuntimeError):
    """A tool the profiler needs is missing (compiler, unicorn, capstone, sources)."""


# ---------------------------------------------------------------------------
# Tools and sources
# ---------------------------------------------------------------------------

def csrc_dir(path=None) -> Path:
    """The C sources with the profiling harness (installed with the package, or ``path``)."""
    try:
        return sources.csrc_dir(path, need=("profile/harness.c", "profile/startup.c"))
    except sources.SourcesUnavailable as exc:
        raise ProfileUnavailable(str(exc)) from None


def toolchain(prefix="arm-none-eabi-"):
    """Paths of gcc, size, addr2line; raises ProfileUnavailable when gcc is missing."""
    gcc = shutil.which(prefix + "gcc")
    if gcc is None:
        raise ProfileUnavailable(
            f"{prefix}gcc not found: install the Arm GNU toolchain (Debian/Ubuntu: "
            "apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)")
    return {"gcc": gcc, "size": shutil.which(prefix + "size"), "addr2line": shutil.which(prefix + "addr2line")}


def _emulator_modules():
    try:
        import capstone
        import unicorn
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ProfileUnavailable(
            f"{exc.name} is not installed: pip install unicorn capstone "
            "(or pip install \".[profile]\" in a wake source tree)") from None
    return unicorn, capstone


# ---------------------------------------------------------------------------
# Minimal ELF32 (little-endian) reader: loadable bytes and symbols
# ---------------------------------------------------------------------------

@dataclass
class Image:
    """A linked profiling image and what was built with it."""

    elf: Path
    core_object: Path
    target: str
    callgraph: Path | None = None
    source: Path | None = None  #: the core's C source it was built from
    sections: list = field(default_factory=list)  #: (name, addr, size, flags, offset)
    segments: list = field(default_factory=list)  #: (vaddr, data, memsz)
    symbols: dict = field(default_factory=dict)  #: name -> (addr, size, type)
    #: every function symbol (addr, size, name): two modules' static functions may share a name
    function_symbols: list = field(default_factory=list)

    @classmethod
    def read(cls, elf, core_object, target, callgraph=None):
        img = cls(Path(elf), Path(core_object), target, Path(callgraph) if callgraph else None)
        raw = img.elf.read_bytes()
        if raw[:4] != b"\x7fELF" or raw[4] != 1 or raw[5] != 1:
            raise ValueError(f"{elf} is not a little-endian ELF32 file")
        (phoff, shoff) = struct.unpack_from("<II", raw, 0x1C)
        (phentsize, phnum, shentsize, shnum, shstrndx) = struct.unpack_from("<HHHHH", raw, 0x2A)
        for k in range(phnum):
            p_type, p_off, p_vaddr, _p_paddr, p_filesz, p_memsz = struct.unpack_from("<6I", raw, phoff + k * phentsize)
            if p_type == 1 and p_memsz:
                img.segments.append((p_vaddr, raw[p_off:p_off + p_filesz], p_memsz))
        shdrs = [struct.unpack_from("<10I", raw, shoff + k * shentsize) for k in range(shnum)]
        shstr = shdrs[shstrndx]

        def name_at(tab, off):
            start = tab[4] + off
            return raw[start:raw.index(b"\0", start)].decode()

        for sh in shdrs:
            img.sections.append((name_at(shstr, sh[0]), sh[3], sh[5], sh[2], sh[4]))
        for sh in shdrs:
            if sh[1] != 2:  # SHT_SYMTAB
                continue
            strtab = shdrs[sh[6]]
            for k in range(sh[5] // 16):
                st_name, value, size, info, _other, shndx = struct.unpack_from("<IIIBBH", raw, sh[4] + 16 * k)
                if st_name == 0 or shndx == 0:
                    continue
                name = name_at(strtab, st_name)
                kind = info & 0xF
                if kind == 2:  # STT_FUNC: clear the Thumb bit
                    value &= ~1
                    if size:
                        img.function_symbols.append((value, size, name))
                if name not in img.symbols or kind in (1, 2):
                    img.symbols[name] = (value, size, kind)
        return img

    def addr(self, name):
        try:
            return self.symbols[name][0]
        except KeyError:
            raise KeyError(f"symbol {name!r} is not in {self.elf.name}") from None

    def functions(self):
        """Sorted (start, end, name) of the function symbols."""
        return sorted({(a, a + s, n) for a, s, n in self.function_symbols})


def _core_flags(target):
    return TARGETS[target][1] + ["-ffreestanding"]


def run_tool(cmd, cwd) -> None:
    """Run one compiler or linker command in ``cwd``; ``RuntimeError`` with its output when it fails."""
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"command failed: {' '.join(map(str, cmd))}\n{proc.stdout}{proc.stderr}")


#: Compilers the core can be built with.  clang targets arm-none-eabi with newlib's headers
#: (``string.h``); the harness, the start-up code and the link always use arm-none-eabi-gcc.
COMPILERS = ("gcc", "clang")
NEWLIB_INCLUDE = "/usr/lib/arm-none-eabi/include"


def clang_command():
    """The clang on PATH: ``clang``, else Debian's versioned ``clang-14`` (the one CI installs); None without."""
    import shutil

    return shutil.which("clang") or shutil.which("clang-14")


def rtp_sources(src):
    """The RTP's modules in ``src`` (csrc/wake_rtp*.c), the core step's first; every one compiles in every
    configuration, the link keeps the entries of the configuration's features (firmware_entries)."""
    return sorted(Path(src).glob("wake_rtp*.c"), key=lambda p: (p.name != "wake_rtp.c", p.name))


def _defined_functions(obj):
    """The global functions an object defines (arm-none-eabi-nm), or None without the tool."""
    nm = shutil.which("arm-none-eabi-nm")
    if nm is None:
        return None
    return [line.split()[-1] for line in subprocess.run([nm, "-g", "--defined-only", str(obj)],
                                                        capture_output=True, text=True, check=True).stdout.splitlines()
            if line.split()[1:2] == ["T"]]


def _compile_command(tools, compiler, flags):
    """The command that compiles a core module for Cortex-M with ``compiler`` (gcc, or clang for arm-none-eabi with
    newlib's headers) and the Makefile's warnings; the source and the output follow."""
    if compiler == "gcc":
        return [tools["gcc"], *WARN_FLAGS, *flags]
    return [clang_command() or "clang", "--target=arm-none-eabi", *WARN_FLAGS, *flags, "-isystem", NEWLIB_INCLUDE]


def _gc_link(run, tools, target, objects, entries, linked):
    """``objects`` linked into the relocatable object ``linked`` as a firmware links them: ``--gc-sections`` from
    the functions ``entries``, so what none of them reaches is dropped."""
    roots = [f"-Wl,--undefined={name}" for name in entries]
    run([tools["gcc"], *TARGETS[target][1], "-nostdlib", "-r", "-Wl,--gc-sections", *roots, *objects,
         "-o", str(linked)])
    return linked


def _linked_rate(run, tools, target, flags, src, out, defs):
    """The front end (wake_rate.c) as a firmware links it: a section per function, linked with ``--gc-sections``
    from its entry points of the configuration (firmware_entries: wake_rate_step with WAKE_RTP_SPLIT 1 only)."""
    sectioned = out / "wake_rate.fs.o"
    run([*_compile_command(tools, "gcc", flags), "-ffunction-sections", "-c", str(src / "wake_rate.c"),
         "-o", str(sectioned)])
    names = _defined_functions(sectioned)
    if names is None:
        return sectioned
    return _gc_link(run, tools, target, [str(sectioned)], firmware_entries(names, defs, prefixes=("wake_rate_",)),
                    out / "wake_rate.o")


def _linked_core(run, tools, target, flags, src, out, core_o, defs, compiler):
    """The core as a firmware links it: every module compiled with a section per function and linked with
    ``--gc-sections`` from the RTP's entry points of the configuration (firmware_entries), so a feature
    module's functions that nothing calls are dropped, as a firmware's link drops them.  Its sections are the
    footprint; the profiled image links ``core_o``, whose code is the same function for function."""
    names = _defined_functions(core_o)
    if names is None:
        return core_o
    sectioned = []
    for module in rtp_sources(src):
        obj = out / (module.stem + ".fs.o")
        run([*_compile_command(tools, compiler, flags), "-ffunction-sections", "-fdata-sections", "-c", str(module),
             "-o", str(obj)])
        sectioned.append(str(obj))
    return _gc_link(run, tools, target, sectioned, firmware_entries(names, defs), out / "wake_rtp_linked.o")


def build_image(target="m4-O2", *, board="generic", build_dir=None, csrc=None, defs=(), debug=True,
                compiler="gcc") -> Image:
    """Cross-compile the core and the harness for ``target`` and link an ELF image.

    ``board`` is ``"generic"`` (flash at 0x08000000) or ``"mps2-an386"`` (the
    QEMU board).  ``defs`` are extra ``-D`` options for the core and harness
    (e.g. ``["-DWAKE_RTP_MAX_LEVEL=5"]``).  ``compiler`` builds the core with
    gcc (stack usage and call graph too) or clang (neither: the image has no
    call-graph stack figure).
    """
    if target not in TARGETS:
        raise ValueError(f"unknown target {target!r}; valid choices: {', '.join(TARGETS)}")
    scripts = {"generic": "generic_m.ld", "mps2-an386": "mps2_an386.ld"}
    if board not in scripts:
        raise ValueError(f"unknown board {board!r}; valid choices: {', '.join(scripts)}")
    if compiler not in COMPILERS:
        raise ValueError(f"unknown compiler {compiler!r}; valid choices: {', '.join(COMPILERS)}")
    src = csrc_dir(csrc)
    prof = src / "profile"
    tools = toolchain()
    out = Path(build_dir) if build_dir else Path(tempfile.mkdtemp(prefix="wake-profile-"))
    out = out / (f"{target}-{board}" if compiler == "gcc" else f"{compiler}-{target}-{board}")
    out.mkdir(parents=True, exist_ok=True)
    flags = _core_flags(target) + list(defs) + (["-g"] if debug else [])
    core_o = out / "wake_rtp_modules.o"

    def run(cmd):
        run_tool(cmd, out)

    # The core alone (every RTP module, csrc/wake_rtp*.c, one object each, linked into one relocatable object),
    # with the Makefile's warnings (gcc: stack usage and call graph too).
    module_objects = []
    for module in rtp_sources(src):
        obj = out / (module.stem + ".o")
        stack_info = ["-fstack-usage", "-fcallgraph-info=su"] if compiler == "gcc" else []
        run([*_compile_command(tools, compiler, flags), *stack_info, "-c", str(module), "-o", str(obj)])
        module_objects.append(str(obj))
    run([tools["gcc"], *TARGETS[target][1], "-nostdlib", "-r", *module_objects, "-o", str(core_o)])
    objects = [str(core_o)]
    linked_o = _linked_core(run, tools, target, flags, src, out, core_o, defs, compiler)
    if (src / "wake_rate.c").is_file():  # the decimating front end (input rates above 150 Hz)
        objects.append(str(_linked_rate(run, tools, target, flags, src, out, defs)))
    harness_flags = ["-std=c99", "-Wall", "-Wextra", *flags, "-fno-tree-loop-distribute-patterns", "-I", str(src)]
    run([tools["gcc"], *harness_flags, "-c", str(prof / "harness.c"), "-o", "harness.o"])
    run([tools["gcc"], *harness_flags, "-c", str(prof / "startup.c"), "-o", "startup.o"])
    elf = out / "profile.elf"
    run([tools["gcc"], *TARGETS[target][1], "-nostdlib", "-ffreestanding", "-T", str(prof / scripts[board]),
         "-L", str(prof), "-Wl,-Map=profile.map",
         "startup.o", "harness.o", *objects, "-lgcc", "-o", str(elf)])
    # the modules' call graphs as one (gcc writes one per module): a step's callee in another module counts
    ci = None
    if compiler == "gcc":
        ci = out / "wake_rtp_modules.ci"
        ci.write_text("".join(Path(o).with_suffix(".ci").read_text() for o in module_objects
                              if Path(o).with_suffix(".ci").is_file()))
    img = Image.read(elf, linked_o, target, ci)
    img.source = src / "wake_rtp.c"
    return img
