"""WakeConfig.ridge_scale: the weight fit's ridge relative to the centred Gram matrix (issue 46)."""

import numpy as np
import pytest
from support import NO_PDKIT, pdkit_dir

from wake import WakeConfig, WakeFilter
from wake.eval.strong_tremor import make_strong_tremor
from wake.hpa.fit import fit_weights, ridge_scale_of


def one_step_nrmse(sig, **settings):
    vol = WakeFilter(fs=sig.fs, backend="reference", **settings).run(sig.measurement).voluntary
    lo = int(5 * sig.fs)
    err = (sig.measurement - vol - sig.tremor)[lo:]
    return float(np.sqrt(np.mean(err**2)) / np.ptp(sig.tremor[lo:]))


def test_the_centred_scale_ignores_an_offset_and_the_gram_scale_grows_with_it():
    rng = np.random.default_rng(3)
    A = rng.standard_normal((400, 5))
    G = A.T @ A
    shifted = A + 9.81
    assert ridge_scale_of(shifted, shifted.T @ shifted, "centred") == pytest.approx(
        ridge_scale_of(A, G, "centred"), rel=1e-9)
    assert ridge_scale_of(shifted, shifted.T @ shifted) > 50 * ridge_scale_of(A, G)
    # an offset with nothing else: floored at 1e-6 of the Gram scale, never 0 or negative (the fit still solves)
    flat = np.full((100, 3), 9.81)
    assert ridge_scale_of(flat, flat.T @ flat, "centred") == pytest.approx(1e-6 * ridge_scale_of(flat, flat.T @ flat))
    w, _, _ = fit_weights(flat, np.full(100, 9.81), ridge_scale="centred")
    assert np.isfinite(w).all() and abs(w.sum() - 1.0) < 1e-6


def test_unknown_rules_are_refused_naming_the_choices():
    with pytest.raises(ValueError, match="valid choices: gram, centred"):
        WakeConfig(ridge_scale="mean")
    with pytest.raises(ValueError, match="valid choices: gram, centred"):
        fit_weights(np.eye(3), np.ones(3), ridge_scale="mean")
    assert WakeConfig(ridge_scale="centred", hpa_backend="c").ridge_scale == "centred"   # the C HPA has it too


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_the_default_is_todays_fit_bit_for_bit(fs):
    sig = make_strong_tremor(seed=5, fs=fs, duration=12.0, kind="accelerometer")
    a = WakeFilter(fs=fs, backend="reference").run(sig.measurement)
    b = WakeFilter(fs=fs, backend="reference", ridge_scale="gram").run(sig.measurement)
    assert np.array_equal(a.voluntary, b.voluntary)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_centred_helps_an_accelerometer_with_gravity_and_leaves_a_gyroscope_alone(fs):
    acc = make_strong_tremor(seed=1, fs=fs, duration=20.0, kind="accelerometer")
    gram, centred = one_step_nrmse(acc), one_step_nrmse(acc, ridge_scale="centred")
    assert centred < 0.9 * gram
    gyro = make_strong_tremor(seed=2, fs=fs, duration=20.0, kind="gyroscope")
    assert one_step_nrmse(gyro, ridge_scale="centred") == pytest.approx(one_step_nrmse(gyro), rel=0.01)


def test_pdkit_one_step_below_every_baseline_on_eleven_of_thirteen_axes_with_the_setting():
    folder = pdkit_dir()
    if folder is None:
        pytest.skip(NO_PDKIT)
    from wake.eval.baselines import baseline_methods
    from wake.eval.pdkit import load_pdkit_folder, tremor_axes
    from wake.eval.truth import tremor_truth

    def score(t, e, fs):
        lo = int(5 * fs)
        return np.sqrt(np.mean((t[lo:] - e[lo:]) ** 2)) / np.ptp(t[lo:])

    wins = {"gram": 0, "centred": 0}
    for rec, c in tremor_axes(load_pdkit_folder(folder)):
        x, fs = rec.recording.samples[:, c].astype(float), rec.recording.fs
        truth = tremor_truth(x, fs)[1]
        best = min(score(truth, x - np.reshape(m.run(x).voluntary, x.shape), fs)
                   for m in baseline_methods(fs).values())
        for rule in wins:
            vol = WakeFilter(fs=fs, backend="reference", ridge_scale=rule).run(x).voluntary
            wins[rule] += score(truth, x - vol, fs) < best
    assert wins["centred"] >= 11
    assert wins["centred"] > wins["gram"]
