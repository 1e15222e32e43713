"""The prediction target (wake.target): one definition of which sample a prediction is for."""

import numpy as np

from wake import WakeFilter
from wake.target import TARGET, PredictionTarget


def test_today_every_prediction_is_for_the_next_sample():
    assert TARGET.horizon == 1
    x = np.sin(np.arange(900) / 9.0)
    res = WakeFilter(backend="reference").run(x)
    np.testing.assert_array_equal(res.voluntary[1:], res.prediction[:-1])
    np.testing.assert_array_equal(res.voluntary, TARGET.voluntary_from(res.prediction))


def test_a_longer_horizon_pairs_each_output_with_a_later_sample():
    outputs, voluntary = np.arange(7.0), 100.0 + np.arange(10.0)   # a(k) for k = 3..9 of a 10-sample window
    for h in (1, 2, 3):
        a, v = PredictionTarget(h).fit_pairs(outputs, voluntary, n_taps=4)
        assert a.shape == v.shape == (7 - h,)
        np.testing.assert_array_equal(v - 100.0, a + 3 + h)   # a(k) (k = a + 3) against v(k + h)
    f = np.array([0.5, 2.0])
    np.testing.assert_allclose(PredictionTarget(3).phasor(f, 100.0), TARGET.phasor(f, 100.0) ** 3)
    np.testing.assert_array_equal(PredictionTarget(2).voluntary_from(np.arange(1.0, 5.0)), [0, 0, 1, 2])
