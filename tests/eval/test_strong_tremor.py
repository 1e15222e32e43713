"""The synthetic strong-tremor set (wake.eval.strong_tremor): what its docstring promises."""

import numpy as np
import pytest
import scipy.signal

from wake.eval.strong_tremor import make_strong_tremor, strong_tremor_dataset


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
def test_a_signal_holds_a_dominant_wandering_4_8_hz_tremor(fs, kind):
    s = make_strong_tremor(seed=12, fs=fs, duration=30.0, kind=kind)
    assert np.allclose(s.measurement, s.voluntary + s.tremor + s.noise)
    assert 4.0 <= s.f0 <= 8.0
    f, p = scipy.signal.welch(s.tremor, fs=fs, nperseg=int(4 * fs))
    assert abs(f[np.argmax(p)] - s.f0) < 0.6
    env = np.abs(scipy.signal.hilbert(s.tremor))
    assert np.std(np.log(env[int(fs):-int(fs)])) > 0.15            # the amplitude wanders
    assert s.tremor.std() > 1.5 * np.std(s.voluntary[int(3 * fs):])             # after the put-down
    if kind == "accelerometer":
        assert abs(np.mean(s.voluntary[int(5 * fs):]) - 9.81) < 0.5 and s.voluntary[0] < 5.0   # gravity, put down


def test_the_set_and_bad_parameters():
    a, b = strong_tremor_dataset(2, duration=5.0), strong_tremor_dataset(2, duration=5.0)
    assert np.array_equal(a[1].measurement, b[1].measurement) and a[0].kind != a[1].kind
    with pytest.raises(ValueError, match="kind must be one of"):
        make_strong_tremor(kind="emg")
    with pytest.raises(ValueError, match="second harmonic"):
        make_strong_tremor(fs=20.0, f0=6.0)
