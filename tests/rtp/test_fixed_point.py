"""The fixed-point C core (wake._rtp via wake.rtp.fixed) against the float reference.

The reference is always given the *quantised* configuration the C core holds
(``FixedPointRTP.taps`` etc.) and Q15-rounded input, so the comparison
measures the core's arithmetic error, which docs/studies/fixed_point.md bounds.
"""

import glob
import os
import shutil
import subprocess

import numpy as np
import pytest

from wake.rtp.reference import ReferenceRTP
from wake.wavelets import filter_bank_taps

_c = pytest.importorskip("wake.rtp.fixed", reason="the C extension wake._rtp is not built")
FixedPointRTP = _c.FixedPointRTP
P_FRAC = _c.P_FRAC

LSB15 = 2.0**-15
from support import CSRC
import fixed_point_bound
from fixed_point_bound import kalman_bound_step, quantized
REPO = str(CSRC.parent)
CSRC = os.path.join(REPO, "csrc")


# -- helpers ---------------------------------------------------------------
def make_weights(rng, level, spread=0.5):
    """Random HPA-like weights with unit DC gain (sum w = 1)."""
    w = rng.uniform(-spread, spread, level)
    w[-1] += 1.0 - w.sum()
    return w


def smooth_signal(n, rng, amp=1.0, fs_hz=100.0):
    t = np.arange(n) / fs_hz
    return amp * (0.6 * np.sin(2 * np.pi * 0.7 * t + rng.uniform(0, 6)) + 0.2 * np.sin(2 * np.pi * 6.0 * t)) + 0.02 * amp * rng.standard_normal(n)


def twin(c):
    """Float reference with exactly the C core's quantised configuration."""
    return ReferenceRTP(c.taps, c.weights, c.measurement_noise, c.process_noise, c.initial_covariance)


def static_bound(c):
    """docs/studies/fixed_point.md, eq. (B1), in full-scale units (:func:`fixed_point_bound.static_bound`)."""
    return fixed_point_bound.static_bound(c.n_taps, _c)


def reference_with_bound(c, x, fs):
    """Step a twin sample by sample; return its output and the per-sample bound (FS units).

    Kalman term, docs/studies/fixed_point.md eq. (B2): B <- (1 - g) B + rho with
    g = w'Pw / S and rho = sum|w| 2^-24 + |e| (sum|w|)^2 4 LSB_P / S.
    """
    ref = twin(c)
    sb = static_bound(c)
    out = np.empty(len(x))
    bound = np.empty(len(x))
    B = 0.0
    for k, m in enumerate(x):
        if np.isnan(m):
            out[k] = ref.step_missing()
        else:
            B = kalman_bound_step(ref, m, B, fs, _c)
            out[k] = ref.step(m)
        bound[k] = sb + B
    return out, bound * fs


# -- agreement with the reference ------------------------------------------
@pytest.mark.parametrize("level", [3, 4, 5, 6])
@pytest.mark.parametrize("wavelet", ["sym3", "db4", "haar"])
@pytest.mark.parametrize("q_ratio,p0_ratio", [(0.0, 0.0), (1e-2, 1.0), (1e-3, 0.0)])
def test_matches_reference_within_bound(level, wavelet, q_ratio, p0_ratio):
    rng = np.random.default_rng(level * 100 + len(wavelet) + int(q_ratio * 1e4))
    fs = 4.0
    x = smooth_signal(3000, rng, amp=1.5)
    R = (0.2 * 1.5) ** 2
    c = FixedPointRTP(filter_bank_taps(wavelet, level), make_weights(rng, level), R, q_ratio * R, p0_ratio * R, full_scale=fs)
    xq = quantized(x, fs)
    y_ref, bound = reference_with_bound(c, xq, fs)
    y_c = c.run(x)
    err = np.abs(y_c - y_ref)
    assert c.saturations == 0 and c.clipped == 0
    assert (err <= bound).all(), f"worst excess {np.max(err - bound):.3g} at {np.argmax(err - bound)}"
    # the bound is tight to within a few LSB: the C core is not accidentally exact
    assert err.max() < bound.max()
    # root-mean-square difference over the reference's output range
    n_c = np.sqrt(np.mean((y_c - y_ref) ** 2)) / np.ptp(y_ref)
    assert n_c < 1e-4   # C vs reference: far below 1 % of the output range


