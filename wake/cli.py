"""Command line: ``wake demo``, ``wake run``, ``wake evaluate``, ``wake profile``, ``wake export-header``, ``wake export-c``, ``wake stream``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

__all__ = ["main"]


def add_filter_arguments(p: argparse.ArgumentParser) -> None:
    """The WAKE settings every command that filters takes (demo, run, stream)."""
    g = p.add_argument_group("WAKE parameters")
    g.add_argument("--wavelet", default="sym3", help="mother wavelet (default: sym3)")
    g.add_argument("--level", type=int, default=5, help="decomposition level J (default: 5)")
    g.add_argument("--window", type=float, default=5.0, dest="window_s", help="HPA window in s (default: 5)")
    g.add_argument("--ar-order", type=int, default=17, help="Yule-Walker order p (default: 17)")
    g.add_argument("--backend", choices=("c", "reference"), default=None,
                   help="RTP backend (default: c when the compiled core is present, else reference)")
    from wake.config import WakeConfig
    from wake.hpa.cutoff import CUTOFF_RULES

    g.add_argument("--cutoff-rule", choices=CUTOFF_RULES, default=WakeConfig.cutoff_rule,
                   help=f"how the HPA finds f_d (default: {WakeConfig.cutoff_rule}): 'paper' a 3 dB valley or "
                        "2 Hz; 'shallow' also a shallower dip below a tremor peak, at or below 4 Hz; 'floor' "
                        "as 'shallow', with both compared to the noise floor above the tremor band (on PADS "
                        "33 %% instead of 82 %% of windows on 2 Hz; docs/design.md, 'Cut-off on real wear')")


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
    from wake._files import refuse_same_file
    from wake.io import write_result_csv
    from wake.io.options import read_from_arguments

    if args.plot:
        from wake.eval.plotting import require_matplotlib

        require_matplotlib()  # before the work, not after it
    if args.out:
        refuse_same_file(args.out, [args.file])
    rec = read_from_arguments(args.file, args)
    plot_channel = _plot_channel(args.plot_channel, rec) if args.plot else 0
    x = rec.samples
    notes = "".join(f"; {note}" for note in rec.notes)
    print(f"{rec.name}: {x.shape[0]} samples x {x.shape[1]} channel(s) ({', '.join(rec.channels)}); "
          f"{rec.timing.describe(rec.fs)}{notes}")
    filt = make_filter(args, rec.fs)
    res = filt.run(x if x.shape[1] > 1 else x[:, 0])
    if args.out:
        rows = write_result_csv(args.out, rec, res)
        print(f"wrote {rows} rows to {args.out} (time, then per channel: measurement, voluntary, tremor)")
    cut = ", ".join(f"{c:.2f}" for c in res.mean_cutoff)
    print(f"{len(res.hpa[0])} HPA runs per channel, mean cut-off f_d = {cut} Hz, backend {res.backend}")
    flags = [u.cutoff_flag for channel in res.hpa for u in channel]
    counts = ", ".join(f"{f} {flags.count(f)}" for f in sorted(set(flags), key=lambda f: (-flags.count(f), f)))
    print(f"cut-off rule {args.cutoff_rule}: {counts} (wake.hpa.CUTOFF_FLAGS says what each means)")
    if res.clipped is not None and np.any(res.clipped):
        print(f"warning: {int(np.sum(res.clipped))} input samples were clipped at full scale", file=sys.stderr)
    if args.plot:
        from wake.eval.plotting import plot_result

        name = rec.channels[plot_channel]
        plot_result(args.plot, x, res, rec.fs, ar_order=filt.ar_order, unit=rec.unit(plot_channel),
                    channel=plot_channel, channel_name=name, title=f"{Path(args.file).name}: {name}")
        print(f"figure written to {args.plot} (channel {name})")
    return 0


def _plot_channel(spec, rec) -> int:
    """The channel ``--plot-channel`` names (a name or a 0-based index among the channels read); default 0."""
    if spec is None:
        return 0
    if spec in rec.channels:
        return rec.channels.index(spec)
    if spec.strip().isdigit() and int(spec) < len(rec.channels):
        return int(spec)
    raise ValueError(f"--plot-channel {spec!r} is not a channel of {rec.name}; channels: "
                     f"{', '.join(rec.channels)} (or a 0-based index below {len(rec.channels)})")


def _delegate(module: str, argv) -> int:
    import importlib

    mod = importlib.import_module(module)
    return int(mod.cli(argv) or 0)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="wake", description="Real-time pathological tremor extraction (WAKE).")
    from wake import __version__

    p.add_argument("--version", action="version", version=f"wake {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    d = sub.add_parser("demo", help="run the paper's synthetic dataset and compare with the paper")
    add_filter_arguments(d)
    d.add_argument("--plot", metavar="PNG", help="draw signal 1 (needs matplotlib)")
    r = sub.add_parser("run", help="process a recording (CSV, PADS or MATLAB .mat)")
    r.add_argument("file", help="recording: delimited text (a header row of names is read), a PADS .txt, or a .mat")
    from wake.io.options import add_reading_arguments

    add_reading_arguments(r)
    r.add_argument("--out", metavar="CSV", help="write time, then per channel measurement, voluntary, tremor "
                                                "(names and units in the header; every value written so that "
                                                "it reads back exactly)")
    r.add_argument("--plot", metavar="PNG", help="draw one channel (needs matplotlib; checked before the work)")
    r.add_argument("--plot-channel", metavar="NAME|INDEX", default=None,
                   help="the channel --plot draws (default: the first); every channel is still filtered and "
                        "written to --out")
    add_filter_arguments(r)
    for name, helptext in (("evaluate", "baselines vs WAKE on synthetic and real recordings"),
                           ("profile", "Cortex-M instruction count, footprint and stack per sample"),
                           ("export-header", "write a C header with taps and weights for firmware"),
                           ("export-c", "write a drop-in firmware folder: C core, configuration header, README"),
                           ("stream", "run on a live stream: text pipes or Lab Streaming Layer")):
        s = sub.add_parser(name, help=helptext, add_help=False)
        s.add_argument("rest", nargs=argparse.REMAINDER)
    return p


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    delegated = {"evaluate": "wake.eval.evaluate", "profile": "wake.firmware.profile.cli",
                 "export-header": "wake.firmware.export", "export-c": "wake.firmware.folder",
                 "stream": "wake.io.stream"}
    if argv and argv[0] in delegated:
        module = delegated[argv[0]]
        try:
            return _delegate(module, argv[1:])
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
