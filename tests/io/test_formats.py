"""The readers of wake.io.formats: the two real ParaDigMa files (Axivity CWA, TSDF) and, for the other formats,
files written in the test by each format's own library; read back, then filtered by `wake run`, `wake stream
--file` and `wake evaluate` (docs/guide/formats.md)."""

import csv
import struct
import sys

import numpy as np
import pytest

from support import NO_PARADIGMA, UNITS, motion, paradigma_dir, tremor_captured

from wake import WakeFilter
from wake.cli import main
from wake.io import read_recording
from wake.io.formats import MissingExtraError, format_of, recordings_in

PARADIGMA = paradigma_dir()
needs_paradigma = pytest.mark.skipif(PARADIGMA is None, reason=NO_PARADIGMA)


def read_output(path):
    """``wake run --out`` / ``wake stream --header``'s CSV: (header names, float rows)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(c) for c in r] for r in rows[1:]])


def column(header, rows, prefix):
    """The column whose header names starts with ``prefix`` (``wake run``'s headers carry a unit)."""
    return rows[:, [i for i, h in enumerate(header) if h.split(" ")[0] == prefix][0]]


# -- the real files ------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def cwa():
    pytest.importorskip("actfast", reason="actfast is not installed (pip install \"wake-tremor[wearables]\")")
    if PARADIGMA is None:
        pytest.skip(NO_PARADIGMA)
    return PARADIGMA / "axivity" / "test_data.CWA"


@pytest.fixture(scope="module")
def tsdf_folder():
    pytest.importorskip("tsdf", reason="tsdf is not installed (pip install \"wake-tremor[tsdf]\")")
    if PARADIGMA is None:
        pytest.skip(NO_PARADIGMA)
    return PARADIGMA / "tsdf_imu"


def cwa_blocks(path):
    """The CWA file's data blocks read by hand (the Open Movement layout): per block its sample count, rate code,
    axes and packing, and its samples as int16 (gyro x/y/z then acc x/y/z for an AX6)."""
    raw = path.read_bytes()
    start = struct.unpack_from("<H", raw, 2)[0] + 4          # the "MD" header block's length
    blocks = [raw[i:i + 512] for i in range(start, len(raw), 512)]
    assert {b[:2] for b in blocks} == {b"AX"}
    counts = [struct.unpack_from("<H", b, 28)[0] for b in blocks]
    rates = {3200 / (1 << (15 - (b[24] & 15))) for b in blocks}
    layouts = {(b[25] >> 4, b[25] & 15) for b in blocks}
    samples = np.concatenate([np.frombuffer(b[30:30 + 12 * c], "<i2").reshape(c, 6) for b, c in zip(blocks, counts)])
    return counts, rates, layouts, samples


def test_actfast_reads_the_cwa_as_its_blocks_say(cwa):
    """actfast is measured, not trusted: every sample equals the file's int16 values scaled by the AX6's ranges
    (+-8 g: 1/4096 g; +-1000 deg/s: 1000/32768), and the count and rate are the blocks'."""
    import actfast

    counts, rates, layouts, raw = cwa_blocks(cwa)
    assert sum(counts) == 36400 and rates == {100.0} and layouts == {(6, 2)}   # 6 axes, unpacked int16
    hf = actfast.read(str(cwa))["timeseries"]["high_frequency"]
    np.testing.assert_array_equal(hf["acceleration"], (raw[:, 3:] / 4096).astype(np.float32))
    np.testing.assert_allclose(hf["gyroscope"], raw[:, :3] * (1000 / 32768), rtol=1e-6)


def test_the_cwa_is_read_at_its_rate_with_its_channels_and_units(cwa):
    rec = read_recording(cwa)
    assert format_of(cwa) == "cwa"
    assert rec.fs == 100.0
    assert rec.channels == ("acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z")
    assert rec.units == ("g",) * 3 + ("deg/s",) * 3
    # the device's clock runs at 99.91 Hz by its block timestamps: 364.3 s on the 100 Hz grid
    assert abs(rec.samples.shape[0] - 36400) < 60 and rec.timing.raw_samples == 36400
    assert rec.timing.resampled and rec.t0 == 0.0
    assert 0.95 < np.median(np.linalg.norm(rec.samples[:, :3], axis=1)) < 1.1    # gravity, in g
    assert not np.isnan(rec.samples).any()
    assert any("AX6" in note for note in rec.notes)


def test_the_tsdf_is_read_with_its_scales_units_and_its_quality_flag_as_missing_samples(tsdf_folder):
    rec = read_recording(tsdf_folder)                     # the folder, its metadata file or a binary file: one
    for path in (tsdf_folder / "imu_meta.json", tsdf_folder / "imu_values.bin"):
        other = read_recording(path)
        np.testing.assert_array_equal(other.samples, rec.samples)
    assert rec.fs == 100.0
    assert rec.channels == tuple(f"{k}_{a}" for k in ("acceleration", "rotation") for a in "xyz")
    assert rec.units == ("m/s^2",) * 3 + ("deg/s",) * 3
    # int16 counts times the scale factors: gravity comes out near 9.81 m/s^2 (9.25: the watch is off by 6 %)
    acc = rec.samples[:, :3]
    assert 8.8 < np.nanmedian(np.linalg.norm(acc, axis=1)) < 10.8
    quality = np.fromfile(tsdf_folder / "imu_quality.bin", np.int8)
    flagged = int((quality == 0).sum())
    assert flagged == 8892
    assert any(f"{flagged} of 72947 rows flagged 0" in note for note in rec.notes)
    missing = np.isnan(rec.samples).all(axis=1)
    assert np.isnan(rec.samples).any(axis=1).sum() == missing.sum()   # a flagged row is missing in every channel
    runs = int(np.count_nonzero(np.diff(np.r_[1, quality, 1]) == -1))   # a grid point beside a flagged row too
    assert flagged <= missing.sum() <= flagged + 3 * runs
    assert 730 < rec.duration < 732            # the metadata: 16:52:20 to 17:04:31, whole seconds
    assert rec.timing.raw_samples == 72947 and rec.timing.resampled


def test_wake_run_filters_the_cwa_end_to_end(cwa, tmp_path, capsys):
    out = tmp_path / "cwa.csv"
    assert main(["run", str(cwa), "--column", "acc_x,gyro_y", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "2 channel(s) (acc_x, gyro_y)" in said and "AX6 read with actfast" in said
    header, rows = read_output(out)
    assert header[0].startswith("time") and rows.shape[0] == read_recording(cwa).samples.shape[0]
    assert {"acc_x [g]", "acc_x_voluntary [g]", "acc_x_tremor [g]", "gyro_y_tremor [deg/s]"} <= set(header)
    np.testing.assert_allclose(column(header, rows, "gyro_y_voluntary") + column(header, rows, "gyro_y_tremor"),
                               column(header, rows, "gyro_y"), atol=1e-9)
    assert np.isfinite(rows).all()


def test_wake_run_filters_the_tsdf_through_its_gaps(tsdf_folder, tmp_path, capsys):
    out = tmp_path / "tsdf.csv"
    assert main(["run", str(tsdf_folder / "imu_meta.json"), "--column", "rotation_x", "--out", str(out)]) == 0
    assert "rows flagged 0 by 'quality': read as missing samples (NaN)" in capsys.readouterr().out
    header, rows = read_output(out)
    x = column(header, rows, "rotation_x")
    voluntary = column(header, rows, "rotation_x_voluntary")
    tremor = column(header, rows, "rotation_x_tremor")
    gaps = np.isnan(x)
    assert gaps.sum() > 8892
    assert np.isnan(tremor[gaps]).all() and np.isfinite(tremor[~gaps]).all()
    assert np.isfinite(voluntary).all()           # the filter predicts through a missing sample


def test_stream_replays_the_real_files_as_wake_run_filters_them(cwa, tsdf_folder, tmp_path, capsys):
    """``wake stream --file`` with --hpa-mode inline gives `wake run`'s output bit for bit (both causal)."""
    n = 1200
    for path, channel in ((cwa, "gyro_x"), (tsdf_folder, "rotation_x")):
        assert main(["stream", "--file", str(path), "--stdout", "--header", "--hpa-mode", "inline",
                     "--max-samples", str(n), "--status", "0", "--backend", "c" if _c() else "reference"]) == 0
        captured = capsys.readouterr()
        lines = captured.out.splitlines()
        header = [h.split(" [")[0] for h in lines[0].split(",")]            # names without their units
        rows = np.array([[float(c) for c in line.split(",")] for line in lines[1:]])
        assert rows.shape[0] == n and header[0] == "time" and f"{channel}_tremor" in header
        assert "replaying" in captured.err
        rec = read_recording(path)
        res = WakeFilter(fs=rec.fs, backend="c" if _c() else "reference").run(rec.samples[:n])
        c = rec.channels.index(channel)
        np.testing.assert_array_equal(rows[:, header.index(f"{channel}_tremor")], res.tremor[:, c])
        np.testing.assert_array_equal(rows[:, 0], rec.time[:n])


def _c():
    from support import has_c_backend

    return has_c_backend()


# -- files written by each format's own library ---------------------------------------------------------------

def write_edf(path, fs, kind, x, bdf=False):
    edfio = pytest.importorskip("edfio", reason="edfio is not installed (pip install \"wake-tremor[edf]\")")
    Signal, File = (edfio.BdfSignal, edfio.Bdf) if bdf else (edfio.EdfSignal, edfio.Edf)
    signals = [Signal(x[:, i], fs, label=f"{kind}_{a}", physical_dimension=UNITS[kind], physical_range=(-20, 20))
               for i, a in enumerate("xyz")]
    File(signals, data_record_duration=1.0).write(path)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
@pytest.mark.parametrize("bdf", [False, True], ids=["edf", "bdf"])
def test_edf_and_bdf_written_by_edfio_read_back_and_filter(tmp_path, fs, kind, bdf):
    x, tremor = motion(fs, kind)
    path = tmp_path / f"rec.{'bdf' if bdf else 'edf'}"
    write_edf(path, fs, kind, x, bdf)
    rec = read_recording(path)
    assert format_of(path) == "edf"
    assert rec.fs == fs and rec.channels == tuple(f"{kind}_{a}" for a in "xyz") and rec.units == (UNITS[kind],) * 3
    assert not rec.timing.resampled and rec.samples.shape == x.shape
    step = 40 / (2 ** (24 if bdf else 16) - 1)              # one digital step of the physical range
    np.testing.assert_allclose(rec.samples, x, atol=step)
    res = WakeFilter(fs=rec.fs, backend="reference").run(rec.samples[:, 2])
    assert tremor_captured(res.tremor, tremor[:, 2], fs) > 0.8


def test_edf_signals_at_other_rates_are_left_out_or_asked_for(tmp_path):
    edfio = pytest.importorskip("edfio", reason="edfio is not installed (pip install \"wake-tremor[edf]\")")
    x, _ = motion(100.0, "gyro", seconds=10)
    slow = np.linspace(30, 31, 100)
    path = tmp_path / "mixed.edf"
    edfio.Edf([edfio.EdfSignal(x[:, 0], 100, label="gyro_x", physical_dimension="rad/s", physical_range=(-5, 5)),
               edfio.EdfSignal(slow, 10, label="temp", physical_dimension="degC", physical_range=(0, 50))],
              data_record_duration=1.0).write(path)
    rec = read_recording(path)
    assert rec.channels == ("gyro_x",) and any("temp (10 Hz)" in note for note in rec.notes)
    assert read_recording(path, columns=["temp"]).fs == 10.0
    assert read_recording(path, columns=[1]).channels == ("temp",)
    with pytest.raises(ValueError, match=r"different rates \(gyro_x 100 Hz, temp 10 Hz\)"):
        read_recording(path, columns=["gyro_x", "temp"])
    with pytest.raises(ValueError, match="no signal 'gyro_y'; signals: gyro_x, temp"):
        read_recording(path, columns="gyro_y")


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_parquet_written_by_pyarrow_reads_as_a_csv_with_a_header_would(tmp_path, fs, kind):
    pa = pytest.importorskip("pyarrow", reason="pyarrow is not installed (pip install \"wake-tremor[parquet]\")")
    import pyarrow.parquet as pq

    rng = np.random.default_rng(1)
    x, tremor = motion(fs, kind)
    n = x.shape[0]
    t_ms = (np.arange(n) + rng.uniform(-0.2, 0.2, n)) * 1000.0 / fs         # a jittered clock in ms
    gap = x[:, 0].copy()
    gap[n // 2] = np.nan
    table = pa.table({"timestamp_ms": t_ms, f"{kind}_x [{UNITS[kind]}]": pa.array(gap, from_pandas=True),
                      f"{kind}_y [{UNITS[kind]}]": x[:, 1], f"{kind}_z [{UNITS[kind]}]": x[:, 2],
                      "subject": ["s01"] * n})
    path = tmp_path / "rec.parquet"
    pq.write_table(table, path)
    rec = read_recording(path)
    assert rec.fs == fs and rec.channels == tuple(f"{kind}_{a}" for a in "xyz") and rec.units == (UNITS[kind],) * 3
    assert rec.timing.resampled and "in ms (from its name)" in rec.timing.unit_note
    assert any("subject left out" in note for note in rec.notes)
    assert np.isnan(rec.samples[:, 0]).sum() in (1, 2) and not np.isnan(rec.samples[:, 1:]).any()
    res = WakeFilter(fs=rec.fs, backend="reference").run(rec.samples[:, 2])
    m = min(res.tremor.shape[0], n)
    assert tremor_captured(res.tremor[:m], tremor[:m, 2], fs) > 0.8
    with pytest.raises(ValueError, match="column 'subject' holds text"):
        read_recording(path, columns=["subject"])


def test_parquet_timestamps_are_a_time_column(tmp_path):
    pa = pytest.importorskip("pyarrow", reason="pyarrow is not installed (pip install \"wake-tremor[parquet]\")")
    import pyarrow.parquet as pq

    x, _ = motion(250.0, "gyro", seconds=4)
    stamps = np.datetime64("2024-05-01T10:00:00", "ns") + (np.arange(x.shape[0]) * 4_000_000).astype("m8[ns]")
    path = tmp_path / "stamped.parquet"
    pq.write_table(pa.table({"time": stamps, "gyro_x": x[:, 0]}), path)
    rec = read_recording(path)
    assert rec.fs == 250.0 and rec.channels == ("gyro_x",) and not rec.timing.resampled


def test_gt3x_and_geneactiv_bin_corrupt_files_are_refused_by_name(tmp_path, capsys):
    """No library writes GT3X or GENEActiv BIN files (actfast, pygt3x and GGIR only read them), so no valid one
    can be made here: what is tested is that actfast is reached and its refusal reaches the user in one line."""
    pytest.importorskip("actfast", reason="actfast is not installed (pip install \"wake-tremor[wearables]\")")
    gt3x = tmp_path / "rec.gt3x"
    gt3x.write_bytes(b"PK\x03\x04 not a zip archive")
    binfile = tmp_path / "rec.bin"
    binfile.write_bytes(b"Device Identity\r\nDevice Unique Serial Code:0\r\n")
    assert format_of(gt3x) == "gt3x" and format_of(binfile) == "geneactiv"
    with pytest.raises(ValueError, match=r"rec.gt3x: not a readable ActiGraph GT3X file \(actfast: .*ZIP"):
        read_recording(gt3x)
    with pytest.raises(ValueError, match=r"rec.bin: not a readable GENEActiv BIN file \(actfast: .*header"):
        read_recording(binfile)
    assert main(["run", str(gt3x)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("wake run: error: ") and "Traceback" not in err


def test_a_missing_library_names_the_extra_that_brings_it(tmp_path, monkeypatch, capsys):
    path = tmp_path / "rec.cwa"
    path.write_bytes(b"MD")
    monkeypatch.setitem(sys.modules, "actfast", None)                 # as if not installed
    with pytest.raises(MissingExtraError, match=r'pip install "wake-tremor\[wearables\]"') as info:
        read_recording(path)
    assert isinstance(info.value, ImportError) and info.value.name == "actfast"
    assert main(["run", str(path)]) == 2
    assert 'needs the optional package \'actfast\'' in capsys.readouterr().err
    for module, extra, name in (("edfio", "edf", "rec.edf"), ("tsdf", "tsdf", "rec_meta.json"),
                                ("pyarrow", "parquet", "rec.parquet")):
        monkeypatch.setitem(sys.modules, module, None)
        f = tmp_path / name
        f.write_text('{"metadata_version": "0.1", "file_name": "x.bin"}' if name.endswith(".json") else "x")
        with pytest.raises(MissingExtraError, match=rf'wake-tremor\[{extra}\]'):
            read_recording(f)


def test_the_dispatch_by_suffix_and_content(tmp_path):
    (tmp_path / "a_meta.json").write_text('{"metadata_version": "0.1", "file_name": "a.bin"}')
    (tmp_path / "a.bin").write_bytes(b"\0" * 8)
    (tmp_path / "other.json").write_text('{"x": 1}')
    (tmp_path / "g.bin").write_bytes(b"Device Identity")
    assert format_of(tmp_path / "a.bin") == "tsdf" and format_of(tmp_path / "a_meta.json") == "tsdf"
    assert format_of(tmp_path / "other.json") is None and format_of(tmp_path / "g.bin") == "geneactiv"
    assert format_of(tmp_path / "REC.CWA") == "cwa" and format_of(tmp_path / "x.pq") == "parquet"
    assert format_of(tmp_path / "sub-1_task-a_tracksys-b_motion.tsv") == "bids"
    assert format_of(tmp_path / "plain.tsv") is None and format_of(tmp_path / "x.mat") is None
    assert recordings_in(tmp_path) == [tmp_path / "a_meta.json", tmp_path / "g.bin"]
    with pytest.raises(ValueError, match="holds 2: a_meta.json; g.bin; give one of them"):
        read_recording(tmp_path)
    with pytest.raises(ValueError, match="--time-column .* applies to delimited text and Parquet"):
        read_recording(tmp_path / "g.bin", time_column=None)


def test_evaluate_takes_the_written_formats(tmp_path):
    """``wake evaluate`` on an EDF, a BDF and a Parquet file (a BIDS folder: tests/io/test_formats_bids.py)."""
    pytest.importorskip("edfio", reason="edfio is not installed (pip install \"wake-tremor[edf]\")")
    pytest.importorskip("pyarrow", reason="pyarrow is not installed (pip install \"wake-tremor[parquet]\")")
    import json

    import pyarrow as pa
    import pyarrow.parquet as pq

    x, _ = motion(100.0, "gyro", seconds=15)
    write_edf(tmp_path / "a.edf", 100.0, "gyro", x[:, :1].repeat(3, axis=1))
    write_edf(tmp_path / "b.bdf", 100.0, "acc", motion(100.0, "acc", seconds=15)[0], bdf=True)
    pq.write_table(pa.table({"time": np.arange(x.shape[0]) / 100.0, "gyro_z": x[:, 2]}), tmp_path / "c.parquet")
    out = tmp_path / "out"
    assert main(["evaluate", str(out), str(tmp_path / "a.edf"), str(tmp_path / "b.bdf"), str(tmp_path / "c.parquet"),
                 "--synthetic", "0", "--backend", "reference", "--no-progress"]) == 0
    rows = json.loads((out / "results.json").read_text())["real"]["rows"]
    assert {(r["recording"], r["axis"]) for r in rows} >= {("a", "gyro_x"), ("b", "acc_z"), ("c", "gyro_z")}
    assert all(np.isfinite(r["methods"]["WAKE-ref"]) for r in rows)


def _fitted_weights(header_text):
    import re

    from wake.rtp.fixed import WEIGHT_FRAC

    block = re.search(r"wake_config_weights\[\d+\] = \{(.*?)\};", header_text, re.S).group(1)
    return np.array([int(v) for v in block.replace("\n", " ").split(",") if v.strip()]) / 2.0**WEIGHT_FRAC


def _check_fit(path, channel, tmp_path, capsys):
    """``wake export-header --fit`` fits ``channel`` of ``path`` as read by read_recording (the last HPA window)."""
    from wake.rtp.fixed import WEIGHT_FRAC

    out = tmp_path / "cfg.h"
    assert main(["export-header", str(out), "--fit", str(path), "--column", channel]) == 0
    rec = read_recording(path, columns=channel)
    expected = WakeFilter(fs=rec.fs, backend="reference").run(rec.samples[:, 0]).hpa[0][-1].weights
    np.testing.assert_allclose(_fitted_weights(out.read_text()), expected, atol=2.0**-WEIGHT_FRAC)
    assert f"channel '{channel}'" in capsys.readouterr().out


@pytest.mark.skipif(not _c(), reason="the compiled C core wake._rtp is not built")
def test_export_fit_reads_an_edf_file_as_run_does(tmp_path, capsys):
    x, _ = motion(1000.0, "acc", seconds=8)
    write_edf(tmp_path / "rec.edf", 1000.0, "acc", x)
    _check_fit(tmp_path / "rec.edf", "acc_z", tmp_path, capsys)


@pytest.mark.skipif(not _c(), reason="the compiled C core wake._rtp is not built")
def test_export_fit_reads_the_cwa_as_run_does(cwa, tmp_path, capsys):
    _check_fit(cwa, "gyro_y", tmp_path, capsys)


def test_a_truncated_edf_file_is_read_as_far_as_it_goes_and_says_so(tmp_path):
    pytest.importorskip("edfio", reason="edfio is not installed (pip install \"wake-tremor[edf]\")")
    x, _ = motion(100.0, "gyro", seconds=10)
    path = tmp_path / "rec.edf"
    write_edf(path, 100.0, "gyro", x)
    data = path.read_bytes()
    header = 256 * 4                                              # 3 signals: 256 + 3 * 256 bytes
    (tmp_path / "cut.edf").write_bytes(data[:header + 3 * 2 * 100 * 4 + 50])   # 4 whole records, and a part
    rec = read_recording(tmp_path / "cut.edf")
    assert rec.samples.shape == (400, 3) and any("Incomplete data record" in n for n in rec.notes)
    np.testing.assert_allclose(rec.samples, x[:400], atol=40 / 65535)
    (tmp_path / "empty.edf").write_bytes(data[:header])
    with pytest.raises(ValueError, match="need at least two samples, the file holds 0"):
        read_recording(tmp_path / "empty.edf")


def test_an_fs_against_the_files_clock_is_refused_unless_resampling_is_asked_for(tmp_path):
    """The rule of every reader (wake.io.recording.check_rate) holds for a format with its own clock."""
    x, _ = motion(100.0, "acc", seconds=6)
    write_edf(tmp_path / "rec.edf", 100.0, "acc", x)
    with pytest.raises(ValueError, match="250"):
        read_recording(tmp_path / "rec.edf", fs=250.0)
    rec = read_recording(tmp_path / "rec.edf", fs=250.0, resample=True)
    assert rec.fs == 250.0 and rec.timing.resampled and abs(rec.samples.shape[0] - 1500) <= 3
    assert read_recording(tmp_path / "rec.edf", fs=100.0).samples.shape == x.shape   # the clock's own rate: as is
