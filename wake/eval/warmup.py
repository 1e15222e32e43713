"""Scores by time since start: what a wearer lives through in the first seconds.

The paper leaves the first HPA window (5 s) out of every score.  A wearer
does not, so the functions here score each method per slice of time since
switch-on (:data:`SLICES`), beside the whole recording from 0.5 s, against a
ground truth that does not depend on WAKE's own cut-off
(:func:`independent_ground_truth`).
"""

from __future__ import annotations

import numpy as np
import scipy.signal

from wake.hpa.sharp import sharp_highpass

__all__ = ["SLICES", "independent_cutoff", "independent_ground_truth", "slice_nrmse", "error_curve", "mean_slices",
           "mean_curve"]

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
    x = np.asarray(x, dtype=float)
    nper = int(min(x.size, 4 * fs))  # 0.25 Hz bins
    f, p = scipy.signal.welch(x - x.mean(), fs=fs, nperseg=nper)
    inside = (f >= band[0]) & (f <= band[1])
    if not inside.any():
        raise ValueError(f"no Welch bin between {band[0]} and {band[1]} Hz at fs = {fs} Hz and {x.size} samples")
    return float(f[inside][np.argmin(p[inside])])


def independent_ground_truth(x, fs, band=(1.5, 5.0)):
    """(voluntary, tremor, cutoff): sharp FFT high-pass at :func:`independent_cutoff`."""
    cutoff = independent_cutoff(x, fs, band)
    tremor = sharp_highpass(np.asarray(x, dtype=float), fs, cutoff)
    return np.asarray(x, dtype=float) - tremor, tremor, cutoff


def slice_nrmse(truth, estimate, fs, slices=None):
    """NRMSE of ``estimate`` against ``truth`` over each slice of time since start.

    Each slice is normalised by the range of the truth within it (the
    paper's NRMSE applied to that stretch).  Slices the recording does not
    reach are NaN.

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
        t, e = truth[lo:hi], estimate[lo:hi]
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
