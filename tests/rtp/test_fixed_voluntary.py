"""The voluntary motion at n + h on the C core (WAKE_RTP_VOLUNTARY_AHEAD, issue 32) against the float reference.

The reference is given the quantised configuration the C core holds (taps, w, w_h, R, q, p0) and Q15-rounded
input, so the difference is the core's arithmetic error; docs/studies/fixed_point.md's per-sample bound of the
one-step prediction (eqs. B1, B2), carried over to ``v_h = w_h' (a + d) = h_h' window + w_h' d_s + k (z - z_s)``,
bounds it.
"""

import pickle

import numpy as np
import pytest

from wake import WakeConfig
from wake.hpa import run_hpa
from wake.rtp.reference import ReferenceRTP
from wake.wavelets import filter_bank_taps

_c = pytest.importorskip("wake.rtp.fixed", reason="the C extension wake._rtp is not built")
FixedPointRTP = _c.FixedPointRTP

from fixed_point_bound import kalman_bound_step, quantized, static_bound  # noqa: E402


def signal(n, seed, amp=1.0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 100.0
    return amp * (0.6 * np.sin(2 * np.pi * 0.7 * t + rng.uniform(0, 6)) + 0.2 * np.sin(2 * np.pi * 6.0 * t)
                  + 0.02 * rng.standard_normal(n))


def fitted_weights(x, horizon, level=5):
    """``w`` and ``w_h`` of one Python HPA over ``x`` at ``horizon`` (what a WakeFilter installs)."""
    config = WakeConfig(backend="reference", horizon=horizon, level=level)
    upd = run_hpa(x, config, taps=filter_bank_taps(config.wavelet, config.level, config.mode))
    assert upd.weights_ahead is not None
    return upd.weights, upd.weights_ahead


def core_and_twin(level, w, w_h, q_ratio, p0_ratio, fs=4.0, R=0.09):
    c = FixedPointRTP(filter_bank_taps("sym3", level), w, R, q_ratio * R, p0_ratio * R, full_scale=fs)
    c.set_weights_ahead(w_h)
    ref = ReferenceRTP(c.taps, c.weights, c.measurement_noise, c.process_noise, c.initial_covariance)
    ref.set_weights_ahead(c.weights_ahead)
    return c, ref


def twin_with_bound(c, ref, x, fs):
    """Step the twin; return its ``v_h`` and the per-sample bound of ``|v_h,C - v_h|`` (physical units).

    One-step bound (tests/rtp/test_fixed_point.py): static ``2^-16 + 2^-24 + N 2^-(FIR+1)`` and the Kalman
    term ``B`` on ``z``.  For ``v_h``: the static part with ``h_h``'s taps (the output is Q23, not Q15: the
    ``2^-16`` term covers its roundings), ``|k| B`` for the error of ``z`` seen through
    ``k = w_h' w / |w|^2``, and the roundings of ``k`` (Q24) and of ``w_h' d_s`` (Q23) times ``|z - z_s|``.
    """
    w, w_h = ref.weights, ref.weights_ahead
    omega = float(w @ w)
    k = float(w_h @ w) / omega
    static = static_bound(c.n_taps, _c)
    out, bound, B, z0 = np.empty(len(x)), np.empty(len(x)), 0.0, float(w @ ref.correction)
    for i, m in enumerate(x):
        B = kalman_bound_step(ref, m, B, fs, _c)
        ref.step(m)
        out[i] = ref.last_voluntary_ahead
        moved = abs(float(w @ ref.correction) - z0) / fs
        bound[i] = static + abs(k) * B + moved * 2.0**-24 * (1.0 + 1.0 / omega) + 2.0**-23
    return out, bound * fs


@pytest.mark.parametrize("h", [2, 5, 10])
@pytest.mark.parametrize("q_ratio, p0_ratio", [(0.0, 0.0), (1e-2, 1.0), (1e-3, 0.0)])
def test_matches_the_float_reference_within_the_bound(h, q_ratio, p0_ratio):
    fs = 4.0
    x = signal(3000, seed=h, amp=1.5)
    w, w_h = fitted_weights(x[:500], h)
    c, ref = core_and_twin(5, w, w_h, q_ratio, p0_ratio, fs=fs)
    xq = quantized(x, fs)
    want, bound = twin_with_bound(c, ref, xq, fs)
    outputs = c.run_outputs(x)
    got = outputs[4]
    err = np.abs(got - want)
    assert c.saturations == 0 and c.voluntary_ahead_saturations == 0 and c.clipped == 0
    assert (err <= bound).all(), f"worst excess {np.max(err - bound):.3g} at {np.argmax(err - bound)}"
    assert err.max() > 0                       # not accidentally exact: the bound is what holds
    assert np.abs(got - outputs[0]).max() > 1e-3   # and w_h moves it: it is not the one-step prediction
    assert np.sqrt(np.mean((got - want) ** 2)) / np.ptp(want) < 1e-4


def test_the_one_step_outputs_do_not_move_with_w_h():
    x = signal(1500, seed=3)
    w, w_h = fitted_weights(x[:500], 5)
    plain = FixedPointRTP(filter_bank_taps("sym3", 5), w, 0.09, 9e-4, 0.09, full_scale=4.0)
    with_h = pickle.loads(pickle.dumps(plain))
    with_h.set_weights_ahead(w_h)
    a, b = plain.run_outputs(x), with_h.run_outputs(x)
    for row in range(4):                       # voluntary, tremor ahead, confidence, command: bit for bit
        np.testing.assert_array_equal(a[row], b[row])
    np.testing.assert_array_equal(a[4], a[0])  # without w_h the last row is the one-step prediction held
    assert np.abs(b[4] - b[0]).max() > 1e-3
    np.testing.assert_array_equal(plain.window, with_h.window)
    for mine, theirs in zip(plain._kalman_state(), with_h._kalman_state()):   # d and P
        np.testing.assert_array_equal(mine, theirs)
    assert plain.saturations == with_h.saturations


def test_set_weights_and_missing_samples_keep_it_with_the_reference():
    """A weight change restarts d_s and z_s (materialised, rounded) and missing samples predict through."""
    fs = 4.0
    x = signal(2000, seed=9)
    w, w_h = fitted_weights(x[:500], 5)
    c, ref = core_and_twin(5, w, w_h, 1e-2, 1.0, fs=fs)
    x[700:705] = np.nan
    xq = quantized(x, fs)
    got, want = np.empty(len(x)), np.empty(len(x))
    for i, m in enumerate(x):
        if i == 1000:
            w2 = np.asarray(w) * 0.9
            c.set_weights(w2, 0.09, 9e-4)
            ref.set_weights(c.weights, c.measurement_noise, c.process_noise)
        c.step(m)
        ref.step(xq[i]) if np.isfinite(m) else ref.step_missing()
        got[i], want[i] = c.last_voluntary_ahead, ref.last_voluntary_ahead
    assert np.abs(got - want).max() < 4 * 2.0**-15 * fs   # as test_set_weights_keeps_state's one-step bound


def test_a_state_round_trip_keeps_w_h_and_an_older_state_holds_the_one_step_prediction():
    x = signal(1200, seed=4)
    w, w_h = fitted_weights(x[:500], 10)
    c = FixedPointRTP(filter_bank_taps("sym3", 5), w, 0.09, 9e-4, 0.09, full_scale=4.0)
    c.set_weights_ahead(w_h)
    c.run(x[:600])
    clone = pickle.loads(pickle.dumps(c))
    np.testing.assert_array_equal(clone.weights_ahead, c.weights_ahead)
    np.testing.assert_array_equal(clone.run_outputs(x[600:]), c.run_outputs(x[600:]))
    # a state saved before the core had w_h (layout 1, the struct up to its w_h) loads and holds y
    st = c.__getstate__()
    old = dict(st, struct=st["struct"][: FixedPointRTP._STRUCT_SIZES[1]])
    del old["layout"]
    before = FixedPointRTP.__new__(FixedPointRTP)
    before.__setstate__(old)
    assert before.weights_ahead is None
    y = before.run_outputs(x[:50])
    np.testing.assert_array_equal(y[4], y[0])
    # the hand-over to another full scale carries w_h
    moved, _ = c.rescaled(8.0)
    np.testing.assert_allclose(moved.weights_ahead, c.weights_ahead)
    np.testing.assert_allclose(moved.run_outputs(x[:200])[4], c.run_outputs(x[:200])[4], atol=4 * 2.0**-15 * 8.0)


@pytest.mark.parametrize("bad, match", [([0.1] * 4, "weights must be 5 finite numbers"),
                                        ([0.1, 0.1, 0.1, 0.1, 65.0], "within ±64"),
                                        ([0.1, 0.1, np.nan, 0.1, 0.1], "finite"),
                                        (None, "cannot uninstall")])
def test_a_bad_w_h_is_refused_and_changes_nothing(bad, match):
    c = FixedPointRTP(filter_bank_taps("sym3", 5), np.full(5, 0.2), 0.09, full_scale=4.0)
    c.set_weights_ahead(np.full(5, 0.1))
    before = bytes(_c.ffi.buffer(c._state))
    with pytest.raises(ValueError, match=match):
        c.set_weights_ahead(bad)
    assert bytes(_c.ffi.buffer(c._state)) == before


def test_the_c_setter_refuses_what_the_python_side_cannot_send():
    """wake_rtp_set_voluntary_ahead itself: NULL, |w_h| > 64 (Q24) and an uninitialised struct."""
    lib, ffi = _c.lib, _c.ffi
    c = FixedPointRTP(filter_bank_taps("sym3", 3), [0.0, 0.0, 1.0], 0.09, full_scale=4.0)
    top = int(lib.WAKE_RTP_WEIGHT_MAX)
    assert lib.wake_rtp_set_voluntary_ahead(c._state, ffi.NULL) == lib.WAKE_RTP_E_NULL
    assert lib.wake_rtp_set_voluntary_ahead(c._state, ffi.new("int32_t[]", [0, top + 1, 0])) == lib.WAKE_RTP_E_WEIGHTS
    assert lib.wake_rtp_set_voluntary_ahead(c._state, ffi.new("int32_t[]", [0, -top - 1, 0])) == lib.WAKE_RTP_E_WEIGHTS
    assert not c.has_weights_ahead
    assert lib.wake_rtp_set_voluntary_ahead(c._state, ffi.new("int32_t[]", [0, top, -top])) == lib.WAKE_RTP_OK
    assert lib.wake_rtp_set_voluntary_ahead(ffi.new("wake_rtp_t *"), ffi.new("int32_t[]", 3)) == lib.WAKE_RTP_E_UNINIT
    out = ffi.new("int32_t *")                    # the instance alone (wake_voluntary_ahead.h) reads the RTP's output
    c._state.voluntary_ahead.output = -12345
    assert lib.wake_voluntary_ahead_output(ffi.addressof(c._state, "voluntary_ahead"), out) == lib.WAKE_RTP_OK
    assert out[0] == -12345 and c.last_voluntary_ahead == -12345 * c.full_scale / 2.0**23
    assert lib.wake_voluntary_ahead_output(ffi.NULL, out) == lib.WAKE_RTP_E_NULL
    c._state.voluntary_ahead.weights[0] = top + 1            # a corrupted w_h is caught by the next configuration call
    assert lib.wake_rtp_reset(c._state) == lib.WAKE_RTP_E_CORRUPT
