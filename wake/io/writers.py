"""Write what WAKE made of a recording: a CSV with a time column, channel names and units.

The header cells read ``name [unit]`` (``name`` alone when the unit is not
known), so :func:`wake.io.read_csv` reads the file back with its names,
units and time column.  Per channel, three columns: the measurement, the
voluntary motion (predicted for that sample from the samples before it) and
the tremor (measurement minus voluntary); with ``ahead=True`` three more: the
tremor at that sample predicted ``horizon`` samples before, the confidence
then and the gated command (:class:`~wake.WakeResult`'s ``tremor_ahead``,
``confidence`` and ``command``), and the voluntary motion at that sample
predicted ``horizon`` samples before (``voluntary_ahead``) when the filter
makes it (:func:`ahead_columns`).

Every value is written in the shortest form that reads back as the same
double (:func:`exact_cell`, Python's ``repr``: ``-17.31873`` for the input
``-17.31873``, ``0.98``, ``0.1``; not the 17 significant digits of
``%.17g``, ``-17.318729999999999``): the file holds the filter's outputs
exactly, not a rounding of them, in no more characters than that needs.
:func:`exact_lines` writes a table so; ``wake stream`` writes its lines with
it too.
"""

from __future__ import annotations

import numpy as np

from wake._files import atomic_write_text
from wake.target import voluntary_ahead_refusal

__all__ = ["TREMOR_COLUMNS", "ahead_columns", "exact_cell", "exact_lines", "result_columns", "write_result_csv",
           "write_tremor_csv"]


def exact_cell(value) -> str:
    """The shortest text that reads back as the same double (``repr``); ``nan`` for a missing value.

    Examples
    --------
    >>> from wake.io.writers import exact_cell
    >>> exact_cell(-17.31873), exact_cell(0.1 + 0.2), exact_cell(float("nan"))
    ('-17.31873', '0.30000000000000004', 'nan')
    """
    return repr(float(value))


def exact_lines(table) -> str:
    """The rows of ``table`` (2-D, or 1-D for one row), comma-separated, one line each, with :func:`exact_cell`.

    Built column by column from Python floats (``tolist``), which is as fast as ``numpy.savetxt``'s
    ``%.17g`` (bench/write_exact.py).

    Examples
    --------
    >>> import numpy as np
    >>> from wake.io.writers import exact_lines
    >>> exact_lines(np.array([[0.0, -17.31873], [0.01, 0.98]]))
    '0.0,-17.31873\\n0.01,0.98\\n'
    """
    table = np.asarray(table, dtype=float)
    table = table.reshape(1, -1) if table.ndim == 1 else table
    if table.shape[0] == 0:
        return ""
    cells = [list(map(repr, col)) for col in table.T.tolist()]
    return "\n".join(map(",".join, zip(*cells))) + "\n"


def _label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


#: The tremor-ahead columns of each channel (with ``ahead=True``): the result's attribute and the suffix.
AHEAD_COLUMNS = (("tremor_ahead", True), ("confidence", False), ("command", True))

#: The voluntary motion ahead (:attr:`wake.WakeResult.voluntary_ahead`), after them when the filter makes it.
VOLUNTARY_AHEAD_COLUMN = ("voluntary_ahead", True)


def ahead_columns(config) -> tuple:
    """The ahead columns of each channel of a filter with ``config`` (``(name, has_unit)`` pairs):
    :data:`AHEAD_COLUMNS`, then :data:`VOLUNTARY_AHEAD_COLUMN` unless
    :func:`wake.target.voluntary_ahead_refusal` refuses it (the C HPA at a horizon above 1).

    Examples
    --------
    >>> from wake import WakeConfig
    >>> [name for name, _ in ahead_columns(WakeConfig(backend="reference", horizon=5))]
    ['tremor_ahead', 'confidence', 'command', 'voluntary_ahead']
    """
    made = voluntary_ahead_refusal(config.horizon, config.backend, config.hpa_backend) is None
    return AHEAD_COLUMNS + ((VOLUNTARY_AHEAD_COLUMN,) if made else ())


def _ahead(ahead) -> tuple:
    return AHEAD_COLUMNS if ahead is True else tuple(ahead or ())


