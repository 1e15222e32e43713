"""Worst-case firmware cost of the fixed-point core: ``wake profile``.

What one ``wake_rtp_step`` costs on a Cortex-M, counted instruction by
instruction in an emulator, and how much memory the core takes.

Method (details and numbers in ``docs/studies/profiling.md``):

1. The core (``csrc/wake_rtp.c``) is cross-compiled with ``arm-none-eabi-gcc``
   for each target (Cortex-M4 ``-O2`` and ``-Os``, Cortex-M0+ ``-O2``), with
   the warning flags of ``csrc/Makefile``, and linked with the bare-metal
   harness of ``csrc/profile/`` (``-nostdlib -ffreestanding``, libgcc allowed)
   into a small ELF image.
2. The image runs in ``unicorn`` (Thumb, M-class, CPU model Cortex-M4; the
   Cortex-M0+ images run on the Cortex-M4 model, Thumb-1 being a subset of
   Thumb-2).  ``wake_rtp_step`` is called directly, with ``lr`` pointing to a
   stop address, once per sample.
3. Instructions are counted with a *block* hook: for each translated block
   that runs, the number of instructions ``capstone`` decodes in it is added
   (cached per block).  A per-instruction hook would miss the instructions
   of an IT block whose condition fails; the processor still issues them.
4. Worst case, not average: every configuration is driven with adversarial
   inputs (silence, full-scale square waves, full-scale steps, saturating
   spikes, random samples, plus a realistic synthetic recording), with a
   weight update (``wake_rtp_set_weights``) half-way through, with the Kalman
   correction active (q > 0, p0 > 0) and inert (q = 0, P = 0).  Taps and
   weights come from the project's own filter bank and HPA fits.
5. Footprint: ``arm-none-eabi-size`` of the core object alone,
   ``sizeof(wake_rtp_t)`` read from the image, and the worst-case stack
   depth of ``wake_rtp_step`` from ``-fstack-usage``/``-fcallgraph-info=su``
   (summed along the call graph), checked against the depth measured by
   painting the stack in the emulator.

The count is cross-checked once against QEMU (``qemu-system-arm -M
mps2-an386``), tracing the same image instruction by instruction
(:func:`qemu_crosscheck`).

Needs the C sources (installed with the package, :mod:`wake.firmware.sources`),
``arm-none-eabi-gcc`` and the ``profile`` extra (``pip install ".[profile]"``
from a source tree: unicorn, capstone).
"""

from __future__ import annotations

from wake.firmware.profile.build import (DEFAULT_TARGET, INPUT_KINDS, TARGET_LIMITS, TARGETS, Image, ProfileUnavailable,
                                         build_image, csrc_dir, toolchain)
from wake.firmware.profile.cli import cli
from wake.firmware.profile.emulator import BlockCounter, Emulator
from wake.firmware.profile.report import footprint, qemu_crosscheck
from wake.firmware.profile.scenarios import (adversarial_inputs, arithmetic_floor, fitted_parameters,
                                             profile_configuration)

__all__ = ["TARGETS", "DEFAULT_TARGET", "TARGET_LIMITS", "BlockCounter", "Image", "Emulator", "build_image",
           "arithmetic_floor", "adversarial_inputs", "fitted_parameters", "profile_configuration", "footprint",
           "qemu_crosscheck", "cli", "csrc_dir", "toolchain", "ProfileUnavailable", "INPUT_KINDS"]
