"""Command line: ``wake demo``, ``wake run``, ``wake stream``, ``wake evaluate``, ``wake profile``,
``wake export-header``, ``wake export-c``.

The top layer of the package (docs/reference/architecture.md).  :data:`COMMANDS` is
the table of commands: each entry names the function that runs it, and each
function imports its module explicitly (lazily, so that ``wake --help`` loads
nothing heavy).  ``demo``, ``run`` and ``stream`` are written here; the
others keep their options next to their code (``cli()`` of their module).
"""

from __future__ import annotations

import argparse
import math
import signal
import sys
import threading
from pathlib import Path

import numpy as np

from wake.config import WakeConfig
from wake.registry import cutoff_rule_names, cutoff_rules
from wake.sampling import rate_note

__all__ = ["COMMANDS", "main"]


def add_filter_arguments(p: argparse.ArgumentParser) -> None:
    """The WAKE settings every command that filters takes (demo, run, stream)."""
    g = p.add_argument_group("WAKE parameters")
    g.add_argument("--wavelet", default="sym3", help="mother wavelet (default: sym3)")
    g.add_argument("--level", type=int, default=5, help="decomposition level J (default: 5)")
    g.add_argument("--window", type=float, default=5.0, dest="window_s", help="HPA window in s (default: 5)")
    g.add_argument("--ar-order", type=int, default=17, help="Yule-Walker order p (default: 17)")
    g.add_argument("--backend", choices=("c", "reference"), default=None,
                   help="RTP backend (default: c when the compiled core is present, else reference)")
    import wake.hpa.cutoff  # noqa: F401  (registers the built-in cut-off rules)

    rules = "; ".join(f"'{r.name}' {r.description}" for r in cutoff_rules()).replace("%", "%%")
    g.add_argument("--cutoff-rule", choices=cutoff_rule_names(), default=WakeConfig.cutoff_rule,
                   help=f"how the HPA finds f_d (default: {WakeConfig.cutoff_rule}): {rules} "
                        "(docs/studies/design.md, 'Cut-off on real wear')")


def add_horizon_argument(p: argparse.ArgumentParser) -> None:
    """``--horizon-ms`` (run, stream): the tremor-ahead columns, predicted that far ahead."""
    p.add_argument("--horizon-ms", type=float, default=None, metavar="MS",
                   help="also write the tremor predicted MS ms ahead, its confidence (0..1) and the gated "
                        "command (confidence x tremor ahead) per channel; rounded to whole samples at the "
                        "sampling rate, 1..32 samples (docs/studies/design.md, 'How a firmware uses the command and "
                        "the confidence')")


def make_filter(args, fs, **settings):
    """The WakeFilter of the options of :func:`add_filter_arguments` (and ``settings``) at ``fs``."""
    from wake.filter import WakeFilter

    # backend None: the C core when installed, else the reference (with a CoreMissingWarning)
    return WakeFilter(fs=fs, wavelet=args.wavelet, level=args.level, window_s=args.window_s,
                      ar_order=args.ar_order, backend=args.backend, cutoff_rule=args.cutoff_rule, **settings)


def _cmd_demo(args) -> int:
    from wake.eval.metrics import nrmse, prf, snr_out
    from wake.eval.synthetic import PAPER_WAKE, paper_dataset

    if args.plot:
        from wake.eval.plotting import require_matplotlib

        require_matplotlib()  # before the work, not after it

    data = paper_dataset()
    filt = make_filter(args, data[0].fs)
    print(f"WAKE on the paper's synthetic dataset (backend {filt.backend}, {filt.wavelet}, J={filt.level}, "
          f"L={filt.window_s:g} s, p={filt.ar_order}); as in the paper, the warm-up of {filt.window_samples} "
          "samples is left out, except in 'whole' (NRMSE from 0.5 s: what a wearer lives through)")
    head = (f"{'signal':>6} {'SNR_in':>7} | {'PRF%':>7} {'paper':>7} | {'SNR_out':>7} {'paper':>7} | "
            f"{'NRMSE':>7} {'paper':>7} | {'whole':>7}")
    print(head)
    print("-" * len(head))
    ours = []
    for i, s in enumerate(data):
        res = filt.run(s.measurement)
        start = res.warmup
        row = (prf(s.voluntary, res.voluntary, start), snr_out(s.voluntary, res.voluntary, start),
               nrmse(s.voluntary, res.voluntary, start), nrmse(s.voluntary, res.voluntary, int(round(0.5 * s.fs))))
        ours.append(row)
        print(f"{i + 1:>6} {s.snr_db:>7.1f} | {row[0]:>7.2f} {PAPER_WAKE['prf'][i]:>7.2f} | "
              f"{row[1]:>7.2f} {PAPER_WAKE['snr_out'][i]:>7.2f} | {row[2]:>7.4f} {PAPER_WAKE['nrmse'][i]:>7.4f} | "
              f"{row[3]:>7.4f}")
    ours = np.array(ours)
    paper = np.array(PAPER_WAKE["nrmse"])
    print("-" * len(head))
    print(f"{'mean':>6} {'':>7} | {ours[:, 0].mean():>7.2f} {np.mean(PAPER_WAKE['prf']):>7.2f} | "
          f"{ours[:, 1].mean():>7.2f} {np.mean(PAPER_WAKE['snr_out']):>7.2f} | "
          f"{ours[:, 2].mean():>7.4f} {paper.mean():>7.4f} | {ours[:, 3].mean():>7.4f}")
    print(f"NRMSE relative to the paper: mean {ours[:, 2].mean() / paper.mean():.3f}, "
          f"worst signal {np.max(ours[:, 2] / paper):.3f}")
    if args.plot:
        from wake.eval.plotting import plot_result

        s = data[0]
        res = filt.run(s.measurement)
        plot_result(args.plot, s.measurement, res, filt.fs, voluntary_truth=s.voluntary,
                    tremor_truth=s.noise, ar_order=filt.ar_order, title="synthetic signal 1")
        print(f"figure written to {args.plot}")
    return 0


