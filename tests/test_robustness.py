"""Robustness of the C core and the filter: fuzzing, corrupted state, a 24-hour stream."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from support import has_c_backend
from wake import WakeFilter
from wake.eval.long_stream import drifting_tremor_stream
from wake.wavelets import filter_bank_taps

pytestmark = pytest.mark.skipif(not has_c_backend(), reason="the compiled C core wake._rtp is not built")

WAVELETS = ["haar", "db2", "db3", "sym3", "db5", "sym5", "db7"]


@st.composite
def configurations(draw):
    level = draw(st.integers(1, 6))
    if draw(st.booleans()):
        taps = filter_bank_taps(draw(st.sampled_from(WAVELETS)), level)
    else:  # arbitrary taps whose rows stay inside the accepted |sum| < 2
        raw = np.array(draw(st.lists(st.floats(-0.999, 0.999), min_size=level * 2**level, max_size=level * 2**level)))
        taps = raw.reshape(level, 2**level)
        norms = np.abs(taps).sum(axis=1, keepdims=True)
        taps = np.where(norms > 1.9, taps * 1.9 / np.maximum(norms, 1e-12), taps)
    weights = draw(st.lists(st.floats(-64, 64), min_size=level, max_size=level))
    r = draw(st.floats(1e-6, 0.4))
    q = draw(st.sampled_from([0.0, 1e-8, 1e-5, 1e-2, 0.3]))
    p0 = draw(st.sampled_from([0.0, 1e-4, 0.1, 0.45]))
    return taps, weights, r, q, p0


samples = st.one_of(
    st.lists(st.floats(-3, 3, allow_nan=False), min_size=1, max_size=400).map(np.array),
    st.tuples(st.integers(1, 40), st.integers(20, 400)).map(
        lambda p: np.where((np.arange(p[1]) // p[0]) % 2 == 0, 1.0, -1.0)),  # full-scale square waves
    st.integers(10, 400).map(lambda n: np.r_[np.zeros(n // 2), np.full(n - n // 2, 0.99998)]),  # steps
    st.integers(10, 400).map(lambda n: np.eye(1, n, n // 2)[0] * 5.0),  # a single spike beyond full scale
    st.integers(1, 300).map(np.zeros),  # silence
)


def check_state(rtp):
    J = rtp.level
    P = rtp.covariance.reshape(J, J)
    assert np.array_equal(P, P.T), "covariance lost its symmetry"
    assert np.all(np.diag(P) >= 0), "covariance diagonal went negative"
    lsb = rtp.full_scale**2 / 2.0**32
    # Each entry of P is rounded on its own (wake_rtp_get_state rebuilds it from s and w, within about 1 LSB
    # each), and near a rank-deficient P a diagonal of a few LSB moves sqrt(P_ii P_jj) by many: so the bound
    # takes the diagonals' rounding (2 LSB) before the square root, not after it.
    diag = np.diag(P) + 2 * lsb
    bound = np.sqrt(np.outer(diag, diag))
    assert np.all(np.abs(P) <= bound + 2 * lsb), "an off-diagonal exceeds sqrt(P_ii P_jj)"
    assert np.all(np.isfinite(rtp.correction))


@pytest.mark.skipif(not has_c_backend(), reason="the C extension is not built (python build_ffi.py)")
def test_a_nearly_singular_covariance_passes_the_check_within_its_rounding():
    """The example the fuzz test once found: a large weight (43.75) shrinks P along w to a few LSB, where the
    entries' own rounding moved |P_12| 4 LSB past sqrt(P_11 P_22) as the diagonals stood."""
    from wake.rtp.fixed import FixedPointRTP

    taps = np.array([[0, 0, 0, 0, 0, 0, 0.5, 0.5], [0, 0, 0, 0, 0.25, 0.25, 0.25, 0.25], [0.125] * 8])
    rtp = FixedPointRTP(taps, [0.0, 43.75, 0.5], 1e-6, 0.0, 1e-4, full_scale=1.0)
    rtp.run(np.r_[np.zeros(5), np.full(5, 0.99998)])
    P = rtp.covariance.reshape(3, 3)
    lsb = 2.0**-32
    assert P[1, 1] < 100 * lsb < P[2, 2]                            # the case: one diagonal of a few dozen LSB
    assert abs(P[1, 2]) > np.sqrt(P[1, 1] * P[2, 2])                # past the bound as the diagonals stand
    check_state(rtp)                                                # within it once their rounding is counted


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(configurations(), samples, samples, st.data())
def test_fuzz_c_core(config, first, second, data):
    from wake.rtp.fixed import FixedPointRTP

    taps, weights, r, q, p0 = config
    rtp = FixedPointRTP(taps, weights, r, q, p0, full_scale=1.0)
    y = rtp.run(first)
    assert np.all(np.isfinite(y)) and np.all(np.abs(y) <= 1.0)
    check_state(rtp)
    # new HPA weights between two samples, then more input and a gap
    w2 = data.draw(st.lists(st.floats(-64, 64), min_size=len(weights), max_size=len(weights)))
    rtp.set_weights(w2, r, q)
    gap = np.r_[second, np.full(data.draw(st.integers(0, 50)), np.nan), first]
    y = rtp.run(gap)
    assert np.all(np.isfinite(y)) and np.all(np.abs(y) <= 1.0)
    check_state(rtp)
    assert rtp.clipped >= int(np.sum(np.abs(first) > 1.0))


