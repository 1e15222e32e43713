"""Worst-case firmware cost per sample of the fixed-point core (CI entry point).

    python bench/firmware_cost.py --quick --check      # CI: default configuration, exit 1 on a regression
    python bench/firmware_cost.py --quick --check-goals  # exit 1 while a goal of the cost issue is missed
    python bench/firmware_cost.py --hotspots --qemu    # full table, hotspots, QEMU cross-check

Same options as ``wake profile`` (see ``--help``): cross-compiles csrc/ with
arm-none-eabi-gcc for Cortex-M4 (-O2, -Os) and Cortex-M0+ (-O2), counts the
instructions of every ``wake_rtp_step`` in unicorn, computes the static bound
of the step from the image and prints Markdown tables.  The goals and the
regression ceilings are ``TARGET_LIMITS`` and ``CEILING_LIMITS`` in
``wake/firmware/profile/build.py``.

Exit status: 0 ceilings held (or no --check), 1 a measured step above its
static bound, a ceiling exceeded, or (--check-goals) a goal missed, 3 a tool
is missing (arm-none-eabi-gcc, unicorn, capstone).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

from wake.firmware.profile import cli  # noqa: E402

if __name__ == "__main__":
    sys.exit(cli())