def _cmd_run(args) -> int:
    from wake._files import check_output_path, refuse_same_file
    from wake.io import write_result_csv
    from wake.io.writers import ahead_columns
    from wake.target import voluntary_ahead_refusal
    from wake.io.options import horizon_setting, plot_channel_index, read_from_arguments
    from wake.io.formats.bids import derivative_writer
    from wake import __version__

    if args.plot:
        from wake.eval.plotting import require_matplotlib

        require_matplotlib()  # before the work, not after it
    for option, out in (("--out", args.out), ("--tremor-out", args.tremor_out), ("--plot", args.plot)):
        if out:
            check_output_path(out, option=option)  # before the work, not after it
            refuse_same_file(out, [args.file], option=option)
    if args.out and args.tremor_out and Path(args.out).resolve() == Path(args.tremor_out).resolve():
        raise ValueError(f"--tremor-out {args.tremor_out} is also --out: the tremor table would overwrite the "
                         "filtered signals; choose another path")
    rec = read_from_arguments(args.file, args)
    write_bids = derivative_writer(args.bids_out, rec, __version__) if args.bids_out else None  # checked now
    if args.combine:
        from wake.io.combine import combine_axes
        rec = combine_axes(rec, args.combine)
    plot_channel = plot_channel_index(args.plot_channel, rec) if args.plot else 0
    x = rec.samples
    notes = "".join(f"; {note}" for note in rec.notes)
    print(f"{rec.name}: {x.shape[0]} samples x {x.shape[1]} channel(s) ({', '.join(rec.channels)}); "
          f"{rec.timing.describe(rec.fs)}{notes}")
    horizon, said = horizon_setting(args, rec.fs)
    if said:
        print(said)
    filt = make_filter(args, rec.fs, **horizon)
    from wake.io.progress import run_progress
    with run_progress(filt, x.shape[0], x.shape[1], args.progress):
        res = filt.run(x if x.shape[1] > 1 else x[:, 0], names=rec.channels)
    if args.out:
        columns = ahead_columns(filt.config) if horizon else ()
        rows = write_result_csv(args.out, rec, res, ahead=columns)
        ahead = "".join(f", {name}" for name, _ in columns)
        print(f"wrote {rows} rows to {args.out} (time, then per channel: measurement, voluntary, tremor{ahead})")
        why = voluntary_ahead_refusal(filt.horizon, filt.backend, filt.hpa_backend) if horizon else None
        if why:
            print(f"no voluntary_ahead column: {why}")
    if write_bids:
        print(write_bids(rec, res, filt))
    cut = ", ".join(f"{c:.2f}" for c in res.mean_cutoff)
    print(f"{len(res.hpa[0])} HPA runs per channel, mean cut-off f_d = {cut} Hz, backend {res.backend}")
    print(rate_note(rec.fs))
    flags = [u.cutoff_flag for channel in res.hpa for u in channel]
    counts = ", ".join(f"{f} {flags.count(f)}" for f in sorted(set(flags), key=lambda f: (-flags.count(f), f)))
    print(f"cut-off rule {args.cutoff_rule}: {counts} (wake.hpa.CUTOFF_FLAGS says what each means)")
    if res.clipped is not None and np.any(res.clipped):
        print(f"warning: {int(np.sum(res.clipped))} input samples were clipped at full scale", file=sys.stderr)
    tables = res.tremor_stats(rec.fs, filt.config.tremor_band, x=x)
    from wake.hpa.characterise import summary_lines

    print("\n".join(summary_lines(rec.channels, [rec.unit(c) for c in range(len(rec.channels))], tables,
                                  filt.config)))
    if args.tremor_out:
        from wake.io import write_tremor_csv

        rows = write_tremor_csv(args.tremor_out, rec.channels, rec.units, tables)
        print(f"wrote {rows} rows to {args.tremor_out} (one per HPA window and channel: frequency, rms, "
              "peak_to_peak, band_power, time_share, tsi, reason)")
    if args.plot:
        from wake.eval.plotting import plot_result, plot_tremor, tremor_figure_path

        name = rec.channels[plot_channel]
        plot_result(args.plot, x, res, rec.fs, ar_order=filt.ar_order, unit=rec.unit(plot_channel),
                    channel=plot_channel, channel_name=name, title=f"{Path(args.file).name}: {name}")
        second = tremor_figure_path(args.plot)
        plot_tremor(second, tables[plot_channel], filt.config.window_samples, unit=rec.unit(plot_channel),
                    channel_name=name, title=f"{Path(args.file).name}: {name}")
        print(f"figure written to {args.plot} (channel {name})")
        print(f"the tremor over time (frequency, amplitude, TSI, time share) written to {second}")
    return 0


