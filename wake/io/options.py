"""The command-line options that read a recording, shared by every command that reads one.

``wake run FILE`` and ``wake export-header/export-c --fit FILE`` read a file
with the same reader (:func:`wake.io.read_recording`), the same column,
time-column, rate, decimal-mark and unit rules and the same refusals: both
call :func:`add_reading_arguments` and :func:`read_from_arguments`.
"""

from __future__ import annotations

from wake.io.readers import FORMATS, read_recording
from wake.io.text_table import DECIMAL_MARKS

__all__ = ["add_reading_arguments", "add_stream_io_arguments", "checked_fs", "column_list", "horizon_setting",
           "one_line_warnings", "plot_channel_index", "read_from_arguments"]


def add_reading_arguments(p, *, what: str = "the recording", fs_help: str | None = None,
                          stream: bool = False) -> None:
    """Add ``--fs``, ``--resample``, ``--time-column``, ``--column``, ``--format``, ``--decimal`` and ``--units`` to
    parser ``p``; ``stream=True`` (``wake stream``: text lines, not resampled) leaves out ``--format`` and
    ``--resample``."""
    g = p.add_argument_group(f"reading {what}")
    g.add_argument("--fs", type=float, default=None,
                   help=fs_help or "sampling rate in Hz (default: from the time column; required when there is none)")
    if not stream:
        g.add_argument("--resample", action="store_true",
                       help="with --fs beside a time column: resample onto --fs even when it contradicts the "
                            "time column's own rate (by over 5 %%); without --resample such an --fs is refused, "
                            "naming both rates")
    g.add_argument("--time-column", default="auto", metavar="auto|none|NAME|INDEX",
                   help="the time column: detected by default (a column named like time, in any of several "
                        "languages and units, e.g. 'time', 'Zeit [s]', 'timestamp_ms', wherever it stands; or, "
                        "without a header row, a first numeric column increasing in even steps: "
                        "wake.io.time_column); its unit from the header, e.g. 'time [ms]' or 'timestamp_ms', "
                        "else from its step size; irregular timestamps are resampled onto a uniform grid")
    g.add_argument("--column", action="append", metavar="NAME|INDEX",
                   help="channel(s): header names or 0-based file column indices, comma-separated or repeated "
                        "(default: every numeric column but the time column)")
    if not stream:
        g.add_argument("--format", choices=FORMATS, default="auto",
                       help="file format (default: by suffix and content, docs/guide/formats.md; .mat by suffix, else "
                            "delimited text; PADS by its shape)")
    g.add_argument("--decimal", choices=DECIMAL_MARKS, default="auto",
                   help="decimal mark of delimited text (default: auto, a comma between digits in a file "
                        "separated by semicolons or tabs, as in '0,5;1,2')")
    g.add_argument("--units", default=None, metavar="UNIT[,UNIT...]",
                   help="units of the channels where the file names none (one for all, or one per channel): "
                        "they label the output columns and the figure's axes")


def add_stream_io_arguments(p) -> None:
    """``wake stream``'s sources (``--stdin``, ``--lsl-in``, ``--file``), sinks (``--stdout``, ``--lsl-out``) and
    the reading options of ``--stdin`` (:func:`add_reading_arguments` with ``stream=True``)."""
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--stdin", action="store_true",
                     help="read one line per sample, by the rules of wake run (delimiter, decimal mark, header, "
                          "text columns and time column from the first lines)")
    src.add_argument("--lsl-in", metavar="NAME", help="read the Lab Streaming Layer stream of this name")
    src.add_argument("--file", metavar="PATH", help="replay a recording `wake run` reads, sample by sample")
    dst = p.add_mutually_exclusive_group(required=True)
    dst.add_argument("--stdout", action="store_true", help="write one line per sample, the columns of wake run --out: time, then per "
                                                          "channel measurement, voluntary, tremor")
    dst.add_argument("--lsl-out", metavar="NAME", help="publish an LSL stream of this name")
    add_reading_arguments(p, what="--stdin (the rules of wake run, on its first lines)", stream=True,
                          fs_help="sampling rate in Hz (default: from the input's time column with --stdin, "
                                  "the stream's nominal rate with LSL; required when there is none)")


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
                              columns=column_list(args.column), decimal=args.decimal, units=units,
                              resample=args.resample)
    except ValueError as exc:
        if option == "file":
            raise
        raise ValueError(f"{option} {exc}") from None


def plot_channel_index(spec, rec) -> int:
    """The channel ``--plot-channel`` names (a name or a 0-based index among the channels read); default 0."""
    if spec is None:
        return 0
    if spec in rec.channels:
        return rec.channels.index(spec)
    if spec.strip().isdigit() and int(spec) < len(rec.channels):
        return int(spec)
    raise ValueError(f"--plot-channel {spec!r} is not a channel of {rec.name}; channels: "
                     f"{', '.join(rec.channels)} (or a 0-based index below {len(rec.channels)})")


def one_line_warnings(command: str):
    """``warnings.formatwarning`` for a command-line user: ``wake run: warning (RateWarning): MESSAGE`` on one
    line, without the line of our source that raised it (``.../wake/cli.py:73: ... return WakeFilter(...``)."""

    def formatwarning(message, category, filename, lineno, line=None):
        text = " ".join(str(message).split())
        return f"{' '.join(('wake', command)).strip()}: warning ({category.__name__}): {text}\n"

    return formatwarning


def horizon_setting(args, fs) -> dict:
    """``{"horizon": samples}`` from ``--horizon-ms`` at ``fs`` (empty without it), and a line saying the
    rounding (``""`` without it)."""
    if getattr(args, "horizon_ms", None) is None:
        return {}, ""
    from wake.ahead import MAX_HORIZON, horizon_from_ms
    from wake.sampling import decimation_for

    h = horizon_from_ms(args.horizon_ms, fs, MAX_HORIZON * decimation_for(fs))
    return {"horizon": h}, (f"horizon: {args.horizon_ms:g} ms at {fs:g} Hz is {h} sample(s) "
                            f"({1000.0 * h / fs:g} ms; rounded to the nearest sample)")
