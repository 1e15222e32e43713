import numpy as np
import pytest
import pywt

from wake.wavelets import filter_bank_outputs, filter_bank_taps, wavelet_approximations


@pytest.mark.parametrize("wavelet", ["sym3", "db3", "haar", "db5"])
@pytest.mark.parametrize("level", [3, 5, 6])
def test_taps_reproduce_pywavelets_at_the_newest_sample(wavelet, level, rng):
    taps = filter_bank_taps(wavelet, level)
    window = rng.normal(size=2**level)
    direct = wavelet_approximations(window, wavelet, level)[-1]
    np.testing.assert_allclose(taps @ window, direct, atol=1e-12)


def test_taps_are_low_pass_with_unit_dc_gain():
    taps = filter_bank_taps("sym3", 5)
    np.testing.assert_allclose(taps.sum(axis=1), 1.0, atol=1e-12)
    # deeper levels reject an 8 Hz tremor (fs = 100 Hz) more strongly
    n = np.arange(32)
    gains = [abs(np.dot(row[::-1], np.exp(-2j * np.pi * 8 / 100 * n))) for row in taps]
    assert gains[-1] < gains[0]


def test_full_window_approximations_match_waverec(rng):
    x = rng.normal(size=300)
    A = wavelet_approximations(x, "sym3", 4, mode="symmetric")
    c = pywt.wavedec(x, "sym3", mode="symmetric", level=2)
    c = [c[0]] + [np.zeros_like(d) for d in c[1:]]
    np.testing.assert_allclose(A[:, 1], pywt.waverec(c, "sym3", mode="symmetric")[:300])


def test_filter_bank_outputs_align_with_windows(rng):
    taps = filter_bank_taps("sym3", 3)
    x = rng.normal(size=40)
    out = filter_bank_outputs(x, taps)
    assert out.shape == (33, 3)
    np.testing.assert_allclose(out[5], taps @ x[5:13])


def test_errors_name_valid_choices():
    with pytest.raises(ValueError, match="unknown wavelet 'nope'.*sym3"):
        filter_bank_taps("nope", 3)
    with pytest.raises(ValueError, match="level must be from 1 to 6"):
        filter_bank_taps("sym3", 7)
    with pytest.raises(ValueError, match="unknown extension mode"):
        filter_bank_taps("sym3", 3, mode="mirror-ish")
    with pytest.raises(ValueError, match="at least 2\\*\\*5 = 32 samples"):
        wavelet_approximations(np.ones(10), "sym3", 5)
