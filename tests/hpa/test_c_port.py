"""The single-precision C HPA (csrc/wake_hpa.c) against the Python HPA, the reference."""

import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from support import ci_passed, missing_tools

from wake import WakeConfig, WakeFilter
from wake.eval.metrics import nrmse
from wake.eval.synthetic import make_signal, paper_dataset
from wake.hpa import run_hpa
from wake.rtp import c_backend_available
from wake.wavelets import filter_bank_taps

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")

CONFIG = WakeConfig(backend="reference")
TAPS = filter_bank_taps("sym3", 5)
GRID = CONFIG.fs / 1022  # one step of the AR-spectrum grid, Hz
CSRC = Path(__file__).resolve().parents[2] / "csrc"


def both(x, config=CONFIG, **kw):
    """Both HPAs on the window the C one reads: x quantised to int16 with its full scale."""
    from wake.hpa.c_port import quantize_window, run_hpa_c, window_full_scale

    fs = window_full_scale(x)
    seen = quantize_window(x, fs) * (fs / 32768)
    return run_hpa(seen, config, taps=TAPS, **kw), run_hpa_c(x, config, taps=TAPS, **kw)


def windows():
    t = np.arange(500) / 100.0
    rng = np.random.default_rng(3)
    out = {f"synthetic {i}": s.measurement[1000:1500] for i, s in enumerate(paper_dataset()[:4])}
    out["offset 1000x the tremor"] = 50.0 + np.sin(2 * np.pi * 0.4 * t) + 0.05 * np.sin(2 * np.pi * 6 * t)
    out["pure tremor"] = np.sin(2 * np.pi * 8 * t)
    out["pure voluntary"] = np.sin(2 * np.pi * 0.3 * t)
    out["white noise"] = rng.normal(size=500)
    out["warm-up length 200"] = paper_dataset()[0].measurement[:200]
    return out


@pytest.mark.parametrize("name", list(windows()))
def test_c_hpa_agrees_with_the_python_hpa(name):
    x = windows()[name]
    py, c = both(x)
    assert c.cutoff_flag == py.cutoff_flag
    assert abs(c.cutoff - py.cutoff) <= GRID
    assert c.measurement_noise == pytest.approx(py.measurement_noise, rel=2e-3)
    # the weights of a nearly collinear fit may differ along directions the data barely excite;
    # what the RTP feels is the fit they give
    assert c.fit_error <= 1.05 * py.fit_error + 1e-6 * np.std(x)
    assert np.isfinite(c.weights).all() and np.abs(c.weights).max() <= 32


def test_c_hpa_runs_every_cutoff_rule_like_the_python_hpa():
    """Each rule on windows that take each of its branches: a valley at the noise floor (the synthetic set),
    a shallow dip well above it (a tremor shoulder), a weak tremor bump on a flat floor."""
    t = np.arange(500) / 100.0
    rng = np.random.default_rng(5)
    # a random walk (voluntary content falling as 1/f^2) into a weak 6 Hz tremor: a shallow dip, far above
    # the noise floor
    shoulder = (np.cumsum(np.random.default_rng(0).normal(size=500)) * 0.05 + 0.05 * np.sin(2 * np.pi * 6 * t)
                + 0.002 * np.random.default_rng(1).normal(size=500))
    flat = 0.02 * np.sin(2 * np.pi * 0.2 * t) + rng.normal(size=500) + 0.15 * np.sin(2 * np.pi * 8 * t)
    cases = {"synthetic": make_signal(7.5, seed=1).measurement[:500], "shoulder": shoulder, "flat floor": flat}
    seen = set()
    for rule in ("paper", "shallow", "floor"):
        cfg = WakeConfig(backend="reference", cutoff_rule=rule)
        for name, x in cases.items():
            from wake.hpa.c_port import quantize_window, run_hpa_c, window_full_scale

            full = window_full_scale(x)
            py = run_hpa(quantize_window(x, full) * (full / 32768), cfg, taps=TAPS)
            c = run_hpa_c(x, cfg, taps=TAPS)
            assert (c.cutoff_flag, name, rule) == (py.cutoff_flag, name, rule)
            assert abs(c.cutoff - py.cutoff) <= GRID, (name, rule)
            seen.add((rule, py.cutoff_flag))
    # the cases reach the floor rule's three outcomes, and the other rules' own
    assert {("floor", "floor_valley"), ("floor", "shallow_valley"), ("floor", "no_valley"),
            ("shallow", "shallow_valley"), ("paper", "valley"), ("paper", "no_valley")} <= seen, seen


