"""A rate that contradicts the file's own time column is refused, naming both rates, unless ``--resample``
asks for that grid (issue 43, item 3); at 100 Hz and 1 kHz, gyroscope and accelerometer with gravity."""

import numpy as np
import pytest

from io_recordings import KINDS, RATES, signals, write
from wake.cli import main
from wake.io import read_recording


def _file(tmp_path, kind, fs):
    names, units, x = signals(kind, fs, seconds=8.0)
    t = np.arange(x.shape[0]) / fs
    return write(tmp_path / f"{kind}.csv", ["time [s]", *(f"{n} [{u}]" for n, u in zip(names, units))],
                 [[ti, *row] for ti, row in zip(t, x)]), x


@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
def test_a_contradicting_fs_is_refused_with_both_rates(tmp_path, capsys, kind, fs):
    path, x = _file(tmp_path, kind, fs)
    wrong = fs * 10 if fs < 1000 else fs / 10
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", f"{wrong:g}", "--out", str(out), "--backend", "reference"]) == 2
    err = capsys.readouterr().err
    assert f"{wrong:g} Hz contradicts the time column 'time', which runs at {fs:g} Hz" in err
    assert "--resample" in err and "--time-column none" in err and "Traceback" not in err
    assert not out.exists()
    with pytest.raises(ValueError, match=f"fs \\(--fs\\) {wrong:g} Hz contradicts"):
        read_recording(path, fs=wrong)


@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
def test_resample_asks_for_the_grid_and_an_agreeing_fs_needs_nothing(tmp_path, kind, fs):
    path, x = _file(tmp_path, kind, fs)
    rec = read_recording(path, fs=fs * 1.01)  # within 5 %: the user's grid, resampled
    assert rec.fs == pytest.approx(fs * 1.01) and rec.timing.resampled
    grid = fs * 2
    rec = read_recording(path, fs=grid, resample=True)
    assert rec.fs == grid and rec.samples.shape[0] == 2 * (x.shape[0] - 1) + 1
    np.testing.assert_allclose(rec.samples[::2], x, atol=1e-9)
    rec = read_recording(path, fs=grid, time_column=None)  # the time column ignored: the rows taken as given
    assert rec.fs == grid and rec.channels[0] == "time" and rec.samples.shape[0] == x.shape[0]


@pytest.mark.parametrize("fs", RATES)
def test_the_cli_resamples_with_resample(tmp_path, capsys, fs):
    path, x = _file(tmp_path, "gyro", fs)
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", f"{fs / 2:g}", "--resample", "--out", str(out),
                 "--backend", "reference"]) == 0
    assert f"onto a uniform {fs / 2:g} Hz grid" in capsys.readouterr().out
    assert len(out.read_text().splitlines()) - 1 == (x.shape[0] - 1) // 2 + 1
