"""Read recordings: CSV (with or without a header and a time column), PADS and MATLAB ``.mat``.

:func:`read_recording` is the one entry point; it returns a
:class:`~wake.io.recording.Recording` on a uniform grid with channel names
and units.

Time column (``time_column="auto"``): the rule of :mod:`wake.io.time_column`
(:func:`~wake.io.time_column.find_time_column`): a column named like time
(``time``, ``Zeit [s]``, ``timestamp_ms``, ``TimeUs``, ... anywhere, text
columns passed over) or, in a file without names, a first numeric column
shaped like a clock (a plain row counter 0, 1, 2, ... is read as an index and
dropped, and the rate must be given).  Its unit (s, ms, us, ns) comes from
its header (``t [ms]``, ``timestamp_ms``) or, when the header says none, from
its step size; ``Recording.timing`` says which and why.

Delimited text (:mod:`wake.io.text_table`): only the columns asked for are
parsed as numbers, so text columns beside the signals (a subject id, a
label) are no obstacle; a decimal comma is detected or given
(``decimal=","``).

Rate: the time column's (:func:`~wake.io.recording.nominal_rate`), or ``fs``
when given; an ``fs`` that contradicts the time column's own rate by over
5 % is refused with a message naming both rates, unless ``resample=True``
(``--resample``) asks for that grid (:func:`~wake.io.recording.check_rate`).
A file with neither is refused with a message that names both fixes.

Header cells may carry a unit: ``acc_x [g]`` or ``acc_x (g)`` is channel
``acc_x`` in ``g``.  PADS files (7 numeric columns, time then accelerometer
x/y/z in g and gyroscope x/y/z in rad/s, no header) are recognised by shape
and get their channel names and units.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from wake._validation import check_positive
from wake.io import formats
from wake.io.recording import Recording, Timing, analyse_time, check_rate, resample_uniform
from wake.io.text_table import TextTable, check_decimal_mark, read_text_table
from wake.io.time_column import TimeUnit, find_time_column, is_row_counter, unit_from_name, unit_from_steps

__all__ = ["FORMATS", "PADS_CHANNELS", "PADS_UNITS", "TableLayout", "read_recording", "read_csv", "read_pads",
           "table_layout"]

#: Formats :func:`read_recording` knows (``"auto"`` picks by content and suffix; after mat: :mod:`wake.io.formats`).
FORMATS = ("auto", "csv", "pads", "mat", *formats.FORMATS)
#: Channel names of a PADS recording, in file order after the time column.
PADS_CHANNELS = ("acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z")
#: Units of :data:`PADS_CHANNELS`.
PADS_UNITS = ("g", "g", "g", "rad/s", "rad/s", "rad/s")

_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]\s*$")


def split_unit(cell: str) -> tuple[str, str]:
    """``"acc_x [g]"`` -> ``("acc_x", "g")``; ``"acc_x"`` -> ``("acc_x", "")``."""
    cell = cell.strip()
    m = _UNIT.match(cell)
    return (m.group(1).strip(), m.group(2)) if m and m.group(1).strip() else (cell, "")


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


def _select(names, columns, path, time_index, text=()):
    """File column indices for ``columns`` (names or file indices; ``None``: every column but time and ``text``)."""
    if columns is None:
        idx = [i for i in range(len(names)) if i != time_index and i not in text]
        if not idx:
            raise ValueError(f"{path}: no numeric column to filter (text columns: "
                             f"{', '.join(names[i] for i in text)})")
        return idx
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


def _finish(path, name, column, names, units, time_index, time_unit, fs, columns, *, text=(), notes=(),
            rate_source="--fs", resample=False):
    """Select the channels, take the time column and put the samples on a uniform grid.

    ``column(j)`` gives file column ``j`` as floats (only the columns used are asked for); ``time_unit`` is
    the :class:`~wake.io.time_column.TimeUnit` of the time column, None to judge it from its steps.
    """
    idx = _select(names, columns, path, time_index, text)
    values = np.column_stack([column(i) for i in idx])
    ch_names = tuple(names[i] for i in idx)
    ch_units = tuple(units[i] for i in idx) if any(units) else ()
    skipped = [names[i] for i in text]  # with no columns asked for, every text column is left out
    if skipped and columns is None:
        notes = (*notes, f"text column{'s' if len(skipped) > 1 else ''} {', '.join(skipped)} left out")
    if time_index is None:
        if fs is None:
            raise ValueError(f"{path} has no time column, so the sampling rate is unknown: give it with --fs HZ "
                             "(fs=...), or name the time column with --time-column NAME (time_column=...)")
        fs = check_positive("fs", fs)
        return Recording(name, fs, ch_names, values, str(path), units=ch_units, timing=Timing(rate_source),
                         notes=tuple(notes))
    raw = column(time_index)
    time_unit = unit_from_steps(raw) if time_unit is None else time_unit
    time = raw * time_unit.seconds
    try:
        given = "fs (--fs)" if rate_source == "--fs" else rate_source
        rate = check_rate(fs, time, resample=resample, given=given, column=f"the time column {names[time_index]!r}")
        timing = analyse_time(time, rate)
        if timing.resampled:
            values, _ = resample_uniform(time, values, rate)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc} ({time_unit.describe(names[time_index])})") from None
    timing = replace(timing, unit_note=time_unit.describe(names[time_index]))
    return Recording(name, rate, ch_names, values, str(path), units=ch_units, t0=float(time[0]), timing=timing,
                     notes=tuple(notes))


def read_csv(path, *, fs=None, time_column="auto", columns=None, name=None, decimal="auto",
             resample=False) -> Recording:
    """A delimited text file: comma, semicolon, tab or whitespace separated.

    Parameters
    ----------
    path : str or Path
    fs : float, optional
        Sampling rate of the output grid, Hz.  Default: the time column's.
        Beside a time column it must agree with the column's own rate
        (within 5 %, :func:`wake.io.recording.check_rate`) unless
        ``resample`` is True.
    time_column : "auto", None, str or int
        ``"auto"``: detect (module docstring); ``None``: there is none; a
        header name or a 0-based index: that column.
    columns : str, int or sequence of them, optional
        Channels to keep (header names or 0-based file column indices);
        default: every numeric column but the time column (text columns,
        such as a subject id, are left out and said so in ``notes``).
    name : str, optional
        Recording name (default: the file stem).
    decimal : {"auto", ".", ","}
        Decimal mark (:mod:`wake.io.text_table`): ``"auto"`` reads
        ``0,5;1,2`` as two numbers, 0.5 and 1.2.
    resample : bool
        Resample the time column onto ``fs`` even where ``fs`` contradicts
        the column's own rate (``--resample``).

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
    lay = table_layout(read_text_table(path, decimal), time_column, path, columns)
    return _finish(path, name or path.stem, lay.column, lay.names, lay.units, lay.time_index, lay.time_unit, fs,
                   columns, text=lay.text, notes=lay.notes, resample=resample)


