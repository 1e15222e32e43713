"""WAKE on a live stream, over text pipes or Lab Streaming Layer (the streams of ``wake stream``).

The command line (its options, checks and signal handling) is in :mod:`wake.cli`;
this module reads and writes the streams.

Every input sample gets exactly one output sample, in order:

* ``--stdin`` / ``--stdout``: one line per sample, read by the rules of
  ``wake run`` (:class:`LineLayout`, :func:`wake.io.readers.table_layout`):
  the delimiter and decimal mark, a header row, text columns (left out) and
  the time column (:mod:`wake.io.time_column`) are taken from the first
  lines, the channels are named as ``wake run`` names them (the header's
  names, else ``col{j}`` after the file column), ``--column``,
  ``--time-column``, ``--decimal`` and ``--units`` mean what they mean
  there, and ``--fs`` may be left out when a time column gives the rate (an
  ``--fs`` that contradicts it is refused).  Only where a column's shape
  alone can tell whether it is time (no header row, ``--time-column auto``)
  does the stream read :data:`DETECT_LINES` lines before it answers the
  first (then at once); ``--time-column none`` (or a header row) answers
  from the first line.  A time column is not resampled: its value, in s, is
  copied to the output line.
* ``--lsl-in NAME`` / ``--lsl-out NAME``: an LSL inlet resolved by name (any
  channel count, its nominal rate as ``fs``) and an outlet of
  ``2 x channels`` values with the input's timestamps and channel labels.
  Needs the optional ``pylsl`` (``pip install pylsl``, or ``pip install ".[lsl]"`` in a source tree).

Output per input sample ``x(n)``, over pipes the columns of ``wake run --out``
(:func:`wake.io.writers.result_columns`): the time in s, then per channel the
measurement, the voluntary motion ``v(n)`` (predicted from the samples before
``n``: ``WakeFilter.run``'s ``voluntary[n]``) and the tremor ``x(n) - v(n)``,
and with ``--horizon-ms`` that channel's ahead columns (:func:`_kinds`); over
LSL, per channel the voluntary motion, the tremor and the ahead columns.
Values are written in the shortest form that reads back exactly.  With
``--hpa-mode inline`` the output equals ``WakeFilter.run`` bit for bit; the
default ``thread`` keeps the HPA off the sample path, so its weights take
effect a few samples later (``docs/design.md``, "Streaming").

Since ``v(n)`` is known before ``x(n)`` arrives, a sample's output line is written first and the filter
takes the sample in afterwards: the filter's work is not on the sample-in -> result-out path.

Ctrl-C, SIGTERM or the end of the input stop the stream cleanly: every sample
read has its output written, and a summary goes to stderr.
"""

from __future__ import annotations

import gc
import math
import signal
import sys
import time
from collections import deque

import numpy as np

from wake.sampling import rate_note
from wake._files import silence_stdout
from wake.io.writers import VOLUNTARY_AHEAD_COLUMN, ahead_columns

__all__ = ["StreamProcessor", "StreamStop", "run_pipes", "run_lsl", "SWITCH_INTERVAL_S"]

#: GIL switch interval while an HPA thread runs beside the sample path (default Python: 5 ms).
SWITCH_INTERVAL_S = 2e-4

LSL_HINT = "pylsl is not installed: pip install pylsl, or pip install \".[lsl]\" in a wake source tree"


