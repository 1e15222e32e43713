"""MATLAB ``.mat`` recordings (:func:`read_mat`), read by the rules of :mod:`wake.io.readers`.

:func:`wake.io.read_recording` hands a ``.mat`` file (or ``format="mat"``) to :func:`read_mat`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wake.io.readers import _finish, _no_time
from wake.io.recording import Recording
from wake.io.time_column import TimeUnit

__all__ = ["read_mat"]

_MAT_TIME = ("t", "time", "timestamp", "timestamps", "Time", "T")
_MAT_RATE = ("fs", "Fs", "FS", "srate", "sampling_rate", "sample_rate", "samplerate", "SampleRate")


def read_mat(path, *, fs=None, time_column="auto", columns=None, name=None, resample=False) -> Recording:
    """A MATLAB ``.mat`` file (v4 to v7; v7.3 is HDF5 and is refused with a hint).

    Numeric variables of the recording's length become channels: a vector is
    one channel named after the variable, an ``n x k`` matrix (or ``k x n``)
    gives ``var_0 .. var_{k-1}``.  A vector named ``t`` / ``time`` /
    ``timestamp`` is the time column; a scalar named ``fs`` / ``Fs`` /
    ``srate`` / ``sampling_rate`` is the rate when ``fs`` is not given.
    """
    import scipy.io

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    try:
        mat = scipy.io.loadmat(path, squeeze_me=False)
    except NotImplementedError:
        raise ValueError(f"{path}: a MATLAB v7.3 (HDF5) file; save it with save(..., '-v7') or export a CSV") \
            from None
    # IndexError: scipy 1.8-1.12's loadmat on a short non-MATLAB file (later releases raise MatReadError)
    except (ValueError, TypeError, OSError, IndexError, scipy.io.matlab.MatReadError) as exc:
        raise ValueError(f"{path}: not a readable MATLAB file ({exc})") from None
    arrays = {k: np.asarray(v) for k, v in mat.items() if not k.startswith("__")}
    numeric = {k: v for k, v in arrays.items() if v.dtype.kind in "iuf" and v.size > 0}
    rate_source = "--fs"
    if fs is None:
        for k in _MAT_RATE:
            if k in numeric and numeric[k].size == 1:
                fs = float(numeric.pop(k).reshape(-1)[0])
                rate_source = f"the file's {k!r} variable"
                break
    else:
        for k in _MAT_RATE:
            numeric.pop(k, None)
    time = None
    if not _no_time(time_column):
        keys = _MAT_TIME if time_column == "auto" else (time_column,)
        for k in keys:
            if k in numeric and 1 in numeric[k].shape and numeric[k].size > 1:
                time = numeric.pop(k).reshape(-1).astype(float)
                break
        else:
            if time_column != "auto":
                raise ValueError(f"{path}: no time vector {time_column!r}; variables: {', '.join(arrays)}")
    length = time.size if time is not None else max((max(v.shape) for v in numeric.values()), default=0)
    names, cols = [], []
    for k, v in numeric.items():
        v = v.astype(float)
        if v.ndim != 2 or length not in v.shape:
            continue
        v = v if v.shape[0] == length else v.T
        if v.shape[1] == 1:
            names.append(k)
            cols.append(v[:, 0])
        else:
            names.extend(f"{k}_{i}" for i in range(v.shape[1]))
            cols.extend(v.T)
    if not cols:
        what = f"of {length} samples" if length else "of numbers"
        raise ValueError(f"{path}: no numeric vector or matrix {what}; variables: "
                         f"{', '.join(f'{k} {v.shape}' for k, v in arrays.items())}")
    data = np.column_stack(cols)
    if np.isinf(data).any():
        raise ValueError(f"{path}: a variable holds inf (use nan for a missing sample)")
    time_index = None
    if time is not None:
        data = np.column_stack([time, data])
        names = ["time", *names]
        time_index = 0
    units = [""] * len(names)
    return _finish(path, name or path.stem, lambda j: data[:, j], names, units, time_index, TimeUnit(), fs, columns,
                   rate_source=rate_source, resample=resample)
