"""Error measures of the paper and the offline ground truth for real recordings."""

from __future__ import annotations

import numpy as np

from wake.hpa.sharp import sharp_highpass

__all__ = ["nrmse", "prf", "snr_out", "offline_ground_truth", "best_lag"]


def _pair(truth, estimate, start):
    truth = np.asarray(truth, dtype=float)
    estimate = np.asarray(estimate, dtype=float)
    if truth.shape != estimate.shape:
        raise ValueError(f"truth and estimate differ in shape: {truth.shape} vs {estimate.shape}")
    if not 0 <= start < truth.shape[0]:
        raise ValueError(f"start must be within [0, {truth.shape[0]}), got {start}")
    return truth[start:], estimate[start:]


def nrmse(truth, estimate, start=0):
    """Normalised RMSE of the paper: RMS error over the range of the truth.

    ``sqrt(mean((truth - estimate)**2)) / (max(truth) - min(truth))``, over
    samples ``start:`` (the paper leaves the warm-up out).

    Examples
    --------
    >>> from wake.eval.metrics import nrmse
    >>> round(nrmse([0.0, 1.0, 2.0], [0.0, 1.0, 1.0]), 4)
    0.2887
    """
    t, e = _pair(truth, estimate, start)
    span = t.max() - t.min()
    if span == 0:
        raise ValueError("the truth is constant over the scored samples; NRMSE is undefined")
    return float(np.sqrt(np.mean((t - e) ** 2)) / span)


def prf(truth, estimate, start=0):
    """Power ratio factor in percent: ``100 * sum((s_v - v_hat)**2) / sum(s_v**2)``."""
    t, e = _pair(truth, estimate, start)
    return float(100.0 * np.sum((t - e) ** 2) / np.sum(t**2))


def snr_out(truth, estimate, start=0):
    """Output SNR in dB: ``10 log10(P(s_v) / P(s_v - v_hat))`` (= ``10 log10(100 / PRF)``)."""
    t, e = _pair(truth, estimate, start)
    return float(10 * np.log10(np.sum(t**2) / np.sum((t - e) ** 2)))


def offline_ground_truth(x, fs, cutoff):
    """The paper's offline ground truth: a sharp high-pass of the whole recording.

    Parameters
    ----------
    x : array_like, shape (n,)
    fs : float
    cutoff : float
        The mean of the cut-offs ``f_d`` over all HPA runs.

    Returns
    -------
    voluntary, tremor : numpy.ndarray
    """
    x = np.asarray(x, dtype=float)
    tremor = sharp_highpass(x, fs, cutoff)
    return x - tremor, tremor


def best_lag(truth, estimate, max_lag=25):
    """Delay in samples (estimate behind truth > 0) that maximises the cross-correlation."""
    t = np.asarray(truth, dtype=float) - np.mean(truth)
    e = np.asarray(estimate, dtype=float) - np.mean(estimate)
    lags = np.arange(-max_lag, max_lag + 1)
    n = t.shape[0]
    scores = [np.dot(t[: n - k], e[k:]) if k >= 0 else np.dot(t[-k:], e[: n + k]) for k in lags]
    return int(lags[int(np.argmax(scores))])
