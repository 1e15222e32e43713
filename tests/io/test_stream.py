"""``wake stream``: every sample in gets its output, in order, equal to ``WakeFilter.run``; clean stops; LSL."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from wake import WakeFilter
from wake.eval.synthetic import make_signal
from wake.cli import main
from wake.io.stream import StreamProcessor

FS = 100.0


@pytest.fixture(scope="module")
def signal3():
    s = make_signal(5.0, seed=1, duration=12.0)
    return np.column_stack([s.measurement, -s.measurement, 0.5 * s.measurement])


def _env():
    """The subprocess imports the same wake as this test (an installed copy, or the checkout)."""
    import wake

    env = dict(os.environ)
    home = os.path.dirname(os.path.dirname(os.path.abspath(wake.__file__)))
    env["PYTHONPATH"] = home + os.pathsep + env.get("PYTHONPATH", "")
    return env


#: The subprocesses' working directory: `python -m` puts it first on sys.path, so it must hold no `wake`
#: (from a checkout's root the source tree, without its compiled core, would shadow the installed copy).
HERE = os.path.dirname(os.path.abspath(__file__))


def stream(args, text, timeout=120):
    return subprocess.run([sys.executable, "-m", "wake", "stream", *args], input=text, capture_output=True,
                          text=True, timeout=timeout, env=_env(), cwd=HERE)


def lines_of(x, stamps=None):
    rows = x.tolist()
    if stamps is not None:
        rows = [[t, *r] for t, r in zip(stamps.tolist(), rows)]
    return "".join(",".join(repr(v) for v in r) + "\n" for r in rows)


def test_pipes_inline_equal_run_bit_for_bit_with_header_and_timestamps(signal3):
    stamps = 1000.0 + np.arange(len(signal3)) / FS
    text = "time,gx,gy,gz\n" + lines_of(signal3, stamps)
    res = stream(["--stdin", "--stdout", "--fs", "100", "--hpa-mode", "inline", "--timestamps", "--header"], text)
    assert res.returncode == 0, res.stderr
    out = res.stdout.splitlines()
    # wake run --out's columns: the time in s, then per channel the measurement, voluntary, tremor
    assert out[0] == ("time [s],gx,gx_voluntary,gx_tremor,gy,gy_voluntary,gy_tremor,gz,gz_voluntary,gz_tremor")
    got = np.array([[float(v) for v in line.split(",")] for line in out[1:]])
    assert got.shape == (len(signal3), 10)
    ref = WakeFilter(fs=FS).run(signal3)
    np.testing.assert_array_equal(got[:, 0], stamps)
    np.testing.assert_array_equal(got[:, 1::3], signal3)
    np.testing.assert_array_equal(got[:, 2::3], ref.voluntary)
    np.testing.assert_array_equal(got[:, 3::3], ref.tremor)
    assert "end of input: 1200 samples" in res.stderr and "f_d [Hz]: gx" in res.stderr
    # the first stderr line says when the filter is ready, so a producer can start its clock then
    assert res.stderr.splitlines()[0] == "wake stream: ready, reading stdin at 100 Hz"


def test_thread_mode_answers_every_sample_and_matches_run_until_the_first_swap(signal3):
    res = stream(["--stdin", "--stdout", "--fs", "100"], lines_of(signal3))
    assert res.returncode == 0, res.stderr
    got = np.loadtxt(res.stdout.splitlines(), delimiter=",")
    assert got.shape == (len(signal3), 10) and np.isfinite(got).all()
    ref = WakeFilter(fs=FS).run(signal3)
    first_hpa = ref.hpa[0][0].index  # nothing can differ before the first HPA result exists
    np.testing.assert_array_equal(got[:first_hpa, 2::3], ref.voluntary[:first_hpa])
    np.testing.assert_allclose(got[:, 3::3] + got[:, 2::3], signal3, atol=1e-12)  # tremor = x - voluntary
    np.testing.assert_array_equal(got[:, 0], np.arange(len(signal3)) / FS)  # no time column: n / fs


def test_ctrl_c_stops_cleanly_with_every_sample_answered(signal3):
    # --time-column none: the first line is answered at once (no lines read ahead to judge a column's shape)
    p = subprocess.Popen([sys.executable, "-m", "wake", "stream", "--stdin", "--stdout", "--fs", "100",
                          "--time-column", "none"],
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_env(),
                         cwd=HERE)
    try:
        p.stdin.write(lines_of(signal3[:50]))
        p.stdin.flush()
        answered = [p.stdout.readline() for _ in range(50)]  # the stream is now waiting for sample 51
        assert all(line.count(",") == 9 for line in answered)
        time.sleep(0.2)
        p.send_signal(signal.SIGINT)
        rest, err = p.communicate(timeout=30)
    finally:
        p.kill()
    assert p.returncode == 0, err
    assert rest == "" and "stopped by signal: 50 samples" in err and "Traceback" not in err


@pytest.mark.parametrize("policy", ["stop", "missing"])
def test_a_bad_line(policy, signal3):
    text = lines_of(signal3[:30]) + "1.0,abc,2.0\n" + lines_of(signal3[30:40])
    res = stream(["--stdin", "--stdout", "--fs", "100", "--bad-lines", policy], text)
    out = res.stdout.splitlines()
    assert "Traceback" not in res.stderr
    if policy == "stop":
        assert res.returncode == 2 and len(out) == 30
        assert "input line 31: could not convert string to float: 'abc'" in res.stderr
        assert "--bad-lines missing" in res.stderr
    else:
        assert res.returncode == 0 and len(out) == 41
        bad = np.array([float(v) for v in out[30].split(",")])
        assert np.isfinite(bad[2::3]).all() and np.isnan(bad[3::3]).all()  # a prediction, no tremor
        assert np.isnan(bad[1::3]).all() and bad[0] == 30 / FS  # no measurement; the time goes on
        assert "bad lines 1" in res.stderr


@pytest.mark.parametrize("args, message", [
    (["--stdin", "--stdout"], "the input has no time column, so the sampling rate is unknown: give it with --fs HZ"),
    (["--stdin", "--stdout", "--fs", "0"], "--fs must be > 0 Hz"),
    (["--stdin", "--stdout", "--fs", "100", "--level", "9"], "level must be from 1 to"),
])
def test_setting_errors_exit_2_before_reading(args, message):
    res = stream(args, "1\n2\n")
    assert res.returncode == 2 and message in res.stderr and res.stdout == ""
    assert "Traceback" not in res.stderr


def test_processor_aligns_like_run_and_passes_missing_samples(signal3):
    x = signal3[:700, :1].copy()
    x[300] = np.nan
    sp = StreamProcessor(WakeFilter(fs=FS, backend="reference", hpa_mode="inline"), ["g"])
    vol = np.array([sp.process(v)[0] for v in x])
    ref = WakeFilter(fs=FS, backend="reference").run(x)
    np.testing.assert_array_equal(vol, ref.voluntary)
    with pytest.raises(ValueError, match="2 values where the stream has 1"):
        sp.process([1.0, 2.0])


def samples_in(filt) -> int:
    channels = filt.get_state().channels
    return channels[0].schedule.count if channels else 0


def test_answer_goes_out_before_the_filter_takes_the_sample_in(signal3):
    # The latency path holds no filtering: answer() returns the prediction made
    # from the samples before, and the filter's update() runs in advance().
    x = signal3[:620, :2]
    sp = StreamProcessor(WakeFilter(fs=FS, backend="reference", hpa_mode="inline"), ["a", "b"])
    vol = []
    for i, v in enumerate(x):
        out, trem = sp.answer(v)
        assert samples_in(sp.filt) == i  # the sample is not in the filter yet
        np.testing.assert_array_equal(trem, v - out)
        vol.append(out)
        sp.advance()
        sp.advance()  # a second call has nothing left to feed
        assert samples_in(sp.filt) == i + 1
    ref = WakeFilter(fs=FS, backend="reference").run(x)
    np.testing.assert_array_equal(np.array(vol), ref.voluntary)
    # answer() twice in a row still feeds both samples, in order
    sp2 = StreamProcessor(WakeFilter(fs=FS, backend="reference", hpa_mode="inline"), ["a", "b"])
    got = [sp2.answer(v)[0] for v in x]
    np.testing.assert_array_equal(np.array(got), ref.voluntary)


def test_lsl_without_pylsl_says_how_to_install(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "pylsl", None)
    assert main(["stream", "--lsl-in", "x", "--lsl-out", "y"]) == 2
    assert "pip install pylsl" in capsys.readouterr().err


def test_lsl_loopback_every_sample_in_order_equal_to_run(signal3):
    pylsl = pytest.importorskip("pylsl", reason="pylsl is not installed (pip install pylsl)")
    tag = f"{os.getpid()}-{time.monotonic_ns()}"
    info = pylsl.StreamInfo(f"wake-test-in-{tag}", "IMU", 3, FS, pylsl.cf_double64, f"src-{tag}")
    chans = info.desc().append_child("channels")
    for name in ("gx", "gy", "gz"):
        c = chans.append_child("channel")
        c.append_child_value("label", name)
        c.append_child_value("unit", "rad/s")
    outlet = pylsl.StreamOutlet(info)
    p = subprocess.Popen([sys.executable, "-m", "wake", "stream", "--lsl-in", f"wake-test-in-{tag}",
                          "--lsl-out", f"wake-test-out-{tag}", "--hpa-mode", "inline", "--status", "0"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=_env(), cwd=HERE)
    try:
        found = pylsl.resolve_byprop("name", f"wake-test-out-{tag}", timeout=30)
        assert found, "wake stream did not publish its outlet"
        inlet = pylsl.StreamInlet(found[0], max_buflen=360)
        inlet.open_stream(timeout=10)
        desc = inlet.info(timeout=10).desc().child("channels").child("channel")
        labels = []
        while not desc.empty():
            labels.append(desc.child_value("label"))
            desc = desc.next_sibling()
        assert labels == ["gx_voluntary", "gx_tremor", "gy_voluntary", "gy_tremor", "gz_voluntary", "gz_tremor"]
        assert outlet.wait_for_consumers(10)
        stamps = pylsl.local_clock() + np.arange(len(signal3)) / FS
        for row, t in zip(signal3.tolist(), stamps.tolist()):
            outlet.push_sample(row, t)
        got, got_t = [], []
        deadline = time.monotonic() + 60
        while len(got) < len(signal3) and time.monotonic() < deadline:
            chunk, t = inlet.pull_chunk(timeout=0.5)
            got += chunk
            got_t += t
        del outlet  # the end of the input stream: wake stream stops
        err = p.communicate(timeout=60)[1]
    finally:
        p.kill()
    assert p.returncode == 0, err
    assert len(got) == len(signal3)
    ref = WakeFilter(fs=FS).run(signal3)
    g = np.array(got)
    np.testing.assert_array_equal(g[:, 0::2], ref.voluntary)  # grouped by channel, as wake run groups them
    np.testing.assert_array_equal(g[:, 1::2], ref.tremor)
    np.testing.assert_allclose(got_t, stamps, rtol=0, atol=1e-6)  # the input's timestamps, in order
    assert "the input stream ended: 1200 samples" in err


def test_pipes_with_a_horizon_write_the_tremor_ahead_of_each_sample_as_run_aligns_it(signal3):
    x = signal3[:, :2]
    res = stream(["--stdin", "--stdout", "--fs", "100", "--hpa-mode", "inline", "--header", "--horizon-ms", "47"],
                 lines_of(x))
    assert res.returncode == 0, res.stderr
    assert "horizon: 47 ms at 100 Hz is 5 sample(s) (50 ms; rounded to the nearest sample)" in res.stderr
    out = res.stdout.splitlines()
    ref = WakeFilter(fs=FS, horizon=5).run(x)
    # the default backend, C core or float reference: both give the voluntary_ahead column (w_h)
    kinds = ("", "_voluntary", "_tremor", "_tremor_ahead", "_confidence", "_command", "_voluntary_ahead")
    assert "no voluntary_ahead column" not in res.stderr
    assert out[0] == "time [s]," + ",".join(f"col{c}{k}" for c in range(2) for k in kinds)  # as wake run
    got = np.array([[float(v) for v in line.split(",")] for line in out[1:]])[:, 1:].reshape(len(x), 2, 7)
    np.testing.assert_array_equal(got[:, :, 1], ref.voluntary)
    # the line of sample n carries what the filter predicts for n + 5: run() aligns it 5 rows later
    for i, name in enumerate(("tremor_ahead", "confidence", "command")):
        np.testing.assert_array_equal(got[:-5, :, 3 + i], getattr(ref, name)[5:])
    assert got[:, :, 4].max() > 0.3


def test_pipes_with_a_horizon_on_the_reference_write_the_voluntary_motion_ahead_as_run_aligns_it(signal3):
    x = signal3[:, :1]
    res = stream(["--stdin", "--stdout", "--fs", "100", "--hpa-mode", "inline", "--header", "--horizon-ms", "50",
                  "--backend", "reference"], lines_of(x))
    assert res.returncode == 0, res.stderr
    out = res.stdout.splitlines()
    assert out[0] == ("time [s],col0,col0_voluntary,col0_tremor,col0_tremor_ahead,col0_confidence,col0_command,"
                      "col0_voluntary_ahead")
    got = np.array([[float(v) for v in line.split(",")] for line in out[1:]])
    ref = WakeFilter(fs=FS, horizon=5, backend="reference").run(x[:, 0])
    # the line of sample n carries the voluntary motion predicted for n + 5: run() aligns it 5 rows later
    np.testing.assert_array_equal(got[:-5, 7], ref.voluntary_ahead[5:])
    assert not np.array_equal(ref.voluntary_ahead[600:], ref.voluntary[596:-4])   # w_h, not v held


def test_a_horizon_outside_1_to_32_samples_is_refused_before_reading():
    res = stream(["--stdin", "--stdout", "--fs", "100", "--horizon-ms", "400"], "1\n2\n")
    assert res.returncode == 2 and res.stdout == ""
    assert "400 ms is 40 samples at 100 Hz; it must round to 1..32 samples" in res.stderr
