"""Wavelet approximations: the HPA's full-window ones and the RTP's filter bank.

The paper uses the level-j approximation ``a_j`` of a signal: the signal
rebuilt from its level-j approximation coefficients alone, every detail set
to zero.  Two views of the same operator live here:

* :func:`wavelet_approximations` applies it to a whole HPA window with
  PyWavelets (the paper's matrix ``A_L``).
* :func:`filter_bank_taps` turns it into ``J`` fixed FIR tap vectors of
  length ``2**J``.  Because the decomposition and the reconstruction are
  linear, the value of ``a_j`` at the *newest* sample of a ``2**J`` window is
  a dot product of the window with one tap vector.  That is the per-sample
  filter bank of the RTP, and what the fixed-point C core computes.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pywt

from wake._validation import check_level, check_mode, check_wavelet
from wake.limits import MAX_LEVEL

__all__ = [
    "default_weights",
    "wavelet_approximations",
    "filter_bank_taps",
    "sliding_rows",
    "filter_bank_outputs",
    "DEFAULT_MODE",
]

#: Signal extension mode at the window boundaries.  The paper leaves it open;
#: ``"constant"`` (edge replication) measured best for the causal end-of-window
#: output on the synthetic set (docs/studies/design.md, "Boundary mode").
DEFAULT_MODE = "constant"


def _approximation(x: np.ndarray, wavelet: pywt.Wavelet, level: int, mode: str) -> np.ndarray:
    """Rebuild ``x`` from its level-``level`` approximation coefficients only."""
    with warnings.catch_warnings():
        # A level above pywt.dwt_max_level only means every coefficient feels
        # the boundary; for the short RTP window that is the point.
        warnings.simplefilter("ignore", UserWarning)
        coeffs = pywt.wavedec(x, wavelet, mode=mode, level=level)
    coeffs = [coeffs[0]] + [np.zeros_like(c) for c in coeffs[1:]]
    return pywt.waverec(coeffs, wavelet, mode=mode)[: x.shape[0]]


def wavelet_approximations(x, wavelet="sym3", level=5, mode=DEFAULT_MODE):
    """Level-1..J wavelet approximations of a window (the paper's ``A_L``).

    Parameters
    ----------
    x : array_like, shape (n,)
        Window of samples.  ``n`` must be at least ``2**level``.
    wavelet : str
        A discrete PyWavelets wavelet name (``pywt.wavelist(kind="discrete")``).
    level : int
        Number of approximation levels ``J`` (1 <= J <= 8).
    mode : str
        PyWavelets signal extension mode.

    Returns
    -------
    numpy.ndarray, shape (n, level)
        Column ``j - 1`` is the level-``j`` approximation, same length as ``x``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.wavelets import wavelet_approximations
    >>> x = np.sin(2 * np.pi * 0.5 * np.arange(256) / 100.0)
    >>> A = wavelet_approximations(x, "sym3", 3)
    >>> A.shape
    (256, 3)
    >>> bool(np.abs(A[:, 0] - x).max() < 0.01)   # level 1 keeps a slow sine
    True
    """
    wav = check_wavelet(wavelet)
    level = check_level(level, MAX_LEVEL)
    mode = check_mode(mode)
    x = np.asarray(x, dtype=float)
    if x.ndim != 1:
        raise ValueError(f"x must be one-dimensional, got shape {x.shape}")
    if x.shape[0] < 2**level:
        raise ValueError(
            f"a level-{level} decomposition needs at least 2**{level} = {2**level} samples, "
            f"got {x.shape[0]}; use a longer window or a lower level"
        )
    return np.column_stack([_approximation(x, wav, j, mode) for j in range(1, level + 1)])


def filter_bank_taps(wavelet="sym3", level=5, mode=DEFAULT_MODE):
    """FIR taps of the RTP filter bank.

    Row ``j - 1`` holds the ``2**level`` taps whose dot product with the
    newest ``2**level`` samples (oldest first) equals the level-``j``
    approximation of that window at its newest sample.

    Parameters
    ----------
    wavelet, level, mode
        As in :func:`wavelet_approximations`.

    Returns
    -------
    numpy.ndarray, shape (level, 2**level)

    Examples
    --------
    >>> from wake.wavelets import filter_bank_taps
    >>> taps = filter_bank_taps("sym3", 5)
    >>> taps.shape
    (5, 32)
    >>> bool(abs(taps.sum(axis=1) - 1).max() < 1e-9)   # unit gain at DC
    True
    """
    wav = check_wavelet(wavelet)
    level = check_level(level, MAX_LEVEL)
    mode = check_mode(mode)
    if isinstance(wavelet, str):
        # a constant of (name, level, mode): probed once per process (160 PyWavelets calls at level 5), not
        # at every filter's construction
        return _named_taps(wavelet, level, mode).copy()
    return _taps(wav, level, mode)


@functools.lru_cache(maxsize=64)
def _named_taps(name, level, mode):
    return _taps(pywt.Wavelet(name), level, mode)


def _taps(wav, level, mode):
    n = 2**level
    taps = np.empty((level, n))
    eye = np.eye(n)
    for j in range(1, level + 1):
        # The operator is linear: its last output row, probed with unit impulses.
        taps[j - 1] = [_approximation(eye[i], wav, j, mode)[-1] for i in range(n)]
    return taps


def filter_bank_outputs(x, taps):
    """Filter bank outputs at every sample whose window is full.

    Parameters
    ----------
    x : array_like, shape (n,) or (W, n)
        One window, or a stack of windows of one length (the outputs of each, ``(W, n - N + 1, J)``).
    taps : array_like, shape (J, N)

    Returns
    -------
    numpy.ndarray, shape (n - N + 1, J)
        Row ``i`` is the filter bank applied to ``x[i : i + N]``, i.e. the
        RTP's approximations at sample ``i + N - 1``.
    """
    taps = np.asarray(taps, dtype=float)
    x = np.asarray(x, dtype=float)
    n_taps = taps.shape[1]
    if x.shape[-1] < n_taps:
        raise ValueError(f"need at least {n_taps} samples for the filter bank, got {x.shape[-1]}")
    return sliding_rows(x, n_taps) @ taps.T


def sliding_rows(x, n: int) -> np.ndarray:
    """``numpy.lib.stride_tricks.sliding_window_view(x, n, axis=-1)``, read-only, built directly: the same view
    (shape, strides, values) without the helper's argument handling, which costs several times the view on
    the per-window paths (the filter bank over an HPA window, the float RTP's block).

    Examples
    --------
    >>> sliding_rows(np.arange(5.0), 3).tolist()
    [[0.0, 1.0, 2.0], [1.0, 2.0, 3.0], [2.0, 3.0, 4.0]]
    """
    x = np.asarray(x)
    if not 1 <= n <= x.shape[-1]:
        raise ValueError(f"need a window length n in [1, {x.shape[-1]}] (the last axis's length), got {n}")
    shape, strides = x.shape[:-1] + (x.shape[-1] - n + 1, n), x.strides + (x.strides[-1],)
    if not x.flags.c_contiguous:
        return np.lib.stride_tricks.as_strided(x, shape, strides, writeable=False)
    rows = np.ndarray(shape, x.dtype, x, 0, strides)
    rows.flags.writeable = False
    return rows


def default_weights(level):
    """Weights of the filter bank's deepest approximation alone, a plain low-pass: the RTP's weights before
    any HPA fit (:mod:`wake.hpa.fit` re-exports it).

    Examples
    --------
    >>> default_weights(3)
    array([0., 0., 1.])
    """
    w = np.zeros(level)
    w[-1] = 1.0
    return w
