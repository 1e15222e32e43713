"""A time column's unit: from its header, its name or its step size, and said in the timing line."""

import numpy as np
import pytest

from wake.cli import main
from wake.io import read_csv
from wake.io.time_column import is_time_name, unit_from_name, unit_from_steps


def _write(path, header, time, value):
    lines = [header] + [f"{t:g},{v:.6f}" for t, v in zip(time, value)]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def signal():
    n = 1200
    return np.sin(2 * np.pi * 1.0 * np.arange(n) / 100.0) + 0.1 * np.sin(2 * np.pi * 6.0 * np.arange(n) / 100.0)


@pytest.mark.parametrize("name, scale", [("timestamp_ms", 1e3), ("time_ms", 1e3), ("t [ms]", 1e3), ("TimeMs", 1e3),
                                         ("time_msec", 1e3), ("millis", 1e3), ("time_us", 1e6),
                                         ("timestamp [us]", 1e6), ("t_ns", 1e9), ("time", 1.0),
                                         ("timestamp_s", 1.0), ("elapsed_sec", 1.0)])
def test_a_named_time_column_is_read_in_its_unit(tmp_path, signal, name, scale):
    path = _write(tmp_path / "rec.csv", f"{name},gyro_x", np.arange(signal.size) / 100.0 * scale, signal)
    rec = read_csv(path)
    assert rec.fs == 100.0
    assert rec.channels == ("gyro_x",)
    np.testing.assert_allclose(rec.samples[:, 0], signal, atol=1e-6)


def test_timestamp_ms_is_not_taken_as_a_signal_and_says_its_unit(tmp_path, signal, capsys):
    path = _write(tmp_path / "rec.csv", "timestamp_ms,gyro_x", np.arange(signal.size) * 10.0, signal)
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--out", str(out), "--backend", "reference"]) == 0
    said = capsys.readouterr().out
    assert "100 Hz" in said and "time column 'timestamp_ms' in ms (from its name)" in said
    header = out.read_text().splitlines()[0]
    assert "timestamp_ms_voluntary" not in header and "gyro_x_voluntary" in header


def test_naming_the_ms_column_reads_it_in_ms(tmp_path, signal):
    path = tmp_path / "rec.csv"
    path.write_text("gyro_x,timestamp_ms\n" + "\n".join(f"{v:.6f},{10 * i}" for i, v in enumerate(signal)) + "\n")
    rec = read_csv(path, time_column="timestamp_ms")
    assert rec.fs == 100.0 and rec.channels == ("gyro_x",) and rec.samples.shape == (signal.size, 1)
    assert "time column 'timestamp_ms' in ms (from its name)" in rec.timing.describe(rec.fs)


def test_an_unlabelled_clock_in_ms_is_judged_from_its_steps_and_says_so(tmp_path, signal):
    path = tmp_path / "rec.csv"
    path.write_text("\n".join(f"{10 * i},{v:.6f}" for i, v in enumerate(signal)) + "\n")
    rec = read_csv(path)
    assert rec.fs == 100.0
    assert "in ms (from the size of its steps)" in rec.timing.describe(rec.fs)


def test_a_time_column_in_seconds_is_not_rescaled(tmp_path, signal):
    path = tmp_path / "rec.csv"
    path.write_text("\n".join(f"{i / 100:.2f},{v:.6f}" for i, v in enumerate(signal)) + "\n")
    rec = read_csv(path)
    assert rec.fs == 100.0 and "in s" in rec.timing.describe(rec.fs)


def test_unit_rules():
    assert unit_from_name("timestamp_ms").unit == "ms"
    assert unit_from_name("time", "ms").source == "unit cell"
    assert unit_from_name("time") is None
    assert is_time_name("ts_ms") and is_time_name("timestamp") and not is_time_name("gyro_x")
    assert not is_time_name("s")  # a one-letter signal name, not "seconds"
    assert unit_from_steps(np.arange(10) * 10.0).unit == "ms"
    assert unit_from_steps(np.arange(10) * 1000.0).unit == "us"
    assert unit_from_steps(np.arange(10) / 100.0).unit == "s"
