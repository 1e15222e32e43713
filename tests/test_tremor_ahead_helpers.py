"""The helpers of bench/tremor_ahead.py (issue 32's design study): the predictors and the gate's gain do what
docs/studies/design.md ("Tremor ahead", "The design study") says they do."""

import functools
import importlib.util
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


@functools.lru_cache(maxsize=None)
def _ahead():
    spec = importlib.util.spec_from_file_location("bench_ahead", ROOT / "bench" / "ahead.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["bench_ahead"] = mod                  # its dataclass looks its module up by name
    spec.loader.exec_module(mod)
    return mod


def test_iterated_ar_is_the_recursion_run_h_times():
    ahead = _ahead()
    a = np.array([1.0, -1.2, 0.5, -0.1])            # y(n) = 1.2 y(n-1) - 0.5 y(n-2) + 0.1 y(n-3)
    rng = np.random.default_rng(1)
    y = list(rng.standard_normal(3))
    past = np.array(y[::-1])                          # y(n), y(n-1), y(n-2)
    for _ in range(5):
        y.append(-a[1:] @ np.array(y[-1:-4:-1]))
    for h in (1, 2, 5):
        assert np.isclose(ahead.ar_iterated(a, h) @ past, y[2 + h])


def test_direct_least_squares_predicts_a_sinusoid_exactly_and_apply_fir_is_causal():
    ahead = _ahead()
    t = np.arange(400) / 100.0
    s = np.sin(2 * np.pi * 7.0 * t + 0.3)
    for h in (1, 5, 10):
        c = ahead.ls_direct(s, s, h, 4, ridge=1e-12)
        P = ahead.apply_fir(s, [(50, c)], 4)
        assert np.all(P[:50] == 0)                    # no model before its start
        assert np.max(np.abs(P[50:-h] - s[50 + h:])) < 1e-6
        # P[n] depends on s[:n + 1] only
        late = s.copy()
        late[200:] += 1.0
        assert np.array_equal(ahead.apply_fir(late, [(50, c)], 4)[:200], P[:200])


def test_command_plays_the_prediction_h_samples_later():
    ahead = _ahead()
    P = np.arange(1.0, 7.0)
    assert ahead.command(P, 2).tolist() == [0, 0, 1, 2, 3, 4]


def test_held_out_gain_scores_the_previous_model_on_the_new_samples_only():
    ahead = _ahead()
    n, h = 300, 2
    T = np.sin(np.arange(n + h) * 0.5)
    W = [ahead.Window(100, 0, 2.0, "valley", T[:100]), ahead.Window(200, 0, 2.0, "valley", T[:200])]
    P = np.zeros(n)
    P[100:] = 0.5 * T[100 + h:n + h]                  # the previous model predicts half of T(n + h)
    gain, skill = ahead.held_out_gain(P, W, h)
    assert np.isnan(gain[0]) and np.isclose(gain[1], 2.0) and np.isclose(skill[1], 0.75)


def test_baselines_extrapolation_at_one_step_is_their_own_model_tremor():
    from wake.eval.evaluate import baseline_methods

    ahead = _ahead()
    rng = np.random.default_rng(0)
    x = np.cumsum(rng.standard_normal((200, 2)), axis=0) * 0.1 + np.sin(np.arange(200)[:, None] * 0.5)
    P = ahead.baselines_ahead(x, 100.0, (1, 3))
    for name, method in baseline_methods(100.0).items():
        assert np.allclose(P[name][1][:-1], method.run(x).model_tremor[1:], atol=1e-12)


def test_chosen_gate_is_the_clipped_held_out_gain_and_shut_without_a_tremor_peak():
    ahead = _ahead()
    n, h = 400, 1
    T = np.sin(np.arange(n + h) * 0.5)
    P = np.zeros(n)
    P[100:] = 2.0 * T[100 + h:n + h]                  # over-shoots twice: gain 0.5
    W = [ahead.Window(100, 0, 2.0, "valley", T[:100]), ahead.Window(200, 0, 2.0, "valley", T[:200]),
         ahead.Window(300, 0, 2.0, "no_tremor_peak", T[:300])]
    g = ahead.chosen_gate(P, W, h, n)
    assert np.all(g[:200] == 0)                       # nothing scored before the second HPA
    assert np.allclose(g[200:300], 0.5) and np.all(g[300:] == 0)
