"""Loaders for real recordings: the PADS smartwatch format and plain CSV.

PADS (Varghese et al. 2024, PhysioNet, version 1.0.0) stores one recording
per ``.txt`` file: plain CSV, no header, 7 columns (time in s, accelerometer
x/y/z in g, gyroscope x/y/z in rad/s), 100 Hz nominal but with uneven
timestamps.  WAKE and the baselines assume a uniform grid, so
:func:`load_pads` resamples every channel onto ``t0 + i/fs`` (``t0`` the
first timestamp, ``i = 0 .. floor((t_end - t0) fs)``) by linear
interpolation in the time column.  Repeated timestamps (PADS has steps under
0.1 ms after a gap, and a zero step would make interpolation ambiguous) are
merged into one sample holding their mean.  A time column that goes
backwards is an error.

The folder used by the evaluation is found through the ``WAKE_PADS_DIR``
environment variable or an explicit path (:func:`default_pads_dir`).
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wake._validation import check_positive

__all__ = ["Recording", "PADS_CHANNELS", "load_pads", "load_pads_folder", "load_csv", "default_pads_dir"]

#: Channel names of a PADS recording, in file order after the time column.
PADS_CHANNELS = ("acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z")
#: Units of :data:`PADS_CHANNELS`.
PADS_UNITS = ("g", "g", "g", "rad/s", "rad/s", "rad/s")


@dataclass
class Recording:
    """One recording on a uniform time grid."""

    name: str
    fs: float  #: sampling rate of ``samples``, Hz
    channels: tuple  #: one name per column of ``samples``
    samples: np.ndarray  #: shape (n, len(channels)), uniformly sampled
    source: str = ""  #: file it was read from
    irregular_steps: int = 0  #: PADS: time steps off the nominal 1/fs by more than 50 %

    @property
    def duration(self) -> float:
        return self.samples.shape[0] / self.fs

    def channel(self, name) -> np.ndarray:
        """One channel by name (or by index)."""
        if isinstance(name, (int, np.integer)):
            return self.samples[:, int(name)]
        try:
            return self.samples[:, self.channels.index(name)]
        except ValueError:
            raise ValueError(f"{self.name} has no channel {name!r}; channels: {', '.join(self.channels)}") from None


def _read_numeric_rows(path: Path):
    """All rows of a CSV file as lists of strings (blank lines dropped).

    A UTF-8 byte-order mark (spreadsheet exports write one) is stripped, so
    it cannot turn the first number into text and cost the first sample.
    """
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = [row for row in csv.reader(fh) if row and any(cell.strip() for cell in row)]
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text CSV file") from None
    if not rows:
        raise ValueError(f"{path}: the file is empty")
    return rows


def _to_float(rows, path: Path, first_line: int):
    width = len(rows[0])
    out = np.empty((len(rows), width))
    for i, row in enumerate(rows):
        if len(row) != width:
            raise ValueError(
                f"{path}, line {first_line + i}: {len(row)} columns where the file has {width}"
            )
        try:
            out[i] = [float(cell) for cell in row]
        except ValueError:
            raise ValueError(f"{path}, line {first_line + i}: non-numeric value in {row!r}") from None
    if not np.isfinite(out).all():
        i = int(np.argwhere(~np.isfinite(out))[0][0])
        raise ValueError(f"{path}, line {first_line + i}: non-finite value (nan/inf)")
    return out


def resample_uniform(time, values, fs):
    """Linear interpolation of ``values`` (n, channels) at ``time`` onto ``t0 + i/fs``.

    Repeated timestamps are merged (mean of their values).  Returns the
    uniform samples and the number of raw steps off ``1/fs`` by over 50 %.
    """
    time = np.asarray(time, dtype=float)
    values = np.asarray(values, dtype=float).reshape(time.shape[0], -1)
    steps = np.diff(time)
    if (steps < 0).any():
        i = int(np.argmax(steps < 0))
        raise ValueError(f"the time column goes backwards at row {i + 2} ({time[i]} -> {time[i + 1]} s)")
    irregular = int(np.count_nonzero(np.abs(steps * fs - 1.0) > 0.5))
    uniq, inverse, counts = np.unique(time, return_inverse=True, return_counts=True)
    if uniq.size < 2:
        raise ValueError("need at least two distinct timestamps to resample")
    merged = np.zeros((uniq.size, values.shape[1]))
    np.add.at(merged, inverse, values)
    merged /= counts[:, None]
    n = int(np.floor((uniq[-1] - uniq[0]) * fs + 1e-9)) + 1
    grid = uniq[0] + np.arange(n) / fs
    out = np.column_stack([np.interp(grid, uniq, merged[:, c]) for c in range(values.shape[1])])
    return out, irregular


def load_pads(path, fs=100.0) -> Recording:
    """Read one PADS recording and resample it onto a uniform ``fs`` grid.

    Parameters
    ----------
    path : str or Path
        A ``NNN_<Task>_<Wrist>.txt`` file: 7 comma-separated numeric columns.
    fs : float
        Rate of the output grid (PADS nominal: 100 Hz).

    Returns
    -------
    Recording
        Channels :data:`PADS_CHANNELS`.
    """
    path = Path(path)
    fs = check_positive("fs", fs)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    rows = _read_numeric_rows(path)
    if len(rows[0]) != 7:
        raise ValueError(
            f"{path}: a PADS recording has 7 columns (time, acc x/y/z, gyro x/y/z), "
            f"the first line has {len(rows[0])}"
        )
    data = _to_float(rows, path, 1)
    if data.shape[0] < 2:
        raise ValueError(f"{path}: need at least two samples, got {data.shape[0]}")
    try:
        samples, irregular = resample_uniform(data[:, 0], data[:, 1:], fs)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return Recording(path.stem, fs, PADS_CHANNELS, samples, str(path), irregular)


def load_pads_folder(folder, pattern="*.txt", fs=100.0) -> list:
    """Every PADS recording in ``folder`` matching ``pattern``, sorted by name.

    Other files (``observation_NNN.json``, README.md) are ignored.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: not a folder")
    files = sorted(p for p in folder.glob(pattern) if p.is_file())
    if not files:
        raise ValueError(f"{folder}: no recording matches {pattern!r}")
    return [load_pads(p, fs) for p in files]


