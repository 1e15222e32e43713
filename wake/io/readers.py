"""Read recordings: CSV (with or without a header and a time column), PADS and MATLAB ``.mat``.

:func:`read_recording` is the one entry point; it returns a
:class:`~wake.io.recording.Recording` on a uniform grid with channel names
and units.

Time column (``time_column="auto"``): the first column is taken as time when
its header names it so (``t``, ``time``, ``timestamp``, ``time_s``,
``time [ms]``, ...) or, without such a name, when it is shaped like a clock:
non-decreasing, advancing, with at least 90 % of its steps within 50 % of the
median step, and not a plain row counter (integers stepping by exactly 1:
those are read as an index and dropped, and the rate must be given).  A time
column in milliseconds must say so in its name (``time_ms``, ``t [ms]``).

Rate: ``fs`` when given, else the time column's (:func:`nominal_rate`); a
file with neither is refused with a message that names both fixes.

Header cells may carry a unit: ``acc_x [g]`` or ``acc_x (g)`` is channel
``acc_x`` in ``g``.  PADS files (7 numeric columns, time then accelerometer
x/y/z in g and gyroscope x/y/z in rad/s, no header) are recognised by shape
and get their channel names and units.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from wake._validation import check_positive
from wake.io.recording import Recording, analyse_time, nominal_rate, resample_uniform

__all__ = ["FORMATS", "PADS_CHANNELS", "PADS_UNITS", "read_recording", "read_csv", "read_pads", "read_mat"]

#: Formats :func:`read_recording` knows (``"auto"`` picks by content and suffix).
FORMATS = ("auto", "csv", "pads", "mat")
#: Channel names of a PADS recording, in file order after the time column.
PADS_CHANNELS = ("acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z")
#: Units of :data:`PADS_CHANNELS`.
PADS_UNITS = ("g", "g", "g", "rad/s", "rad/s", "rad/s")

_TIME_NAME = re.compile(r"(t|time|times|timestamp|timestamps|time_?s|time_?sec|seconds|secs?|time_?ms|elapsed)",
                        re.IGNORECASE)
_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]\s*$")
_MAT_TIME = ("t", "time", "timestamp", "timestamps", "Time", "T")
_MAT_RATE = ("fs", "Fs", "FS", "srate", "sampling_rate", "sample_rate", "samplerate", "SampleRate")


def split_unit(cell: str) -> tuple[str, str]:
    """``"acc_x [g]"`` -> ``("acc_x", "g")``; ``"acc_x"`` -> ``("acc_x", "")``."""
    cell = cell.strip()
    m = _UNIT.match(cell)
    return (m.group(1).strip(), m.group(2)) if m and m.group(1).strip() else (cell, "")


def _time_scale(name: str, unit: str) -> float | None:
    """Seconds per time unit when ``name [unit]`` names a time column, else None."""
    if unit.lower() in ("ms", "msec", "milliseconds"):
        return 1e-3
    if unit.lower() in ("us", "µs", "microseconds"):
        return 1e-6
    if not _TIME_NAME.fullmatch(name.replace(" ", "_")):
        return None
    return 1e-3 if name.lower().replace(" ", "_").endswith("ms") else 1.0


def _shaped_like_time(col: np.ndarray) -> bool:
    if col.size < 3 or not np.isfinite(col).all():
        return False
    steps = np.diff(col)
    if (steps < 0).any() or not (steps > 0).any():
        return False
    if _is_row_counter(col):
        return False  # 0, 1, 2, ... is an index, not seconds
    median = np.median(steps[steps > 0])
    return np.mean(np.abs(steps - median) <= 0.5 * median) >= 0.9


def _is_row_counter(col: np.ndarray) -> bool:
    return col.size >= 2 and np.all(np.diff(col) == 1) and np.all(col == np.round(col))


def _read_rows(path: Path):
    """All non-blank rows as lists of stripped strings; lines starting with '#' are comments."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            text = fh.read()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file (for MATLAB files use the .mat suffix or --format mat)") from None
    lines = [(i + 1, line) for i, line in enumerate(text.splitlines()) if line.strip() and not
             line.lstrip().startswith("#")]
    if not lines:
        raise ValueError(f"{path}: the file holds no data")
    sample = "\n".join(line for _, line in lines[:20])
    delimiter = ","
    if "," not in sample:
        delimiter = ";" if ";" in sample else ("\t" if "\t" in sample else None)
    rows = []
    for lineno, line in lines:
        cells = line.split() if delimiter is None else next(csv.reader([line], delimiter=delimiter))
        rows.append((lineno, [c.strip() for c in cells]))
    return rows


