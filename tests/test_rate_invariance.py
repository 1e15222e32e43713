"""One recording at 50, 100, 200, 500 and 1000 Hz through the public surface (issue 43, "Done when"):
``WakeFilter.run`` + ``tremor_stats``, ``wake run --tremor-out --plot``, ``wake stream`` and ``wake evaluate``.

At every rate the time outputs span the whole recording (the last HPA window ends within one window of
its end), the dominant tremor frequencies agree with an independent FFT (scipy's Hann periodogram of the
same samples) within one bin, and the number of full HPA windows agrees across rates within one.  The
recording has two channels: a wrist gyroscope (deg/s, slow motion around zero) and an accelerometer axis
with gravity on it (m/s^2, about 9.5 with a slow tilt); their tremor lies off the FFT's bins (6.1 and
4.9 Hz for bins of 0.2 Hz).  Above 149 Hz the HPA runs on the decimated stream (wake.rate): before issue
43 its windows were counted in bank samples and every output built on them ended 2-10x too early.
"""

import csv
import io
import json
import re
import sys

import numpy as np
import pytest
from scipy.signal import periodogram

from wake import WakeFilter
from wake.cli import main
from wake.hpa.characterise import summarise

RATES = (50.0, 100.0, 200.0, 500.0, 1000.0)
SECONDS = 22.0          # four full 5 s windows and 2 s more
WINDOW_S = 5.0          # the default HPA window
BAND = (2.5, 15.0)      # the default tremor band
CHANNELS = ("gyro_x", "acc_z")
TREMOR_HZ = (6.1, 4.9)


def recording(fs):
    """(time, samples (n, 2)) of the same motion sampled at ``fs``."""
    t = np.arange(int(round(SECONDS * fs))) / fs
    noise = np.random.default_rng(int(fs)).standard_normal((t.size, 2))
    gyro = (40.0 * np.sin(2 * np.pi * 0.35 * t) + 15.0 * np.sin(2 * np.pi * 0.9 * t + 1.0)
            + 8.0 * np.sin(2 * np.pi * TREMOR_HZ[0] * t) + 0.3 * noise[:, 0])
    tilt = 0.5 * np.sin(2 * np.pi * 0.25 * t)
    acc = 9.81 * np.cos(tilt) + 0.6 * np.sin(2 * np.pi * TREMOR_HZ[1] * t) + 0.02 * noise[:, 1]
    return t, np.column_stack([gyro, acc])


def fft_peak(window, fs):
    """The independent estimate: the highest bin of the Hann periodogram in the tremor band, and the bin width."""
    f, p = periodogram(window, fs, window="hann", detrend="linear")
    band = (f >= BAND[0]) & (f <= BAND[1])
    return float(f[band][np.argmax(p[band])]), float(f[1] - f[0])


def check_windows(fs, x, ends, frequencies, samples, where):
    """Per channel: the last window ends within one window of the end, every full window's frequency lies
    within one bin of the FFT of its samples; returns the number of full windows."""
    n, L = x.shape[0], int(round(WINDOW_S * fs))
    assert n / fs - WINDOW_S <= ends[-1] <= n / fs + 1e-9, \
        f"{where} at {fs:g} Hz: the last window ends at {ends[-1]:g} s of a {n / fs:g} s recording"
    full = 0
    for end, f0, size in zip(ends, frequencies, samples):
        if size != L:
            continue
        full += 1
        stop = int(round(end * fs))
        peak, bin_hz = fft_peak(x[stop - L:stop], fs)
        assert abs(f0 - peak) <= bin_hz + 1e-9, \
            f"{where} at {fs:g} Hz, window ending {end:g} s: {f0:.3f} Hz against the FFT's {peak:.3f} Hz"
    return full


def assert_within_one(counts, what):
    assert max(counts.values()) - min(counts.values()) <= 1 and min(counts.values()) >= 3, \
        f"{what}: full windows per rate {counts}"


def _write(folder, fs, with_time=True):
    t, x = recording(fs)
    path = folder / f"rec_{fs:g}hz.csv"
    cols = [t, x] if with_time else [x]
    head = ("time [s]," if with_time else "") + "gyro_x [deg/s],acc_z [m/s^2]"
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=head, comments="", fmt="%.9g")
    return path, x


def test_run_and_tremor_stats_span_the_recording_at_every_rate():
    counts = {c: {} for c in CHANNELS}
    for fs in RATES:
        _, x = recording(fs)
        filt = WakeFilter(fs=fs)
        tables = filt.run(x).tremor_stats(fs, x=x)
        for c, (name, table) in enumerate(zip(CHANNELS, tables)):
            full = check_windows(fs, x[:, c], table["end_time"], table["frequency"], table["samples"],
                                 f"tremor_stats {name}")
            assert summarise(table, filt.window_samples)["windows"] == full
            assert table["index"][-1] / fs == table["end_time"][-1]     # index counts input samples
            counts[name][fs] = full
    for name in CHANNELS:
        assert_within_one(counts[name], f"tremor_stats {name}")


