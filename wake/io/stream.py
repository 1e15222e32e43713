"""WAKE on a live stream, over text pipes or Lab Streaming Layer (the streams of ``wake stream``).

The command line (its options, checks and signal handling) is in :mod:`wake.cli`;
this module reads and writes the streams.

Every input sample gets exactly one output sample, in order:

* ``--stdin`` / ``--stdout`` (:mod:`wake.io.pipes`): one line per sample, read by the rules of
  ``wake run`` (:class:`~wake.io.pipes.LineLayout`, :func:`wake.io.readers.table_layout`):
  the delimiter and decimal mark, a header row, text columns (left out) and
  the time column (:mod:`wake.io.time_column`) are taken from the first
  lines, the channels are named as ``wake run`` names them (the header's
  names, else ``col{j}`` after the file column), ``--column``,
  ``--time-column``, ``--decimal`` and ``--units`` mean what they mean
  there, and ``--fs`` may be left out when a time column gives the rate (an
  ``--fs`` that contradicts it is refused).  Only where a column's shape
  alone can tell whether it is time (no header row, ``--time-column auto``)
  does the stream read :data:`~wake.io.pipes.DETECT_LINES` lines before it answers the
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
effect a few samples later (``docs/studies/design.md``, "Streaming").

Since ``v(n)`` is known before ``x(n)`` arrives, a sample's output line is written first and the filter
takes the sample in afterwards: the filter's work is not on the sample-in -> result-out path.

Ctrl-C, SIGTERM or the end of the input stop the stream cleanly: every sample
read has its output written, and a summary goes to stderr.
"""

from __future__ import annotations

import gc
import math
import signal
import time
from collections import deque

import numpy as np

from wake.sampling import rate_note
from wake.io.writers import VOLUNTARY_AHEAD_COLUMN, ahead_columns

__all__ = ["StreamProcessor", "StreamStop", "run_lsl", "SWITCH_INTERVAL_S"]

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
