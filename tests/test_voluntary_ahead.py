"""The voluntary motion at n + h (issue 32): the HPA's second weight vector w_h and the RTP's w_h' (a + d)."""

import numpy as np
import pytest

from support import NO_CORE, has_c_backend
from wake import WakeConfig, WakeFilter
from wake.eval.synthetic import make_signal
from wake.hpa import fit_weights, run_hpa
from wake.rtp.reference import ReferenceRTP
from wake.target import PredictionTarget
from wake.wavelets import filter_bank_outputs, filter_bank_taps

FS = 100.0


def slow_sine(seconds=20.0, tremor=0.2, seed=0):
    """A slow sinusoid (the voluntary part) plus a 6-Hz tremor and a little noise."""
    t = np.arange(int(seconds * FS)) / FS
    voluntary = np.sin(2 * np.pi * 0.4 * t)
    rng = np.random.default_rng(seed)
    return voluntary + tremor * np.sin(2 * np.pi * 6.0 * t) + 0.01 * rng.standard_normal(t.size), voluntary


def rms(a):
    return float(np.sqrt(np.mean(np.square(a))))


@pytest.mark.parametrize("backend", ["reference", "c"])
def test_at_horizon_1_it_is_the_one_step_voluntary_and_nothing_else_moves(backend):
    if backend == "c" and not has_c_backend():
        pytest.skip(NO_CORE)
    x = make_signal(20.0, seed=4).measurement
    one = WakeFilter(backend=backend).run(x)
    np.testing.assert_array_equal(one.voluntary_ahead, one.voluntary)
    assert all(u.weights_ahead is None for u in one.hpa[0])
    # at h = 5 the one-step outputs stay bit for bit those of horizon 1
    five = WakeFilter(backend=backend, horizon=5).run(x)
    np.testing.assert_array_equal(five.prediction, one.prediction)
    np.testing.assert_array_equal(five.voluntary, one.voluntary)
    np.testing.assert_array_equal([u.weights for u in five.hpa[0]], [u.weights for u in one.hpa[0]])


@pytest.mark.parametrize("h, ratio", [(2, 0.85), (5, 0.8), (10, 0.5)])   # measured: 0.71, 0.70, 0.43
def test_fitting_ahead_beats_holding_the_one_step_prediction_on_a_slow_sinusoid(h, ratio):
    x, truth = slow_sine()
    res = WakeFilter(backend="reference", horizon=h).run(x)
    after = slice(500, None)   # after the 5-s HPA
    held = PredictionTarget(h - 1).voluntary_from(res.voluntary)   # the one-step v(k - h + 1), used for k
    fitted, holding = rms((res.voluntary_ahead - truth)[after]), rms((held - truth)[after])
    assert fitted < ratio * holding, (fitted, holding)
    # and it is a prediction made h samples before: it cannot beat the one-step estimate by much
    assert fitted > 0.5 * rms((res.voluntary - truth)[after])


def test_the_hpa_fits_w_h_with_the_one_step_fit_on_the_pairs_h_samples_ahead():
    x, _ = slow_sine(5.0)
    config = WakeConfig(backend="reference", horizon=5)
    taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    upd = run_hpa(x, config, taps=taps)
    assert upd.weights_ahead is not None and upd.weights_ahead.shape == upd.weights.shape
    # the same rules: recompute the pairs from the window's own voluntary truth (x minus the HPA's tremor truth)
    from wake.hpa.sharp import detrended_highpass

    voluntary_gt = x - detrended_highpass(x, FS, upd.cutoff)
    pairs = PredictionTarget(5).fit_pairs(filter_bank_outputs(x, taps), voluntary_gt, taps.shape[1])
    np.testing.assert_array_equal(upd.weights_ahead, fit_weights(*pairs, config.ridge)[0])
    assert not np.allclose(upd.weights_ahead, upd.weights, atol=1e-3)
    assert run_hpa(x, config.replace(horizon=1), taps=taps).weights_ahead is None


def test_a_short_warm_up_window_without_a_clean_valley_keeps_w_h_too():
    t = np.arange(100) / FS
    x = 0.01 * t + 0.001 * np.random.default_rng(1).standard_normal(t.size)   # 1 s, no tremor peak
    upd = run_hpa(x, WakeConfig(backend="reference", horizon=5))
    assert "weights_kept" in upd.flags and upd.weights_ahead is None


def test_the_reference_rtp_outputs_w_h_dot_the_state_of_its_one_step_prediction():
    taps = filter_bank_taps("sym3", 5, "constant")
    w, w_h = np.full(5, 0.2), np.array([0.1, 0.3, 0.2, 0.25, 0.15])
    x, _ = slow_sine(3.0)
    x[150] = np.nan
    loop = ReferenceRTP(taps, w, 0.01, 1e-4, 1e-3)
    loop.set_weights_ahead(w_h)
    got = []
    for v in x:
        y = loop.step_missing() if np.isnan(v) else loop.step(v)
        state = loop._filter_bank() + loop.correction
        assert y == pytest.approx(float(w @ state), abs=1e-12)
        assert loop.last_voluntary_ahead == pytest.approx(float(w_h @ state), abs=1e-12)
        got.append(loop.last_voluntary_ahead)
    block = ReferenceRTP(taps, w, 0.01, 1e-4, 1e-3)
    block.set_weights_ahead(w_h)
    out = block.run_outputs(x)
    np.testing.assert_array_equal(out[4], got)          # block and sample path bit for bit
    plain = ReferenceRTP(taps, w, 0.01, 1e-4, 1e-3).run(x)
    np.testing.assert_array_equal(out[0], plain)        # w_h does not touch the one-step prediction
    with pytest.raises(ValueError, match="weights_ahead must be 5 finite numbers"):
        block.set_weights_ahead([1.0, np.nan, 0, 0, 0])


