"""Sharp FFT high-pass filter (the paper's Algorithm "sharp high-pass")."""

from __future__ import annotations

import functools

import numpy as np

from wake._validation import check_positive

__all__ = ["sharp_highpass", "end_point_line", "detrended_highpass"]


def sharp_highpass(x, fs, cutoff):
    """Zero every FFT bin at or below ``cutoff`` and transform back.

    S1 FFT of the window; S2 an index vector with ones above ``f_d``; S3 their
    product; S4 the inverse FFT.  The result is the tremor ground truth of an
    HPA window; ``x - sharp_highpass(x, fs, f_d)`` is the voluntary one.

    Parameters
    ----------
    x : array_like, shape (n,) or (n, channels)
        Samples along axis 0.
    fs : float
        Sampling rate in Hz.
    cutoff : float
        ``f_d`` in Hz, ``0 <= cutoff <= fs/2``.

    Returns
    -------
    numpy.ndarray, same shape as ``x``

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa.sharp import sharp_highpass
    >>> t = np.arange(500) / 100.0
    >>> x = np.sin(2 * np.pi * 0.4 * t) + 0.2 * np.sin(2 * np.pi * 8 * t)
    >>> bool(np.allclose(sharp_highpass(x, 100.0, 3.0), 0.2 * np.sin(2 * np.pi * 8 * t)))
    True
    """
    fs = check_positive("fs", fs)
    cutoff = check_positive("cutoff", cutoff, allow_zero=True)
    if cutoff > fs / 2:
        raise ValueError(f"cutoff must be within [0, fs/2 = {fs / 2}] Hz, got {cutoff}")
    return _zero_below(np.asarray(x, dtype=float), fs, cutoff, axis=0)


def _zero_below(x, fs, cutoff, axis):
    """The sharp high-pass along ``axis``: every FFT bin at or below ``cutoff`` zeroed.  ``cutoff`` is one
    number, or along the last axis one per row of ``x`` (W, n) (each row's bins those of its own FFT)."""
    n = x.shape[axis]
    spectrum = np.fft.rfft(x, axis=axis)
    keep = _bin_freqs(n, fs) > (cutoff if np.ndim(cutoff) == 0 else np.asarray(cutoff)[:, None])
    spectrum[~keep] = 0.0
    return np.fft.irfft(spectrum, n, axis=axis)


@functools.lru_cache(maxsize=64)
def _bin_freqs(n: int, fs: float) -> np.ndarray:
    """``np.fft.rfftfreq(n, 1 / fs)``, read-only, made once per window length and rate."""
    freqs = np.fft.rfftfreq(n, 1.0 / fs)
    freqs.flags.writeable = False
    return freqs


def end_point_line(x):
    """The line through the first and the last sample of ``x`` (1-D), sample by sample.

    Examples
    --------
    >>> from wake.hpa.sharp import end_point_line
    >>> end_point_line([1.0, 5.0, -2.0, 4.0]).tolist()
    [1.0, 2.0, 3.0, 4.0]
    """
    x = np.asarray(x, dtype=float)
    if x.ndim not in (1, 2) or x.shape[-1] < 2:
        raise ValueError(f"need a 1-D window of at least 2 samples (or a stack of them, one per row), got "
                         f"shape {x.shape}")
    n = x.shape[-1]
    first, last = x[..., :1], x[..., -1:]
    return first + (last - first) * (np.arange(n) / (n - 1))


def detrended_highpass(x, fs, cutoff):
    """:func:`sharp_highpass` of ``x`` minus the line through its end points: the HPA's tremor ground truth.

    The FFT treats the window as one period of a periodic signal.  A window
    that ends higher than it starts (a voluntary movement in progress) then
    has a jump at the seam, and the jump's high-frequency content would land
    in the tremor truth at both ends of the window, where the causal fit's
    newest rows are.  The line through the first and last samples is
    voluntary by definition; taking it out first removes the jump
    (docs/studies/design.md, "Tremor ground truth of a window").

    ``x`` may be a stack of windows of one length, ``(W, n)``, with ``cutoff`` one per row (``(W,)``, each
    within ``[0, fs/2]``).

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa.sharp import detrended_highpass, sharp_highpass
    >>> t = np.arange(500) / 100.0
    >>> ramp = 0.5 * t                                   # voluntary drift, no tremor
    >>> float(np.abs(sharp_highpass(ramp, 100.0, 2.0)).max()) > 0.5
    True
    >>> float(np.abs(detrended_highpass(ramp, 100.0, 2.0)).max()) < 1e-12
    True
    """
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        return sharp_highpass(x - end_point_line(x), fs, cutoff)
    # a stack of windows (W, n), a cut-off per row: each row bit for bit its own window's truth
    fs = check_positive("fs", fs)
    cutoff = np.asarray(cutoff, dtype=float)
    if cutoff.shape != x.shape[:1] or not (cutoff.size == 0 or (cutoff.min() >= 0 and cutoff.max() <= fs / 2)):
        raise ValueError(f"a stack of {x.shape[0]} windows needs {x.shape[0]} cut-offs, each within [0, fs/2 = "
                         f"{fs / 2}] Hz; got {cutoff!r}")
    return _zero_below(x - end_point_line(x), fs, cutoff, axis=-1)
