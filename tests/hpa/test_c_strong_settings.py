"""The C HPA's ridge_scale="centred" and gate_cutoff (issue 46) against the Python HPA, the reference.

The tolerances are those of the C-vs-Python HPA tests: per window the same cut-off flag, ``f_d`` within one
grid step, R within 2e-3 and the fit within 5 % (tests/hpa/test_c_port.py; here the fit's residual of each
side's weights computed in float64 on the same rows, so that the C HPA's own e_L is checked beside it); the
tremor ahead's coefficients within 5e-3 of the largest, the gate's goal within 2e-3 and the window's command
within 1 % NRMSE (tests/hpa/test_c_ahead.py); the whole filter within 1 % NRMSE
(docs/studies/hpa_c.md).  Per window at 100 and 200 Hz (one bank rate each, windows of 500 and 1,000
samples: the Hz values scale), the filter at 100 and 1000 Hz; gyroscope and accelerometer with gravity.
"""

import warnings

import numpy as np
import pytest
from support import NO_PADS, NO_PDKIT, pads_dir, pdkit_dir

from wake import WakeConfig, WakeFilter
from wake.ahead import NO_TREMOR_FLAGS
from wake.eval.strong_tremor import make_strong_tremor
from wake.hpa import run_hpa
from wake.hpa.sharp import detrended_highpass
from wake.rtp import c_backend_available
from wake.target import TARGET
from wake.wavelets import filter_bank_outputs, filter_bank_taps

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")

TAPS = filter_bank_taps("sym3", 5)
N = 2**5
FIT_TOL, R_TOL = 1.05, 2e-3
COEF_TOL, GOAL_TOL, COMMAND_NRMSE = 5e-3, 2e-3, 0.01


