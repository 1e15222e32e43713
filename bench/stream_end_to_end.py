"""End-to-end latency of ``wake stream``: sample in -> result out, in real time.

Streams 6 channels at 100 Hz (the PADS recordings, joined end to end and
repeated, or a synthetic 6-axis signal when PADS is absent) into a
``wake stream`` subprocess, paced by the clock, for ``--duration`` seconds
(default 300 = 5 minutes), and times every sample from the moment it is
written to the moment its output arrives:

* ``--transport pipe``: ``wake stream --stdin --stdout``; the latency is
  taken with ``time.perf_counter`` in this process (write -> line read back);
* ``--transport lsl``: an LSL outlet -> ``wake stream --lsl-in/--lsl-out`` ->
  an inlet; the latency is ``pylsl.local_clock()`` at arrival minus the
  sample's timestamp (set at push).

It reports the median, p99, p99.9 and maximum, and whether the stream kept
up (every sample answered, in order, and the lag did not grow).  Not a test:
run it by hand on a quiet machine::

    python bench/stream_end_to_end.py                    # 5 minutes over pipes
    python bench/stream_end_to_end.py --transport lsl    # 5 minutes over LSL (needs pylsl)
    python bench/stream_end_to_end.py --duration 30      # a quick look

``--echo-baseline`` also times, side by side and fed by the same clock, a
process that only passes every sample back over the same transport: the
floor of the machine and the transport at that moment.  Shared machines
vary from run to run; compare the rows of one run.  With the echo, it also
reports ``wake stream``'s latency minus the echo's, sample by sample: a stall
of the whole machine delays both and cancels there.  ``--hpa-mode thread
inline`` runs one ``wake stream`` per mode, side by side::

    python bench/stream_end_to_end.py --hpa-mode thread inline --echo-baseline
"""

from __future__ import annotations

import argparse
import math
import os
import selectors
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

FS = 100.0
TARGET_P999_MS = 2.0
HPA_MODES = ("thread", "inline")


def six_channels(n: int) -> tuple[np.ndarray, str]:
    from wake.eval.datasets import default_pads_dir, load_pads_folder

    folder = default_pads_dir(cwd=ROOT)
    if folder is not None and folder.is_dir():
        recs = load_pads_folder(folder)
        x = np.concatenate([r.samples for r in recs])
        source = f"PADS, {len(recs)} recordings joined"
    else:
        from wake.eval.synthetic import make_signal

        s = make_signal(10.0, seed=5, duration=60.0)
        x = np.column_stack([s.measurement * k for k in (1.0, -0.5, 0.8, 2.0, -1.2, 0.3)])
        source = "synthetic (PADS not found)"
    reps = int(np.ceil(n / len(x)))
    return np.tile(x, (reps, 1))[:n], source


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


#: The floor of the machine and the pipes: a Python process that echoes every line, doing nothing else.
ECHO = ("import sys\nprint('echo: ready', file=sys.stderr, flush=True)\nfor line in sys.stdin:\n    sys.stdout.write(line)\n    sys.stdout.flush()\n"
        "print('echo: end of input', file=sys.stderr)")


def _paced(n, send):
    """Call ``send(i)`` for i = 0 .. n-1 at 100 Hz by the clock (sleeping in between)."""
    start = time.perf_counter() + 0.5
    for i in range(n):
        due = start + i / FS
        while (now := time.perf_counter()) < due:
            time.sleep(min(due - now, 0.002))
        send(i)


