"""The per-sample adaptive tremor-ahead predictors of wake.ahead_models (issue 46) and their gated command."""

import numpy as np
import pytest

from wake import WakeConfig, WakeFilter
from wake.ahead import fit_predictor
from wake.ahead_models import ADAPTIVE, NLMSPredictor, RLSPredictor, adaptive_predictor
from wake.eval.ahead_select import command_with
from wake.eval.strong_tremor import make_strong_tremor


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("cls", [NLMSPredictor, RLSPredictor])
def test_each_learns_a_drifting_tremor_from_its_own_past(fs, cls):
    t = np.arange(int(40 * fs)) / fs
    s = np.sin(2 * np.pi * (6.0 * t + 0.05 * t**2))          # 6 -> 10 Hz over 40 s
    h = int(round(0.02 * fs))
    pred = cls(8, horizon=h)
    P = np.array([pred.step(v) for v in s])
    tail = slice(int(30 * fs), s.size - h)
    err = np.sqrt(np.mean((P[tail] - s[tail.start + h:]) ** 2))
    frozen = fit_predictor(s[:int(5 * fs)], s[:int(5 * fs)], h)   # fitted once at the start, never adapted
    F = np.array([np.asarray(frozen) @ s[k - 7:k + 1][::-1] for k in range(tail.start, tail.stop)])
    assert err < 0.15 and err < 0.5 * np.sqrt(np.mean((F - s[tail.start + h:]) ** 2))


def test_install_sets_the_coefficients_and_keeps_the_delay_line():
    pred = NLMSPredictor(4, horizon=2)
    for v in (1.0, 2.0, 3.0):
        pred.step(v)
    pred.install([1.0, 0.0])                                   # shorter: zero-padded
    assert pred.coefficients.tolist() == [1.0, 0.0, 0.0, 0.0]
    assert pred.line[:3].tolist() == [3.0, 2.0, 1.0]
    pred.install(np.arange(6.0))                               # longer: its newest four
    assert pred.coefficients.tolist() == [0.0, 1.0, 2.0, 3.0]


@pytest.mark.parametrize("bad, match", [(dict(taps=0, horizon=2), "taps must be a positive integer"),
                                        (dict(taps=8, horizon=1.5), "horizon must be a positive integer"),
                                        (dict(taps=8, horizon=2, mu=0.0), "mu must lie in")])
def test_bad_settings_are_refused(bad, match):
    with pytest.raises(ValueError, match=match):
        NLMSPredictor(**bad)
    with pytest.raises(ValueError, match="forget must lie in"):
        RLSPredictor(8, 2, forget=1.5)
    with pytest.raises(ValueError, match="nlms8"):
        adaptive_predictor("lms", 2)


@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
@pytest.mark.parametrize("name", ADAPTIVE)
def test_the_gated_command_of_each_helps_on_strong_tremor(kind, name):
    sig = make_strong_tremor(seed=11, duration=25.0, kind=kind)
    cfg = WakeConfig(fs=sig.fs, horizon=5, backend="reference")
    res = WakeFilter(config=cfg).run(sig.measurement)
    P, g, cmd = command_with(sig.measurement, res, cfg, 5, name)
    assert P.shape == g.shape == cmd.shape == sig.measurement.shape
    assert g.min() >= 0.0 and g.max() <= 1.0 and g[:200].max() == 0.0   # shut until the second HPA
    lo = 500
    assert np.sqrt(np.mean((cmd[lo:] - sig.tremor[lo:]) ** 2)) < 0.5 * np.sqrt(np.mean(sig.tremor[lo:] ** 2))


def test_command_with_names_every_predictor_when_refusing_one():
    sig = make_strong_tremor(seed=1, duration=8.0)
    cfg = WakeConfig(fs=sig.fs, horizon=2, backend="reference")
    res = WakeFilter(config=cfg).run(sig.measurement)
    with pytest.raises(ValueError, match="'fir8', 'fir40', 'order-select', 'nlms8', 'rls16'"):
        command_with(sig.measurement, res, cfg, 2, "kalman")