def test_uninitialised_and_corrupted_state_is_refused():
    from wake._rtp import ffi, lib

    out = ffi.new("int16_t *")
    blank = ffi.new("wake_rtp_t *")  # zeroed: never initialised
    assert lib.wake_rtp_step(blank, 100, out) == lib.WAKE_RTP_E_UNINIT
    assert lib.wake_rtp_step_missing(blank, out) == lib.WAKE_RTP_E_UNINIT
    assert lib.wake_rtp_step(ffi.NULL, 100, out) == lib.WAKE_RTP_E_NULL
    taps = filter_bank_taps("sym3", 3)
    q_taps = ffi.new("int16_t[]", [int(round(v * 2**15)) for v in taps.ravel()])
    weights = ffi.new("int32_t[]", [0, 0, 1 << 24])
    s = ffi.new("wake_rtp_t *")
    assert lib.wake_rtp_init(s, 3, q_taps, weights, 1 << 20, 0, 0) == lib.WAKE_RTP_OK
    assert lib.wake_rtp_step(s, 1000, out) == lib.WAKE_RTP_OK
    s.level = 200  # a stray write: magic intact, fields inconsistent
    assert lib.wake_rtp_step(s, 1000, out) == lib.WAKE_RTP_E_CORRUPT
    rng = np.random.default_rng(0)
    for _ in range(200):  # random garbage: an error status, never a crash
        junk = ffi.new("wake_rtp_t *")
        ffi.memmove(junk, rng.integers(0, 256, ffi.sizeof("wake_rtp_t"), dtype=np.uint8).tobytes(),
                    ffi.sizeof("wake_rtp_t"))
        assert lib.wake_rtp_step(junk, 1, out) in (lib.WAKE_RTP_E_UNINIT, lib.WAKE_RTP_E_CORRUPT)


