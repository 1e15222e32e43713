"""The time column is found as wide as the README says (issue 43, item 6): by a name in other languages and
units, after a text column, and by its shape without a header; at 100 Hz and 1 kHz, gyroscope and
accelerometer with gravity."""

import numpy as np
import pytest

from io_recordings import KINDS, RATES, signals, write
from wake.io import read_recording
from wake.io.time_column import is_time_name


@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name, scale", [("Zeit [s]", 1.0), ("Zeit", 1.0), ("time_ms", 1e3), ("temps (s)", 1.0),
                                         ("tiempo_ms", 1e3), ("Timestamp (ms)", 1e3), ("unix_time", 1.0)])
def test_a_first_column_named_like_time_in_another_language_or_unit_is_time(tmp_path, kind, fs, name, scale):
    names, units, x = signals(kind, fs)
    t = 1700.0 + np.arange(x.shape[0]) / fs
    path = write(tmp_path / "rec.csv", [name, *names], [[ti * scale, *row] for ti, row in zip(t, x)])
    rec = read_recording(path)
    assert rec.fs == fs and rec.channels == names and rec.samples.shape == x.shape
    np.testing.assert_allclose(rec.samples, x, rtol=1e-12, atol=1e-9)
    assert rec.t0 == pytest.approx(1700.0)


@pytest.mark.parametrize("fs", (200.0, 1000.0))
def test_timestamp_ms_after_a_subject_column_is_found(tmp_path, fs):
    _, _, acc = signals("acc", fs)
    _, _, gyro = signals("gyro", fs)
    t = 1_700_000_000_000 + np.arange(acc.shape[0]) * (1000.0 / fs)  # epoch milliseconds: 1 kHz steps by 1
    rows = [["P01", int(ti), *a, *g] for ti, a, g in zip(t, acc, gyro)]
    path = write(tmp_path / "phone.csv", ["subject", "timestamp_ms", "ax", "ay", "az", "gx", "gy", "gz"],
                 [[str(c) if isinstance(c, (int, str)) else c for c in r] for r in rows])
    rec = read_recording(path)
    assert rec.fs == fs
    assert rec.channels == ("ax", "ay", "az", "gx", "gy", "gz")
    np.testing.assert_allclose(rec.samples, np.hstack([acc, gyro]), rtol=1e-12, atol=1e-9)
    assert "time column 'timestamp_ms' in ms" in rec.timing.describe(rec.fs)


@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
def test_without_a_header_a_clock_after_a_text_column_is_found_by_its_shape(tmp_path, kind, fs):
    _, _, x = signals(kind, fs)
    t = np.arange(x.shape[0]) / fs
    path = write(tmp_path / "rec.csv", None, [["S1", ti, *row] for ti, row in zip(t, x)])
    rec = read_recording(path)
    assert rec.fs == fs and rec.channels == ("col2", "col3", "col4")
    np.testing.assert_allclose(rec.samples, x, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("fs", RATES)
def test_a_named_signal_that_steps_evenly_is_still_a_signal(tmp_path, fs):
    n = int(10 * fs)
    ramp = np.arange(n) * 0.5  # a named column: its name decides, not its shape
    path = write(tmp_path / "rec.csv", ["angle", "gx"], [[r, np.sin(i / 10)] for i, r in enumerate(ramp)])
    with pytest.raises(ValueError, match="has no time column"):
        read_recording(path)
    assert read_recording(path, fs=fs).channels == ("angle", "gx")


def test_the_name_rule():
    from wake.io.time_column import find_time_column

    for name in ("t", "time", "Zeit", "zeit_ms", "Zeitstempel", "temps", "tiempo", "tempo", "tijd", "czas",
                 "timestamp_ms", "TimeUs", "elapsed_time", "loggingTime", "unix_time", "ms", "millis", "seconds"):
        assert is_time_name(name), name
    for name in ("gyro_x", "end_time", "time_share", "reaction_time", "s", "us", "subject", "acc_z"):
        assert not is_time_name(name), name
    assert find_time_column(["subject", "x"], lambda j: j == 0, None, True) == (None, "")
