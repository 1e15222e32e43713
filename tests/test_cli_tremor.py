"""`wake run` reports the tremor characterisation: a paragraph per channel, --tremor-out, the tremor figure."""

import numpy as np
import pytest

from wake import WakeFilter
from wake.cli import main
from wake.hpa.characterise import summarise
from wake.io.writers import TREMOR_COLUMNS, tremor_header

FS = 100.0


@pytest.fixture
def tremor_recording(tmp_path):
    """20 s, two channels with a time column: a 6 Hz tremor of amplitude 0.2 on slow motion, and no tremor."""
    rng = np.random.default_rng(4)
    t = np.arange(2000) / FS
    slow = np.sin(2 * np.pi * 0.3 * t)
    a = slow + 0.2 * np.sin(2 * np.pi * 6.0 * t) + 0.002 * rng.normal(size=t.size)
    b = 0.5 * slow + 0.01 * rng.normal(size=t.size)
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack([t, a, b]), delimiter=",", header="time [s],wrist [rad/s],still [rad/s]",
               comments="")
    return path, np.column_stack([a, b])


def test_run_prints_a_tremor_paragraph_per_channel(tremor_recording, capsys):
    path, _ = tremor_recording
    assert main(["run", str(path), "--backend", "reference"]) == 0
    out = capsys.readouterr().out
    wrist = next(line for line in out.splitlines() if line.strip().startswith("wrist:"))
    still = next(line for line in out.splitlines() if line.strip().startswith("still:"))
    assert "a tremor peak in 4 of 4 windows; median frequency 6.00 Hz" in wrist
    assert "rad/s" in wrist and "in tremor 100 % of the time" in wrist
    rms = float(wrist.split("RMS ")[1].split()[0])
    assert rms == pytest.approx(0.2 / np.sqrt(2), rel=0.02)
    p2p = float(wrist.split("peak-to-peak ")[1].split()[0])
    assert p2p == pytest.approx(0.4, rel=0.05)
    assert "a tremor peak in 0 of 4 windows; RMS" in still and "in tremor 0 % of the time" in still
    assert "median frequency" not in still


def test_tremor_out_writes_one_row_per_window_and_channel(tremor_recording, tmp_path, capsys):
    path, x = tremor_recording
    out = tmp_path / "tremor.csv"
    assert main(["run", str(path), "--backend", "reference", "--tremor-out", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert lines[0].split(",") == ["channel", "unit"] + tremor_header(["rad/s", "rad/s"])
    assert "rms [rad/s]" in lines[0] and "band_power [(rad/s)^2]" in lines[0] and "[unit" not in lines[0]
    rows = [line.split(",") for line in lines[1:]]
    res = WakeFilter(backend="reference").run(x)
    tables = res.tremor_stats(FS, x=x)
    assert len(rows) == sum(len(t) for t in tables)
    assert f"wrote {len(rows)} rows to {out}" in capsys.readouterr().out
    wrist = [r for r in rows if r[0] == "wrist"]
    assert [int(r[2]) for r in wrist] == tables[0]["index"].tolist()
    column = {name: i + 2 for i, (name, _) in enumerate(TREMOR_COLUMNS)}
    assert [float(r[column["frequency"]]) for r in wrist] == tables[0]["frequency"].tolist()
    still = [r for r in rows if r[0] == "still"]
    assert {r[1] for r in still} == {"rad/s"}
    assert all(r[column["reason"]] == "no_tremor_peak" and r[column["frequency"]] == "nan" for r in still)
    assert summarise(tables[0], 500)["frequency"] == pytest.approx(6.0, abs=0.05)


def test_tremor_out_may_not_overwrite_the_input_or_the_output(tremor_recording, tmp_path, capsys):
    path, _ = tremor_recording
    assert main(["run", str(path), "--tremor-out", str(path)]) == 2
    out = tmp_path / "o.csv"
    assert main(["run", str(path), "--out", str(out), "--tremor-out", str(out)]) == 2
    assert not out.exists()
    err = capsys.readouterr().err
    assert "--tremor-out" in err and "is the input file" in err and "is also --out" in err


def test_plot_draws_the_tremor_over_time_beside_the_figure(tremor_recording, tmp_path, capsys):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (pip install matplotlib)")
    import matplotlib.pyplot as plt

    from wake.eval import plotting

    path, _ = tremor_recording
    seen = {}
    real_close = plt.close

    def keep(fig):
        seen.setdefault("legends", []).append([t.get_text() for a in fig.axes if a.get_legend()
                                               for t in a.get_legend().get_texts()])
        seen.setdefault("xdata", []).append([line.get_xdata() for a in fig.axes for line in a.get_lines()])
        real_close(fig)

    plt.close = keep
    try:
        assert main(["run", str(path), "--backend", "reference", "--plot", str(tmp_path / "f.png"),
                     "--plot-channel", "wrist"]) == 0
    finally:
        plt.close = real_close
    assert (tmp_path / "f-tremor.png").read_bytes()[:4] == b"\x89PNG"
    assert f"the tremor over time (frequency, amplitude, TSI, time share) written to {tmp_path / 'f-tremor.png'}" \
        in capsys.readouterr().out
    legends = seen["legends"][1]
    for label in ("dominant tremor frequency", "RMS", "median peak-to-peak",
                  "TSI: IQR of the cycle-to-cycle frequency change", "share of the window in tremor"):
        assert label in legends
    # one point per HPA window, at the window's end time
    ends = WakeFilter(backend="reference").run(np.loadtxt(path, delimiter=",", skiprows=1)[:, 1]).hpa[0]
    assert sorted(set(np.concatenate(seen["xdata"][1]).tolist())) == [u.index / FS for u in ends]
    assert plotting.tremor_figure_path("a/b.png").endswith("b-tremor.png")
