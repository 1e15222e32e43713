"""``wake evaluate`` end to end (quick, synthetic + PADS-format files written here) and the literal RTP."""

import re

import numpy as np
import pytest

from wake.eval.evaluate import cli
from wake.rtp.literal import (first_column_taps, hpa_schedule, literal_rtp_predict, literal_rtp_run,
                              operation_counts)
from wake.wavelets import wavelet_approximations


def _fake_pads(folder, rng, count=2, seconds=12.0):
    folder.mkdir()
    for i in range(count):
        t = np.cumsum(rng.uniform(0.008, 0.012, int(seconds * 100)))
        t -= t[0]
        vol = np.sin(2 * np.pi * 0.4 * t)[:, None] * rng.uniform(0.5, 2.0, 6)
        trem = 0.2 * np.sin(2 * np.pi * (5 + i) * t[:, None] + rng.uniform(0, 6, 6))
        vals = vol + trem + 0.02 * rng.standard_normal((t.size, 6))
        rows = np.column_stack([t, vals])
        (folder / f"{100 + i}_Task_LeftWrist.txt").write_text(
            "\n".join(",".join(f"{v:.10f}" for v in r) for r in rows) + "\n")
    (folder / "observation_100.json").write_text("{}")
    return folder


def _table_numbers(text):
    """Every cell of every Markdown table row, numbers only."""
    cells = []
    for line in text.splitlines():
        if line.startswith("|") and not line.startswith("|---"):
            cells += [c.strip().strip("*") for c in line.strip("|").split("|")]
    return cells


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    base = tmp_path_factory.mktemp("evaluate")
    pads = _fake_pads(base / "pads", np.random.default_rng(7))
    out = base / "out"
    status = cli([out, "--quick", "--pads", pads, "--backend", "reference"])
    return status, out


@pytest.mark.slow
def test_quick_run_writes_the_report(quick_report):
    status, out = quick_report
    assert status == 0
    text = (out / "report.md").read_text()
    for heading in ("## Headline", "## Synthetic set", "### NRMSE (lower is better)", "### PRF %",
                    "### SNR_out dB", "## Real recordings", "### Mean tremor NRMSE per method", "## Delay",
                    "## Ablation"):
        assert heading in text
    assert "| Signal | SNR_in dB | BMFLC | BMFLC (paper) | E-BMFLC | E-BMFLC (paper) | WFLC | eHWFLC-KF | " \
           "WAKE-ref | WAKE (paper) |" in text
    assert "| Recording | Axis | f_d Hz | BMFLC | E-BMFLC | WFLC | eHWFLC-KF | WAKE-ref |" in text
    assert "100_Task_LeftWrist | gyro_z" in text and "101_Task_LeftWrist | acc_x" in text
    cells = _table_numbers(text)
    assert not any(c.lower() in ("nan", "inf", "-inf", "n/a") for c in cells)
    numbers = [float(c) for c in cells if re.fullmatch(r"-?\d+(\.\d+)?", c)]
    assert len(numbers) > 100 and np.isfinite(numbers).all()
    # The headline rows hold one finite NRMSE per method.
    head = [ln for ln in text.splitlines() if ln.startswith("| Synthetic (voluntary NRMSE)")][0]
    vals = [float(c) for c in head.strip("|").split("|")[1:]]
    assert len(vals) == 5 and all(0 < v < 1 for v in vals)
    assert (out / "results.json").is_file()


def test_quick_run_figures(quick_report):
    pytest.importorskip("matplotlib")
    _, out = quick_report
    assert (out / "fig_nrmse_synthetic.png").stat().st_size > 1000
    assert (out / "fig_nrmse_real.png").stat().st_size > 1000
    assert list(out.glob("fig_tremor_*.png"))
    assert (out / "fig_error_vs_time.png").stat().st_size > 1000
    assert (out / "fig_spectra_by_flag.png").stat().st_size > 1000


def test_quick_run_scores_time_since_start_and_the_flags(quick_report):
    import json

    _, out = quick_report
    text = (out / "report.md").read_text()
    section = text.split("## Time since start")[1].split("\n## ")[0]
    header = "| method | 0.5-1 s | 1-2 s | 2-5 s | after 5 s | whole (from 0.5 s) |"
    assert section.count(header) == 2                       # synthetic and PADS
    for method in ("BMFLC", "E-BMFLC", "WFLC", "WAKE-ref", "zero tremor (voluntary = x)",
                   "zero prediction (voluntary = 0)"):
        assert section.count(f"| {method} |") == 2
    # one lowest entry in bold per slice and table
    for table in section.split(header)[1:]:
        rows = [ln for ln in table.splitlines() if ln.startswith("| ")]
        bold = [[c.strip().startswith("**") for c in r.strip("|").split("|")[1:]] for r in rows]
        assert [sum(col) for col in zip(*bold)] == [1] * 5
    res = json.loads((out / "results.json").read_text())
    # the whole-recording figure sits beside the after-warm-up one, for every method
    for part in ("synthetic", "real"):
        for method, scores in res[part]["slices"].items():
            # predicting 0 scores the whole signal against the tremor's range: 2.06 on these fake recordings
            top = 3 if method.startswith("zero prediction") else 2
            assert 0 < scores["whole (from 0.5 s)"] < top and 0 < scores["after 5 s"] < top
        t, err = res[part]["curves"]["WAKE-ref"]
        assert t[0] == 0.25 and len(t) == len(err) >= 20
    flags = res["real"]["flags"]
    assert sum(flags.values()) == 2 * 6 * 6                  # 12 s recordings: HPAs at 1, 2, 3, 4, 5 and 10 s
    assert "| flag | windows | share |" in text.split("## The cut-off on PADS")[1]
    assert all("x" not in w for ws in res["real"]["flag_windows"].values() for w in ws)


