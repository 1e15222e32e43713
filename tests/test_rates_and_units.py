"""The rough edges of issue 43, item 10, in this scope: a rate too low for the tremor band says which rates
are supported; the PSD axis and the --tremor-out header carry the recording's unit; ordinals read right."""

import warnings

import numpy as np
import pytest

from wake import WakeFilter
from wake.cli import main
from wake.sampling import RateWarning, rate_note


def _gyro(fs, seconds=12.0):
    t = np.arange(int(seconds * fs)) / fs
    return 40.0 * np.sin(2 * np.pi * 0.4 * t) + 8.0 * np.sin(2 * np.pi * 6.0 * t)


def _accel(fs, seconds=12.0):
    t = np.arange(int(seconds * fs)) / fs
    return 9.81 * np.cos(0.3 * np.sin(2 * np.pi * 0.2 * t)) + 0.5 * np.sin(2 * np.pi * 5.0 * t)


@pytest.mark.parametrize("fs", [20.0, 25.0])
def test_a_rate_too_low_for_the_tremor_band_names_the_supported_rates(tmp_path, capsys, fs):
    path = tmp_path / "slow.csv"
    np.savetxt(path, _gyro(fs)[:, None], header="gx", comments="")
    assert main(["run", str(path), "--fs", f"{fs:g}", "--backend", "reference"]) == 2
    err = capsys.readouterr().err.strip()
    assert f"fs = {fs:g} Hz is too low for the tremor band 2.5-15 Hz" in err
    assert "needs at least 30 Hz" in err and "WAKE supports 50-1000 Hz" in err
    assert "tremor_band must satisfy" not in err and len(err.splitlines()) == 1
    # wake stream: the same line, before reading a sample
    assert main(["stream", "--stdin", "--stdout", "--fs", f"{fs:g}"]) == 2
    assert "WAKE supports 50-1000 Hz" in capsys.readouterr().err
    # from Python the band can move below fs/2 (with the rate's warning)
    with pytest.warns(RateWarning):
        assert WakeFilter(fs=fs, tremor_band=(2.5, fs / 2 - 1.0), backend="reference").fs == fs


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("unit, squared, make", [("deg/s", "(deg/s)^2", _gyro), ("g", "g^2", _accel)])
def test_the_psd_axis_and_the_tremor_header_carry_the_unit(tmp_path, capsys, monkeypatch, fs, unit, squared, make):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (pip install matplotlib)")
    import matplotlib.pyplot as plt

    x = make(fs)
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack([x, 0.5 * x]), delimiter=",", header=f"a [{unit}],b [{unit}]", comments="")
    labels = []
    real_close = plt.close

    def keep(fig):
        labels.append([a.get_ylabel() for a in fig.axes])
        real_close(fig)

    monkeypatch.setattr(plt, "close", keep)
    tremor = tmp_path / "t.csv"
    assert main(["run", str(path), "--fs", f"{fs:g}", "--backend", "reference", "--plot", str(tmp_path / "f.png"),
                 "--tremor-out", str(tremor)]) == 0
    assert f"PSD ({squared}/Hz)" in labels[0]
    header = tremor.read_text().splitlines()[0].split(",")
    assert f"rms [{unit}]" in header and f"peak_to_peak [{unit}]" in header and f"band_power [{squared}]" in header
    assert not any("unit]" in cell or "unit^2" in cell for cell in header)


def test_mixed_units_leave_the_header_to_the_unit_column(tmp_path):
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack([_gyro(100.0), _accel(100.0)]), delimiter=",",
               header="gx [deg/s],ax [g]", comments="")
    tremor = tmp_path / "t.csv"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["run", str(path), "--fs", "100", "--backend", "reference", "--tremor-out", str(tremor)]) == 0
    lines = tremor.read_text().splitlines()
    header = lines[0].split(",")
    assert "rms" in header and "band_power" in header and not any("[unit" in cell for cell in header)
    assert {line.split(",")[1] for line in lines[1:]} == {"deg/s", "g"}


@pytest.mark.parametrize("fs, words", [(200.0, "every 2nd also"), (300.0, "every 3rd also"),
                                       (1000.0, "every 10th also"), (2100.0, "every 21st also")])
def test_the_rate_note_says_its_ordinals_right(fs, words):
    assert words in rate_note(fs)
