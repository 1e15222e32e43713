"""Scores by time since start: what a wearer lives through in the first seconds.

The paper leaves the first HPA window (5 s) out of every score.  A wearer
does not, so the functions here score each method per slice of time since
switch-on (:data:`SLICES`), beside the whole recording from 0.5 s, against a
ground truth that does not depend on WAKE's own cut-off
(:func:`independent_ground_truth`).
"""

from __future__ import annotations

import numpy as np


__all__ = ["SLICES", "independent_cutoff", "independent_ground_truth", "slice_nrmse", "error_curve", "mean_slices",
           "mean_curve", "approximation_predictions", "truth_fitted_prediction"]

#: Slices of time since start, in seconds (None: to the end).  "whole" starts
#: at 0.5 s: before that no causal method has seen a tremor period.
SLICES = {"0.5-1 s": (0.5, 1.0), "1-2 s": (1.0, 2.0), "2-5 s": (2.0, 5.0), "after 5 s": (5.0, None),
          "whole (from 0.5 s)": (0.5, None)}


def independent_cutoff(x, fs, band=(1.5, 5.0)):
    """The valley of the whole recording's Welch spectrum between ``band[0]`` and ``band[1]`` Hz.

    A cut-off that WAKE's HPA never sees, so that scoring WAKE against the
    tremor above it does not favour WAKE (the paper's offline truth uses
    WAKE's own mean ``f_d``).
    """
    from scipy.signal import welch  # here: importing scipy.signal takes a second, and only recordings need it

    x = np.asarray(x, dtype=float)
    nper = int(min(x.size, 4 * fs))  # 0.25 Hz bins
    f, p = welch(x - x.mean(), fs=fs, nperseg=nper)
    inside = (f >= band[0]) & (f <= band[1])
    if not inside.any():
        raise ValueError(f"no Welch bin between {band[0]} and {band[1]} Hz at fs = {fs} Hz and {x.size} samples")
    return float(f[inside][np.argmin(p[inside])])


def independent_ground_truth(x, fs, band=(1.5, 5.0)):
    """(voluntary, tremor, cutoff): the offline truth of a recording, :func:`wake.eval.truth.tremor_truth`
    at :func:`independent_cutoff` (a high-pass with a smooth transition, safe against start transients,
    steps and gaps; before issue 46 the sharp FFT high-pass)."""
    from wake.eval.truth import tremor_truth

    return tremor_truth(x, fs, band=band)


def slice_nrmse(truth, estimate, fs, slices=None):
    """NRMSE of ``estimate`` against ``truth`` over each slice of time since start.

    Each slice is normalised by the range of the truth within it (the
    paper's NRMSE applied to that stretch).  Slices the recording does not
    reach are NaN; samples without a truth (NaN: a gap) are left out.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.warmup import slice_nrmse
    >>> t = np.arange(1000) / 100.0
    >>> s = slice_nrmse(np.sin(t), np.sin(t) + 0.01, 100.0)
    >>> round(s["after 5 s"], 4) > 0
    True
    """
    truth = np.asarray(truth, dtype=float)
    estimate = np.asarray(estimate, dtype=float)
    out = {}
    for name, (a, b) in (slices or SLICES).items():
        lo = int(round(a * fs))
        hi = truth.size if b is None else min(truth.size, int(round(b * fs)))
        if hi - lo < 2:
            out[name] = float("nan")
            continue
        known = np.isfinite(truth[lo:hi])                 # a gap has no truth (wake.eval.truth): left out
        t, e = truth[lo:hi][known], estimate[lo:hi][known]
        if t.size < 2:
            out[name] = float("nan")
            continue
        span = t.max() - t.min()
        out[name] = float(np.sqrt(np.mean((t - e) ** 2)) / span) if span > 0 else float("nan")
    return out


def error_curve(truth, estimate, fs, bin_s=0.5, start_s=0.5):
    """RMS error per ``bin_s`` of time since start, over the range of the truth from ``start_s`` on.

    One normalisation for the whole recording (unlike :func:`slice_nrmse`),
    so the curve shows how the error itself falls as the filter warms up.

    Returns
    -------
    t : numpy.ndarray
        Bin centres, seconds since start.
    err : numpy.ndarray
        RMS error in the bin divided by ``max(truth) - min(truth)`` after ``start_s``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.warmup import error_curve
    >>> t, e = error_curve(np.sin(np.arange(1000) / 10.0), np.zeros(1000), 100.0)
    >>> t[:2].tolist(), bool(np.all(e > 0))
    ([0.25, 0.75], True)
    """
    truth = np.asarray(truth, dtype=float)
    estimate = np.asarray(estimate, dtype=float)
    if truth.shape != estimate.shape or truth.ndim != 1:
        raise ValueError(f"truth and estimate must be 1-D of one length, got {truth.shape} and {estimate.shape}")
    width = int(round(bin_s * fs))
    if width < 1:
        raise ValueError(f"bin_s = {bin_s} s is shorter than one sample at fs = {fs} Hz")
    lo = int(round(start_s * fs))
    span = np.ptp(truth[lo:]) if truth.size > lo + 1 else 0.0
    n = truth.size // width
    sq = ((truth[: n * width] - estimate[: n * width]) ** 2).reshape(n, width)
    err = np.sqrt(sq.mean(axis=1)) / span if span > 0 else np.full(n, np.nan)
    return (np.arange(n) + 0.5) * bin_s, err


