"""The Q formats of wake.rtp.qformat are those of csrc/wake_rtp.h (and wake_rtp_types.h, which it includes), and
need no compiled core."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from support import CSRC, has_c_backend
from wake.rtp import qformat

ROOT = Path(__file__).resolve().parents[2]


def header_defines():
    """``#define WAKE_RTP_NAME value`` of the header, the values evaluated (defaults of ``#ifndef`` blocks)."""
    text = (CSRC / "wake_rtp_types.h").read_text() + (CSRC / "wake_rtp.h").read_text()
    values = {}
    for name, expr in re.findall(r"#define\s+(WAKE_RTP_\w+)\s+(.+)", text):
        expr = re.sub(r"/\*.*", "", expr).strip()
        expr = re.sub(r"INT32_C\((\w+)\)", r"\1", expr)
        try:
            values[name] = eval(expr, {}, values)  # plain integer arithmetic on earlier names
        except Exception:
            continue
    return values


def test_the_formats_are_the_headers():
    h = header_defines()
    assert qformat.P_FRAC == h["WAKE_RTP_P_FRAC"]
    assert qformat.MAX_LEVEL == h["WAKE_RTP_MAX_LEVEL"]
    assert qformat.SAMPLE_FRAC == h["WAKE_RTP_SAMPLE_FRAC"]
    assert qformat.TAP_FRAC == h["WAKE_RTP_TAP_FRAC"]
    assert qformat.STATE_FRAC == h["WAKE_RTP_STATE_FRAC"]
    assert qformat.WEIGHT_FRAC == h["WAKE_RTP_WEIGHT_FRAC"]
    assert qformat.WEIGHT_MAX * 2**qformat.WEIGHT_FRAC == h["WAKE_RTP_WEIGHT_MAX"]
    assert qformat.TAP_ROW_ABS_MAX == h["WAKE_RTP_TAP_ROW_ABS_MAX"]


def test_the_compiled_core_has_the_same_formats():
    if not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    from types import SimpleNamespace

    from wake._rtp import lib

    assert qformat.format_mismatches(lib) == []
    names = [n for n in dir(lib) if n.startswith("WAKE_RTP_")]
    other = SimpleNamespace(**{n: getattr(lib, n) for n in names})
    other.WAKE_RTP_P_FRAC = qformat.P_FRAC - 2
    assert qformat.format_mismatches(other) == [f"WAKE_RTP_P_FRAC = {qformat.P_FRAC - 2} (wake.rtp.qformat: "
                                                f"{qformat.P_FRAC})"]


HIDE_CORE = "import sys; sys.modules['wake._rtp'] = None; from wake.cli import main; sys.exit(main({args!r}))"


def _export(tmp_path, name, hide):
    out = tmp_path / name
    args = ["export-header", str(out), "--full-scale", "4"]
    code = HIDE_CORE.format(args=args) if hide else f"import sys; from wake.cli import main; sys.exit(main({args!r}))"
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return out.read_text()


def test_export_header_works_without_the_compiled_core(tmp_path):
    text = _export(tmp_path, "hidden.h", hide=True)
    assert f"WAKE_RTP_P_FRAC != {qformat.P_FRAC}" in text
    if has_c_backend():
        assert text == _export(tmp_path, "with_core.h", hide=False)
