"""The baselines' C loops (wake/eval/native/wake_eval.c) against their Python loops (the reference kept in
wake/eval/baselines.py): every output within 1e-12 of the largest, at two sampling rates, on a gyroscope-like
signal and on accelerometer channels with gravity, with and without extrapolation."""

import numpy as np
import pytest

from wake.eval.baselines import BASELINES, ENGINES, BMFLC
from wake.eval.synthetic import make_signal

pytest.importorskip("wake._rtp", reason="the compiled core (python build_ffi.py) holds the baselines' C loops")

#: Largest difference allowed, relative to the largest magnitude of the output: the regressors and E-BMFLC's
#: information matrix are the same operations in both loops; only sums and the Cholesky solve round differently.
TOLERANCE = 1e-12


def _signals(fs):
    """A gyroscope-like signal (rad/s, zero mean) and two accelerometer axes with gravity (m/s^2)."""
    s = make_signal(5.0, seed=11, fs=fs, duration=12.0)
    gyro = s.measurement
    accel = np.column_stack((9.81 + 0.4 * s.measurement, -1.2 + 0.2 * s.tremor + 0.05 * s.voluntary))
    return {"gyroscope": gyro, "accelerometer": accel}


def _outputs(res, horizons):
    out = {"voluntary": res.voluntary, "tremor": res.tremor, "model_tremor": res.model_tremor}
    if res.frequency is not None:
        out["frequency"] = res.frequency
    out.update({f"ahead {h}": res.ahead[h] for h in horizons})
    return out


#: The baselines with a C loop (a class says which engines its run takes; the default, every one)
C_LOOPED = [name for name, cls in BASELINES.items() if "c" in getattr(cls, "engines", ENGINES)]


def test_every_baseline_has_a_c_loop():
    assert C_LOOPED == ["BMFLC", "E-BMFLC", "WFLC", "eHWFLC-KF"] == list(BASELINES)


def _assert_c_loop_matches_python(method, x, horizons=(1, 7)):
    """Every output of the C loop within TOLERANCE of the largest of the Python loop's; returns the C loop's."""
    ref = _outputs(method.run(x, horizons, engine="python"), horizons)
    fast = _outputs(method.run(x, horizons, engine="c"), horizons)
    assert ref.keys() == fast.keys()
    for key, want in ref.items():
        got = fast[key]
        assert got.shape == want.shape == x.shape, key
        scale = np.max(np.abs(want))
        assert scale > 0, key  # the comparison is not between zeros
        assert np.max(np.abs(got - want)) <= TOLERANCE * scale, (key, np.max(np.abs(got - want)) / scale)
    return fast


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyroscope", "accelerometer"])
@pytest.mark.parametrize("name", C_LOOPED)
def test_c_loop_matches_the_python_loop(name, kind, fs):
    x = _signals(fs)[kind]
    if fs == 1000.0:
        x = x[:4000]  # the Python E-BMFLC takes about 0.5 ms a sample
    method = BASELINES[name](fs=fs)
    fast = _assert_c_loop_matches_python(method, x)
    # the default engine is the C loop when the core is built
    assert np.array_equal(method.run(x).voluntary, fast["voluntary"])


def _pads(fs):
    """A real wrist recording (PADS 088: a smartwatch's accelerometer in g and gyroscope in rad/s, 6 axes, 10 s)
    read onto ``fs``; None when the recordings are absent."""
    from support import pads_dir

    from wake.eval.datasets import load_pads_folder

    folder = pads_dir()
    if folder is None:
        return None
    return load_pads_folder(folder, "088_*.txt", fs=fs)[0].samples


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("name", C_LOOPED)
def test_c_loop_matches_the_python_loop_on_a_real_recording(name, fs):
    """The same comparison on a smartwatch recording of a patient's wrist, each axis its own channel, at its own
    rate (100 Hz) and read onto 1000 Hz."""
    from support import NO_PADS

    x = _pads(fs)
    if x is None:
        pytest.skip(NO_PADS)
    if fs == 1000.0:
        x = x[:3000]  # the Python E-BMFLC takes about 0.5 ms a sample
    _assert_c_loop_matches_python(BASELINES[name](fs=fs), x)


def test_c_loop_sees_every_channel_apart():
    x = _signals(100.0)["accelerometer"]
    both = BMFLC().run(x, engine="c")
    second = BMFLC().run(x[:, 1], engine="c")
    assert np.array_equal(both.voluntary[:, 1], second.voluntary)
    assert not np.array_equal(both.voluntary[:, 0], both.voluntary[:, 1])


@pytest.mark.parametrize("bad", ["fortran", "", None, "C"])
def test_engine_must_be_a_known_name(bad):
    with pytest.raises(ValueError, match="engine must be one of"):
        BMFLC().run(np.zeros(100), engine=bad)
    assert "python" in ENGINES and "c" in ENGINES


def test_ehwflc_c_loop_sees_every_channel_apart_and_refuses_bad_engines():
    from wake.eval.ehwflc import EHWFLCKF

    x = _signals(100.0)["accelerometer"][:2000]
    both = EHWFLCKF().run(x, (3,), engine="c")
    second = EHWFLCKF().run(x[:, 1], (3,), engine="c")
    assert np.array_equal(both.voluntary[:, 1], second.voluntary)
    assert np.array_equal(both.ahead[3][:, 1], second.ahead[3])
    assert not np.array_equal(both.voluntary[:, 0], both.voluntary[:, 1])
    with pytest.raises(ValueError, match="engine must be one of"):
        EHWFLCKF().run(x, engine="fortran")