@pytest.mark.parametrize("level", [3, 5, 6])
def test_nrmse_within_one_percent_of_reference(level):
    """NRMSE of the C prediction against the true voluntary motion is within 1 % relative of the reference's."""
    rng = np.random.default_rng(7 + level)
    fs = 3.0
    n = 4000
    t = np.arange(n) / 100.0
    voluntary = 0.8 * np.sin(2 * np.pi * 0.5 * t) + 0.3 * np.sin(2 * np.pi * 1.1 * t + 1)
    x = voluntary + 0.25 * np.sin(2 * np.pi * 6.0 * t) + 0.01 * rng.standard_normal(n)
    R = 0.25**2 / 2
    c = FixedPointRTP(filter_bank_taps("sym3", level), make_weights(rng, level, 0.3), R, 1e-3 * R, R, full_scale=fs)
    ref = ReferenceRTP(filter_bank_taps("sym3", level), c.weights, R, 1e-3 * R, R)   # unquantised float pipeline
    y_c, y_r = c.run(x), ref.run(x)
    truth = voluntary[1:]               # y(n) predicts the voluntary motion at n + 1
    e_c = np.sqrt(np.mean((y_c[:-1] - truth) ** 2)) / np.ptp(truth)
    e_r = np.sqrt(np.mean((y_r[:-1] - truth) ** 2)) / np.ptp(truth)
    assert abs(e_c - e_r) <= 0.01 * e_r, (e_c, e_r)


def test_single_step_and_run_agree():
    rng = np.random.default_rng(3)
    taps = filter_bank_taps("sym3", 5)
    w = make_weights(rng, 5)
    a = FixedPointRTP(taps, w, 0.01, 1e-5, 0.01, full_scale=2.0)
    b = FixedPointRTP(taps, w, 0.01, 1e-5, 0.01, full_scale=2.0)
    x = smooth_signal(500, rng)
    x[[10, 11, 200, 499]] = np.nan
    y_run = a.run(x)
    y_step = np.array([b.step(v) for v in x])
    np.testing.assert_array_equal(y_run, y_step)
    np.testing.assert_array_equal(a.covariance, b.covariance)


