"""``wake stream --file PATH --stdout``: a recording replayed through the stream, sample by sample.

The file is read as ``wake run`` reads it (:func:`wake.io.options.read_from_arguments`: any format of
:func:`wake.io.read_recording`, with ``--column``, ``--time-column``, ``--fs``, ``--units``), then each
sample is one input line of the ``--stdin`` loop (:mod:`wake.io.pipes`): a header of ``time [s]`` and the
channels with their units, then per sample its time and values (a missing sample as ``nan``).  The output
is what ``--stdin`` writes for those lines: ``wake run --out``'s columns.
"""

from __future__ import annotations

import io
import sys
from argparse import Namespace

import numpy as np

from wake.io.options import read_from_arguments
from wake.io.pipes import _Pipe
from wake.sampling import rate_note

__all__ = ["run_file"]


def run_file(args, make_filter, stop, log) -> int:
    """Replay ``args.file`` (options of ``wake stream``) to stdout; the exit status, as :func:`run_pipes`."""
    rec = read_from_arguments(args.file, Namespace(**{**vars(args), "format": "auto", "resample": False}),
                              option="--file")
    head = ["time [s]", *(f"{c} [{rec.unit(j)}]" if rec.unit(j) else c for j, c in enumerate(rec.channels))]
    rows = np.column_stack([rec.time, rec.samples])
    text = "\n".join([",".join(head), *(",".join(repr(float(v)) for v in row) for row in rows)]) + "\n"
    replay = Namespace(**{**vars(args), "fs": rec.fs, "time_column": "auto", "column": None, "decimal": ".",
                          "units": None, "timestamps": False})
    pipe = _Pipe(replay, stop, log, make_filter, io.StringIO(text), sys.stdout)
    try:
        pipe.make(rec.fs)
        log(f"wake stream: replaying {rec.name}: {rec.samples.shape[0]} samples x {len(rec.channels)} channel(s) "
            f"({', '.join(rec.channels)}); {rec.timing.describe(rec.fs)}")
        log(rate_note(rec.fs))
        return pipe.run()
    finally:
        if pipe.filt is not None:
            pipe.filt.close()  # also on an early error return: the worker never outlives the command
