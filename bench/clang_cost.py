"""The C core built with clang instead of gcc: instructions per sample and code size (cost issue: within 1.3x).

    python bench/clang_cost.py            # needs clang, arm-none-eabi-gcc (harness, link, newlib headers), unicorn

The core (csrc/wake_rtp.c) is compiled by ``clang --target=arm-none-eabi``
with the Makefile's warnings and the same target flags as ``wake profile``
(``build_image(..., compiler="clang")``); the harness, the start-up code and
the link stay with arm-none-eabi-gcc (one EABI).  Instructions are counted with the profiler's block-hook counter over
the same adversarial inputs (80 samples per kind, J = 5, sym3), beside the
gcc figures of the same run.  The static bound is not computed for clang
images: the control-flow reconstruction of wake.firmware.wcet follows gcc's
code shapes (clang's tail calls break it), so only measured maxima compare.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from wake.firmware.profile import build as B  # noqa: E402
from wake.firmware.profile.emulator import Emulator  # noqa: E402
from wake.firmware.profile.report import section_sizes  # noqa: E402
from wake.firmware.profile.scenarios import profile_configuration  # noqa: E402

def measure(image):
    emu = Emulator(image)
    maxima = {k: profile_configuration(emu, "sym3", 5, kalman=k, n=80).max for k in (True, False)}
    sizes = section_sizes(image.core_object)
    return maxima, sizes[".text"] + sizes[".rodata"]


def main():
    if B.clang_command() is None or not Path(B.NEWLIB_INCLUDE).is_dir():
        print("clang or the newlib headers (gcc-arm-none-eabi, libnewlib-arm-none-eabi) are missing")
        return 3
    out = Path(tempfile.mkdtemp(prefix="wake-clang-"))
    print("| target | Kalman | gcc measured max | clang measured max | clang / gcc | gcc code | clang code | clang / gcc |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for target in B.TARGETS:
        g, gcode = measure(B.build_image(target, build_dir=out / "gcc", defs=["-DWAKE_RTP_MAX_LEVEL=5"]))
        c, ccode = measure(B.build_image(target, build_dir=out, defs=["-DWAKE_RTP_MAX_LEVEL=5"], compiler="clang"))
        for k in (True, False):
            print(f"| {target} | {'active' if k else 'inert'} | {g[k]:,} | {c[k]:,} | {c[k] / g[k]:.2f} | "
                  f"{gcode:,} B | {ccode:,} B | {ccode / gcode:.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
