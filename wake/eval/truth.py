"""The offline tremor ground truth of a real recording: one definition for every real-data score.

A recording's tremor is not known; every real-data evaluation (``wake evaluate``, the benches, the tests)
scores against the part of the whole recording above a cut-off that WAKE never sees
(:func:`wake.eval.warmup.independent_cutoff`, the Welch valley between 1.5 and 5 Hz).  How that part is
taken decides whether the truth survives a real recording:

* the paper's **sharp FFT high-pass** (every bin at or below the cut-off zeroed) has an impulse response
  that decays as ``1/t``: a step (a phone put down on a table, 1.7 -> 9.6 m/s^2 in 3 s) rings across the
  whole recording, and the FFT's wrap-around joins the last sample to the first;
* :func:`smooth_highpass`, used here, takes out the line through the end points (no seam), mirrors the
  record at both ends (no wrap-around step) and passes the spectrum through a **raised-cosine transition**
  ``TRANSITION_HZ`` wide centred on the cut-off: its impulse response decays within about
  ``2 / TRANSITION_HZ`` s, so a step or a start transient corrupts the truth next to it only;
* a **gap** (NaN samples) splits the recording: each finite run gets its own truth (a run shorter than
  ``MIN_RUN_S`` gets none: NaN), and the gap stays NaN (no score is taken there).

The choice was made by measurement (docs/studies/evaluation.md, "The tremor ground truth of a recording";
``python bench/truth_choice.py``); its failure cases are written there.

Examples
--------
>>> import numpy as np
>>> from wake.eval.truth import tremor_truth
>>> t = np.arange(3000) / 100.0
>>> tremor = 0.3 * np.sin(2 * np.pi * 6 * t)
>>> x = tremor + 8.0 * (t > 1.0)                 # a step at 1 s (a phone put down)
>>> voluntary, truth, cutoff = tremor_truth(x, 100.0)
>>> bool(np.abs(truth - tremor)[500:-100].max() < 0.01)    # the last second: the run's end (docs)
True
"""

from __future__ import annotations

import numpy as np

from wake._validation import check_positive

__all__ = ["TRANSITION_HZ", "MIN_RUN_S", "smooth_highpass", "tremor_truth", "finite_runs"]

#: Width of the raised-cosine transition band of :func:`smooth_highpass`, Hz (centred on the cut-off).
TRANSITION_HZ = 1.0

#: A finite run shorter than this (s) between gaps gets no truth (NaN): too short for a tremor period to
#: be told from its own end points.
MIN_RUN_S = 1.0


def smooth_highpass(x, fs, cutoff, transition_hz=TRANSITION_HZ):
    """Zero-phase FFT high-pass with a raised-cosine transition band, safe against steps and the seam.

    ``x`` minus the line through its end points, mirrored at both ends (length ``3 n``), through a gain of
    0 below ``cutoff - transition_hz / 2``, 1 above ``cutoff + transition_hz / 2`` and a half cosine
    between; the middle third is returned.

    Parameters
    ----------
    x : array_like, shape (n,)
        One channel of finite samples, ``n >= 2``.
    fs : float
        Sampling rate, Hz.
    cutoff : float
        Centre of the transition, Hz, in ``(0, fs/2)``.
    transition_hz : float
        Width of the transition, Hz (> 0; :data:`TRANSITION_HZ`).

    Returns
    -------
    numpy.ndarray, shape (n,)

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.truth import smooth_highpass
    >>> t = np.arange(1000) / 100.0
    >>> x = 2 * t + np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 7 * t)
    >>> bool(np.abs(smooth_highpass(x, 100.0, 3.0) - 0.2 * np.sin(2 * np.pi * 7 * t))[100:-100].max() < 5e-3)
    True
    """
    fs = check_positive("fs", fs)
    cutoff = check_positive("cutoff", cutoff)
    transition_hz = check_positive("transition_hz", transition_hz)
    if not cutoff < fs / 2:
        raise ValueError(f"cutoff must lie in (0, fs/2 = {fs / 2:g}) Hz, got {cutoff!r}")
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2 or not np.isfinite(x).all():
        raise ValueError(f"x must be one channel of at least 2 finite samples, got shape {x.shape}"
                         + ("" if x.ndim != 1 or x.size < 2 else " with NaN or inf"))
    n = x.size
    d = x - (x[0] + (x[-1] - x[0]) * np.arange(n) / (n - 1))
    ext = np.concatenate((-d[::-1], d, -d[::-1]))     # odd mirror: continuous at both joins (d is 0 there)
    f = np.fft.rfftfreq(ext.size, 1.0 / fs)
    lo, hi = cutoff - transition_hz / 2, cutoff + transition_hz / 2
    gain = np.clip((f - lo) / (hi - lo), 0.0, 1.0)
    gain = 0.5 - 0.5 * np.cos(np.pi * gain)
    return np.fft.irfft(np.fft.rfft(ext) * gain, ext.size)[n:2 * n]


