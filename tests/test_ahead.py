"""The tremor-ahead rule (wake.ahead): the fit, the held-out gain, the gate's goal and its ramp."""

import numpy as np
import pytest

from wake.ahead import (COEFFICIENT_LIMIT, MIN_HELD_OUT, NO_TREMOR_FLAGS, AheadStep, fit_predictor, gate_target,
                        held_out_gain, predictions, ramp_step)


def sinusoid(n=500, f=6.0, fs=100.0):
    return np.sin(2 * np.pi * f * np.arange(n) / fs)


@pytest.mark.parametrize("h", [1, 2, 5, 10])
def test_a_clean_sinusoid_is_predicted_h_samples_ahead(h):
    s = sinusoid()
    c = fit_predictor(s, s, h)
    P = predictions(s, c)
    err = P[20:-h] - s[20 + h:]
    assert np.sqrt(np.mean(err**2)) < 0.02


def test_the_fit_learns_to_damp_white_noise_in_the_estimate():
    rng = np.random.default_rng(0)
    s = sinusoid(2000)
    noisy = s + rng.normal(0, 1.0, s.size)
    c = fit_predictor(noisy, s, 5)
    P = predictions(noisy, c)
    # the Wiener fit scales down: its error is below the error of predicting the noisy input itself
    assert np.mean((P[20:-5] - s[25:]) ** 2) < 0.5 * np.mean((noisy[20:-5] - s[25:]) ** 2)


def test_coefficients_are_clipped_and_degenerate_windows_give_zeros():
    assert not np.any(fit_predictor(np.zeros(100), np.zeros(100), 1))
    assert not np.any(fit_predictor(np.ones(5), np.ones(5), 1))  # fewer than two rows
    rng = np.random.default_rng(1)
    y = rng.normal(size=300) * 1e-3
    c = fit_predictor(y, 1e3 * np.roll(y, -1), 1)
    assert np.all(np.abs(c) <= COEFFICIENT_LIMIT) and np.max(np.abs(c)) == COEFFICIENT_LIMIT


def test_bad_arguments_are_refused_with_what_was_wrong():
    with pytest.raises(ValueError, match="horizon"):
        fit_predictor(np.zeros(10), np.zeros(10), 0)
    with pytest.raises(ValueError, match="one length"):
        fit_predictor(np.zeros(10), np.zeros(11), 1)


def test_held_out_gain_is_the_clipped_least_squares_scale_of_the_previous_model():
    s = sinusoid()
    c = fit_predictor(s, s, 2)
    assert held_out_gain(s, s, c, 2, 100) == pytest.approx(1.0, abs=0.02)
    assert held_out_gain(s, 0.5 * s, c, 2, 100) == pytest.approx(0.5, abs=0.02)
    assert held_out_gain(s, -s, c, 2, 100) == 0.0           # anti-correlated: shut
    assert held_out_gain(s, 3 * s, c, 2, 100) == 1.0        # clipped
    assert held_out_gain(s, s, None, 2, 100) == 0.0         # the first HPA has nothing to score
    assert held_out_gain(s, s, c, 2, MIN_HELD_OUT - 1) == 0.0


def test_held_out_gain_scores_only_the_new_samples():
    s = sinusoid()
    t = s.copy()
    t[:400] = -s[:400]          # the old part disagrees; the 100 new samples agree
    c = fit_predictor(s, s, 1)
    assert held_out_gain(s, t, c, 1, 100) == pytest.approx(1.0, abs=0.02)
    assert held_out_gain(s, t, c, 1, 300) < 0.5


def test_gate_goal_is_zero_without_a_tremor_peak():
    for flag in NO_TREMOR_FLAGS:
        assert gate_target(0.8, flag) == 0.0
    assert gate_target(0.8, "valley") == 0.8


def test_the_gate_ramps_with_its_time_constant_and_the_command_is_gated():
    fs = 100.0
    step = AheadStep([1.0], fs)
    step.set_goal(1.0)
    n = int(0.3 * fs)
    for _ in range(n):
        predicted, gate, command = step.step(2.0)
    assert gate == pytest.approx(1 - (1 - ramp_step(fs)) ** n)
    assert gate == pytest.approx(1 - np.exp(-1), abs=0.01)
    assert command == pytest.approx(gate * predicted) and predicted == 2.0
    step.set_goal(7.0)
    assert step.goal == 1.0
    with pytest.raises(ValueError, match="coefficients"):
        step.set_model([1.0, 2.0], 1.0)


@pytest.mark.parametrize("ratio", [-0.0, 0.0, 0.25, 1.0, 1.0 + 2**-52, -3.0, -5e-324, 5e-324, np.inf, -np.inf, np.nan])
def test_the_gain_is_clipped_as_np_clip_clips_it(ratio):
    """scale_gain clips <target, p> / <p, p> without np.clip's wrappers: every bit of np.clip's answer (-0.0 kept,
    NaN passed on), and 0 for predictions without power."""
    from wake.ahead import scale_gain

    p = np.array([1.0, 0.0])
    target = np.array([ratio, 5.0])   # <target, p> / <p, p> = ratio
    want = float(np.clip(float(target @ p) / float(p @ p), 0.0, 1.0))
    assert np.array(scale_gain(p, target)).tobytes() == np.array(want).tobytes()
    assert scale_gain(np.zeros(2), target) == 0.0
