"""The C HPA's batch driver (wake/native/wake_batch.c, wake.hpa.c_batch) against the path it replaces.

``WakeFilter(backend="c", hpa_backend="c")`` hands runs of HPA points to the driver; every point it does not
cover, or refuses, runs on ``Channel.hpa``.  With the driver switched off (``c_batch.covers`` False) every
point runs there: outputs and HPA history must be the same bit for bit, at 100 and 1000 Hz (the rate adapter),
on a gyroscope and on an accelerometer with gravity.
"""

import numpy as np
import pytest
from support import assert_same_history, assert_same_results, motion

from wake import WakeFilter
from wake.hpa import c_batch
from wake.rtp import c_backend_available

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")

@pytest.fixture
def taken(monkeypatch):
    """The points the driver was handed, counted."""
    count = [0]
    flush = c_batch.Batch.flush

    def counting(self, y):
        count[0] += len(self.points)
        return flush(self, y)

    monkeypatch.setattr(c_batch.Batch, "flush", counting)
    return count


def without_driver(run, monkeypatch):
    with monkeypatch.context() as m:
        m.setattr(c_batch, "covers", lambda channel: False)
        return run()


def assert_same_run(x, monkeypatch, taken, **settings):
    run = lambda: WakeFilter(backend="c", hpa_backend="c", **settings).run(x)  # noqa: E731
    res = run()
    used = taken[0]
    ref = without_driver(run, monkeypatch)
    assert taken[0] == used
    assert_same_results(res, ref)
    return used


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_driver_matches_the_point_by_point_path(fs, kind, monkeypatch, taken):
    x, _ = motion(fs, kind, seconds=40.0)
    used = assert_same_run(x, monkeypatch, taken, fs=fs)
    assert used >= 3 * 6   # three channels, most of their 11 points on the driver


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_blocks_and_updates_unchanged(fs, kind, monkeypatch, taken):
    x = motion(fs, kind, seconds=25.0)[0][:, 2]
    cuts = np.cumsum([1, 333, 2000, 7, 4000])
    cuts = cuts[cuts < x.shape[0]]

    def blocks():
        f = WakeFilter(backend="c", hpa_backend="c", fs=fs)
        out = np.concatenate([f.update_block(part) for part in np.split(x, cuts)])
        return out, f.hpa_history

    out, hist = blocks()
    assert taken[0] > 0
    ref, ref_hist = without_driver(blocks, monkeypatch)
    assert np.array_equal(out, ref, equal_nan=True)
    assert_same_history(hist, ref_hist)
    f = WakeFilter(backend="c", hpa_backend="c", fs=fs)
    stepped = np.array([f.update(float(v)) for v in x[: x.shape[0] // 2]])
    assert np.array_equal(stepped, out[: x.shape[0] // 2], equal_nan=True)


@pytest.mark.filterwarnings("ignore::wake.rtp.adaptive.ClippingWarning")   # the clipped case's, both ways
@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_gaps_clipping_and_a_jump_fall_back_point_by_point(fs, monkeypatch, taken):
    x = motion(fs, "acc", seconds=40.0, seed=2)[0][:, 2].copy()
    n = x.shape[0]
    x[n // 4 : n // 4 + int(2 * fs)] = np.nan        # a long gap
    x[n // 2 : n // 2 + 5] = np.nan                  # a short one
    x[3 * n // 4 :] += 40.0                          # a jump: the overflow rule raises the full scale
    used = assert_same_run(x, monkeypatch, taken, fs=fs)
    assert used > 0
    taken[0] = 0
    assert_same_run(x, monkeypatch, taken, fs=fs, full_scale=4.0)   # clipped at a fixed full scale


@pytest.mark.parametrize("settings", [dict(horizon=5), dict(horizon=20, gate_cutoff=None),
                                      dict(initial_weights="prior"), dict(horizon=2, gate_cutoff=4.0),
                                      dict(horizon=2, ridge_scale="centred", kind="acc")])
def test_tremor_ahead_options(settings, monkeypatch, taken):
    settings = dict(settings)
    x = motion(100.0, settings.pop("kind", "gyro"), seconds=40.0, seed=4)[0]
    try:
        assert_same_run(x, monkeypatch, taken, **settings)
    except TypeError as exc:   # a setting this version does not have
        pytest.skip(str(exc))
    assert taken[0] > 0


def test_a_point_the_driver_refuses_runs_on_the_channel(monkeypatch, taken):
    """The driver stops after its first point of each call (as after a refusal): the rest run as before."""
    ffi, lib = c_batch._core()

    class OnePoint:
        def __getattr__(self, name):
            return getattr(lib, name)

        def wake_batch_run(self, *args):
            args = list(args)
            args[5], args[6] = args[7][0], min(args[6], 1)   # to the first point, no tail: as a refusal leaves it
            lib.wake_batch_run(*args)
            return lib.WAKE_BATCH_HPA_REFUSED

    monkeypatch.setattr(c_batch, "_core", lambda: (ffi, OnePoint()))
    x = motion(100.0, "acc", seconds=40.0, seed=5)[0]
    assert assert_same_run(x, monkeypatch, taken) >= 3 * 6


def test_bad_input_refused_alike(monkeypatch):
    x = motion(100.0, "gyro", seconds=10.0)[0][:, 0].copy()
    x[700] = np.inf
    messages = []
    for run in (lambda: WakeFilter(backend="c", hpa_backend="c").run(x),) * 2:
        with pytest.raises(ValueError) as info:
            run() if not messages else without_driver(run, monkeypatch)
        messages.append(str(info.value))
    assert messages[0] == messages[1] and "inf" in messages[0]
