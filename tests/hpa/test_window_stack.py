"""The HPA's window-only steps on a stack of windows (issue 44's batch path) against each window alone: the
same numbers, bit for bit, not close ones."""

import numpy as np
import pytest

from support import motion
from wake import WakeConfig, WakeFilter
from wake.hpa.run import analyse_windows, finish_hpa, run_hpa
from wake.hpa.spectrum import levinson_durbin
from wake.wavelets import filter_bank_taps

FIELDS = ("x", "silent", "cutoff", "flag", "tremor_gt", "voluntary_gt", "measurement_noise", "outputs", "weights",
          "fit_error", "ridge", "shrink")


def _same(a, b):
    for name in FIELDS:
        u, v = getattr(a, name), getattr(b, name)
        if isinstance(u, np.ndarray) or isinstance(v, np.ndarray):
            np.testing.assert_array_equal(u, v, err_msg=name)
        else:
            assert u == v and type(u) is type(v), (name, u, v)


def _windows(fs, kind, n):
    """Windows of ``n`` samples of one axis of a wrist recording, one every half window, a silent one among them."""
    x = motion(fs, kind, seconds=30.0)[0][:, 2 if kind == "acc" else 0]
    rows = [x[k : k + n] for k in range(0, x.size - n + 1, n // 2)][:12]
    rows.insert(3, np.full(n, rows[0][0]))   # no spread: the HPA keeps what it has
    return np.array(rows)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_a_stack_gives_each_window_its_own_numbers(fs, kind):
    config = WakeConfig(fs=fs)
    taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    for n in (config.window_samples, int(1.5 * fs)):   # a full window, and a warm-up one
        stack = _windows(fs, kind, n)
        together = analyse_windows(stack, config, taps=taps)
        assert [a.silent for a in together].count(True) == 1
        for row, a in zip(stack, together):
            _same(a, analyse_windows(row[None], config, taps=taps)[0])
            # and the update finished from it is run_hpa's on that window
            upd = finish_hpa(a, config, previous_weights=np.full(config.level, 0.2), index=n,
                             previous_ahead=np.full(8, 0.1), new_samples=n // 2)
            ref = run_hpa(row, config, taps=taps, previous_weights=np.full(config.level, 0.2), index=n,
                          previous_ahead=np.full(8, 0.1), new_samples=n // 2)
            for name in ("cutoff", "cutoff_flag", "measurement_noise", "fit_error", "ridge", "flags", "ahead_gain",
                         "ahead_goal"):
                assert getattr(upd, name) == getattr(ref, name), name
            np.testing.assert_array_equal(upd.weights, ref.weights)
            np.testing.assert_array_equal(upd.ahead_coefficients, ref.ahead_coefficients)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_windows_of_many_lengths_at_once_give_each_its_own_numbers(fs, kind):
    """The batch path's block: the warm-up windows (1 to 4 s, each its own length) beside full ones, a silent one
    among them, analysed in one call; each window's analysis, and the update finished from it, bit for bit its
    own; the spectra and the weight fits of such a list of stacks too."""
    from wake.hpa.fit import fit_stacks, fit_weights
    from wake.hpa.spectrum import ar_psd, ar_psds

    config = WakeConfig(fs=fs)
    taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    x = motion(fs, kind, seconds=30.0)[0][:, 2 if kind == "acc" else 0]
    L = config.window_samples
    windows = [x[: int(k * fs)] for k in (1, 2, 3, 4)] + [x[k : k + L] for k in range(0, 4 * L, L // 2)]
    windows.insert(6, np.full(L, x[0]))   # no spread: the HPA keeps what it has
    windows.insert(2, x[100 : 100 + int(2 * fs)])   # a second window of 2 s
    together = analyse_windows(windows, config, taps=taps)
    assert len(together) == len(windows) and [a.silent for a in together].count(True) == 1
    previous = np.full(config.level, 0.2)
    for window, a in zip(windows, together):
        _same(a, analyse_windows(window[None], config, taps=taps)[0])
        upd = finish_hpa(a, config, previous_weights=previous, index=window.size, previous_ahead=np.full(8, 0.1),
                         new_samples=window.size // 2)
        ref = run_hpa(window, config, taps=taps, previous_weights=previous, index=window.size,
                      previous_ahead=np.full(8, 0.1), new_samples=window.size // 2)
        for name in ("cutoff", "cutoff_flag", "measurement_noise", "fit_error", "ridge", "flags", "ahead_gain",
                     "ahead_goal"):
            assert getattr(upd, name) == getattr(ref, name), name
        np.testing.assert_array_equal(upd.ahead_coefficients, ref.ahead_coefficients)
    full = [w for w in windows if w.size == L and np.ptp(w) > 0][:3]
    stacks = [windows[0][None], np.stack(full), np.stack([w for w in windows if w.size == int(2 * fs)])]
    orders = [17, 17, 9]   # two AR orders: two frequency grids of the same size
    for stack, order, (freqs, psd) in zip(stacks, orders, ar_psds(stacks, fs, orders)):
        for row, got in zip(stack, psd):
            want = ar_psd(row, fs, order)
            np.testing.assert_array_equal(freqs, want[0])
            np.testing.assert_array_equal(got, want[1])
    rows = [(a.outputs[:-1], a.voluntary_gt[taps.shape[1]:]) for a in together if not a.silent]
    w, err, used = fit_stacks([np.stack([A]) for A, _ in rows], [np.stack([y]) for _, y in rows], config.ridge)
    for i, (A, y) in enumerate(rows):
        alone = fit_weights(A, y, config.ridge)
        np.testing.assert_array_equal(w[i], alone[0])
        assert (err[i], used[i]) == alone[1:]


def test_a_list_of_windows_is_refused_unless_each_is_1d():
    config = WakeConfig()
    with pytest.raises(ValueError, match="each window must be 1-D"):
        analyse_windows([np.ones(500), np.ones((2, 500))], config)


def test_levinson_rows_stop_where_their_error_reaches_zero(rng):
    """A row whose prediction error reaches 0 stops there, the others go on: each row is the one-row recursion."""
    x = rng.standard_normal((4, 300))
    r = np.array([[np.dot(s[: s.size - k], s[k:]) / s.size for k in range(9)] for s in x])
    r[1] = [1.0, 1.0] + [1.0] * 7        # a perfectly predictable row: its error is 0 after order 1
    r[2] = 0.0                           # silent: no order at all
    a, sigma2, refl = levinson_durbin(r, 8)
    assert sigma2[1] == 0.0 and sigma2[2] == 0.0
    for i in range(4):
        one = levinson_durbin(r[i], 8)
        np.testing.assert_array_equal(a[i], one[0])
        assert sigma2[i] == one[1]
        np.testing.assert_array_equal(refl[i], one[2])


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_run_is_the_stream_with_windows_analysed_in_batches(fs, kind):
    """run() analyses its windows in batches (Channel.points); update() one at a time: the same HPA history and
    predictions, bit for bit, on the float reference and the C core."""
    x = motion(fs, kind, seconds=22.0)[0][:, 2 if kind == "acc" else 0]
    for backend in ("reference", "c") if _has_c() else ("reference",):
        batch = WakeFilter(fs=fs, backend=backend).run(x)
        stream = WakeFilter(fs=fs, backend=backend)
        pred = np.array([stream.update(float(v)) for v in x])
        np.testing.assert_array_equal(batch.prediction, pred)
        updates = stream.hpa_history[0]
        assert len(batch.hpa[0]) == len(updates) > 5
        for u, v in zip(batch.hpa[0], updates):
            assert (u.index, u.cutoff, u.measurement_noise, u.fit_error) == (v.index, v.cutoff, v.measurement_noise,
                                                                             v.fit_error)
            np.testing.assert_array_equal(u.weights, v.weights)


def _has_c():
    from wake.rtp import c_backend_available

    return c_backend_available()


@pytest.mark.parametrize("horizon", [1, 5])
def test_the_predictor_fit_of_a_stack_is_each_series_own(rng, horizon):
    """wake.ahead.fit_predictor on a stack (W, n): each row's coefficients those of its own fit, a series
    without power zeros, as alone."""
    from wake.ahead import fit_predictor

    est = rng.standard_normal((5, 480)) * rng.uniform(0.01, 100.0, (5, 1))
    truth = np.roll(est, -3, axis=1) + 0.1 * rng.standard_normal((5, 480))
    est[2] = 0.0                                    # no power: zeros
    together = fit_predictor(est, truth, horizon)
    assert together.shape == (5, 8) and not together[2].any()
    for i in range(5):
        np.testing.assert_array_equal(together[i], fit_predictor(est[i], truth[i], horizon))


@pytest.mark.parametrize("fs", [100.0, 1000.0])
@pytest.mark.parametrize("kind", ["gyro", "acc"])
def test_a_block_s_windows_are_prepared_each_as_alone(fs, kind):
    """wake.hpa.schedule.prepare_windows on windows of many lengths (a glitch in one, a gap in another, None for a
    point inside a long gap): each window and robust peak what prepare_window and robust_peak give it alone."""
    from wake.hpa.schedule import prepare_window, prepare_windows
    from wake.rtp.full_scale import robust_peak

    x = motion(fs, kind, seconds=30.0)[0][:, 2 if kind == "acc" else 0]
    L = WakeConfig(fs=fs).window_samples
    windows = [x[: int(k * fs)].copy() for k in (1, 2, 3, 4)] + [x[k : k + L].copy() for k in range(0, 5 * L, L)]
    windows[2][7] = 1e9                      # an outlier: dropped and filled
    windows.insert(3, None)
    for case in ("clean", "gap"):
        if case == "gap":
            windows[6][10:20] = np.nan       # a gap: every window goes alone
        got = prepare_windows(windows)
        for window, done in zip(windows, got):
            if window is None:
                assert done is None
                continue
            peak = robust_peak(window)
            assert done[1] == peak
            np.testing.assert_array_equal(done[0], prepare_window(window, peak))
        assert np.isfinite(got[2][0][7]) and abs(got[2][0][7]) < 1e3   # the outlier filled in
        assert got[0][0] is windows[0]       # a clean window is passed on as it is
