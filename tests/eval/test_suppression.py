"""Closed-loop suppression (wake.eval.suppression): the actuator's lag, the reduction and the disturbance."""

import numpy as np
import pytest

from wake.eval.strong_tremor import make_strong_tremor
from wake.eval.suppression import Actuator, actuate, suppression, suppression_section
from wake.eval.truth import tremor_truth
from wake.eval.tremor_ahead import aligned


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("order", [1, 2])
def test_the_lag_has_unit_gain_and_delays_a_tremor(fs, order):
    act = Actuator(order=order)
    assert abs(actuate(np.ones(int(fs)), fs, act)[-1] - 1.0) < 1e-3
    t = np.arange(int(4 * fs)) / fs
    out = actuate(np.sin(2 * np.pi * 6 * t), fs, act)
    lag = np.argmax(np.correlate(out[int(fs):], np.sin(2 * np.pi * 6 * t)[int(fs):], "full")) - (t.size - int(fs) - 1)
    assert 0 < lag / fs < 0.03


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
def test_a_perfect_prediction_reduces_most_a_delayed_copy_less_and_zero_nothing(fs, kind):
    s = make_strong_tremor(seed=9, fs=fs, duration=15.0, kind=kind, freq_sd_hz=0.05, amp_sd=0.05, h2=0.0)
    _, T, fc = tremor_truth(s.measurement, fs)
    instant, _ = suppression(T, T, fs, fc, Actuator(tau_ms=1e-3))
    lagged, _ = suppression(T, T, fs, fc)                         # the default 10 ms lag, uncompensated
    w = 2 * np.pi * s.f0 * 0.010
    expected = 100 * (1 - abs(1 - 1 / (1 + 1j * w)) ** 2)        # what a first-order lag leaves at f0
    h = int(0.05 * fs)
    late, _ = suppression(T, aligned(T, h), fs, fc)              # the tremor now, played 50 ms late
    none, dist = suppression(T, np.zeros_like(T), fs, fc)
    assert instant > 99.5 and abs(lagged - expected) < 3.0
    assert late < lagged and none == 0.0 and dist == 0.0
    _, disturbance = suppression(T, T + 0.5 * np.sin(2 * np.pi * 0.3 * np.arange(T.size) / fs), fs, fc)
    assert 0.25 < disturbance < 0.45                             # a slow push shows as voluntary disturbance


def test_the_report_section_and_bad_actuators():
    assert suppression_section({}) == ""
    with pytest.raises(ValueError, match="order must be 1"):
        Actuator(order=3)
    with pytest.raises(ValueError, match="tau_ms"):
        Actuator(tau_ms=-1.0)
    with pytest.raises(ValueError, match="natural frequency"):
        actuate(np.ones(10), 20.0, Actuator(order=2, natural_hz=15.0))
