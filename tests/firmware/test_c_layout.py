"""The RTP's C modules: one concern per file, the build lists naming them all, no `.c` included anywhere.

docs/reference/architecture.md ("The C core's files") lists the modules; these tests keep the layout it
describes: every module a few hundred lines at most, a feature switch tested in a `.c` only by the module
of that feature, every build list (Makefile, CMake, export-c and its layouts) naming every module, and
the verification layer (unit tests, proofs, fuzz harnesses) reaching internals through headers only.
"""

import re

import pytest

from support import CSRC
from wake.firmware.sources import RTP_INTERNAL, RTP_SOURCES

#: the longest a module of the RTP may be (issue 45)
MAX_LINES = 800
#: the feature switches (each chooses a module and its state; WAKE_RTP_KALMAN is still a switch inside the
#: core's and the state's modules, see the architecture reference)
FEATURES = ("WAKE_RTP_SPLIT", "WAKE_RTP_AHEAD", "WAKE_RTP_VOLUNTARY_AHEAD")
#: where a `.c` may test a feature switch: the split step's whole-file guard; the voluntary ahead's guard around
#: all but its instance's output entry (wake_voluntary_ahead.h); the host's block entry, which exists in the
#: voluntary build only (the tremor ahead is an instance, wake_ahead.h, and tests none)
ALLOWED = {"wake_rtp_split.c": ["WAKE_RTP_SPLIT"],
           "wake_rtp_voluntary.c": ["WAKE_RTP_VOLUNTARY_AHEAD"],
           "wake_rtp_block.c": ["WAKE_RTP_VOLUNTARY_AHEAD"]}


def rtp_modules():
    return sorted(p.name for p in CSRC.glob("wake_rtp*.c"))


def switches_tested(text: str) -> list:
    """The feature switches each `#if` / `#elif` of the text names, in order (WAKE_RTP_SPLIT_FIR is not one)."""
    found = []
    for line in text.splitlines():
        if re.match(r"\s*#\s*(if|elif)\b", line):
            found += [f for f in FEATURES if re.search(rf"\b{f}\b", line)]
    return found


def test_the_modules_are_the_ones_every_build_lists():
    assert sorted(RTP_SOURCES) == rtp_modules()
    assert RTP_SOURCES[0] == "wake_rtp.c"
    makefile = (CSRC / "Makefile").read_text()
    cmake = (CSRC / "CMakeLists.txt").read_text()
    for name in RTP_SOURCES:
        assert re.search(rf"\b{re.escape(name)}\b", makefile.split("HDR")[0]), f"{name} not in csrc/Makefile's SRC"
        assert name in cmake, f"{name} not in csrc/CMakeLists.txt"
    for header in RTP_INTERNAL:
        assert (CSRC / header).is_file(), header
        assert header in makefile, f"{header} not in csrc/Makefile's HDR"


@pytest.mark.parametrize("name", rtp_modules())
def test_a_module_is_a_few_hundred_lines(name):
    lines = (CSRC / name).read_text().count("\n")
    assert lines <= MAX_LINES, f"{name}: {lines} lines; split it by concern"


@pytest.mark.parametrize("name", rtp_modules())
def test_a_feature_switch_is_tested_only_by_its_module(name):
    assert switches_tested((CSRC / name).read_text()) == ALLOWED.get(name, []), name


def test_the_switch_finder_sees_a_switch_and_ignores_the_arithmetic():
    assert switches_tested("#if WAKE_RTP_SPLIT\n#endif\n#if WAKE_RTP_SPLIT_FIR\n") == ["WAKE_RTP_SPLIT"]
    assert switches_tested("#elif WAKE_RTP_AHEAD && X\n  /* #if WAKE_RTP_SPLIT */") == ["WAKE_RTP_AHEAD"]


def test_the_verification_layer_includes_no_c_file_of_the_rtp():
    drivers = [*CSRC.glob("tests/*.c"), *CSRC.glob("tests/prove/*.c"), *CSRC.glob("tests/fuzz/*.c")]
    assert drivers
    for path in drivers:
        for include in re.findall(r'#\s*include\s+"([^"]+)"', path.read_text()):
            assert not re.fullmatch(r"(.*/)?wake_rtp\w*\.c", include), f"{path.name} includes {include}"


def test_every_bound_for_the_analyser_points_at_its_argument():
    text = (CSRC / "internal" / "wake_bounds.h").read_text()
    bounds = re.findall(r"#define (WAKE_BOUND_RTP_\w+)", text)
    assert bounds
    used = "".join((CSRC / p).read_text() for p in (*RTP_SOURCES, *RTP_INTERNAL) if not p.endswith("bounds.h"))
    for name in bounds:
        assert re.search(rf"\b{name}\b", used), f"{name} is not used"
    assert '"Corrupted state"' in text
    study = (CSRC.parent / "docs" / "studies" / "verification.md").read_text()
    assert "### Corrupted state" in study and "wake_bounds.h" in study