def run_pipe(x: np.ndarray, extras, echo=False) -> list:
    """Latencies (s) of ``wake stream`` (one process per entry of ``extras``, its extra arguments) and, with
    ``echo``, of the echo process, all fed side by side by the same clock.

    One thread paces the input and reads every output with ``select``: with a reader thread per process,
    the bench's own threads would wait for each other's interpreter lock (5 ms switch interval), and
    its latency figures would carry that wait.
    """
    cmds = [[sys.executable, "-m", "wake", "stream", "--stdin", "--stdout", "--fs", str(FS), "--status", "0",
             "--time-column", "none", *extra]  # no lines read ahead to judge a column's shape
            for extra in extras]
    if echo:
        cmds.append([sys.executable, "-c", ECHO])
    procs = [subprocess.Popen(c, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, bufsize=0,
                              env=_env()) for c in cmds]
    for p in procs:  # the clock starts when every process is ready for its first sample
        first = p.stderr.readline().decode()
        if "ready" not in first:
            raise SystemExit(f"{p.args[1:3]} did not start: {first}{p.stderr.read().decode()}")
    n = len(x)
    sent = np.full((len(procs), n), np.nan)
    got = np.full((len(procs), n), np.nan)
    answered = [0] * len(procs)
    lines = [(",".join(repr(v) for v in row) + "\n").encode() for row in x.tolist()]
    sel = selectors.DefaultSelector()
    for k, p in enumerate(procs):
        os.set_blocking(p.stdout.fileno(), False)
        sel.register(p.stdout.fileno(), selectors.EVENT_READ, k)
    start = time.perf_counter() + 0.5
    i, still_open, deadline = 0, len(procs), math.inf
    while still_open and time.perf_counter() < deadline:
        now = time.perf_counter()
        if i < n and now >= start + i / FS:
            for k in (range(len(procs)) if i % 2 == 0 else reversed(range(len(procs)))):  # none always first
                sent[k, i] = time.perf_counter()
                os.write(procs[k].stdin.fileno(), lines[i])
            i += 1
            if i == n:  # end of input: every process answers what it read, then ends
                for p in procs:
                    p.stdin.close()
                deadline = time.perf_counter() + 30
            continue
        for key, _ in sel.select(start + i / FS - now if i < n else deadline - now):
            k = key.data
            t = time.perf_counter()
            chunk = os.read(key.fd, 1 << 16)
            if not chunk:
                sel.unregister(key.fd)
                still_open -= 1
                continue
            count = min(chunk.count(b"\n"), n - answered[k])
            got[k, answered[k]:answered[k] + count] = t
            answered[k] += count
    for p in procs:
        p.wait(timeout=30)
        err = p.stderr.read().decode()
        if p.returncode != 0:
            raise SystemExit(f"{p.args[1:3]} failed ({p.returncode}):\n{err}")
        print(" ".join(p.args[-2:]) + ": " + err.strip().splitlines()[-1], file=sys.stderr)
    return list(got - sent)


#: The floor over LSL: an inlet whose every sample goes straight to an outlet, as ``wake stream`` would send it.
LSL_ECHO = """import sys, pylsl
inlet = pylsl.StreamInlet(pylsl.resolve_byprop("name", sys.argv[1], timeout=30)[0], max_buflen=360, recover=False)
inlet.open_stream(timeout=10)
n = inlet.info().channel_count()
outlet = pylsl.StreamOutlet(pylsl.StreamInfo(sys.argv[2], "echo", 2 * n, 100.0, pylsl.cf_double64, "echo"))
try:
    while True:
        sample, stamp = inlet.pull_sample(timeout=0.2)
        if sample is not None:
            outlet.push_sample(sample + sample, stamp)
except Exception:
    pass
print("echo: end of input", file=sys.stderr)
"""