def _numeric(rows, path: Path) -> np.ndarray:
    width = len(rows[0][1])
    out = np.empty((len(rows), width))
    for i, (lineno, row) in enumerate(rows):
        if len(row) != width:
            raise ValueError(f"{path}, line {lineno}: {len(row)} columns where the file has {width} "
                             "(a ragged row: fix or delete that line)")
        try:
            out[i] = [float(c) if c else np.nan for c in row]
        except ValueError:
            bad = next(c for c in row if not _is_number(c))
            raise ValueError(f"{path}, line {lineno}: {bad!r} is not a number (empty cells are read as missing "
                             "samples; only a first line may hold column names)") from None
    inf = np.isinf(out)
    if inf.any():
        i = int(np.argwhere(inf)[0][0])
        raise ValueError(f"{path}, line {rows[i][0]}: infinite value (leave the cell empty or write nan for a "
                         "missing sample)")
    return out


def _is_number(cell: str) -> bool:
    try:
        float(cell)
        return True
    except ValueError:
        return not cell


def _no_time(time_column) -> bool:
    """``None`` or the string ``"none"`` (as the command line spells it): the file has no time column."""
    return time_column is None or (isinstance(time_column, str) and time_column.lower() == "none")


def _column_index(spec, names, path, what="column") -> int:
    """The file column a header name or a 0-based index (a digit string counts as an index) stands for."""
    if isinstance(spec, str) and spec.strip().lstrip("-").isdigit():
        spec = int(spec)
    if isinstance(spec, str):
        name = split_unit(spec)[0]
        if name not in names:
            raise ValueError(f"{path}: no {what} {spec!r}; columns: {', '.join(names)}")
        return names.index(name)
    if isinstance(spec, (int, np.integer)) and not isinstance(spec, bool):
        if not -len(names) <= spec < len(names):
            raise ValueError(f"{path}: {what} index {spec} out of range (the file has {len(names)} columns, "
                             f"0..{len(names) - 1})")
        return int(spec) % len(names)
    raise ValueError(f"{what} must be a name or a 0-based index, got {spec!r}")


def _select(names, columns, path, time_index):
    """File column indices for ``columns`` (names or file indices, ``None`` = every non-time column)."""
    if columns is None:
        return [i for i in range(len(names)) if i != time_index]
    if isinstance(columns, (str, int, np.integer)):
        wanted = [columns]
    elif isinstance(columns, (list, tuple)):
        wanted = list(columns)
    else:
        raise ValueError(f"column must be a name, a 0-based index or a list of them, got {columns!r}")
    idx = []
    for c in wanted:
        i = _column_index(c, names, path)
        if i == time_index:
            raise ValueError(f"{path}: column {c!r} is the time column; pass time_column=None "
                             "(--time-column none) to filter it as a signal")
        idx.append(i)
    if not idx:
        raise ValueError(f"{path}: no column selected")
    return idx


def _finish(path, name, data, names, units, time_index, time_scale, fs, columns):
    """Select the channels, take the time column and put the samples on a uniform grid."""
    idx = _select(names, columns, path, time_index)
    values = data[:, idx]
    ch_names = tuple(names[i] for i in idx)
    ch_units = tuple(units[i] for i in idx) if any(units) else ()
    if time_index is None:
        if fs is None:
            raise ValueError(f"{path} has no time column, so the sampling rate is unknown: give it with --fs HZ "
                             "(fs=...), or name the time column with --time-column NAME (time_column=...)")
        fs = check_positive("fs", fs)
        return Recording(name, fs, ch_names, values, str(path), units=ch_units)
    time = data[:, time_index] * time_scale
    try:
        rate = nominal_rate(time) if fs is None else check_positive("fs", fs)
        timing = analyse_time(time, rate)
        if timing.resampled:
            values, _ = resample_uniform(time, values, rate)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return Recording(name, rate, ch_names, values, str(path), units=ch_units, t0=float(time[0]), timing=timing)


