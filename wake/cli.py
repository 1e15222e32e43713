"""Command line: ``wake demo``, ``wake run``, ``wake evaluate``, ``wake profile``, ``wake export-header``, ``wake export-c``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

__all__ = ["main"]


def _filter_arguments(p: argparse.ArgumentParser):
    g = p.add_argument_group("WAKE parameters")
    g.add_argument("--wavelet", default="sym3", help="mother wavelet (default: sym3)")
    g.add_argument("--level", type=int, default=5, help="decomposition level J (default: 5)")
    g.add_argument("--window", type=float, default=5.0, dest="window_s", help="HPA window in s (default: 5)")
    g.add_argument("--ar-order", type=int, default=17, help="Yule-Walker order p (default: 17)")
    g.add_argument("--backend", choices=("c", "reference"), default=None,
                   help="RTP backend (default: c when the compiled core is present, else reference)")


def _make_filter(args, fs):
    from wake.filter import WakeFilter

    backend = args.backend or default_backend()
    return WakeFilter(fs=fs, wavelet=args.wavelet, level=args.level, window_s=args.window_s,
                      ar_order=args.ar_order, backend=backend)


def default_backend():
    """``"c"`` when the compiled core imports, else ``"reference"``."""
    from wake.rtp import c_backend_available

    return "c" if c_backend_available() else "reference"


def _cmd_demo(args) -> int:
    from wake.eval.metrics import nrmse, prf, snr_out
    from wake.eval.synthetic import PAPER_WAKE, paper_dataset

    data = paper_dataset()
    filt = _make_filter(args, data[0].fs)
    print(f"WAKE on the paper's synthetic dataset (backend {filt.backend}, {filt.wavelet}, J={filt.level}, "
          f"L={filt.window_s:g} s, p={filt.ar_order}); warm-up of {filt.window_samples} samples left out")
    head = f"{'signal':>6} {'SNR_in':>7} | {'PRF%':>7} {'paper':>7} | {'SNR_out':>7} {'paper':>7} | {'NRMSE':>7} {'paper':>7}"
    print(head)
    print("-" * len(head))
    ours = []
    for i, s in enumerate(data):
        res = filt.run(s.measurement)
        start = res.warmup
        row = (prf(s.voluntary, res.voluntary, start), snr_out(s.voluntary, res.voluntary, start),
               nrmse(s.voluntary, res.voluntary, start))
        ours.append(row)
        print(f"{i + 1:>6} {s.snr_db:>7.1f} | {row[0]:>7.2f} {PAPER_WAKE['prf'][i]:>7.2f} | "
              f"{row[1]:>7.2f} {PAPER_WAKE['snr_out'][i]:>7.2f} | {row[2]:>7.4f} {PAPER_WAKE['nrmse'][i]:>7.4f}")
    ours = np.array(ours)
    paper = np.array(PAPER_WAKE["nrmse"])
    print("-" * len(head))
    print(f"{'mean':>6} {'':>7} | {ours[:, 0].mean():>7.2f} {np.mean(PAPER_WAKE['prf']):>7.2f} | "
          f"{ours[:, 1].mean():>7.2f} {np.mean(PAPER_WAKE['snr_out']):>7.2f} | "
          f"{ours[:, 2].mean():>7.4f} {paper.mean():>7.4f}")
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


def _read_csv(path, column, fs):
    from wake.eval.datasets import load_csv

    return load_csv(path, column=column, fs=fs)


def _cmd_run(args) -> int:
    from wake._files import atomic_write_text, refuse_same_file

    if not args.fs > 0:
        raise ValueError(f"--fs must be > 0 Hz, got {args.fs}")
    if args.out:
        refuse_same_file(args.out, [args.file])
    rec = _read_csv(args.file, args.column, args.fs)
    x = rec.samples
    filt = _make_filter(args, args.fs)
    res = filt.run(x)
    out = np.column_stack([x.reshape(len(x), -1), np.reshape(res.voluntary, (len(x), -1)),
                           np.reshape(res.tremor, (len(x), -1))])
    k = out.shape[1] // 3
    names = ([f"measurement_{c}" for c in range(k)] + [f"voluntary_{c}" for c in range(k)]
             + [f"tremor_{c}" for c in range(k)]) if k > 1 else ["measurement", "voluntary", "tremor"]
    if args.out:
        import io

        buf = io.StringIO()
        np.savetxt(buf, out, delimiter=",", header=",".join(names), comments="", fmt="%.9g")
        atomic_write_text(args.out, buf.getvalue())
        print(f"wrote {len(x)} rows to {args.out}")
    cut = ", ".join(f"{c:.2f}" for c in res.mean_cutoff)
    print(f"{len(x)} samples, {len(res.hpa[0])} HPA runs per channel, mean cut-off f_d = {cut} Hz, "
          f"backend {res.backend}")
    if res.clipped is not None and np.any(res.clipped):
        print(f"warning: {int(np.sum(res.clipped))} input samples were clipped at full scale", file=sys.stderr)
    if args.plot:
        from wake.eval.plotting import plot_result

        plot_result(args.plot, np.reshape(x, (len(x), -1))[:, 0], res, args.fs, ar_order=filt.ar_order,
                    title=Path(args.file).name)
        print(f"figure written to {args.plot}")
    return 0


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
    _filter_arguments(d)
    d.add_argument("--plot", metavar="PNG", help="draw signal 1 (needs matplotlib)")
    r = sub.add_parser("run", help="process a CSV recording")
    r.add_argument("file", help="CSV file, one sample per row (a header row is skipped)")
    r.add_argument("--fs", type=float, required=True, help="sampling rate in Hz")
    r.add_argument("--column", type=int, default=None,
                   help="0-based column to process (default: every column)")
    r.add_argument("--out", metavar="CSV", help="write measurement, voluntary and tremor columns")
    r.add_argument("--plot", metavar="PNG", help="draw the first channel (needs matplotlib)")
    _filter_arguments(r)
    for name, helptext in (("evaluate", "baselines vs WAKE on synthetic and real recordings"),
                           ("profile", "Cortex-M instruction count, footprint and stack per sample"),
                           ("export-header", "write a C header with taps and weights for firmware"),
                           ("export-c", "write a drop-in firmware folder: C core, configuration header, README")):
        s = sub.add_parser(name, help=helptext, add_help=False)
        s.add_argument("rest", nargs=argparse.REMAINDER)
    return p


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    delegated = {"evaluate": "wake.eval.evaluate", "profile": "wake.firmware.profile.cli",
                 "export-header": "wake.firmware.export", "export-c": "wake.firmware.folder"}
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
    except (ValueError, OSError) as exc:
        print(f"wake {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
