"""What `wake run` leaves behind: files with the umask's mode, values that read back exactly, figures that
are refused before the work when they cannot be drawn, and any channel drawn without cutting the output."""

import os
import sys

import numpy as np
import pytest

from wake import WakeFilter
from wake._files import atomic_write_text
from wake.cli import main


@pytest.fixture
def umask_027():
    old = os.umask(0o027)
    yield
    os.umask(old)


def test_new_files_follow_the_umask(tmp_path, umask_027, recording):
    path, _ = recording
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--column", "a", "--out", str(out), "--backend", "reference"]) == 0
    assert out.stat().st_mode & 0o777 == 0o640
    folder = tmp_path / "fw"
    assert main(["export-c", str(folder)]) == 0
    assert {p.stat().st_mode & 0o777 for p in folder.rglob("*") if p.is_file()} == {0o640}
    assert {p.stat().st_mode & 0o777 for p in folder.rglob("*") if p.is_dir()} == {0o750}   # internal/


def test_an_existing_file_keeps_its_mode(tmp_path):
    target = tmp_path / "kept.txt"
    target.write_text("old")
    target.chmod(0o604)
    atomic_write_text(target, "new")
    assert target.read_text() == "new" and target.stat().st_mode & 0o777 == 0o604


def test_the_output_csv_reads_back_bit_for_bit(tmp_path, recording):
    path, s = recording
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--out", str(out), "--backend", "reference"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    res = WakeFilter(fs=100.0, backend="reference").run(np.column_stack([s.measurement, -s.measurement]))
    assert np.array_equal(data[:, 2], res.voluntary[:, 0]) and np.array_equal(data[:, 6], res.tremor[:, 1])


def test_plot_without_matplotlib_is_refused_before_the_work(tmp_path, recording, monkeypatch, capsys):
    path, _ = recording
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as if it were not installed
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--out", str(out), "--plot", str(tmp_path / "f.png")]) == 2
    captured = capsys.readouterr()
    assert "plotting needs matplotlib" in captured.err
    assert captured.out == "" and not out.exists()  # nothing read, filtered or written first
    assert main(["demo", "--plot", str(tmp_path / "d.png")]) == 2
    assert capsys.readouterr().out == ""


def test_any_channel_can_be_drawn_and_the_output_keeps_every_channel(tmp_path, recording, capsys):
    pytest.importorskip("matplotlib")
    path, _ = recording
    out, png = tmp_path / "out.csv", tmp_path / "b.png"
    assert main(["run", str(path), "--fs", "100", "--out", str(out), "--plot", str(png), "--plot-channel", "b",
                 "--units", "rad/s", "--backend", "reference"]) == 0
    assert png.stat().st_size > 10_000
    said = capsys.readouterr().out
    assert f"figure written to {png} (channel b)" in said
    assert np.loadtxt(out, delimiter=",", skiprows=1).shape[1] == 7  # both channels still written
    assert main(["run", str(path), "--fs", "100", "--plot", str(png), "--plot-channel", "c"]) == 2
    assert "channels: a, b" in capsys.readouterr().err
