"""EDF, EDF+ and BDF (BioSemi's 24-bit EDF), read with ``edfio`` (``pip install "wake-tremor[edf]"``).

Every signal of an EDF file has its own rate.  The channels read are the
signals at one rate: the ones asked for (``columns``: labels or 0-based
signal indices; they must share a rate), else every signal at the highest
rate (the others are left out, and ``notes`` names them).  Units are the
signals' physical dimensions; time is ``i / rate`` from the recording's
start.  EDF+ annotations are not signals and are not read.

Examples
--------
>>> import os, tempfile
>>> import numpy as np
>>> import edfio                                          # doctest: +SKIP
>>> path = os.path.join(tempfile.mkdtemp(), "rec.edf")
>>> edfio.Edf([edfio.EdfSignal(np.zeros(1000), 100, label="gyro_x", physical_dimension="deg/s",
...                            physical_range=(-500, 500))]).write(path)   # doctest: +SKIP
>>> from wake.io import read_recording
>>> rec = read_recording(path)                            # doctest: +SKIP
>>> rec.fs, rec.channels, rec.units                        # doctest: +SKIP
(100.0, ('gyro_x',), ('deg/s',))
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from wake.io.formats._base import Table, normalise_unit, require

__all__ = ["read_edf", "is_bdf"]


def is_bdf(path: Path) -> bool:
    """A BDF file starts with the byte 255 and ``BIOSEMI``; an EDF file with ``0`` and spaces."""
    with open(path, "rb") as f:
        return f.read(8) == b"\xffBIOSEMI"


def read_edf(path: Path, columns=None) -> Table:
    """The signals of an EDF / BDF file at one rate (module docstring); ``meta["columns"]`` says they were chosen."""
    edfio = require("edfio", "edf", "an EDF or BDF file")
    bdf = is_bdf(path)
    with warnings.catch_warnings(record=True) as said:   # a repaired header: said in the notes, not as a warning
        warnings.simplefilter("always")
        try:
            edf = edfio.read_bdf(path) if bdf else edfio.read_edf(path)
        except (ValueError, OSError, UnicodeDecodeError, IndexError) as exc:
            raise ValueError(f"{path}: not a readable {'BDF' if bdf else 'EDF'} file (edfio: {exc})") from None
    signals = list(edf.signals)
    if not signals:
        raise ValueError(f"{path}: the file holds no signal (only annotations)")
    labels = [s.label.strip() or f"signal{i}" for i, s in enumerate(signals)]
    if columns is None:
        top = max(s.sampling_frequency for s in signals)
        chosen = [i for i, s in enumerate(signals) if s.sampling_frequency == top]
    else:
        chosen = [_signal_index(c, labels, path) for c in ([columns] if isinstance(columns, (str, int)) else columns)]
        rates = sorted({signals[i].sampling_frequency for i in chosen})
        if len(rates) > 1:
            raise ValueError(f"{path}: the channels asked for have different rates "
                             f"({', '.join(f'{labels[i]} {signals[i].sampling_frequency:g} Hz' for i in chosen)}); "
                             "ask for channels of one rate")
    fs = float(signals[chosen[0]].sampling_frequency)
    n = min(len(signals[i].data) for i in chosen)
    if n < 2:
        raise ValueError(f"{path}: need at least two samples, the file holds {n} (a truncated file?)")
    values = np.column_stack([np.asarray(signals[i].data[:n], dtype=float) for i in chosen])
    left = [f"{labels[i]} ({signals[i].sampling_frequency:g} Hz)" for i in range(len(signals)) if i not in chosen]
    notes = (f"{'BDF' if bdf else 'EDF'} signals at {fs:g} Hz",) + tuple(f"edfio: {w.message}" for w in said)
    if left and columns is None:
        notes += (f"signals at other rates left out: {', '.join(left)} (ask for them with --column)",)
    units = [normalise_unit(signals[i].physical_dimension) for i in chosen]
    return Table(path.stem, [labels[i] for i in chosen], units, values, time=np.arange(n) / fs, notes=notes,
                 meta={"columns": True, "fs": fs})


def _signal_index(spec, labels, path) -> int:
    if isinstance(spec, str) and spec.strip().isdigit():
        spec = int(spec)
    if isinstance(spec, (int, np.integer)) and not isinstance(spec, bool):
        if not 0 <= spec < len(labels):
            raise ValueError(f"{path}: signal index {spec} out of range (the file has {len(labels)} signals, "
                             f"0..{len(labels) - 1})")
        return int(spec)
    if spec not in labels:
        raise ValueError(f"{path}: no signal {spec!r}; signals: {', '.join(labels)}")
    return labels.index(spec)