def read_csv(path, *, fs=None, time_column="auto", columns=None, name=None) -> Recording:
    """A delimited text file: comma, semicolon, tab or whitespace separated.

    Parameters
    ----------
    path : str or Path
    fs : float, optional
        Sampling rate of the output grid, Hz.  Default: the time column's.
    time_column : "auto", None, str or int
        ``"auto"``: detect (module docstring); ``None``: there is none; a
        header name or a 0-based index: that column.
    columns : str, int or sequence of them, optional
        Channels to keep (header names or 0-based file column indices);
        default: every column but the time column.
    name : str, optional
        Recording name (default: the file stem).

    Examples
    --------
    >>> import tempfile, os
    >>> from wake.io import read_csv
    >>> path = os.path.join(tempfile.mkdtemp(), "rec.csv")
    >>> _ = open(path, "w").write("time [s],gyro_x [rad/s]\\n0.00,0.1\\n0.01,0.2\\n0.02,0.3\\n")
    >>> rec = read_csv(path)
    >>> rec.fs, rec.channels, rec.units
    (100.0, ('gyro_x',), ('rad/s',))
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file" + (" (it is a folder)" if path.is_dir() else ""))
    rows = _read_rows(path)
    header = None
    if not all(_is_number(c) for c in rows[0][1]):
        header = [split_unit(c) for c in rows[0][1]]
        rows = rows[1:]
        if not rows:
            raise ValueError(f"{path}: a header but no data")
    data = _numeric(rows, path)
    width = data.shape[1]
    if header is not None and len(header) != width:
        raise ValueError(f"{path}: the header names {len(header)} columns, the data has {width}")
    names = [h[0] for h in header] if header else [f"col{i}" for i in range(width)]
    units = [h[1] for h in header] if header else [""] * width
    time_index, scale = _find_time(data, names, units, time_column, path, header is not None)
    if header is None and width == 7 and time_index == 0 and time_column == "auto":
        names, units = ["time", *PADS_CHANNELS], ["s", *PADS_UNITS]  # the PADS layout
    if time_index is None and header is None and width > 1 and _is_row_counter(data[:, 0]) and columns is None \
            and time_column == "auto":
        # a row counter as the first column: an index, not a signal
        names, units, data = names[1:], units[1:], data[:, 1:]
    return _finish(path, name or path.stem, data, names, units, time_index, scale, fs, columns)


def _find_time(data, names, units, time_column, path, has_header):
    width = data.shape[1]
    if _no_time(time_column):
        return None, 1.0
    if isinstance(time_column, str) and time_column.lower() == "auto":
        if width < 2:
            return None, 1.0
        scale = _time_scale(names[0], units[0]) if has_header else None
        if scale is not None:
            return 0, scale
        if (not has_header or not names[0]) and _shaped_like_time(data[:, 0]):
            return 0, 1.0  # unnamed: by its shape
        return None, 1.0  # a named column that is not called time is a signal
    if isinstance(time_column, bool) or not isinstance(time_column, (str, int, np.integer)):
        raise ValueError(f"time_column must be 'auto', None, a name or an index, got {time_column!r}")
    i = _column_index(time_column, names, path, what="time column")
    if width < 2:
        raise ValueError(f"{path}: the only column cannot be both time and signal")
    scale = _time_scale(names[i], units[i])
    return i, 1.0 if scale is None else scale


def read_pads(path, fs=100.0, columns=None) -> Recording:
    """One PADS recording (Varghese et al. 2024) resampled onto a uniform ``fs`` grid.

    7 comma-separated numeric columns, no header: time in s, accelerometer
    x/y/z in g, gyroscope x/y/z in rad/s (:data:`PADS_CHANNELS`).
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    rows = _read_rows(path)
    if len(rows[0][1]) != 7:
        raise ValueError(f"{path}: a PADS recording has 7 columns (time, acc x/y/z, gyro x/y/z), "
                         f"the first line has {len(rows[0][1])}")
    data = _numeric(rows, path)
    if np.isnan(data).any():
        i = int(np.argwhere(np.isnan(data))[0][0])
        raise ValueError(f"{path}, line {rows[i][0]}: an empty or nan cell (PADS recordings have none)")
    if data.shape[0] < 2:
        raise ValueError(f"{path}: need at least two samples, got {data.shape[0]}")
    fs = check_positive("fs", fs)
    return _finish(path, path.stem, data, ["time", *PADS_CHANNELS], ["s", *PADS_UNITS], 0, 1.0, fs, columns)


def read_mat(path, *, fs=None, time_column="auto", columns=None, name=None) -> Recording:
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
    except (ValueError, TypeError, OSError, scipy.io.matlab.MatReadError) as exc:
        raise ValueError(f"{path}: not a readable MATLAB file ({exc})") from None
    arrays = {k: np.asarray(v) for k, v in mat.items() if not k.startswith("__")}
    numeric = {k: v for k, v in arrays.items() if v.dtype.kind in "iuf" and v.size > 0}
    if fs is None:
        for k in _MAT_RATE:
            if k in numeric and numeric[k].size == 1:
                fs = float(numeric.pop(k).reshape(-1)[0])
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
    return _finish(path, name or path.stem, data, names, units, time_index, 1.0, fs, columns)


def read_recording(path, *, format="auto", fs=None, time_column="auto", columns=None) -> Recording:
    """Read a recording in any known format onto a uniform grid.

    Parameters
    ----------
    path : str or Path
    format : {"auto", "csv", "pads", "mat"}
        ``"auto"``: ``.mat`` files are MATLAB, everything else delimited
        text (PADS files are recognised by their shape).
    fs, time_column, columns
        See :func:`read_csv`.

    Returns
    -------
    Recording
        With ``timing`` saying whether the time column was resampled.

    Raises
    ------
    ValueError
        Unreadable or inconsistent input; the message names the line and the fix.
    """
    if format not in FORMATS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {format!r}")
    path = Path(path)
    if format == "mat" or (format == "auto" and path.suffix.lower() == ".mat"):
        return read_mat(path, fs=fs, time_column=time_column, columns=columns)
    if format == "pads":
        return read_pads(path, fs=100.0 if fs is None else fs, columns=columns)
    return read_csv(path, fs=fs, time_column=time_column, columns=columns)
