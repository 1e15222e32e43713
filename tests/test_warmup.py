"""The first seconds after switch-on: start-up weights and the progressive HPA (docs/studies/design.md, "Warm-up").

The choices measured there are pinned here: the designed prior beats the
deepest approximation before the first HPA, the warm-up HPA runs at 2, 3
and 4 s beat waiting for the first full window, and together they lower the
whole-recording error on the synthetic set and on PADS without changing the
error after 5 s.
"""

import warnings

import numpy as np
import pytest

from support import NO_PADS, pads_dir
from wake import WakeConfig, WakeFilter
from wake.eval.warmup import SLICES, independent_ground_truth, mean_slices, slice_nrmse
from wake.hpa import FALLBACK_FLAGS, fit_weights, run_hpa
from wake.hpa.prior import prior_weights
from wake.wavelets import filter_bank_taps

FIRST_RELEASE = dict(warmup_hpa_s=(), initial_weights="deepest")


def _response(w, taps, f, fs):
    delays = np.arange(taps.shape[1] - 1, -1, -1)
    return np.exp(-2j * np.pi * np.outer(f, delays) / fs) @ (taps.T @ w)


def test_prior_predicts_the_voluntary_band_and_damps_tremor():
    cfg = WakeConfig()
    taps = filter_bank_taps(cfg.wavelet, cfg.level)
    w = prior_weights(cfg, taps)
    assert w.sum() == pytest.approx(1.0, abs=1e-12)       # unit gain at DC
    f = np.array([0.5, 1.0, 8.0, 10.0])
    h = _response(w, taps, f, cfg.fs)
    d = _response(np.eye(cfg.level)[-1], taps, f, cfg.fs)  # the deepest approximation alone
    # at 0.5-1 Hz the prior lags less than the deepest approximation (phase delay, samples)
    lag = lambda resp: -np.angle(resp[:2]) * cfg.fs / (2 * np.pi * f[:2])  # noqa: E731
    assert np.all(lag(h) < lag(d) - 1)
    assert np.all(np.abs(h[:2]) > 0.9)
    # and it damps 8-10 Hz tremor more than the deepest approximation does
    assert np.all(np.abs(h[2:]) < np.abs(d[2:]))


@pytest.mark.parametrize("level", [1, 3, 6])
def test_prior_exists_for_every_level(level):
    w = prior_weights(WakeConfig(level=level))
    assert w.shape == (level,) and np.isfinite(w).all()


def _slices(signals, **settings):
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for s in signals:
            v = WakeFilter(fs=s.fs, backend="reference", **settings).run(s.measurement).voluntary
            rows.append(slice_nrmse(s.voluntary, v, s.fs))
    return {k: float(np.mean([r[k] for r in rows])) for k in SLICES}


def _pads_slices(**settings):
    """Mean PADS tremor NRMSE per slice against the independent truth (reference backend)."""
    from wake.eval.datasets import load_pads_folder

    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for rec in load_pads_folder(pads_dir()):
            res = WakeFilter(fs=rec.fs, backend="reference", **settings).run(rec.samples)
            for c in range(rec.samples.shape[1]):
                _, tremor, _ = independent_ground_truth(rec.samples[:, c], rec.fs)
                rows.append(slice_nrmse(tremor, res.tremor[:, c], rec.fs))
    return {k: float(np.mean([r[k] for r in rows])) for k in SLICES}


def test_warmup_beats_the_first_release_in_every_slice_on_the_synthetic_set(paper_signals):
    now = _slices(paper_signals)
    before = _slices(paper_signals, **FIRST_RELEASE)
    for k in ("0.5-1 s", "1-2 s", "2-5 s", "whole (from 0.5 s)"):
        assert now[k] < before[k], (k, now[k], before[k])
    # the progressive HPA does the work in 2-5 s: half the error of the prior alone
    assert now["2-5 s"] < 0.6 * _slices(paper_signals, warmup_hpa_s=())["2-5 s"]
    # after 5 s nothing changes by more than 2 %
    assert now["after 5 s"] <= 1.02 * before["after 5 s"]


