"""``wake stream``: WAKE on a live stream, over text pipes or Lab Streaming Layer.

Every input sample gets exactly one output sample, in order:

* ``--stdin`` / ``--stdout``: one line of comma-separated values per sample
  (optionally led by a timestamp with ``--timestamps``, copied to the output);
  a first line that is not numeric names the channels.
* ``--lsl-in NAME`` / ``--lsl-out NAME``: an LSL inlet resolved by name (any
  channel count, its nominal rate as ``fs``) and an outlet of
  ``2 x channels`` values with the input's timestamps and channel labels.
  Needs the optional ``pylsl`` (``pip install pylsl``, or ``pip install ".[lsl]"`` in a source tree).

Output per input sample ``x(n)``: the voluntary motion ``v(n)`` (predicted
from the samples before ``n``: what :meth:`WakeFilter.run` gives as
``voluntary[n]``), then the tremor ``x(n) - v(n)``: all voluntary values
first, then all tremor values.  With ``--hpa-mode inline`` the output equals
``WakeFilter.run`` on the same data bit for bit; the default ``thread`` keeps
the HPA off the sample path, so its weights take effect a few samples later
(``docs/design.md``, "Streaming").

Since ``v(n)`` is known before ``x(n)`` arrives, a sample's output line is
written first and the filter takes the sample in afterwards, while the stream
waits for the next one: the filter's work is not on the sample-in ->
result-out path.

Ctrl-C, SIGTERM or the end of the input stop the stream cleanly: every sample
read has its output written, and a summary goes to stderr.
"""

from __future__ import annotations

import argparse
import gc
import math
import signal
import sys
import threading
import time
from collections import deque

import numpy as np

from wake._files import silence_stdout

__all__ = ["StreamProcessor", "cli"]

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


class _Stop:
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


def _fmt(values) -> str:
    return ",".join(repr(float(v)) for v in values)


def _parse(line: str, expect: int | None):
    cells = [c.strip() for c in line.split(",")]
    out = []
    for c in cells:
        if c == "" or c.lower() == "nan":
            out.append(math.nan)
            continue
        v = float(c)  # ValueError: the caller names the line
        if math.isinf(v):
            raise ValueError("inf (send nan or an empty cell for a missing sample)")
        out.append(v)
    if expect is not None and len(out) != expect:
        raise ValueError(f"{len(out)} values where the stream has {expect}")
    return out


def _make_filter(args, fs):
    from wake.cli import make_filter

    return make_filter(args, fs, hpa_mode=args.hpa_mode)


def _ready(filt):
    """Before the first sample: the HPA worker running, and the objects of the set-up out of the GC's way."""
    filt.start_worker()
    gc.collect()
    gc.freeze()  # the set-up's objects (numpy, scipy, ...) are never scanned again: short collections


def _run_pipes(args, stop, log) -> int:
    fin, fout = sys.stdin, sys.stdout
    filt = _make_filter(args, args.fs)
    try:
        _ready(filt)
        log(f"wake stream: ready, reading stdin at {args.fs:g} Hz")
        return _pipe_loop(args, stop, log, filt, fin, fout)
    finally:
        filt.close()  # also on an early error return: the worker never outlives the command


def _pipe_loop(args, stop, log, filt, fin, fout) -> int:
    names = None
    proc = None
    width = None
    lineno = 0
    last_status = time.monotonic()
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
            if proc is None and names is None and not _numeric_line(text):
                names = [c.strip() for c in text.split(",")]
                if args.timestamps:
                    names = names[1:]
                continue
            try:
                values = _parse(text, width)
            except ValueError as exc:
                if args.bad_lines == "stop" or width is None:
                    log(f"wake stream: error: input line {lineno}: {exc}; fix the line or pass --bad-lines "
                        "missing to treat it as a missing sample")
                    return 2
                values = [math.nan] * width
                proc.bad += 1
                if proc.bad <= 5:
                    log(f"wake stream: warning: input line {lineno}: {exc}; taken as a missing sample")
            if width is None:
                width = len(values)
                n_ch = width - (1 if args.timestamps else 0)
                if n_ch < 1:
                    log("wake stream: error: --timestamps needs at least one value after the timestamp")
                    return 2
                if names is not None and len(names) != n_ch:
                    log(f"wake stream: error: the header names {len(names)} channels, line {lineno} has {n_ch}")
                    return 2
                names = names or [f"ch{i}" for i in range(n_ch)]
                proc = StreamProcessor(filt, names)
                if args.header:
                    head = (["time"] if args.timestamps else []) + [f"{c}_voluntary" for c in names] + \
                        [f"{c}_tremor" for c in names]
                    fout.write(",".join(head) + "\n")
            stamp = values[:1] if args.timestamps else []
            vol, trem = proc.answer(values[1:] if args.timestamps else values)
            fout.write(_fmt([*stamp, *vol, *trem]) + "\n")
            fout.flush()
            done, last_status = _after_sample(proc, args, log, t_in, last_status)
            if done:
                break
    except BrokenPipeError:
        log("wake stream: error: the output pipe was closed by the reader; stopping")
        silence_stdout()
        _finish(proc, log, "output closed")
        return 1
    _finish(proc, log, "stopped by signal" if stop.requested else "end of input")
    return 0


