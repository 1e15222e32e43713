"""``wake stream --stdin --stdout``: text lines in, read by the rules of ``wake run``; ``wake run``'s columns out.

:class:`LineLayout` applies the reader's rules (:func:`wake.io.readers.table_layout`) to the stream's first
lines and then to every line; :func:`run_pipes` answers each sample (the filter, status lines and the stop
rules are :mod:`wake.io.stream`'s).  What a line holds is said in :mod:`wake.io.stream`.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from wake._files import silence_stdout
from wake.io.stream import StreamProcessor, _after_sample, _answer, _finish, _ready
from wake.io.writers import ahead_columns
from wake.sampling import rate_note

__all__ = ["DETECT_LINES", "LineLayout", "RATE_LINES", "run_pipes"]


#: Lines a text stream reads before it decides its columns when only a column's shape can tell whether it is
#: time (no header row, ``--time-column auto``): the first of them are answered once that is decided.
DETECT_LINES = 100
#: Data lines a stream with a time column and no ``--fs`` reads to know its rate (and with ``--fs``, to
#: check it against the time column: fewer steps than this are not enough to call a rate contradicted).
RATE_LINES = 10


class LineLayout:
    """The columns of a text stream: the rules of ``wake run`` (:func:`wake.io.readers.table_layout`) applied
    to its first lines, then used on every line.

    Parameters
    ----------
    lines : list of (int, str)
        The stream's first lines (line number, text; no comments or blank lines).
    args : argparse.Namespace
        ``wake stream``'s options: ``fs``, ``time_column``, ``timestamps``, ``column``, ``decimal``, ``units``.

    Attributes
    ----------
    channels, units : tuple of str
        The channels' names and units, as ``wake run`` names them (the header's, else ``col{j}``).
    fs : float
        The rate: ``--fs``, else the time column's.
    rows : list of (int, list of str)
        The data rows among ``lines`` (line number, cells), to be answered first.
    """

    def __init__(self, lines, args):
        from wake.io.options import column_list
        from wake.io.readers import _select, table_layout, with_units
        from wake.io.recording import check_rate
        from wake.io.text_table import table_from_lines
        from wake.io.time_column import unit_from_steps

        time_column = 0 if getattr(args, "timestamps", False) else getattr(args, "time_column", "auto")
        columns = column_list(getattr(args, "column", None))
        table = table_from_lines(lines, getattr(args, "decimal", "auto"), "input")
        lay = table_layout(table, time_column, "input", columns)
        idx = _select(lay.names, columns, "input", lay.time_index, lay.text)
        self.table, self.start, self.index = table, lay.start, [i + lay.start for i in idx]
        self.channels = tuple(lay.names[i] for i in idx)
        self.units = tuple(lay.units[i] for i in idx)
        self.time_index = None if lay.time_index is None else lay.time_index + lay.start
        self.time_name = "" if lay.time_index is None else lay.names[lay.time_index]
        self.text = [lay.names[j] for j in lay.text]
        fs = args.fs
        self.time_unit = None
        if self.time_index is not None:
            raw = lay.column(lay.time_index)
            self.time_unit = lay.time_unit or unit_from_steps(raw)
            time = raw * self.time_unit.seconds
            if fs is None:
                if time.size < 2:
                    raise ValueError("the stream ended before its time column gave a rate: give it with --fs HZ")
                fs = check_rate(None, time)
            elif time.size >= RATE_LINES:
                fs = check_rate(fs, time, given="--fs", column=f"the time column {self.time_name!r}",
                                can_resample=False)
        if fs is None:
            raise ValueError("the input has no time column, so the sampling rate is unknown: give it with --fs HZ "
                             "(or name its time column with --time-column NAME)")
        self.fs = float(fs)
        if getattr(args, "units", None) is not None:
            cells = [u.strip() for u in args.units.split(",")]
            from wake.io.recording import Recording

            rec = Recording("input", self.fs, self.channels, np.zeros((0, len(self.channels))),
                            units=self.units if any(self.units) else ())
            self.units = with_units(rec, cells[0] if len(cells) == 1 else cells).units
        self.rows = [(lineno, [table.cells[j][r] for j in range(table.width)])
                     for r, lineno in enumerate(table.lines)]

    def describe(self) -> str:
        """One line: the channels, the columns left out and the time column."""
        what = f"channels {', '.join(self.channels)}"
        if self.text:
            what += f"; text column{'s' if len(self.text) > 1 else ''} {', '.join(self.text)} left out"
        if self.time_index is not None:
            what += f"; {self.time_unit.describe(self.time_name)}, copied to the output in s (not resampled)"
        return what + f"; {self.fs:g} Hz"

    def cells(self, line: str) -> list:
        """The cells of a later line (the first lines' delimiter)."""
        return self.table.split(line)

    def values(self, cells) -> list:
        """The channels' values of one line's cells (ValueError, naming the problem, for a bad line)."""
        if len(cells) != self.table.width:
            raise ValueError(f"{len(cells)} values where the stream has {self.table.width}")
        return [self.table.number(cells[i]) for i in self.index]  # float()'s message names a bad cell

    def time(self, cells, n: int) -> float:
        """The time of a line in s: its time column's, else ``n / fs`` (``n``: the sample's index)."""
        if self.time_index is None:
            return n / self.fs
        try:
            return self.table.number(cells[self.time_index]) * self.time_unit.seconds
        except (ValueError, IndexError):
            return math.nan


def _enough(pending, args) -> bool:
    """Whether the stream's first lines (``pending``) settle its columns (:class:`LineLayout`)."""
    from wake.io.text_table import table_from_lines

    if len(pending) >= DETECT_LINES:
        return True
    try:
        table = table_from_lines(pending, getattr(args, "decimal", "auto"), "input")
    except ValueError:
        return len(pending) >= 2  # let the layout say what is wrong
    if len(pending) == 1 and table.header is not None:
        return False  # a header, or text cells: the second line tells which
    explicit = getattr(args, "timestamps", False) or str(getattr(args, "time_column", "auto")).lower() != "auto"
    named = table.header is not None and all(c.strip() for c in table.header)
    if not (explicit or named):
        return False  # only a column's shape can tell whether it is time: DETECT_LINES
    return table.rows >= (1 if args.fs is not None else RATE_LINES)


def run_pipes(args, make_filter, stop, log) -> int:
    """``--stdin`` / ``--stdout``: one line in, one line out, until the input ends or ``stop`` is requested.

    ``args`` holds the options of ``wake stream`` (``wake.cli``), ``make_filter(fs)`` builds the filter,
    ``stop`` is a :class:`~wake.io.stream.StreamStop`, ``log(message)`` writes a status line.  Returns the
    exit status.

    The input is read by the rules of ``wake run`` (:class:`LineLayout`), and each output line holds the
    columns of ``wake run --out`` (:func:`wake.io.writers.result_columns`): the time in s, then per channel
    the measurement, the voluntary motion, the tremor (and with ``--horizon-ms`` the ahead columns).
    """
    pipe = _Pipe(args, stop, log, make_filter, sys.stdin, sys.stdout)
    try:
        if args.fs is not None:
            pipe.make(args.fs)
            log(f"wake stream: ready, reading stdin at {args.fs:g} Hz")
            log(rate_note(args.fs))  # after the ready line, which a producer waits for
        else:
            log("wake stream: ready, reading stdin (the rate from its time column)")
        return pipe.run()
    finally:
        if pipe.filt is not None:
            pipe.filt.close()  # also on an early error return: the worker never outlives the command


class _Stop(Exception):
    """Stop the stream with ``code`` (0 after ``--max-samples``, 2 after a bad line or a bad start)."""

    def __init__(self, code):
        super().__init__(code)
        self.code = code


class _Pipe:
    """The state of one ``--stdin`` / ``--stdout`` run: the first lines, the layout, the filter."""

    def __init__(self, args, stop, log, make_filter, fin, fout):
        self.args, self.stop, self.log, self.make_filter, self.fin, self.fout = args, stop, log, make_filter, fin, fout
        self.filt = self.layout = self.proc = None
        self.pending = []  # the first lines, until they settle the columns
        self.last_status = time.monotonic()

    def make(self, fs):
        self.filt = self.make_filter(fs)
        _ready(self.filt)

    def run(self) -> int:
        try:
            try:
                self._read()
                if self.layout is None and self.pending:  # the input ended before the first lines settled
                    self._start()
            except _Stop as stop:
                if stop.code == 0:
                    _finish(self.proc, self.log, "end of input")
                return stop.code
        except BrokenPipeError:
            self.log("wake stream: error: the output pipe was closed by the reader; stopping")
            silence_stdout()
            _finish(self.proc, self.log, "output closed")
            return 1
        _finish(self.proc, self.log, "stopped by signal" if self.stop.requested else "end of input")
        return 0

    def _read(self):
        lineno = 0
        while not self.stop.requested:
            self.stop.reading = True
            try:
                line = self.fin.readline()
            except KeyboardInterrupt:
                break
            finally:
                self.stop.reading = False
            if not line:
                break
            t_in = time.perf_counter()
            lineno += 1
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            if self.layout is not None:
                self._one(lineno, self.layout.cells(line.rstrip("\r\n")), t_in)
                continue
            self.pending.append((lineno, text))
            if _enough(self.pending, self.args):
                self._start()

    def _start(self):
        """Decide the columns on the first lines, make the filter, write the header, answer those lines."""
        try:
            layout = LineLayout(self.pending, self.args)
        except ValueError as exc:
            self.log(f"wake stream: error: {exc}")
            raise _Stop(2) from None
        if self.filt is None:
            self.make(layout.fs)
            self.log(rate_note(layout.fs))
        self.log(f"wake stream: {layout.describe()}")
        self.layout, self.proc = layout, StreamProcessor(self.filt, layout.channels)
        if self.args.header:
            from wake.io.writers import result_columns

            ahead = ahead_columns(self.filt.config) if getattr(self.args, "horizon_ms", None) is not None else ()
            self.fout.write(",".join(result_columns(layout.channels, layout.units, ahead)) + "\n")
        t_in = time.perf_counter()  # the wait for the first lines and the filter's set-up are not latency
        for n, cells in layout.rows:
            self._one(n, cells, t_in)

    def _one(self, lineno, cells, t_in):
        """Answer one data line."""
        layout, proc, args = self.layout, self.proc, self.args
        try:
            values = layout.values(cells)
        except ValueError as exc:
            if args.bad_lines == "stop":
                self.log(f"wake stream: error: input line {lineno}: {exc}; fix the line or pass --bad-lines "
                         "missing to treat it as a missing sample")
                raise _Stop(2) from None
            values = [math.nan] * len(layout.channels)
            proc.bad += 1
            if proc.bad <= 5:
                self.log(f"wake stream: warning: input line {lineno}: {exc}; taken as a missing sample")
        stamp = layout.time(cells, proc.samples)
        out = _answer(proc, args, values)
        per_channel = np.column_stack([np.asarray(values, dtype=float), *out])  # (channels, kinds): as wake run
        self.fout.write(",".join(repr(float(v)) for v in (stamp, *per_channel.reshape(-1))) + "\n")
        self.fout.flush()
        done, self.last_status = _after_sample(proc, args, self.log, t_in, self.last_status)
        if done:
            raise _Stop(0)