def _stream_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="wake stream",
        description="Run WAKE on a live stream: voluntary motion and tremor out for every sample in.")
    from wake.io.options import add_stream_io_arguments

    add_stream_io_arguments(p)
    p.add_argument("--timestamps", action="store_true",
                   help="--stdin: the first value of each line is its timestamp (the same as --time-column 0)")
    p.add_argument("--header", action="store_true",
                   help="--stdout: write a line of column names first (wake run --out's: 'time [s]', then per "
                        "channel the measurement, _voluntary, _tremor)")
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
    add_filter_arguments(p)
    add_horizon_argument(p)
    return p


def _cmd_stream(argv) -> int:
    """``wake stream``: WAKE on a live stream (:mod:`wake.io.stream`)."""
    from wake.io.options import horizon_setting
    from wake.io.pipes import run_pipes
    from wake.io.replay import run_file
    from wake.io.stream import SWITCH_INTERVAL_S, StreamStop, run_lsl
    from wake.target import voluntary_ahead_refusal

    args = _stream_parser().parse_args(argv)
    if args.fs is not None and not (math.isfinite(args.fs) and args.fs > 0):
        raise ValueError(f"--fs must be > 0 Hz, got {args.fs}")
    if args.max_samples < 0 or args.status < 0:
        raise ValueError("--max-samples and --status must be >= 0")
    if bool(args.stdin or args.file) != args.stdout:
        raise ValueError("use --stdin or --file with --stdout, or --lsl-in with --lsl-out")

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    def make(fs, quiet=False):
        horizon, said = horizon_setting(args, fs)
        if said and not quiet:
            log(f"wake stream: {said}")   # stdout carries the samples
        filt = make_filter(args, fs, hpa_mode=args.hpa_mode, **horizon)
        why = voluntary_ahead_refusal(filt.horizon, filt.backend, filt.hpa_backend) if said else None
        if why and not quiet:
            log(f"wake stream: no voluntary_ahead column: {why}")
        return filt

    if args.fs is not None or args.horizon_ms is None:   # an LSL rate is known only once the stream is found
        make(args.fs or 100.0, quiet=True).close()  # every filter setting checked before the stream starts

    if args.hpa_mode == "thread":
        # The HPA worker holds the GIL in its Python parts; with the default 5 ms switch interval a
        # sample arriving then waits up to 5 ms for it.  0.2 ms bounds that wait (bench/stream_end_to_end.py).
        sys.setswitchinterval(SWITCH_INTERVAL_S)
    stop = StreamStop()
    main_thread = threading.current_thread() is threading.main_thread()
    old = stop.install() if main_thread else []  # signal handlers can only be set from the main thread
    try:
        return (run_file if args.file else run_pipes if args.stdin else run_lsl)(args, make, stop, log)
    finally:
        for sig, handler in zip((signal.SIGINT, getattr(signal, "SIGTERM", None)), old):
            signal.signal(sig, handler)


def _cmd_evaluate(argv) -> int:
    from wake.eval.evaluate import cli

    return cli(argv)


