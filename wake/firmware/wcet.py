"""Static worst-case bound of ``wake_rtp_step`` from the compiled image.

The bound is the longest path through the control-flow graph (CFG) of the
function and of everything it calls (the core's helpers and libgcc's), built
from the disassembly of the linked ELF image (capstone), in two measures:
instructions issued and cycles of a per-instruction timing model.

How it works (``docs/studies/profiling.md`` has the details and the tables):

1. Each function is cut into basic blocks at branch targets and after
   branches and returns.  A call (``bl``) costs the callee's bound; a branch
   out of the function is a tail call.  Indirect branches other than returns
   (``blx reg``, ``tbb``, ``mov pc``) are refused: no bound without a target.
2. Loops are the natural loops of the DFS back edges.  A loop's trip count
   comes from the source: every loop of the per-sample path carries a comment
   ``/* wcet-loop: EXPR */`` on one of its lines, ``EXPR`` in ``N`` (= 2^J)
   and ``J``; the instructions of the loop are mapped to their source lines
   with ``addr2line``.  A loop without an annotation is an error.  ``B``
   counts iterations of the body.  The header runs at most ``B + 1`` times
   when it can leave the loop before the rest of the body (test at the top),
   else ``B`` times (a one-block loop that tests at its end, the shape gcc
   gives ``for`` loops with a guard and ``do``-``while`` loops); the bound is
   ``(H - 1) * (longest header -> back edge) + (longest header -> exit)``,
   loops collapsed innermost first.
3. Instructions inside an IT block whose condition fails are counted (the
   core issues them); the measured counts are taken the same way.
4. ``exclude`` names functions whose calls cost nothing: the inert bound
   excludes ``wake_rtpi_kalman_update`` (skipped while the Kalman filter is inert).

Cycle models (zero wait states, from the Arm Technical Reference Manuals of
the Cortex-M4 and Cortex-M0+) assign each instruction its worst cycle count;
a taken branch pays the pipeline refill.  See :mod:`wake.firmware.cycles`.
"""

from __future__ import annotations

import functools
import re
import subprocess
from dataclasses import dataclass, field

from .cfg import dag_longest, natural_loops
from .cycles import CONDITIONS, CYCLE_MODELS, CycleModel, base_mnemonic, cycle_model_for, instruction_cycles
from .profile.build import Image, _emulator_modules, toolchain

__all__ = ["WcetError", "Bound", "static_bound", "CYCLE_MODELS", "instruction_cycles", "CycleModel"]

LOOP_ANNOTATION = re.compile(r"wcet-loop:\s*(.+?)\s*\*/")   # the expression may hold `*` ("2 * N")


class WcetError(RuntimeError):
    """The image has a construct the static bound cannot handle (unbounded loop, indirect jump)."""



# ---------------------------------------------------------------------------
# Disassembly and CFG
# ---------------------------------------------------------------------------

@dataclass
class Insn:
    addr: int
    size: int
    mnemonic: str
    op_str: str
    kind: str           #: "plain", "jump", "cjump", "call", "ret", "cret"
    target: int | None = None


@dataclass
class Block:
    start: int
    insns: list
    succ: list = field(default_factory=list)   #: (target block start or None for return, taken?)
    calls: list = field(default_factory=list)  #: callee addresses


def _read(image: Image, addr: int, size: int) -> bytes:
    for vaddr, data, _memsz in image.segments:
        if vaddr <= addr and addr + size <= vaddr + len(data):
            return bytes(data[addr - vaddr:addr - vaddr + size])
    raise WcetError(f"address {addr:#x} is not in a loaded segment of {image.elf.name}")


def _function_at(image: Image, addr: int):
    for start, end, name in image.functions():
        if start <= addr < end:
            return start, end, name
    raise WcetError(f"no function symbol contains {addr:#x}")


