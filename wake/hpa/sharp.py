"""Sharp FFT high-pass filter (the paper's Algorithm "sharp high-pass")."""

from __future__ import annotations

import numpy as np

from wake._validation import check_positive

__all__ = ["sharp_highpass"]


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
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    spectrum = np.fft.rfft(x, axis=0)
    keep = np.fft.rfftfreq(n, 1.0 / fs) > cutoff
    spectrum[~keep] = 0.0
    return np.fft.irfft(spectrum, n, axis=0)