class StreamProcessor:
    """One sample in, its voluntary motion and tremor out; counts and latencies for the status line.

    Parameters
    ----------
    filt : WakeFilter
        A fresh filter; the processor feeds it with :meth:`WakeFilter.update`.
    channels : sequence of str
        Channel names (for the status line).

    Examples
    --------
    >>> from wake import WakeFilter
    >>> from wake.io.stream import StreamProcessor
    >>> sp = StreamProcessor(WakeFilter(fs=100.0, backend="reference"), ["x"])
    >>> sp.process([0.5])
    (array([0.]), array([0.5]))
    """

    def __init__(self, filt, channels):
        self.filt = filt
        self.channels = tuple(channels)
        self._next = np.zeros(len(self.channels))
        self._pending = None  # the answered sample whose update() is still to run
        self.samples = 0
        self.bad = 0
        self.latencies = deque(maxlen=200_000)
        self._voluntary_ahead = VOLUNTARY_AHEAD_COLUMN in ahead_columns(filt.config)  # answer_ahead's last column

    def answer(self, values):
        """``values`` (one per channel, NaN = missing) -> (voluntary, tremor) of this sample, at once.

        The voluntary motion of a sample was predicted from the samples before
        it, so the answer needs no filtering: the stream writes it first and
        calls :meth:`advance` (the filter's ``update()``) while it waits for the
        next sample.  The filter's work is then off the sample-in -> result-out
        path (README, "Live streams": the end-to-end latency).
        """
        x = np.asarray(values, dtype=float).reshape(-1)
        if x.size != len(self.channels):
            raise ValueError(f"{x.size} values where the stream has {len(self.channels)} channel(s)")
        self.advance()  # a sample answered but not yet taken in goes first: the order is kept
        voluntary = self._next
        self._pending = x
        self.samples += 1
        return voluntary, x - voluntary

    def advance(self):
        """Feed the last answered sample to the filter (no-op when there is none)."""
        if self._pending is not None:
            x, self._pending = self._pending, None
            self._next = np.atleast_1d(self.filt.update(x)).astype(float)

    def answer_ahead(self, values):
        """:meth:`answer`, then :meth:`advance` at once, and the tremor ahead the filter made of this sample:
        ``(voluntary, tremor, tremor_ahead, confidence, command)`` and ``voluntary_ahead`` when the filter
        makes it (:func:`wake.io.writers.ahead_columns`), one array each (one value per channel).

        The ahead ones are for ``horizon`` samples after this one (:attr:`wake.WakeFilter.last_ahead`,
        ``last_voluntary_ahead``): the filter's ``update()`` runs before the answer, unlike :meth:`answer`.
        """
        voluntary, tremor = self.answer(values)
        self.advance()
        ahead = (*self.filt.last_ahead, *((self.filt.last_voluntary_ahead,) if self._voluntary_ahead else ()))
        return (voluntary, tremor, *(np.atleast_1d(np.asarray(a, dtype=float)) for a in ahead))

    def process(self, values):
        """:meth:`answer` and :meth:`advance` in one call."""
        out = self.answer(values)
        self.advance()
        return out

    def latency_summary(self) -> str:
        if not self.latencies:
            return "latency -"
        lat = np.asarray(self.latencies) * 1e3
        p50, p99, p999 = np.percentile(lat, [50, 99, 99.9])
        return f"latency p50 {p50:.3f} ms, p99 {p99:.3f} ms, p99.9 {p999:.3f} ms, max {lat.max():.3f} ms"

    def status(self) -> str:
        hist = self.filt.hpa_history if self.samples else []
        cut = ", ".join(f"{c} {h[-1].cutoff:.2f}" if h else f"{c} -" for c, h in zip(self.channels, hist))
        clipped = sum(int(getattr(r, "clipped", 0)) for r in (self.filt.rtp_states if self.samples else []))
        return (f"{self.samples} samples; f_d [Hz]: {cut or '-'}; clipped {clipped}; bad lines {self.bad}; "
                f"{self.latency_summary()}")


class StreamStop:
    """SIGINT/SIGTERM: interrupt a blocking read, but never a sample in flight."""

    def __init__(self):
        self.requested = False
        self.reading = False

    def __call__(self, signum, frame):
        self.requested = True
        if self.reading:
            raise KeyboardInterrupt

    def install(self):
        old = [signal.signal(signal.SIGINT, self)]
        if hasattr(signal, "SIGTERM"):
            old.append(signal.signal(signal.SIGTERM, self))
        return old


