"""Recordings in: time columns, resampling, names and units, PADS and MATLAB files, and every format error."""

import numpy as np
import pytest

from support import NO_PADS, pads_dir

from wake.cli import main
from wake.io import read_csv, read_mat, read_recording, resample_uniform, write_result_csv
from wake.io.recording import nominal_rate


def jittered_times(n, fs, rng, jitter=0.2):
    return np.arange(n) / fs + rng.uniform(-jitter, jitter, n) / fs


def test_round_trip_keeps_time_names_and_units(tmp_path, rng):
    n = 700
    t = 3.0 + np.arange(n) / 100.0
    x = np.column_stack([np.sin(2 * np.pi * 5 * t), np.cos(2 * np.pi * 1 * t)])
    src = tmp_path / "in.csv"
    np.savetxt(src, np.column_stack([t, x]), delimiter=",", header="time [s],gyro_x [rad/s],acc_z [g]",
               comments="", fmt="%.10g")
    rec = read_csv(src)
    assert (rec.fs, rec.channels, rec.units, rec.t0) == (100.0, ("gyro_x", "acc_z"), ("rad/s", "g"), 3.0)
    assert not rec.timing.resampled
    np.testing.assert_allclose(rec.samples, x, rtol=1e-9)
    from wake import WakeFilter

    res = WakeFilter(fs=rec.fs, backend="reference").run(rec.samples)
    out = tmp_path / "out.csv"
    assert write_result_csv(out, rec, res) == n
    back = read_csv(out)
    assert back.channels == ("gyro_x", "gyro_x_voluntary", "gyro_x_tremor", "acc_z", "acc_z_voluntary",
                             "acc_z_tremor")
    assert back.units == ("rad/s",) * 3 + ("g",) * 3 and back.fs == 100.0 and back.t0 == 3.0
    np.testing.assert_allclose(back.channel("acc_z_voluntary"), res.voluntary[:, 1], rtol=1e-8, atol=1e-12)


def test_irregular_timestamps_are_resampled_and_reported(tmp_path, rng):
    fs = 100.0
    t = jittered_times(2000, fs, rng)
    t.sort()
    f = lambda tt: np.sin(2 * np.pi * 0.7 * tt)  # noqa: E731  slow enough for linear interpolation
    path = tmp_path / "jitter.csv"
    np.savetxt(path, np.column_stack([t, f(t)]), delimiter=",", fmt="%.10f")  # no header: time by its shape
    rec = read_recording(path)
    assert rec.fs == 100.0 and rec.timing.resampled and rec.timing.source == "time column"
    assert 0.0005 < rec.timing.jitter < 0.002  # uniform +-2 ms: std 1.15 ms
    np.testing.assert_allclose(rec.samples[:, 0], f(rec.time), atol=2e-3)
    assert "resampled 2000 timestamped rows onto a uniform 100 Hz grid" in rec.timing.describe(rec.fs)


def test_time_in_milliseconds_by_its_name(tmp_path):
    path = tmp_path / "ms.csv"
    path.write_text("t [ms];x\n" + "".join(f"{4 * i};{i % 5}\n" for i in range(100)))  # semicolons, 250 Hz
    rec = read_recording(path)
    assert rec.fs == 250.0 and rec.channels == ("x",) and rec.samples.shape == (100, 1)


def test_comment_lines_tabs_and_a_row_counter(tmp_path):
    path = tmp_path / "counter.tsv"
    path.write_text("# exported by a logger\n" + "".join(f"{i}\t{0.1 * i}\n" for i in range(50)))
    with pytest.raises(ValueError, match="has no time column.*--fs HZ.*--time-column"):
        read_recording(path)  # 0, 1, 2, ... is an index, not seconds
    rec = read_recording(path, fs=50.0)
    assert rec.channels == ("col1",) and rec.samples.shape == (50, 1)
    np.testing.assert_allclose(rec.samples[:, 0], 0.1 * np.arange(50))