def test_wake_run_tremor_out_and_plot_span_the_recording_at_every_rate(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (pip install matplotlib)")
    import matplotlib.pyplot as plt

    drawn = []
    real_close = plt.close

    def keep(fig):
        drawn.append(fig)
        real_close(fig)

    monkeypatch.setattr(plt, "close", keep)
    counts = {c: {} for c in CHANNELS}
    for fs in RATES:
        path, x = _write(tmp_path, fs)
        tremor, figure = tmp_path / f"t{fs:g}.csv", tmp_path / f"p{fs:g}.png"
        drawn.clear()
        assert main(["run", str(path), "--tremor-out", str(tremor), "--plot", str(figure)]) == 0
        out = capsys.readouterr().out
        with open(tremor, newline="") as f:
            rows = list(csv.DictReader(f))
        for c, name in enumerate(CHANNELS):
            mine = [r for r in rows if r["channel"] == name]
            ends = np.array([float(r["end_time [s]"]) for r in mine])
            full = check_windows(fs, x[:, c], ends, [float(r["frequency [Hz]"]) for r in mine],
                                 [int(r["samples"]) for r in mine], f"--tremor-out {name}")
            said = re.search(rf"{name}: a tremor peak in (\d+) of (\d+) windows; median frequency ([\d.]+) Hz", out)
            assert said and int(said.group(2)) == full and int(said.group(1)) == full, out
            peak, _ = fft_peak(x[:, c], fs)
            assert abs(float(said.group(3)) - peak) <= 1.0 / WINDOW_S, (name, fs, said.group(0), peak)
            counts[name][fs] = full
        # the spectrum panel's last window and the tremor figure's points end where the table ends
        legend = [t.get_text() for t in drawn[0].axes[3].get_legend().get_texts()]
        ending = float(re.search(r"ending at ([\d.]+) s", " ".join(legend)).group(1))
        assert SECONDS - WINDOW_S <= ending <= SECONDS, (fs, legend)
        points = np.concatenate([line.get_xdata() for line in drawn[1].axes[0].get_lines()])
        assert SECONDS - WINDOW_S <= points.max() <= SECONDS, fs
    for name in CHANNELS:
        assert_within_one(counts[name], f"wake run {name}")


def test_wake_stream_spans_the_recording_at_every_rate(tmp_path, capsys, monkeypatch):
    for fs in RATES:
        t, x = recording(fs)
        rows = np.column_stack([t, x]).tolist()
        lines = "time,gyro_x,acc_z\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in rows)
        monkeypatch.setattr(sys, "stdin", io.StringIO(lines))
        assert main(["stream", "--stdin", "--stdout", "--fs", f"{fs:g}", "--timestamps", "--header",
                     "--hpa-mode", "inline", "--status", "0"]) == 0
        out = capsys.readouterr().out.splitlines()
        head, values = out[0].split(","), np.array([[float(v) for v in line.split(",")] for line in out[1:]])
        # the columns of wake run: time, then per channel its measurement, voluntary motion and tremor
        assert head == ["time [s]", "gyro_x", "gyro_x_voluntary", "gyro_x_tremor",
                        "acc_z", "acc_z_voluntary", "acc_z_tremor"]
        assert values.shape == (t.size, 7) and values[-1, 0] == t[-1], f"{fs:g} Hz: {values.shape} rows"
        # a line holds the sample's voluntary motion, predicted before it came: what wake run writes
        voluntary = values[:, [2, 5]]
        res = WakeFilter(fs=fs).run(x)
        np.testing.assert_allclose(voluntary, res.voluntary, rtol=0, atol=1e-9 * np.abs(x).max())
        L = int(round(WINDOW_S * fs))
        for c in range(2):   # the stream's tremor over the last full window has the input's tremor peak
            tremor = x[:, c] - voluntary[:, c]
            got, bin_hz = fft_peak(tremor[-L:], fs)
            want, _ = fft_peak(x[-L:, c], fs)
            assert abs(got - want) <= bin_hz + 1e-9, (fs, CHANNELS[c], got, want)


def test_wake_evaluate_spans_the_recording_at_every_rate(tmp_path, capsys):
    files = [str(_write(tmp_path, fs)[0]) for fs in RATES]
    out = tmp_path / "out"
    assert main(["evaluate", str(out), *files, "--synthetic", "0", "--backend", "reference", "--no-progress",
                 "--store-format", "csv"]) == 0
    capsys.readouterr()
    csv.field_size_limit(1 << 30)
    with open(out / "store" / "results.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["method"] == "WAKE-ref" and r["hpa"]]
    counts = {c: {} for c in CHANNELS}
    for fs in RATES:
        _, x = recording(fs)
        L = int(round(WINDOW_S * fs))
        for c, name in enumerate(CHANNELS):
            row = next(r for r in rows if r["recording"] == f"rec_{fs:g}hz" and r["channel"] == name)
            assert float(row["fs"]) == fs
            hpa = json.loads(row["hpa"])   # [index, cutoff, flag, first sample] per HPA window
            assert SECONDS - WINDOW_S <= hpa[-1][0] / fs <= SECONDS, (fs, name, hpa[-1])
            full = [h for h in hpa if h[0] - h[3] == L]
            counts[name][fs] = len(full)
            # evaluate reports no dominant frequency; its cut-off must still part the voluntary motion from the
            # tremor the FFT finds
            peak, _ = fft_peak(x[:, c], fs)
            assert float(row["cutoff"]) < peak, (fs, name, row["cutoff"], peak)
    for name in CHANNELS:
        assert_within_one(counts[name], f"wake evaluate {name}")
    assert "PADS" not in (out / "report.md").read_text()
