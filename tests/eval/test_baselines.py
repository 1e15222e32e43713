"""BMFLC, E-BMFLC and WFLC: causality, tracking, step-size bound, input checks."""

import numpy as np
import pytest

from wake.eval.baselines import BMFLC, EBMFLC, WFLC

FS = 100.0


def _amplitude(y):
    """Amplitude of a (near) sinusoid from its RMS."""
    return float(np.sqrt(2 * np.mean(np.square(y))))


def _sine(freq, amp, seconds, phase=0.4, offset=0.0):
    t = np.arange(int(seconds * FS)) / FS
    return amp * np.sin(2 * np.pi * freq * t + phase) + offset


ALL = [BMFLC(), EBMFLC(), WFLC()]


@pytest.mark.parametrize("method", ALL, ids=lambda m: m.name)
def test_causal_one_step_ahead(method, rng):
    x = rng.standard_normal((700, 2)) + np.sin(np.arange(700) / 20.0)[:, None]
    k = 400
    y = x.copy()
    y[k:] += rng.standard_normal(y[k:].shape) * 3.0
    a = method.run(x)
    b = method.run(y)
    # voluntary[k] may depend on x[:k] only: identical up to and including k.
    assert np.array_equal(a.voluntary[: k + 1], b.voluntary[: k + 1])
    # ... and the perturbation does reach the later predictions (the check is not vacuous).
    assert not np.array_equal(a.voluntary[k + 1 :], b.voluntary[k + 1 :])
    assert np.array_equal(a.tremor, x - a.voluntary)


@pytest.mark.parametrize("method", ALL, ids=lambda m: m.name)
def test_extrapolation_leaves_the_one_step_outputs_alone_and_is_causal(method, rng):
    x = rng.standard_normal((500, 2)) + np.sin(np.arange(500) / 3.0)[:, None]
    plain, ahead = method.run(x), method.run(x, horizons=(4, 1, 4))
    for name in ("voluntary", "tremor", "model_tremor"):
        assert np.array_equal(getattr(plain, name), getattr(ahead, name))
    assert sorted(ahead.ahead) == [1, 4] and plain.ahead == {}
    # the one-sample extrapolation after sample k is the model's own one-step tremor at k + 1 ...
    np.testing.assert_allclose(ahead.ahead[1][:-1], plain.model_tremor[1:], atol=1e-12)
    # ... and what is said at k depends on x[:k + 1] only
    k, y = 300, x.copy()
    y[k + 1:] += 5.0
    assert np.array_equal(method.run(y, horizons=(4,)).ahead[4][:k + 1], ahead.ahead[4][:k + 1])
    assert ahead.ahead[4].shape == x.shape and method.run(x[:, 0], horizons=(2,)).ahead[2].shape == (500,)


@pytest.mark.parametrize("bad", [0, -1, 1.5, "2"])
def test_extrapolation_horizon_must_be_a_positive_integer(bad):
    with pytest.raises((ValueError, TypeError), match="horizon"):
        BMFLC().run(np.zeros(50), horizons=(bad,))


@pytest.mark.parametrize("method", ALL, ids=lambda m: m.name)
def test_shapes_and_channels_independent(method, rng):
    x = rng.standard_normal((300, 3))
    res = method.run(x)
    assert res.voluntary.shape == x.shape and res.tremor.shape == x.shape
    single = method.run(x[:, 1])
    assert single.voluntary.shape == (300,)
    np.testing.assert_allclose(single.voluntary, res.voluntary[:, 1], rtol=1e-9, atol=1e-12)


def test_bmflc_tracks_tremor_amplitude():
    # 9 Hz lies on the bank (6..14 Hz); after 60 s the bank output holds the
    # sinusoid within 2 % and the bias (voluntary) stays at the offset.
    x = _sine(9.0, 1.5, 60.0, offset=0.3)
    res = BMFLC(df=0.2, mu=0.01, mu_bias=0.1).run(x)
    tail = slice(-300, None)
    assert _amplitude(res.model_tremor[tail]) == pytest.approx(1.5, rel=0.02)
    assert np.mean(res.voluntary[tail]) == pytest.approx(0.3, abs=0.02)


def test_ebmflc_no_steady_state_amplitude_bias():
    # A constant-amplitude sinusoid on a bin, plus an offset: with the
    # least-squares memory the tracked amplitude is unbiased (a leaky-LMS
    # forgetting factor would shrink it to mu/(mu + 1 - rho) of the truth).
    m = EBMFLC(f_max=20.0, df=0.5, f_cut=2.0, memory_s=2.0, alpha=0.05, ridge=1e-3)
    x = _sine(7.0, 1.5, 20.0, offset=0.5)
    res = m.run(x)
    tail = slice(-500, None)
    assert _amplitude(res.model_tremor[tail]) == pytest.approx(1.5, rel=0.01)
    assert np.mean(res.voluntary[tail]) == pytest.approx(0.5, abs=0.01)
    # The leaky form's bias for comparison: it would fail the assertion above.
    mu = 0.01
    assert mu / (mu + 1 - m.rho) < 0.99


