"""Per-instruction cycle models of the Cortex-M4 and Cortex-M0+ (zero wait states).

From the Arm Technical Reference Manuals: each instruction gets its worst
cycle count; a taken branch pays the pipeline refill.  The static bound
(:mod:`wake.firmware.wcet`) and the emulator's measured counts
(:mod:`wake.firmware.profile.emulator`) both price instructions with these
models, so the bound and the measurement are in the same units.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["CONDITIONS", "CYCLE_MODELS", "CycleModel", "base_mnemonic", "cycle_model_for", "instruction_cycles"]

#: Condition suffixes of Thumb-2 branches and IT blocks.
CONDITIONS = ("eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt", "le", "al")


def base_mnemonic(mnemonic: str) -> str:
    m = mnemonic.split(".")[0]
    return m


@dataclass(frozen=True)
class CycleModel:
    """Worst-case cycles per instruction, zero wait states."""

    name: str
    load: int            #: LDR/LDRB/LDRH/LDRSB/LDRSH/STR... (single)
    load_double: int     #: LDRD/STRD
    multiple_base: int   #: LDM/STM/PUSH/POP: base + 1 per register
    pc_load_extra: int   #: POP/LDM that writes pc: refill
    branch_taken: int    #: B, Bcc taken, CBZ/CBNZ taken, BX
    branch_not_taken: int
    call: int            #: BL
    multiply: int        #: MUL(S)
    multiply_acc: int    #: MLA/MLS
    long_multiply: int   #: SMULL/UMULL/SMLAL/UMLAL and DSP multiplies
    divide: int          #: SDIV/UDIV worst case
    other: int = 1

    def cycles(self, mnemonic: str, op_str: str, *, taken: bool) -> int:
        m = base_mnemonic(mnemonic)
        stripped = m
        if m not in _KNOWN and len(m) > 2 and m[-2:] in CONDITIONS and m[:-2] in _KNOWN:
            stripped = m[:-2]
        m = stripped
        if m in ("ldr", "ldrb", "ldrh", "ldrsb", "ldrsh", "ldrex", "str", "strb", "strh", "strex"):
            return self.load + (self.pc_load_extra if m == "ldr" and op_str.startswith("pc") else 0)
        if m in ("ldrd", "strd"):
            return self.load_double
        if m in ("ldm", "ldmia", "ldmdb", "ldmfd", "stm", "stmia", "stmdb", "stmea", "push", "pop"):
            regs = _register_count(op_str)
            pc = m in ("pop", "ldm", "ldmia", "ldmfd", "ldmdb") and "pc" in op_str
            return self.multiple_base + regs + (self.pc_load_extra if pc else 0)
        if m in ("b", "cbz", "cbnz", "bx"):
            return self.branch_taken if taken else self.branch_not_taken
        if m in ("bl", "blx"):
            return self.call
        if m in ("mul", "muls"):
            return self.multiply
        if m in ("mla", "mls"):
            return self.multiply_acc
        if m in _LONG_MULTIPLY:
            return self.long_multiply
        if m in ("sdiv", "udiv"):
            return self.divide
        return self.other


_LONG_MULTIPLY = {"smull", "umull", "smlal", "umlal", "smlald", "smlsld", "smlad", "smlsd", "smuad", "smusd",
                  "smlabb", "smlabt", "smlatb", "smlatt", "smulbb", "smulbt", "smultb", "smultt", "smmul",
                  "smmla", "smmls", "smlawb", "smlawt", "smulwb", "smulwt", "umaal"}
_KNOWN = {"ldr", "ldrb", "ldrh", "ldrsb", "ldrsh", "ldrex", "str", "strb", "strh", "strex", "ldrd", "strd", "ldm",
          "ldmia", "ldmdb", "ldmfd", "stm", "stmia", "stmdb", "stmea", "push", "pop", "b", "cbz", "cbnz", "bx", "bl",
          "blx", "mul", "muls", "mla", "mls", "sdiv", "udiv"} | _LONG_MULTIPLY


def _register_count(op_str: str) -> int:
    m = re.search(r"\{([^}]*)\}", op_str)
    if not m:
        return 1
    n = 0
    for part in m.group(1).split(","):
        part = part.strip()
        if "-" in part:
            lo, hi = (int(x.strip().lstrip("r")) for x in part.split("-"))
            n += hi - lo + 1
        elif part:
            n += 1
    return n


#: Cortex-M4 (TRM r0p1, table 3-1) and Cortex-M0+ (TRM r0p1, table 3-1, single-cycle multiplier).
CYCLE_MODELS = {
    # M4: LDR 2 (1 when pipelined with a following load: not assumed), LDRD 1 + 2, LDM/STM 1 + N,
    # a branch that is taken or writes pc 1 + P with P = 1..3 (3 assumed), MUL 1, MLA 2,
    # SMULL/UMULL/SMLAL/UMLAL 1, SDIV/UDIV 2..12 (12 assumed).
    "m4": CycleModel("Cortex-M4", load=2, load_double=3, multiple_base=1, pc_load_extra=3, branch_taken=4,
                     branch_not_taken=1, call=4, multiply=1, multiply_acc=2, long_multiply=1, divide=12),
    # M0+: LDR/STR 2, LDM/STM/PUSH/POP 1 + N, POP {pc} 3 + N, B taken 2 (not taken 1), BL 3, BX 2,
    # MULS 1 (the single-cycle multiplier option; the iterative one takes 32).
    "m0plus": CycleModel("Cortex-M0+", load=2, load_double=3, multiple_base=1, pc_load_extra=2, branch_taken=2,
                         branch_not_taken=1, call=3, multiply=1, multiply_acc=2, long_multiply=1, divide=12),
}


def cycle_model_for(target: str) -> CycleModel:
    return CYCLE_MODELS["m0plus" if target.startswith("m0") else "m4"]


def instruction_cycles(model: CycleModel, mnemonic: str, op_str: str, taken: bool) -> int:
    return model.cycles(mnemonic, op_str, taken=taken)