def test_c_hpa_finds_no_valley_where_rest_tremor_rises_from_the_lowest_bin_like_the_python_hpa():
    """Rest tremor on slow drift (docs/studies/design.md, "Rest tremor with little voluntary motion"): the shallow
    minimum on the search's lowest bin is no dip, in both HPAs, window by window."""
    from wake.eval.synthetic import make_rest_tremor

    x = make_rest_tremor(seed=2030, drift_db=-20.0).measurement
    for rule in ("shallow", "floor"):
        cfg = WakeConfig(backend="reference", cutoff_rule=rule)
        flags = []
        for start in range(0, x.size - 500 + 1, 500):
            py, c = both(x[start:start + 500], cfg)
            assert (c.cutoff_flag, start, rule) == (py.cutoff_flag, start, rule)
            assert abs(c.cutoff - py.cutoff) <= GRID, (start, rule)
            flags.append(c.cutoff_flag)
            assert c.cutoff > cfg.cutoff_range[0] + GRID, (start, rule)        # never on the lowest bin
        assert flags.count("no_valley") >= 5, (rule, flags)


def test_a_short_window_without_a_clean_valley_keeps_the_weights_like_the_python_hpa():
    """wake.hpa.run.CLEAN_ONLY_BELOW_S: under 2 s of samples, a fit is installed only on a clean valley."""
    prev = np.array([0.1, 0.2, 0.3, 0.2, 0.2])
    t = np.arange(100) / 100.0
    trend = np.cumsum(np.random.default_rng(2).normal(size=100)) * 0.05 + 0.3 * t
    py, c = both(trend, previous_weights=prev)
    assert c.cutoff_flag == py.cutoff_flag not in ("valley", "floor_valley")
    assert "weights_kept" in c.flags and "weights_kept" in py.flags
    np.testing.assert_allclose(c.weights, prev, rtol=1e-7)
    py, c = both(make_signal(7.5, seed=1).measurement[:100], previous_weights=prev)
    assert c.cutoff_flag == py.cutoff_flag == "floor_valley"
    assert "weights_kept" not in c.flags and not np.allclose(c.weights, prev)


def test_the_python_mirrors_of_the_c_hpa_constants_agree():
    """c_port and wake.hpa.cutoff restate a few numbers of wake_hpa.h; they must not drift apart."""
    from wake._rtp import lib
    from wake.hpa.c_port import c_mirror_problems
    from wake.registry import cutoff_rule_names

    assert c_mirror_problems(lib) == []
    assert [cutoff_rule_names().index(r) for r in ("paper", "shallow", "floor")] == [
        lib.WAKE_HPA_RULE_PAPER, lib.WAKE_HPA_RULE_SHALLOW, lib.WAKE_HPA_RULE_FLOOR]


def test_a_silent_window_keeps_the_previous_weights_like_the_python_hpa():
    prev = np.array([0.1, 0.2, 0.3, 0.2, 0.2])
    py, c = both(np.full(300, 0.7), previous_weights=prev)
    assert c.cutoff_flag == py.cutoff_flag == "silent"
    assert "weights_kept" in c.flags
    np.testing.assert_allclose(c.weights, prev, rtol=1e-7)


def test_the_pipeline_on_the_c_hpa_scores_within_one_percent_of_the_python_hpa():
    s = make_signal(5.0, seed=7, duration=30.0)
    res = {b: WakeFilter(backend="c", hpa_backend=b).run(s.measurement) for b in ("python", "c")}
    scores = {b: nrmse(s.voluntary, r.voluntary, 500) for b, r in res.items()}
    assert abs(scores["c"] / scores["python"] - 1) < 0.01
    assert [u.cutoff_flag for u in res["c"].hpa[0]] == [u.cutoff_flag for u in res["python"].hpa[0]]


