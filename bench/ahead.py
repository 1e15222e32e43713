"""Helpers of ``bench/tremor_ahead.py``: tremor predictors h samples ahead, their oracle and their gates.

Notation (one channel of one recording, ``N`` samples):

* ``y[n]``: WAKE's causal tremor estimate, ``x[n] - voluntary[n]`` (``voluntary[n]`` is predicted from
  ``x[:n]``), what a device has at sample ``n``;
* ``T[n]``: the true tremor (PADS: the independent sharp high-pass of the whole recording; synthetic: ``s_t``);
* a *prediction* ``P[n]`` is the estimate of ``T[n + h]`` an actuator is given at sample ``n``, made from
  ``y[:n + 1]`` (and the HPA windows completed by then);
* the *command* scored at sample ``m`` is ``P[m - h]`` (0 for ``m < h``), against ``T[m]``.

Every predictor is refitted at each HPA of the WakeFilter (``WakeResult.hpa[c][i].index``: at 1, 2, 3, 4 s and
then every 5 s) from what that HPA knows: its window ``x[index - m : index]``, its cut-off ``f_d`` and flag, and
the window's sharp high-pass tremor truth (``detrended_highpass``, recomputed here exactly as ``run_hpa`` does;
outlier and gap handling is left out: the recordings here have neither).  A model fitted at ``index`` predicts
from ``n = index`` on; before the first HPA every predictor says 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from wake.hpa.cutoff import FALLBACK_FLAGS
from wake.hpa.sharp import detrended_highpass
from wake.hpa.spectrum import yule_walker

HORIZONS = (1, 2, 5, 10)


@dataclass
class Window:
    """What one HPA run knows (one entry of ``WakeResult.hpa``), with its window's tremor truth."""

    index: int        #: samples received when the HPA ran; the model predicts from n = index on
    start: int        #: first sample of the window
    cutoff: float
    flag: str
    truth: np.ndarray  #: the window's sharp high-pass tremor truth, samples start .. index - 1

    @property
    def fallback(self):
        return self.flag in FALLBACK_FLAGS


def hpa_windows(x, hpa, fs, window_samples):
    """The :class:`Window` of each HPA update of one channel."""
    out = []
    for u in hpa:
        m = min(u.index, window_samples)
        w = np.asarray(x[u.index - m:u.index], dtype=float)
        out.append(Window(u.index, u.index - m, float(u.cutoff), u.cutoff_flag,
                          detrended_highpass(w, fs, u.cutoff)))
    return out


# -- linear predictors: P[n] = sum_k c[k] y[n - k] ------------------------------------------------------------


def lagged(s, p):
    """Rows ``[s[k], s[k-1], ..., s[k-p+1]]`` for every k (zeros before the start)."""
    s = np.asarray(s, dtype=float)
    pad = np.concatenate((np.zeros(p - 1), s))
    return np.lib.stride_tricks.sliding_window_view(pad, p)[:, ::-1]


def ls_direct(inp, target, h, p, ridge=1e-3):
    """Least-squares direct h-step predictor: ``target[k + h] ~ c . inp[k .. k-p+1]`` over the rows with full
    history; ``ridge`` relative to the mean diagonal of the Gram matrix."""
    X = lagged(inp, p)[p - 1:len(inp) - h]
    t = np.asarray(target, dtype=float)[p - 1 + h:]
    if X.shape[0] < 2:
        return np.zeros(p)
    G = X.T @ X
    lam = ridge * np.trace(G) / p + 1e-300
    return np.linalg.solve(G + lam * np.eye(p), X.T @ t)


def ar_iterated(a, h):
    """Coefficients ``c`` of the h-step prediction of an AR model ``[1, a_1, ..., a_p]`` iterated h times."""
    p = len(a) - 1
    C = np.zeros((p, p))
    C[0] = -np.asarray(a[1:], dtype=float)
    C[1:, :-1] = np.eye(p - 1)
    return np.linalg.matrix_power(C, h)[0]


def apply_fir(y, segments, p):
    """``P[n] = c . y[n .. n-p+1]`` with the coefficients of the segment holding n; segments = [(start, c)]."""
    Y = lagged(y, p)
    P = np.zeros(len(y))
    bounds = [s for s, _ in segments] + [len(y)]
    for (s, c), e in zip(segments, bounds[1:]):
        P[s:e] = Y[s:e] @ c
    return P


