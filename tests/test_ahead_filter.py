"""The tremor ahead in the library: the HPA's predictor and gate goal, the RTP's step, the filter's outputs."""

import pickle

import numpy as np
import pytest

from support import NO_CORE, has_c_backend
from wake import WakeConfig, WakeFilter
from wake.ahead import MAX_HORIZON, TAPS, AheadStep, fit_predictor, gate_target, held_out_gain
from wake.eval.synthetic import make_signal
from wake.hpa import run_hpa
from wake.hpa.sharp import detrended_highpass
from wake.hpa.cutoff import find_cutoff
from wake.hpa.spectrum import ar_psd, window_order
from wake.rtp.reference import ReferenceRTP
from wake.wavelets import filter_bank_outputs, filter_bank_taps

BACKENDS = ["reference", pytest.param("c", marks=pytest.mark.skipif(not has_c_backend(), reason=NO_CORE))]


@pytest.fixture(scope="module")
def signal():
    return make_signal(7.0, seed=5, duration=16.0).measurement


# -- the HPA -----------------------------------------------------------------------------------------------


def test_run_hpa_fits_the_predictor_of_the_estimate_with_the_weights_it_installs(signal):
    cfg = WakeConfig(horizon=5)
    taps = filter_bank_taps(cfg.wavelet, cfg.level, cfg.mode)
    x = signal[:500]
    before = np.linspace(0.1, 0.3, cfg.level)
    w = run_hpa(x, cfg, taps=taps, previous_weights=before).weights
    assert not np.allclose(w, before)
    # the rule, restated from its parts: y(k) = x(k) - w . a(k-1), k = N .. L-1, with the weights this HPA
    # installs (not those in use before it), against the window truth
    N = cfg.n_taps
    y = x[N:] - filter_bank_outputs(x, taps)[:-1] @ w
    freqs, psd = ar_psd(x, cfg.fs, window_order(x.size, cfg.ar_order))
    cutoff, flag = find_cutoff(freqs, psd, tremor_band=cfg.tremor_band, cutoff_range=cfg.cutoff_range,
                               default_cutoff=cfg.default_cutoff, rule=cfg.cutoff_rule,
                               shallow_max=cfg.shallow_max)
    truth = detrended_highpass(x, cfg.fs, cutoff)[N:]
    previous = fit_predictor(y[:300], truth[:300], 5)          # as if an earlier window had fitted it
    upd = run_hpa(x, cfg, taps=taps, previous_weights=before, previous_ahead=previous, new_samples=100)
    np.testing.assert_allclose(upd.ahead_coefficients, fit_predictor(y, truth, 5), rtol=1e-9, atol=1e-12)
    gain = held_out_gain(y, truth, previous, 5, 100)
    assert upd.ahead_gain == pytest.approx(gain, abs=1e-12)
    assert upd.ahead_goal == pytest.approx(gate_target(gain, flag), abs=1e-12)
    assert upd.ahead_coefficients.shape == (TAPS,) and 0 < upd.ahead_gain <= 1


def test_the_first_hpa_has_nothing_to_score_and_keeps_the_gate_shut(signal):
    upd = run_hpa(signal[:500], WakeConfig(horizon=2))
    assert upd.ahead_gain == 0.0 and upd.ahead_goal == 0.0
    assert np.any(upd.ahead_coefficients != 0)


def test_a_silent_window_shuts_the_gate_and_keeps_the_predictor():
    kept = np.arange(TAPS) / 10.0
    upd = run_hpa(np.zeros(500), WakeConfig(), previous_ahead=kept, new_samples=500)
    assert upd.cutoff_flag == "silent" and upd.ahead_goal == 0.0
    np.testing.assert_array_equal(upd.ahead_coefficients, kept)


@pytest.mark.parametrize("bad", [0, 33, 2.5, "5", True])
def test_the_horizon_is_validated_with_its_range(bad):
    with pytest.raises(ValueError, match=r"horizon must .*\[1, 32\]"):
        WakeConfig(horizon=bad)
    assert MAX_HORIZON == 32 and WakeConfig(horizon=32).horizon == 32


# -- the RTP ---------------------------------------------------------------------------------------------


def _reference():
    return ReferenceRTP(filter_bank_taps("sym3", 5, "constant"), np.full(5, 0.2), 1.0, 0.01, 0.1, fs=100.0)


def test_run_ahead_is_the_loop_of_step_bit_for_bit(signal):
    x = signal[:1200].copy()
    x[300:310] = np.nan
    x[900] = np.nan
    c = np.random.default_rng(2).normal(size=TAPS) * 0.3
    a, b = _reference(), _reference()
    a.set_ahead(c, 0.7)
    b.set_ahead(c, 0.7)
    blocks = [a.run_ahead(x[:600])]
    a.set_ahead(c / 2, 0.2)
    blocks.append(a.run_ahead(x[600:]))
    loop = []
    for k, v in enumerate(x):
        if k == 600:
            b.set_ahead(c / 2, 0.2)
        y = b.step_missing() if np.isnan(v) else b.step(v)
        loop.append((y,) + b.last_ahead)
    np.testing.assert_array_equal(np.array(loop), np.column_stack([np.concatenate(z) for z in zip(*blocks)]))
    # run() is the first of the four, and steps the tremor ahead alike
    c2 = _reference()
    c2.set_ahead(c, 0.7)
    np.testing.assert_array_equal(c2.run(x[:600]), blocks[0][0])
    assert c2.last_ahead == tuple(z[-1] for z in blocks[0][1:])