def _decode(md, csarm, code: bytes, base: int, addr: int) -> Insn | None:
    """One Thumb instruction at addr (None when capstone cannot decode it)."""
    off = addr - base
    i = next(md.disasm(code[off:off + 4], addr, count=1), None)
    if i is None:
        return None
    m = base_mnemonic(i.mnemonic)
    cond = i.cc not in (csarm.ARM_CC_AL, csarm.ARM_CC_INVALID)
    writes_pc = m in ("pop", "ldm", "ldmia", "ldmfd", "ldmdb") and "pc" in i.op_str
    kind, target = "plain", None
    if m in ("bl", "blx"):
        if not i.operands or i.operands[0].type != csarm.ARM_OP_IMM:
            kind = f"bad: indirect call at {i.address:#x}: {i.mnemonic} {i.op_str}"
        else:
            kind, target = "call", i.operands[0].imm
    elif m == "bx" or writes_pc or (m == "ldr" and i.op_str.startswith("pc")):
        kind = "cret" if cond else "ret"
        if m == "bx" and i.op_str.strip() != "lr":
            kind = f"bad: indirect branch at {i.address:#x}: {i.mnemonic} {i.op_str}"
    elif m in ("b", "cbz", "cbnz") or (len(m) == 3 and m[0] == "b" and m[1:] in CONDITIONS):
        target = i.operands[-1].imm
        kind = "cjump" if (cond or m in ("cbz", "cbnz")) else "jump"
    elif m in ("tbb", "tbh") or (m == "mov" and i.op_str.startswith("pc")):
        kind = f"bad: computed jump at {i.address:#x}: {i.mnemonic} {i.op_str}"
    return Insn(i.address, i.size, i.mnemonic, i.op_str, kind, target)


def _disassemble(image: Image, start: int, end: int) -> list[Insn]:
    """The instructions reachable from the entry (recursive descent: literal pools are skipped)."""
    _, capstone = _emulator_modules()
    from capstone import arm as csarm

    md = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
    md.detail = True
    code = _read(image, start, end - start) + b"\0\0"
    found, work = {}, [start]
    while work:
        addr = work.pop()
        while start <= addr < end and addr not in found:
            i = _decode(md, csarm, code, start, addr)
            if i is None:
                raise WcetError(f"capstone cannot decode the instruction at {addr:#x}")
            if i.kind == "call" and start <= i.target < end:
                i.kind = "jump"     # Thumb-1 "far jump": BL inside the function (gcc saves lr for it)
            found[addr] = i
            if i.kind in ("jump", "cjump") and start <= i.target < end:
                work.append(i.target)
            if i.kind in ("jump", "ret") or i.kind.startswith("bad"):
                break
            addr += i.size
    return [found[a] for a in sorted(found)]


def _blocks(insns: list[Insn], start: int, end: int) -> dict[int, Block]:
    leaders = {start}
    for k, i in enumerate(insns):
        if i.kind in ("jump", "cjump") and start <= i.target < end:
            leaders.add(i.target)
        if i.kind in ("jump", "cjump", "ret", "cret") and k + 1 < len(insns):
            leaders.add(insns[k + 1].addr)
    blocks, cur = {}, None
    for k, i in enumerate(insns):
        if k and insns[k - 1].addr + insns[k - 1].size != i.addr:
            leaders.add(i.addr)
        if i.addr in leaders:
            cur = Block(i.addr, [])
            blocks[i.addr] = cur
        cur.insns.append(i)
        if i.kind == "call":
            cur.calls.append(i.target)
    order = sorted(blocks)
    for n, b in enumerate(order):
        blk = blocks[b]
        last = blk.insns[-1]
        nxt = last.addr + last.size
        if last.kind == "jump":
            blk.succ.append((last.target if start <= last.target < end else ("tail", last.target), True))
        elif last.kind == "cjump":
            blk.succ.append((last.target if start <= last.target < end else ("tail", last.target), True))
            blk.succ.append((nxt, False))
        elif last.kind == "ret":
            blk.succ.append((None, True))
        elif last.kind == "cret":
            blk.succ.append((None, True))
            blk.succ.append((nxt, False))
        else:
            blk.succ.append((nxt, False))
    return blocks


# ---------------------------------------------------------------------------
# Loop bounds from the source
# ---------------------------------------------------------------------------