@pytest.mark.slow
@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_warmup_lowers_the_whole_recording_error_on_pads():
    now, before = _pads_slices(), _pads_slices(**FIRST_RELEASE)
    for k in ("0.5-1 s", "1-2 s", "2-5 s", "whole (from 0.5 s)"):
        assert now[k] < before[k], k
    assert now["after 5 s"] <= 1.02 * before["after 5 s"]


def test_schedule_of_the_warmup_hpa():
    assert WakeConfig().warmup_hpa_s == (1.0, 2.0, 3.0, 4.0)
    assert [WakeConfig().next_hpa(c) for c in (0, 100, 200, 399, 400, 500, 1000)] == [100, 200, 300, 400, 500, 1000,
                                                                                     1500]
    assert WakeConfig(window_s=2.5).warmup_hpa_s == (1.0, 2.0)      # only those before the first window
    assert WakeConfig(fs=50.0, level=6).warmup_hpa_s == (3.0, 4.0)    # 2**(J+1) = 128 samples needed
    assert WakeConfig(warmup_hpa_s=()).next_hpa(0) == 500              # the paper's schedule
    assert WakeConfig(window_s=20.0).warmup_hpa_s == (1.0, 2.0, 3.0, 4.0, 8.0, 12.0, 16.0)


@pytest.mark.parametrize("bad, match", [((0.1,), "at least 64 samples"), ((6.0,), "before the first full window"),
                                        ((3.0, 2.0), "strictly increasing"), ((float("nan"),), "finite"),
                                        (3.0, "tuple"), (("2",), "finite")])
def test_warmup_schedule_is_validated(bad, match):
    with pytest.raises(ValueError, match=match):
        WakeConfig(warmup_hpa_s=bad)


def test_initial_weights_choices_are_named():
    with pytest.raises(ValueError, match="prior, deepest"):
        WakeConfig(initial_weights="zeros")


def test_a_warmup_window_fits_with_a_lower_ar_order_and_stays_finite():
    t = np.arange(64) / 100.0
    x = np.sin(2 * np.pi * 0.4 * t) + 0.3 * np.sin(2 * np.pi * 6 * t)
    upd = run_hpa(x, WakeConfig(ar_order=40, window_s=10.0))  # p = 40 would need 81 samples
    assert np.isfinite(upd.weights).all() and 0.5 <= upd.cutoff <= 6.0


def test_fit_can_be_pulled_towards_start_weights():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(40, 3))
    y = A @ [1.0, -2.0, 0.5] + 0.1 * rng.normal(size=40)
    free, _, _ = fit_weights(A, y, ridge=0.0)
    center = np.array([0.0, 0.0, 1.0])
    pulled, _, _ = fit_weights(A, y, ridge=0.0, center=center, shrink=1e6)
    np.testing.assert_allclose(pulled, center, atol=1e-4)
    half, _, _ = fit_weights(A, y, ridge=0.0, center=center, shrink=1.0)
    assert np.linalg.norm(half - center) < np.linalg.norm(free - center)


def test_reset_starts_the_warmup_again(signal10):
    x = signal10.measurement[:700]
    f = WakeFilter(backend="reference")
    first = f.update_block(x)
    f.reset()
    np.testing.assert_array_equal(f.update_block(x), first)
    assert [u.index for u in f.hpa_history[0]] == [100, 200, 300, 400, 500]


def test_export_header_carries_the_start_up_weights(tmp_path):
    import re

    from wake.firmware.export import export_header
    from wake.rtp.fixed import quantize_weights

    text = export_header(tmp_path / "cfg.h", wavelet="sym3", level=5, measurement_noise=1e-3, full_scale=4.0,
                         sample_rate=100.0, weights=[0, 0, 0, 0, 1])
    block = re.search(r"wake_config_start_weights\[5\] = \{\s*([^}]*)\}", text).group(1)
    start = [int(v) for v in block.replace(",", " ").split()]
    assert start == list(quantize_weights(prior_weights(WakeConfig()), 5))
    # the fitted (here: given) weights stay separate
    assert re.search(r"wake_config_weights\[5\] = \{\s*0, 0, 0, 0, 16777216", text)