def test_the_step_follows_the_contract():
    rtp = _reference()
    rtp.set_ahead(np.r_[1.0, np.zeros(TAPS - 1)], 1.0)
    first = rtp.step(2.0)
    assert rtp.last_ahead == (0.0, pytest.approx(1 / 30), 0.0)   # the first sample has no estimate
    rtp.step(3.0)
    assert rtp.last_ahead[0] == 3.0 - first                       # e(n) = m(n) - y(n-1), newest tap
    gate = rtp.last_ahead[1]
    rtp.step_missing()                                            # estimate 0, goal 0
    assert rtp.last_ahead[0] == 0.0 and rtp.ahead.goal == 0.0 and rtp.last_ahead[1] < gate
    rtp.reset()
    assert rtp.last_ahead == (0.0, 0.0, 0.0) and not rtp.ahead.history.any() and rtp.ahead.gate == 0.0


@pytest.mark.parametrize("coefficients, goal, match", [
    (np.zeros(7), 0.5, "8 finite coefficients"), (np.full(8, np.nan), 0.5, "8 finite coefficients"),
    (np.full(8, 9.0), 0.5, r"within \+-8"),
    (np.zeros(8), 1.5, r"goal must be a number in \[0, 1\]"), (np.zeros(8), "x", r"goal must be a number"),
    (np.zeros(8), np.nan, r"goal must be a number in \[0, 1\]")])
def test_set_ahead_refuses_what_it_cannot_run(coefficients, goal, match):
    with pytest.raises(ValueError, match=match):
        _reference().set_ahead(coefficients, goal)


# -- the filter --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", BACKENDS)
def test_streaming_equals_batch_for_the_tremor_ahead(signal, backend):
    x = signal.copy()
    x[700:705] = np.nan
    h = 5
    res = WakeFilter(backend=backend, horizon=h).run(x)
    f = WakeFilter(backend=backend, horizon=h)
    rows = []
    for v in x:
        y = f.update(float(v))
        rows.append((y,) + f.last_ahead)
    rows = np.array(rows)
    g = WakeFilter(backend=backend, horizon=h)
    blocks = [g.update_block_ahead(x[i:i + 333]) for i in range(0, x.size, 333)]
    block = np.column_stack([np.concatenate(z) for z in zip(*blocks)])
    np.testing.assert_array_equal(rows, block)
    np.testing.assert_array_equal(rows[:, 0], res.prediction)
    # the result aligns each to the sample it is for
    for col, name in ((1, "tremor_ahead"), (2, "confidence"), (3, "command")):
        np.testing.assert_array_equal(getattr(res, name)[h:], rows[:-h, col])
        assert not getattr(res, name)[:h].any()
    assert res.horizon == h
    assert res.confidence.max() > 0.3 and ((res.confidence >= 0) & (res.confidence <= 1)).all()
    if backend == "reference":
        np.testing.assert_array_equal(res.command, res.confidence * res.tremor_ahead)
    else:
        # the C core rounds g P to Q23 of its full scale FS, a power of two at most 32 x max|x|
        lsb = 32 * np.nanmax(np.abs(x)) * 2.0**-23
        np.testing.assert_allclose(res.command, res.confidence * res.tremor_ahead, rtol=0, atol=2 * lsb)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_voluntary_output_does_not_depend_on_the_horizon(signal, backend):
    base = WakeFilter(backend=backend).run(signal)
    for h in (2, 5, 10, 32):
        res = WakeFilter(backend=backend, horizon=h).run(signal)
        np.testing.assert_array_equal(res.prediction, base.prediction)
        for u, v in zip(res.hpa[0], base.hpa[0]):
            np.testing.assert_array_equal(u.weights, v.weights)
        assert not np.array_equal(res.tremor_ahead, base.tremor_ahead)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_saved_state_continues_the_tremor_ahead_bit_for_bit(signal, backend):
    f = WakeFilter(backend=backend, horizon=3)
    f.update_block(signal[:1111])
    state = pickle.loads(pickle.dumps(f.get_state()))
    a = f.update_block_ahead(signal[1111:])
    g = WakeFilter(backend=backend, horizon=3)
    g.set_state(state)
    b = g.update_block_ahead(signal[1111:])
    for u, v in zip(a, b):
        np.testing.assert_array_equal(u, v)
    assert a[2].max() > 0   # the gate opened: the state carried something


