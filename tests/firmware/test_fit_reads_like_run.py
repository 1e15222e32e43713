"""`wake export-header/export-c --fit FILE` read FILE exactly as `wake run FILE` does, and say what they fitted."""

import re

import numpy as np
import pytest

from support import NO_CORE, has_c_backend

from wake import WakeFilter
from wake.cli import main
from wake.eval.synthetic import make_signal
from wake.io import PADS_CHANNELS, read_recording
from wake.rtp.fixed import WEIGHT_FRAC

pytestmark = pytest.mark.skipif(not has_c_backend(), reason=NO_CORE)


@pytest.fixture
def pads_like(tmp_path):
    """A PADS-shaped file: time in s first, then six signals; acc_x is a WAKE-shaped signal, the rest noise."""
    s = make_signal(5.0, seed=2, duration=12.0)
    n = s.measurement.size
    rng = np.random.default_rng(0)
    cols = [np.arange(n) / 100.0, s.measurement] + [0.01 * rng.standard_normal(n) for _ in range(5)]
    path = tmp_path / "001_Task_LeftWrist.txt"
    np.savetxt(path, np.column_stack(cols), delimiter=",", fmt="%.10f")
    return path, s


def _weights(header_text):
    block = re.search(r"wake_config_weights\[\d+\] = \{(.*?)\};", header_text, re.S).group(1)
    return np.array([int(v) for v in block.replace("\n", " ").split(",") if v.strip()]) / 2.0**WEIGHT_FRAC


def _expected(x, fs=100.0):
    return WakeFilter(fs=fs, backend="reference").run(x).hpa[0][-1].weights


def test_the_time_column_is_not_fitted(pads_like, tmp_path, capsys):
    path, s = pads_like
    out = tmp_path / "cfg.h"
    assert main(["export-header", str(out), "--fit", str(path)]) == 0
    w = _weights(out.read_text())
    np.testing.assert_allclose(w, _expected(s.measurement), atol=2.0**-WEIGHT_FRAC)
    time_ramp = _expected(np.arange(s.measurement.size) / 100.0)
    assert np.max(np.abs(w - time_ramp)) > 0.01  # not the weights of the time ramp, as the first release baked
    said = capsys.readouterr().out
    assert "fitted on channel 'acc_x' (the first of 6; choose with --column)" in said
    assert "at 100 Hz" in said and "fit error e_L" in said
    assert "fitted on channel 'acc_x'" in out.read_text()  # the header says it too


def test_column_by_name_as_in_wake_run(pads_like, tmp_path, capsys):
    path, _ = pads_like
    out = tmp_path / "cfg.h"
    assert main(["export-header", str(out), "--fit", str(path), "--column", "gyro_x"]) == 0
    rec = read_recording(path, columns="gyro_x")
    np.testing.assert_allclose(_weights(out.read_text()), _expected(rec.samples[:, 0]), atol=2.0**-WEIGHT_FRAC)
    assert "channel 'gyro_x' of" in capsys.readouterr().out


def test_export_c_says_what_it_fitted_in_its_readme(pads_like, tmp_path):
    path, _ = pads_like
    folder = tmp_path / "fw"
    assert main(["export-c", str(folder), "--fit", str(path), "--column", "acc_x"]) == 0
    readme = (folder / "README.md").read_text()
    assert "weights: fitted on channel 'acc_x' of 001_Task_LeftWrist.txt at 100 Hz" in readme


@pytest.mark.parametrize("args, message", [
    (["--fit", "{plain}"], "has no time column, so the sampling rate is unknown"),   # as `wake run` refuses it
    (["--fit", "{pads}", "--column", "gyro_x,gyro_y"], "fitted on one channel"),
    (["--fit", "{pads}", "--column", "nope"], "no column 'nope'; columns: time, " + ", ".join(PADS_CHANNELS)),
    (["--fit", "{pads}", "--fs", "-1"], "--fs must be > 0"),
])
def test_refusals_match_wake_run(pads_like, tmp_path, capsys, args, message):
    path, s = pads_like
    plain = tmp_path / "plain.csv"
    np.savetxt(plain, s.measurement[:, None], delimiter=",")
    args = [a.replace("{plain}", str(plain)).replace("{pads}", str(path)) for a in args]
    assert main(["export-header", str(tmp_path / "cfg.h"), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "cfg.h").exists()


def test_plain_file_with_fs_is_fitted(tmp_path, capsys):
    s = make_signal(5.0, seed=2, duration=12.0)
    plain = tmp_path / "plain.csv"
    np.savetxt(plain, s.measurement[:, None], delimiter=",")
    out = tmp_path / "cfg.h"
    assert main(["export-header", str(out), "--fit", str(plain), "--fs", "100"]) == 0
    np.testing.assert_allclose(_weights(out.read_text()), _expected(s.measurement), atol=2.0**-WEIGHT_FRAC)
    assert "100 Hz from --fs" in capsys.readouterr().out
