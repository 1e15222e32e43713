"""Instruction counting in unicorn: a block hook plus capstone, so condition-failed IT-block
instructions count too."""


import struct

import numpy as np

from .build import (
    INFO_MAGIC,
    NEVER,
    PROFILE_MAGIC,
    STACK_PAINT,
    STACK_PROBE,
    Image,
    _emulator_modules,
)

# ---------------------------------------------------------------------------
# Instruction counting
# ---------------------------------------------------------------------------

class BlockCounter:
    """Count executed Thumb instructions with a unicorn block hook.

    For every translated block that executes, the number of instructions
    capstone decodes in its bytes is added (cached per ``(address, size)``).
    This counts instructions skipped inside an IT block (condition failed):
    the processor still issues them, while unicorn's per-instruction hook
    does not report them.  ``hits`` keeps how often each block ran, for
    per-function attribution.
    """

    def __init__(self, uc, *, keep_hits=False, cycle_model=None):
        unicorn, capstone = _emulator_modules()
        self._uc = uc
        self._md = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
        self._sizes = {}
        self._cycles = {}
        self._model = cycle_model
        self._prev = None   #: (end address, extra cycles if the next block is not the fall-through)
        self.count = 0
        self.cycles = 0
        self.keep_hits = keep_hits
        self.hits = {}
        self._handle = uc.hook_add(unicorn.UC_HOOK_BLOCK, self._on_block)

    def instructions_in(self, address, size):
        """Instructions capstone decodes in the block ``[address, address + size)``."""
        key = (address, size)
        n = self._sizes.get(key)
        if n is None:
            code = bytes(self._uc.mem_read(address, size)) if size else b""
            n = 0
            used = 0
            for _addr, isize, _mn, _op in self._md.disasm_lite(code, address):
                n += 1
                used += isize
            if used != size:
                raise RuntimeError(f"capstone decoded {used} of {size} bytes of the block at {address:#x}")
            self._sizes[key] = n
        return n

    def _block_cycles(self, address, size):
        """(cycles with every branch not taken, extra cycles when the block's last branch is taken)."""
        key = (address, size)
        hit = self._cycles.get(key)
        if hit is None:
            code = bytes(self._uc.mem_read(address, size)) if size else b""
            base, extra = 0, 0
            insns = list(self._md.disasm_lite(code, address))
            for k, (_a, _s, mn, op) in enumerate(insns):
                c = self._model.cycles(mn, op, taken=False)
                base += c
                if k == len(insns) - 1:
                    extra = self._model.cycles(mn, op, taken=True) - c
            hit = self._cycles[key] = (base, extra)
        return hit

    def _on_block(self, uc, address, size, _user):
        self.count += self.instructions_in(address, size)
        if self._model is not None:
            if self._prev is not None and address != self._prev[0]:
                self.cycles += self._prev[1]       # the previous block's last branch was taken
            base, extra = self._block_cycles(address, size)
            self.cycles += base
            self._prev = (address + size, extra)
        if self.keep_hits:
            key = (address, size)
            self.hits[key] = self.hits.get(key, 0) + 1

    def reset(self):
        self.count = 0
        self.cycles = 0
        self._prev = None
        self.hits = {}

    def finish(self):
        """Price the last block's exit (the return is a taken branch)."""
        if self._model is not None and self._prev is not None:
            self.cycles += self._prev[1]
            self._prev = None

    def close(self):
        self._uc.hook_del(self._handle)


