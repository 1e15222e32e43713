import numpy as np
import pytest
import scipy.linalg
import scipy.signal

from wake.hpa.spectrum import ar_psd, autocorrelation, levinson_durbin, yule_walker


def test_levinson_matches_toeplitz_solve(rng):
    x = rng.normal(size=400)
    r = autocorrelation(x, 10)
    a, sigma2, refl = levinson_durbin(r, 10)
    direct = scipy.linalg.solve_toeplitz(r[:10], -r[1:11])
    np.testing.assert_allclose(a[1:], direct, rtol=1e-9, atol=1e-12)
    # sigma^2 = gamma(0) prod(1 - k_i^2), the paper's MMSE noise variance
    assert sigma2 == pytest.approx(r[0] * np.prod(1 - refl**2), rel=1e-12)
    assert sigma2 == pytest.approx(r[0] + np.dot(a[1:], r[1:11]), rel=1e-9)


def test_yule_walker_recovers_ar2(rng):
    true = np.array([1.0, -1.2, 0.5])
    x = scipy.signal.lfilter([1.0], true, rng.normal(size=20000))
    a, sigma2 = yule_walker(x, 2)
    np.testing.assert_allclose(a, true, atol=0.03)
    assert sigma2 == pytest.approx(1.0, rel=0.05)


def test_psd_peaks_at_tremor(rng):
    t = np.arange(500) / 100.0
    x = 2 * np.sin(2 * np.pi * 0.4 * t) + 0.5 * np.sin(2 * np.pi * 7.0 * t) + 0.05 * rng.normal(size=t.size)
    f, p = ar_psd(x, 100.0, order=17)
    band = (f > 4) & (f < 12)
    assert abs(f[band][np.argmax(p[band])] - 7.0) < 0.3
    assert np.all(p > 0) and np.all(np.isfinite(p))


def test_silent_window_is_finite():
    f, p = ar_psd(np.zeros(200), 100.0, order=5)
    assert np.all(np.isfinite(p))


@pytest.mark.parametrize("bad", [dict(fs=0), dict(fs=-1.0), dict(order=0), dict(order=2.5)])
def test_bad_arguments(bad):
    kw = dict(fs=100.0, order=4)
    kw.update(bad)
    with pytest.raises(ValueError):
        ar_psd(np.ones(50) + np.arange(50), **kw)


def test_order_too_high_for_window():
    with pytest.raises(ValueError, match="AR\\(17\\) fit needs more than 17"):
        ar_psd(np.arange(10.0), 100.0, order=17)


@pytest.mark.parametrize("n, max_lag", [(1, 0), (7, 6), (400, 17), (3001, 40)])
def test_autocorrelation_matches_full_correlation(rng, n, max_lag):
    # Only the first max_lag + 1 lags are computed (O(p L)); they must equal the biased
    # estimate taken from the full O(L^2) correlation.
    x = rng.normal(size=n)
    full = np.correlate(x, x, mode="full")[n - 1 : n + max_lag] / n
    np.testing.assert_allclose(autocorrelation(x, max_lag), full, rtol=1e-12, atol=1e-12)


def test_autocorrelation_rejects_lag_beyond_window():
    with pytest.raises(ValueError, match="max_lag must be below"):
        autocorrelation(np.ones(5), 5)