def run_lsl(x: np.ndarray, extras, echo=False) -> list:
    """Latencies (s) over LSL: one outlet read by ``wake stream`` (one process per entry of ``extras``) and,
    with ``echo``, by the echo process."""
    import pylsl

    tag = f"{os.getpid()}"
    info = pylsl.StreamInfo(f"wake-bench-in-{tag}", "IMU", x.shape[1], FS, pylsl.cf_double64, f"bench-{tag}")
    outlet = pylsl.StreamOutlet(info)
    source = f"wake-bench-in-{tag}"
    cmds = {f"wake-bench-out{k}-{tag}": [sys.executable, "-m", "wake", "stream", "--lsl-in", source, "--lsl-out",
                                         f"wake-bench-out{k}-{tag}", "--status", "0", *extra]
            for k, extra in enumerate(extras)}
    if echo:
        cmds[f"wake-bench-echo-{tag}"] = [sys.executable, "-c", LSL_ECHO, source, f"wake-bench-echo-{tag}"]
    procs = [subprocess.Popen(c, stderr=subprocess.PIPE, text=True, env=_env()) for c in cmds.values()]
    inlets = []
    for name in cmds:
        inlet = pylsl.StreamInlet(pylsl.resolve_byprop("name", name, timeout=30)[0], max_buflen=360)
        inlet.open_stream(timeout=10)
        inlets.append(inlet)
    outlet.wait_for_consumers(10)
    if len(procs) > 1:
        time.sleep(2.0)  # LSL tells whether an outlet has consumers, not how many: let the second one connect
    lat = np.full((len(procs), len(x)), np.nan)

    def reader(k):
        for i in range(len(x)):
            sample, stamp = inlets[k].pull_sample(timeout=2.0)
            if sample is None:
                return
            lat[k, i] = pylsl.local_clock() - stamp

    threads = [threading.Thread(target=reader, args=(k,), daemon=True) for k in range(len(procs))]
    for th in threads:
        th.start()
    rows = x.tolist()
    _paced(len(x), lambda i: outlet.push_sample(rows[i], pylsl.local_clock()))
    for th in threads:
        th.join(timeout=30)
    outlet = None  # closes the stream: the readers of wake stream and the echo see its end
    for p in procs:
        err = p.communicate(timeout=30)[1]
        print(" ".join(p.args[-2:]) + ": " + (err.strip().splitlines()[-1] if err.strip() else ""), file=sys.stderr)
    return list(lat)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=300.0, help="seconds of streamed data (default 300)")
    ap.add_argument("--transport", choices=("pipe", "lsl"), default="pipe")
    ap.add_argument("--hpa-mode", choices=HPA_MODES, nargs="+", default=["thread"],
                    help="one wake stream process per mode given, fed side by side by the same clock")
    ap.add_argument("--echo-baseline", action="store_true",
                    help="also time a process that only echoes the lines: the floor of this machine and its pipes")
    args = ap.parse_args(argv)
    n = int(args.duration * FS)
    x, source = six_channels(n)
    extras = [["--hpa-mode", mode] for mode in args.hpa_mode]
    lat = (run_pipe if args.transport == "pipe" else run_lsl)(x, extras, echo=args.echo_baseline)
    for k, mode in enumerate(args.hpa_mode):
        report(lat[k], n, f"wake stream, {args.transport}, hpa_mode={mode}", args.duration, source)
    if args.echo_baseline:
        for k, mode in enumerate(args.hpa_mode):
            report_excess(lat[k], lat[-1], f"wake stream ({mode}) minus the echo, sample by sample")
        report(lat[-1], n, f"echo baseline, {args.transport} (no filtering), fed side by side", args.duration, source)
    return 0


def report_excess(lat, echo, what) -> None:
    """What ``wake stream`` adds to the machine's floor: its latency minus the echo's, per sample.

    Both processes got each sample within microseconds of each other, so a stall of the whole machine
    (a hypervisor taking the cores, which lasts up to hundreds of ms here) delays both and cancels.
    """
    both = np.isfinite(lat) & np.isfinite(echo)
    ms = (np.asarray(lat)[both] - np.asarray(echo)[both]) * 1e3
    p50, p99, p999 = np.percentile(ms, [50, 99, 99.9])
    print(f"{what}: {both.sum()} samples")
    print("| median | p99 | p99.9 | max |")
    print("|---:|---:|---:|---:|")
    print(f"| {p50:+.3f} ms | {p99:+.3f} ms | {p999:+.3f} ms | {ms.max():+.3f} ms |")


def report(lat, n, what, duration, source) -> None:
    answered = int(np.isfinite(lat).sum())
    ms = lat[np.isfinite(lat)] * 1e3
    p50, p99, p999 = np.percentile(ms, [50, 99, 99.9])
    half = len(ms) // 2
    drift = np.median(ms[half:]) - np.median(ms[:half])
    print(f"{what}: {n} samples x 6 channels at {FS:g} Hz ({duration:g} s, {source})")
    print("| answered | median | p99 | p99.9 | max | median drift (2nd half - 1st) |")
    print("|---:|---:|---:|---:|---:|---:|")
    print(f"| {answered} of {n} | {p50:.3f} ms | {p99:.3f} ms | {p999:.3f} ms | {ms.max():.3f} ms | {drift:+.3f} ms |")
    ok = answered == n and p999 < TARGET_P999_MS
    print(f"target p99.9 < {TARGET_P999_MS:g} ms with every sample answered: {'met' if ok else 'MISSED'}")


if __name__ == "__main__":
    sys.exit(main())