def test_the_gate_opens_at_the_second_hpa_and_the_goal_is_the_hpas(signal):
    res = WakeFilter(backend="reference", horizon=2).run(signal)
    hpa = res.hpa[0]
    assert hpa[0].ahead_goal == 0.0 and hpa[1].ahead_goal > 0
    # before the second HPA's swap the confidence (aligned h later) is 0
    assert not res.confidence[:hpa[1].applied_at + 1].any()
    assert res.confidence[hpa[1].applied_at + 2] > 0
    # between two HPAs the gate ramps towards the goal, never past it
    step = AheadStep(np.zeros(TAPS), 100.0)
    assert step.alpha == pytest.approx(1 / 30)


@pytest.mark.skipif(not has_c_backend(), reason=NO_CORE)
def test_the_c_core_of_the_adaptive_rtp_follows_the_same_rule():
    from wake.rtp.adaptive import AdaptiveRTP

    taps = filter_bank_taps("sym3", 5, "constant")
    rtp = AdaptiveRTP(taps, np.full(5, 0.2), 1.0, backend="c", full_scale=8.0)   # the C core from sample 1
    assert rtp.on_c
    lsb = 8.0 * 2.0**-15                                    # the estimate's Q15 of the full scale
    rtp.set_ahead(np.r_[1.0, np.zeros(TAPS - 1)], 1.0)
    y = rtp.step(2.0)
    assert rtp.last_ahead[0] == 0.0                        # the first sample has no estimate
    rtp.step(3.0)
    assert abs(rtp.last_ahead[0] - (3.0 - y)) <= lsb        # e(n) = m(n) - y(n-1), y from the C core
    gate = rtp.last_ahead[1]
    assert 0 < gate < 1
    rtp.step(float("nan"))
    assert rtp.last_ahead[0] == 0.0 and rtp.last_ahead[1] < gate
    with pytest.raises(ValueError, match=r"goal must be a number in \[0, 1\]"):
        rtp.set_ahead(np.zeros(TAPS), -0.5)


@pytest.mark.skipif(not has_c_backend(), reason=NO_CORE)
def test_a_fixed_full_scale_stream_equals_its_batch_for_the_tremor_ahead(signal):
    res = WakeFilter(backend="c", full_scale=8.0, horizon=4).run(signal)
    f = WakeFilter(backend="c", full_scale=8.0, horizon=4)
    rows = np.array([(f.update(float(v)),) + f.last_ahead for v in signal])
    np.testing.assert_array_equal(rows[:, 0], res.prediction)
    np.testing.assert_array_equal(rows[:-4, 3], res.command[4:])
    assert res.confidence.max() > 0.3


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_tremor_ahead_at_1khz_runs_at_the_bank_rate_and_holds_over_each_group(backend):
    from scipy.signal import resample_poly

    from wake.eval.metrics import nrmse
    from wake.eval.synthetic import paper_dataset

    s = paper_dataset()[0]
    x, truth = resample_poly(s.measurement, 10, 1), resample_poly(s.tremor, 10, 1)
    res = WakeFilter(fs=1000.0, horizon=50, backend=backend).run(x)
    assert res.horizon == 50 and WakeConfig(fs=1000.0, horizon=50).bank_horizon == 5
    # after 5 s the gated command 50 ms ahead is below sending nothing (0.147 against 0.161 on the set)
    assert nrmse(truth, res.command, start=5000) < 0.97 * nrmse(truth, np.zeros_like(truth), start=5000)
    f = WakeFilter(fs=1000.0, horizon=50, backend=backend)
    rows = np.array([f.last_ahead[2] if f.update(float(v)) is not None else 0.0 for v in x[:2500]])
    np.testing.assert_array_equal(rows[:-50], res.command[50:2500])
    with pytest.raises(ValueError, match=r"\[1, 320\] at 1000 Hz"):
        WakeConfig(fs=1000.0, horizon=321)


@pytest.mark.skipif(not has_c_backend(), reason=NO_CORE)
def test_a_window_clipped_at_the_full_scale_shuts_the_gate_until_the_next_hpa(signal):
    from wake import ClippingWarning

    # a full scale that the tremor peaks cross on far more than GLITCH_SHARE of every window
    peak = float(np.quantile(np.abs(signal), 0.9))
    with pytest.warns(ClippingWarning):
        clipped = WakeFilter(backend="c", full_scale=peak, horizon=4).run(signal)
    wide = WakeFilter(backend="c", full_scale=4 * np.abs(signal).max(), horizon=4).run(signal)
    hpa = clipped.hpa[0]
    assert all("clipping" in u.flags for u in hpa[1:])
    # the HPA itself would open the gate (its goal is its held-out gain), the installation shuts it
    assert any(u.ahead_goal > 0 for u in hpa[1:])
    assert not clipped.confidence.any() and not clipped.command.any()
    # without clipping the same signal opens the gate
    assert not any("clipping" in u.flags for u in wide.hpa[0])
    assert wide.confidence.max() > 0.3
