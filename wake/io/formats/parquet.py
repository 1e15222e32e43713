"""Apache Parquet tables, read with ``pyarrow`` (``pip install "wake-tremor[parquet]"``).

A Parquet file is read as a delimited text file with a header would be:
its column names are the header (``acc_x [g]`` is channel ``acc_x`` in
``g``), the time column is found by the same rules
(:mod:`wake.io.time_column`: ``time``, ``timestamp_ms``, ...), text columns
(a subject id) are left out, and a null is a missing sample (NaN).  A column
of Arrow timestamps is a time column in seconds.

Examples
--------
>>> import os, tempfile
>>> import pyarrow as pa, pyarrow.parquet as pq          # doctest: +SKIP
>>> path = os.path.join(tempfile.mkdtemp(), "rec.parquet")
>>> pq.write_table(pa.table({"time [s]": [0.0, 0.01, 0.02], "gyro_x [rad/s]": [0.1, 0.2, 0.3]}), path)  # doctest: +SKIP
>>> from wake.io import read_recording
>>> rec = read_recording(path)                            # doctest: +SKIP
>>> rec.fs, rec.channels, rec.units                        # doctest: +SKIP
(100.0, ('gyro_x',), ('rad/s',))
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wake.io.formats._base import Table, require

__all__ = ["read_parquet"]


def read_parquet(path: Path) -> Table:
    """Every column of a Parquet file, numeric ones as floats (module docstring)."""
    require("pyarrow", "parquet", "a Parquet file")
    import pyarrow as pa
    import pyarrow.parquet as pq

    from wake.io.readers import split_unit

    try:
        table = pq.read_table(path)
    except (pa.ArrowException, OSError) as exc:
        raise ValueError(f"{path}: not a readable Parquet file (pyarrow: {exc})") from None
    if table.num_rows < 2 or table.num_columns < 1:
        raise ValueError(f"{path}: need at least two rows and one column, the file has {table.num_rows} rows and "
                         f"{table.num_columns} columns")
    names, units, cols, text = [], [], [], []
    for j, (field, column) in enumerate(zip(table.schema, table.columns)):
        name, unit = split_unit(field.name)
        kind = field.type
        if pa.types.is_timestamp(kind) or pa.types.is_date64(kind):
            ns = column.cast(pa.timestamp("ns")).cast(pa.int64()).to_numpy(zero_copy_only=False)
            values, unit = ns.astype(float) * 1e-9, "s"
        elif pa.types.is_integer(kind) or pa.types.is_floating(kind) or pa.types.is_boolean(kind) \
                or pa.types.is_decimal(kind):
            values = column.cast(pa.float64()).fill_null(float("nan")).to_numpy(zero_copy_only=False)
        else:
            values = np.full(table.num_rows, np.nan)
            text.append(j)
        names.append(name)
        units.append(unit)
        cols.append(np.asarray(values, dtype=float))
    return Table(path.stem, names, units, np.column_stack(cols), time=None, text=tuple(text),
                 notes=("Parquet",))