def load_csv(path, column=None, fs=None, name=None) -> Recording:
    """A plain CSV of uniformly sampled numbers (one sample per line).

    Parameters
    ----------
    path : str or Path
    column : int, str, sequence of those, or None
        Which column(s) to keep: an index, a header name, or ``None`` for all.
    fs : float
        Sampling rate in Hz (required: a plain CSV does not say).
    name : str, optional
        Recording name (default: the file stem).

    A first line with any non-numeric field is taken as a header.
    """
    path = Path(path)
    if fs is None:
        raise ValueError("load_csv needs the sampling rate: pass fs=<Hz>")
    fs = check_positive("fs", fs)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    rows = _read_numeric_rows(path)
    header = None
    try:
        [float(c) for c in rows[0]]
    except ValueError:
        header = [c.strip() for c in rows[0]]
        rows = rows[1:]
        if not rows:
            raise ValueError(f"{path}: a header but no data")
    data = _to_float(rows, path, 2 if header else 1)
    names = tuple(header) if header else tuple(f"col{i}" for i in range(data.shape[1]))
    if column is not None:
        if isinstance(column, (int, np.integer, str)):
            wanted = [column]
        elif isinstance(column, (list, tuple)):
            wanted = list(column)
        else:
            raise ValueError(f"column must be an index, a header name or a list of them, got {column!r}")
        idx = []
        for c in wanted:
            if isinstance(c, str):
                if c not in names:
                    raise ValueError(f"{path}: no column {c!r}; columns: {', '.join(names)}")
                idx.append(names.index(c))
            elif isinstance(c, (int, np.integer)) and not isinstance(c, bool):
                if not -data.shape[1] <= c < data.shape[1]:
                    raise ValueError(f"{path}: column index {c} out of range (the file has {data.shape[1]})")
                idx.append(int(c) % data.shape[1])
            else:
                raise ValueError(f"column must be an index, a header name or a list of them, got {c!r}")
        data = data[:, idx]
        names = tuple(names[i] for i in idx)
    return Recording(name or path.stem, fs, names, data, str(path))


def default_pads_dir(explicit=None, cwd=None):
    """Where the PADS folder is: ``explicit``, else ``$WAKE_PADS_DIR``, else
    ``../shared/data/pads`` relative to ``cwd`` (the current directory) if it
    exists; ``None`` when none applies."""
    if explicit:
        return Path(explicit)
    env = os.environ.get("WAKE_PADS_DIR")
    if env:
        return Path(env)
    guess = Path(cwd or os.getcwd()).resolve().parent / "shared" / "data" / "pads"
    return guess if guess.is_dir() else None
