"""The selectable tremor-ahead predictors (wake.ahead_models.fit_model) run as the filter runs its own
(wake.eval.ahead_select): "fir8" reproduces the filter's command, the others are scored against the
hindsight 40-tap limit on the strong synthetic set."""

import numpy as np
import pytest

from wake import WakeConfig, WakeFilter
from wake.ahead import horizon_from_ms
from wake.ahead_models import ORDERS, PREDICTORS, fit_model, fit_selected
from wake.eval.ahead_select import command_with, wiener_limit
from wake.eval.strong_tremor import make_strong_tremor
from wake.eval.warmup import slice_nrmse


@pytest.mark.parametrize("fs", [100.0, 128.0])
@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
def test_fir8_reproduces_the_filters_command(fs, kind):
    s = make_strong_tremor(seed=11, fs=fs, duration=12.0, kind=kind)
    h = horizon_from_ms(20, fs)
    cfg = WakeConfig(fs=fs, horizon=h, backend="reference")
    res = WakeFilter(config=cfg).run(s.measurement)
    P, g, cmd = command_with(s.measurement, res, cfg, h, "fir8")
    assert np.allclose(cmd, res.command, atol=1e-9 * np.abs(res.command).max())
    assert np.allclose(g, res.confidence, atol=1e-12)


def test_a_decimating_rate_is_refused_with_the_way_out():
    s = make_strong_tremor(seed=1, fs=1000.0, duration=8.0)
    cfg = WakeConfig(fs=1000.0, horizon=20, backend="reference")
    res = WakeFilter(config=cfg).run(s.measurement)
    with pytest.raises(ValueError, match="decimation=1"):
        command_with(s.measurement, res, cfg, 20)


@pytest.mark.parametrize("fs", [100.0, 128.0])
def test_a_longer_predictor_comes_closer_to_the_40_tap_limit_where_tremor_is_strong(fs):
    """On strong tremor the 8-tap structure is what stops today's design (bench/strong_ahead.py)."""
    ratios = {p: [] for p in PREDICTORS}
    zero = []
    for seed in (4600, 4601, 4602):
        s = make_strong_tremor(seed=seed, fs=fs, duration=25.0, kind=("gyroscope", "accelerometer")[seed % 2])
        h = horizon_from_ms(50, fs)
        cfg = WakeConfig(fs=fs, horizon=h, backend="reference")
        res = WakeFilter(config=cfg).run(s.measurement)
        lim = slice_nrmse(s.tremor, wiener_limit(s.measurement - res.voluntary, s.tremor, h), fs)["after 5 s"]
        for p in PREDICTORS:
            cmd = command_with(s.measurement, res, cfg, h, p)[2]
            ratios[p].append(slice_nrmse(s.tremor, cmd, fs)["after 5 s"] / lim)
        zero.append(slice_nrmse(s.tremor, np.zeros_like(s.tremor), fs)["after 5 s"] / lim)
    mean = {p: float(np.mean(v)) for p, v in ratios.items()}
    assert mean["fir40"] < mean["fir8"] and mean["order-select"] < mean["fir8"]
    assert all(1.0 <= v < float(np.mean(zero)) for v in mean.values())


def test_fit_selected_picks_a_short_order_on_noise_and_a_long_one_on_a_steady_tremor(rng):
    t = np.arange(500) / 100.0
    noise = rng.standard_normal(500)
    c = fit_selected(noise, rng.standard_normal(500), 5)
    assert c.shape == (max(ORDERS),) and np.count_nonzero(c) == min(ORDERS)
    s = np.sin(2 * np.pi * 6 * t) + 0.4 * np.sin(2 * np.pi * 11 * t + 1)
    y = s + 0.3 * rng.standard_normal(500)
    assert np.count_nonzero(fit_selected(y, s, 5)) > min(ORDERS)


def test_fit_model_and_fit_selected_reject_bad_input():
    s = np.sin(np.arange(300) / 3.0)
    with pytest.raises(ValueError, match="predictor must be one of"):
        fit_model(s, s, 2, "burg")
    with pytest.raises(ValueError, match="held_out must lie in"):
        fit_selected(s, s, 2, held_out=1.0)
    with pytest.raises(ValueError, match="orders must be positive"):
        fit_selected(s, s, 2, orders=(0, 8))
    with pytest.raises(ValueError, match="one length"):
        fit_selected(s, s[:-1], 2)
    with pytest.raises(ValueError, match="at least 1 sample"):
        fit_selected(s, s, 0)
