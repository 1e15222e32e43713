"""The command-line options that read a recording, shared by every command that reads one.

``wake run FILE`` and ``wake export-header/export-c --fit FILE`` read a file
with the same reader (:func:`wake.io.read_recording`), the same column,
time-column, rate, decimal-mark and unit rules and the same refusals: both
call :func:`add_reading_arguments` and :func:`read_from_arguments`.
"""

from __future__ import annotations

from wake.io.readers import FORMATS, read_recording
from wake.io.text_table import DECIMAL_MARKS

__all__ = ["add_reading_arguments", "checked_fs", "column_list", "read_from_arguments"]


def add_reading_arguments(p, *, what: str = "the recording", fs_help: str | None = None) -> None:
    """Add ``--fs``, ``--time-column``, ``--column``, ``--format``, ``--decimal`` and ``--units`` to parser ``p``."""
    g = p.add_argument_group(f"reading {what}")
    g.add_argument("--fs", type=float, default=None,
                   help=fs_help or "sampling rate in Hz (default: from the time column; required when there is none)")
    g.add_argument("--time-column", default="auto", metavar="auto|none|NAME|INDEX",
                   help="the time column: detected by default (a first column named like time, or increasing in "
                        "even steps; its unit from the header, e.g. 'time [ms]' or 'timestamp_ms', else from its "
                        "step size); irregular timestamps are resampled onto --fs")
    g.add_argument("--column", action="append", metavar="NAME|INDEX",
                   help="channel(s): header names or 0-based file column indices, comma-separated or repeated "
                        "(default: every numeric column but the time column)")
    g.add_argument("--format", choices=FORMATS, default="auto",
                   help="file format (default: by suffix and content, docs/formats.md; .mat by suffix, else "
                        "delimited text; PADS by its shape)")
    g.add_argument("--decimal", choices=DECIMAL_MARKS, default="auto",
                   help="decimal mark of delimited text (default: auto, a comma between digits in a file "
                        "separated by semicolons or tabs, as in '0,5;1,2')")
    g.add_argument("--units", default=None, metavar="UNIT[,UNIT...]",
                   help="units of the channels where the file names none (one for all, or one per channel): "
                        "they label the output columns and the figure's axes")


def column_list(values):
    """``--column a,b --column 3`` -> ``["a", "b", "3"]`` (None when not given)."""
    if not values:
        return None
    out = []
    for value in values:
        for cell in value.split(","):
            cell = cell.strip()
            if not cell:
                raise ValueError(f"--column {value!r} has an empty name; give names or 0-based indices, "
                                 "comma-separated")
            out.append(cell)  # a digit string is an index (wake.io.readers)
    return out


def checked_fs(args):
    """``args.fs`` (None when not given), refused unless it is > 0."""
    if args.fs is not None and not args.fs > 0:
        raise ValueError(f"--fs must be > 0 Hz, got {args.fs}")
    return args.fs


def read_from_arguments(path, args, *, option: str = "file"):
    """Read ``path`` with the options of :func:`add_reading_arguments` (``option`` names it in errors)."""
    checked_fs(args)
    units = None
    if args.units is not None:
        cells = [u.strip() for u in args.units.split(",")]
        units = cells[0] if len(cells) == 1 else cells
    try:
        return read_recording(path, format=args.format, fs=args.fs, time_column=args.time_column,
                              columns=column_list(args.column), decimal=args.decimal, units=units)
    except ValueError as exc:
        if option == "file":
            raise
        raise ValueError(f"{option} {exc}") from None
