"""What every format reader of :mod:`wake.io.formats` hands back, and how it asks for its library."""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

import numpy as np

__all__ = ["MissingExtraError", "Table", "require", "normalise_unit"]

#: Spellings of a unit that files use, and the one :class:`~wake.io.recording.Recording` carries.
_UNIT_SPELLINGS = {"m/s/s": "m/s^2", "m/s2": "m/s^2", "m s-2": "m/s^2", "m/s²": "m/s^2", "dps": "deg/s",
                   "°/s": "deg/s", "degrees/s": "deg/s", "rad s-1": "rad/s"}


class MissingExtraError(ImportError, ValueError):
    """The library a format needs is not installed; the message names the extra that brings it.

    An :class:`ImportError` (what it is) and a :class:`ValueError` (so that the command line reports it in one
    line, as it does every input it cannot read).
    """


def require(module: str, extra: str, what: str):
    """Import ``module`` for reading ``what``, or raise :class:`MissingExtraError` naming ``extra``."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtraError(f"reading {what} needs the optional package {module!r}, which is not installed: "
                                f"pip install \"wake-tremor[{extra}]\" (or \"wake-tremor[all-formats]\" for every "
                                "format)", name=module) from None


def normalise_unit(unit: str) -> str:
    """``"m/s/s"`` -> ``"m/s^2"``, ``"dps"`` -> ``"deg/s"``; other units as written (stripped)."""
    unit = (unit or "").strip()
    return _UNIT_SPELLINGS.get(unit.lower(), unit)


@dataclass
class Table:
    """A recording as a format reader found it, before wake's rules (channels, time, grid) are applied.

    ``values[:, j]`` is channel ``names[j]`` in ``units[j]``.  ``time`` is the
    time of every row in seconds from the first, when the format has a clock
    of its own (a device's timestamps, a rate in its header); ``None`` for a
    table of named columns (Parquet), whose time column is found by the rules
    of delimited text (:mod:`wake.io.time_column`).  A missing sample is NaN.
    """

    name: str
    names: list
    units: list
    values: np.ndarray
    time: np.ndarray = None
    text: tuple = ()  #: indices of columns that are not numbers (left out unless asked for)
    notes: tuple = ()  #: what the reader inferred, for the user ("starts 2021-06-27T16:52:20Z")
    meta: dict = field(default_factory=dict)  #: what a writer of derivatives needs (the BIDS entities, ...)

    def column(self, j: int) -> np.ndarray:
        """Channel ``j`` as floats; a text column is refused by name."""
        if j in self.text:
            raise ValueError(f"{self.name}: column {self.names[j]!r} holds text, not numbers")
        return self.values[:, j]