def predictor_ar(y, windows, h, p):
    """AR(p), Yule-Walker on the window's truth, iterated h steps on ``y``."""
    segs = [(w.index, ar_iterated(yule_walker(w.truth, min(p, (len(w.truth) - 1) // 2))[0], h)) for w in windows]
    return apply_fir(y, [(s, np.pad(c, (0, p - len(c)))) for s, c in segs], p)


def predictor_direct_truth(y, windows, h, p, ridge=1e-3):
    """Direct h-step least squares on the window's truth (truth -> truth), applied to ``y``."""
    return apply_fir(y, [(w.index, ls_direct(w.truth, w.truth, h, p, ridge)) for w in windows], p)


def predictor_direct_wiener(y, windows, h, p, ridge=1e-3):
    """Direct h-step least squares from WAKE's own estimate over the window to the window's truth
    (``y`` -> truth): a Wiener predictor of what the device actually sees."""
    return apply_fir(y, [(w.index, ls_direct(y[w.start:w.index], w.truth, h, p, ridge)) for w in windows], p)


# -- a Kalman oscillator at the window's dominant tremor frequency --------------------------------------------


def dominant_frequency(truth, fs, lo, hi=15.0, order=12):
    """Peak of the window truth's AR spectrum between ``lo`` and ``hi`` Hz."""
    from wake.hpa.spectrum import ar_psd

    f, psd = ar_psd(truth, fs, min(order, (len(truth) - 1) // 2))
    band = (f > lo) & (f <= hi)
    return float(f[band][np.argmax(psd[band])]) if band.any() else float(lo)


def oscillator_design(f0, fs, bandwidth, power, noise):
    """Steady-state Kalman gain of ``s[n+1] = rho R(omega) s[n] + q``, ``y = s_0 + r``.

    ``rho = exp(-pi bandwidth / fs)`` (a resonance ``bandwidth`` Hz wide), ``q = (1 - rho^2) power`` (so the
    state's variance is ``power``), ``r = noise``.  Returns (F, K)."""
    om = 2 * np.pi * f0 / fs
    rho = np.exp(-np.pi * bandwidth / fs)
    F = rho * np.array([[np.cos(om), -np.sin(om)], [np.sin(om), np.cos(om)]])
    H = np.array([[1.0, 0.0]])
    q = max((1 - rho**2) * power, 1e-30)
    r = max(noise, 1e-9 * power, 1e-30)
    # a-priori covariance; filtering gain K = P H' / (H P H' + r)
    Pm = scipy.linalg.solve_discrete_are(F.T, H.T, q * np.eye(2), np.array([[r]]))
    K = (Pm @ H.T / (H @ Pm @ H.T + r)).ravel()
    return F, K


def predictor_oscillator(y, windows, fs, horizons, bandwidth=1.0, noise_scale=1.0):
    """Kalman oscillator per window (frequency: the window truth's AR peak above f_d; power: the truth's
    variance; measurement noise: ``noise_scale`` x the variance of ``y - truth`` over the window), state
    carried over a refit, extrapolated ``h`` steps: ``P_h[n] = e_1' F^h s[n|n]``.  Returns {h: P}."""
    N = len(y)
    P = {h: np.zeros(N) for h in horizons}
    if not windows:
        return P
    s = np.zeros(2)
    bounds = [w.index for w in windows] + [N]
    for w, e in zip(windows, bounds[1:]):
        f0 = dominant_frequency(w.truth, fs, w.cutoff)
        noise = noise_scale * float(np.var(y[w.start:w.index] - w.truth))
        F, K = oscillator_design(f0, fs, bandwidth, float(np.var(w.truth)), noise)
        rows = {h: np.linalg.matrix_power(F, h)[0] for h in horizons}
        states = np.empty((e - w.index, 2))
        for n in range(w.index, e):
            s = F @ s
            s = s + K * (y[n] - s[0])
            states[n - w.index] = s
        for h in horizons:
            P[h][w.index:e] = states @ rows[h]
    return P


# -- scoring --------------------------------------------------------------------------------------------------


def command(P, h):
    """What the actuator plays at sample m: the prediction made at m - h (0 before)."""
    out = np.zeros_like(P)
    out[h:] = P[:-h]
    return out


def oracle(T, y, h, p, ridge=1e-6):
    """Hindsight predictors on the whole recording: (on the true past, its coefficients on ``y``,
    the hindsight Wiener predictor from ``y``)."""
    c = ls_direct(T, T, h, p, ridge)
    cw = ls_direct(y, T, h, p, ridge)
    return apply_fir(T, [(0, c)], p), apply_fir(y, [(0, c)], p), apply_fir(y, [(0, cw)], p)


# -- gates ----------------------------------------------------------------------------------------------------


def ramp(target, fs, tau_s):
    """First-order ramp of a gate target towards itself (time constant ``tau_s``)."""
    a = 1.0 / max(1.0, tau_s * fs)
    g = np.empty_like(target)
    v = 0.0
    for n, t in enumerate(target):
        v += a * (t - v)
        g[n] = v
    return g


def held_out_gain(P, windows, h, previous_end=True):
    """Per window, the regression gain ``<T, P> / <P, P>`` of the predictions made *before* this HPA (by the
    previous model, on samples it was not fitted on) against this window's truth, over the samples this window
    adds: a held-out estimate of how far the command can be trusted.  NaN when there is nothing to score."""
    gains, skills = [], []
    for i, w in enumerate(windows):
        if i == 0:
            gains.append(np.nan)
            skills.append(np.nan)
            continue
        prev = windows[i - 1]
        lo = max(prev.index, w.start)            # samples new since the previous HPA, in this window
        # predictions made at n in [lo - h, w.index - h) target samples n + h in [lo, w.index)
        lo_n = max(lo - h, prev.index)
        n = np.arange(lo_n, w.index - h)
        if n.size < 10:
            gains.append(np.nan)
            skills.append(np.nan)
            continue
        t = w.truth[n + h - w.start]
        p = P[n]
        pp = float(p @ p)
        gains.append(float(t @ p) / pp if pp > 0 else 0.0)
        skills.append(1.0 - float(np.sum((t - p) ** 2)) / max(float(t @ t), 1e-300))
    return np.array(gains), np.array(skills)


def in_sample_skill(y, windows, coefs, h, p):
    """Per window, the skill ``1 - |T - P|^2 / |T|^2`` of the window's own FIR predictor on its own window
    (input: ``y`` over the window; target: the window's truth)."""
    out = []
    for w, c in zip(windows, coefs):
        seg = y[w.start:w.index]
        P = lagged(seg, p) @ c
        t = w.truth[p - 1 + h:]
        q = P[p - 1:len(seg) - h]
        out.append(1.0 - float(np.sum((t - q) ** 2)) / max(float(t @ t), 1e-300))
    return np.array(out)


def running_ratio(y, P, h, fs, tau_s=1.0):
    """Causal ratio of the prediction's recent error against the estimate (``y[n] - P[n-h]``, known at n) to
    the estimate's recent power; both as exponential means with time constant ``tau_s``."""
    a = 1.0 / (tau_s * fs)
    err = np.zeros_like(y)
    err[h:] = y[h:] - P[:-h]
    e2 = scipy_lfilter_ema(err**2, a)
    y2 = scipy_lfilter_ema(y**2, a)
    return e2 / np.maximum(y2, 1e-300)


def scipy_lfilter_ema(v, a):
    import scipy.signal

    return scipy.signal.lfilter([a], [1, -(1 - a)], v)


#: Cut-off flags of a window without a tremor peak: nothing to predict, the chosen gate stays shut.
NO_TREMOR_FLAGS = ("no_tremor_peak", "silent")


def chosen_gate(P, windows, h, N):
    """The chosen gate's target per sample: the held-out gain (:func:`held_out_gain`) clipped to [0, 1], and 0
    while the last HPA window had no tremor peak (:data:`NO_TREMOR_FLAGS`)."""
    gain, _ = held_out_gain(P, windows, h)
    peak = np.array([0.0 if w.flag in NO_TREMOR_FLAGS else 1.0 for w in windows])
    return step_target(windows, N, np.clip(np.nan_to_num(gain), 0, 1) * peak)


def step_target(windows, N, values):
    """A per-window value held from the window's index until the next (0 before the first)."""
    out = np.zeros(N)
    bounds = [w.index for w in windows] + [N]
    for w, e, v in zip(windows, bounds[1:], values):
        out[w.index:e] = v
    return out


# -- the baselines' own extrapolation: library code now (wake.eval.tremor_ahead, read by wake evaluate) ----------

from wake.eval.tremor_ahead import baselines_ahead  # noqa: E402,F401  (bench/tremor_ahead.py reads it from here)


# -- variants of the chosen predictor and gate ----------------------------------------------------------------


def ls_direct_trimmed(inp, target, h, p, trim, ridge=1e-3):
    """:func:`ls_direct` without the ``trim`` first and last samples of the window (the FFT truth's edges)."""
    if trim <= 0 or len(inp) <= 2 * trim + p + h + 2:
        return ls_direct(inp, target, h, p, ridge)
    return ls_direct(inp[trim:-trim], target[trim:-trim], h, p, ridge)


def predictor_direct_wiener_trimmed(y, windows, h, p, trim, ridge=1e-3):
    return apply_fir(y, [(w.index, ls_direct_trimmed(y[w.start:w.index], w.truth, h, p, trim, ridge))
                         for w in windows], p)


def split_gain(y, windows, h, p, share=0.3, ridge=1e-3):
    """Per window, a held-out gain inside the window itself: the predictor fitted on its first ``1 - share``,
    scored (``<T, P> / <P, P>``) on its last ``share``."""
    out = []
    for w in windows:
        seg, t = y[w.start:w.index], w.truth
        cut = int(round((1 - share) * len(seg)))
        if cut < p + h + 8 or len(seg) - cut < p + h + 8:
            out.append(0.0)
            continue
        c = ls_direct(seg[:cut], t[:cut], h, p, ridge)
        P = lagged(seg, p) @ c
        n = np.arange(cut, len(seg) - h)
        q, tt = P[n], t[n + h]
        qq = float(q @ q)
        out.append(float(tt @ q) / qq if qq > 0 else 0.0)
    return np.array(out)


def predictor_direct_inputs(signals, truth_windows, h, taps, ridge=1e-3):
    """Direct h-step least squares from several inputs (each with its own number of taps) to the window's
    truth: ``signals`` are full-length arrays (WAKE's estimate, the measurement, its first difference...),
    ``truth_windows`` the :class:`Window` list.  Columns are scaled to unit RMS before the ridge."""
    N = len(signals[0])
    X = np.hstack([lagged(s, p) for s, p in zip(signals, taps)])
    P = np.zeros(N)
    p = max(taps)
    bounds = [w.index for w in truth_windows] + [N]
    for w, e in zip(truth_windows, bounds[1:]):
        Xw = np.hstack([lagged(s[w.start:w.index], q) for s, q in zip(signals, taps)])[p - 1:len(w.truth) - h]
        t = w.truth[p - 1 + h:]
        if Xw.shape[0] < 2:
            continue
        sc = np.maximum(np.sqrt((Xw**2).mean(axis=0)), 1e-300)
        G = (Xw / sc).T @ (Xw / sc)
        lam = ridge * np.trace(G) / G.shape[0]
        c = np.linalg.solve(G + lam * np.eye(G.shape[0]), (Xw / sc).T @ t) / sc
        P[w.index:e] = X[w.index:e] @ c
    return P


def predictor_ar_on_estimate(y, h, p=20, every=50, window=500, start=50):
    """The issue's sketch: AR(p) by Yule-Walker on WAKE's own past estimate (the last ``window`` samples),
    refitted every ``every`` samples from ``start`` on, iterated ``h`` steps."""
    segs = []
    for n in range(start, len(y), every):
        seg = y[max(0, n - window):n]
        q = min(p, (len(seg) - 1) // 2)
        c = ar_iterated(yule_walker(seg, q)[0], h)
        segs.append((n, np.pad(c, (0, p - len(c)))))
    return apply_fir(y, segs, p)