def test_streaming_on_the_c_hpa_equals_the_batch_run():
    x = make_signal(5.0, seed=8, duration=14.0).measurement
    batch = WakeFilter(backend="c", hpa_backend="c").run(x).prediction
    filt = WakeFilter(backend="c", hpa_backend="c")
    stream = np.concatenate([filt.update_block(x[:777]), filt.update_block(x[777:])])
    np.testing.assert_array_equal(stream, batch)


def test_bad_settings_are_refused_with_the_fix():
    with pytest.raises(ValueError, match="unknown hpa_backend 'fortran'; valid choices: python, c"):
        WakeConfig(hpa_backend="fortran")
    with pytest.raises(ValueError, match="WAKE_HPA_MAX_WINDOW = 1024.*hpa_backend='python'"):
        WakeFilter(window_s=20.0, hpa_backend="c")


def test_run_hpa_c_refuses_bad_windows():
    from wake.hpa.c_port import run_hpa_c

    with pytest.raises(ValueError, match="NaN or inf"):
        run_hpa_c(np.r_[np.ones(99), np.nan], CONFIG, taps=TAPS)
    with pytest.raises(ValueError, match="64..500 samples"):
        run_hpa_c(np.ones(10), CONFIG, taps=TAPS)
    with pytest.raises(ValueError, match="full_scale must be finite"):
        run_hpa_c(np.ones(100), CONFIG, taps=TAPS, full_scale=-1.0)


@settings(max_examples=60, deadline=None)
@given(n=st.integers(64, 500), seed=st.integers(0, 2**32 - 1), scale=st.sampled_from([1, 30, 3000, 32767]),
       offset=st.integers(-30000, 30000), rule=st.sampled_from(["paper", "shallow"]))
def test_any_int16_window_gives_a_finite_result(n, seed, scale, offset, rule):
    from wake._rtp import ffi, lib
    from wake.hpa.c_port import hpa_config
    from wake.rtp.fixed import quantize_taps

    rng = np.random.default_rng(seed)
    x = np.clip(offset + scale * rng.standard_normal(n).cumsum() / np.sqrt(n), -32768, 32767).astype(np.int16)
    taps = np.ascontiguousarray(quantize_taps(TAPS), dtype=np.int16)
    h = ffi.new("wake_hpa_t *")
    w0 = np.array([0, 0, 0, 0, 1], dtype=np.float32)
    tc = ffi.from_buffer("int16_t[]", taps)
    assert lib.wake_hpa_init(h, hpa_config(WakeConfig(cutoff_rule=rule, backend="reference")), tc,
                             ffi.from_buffer("float[]", w0)) == lib.WAKE_HPA_OK
    xb = ffi.from_buffer("int16_t[]", x)
    assert lib.wake_hpa_start(h, xb, n, n) == lib.WAKE_HPA_OK
    assert lib.wake_hpa_run(h) == lib.WAKE_HPA_DONE
    r = ffi.new("wake_hpa_result_t *")
    assert lib.wake_hpa_take(h, r) == lib.WAKE_HPA_OK
    w = np.array([r.weights[j] for j in range(5)])
    assert np.isfinite(w).all() and np.abs(w).max() <= 32
    assert 0 <= r.flag <= 4 and 0.5 <= r.cutoff <= 6.0
    assert np.isfinite(r.measurement_noise) and r.measurement_noise > 0 and r.fit_mse >= 0


@pytest.mark.skipif(missing_tools("make", "arm-none-eabi-gcc", "qemu-system-arm") is not None,
                    reason=str(missing_tools("make", "arm-none-eabi-gcc", "qemu-system-arm")))