# -- adversarial inputs, saturation, clipping -------------------------------
def _adversarial(kind, n=2000):
    k = np.arange(n)
    if kind == "step":
        return np.where(k < n // 2, -1.0, 1.0) * (1 - 2**-15)
    if kind == "square":
        return np.where((k // 13) % 2 == 0, -1.0, 1.0) * (1 - 2**-15)
    if kind == "silence":
        return np.zeros(n)
    if kind == "spike":
        x = np.zeros(n)
        x[[100, 101, 700, 1500]] = [1.0 - 2**-15, -1.0, 0.5, 1.0 - 2**-15]
        return x
    raise ValueError(kind)


@pytest.mark.parametrize("kind", ["step", "square", "silence", "spike"])
@pytest.mark.parametrize("active", [False, True])
def test_adversarial_inputs(kind, active):
    rng = np.random.default_rng(11)
    level, fs = 5, 1.0
    R = 1e-2
    c = FixedPointRTP(filter_bank_taps("db4", level), make_weights(rng, level), R, 1e-2 * R if active else 0.0,
                      R if active else 0.0, full_scale=fs)
    x = _adversarial(kind)
    y_ref, bound = reference_with_bound(c, quantized(x, fs), fs)
    y_c = c.run(x)
    over = np.abs(y_ref) >= 1.0 - 2**-15
    if over.any():
        # the reference leaves full scale: the C output pins at the rails and counts it
        assert c.saturations > 0
        assert np.all(np.abs(y_c[over]) >= 1.0 - 2**-14)
    else:
        assert c.saturations == 0
    # until the first excursion beyond full scale, the bound holds sample by sample
    first = np.argmax(over) if over.any() else len(x)
    err = np.abs(y_c - y_ref)[:first]
    assert (err <= bound[:first]).all()
    if kind == "silence":
        assert np.all(y_c == 0.0)


def test_full_scale_square_wave_saturates_and_counts():
    level = 4
    w = np.array([10.0, -10.0, 10.0, -9.0])     # gain far above 1: must leave full scale
    c = FixedPointRTP(filter_bank_taps("sym3", level), w, 1e-3, full_scale=1.0)
    y = c.run(_adversarial("square"))
    assert c.saturations > 0
    assert y.max() == pytest.approx(1.0 - 2**-15) and y.min() == -1.0
    c.reset()
    assert c.saturations == 0


def test_clipping_is_counted_and_matches_clipped_reference():
    rng = np.random.default_rng(5)
    fs = 1.0
    c = FixedPointRTP(filter_bank_taps("sym3", 3), make_weights(rng, 3, 0.2), 1e-2, 1e-4, 1e-2, full_scale=fs)
    x = 0.5 * smooth_signal(1000, rng)
    x[[50, 300, 301, 900]] = [1.7, -3.0, 2.0, 1.0]   # 1.0 is just above the largest Q15 value
    y_c = c.run(x)
    assert c.clipped == 4
    y_ref, bound = reference_with_bound(c, quantized(x, fs), fs)
    assert (np.abs(y_c - y_ref) <= bound).all()
    c.step(5.0)
    assert c.clipped == 5


# -- missing samples ---------------------------------------------------------
def test_missing_samples():
    rng = np.random.default_rng(9)
    fs, level = 2.0, 4
    c = FixedPointRTP(filter_bank_taps("sym3", level), make_weights(rng, level, 0.3), 0.02, 2e-4, 0.02, full_scale=fs)
    assert c.step_missing() == 0.0 and not c.primed        # before the first sample: nothing
    x = smooth_signal(1500, rng)
    x[::17] = np.nan
    x[600:603] = np.nan
    y_ref, bound = reference_with_bound(c, quantized(x, fs), fs)
    y_c = c.run(x)
    # each stand-in enters the C window rounded to Q15 (the reference keeps it exact):
    # docs/studies/fixed_point.md eq. (B3) adds sum_j |w_j| sum_i |B_ji| 2^-16 per stand-in in the window
    taps = c.taps
    per = float(np.abs(c.weights) @ np.abs(taps).sum(axis=1)) * 2.0**-16 * fs
    in_window = np.convolve(np.isnan(x).astype(float), np.ones(c.n_taps))[: len(x)]
    extra = per * in_window * 4     # feedback through the innovation: factor <= 4 over this run (measured < 2)
    err = np.abs(y_c - y_ref)
    assert (err <= bound + extra).all()
    assert np.isnan(x).sum() > 0 and err.max() > 0


# -- state hand-over ---------------------------------------------------------
def test_load_state_round_trip():
    rng = np.random.default_rng(21)
    fs, level = 2.0, 5
    taps = filter_bank_taps("sym3", level)
    w = make_weights(rng, level)
    R = 0.03
    x = smooth_signal(3000, rng)
    # float warm-up on the reference, hand over to C
    ref = ReferenceRTP(taps, w, R, 1e-2 * R, R)
    ref.run(quantized(x[:1000], fs))
    c = FixedPointRTP(taps, w, R, 1e-2 * R, R, full_scale=fs)
    window = np.concatenate((ref.buffer[ref.head:], ref.buffer[: ref.head]))
    c.load_state(window, ref.correction, ref.covariance, ref.last_output)
    np.testing.assert_allclose(c.window, window, atol=fs * 2**-16)
    np.testing.assert_allclose(c.correction, ref.correction, atol=fs * 2**-24)
    # of P the core keeps its variance along w (docs/studies/fixed_point.md): P restarts as (w'Pw / w'w) I
    P_ref = ref.covariance.reshape(level, level)
    wq = c.weights
    lam = wq @ P_ref @ wq / (wq @ wq)
    np.testing.assert_allclose(c.covariance.reshape(level, level), lam * np.eye(level), atol=2 * fs**2 * 2.0**-P_FRAC)
    assert c.last_output == pytest.approx(ref.last_output, abs=fs * 2**-24)
    # continue both: the same accuracy as a cold start (plus the quantisation of taps and weights)
    y_c = c.run(x[1000:])
    y_r = ref.run(quantized(x[1000:], fs))
    assert np.abs(y_c - y_r).max() < 4 * LSB15 * fs
    # C -> C: reading the state back and loading it into a fresh instance continues identically
    d = FixedPointRTP(taps, w, R, 1e-2 * R, R, full_scale=fs)
    d.load_state(c.window, c.correction, c.covariance, c.last_output)
    np.testing.assert_array_equal(c.run(x[:500]), d.run(x[:500]))


@pytest.mark.parametrize("weight", [0.004530577744975932, 1e-3, 0.02])
def test_a_state_read_after_tiny_weights_loads_again(weight):
    # with |w| << 1, |w|^2 in Q24 has few bits and the covariance form once read P_ii = -25 LSB back,
    # which load_state refuses: a saved state that could not be restored
    c = FixedPointRTP([[0.0, 0.0]], [6.0], 2**-8, 0.0, 1e-4, full_scale=1.0)
    c.run(np.tile([1.0, -1.0], 10))
    c.set_weights([weight], 2**-8, 0.0)
    P = c.covariance
    assert (np.diag(P.reshape(1, 1)) >= 0).all()
    d = FixedPointRTP([[0.0, 0.0]], [weight], 2**-8, 0.0, 1e-4, full_scale=1.0)
    d.load_state(c.window, c.correction, P, c.last_output)
    x = np.sin(np.arange(50.0))
    np.testing.assert_allclose(d.run(x), c.run(x), atol=2**-14)


def test_set_weights_keeps_state():
    rng = np.random.default_rng(4)
    fs, level = 2.0, 4
    taps = filter_bank_taps("db4", level)
    c = FixedPointRTP(taps, make_weights(rng, level), 0.02, 2e-4, 0.02, full_scale=fs)
    ref = twin(c)
    x = smooth_signal(2000, rng)
    c.run(x[:1000])
    ref.run(quantized(x[:1000], fs))
    before = (c.window.copy(), c.correction.copy(), c.covariance.copy(), c.last_output)
    w2 = make_weights(rng, level)
    c.set_weights(w2, 0.05, 1e-4)
    np.testing.assert_array_equal(c.window, before[0])
    np.testing.assert_array_equal(c.correction, before[1])
    assert c.last_output == before[3]
    ref.set_weights(c.weights, c.measurement_noise, c.process_noise)
    # P restarted as (w'Pw / w'w) I with the old w, in the core as in the reference
    np.testing.assert_allclose(c.covariance, ref.covariance, atol=4 * fs**2 * 2.0**-P_FRAC)
    assert np.ptp(np.diag(before[2].reshape(level, level))) > 100 * fs**2 * 2.0**-P_FRAC
    y_c = c.run(x[1000:])
    y_r = ref.run(quantized(x[1000:], fs))
    assert np.abs(y_c - y_r).max() < 4 * LSB15 * fs
    c.set_weights(w2, 0.05)       # process noise kept when omitted
    assert c.process_noise == pytest.approx(1e-4, rel=1e-4)


def test_instances_independent():
    rng = np.random.default_rng(8)
    taps = filter_bank_taps("sym3", 5)
    w = make_weights(rng, 5)
    a = FixedPointRTP(taps, w, 0.02, 1e-4, 0.02, full_scale=2.0)
    alone = FixedPointRTP(taps, w, 0.02, 1e-4, 0.02, full_scale=2.0)
    other = FixedPointRTP(filter_bank_taps("db4", 3), make_weights(rng, 3), 0.4, 0.01, 0.4, full_scale=1.0)
    x = smooth_signal(1000, rng)
    ya = []
    for v in x:
        ya.append(a.step(v))
        other.step(rng.uniform(-3, 3))
    np.testing.assert_array_equal(np.array(ya), alone.run(x))
    assert other.clipped > 0 and a.clipped == 0


# -- bad inputs -------------------------------------------------------------
def test_bad_inputs():
    taps = filter_bank_taps("sym3", 3)
    with pytest.raises(ValueError, match=r"±64 in Q24"):
        FixedPointRTP(taps, [0, 0, 65], 1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="sum of \\|taps\\| must be below 2.0"):
        FixedPointRTP(np.where(np.arange(8) < 3, 0.9, 0.0) * np.ones((3, 1)), [0, 0, 1], 1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="within ±1"):
        FixedPointRTP(np.where(np.arange(8) == 7, 1.0, 0.0) * np.ones((3, 1)), [0, 0, 1], 1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="levels 1..6"):
        FixedPointRTP(np.full((7, 128), 1 / 256), np.ones(7) / 7, 1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="shape"):
        FixedPointRTP(np.ones((3, 7)), [0, 0, 1], 1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="measurement_noise R must be finite and > 0"):
        FixedPointRTP(taps, [0, 0, 1], 0.0, full_scale=1.0)
    with pytest.raises(ValueError, match="rounds to zero"):
        FixedPointRTP(taps, [0, 0, 1], 1e-3, 1e-12, full_scale=1.0)
    with pytest.raises(ValueError, match=r"within \[0, "):
        FixedPointRTP(taps, [0, 0, 1], 1.0, full_scale=1.0)
    with pytest.raises(ValueError, match="full_scale"):
        FixedPointRTP(taps, [0, 0, 1], 1e-3, full_scale=0.0)
    with pytest.raises(ValueError, match="3 finite numbers"):
        FixedPointRTP(taps, [0, 1], 1e-3, full_scale=1.0)
    c = FixedPointRTP(taps, [0, 0, 1], 1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="±64"):
        c.set_weights([100, 0, 0], 1e-3)
    np.testing.assert_array_equal(c.weights, [0, 0, 1])   # unchanged after the error
    with pytest.raises(ValueError, match="window"):
        c.load_state(np.zeros(5), np.zeros(3), np.zeros(9), 0.0)
    with pytest.raises(ValueError, match="diagonal"):
        c.load_state(np.zeros(8), np.zeros(3), -np.eye(3) * 1e-3, 0.0)
    with pytest.raises(ValueError, match="correction must lie within"):
        c.load_state(np.zeros(8), [1e3, 0, 0], np.zeros(9), 0.0)


def test_corrupted_struct_raises():
    c = FixedPointRTP(filter_bank_taps("sym3", 3), [0, 0, 1], 1e-3, full_scale=1.0)
    c._state.magic = 0
    with pytest.raises(RuntimeError, match="uninitialised"):
        c.step(0.1)
    c._state.magic = _c.lib.WAKE_RTP_MAGIC if hasattr(_c.lib, "WAKE_RTP_MAGIC") else 0x57414B45
    c._state.head = 999
    with pytest.raises(RuntimeError, match="corrupted"):
        c.run(np.zeros(4))


# -- exported header, compiled with the C library ---------------------------
@pytest.mark.skipif(shutil.which("gcc") is None and shutil.which("cc") is None, reason="no C compiler on PATH")
def test_export_header_compiles_and_matches(tmp_path):
    from wake.firmware.export import export_header

    cc = shutil.which("gcc") or shutil.which("cc")
    rng = np.random.default_rng(12)
    level, fs = 5, 2.5
    w = make_weights(rng, level)
    R, q, p0 = 0.02, 2e-4, 0.01
    export_header(tmp_path / "wake_config.h", wavelet="sym3", level=level, weights=w,
                  measurement_noise=R, process_noise=q, initial_covariance=p0, full_scale=fs)
    c = FixedPointRTP(filter_bank_taps("sym3", level), w, R, q, p0, full_scale=fs)
    x = smooth_signal(400, rng)
    x_q = np.round(x / fs * 32768).astype(int)
    prog = tmp_path / "main.c"
    prog.write_text(
        """#include <stdio.h>
#include "wake_rtp.h"
#include "wake_config.h"
static const int16_t input[] = {%s};
int main(void) {
    wake_rtp_t s; int16_t y; unsigned i;
    printf("%%d %%d %%ld %%ld %%ld\\n", WAKE_CONFIG_LEVEL, WAKE_CONFIG_N_TAPS,
           (long)WAKE_CONFIG_R, (long)WAKE_CONFIG_Q, (long)WAKE_CONFIG_P0);
    for (i = 0; i < WAKE_CONFIG_LEVEL * WAKE_CONFIG_N_TAPS; ++i) printf("%%d ", wake_config_taps[i]);
    printf("\\n");
    for (i = 0; i < WAKE_CONFIG_LEVEL; ++i) printf("%%ld ", (long)wake_config_weights[i]);
    printf("\\n");
    if (wake_rtp_init(&s, WAKE_CONFIG_LEVEL, wake_config_taps, wake_config_weights,
                      WAKE_CONFIG_R, WAKE_CONFIG_Q, WAKE_CONFIG_P0) != WAKE_RTP_OK) return 2;
    for (i = 0; i < sizeof(input) / sizeof(input[0]); ++i) {
        if (wake_rtp_step(&s, input[i], &y) != WAKE_RTP_OK) return 3;
        printf("%%d ", y);
    }
    printf("\\n");
    return 0;
}
"""
        % ", ".join(str(v) for v in x_q)
    )
    exe = tmp_path / "main"
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-I", str(tmp_path), "-I", CSRC,
                    str(prog), *sorted(glob.glob(os.path.join(CSRC, "wake_rtp*.c"))), "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout.splitlines()
    head = [int(v) for v in out[0].split()]
    assert head[:2] == [level, 2**level]
    assert head[2] == round(R / fs**2 * 2**P_FRAC)
    assert head[3] == round(q / fs**2 * 2**P_FRAC)
    assert head[4] == round(p0 / fs**2 * 2**P_FRAC)
    np.testing.assert_array_equal(np.array(out[1].split(), dtype=int), np.round(filter_bank_taps("sym3", level) * 2**15).ravel())
    np.testing.assert_array_equal(np.array(out[2].split(), dtype=int), np.round(w * 2**24))
    y_fw = np.array(out[3].split(), dtype=int) / 32768 * fs
    np.testing.assert_array_equal(y_fw, c.run(x))       # firmware == Python wrapper, bit for bit


def test_export_header_rejects_bad_values(tmp_path):
    from wake.firmware.export import export_header

    with pytest.raises(ValueError, match="±64"):
        export_header(tmp_path / "x.h", wavelet="sym3", level=3, weights=[0, 0, 100],
                      measurement_noise=1e-3, full_scale=1.0)
    with pytest.raises(ValueError, match="C identifier"):
        export_header(tmp_path / "x.h", wavelet="sym3", level=3, measurement_noise=1e-3, full_scale=1.0, name="1bad")


def test_highest_level_is_defined_once():
    """The C struct's WAKE_RTP_MAX_LEVEL is the package's MAX_LEVEL (wake.config)."""
    from wake.config import MAX_LEVEL

    assert _c.MAX_LEVEL == MAX_LEVEL


def test_first_sample_gets_only_the_time_update():
    """The first sample primes the window and had no prediction before it: no measurement update, so P
    grows from p0 I to (p0 + q) I and d stays 0, in the C core and the float reference alike (the
    choice keeps the priming off the Kalman path of wake_rtp_step's static bound; docs/studies/design.md)."""
    rng = np.random.default_rng(4)
    level, fs = 4, 2.0
    w = make_weights(rng, level, 0.3)
    r, q, p0 = 0.02, 2e-4, 0.02
    c = FixedPointRTP(filter_bank_taps("sym3", level), w, r, q, p0, full_scale=fs)
    ref = ReferenceRTP(filter_bank_taps("sym3", level), w, r, q, p0)
    c.step(0.7)
    ref.step(0.7)
    np.testing.assert_allclose(ref.covariance.reshape(level, level), (p0 + q) * np.eye(level), rtol=1e-12)
    np.testing.assert_allclose(c.covariance.reshape(level, level), (p0 + q) * np.eye(level), rtol=1e-3, atol=1e-9)
    assert not np.any(ref.correction) and not np.any(c.correction)
    c.step(0.9)                                     # the second sample is measured: P shrinks along w
    ref.step(0.9)
    assert np.trace(ref.covariance.reshape(level, level)) < level * (p0 + 2 * q)
    np.testing.assert_allclose(c.covariance, ref.covariance, rtol=2e-3, atol=1e-8)


def test_a_state_pickled_with_another_struct_layout_is_refused():
    """A pickle from a core whose wake_rtp_t differs (e.g. before the covariance restart) must not be loaded."""
    import pickle

    rng = np.random.default_rng(8)
    c = FixedPointRTP(filter_bank_taps("sym3", 4), make_weights(rng, 4), 0.02, 2e-4, 0.02, full_scale=2.0)
    c.run(smooth_signal(200, rng))
    st = c.__getstate__()
    clone = pickle.loads(pickle.dumps(c))
    np.testing.assert_array_equal(clone.run(np.zeros(10)), c.run(np.zeros(10)))
    old = dict(st, struct=st["struct"] + bytes(8))
    with pytest.raises(ValueError, match="another version of the C core"):
        FixedPointRTP.__new__(FixedPointRTP).__setstate__(old)
