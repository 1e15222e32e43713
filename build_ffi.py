"""cffi (API mode) build script for ``wake._rtp``, the compiled C core.

Used by ``setup.py`` (``cffi_modules``); for development it can also be run
directly (``python build_ffi.py``) to compile the extension in place.

The extension is compiled from every C source of the core (``csrc/wake_*.c``,
the same files a firmware links) with :data:`CONFIGURATION`, the one place its
build settings are written (docs/reference/packaging.md, "The Python extension's
configuration"), plus the host-only evaluation loops (``wake/eval/native``: not
firmware code, so not in csrc/) and the host-only batch driver of the C HPA
path (``wake/native``).  cffi reads its declarations from
``csrc/wake_cffi.h`` and ``wake/eval/native/wake_eval_cffi.h``, files written for cffi (no
preprocessor conditionals, no comments to strip): cffi's API mode compiles each
of them against the headers, so a declaration that no longer matches its
header fails this build or the extension's import.
"""

import glob
import os
import sys

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC = "csrc"

#: The public headers the extension includes, wake_rtp.h first (the others use its types).
HEADERS = ("wake_rtp.h", "wake_hpa.h", "wake_rate.h")
#: The cffi declarations of those headers in this configuration, and of the evaluation loops.
CDEF = "wake_cffi.h"
#: The extension's configuration: the tremor ahead of the HPA (WAKE_HPA_AHEAD) and the voluntary motion ahead
#: of the RTP (WAKE_RTP_VOLUNTARY_AHEAD, w_h); the HPA's host limits: any window up to 1024 samples, AR order up
#: to 128, every PSD bin.  Everything else keeps the headers' defaults (the firmware's).
CONFIGURATION = (("WAKE_HPA_AHEAD", "1"), ("WAKE_RTP_VOLUNTARY_AHEAD", "1"), ("WAKE_HPA_MAX_WINDOW", "1024"),
                 ("WAKE_HPA_MAX_ORDER", "128"), ("WAKE_HPA_MAX_PSD_BINS", "512"))
#: Host-only C beside the core: the evaluation's baseline loops, kept with the evaluation (wake/eval/native), out of
#: the firmware tree csrc/; their cffi declarations are read after CDEF's.
EVAL_DIR = "wake/eval/native"
EVAL_HEADER, EVAL_SOURCE, EVAL_CDEF = "wake_eval.h", f"{EVAL_DIR}/wake_eval.c", "wake_eval_cffi.h"
#: Host-only C beside the core: the batch driver of run(hpa_backend="c") (wake/native), which reaches the core
#: through its public headers only; its cffi declarations are read last.
NATIVE_DIR = "wake/native"
NATIVE_HEADER, NATIVE_SOURCE, NATIVE_CDEF = "wake_batch.h", f"{NATIVE_DIR}/wake_batch.c", "wake_batch_cffi.h"


def sources():
    return sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, CSRC, "wake_*.c")))


def cdef_text() -> str:
    """The declarations cffi reads (``csrc/wake_cffi.h``, the evaluation loops' ``wake_eval_cffi.h``, then the
    batch driver's ``wake_batch_cffi.h``)."""
    text = []
    for folder, name in ((CSRC, CDEF), (EVAL_DIR, EVAL_CDEF), (NATIVE_DIR, NATIVE_CDEF)):
        with open(os.path.join(HERE, folder, name), encoding="utf-8") as fh:
            text.append(fh.read())
    return "\n".join(text)


ffibuilder = FFI()
ffibuilder.cdef(cdef_text())

ffibuilder.set_source(
    "wake._rtp",
    "\n".join(f'#include "{h}"' for h in (*HEADERS, EVAL_HEADER, NATIVE_HEADER)),
    sources=[s.replace(os.sep, "/") for s in sources()] + [EVAL_SOURCE, NATIVE_SOURCE],
    # libm: the baselines' sin, cos, sqrt, fmod (EVAL_DIR), the batch driver's rint and pow (NATIVE_DIR)
    libraries=[] if sys.platform == "win32" else ["m"],
    include_dirs=[CSRC, EVAL_DIR, NATIVE_DIR],
    # The HPA's floats must round the same on every machine: no fused multiply-add.
    extra_compile_args=["-ffp-contract=off"],
    define_macros=list(CONFIGURATION),
)

def defines() -> str:
    """:data:`CONFIGURATION` as compiler options (``python build_ffi.py --defines``): the standalone firmware's
    build takes them (``csrc/Makefile``), so that the extension's configuration is one a firmware is built with."""
    return " ".join(f"-D{name}={value}" for name, value in CONFIGURATION)


if __name__ == "__main__" and sys.argv[1:] == ["--defines"]:
    print(defines())
elif __name__ == "__main__":
    os.chdir(HERE)
    ffibuilder.compile(verbose=False)
    # ffibuilder.compile() writes wake/_rtp*.so relative to the cwd: the repo top.
