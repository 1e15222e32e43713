"""Motion-BIDS: a dataset written by the test is read (a file or its folder), filtered by `wake run`, `wake stream
--file` and `wake evaluate`, and `wake run --bids-out` writes a derivative that a BIDS reader (pybids) accepts."""

import json
import warnings

import numpy as np
import pytest

from support import UNITS, motion, tremor_captured

from wake.cli import main
from wake.io import read_recording
from wake.io.formats.bids import entities, motion_files


def write_dataset(root, recordings):
    """A Motion-BIDS dataset: ``recordings`` is a list of (sub, task, tracksys, fs, kind, x, latency)."""
    root.mkdir(parents=True, exist_ok=True)
    (root / "dataset_description.json").write_text(json.dumps({"Name": "wake test", "BIDSVersion": "1.9.0"}))
    subs = sorted({r[0] for r in recordings})
    (root / "participants.tsv").write_text("participant_id\n" + "".join(f"sub-{s}\n" for s in subs))
    paths = []
    for sub, task, tracksys, fs, kind, x, latency in recordings:
        folder = root / f"sub-{sub}" / "motion"
        folder.mkdir(parents=True, exist_ok=True)
        stem = folder / f"sub-{sub}_task-{task}_tracksys-{tracksys}"
        cols = [x] if latency is None else [latency[:, None], x]
        data = np.column_stack(cols)
        with open(f"{stem}_motion.tsv", "w") as f:
            for row in data:
                f.write("\t".join("n/a" if np.isnan(v) else repr(float(v)) for v in row) + "\n")
        rows = [] if latency is None else [("latency", "n/a", "LATENCY", "n/a", "s")]
        rows += [(f"{kind}_{a}", a, {"gyro": "GYRO", "acc": "ACCEL"}[kind], "LeftWrist", UNITS[kind]) for a in "xyz"]
        (folder / f"{stem.name}_channels.tsv").write_text(
            "name\tcomponent\ttype\ttracked_point\tunits\n" + "".join("\t".join(r) + "\n" for r in rows))
        (folder / f"{stem.name}_motion.json").write_text(json.dumps({
            "SamplingFrequency": fs, "TaskName": task, "TrackingSystemName": tracksys,
            f"{'GYRO' if kind == 'gyro' else 'ACCEL'}ChannelCount": 3}))
        paths.append(folder / f"{stem.name}_motion.tsv")
    return paths


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_a_motion_bids_recording_reads_by_its_sidecars(tmp_path, fs, kind):
    x, tremor = motion(fs, kind)
    x[50, 1] = np.nan                                      # an n/a cell: a missing sample
    (path,) = write_dataset(tmp_path / "ds", [("01", "tremor", "imu", fs, kind, x, None)])
    rec = read_recording(path)
    assert rec.fs == fs and rec.channels == tuple(f"{kind}_{a}" for a in "xyz") and rec.units == (UNITS[kind],) * 3
    assert not rec.timing.resampled and rec.samples.shape == x.shape
    np.testing.assert_array_equal(np.isnan(rec.samples), np.isnan(x))
    np.testing.assert_allclose(rec.samples, x)
    assert any("tracksys-imu" in note for note in rec.notes)
    folder = read_recording(tmp_path / "ds")              # the dataset's folder: its one recording
    np.testing.assert_array_equal(folder.samples, rec.samples)
    json_side = read_recording(str(path).replace("_motion.tsv", "_motion.json"))
    assert json_side.source == rec.source
    from wake import WakeFilter

    res = WakeFilter(fs=rec.fs, backend="reference").run(rec.samples[:, 0])
    assert tremor_captured(res.tremor, tremor[:, 0], fs) > 0.8


def test_a_latency_channel_is_the_time_and_inherited_sidecars_apply(tmp_path):
    rng = np.random.default_rng(2)
    x, _ = motion(200.0, "gyro", seconds=6)
    latency = (np.arange(x.shape[0]) + rng.uniform(-0.2, 0.2, x.shape[0])) / 200.0 + 5.0
    (path,) = write_dataset(tmp_path / "ds", [("02", "rest", "watch", "n/a", "gyro", x, latency)])
    rec = read_recording(path)
    assert rec.fs == 200.0 and rec.channels == ("gyro_x", "gyro_y", "gyro_z") and rec.timing.resampled
    assert rec.t0 == 0.0
    # the json moved to the dataset's top as task-rest_tracksys-watch_motion.json: inherited
    side = path.with_name(path.name.replace("_motion.tsv", "_motion.json"))
    top = tmp_path / "ds" / "task-rest_tracksys-watch_motion.json"
    side.rename(top)
    assert read_recording(path).fs == 200.0
    top.unlink()
    with pytest.raises(ValueError, match=r"no \*_motion.json for this recording"):
        read_recording(path)