def _ready(filt):
    """Before the first sample: the HPA worker running, and the objects of the set-up out of the GC's way."""
    filt.start_worker()
    gc.collect()
    gc.freeze()  # the set-up's objects (numpy, scipy, ...) are never scanned again: short collections


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
    ``stop`` is a :class:`StreamStop`, ``log(message)`` writes a status line.  Returns the exit status.

    The input is read by the rules of ``wake run`` (:class:`LineLayout`), and each output line holds the
    columns of ``wake run --out`` (:func:`wake.io.writers.result_columns`): the time in s, then per channel
    the measurement, the voluntary motion, the tremor (and with ``--horizon-ms`` the ahead columns).
    """
    fin, fout = sys.stdin, sys.stdout
    held = {}
    try:
        if args.fs is not None:
            held["filt"] = make_filter(args.fs)
            _ready(held["filt"])
            log(f"wake stream: ready, reading stdin at {args.fs:g} Hz")
            log(rate_note(args.fs))  # after the ready line, which a producer waits for
        else:
            log("wake stream: ready, reading stdin (the rate from its time column)")
        return _pipe_loop(args, stop, log, make_filter, held, fin, fout)
    finally:
        if "filt" in held:
            held["filt"].close()  # also on an early error return: the worker never outlives the command


def _pipe_loop(args, stop, log, make_filter, held, fin, fout) -> int:
    pending = []  # the first lines, until they settle the columns
    state = {"layout": None, "proc": None}
    lineno = 0
    last_status = time.monotonic()

    def start():
        """Decide the columns on ``pending``, make the filter, write the header; an exit status on error."""
        try:
            layout = LineLayout(pending, args)
        except ValueError as exc:
            log(f"wake stream: error: {exc}")
            return 2
        if "filt" not in held:
            held["filt"] = make_filter(layout.fs)
            _ready(held["filt"])
            log(rate_note(layout.fs))
        log(f"wake stream: {layout.describe()}")
        state["layout"], state["proc"] = layout, StreamProcessor(held["filt"], layout.channels)
        if args.header:
            from wake.io.writers import result_columns

            ahead = ahead_columns(held["filt"].config) if getattr(args, "horizon_ms", None) is not None else ()
            fout.write(",".join(result_columns(layout.channels, layout.units, ahead)) + "\n")
        return None

    def one(lineno, cells, t_in):
        """Answer one data line; an exit status when the stream must stop."""
        nonlocal last_status
        layout, proc = state["layout"], state["proc"]
        try:
            values = layout.values(cells)
        except ValueError as exc:
            if args.bad_lines == "stop":
                log(f"wake stream: error: input line {lineno}: {exc}; fix the line or pass --bad-lines "
                    "missing to treat it as a missing sample")
                return 2
            values = [math.nan] * len(layout.channels)
            proc.bad += 1
            if proc.bad <= 5:
                log(f"wake stream: warning: input line {lineno}: {exc}; taken as a missing sample")
        stamp = layout.time(cells, proc.samples)
        out = _answer(proc, args, values)
        fout.write(_line(stamp, values, out) + "\n")
        fout.flush()
        done, last_status = _after_sample(proc, args, log, t_in, last_status)
        return 0 if done else None

    try:
        while not stop.requested:
            stop.reading = True
            try:
                line = fin.readline()
            except KeyboardInterrupt:
                break
            finally:
                stop.reading = False
            if not line:
                break
            t_in = time.perf_counter()
            lineno += 1
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            if state["layout"] is None:
                pending.append((lineno, text))
                if not _enough(pending, args):
                    continue
                code = start()
                if code is not None:
                    return code
                t_in = time.perf_counter()  # the wait for the first lines and the filter's set-up are not latency
                for n, cells in state["layout"].rows:
                    code = one(n, cells, t_in)
                    if code is not None:
                        return _stopped(state["proc"], log, code)
                continue
            code = one(lineno, state["layout"].cells(line.rstrip("\r\n")), t_in)
            if code is not None:
                return _stopped(state["proc"], log, code)
        if state["layout"] is None and pending:  # the input ended before the first lines settled the columns
            code = start()
            if code is not None:
                return code
            t_in = time.perf_counter()
            for n, cells in state["layout"].rows:
                code = one(n, cells, t_in)
                if code is not None:
                    return _stopped(state["proc"], log, code)
    except BrokenPipeError:
        log("wake stream: error: the output pipe was closed by the reader; stopping")
        silence_stdout()
        _finish(state["proc"], log, "output closed")
        return 1
    _finish(state["proc"], log, "stopped by signal" if stop.requested else "end of input")
    return 0


def _stopped(proc, log, code):
    """After ``--max-samples`` (code 0) the summary; after a bad line (code 2) the error was said."""
    if code == 0:
        _finish(proc, log, "end of input")
    return code


def _line(stamp, values, out) -> str:
    """One output line: the time, then per channel the measurement and the answer's columns (``wake run``'s
    order, :func:`wake.io.writers.result_columns`)."""
    per_channel = np.column_stack([np.asarray(values, dtype=float), *out])  # (channels, kinds)
    return ",".join(repr(float(v)) for v in (stamp, *per_channel.reshape(-1)))


def _kinds(args, filt) -> tuple:
    """The output columns of each channel, in order: voluntary and tremor, and with ``--horizon-ms`` the
    tremor ahead and the voluntary motion ahead when ``filt`` makes it (:func:`ahead_columns`)."""
    ahead = getattr(args, "horizon_ms", None) is not None
    return ("voluntary", "tremor") + (tuple(name for name, _ in ahead_columns(filt.config)) if ahead else ())


def _answer(proc, args, values) -> tuple:
    """The arrays of one output line (:func:`_kinds`): :meth:`StreamProcessor.answer`, or ``answer_ahead``
    with ``--horizon-ms``."""
    if getattr(args, "horizon_ms", None) is not None:
        return proc.answer_ahead(values)
    return proc.answer(values)


def _after_sample(proc, args, log, t_in, last_status):
    """Record the sample's latency, print the status line when due; (stop now?, time of the last status)."""
    proc.latencies.append(time.perf_counter() - t_in)
    proc.advance()  # the filter's update() runs now, after the answer went out
    if args.status and time.monotonic() - last_status >= args.status:
        last_status = time.monotonic()
        log(f"wake stream: {proc.status()}")
    return bool(args.max_samples) and proc.samples >= args.max_samples, last_status