@dataclass(frozen=True)
class TableLayout:
    """What the rules make of a delimited text table: names, units, text columns and the time column.

    Indices count the table's columns from ``start`` (1 when a headerless first column is a row counter,
    read as an index and dropped; else 0).  ``wake run`` (:func:`read_csv`) and ``wake stream``
    (:mod:`wake.io.stream`, on its first lines) both take their columns from :func:`table_layout`.
    """

    table: TextTable
    names: tuple  #: per column from ``start``: the header's names, else ``col{j}`` (the file column's index)
    units: tuple  #: per column from ``start``: the header's unit cells ("" for none)
    time_index: int | None  #: the time column (from ``start``), or None
    time_unit: TimeUnit | None  #: its unit (None: judge it from its steps)
    text: tuple  #: the text columns (from ``start``)
    start: int  #: table columns before the first one counted
    notes: tuple  #: what the reader inferred (a decimal comma)

    def column(self, j: int) -> np.ndarray:
        """Column ``j`` (from ``start``) as floats."""
        return self.table.numbers(j + self.start, self.names[j])


def table_layout(table: TextTable, time_column="auto", path="input", columns=None) -> TableLayout:
    """The names, units, text columns and time column of ``table``, by the rules of this module.

    ``columns`` matters only to a headerless row counter: when channels are asked for by file index,
    it is not dropped, so that the indices stay the file's.

    Examples
    --------
    >>> from wake.io.readers import table_layout
    >>> from wake.io.text_table import table_from_lines
    >>> rows = ["subject,timestamp_ms,gx [deg/s]"] + [f"P01,{10 * i},{0.5 * i}" for i in range(5)]
    >>> lay = table_layout(table_from_lines(list(enumerate(rows, 1))))
    >>> lay.names, lay.units, lay.time_index, lay.time_unit.unit, lay.text
    (('subject', 'timestamp_ms', 'gx'), ('', '', 'deg/s'), 1, 'ms', (0,))
    """
    width = table.width
    header = [split_unit(c) for c in table.header] if table.header is not None else None
    names = [h[0] for h in header] if header else [f"col{i}" for i in range(width)]
    units = [h[1] for h in header] if header else [""] * width
    parsed = {}

    def column(j):
        if j not in parsed:
            parsed[j] = table.numbers(j, names[j])
        return parsed[j]

    text = tuple(j for j in range(width) if table.is_text(j))
    time_index, time_unit = _find_time(column, names, units, time_column, path, header is not None, text)
    if header is None and width == 7 and time_index == 0 and time_column == "auto" and not text:
        names, units = ["time", *PADS_CHANNELS], ["s", *PADS_UNITS]  # the PADS layout
    start = 0
    if time_index is None and header is None and width > 1 and 0 not in text and columns is None \
            and time_column == "auto" and is_row_counter(column(0)):
        start = 1  # a row counter as the first column: an index, not a signal
    notes = ("decimal comma",) if table.decimal_comma else ()
    return TableLayout(table, tuple(names[start:]), tuple(units[start:]),
                       None if time_index is None else time_index - start, time_unit,
                       tuple(j - start for j in text if j >= start), start, notes)


