"""The tremor characterisation of every PADS recording and axis (docs/studies/characterisation.md, "On PADS").

    python bench/characterise_pads.py [--pads DIR] [--markdown]

Each recording is read as ``wake run`` reads it (resampled onto a 100 Hz
grid), filtered with the default settings (:data:`BACKEND`), and summed up per axis with
:func:`wake.hpa.characterise.summarise` over the full 5 s HPA windows (two
per recording: 0-5 s and 5-10 s, the whole recording but its last 0.24 s;
the warm-up windows overlap the first and are left out).  The condition
labels are PADS's, as the data folder's README lists them.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wake import WakeFilter  # noqa: E402
from wake.eval.datasets import default_pads_dir, load_pads_folder  # noqa: E402
from wake.hpa.characterise import summarise  # noqa: E402

#: The RTP backend: the reference, so that the table is the same with or without the compiled core (the HPA's
#: f_d and flag, all the characterisation reads besides the samples, are Python either way).
BACKEND = "reference"

#: PADS's condition label per subject (the data folder's README, from the PADS patient metadata).
CONDITION = {"066": "ET", "070": "ET", "079": "ET", "088": "ET", "019": "PD", "040": "PD", "087": "PD",
             "105": "PD", "027": "HC", "052": "HC"}


def rows(folder):
    """``(recording, condition, axis, unit, summary)`` for every recording and axis, ET first, then PD, HC."""
    out = []
    for rec in load_pads_folder(folder):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a reference backend's CoreMissingWarning is not the point here
            filt = WakeFilter(fs=rec.fs, backend=BACKEND)
            tables = filt.run(rec.samples).tremor_stats(rec.fs, filt.config.tremor_band, x=rec.samples)
        for c, name in enumerate(rec.channels):
            out.append((rec.name, CONDITION.get(rec.name[:3], "?"), name, rec.unit(c),
                        summarise(tables[c], filt.config.window_samples)))
    order = {"ET": 0, "PD": 1, "HC": 2}
    return sorted(out, key=lambda r: (order.get(r[1], 3), r[0]))


def _number(value, fmt, unit=""):
    return "-" if value != value else format(value, fmt) + (f" {unit}" if unit else "")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pads", default=None, help="the PADS folder (default: ../shared/data/pads or $WAKE_PADS_DIR)")
    p.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = p.parse_args(argv)
    folder = default_pads_dir(args.pads, cwd=ROOT)
    if folder is None or not folder.is_dir():
        print("PADS folder not found: pass --pads DIR or set WAKE_PADS_DIR", file=sys.stderr)
        return 2
    head = ["recording", "cond.", "axis", "tremor windows", "frequency (Hz)", "RMS", "peak-to-peak", "TSI (Hz)",
            "time share"]
    sep = " | " if args.markdown else "  "
    print(("| " if args.markdown else "") + sep.join(head) + (" |" if args.markdown else ""))
    if args.markdown:
        print("|" + "|".join("---" for _ in head) + "|")
    for name, cond, axis, unit, s in rows(folder):
        cells = [name, cond, axis, f"{s['tremor_windows']} / {s['windows']}", _number(s["frequency"], ".2f"),
                 _number(s["rms"], ".3g", unit), _number(s["peak_to_peak"], ".3g", unit),
                 _number(s["tsi"], ".2f"), f"{100 * s['time_share']:.0f} %"]
        print(("| " if args.markdown else "") + sep.join(cells) + (" |" if args.markdown else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