def _source_lines(image: Image, addrs) -> dict[int, tuple[str, int]]:
    tool = toolchain().get("addr2line")
    if tool is None:
        raise WcetError("arm-none-eabi-addr2line is needed to read the loop bounds")
    addrs = sorted(set(addrs))
    proc = subprocess.run([tool, "-a", "-e", str(image.elf)], input="\n".join(f"{a:#x}" for a in addrs) + "\n",
                          capture_output=True, text=True, check=True)
    out, lines = {}, proc.stdout.splitlines()
    for k in range(0, len(lines) - 1, 2):
        where = lines[k + 1].rsplit(":", 1)
        if len(where) == 2 and where[1].split()[0].isdigit():
            out[int(lines[k], 16)] = (where[0], int(where[1].split()[0]))
    return out


@functools.lru_cache(maxsize=None)
def _file_lines(path: str) -> list[str]:
    try:
        with open(path, encoding="utf-8") as fh:
            return fh.read().splitlines()
    except OSError:
        return []


def _loop_bound(image: Image, body_addrs, level: int, where: str) -> int:
    found = set()
    for path, line in _source_lines(image, body_addrs).values():
        text = _file_lines(path)
        if 1 <= line <= len(text):
            m = LOOP_ANNOTATION.search(text[line - 1])
            if m:
                found.add(m.group(1))
    if len(found) != 1:
        raise WcetError(f"loop in {where}: {'no' if not found else 'several'} `wcet-loop:` annotation(s) "
                        f"on its source lines ({sorted(found)})")
    expr = found.pop()
    if not re.fullmatch(r"[NJ0-9+\-*/() ]+", expr):
        raise WcetError(f"loop bound {expr!r} in {where} may only use N, J, integers and + - * / ( )")
    return int(eval(expr, {"__builtins__": {}}, {"N": 2**level, "J": level}))  # noqa: S307 - checked above


# ---------------------------------------------------------------------------
# Longest path
# ---------------------------------------------------------------------------

@dataclass
class Bound:
    """Static bound of one function (and its callees)."""

    function: str
    instructions: int
    cycles: int
    loops: list          #: (function, header address, trip count)
    callees: list        #: names of every function reached


