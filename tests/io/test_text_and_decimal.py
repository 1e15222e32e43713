"""Text columns beside the signals, decimal-comma files, units for headerless files, a .mat's own rate."""

import numpy as np
import pytest

from wake.cli import main
from wake.io import read_csv, read_recording


@pytest.fixture
def values():
    t = np.arange(1200) / 100.0
    return np.sin(2 * np.pi * t) + 0.2 * np.sin(2 * np.pi * 6 * t), np.cos(2 * np.pi * t)


def test_a_text_column_is_not_parsed_when_not_asked_for(tmp_path, values, capsys):
    gx, gy = values
    path = tmp_path / "rec.csv"
    path.write_text("subject,time,gyro_x,label,gyro_y\n" + "\n".join(
        f"S01,{i / 100:.2f},{a:.6f},{'rest' if i % 2 else 'move'},{b:.6f}" for i, (a, b) in enumerate(zip(gx, gy))))
    rec = read_csv(path, time_column="time", columns="gyro_x")
    assert rec.channels == ("gyro_x",) and rec.fs == 100.0
    np.testing.assert_allclose(rec.samples[:, 0], gx, atol=1e-6)
    assert main(["run", str(path), "--time-column", "time", "--column", "gyro_x", "--backend", "reference"]) == 0
    # asked for nothing: the text columns are left out, and said so
    rec = read_csv(path, time_column="time")
    assert rec.channels == ("gyro_x", "gyro_y")
    assert any("subject, label left out" in note for note in rec.notes)


def test_asking_for_a_text_column_names_it_and_its_line(tmp_path, values):
    path = tmp_path / "rec.csv"
    path.write_text("subject,gyro_x\n" + "\n".join(f"S01,{a:.6f}" for a in values[0]))
    with pytest.raises(ValueError, match=r"line 2: 'S01' is not a number \(column 'subject'"):
        read_csv(path, fs=100.0, columns="subject")


def test_a_headerless_file_with_a_text_column_is_not_taken_for_a_header(tmp_path, values):
    path = tmp_path / "rec.csv"
    path.write_text("\n".join(f"S01,{a:.6f}" for a in values[0]))
    rec = read_csv(path, fs=100.0)
    assert rec.samples.shape == (values[0].size, 1)
    np.testing.assert_allclose(rec.samples[:, 0], values[0], atol=1e-6)


@pytest.mark.parametrize("sep", [";", "\t"])
def test_decimal_comma_files_are_detected(tmp_path, values, sep):
    gx, gy = values
    path = tmp_path / "rec.csv"
    path.write_text(f"time{sep}gyro_x{sep}gyro_y\n" + "\n".join(
        f"{i / 100:.2f}{sep}{a:.6f}{sep}{b:.6f}".replace(".", ",") for i, (a, b) in enumerate(zip(gx, gy))))
    rec = read_csv(path)
    assert rec.fs == 100.0 and rec.channels == ("gyro_x", "gyro_y")
    np.testing.assert_allclose(rec.samples, np.column_stack([gx, gy]), atol=1e-6)
    assert "decimal comma" in rec.notes


def test_decimal_option_reads_what_auto_cannot_tell(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("5,5\n3,25\n2,0\n")  # one column with a decimal comma, or two columns? The file cannot say
    assert read_csv(path, fs=100.0).samples.shape == (3, 2)
    rec = read_csv(path, fs=100.0, decimal=",")
    assert rec.samples[:, 0].tolist() == [5.5, 3.25, 2.0]


def test_decimal_choices_are_named(capsys):
    with pytest.raises(SystemExit):
        main(["run", "x.csv", "--fs", "100", "--decimal", ";"])
    assert "choose from 'auto', '.', ','" in capsys.readouterr().err


def test_units_label_a_headerless_file(tmp_path, values):
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack(values), delimiter=",")
    rec = read_recording(path, fs=100.0, units="rad/s")
    assert rec.units == ("rad/s", "rad/s")
    rec = read_recording(path, fs=100.0, units=["rad/s", "g"])
    assert rec.units == ("rad/s", "g")
    with pytest.raises(ValueError, match="one unit for every channel or one per channel"):
        read_recording(path, fs=100.0, units=["rad/s", "g", "m"])
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--units", "rad/s", "--out", str(out),
                 "--backend", "reference"]) == 0
    assert out.read_text().splitlines()[0].startswith("time [s],col0 [rad/s],col0_voluntary [rad/s]")


def test_a_mat_files_own_rate_is_not_called_fs_option(tmp_path, values, capsys):
    scipy_io = pytest.importorskip("scipy.io")
    path = tmp_path / "rec.mat"
    scipy_io.savemat(path, {"gyro_x": values[0], "fs": 100.0})
    rec = read_recording(path)
    assert rec.fs == 100.0
    said = rec.timing.describe(rec.fs)
    assert "--fs" not in said and "the file's 'fs' variable" in said
    assert read_recording(path, fs=100.0).timing.describe(100.0) == "100 Hz from --fs"
