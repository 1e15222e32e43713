"""Axivity CWA, ActiGraph GT3X and GENEActiv BIN, read with ``actfast`` (``pip install "wake-tremor[wearables]"``).

``actfast`` (a compiled reader of the three formats, no Java) returns each
file's sensor streams with their timestamps.  The stream with the
accelerometer is the recording: acceleration in g becomes ``acc_x``,
``acc_y``, ``acc_z``, a gyroscope in deg/s ``gyro_x`` .. ``gyro_z`` and a
magnetometer ``mag_x`` .. (the names of PADS recordings); any other sensor of
that stream (light, temperature, a button) keeps its own name.  The time is
the device's timestamps, from the first sample; the wall-clock start and the
device are in ``notes``.

Examples
--------
>>> from wake.io import read_recording
>>> rec = read_recording("test_data.CWA")            # doctest: +SKIP
>>> rec.fs, rec.channels, rec.units                   # doctest: +SKIP
(100.0, ('acc_x', 'acc_y', 'acc_z', 'gyro_x', 'gyro_y', 'gyro_z'), ('g', 'g', 'g', 'deg/s', 'deg/s', 'deg/s'))
"""

from __future__ import annotations

from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from wake.io.formats._base import Table, require

__all__ = ["read_wearable", "FORMAT_NAMES"]

#: The formats of this module, as ``read_recording(format=...)`` names them, and how a user calls them.
FORMAT_NAMES = {"cwa": "an Axivity CWA file", "gt3x": "an ActiGraph GT3X file", "geneactiv": "a GENEActiv BIN file"}
#: actfast's sensor names -> (wake's channel prefix, unit).
_SENSORS = {"acceleration": ("acc", "g"), "gyroscope": ("gyro", "deg/s"), "magnetometer": ("mag", "uT")}
_AXES = "xyz"


def read_wearable(path: Path, fmt: str) -> Table:
    """The accelerometer stream of a CWA / GT3X / GENEActiv BIN file (module docstring)."""
    actfast = require("actfast", "wearables", FORMAT_NAMES[fmt])
    try:
        data = actfast.read(str(path))
    except (ValueError, OSError, RuntimeError) as exc:
        raise ValueError(f"{path}: not a readable {FORMAT_NAMES[fmt].split(' ', 1)[1]} (actfast: {exc})") from None
    streams = [s for s in data.get("timeseries", {}).values() if "acceleration" in s and "datetime" in s]
    if not streams:
        raise ValueError(f"{path}: the file holds no accelerometer samples (actfast read {data.get('format')!r} "
                         f"with streams {', '.join(data.get('timeseries', {})) or 'none'})")
    stream = max(streams, key=lambda s: len(s["datetime"]))
    stamps = np.asarray(stream["datetime"], dtype=np.int64)
    n = stamps.size
    if n < 2:
        raise ValueError(f"{path}: need at least two samples, the file holds {n}")
    names, units, cols = [], [], []
    for key, arr in stream.items():
        arr = np.asarray(arr)
        if key == "datetime" or arr.shape[:1] != (n,) or arr.dtype.kind not in "iufb":
            continue
        prefix, unit = _SENSORS.get(key, (key, ""))
        arr = arr.astype(float).reshape(n, -1)
        if arr.shape[1] == 1:
            names.append(prefix)
            units.append(unit)
        else:
            names.extend(f"{prefix}_{_AXES[i]}" if arr.shape[1] <= 3 else f"{prefix}_{i}" for i in range(arr.shape[1]))
            units.extend([unit] * arr.shape[1])
        cols.append(arr)
    start = datetime.fromtimestamp(stamps[0] / 1e9, tz=timezone.utc).replace(tzinfo=None).isoformat(timespec="seconds")
    meta = data.get("metadata", {})
    device = meta.get("device", {})
    what = " ".join(str(v) for v in (data.get("format", ""), device.get("hardware_type", "")) if v)
    notes = (f"{what} read with actfast, starts {start} (device clock)",)
    return Table(path.stem, names, units, np.column_stack(cols), time=(stamps - stamps[0]) * 1e-9, notes=notes,
                 meta={"format": data.get("format", fmt), "start": start, "metadata": meta})
