"""A recording on a uniform time grid, and how it got there from a time column.

WAKE and the baselines assume one sample every ``1/fs`` seconds.  Recorders
rarely deliver that: the PADS smartwatch files step 9.8, 10.2, 25 ms, ...
A file's time column is therefore analysed (:func:`analyse_time`) and, when
its steps are uneven or the rate asked for is not the file's, every channel
is interpolated linearly onto ``t0 + i/fs`` (:func:`resample_uniform`).
What was done is kept in :class:`Timing` so that tools can say so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["COMMON_RATES", "RATE_TOLERANCE", "Recording", "Timing", "analyse_time", "check_rate", "nominal_rate",
           "resample_uniform", "REGULAR_TOLERANCE"]

#: A time column whose every step is within this fraction of the median step
#: (and whose rate is the one asked for) is used as it is, without resampling.
REGULAR_TOLERANCE = 0.01


@dataclass(frozen=True)
class Timing:
    """What the time column said, and what was done with it."""

    source: str  #: "time column", "--fs" (no time column) or "stream"
    median_step: float = float("nan")  #: s, of the raw time column
    jitter: float = float("nan")  #: s, standard deviation of the raw steps
    max_step: float = float("nan")  #: s, the longest raw step (a gap shows here)
    irregular_steps: int = 0  #: raw steps off the median by more than 50 %
    resampled: bool = False  #: interpolated onto a uniform grid
    raw_samples: int = 0  #: rows before resampling
    unit_note: str = ""  #: which unit the time column was read in, and why ("time column 't' in ms (from its name)")

    def describe(self, fs: float) -> str:
        """One line for a human: the rate, and the jitter when there was a time column."""
        if self.source != "time column":
            return f"{fs:g} Hz from {self.source}"
        what = (f"resampled {self.raw_samples} timestamped rows onto a uniform {fs:g} Hz grid"
                if self.resampled else f"time column regular at {fs:g} Hz, used as is")
        unit = f"; {self.unit_note}" if self.unit_note else ""
        return (f"{what} (steps: median {1e3 * self.median_step:.3f} ms, jitter {1e3 * self.jitter:.3f} ms "
                f"std, longest {1e3 * self.max_step:.3f} ms, {self.irregular_steps} off by over 50 %{unit})")


@dataclass
class Recording:
    """One recording on a uniform time grid.

    ``samples[i]`` was taken at ``t0 + i / fs`` seconds.
    """

    name: str
    fs: float  #: sampling rate of ``samples``, Hz
    channels: tuple  #: one name per column of ``samples``
    samples: np.ndarray  #: shape (n, len(channels)), uniformly sampled
    source: str = ""  #: file it was read from
    units: tuple = ()  #: one unit per channel ("" when unknown), or () when none is known
    t0: float = 0.0  #: time of the first sample, s
    timing: Timing = field(default_factory=lambda: Timing("--fs"))
    notes: tuple = ()  #: what the reader inferred beyond the timing ("decimal comma", "text column id left out")

    @property
    def duration(self) -> float:
        return self.samples.shape[0] / self.fs

    @property
    def irregular_steps(self) -> int:
        """Raw time steps off the nominal ``1/fs`` by more than 50 % (0 without a time column)."""
        return self.timing.irregular_steps

    @property
    def time(self) -> np.ndarray:
        """The time of every sample, s."""
        return self.t0 + np.arange(self.samples.shape[0]) / self.fs

    def unit(self, index: int) -> str:
        return self.units[index] if index < len(self.units) else ""

    def channel(self, name) -> np.ndarray:
        """One channel by name (or by index)."""
        if isinstance(name, (int, np.integer)):
            return self.samples[:, int(name)]
        try:
            return self.samples[:, self.channels.index(name)]
        except ValueError:
            raise ValueError(f"{self.name} has no channel {name!r}; channels: {', '.join(self.channels)}") from None


def _check_time(time: np.ndarray) -> np.ndarray:
    if time.ndim != 1 or time.size < 2:
        raise ValueError("need at least two timestamps")
    if not np.isfinite(time).all():
        i = int(np.argmax(~np.isfinite(time)))
        raise ValueError(f"the time column holds a non-finite value at row {i + 1}")
    steps = np.diff(time)
    if (steps < 0).any():
        i = int(np.argmax(steps < 0))
        raise ValueError(f"the time column goes backwards at row {i + 2} ({float(time[i]):g} -> "
                         f"{float(time[i + 1]):g} s)")
    if not (steps > 0).any():
        raise ValueError("the time column never advances: every timestamp is the same")
    return steps


#: Rates sensors are commonly run at; a time column within 1 % of one is taken to stand for it.
COMMON_RATES = (10, 20, 25, 30, 32, 50, 60, 64, 100, 120, 125, 128, 200, 250, 256, 400, 500, 512, 1000, 1024,
                2000, 2048, 4000, 4096, 8000)


def nominal_rate(time) -> float:
    """The sampling rate a time column stands for: 1 / the median positive step.

    A jittered clock gives 99.35 for a 100 Hz sensor (the PADS files), so a
    rate within 1 % of a common sensor rate (:data:`COMMON_RATES`) is taken
    to be that rate, else one within 1 % of a whole number of Hz is rounded
    to it.  The samples are interpolated at their true times either way
    (:func:`resample_uniform`): the choice sets the grid, not the clock.
    """
    steps = _check_time(np.asarray(time, dtype=float))
    rate = 1.0 / float(np.median(steps[steps > 0]))
    for common in COMMON_RATES:
        if abs(rate - common) <= 0.01 * common:
            return float(common)
    whole = round(rate)
    return float(whole) if whole > 0 and abs(rate - whole) <= 0.01 * whole else rate


#: A rate that differs from a time column's own rate by more than this fraction of it contradicts the column.
RATE_TOLERANCE = 0.05


def check_rate(fs, time, *, resample: bool = False, given: str = "fs (--fs)", column: str = "the time column",
               can_resample: bool = True):
    """The rate of the output grid: the time column's own (:func:`nominal_rate`) when ``fs`` is None, else
    ``fs``, refused when it contradicts the column by over :data:`RATE_TOLERANCE` unless ``resample``.

    A rate given beside a time column that runs at another one is most often a slip (the wrong file, a
    unit misread), and resampling a 100 Hz file onto 1 kHz makes ten rows of every one without a word; so
    it takes ``resample=True`` (``--resample``) to ask for that.  ``can_resample=False`` (a live stream,
    which is not resampled) leaves that way out of the message.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.io.recording import check_rate
    >>> check_rate(None, np.arange(50) / 100.0), check_rate(100.0, np.arange(50) / 99.4)
    (100.0, 100.0)
    >>> check_rate(1000.0, np.arange(50) / 100.0)
    Traceback (most recent call last):
    ...
    ValueError: fs (--fs) 1000 Hz contradicts the time column, which runs at 100 Hz: leave the rate out to use 100 Hz, or ask for a 1000 Hz grid with resample=True (--resample); to ignore the time column, time_column=None (--time-column none)
    """
    own = nominal_rate(time)
    if fs is None:
        return own
    if not (np.isfinite(fs) and fs > 0):
        raise ValueError(f"{given} must be > 0 Hz, got {fs}")
    fs = float(fs)
    if not resample and abs(fs - own) > RATE_TOLERANCE * own:
        if not can_resample:
            raise ValueError(f"{given} {fs:g} Hz contradicts {column}, which runs at {own:g} Hz: leave the rate "
                             f"out to use {own:g} Hz; to ignore the time column, --time-column none")
        raise ValueError(f"{given} {fs:g} Hz contradicts {column}, which runs at {own:g} Hz: leave the rate out "
                         f"to use {own:g} Hz, or ask for a {fs:g} Hz grid with resample=True (--resample); to "
                         "ignore the time column, time_column=None (--time-column none)")
    return fs


def analyse_time(time, fs: float) -> Timing:
    """Steps, jitter and gaps of a time column, and whether it must be resampled onto ``fs``."""
    time = np.asarray(time, dtype=float)
    steps = _check_time(time)
    median = float(np.median(steps[steps > 0]))
    off = np.abs(steps - 1.0 / fs) > REGULAR_TOLERANCE / fs
    return Timing(
        source="time column", median_step=median, jitter=float(np.std(steps)), max_step=float(steps.max()),
        irregular_steps=int(np.count_nonzero(np.abs(steps * fs - 1.0) > 0.5)), resampled=bool(off.any()),
        raw_samples=int(time.size))


def resample_uniform(time, values, fs):
    """Linear interpolation of ``values`` (n, channels) at ``time`` onto ``t0 + i/fs``.

    Repeated timestamps are merged (mean of their values): a zero step would
    make the interpolation ambiguous.  NaN values (missing samples) stay
    missing: a grid point next to one is NaN.  Returns the uniform samples
    and the number of raw steps off ``1/fs`` by over 50 %.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.io import resample_uniform
    >>> y, off = resample_uniform([0.0, 0.012, 0.019, 0.031], [[0.0], [1.2], [1.9], [3.1]], 100.0)
    >>> np.round(y[:, 0], 6).tolist(), off
    ([0.0, 1.0, 2.0, 3.0], 0)
    """
    time = np.asarray(time, dtype=float)
    values = np.asarray(values, dtype=float).reshape(time.shape[0], -1)
    steps = _check_time(time)
    irregular = int(np.count_nonzero(np.abs(steps * fs - 1.0) > 0.5))
    uniq, inverse, counts = np.unique(time, return_inverse=True, return_counts=True)
    merged = np.zeros((uniq.size, values.shape[1]))
    np.add.at(merged, inverse, values)
    merged /= counts[:, None]
    n = int(np.floor((uniq[-1] - uniq[0]) * fs + 1e-9)) + 1
    grid = uniq[0] + np.arange(n) / fs
    out = np.column_stack([np.interp(grid, uniq, merged[:, c]) for c in range(values.shape[1])])
    return out, irregular