def test_bids_errors_say_what_is_wrong(tmp_path):
    x, _ = motion(100.0, "acc", seconds=3)
    paths = write_dataset(tmp_path / "ds", [("01", "a", "imu", 100.0, "acc", x, None),
                                            ("02", "a", "imu", 100.0, "acc", x, None)])
    with pytest.raises(ValueError, match="holds 2: sub-01/motion/sub-01_task-a_tracksys-imu_motion.tsv; sub-02"):
        read_recording(tmp_path / "ds")
    channels = paths[0].with_name("sub-01_task-a_tracksys-imu_channels.tsv")
    channels.write_text("\n".join(channels.read_text().splitlines()[:-1]) + "\n")
    with pytest.raises(ValueError, match="lists 2 channels but sub-01_task-a_tracksys-imu_motion.tsv has 3 columns"):
        read_recording(paths[0])
    assert entities(paths[1]) == {"sub": "02", "task": "a", "tracksys": "imu"}
    assert motion_files(tmp_path / "ds") == paths


def test_wake_run_writes_a_bids_derivative_that_pybids_accepts(tmp_path, capsys):
    bids = pytest.importorskip("bids", reason="pybids is not installed (pip install pybids, or the test extra)")
    x, _ = motion(100.0, "gyro", seconds=12)
    x[300:305, 0] = np.nan
    ds = tmp_path / "ds"
    (path,) = write_dataset(ds, [("01", "tremor", "imu", 100.0, "gyro", x, None)])
    out = ds / "derivatives" / "wake"
    assert main(["run", str(ds), "--bids-out", str(out), "--backend", "reference"]) == 0
    assert "wrote a BIDS derivative to" in capsys.readouterr().out
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        layout = bids.BIDSLayout(ds, derivatives=str(out), validate=True)
        derived = layout.derivatives["wake"].get(suffix="motion", extension=".tsv", desc="wake")
    assert len(derived) == 1
    meta = derived[0].get_metadata()
    assert meta["SamplingFrequency"] == 100.0 and meta["TaskName"] == "tremor" and meta["GYROChannelCount"] == 6
    assert meta["Sources"] == ["bids:raw:sub-01/motion/sub-01_task-tremor_tracksys-imu_motion.tsv"]
    assert derived[0].entities["subject"] == "01" and derived[0].entities["desc"] == "wake"
    # the file names: the raw dataset's are valid BIDS, and the derivative's are those with desc-wake (the
    # derivatives' entity, which the raw rules of the validator do not know)
    from bids_validator import BIDSValidator

    files = sorted(p for p in ds.rglob("*") if p.is_file() and "derivatives" not in p.parts)
    assert all(BIDSValidator().is_bids("/" + p.relative_to(ds).as_posix()) for p in files)
    made = sorted(p.relative_to(out).as_posix() for p in out.rglob("sub-*") if p.is_file())
    assert len(made) == 3 and all(BIDSValidator().is_bids("/" + m.replace("_desc-wake", "")) for m in made)
    # the derivative reads back as a recording: voluntary + tremor is the measurement, n/a where it was missing
    rec = read_recording(derived[0].path)
    assert rec.channels == tuple(f"gyro_{a}_{k}" for a in "xyz" for k in ("voluntary", "tremor"))
    assert rec.units == ("rad/s",) * 6 and rec.fs == 100.0
    total = rec.samples[:, 0::2] + rec.samples[:, 1::2]
    np.testing.assert_allclose(total[np.isfinite(x)], x[np.isfinite(x)], atol=1e-9)
    assert np.isnan(rec.samples[300:305, 1]).all()
    # a second run keeps the dataset_description; a folder of another dataset is refused
    assert main(["run", str(path), "--bids-out", str(out), "--backend", "reference"]) == 0
    assert main(["run", str(path), "--bids-out", str(ds), "--backend", "reference"]) == 2
    assert "not of a wake derivative" in capsys.readouterr().err


def test_bids_out_is_refused_before_the_work_for_other_inputs(tmp_path, capsys):
    csv = tmp_path / "rec.csv"
    np.savetxt(csv, motion(100.0, "gyro", seconds=6)[0], delimiter=",", header="a,b,c", comments="")
    assert main(["run", str(csv), "--fs", "100", "--bids-out", str(tmp_path / "d")]) == 2
    err = capsys.readouterr()
    assert "--bids-out writes a BIDS derivative of a Motion-BIDS recording" in err.err
    assert "HPA runs" not in err.out and not (tmp_path / "d").exists()


def test_stream_and_evaluate_take_a_bids_dataset(tmp_path, capsys):
    fs = 100.0
    x1, _ = motion(fs, "gyro", seconds=12, seed=1)
    x2, _ = motion(fs, "acc", seconds=12, seed=2)
    ds = tmp_path / "ds"
    p1, p2 = write_dataset(ds, [("01", "tremor", "imu", fs, "gyro", x1, None),
                                ("02", "tremor", "imu", fs, "acc", x2, None)])
    assert main(["stream", "--file", str(p2), "--stdout", "--header", "--status", "0", "--backend", "reference"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split(",")[:3] == ["time [s]", "acc_x [m/s^2]", "acc_x_voluntary [m/s^2]"]
    assert len(lines) == 1 + x2.shape[0]
    out = tmp_path / "out"
    assert main(["evaluate", str(out), str(ds), "--synthetic", "0", "--backend", "reference", "--no-progress"]) == 0
    rows = json.loads((out / "results.json").read_text())["real"]["rows"]
    names = {r["recording"] for r in rows}
    assert names == {"sub-01_task-tremor_tracksys-imu", "sub-02_task-tremor_tracksys-imu"}   # not participants.tsv