def mean_slices(rows):
    """Mean over signals of :func:`slice_nrmse` dictionaries (NaN slices left out)."""
    return {name: float(np.nanmean([r[name] for r in rows])) for name in rows[0]}


def mean_curve(curves):
    """Mean of :func:`error_curve` outputs over signals, on the shortest common time axis."""
    n = min(len(t) for t, _ in curves)
    return curves[0][0][:n], np.nanmean([e[:n] for _, e in curves], axis=0)


# -- what any HPA could reach in the first seconds -------------------------------------------------


def approximation_predictions(x, config=None):
    """The RTP's one-step-ahead prediction of each approximation alone: column j is ``voluntary`` with ``w = e_j``.

    With the Kalman filter inert (the default) WAKE's prediction is linear in
    the weights, so ``approximation_predictions(x) @ w`` is what
    ``WakeFilter.run(x).voluntary`` gives while the weights are ``w``
    (float reference; row 0 is 0, nothing has been seen).

    Parameters
    ----------
    x : array_like, shape (n,)
        One channel.
    config : WakeConfig, optional
        ``wavelet``, ``level`` and ``mode`` are used (default: ``WakeConfig()``).

    Returns
    -------
    numpy.ndarray, shape (n, level)

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.warmup import approximation_predictions
    >>> A = approximation_predictions(np.ones(64))
    >>> A.shape, float(A[0, 0]), bool(np.allclose(A[40:].sum(axis=1) > 0, True))
    ((64, 5), 0.0, True)
    """
    from wake.config import WakeConfig
    from wake.rtp.reference import ReferenceRTP
    from wake.wavelets import filter_bank_taps

    config = WakeConfig() if config is None else config
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or not np.isfinite(x).all():
        raise ValueError(f"x must be one channel of finite samples, shape (n,); got shape {x.shape}"
                         + ("" if x.ndim != 1 else " with NaN or inf"))
    taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    out = np.zeros((x.size, config.level))
    for j in range(config.level):
        unit = np.zeros(config.level)
        unit[j] = 1.0
        out[1:, j] = ReferenceRTP(taps, unit, 1.0).run(x)[:-1]
    return out


def truth_fitted_prediction(x, voluntary, fs, config=None, *, refit_s=None, pull=0.0, start_s=0.0):
    """WAKE's prediction with weights fitted by least squares to the *true* voluntary motion.

    A yardstick, not a method: an HPA estimates the voluntary motion of its
    window (cut-off, sharp high-pass) and fits ``w`` to that estimate; here
    the fit gets the truth itself, on every sample seen so far (from
    ``start_s``).  That takes the HPA's estimation error out; what is left
    is how well fixed weights fitted on past samples carry over to the next
    ones.  It is not a strict lower bound: where a fit carries over badly,
    keeping the start-up weights can score lower (``pull`` spans the two;
    ``bench/warmup_bound.py`` also takes a per-signal hindsight choice).

    Parameters
    ----------
    x : array_like, shape (n,)
        The measurement (one channel).
    voluntary : array_like, shape (n,)
        Its true voluntary motion.
    fs : float
        Sampling rate, Hz.
    config : WakeConfig, optional
        Filter bank and start-up weights (``prior_weights(config)``).
    refit_s : sequence of float, optional
        Times (s) at which the weights are refitted, on every sample before;
        ``None``: before every sample, from 0.5 s (the limit of any HPA
        schedule).  Before the first refit the start-up weights predict.
    pull : float
        Pulls the fit towards the start-up weights ``w0``:
        ``min |v - A w|^2 + pull * tr(A'A) / J * |w - w0|^2``.
    start_s : float
        First sample used by the fits.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The prediction ``v_hat[n]`` from the samples before ``n``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.warmup import truth_fitted_prediction
    >>> t = np.arange(300) / 100.0
    >>> v = np.sin(2 * np.pi * 0.5 * t); x = v + 0.2 * np.sin(2 * np.pi * 9 * t)
    >>> p = truth_fitted_prediction(x, v, 100.0)
    >>> bool(np.sqrt(np.mean((p[100:] - v[100:]) ** 2)) < 0.05)
    True
    """
    from wake.config import WakeConfig
    from wake.hpa.prior import prior_weights

    config = WakeConfig(fs=fs) if config is None else config
    voluntary = np.asarray(voluntary, dtype=float)
    A = approximation_predictions(x, config)
    if voluntary.shape != (A.shape[0],):
        raise ValueError(f"voluntary must have the shape of x, {(A.shape[0],)}; got {voluntary.shape}")
    if pull < 0:
        raise ValueError(f"pull must be >= 0, got {pull}")
    w0 = prior_weights(config)
    J = A.shape[1]
    first = max(1, int(round(start_s * fs)))     # row 0 predicts nothing
    if refit_s is None:
        at = set(range(max(first + 1, int(round(0.5 * fs))), A.shape[0]))
    else:
        at = {int(round(t * fs)) for t in refit_s}
    out = A @ w0
    gram, rhs, w = np.zeros((J, J)), np.zeros(J), w0
    for n in range(first, A.shape[0]):
        if n in at and gram.any():
            scale = pull * np.trace(gram) / J
            w = np.linalg.lstsq(gram + scale * np.eye(J), rhs + scale * w0, rcond=None)[0]
        out[n] = A[n] @ w
        gram += np.outer(A[n], A[n])
        rhs += A[n] * voluntary[n]
    return out