@pytest.mark.parametrize("fs, h, backend", [(100.0, 5, "reference"), (1000.0, 50, "reference"), (100.0, 5, "c")])
def test_batch_equals_streaming(fs, h, backend):
    if backend == "c" and not has_c_backend():
        pytest.skip(NO_CORE)
    x = make_signal(12.0, seed=2).measurement
    if fs != FS:
        x = np.interp(np.arange(x.size * 10) / fs, np.arange(x.size) / FS, x)
    x[700:705] = np.nan
    res = WakeFilter(fs=fs, backend=backend, horizon=h).run(x)
    f = WakeFilter(fs=fs, backend=backend, horizon=h)
    raw = []
    for v in x[:2000]:
        f.update(float(v))
        raw.append(f.last_voluntary_ahead)
    pred, ahead = f.update_block_voluntary_ahead(x[2000:])
    raw = np.r_[raw, ahead]
    np.testing.assert_array_equal(PredictionTarget(h).voluntary_from(raw), res.voluntary_ahead)
    np.testing.assert_array_equal(pred, res.prediction[2000:])
    assert rms(res.voluntary_ahead[-500:] - res.voluntary[-500:]) > 0   # it is its own output


@pytest.mark.parametrize("backend", ["reference", "c"])
def test_a_saved_stream_goes_on_with_its_w_h(backend):
    if backend == "c" and not has_c_backend():
        pytest.skip(NO_CORE)
    x = make_signal(14.0, seed=5).measurement
    f = WakeFilter(backend=backend, horizon=5)
    f.update_block(x[:900])
    g = WakeFilter(backend=backend, horizon=5)
    g.set_state(f.get_state())
    np.testing.assert_array_equal(f.update_block_voluntary_ahead(x[900:])[1],
                                  g.update_block_voluntary_ahead(x[900:])[1])


@pytest.mark.parametrize("settings, needs", [(dict(backend="c", hpa_backend="c"), "hpa_backend='python'"),
                                             (dict(backend="reference", hpa_backend="c"), "hpa_backend='python'")])
def test_a_backend_without_w_h_refuses_it_and_names_the_one_that_can(settings, needs):
    if not has_c_backend():
        pytest.skip(NO_CORE)
    x = make_signal(8.0, seed=1).measurement
    f = WakeFilter(horizon=5, **settings)
    res = f.run(x)
    assert res.tremor_ahead is not None       # the tremor ahead is there on every backend
    with pytest.raises(ValueError, match=f"voluntary_ahead at horizon 5 needs {needs}"):
        res.voluntary_ahead
    f.update(1.0)
    with pytest.raises(ValueError, match=needs):
        f.last_voluntary_ahead
    with pytest.raises(ValueError, match=needs):
        f.update_block_voluntary_ahead(x[:10])
    # at horizon 1 it is the one-step voluntary on every backend, the stream's too
    one = WakeFilter(horizon=1, **settings)
    np.testing.assert_array_equal(one.run(x).voluntary_ahead, one.run(x).voluntary)
    assert one.update(1.0) == one.last_voluntary_ahead


@pytest.mark.parametrize("h", [2, 5, 10])
def test_the_c_core_gives_it_as_the_float_reference_does(paper_signals, h):
    """backend='c' with the Python HPA: w_h' (a + d) in fixed point (WAKE_RTP_VOLUNTARY_AHEAD), its NRMSE
    against the voluntary truth at n + h within 1 % relative of the float reference's (the bound
    tests/test_filter_c.py holds the one-step voluntary to)."""
    if not has_c_backend():
        pytest.skip(NO_CORE)
    from wake.eval.metrics import nrmse

    for s in paper_signals[:3]:
        c = WakeFilter(backend="c", horizon=h).run(s.measurement)
        r = WakeFilter(backend="reference", horizon=h).run(s.measurement)
        assert c.backend == "c" and c.full_scale[0] is not None       # the C core ran after the warm-up
        nc, nr = nrmse(s.voluntary, c.voluntary_ahead, 500), nrmse(s.voluntary, r.voluntary_ahead, 500)
        assert abs(nc - nr) <= 0.01 * nr, (nc, nr)
        assert c.saturations[0] == 0 and c.clipped[0] == 0
        # until the switch to the C core (the first HPA) both ran the float reference: bit for bit
        first = c.hpa[0][0].index
        np.testing.assert_array_equal(c.voluntary_ahead[:first], r.voluntary_ahead[:first])
        # and after it the C core runs w_h, not the one-step prediction held
        held = PredictionTarget(h - 1).voluntary_from(c.voluntary)
        assert rms((c.voluntary_ahead - held)[600:]) > 1e-3
