"""Field faults of the fixed-point path: a glitch, a quiet start, a DC jump, a huge sample.

Each stream is one a wearable meets in its first minute; the C backend must
stay within 1.2x of the float reference's tremor NRMSE on it (whole
recording and after the first window), and say when it clips.
"""

import warnings

import numpy as np
import pytest

from support import NO_CORE, has_c_backend
from wake import WakeFilter
from wake.eval.metrics import nrmse
from wake.eval.synthetic import make_signal
from wake.rtp.full_scale import FullScalePolicy, first_persistent_overflow, power_of_two_at_least, robust_peak

needs_core = pytest.mark.skipif(not has_c_backend(), reason=NO_CORE)


def _stream(kind):
    s = make_signal(5.0, seed=1, duration=60.0)
    x, vol = s.measurement.copy(), s.voluntary.copy()
    if kind == "glitch":          # one knock in the first HPA window
        x[200] = 1e5
    elif kind == "quiet":         # device at rest for the first window
        x[:500] = 0.0
        vol[:500] = 0.0
    elif kind == "nan_start":     # no data for the first window
        x[:500] = np.nan
    elif kind == "dc_jump":       # the sensor's offset jumps by 50 (far beyond 16x the first peak)
        x[3000:] += 50.0
        vol[3000:] += 50.0
    elif kind == "late_glitch":
        x[2345] = -1e5
    elif kind == "rail":          # the sensor sticks at a rail of 1e3 for 2 s
        x[2000:2200] = 1e3
    elif kind == "huge":          # one sample of 1e155 (its square overflows a float64)
        x[2500] = 1e155
    return x, vol


def _tremor_nrmse(x, vol, result, start, memory=32):
    """Tremor NRMSE over the samples that are signal.

    A glitch, a rail or a gap is neither tremor nor motion, and for the next
    ``memory`` samples (2**J, the filter bank's window) every prediction still
    holds it; those samples are left out of the score, for both backends alike.
    """
    fault = ~np.isfinite(x) | (np.abs(x) >= 5e2)
    reach = np.convolve(fault, np.ones(memory + 1), mode="full")[: x.size] > 0
    keep = ~reach
    tremor_truth = np.where(keep, x - vol, 0.0)
    tremor_est = np.where(keep, x - result.voluntary, 0.0)
    return nrmse(tremor_truth[start:], tremor_est[start:])


@needs_core
@pytest.mark.parametrize("kind", ["glitch", "quiet", "nan_start", "dc_jump", "late_glitch", "rail", "huge"])
def test_c_path_survives_what_the_reference_survives(kind):
    x, vol = _stream(kind)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = WakeFilter(fs=100.0).run(x)
        ref = WakeFilter(fs=100.0, backend="reference").run(x)
    for start in (0, 500):  # whole recording, and after the first window
        e_c, e_ref = _tremor_nrmse(x, vol, c, start), _tremor_nrmse(x, vol, ref, start)
        assert e_c <= 1.2 * e_ref, (kind, start, e_c, e_ref)
    assert np.isfinite(c.voluntary).all() and np.isfinite(c.prediction).all()
    # the prediction is alive to the end (the old policy left it exactly 0 after a glitch)
    assert np.std(c.voluntary[-1000:]) > 0.1 * np.std(vol[-1000:])


@needs_core
def test_one_glitch_does_not_set_the_full_scale():
    x, _ = _stream("glitch")
    r = WakeFilter(fs=100.0).run(x)
    peak = robust_peak(x[:500])
    assert r.full_scale[0] == power_of_two_at_least(16.0 * peak) < 1e3


@needs_core
def test_dc_jump_raises_the_full_scale_within_a_few_samples():
    x, _ = _stream("dc_jump")
    f = WakeFilter(fs=100.0)
    f.update_block(x[:2999])
    before = f._channels[0].rtp.full_scale
    y = f.update_block(x[2999:3200])
    assert before < 50
    assert f._channels[0].rtp.full_scale >= 16 * 50 and f._channels[0].rtp.full_scale_changes == 1
    assert f.rtp_states[0].clipped <= 4          # the samples of the run that raised it
    assert abs(y[-1] - x[3199]) < 10             # the prediction follows the new level