def result_columns(channels, units=(), ahead=False) -> list[str]:
    """Header cells: ``time [s]``, then per channel ``c``, ``c_voluntary``, ``c_tremor`` (with units), and
    with ``ahead`` ``c_tremor_ahead``, ``c_confidence`` (no unit), ``c_command`` (``ahead=True``), or the
    columns ``ahead`` names (:func:`ahead_columns`)."""
    cells = ["time [s]"]
    for i, c in enumerate(channels):
        unit = units[i] if i < len(units) else ""
        cells += [_label(c, unit), _label(f"{c}_voluntary", unit), _label(f"{c}_tremor", unit)]
        cells += [_label(f"{c}_{name}", unit if has_unit else "") for name, has_unit in _ahead(ahead)]
    return cells


def write_result_csv(path, recording, result, ahead=False) -> int:
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
    extra = [np.reshape(getattr(result, name), (n, -1)) for name, _ in _ahead(ahead)]
    for c in range(k):
        cols += [x[:, c], vol[:, c], trem[:, c]] + [e[:, c] for e in extra]
    header = ",".join(result_columns(recording.channels, recording.units, ahead))
    atomic_write_text(path, header + "\n" + exact_lines(np.column_stack(cols)))
    return n


#: Header cells of :func:`write_tremor_csv` after ``channel`` and ``unit``: the fields of a
#: ``wake.hpa.characterise.tremor_table`` row, with their units (``unit`` is the channel's).
TREMOR_COLUMNS = (("index", "index"), ("end_time", "end_time [s]"), ("samples", "samples"),
                  ("cutoff", "cutoff [Hz]"), ("frequency", "frequency [Hz]"), ("rms", "rms [unit]"),
                  ("peak_to_peak", "peak_to_peak [unit]"), ("band_power", "band_power [unit^2]"),
                  ("time_share", "time_share"), ("tsi", "tsi [Hz]"), ("reason", "reason"))


def squared_unit(unit: str) -> str:
    """The square of a unit, as text: the unit of ``band_power`` and of a power spectral density's numerator.

    A compound unit is bracketed, so that ``deg/s`` squared does not read as
    ``deg/s^2``; no unit gives ``""``.

    Examples
    --------
    >>> from wake.io.writers import squared_unit
    >>> squared_unit("deg/s"), squared_unit("g"), squared_unit("m/s^2"), squared_unit("")
    ('(deg/s)^2', 'g^2', '(m/s^2)^2', '')
    """
    unit = (unit or "").strip()
    if not unit:
        return ""
    return f"{unit}^2" if unit.replace("_", "").isalpha() else f"({unit})^2"


def tremor_header(units) -> list:
    """The cells of :data:`TREMOR_COLUMNS` with ``unit`` written out: the channels' unit when they share one
    (``rms [deg/s]``, ``band_power [(deg/s)^2]``), else none (each row's ``unit`` column says it).

    Examples
    --------
    >>> tremor_header(["deg/s", "deg/s"])[5:8]
    ['rms [deg/s]', 'peak_to_peak [deg/s]', 'band_power [(deg/s)^2]']
    >>> tremor_header(["g", "deg/s"])[5:8]
    ['rms', 'peak_to_peak', 'band_power']
    """
    shared = set(units)
    unit = shared.pop() if len(shared) == 1 else ""
    if not unit:
        return [cell.replace(" [unit^2]", "").replace(" [unit]", "") for _, cell in TREMOR_COLUMNS]
    return [cell.replace("[unit^2]", f"[{squared_unit(unit)}]").replace("[unit]", f"[{unit}]")
            for _, cell in TREMOR_COLUMNS]


def write_tremor_csv(path, channels, units, tables) -> int:
    """Write the tremor characterisation of every HPA window, one row per window and channel; returns the rows.

    ``tables`` holds per channel the structured array of
    ``wake.hpa.characterise.tremor_table``.  Columns: ``channel``, ``unit``,
    then :data:`TREMOR_COLUMNS`; numbers in their shortest exact form
    (:func:`exact_cell`), NaN as ``nan``, written atomically.
    """
    if len(tables) != len(channels):
        raise ValueError(f"{len(tables)} tables for {len(channels)} channels")
    lines = [",".join(["channel", "unit"] + tremor_header([units[c] if c < len(units) else ""
                                                          for c in range(len(channels))]))]
    for c, (name, table) in enumerate(zip(channels, tables)):
        unit = units[c] if c < len(units) else ""
        for row in table:
            cells = [str(row[f]) if f in ("index", "samples", "reason") else exact_cell(row[f])
                     for f, _ in TREMOR_COLUMNS]
            lines.append(",".join([name, unit] + cells))
    atomic_write_text(path, "\n".join(lines) + "\n")
    return len(lines) - 1