def test_error_curve_is_the_binned_rms_over_one_range():
    from wake.eval.warmup import error_curve, mean_curve

    fs = 100.0
    truth = np.sin(2 * np.pi * np.arange(1000) / fs)          # range 2 after 0.5 s
    est = truth.copy()
    est[:100] += 0.5                                          # first second off by 0.5
    t, err = error_curve(truth, est, fs)
    assert t.tolist()[:3] == [0.25, 0.75, 1.25] and t.size == 20
    np.testing.assert_allclose(err[:2], 0.5 / np.ptp(truth[50:]))
    assert np.all(err[2:] == 0)
    tm, em = mean_curve([(t, err), (t[:10], 3 * err[:10])])
    assert tm.size == 10 and em[0] == pytest.approx(2 * err[0])
    with pytest.raises(ValueError, match="one length"):
        error_curve(truth, est[:-1], fs)
    with pytest.raises(ValueError, match="shorter than one sample"):
        error_curve(truth, est, fs, bin_s=0.001)


def test_floor_rule_lowers_the_synthetic_error_where_shallow_raised_it(paper_signals):
    """docs/studies/design.md, "Cut-off on real wear": the 'shallow' rule alone raises the synthetic whole-recording
    error a little (0.07390 -> 0.07396 with the C core); the 'floor' rule, the default, lowers it (0.07158):
    shallow dips at the noise floor give the default, valleys at the floor their low edge."""
    floor = _slices(paper_signals)
    paper = _slices(paper_signals, cutoff_rule="paper")
    shallow = _slices(paper_signals, cutoff_rule="shallow")
    assert WakeConfig().cutoff_rule == "floor"
    assert shallow["whole (from 0.5 s)"] > paper["whole (from 0.5 s)"]
    for k in ("2-5 s", "after 5 s", "whole (from 0.5 s)"):
        assert floor[k] < 0.98 * paper[k], (k, floor[k], paper[k])


