"""``wake run`` and ``wake stream`` share one reader and one set of rules (issue 43, item 7): fed every
delimited-text layout the reader tests read (tests/io_recordings.TEXT_LAYOUTS), at 100 Hz and 1 kHz, from a
gyroscope and from an accelerometer with gravity, both name the same channels and write the same columns
(``wake run --out``'s header line is ``wake stream --header``'s) and, with ``--hpa-mode inline`` on a file
whose time column (if any) is regular, the same values in them."""

import gc
import io
import sys

import numpy as np
import pytest

from io_recordings import KINDS, RATES, TEXT_LAYOUTS, make_layout
from wake.cli import main


def _stream(path, options, monkeypatch, capsys):
    monkeypatch.setattr(sys, "stdin", io.StringIO(path.read_text()))
    monkeypatch.setattr(gc, "freeze", lambda: None)  # in this process, keep the test run's objects collectable
    code = main(["stream", "--stdin", "--stdout", "--header", "--hpa-mode", "inline", "--status", "0",
                 "--backend", "reference", *options])
    said = capsys.readouterr()
    assert code == 0, said.err
    return said.out.splitlines()


@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("layout", sorted(TEXT_LAYOUTS))
def test_run_and_stream_name_the_same_channels_and_columns(tmp_path, monkeypatch, capsys, layout, kind, fs):
    path, options = make_layout(tmp_path, layout, kind, fs)
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--out", str(out), "--backend", "reference", *options]) == 0
    ran = capsys.readouterr().out
    run_lines = out.read_text().splitlines()
    streamed = _stream(path, options, monkeypatch, capsys)
    assert streamed[0] == run_lines[0]  # the same channel names, units and columns, grouped by channel
    channels = ran.splitlines()[0].split("channel(s) (")[1].split(")")[0]
    assert run_lines[0].split(",")[1].split(" [")[0] == channels.split(", ")[0]
    assert "voluntary" in run_lines[0] and len(run_lines[0].split(",")) == 1 + 3 * len(channels.split(", "))
    if TEXT_LAYOUTS[layout][2]:  # no resampling: the same rows, and with the HPA inline the same values
        got = np.array([[float(c) for c in line.split(",")] for line in streamed[1:]])
        want = np.array([[float(c) for c in line.split(",")] for line in run_lines[1:]])
        assert got.shape == want.shape
        np.testing.assert_array_equal(got[:, 1:], want[:, 1:])
        np.testing.assert_allclose(got[:, 0] - got[0, 0], want[:, 0] - want[0, 0], atol=1e-6)  # epoch: 2e-7 s a step
