"""Worst-case firmware cost per sample of the fixed-point core (CI entry point).

    python bench/firmware_cost.py --quick --check      # CI: default configuration, exit 1 on a missed target
    python bench/firmware_cost.py --hotspots --qemu    # full table, hotspots, QEMU cross-check

Same options as ``wake profile`` (see ``--help``): cross-compiles csrc/ with
arm-none-eabi-gcc for Cortex-M4 (-O2, -Os) and Cortex-M0+ (-O2), counts the
instructions of every ``wake_rtp_step`` in unicorn and prints Markdown
tables.  Targets for J = 5, sym3 on Cortex-M4 -O2: worst case <= 1,500
instructions per sample, ``sizeof(wake_rtp_t)`` <= 1 KiB, code <= 4 KiB.

Exit status: 0 targets met (or no --check), 1 a target missed, 3 a tool is
missing (arm-none-eabi-gcc, unicorn, capstone).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

from wake.firmware.profile import cli  # noqa: E402

if __name__ == "__main__":
    sys.exit(cli())
