import numpy as np
import pytest

from wake import WakeFilter
from wake.eval.metrics import nrmse
from wake.eval.synthetic import PAPER_WAKE

REF = dict(backend="reference")


def test_run_equals_streaming_updates(signal10):
    x = signal10.measurement[:1600]
    f = WakeFilter(**REF)
    res = f.run(x)
    stream = [0.0] + [f.update(v) for v in x[:-1]]
    np.testing.assert_array_equal(res.voluntary, stream)  # bit for bit
    assert len(f.hpa_history[0]) == len(res.hpa[0]) - (1 if len(x) % 500 == 0 else 0)
    np.testing.assert_allclose(res.tremor, x - res.voluntary)


@pytest.mark.parametrize("k", [0, 1, 31, 250, 499, 500, 501, 1234])
def test_causality_perturbing_the_future_leaves_the_past_bit_identical(k, signal10, rng):
    x = signal10.measurement[:1500].copy()
    base = WakeFilter(**REF).run(x).voluntary
    y = x.copy()
    y[k:] += rng.normal(size=y.size - k) * 5
    pert = WakeFilter(**REF).run(y).voluntary
    assert np.array_equal(base[: k + 1], pert[: k + 1])
    assert not np.array_equal(base[k + 1 :], pert[k + 1 :])


def test_warmup_is_defined_and_finite(signal10):
    res = WakeFilter(**REF).run(signal10.measurement[:600])
    assert res.warmup == 500
    assert res.voluntary[0] == 0.0  # nothing seen yet
    assert np.all(np.isfinite(res.voluntary))
    # before the first HPA the prior weights predict: smoother than the measurement
    assert np.std(np.diff(res.voluntary[40:200])) < np.std(np.diff(signal10.measurement[40:200]))


def test_hpa_history(signal10):
    res = WakeFilter(**REF).run(signal10.measurement)
    upd = res.hpa[0]
    # warm-up HPA runs at 1, 2, 3 and 4 s on every sample so far, then one every window (5 s)
    assert [u.index for u in upd] == [100, 200, 300, 400] + list(range(500, 5001, 500))
    assert all(0.5 <= u.cutoff <= 6.0 for u in upd)
    assert res.mean_cutoff[0] == pytest.approx(np.mean([u.cutoff for u in upd]))


def test_channels_are_independent(signal10, rng):
    a = signal10.measurement[:1200]
    b = rng.normal(size=1200)
    both = WakeFilter(**REF).run(np.column_stack([a, b]))
    assert both.voluntary.shape == (1200, 2)
    np.testing.assert_array_equal(both.voluntary[:, 0], WakeFilter(**REF).run(a).voluntary)
    np.testing.assert_array_equal(both.voluntary[:, 1], WakeFilter(**REF).run(b).voluntary)


def test_integer_and_float32_input(signal10):
    x = signal10.measurement[:1000]
    ints = np.round(x * 1000).astype(np.int32)
    res_i = WakeFilter(**REF).run(ints)
    res_f = WakeFilter(**REF).run(ints.astype(float))
    np.testing.assert_array_equal(res_i.voluntary, res_f.voluntary)
    res32 = WakeFilter(**REF).run(x.astype(np.float32))
    # float32 in, float32 out (computed in float64, rounded once at the end)
    assert res32.voluntary.dtype == np.float32 and np.all(np.isfinite(res32.voluntary))
    np.testing.assert_allclose(res32.voluntary, WakeFilter(**REF).run(x.astype(np.float32).astype(float)).voluntary,
                               rtol=1e-6, atol=1e-6)


def test_accuracy_on_the_paper_synthetic_set(paper_signals):
    """The README's claim: at or below the paper's WAKE NRMSE on every signal,
    and at least 25 % below it on average (warm-up excluded)."""
    ours = np.array([nrmse(s.voluntary, WakeFilter(**REF).run(s.measurement).voluntary, 500)
                     for s in paper_signals])
    paper = np.array(PAPER_WAKE["nrmse"])
    assert np.all(ours <= paper)
    assert ours.mean() <= 0.75 * paper.mean()


def test_reset_restarts_the_stream(signal10):
    f = WakeFilter(**REF)
    first = [f.update(v) for v in signal10.measurement[:700]]
    f.reset()
    again = [f.update(v) for v in signal10.measurement[:700]]
    assert first == again


def test_streaming_several_channels():
    f = WakeFilter(**REF)
    out = f.update([1.0, 2.0])
    assert out.shape == (2,)
    with pytest.raises(ValueError, match="streams 2 channel"):
        f.update([1.0, 2.0, 3.0])


@pytest.mark.parametrize("x, match", [
    (np.r_[np.ones(600), np.inf], "only NaN is accepted as a missing-sample marker"),
    (np.ones(499), "at least one HPA window of 500 samples"),
    (np.ones((3, 5000)), "shape \\(3, 5000\\): if its rows are channels, pass x.T"),
    (np.ones((600, 2, 2)), "shape \\(n,\\) or \\(n, channels\\)"),
    (np.array([], dtype=float), "empty"),
    (np.array(["a"] * 600), "real numbers"),
    (np.ones(600, dtype=complex), "real numbers"),
    (3.0, "scalar"),
])
def test_bad_recordings(x, match):
    with pytest.raises(ValueError, match=match):
        WakeFilter(**REF).run(x)


@pytest.mark.parametrize("kwargs, match", [
    (dict(fs=0), "fs must lie in \\(0, 100000\\]"),
    (dict(fs=-100.0), "fs must lie in"),
    (dict(fs=float("nan")), "fs must lie in"),
    (dict(fs=1e308), "fs must lie in"),
    (dict(full_scale=1e200), "full_scale must lie in"),
    (dict(headroom=1e300), "headroom must lie in"),
    (dict(wavelet="morl"), "unknown wavelet 'morl'"),
    (dict(level=9), "level must be from 1 to 6"),
    (dict(level=7, backend="c"), "level must be from 1 to 6"),
    (dict(level=6, window_s=1.0), "need at least 128"),
    (dict(window_s=0.3), "lengthen window_s"),
    (dict(backend="gpu"), "valid choices: c, reference"),
    (dict(fit="bfgs"), "valid choices: causal, paper"),
    (dict(process_noise_ratio=-1), "process_noise_ratio must lie in"),
    (dict(tremor_band=(8, 4)), "tremor_band"),
    (dict(cutoff_range=(1.0,)), "cutoff_range must be a pair"),
    (dict(default_cutoff=9.0), "default_cutoff must lie in cutoff_range"),
    (dict(headroom=0.5), "headroom must lie in \\[1, 10000\\]"),
    (dict(ar_order=0), "ar_order"),
])
def test_bad_configuration(kwargs, match):
    kw = dict(REF)
    kw.update(kwargs)
    with pytest.raises(ValueError, match=match):
        WakeFilter(**kw)


def test_update_refuses_inf_and_empty():
    f = WakeFilter(**REF)
    with pytest.raises(ValueError, match="pass NaN for a missing sample"):
        f.update(np.inf)
    with pytest.raises(ValueError, match="empty"):
        f.update([])


def test_a_rate_outside_the_supported_range_warns_naming_it():
    import warnings

    from wake.filter import RateWarning

    for fs in (40.0, 2000.0):
        with pytest.warns(RateWarning, match="outside the supported 50-1000 Hz"):
            WakeFilter(fs=fs, backend="reference", tremor_band=(2.5, 15.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for fs in (50.0, 100.0, 200.0, 250.0, 500.0, 1000.0):
            WakeFilter(fs=fs, backend="reference")
