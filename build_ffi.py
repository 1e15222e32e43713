"""cffi (API mode) build script for ``wake._rtp``, the compiled C core.

Used by ``setup.py`` (``cffi_modules``); for development it can also be run
directly (``python build_ffi.py``) to compile the extension in place.

The cffi declarations are generated from the public headers (``csrc/wake_*.h``)
rather than written out a second time: :func:`cdef_from_header` keeps the
``#define WAKE_...`` constants (as ``#define NAME ...``, cffi reads the
values from the compiled code), enum and struct typedefs (array sizes become
``[...]``) and function prototypes, and drops comments, other preprocessor
lines, conditional blocks (but ``#if WAKE_RTP_AHEAD``, ``#if WAKE_RTP_VOLUNTARY_AHEAD`` and ``#if WAKE_HPA_AHEAD``,
which the Python build compiles in) and
``static inline`` helpers.  A public header
therefore holds only those four kinds of declaration.
"""

import glob
import os
import re
import sys

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC = "csrc"


def _strip_conditionals(lines):
    """Drop #if/#ifdef blocks (C++ guards, configuration checks); keep #ifndef ones and ``#if WAKE_RTP_AHEAD`` /
    ``#if WAKE_RTP_VOLUNTARY_AHEAD`` / ``#if WAKE_HPA_AHEAD`` (the Python build compiles them in)."""
    out, stack = [], []  # stack of "keep"/"drop" per open conditional
    for line in lines:
        s = line.strip()
        m = re.match(r"#\s*(if|ifdef|ifndef|elif|else|endif)\b", s)
        if m:
            kind = m.group(1)
            if kind in ("if", "ifdef", "ifndef"):
                # keep the include guard, `#ifndef NAME / #define NAME default` blocks and the optional
                # parts the Python build compiles in (the tremor ahead: WAKE_RTP_AHEAD 1, WAKE_HPA_AHEAD 1; the
                # voluntary motion ahead: WAKE_RTP_VOLUNTARY_AHEAD 1)
                keep = kind == "ifndef" or re.fullmatch(r"#\s*if\s+WAKE_(RTP|HPA|RTP_VOLUNTARY)_AHEAD", s) is not None
                stack.append("keep" if keep else "drop")
            elif kind == "endif":
                stack.pop()
            continue
        if "drop" in stack:
            continue
        out.append(line)
    return out


def cdef_from_header(text: str) -> str:
    """cffi declarations for one public header (see the module docstring)."""
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    lines = _strip_conditionals(text.splitlines())
    out = []
    for line in lines:
        s = line.strip()
        m = re.match(r"#\s*define\s+(WAKE_\w+)\s+\S", s)
        if m and not m.group(1).endswith("_H"):
            out.append(f"#define {m.group(1)} ...")
            continue
        if s.startswith("#"):
            continue
        out.append(line)
    body = "\n".join(out)
    body = re.sub(r"static\s+inline[^{;]*\{.*?\n\}", "", body, flags=re.S)  # inline helpers
    body = re.sub(r"\[[^\]]*WAKE_\w+[^\]]*\]", "[...]", body)             # sizes from macros
    return body


def public_headers():
    # wake_rtp.h first: the other headers use its types
    return sorted(glob.glob(os.path.join(HERE, CSRC, "wake_*.h")), key=lambda p: (not p.endswith("wake_rtp.h"), p))


def sources():
    return sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, CSRC, "wake_*.c")))


#: Host-only C beside the core: the evaluation's baseline loops (no firmware build links csrc/eval).
EVAL_HEADER, EVAL_SOURCE = f"{CSRC}/eval/wake_eval.h", f"{CSRC}/eval/wake_eval.c"

ffibuilder = FFI()
for header in public_headers() + [os.path.join(HERE, EVAL_HEADER)]:
    with open(header, encoding="utf-8") as fh:
        ffibuilder.cdef(cdef_from_header(fh.read()), override=True)

ffibuilder.set_source(
    "wake._rtp",
    "\n".join(f'#include "{os.path.basename(h)}"' for h in public_headers()) + '\n#include "eval/wake_eval.h"',
    sources=[s.replace(os.sep, "/") for s in sources()] + [EVAL_SOURCE],
    libraries=[] if sys.platform == "win32" else ["m"],  # libm: the baselines' sin, cos, sqrt, fmod (csrc/eval)
    include_dirs=[CSRC],
    # The HPA's floats must round the same on every machine: no fused multiply-add.
    extra_compile_args=["-ffp-contract=off"],
    # The HPA fits the tremor ahead (WAKE_HPA_AHEAD) on the host; the RTP runs the voluntary motion ahead
    # (WAKE_RTP_VOLUNTARY_AHEAD, w_h). Host limits of the C HPA: any window up to 1024 samples, AR order up to 128,
    # every PSD bin.
    define_macros=[("WAKE_HPA_AHEAD", "1"), ("WAKE_RTP_VOLUNTARY_AHEAD", "1"), ("WAKE_HPA_MAX_WINDOW", "1024"), ("WAKE_HPA_MAX_ORDER", "128"), ("WAKE_HPA_MAX_PSD_BINS", "512")],
)

if __name__ == "__main__":
    os.chdir(HERE)
    ffibuilder.compile(verbose=False)
    # ffibuilder.compile() writes wake/_rtp*.so relative to the cwd: the repo top.
