"""Loaders of the evaluation: the PADS folder and plain CSV, on top of :mod:`wake.io`.

PADS (Varghese et al. 2024, PhysioNet, version 1.0.0) stores one recording
per ``.txt`` file: plain CSV, no header, 7 columns (time in s, accelerometer
x/y/z in g, gyroscope x/y/z in rad/s), 100 Hz nominal but with uneven
timestamps.  WAKE and the baselines assume a uniform grid, so
:func:`load_pads` resamples every channel onto ``t0 + i/fs`` by linear
interpolation in the time column (:func:`wake.io.resample_uniform`).

The folder used by the evaluation is found through the ``WAKE_PADS_DIR``
environment variable or an explicit path (:func:`default_pads_dir`).
"""

from __future__ import annotations

import os
from pathlib import Path

from wake.io import PADS_CHANNELS, PADS_UNITS, Recording, read_csv, read_pads, resample_uniform

__all__ = ["Recording", "PADS_CHANNELS", "PADS_UNITS", "load_pads", "load_pads_folder", "load_csv",
           "default_pads_dir", "resample_uniform"]


def load_pads(path, fs=100.0) -> Recording:
    """Read one PADS recording and resample it onto a uniform ``fs`` grid (:func:`wake.io.read_pads`)."""
    return read_pads(path, fs=fs)


def dataset_files(folder, pattern, what="recording") -> list:
    """The files of ``folder`` matching ``pattern``, sorted by name: the one rule every dataset's folder is read by.

    Raises ``ValueError`` naming the folder when it is not one or holds no match.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp()); _ = (d / "b.txt").write_text(""); _ = (d / "a.txt").write_text("")
    >>> [p.name for p in dataset_files(d, "*.txt")]
    ['a.txt', 'b.txt']
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: not a folder")
    files = sorted(p for p in folder.glob(pattern) if p.is_file())
    if not files:
        raise ValueError(f"{folder}: no {what} matches {pattern!r}")
    return files


def default_data_dir(name, env_var, explicit=None, cwd=None):
    """Where a dataset's folder is: ``explicit``, else ``$env_var``, else ``../shared/data/<name>`` relative to
    ``cwd`` (the current directory) if it exists; ``None`` when none applies."""
    if explicit:
        return Path(explicit)
    env = os.environ.get(env_var)
    if env:
        return Path(env)
    guess = Path(cwd or os.getcwd()).resolve().parent / "shared" / "data" / name
    return guess if guess.is_dir() else None


def load_pads_folder(folder, pattern="*.txt", fs=100.0) -> list:
    """Every PADS recording in ``folder`` matching ``pattern``, sorted by name.

    Other files (``observation_NNN.json``, README.md) are ignored.
    """
    return [load_pads(p, fs) for p in dataset_files(folder, pattern)]


def load_csv(path, column=None, fs=None, name=None) -> Recording:
    """A plain CSV of uniformly sampled numbers, no time column (:func:`wake.io.read_csv`).

    ``column``: an index, a header name, a list of them or ``None`` for all;
    ``fs`` is required (a plain CSV does not say).
    """
    if fs is None:
        raise ValueError("load_csv needs the sampling rate: pass fs=<Hz>")
    return read_csv(path, fs=fs, time_column=None, columns=column, name=name)


def default_pads_dir(explicit=None, cwd=None):
    """Where the PADS folder is: ``explicit``, else ``$WAKE_PADS_DIR``, else
    ``../shared/data/pads`` relative to ``cwd`` (the current directory) if it
    exists; ``None`` when none applies (:func:`default_data_dir`)."""
    return default_data_dir("pads", "WAKE_PADS_DIR", explicit, cwd)
