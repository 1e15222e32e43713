"""The Cortex-M cost of the on-device HPA (wake.firmware.hpa_cost) is measured, and its memory goal held."""

import shutil

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None,
                                reason="arm-none-eabi-gcc is not installed (the Arm GNU toolchain)")


def test_one_window_on_cortex_m4f_finishes_within_the_next_window_and_fits_6_kib(tmp_path):
    pytest.importorskip("unicorn")
    pytest.importorskip("capstone")
    from wake.firmware.hpa_cost import HPA_GOALS, measure_hpa, profile_windows

    window = {"synthetic 1": profile_windows(n_synthetic=1)["synthetic 1"]}
    r = measure_hpa("m4f-O2", windows=window, build_dir=tmp_path)
    row = r["rows"][0]
    assert row["whole"] > 100_000                       # a real run, not an early exit
    assert row["slices"] < 500                          # done before the next L = 500 samples
    assert row["sliced_total"] >= row["whole"] * 0.9    # the slices do the same work
    assert r["ram_hpa"] <= HPA_GOALS["ram"]             # both window buffers included
    assert 0 < r["stack"] <= 400
    assert np.isfinite(r["whole_median"])
