"""The C core built with clang stays within 1.3x of gcc's instruction counts and code size (docs/studies/profiling.md)."""

import shutil
from pathlib import Path

import pytest

from wake.firmware.profile import build as B

def _missing() -> str | None:
    """Exactly what is missing for this comparison, or None."""
    missing = [] if B.clang_command() else ["clang (or clang-14)"]
    missing += [tool for tool in ("arm-none-eabi-gcc",) if shutil.which(tool) is None]
    if not Path(B.NEWLIB_INCLUDE).is_dir():
        missing.append(f"the newlib headers ({B.NEWLIB_INCLUDE})")
    if not missing:
        return None
    return f"{' and '.join(missing)} {'is' if len(missing) == 1 else 'are'} not installed (CI needs only gcc)"


pytestmark = pytest.mark.skipif(_missing() is not None, reason=str(_missing()))


@pytest.mark.parametrize("target", list(B.TARGETS))
def test_clang_code_is_within_1_3x_of_gcc(tmp_path, target):
    from wake.firmware.profile.report import section_sizes

    size = {}
    for compiler in ("gcc", "clang"):
        image = B.build_image(target, build_dir=tmp_path / compiler, defs=["-DWAKE_RTP_MAX_LEVEL=5"],
                              compiler=compiler)
        sections = section_sizes(image.core_object)
        size[compiler] = sections[".text"] + sections[".rodata"]
    assert size["gcc"] > 1000                       # a real core, not an empty object
    assert size["clang"] <= 1.3 * size["gcc"], size


def test_clang_step_counts_are_within_1_3x_of_gcc_on_cortex_m4(tmp_path):
    pytest.importorskip("unicorn")
    pytest.importorskip("capstone")
    from wake.firmware.profile.emulator import Emulator
    from wake.firmware.profile.scenarios import profile_configuration

    worst = {}
    for compiler in ("gcc", "clang"):
        emu = Emulator(B.build_image("m4-O2", build_dir=tmp_path / compiler, defs=["-DWAKE_RTP_MAX_LEVEL=5"],
                                     compiler=compiler))
        worst[compiler] = {k: profile_configuration(emu, "sym3", 5, kalman=k, n=40).max for k in (True, False)}
    for kalman in (True, False):
        assert worst["gcc"][kalman] > 100
        assert worst["clang"][kalman] <= 1.3 * worst["gcc"][kalman], (kalman, worst)
