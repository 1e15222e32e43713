"""Every value is written in the shortest form that reads back exactly (issue 43, item 8): the input's
``-17.31873`` stays ``-17.31873``, the time column ``0.01``; every cell reads back as the same double; at
100 Hz and 1 kHz, gyroscope and accelerometer with gravity."""

import numpy as np
import pytest

from io_recordings import KINDS, RATES, signals, write
from wake import WakeFilter
from wake.cli import main
from wake.io import read_recording


@pytest.mark.parametrize("fs", RATES)
@pytest.mark.parametrize("kind", KINDS)
def test_the_result_file_holds_the_shortest_exact_form(tmp_path, capsys, kind, fs):
    names, _, x = signals(kind, fs, seconds=8.0)
    x = np.round(x, 5)  # as a logger writes it
    x[3, 0] = -17.31873
    t = np.arange(x.shape[0]) / fs
    path = write(tmp_path / "in.csv", ["time", *names], [[f"{ti:.3f}", *(f"{v:.5f}" for v in row)]
                                                          for ti, row in zip(t, x)])
    out = tmp_path / "out.csv"
    tremor = tmp_path / "tremor.csv"
    assert main(["run", str(path), "--out", str(out), "--tremor-out", str(tremor), "--backend", "reference"]) == 0
    lines = out.read_text().splitlines()
    rows = [line.split(",") for line in lines[1:]]
    assert rows[3][1] == "-17.31873"  # the input's own digits, not -17.318729999999999
    assert rows[1][0] == repr(1 / fs) and rows[2][0] == repr(2 / fs)  # 0.01, 0.001: not 0.01000000000000000021
    for j in range(1, 1 + 3 * len(names), 3):
        assert [float(r[j]) for r in rows] == x[:, (j - 1) // 3].tolist()
    rec = read_recording(path)
    res = WakeFilter(fs=fs, backend="reference").run(rec.samples)
    back = np.array([[float(c) for c in r] for r in rows])
    assert np.array_equal(back[:, 2::3], res.voluntary) and np.array_equal(back[:, 3::3], res.tremor)
    assert all(c == repr(float(c)) for r in rows for c in r)  # the shortest: repr of what it reads back as
    end_times = [line.split(",")[3] for line in tremor.read_text().splitlines()[1:]]
    assert end_times and all(e == repr(float(e)) and len(e) < 17 for e in end_times)


def test_exact_cells_and_lines():
    from wake.io.writers import exact_cell, exact_lines

    assert exact_cell(0.98) == "0.98" and exact_cell(-17.31873) == "-17.31873" and exact_cell(np.nan) == "nan"
    a = np.array([[0.1, 1e-300, -0.0], [np.pi, 5e-324, np.nan]])
    text = exact_lines(a)
    assert text == "0.1,1e-300,-0.0\n3.141592653589793,5e-324,nan\n"
    assert np.array_equal(np.array([[float(c) for c in line.split(",")] for line in text.splitlines()]), a,
                          equal_nan=True)
    assert exact_lines(np.zeros((0, 3))) == ""
