"""Hyper-parameter adjustment (HPA, the paper's Algorithm 1).

One HPA run takes the last ``L`` samples and returns what the RTP needs:

S1. :func:`wake.hpa.spectrum.ar_psd`, the Yule-Walker spectrum of the window;
S2. :func:`find_cutoff`, the cut-off ``f_d`` at the valley between the
    voluntary and the tremor band (with a documented fallback);
    :func:`wake.hpa.sharp.detrended_highpass` (the paper's sharp FFT
    high-pass, after the line through the window's end points is taken out)
    then gives the tremor ground truth and ``R``, its variance;
S3. the ``J`` wavelet approximations (:mod:`wake.wavelets`);
S4. :func:`fit_weights`, the weights ``w`` that minimise the paper's error
    ``e_L``.

The paper fits ``w`` on full-window approximations of the same samples, but
the RTP predicts the *next* sample from the *causal* end-of-window
approximations.  ``fit="causal"`` (the default) fits what the RTP actually
sees: the filter-bank output at sample ``k`` against the voluntary ground
truth at ``k + 1``.  ``fit="paper"`` keeps the paper's fit.  The measured
difference is in docs/studies/design.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wake.ahead import TAPS, fit_predictor, gate_target, held_out_gain
from wake.config import WakeConfig
from wake.hpa.cutoff import find_cutoff
from wake.target import TARGET, PredictionTarget
from wake.hpa.fit import default_weights, fit_stacks, fit_weights
from wake.hpa.sharp import detrended_highpass
from wake.hpa.spectrum import ar_psds, row_var, window_order
from wake.wavelets import filter_bank_outputs, filter_bank_taps, wavelet_approximations

__all__ = ["HPAUpdate", "WindowAnalysis", "ahead_fit", "analyse_windows", "finish_hpa", "gate_truth", "run_hpa",
           "tremor_ahead", "voluntary_ahead_weights"]

@dataclass(frozen=True)
class HPAUpdate:
    """What one HPA run produced (one entry of ``WakeResult.hpa``)."""

    index: int  #: number of samples received when the HPA ran
    cutoff: float  #: f_d in Hz
    cutoff_flag: str  #: a key of :data:`CUTOFF_FLAGS`
    weights: np.ndarray  #: observation vector w, shape (J,)
    measurement_noise: float  #: R, the variance of the tremor ground truth
    fit_error: float  #: the paper's e_L (RMS fit error over the window)
    ridge: float  #: the ridge factor finally used (raised when the fit was ill-conditioned)
    flags: tuple = field(default_factory=tuple)  #: extra notes: "regularised", "weights_kept"
    applied_at: int = -1  #: sample count at which the RTP took these weights (-1: not installed; the filter records it)
    ahead_coefficients: np.ndarray | None = None  #: the tremor-ahead predictor, shape (8,) (wake.ahead); None: none
    ahead_gain: float = 0.0  #: the held-out gain of the previous predictor on the samples new since its HPA
    ahead_goal: float = 0.0  #: the gate's goal (the gain, 0 without a tremor peak)
    #: w_h, the weights of the voluntary motion ``horizon`` samples ahead, shape (J,) (horizon > 1, the fit
    #: installed); None: the RTP keeps the w_h it has (the one-step prediction held before the first)
    weights_ahead: np.ndarray | None = None


def recorded(update: HPAUpdate, **changes) -> HPAUpdate:
    """``dataclasses.replace(update, **changes)`` without its per-call field walk (an HPA's result is recorded
    once per window on the batch path): a new :class:`HPAUpdate`, ``update`` untouched.

    Examples
    --------
    >>> u = HPAUpdate(5, 2.0, "valley", np.ones(2), 1.0, 0.1, 1e-6)
    >>> recorded(u, applied_at=6).applied_at, u.applied_at
    (6, -1)
    """
    unknown = set(changes) - set(HPAUpdate.__dataclass_fields__)
    if unknown:
        raise TypeError(f"HPAUpdate has no field(s) {sorted(unknown)}")
    new = object.__new__(HPAUpdate)
    new.__dict__.update(update.__dict__, **changes)
    return new


#: Pull of a warm-up fit towards the start-up weights: shrink = WARMUP_SHRINK * (L - n) / L
#: for a window of n < L samples, 0 for a full window (docs/studies/design.md, "Warm-up").
WARMUP_SHRINK = 0.0

#: A warm-up fit on fewer than this many seconds of samples is installed only when the window's spectrum
#: separates voluntary motion from tremor cleanly (a cut-off flag in :data:`CLEAN_FLAGS`); otherwise the
#: weights in use stay (flag ``"weights_kept"``).  One second cannot resolve a shoulder or a missing
#: tremor peak, and a fit on it extrapolates the slow trend (docs/studies/design.md, "Warm-up").
CLEAN_ONLY_BELOW_S = 2.0

#: The cut-off flags of a clean separation: a valley 3 dB deep, at or above the noise floor.
CLEAN_FLAGS = ("valley", "floor_valley")


def clean_only_below(config: WakeConfig) -> int:
    """Window length in samples below which only a clean separation installs a fit (:data:`CLEAN_ONLY_BELOW_S`)."""
    return int(round(CLEAN_ONLY_BELOW_S * config.fs))


def gate_truth(x, fs: float, cutoff: float, tremor_gt, gate_cutoff):
    """The truth the gate's held-out gain is measured against (``WakeConfig.gate_cutoff``).

    ``tremor_gt`` (the window's tremor above the HPA's cut-off ``f_d``) when ``gate_cutoff`` is None or at
    most ``f_d``; else the window's sharp high-pass above ``gate_cutoff``
    (:func:`wake.hpa.sharp.detrended_highpass`, the same samples ``x``).  The gain is the least-squares scale
    of the predictions onto this truth, so a gated command is no worse than zero against it on the held-out
    samples: a rhythm between ``f_d`` and ``gate_cutoff`` (pdkit's 3-Hz pronation-supination, which a
    recording's truth calls voluntary) no longer opens the gate by itself.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(500) / 100.0
    >>> x = np.sin(2 * np.pi * 3.0 * t) + 0.1 * np.sin(2 * np.pi * 7.0 * t)
    >>> T = detrended_highpass(x, 100.0, 2.0)
    >>> gate_truth(x, 100.0, 2.0, T, None) is T, round(float(np.std(gate_truth(x, 100.0, 2.0, T, 4.0))), 3)
    (True, 0.07)
    """
    if gate_cutoff is None or gate_cutoff <= cutoff:
        return tremor_gt
    return detrended_highpass(x, fs, gate_cutoff)


def tremor_ahead(x, outputs, weights, tremor_gt, config: WakeConfig, flag: str, previous_ahead=None,
                 new_samples: int = 0, cutoff: float = 0.0, fitted=None) -> dict:
    """The tremor-ahead fields of an :class:`HPAUpdate` (docs/studies/design.md, "Tremor ahead").

    WAKE's tremor estimate over the window, ``y(k) = x(k) - w . a(k-1)`` for ``k = N .. n-1`` (``a``: the
    filter-bank ``outputs``, ``w``: the weights this HPA installs), against the window's truth ``tremor_gt``: the
    :func:`wake.ahead.fit_predictor` at ``config.horizon``, the :func:`wake.ahead.held_out_gain` of
    ``previous_ahead`` on the ``new_samples`` samples since its HPA (against :func:`gate_truth` at the
    window's ``cutoff``), and the :func:`wake.ahead.gate_target`.  ``fitted``: :func:`ahead_fit`'s result for
    these weights, when a batch path has it.
    """
    estimate, truth, coefficients = ahead_fit(x, outputs, weights, tremor_gt, config.horizon) if fitted is None \
        else fitted
    if config.gate_cutoff is not None:
        N = x.shape[-1] - outputs.shape[-2] + 1
        truth = gate_truth(x, config.fs, cutoff, tremor_gt, config.gate_cutoff)[N:]
    gain = held_out_gain(estimate, truth, previous_ahead, config.horizon, new_samples)
    return dict(ahead_coefficients=coefficients, ahead_gain=gain, ahead_goal=gate_target(gain, flag))


def ahead_fit(x, outputs, weights, tremor_gt, horizon: int):
    """``(estimate, truth, coefficients)`` of :func:`tremor_ahead`: WAKE's tremor estimate over the window, its
    truth and the :func:`wake.ahead.fit_predictor` between them; a stack of windows (W, n) with their outputs
    (W, m, J) and weights (W, J) gives one row each, bit for bit each window's own."""
    N = x.shape[-1] - outputs.shape[-2] + 1
    w = np.asarray(weights, dtype=float)
    if x.ndim == 1:
        estimate = x[N:] - outputs[:-1] @ w
    else:   # (W, m-1, J) @ (W, J, 1): the gemv of each window
        estimate = x[:, N:] - (outputs[:, :-1] @ w[:, :, None])[:, :, 0]
    truth = tremor_gt[..., N:]
    return estimate, truth, fit_predictor(estimate, truth, horizon)


def voluntary_ahead_weights(outputs, voluntary_gt, n_taps: int, horizon: int, ridge: float, start_weights,
                            shrink: float, ridge_scale: str = "gram"):
    """``w_h``: the weights of the voluntary motion ``horizon`` samples ahead (None at ``horizon = 1``).

    The one-step fit (:func:`wake.hpa.fit.fit_weights`, the same ridge, weight limit and warm-up pull) on
    ``PredictionTarget(horizon).fit_pairs``: the filter-bank outputs ``a(k)`` against the voluntary ground
    truth ``v(k + horizon)`` of the same window (docs/studies/design.md, "Voluntary motion at n + h").

    Examples
    --------
    >>> import numpy as np
    >>> rows = np.column_stack((np.sin(np.arange(60) / 5.0), np.cos(np.arange(60) / 5.0)))
    >>> truth = np.r_[np.zeros(6), np.sin(np.arange(57) / 5.0)]   # 4 taps: a(i) is of sample i + 3
    >>> # so with h = 3 the truth v(i + 6) is a_0(i)
    >>> np.round(voluntary_ahead_weights(rows, truth, 4, 3, 0.0, None, 0.0), 6).tolist()
    [1.0, 0.0]
    """
    if horizon == 1:
        return None
    approx, target = PredictionTarget(horizon).fit_pairs(outputs, voluntary_gt, n_taps)
    return fit_weights(approx, target, ridge, center=start_weights, shrink=shrink, ridge_scale=ridge_scale)[0]


def run_hpa(window, config: WakeConfig, *, taps=None, previous_weights=None, index: int = 0,
            start_weights=None, previous_ahead=None, new_samples: int = 0) -> HPAUpdate:
    """One HPA run over a window of the last ``L`` samples.

    Parameters
    ----------
    window : array_like, shape (n,)
        The samples, oldest first, finite (:class:`~wake.WakeFilter`
        interpolates gaps before it calls this).  Usually the last ``L``
        samples; a warm-up HPA passes every sample seen so far (at least
        ``2 * 2**J``).
    config : WakeConfig
        Sampling rate, wavelet, level, AR order, fit, ridge and the cut-off
        search settings.
    taps : numpy.ndarray, shape (J, 2**J), optional
        The RTP filter bank (:func:`wake.wavelets.filter_bank_taps`);
        computed from ``config`` when not given.
    previous_weights : numpy.ndarray, optional
        Kept when the window is silent, and when a warm-up window shorter
        than :data:`CLEAN_ONLY_BELOW_S` has no clean valley (a cut-off flag
        outside :data:`CLEAN_FLAGS`).
    index : int
        Number of samples received when the HPA ran (recorded in the result).
    start_weights : numpy.ndarray, optional
        The weights before the first HPA; a warm-up window (shorter than
        ``L``) is fitted with a pull towards them that fades as the window
        grows (:data:`WARMUP_SHRINK`).
    previous_ahead : numpy.ndarray, shape (8,), optional
        The previous HPA's tremor-ahead predictor (None before the first:
        the gate's goal is 0).
    new_samples : int
        Samples received since the previous HPA (its held-out samples).

    Returns
    -------
    HPAUpdate

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeConfig
    >>> from wake.hpa import run_hpa
    >>> t = np.arange(500) / 100.0
    >>> upd = run_hpa(np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 8 * t), WakeConfig())
    >>> upd.cutoff_flag, upd.weights.shape
    ('valley', (5,))
    """
    x = np.asarray(window, dtype=float)
    return finish_hpa(analyse_windows(x[None], config, taps=taps, start_weights=start_weights)[0], config,
                      previous_weights=previous_weights, index=index, start_weights=start_weights,
                      previous_ahead=previous_ahead, new_samples=new_samples)


@dataclass(frozen=True)
class WindowAnalysis:
    """What an HPA computes from its window alone (:func:`analyse_windows`): S1 to S4 before the choices that
    read the previous HPA's results (:func:`finish_hpa`)."""

    x: np.ndarray                #: the window
    silent: bool                 #: no spread: nothing below is computed
    cutoff: float = 0.0
    flag: str = ""
    tremor_gt: np.ndarray | None = None
    voluntary_gt: np.ndarray | None = None
    measurement_noise: float = 0.0
    outputs: np.ndarray | None = None   #: the filter-bank outputs over the window
    weights: np.ndarray | None = None   #: the fit (installed unless a short window keeps the weights in use)
    fit_error: float = 0.0
    ridge: float = 0.0
    shrink: float = 0.0
    ahead: tuple | None = None          #: ahead_fit with these weights (None: the window may keep others)


def analyse_windows(windows, config: WakeConfig, *, taps=None, start_weights=None) -> list:
    """The window-only steps of :func:`run_hpa` for many windows at once: one :class:`WindowAnalysis` per window,
    each bit for bit what that window alone gives.

    ``windows`` is a stack of windows of one length, ``(W, n)``, or a sequence of 1-D windows of any lengths (a
    block's warm-up windows beside its full ones).  The spectra, high-passes, filter-bank outputs and fits are
    taken for every window of one length at once, the Levinson recursion, the cut-off search and the solves for
    every window at once.  No window depends on another, nor on an earlier HPA: a batch path analyses every
    window of a block first, then finishes them in order (:func:`finish_hpa`).
    """
    fs, ridge, L = config.fs, config.ridge, config.window_samples
    if taps is None:
        taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    out = [None] * len(windows)
    groups = []   # (where in out, the live windows of one length, their spread)
    for where, X in _by_length(windows):
        spread = np.sqrt(row_var(X))   # np.std(X, axis=1)
        live = spread > 1e-12 * np.maximum(1.0, np.max(np.abs(X), axis=1))
        if not live.all():
            for i in np.flatnonzero(~live):
                out[where[i]] = WindowAnalysis(X[i], True)
            X, spread, where = X[live], spread[live], where[live]
        if X.shape[0]:
            groups.append((where, X, spread))
    if not groups:
        return out
    # a warm-up window may be shorter than L: its AR order is capped (window_order)
    orders = [window_order(X.shape[1], config.ar_order) for _, X, _ in groups]
    found = _cutoffs(ar_psds([X for _, X, _ in groups], fs, orders), orders, config)
    parts = []   # per group: tremor_gt, voluntary_gt, R, outputs, the fit's rows and targets, shrink
    for (where, X, spread), cutoffs in zip(groups, found):
        n = X.shape[1]
        # the window's end-point line is voluntary: taken out first, it leaves no seam in the FFT
        tremor_gt = detrended_highpass(X, fs, [cutoff for cutoff, _ in cutoffs])
        voluntary_gt = X - tremor_gt
        # R: variance of the tremor ground truth, floored at 1e-6 of the window's variance so that a window
        # with no tremor still gives S = w'Pw + R > 0 (max(var, floor), row by row)
        noise, floor = row_var(tremor_gt), 1e-6 * spread**2
        noise = np.where(floor > noise, floor, noise)
        outputs = filter_bank_outputs(X, taps)
        if config.fit == "causal":
            # a(k) for k = N-1 .. L-1-h against v_GT(k + h), h = TARGET.horizon (wake.target)
            approx, target = TARGET.fit_pairs(outputs, voluntary_gt, taps.shape[1])
        else:
            approx = np.stack([wavelet_approximations(x, config.wavelet, config.level, config.mode) for x in X])
            target = voluntary_gt
        shrink = WARMUP_SHRINK * (L - n) / L if (start_weights is not None and n < L) else 0.0
        parts.append((tremor_gt, voluntary_gt, noise, outputs, approx, target, shrink))
    w, err, used = fit_stacks([p[4] for p in parts], [p[5] for p in parts], ridge, center=start_weights,
                              shrinks=[p[6] for p in parts], ridge_scale=config.ridge_scale)
    start = 0
    for (where, X, _), cutoffs, (tremor_gt, voluntary_gt, noise, outputs, _, _, shrink) in zip(groups, found, parts):
        stop = start + X.shape[0]
        # a window of CLEAN_ONLY_BELOW_S or more installs its fit: the tremor-ahead fit on it is window-only too
        ahead = ahead_fit(X, outputs, w[start:stop], tremor_gt, config.horizon) \
            if X.shape[1] >= clean_only_below(config) else None
        for j, i in enumerate(where):
            out[i] = WindowAnalysis(X[j], False, cutoffs[j][0], cutoffs[j][1], tremor_gt[j], voluntary_gt[j],
                                    float(noise[j]), outputs[j], w[start + j].copy(), float(err[start + j]),
                                    float(used[start + j]), shrink,
                                    None if ahead is None else tuple(part[j] for part in ahead))
        start = stop
    return out


def _by_length(windows) -> list:
    """``[(where, stack)]``: the windows of each length stacked, with their places in ``windows`` (a stack of one
    length, (W, n), is one group as it is)."""
    if isinstance(windows, np.ndarray) and windows.ndim == 2:
        return [(np.arange(windows.shape[0]), np.asarray(windows, dtype=float))]
    places = {}
    for i, x in enumerate(windows):
        places.setdefault(np.shape(x), []).append(i)
    for shape in places:
        if len(shape) != 1:
            raise ValueError(f"each window must be 1-D (or the windows one stack (W, n)), got one of shape {shape}")
    return [(np.array(where), np.array([windows[i] for i in where], dtype=float)) for where in places.values()]


def _cutoffs(spectra, orders, config: WakeConfig) -> list:
    """:func:`find_cutoff` of every row of ``spectra`` (one ``(freqs, psd)`` per group of windows): the rows on one
    frequency grid (one AR order) searched at once; a list of ``(cutoff, flag)`` per group."""
    by_order = {}
    for k, order in enumerate(orders):
        by_order.setdefault(order, []).append(k)
    found = [None] * len(spectra)
    for ks in by_order.values():
        psd = np.concatenate([spectra[k][1] for k in ks]) if len(ks) > 1 else spectra[ks[0]][1]
        rows = find_cutoff(spectra[ks[0]][0], psd, tremor_band=config.tremor_band, cutoff_range=config.cutoff_range,
                           default_cutoff=config.default_cutoff, rule=config.cutoff_rule,
                           shallow_max=config.shallow_max)
        start = 0
        for k in ks:
            found[k], start = rows[start:start + spectra[k][1].shape[0]], start + spectra[k][1].shape[0]
    return found


def finish_hpa(a: WindowAnalysis, config: WakeConfig, *, previous_weights=None, index: int = 0,
               start_weights=None, previous_ahead=None, new_samples: int = 0) -> HPAUpdate:
    """The :class:`HPAUpdate` of an analysed window (:func:`analyse_windows`), given what the previous HPA left
    (the arguments of :func:`run_hpa`): the weights kept or installed, ``w_h`` and the tremor ahead."""
    level, ridge = config.level, config.ridge
    if a.silent:
        w = np.array(previous_weights, dtype=float) if previous_weights is not None else default_weights(level)
        floor = max(1e-12, (1e-6 * np.max(np.abs(a.x))) ** 2)
        # a silent window has nothing to predict: the predictor stays, the gate shuts
        kept = np.zeros(TAPS) if previous_ahead is None else np.array(previous_ahead, dtype=float)
        return HPAUpdate(index, float(config.default_cutoff), "silent", w, float(floor), 0.0, float(ridge),
                         ("weights_kept",), ahead_coefficients=kept)
    flags = []
    w, ahead_weights, fitted = a.weights, None, a.ahead
    if a.ridge > ridge:
        flags.append("regularised")
    if a.x.size < clean_only_below(config) and a.flag not in CLEAN_FLAGS:
        # a short warm-up window without a clean valley: its fit is not installed
        w = np.array(previous_weights, dtype=float) if previous_weights is not None else default_weights(level)
        flags.append("weights_kept")
        fitted = None
    else:
        # the voluntary motion h samples ahead, fitted by the same rules (None at h = 1 and when kept)
        n_taps = a.x.size - a.outputs.shape[0] + 1   # the filter bank's length (outputs: one per full history)
        ahead_weights = voluntary_ahead_weights(a.outputs, a.voluntary_gt, n_taps, config.horizon, ridge,
                                                start_weights, a.shrink, config.ridge_scale)
    # the predictor learns from the estimate these weights will give from now on (docs/studies/design.md, "Tremor
    # ahead": with the weights in use before this HPA, PADS at 100 ms came to 1.008 x zero after 5 s)
    ahead = tremor_ahead(a.x, a.outputs, w, a.tremor_gt, config, a.flag, previous_ahead, new_samples, a.cutoff, fitted)
    return HPAUpdate(index, a.cutoff, a.flag, w, a.measurement_noise, a.fit_error, a.ridge, tuple(flags),
                     weights_ahead=ahead_weights, **ahead)
