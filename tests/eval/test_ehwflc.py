"""eHWFLC-KF (wake.eval.ehwflc): the baselines' contract, its tremor model and extrapolation, input checks."""

import numpy as np
import pytest

from wake.eval.baselines import BASELINES, baseline_methods
from wake.eval.ehwflc import EHWFLCKF
from wake.eval.strong_tremor import make_strong_tremor


def test_it_is_registered_with_the_other_baselines():
    assert BASELINES["eHWFLC-KF"] is EHWFLCKF
    assert isinstance(baseline_methods(100.0)["eHWFLC-KF"], EHWFLCKF)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
def test_it_tracks_a_strong_tremor_and_extrapolates_it(fs, kind):
    s = make_strong_tremor(seed=21, fs=fs, duration=15.0, kind=kind, freq_sd_hz=0.1, amp_sd=0.1)
    res = EHWFLCKF(fs=fs).run(s.measurement, horizons=(int(0.02 * fs),))
    lo = int(5 * fs)
    err = np.sqrt(np.mean((res.tremor - s.tremor)[lo:] ** 2)) / np.std(s.tremor)
    # Below zero's 1.0 at both rates.  Locked on the tremor's frequency, the model is good and extrapolates;
    # this seed also shows the two ways it is not: at 100 Hz the fundamental is still on its way from 6 Hz
    # after 15 s, at 1000 Hz (accelerometer) it locks on 3.5 Hz, a 7.1-Hz tremor taken as its second
    # harmonic (docs/studies/baselines.md, "eHWFLC-KF").
    assert err < 0.7
    locked = abs(np.median(res.frequency[lo:]) - s.f0) < 0.3
    assert (err < 0.2) == locked
    h = int(0.02 * fs)
    ahead = res.ahead[h]
    err_ahead = np.sqrt(np.mean((ahead[lo:-h] - s.tremor[lo + h:]) ** 2)) / np.std(s.tremor)
    assert err_ahead < 0.6 if locked else err_ahead > err


def test_one_step_outputs_do_not_depend_on_the_horizons_asked_and_channels_are_independent():
    s = make_strong_tremor(seed=2, duration=6.0)
    x = np.column_stack([s.measurement, 3.0 * s.measurement[::-1]])
    two = EHWFLCKF().run(x, horizons=(1, 5))
    one = EHWFLCKF().run(x[:, 0])
    assert np.array_equal(two.voluntary[:, 0], one.voluntary)
    assert np.allclose(EHWFLCKF().run(x[:, 1]).voluntary, two.voluntary[:, 1])


def test_scale_free():
    s = make_strong_tremor(seed=4, duration=8.0)
    a, b = EHWFLCKF().run(s.measurement), EHWFLCKF().run(1000.0 * s.measurement)
    assert np.allclose(1000.0 * a.tremor, b.tremor, rtol=1e-6, atol=1e-6 * np.abs(b.tremor).max())


def test_bad_parameters_say_what_is_wrong():
    with pytest.raises(ValueError, match="top harmonic"):
        EHWFLCKF(fs=50.0, n_harmonics=3)
    assert EHWFLCKF(fs=50.0).n_harmonics == 2
    with pytest.raises(ValueError, match="f0 must lie in f_range"):
        EHWFLCKF(f0=20.0)
    with pytest.raises(ValueError, match="beta"):
        EHWFLCKF(beta=2.0)
    with pytest.raises(ValueError, match="q_tremor"):
        EHWFLCKF(q_tremor=0.0)
