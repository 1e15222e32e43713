"""Storing for ``wake evaluate``: a result store that survives interruption.

Layout of ``OUT_DIR/store/``::

    parts/<time>-<hash>.parquet  one file per finished batch of tasks (one task or a few), written as it finishes
    results.parquet              every part merged, once a run completes (:meth:`ResultStore.compact`)

(``.csv`` instead of ``.parquet`` where pyarrow is not installed.)  A part is
written to a temporary name and renamed, so a run killed at any instant
leaves whole parts only; a rerun finds which tasks are done and computes the
rest.  A task recorded with an error counts as not done, so a rerun tries it
again; part names begin with the time they were written, so when a task is
in several parts the latest record is the one read.  Rows come back in the order of the tasks the caller asks for, never
in the order they finished, which is what makes a parallel run's report the
same as a serial one's.
"""

from __future__ import annotations

import csv
import hashlib
import os
import time
from pathlib import Path

__all__ = ["ResultStore", "parquet_available"]


def parquet_available():
    """True when pyarrow can be imported (else the store writes CSV)."""
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


class ResultStore:
    """Rows of one evaluation, one part file per finished batch of tasks, in ``folder``.

    Parameters
    ----------
    folder : str or Path
    columns : dict
        Column name -> type (``str``, ``int`` or ``float``), every row has them all.
    format : {"auto", "parquet", "csv"}
        ``"auto"``: Parquet when pyarrow is installed, CSV otherwise.

    Examples
    --------
    >>> import tempfile
    >>> from wake.eval.store import ResultStore
    >>> store = ResultStore(tempfile.mkdtemp(), {"task": str, "error": str, "nrmse": float}, format="csv")
    >>> store.add("a", [{"task": "a", "error": "", "nrmse": 0.25}])
    >>> sorted(store.done()), store.rows(["a"])[0]["nrmse"]
    (['a'], 0.25)
    """

    def __init__(self, folder, columns, format="auto"):
        if format not in ("auto", "parquet", "csv"):
            raise ValueError(f"store format must be auto, parquet or csv, got {format!r}")
        if format == "parquet" and not parquet_available():
            raise ValueError("a Parquet store needs pyarrow: pip install \"wake-tremor[cohort]\" "
                             "(or pip install \".[cohort]\" in a wake source tree)")
        self.folder = Path(folder)
        self.columns = dict(columns)
        self.format = ("parquet" if parquet_available() else "csv") if format == "auto" else format
        self.parts = self.folder / "parts"
        self.parts.mkdir(parents=True, exist_ok=True)

    # ------------------------------------------------------------------ files
    def _files(self):
        """Every file holding rows, merged first, then the parts (a part overrides the merged file)."""
        merged = [self.folder / f"results.{ext}" for ext in ("parquet", "csv")]
        return [f for f in merged if f.is_file()] + sorted(
            p for p in self.parts.iterdir() if p.suffix in (".parquet", ".csv") and not p.name.startswith("."))

    def _write(self, path, rows):
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        if self.format == "parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            types = {str: pa.string(), int: pa.int64(), float: pa.float64()}
            schema = pa.schema([(name, types[kind]) for name, kind in self.columns.items()])
            pq.write_table(pa.Table.from_pylist([self._typed(r) for r in rows], schema=schema), tmp)
        else:
            with open(tmp, "w", newline="") as fh:
                writer = csv.DictWriter(fh, fieldnames=list(self.columns))
                writer.writeheader()
                writer.writerows(self._typed(r) for r in rows)
        os.replace(tmp, path)

    def _typed(self, row):
        return {name: kind(row[name]) for name, kind in self.columns.items()}

    def _read(self, path, columns=None):
        """The rows of one file, one at a time (a batch of Python objects at most: memory stays flat)."""
        names = list(self.columns) if columns is None else columns
        if path.suffix == ".parquet":
            import pyarrow.parquet as pq

            for batch in pq.ParquetFile(path).iter_batches(batch_size=512, columns=names):
                yield from batch.to_pylist()
            return
        with open(path, newline="") as fh:
            for r in csv.DictReader(fh):
                yield {k: self.columns[k](r[k]) for k in names}

    # ------------------------------------------------------------------ API
    def add(self, task_key, rows):
        """Record the rows of one finished task (replacing any earlier record of it)."""
        self.add_many([(task_key, rows)])

    def add_many(self, pairs):
        """Record ``[(task key, rows), ...]``, finished tasks, in one part (replacing earlier records of them)."""
        pairs = list(pairs)
        if not pairs:
            return
        digest = hashlib.sha1("\n".join(key for key, _ in pairs).encode()).hexdigest()[:20]
        self._write(self.parts / f"{time.time_ns():020d}-{digest}.{self.format}",
                    [r for _, rows in pairs for r in rows])

    def _by_task(self, columns=None, convert=None):
        by_task = {}
        for path in self._files():
            grouped = {}
            for row in self._read(path, columns):
                grouped.setdefault(row["task"], []).append(row if convert is None else convert(row))
            by_task.update(grouped)
        return by_task

    def done(self):
        """Keys of the tasks recorded without an error."""
        return {k for k, rows in self._by_task(["task", "error"]).items() if not any(r["error"] for r in rows)}

    def rows(self, task_keys, convert=None):
        """The rows of ``task_keys``, in that order (tasks not in the store are left out).

        ``convert``: applied to each row as it is read (to keep a large store's rows small).
        """
        wanted = set(task_keys)
        by_task = self._by_task(convert=lambda r: None if r["task"] not in wanted else
                                (r if convert is None else convert(r)))
        return [r for k in task_keys for r in by_task.get(k, ())]

    def compact(self):
        """Merge every part into ``results.<format>`` and delete the parts (rows of every task kept)."""
        files = self._files()
        if not any(f.parent == self.parts for f in files):
            return
        target = self.folder / f"results.{self.format}"
        if self.format == "parquet" and all(f.suffix == ".parquet" for f in files):
            self._compact_parquet(files, target)     # in Arrow: no Python object per row
        else:
            self._write(target, [r for rows in self._by_task().values() for r in rows])
        for f in files:
            if f.parent == self.parts or f.suffix != f".{self.format}":
                f.unlink()

    def _compact_parquet(self, files, target, rows_per_group=8192):
        """Stream every part, and the merged file less the tasks the parts redo, into ``target``."""
        import pyarrow as pa
        import pyarrow.compute as pc
        import pyarrow.parquet as pq

        parts = [f for f in files if f.parent == self.parts]
        latest = {}                               # task -> the last part holding it (the record read)
        for f in parts:
            latest.update((t, f) for t in pq.read_table(f, columns=["task"]).column("task").unique().to_pylist())
        redone = pa.array(list(latest), pa.string())
        tmp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
        pending, count = [], 0
        with pq.ParquetWriter(tmp, pq.read_schema(parts[0])) as writer:
            for f in files:
                if f.parent == self.parts:
                    mine = pa.array([t for t, last in latest.items() if last == f], pa.string())
                    batches = (b.filter(pc.is_in(b["task"], value_set=mine)) for b in pq.read_table(f).to_batches())
                else:
                    batches = (b.filter(pc.invert(pc.is_in(b["task"], value_set=redone)))
                               for b in pq.ParquetFile(f).iter_batches(batch_size=rows_per_group))
                for batch in batches:
                    pending.append(batch)
                    count += batch.num_rows
                    if count >= rows_per_group:
                        writer.write_table(pa.Table.from_batches(pending))
                        pending, count = [], 0
            if pending:
                writer.write_table(pa.Table.from_batches(pending))
        os.replace(tmp, target)
