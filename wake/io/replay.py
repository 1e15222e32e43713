"""``wake stream --file PATH --stdout``: a recording replayed through the stream, sample by sample.

The file is read by :func:`wake.io.read_recording` (any format it reads:
delimited text, PADS, MATLAB and those of :mod:`wake.io.formats`; ``--fs``
resamples it), then each sample is one input line of the ``--stdin`` loop of
:mod:`wake.io.stream`: the recording's channel names as its header, its time
as the line's timestamp (``--timestamps`` is implied and the output's first
column), a missing sample (NaN) as ``nan``.  The output is what ``--stdin``
would write for the same lines.
"""

from __future__ import annotations

import io
import sys
from argparse import Namespace

import numpy as np

from wake.io.readers import read_recording
from wake.io.stream import _fmt, _pipe_loop, _ready
from wake.sampling import rate_note

__all__ = ["run_file"]


def run_file(args, make_filter, stop, log) -> int:
    """Replay ``args.file`` (options of ``wake stream``) to stdout; the exit status, as :func:`run_pipes`."""
    rec = read_recording(args.file, fs=args.fs)
    lines = [",".join(["time", *rec.channels])]
    lines += [_fmt(row) for row in np.column_stack([rec.time, rec.samples])]
    replay = Namespace(**{**vars(args), "fs": rec.fs, "timestamps": True})
    filt = make_filter(rec.fs)
    try:
        _ready(filt)
        log(f"wake stream: replaying {rec.name}: {rec.samples.shape[0]} samples x {len(rec.channels)} channel(s) "
            f"({', '.join(rec.channels)}); {rec.timing.describe(rec.fs)}")
        log(rate_note(rec.fs))
        return _pipe_loop(replay, stop, log, filt, io.StringIO("\n".join(lines) + "\n"), sys.stdout)
    finally:
        filt.close()
