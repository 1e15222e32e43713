"""The extension's cffi declarations (csrc/wake_cffi.h) against the C it is compiled from.

build_ffi.py reads its declarations from csrc/wake_cffi.h, written for cffi.  cffi's API mode checks
every declaration in that file against the headers (a field of the wrong size or offset stops the import);
these tests check the other direction: every public function the extension's sources define is declared
(but the entries of a feature its configuration leaves off, wake.firmware.sources.FEATURE_ENTRIES: their
module compiles in every build), and the file is one cffi reads as it is (no preprocessor conditionals to strip).
"""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from support import load_build_ffi
from wake.firmware.sources import FEATURE_ENTRIES, firmware_entries

CSRC = Path(__file__).resolve().parents[2] / "csrc"

build_ffi = load_build_ffi()

ROOT = Path(__file__).resolve().parents[2]


def test_cdef_holds_no_conditional_or_include():
    text = (ROOT / "csrc" / build_ffi.CDEF).read_text()
    directives = {line.split()[0] for line in text.splitlines() if line.lstrip().startswith("#")}
    assert directives == {"#define"}, f"wake_cffi.h must hold declarations cffi reads as they are: {directives}"


def test_every_defined_function_is_declared():
    lib = pytest.importorskip("wake._rtp", reason="the extension is not built (python build_ffi.py)")
    nm = shutil.which("nm")
    if nm is None:
        pytest.skip("nm (binutils) is not installed: cannot list the extension's symbols")
    out = subprocess.run([nm, "-D", "--defined-only", lib.__file__], capture_output=True, text=True, check=True).stdout
    # the RTP's internal functions (wake_rtpi_*, csrc/internal/wake_rtp_internal.h) are not the API
    defined = {f[2] for f in (line.split() for line in out.splitlines())
               if len(f) == 3 and f[1] == "T" and f[2].startswith("wake_") and not f[2].startswith("wake_rtpi_")}
    assert {"wake_rtp_step", "wake_hpa_run", "wake_rate_push", "wake_rtp_set_voluntary_ahead"} <= defined
    # the functions the C files share among themselves (csrc/internal/*.h) are not the extension's API
    internal = {m for h in CSRC.glob("internal/*.h")
                for m in re.findall(r"\b(wake_\w+)\(", h.read_text(encoding="utf-8"))}
    assert "wake_hpa_step_solve" in internal
    # the entries of a feature the configuration leaves off (the split step): compiled, not the extension's API
    defs = [f"-D{name}={value}" for name, value in build_ffi.CONFIGURATION]
    off = {e for entries in FEATURE_ENTRIES.values() for e in entries} - set(
        firmware_entries(defined, defs, prefixes=("wake_rtp_", "wake_rate_")))
    assert {"wake_rtp_prepare", "wake_rate_step"} <= off and "wake_rtp_run_outputs" not in off
    missing = sorted(defined - set(dir(lib.lib)) - internal - off)
    assert not missing, f"defined in csrc/ but not declared in csrc/wake_cffi.h: {missing}"


def test_configuration_matches_the_compiled_constants():
    lib = pytest.importorskip("wake._rtp", reason="the extension is not built (python build_ffi.py)").lib
    config = dict(build_ffi.CONFIGURATION)
    assert lib.WAKE_RTP_VOLUNTARY_AHEAD == int(config["WAKE_RTP_VOLUNTARY_AHEAD"])
    assert lib.WAKE_HPA_AHEAD == int(config["WAKE_HPA_AHEAD"])
    assert lib.WAKE_HPA_MAX_WINDOW == int(config["WAKE_HPA_MAX_WINDOW"])
    assert lib.WAKE_RTP_SPLIT == 0 and lib.WAKE_RTP_AHEAD == 1 and lib.WAKE_RTP_KALMAN == 1