@pytest.mark.slow
def test_synthetic_only(tmp_path):
    status = cli([tmp_path, "--quick", "--synthetic-only", "--backend", "reference"])
    assert status == 0
    text = (tmp_path / "report.md").read_text()
    assert "## Synthetic set" in text and "## Real recordings" not in text


def test_missing_pads_folder_is_an_error(tmp_path, capsys):
    assert cli([tmp_path / "out", "--quick", "--pads", tmp_path / "missing", "--backend", "reference"]) == 2
    assert "not a folder" in capsys.readouterr().err


# ----------------------------------------------------------------------------- literal RTP
def test_literal_rtp_matches_hand_computation_haar_level1():
    # J = 1, Haar: both level-1 approximations of [m1, m2] equal (m1 + m2)/2.
    m = np.array([0.7, -0.3])
    w, R, p0, q = 1.3, 0.5, 2.0, 0.1
    assert wavelet_approximations(m, "haar", 1)[:, 0] == pytest.approx([0.2, 0.2])
    x, P = 0.2, p0
    for z in m:
        P = P + q
        r = z - w * x
        S = w * P * w + R
        K = P * w / S
        x = x + K * r
        P = P - K * w * P
    expected = w * x
    got = literal_rtp_predict(m, [w], R, p0, q, wavelet="haar")
    assert got == pytest.approx(expected, rel=1e-12)


def test_literal_rtp_without_kalman_gain_is_the_first_column():
    rng = np.random.default_rng(3)
    window = rng.standard_normal(8)
    w = rng.standard_normal(3)
    got = literal_rtp_predict(window, w, 1.0, p0=0.0, q=0.0)
    assert got == pytest.approx(w @ wavelet_approximations(window, "sym3", 3)[0], rel=1e-12)
    np.testing.assert_allclose(first_column_taps("sym3", 3) @ window,
                               wavelet_approximations(window, "sym3", 3)[0], atol=1e-12)


def test_literal_rtp_run_equals_per_window_predictions():
    rng = np.random.default_rng(5)
    x = np.cumsum(rng.standard_normal(60)) * 0.1
    level = 3
    sched = [(0, np.array([0.0, 0.0, 1.0]), 1.0), (20, rng.standard_normal(3), 0.3), (41, rng.standard_normal(3), 2.0)]
    out = literal_rtp_run(x, sched, level, p0_scale=1.5, q=0.01)
    padded = np.concatenate((np.full(7, x[0]), x))
    for i in range(x.size - 1):
        _, w, R = [s for s in sched if s[0] <= i][-1]
        direct = literal_rtp_predict(padded[i : i + 8], w, R, 1.5 * R, 0.01 * R)
        assert out[i + 1] == pytest.approx(direct, rel=1e-9, abs=1e-12)


def test_hpa_schedule_alignment():
    class U:
        def __init__(self, index):
            self.index, self.weights, self.measurement_noise = index, np.ones(2), 0.5

    sched = hpa_schedule([U(500), U(1000)], 2, 800)
    assert [s[0] for s in sched] == [0, 499]  # in force from the step on sample index - 1


def test_operation_counts():
    c = operation_counts(1)  # J = 1, N = 2
    assert c == {"wake_general": 2 + 2 + 4, "wake_inert": 2 + 2, "literal": 2 + 2 * (2 + 4) + 1}
    c5 = operation_counts(5)
    assert c5["literal"] > 10 * c5["wake_inert"]


def test_quick_run_reports_the_tremor_ahead_per_horizon_and_slice(quick_report):
    import json

    _, out = quick_report
    section = (out / "report.md").read_text().split("## Tremor ahead")[1].split("\n## ")[0]
    header = "| method | 0.5-1 s | 1-2 s | 2-5 s | after 5 s | whole (from 0.5 s) |"
    assert section.count(header) == 2 * 4                   # synthetic and PADS, at 10, 20, 50 and 100 ms
    for method in ("WAKE command (gated)", "zero (the actuator stays off)", "BMFLC, own extrapolation",
                   "E-BMFLC, own extrapolation", "WFLC, own extrapolation", "eHWFLC-KF, own extrapolation",
                   "oracle: hindsight 8-tap LS on the true tremor, fed the true past",
                   "limit: hindsight 8-tap Wiener, WAKE estimate -> true tremor"):
        assert section.count(f"| {method} |") == 8
    assert section.count("| h | 0.5-1 s | 1-2 s | 2-5 s | after 5 s | whole (from 0.5 s) | no harm |") == 2
    res = json.loads((out / "results.json").read_text())["ahead"]
    assert res["real"]["axes"] == 2 * 6 and res["paper"]["axes"] == 2
    for part in res.values():
        assert sorted(float(ms) for ms in part["horizons"]) == [10, 20, 50, 100]
        for methods in part["horizons"].values():
            zero, oracle = methods["zero (the actuator stays off)"], methods[
                "oracle: hindsight 8-tap LS on the true tremor, fed the true past"]
            assert oracle["after 5 s"] < zero["after 5 s"]