def _finish(proc, log, why):
    """The summary line; the filter is closed first so that it counts an HPA that was in flight."""
    if proc is None:
        log(f"wake stream: {why}: no samples")
        return
    proc.filt.close()
    log(f"wake stream: {why}: {proc.status()}")


def _lsl_labels(info, n):
    labels, units = [], []
    ch = info.desc().child("channels").child("channel")
    for _ in range(n):
        if ch.empty():
            break
        labels.append(ch.child_value("label") or f"ch{len(labels)}")
        units.append(ch.child_value("unit"))
        ch = ch.next_sibling()
    labels += [f"ch{i}" for i in range(len(labels), n)]
    units += [""] * (n - len(units))
    return labels, units


def _lsl_lost_error(pylsl):
    """pylsl's LostError (top level in older releases, ``pylsl.util`` in newer ones)."""
    lost = getattr(pylsl, "LostError", None)
    if lost is None:
        from pylsl.util import LostError as lost
    return lost


def run_lsl(args, make_filter, stop, log) -> int:
    """``--lsl-in`` / ``--lsl-out``: as :func:`run_pipes`, between two Lab Streaming Layer streams."""
    try:
        import pylsl
    except ImportError:
        log(f"wake stream: error: {LSL_HINT}")
        return 2
    found = pylsl.resolve_byprop("name", args.lsl_in, timeout=args.lsl_timeout)
    if not found:
        log(f"wake stream: error: no LSL stream named {args.lsl_in!r} found within {args.lsl_timeout:g} s "
            "(check the name, and that the sender is on this network)")
        return 2
    inlet = pylsl.StreamInlet(found[0], max_buflen=360, recover=False)
    info = inlet.info(timeout=args.lsl_timeout)
    inlet.open_stream(timeout=args.lsl_timeout)
    n_ch = info.channel_count()
    fs = args.fs or info.nominal_srate()
    if not fs or fs <= 0:
        log(f"wake stream: error: LSL stream {args.lsl_in!r} has an irregular rate; give the rate with --fs HZ")
        return 2
    labels, units = _lsl_labels(info, n_ch)
    filt = make_filter(fs)
    kinds = _kinds(args, filt)
    out_info = pylsl.StreamInfo(args.lsl_out, "WAKE", len(kinds) * n_ch, fs, pylsl.cf_double64,
                                f"wake-{info.source_id()}")
    chans = out_info.desc().append_child("channels")
    for label, unit in zip(labels, units):  # grouped by channel, as wake run groups its columns
        for kind in kinds:
            c = chans.append_child("channel")
            c.append_child_value("label", f"{label}_{kind}")
            c.append_child_value("unit", "" if kind == "confidence" else unit)
            c.append_child_value("type", kind)
    out_info.desc().append_child_value("source", f"wake stream from {args.lsl_in}")
    proc = StreamProcessor(filt, labels)
    _ready(proc.filt)
    outlet = pylsl.StreamOutlet(out_info)  # visible only once the filter is ready for the first sample
    log(f"wake stream: {args.lsl_in} ({n_ch} channels at {fs:g} Hz) -> {args.lsl_out}")
    log(rate_note(fs))
    last_status = time.monotonic()
    why = "end of stream"
    try:
        while not stop.requested:
            stop.reading = True
            try:
                sample, stamp = inlet.pull_sample(timeout=0.2)
            except KeyboardInterrupt:
                break
            finally:
                stop.reading = False
            if sample is None:
                continue
            t_in = time.perf_counter()
            values = [math.nan if (v is None or math.isinf(v)) else float(v) for v in sample]
            outlet.push_sample(np.column_stack(_answer(proc, args, values)).reshape(-1).tolist(), stamp)
            done, last_status = _after_sample(proc, args, log, t_in, last_status)
            if done:
                break
    except _lsl_lost_error(pylsl):
        why = "the input stream ended"
    if stop.requested:
        why = "stopped by signal"
    if outlet.have_consumers():
        time.sleep(0.5)  # let the outlet's sender thread hand the last samples to its consumers
    _finish(proc, log, why)
    del outlet
    return 0
