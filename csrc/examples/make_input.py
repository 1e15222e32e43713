"""Write the recorded signal the standalone firmware example runs on (int16 little-endian Q15).

    python make_input.py OUT [--pads FILE --axis K] [--seconds 50]

Default: signal 1 of the paper's synthetic set (wake.eval.synthetic), 50 s at
100 Hz.  With --pads, one axis of a PADS recording.  The full scale is the
runtime's rule: a power of two above 16 times the robust peak.
"""

import argparse
import sys

import numpy as np


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--pads", help="a PADS recording (text, 6 axes at 100 Hz)")
    ap.add_argument("--axis", type=int, default=0)
    ap.add_argument("--seconds", type=float, default=50.0)
    args = ap.parse_args(argv)
    from wake.hpa.c_port import quantize_window
    from wake.rtp.full_scale import power_of_two_at_least, robust_peak

    if args.pads:
        from wake.eval.datasets import load_pads

        x = load_pads(args.pads).samples[:, args.axis]
    else:
        from wake.eval.synthetic import paper_dataset

        x = paper_dataset(duration=args.seconds)[0].measurement
    x = np.asarray(x[: int(round(args.seconds * 100))], dtype=float)
    scale = power_of_two_at_least(16 * robust_peak(x))
    q = quantize_window(x, scale).astype("<i2")
    q.tofile(args.out)
    print(f"wrote {q.size} samples to {args.out} (full scale {scale:g})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
