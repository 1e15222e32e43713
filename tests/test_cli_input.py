"""What a command-line user sees of the input side (issue 43, item 10): a warning is one clean line, not a
line of our source; an output path in a missing folder fails before any work, naming the folder.  At several
rates, gyroscope and accelerometer with gravity."""

import os
import subprocess
import sys

import numpy as np
import pytest

from io_recordings import KINDS, RATES, signals, write
from wake.cli import main

HERE = os.path.dirname(os.path.abspath(__file__))


def _file(tmp_path, kind, fs, seconds=6.0):
    names, units, x = signals(kind, fs, seconds=seconds)
    t = np.arange(x.shape[0]) / fs
    return write(tmp_path / f"{kind}_{fs:g}.csv", ["time", *names], [[ti, *row] for ti, row in zip(t, x)])


def _env():
    import wake

    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(os.path.abspath(wake.__file__)))
    return env


@pytest.mark.parametrize("fs", (40.0, 2000.0))  # outside 50-1000 Hz: a RateWarning
@pytest.mark.parametrize("kind", KINDS)
def test_a_warning_is_one_line_without_a_source_line(tmp_path, kind, fs):
    path = _file(tmp_path, kind, fs)
    res = subprocess.run([sys.executable, "-m", "wake", "run", str(path), "--backend", "reference"],
                         capture_output=True, text=True, env=_env(), cwd=HERE, timeout=300)
    assert res.returncode == 0, res.stderr
    lines = res.stderr.splitlines()
    warned = [line for line in lines if "outside the supported 50-1000 Hz" in line]
    assert len(warned) == 1 and warned[0].startswith("wake run: warning (RateWarning): fs = ")
    assert not any(".py:" in line or "WakeFilter(" in line or "warnings.warn" in line for line in lines), lines


@pytest.mark.parametrize("option", ["--out", "--tremor-out", "--plot"])
@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
def test_an_output_in_a_missing_folder_fails_before_the_work(tmp_path, capsys, kind, fs, option):
    path = _file(tmp_path, kind, fs)
    missing = tmp_path / "no" / "such" / "dir"
    target = missing / ("o.png" if option == "--plot" else "o.csv")
    assert main(["run", str(path), option, str(target), "--backend", "reference"]) == 2
    said = capsys.readouterr()
    assert said.out == ""  # nothing read, nothing filtered
    assert f"{option} {target}: the folder {missing} does not exist" in said.err
    assert ".tmp" not in said.err


@pytest.mark.parametrize("fs", RATES)
def test_an_output_that_is_a_folder_is_refused_before_the_work(tmp_path, capsys, fs):
    path = _file(tmp_path, "gyro", fs)
    assert main(["run", str(path), "--out", str(tmp_path), "--backend", "reference"]) == 2
    said = capsys.readouterr()
    assert said.out == "" and "is a folder; give a file name in it" in said.err
