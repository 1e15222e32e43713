"""The two batch paths of the C backend against the point-by-point path they replace.

* ``"install"``: ``WakeFilter(backend="c")`` with the Python HPA finishes a run of analysed windows in Python and
  hands their RTP stretches and installs to one C call (``wake.hpa.c_batch.InstallBatch``, ``wake_batch_install``).
* ``"driver"``: ``WakeFilter(backend="c", hpa_backend="c")`` hands runs of HPA points to the C driver
  (``wake.hpa.c_batch.Batch``, ``wake_batch_run``).

Every point a path does not cover, or that its C call refuses, runs on ``Channel.hpa``.  With the path switched
off (its ``covers`` rule False) every point runs there: outputs and HPA history must be the same bit for bit, at
100 and 1000 Hz (the rate adapter), on a gyroscope and on an accelerometer with gravity.  What only one path has
is tested in tests/hpa/test_install_batch.py and tests/hpa/test_c_batch.py.
"""

import numpy as np
import pytest
from support import assert_same_history, motion

from batch_paths import PATHS, assert_same_run, without_path
from wake import WakeFilter
from wake.rtp import c_backend_available

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")


@pytest.fixture(params=sorted(PATHS))
def path(request):
    return PATHS[request.param]


@pytest.fixture
def taken(path, monkeypatch):
    return path.count_points(monkeypatch)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_the_path_matches_the_point_by_point_path(path, fs, kind, monkeypatch, taken):
    x, _ = motion(fs, kind, seconds=40.0)
    used = assert_same_run(path, x, monkeypatch, taken, fs=fs)
    assert used >= 3 * 6   # three channels, most of their 11 points on the path


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_blocks_and_updates_unchanged(path, fs, kind, monkeypatch, taken):
    x = motion(fs, kind, seconds=25.0)[0][:, 2]
    cuts = np.cumsum([1, 333, 2000, 7, 4000])
    cuts = cuts[cuts < x.shape[0]]

    def blocks():
        f = path.filter(fs=fs)
        out = np.concatenate([f.update_block(part) for part in np.split(x, cuts)])
        return out, f.hpa_history

    out, hist = blocks()
    assert taken[0] > 0
    ref, ref_hist = without_path(path, blocks, monkeypatch)
    assert np.array_equal(out, ref, equal_nan=True)
    assert_same_history(hist, ref_hist)
    f = path.filter(fs=fs)
    stepped = np.array([f.update(float(v)) for v in x[: x.shape[0] // 2]])
    assert np.array_equal(stepped, out[: x.shape[0] // 2], equal_nan=True)


@pytest.mark.filterwarnings("ignore::wake.rtp.adaptive.ClippingWarning")   # the clipped case's, both ways
@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_gaps_clipping_and_a_jump_fall_back_point_by_point(path, fs, monkeypatch, taken):
    x = motion(fs, "acc", seconds=40.0, seed=2)[0][:, 2].copy()
    n = x.shape[0]
    x[n // 4 : n // 4 + int(2 * fs)] = np.nan        # a long gap
    x[n // 2 : n // 2 + 5] = np.nan                  # a short one
    x[3 * n // 4 :] += 40.0                          # a jump: the overflow rule raises the full scale
    used = assert_same_run(path, x, monkeypatch, taken, fs=fs)
    assert used > 0
    taken[0] = 0
    assert_same_run(path, x, monkeypatch, taken, fs=fs, full_scale=4.0)   # clipped at a fixed full scale


def test_bad_input_refused_alike(path, monkeypatch):
    x = motion(100.0, "gyro", seconds=10.0)[0][:, 0].copy()
    x[700] = np.inf
    messages = []
    for run in (lambda: path.filter().run(x),) * 2:
        with pytest.raises(ValueError) as info:
            run() if not messages else without_path(path, run, monkeypatch)
        messages.append(str(info.value))
    assert messages[0] == messages[1] and "inf" in messages[0]


def test_both_paths_are_tested():
    assert sorted(PATHS) == ["driver", "install"]
    assert isinstance(PATHS["driver"].filter(), WakeFilter)
