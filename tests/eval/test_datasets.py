"""PADS and plain-CSV loaders (small files written here; real data when present)."""

import numpy as np
import pytest

from support import NO_PADS, pads_dir
from wake.eval.datasets import PADS_CHANNELS, default_pads_dir, load_csv, load_pads, load_pads_folder


def _write_pads(path, t, values):
    rows = np.column_stack([t, values])
    path.write_text("\n".join(",".join(f"{v:.10f}" for v in r) for r in rows) + "\n")
    return path


def _linear_values(t):
    # Linear in time per channel: linear interpolation must reproduce it exactly.
    return np.column_stack([a + b * t for a, b in zip(range(6), (0.5, -1.0, 2.0, 0.1, 3.0, -0.2))])


def test_pads_resamples_uneven_time_onto_uniform_grid(tmp_path, rng):
    t = np.cumsum(rng.uniform(0.006, 0.014, 300))
    t -= t[0]
    rec = load_pads(_write_pads(tmp_path / "001_Task_LeftWrist.txt", t, _linear_values(t)))
    assert rec.name == "001_Task_LeftWrist"
    assert rec.fs == 100.0
    assert rec.channels == PADS_CHANNELS
    n = int(np.floor(t[-1] * 100 + 1e-9)) + 1
    assert rec.samples.shape == (n, 6)
    grid = np.arange(n) / 100.0
    np.testing.assert_allclose(rec.samples, _linear_values(grid), atol=1e-8)
    np.testing.assert_allclose(rec.channel("gyro_y"), rec.samples[:, 4])


def test_pads_merges_repeated_timestamps_and_counts_irregular_steps(tmp_path):
    t = np.array([0.0, 0.01, 0.02, 0.045, 0.045, 0.05, 0.06])
    v = np.zeros((7, 6))
    v[:, 0] = [0, 1, 2, 3, 5, 5, 6]  # the two samples at 0.045 s average to 4
    rec = load_pads(_write_pads(tmp_path / "a.txt", t, v))
    expected = np.interp(np.arange(7) / 100, [0, 0.01, 0.02, 0.045, 0.05, 0.06], [0, 1, 2, 4, 5, 6])
    np.testing.assert_allclose(rec.samples[:, 0], expected)
    assert rec.irregular_steps == 2  # 25 ms and 0 ms


@pytest.mark.parametrize(
    "content, match",
    [
        ("", "holds no data"),
        ("0.0,1,2,3\n0.01,1,2,3\n", "7 columns"),
        ("0.0,1,2,3,4,5,6\n0.01,1,2,3,4,5\n", "line 2: 6 columns"),
        ("0.0,1,2,3,4,5,6\n0.01,1,2,x,4,5,6\n", "line 2: 'x' is not a number"),
        ("0.0,1,2,3,4,5,6\n0.01,1,2,nan,4,5,6\n", "line 2: an empty or nan cell"),
        ("0.0,1,2,3,4,5,6\n", "at least two samples"),
        ("0.02,1,2,3,4,5,6\n0.01,1,2,3,4,5,6\n", "backwards"),
        ("0.01,1,2,3,4,5,6\n0.01,1,2,3,4,5,6\n", "never advances"),
    ],
)
def test_pads_malformed_files(tmp_path, content, match):
    p = tmp_path / "bad.txt"
    p.write_text(content)
    with pytest.raises(ValueError, match=match):
        load_pads(p)


def test_pads_missing_file(tmp_path):
    with pytest.raises(ValueError, match="no such file"):
        load_pads(tmp_path / "nope.txt")


def test_pads_folder_ignores_other_files(tmp_path):
    t = np.arange(50) / 100.0
    _write_pads(tmp_path / "002_B_RightWrist.txt", t, _linear_values(t))
    _write_pads(tmp_path / "001_A_LeftWrist.txt", t, _linear_values(t))
    (tmp_path / "observation_001.json").write_text("{}")
    recs = load_pads_folder(tmp_path)
    assert [r.name for r in recs] == ["001_A_LeftWrist", "002_B_RightWrist"]
    with pytest.raises(ValueError, match="no recording"):
        load_pads_folder(tmp_path / "..", pattern="*.nothing")
    with pytest.raises(ValueError, match="not a folder"):
        load_pads_folder(tmp_path / "missing")


def test_load_csv_with_and_without_header(tmp_path):
    p = tmp_path / "h.csv"
    p.write_text("time,left,right\n0,1.5,2\n1,2.5,3\n2,3.5,4\n")
    rec = load_csv(p, fs=50.0)
    assert rec.channels == ("time", "left", "right") and rec.fs == 50.0
    assert rec.samples.shape == (3, 3)
    one = load_csv(p, column="right", fs=50.0)
    np.testing.assert_array_equal(one.samples[:, 0], [2, 3, 4])
    two = load_csv(p, column=[2, "left"], fs=50.0)
    assert two.channels == ("right", "left")
    q = tmp_path / "plain.csv"
    q.write_text("1.0\n2.0\n\n3.0\n")
    rec = load_csv(q, fs=100.0, name="x")
    assert rec.name == "x" and rec.channels == ("col0",)
    np.testing.assert_array_equal(rec.samples[:, 0], [1, 2, 3])


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(), "sampling rate"),
        (dict(fs=-1.0), "fs"),
        (dict(fs=100.0, column="nope"), "no column 'nope'"),
        (dict(fs=100.0, column=7), "out of range"),
        (dict(fs=100.0, column=1.5), "column must be"),
    ],
)
def test_load_csv_errors(tmp_path, kwargs, match):
    p = tmp_path / "h.csv"
    p.write_text("a,b\n1,2\n3,4\n")
    with pytest.raises(ValueError, match=match):
        load_csv(p, **kwargs)


def test_load_csv_header_only(tmp_path):
    p = tmp_path / "h.csv"
    p.write_text("a,b\n")
    with pytest.raises(ValueError, match="header but no data"):
        load_csv(p, fs=10.0)


def test_default_pads_dir(tmp_path, monkeypatch):
    monkeypatch.delenv("WAKE_PADS_DIR", raising=False)
    assert default_pads_dir("given") == type(tmp_path)("given")
    work = tmp_path / "checkout"
    work.mkdir()
    assert default_pads_dir(cwd=work) is None
    (tmp_path / "shared" / "data" / "pads").mkdir(parents=True)
    assert default_pads_dir(cwd=work) == (tmp_path / "shared" / "data" / "pads").resolve()
    monkeypatch.setenv("WAKE_PADS_DIR", str(tmp_path))
    assert default_pads_dir(cwd=work) == tmp_path


@pytest.mark.realdata
@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_real_pads_folder_loads():
    recs = load_pads_folder(pads_dir())
    assert len(recs) == 10
    for r in recs:
        assert r.channels == PADS_CHANNELS
        assert 1000 <= r.samples.shape[0] <= 1040  # 1024 rows over about 10.2-10.3 s at 100 Hz
        assert np.isfinite(r.samples).all()
        assert np.abs(r.samples[:, :3]).max() < 16  # g
    by_name = {r.name: r for r in recs}
    assert by_name["040_LiftHold_LeftWrist"].irregular_steps >= 2  # the 20 ms gap and the 0.09 ms step