class Emulator:
    """An :class:`Image` loaded in unicorn (Thumb, M-class, Cortex-M4 model)."""

    def __init__(self, image: Image, *, keep_hits=False):
        unicorn, _ = _emulator_modules()
        from unicorn import arm_const

        self.image = image
        self._unicorn = unicorn
        self.uc = unicorn.Uc(unicorn.UC_ARCH_ARM, unicorn.UC_MODE_THUMB | unicorn.UC_MODE_MCLASS)
        self.cpu_model = "default"
        if hasattr(self.uc, "ctl_set_cpu_model") and hasattr(arm_const, "UC_CPU_ARM_CORTEX_M4"):
            self.uc.ctl_set_cpu_model(arm_const.UC_CPU_ARM_CORTEX_M4)
            self.cpu_model = "cortex-m4"
        self._regs = arm_const
        for lo, hi in _merge_ranges(self._regions()):
            self.uc.mem_map(lo, hi - lo)
        for vaddr, data, _memsz in image.segments:
            if data:
                self.uc.mem_write(vaddr, bytes(data))
        self.stack_top = image.addr("_estack")
        self.stop = image.addr("profile_stop")
        from wake.firmware.cycles import cycle_model_for

        self.cycle_model = cycle_model_for(image.target)
        self.counter = BlockCounter(self.uc, keep_hits=keep_hits, cycle_model=self.cycle_model)
        self.last_cycles = None
        info = self.read_words(image.addr("g_profile_info"), 14)
        if info[0] != INFO_MAGIC:
            raise RuntimeError("g_profile_info not found in the image")
        (self.sizeof_state, self.sizeof_config, self.off_weights, self.off_weights2, self.off_taps,
         self.off_input, self.max_samples, self.max_level, self.p_frac, self.sample_frac, self.tap_frac,
         self.weight_frac, self.tap_row_abs_max) = info[1:]

    @property
    def formats(self):
        """Number formats of the build: fraction bits and the tap-row bound."""
        return {"p_frac": self.p_frac, "sample_frac": self.sample_frac, "tap_frac": self.tap_frac,
                "weight_frac": self.weight_frac, "tap_row_abs_max": self.tap_row_abs_max}

    def _regions(self):
        align = 0x10000
        for name, addr, size, flags, _off in self.image.sections:
            if flags & 0x2 and size:  # SHF_ALLOC
                yield addr - addr % align, -(-(addr + size) // align) * align
        top = self.image.addr("_estack")
        yield top - STACK_PROBE * 4 - (top - STACK_PROBE * 4) % align, -(-top // align) * align

    def read_words(self, addr, n):
        return list(struct.unpack(f"<{n}I", bytes(self.uc.mem_read(addr, 4 * n))))

    def call(self, func, *args, count=True, stack=False, limit=1_000_000):
        """Call ``func`` (a symbol name or address) with up to 4 integer arguments.

        Returns ``(r0, instructions, stack_bytes)``; ``instructions`` is None
        unless ``count``, ``stack_bytes`` is None unless ``stack``.
        """
        r = self._regs
        addr = self.image.addr(func) if isinstance(func, str) else int(func)
        if len(args) > 4:
            raise ValueError("at most 4 register arguments")
        sp = self.stack_top & ~7
        if stack:
            self.uc.mem_write(sp - STACK_PROBE, bytes([STACK_PAINT]) * STACK_PROBE)
        for reg, val in zip((r.UC_ARM_REG_R0, r.UC_ARM_REG_R1, r.UC_ARM_REG_R2, r.UC_ARM_REG_R3), args):
            self.uc.reg_write(reg, int(val) & 0xFFFFFFFF)
        self.uc.reg_write(r.UC_ARM_REG_SP, sp)
        self.uc.reg_write(r.UC_ARM_REG_LR, self.stop | 1)
        self.counter.reset()
        self.uc.emu_start(addr | 1, self.stop, count=limit)
        self.counter.finish()
        self.last_cycles = self.counter.cycles
        pc = self.uc.reg_read(r.UC_ARM_REG_PC)
        if pc != self.stop:
            raise RuntimeError(f"{func} did not return within {limit} instructions (pc {pc:#x})")
        depth = None
        if stack:
            probe = bytes(self.uc.mem_read(sp - STACK_PROBE, STACK_PROBE))
            untouched = len(probe) - len(probe.lstrip(bytes([STACK_PAINT])))
            depth = STACK_PROBE - untouched
            depth = -(-depth // 4) * 4  # whole words
        return self.uc.reg_read(r.UC_ARM_REG_R0), (self.counter.count if count else None), depth

    # -- the harness ------------------------------------------------------
    def write_config(self, params, inputs=(), update_at=NEVER):
        """Write g_profile_config: parameters (see :func:`fitted_parameters`) and an input sequence."""
        level = params["level"]
        inputs = np.asarray(inputs, dtype=np.int16).reshape(-1)
        if level > self.max_level:
            raise ValueError(f"the image is built for levels up to {self.max_level}, got {level}")
        if inputs.size > self.max_samples:
            raise ValueError(f"at most {self.max_samples} samples, got {inputs.size}")
        blob = bytearray(self.sizeof_config)
        struct.pack_into("<IiIIiiiii", blob, 0, PROFILE_MAGIC, level, inputs.size, update_at,
                         params["r"], params["q"], params["p0"], params["r2"], params["q2"])
        struct.pack_into(f"<{level}i", blob, self.off_weights, *map(int, params["weights"]))
        struct.pack_into(f"<{level}i", blob, self.off_weights2, *map(int, params["weights2"]))
        taps = np.asarray(params["taps"], dtype="<i2").reshape(-1)
        blob[self.off_taps:self.off_taps + 2 * taps.size] = taps.tobytes()
        blob[self.off_input:self.off_input + 2 * inputs.size] = inputs.astype("<i2").tobytes()
        self.uc.mem_write(self.image.addr("g_profile_config"), bytes(blob))
        return bytes(blob)

    def init(self):
        st, _, _ = self.call("profile_init", count=False)
        if st != 0:
            raise RuntimeError(f"wake_rtp_init failed in the image (status {_signed(st)})")

    def set_weights(self):
        st, n, _ = self.call("profile_set_weights")
        if st != 0:
            raise RuntimeError(f"wake_rtp_set_weights failed in the image (status {_signed(st)})")
        return n

    def step(self, sample, *, stack=False, out_index=0):
        """One ``wake_rtp_step``; returns ``(prediction, instructions, stack_bytes)``."""
        out = self.image.addr("g_output") + 2 * out_index
        st, n, depth = self.call("wake_rtp_step", self.image.addr("g_state"), int(sample), out, stack=stack)
        if st != 0:
            raise RuntimeError(f"wake_rtp_step failed in the image (status {_signed(st)})")
        y = struct.unpack("<h", bytes(self.uc.mem_read(out, 2)))[0]
        return y, n, depth


def _signed(v):
    return v - (1 << 32) if v & 0x80000000 else v


def _merge_ranges(ranges):
    out = []
    for lo, hi in sorted(ranges):
        if out and lo <= out[-1][1]:
            out[-1][1] = max(out[-1][1], hi)
        else:
            out.append([lo, hi])
    return [tuple(r) for r in out]