def _cmd_profile(argv) -> int:
    from wake.firmware.profile.cli import cli

    return cli(argv)


def _cmd_export_header(argv) -> int:
    from wake.firmware.export import cli

    return cli(argv)


def _cmd_export_c(argv) -> int:
    from wake.firmware.folder import cli

    return cli(argv)


#: ``wake COMMAND``: (one line of help, the function that runs it on the rest of the command line).
#: ``demo`` and ``run`` are parsed by :func:`build_parser` and run by :func:`_cmd_demo` / :func:`_cmd_run`.
COMMANDS = {
    "stream": ("run on a live stream: text pipes or Lab Streaming Layer", _cmd_stream),
    "evaluate": ("baselines vs WAKE on synthetic and real recordings", _cmd_evaluate),
    "profile": ("Cortex-M instruction count, footprint and stack per sample", _cmd_profile),
    "export-header": ("write a C header with taps and weights for firmware", _cmd_export_header),
    "export-c": ("write a drop-in firmware folder: C core, configuration header, README", _cmd_export_c),
}


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="wake", description="Real-time pathological tremor extraction (WAKE).")
    from wake import __version__

    p.add_argument("--version", action="version", version=f"wake {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    d = sub.add_parser("demo", help="run the paper's synthetic dataset and compare with the paper")
    add_filter_arguments(d)
    d.add_argument("--plot", metavar="PNG", help="draw signal 1 (needs matplotlib)")
    r = sub.add_parser("run", help="process a recording (CSV, PADS, MATLAB, wearable formats, Motion-BIDS)")
    r.add_argument("file", help="recording: delimited text, a PADS .txt, a .mat or a file/folder of docs/guide/formats.md")
    from wake.io.options import add_reading_arguments

    add_reading_arguments(r)
    r.add_argument("--out", metavar="CSV", help="write time, then per channel measurement, voluntary, tremor "
                                                "(names and units in the header; every value written so that "
                                                "it reads back exactly)")
    r.add_argument("--tremor-out", metavar="CSV",
                   help="write the tremor characterisation of every HPA window, one row per window and channel: "
                        "channel, unit, index, end_time, samples, cutoff, frequency, rms, peak_to_peak, "
                        "band_power, time_share, tsi, reason (a NaN field's reason); docs/studies/characterisation.md")
    r.add_argument("--bids-out", metavar="DIR", help="write a BIDS derivative of a Motion-BIDS input (docs/guide/formats.md)")
    r.add_argument("--plot", metavar="PNG", help="draw one channel, and its tremor over time (frequency, "
                                                 "amplitude, TSI, time share) beside it in PNG's name with "
                                                 "'-tremor' (needs matplotlib; checked before the work)")
    r.add_argument("--combine", choices=("norm", "pca"), default=None,
                   help="each x, y, z triple of channels into one: 'norm' the magnitude (an accelerometer's less "
                        "gravity), 'pca' the principal axis (for a gyroscope); wake.io.combine says how")
    r.add_argument("--progress", choices=("auto", "on", "off"), default="auto",
                   help="a progress bar (needs tqdm); auto: on a terminal, for 2 million samples or more")
    r.add_argument("--plot-channel", metavar="NAME|INDEX", default=None,
                   help="the channel --plot draws (default: the first); every channel is still filtered and "
                        "written to --out")
    add_filter_arguments(r)
    add_horizon_argument(r)
    for name, (helptext, _) in COMMANDS.items():
        s = sub.add_parser(name, help=helptext, add_help=False)
        s.add_argument("rest", nargs=argparse.REMAINDER)
    return p


def main(argv=None) -> int:
    import warnings

    argv = list(sys.argv[1:] if argv is None else argv)
    saved = warnings.formatwarning
    from wake.io.options import one_line_warnings

    warnings.formatwarning = one_line_warnings(argv[0] if argv and not argv[0].startswith("-") else "")
    try:
        return _main(argv)
    finally:
        warnings.formatwarning = saved


def _main(argv) -> int:
    parser = build_parser()
    if argv and argv[0] in COMMANDS:
        _, command = COMMANDS[argv[0]]
        try:
            return int(command(argv[1:]) or 0)
        except (ValueError, OSError) as exc:
            print(f"wake {argv[0]}: error: {exc}", file=sys.stderr)
            return 2
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return {"demo": _cmd_demo, "run": _cmd_run}[args.command](args)
    except BrokenPipeError:  # `wake demo | head`: the reader left; not an error of ours
        from wake._files import silence_stdout

        silence_stdout()
        return 0
    except (ValueError, OSError) as exc:
        print(f"wake {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