@pytest.mark.slow
def test_standalone_firmware_on_a_cortex_m4f_under_qemu_equals_the_host_build_bit_for_bit(tmp_path):
    import sys

    if ci_passed("standalone-check"):
        # CI's step built and compared them in csrc/build: its outputs are checked, not made again
        build = CSRC / "build"
        assert (build / "run_host" / "predictions.q15").read_bytes() == \
            (build / "run_qemu" / "predictions.q15").read_bytes()
    else:
        build = tmp_path
        proc = subprocess.run(["make", "-C", str(CSRC), "standalone-check", f"BUILD={build}",
                               f"PYTHON={sys.executable}"], capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
        assert "predictions and weights identical" in proc.stdout
    pred = np.fromfile(build / "run_qemu" / "predictions.q15", dtype="<i2")
    weights = np.fromfile(build / "run_qemu" / "weights.bin", dtype="<i4").reshape(-1, 8)
    assert pred.size == 5000 and np.abs(pred).max() > 0
    assert len(weights) >= 9 and (np.diff(weights[:, 0]) > 0).all()  # an HPA installed every L samples


def _device_results(q, config, taps):
    """The on-device HPA fed sample by sample (NaN-marked samples through wake_hpa_push_missing), each HPA
    run to its end as soon as it starts: the (index, weights) of every result."""
    from wake._rtp import ffi, lib
    from wake.hpa.c_port import hpa_config
    from wake.hpa.prior import prior_weights
    from wake.rtp.fixed import quantize_taps

    h = ffi.new("wake_hpa_t *")
    taps_q = np.ascontiguousarray(quantize_taps(taps), dtype=np.int16)
    start = np.asarray(prior_weights(config, taps), dtype=np.float32)
    assert lib.wake_hpa_init(h, hpa_config(config), ffi.from_buffer("int16_t[]", taps_q),
                             ffi.from_buffer("float[]", start)) == lib.WAKE_HPA_OK
    res = ffi.new("wake_hpa_result_t *")
    out = []
    for v in q:
        st = lib.wake_hpa_push_missing(h) if v is None else lib.wake_hpa_push(h, int(v))
        assert st in (lib.WAKE_HPA_OK, lib.WAKE_HPA_STARTED)
        if st == lib.WAKE_HPA_STARTED:
            assert lib.wake_hpa_run(h) == lib.WAKE_HPA_DONE and lib.wake_hpa_take(h, res) == lib.WAKE_HPA_OK
            out.append((int(res.index), np.array([res.weights[j] for j in range(config.level)])))
    return out, int(h.gap_skipped)


def test_the_device_hpa_follows_the_schedule_around_long_gaps():
    """docs/studies/design.md, "Missing samples": a long gap skips the HPA points inside it and restarts the schedule
    at its end, on the device (wake_hpa_push_missing) as on the host; windows without a short gap agree."""
    s = make_signal(10.0, seed=5, duration=45.0)
    x = s.measurement.copy()
    x[1000:1300] = np.nan                                 # long: the schedule restarts at sample 1300
    x[2750:2790] = np.nan                                 # short: held on the device, interpolated on the host
    x[3200:3500] = np.nan                                 # long, over the point 1300 + 4 L = 3300
    full_scale = 2.0 ** np.ceil(np.log2(np.nanmax(np.abs(x)) * 1.01))
    q = [None if np.isnan(v) else int(np.clip(np.rint(v * 32768 / full_scale), -32768, 32767)) for v in x]
    device, skipped = _device_results(q, CONFIG, TAPS)
    seen = np.array([np.nan if v is None else v * full_scale / 32768 for v in q])
    host = WakeFilter(backend="reference").run(seen).hpa[0]
    assert [i for i, _ in device] == [u.index for u in host]
    assert [u.index for u in host if 1300 < u.index < 4100] == [1500, 1600, 1700, 1800, 2300, 2800,
                                                                3700, 3800, 3900, 4000]
    assert skipped == 1                                   # the point 3300, inside the second long gap
    # the host's schedule object on its own, one to one with the device's feed(): points and skips
    from wake.hpa.schedule import HPASchedule

    schedule = HPASchedule(CONFIG)
    points = [schedule.count for v in seen if schedule.push(v) and schedule.take_window() is not None]
    assert points == [i for i, _ in device] and schedule.gap_skipped == skipped
    for (index, w), u in zip(device, host):
        if index <= 2750 or index >= 3500:                # windows without the short gap
            py, c = u.weights, w
            assert np.max(np.abs(c - py)) <= 0.05 * max(1.0, np.max(np.abs(py))), (index, c, py)
