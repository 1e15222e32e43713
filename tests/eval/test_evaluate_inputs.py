"""`wake evaluate OUT FILES`: the user's recordings are named as what they are, not as PADS, and files
without a time column get one line saying that --fs serves, before the work (issue 43, item 5)."""

import numpy as np
import pytest

from wake.eval.evaluate import cli


def _recording(fs, seconds, phase=0.0):
    """Two columns, no header, no time column: a gyroscope axis (deg/s) and an accelerometer axis with gravity."""
    t = np.arange(int(seconds * fs)) / fs
    gyro = 40.0 * np.sin(2 * np.pi * 0.4 * t) + 8.0 * np.sin(2 * np.pi * 6.0 * t + phase)
    acc = 9.81 * np.cos(0.3 * np.sin(2 * np.pi * 0.2 * t)) + 0.5 * np.sin(2 * np.pi * 5.0 * t + phase)
    return np.column_stack([gyro, acc])


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_files_without_a_time_column_say_that_fs_serves(tmp_path, capsys, fs):
    for i in range(3):
        np.savetxt(tmp_path / f"chfig{i}.txt", _recording(fs, 8.0, i), fmt="%.6f")
    out = tmp_path / "out"
    assert cli([out, str(tmp_path / "chfig*.txt"), "--synthetic", "0", "--backend", "reference",
                "--no-progress"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert "chfig0.txt, chfig1.txt, chfig2.txt have no time column" in lines[0] and "--fs HZ" in lines[0]
    assert "--time-column" not in lines[0]          # an option wake evaluate does not have
    assert not (out / "report.md").exists()          # refused before the work


def test_the_report_names_the_users_recordings(tmp_path, capsys):
    for i in range(2):
        np.savetxt(tmp_path / f"chfig{i}.txt", _recording(200.0, 12.0, i), fmt="%.6f")
    out = tmp_path / "out"
    assert cli([out, str(tmp_path / "chfig*.txt"), "--fs", "200", "--synthetic", "0", "--backend", "reference",
                "--no-progress"]) == 0
    text = (out / "report.md").read_text()
    assert "PADS" not in text
    assert "| chfig0.txt, chfig1.txt (tremor NRMSE) |" in text
    assert "## Real recordings (chfig0.txt, chfig1.txt)" in text
    assert "## The cut-off on chfig0.txt, chfig1.txt" in text
    assert "PADS" not in capsys.readouterr().out