@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_floor_rule_lowers_the_pads_error_and_leaves_few_windows_on_the_default():
    from wake.eval.datasets import load_pads_folder

    floor, paper, flags = [], [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for rec in load_pads_folder(pads_dir()):
            res = WakeFilter(fs=rec.fs, backend="reference").run(rec.samples)
            v_paper = WakeFilter(fs=rec.fs, backend="reference", cutoff_rule="paper").run(rec.samples).voluntary
            flags += [u.cutoff_flag for ch in res.hpa for u in ch]
            for c in range(rec.samples.shape[1]):
                _, tremor, _ = independent_ground_truth(rec.samples[:, c], rec.fs)
                floor.append(slice_nrmse(tremor, res.tremor[:, c], rec.fs))
                paper.append(slice_nrmse(tremor, rec.samples[:, c] - v_paper[:, c], rec.fs))
    mean = lambda rows, k: float(np.mean([r[k] for r in rows]))  # noqa: E731
    # far fewer windows on the constant default cut-off than the paper rule (82 %): 24 % when the rule came
    # in (its target: at most 30 %), 33 % since a spectrum rising from 0.5 Hz into the tremor peak is no dip
    # and falls back, which lowers the PADS error (docs/studies/design.md, "Rest tremor with little voluntary motion")
    on_default = sum(f in FALLBACK_FLAGS for f in flags) / len(flags)
    assert on_default <= 0.35, on_default
    for k in ("whole (from 0.5 s)", "after 5 s"):
        assert mean(floor, k) < 0.95 * mean(paper, k), k


@pytest.mark.slow
def _plain_truth(x, fs, cutoff):
    """The tremor truth without the end-point line: the sharp high-pass of each window of a stack (W, n), at its
    cut-off (what wake.hpa.run.detrended_highpass is replaced by)."""
    from wake.hpa.sharp import sharp_highpass

    rows = np.atleast_2d(x)
    return np.stack([sharp_highpass(r, fs, c) for r, c in zip(rows, np.atleast_1d(cutoff))]).reshape(np.shape(x))


def test_detrended_truth_lowers_the_synthetic_error_under_the_paper_rule(paper_signals, monkeypatch):
    """docs/studies/design.md, "Tremor ground truth of a window": with the paper's cut-off rule the end-point line
    taken out before the sharp high-pass lowers the synthetic error after 2 s and over the whole recording
    (0.07424 -> 0.07390 with the C core).  With the defaults (the 'floor' rule, a warm-up HPA at 1 s) it
    lowers the synthetic 1-2 s and whole-recording error (0.1385 -> 0.1224, 0.0703 -> 0.0701) and PADS in
    every slice from 2 s on (the next test)."""
    import wake.hpa.run as hpa_run

    detrended = _slices(paper_signals, cutoff_rule="paper")
    floor_detrended = _slices(paper_signals)
    monkeypatch.setattr(hpa_run, "detrended_highpass", _plain_truth)
    plain = _slices(paper_signals, cutoff_rule="paper")
    floor_plain = _slices(paper_signals)
    for k in ("2-5 s", "after 5 s", "whole (from 0.5 s)"):
        assert detrended[k] < plain[k], (k, detrended[k], plain[k])
    for k in ("1-2 s", "whole (from 0.5 s)"):
        assert floor_detrended[k] < floor_plain[k], (k, floor_detrended[k], floor_plain[k])


@pytest.mark.slow
@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_detrended_truth_lowers_the_pads_error_under_the_default_rule(monkeypatch):
    import wake.hpa.run as hpa_run

    detrended = _pads_slices()
    monkeypatch.setattr(hpa_run, "detrended_highpass", _plain_truth)
    plain = _pads_slices()
    for k in ("2-5 s", "after 5 s", "whole (from 0.5 s)"):
        assert detrended[k] < 0.995 * plain[k], (k, detrended[k], plain[k])


def test_a_short_warmup_fit_is_installed_only_on_a_clean_valley():
    """docs/studies/design.md, "Warm-up": a fit on less than CLEAN_ONLY_BELOW_S (2 s) of samples is installed only
    with a 'valley' or 'floor_valley' cut-off; otherwise the weights in use stay (flag weights_kept)."""
    from wake.eval.synthetic import make_signal
    from wake.hpa.run import CLEAN_FLAGS, clean_only_below

    cfg = WakeConfig(backend="reference")
    taps = filter_bank_taps(cfg.wavelet, cfg.level)
    prev = np.array([0.1, 0.2, 0.3, 0.2, 0.2])
    assert clean_only_below(cfg) == 200 and CLEAN_FLAGS == ("valley", "floor_valley")
    clean = run_hpa(make_signal(7.5, seed=1).measurement[:100], cfg, taps=taps, previous_weights=prev)
    assert clean.cutoff_flag == "floor_valley" and "weights_kept" not in clean.flags
    assert not np.allclose(clean.weights, prev)
    t = np.arange(200) / cfg.fs
    trend = np.cumsum(np.random.default_rng(2).normal(size=200)) * 0.05 + 0.3 * t   # no tremor peak
    short = run_hpa(trend[:100], cfg, taps=taps, previous_weights=prev)
    assert short.cutoff_flag not in CLEAN_FLAGS and "weights_kept" in short.flags
    np.testing.assert_array_equal(short.weights, prev)
    # from 2 s on every fit is installed, whatever the flag
    long = run_hpa(trend, cfg, taps=taps, previous_weights=prev)
    assert long.cutoff_flag not in CLEAN_FLAGS and "weights_kept" not in long.flags


def test_the_one_second_hpa_lowers_the_synthetic_1_to_2_s_error(paper_signals):
    now = _slices(paper_signals)
    before = _slices(paper_signals, warmup_hpa_s=(2.0, 3.0, 4.0))
    assert now["1-2 s"] < 0.8 * before["1-2 s"], (now["1-2 s"], before["1-2 s"])
    assert now["whole (from 0.5 s)"] < before["whole (from 0.5 s)"]
    for k in ("0.5-1 s", "2-5 s", "after 5 s"):
        assert now[k] <= before[k] * 1.001, k


@pytest.mark.slow
@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_the_one_second_hpa_does_not_cost_pads():
    now, before = _pads_slices(), _pads_slices(warmup_hpa_s=(2.0, 3.0, 4.0))
    for k in SLICES:
        assert now[k] <= before[k] * 1.001, (k, now[k], before[k])


# -- the bound: weights fitted to the true voluntary motion (docs/studies/design.md, "What any HPA could reach") --

def test_approximation_predictions_are_wakes_prediction_per_weight(signal10):
    from wake.eval.warmup import approximation_predictions

    x = signal10.measurement
    A = approximation_predictions(x)
    w = prior_weights(WakeConfig(fs=signal10.fs))
    v = WakeFilter(fs=signal10.fs, backend="reference", warmup_hpa_s=()).run(x).voluntary
    first_hpa = WakeConfig(fs=signal10.fs).window_samples
    np.testing.assert_allclose(A[:first_hpa] @ w, v[:first_hpa], rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="finite"):
        approximation_predictions(np.r_[x[:10], np.nan])


def test_truth_fitted_prediction_fits_every_sample_before_each_refit(signal10):
    from wake.eval.warmup import approximation_predictions, truth_fitted_prediction

    x, v, fs = signal10.measurement, signal10.voluntary, signal10.fs
    A = approximation_predictions(x)
    w0 = prior_weights(WakeConfig(fs=fs))
    p = truth_fitted_prediction(x, v, fs, refit_s=(1.0,))
    w1 = np.linalg.lstsq(A[1:100], v[1:100], rcond=None)[0]
    np.testing.assert_allclose(p[:100], A[:100] @ w0, atol=1e-12)
    np.testing.assert_allclose(p[100:], A[100:] @ w1, atol=1e-9)
    # no refit: the start-up weights throughout; a strong pull: nearly the start-up weights
    np.testing.assert_allclose(truth_fitted_prediction(x, v, fs, refit_s=()), A @ w0, atol=1e-12)
    pulled = truth_fitted_prediction(x, v, fs, refit_s=(1.0,), pull=1e6)
    assert np.abs(pulled - A @ w0).max() < 1e-3 * np.abs(A @ w0).max()
    with pytest.raises(ValueError, match="shape of x"):
        truth_fitted_prediction(x, v[:-1], fs)


@pytest.mark.slow
def test_no_hpa_schedule_reaches_the_early_targets_on_the_synthetic_set(paper_signals):
    """Fitted to the true voluntary motion before every sample, WAKE's weights still miss the issue's
    1-2 s target (1.5x the after-5-s error) and BMFLC's 0.5-1 s error; the default HPA is close to
    the same bound at its own times."""
    from wake.eval.baselines import BMFLC
    from wake.eval.warmup import truth_fitted_prediction

    limit, at_times, bmflc = [], [], []
    for s in paper_signals:
        limit.append(slice_nrmse(s.voluntary, truth_fitted_prediction(s.measurement, s.voluntary, s.fs), s.fs))
        times = WakeConfig(fs=s.fs).warmup_hpa_s
        at_times.append(slice_nrmse(s.voluntary, truth_fitted_prediction(s.measurement, s.voluntary, s.fs,
                                                                         refit_s=times), s.fs))
        bmflc.append(slice_nrmse(s.voluntary, BMFLC(fs=s.fs).run(s.measurement).voluntary, s.fs))
    limit, at_times, bmflc = (mean_slices(r) for r in (limit, at_times, bmflc))
    wake = _slices(paper_signals)
    assert limit["1-2 s"] > 1.5 * wake["after 5 s"], (limit["1-2 s"], wake["after 5 s"])
    assert limit["0.5-1 s"] > bmflc["0.5-1 s"], (limit["0.5-1 s"], bmflc["0.5-1 s"])
    # the HPA with its estimated truth is within 5 % of the truth-fitted weights at the same times
    assert wake["1-2 s"] < 1.05 * at_times["1-2 s"], (wake["1-2 s"], at_times["1-2 s"])
