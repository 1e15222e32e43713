"""Write what WAKE made of a recording: a CSV with a time column, channel names and units.

The header cells read ``name [unit]`` (``name`` alone when the unit is not
known), so :func:`wake.io.read_csv` reads the file back with its names,
units and time column.  Per channel, three columns: the measurement, the
voluntary motion (predicted for that sample from the samples before it) and
the tremor (measurement minus voluntary).
"""

from __future__ import annotations

import io

import numpy as np

from wake._files import atomic_write_text

__all__ = ["result_columns", "write_result_csv"]


def _label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


def result_columns(channels, units=()) -> list[str]:
    """Header cells: ``time [s]``, then per channel ``c``, ``c_voluntary``, ``c_tremor`` (with units)."""
    cells = ["time [s]"]
    for i, c in enumerate(channels):
        unit = units[i] if i < len(units) else ""
        cells += [_label(c, unit), _label(f"{c}_voluntary", unit), _label(f"{c}_tremor", unit)]
    return cells


def write_result_csv(path, recording, result) -> int:
    """Write ``recording`` and the :class:`~wake.filter.WakeResult` of it; returns the rows written.

    Written atomically: a crash leaves the old file or none, never half of one.
    """
    x = recording.samples.reshape(recording.samples.shape[0], -1)
    n, k = x.shape
    vol = np.reshape(result.voluntary, (n, -1))
    trem = np.reshape(result.tremor, (n, -1))
    if vol.shape != (n, k):
        raise ValueError(f"the result has shape {vol.shape}, the recording {x.shape}")
    cols = [recording.time]
    for c in range(k):
        cols += [x[:, c], vol[:, c], trem[:, c]]
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack(cols), delimiter=",", fmt="%.9g",
               header=",".join(result_columns(recording.channels, recording.units)), comments="")
    atomic_write_text(path, buf.getvalue())
    return n
