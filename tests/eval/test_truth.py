"""The offline tremor truth of a recording (wake.eval.truth): safe against start transients, steps and gaps,
at more than one rate and on both kinds of recording; the old sharp truth rang a start step across the record."""

import numpy as np
import pytest

from wake.eval.strong_tremor import make_strong_tremor
from wake.eval.truth import MIN_RUN_S, finite_runs, smooth_highpass, tremor_truth
from wake.eval.warmup import independent_ground_truth, slice_nrmse
from wake.hpa.sharp import sharp_highpass


def _after(ref, est, fs, start_s=5.0):
    lo = int(start_s * fs)
    ok = np.isfinite(ref[lo:]) & np.isfinite(est[lo:])
    return float(np.sqrt(np.mean((ref[lo:][ok] - est[lo:][ok]) ** 2)) / np.ptp(ref[lo:][ok]))


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
def test_the_truth_recovers_the_tremor_after_a_start_transient(fs, kind):
    s = make_strong_tremor(seed=7, fs=fs, duration=20.0, kind=kind)
    _, truth, cutoff = tremor_truth(s.measurement, fs)
    assert 1.5 <= cutoff <= 5.0
    assert _after(s.tremor, truth, fs) < 0.02
    if kind == "accelerometer":             # the sharp truth rings the put-down step into the scored part
        sharp = sharp_highpass(s.measurement, fs, cutoff)
        assert _after(s.tremor, sharp, fs) > 2 * _after(s.tremor, truth, fs)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_the_truth_does_not_move_when_the_start_is_cropped(fs):
    s = make_strong_tremor(seed=3, fs=fs, duration=20.0, kind="accelerometer")
    k = int(3 * fs)
    _, whole, fc = tremor_truth(s.measurement, fs)
    _, cropped, _ = tremor_truth(s.measurement[k:], fs, cutoff=fc)
    lo = int(5 * fs)
    assert np.sqrt(np.mean((whole[lo:] - cropped[lo - k:]) ** 2)) < 1e-3 * np.ptp(whole[lo:])


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_a_gap_splits_the_truth_and_stays_without_one(fs):
    s = make_strong_tremor(seed=5, fs=fs, duration=20.0)
    x = s.measurement.copy()
    x[int(10 * fs):int(10.5 * fs)] = np.nan
    x[int(15 * fs):int(15 * fs) + int(0.5 * MIN_RUN_S * fs)] = 1.0      # a run too short for a truth ...
    x[int(15 * fs) + int(0.5 * MIN_RUN_S * fs)] = np.nan                 # ... between two gaps
    x[int(15 * fs) - 1] = np.nan
    _, truth, _ = tremor_truth(x, fs)
    assert np.isnan(truth[int(10 * fs):int(10.5 * fs)]).all()
    assert np.isnan(truth[int(15 * fs):int(15 * fs) + int(0.5 * MIN_RUN_S * fs)]).all()
    good = slice(int(6 * fs), int(9 * fs))
    assert np.sqrt(np.mean((truth[good] - s.tremor[good]) ** 2)) < 0.03 * np.ptp(s.tremor)
    # scores leave the gap out instead of turning NaN
    assert np.isfinite(slice_nrmse(truth, np.zeros_like(truth), fs)["after 5 s"])


def test_independent_ground_truth_is_the_one_definition():
    s = make_strong_tremor(seed=1, duration=12.0, kind="accelerometer")
    v, t, fc = independent_ground_truth(s.measurement, s.fs)
    v2, t2, fc2 = tremor_truth(s.measurement, s.fs)
    assert fc == fc2 and np.array_equal(t, t2) and np.allclose(v + t, s.measurement)


def test_finite_runs_and_bad_input():
    assert finite_runs([np.nan, 1.0, 2.0, np.nan, 3.0]) == [(1, 3), (4, 5)]
    with pytest.raises(ValueError, match="cutoff must lie in"):
        smooth_highpass(np.ones(100), 100.0, 60.0)
    with pytest.raises(ValueError, match="NaN or inf"):
        smooth_highpass(np.r_[np.ones(10), np.nan], 100.0, 3.0)
    with pytest.raises(ValueError, match="mark missing samples with NaN"):
        tremor_truth(np.r_[np.ones(500), np.inf], 100.0)
    with pytest.raises(ValueError, match="no run of finite samples"):
        tremor_truth(np.full(50, np.nan), 100.0)
    with pytest.raises(ValueError, match="one channel"):
        tremor_truth(np.ones((100, 2)), 100.0)
