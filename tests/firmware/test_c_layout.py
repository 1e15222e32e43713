"""The RTP's C modules: one concern per file, the build lists naming them all, no `.c` included anywhere.

docs/reference/architecture.md ("The C core's files") lists the modules; these tests keep the layout it
describes: every module a few hundred lines at most, no feature switch tested in any `.c` (a feature is the
entries a firmware links: wake.firmware.sources.FEATURE_ENTRIES, which the Makefile's cross link reads through
the generated csrc/wake_features.mk), every build list (Makefile, CMake, export-c and its layouts) naming every
module, and the verification layer (unit tests, proofs, fuzz harnesses) reaching internals through headers only.
"""

import re

import pytest

from support import CSRC
from wake.firmware.sources import (FEATURE_DEFAULTS, FEATURE_ENTRIES, FEATURES_MAKE, HPA_SOURCES, RTP_INTERNAL,
                                   RTP_SOURCES, features_make_text, firmware_entries)

#: the longest a module of the RTP may be (issue 45)
MAX_LINES = 800
#: the feature switches: each adds an instance's state to a struct (in a header) and entries a firmware links
#: or not; WAKE_RTP_KALMAN is a size variant of the core (its modules test it), not one of them, see the
#: architecture reference
FEATURES = ("WAKE_RTP_SPLIT", "WAKE_RTP_AHEAD", "WAKE_RTP_VOLUNTARY_AHEAD", "WAKE_HPA_AHEAD")
#: where a `.c` may test a feature switch: nowhere (issue 45)
ALLOWED = {}


def rtp_modules():
    return sorted(p.name for p in CSRC.glob("wake_rtp*.c"))


def switched_modules():
    """Every `.c` of the library a feature switch could hide in: the RTP's modules, the front end, the HPA's."""
    return sorted({*rtp_modules(), "wake_rate.c", *HPA_SOURCES, *(p.name for p in CSRC.glob("wake_hpa*.c"))})


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


@pytest.mark.parametrize("name", switched_modules())
def test_no_module_tests_a_feature_switch(name):
    assert switches_tested((CSRC / name).read_text()) == ALLOWED.get(name, []), name


def test_the_switch_finder_scans_the_front_end_and_the_hpa():
    names = switched_modules()
    assert "wake_rate.c" in names and "wake_hpa.c" in names and "wake_hpa_ahead.c" in names
    assert all((CSRC / n).is_file() for n in names)


def test_the_makefile_reads_the_one_list_of_feature_entries():
    assert set(FEATURE_ENTRIES) == set(FEATURE_DEFAULTS)
    assert (CSRC / FEATURES_MAKE).read_text() == features_make_text(), (
        f"csrc/{FEATURES_MAKE} is stale: run python -m wake.firmware.sources --write-make")
    makefile = (CSRC / "Makefile").read_text()
    assert f"include {FEATURES_MAKE}" in makefile
    assert "wake_entries_off" in makefile.split("define cross_link_of")[1].split("endef")[0]


@pytest.mark.parametrize("defs,off", [
    ([], {"WAKE_RTP_SPLIT", "WAKE_RTP_VOLUNTARY_AHEAD"}),
    (["-DWAKE_RTP_AHEAD=0"], {"WAKE_RTP_AHEAD", "WAKE_RTP_SPLIT", "WAKE_RTP_VOLUNTARY_AHEAD"}),
    (["-DWAKE_RTP_SPLIT=1"], {"WAKE_RTP_VOLUNTARY_AHEAD"}),
    (["-DWAKE_RTP_VOLUNTARY_AHEAD"], {"WAKE_RTP_SPLIT"}),
])
def test_a_firmware_links_only_its_features_entries(defs, off):
    every = [e for entries in FEATURE_ENTRIES.values() for e in entries] + ["wake_rtp_step", "wake_rate_push"]
    kept = set(firmware_entries(every, defs, prefixes=("wake_rtp_", "wake_rate_")))
    assert {"wake_rtp_step", "wake_rate_push"} <= kept
    for switch, entries in FEATURE_ENTRIES.items():
        assert kept.isdisjoint(entries) if switch in off else kept.issuperset(entries), (switch, defs)


@pytest.mark.skipif(not __import__("shutil").which("make"), reason="make is not installed")
@pytest.mark.parametrize("defs", ["", "-mcpu=cortex-m4 -DWAKE_RTP_AHEAD=0", "-DWAKE_RTP_SPLIT=1",
                                  "-DWAKE_RTP_VOLUNTARY_AHEAD=1"])
def test_the_makefile_leaves_off_what_firmware_entries_leaves_off(defs, tmp_path):
    """make evaluates wake_entries_off for the flags: the same entries as firmware_entries leaves out."""
    import subprocess

    probe = tmp_path / "probe.mk"
    probe.write_text(f"include {CSRC / FEATURES_MAKE}\nall:\n\t@echo $(strip $(call wake_entries_off,{defs}))\n")
    got = subprocess.run(["make", "-s", "-f", str(probe)], capture_output=True, text=True, check=True).stdout.split()
    every = [e for entries in FEATURE_ENTRIES.values() for e in entries]
    assert sorted(got) == sorted(set(every) - set(firmware_entries(every, defs.split(),
                                                                    prefixes=("wake_rtp_", "wake_rate_"))))


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
