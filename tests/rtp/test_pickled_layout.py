"""A FixedPointRTP pickled by the code before the tremor ahead and the voluntary motion ahead became instances
(wake_ahead.h, wake_voluntary_ahead.h) loads and continues bit for bit.  The voluntary ahead's instance aligns to
its int64 fields, which moved w_h by 4 bytes at the same struct size: a state pickled since then says so
(``"layout": 2``), one without the key is moved onto the new offsets as it loads (layout 1).

tests/data/rtp_struct_before_instances.pkl holds, per case, an instance pickled after ``SAVED_AT`` samples (a
predictor, a gate on its way to its goal and a w_h installed, so every feature's fields are non-zero), the
samples that follow and the outputs ``run_outputs`` gave on them, all written by that code::

    PYTHONPATH=<checkout before the change> python tests/rtp/test_pickled_layout.py --write
"""

import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parents[1] / "data" / "rtp_struct_before_instances.pkl"
#: samples before the pickle, and after it
SAVED_AT, CONTINUED = 400, 300
#: (sampling rate, kind of recording): a gyroscope (no offset) at 100 Hz, an accelerometer with gravity at 1000 Hz
CASES = ((100.0, "gyroscope"), (1000.0, "accelerometer"))


def _recording(fs, kind, n):
    rng = np.random.default_rng(int(fs))
    t = np.arange(n) / fs
    x = 0.6 * np.sin(2 * np.pi * 0.5 * t) + 0.2 * np.sin(2 * np.pi * 6.0 * t) + rng.normal(0, 0.01, n)
    return x + (9.81 if kind == "accelerometer" else 0.0)


def _instance(fs, kind):
    from wake.rtp.fixed import FixedPointRTP
    from wake.wavelets import filter_bank_taps

    level = 4
    w = np.r_[0.2, -0.1, 0.3, 0.6]
    return FixedPointRTP(filter_bank_taps("sym3", level), w, 0.02, 1e-4, 0.02,
                         full_scale=16.0 if kind == "accelerometer" else 2.0, fs=fs)


def _write():
    cases = {}
    for fs, kind in CASES:
        x = _recording(fs, kind, SAVED_AT + CONTINUED)
        rtp = _instance(fs, kind)
        rtp.run(x[: SAVED_AT // 2])
        rtp.set_ahead(np.r_[0.9, -0.4, 0.1, 0.0, 0.05, 0.0, -0.02, 0.01], 0.8)
        rtp.set_weights_ahead(np.r_[0.1, -0.2, 0.4, 0.7])
        rtp.run(x[SAVED_AT // 2: SAVED_AT])
        blob = pickle.dumps(rtp)
        cases[(fs, kind)] = (blob, x[SAVED_AT:], [np.asarray(r) for r in rtp.run_outputs(x[SAVED_AT:])])
    DATA.write_bytes(pickle.dumps(cases))


@pytest.mark.parametrize("fs, kind", CASES)
def test_a_state_pickled_before_the_instances_continues_bit_for_bit(fs, kind):
    from support import has_c_backend

    if not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    from wake._rtp import ffi
    from wake.rtp.fixed import FixedPointRTP

    blob, rest, expected = pickle.loads(DATA.read_bytes())[(fs, kind)]
    rtp = pickle.loads(blob)
    assert len(rtp.__getstate__()["struct"]) == ffi.sizeof("wake_rtp_t") == FixedPointRTP._STRUCT_SIZES[0]
    assert rtp.fs == fs and rtp.has_weights_ahead and rtp.last_ahead[1] > 0       # the features came along
    assert rtp.ahead_coefficients[0] == pytest.approx(0.9, abs=2**-27)
    got = rtp.run_outputs(rest)
    assert len(got) == len(expected) == 5
    for g, e in zip(got, expected):
        np.testing.assert_array_equal(np.asarray(g), e)


@pytest.mark.parametrize("fs, kind", CASES)
def test_a_new_pickle_says_its_layout_and_round_trips_bit_for_bit(fs, kind):
    from support import has_c_backend

    if not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    from wake._rtp import ffi
    from wake.rtp.fixed_voluntary import STRUCT_LAYOUT

    x = _recording(fs, kind, SAVED_AT + CONTINUED)
    rtp = _instance(fs, kind)
    rtp.set_ahead(np.r_[0.9, -0.4, 0.1, 0.0, 0.05, 0.0, -0.02, 0.01], 0.8)
    rtp.set_weights_ahead(np.r_[0.1, -0.2, 0.4, 0.7])
    rtp.run(x[:SAVED_AT])
    state = rtp.__getstate__()
    assert state["layout"] == STRUCT_LAYOUT == 2
    clone = pickle.loads(pickle.dumps(rtp))
    taps = slice(ffi.offsetof("wake_rtp_t", "taps"), ffi.offsetof("wake_rtp_t", "taps") + ffi.sizeof("void *"))
    got, saved = bytearray(clone.__getstate__()["struct"]), bytearray(state["struct"])
    got[taps] = saved[taps] = bytes(ffi.sizeof("void *"))             # the taps pointer is this process's
    assert got == saved
    np.testing.assert_array_equal(clone.weights_ahead, rtp.weights_ahead)
    for g, e in zip(clone.run_outputs(x[SAVED_AT:]), rtp.run_outputs(x[SAVED_AT:])):
        np.testing.assert_array_equal(np.asarray(g), np.asarray(e))


@pytest.mark.parametrize("fs, kind", CASES)
def test_layout_1_moves_w_h_alone_and_a_bad_layout_is_refused(fs, kind):
    from support import has_c_backend

    if not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    from wake._rtp import ffi
    from wake.rtp.fixed import FixedPointRTP
    from wake.rtp.fixed_voluntary import LAYOUT_1_SIZES, migrate_struct

    blob, _, _ = pickle.loads(DATA.read_bytes())[(fs, kind)]
    rtp = pickle.loads(blob)                                            # layout 1, migrated as it loaded
    state = rtp.__getstate__()
    new = state["struct"]
    w_h = ffi.offsetof("wake_rtp_t", "voluntary_ahead")
    before = LAYOUT_1_SIZES[1]                                         # where layout 1 held w_h
    assert before == w_h - 4
    weights = np.frombuffer(new[w_h:w_h + 4 * rtp.level], dtype=np.int32)
    np.testing.assert_array_equal(weights / 2.0**24, rtp.weights_ahead)
    assert weights.any()
    # the layout-1 bytes of this state: w_h back at its old offset, its padding after it
    size = ffi.sizeof("wake_rtp_t")
    rest = ffi.offsetof("wake_voluntary_ahead_t", "z_start") + w_h
    layout_1 = new[:before] + new[w_h:rest] + bytes(4) + new[rest:]
    assert len(layout_1) == size == LAYOUT_1_SIZES[0]
    assert migrate_struct(layout_1, 1)[:before] == new[:before]
    assert migrate_struct(layout_1, 1)[w_h:] == new[w_h:]
    assert migrate_struct(new, 2) == new
    for bad in ({"layout": 3}, {"layout": 2, "struct": new[:before]}, {"layout": 1, "struct": new[:before + 4]}):
        with pytest.raises(ValueError, match="another version of the C core.*re-create the filter"):
            FixedPointRTP.__new__(FixedPointRTP).__setstate__(dict(state, **bad))


if __name__ == "__main__" and sys.argv[1:] == ["--write"]:
    _write()
