"""TSDF, the Time Series Data Format of the ParaDigMa toolbox, read with ``tsdf`` (``pip install "wake-tremor[tsdf]"``).

A TSDF recording is a metadata file (``*_meta.json``) naming binary files of
rows: here the one with the time channel, the ones with the signals and,
when present, a quality flag.  The recording is read from the metadata file,
from any of its binary files, or from a folder that holds one metadata file.

- Time: a channel named ``time`` whose unit says how to read it:
  ``time_delta_ms`` (the step from the previous row, summed), or
  ``time_relative_ms`` / ``time_absolute_unix_ms`` (and ``_s``, ``_us``,
  ``_ns``).  Time starts at 0; the file's ``start_iso8601`` is in ``notes``.
- Signals: every other numeric channel, times its ``scale_factors`` (int16
  counts to m/s^2 or deg/s), in the units the metadata names.
- Quality: a channel named ``quality`` (or ending in ``_quality``, ``_flag``):
  a row whose flag is 0 is a missing sample, NaN in every channel, so the
  filter predicts through it (``docs/guide/formats.md``).

Examples
--------
>>> from wake.io import read_recording
>>> rec = read_recording("tsdf_imu/imu_meta.json")     # doctest: +SKIP
>>> rec.fs, rec.channels[:3], rec.units[:3]            # doctest: +SKIP
(100.0, ('acceleration_x', 'acceleration_y', 'acceleration_z'), ('m/s^2', 'm/s^2', 'm/s^2'))
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from wake.io.formats._base import Table, normalise_unit, require

__all__ = ["read_tsdf", "is_tsdf_meta", "tsdf_meta_for"]

_TIME_UNIT = re.compile(r"^time_(delta|relative|absolute_unix|absolute)?_?(s|ms|us|ns)$")
_SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}


def is_tsdf_meta(path: Path) -> bool:
    """A JSON file with TSDF's keys (``metadata_version`` and a ``file_name`` or nested ``sensors``)."""
    try:
        with open(path, encoding="utf-8") as f:
            head = json.load(f)
    except (OSError, ValueError):
        return False
    return isinstance(head, dict) and "metadata_version" in head and ("file_name" in head or "sensors" in head)


def tsdf_meta_for(binary: Path):
    """The metadata file beside ``binary`` that names it, or None."""
    for meta in sorted(binary.parent.glob("*meta.json")):
        try:
            if binary.name in meta.read_text(encoding="utf-8") and is_tsdf_meta(meta):
                return meta
        except OSError:
            continue
    return None


def _is_quality(name: str) -> bool:
    name = name.lower()
    return name == "quality" or name.endswith(("_quality", "_flag"))


def read_tsdf(path: Path) -> Table:
    """A TSDF recording from its metadata file (module docstring)."""
    tsdf = require("tsdf", "tsdf", "a TSDF recording")
    try:
        metas = tsdf.load_metadata_from_path(path)
    except Exception as exc:  # the library raises its own, unexported, error classes
        raise ValueError(f"{path}: not a readable TSDF metadata file (tsdf: {exc})") from None
    time = quality = None
    names, units, cols, notes = [], [], [], []
    rows = None
    for meta in metas.values():
        try:
            arr = np.asarray(tsdf.load_ndarray_from_binary(meta))
        except Exception as exc:
            raise ValueError(f"{path}: cannot read {meta.file_name} (tsdf: {exc})") from None
        arr = arr.reshape(arr.shape[0], -1)
        if rows is not None and arr.shape[0] != rows:
            raise ValueError(f"{path}: {meta.file_name} has {arr.shape[0]} rows where the others have {rows}")
        rows = arr.shape[0]
        scales = list(getattr(meta, "scale_factors", None) or [1.0] * arr.shape[1])
        if len(scales) == 1:
            scales = scales * arr.shape[1]
        for j, (name, unit) in enumerate(zip(meta.channels, meta.units)):
            col = arr[:, j].astype(float)
            m = _TIME_UNIT.match(str(unit).lower())
            if name.lower() == "time" and m:
                col = col * float(scales[j]) * _SECONDS[m.group(2)]
                time = np.cumsum(col) if m.group(1) == "delta" else col
            elif _is_quality(name):
                quality = (name, arr[:, j])
            else:
                names.append(name)
                units.append(normalise_unit(unit))
                cols.append(col * float(scales[j]))
    if time is None:
        raise ValueError(f"{path}: no time channel (a channel 'time' in time_delta_ms, time_relative_ms or "
                         "time_absolute_unix_ms, ...)")
    if not cols:
        raise ValueError(f"{path}: no signal channel beside time and quality")
    values = np.column_stack(cols)
    if quality is not None:
        bad = quality[1] == 0
        values[bad] = np.nan
        notes.append(f"{int(bad.sum())} of {rows} rows flagged 0 by {quality[0]!r}: read as missing samples (NaN)")
    first = next(iter(metas.values()))
    start = getattr(first, "start_iso8601", "")
    if start:
        notes.insert(0, f"TSDF, starts {start}")
    stem = path.name[:-len("_meta.json")] if path.name.endswith("_meta.json") else path.stem
    return Table(stem, names, units, values, time=time - time[0], notes=tuple(notes),
                 meta={"start": start, "quality_missing": int(np.sum(quality[1] == 0)) if quality else 0})
