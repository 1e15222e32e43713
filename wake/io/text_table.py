"""Delimited text as a table of columns: delimiter, decimal mark, header row, and which columns are numbers.

Only the columns a caller asks for have to be numbers: a subject id or a
label beside the signals is kept as text and never parsed into the samples
(:meth:`TextTable.numbers` refuses a text column by name, with its line).

Decimal mark: ``"."``, ``","`` or ``"auto"``.  ``"auto"`` reads a comma as
the decimal mark when the cells are separated by semicolons or tabs and
every comma stands between two digits (``0,5;1,2``), the way spreadsheets
in many locales write CSV; otherwise a comma separates cells.
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["DECIMAL_MARKS", "TextTable", "check_decimal_mark", "read_text_table", "table_from_lines"]

#: Accepted values of ``decimal``.
DECIMAL_MARKS = ("auto", ".", ",")

_DECIMAL_COMMA = re.compile(r"\d,\d")
_STRAY_COMMA = re.compile(r"(?<!\d),|,(?!\d)")


def check_decimal_mark(decimal: str) -> str:
    """``decimal`` if it is one of :data:`DECIMAL_MARKS`, else ValueError naming them."""
    if decimal not in DECIMAL_MARKS:
        raise ValueError(f"decimal must be one of {', '.join(repr(d) for d in DECIMAL_MARKS)}, got {decimal!r}")
    return decimal


def _to_float(cell: str, comma: bool) -> float:
    """A cell as a float; an empty cell is a missing sample (NaN)."""
    if not cell:
        return np.nan
    return float(cell.replace(",", ".") if comma else cell)


def _is_number(cell: str, comma: bool = False) -> bool:
    try:
        _to_float(cell, comma)
        return True
    except ValueError:
        return False


@dataclass
class TextTable:
    """The cells of a delimited text file, by column.

    ``cells[j]`` holds column ``j`` as strings; ``lines[i]`` is the file line
    of row ``i``; ``header`` the first row's cells when it names the columns.
    """

    path: Path
    cells: list  #: per column, a tuple of strings
    lines: list  #: file line number of every data row
    header: list | None  #: cells of the header row, or None
    delimiter: str | None  #: None: runs of white space
    decimal_comma: bool  #: a comma is the decimal mark

    @property
    def width(self) -> int:
        return len(self.cells)

    @property
    def rows(self) -> int:
        return len(self.lines)

    def first_text_cell(self, j: int):
        """``(line, cell)`` of the first cell of column ``j`` that is not a number, or None."""
        for line, cell in zip(self.lines, self.cells[j]):
            if not _is_number(cell, self.decimal_comma):
                return line, cell
        return None

    def is_text(self, j: int) -> bool:
        """Column ``j`` holds no number at all (a label, a subject id)."""
        return not any(cell and _is_number(cell, self.decimal_comma) for cell in self.cells[j])

    def split(self, line: str) -> list:
        """The cells of one more line of the same file (the table's delimiter), stripped."""
        cells = line.split() if self.delimiter is None else next(csv.reader([line], delimiter=self.delimiter))
        return [c.strip() for c in cells]

    def number(self, cell: str) -> float:
        """One cell as a float with the table's decimal mark (empty: NaN); ValueError for text or inf."""
        v = _to_float(cell, self.decimal_comma)
        if np.isinf(v):
            raise ValueError(f"infinite value {cell!r} (leave the cell empty or write nan for a missing sample)")
        return v

    def numbers(self, j: int, name: str = "") -> np.ndarray:
        """Column ``j`` as floats (empty cells: NaN); a text cell or an infinite value is refused with its line."""
        try:
            out = np.array([_to_float(c, self.decimal_comma) for c in self.cells[j]], dtype=float)
        except ValueError:
            line, bad = self.first_text_cell(j)
            what = f"column {name!r}" if name else f"column {j}"
            raise ValueError(f"{self.path}, line {line}: {bad!r} is not a number ({what}; empty cells are read "
                             "as missing samples; only a first line may hold column names; leave a text column "
                             "out with --column)") from None
        inf = np.isinf(out)
        if inf.any():
            line = self.lines[int(np.argmax(inf))]
            raise ValueError(f"{self.path}, line {line}: infinite value (leave the cell empty or write nan for a "
                             "missing sample)")
        return out


def _lines(path: Path):
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            text = fh.read()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file (for MATLAB files use the .mat suffix or --format mat)") from None
    lines = [(i + 1, line) for i, line in enumerate(text.splitlines())
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise ValueError(f"{path}: the file holds no data")
    return lines


def _dialect(sample_lines, decimal: str):
    """``(delimiter, decimal_comma)`` of the file, from its first lines (module docstring)."""
    sample = "\n".join(sample_lines)
    check_decimal_mark(decimal)
    other = ";" if ";" in sample else ("\t" if "\t" in sample else None)
    if decimal == ",":
        return other, True
    if decimal == "auto" and other is not None and _DECIMAL_COMMA.search(sample) \
            and not _STRAY_COMMA.search(sample):
        return other, True
    if "," in sample:
        return ",", False
    return other, False


def _is_header(first, second, comma: bool) -> bool:
    """The first row names the columns: it has a non-number where the next row has a number.

    A text column (a subject id on every row) is not a header: its cells are
    text in both rows.  A file of one row is a header when any cell is text.
    """
    if second is None:
        return not all(_is_number(c, comma) for c in first)
    return any(not _is_number(a, comma) and _is_number(b, comma) for a, b in zip(first, second))


def read_text_table(path, decimal: str = "auto") -> TextTable:
    """Read a delimited text file into a :class:`TextTable` (lines starting with ``#`` are comments).

    Examples
    --------
    >>> import tempfile, os
    >>> from wake.io.text_table import read_text_table
    >>> path = os.path.join(tempfile.mkdtemp(), "rec.csv")
    >>> _ = open(path, "w").write("subject;gyro_x\\nS01;0,5\\nS01;1,25\\n")
    >>> table = read_text_table(path)
    >>> table.header, table.is_text(0), table.numbers(1).tolist()
    (['subject', 'gyro_x'], True, [0.5, 1.25])
    """
    path = Path(path)
    return table_from_lines(_lines(path), decimal, path)


def table_from_lines(lines, decimal: str = "auto", source="input") -> TextTable:
    """A :class:`TextTable` of ``(line number, text)`` pairs (no comment or blank lines): the rules of
    :func:`read_text_table` for lines that come from elsewhere (``wake stream`` reads its first lines so)."""
    path = source if isinstance(source, Path) else Path(str(source))
    delimiter, comma = _dialect([line for _, line in lines[:20]], decimal)
    rows = []
    for lineno, line in lines:
        cells = line.split() if delimiter is None else next(csv.reader([line], delimiter=delimiter))
        rows.append((lineno, [c.strip() for c in cells]))
    header = None
    if _is_header(rows[0][1], rows[1][1] if len(rows) > 1 else None, comma):
        header = rows[0][1]
        rows = rows[1:]
        if not rows:
            raise ValueError(f"{path}: a header but no data")
    width = len(rows[0][1])
    for lineno, row in rows:
        if len(row) != width:
            raise ValueError(f"{path}, line {lineno}: {len(row)} columns where the file has {width} "
                             "(a ragged row: fix or delete that line)")
    if header is not None and len(header) != width:
        raise ValueError(f"{path}: the header names {len(header)} columns, the data has {width}")
    cells = [tuple(row[j] for _, row in rows) for j in range(width)]
    return TextTable(path, cells, [lineno for lineno, _ in rows], header, delimiter, comma)
