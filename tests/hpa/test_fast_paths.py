"""The HPA path's faster forms against the slow ones they replaced: the same values, not close ones."""

import numpy as np
import pytest

from wake.hpa.cutoff import floor_rule, _analyse
from wake.rtp.full_scale import GLITCH_SHARE, robust_peak
from wake.wavelets import _taps, filter_bank_taps


def _walk_edge(freqs, db, valley, lo, edge_db):
    """The floor rule's low edge as it was found: bin by bin down from the valley."""
    edge = valley
    while edge > 0 and freqs[edge - 1] >= lo and db[edge - 1] <= db[valley] + edge_db:
        edge -= 1
    return edge


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_floor_edge_is_the_bin_the_walk_reaches(fs, rng):
    freqs = np.linspace(0.0, fs / 2, 512)
    settings = dict(cutoff_range=(0.5, 6.0), tremor_band=(2.5, 15.0), default_cutoff=2.0, min_depth_db=3.0,
                    shallow_max=4.0, floor_margin_db=15.0, edge_db=3.0)
    seen = 0
    for _ in range(400):
        # voluntary content, a gap near the noise floor with ripple, a tremor peak, then the floor
        gap = rng.uniform(-60.0, -40.0)
        db = np.where(freqs < rng.uniform(0.5, 2.0), rng.uniform(-10.0, 0.0), gap + rng.normal(0, 2.0, freqs.size))
        db = np.where(np.abs(freqs - rng.uniform(6.0, 12.0)) < 0.6, rng.uniform(-20.0, -5.0), db)
        db = np.where(freqs > 15.0, gap - rng.uniform(0.0, 10.0), db)
        spectrum = _analyse(freqs, 10 ** (db / 10), settings)
        cutoff, flag = floor_rule(spectrum)
        if flag != "floor_valley":
            continue
        seen += 1
        edge = _walk_edge(freqs, spectrum.db, spectrum.valley, 0.5, 3.0)
        assert cutoff == float(freqs[edge])
    assert seen > 50  # the spectra do reach the branch


@pytest.mark.parametrize("n", [1, 2, 99, 100, 101, 500, 501, 5000, 5001])
def test_robust_peak_is_numpys_lower_quantile(n, rng):
    for _ in range(20):
        x = rng.standard_cauchy(n) * 10 ** rng.uniform(-6, 6)
        x[rng.random(n) < 0.05] = np.nan
        finite = np.abs(x[np.isfinite(x)])
        want = float(np.quantile(finite, 1 - GLITCH_SHARE, method="lower")) if finite.size else 0.0
        assert robust_peak(x) == want
    assert robust_peak(np.full(n, np.nan)) == 0.0


@pytest.mark.parametrize("wavelet,level", [("sym3", 5), ("db4", 3), ("haar", 6)])
def test_filter_bank_taps_come_from_a_cache_that_callers_cannot_change(wavelet, level):
    import pywt

    first = filter_bank_taps(wavelet, level)
    assert np.array_equal(first, _taps(pywt.Wavelet(wavelet), level, "constant"))
    first[:] = 0.0  # a caller scribbling on its copy ...
    again = filter_bank_taps(wavelet, level)
    assert np.array_equal(again, _taps(pywt.Wavelet(wavelet), level, "constant"))  # ... changes nothing
    assert again is not filter_bank_taps(wavelet, level)
