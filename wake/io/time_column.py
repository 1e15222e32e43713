"""Which column is time, and in which unit: the one rule every reader follows (:func:`find_time_column`).

With ``time_column="auto"`` the time column is, among the columns that hold
numbers (text columns, such as a subject id, are passed over):

1. **By name**: the first column named like time (:func:`is_time_name`).  Its
   name, split into words at anything but letters and digits and at a
   lower-to-upper case step (``timestampMs`` -> ``timestamp``, ``ms``), holds
   a time word (:data:`TIME_WORDS`: ``t``, ``time``, ``timestamp``, ``ts``,
   ``elapsed``, ``clock``, and ``Zeit``, ``Zeitstempel``, ``temps``,
   ``tiempo``, ``tempo``, ``tijd``, ``tid``, ``czas``, ``aika``, ``zaman`` ...)
   and nothing but time words, unit words (``s``, ``ms``, ``millis``, ``us``,
   ``ns``, ...; :data:`UNIT_WORDS`) and a few qualifiers (:data:`QUALIFIERS`:
   ``unix``, ``epoch``, ``utc``, ``system``, ``sensor``, ``logging``,
   ``since``, ``start`` ...).  So ``time``, ``Zeit [s]``, ``time_ms``,
   ``timestamp_ms``, ``TimeUs``, ``elapsed_time``, ``unix_time`` and
   ``loggingTime`` are time, and so is a name that is a unit alone (``ms``,
   ``millis``, ``seconds``; not ``s``, ``us`` or ``ns``, which are also
   signal names); ``end_time``, ``time_share`` or ``reaction_time`` are not.
   The column may stand anywhere (``subject,timestamp_ms,ax,...``).
2. **By shape**, when no column is named like time: the first numeric column,
   if it has no name (a file without a header row, or an empty header cell),
   is time when it is shaped like a clock (:func:`shaped_like_time`:
   non-decreasing, advancing, at least 90 % of its steps within 50 % of the
   median step, and not a row counter 0, 1, 2, ...).  A column with a name
   that is not a time name is a signal, however it steps.

Its unit comes, in this order, from the unit cell (``time [ms]``), from a
unit word in the name (``_ms``, ``msec``, ``millis``, ``_us``, ``usec``,
``micros``, ``_ns``; ``_s``, ``sec`` for seconds) or, when neither says, from
the size of its steps (:func:`unit_from_steps`): a clock read as seconds
that would run below 10 Hz is read in the first of ms, us or ns that gives
a rate between 10 Hz and 100 kHz.  :class:`TimeUnit` says which unit was
taken and why, so the reader can tell the user.

Examples
--------
>>> from wake.io.time_column import is_time_name
>>> [is_time_name(n) for n in ("Zeit", "timestamp_ms", "TimeUs", "end_time", "gyro_x")]
[True, True, True, False, False]
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["QUALIFIERS", "TIME_WORDS", "TimeUnit", "UNIT_SECONDS", "UNIT_WORDS", "find_time_column",
           "is_time_name", "shaped_like_time", "is_row_counter", "unit_from_name", "unit_from_steps"]

#: Seconds per unit, for every unit a time column may be in.
UNIT_SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}

#: The words that name a time unit, per unit.
UNIT_WORDS = {
    "s": ("s", "sec", "secs", "second", "seconds"),
    "ms": ("ms", "msec", "msecs", "millis", "milli", "millisecond", "milliseconds"),
    "us": ("us", "µs", "usec", "usecs", "micros", "micro", "microsecond", "microseconds"),
    "ns": ("ns", "nsec", "nsecs", "nanos", "nano", "nanosecond", "nanoseconds"),
}
_WORD_UNIT = {word: unit for unit, words in UNIT_WORDS.items() for word in words}
#: Words that name time, in English and in the languages sensor software is most often set up in.
TIME_WORDS = ("t", "time", "times", "timestamp", "timestamps", "ts", "elapsed", "clock",
              "zeit", "zeitstempel", "uhrzeit", "temps", "horodatage", "tiempo", "tempo", "tijd", "tijdstempel",
              "tid", "tidsstempel", "tidsstämpel", "czas", "čas", "aika", "aikaleima", "zaman", "время", "时间")
#: Words that may stand beside a time word in a time column's name (``unix_time``, ``loggingTime``).
QUALIFIERS = ("unix", "epoch", "utc", "gmt", "local", "system", "sys", "sensor", "device", "logging", "log",
              "sample", "event", "relative", "rel", "absolute", "abs", "since", "start", "real", "stamp")

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
    return [w for w in re.split(r"[\W_]+", spaced.lower()) if w]


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
    """The header names a time column (module docstring, rule 1): ``time``, ``Zeit``, ``ts_ms``, ``millis``.

    ``unit_cell`` is accepted for symmetry with :func:`unit_from_name`; the name alone decides.
    """
    words = _words(name)
    if not words:
        return False
    if any(w in TIME_WORDS for w in words):
        return all(w in TIME_WORDS or w in _WORD_UNIT or w in QUALIFIERS for w in words)
    # "seconds", "ms", "millis": a column named by its unit alone
    return len(words) == 1 and words[0] in _WORD_UNIT and words[0] not in ("s", "us", "ns")


def find_time_column(names, is_text, column, has_header: bool):
    """The time column by the rule of the module docstring: ``(index, reason)``, or ``(None, "")``.

    Parameters
    ----------
    names : sequence of str
        The columns' names (header cells without their units; ``""`` for a cell left empty).
    is_text : callable
        ``is_text(j)``: column ``j`` holds no number (it is never time).
    column : callable
        ``column(j)``: column ``j`` as floats (asked for only when its shape decides).
    has_header : bool
        The names come from a header row (without one, no column has a name).

    Returns
    -------
    index : int or None
    reason : str
        ``"by its name"`` or ``"by its shape"``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.io.time_column import find_time_column
    >>> names = ["subject", "timestamp_ms", "ax"]
    >>> find_time_column(names, lambda j: j == 0, lambda j: np.arange(5.0), True)
    (1, 'by its name')
    >>> find_time_column(["col0", "col1"], lambda j: False, lambda j: np.arange(5) * 0.01 * (j == 0), False)
    (0, 'by its shape')
    """
    if len(names) < 2:
        return None, ""
    numeric = [j for j in range(len(names)) if not is_text(j)]
    if has_header:
        for j in numeric:
            if is_time_name(names[j]):
                return j, "by its name"
    if numeric and len(numeric) > 1:
        j = numeric[0]
        if (not has_header or not names[j].strip()) and shaped_like_time(column(j)):
            return j, "by its shape"
    return None, ""


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
