"""Which column is time, and in which unit.

A column is time when its name says so (``t``, ``time``, ``timestamp``,
``ts``, ``elapsed``, ``time_s``, ``timestamp_ms``, ``time [ms]``,
``TimeUs``, ...) or, without a name, when it is shaped like a clock
(:func:`shaped_like_time`).

Its unit comes, in this order, from the unit cell (``time [ms]``), from a
unit word in the name (``_ms``, ``msec``, ``millis``, ``_us``, ``usec``,
``micros``, ``_ns``; ``_s``, ``sec`` for seconds) or, when neither says, from
the size of its steps (:func:`unit_from_steps`): a clock read as seconds
that would run below 10 Hz is read in the first of ms, us or ns that gives
a rate between 10 Hz and 100 kHz.  :class:`TimeUnit` says which unit was
taken and why, so the reader can tell the user.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["TimeUnit", "UNIT_SECONDS", "is_time_name", "shaped_like_time", "is_row_counter", "unit_from_name",
           "unit_from_steps"]

#: Seconds per unit, for every unit a time column may be in.
UNIT_SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}

_UNIT_WORDS = {
    "s": ("s", "sec", "secs", "second", "seconds"),
    "ms": ("ms", "msec", "msecs", "millis", "milli", "millisecond", "milliseconds"),
    "us": ("us", "µs", "usec", "usecs", "micros", "micro", "microsecond", "microseconds"),
    "ns": ("ns", "nsec", "nsecs", "nanos", "nano", "nanosecond", "nanoseconds"),
}
_WORD_UNIT = {word: unit for unit, words in _UNIT_WORDS.items() for word in words}
_TIME_WORDS = ("t", "time", "times", "timestamp", "timestamps", "ts", "elapsed", "clock")

#: Rates a time column is taken to stand for when its unit is judged from its steps, Hz.
PLAUSIBLE_RATES = (10.0, 1e5)


@dataclass(frozen=True)
class TimeUnit:
    """The unit of a time column and where it was read from."""

    unit: str = "s"  #: a key of :data:`UNIT_SECONDS`
    source: str = "default"  #: "unit cell", "name", "step size" or "default" (seconds, nothing said otherwise)

    @property
    def seconds(self) -> float:
        return UNIT_SECONDS[self.unit]

    def describe(self, name: str = "") -> str:
        """``"in ms (from its name)"``: what a user reads beside the column's name."""
        why = {"unit cell": "from its header", "name": "from its name", "step size": "from the size of its steps",
               "default": "nothing says otherwise"}[self.source]
        what = f"time column {name!r}" if name else "time column"
        return f"{what} in {self.unit} ({why})"


def _words(name: str) -> list:
    """``"timestampMs"`` -> ``["timestamp", "ms"]``; ``"time [ms]"`` -> ``["time", "ms"]``."""
    spaced = re.sub(r"(?<=[a-z])(?=[A-Z])", " ", name)
    return [w for w in re.split(r"[^0-9a-zµ]+", spaced.lower()) if w]


def unit_from_name(name: str, unit_cell: str = "") -> TimeUnit | None:
    """The unit a header says (unit cell first, then a unit word in the name), or None."""
    cell = unit_cell.strip().lower()
    if cell in _WORD_UNIT:
        return TimeUnit(_WORD_UNIT[cell], "unit cell")
    for word in _words(name)[1:] or _words(name):
        if word in _WORD_UNIT:
            return TimeUnit(_WORD_UNIT[word], "name")
    return None


def is_time_name(name: str, unit_cell: str = "") -> bool:
    """The header names a time column: a time word, or a time unit (``time``, ``ts_ms``, ``millis``, ``t [s]``)."""
    words = _words(name)
    if not words:
        return False
    if any(w in _TIME_WORDS for w in words):
        return True
    # "seconds", "ms", "millis": a column named by its unit alone
    return len(words) == 1 and words[0] in _WORD_UNIT and words[0] not in ("s", "us", "ns")


def unit_from_steps(time: np.ndarray) -> TimeUnit:
    """The unit of an unlabelled clock, from its median step (module docstring)."""
    steps = np.diff(np.asarray(time, dtype=float))
    steps = steps[np.isfinite(steps) & (steps > 0)]
    if steps.size == 0:
        return TimeUnit()
    step = float(np.median(steps))
    low, high = PLAUSIBLE_RATES
    if 1.0 / step >= low:
        return TimeUnit()
    for unit in ("ms", "us", "ns"):
        if low <= 1.0 / (step * UNIT_SECONDS[unit]) <= high:
            return TimeUnit(unit, "step size")
    return TimeUnit()


def is_row_counter(col: np.ndarray) -> bool:
    """0, 1, 2, ...: integers stepping by exactly 1 are an index, not a clock."""
    return col.size >= 2 and bool(np.all(np.diff(col) == 1)) and bool(np.all(col == np.round(col)))


def shaped_like_time(col: np.ndarray) -> bool:
    """Non-decreasing, advancing, 90 % of its steps within 50 % of the median step, and not a row counter."""
    if col.size < 3 or not np.isfinite(col).all():
        return False
    steps = np.diff(col)
    if (steps < 0).any() or not (steps > 0).any():
        return False
    if is_row_counter(col):
        return False
    median = np.median(steps[steps > 0])
    return bool(np.mean(np.abs(steps - median) <= 0.5 * median) >= 0.9)