@needs_core
def test_a_fixed_full_scale_stays_and_clipping_warns_at_the_next_hpa():
    x = make_signal(5.0, seed=1, duration=12.0).measurement
    f = WakeFilter(fs=100.0, full_scale=0.25)
    with pytest.warns(RuntimeWarning, match=r"clipped at the fixed-point full scale ±0.25 \(raise full_scale"):
        f.update_block(x)
    assert f._channels[0].rtp.full_scale == 0.25 and f._channels[0].rtp.full_scale_changes == 0
    assert any("clipping" in u.flags for u in f._channels[0].updates)


@needs_core
def test_update_and_update_block_agree_across_a_raise():
    x, _ = _stream("dc_jump")
    x = x[2900:3100]
    a = WakeFilter(fs=100.0, window_s=1.0)
    b = WakeFilter(fs=100.0, window_s=1.0)
    ya = a.update_block(x)
    yb = np.array([b.update(v) for v in x])
    np.testing.assert_array_equal(ya, yb)
    assert a._channels[0].rtp.full_scale == b._channels[0].rtp.full_scale
    assert a.rtp_states[0].clipped == b.rtp_states[0].clipped


@needs_core
def test_quiet_start_waits_for_a_window_with_signal():
    x, _ = _stream("quiet")
    f = WakeFilter(fs=100.0)
    f.update_block(x[:700])
    assert not f._channels[0].rtp.on_c          # no full scale from a window of zeros
    f.update_block(x[700:1001])
    assert f._channels[0].rtp.on_c and f._channels[0].rtp.full_scale == power_of_two_at_least(16 * robust_peak(x[501:1001]))


@needs_core
def test_full_scale_falls_only_after_two_quiet_windows():
    s = make_signal(5.0, seed=2, duration=40.0)
    x = s.measurement * np.where(np.arange(s.measurement.size) < 1500, 1.0, 1e-3)
    f = WakeFilter(fs=100.0)
    f.update_block(x[:2001])                       # windows end at 500, 1000, 1500, 2000: one quiet window so far
    high = f._channels[0].rtp.full_scale
    f.update_block(x[2001:2600])          # the second quiet window ends at 2500
    low = f._channels[0].rtp.full_scale
    assert low <= high / 256
    flags = [u.flags for u in f._channels[0].updates]
    assert any("full_scale_lowered" in fl for fl in flags)


@needs_core
def test_huge_samples_clip_and_count_the_same_way_one_by_one_and_in_blocks():
    x = make_signal(5.0, seed=3, duration=12.0).measurement.copy()
    x[700] = 1e307
    x[900] = -1e154
    a, b = WakeFilter(fs=100.0), WakeFilter(fs=100.0)
    ya = a.update_block(x)
    yb = np.array([b.update(v) for v in x])
    np.testing.assert_array_equal(ya, yb)
    assert a.rtp_states[0].clipped == b.rtp_states[0].clipped == 2
    assert np.isfinite(ya).all()
    # the HPA after the huge sample saw a window without it: finite weights, sensible noise
    upd = a._channels[0].updates[-1]
    assert np.isfinite(upd.weights).all() and np.isfinite(upd.measurement_noise)


def test_policy_rules():
    p = FullScalePolicy(headroom=16.0)
    quiet, loud = np.zeros(100), np.full(100, 3.0)
    assert p.decide(None, quiet) == (None, None)
    assert p.decide(None, loud) == (64.0, "full_scale_set")
    assert p.decide(64.0, loud * 2) == (128.0, "full_scale_raised")
    small = loud / 100
    assert p.decide(64.0, small) == (64.0, None)                     # one small window: hysteresis
    assert p.decide(64.0, small) == (0.5, "full_scale_lowered")      # the second one
    assert p.decide(64.0, loud / 4) == (64.0, None)                  # within 16x: stays
    glitchy = loud.copy()
    glitchy[5] = 1e9
    assert p.target(glitchy) == 64.0


def test_persistent_overflow_runs_carry_across_blocks():
    assert first_persistent_overflow(np.array([5.0, 5.0, 5.0]), 1.0) == (3, 3)
    assert first_persistent_overflow(np.array([5.0]), 1.0, carried=3) == (0, 4)
    assert first_persistent_overflow(np.array([5.0, np.nan, 5.0, 5.0]), 1.0, carried=2) == (4, 2)
    assert first_persistent_overflow(np.array([0.5]), 1.0, carried=3) == (1, 0)