def _after_sample(proc, args, log, t_in, last_status):
    """Record the sample's latency, print the status line when due; (stop now?, time of the last status)."""
    proc.latencies.append(time.perf_counter() - t_in)
    proc.advance()  # the filter's update() runs now, after the answer went out
    if args.status and time.monotonic() - last_status >= args.status:
        last_status = time.monotonic()
        log(f"wake stream: {proc.status()}")
    return bool(args.max_samples) and proc.samples >= args.max_samples, last_status


def _numeric_line(text: str) -> bool:
    try:
        _parse(text, None)
        return True
    except ValueError:
        return False


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


def _run_lsl(args, stop, log) -> int:
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
    out_info = pylsl.StreamInfo(args.lsl_out, "WAKE", 2 * n_ch, fs, pylsl.cf_double64, f"wake-{info.source_id()}")
    chans = out_info.desc().append_child("channels")
    for kind in ("voluntary", "tremor"):
        for label, unit in zip(labels, units):
            c = chans.append_child("channel")
            c.append_child_value("label", f"{label}_{kind}")
            c.append_child_value("unit", unit)
            c.append_child_value("type", kind)
    out_info.desc().append_child_value("source", f"wake stream from {args.lsl_in}")
    proc = StreamProcessor(_make_filter(args, fs), labels)
    _ready(proc.filt)
    outlet = pylsl.StreamOutlet(out_info)  # visible only once the filter is ready for the first sample
    log(f"wake stream: {args.lsl_in} ({n_ch} channels at {fs:g} Hz) -> {args.lsl_out}")
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
            vol, trem = proc.answer(values)
            outlet.push_sample([*vol.tolist(), *trem.tolist()], stamp)
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


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="wake stream",
        description="Run WAKE on a live stream: voluntary motion and tremor out for every sample in.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--stdin", action="store_true", help="read one line of comma-separated values per sample")
    src.add_argument("--lsl-in", metavar="NAME", help="read the Lab Streaming Layer stream of this name")
    dst = p.add_mutually_exclusive_group(required=True)
    dst.add_argument("--stdout", action="store_true", help="write one line per sample: voluntary..., tremor...")
    dst.add_argument("--lsl-out", metavar="NAME", help="publish an LSL stream of this name")
    p.add_argument("--fs", type=float, default=None,
                   help="sampling rate in Hz (required with --stdin; default with LSL: the stream's nominal rate)")
    p.add_argument("--timestamps", action="store_true",
                   help="--stdin: the first value of each line is its timestamp, copied to the output line")
    p.add_argument("--header", action="store_true", help="--stdout: write a line of column names first")
    p.add_argument("--bad-lines", choices=("stop", "missing"), default="stop",
                   help="a line that is not numbers or has the wrong count: stop with an error (default), "
                        "or take it as a missing sample (its output line holds the prediction and nan)")
    p.add_argument("--hpa-mode", choices=("thread", "inline"), default="thread",
                   help="thread (default): the HPA runs on a worker thread, off the sample path; "
                        "inline: on the sample path, and the output equals `wake run` bit for bit")
    p.add_argument("--status", type=float, default=5.0, metavar="S",
                   help="status line on stderr every S seconds (0: only the final summary)")
    p.add_argument("--max-samples", type=int, default=0, help="stop after this many samples (0: no limit)")
    p.add_argument("--lsl-timeout", type=float, default=10.0, metavar="S", help="seconds to find the LSL stream")
    from wake.cli import add_filter_arguments

    add_filter_arguments(p)
    return p


def cli(argv=None) -> int:
    """``wake stream``: see the module docstring."""
    args = build_parser().parse_args(argv)
    if args.stdin and args.fs is None:
        raise ValueError("--stdin needs the sampling rate: give it with --fs HZ")
    if args.fs is not None and not (math.isfinite(args.fs) and args.fs > 0):
        raise ValueError(f"--fs must be > 0 Hz, got {args.fs}")
    if args.max_samples < 0 or args.status < 0:
        raise ValueError("--max-samples and --status must be >= 0")
    if args.stdin != args.stdout:
        raise ValueError("use --stdin with --stdout, or --lsl-in with --lsl-out")
    _make_filter(args, args.fs or 100.0).close()  # every filter setting checked before the stream starts

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    if args.hpa_mode == "thread":
        # The HPA worker holds the GIL in its Python parts; with the default 5 ms switch interval a
        # sample arriving then waits up to 5 ms for it.  0.2 ms bounds that wait (bench/stream_end_to_end.py).
        sys.setswitchinterval(SWITCH_INTERVAL_S)
    stop = _Stop()
    main_thread = threading.current_thread() is threading.main_thread()
    old = stop.install() if main_thread else []  # signal handlers can only be set from the main thread
    try:
        return _run_pipes(args, stop, log) if args.stdin else _run_lsl(args, stop, log)
    finally:
        for sig, handler in zip((signal.SIGINT, getattr(signal, "SIGTERM", None)), old):
            signal.signal(sig, handler)
