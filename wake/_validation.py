"""Input checks shared by the public functions.

Every check raises :class:`ValueError` (or :class:`TypeError` for a wrong
type) with a message that names what was wrong and what would be valid.
"""

from __future__ import annotations

import math
import numbers
import sys

import numpy as np
import pywt

_DISCRETE = tuple(pywt.wavelist(kind="discrete"))
_MODES = tuple(pywt.Modes.modes)


def check_wavelet(name) -> pywt.Wavelet:
    """Return the PyWavelets wavelet for ``name`` or say which names exist."""
    if isinstance(name, pywt.Wavelet):
        return name
    if not isinstance(name, str) or name not in _DISCRETE:
        families = ", ".join(pywt.families(short=True)[:7])
        raise ValueError(
            f"unknown wavelet {name!r}; use a discrete PyWavelets name such as "
            f"'sym3', 'db3', 'haar' (families: {families}; full list: pywt.wavelist(kind='discrete'))"
        )
    return pywt.Wavelet(name)


def check_mode(mode) -> str:
    if mode not in _MODES:
        raise ValueError(f"unknown extension mode {mode!r}; valid modes: {', '.join(_MODES)}")
    return mode


def check_level(level, max_level: int) -> int:
    if isinstance(level, bool) or not isinstance(level, numbers.Integral):
        raise ValueError(f"level must be an integer from 1 to {max_level}, got {level!r}")
    level = int(level)
    if not 1 <= level <= max_level:
        raise ValueError(f"level must be from 1 to {max_level}, got {level}")
    return level