def test_out_of_range_configuration_is_rejected_with_a_status():
    from wake._rtp import ffi, lib

    s = ffi.new("wake_rtp_t *")
    taps = ffi.new("int16_t[]", [32767] * 8 * 3)  # each row sums |taps| to ~8: may overflow
    w = ffi.new("int32_t[]", [0, 0, 1 << 24])
    assert lib.wake_rtp_init(s, 3, taps, w, 1 << 20, 0, 0) == lib.WAKE_RTP_E_TAPS
    good = ffi.new("int16_t[]", [4096] * 8 * 3)
    assert lib.wake_rtp_init(s, 7, good, w, 1 << 20, 0, 0) == lib.WAKE_RTP_E_LEVEL
    assert lib.wake_rtp_init(s, 0, good, w, 1 << 20, 0, 0) == lib.WAKE_RTP_E_LEVEL
    big = ffi.new("int32_t[]", [0, 2**31 - 1, 0])  # 128 in Q24: beyond +-64
    assert lib.wake_rtp_init(s, 3, good, big, 1 << 20, 0, 0) == lib.WAKE_RTP_E_WEIGHTS
    assert lib.wake_rtp_init(s, 3, good, w, 0, 0, 0) == lib.WAKE_RTP_E_NOISE
    assert lib.wake_rtp_init(s, 3, good, w, 1 << 20, -1, 0) == lib.WAKE_RTP_E_NOISE
    assert lib.wake_rtp_init(s, 3, ffi.NULL, w, 1 << 20, 0, 0) == lib.WAKE_RTP_E_NULL


@settings(max_examples=40, deadline=None)
@given(level=st.integers(1, 6), window_s=st.floats(0.5, 8.0), wavelet=st.sampled_from(WAVELETS),
       ar_order=st.integers(2, 30), scale=st.sampled_from([1e-6, 1.0, 1e4]))
def test_random_filter_configurations_work_or_refuse_clearly(level, window_s, wavelet, ar_order, scale):
    try:
        f = WakeFilter(fs=100.0, level=level, window_s=window_s, wavelet=wavelet, ar_order=ar_order)
    except ValueError as exc:
        assert "window" in str(exc) or "level" in str(exc)
        return
    x = scale * np.sin(np.arange(f.window_samples * 2 + 7) * 0.05) + scale * 0.2 * np.sin(np.arange(f.window_samples * 2 + 7) * 2.1)
    res = f.run(x)
    assert np.all(np.isfinite(res.voluntary))
    assert res.clipped[0] == 0


@pytest.mark.slow
def test_24_hours_at_100_hz_on_the_c_core():
    """8.64 million samples, HPA every 5 s, a live Kalman (q > 0): the
    covariance stays symmetric, positive and bounded, nothing saturates, and
    the last hour's error equals a fresh filter's on the same hour within 5 %."""
    f = WakeFilter(backend="c", full_scale=4.0, process_noise_ratio=1e-6, initial_covariance=1e-3)
    hours = list(drifting_tremor_stream(hours=24.0, seed=3))
    assert sum(len(x) for _, x in hours) == 8_640_000
    peaks = []
    for vol, x in hours:
        y = f.update_block(x)
        rtp = f.rtp_states[0]
        check_state(rtp)
        P = rtp.covariance.reshape(rtp.level, rtp.level)
        # P is rebuilt from the constant-time form with each entry within a few LSB of the
        # exact one (docs/studies/fixed_point.md); entries within 4 LSB of a PSD matrix keep every
        # eigenvalue above -4 J LSB (the spectral norm of the perturbation is at most J max|E_ij|)
        lsb = rtp.full_scale**2 / 2.0**32
        assert np.linalg.eigvalsh(P).min() > -4 * rtp.level * lsb
        peaks.append(np.abs(P).max())
    err_long = np.sqrt(np.mean((y[:-1] - vol[1:]) ** 2))
    assert rtp.saturations == 0 and rtp.clipped == 0
    assert max(peaks) < 1.0  # bounded: P never leaves a small fraction of full scale squared
    assert peaks[-1] <= 1.5 * np.median(peaks)  # and does not creep up over the day
    fresh = WakeFilter(backend="c", full_scale=4.0, process_noise_ratio=1e-6, initial_covariance=1e-3)
    fresh.update_block(hours[-2][1])
    y_fresh = fresh.update_block(hours[-1][1])
    err_fresh = np.sqrt(np.mean((y_fresh[:-1] - vol[1:]) ** 2))
    assert abs(err_long - err_fresh) <= 0.05 * err_fresh
