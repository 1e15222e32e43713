import numpy as np
import pytest

from wake.eval.metrics import best_lag, nrmse, offline_ground_truth, prf, snr_out
from wake.eval.synthetic import PAPER_SNR_DB, make_signal, paper_dataset


def test_paper_dataset_snr_and_components(paper_signals):
    assert [round(s.snr_db, 6) for s in paper_signals] == list(PAPER_SNR_DB)
    for s in paper_signals:
        assert s.measurement.shape == (5000,) and s.fs == 100.0
        np.testing.assert_allclose(s.measurement, s.voluntary + s.white + s.tremor)
        assert 0.2 <= s.voluntary_freq <= 0.9


def test_reproducible_and_seeded():
    a, b, c = make_signal(5.0, seed=7), make_signal(5.0, seed=7), make_signal(5.0, seed=8)
    np.testing.assert_array_equal(a.measurement, b.measurement)
    assert not np.array_equal(a.measurement, c.measurement)
    assert np.array_equal(paper_dataset()[2].measurement, paper_dataset()[2].measurement)


def test_spectral_content_of_components():
    s = make_signal(0.0, seed=1)
    f = np.fft.rfftfreq(5000, 0.01)
    T = np.abs(np.fft.rfft(s.tremor)) ** 2
    assert T[(f >= 5.95) & (f <= 14.05)].sum() / T.sum() > 0.999
    W = np.abs(np.fft.rfft(s.white)) ** 2
    assert W[f > 25].sum() / W.sum() > 0.4  # white: spread over the whole band
    assert np.mean(s.tremor**2) == pytest.approx(np.mean(s.white**2), rel=0.05)  # tremor_share = 0.5


def test_make_signal_checks():
    with pytest.raises(ValueError, match="tremor_share"):
        make_signal(1.0, tremor_share=1.5)
    with pytest.raises(ValueError, match="tremor_band"):
        make_signal(1.0, tremor_band=(6.0, 80.0))


def test_metrics_definitions():
    t = np.array([0.0, 1.0, 2.0, 3.0])
    e = np.array([0.0, 1.0, 2.0, 2.0])
    assert nrmse(t, e) == pytest.approx(0.5 / 3)
    assert prf(t, e) == pytest.approx(100 * 1 / 14)
    assert snr_out(t, e) == pytest.approx(10 * np.log10(100 / prf(t, e)))
    assert nrmse(t, e, start=2) == pytest.approx(np.sqrt(0.5) / 1.0)
    with pytest.raises(ValueError, match="constant"):
        nrmse(np.ones(5), np.zeros(5))
    with pytest.raises(ValueError, match="differ in shape"):
        nrmse(np.ones(5), np.zeros(4))


def test_offline_ground_truth_and_lag():
    t = np.arange(1000) / 100.0
    v, tr = np.sin(2 * np.pi * 0.3 * t), 0.3 * np.sin(2 * np.pi * 8 * t)
    gv, gt = offline_ground_truth(v + tr, 100.0, 3.0)
    np.testing.assert_allclose(gt, tr, atol=1e-9)
    np.testing.assert_allclose(gv, v, atol=1e-9)
    assert best_lag(tr, np.roll(tr, 3)) == 3