def _find_time(column, names, units, time_column, path, has_header, text=()):
    """``(index, TimeUnit or None)`` of the time column (``None`` unit: judge it from the steps)."""
    width = len(names)
    if _no_time(time_column):
        return None, None
    if isinstance(time_column, str) and time_column.lower() == "auto":
        i, _ = find_time_column(names, lambda j: j in text, column, has_header)  # the rule: wake.io.time_column
        return (None, None) if i is None else (i, unit_from_name(names[i], units[i]) if has_header else None)
    if isinstance(time_column, bool) or not isinstance(time_column, (str, int, np.integer)):
        raise ValueError(f"time_column must be 'auto', None, a name or an index, got {time_column!r}")
    i = _column_index(time_column, names, path, what="time column")
    if width < 2:
        raise ValueError(f"{path}: the only column cannot be both time and signal")
    return i, unit_from_name(names[i], units[i])


def read_pads(path, fs=100.0, columns=None) -> Recording:
    """One PADS recording (Varghese et al. 2024) resampled onto a uniform ``fs`` grid.

    7 comma-separated numeric columns, no header: time in s, accelerometer
    x/y/z in g, gyroscope x/y/z in rad/s (:data:`PADS_CHANNELS`).
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    table = read_text_table(path, ".")
    if table.header is not None or table.width != 7:
        raise ValueError(f"{path}: a PADS recording has no header and 7 columns (time, acc x/y/z, gyro x/y/z); "
                         f"this file has {table.width} columns" +
                         (" and a header row" if table.header is not None else ""))
    names = ["time", *PADS_CHANNELS]
    data = np.column_stack([table.numbers(j, names[j]) for j in range(7)])
    if np.isnan(data).any():
        i = int(np.argwhere(np.isnan(data))[0][0])
        raise ValueError(f"{path}, line {table.lines[i]}: an empty or nan cell (PADS recordings have none)")
    if data.shape[0] < 2:
        raise ValueError(f"{path}: need at least two samples, got {data.shape[0]}")
    fs = check_positive("fs", fs)
    return _finish(path, path.stem, lambda j: data[:, j], names, ["s", *PADS_UNITS], 0, TimeUnit("s", "unit cell"),
                   fs, columns, resample=True)  # fs is the grid asked for: a PADS clock runs near 100 Hz


def read_recording(path, *, format="auto", fs=None, time_column="auto", columns=None, decimal="auto",
                   units=None, resample=False) -> Recording:
    """Read a recording in any known format onto a uniform grid.

    Parameters
    ----------
    path : str or Path
    format : {"auto", "csv", "pads", "mat", "cwa", "gt3x", "geneactiv", "edf", "tsdf", "parquet", "bids"}
        ``"auto"``: those of :mod:`wake.io.formats` by suffix and content (a
        folder holding one too), ``.mat`` files are MATLAB, everything else
        delimited text (PADS files are recognised by their shape).
    fs, time_column, columns, decimal, resample
        See :func:`read_csv` (``decimal`` applies to delimited text only).
        An ``fs`` that contradicts the file's time column is refused, naming
        both rates, unless ``resample=True``.
    units : str or sequence of str, optional
        The channels' units where the file does not say them (a headerless
        CSV): one unit for every channel, or one per channel.

    Returns
    -------
    Recording
        With ``timing`` saying whether the time column was resampled and in
        which unit it was read, and ``notes`` what else the reader inferred.

    Raises
    ------
    ValueError
        Unreadable or inconsistent input; the message names the line and the fix.
    """
    if format not in FORMATS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {format!r}")
    check_decimal_mark(decimal)  # before the format is chosen: a .mat file is refused a bad one too
    path = Path(path)
    found = formats.resolve(path, format)
    if found is not None:
        rec = _read_format(*found, fs=fs, time_column=time_column, columns=columns, resample=resample)
    elif format == "mat" or (format == "auto" and path.suffix.lower() == ".mat"):
        from wake.io.matlab import read_mat  # it takes the rules of this module (_finish)

        rec = read_mat(path, fs=fs, time_column=time_column, columns=columns, resample=resample)
    elif format == "pads":
        rec = read_pads(path, fs=100.0 if fs is None else fs, columns=columns)
    else:
        rec = read_csv(path, fs=fs, time_column=time_column, columns=columns, decimal=decimal, resample=resample)
    return rec if units is None else with_units(rec, units)


def _read_format(path, fmt, *, fs, time_column, columns, resample) -> Recording:
    """A file of :mod:`wake.io.formats`: its library reads the table, :func:`_finish` applies the rules."""
    if fmt not in formats.NAMED_COLUMNS and not (isinstance(time_column, str) and time_column.lower() == "auto"):
        raise ValueError(f"{path}: a {fmt} recording's time comes from the file itself; --time-column "
                         "(time_column=) applies to delimited text and Parquet: leave it at auto")
    table = formats.read_table(path, fmt, columns)
    if table.meta.get("columns"):
        columns = None  # the reader took exactly the channels asked for (EDF: one rate)
    if table.time is None:  # named columns (Parquet): the time column is found as in a CSV file's header
        time_index, time_unit = _find_time(table.column, table.names, table.units, time_column, path, True,
                                           table.text)
        return _finish(path, table.name, table.column, table.names, table.units, time_index, time_unit, fs,
                       columns, text=table.text, notes=table.notes, resample=resample)
    width = len(table.names)  # the clock after the channels: a 0-based index names a channel
    names, units = [*table.names, "time"], [*table.units, "s"]
    return _finish(path, table.name, lambda j: table.time if j == width else table.column(j), names, units, width,
                   TimeUnit("s", "unit cell"), fs, columns, notes=table.notes, resample=resample)


def with_units(rec: Recording, units) -> Recording:
    """``rec`` with ``units`` (one for all channels, or one per channel) where the file named none."""
    given = [units] * len(rec.channels) if isinstance(units, str) else list(units)
    if len(given) != len(rec.channels) or not all(isinstance(u, str) for u in given):
        raise ValueError(f"units: give one unit for every channel or one per channel ({len(rec.channels)}: "
                         f"{', '.join(rec.channels)}), got {units!r}")
    merged = tuple(rec.unit(i) or u.strip() for i, u in enumerate(given))
    return replace(rec, units=merged)