class _Analyser:
    def __init__(self, image: Image, level: int, model: CycleModel, exclude=()):
        self.image, self.level, self.model, self.exclude = image, level, model, set(exclude)
        self.memo = {}
        self.loops = []
        self.callees = set()

    def function(self, addr: int, stack=()):
        start, end, name = _function_at(self.image, addr)
        if name in self.exclude:
            return 0, 0
        if start in self.memo:
            return self.memo[start]
        if start in stack:
            raise WcetError(f"recursion through {name} (call stack {[hex(x) for x in stack]}, at {addr:#x})")
        self.callees.add(name)
        insns = _disassemble(self.image, start, end)
        blocks = _blocks(insns, start, end)
        result = self._longest(name, blocks, start, stack + (start,))
        self.memo[start] = result
        return result

    def _block_cost(self, blk: Block, stack):
        for i in blk.insns:
            if i.kind.startswith("bad"):
                raise WcetError(i.kind[5:])
        n = len(blk.insns)
        c = 0
        for i in blk.insns:
            if i.kind in ("jump", "cjump", "ret", "cret"):
                continue  # priced on the edges
            c += self.model.cycles(i.mnemonic, i.op_str, taken=False)
        for callee in blk.calls:
            ci, cc = self.function(callee, stack)
            n += ci
            c += cc
        return n, c

    def _edge_cost(self, blk: Block, taken: bool, tail):
        last = blk.insns[-1]
        extra_n, extra_c = 0, 0
        if last.kind in ("jump", "cjump", "ret", "cret"):
            extra_c = self.model.cycles(last.mnemonic, last.op_str, taken=taken)
        if tail is not None:
            tn, tc = self.function(tail)
            extra_n, extra_c = extra_n + tn, extra_c + tc
        return extra_n, extra_c

    def _longest(self, name, blocks, entry, stack):
        blocks, node, edges = self._graph(blocks, entry, stack)
        loops = natural_loops(edges, entry)
        # collapse loops, innermost (smallest) first
        for h in sorted(loops, key=lambda k: len(loops[k])):
            self._collapse_loop(name, h, loops, blocks, node, edges)
        dist = dag_longest(entry, node, edges, inside=None, stop=None)
        best = [0, 0]
        for u, (n, c) in dist.items():
            for v, (en, ec) in edges[u]:
                if v is None:
                    best = [max(best[0], n + en), max(best[1], c + ec)]
        return tuple(best)

    def _graph(self, blocks, entry, stack):
        """The blocks reachable from ``entry``, their costs (instructions, cycles) and the edges with theirs."""
        reach, work = set(), [entry]
        while work:
            u = work.pop()
            if u is None or isinstance(u, tuple) or u in reach or u not in blocks:
                continue
            reach.add(u)
            work.extend(t for t, _ in blocks[u].succ)
        blocks = {b: blk for b, blk in blocks.items() if b in reach}
        node = {b: self._block_cost(blk, stack) for b, blk in blocks.items()}
        edges = {b: [] for b in blocks}
        for b, blk in blocks.items():
            for tgt, taken in blk.succ:
                tail = None
                if isinstance(tgt, tuple):
                    tail, tgt = tgt[1], None
                edges[b].append((tgt, self._edge_cost(blk, taken, tail)))
        return blocks, node, edges

    def _collapse_loop(self, name, h, loops, blocks, node, edges):
        """Replace the loop headed by ``h`` by one node that costs its bound (``node``, ``edges`` and the
        bodies of the enclosing ``loops`` are updated in place)."""
        body = loops[h]
        inner = [k for k in loops if k != h and loops[k] < body]
        own = set(body)
        for k in inner:
            own -= loops[k] - {k}
        addrs = [i.addr for b in own if b in blocks for i in blocks[b].insns]
        trips = _loop_bound(self.image, addrs, self.level, f"{name} at {h:#x}")
        self.loops.append((name, h, trips))
        dist = dag_longest(h, node, edges, inside=body, stop=h)
        c_back = [0, 0]
        c_exit = [0, 0]
        header_exits = False
        for u in body:
            if u not in dist:
                continue
            for v, (en, ec) in edges[u]:
                if v == h:
                    c_back = [max(c_back[0], dist[u][0] + en), max(c_back[1], dist[u][1] + ec)]
                elif v is None or v not in body:
                    c_exit = [max(c_exit[0], dist[u][0] + en), max(c_exit[1], dist[u][1] + ec)]
                    header_exits |= u == h
        # The header tests at the top (it runs B + 1 times) only if it can leave before the rest of the
        # body.  A header that is its own latch (one block that ends in the test branching back to
        # itself) leaves only after a whole iteration: B times.
        self_latch = any(v == h for v, _ in edges[h])
        runs = trips + 1 if header_exits and not self_latch else trips
        cost = ((runs - 1) * c_back[0] + c_exit[0], (runs - 1) * c_back[1] + c_exit[1])
        exits = {v for u in body for v, _ in edges[u] if v is None or v not in body}
        # the loop becomes one node: entered at h, leaving to its exits (costs already inside)
        for u in body:
            if u != h:
                node.pop(u, None)
                edges.pop(u, None)
        node[h] = cost
        edges[h] = [(v, (0, 0)) for v in exits]
        for u in edges:
            edges[u] = [(v if v not in body else h, c) for v, c in edges[u]]
        for k in loops:
            if k != h and loops[k] >= body:
                loops[k] = (loops[k] - body) | {h}


def static_bound(image: Image, level: int, *, function="wake_rtp_step", exclude=(), model=None) -> Bound:
    """Longest path through ``function`` of ``image`` for filter-bank level ``level``.

    ``exclude``: functions whose calls cost nothing (e.g. ``("wake_rtpi_kalman_update",)``
    for the inert Kalman filter).  ``model``: a :class:`CycleModel`
    (default: by the image's target).
    """
    model = model or cycle_model_for(image.target)
    an = _Analyser(image, int(level), model, exclude)
    n, c = an.function(image.addr(function))
    return Bound(function, int(n), int(c), list(an.loops), sorted(an.callees))