def test_ebmflc_splits_voluntary_and_tremor_bins():
    x = _sine(0.5, 1.0, 20.0) + _sine(8.0, 0.4, 20.0, phase=1.0)
    m = EBMFLC(f_cut=2.0)
    res = m.run(x)
    tail = slice(-500, None)
    np.testing.assert_allclose(res.voluntary[tail], _sine(0.5, 1.0, 20.0)[tail], atol=0.02)
    np.testing.assert_allclose(res.model_tremor[tail], _sine(8.0, 0.4, 20.0, phase=1.0)[tail], atol=0.02)


def test_wflc_converges_to_frequency_and_amplitude():
    x = _sine(5.3, 1.0, 20.0, offset=0.3)
    res = WFLC(mu=0.01, mu0=5e-4, f0=8.0).run(x)
    tail = slice(-500, None)
    assert np.mean(res.frequency[tail]) == pytest.approx(5.3, abs=0.05)
    assert res.frequency[0] == pytest.approx(8.0)
    assert _amplitude(res.model_tremor[tail]) == pytest.approx(1.0, rel=0.05)


def test_wflc_frequency_step_is_scale_free():
    x = _sine(5.3, 1.0, 10.0)
    a = WFLC(mu0=5e-4).run(x).frequency
    b = WFLC(mu0=5e-4).run(1000.0 * x).frequency
    np.testing.assert_allclose(a, b, rtol=1e-9)


def test_wflc_with_frozen_frequency_is_an_flc():
    # mu0 = 0 freezes the frequency: the model is a plain FLC at f0.
    x = _sine(6.0, 1.0, 10.0)
    res = WFLC(mu0=0.0, f0=6.0).run(x)
    assert np.all(res.frequency == 6.0)
    assert _amplitude(res.model_tremor[-300:]) == pytest.approx(1.0, rel=0.01)


def test_lms_bound_is_the_stability_limit(rng):
    x = rng.standard_normal(3000)
    m = BMFLC(df=1.0, mu=0.1, mu_bias=0.05)  # M = 9 pairs: M*mu + mu_bias = 0.95 < 1
    ok = m.run(x)
    assert np.all(np.isfinite(ok.voluntary)) and np.max(np.abs(ok.tremor)) < 100
    # Past the bound (bypassing the constructor check) the same LMS diverges.
    m.mu = 0.12  # 9*0.12 + 0.05 = 1.13
    with np.errstate(over="ignore", invalid="ignore"):
        bad = m.run(x)
    diverged = (~np.isfinite(bad.tremor)).any() or np.max(np.abs(bad.tremor)) > 1e6
    assert diverged


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: BMFLC(df=0.2, mu=0.05, mu_bias=0.1), r"0 < mu < 0\.02195"),  # 41 pairs
        (lambda: BMFLC(mu=0.0), "mu must be"),
        (lambda: BMFLC(mu_bias=1.0), "mu_bias itself"),
        (lambda: BMFLC(band=(14.0, 6.0)), "band"),
        (lambda: BMFLC(band=(6.0, 60.0)), "fs/2"),
        (lambda: BMFLC(df=-1), "df"),
        (lambda: EBMFLC(alpha=1.0), "alpha"),
        (lambda: EBMFLC(f_cut=25.0), "f_cut"),
        (lambda: EBMFLC(f_max=50.0), "f_max"),
        (lambda: EBMFLC(memory_s=0.001), "memory_s"),
        (lambda: EBMFLC(ridge=-1.0), "ridge"),
        (lambda: WFLC(mu=0.95, mu_bias=0.1), "stability range"),
        (lambda: WFLC(f0=20.0), "f0"),
        (lambda: WFLC(n_harmonics=4, mu=0.01), "harmonic"),
        (lambda: WFLC(beta=2.0), "beta"),
        (lambda: WFLC(fs="100"), "fs"),
    ],
)
def test_bad_parameters_raise(make, match):
    with pytest.raises(ValueError, match=match):
        make()


@pytest.mark.parametrize("method", ALL, ids=lambda m: m.name)
def test_bad_input_raises(method):
    with pytest.raises(ValueError, match="non-finite"):
        method.run(np.array([0.0, np.nan, 1.0]))
    with pytest.raises(ValueError, match="shape"):
        method.run(np.zeros((4, 2, 2)))
    with pytest.raises(ValueError, match="empty"):
        method.run(np.zeros(0))
