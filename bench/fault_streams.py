"""Tremor NRMSE of the C backend against the float reference on the field-fault streams.

    python bench/fault_streams.py

The streams are those of tests/test_faults.py (paper-style synthetic signal,
SNR 5 dB, 60 s at 100 Hz, seed 1); scores over the whole recording and after
the first HPA window (5 s).
"""

import sys
import warnings
from pathlib import Path


sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_faults import _stream, _tremor_nrmse  # noqa: E402

from wake import WakeFilter  # noqa: E402


def main():
    print("| stream | C whole | reference whole | C after 5 s | reference after 5 s | clipped | full scale | changes |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for kind in ("clean", "glitch", "quiet", "nan_start", "dc_jump", "late_glitch", "rail", "huge"):
        x, vol = _stream(kind)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = WakeFilter(fs=100.0).run(x)
            ref = WakeFilter(fs=100.0, backend="reference").run(x)
        changes = getattr(c, "full_scale_changes", None)
        changes = "n/a" if changes is None else changes[0]
        e = [_tremor_nrmse(x, vol, r, s) for s in (0, 500) for r in (c, ref)]
        print(f"| {kind} | {e[0]:.4f} | {e[1]:.4f} | {e[2]:.4f} | {e[3]:.4f} | {c.clipped[0]} | "
              f"{c.full_scale[0]:g} | {changes} |")


if __name__ == "__main__":
    main()
