"""A channel without a finite sample is refused, one with fewer than an HPA window is named in a warning
(issue 43, item 2): never scored without a word, from Python and from `wake run`."""

import warnings

import numpy as np
import pytest

from wake import WakeFilter
from wake.cli import main
from wake import SparseChannelWarning
from wake._validation import check_finite_channels


def gyro(fs, seconds=12.0):
    """A wrist gyroscope: slow motion and a 6 Hz tremor around zero (deg/s)."""
    t = np.arange(int(seconds * fs)) / fs
    return 40.0 * np.sin(2 * np.pi * 0.4 * t) + 8.0 * np.sin(2 * np.pi * 6.0 * t)


def accel(fs, seconds=12.0):
    """An accelerometer axis: gravity (9.81 m/s^2) tilted slowly, and a 5 Hz tremor."""
    t = np.arange(int(seconds * fs)) / fs
    return 9.81 * np.cos(0.3 * np.sin(2 * np.pi * 0.2 * t)) + 0.5 * np.sin(2 * np.pi * 5.0 * t)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("make", [gyro, accel])
def test_a_channel_without_a_finite_sample_is_refused_by_name(fs, make):
    good = make(fs)
    x = np.column_stack([good, np.full(good.size, np.nan)])
    with pytest.raises(ValueError, match="channel wrist_y has no finite sample"):
        WakeFilter(fs=fs, backend="reference").run(x, names=["wrist_x", "wrist_y"])
    with pytest.raises(ValueError, match="channel 0 has no finite sample"):
        WakeFilter(fs=fs, backend="reference").run(np.full(good.size, np.nan))


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("make", [gyro, accel])
def test_a_channel_shorter_than_a_window_is_named_in_a_warning(fs, make):
    good = make(fs)
    filt = WakeFilter(fs=fs, backend="reference")
    sparse = good.copy()
    sparse[filt.window_samples - 1:] = np.nan   # one finite sample short of a window
    with pytest.warns(SparseChannelWarning, match=f"channel elbow has {filt.window_samples - 1} finite samples"):
        res = filt.run(np.column_stack([good, sparse]), names=["wrist", "elbow"])
    assert res.voluntary.shape == (good.size, 2)   # filtered all the same
    with warnings.catch_warnings():
        warnings.simplefilter("error", SparseChannelWarning)     # a full window: no warning
        check_finite_channels(good[:, None], filt.window_samples)


def test_names_must_match_the_channels():
    with pytest.raises(ValueError, match="names holds 1 name"):
        WakeFilter(backend="reference").run(np.zeros((600, 2)), names=["a"])


def _write(path, columns, header):
    np.savetxt(path, np.column_stack(columns), delimiter=",", header=header, comments="")
    return path


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_wake_run_refuses_an_all_nan_recording(tmp_path, capsys, fs):
    path = _write(tmp_path / "allnan.csv", [np.full(int(10 * fs), np.nan)] * 2, "gx,gy")
    out = tmp_path / "o.csv"
    assert main(["run", str(path), "--fs", f"{fs:g}", "--backend", "reference", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "channel gx and channel gy have no finite sample" in err
    assert not out.exists()


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("make", [gyro, accel])
def test_wake_run_names_a_sparse_channel(tmp_path, capsys, fs, make):
    good = make(fs)
    sparse = good.copy()
    sparse[int(3 * fs):] = np.nan
    path = _write(tmp_path / "rec.csv", [good, sparse], "wrist,elbow")
    with pytest.warns(SparseChannelWarning, match="channel elbow has"):
        assert main(["run", str(path), "--fs", f"{fs:g}", "--backend", "reference"]) == 0
    out = capsys.readouterr().out
    assert "elbow: no full HPA window (too few finite samples): not characterised" in out
    assert "wrist: a tremor peak in" in out
