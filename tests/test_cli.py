import numpy as np
import pytest

from wake.cli import main
from wake.eval.synthetic import make_signal


def test_demo_prints_the_table(capsys):
    assert main(["demo", "--backend", "reference"]) == 0
    out = capsys.readouterr().out
    assert "NRMSE relative to the paper" in out
    rows = [line for line in out.splitlines() if line.strip()[:2].strip().isdigit()]
    assert len(rows) == 10


@pytest.mark.slow
def test_demo_reports_the_whole_recording_beside_the_papers_score(capsys):
    from wake import WakeFilter
    from wake.eval.metrics import nrmse
    from wake.eval.synthetic import paper_dataset

    assert main(["demo", "--backend", "reference"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[1].split()[-1] == "whole"
    mean_whole = float([line for line in out.splitlines() if line.strip().startswith("mean")][0].split()[-1])
    want = np.mean([nrmse(s.voluntary, WakeFilter(fs=s.fs, backend="reference").run(s.measurement).voluntary, 50)
                    for s in paper_dataset()])
    assert mean_whole == pytest.approx(want, abs=6e-5)


def test_run_writes_csv(recording, tmp_path, capsys):
    path, s = recording
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--column", "0", "--out", str(out)]) == 0
    assert out.read_text().splitlines()[0] == "time [s],a,a_voluntary,a_tremor"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (1200, 4)
    np.testing.assert_allclose(data[:, 0], np.arange(1200) / 100.0, atol=1e-9)
    np.testing.assert_allclose(data[:, 1], s.measurement, rtol=1e-8)
    np.testing.assert_allclose(data[:, 3], data[:, 1] - data[:, 2], atol=1e-7)
    assert "6 HPA runs per channel" in capsys.readouterr().out


def test_run_all_columns(recording, tmp_path):
    path, _ = recording
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--out", str(out)]) == 0
    assert np.loadtxt(out, delimiter=",", skiprows=1).shape == (1200, 7)


@pytest.mark.parametrize("args, message", [
    (["run", "missing.csv", "--fs", "100"], "missing.csv"),
    (["run", "{rec}", "--fs", "-5"], "--fs must be > 0"),
    (["run", "{rec}", "--fs", "100", "--level", "12"], "level must be from 1 to"),
    (["run", "{rec}", "--fs", "100", "--wavelet", "nope"], "unknown wavelet"),
])
def test_errors_are_one_clear_line(args, message, recording, capsys):
    path, _ = recording
    args = [a.replace("{rec}", str(path)) for a in args]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_export_header_fits_weights(recording, tmp_path, capsys):
    pytest.importorskip("wake._rtp", reason="the compiled C core wake._rtp is not built")
    path, _ = recording
    out = tmp_path / "cfg.h"
    assert main(["export-header", str(out), "--fit", str(path), "--column", "0", "--fs", "100"]) == 0
    text = out.read_text()
    assert "wake_config_taps" in text and "wake_config_weights" in text
    assert "#define WAKE_CONFIG_LEVEL 5" in text
    assert main(["export-header", str(out), "--weights", "1,2"]) == 2  # wrong count for level 5
    assert "weights" in capsys.readouterr().err


def test_no_command_prints_help(capsys):
    assert main([]) == 2
    assert "demo" in capsys.readouterr().out


def test_version(capsys):
    from wake import __version__

    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.strip() == f"wake {__version__}"


@pytest.mark.parametrize("command", ["demo", "run", "evaluate", "profile", "export-header"])
def test_every_command_prints_its_help(capsys, command):
    # argparse formats help lazily: a stray "%" in a help text only fails here
    with pytest.raises(SystemExit) as exit_info:
        main([command, "--help"])
    assert exit_info.value.code == 0
    assert "usage:" in capsys.readouterr().out


@pytest.mark.parametrize("through_link", [False, True])
def test_run_refuses_to_write_over_its_input(recording, tmp_path, capsys, through_link):
    recording = recording[0]
    before = recording.read_bytes()
    out = recording
    if through_link:
        out = tmp_path / "link.csv"
        out.symlink_to(recording)
    assert main(["run", str(recording), "--fs", "100", "--column", "0", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "is the input file" in err and "choose another output path" in err
    assert recording.read_bytes() == before


def test_export_header_refuses_to_write_over_the_fit_recording(recording, tmp_path, capsys):
    recording = recording[0]
    before = recording.read_bytes()
    link = tmp_path / "out.h"
    link.symlink_to(recording)
    assert main(["export-header", str(link), "--fit", str(recording)]) == 2
    assert "is the input file" in capsys.readouterr().err
    assert recording.read_bytes() == before


def test_outputs_are_written_whole_and_leave_no_temporary_file(recording, tmp_path):
    recording = recording[0]
    out = tmp_path / "out.csv"
    out.write_text("old content\n")
    assert main(["run", str(recording), "--fs", "100", "--out", str(out)]) == 0
    assert out.read_text().startswith("time [s],a,")
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


@pytest.mark.parametrize("argv, message", [
    (["export-header", "OUT", "--full-scale", "1e200"], "full_scale must lie in (0, 1e+100]"),
    (["export-header", "OUT", "--full-scale", "nan"], "full_scale must lie in"),
    (["run", "REC", "--fs", "1e308"], "fs must lie in (0, 100000]"),
    (["run", "REC", "--fs", "100", "--window", "inf"], "window_s must lie in"),
])
def test_out_of_range_numbers_exit_2_with_one_line(argv, message, recording, tmp_path, capsys):
    recording = recording[0]
    argv = [str(tmp_path / "o.h") if a == "OUT" else str(recording) if a == "REC" else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "Traceback" not in err and len(err.splitlines()) == 1


def test_run_takes_the_cutoff_rule_and_reports_the_flags(tmp_path, capsys):
    from wake import WakeFilter

    # a high-SNR signal whose windows have a tremor peak but no 3 dB valley: the two rules differ
    s = make_signal(20.9, seed=1, duration=12.0)
    path = tmp_path / "rec.csv"
    np.savetxt(path, s.measurement[:, None], delimiter=",", header="a", comments="")
    seen = {}
    for rule in ("paper", "shallow"):
        out = tmp_path / f"{rule}.csv"
        assert main(["run", str(path), "--fs", "100", "--out", str(out), "--cutoff-rule", rule]) == 0
        line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith(f"cut-off rule {rule}:"))
        written = np.loadtxt(out, delimiter=",", skiprows=1)
        want = WakeFilter(fs=100, cutoff_rule=rule).run(written[:, 1])
        flags = [u.cutoff_flag for u in want.hpa[0]]
        for flag in set(flags):
            assert f"{flag} {flags.count(flag)}" in line
        np.testing.assert_allclose(written[:, 2], want.voluntary, rtol=1e-6, atol=1e-9)
        seen[rule] = set(flags)
    assert "no_valley" in seen["paper"] and "shallow_valley" in seen["shallow"]


def test_run_with_a_horizon_writes_the_tremor_ahead_columns_and_says_the_rounding(recording, tmp_path, capsys):
    from wake import WakeFilter

    path, s = recording
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--column", "0", "--out", str(out), "--horizon-ms", "24",
                 "--backend", "reference"]) == 0
    assert "horizon: 24 ms at 100 Hz is 2 sample(s) (20 ms; rounded to the nearest sample)" in capsys.readouterr().out
    assert out.read_text().splitlines()[0] == ("time [s],a,a_voluntary,a_tremor,a_tremor_ahead,a_confidence,"
                                               "a_command,a_voluntary_ahead")
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    ref = WakeFilter(fs=100.0, horizon=2, backend="reference").run(data[:, 1])
    np.testing.assert_array_equal(data[:, 4], ref.tremor_ahead)
    np.testing.assert_array_equal(data[:, 6], ref.command)
    assert 0 < data[:, 5].max() <= 1
    # the voluntary motion 2 samples ahead (w_h), not the one-step estimate held
    np.testing.assert_array_equal(data[:, 7], ref.voluntary_ahead)
    assert not np.array_equal(data[600:, 7], data[599:-1, 2])


def test_run_on_the_c_core_with_a_horizon_writes_its_voluntary_ahead_column(recording, tmp_path, capsys):
    from support import NO_CORE, has_c_backend
    from wake import WakeFilter

    if not has_c_backend():
        pytest.skip(NO_CORE)
    path, _ = recording
    out = tmp_path / "out.csv"
    assert main(["run", str(path), "--fs", "100", "--column", "0", "--out", str(out), "--horizon-ms", "50",
                 "--backend", "c"]) == 0
    assert "no voluntary_ahead column" not in capsys.readouterr().out
    assert out.read_text().splitlines()[0].endswith(",a_command,a_voluntary_ahead")
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    ref = WakeFilter(fs=100.0, horizon=5, backend="c").run(data[:, 1])
    np.testing.assert_array_equal(data[:, 7], ref.voluntary_ahead)    # the C core's w_h' (a + d)
    assert not np.array_equal(data[600:, 7], data[595:-5, 2])         # not the one-step estimate held


@pytest.mark.parametrize("ms", ["4", "330", "nan"])
def test_run_refuses_a_horizon_outside_1_to_32_samples(recording, ms, capsys):
    path, _ = recording
    assert main(["run", str(path), "--fs", "100", "--column", "0", "--horizon-ms", ms]) == 2
    err = capsys.readouterr().err
    assert err.startswith("wake run: error: a horizon of") and "must round to 1..32 samples: 5 to <325 ms" in err