def test_pads_layout_is_recognised_by_shape(tmp_path, rng):
    t = np.cumsum(rng.uniform(0.009, 0.011, 600))
    path = tmp_path / "001_Task_LeftWrist.txt"
    np.savetxt(path, np.column_stack([t, rng.normal(size=(600, 6))]), delimiter=",", fmt="%.10f")
    rec = read_recording(path)
    assert rec.channels == ("acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z")
    assert rec.units == ("g",) * 3 + ("rad/s",) * 3 and rec.fs == 100.0


@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_real_pads_file_reads_like_the_evaluation_loader():
    from wake.eval.datasets import load_pads

    path = sorted(pads_dir().glob("*.txt"))[0]
    rec, ref = read_recording(path), load_pads(path)
    assert rec.channels == ref.channels and rec.fs == ref.fs
    np.testing.assert_array_equal(rec.samples, ref.samples)
    assert rec.timing.resampled and rec.timing.irregular_steps > 0


def test_mat_file_with_time_rate_and_a_matrix(tmp_path):
    import scipy.io

    n = 300
    t = np.arange(n) / 200.0
    gyro = np.column_stack([np.sin(t), np.cos(t), t])
    path = tmp_path / "rec.mat"
    scipy.io.savemat(path, {"t": t, "gyro": gyro.T, "label": "trial 3"})  # a k x n matrix is turned round
    rec = read_mat(path)
    assert rec.fs == 200.0 and rec.channels == ("gyro_0", "gyro_1", "gyro_2")
    np.testing.assert_allclose(rec.samples, gyro)
    scipy.io.savemat(path, {"fs": 50.0, "emg": np.arange(n, dtype=float), "acc": np.ones(n)})
    rec = read_recording(path, columns=["acc"])
    assert rec.fs == 50.0 and rec.channels == ("acc",) and rec.samples.shape == (n, 1)


def test_not_a_mat_file(tmp_path):
    path = tmp_path / "fake.mat"
    path.write_text("1,2,3\n")
    with pytest.raises(ValueError, match="not a readable MATLAB file"):
        read_recording(path)


@pytest.mark.parametrize("content, args, match", [
    ("time,x\n0,1\n0.01,2,3\n", [], "line 3: 3 columns where the file has 2 .a ragged row"),
    ("time,x\n0,1\n0.01,abc\n", [], "line 3: 'abc' is not a number"),
    ("time,x\n0,1\n0.01,2\n0.005,3\n", [], r"goes backwards at row 3 \(0.01 -> 0.005 s\)"),
    ("x,y\n1,2\n3,4\n", [], "has no time column, so the sampling rate is unknown"),
    ("time,x\n0,1\n0.01,2\n", ["--column", "time"], "is the time column"),
    ("time,x\n0,1\n0.01,2\n", ["--column", "gyro"], "no column 'gyro'; columns: time, x"),
    ("time,x\n0,1\n0.01,inf\n", [], "line 3: infinite value"),
    ("time,x\n", [], "a header but no data"),
])
def test_format_errors_exit_2_with_one_line_and_no_output(tmp_path, capsys, content, args, match):
    src = tmp_path / "bad.csv"
    src.write_text(content)
    out = tmp_path / "out.csv"
    assert main(["run", str(src), "--out", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    import re

    assert re.search(match, err), err
    assert not out.exists()


def test_resample_keeps_missing_samples_missing():
    t = np.arange(10) / 10.0
    v = np.arange(10.0)
    v[4] = np.nan
    y, _ = resample_uniform(t, v, 10.0)
    assert np.isnan(y[4, 0]) and np.isfinite(y[:3, 0]).all() and np.isfinite(y[6:, 0]).all()


@pytest.mark.parametrize("step, rate", [(0.010065, 100.0), (1 / 128.3, 128.0), (1 / 333.2, 333.0), (1 / 12.34, 12.34)])
def test_nominal_rate_prefers_common_rates_then_whole_hz(step, rate):
    assert nominal_rate(np.arange(50) * step) == pytest.approx(rate)
