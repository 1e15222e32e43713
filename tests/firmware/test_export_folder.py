"""``wake export-c``: the drop-in firmware folder compiles, runs, and never overwrites by surprise."""

import shutil
import subprocess

import numpy as np
import pytest

from support import CSRC

from wake.cli import main
from wake.firmware.folder import export_folder
from wake.firmware.sources import HPA_INTERNAL_HEADERS, HPA_SOURCES, INTERNAL_HEADERS, RTP_HEADERS, RTP_SOURCES

CONFIG = dict(wavelet="sym3", level=5, measurement_noise=1e-3, full_scale=4.0)
HOST_CC = shutil.which("cc") or shutil.which("gcc")
ARM_CC = shutil.which("arm-none-eabi-gcc")

# A tiny firmware main: start a channel with the exported configuration, feed
# it a ramp and print the predictions (one per line) so the test can compare.
DRIVER = r"""
#include <stdio.h>
#include "wake_rtp.h"
#include "wake_config.h"
int main(void)
{
    static wake_rtp_t rtp;
    int n;
    if (wake_config_init(&rtp) != WAKE_RTP_OK) return 3;
    for (n = 0; n < 64; ++n) {
        wake_q15_t y;
        if (wake_rtp_step(&rtp, (wake_q15_t)(n * 200 - 6000), &y) != WAKE_RTP_OK) return 4;
        printf("%d\n", (int)y);
    }
    return 0;
}
"""


def compile_folder(cc, folder, extra):
    """Compile every .c of the folder plus a unit that uses the configuration header."""
    use = folder / "use_config.c"
    use.write_text('#include "wake_hpa.h"\n#include "wake_config.h"\n'
                   "int start(void) { static wake_rtp_t r; static wake_hpa_t h;\n"
                   "  return wake_config_init(&r) == WAKE_RTP_OK && wake_config_hpa_init(&h) == WAKE_HPA_OK; }\n")
    for src in (*RTP_SOURCES, *HPA_SOURCES, "use_config.c"):
        subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-Wdouble-promotion", "-ffp-contract=off",
                        *extra, "-c", str(folder / src),
                        "-o", str(folder / (src + ".o"))], check=True, capture_output=True, text=True)


def test_folder_holds_the_core_unchanged_and_the_configuration(tmp_path):
    files = export_folder(tmp_path / "fw", sources=CSRC, **CONFIG)
    assert [f.relative_to(tmp_path / "fw").as_posix() for f in files] == [
        "wake_rtp.c", *RTP_HEADERS, "wake_fixed.h", *RTP_SOURCES[1:], *HPA_SOURCES, "wake_hpa.h", *INTERNAL_HEADERS,
        "wake_rate.c", "wake_rate.h", "wake_config.h", "README.md"]
    for name in (*RTP_HEADERS, "wake_fixed.h", *RTP_SOURCES, *HPA_SOURCES, "wake_hpa.h", *INTERNAL_HEADERS,
                 "wake_rate.c", "wake_rate.h"):
        assert (tmp_path / "fw" / name).read_bytes() == (CSRC / name).read_bytes()
    header = (tmp_path / "fw" / "wake_config.h").read_text()
    assert "static inline wake_rtp_status_t wake_config_init(wake_rtp_t *rtp)" in header
    assert "static inline wake_hpa_status_t wake_config_hpa_init(wake_hpa_t *hpa)" in header
    readme = (tmp_path / "fw" / "README.md").read_text()
    assert "add_library(wake_rtp STATIC" in readme and "wake_config_init(&rtp)" in readme


def test_refuses_to_overwrite_without_force(tmp_path):
    out = tmp_path / "fw"
    out.mkdir()
    (out / "wake_rtp.c").write_text("my own edits")
    with pytest.raises(FileExistsError, match="already holds wake_rtp.c.*--force"):
        export_folder(out, sources=CSRC, **CONFIG)
    assert (out / "wake_rtp.c").read_text() == "my own edits"
    export_folder(out, force=True, sources=CSRC, **CONFIG)
    assert (out / "wake_rtp.c").read_bytes() == (CSRC / "wake_rtp.c").read_bytes()


def test_a_file_in_the_way_and_a_bad_configuration_write_nothing(tmp_path, capsys):
    blocker = tmp_path / "fw"
    blocker.write_text("x")
    assert main(["export-c", str(blocker)]) == 2
    assert "is not a directory" in capsys.readouterr().err
    assert main(["export-c", str(tmp_path / "new"), "--full-scale", "-1"]) == 2
    assert "full_scale must lie in" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()


@pytest.mark.skipif(HOST_CC is None, reason="no host C compiler (cc or gcc) on PATH")
def test_exported_folder_builds_and_runs_on_the_host_like_the_python_core(tmp_path):
    out = tmp_path / "fw"
    assert main(["export-c", str(out), "--full-scale", "4"]) == 0
    compile_folder(HOST_CC, out, [])
    (out / "driver.c").write_text(DRIVER)
    exe = out / "driver"
    subprocess.run([HOST_CC, "-std=c99", "-Wall", "-Wextra", "-Werror", "-I", str(out), str(out / "driver.c"),
                    *(str(out / m) for m in RTP_SOURCES), "-o", str(exe)], check=True, capture_output=True, text=True)
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, run.returncode
    got = np.array(run.stdout.split(), dtype=int)
    fixed = pytest.importorskip("wake.rtp.fixed", reason="the C extension is not built")
    from wake.hpa.prior import prior_weights
    from wake.config import WakeConfig
    from wake.wavelets import filter_bank_taps

    taps = filter_bank_taps("sym3", 5)
    start = prior_weights(WakeConfig(fs=100.0, wavelet="sym3", level=5), taps)
    # the CLI's defaults: start-up weights at 100 Hz, R = 1e-3 FS^2, q = p0 = 0
    rtp = fixed.FixedPointRTP(taps, start, 1e-3 * 16.0, 0.0, 0.0, full_scale=4.0)
    x = (np.arange(64) * 200 - 6000) / 32768 * 4.0
    want = np.round(rtp.run(x) / 4.0 * 32768).astype(int)
    np.testing.assert_array_equal(got, want)


@pytest.mark.skipif(ARM_CC is None, reason="arm-none-eabi-gcc is not installed (the Arm GNU toolchain)")
def test_exported_folder_builds_for_cortex_m4(tmp_path):
    out = tmp_path / "fw"
    export_folder(out, sources=CSRC, **CONFIG)
    compile_folder(ARM_CC, out, ["-mcpu=cortex-m4", "-mthumb"])
    assert (out / "wake_rtp.c.o").stat().st_size > 0


def test_the_hpa_file_list_is_the_sources_folders():
    """HPA_SOURCES (what every packaging layout lists) names every csrc/wake_hpa*.c and nothing else, and every
    internal header the HPA's files include."""
    assert sorted(HPA_SOURCES) == sorted(p.name for p in CSRC.glob("wake_hpa*.c"))
    assert sorted(HPA_INTERNAL_HEADERS) == sorted(f"internal/{p.name}" for p in (CSRC / "internal").glob("*.h")
                                                  if p.name.startswith(("wake_hpa", "wake_bounds")))