def finite_runs(x):
    """``[(start, stop), ...]``: the runs of finite samples of a 1-D array.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.truth import finite_runs
    >>> finite_runs([1.0, np.nan, 2.0, 3.0, np.nan])
    [(0, 1), (2, 4)]
    """
    ok = np.isfinite(np.asarray(x, dtype=float))
    edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.astype(np.int8), [0]))))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


def tremor_truth(x, fs, cutoff=None, band=(1.5, 5.0), transition_hz=TRANSITION_HZ):
    """``(voluntary, tremor, cutoff)`` of one channel: the offline truth every real-data score uses.

    Parameters
    ----------
    x : array_like, shape (n,)
        One channel; NaN marks missing samples (a gap).
    fs : float
        Sampling rate, Hz.
    cutoff : float, optional
        Hz; by default the Welch valley of the recording between ``band[0]`` and ``band[1]``
        (:func:`wake.eval.warmup.independent_cutoff`, over the finite samples).
    band : (float, float)
        Where the valley is looked for.
    transition_hz : float
        :func:`smooth_highpass`'s transition width.

    Returns
    -------
    voluntary, tremor : numpy.ndarray, shape (n,)
        ``x - tremor`` and the tremor: :func:`smooth_highpass` of each finite run of at least
        :data:`MIN_RUN_S`; NaN in gaps and in shorter runs.
    cutoff : float

    Examples
    --------
    >>> import numpy as np
    >>> from wake.eval.truth import tremor_truth
    >>> t = np.arange(2000) / 100.0
    >>> x = np.sin(2 * np.pi * 0.4 * t) + 0.2 * np.sin(2 * np.pi * 6 * t)
    >>> x[900:950] = np.nan
    >>> v, tr, fc = tremor_truth(x, 100.0, cutoff=3.0)
    >>> bool(np.isnan(tr[900:950]).all()), bool(np.nanmax(np.abs(tr - 0.2 * np.sin(2 * np.pi * 6 * t))[100:700]) < 0.01)
    (True, True)
    """
    from wake.eval.warmup import independent_cutoff

    fs = check_positive("fs", fs)
    x = np.asarray(x, dtype=float)
    if x.ndim != 1:
        raise ValueError(f"x must be one channel, shape (n,); got shape {x.shape}")
    if np.isinf(x).any():
        raise ValueError("x holds inf: mark missing samples with NaN")
    runs = [(a, b) for a, b in finite_runs(x) if b - a >= max(2, int(round(MIN_RUN_S * fs)))]
    if not runs:
        raise ValueError(f"x has no run of finite samples at least {MIN_RUN_S:g} s long at fs = {fs:g} Hz")
    if cutoff is None:
        longest = max(runs, key=lambda r: r[1] - r[0])
        cutoff = independent_cutoff(x[longest[0]:longest[1]], fs, band)
    tremor = np.full(x.size, np.nan)
    for a, b in runs:
        tremor[a:b] = smooth_highpass(x[a:b], fs, cutoff, transition_hz)
    return x - tremor, tremor, float(cutoff)
