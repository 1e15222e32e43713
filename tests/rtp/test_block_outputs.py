"""The C core's batch path (``wake_rtp_run_outputs``, issue 44) against its per-sample path, bit for bit.

``FixedPointRTP.run``, ``run_outputs`` and ``run_ahead`` make one call of the C core per block; each must
give what a loop of :meth:`~wake.rtp.fixed.FixedPointRTP.step` gives when it reads ``last_ahead`` and
``last_voluntary_ahead`` after every sample, with the same state and counters afterwards, on a gyroscope
(zero-mean) and an accelerometer (gravity on one axis) recording at 100 and 1000 Hz, with missing samples
(the first included) and samples beyond the full scale.  A WakeFilter on the C backend never steps the
C core sample by sample from ``run`` or ``update_block``.
"""

import pickle

import numpy as np
import pytest

from wake import WakeFilter
from wake.eval.synthetic import make_signal
from wake.wavelets import filter_bank_taps

_c = pytest.importorskip("wake.rtp.fixed", reason="the C extension wake._rtp is not built")
FixedPointRTP = _c.FixedPointRTP

BLOCKS = (1, 7, 64, 333, 2, 1000)


def recording(kind, fs, seed=5):
    """``kind`` "gyro": zero-mean rad/s; "accel": m/s^2 with gravity; gaps of NaN and a knock beyond FS."""
    x = make_signal(10.0, seed=seed, fs=fs, duration=12.0).measurement
    if kind == "accel":
        x = 9.81 + 0.5 * x
    n = x.size
    x[0] = np.nan
    x[n // 3: n // 3 + n // 50] = np.nan
    x[n // 2] = 1e6                       # clipped at the full scale
    x[n // 2 + 3] = -1e6
    return x


def core(kind, fs, level=5):
    full_scale = 16.0 if kind == "accel" else 4.0
    taps = filter_bank_taps("sym3", level)
    rng = np.random.default_rng(level)
    return FixedPointRTP(taps, rng.uniform(-0.4, 0.6, level), 0.01, 1e-4, 0.01, full_scale=full_scale, fs=fs), rng


def installs(rtp, rng, k):
    """What an HPA installs between two samples: w and R, the tremor ahead and, from the second on, w_h."""
    rtp.set_weights(rng.uniform(-0.4, 0.6, rtp.level), 0.02)
    rtp.set_ahead(rng.uniform(-1, 1, 8), 0.8)
    if k:
        rtp.set_weights_ahead(rng.uniform(-0.5, 0.9, rtp.level))


def per_sample(rtp, x):
    out = np.empty((5, x.size))
    for k, v in enumerate(x):
        out[0, k] = rtp.step(v)
        out[1:4, k] = rtp.last_ahead
        out[4, k] = rtp.last_voluntary_ahead if rtp.has_weights_ahead else out[0, k]
    return out


def state_bytes(rtp):
    """The C struct's bytes but the taps pointer (each instance points at its own copy)."""
    raw, at = bytes(_c.ffi.buffer(rtp._state)), _c.ffi.offsetof("wake_rtp_t", "taps")
    return raw[:at] + raw[at + _c.ffi.sizeof("void *"):]


def counters(rtp):
    return (rtp.clipped, rtp.saturations, rtp.ahead_saturations, rtp.voluntary_ahead_saturations)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "accel"])
def test_run_outputs_in_blocks_is_the_per_sample_path_bit_for_bit(kind, fs):
    x = recording(kind, fs)
    block, rng_b = core(kind, fs)
    loop, rng_l = core(kind, fs)
    parts, wants, k, i = [], [], 0, 0
    while k < x.size:
        stop = min(x.size, k + BLOCKS[i % len(BLOCKS)] * (1 if fs == 100.0 else 10))
        if i in (2, 4):
            installs(block, rng_b, i == 4)
            installs(loop, rng_l, i == 4)
        parts.append(np.array(block.run_outputs(x[k:stop])))
        wants.append(per_sample(loop, x[k:stop]))
        k, i = stop, i + 1
    got, want = np.concatenate(parts, axis=1), np.concatenate(wants, axis=1)
    np.testing.assert_array_equal(got, want)
    assert counters(block) == counters(loop) and block.clipped >= 2
    assert state_bytes(block) == state_bytes(loop)
    assert block.has_weights_ahead and np.isnan(x).sum() > 10
    assert np.abs(want[4] - want[0]).max() > 1e-3    # w_h was live: the last row is not the prediction held
    assert np.abs(want[2]).max() > 0                 # and so was the gate


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "accel"])
def test_run_and_run_ahead_are_the_per_sample_path(kind, fs):
    x = recording(kind, fs, seed=11)
    a, rng = core(kind, fs)
    installs(a, rng, True)
    b = pickle.loads(pickle.dumps(a))
    c = pickle.loads(pickle.dumps(a))
    want = per_sample(a, x)
    np.testing.assert_array_equal(b.run(x), want[0])
    for got, row in zip(c.run_ahead(x), want[:4]):
        np.testing.assert_array_equal(got, row)
    assert counters(a) == counters(b) == counters(c)
    assert b.run(x[:0]).shape == (0,) and all(r.shape == (0,) for r in b.run_outputs([]))


@pytest.mark.parametrize("settings", [dict(), dict(horizon=5), dict(hpa_backend="c"), dict(full_scale=4.0)])
def test_a_c_backend_filter_never_steps_the_c_core_from_a_batch_path(monkeypatch, settings):
    x = make_signal(10.0, seed=2, duration=15.0).measurement
    x[700:720] = np.nan

    def refuse(self, sample):
        raise AssertionError("a batch path stepped the C core sample by sample")

    want = WakeFilter(backend="c", **settings).run(x)
    monkeypatch.setattr(FixedPointRTP, "step", refuse)
    monkeypatch.setattr(FixedPointRTP, "step_missing", refuse)
    got = WakeFilter(backend="c", **settings).run(x)
    assert got.full_scale[0] > 0                     # the C core ran
    for name in ("prediction", "tremor_ahead", "confidence", "command"):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name))
    f = WakeFilter(backend="c", **settings)
    np.testing.assert_array_equal(np.concatenate([f.update_block(x[:900]), f.update_block(x[900:])]),
                                  want.prediction)
