"""Run the C core's own unit tests (csrc/tests) through make, so CI sees them."""

import os
import shutil
import subprocess

import pytest

from support import CSRC, ci_passed, ci_skip_reason


@pytest.mark.slow
@pytest.mark.skipif(ci_passed("make-test"), reason=ci_skip_reason("test"))
@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc is not installed")
def test_c_unit_tests(tmp_path):
    if not os.path.exists(os.path.join(CSRC, "Makefile")):
        pytest.skip("csrc/ is not part of this installation")
    # build out of tree so a read-only checkout works; CC=gcc for the sanitizers
    proc = subprocess.run(
        ["make", "-C", CSRC, "test", "CC=gcc", f"BUILD={tmp_path}"],
        capture_output=True, text=True, timeout=600,
    )
    out = proc.stdout + proc.stderr
    if proc.returncode != 0 and "fsanitize" in out and "cannot find" in out:
        pytest.skip("the sanitizer runtimes (libasan/libubsan) are not installed")
    assert proc.returncode == 0, out[-4000:]
    assert " 0 failed" in out