def check_positive(name: str, value, *, integer: bool = False, allow_zero: bool = False):
    """A finite positive number (or integer)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a {'positive integer' if integer else 'positive number'}, got {value!r}")
    if integer and not float(value).is_integer():
        raise ValueError(f"{name} must be an integer, got {value!r}")
    value = int(value) if integer else float(value)
    if not np.isfinite(value) or value < 0 or (value == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be finite and {bound}, got {value!r}")
    return value


def as_signal(x, *, name: str = "x", allow_nan: bool = False) -> tuple[np.ndarray, bool]:
    """Normalise a recording to a float64 array of shape ``(n, channels)``.

    Returns the 2-D array and whether the input was 1-D.  Integer and float32
    input are accepted and converted; booleans, complex numbers, objects and
    arrays of more than two dimensions are refused.  A masked array's masked
    entries are missing samples: NaN where ``allow_nan``, else refused.
    """
    # a masked array exists only once numpy.ma is imported: reading np.ma here would import it (and format its
    # docstrings) at filtering time, the first time any signal comes through
    ma = sys.modules.get("numpy.ma")
    masked = ma.getmaskarray(x) if ma is not None and ma.isMaskedArray(x) else None
    arr = np.asarray(ma.getdata(x) if masked is not None else x)
    if arr.dtype == bool or arr.dtype.kind not in "iuf":
        raise ValueError(
            f"{name} must hold real numbers (integer or float), got dtype {arr.dtype}; "
            f"convert it with np.asarray({name}, dtype=float)"
        )
    if arr.ndim == 0:
        raise ValueError(f"{name} must be an array of shape (n,) or (n, channels), got a scalar")
    if arr.ndim > 2:
        raise ValueError(
            f"{name} must have shape (n,) or (n, channels), got {arr.ndim} dimensions {arr.shape}; "
            "reshape it to (n, channels)"
        )
    one_d = arr.ndim == 1
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {np.shape(x)}); give at least one sample per channel")
    arr = arr.astype(np.float64, copy=True).reshape(arr.shape[0], -1)
    if masked is not None and masked.any():
        if not allow_nan:
            raise ValueError(f"{name} is a masked array with {int(masked.sum())} masked value(s); "
                             f"fill them (np.ma.filled) or pass NaN for missing samples where accepted")
        arr[masked.reshape(arr.shape)] = np.nan
    if not allow_nan:
        bad = ~np.isfinite(arr)
        if bad.any():
            i, c = np.argwhere(bad)[0]
            raise ValueError(
                f"{name} holds {int(bad.sum())} non-finite value(s) (first at sample {i}, channel {c}: "
                f"{arr[i, c]!r}); remove or interpolate them, or stream with update() which "
                "treats NaN as a missing sample"
            )
    elif np.isinf(arr).any():
        raise ValueError(f"{name} holds inf; only NaN is accepted as a missing-sample marker: "
                         "pass NaN for a missing sample")
    return arr, one_d


def as_sample(sample, *, name: str = "sample") -> np.ndarray:
    """Normalise one streamed sample (a number, or one number per channel) to a 1-D float64 array.

    The policy of :func:`as_signal` with ``allow_nan=True``, applied to the
    sample as a column of channel values: real numbers only (``True``,
    ``None``, strings and bytes are refused rather than coerced), NaN or a
    masked entry marks a missing sample, inf is refused.
    """
    if sample is None or isinstance(sample, (str, bytes, bool, np.bool_)):  # refused, not coerced
        raise ValueError(f"{name} must be a real number or one per channel, got {sample!r}; "
                         "pass NaN for a missing sample")
    if np.ndim(sample) > 1:
        raise ValueError(f"{name} must be a number or a 1-D array of one value per channel, "
                         f"got shape {np.shape(sample)}; use update_block() for several samples")
    column = np.ma.atleast_1d(sample) if np.ma.isMaskedArray(sample) else np.atleast_1d(sample)
    return as_signal(column, name=name, allow_nan=True)[0].reshape(-1)


def check_number(name: str, value, limits, *, integer: bool = False, low_open: bool = False):
    """``value`` as an int (``integer``) or float within ``limits = (lo, hi)`` (``lo`` excluded with ``low_open``)."""
    lo, hi = limits
    kind = "an integer" if integer else "a number"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be {kind} in {'(' if low_open else '['}{lo:g}, {hi:g}], got {value!r}")
    if integer:
        if not float(value).is_integer():
            raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r}")
        value = int(value)
    else:
        value = float(value)
    ok = math.isfinite(value) and (value > lo if low_open else value >= lo) and value <= hi
    if not ok:
        raise ValueError(f"{name} must lie in {'(' if low_open else '['}{lo:g}, {hi:g}], got {value!r}")
    return value


def check_pair(name: str, value) -> tuple[float, float]:
    """Two finite numbers ``(low, high)`` in Hz."""
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (low, high) in Hz, got {value!r}") from None
    for v in (lo, hi):
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
            raise ValueError(f"{name} must hold two finite numbers, got {value!r}")
    return float(lo), float(hi)


class SparseChannelWarning(UserWarning):
    """A channel of a recording holds fewer finite samples than one HPA window (:func:`check_finite_channels`)."""


def check_finite_channels(x, window_samples: int, names=None) -> None:
    """The rule for a whole recording's channels: each must hold enough finite samples to be scored.

    A channel without a single finite sample (all NaN: missing throughout) is
    an error: there is nothing to filter, and its outputs would be NaN or
    zero without a word.  A channel with some finite samples, but fewer than
    one HPA window, is filtered with a :class:`SparseChannelWarning` naming
    it: its HPA windows rest on interpolated or missing samples, so neither
    its voluntary motion nor its tremor can be trusted.

    Parameters
    ----------
    x : numpy.ndarray, shape (n, channels)
        The recording, NaN marking a missing sample.
    window_samples : int
        ``L``, the HPA window in samples at the rate of ``x``.
    names : sequence of str, optional
        The channels' names for the messages (default ``channel 0``, ...).

    Raises
    ------
    ValueError
        Naming every channel without a finite sample (or when ``names`` does
        not hold one name per channel).

    Examples
    --------
    >>> import numpy as np
    >>> from wake._validation import check_finite_channels
    >>> x = np.column_stack([np.ones(600), np.full(600, np.nan)])
    >>> check_finite_channels(x, 500, names=["wrist", "elbow"])
    Traceback (most recent call last):
    ...
    ValueError: channel elbow has no finite sample (every value is NaN or missing): there is nothing to filter; leave it out (wake run --column) or fix the recording
    """
    if names is not None and len(names) != x.shape[1]:
        raise ValueError(f"names holds {len(names)} name(s) for the {x.shape[1]} channel(s) of x")
    finite = np.count_nonzero(np.isfinite(x), axis=0)
    if finite.min(initial=window_samples) >= window_samples:   # the usual recording: nothing to say
        return
    label = [f"channel {c}" for c in range(x.shape[1])] if names is None else \
        [f"channel {name}" for name in names]
    empty = [label[c] for c in np.flatnonzero(finite == 0)]
    if empty:
        raise ValueError(f"{' and '.join(empty)} {'has' if len(empty) == 1 else 'have'} no finite sample (every "
                         "value is NaN or missing): there is nothing to filter; leave it out (wake run --column) "
                         "or fix the recording")
    import warnings

    for c in np.flatnonzero(finite < window_samples):
        warnings.warn(f"{label[c]} has {int(finite[c])} finite samples, fewer than one HPA window "
                      f"({window_samples}): too few for WAKE to fit its voluntary motion or characterise its "
                      "tremor reliably (the HPA windows rest on interpolated or missing samples)",
                      SparseChannelWarning, stacklevel=3)