def config(fs, **settings):
    """The settings at ``fs`` with the bank at ``fs`` (no decimation): a window of 5 s, 500 or 1,000 samples."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # 200 Hz without decimation is off the tuned rates: deliberate here
        return WakeConfig(fs=fs, decimation=1, backend="reference", **settings)


def signal(kind, fs, seconds=20.0, seed=1):
    return make_strong_tremor(seed=seed, fs=fs, duration=seconds, kind=kind).measurement


def residual(x, cfg, cutoff, weights):
    """e_L of ``weights`` in float64 on the fit rows of window ``x`` (the truth at ``cutoff``)."""
    voluntary = x - detrended_highpass(x, cfg.fs, cutoff)
    A, y = TARGET.fit_pairs(filter_bank_outputs(x, TAPS), voluntary, N)
    return float(np.sqrt(np.mean((A @ weights - y) ** 2)))


def check_fit(x, cfg):
    """One window through both HPAs; the C fit's residual and the Python one's."""
    from wake.hpa.c_port import quantize_window, run_hpa_c, window_full_scale

    full = window_full_scale(x)
    seen = quantize_window(x, full) * (full / 32768)
    py, c = run_hpa(seen, cfg, taps=TAPS), run_hpa_c(x, cfg, taps=TAPS)
    assert c.cutoff_flag == py.cutoff_flag
    assert abs(c.cutoff - py.cutoff) <= cfg.fs / 1022
    assert c.measurement_noise == pytest.approx(py.measurement_noise, rel=R_TOL)
    r_py, r_c = residual(seen, cfg, py.cutoff, py.weights), residual(seen, cfg, py.cutoff, c.weights)
    floor = 1e-6 * np.std(x)
    assert r_c <= FIT_TOL * r_py + floor
    assert c.fit_error == pytest.approx(r_c, rel=0.05, abs=floor)   # the C HPA's own e_L of its weights
    assert np.isfinite(c.weights).all() and np.abs(c.weights).max() <= 32
    return r_py, r_c


@pytest.mark.parametrize("kind", ["accelerometer", "gyroscope"])
@pytest.mark.parametrize("fs", [100.0, 200.0])
def test_centred_ridge_fit_agrees_with_the_python_hpa(fs, kind):
    x, L = signal(kind, fs), int(5 * fs)
    gains = []
    for k in range(1, 4):
        w = x[k * L:(k + 1) * L]
        gram = check_fit(w, config(fs))
        centred = check_fit(w, config(fs, ridge_scale="centred"))
        gains.append((gram, centred))
    if kind == "accelerometer" and fs == 100.0:
        # gravity inflates the Gram ridge: the centred one fits better in both HPAs
        assert all(c[0] < 0.9 * g[0] and c[1] < 0.9 * g[1] for g, c in gains)


def test_centred_ridge_on_a_large_offset_and_a_flat_window_is_at_single_precisions_limit():
    """An offset 50 times a slow motion, and an offset with almost no motion (the centred trace floored at
    1e-6 of the Gram's): the centred ridge leaves the nearly collinear system to the precision of its sums, where
    the C HPA's float32 Gram resolves less than the Python HPA's float64 (docs/studies/hpa_c.md, "The ridge
    relative to the centred Gram").  Its fit is still better than the Gram ridge's in both HPAs, and within
    2.7x of the Python HPA's."""
    from wake.hpa.c_port import quantize_window, run_hpa_c, window_full_scale

    t = np.arange(500) / 100.0
    cases = (50.0 + np.sin(2 * np.pi * 0.4 * t) + 0.05 * np.sin(2 * np.pi * 6 * t),
             9.81 + 1e-3 * np.random.default_rng(0).standard_normal(500))
    for x in cases:
        full = window_full_scale(x)
        seen = quantize_window(x, full) * (full / 32768)
        fits = {}
        for rule in ("gram", "centred"):
            cfg = config(100.0, ridge_scale=rule)
            py, c = run_hpa(seen, cfg, taps=TAPS), run_hpa_c(x, cfg, taps=TAPS)
            assert c.cutoff_flag == py.cutoff_flag
            fits[rule] = [residual(seen, cfg, py.cutoff, u.weights) for u in (py, c)]
        assert fits["centred"][0] < fits["gram"][0] and fits["centred"][1] < fits["gram"][1]
        assert fits["centred"][1] <= 2.7 * fits["centred"][0]


def voluntary_rhythm(fs, seconds=20.0):
    """tests/test_gate_cutoff.py's pronation-supination-like 3.1-Hz voluntary rhythm."""
    t = np.arange(int(seconds * fs)) / fs
    phase = 2 * np.pi * 3.1 * t + 0.3 * np.sin(2 * np.pi * 0.1 * t)
    noise = 0.01 * np.random.default_rng(0).standard_normal(t.size)
    return np.sin(phase) + 0.3 * np.sin(2 * phase + 1.0) + 0.5 * np.sin(2 * np.pi * 0.3 * t) + noise


def check_ahead(stream, cfg, horizon):
    """run_ahead_c over consecutive windows against wake.ahead on each window's estimate, with the gate scored
    against wake.hpa.run.gate_truth (wake.hpa.c_ahead.ahead_agreement); the goals."""
    from wake.hpa.c_ahead import ahead_agreement

    full = 2.0 ** np.ceil(np.log2(np.max(np.abs(stream)) * 1.01))
    rows = ahead_agreement(stream, cfg, taps=TAPS, horizon=horizon, full_scale=full)
    for r in rows:
        c, ref = r["coefficients"], r["reference"]
        assert np.max(np.abs(c - ref)) <= COEF_TOL * max(1.0, np.max(np.abs(ref)))
        assert r["goal"] == pytest.approx(r["reference_goal"], abs=GOAL_TOL)
        if r["flag"] in NO_TREMOR_FLAGS:
            assert r["goal"] == 0.0
        assert r["command_zero"] if r["command_nrmse"] is None else r["command_nrmse"] <= COMMAND_NRMSE
    return [r["goal"] for r in rows[1:]]


@pytest.mark.parametrize("fs", [100.0, 200.0])
def test_gate_cutoff_gate_agrees_with_the_python_rule_and_shuts_on_a_voluntary_rhythm(fs):
    h = int(round(0.02 * fs))
    L = int(5 * fs)
    rhythm = voluntary_rhythm(fs)[:4 * L]
    today = check_ahead(rhythm, config(fs), h)
    gated = check_ahead(rhythm, config(fs, gate_cutoff=4.0), h)
    assert min(today) > 0.9 and max(gated) < 0.3     # the 3.1-Hz rhythm no longer opens the gate
    for kind in ("accelerometer", "gyroscope"):
        tremor = make_strong_tremor(seed=3, fs=fs, duration=20.0, f0=6.0, kind=kind).measurement[:4 * L]
        goals = [check_ahead(tremor, config(fs, gate_cutoff=g), h) for g in (None, 4.0)]
        assert min(goals[1]) > 0.8                    # a 6-Hz tremor keeps it open
        assert np.allclose(goals[0], goals[1], atol=0.05)


@pytest.mark.parametrize("settings", [dict(ridge_scale="centred"), dict(gate_cutoff=4.0),
                                      dict(ridge_scale="centred", gate_cutoff=4.0)])
@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_filter_with_the_c_hpa_runs_each_setting_as_with_the_python_hpa(fs, settings):
    """One-step tremor estimate and the gated command at 20 ms, C HPA against Python HPA, within 1 % NRMSE
    (of the truth's range, after 5 s), on a gyroscope and on an accelerometer with gravity."""
    lo = int(5 * fs)
    for kind in ("accelerometer", "gyroscope"):
        sig = make_strong_tremor(seed=1, fs=fs, duration=20.0, kind=kind)
        runs = {hb: WakeFilter(fs=fs, backend="c", hpa_backend=hb, horizon=int(0.02 * fs), **settings)
                .run(sig.measurement) for hb in ("python", "c")}
        span = np.ptp(sig.tremor[lo:])
        for field in ("voluntary", "command"):
            ref, got = getattr(runs["python"], field)[lo:], getattr(runs["c"], field)[lo:]
            assert np.sqrt(np.mean((got - ref) ** 2)) <= COMMAND_NRMSE * span, (kind, field)
        assert runs["c"].confidence[lo:].max() > 0.5                      # the gate opens on the C HPA's goal


def recordings_axes():
    """(name, samples, fs) of real axes: PADS accelerometer and gyroscope (smartwatch, 100 Hz, two windows
    each), pdkit's tremor axes (smartphone accelerometer with gravity)."""
    out = []
    folder = pads_dir()
    if folder is not None:
        from wake.eval.datasets import load_pads_folder

        for rec in load_pads_folder(folder)[:3]:
            for c, kind in ((0, "acc"), (3, "gyro")):
                out.append((f"PADS {rec.name} {kind}", np.asarray(rec.samples[:, c], dtype=float), rec.fs))
    folder = pdkit_dir()
    if folder is not None:
        from wake.eval.pdkit import load_pdkit_folder, tremor_axes

        for rec, c in tremor_axes(load_pdkit_folder(folder))[:4]:
            out.append((f"pdkit {rec.recording.name} {c}", rec.recording.samples[:, c].astype(float), rec.recording.fs))
    return out


def test_each_setting_agrees_on_real_recordings():
    if pads_dir() is None:
        pytest.skip(NO_PADS)
    if pdkit_dir() is None:
        pytest.skip(NO_PDKIT)
    axes = recordings_axes()
    assert any(a[0].startswith("PADS") for a in axes) and any(a[0].startswith("pdkit") for a in axes)
    for name, x, fs in axes:
        L = int(5 * fs)
        windows = min(4, x.size // L)
        for k in range(windows):
            check_fit(x[k * L:(k + 1) * L], config(fs, ridge_scale="centred"))
        check_ahead(x[:windows * L], config(fs, gate_cutoff=4.0), 2)


def test_the_c_hpa_refuses_bad_settings_and_python_names_the_valid_range():
    from wake.hpa.c_port import _core, hpa_config

    ffi, lib = _core()
    taps = np.zeros((5, N), dtype=np.int16)
    weights = np.zeros(5, dtype=np.float32)
    good = hpa_config(WakeConfig(gate_cutoff=4.0, ridge_scale="centred"))
    h = ffi.new("wake_hpa_t *")
    def init(c):
        return lib.wake_hpa_init(h, c, ffi.from_buffer("int16_t[]", taps), ffi.from_buffer("float[]", weights))
    assert init(good) == lib.WAKE_HPA_OK
    for field, bad in (("gate_cutoff", -1.0), ("gate_cutoff", float("nan")), ("gate_cutoff", 50.0),
                       ("gate_cutoff", float("inf")), ("ridge_scale", 2)):
        c = ffi.new("wake_hpa_config_t *", good[0])
        setattr(c, field, bad)
        assert init(c) == lib.WAKE_HPA_E_CONFIG, (field, bad)
    for bad, match in ((-1.0, r"gate_cutoff must lie in \(0, "), (float("nan"), "gate_cutoff"),
                       (50.0, "below fs/2 = 50 Hz"), (500.0, "below fs/2 = 500 Hz")):
        fs = 1000.0 if bad == 500.0 else 100.0
        with pytest.raises(ValueError, match=match):
            WakeConfig(fs=fs, gate_cutoff=bad, hpa_backend="c")
    with pytest.raises(ValueError, match="valid choices: gram, centred"):
        WakeConfig(ridge_scale="mean", hpa_backend="c")
    # the C HPA takes both settings (the configuration no longer refuses them)
    assert WakeConfig(ridge_scale="centred", gate_cutoff=4.0, hpa_backend="c").gate_cutoff == 4.0


def test_set_previous_ahead_checks_what_it_installs():
    from wake.hpa.c_port import _core, hpa_config, run_hpa_c

    ffi, lib = _core()
    taps = np.zeros((5, N), dtype=np.int16)
    weights = np.zeros(5, dtype=np.float32)
    h = ffi.new("wake_hpa_t *")
    assert lib.wake_hpa_init(h, hpa_config(WakeConfig()), ffi.from_buffer("int16_t[]", taps),
                             ffi.from_buffer("float[]", weights)) == lib.WAKE_HPA_OK
    c = np.full(8, 0.5, dtype=np.float32)
    assert lib.wake_hpa_set_previous_ahead(h, ffi.from_buffer("float[]", c), 123) == lib.WAKE_HPA_OK
    assert list(h.ahead.prev) == [0.5] * 8 and h.ahead.prev_index == 123 and h.ahead.has_prev == 1
    for bad in (np.nan, 8.5, -np.inf):
        d = c.copy()
        d[3] = bad
        assert lib.wake_hpa_set_previous_ahead(h, ffi.from_buffer("float[]", d), 7) == lib.WAKE_HPA_E_CONFIG
    assert h.ahead.prev_index == 123                                        # a refusal changes nothing
    assert lib.wake_hpa_set_previous_ahead(h, ffi.NULL, 7) == lib.WAKE_HPA_E_NULL
    assert lib.wake_hpa_set_previous_ahead(ffi.NULL, ffi.from_buffer("float[]", c), 7) == lib.WAKE_HPA_E_NULL
    window = np.zeros(500, dtype=np.int16)
    assert lib.wake_hpa_start(h, ffi.from_buffer("int16_t[]", window), 500, 500) == lib.WAKE_HPA_OK
    assert lib.wake_hpa_set_previous_ahead(h, ffi.from_buffer("float[]", c), 7) == lib.WAKE_HPA_E_BUSY
    x = signal("gyroscope", 100.0)[:500]
    with pytest.raises(ValueError, match=r"8 finite coefficients within \[-8, 8\]"):
        run_hpa_c(x, WakeConfig(), taps=TAPS, index=1000, previous_ahead=np.full(8, 9.0), new_samples=500)
