"""When the HPA runs, and on which samples: warm-up points, every ``L``, long gaps.

One schedule per channel, fed sample by sample (:meth:`HPASchedule.push`,
the streaming path) or a block at a time (:meth:`HPASchedule.block`, the
batch path); both give the same HPA points and the same windows, because the
block path asks the same three questions at each point (:meth:`point_after`,
:meth:`gap_ended`, :meth:`window_at`) that the sample path asks.

It mirrors the C HPA's schedule (``feed`` in csrc/wake_hpa.c) one to one:

=====================  =========================================
here                   ``wake_hpa_t``
=====================  =========================================
``count``              ``count``
``missing_run``        ``missing_run``
``long_gap``           ``gap_len`` (``ceil(L / 5)``)
``gap_end``            ``base`` (0 here is ``None``: no gap yet)
``next_point``         ``warmup_next`` with ``fill_len``
``gap_skipped``        ``gap_skipped``
=====================  =========================================

The rules (docs/studies/design.md, "Warm-up" and "Missing samples"): warm-up HPAs
at ``config.hpa_points()``, then one every ``L`` samples on the last ``L``;
a run of missing samples at least :data:`GAP_SHARE` of ``L`` long is a long
gap: no HPA inside it, and at its end the schedule starts again from there,
from its first point of :data:`~wake.hpa.run.CLEAN_ONLY_BELOW_S` or more.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wake.config import WakeConfig
from wake.hpa.run import clean_only_below
from wake.rtp.full_scale import _peak_rank, robust_peak

__all__ = ["GAP_SHARE", "HPASchedule", "ScheduleState", "prepare_window", "prepare_windows"]

#: A run of missing samples at least this share of the HPA window long is a long gap: the HPA schedule
#: starts again at its end, warm-up first, as after ``reset()``, and no window reaches back into it
#: (docs/studies/design.md, "Missing samples").  Shorter runs are interpolated over.
GAP_SHARE = 0.2

#: A sample beyond this many robust peaks of its window is an outlier for the HPA (interpolated over,
#: flagged): it would dominate the spectrum and the fit, and near 1e154 its square overflows.
OUTLIER_PEAKS = 1e6
#: ... and beyond this magnitude always (L x^2 stays finite for any window length WakeConfig accepts).
OUTLIER_ABS = 1e150


@dataclass
class ScheduleState:
    """Plain data of an :class:`HPASchedule` (part of :class:`wake.channel.ChannelState`)."""

    count: int
    next_point: int
    missing_run: int
    gap_end: int | None
    gap_skipped: int
    history: np.ndarray  #: the last ``L`` samples, oldest first


class HPASchedule:
    """The HPA points of one channel and the samples each one reads.

    Examples
    --------
    >>> from wake import WakeConfig
    >>> s = HPASchedule(WakeConfig())
    >>> due = [s.count for v in range(1000) if s.push(0.0) and s.take_window() is not None]
    >>> due                                 # warm-up at 1, 2, 3, 4 s, then every L = 500
    [100, 200, 300, 400, 500, 1000]
    """

    def __init__(self, config: WakeConfig):
        self.config = config
        self.window_samples = config.window_samples
        self.long_gap = gap_length(config)   # fixed with the config; push() reads it every sample
        self.history = np.zeros(self.window_samples)  # a ring: self.pos is the oldest sample
        self.pos = 0
        self.count = 0
        self.next_point = config.next_hpa(0)
        self.missing_run = 0        # missing samples in a row up to now
        self.gap_end = None         # count of the last sample of the latest long gap (the schedule runs from it)
        self.gap_skipped = 0        # HPA points skipped: inside a long gap

    # -- the rules ------------------------------------------------------------------
    def point_after(self, count: int) -> int:
        """The next HPA point after ``count`` samples: the schedule from the stream's start, or from the end
        of the latest long gap, there from its first point of ``CLEAN_ONLY_BELOW_S`` (2 s) or more: the weights
        in use were fitted before the gap, and a shorter fit does not beat them (docs/studies/design.md, "Missing
        samples")."""
        if self.gap_end is None:
            return self.config.next_hpa(count)
        return self.gap_end + self.config.next_hpa(max(count - self.gap_end, clean_only_below(self.config) - 1))

    def gap_ended(self, last_missing: int) -> None:
        """A long gap ended with sample number ``last_missing``: the schedule starts again from there, warm-up
        HPAs first, as after ``reset()``."""
        self.gap_end = last_missing
        self.next_point = self.point_after(last_missing)

    def window_at(self, recent) -> np.ndarray | None:
        """The samples the HPA at the current point reads, and the next point scheduled.

        ``recent`` ends with the current sample and holds at least ``min(count, L)`` samples.  Returns
        them from the latest long gap's end on, or None inside a long gap (the HPA is skipped, the weights
        kept).  The schedule runs from the gap's end (:meth:`point_after`), so at least its first point's
        ``2 * 2**J`` samples follow.
        """
        count = self.count
        self.next_point = self.point_after(count)
        if self.missing_run >= self.long_gap:
            self.gap_skipped += 1
            return None
        window = recent[recent.shape[0] - min(count, self.window_samples):]
        if self.gap_end is None:
            return window
        return window[max(0, window.shape[0] - (count - self.gap_end)):]

    # -- the sample path ------------------------------------------------------------
    def push(self, sample: float) -> bool:
        """Take one sample (NaN: missing); True when it completes an HPA point (then call :meth:`take_window`)."""
        L = self.window_samples
        self.history[self.pos] = sample
        self.pos = (self.pos + 1) % L
        self.count += 1
        if sample != sample:
            self.missing_run += 1
        else:
            if self.missing_run >= self.long_gap:
                self.gap_ended(self.count - 1)
            self.missing_run = 0
        return self.count == self.next_point

    def take_window(self) -> np.ndarray | None:
        """At an HPA point of the sample path: :meth:`window_at` on the samples kept."""
        return self.window_at(self.ordered_history())

    def ordered_history(self) -> np.ndarray:
        """The last L samples, oldest first (a copy)."""
        return np.concatenate((self.history[self.pos :], self.history[: self.pos]))

    # -- the block path ---------------------------------------------------------------
    def block(self, x):
        """The HPA points inside block ``x``, as :meth:`push` would find them sample by sample.

        Yields ``(stop, window)`` in order: after sample ``x[stop]`` arrives, the HPA runs on ``window``
        (None: inside a long gap, skipped) before that sample's RTP step.  ``count`` is that sample's
        number while the caller holds the point.  Once exhausted, the schedule stands after ``x``.
        """
        L = self.window_samples
        n = x.shape[0]
        seen = np.concatenate((self.ordered_history(), x))  # the last L samples before x, then x
        base = self.count
        # Long gaps: valid[j] is the index of a present sample, before[j] the run of missing samples before
        # it (the run carried from the last call before the first).
        valid = np.flatnonzero(~np.isnan(x))
        carried = self.missing_run
        if valid.size == n:   # no sample missing: only a run carried into x[0] can end a long gap
            ends = [0] if n and carried >= self.long_gap else []

            def run_at(k):
                return 0
        else:
            before = np.empty_like(valid)   # np.diff(valid, prepend=-1) - 1
            before[:1] = valid[:1]
            np.subtract(valid[1:], valid[:-1], out=before[1:])
            before[1:] -= 1
            if valid.size:
                before[0] += carried
            ends = list(valid[before >= self.long_gap])  # first sample after each long gap

            def run_at(k):
                """Missing samples in a row up to and including x[k]."""
                j = np.searchsorted(valid, k, side="right") - 1
                return int(k - valid[j]) if j >= 0 else int(k + 1 + carried)

        while True:
            stop = self.next_point - base - 1  # index in x of the sample completing the next HPA point
            if ends and ends[0] <= min(stop, n - 1):
                # a long gap ended before that point (push() reschedules when its first sample comes)
                self.gap_ended(base + int(ends.pop(0)))
                continue
            if stop >= n:
                break
            self.count = base + stop + 1
            self.missing_run = run_at(stop)
            yield stop, self.window_at(seen[: L + stop + 1])
        self.count = base + n
        self.missing_run = run_at(n - 1) if n else self.missing_run
        self.history = seen[-L:].copy()
        self.pos = 0

    # -- state ----------------------------------------------------------------------
    def state(self) -> ScheduleState:
        return ScheduleState(self.count, self.next_point, self.missing_run, self.gap_end, self.gap_skipped,
                             self.ordered_history())

    def load(self, state: ScheduleState) -> None:
        self.count, self.next_point, self.missing_run = state.count, state.next_point, state.missing_run
        self.gap_end, self.gap_skipped = state.gap_end, state.gap_skipped
        self.history = np.array(state.history, dtype=float)
        self.pos = 0


def gap_length(config: WakeConfig) -> int:
    """Missing samples in a row that make a long gap (at least one)."""
    return max(1, int(np.ceil(round(GAP_SHARE * config.window_samples, 9))))   # 0.2 * 500 is 100


def prepare_window(window, peak: float | None = None) -> np.ndarray:
    """What the HPA reads of ``window``: outliers (:data:`OUTLIER_PEAKS`, :data:`OUTLIER_ABS`) and gaps
    interpolated over (the one door every window goes through).  ``peak``: the window's
    :func:`~wake.rtp.full_scale.robust_peak`, when the caller has it (the full-scale policy reads it too)."""
    window = _drop_outliers(window, peak)
    if np.isnan(window).any():
        window = _fill_gaps(window)
    return window


def prepare_windows(windows) -> list:
    """``(prepare_window(w, peak), peak)`` of each window of a list (None for None), ``peak`` its robust peak:
    every window at once, whatever its length (one magnitude pass and one outlier test for all, each window's
    peak selected in its own stretch of it; a window with something to drop or fill goes through
    :func:`prepare_window`, a clean one is returned as it is, as there).  A list with a non-finite sample goes
    window by window."""
    where = [i for i, window in enumerate(windows) if window is not None]
    out = [None] * len(windows)
    if not where:
        return out
    lengths = [windows[i].shape[0] for i in where]
    if len(where) == 1 or min(lengths) == 0:   # one window: its own calls cost less
        for i in where:
            peak = robust_peak(windows[i])
            out[i] = (prepare_window(windows[i], peak), peak)
        return out
    flat = np.concatenate([windows[i] for i in where])
    size = np.abs(flat)
    if not np.isfinite(size).all():
        for i in where:
            peak = robust_peak(windows[i])
            out[i] = (prepare_window(windows[i], peak), peak)
        return out
    starts = np.cumsum([0] + lengths)
    peaks, i = [], 0
    while i < len(lengths):   # robust_peak of each: the same rank, selected in its own stretch (a run of windows
        n, j = lengths[i], i  # of one length side by side: one partition along their rows)
        while j < len(lengths) and lengths[j] == n:
            j += 1
        rows = size[starts[i]:starts[j]].reshape(j - i, n).copy()
        k = _peak_rank(n)
        rows.partition(k, axis=1)
        peaks += rows[:, k].tolist()
        i = j
    limits = np.repeat([_outlier_limit(peak) for peak in peaks], lengths)
    wild = np.logical_or.reduceat(size > limits, starts[:-1])
    for i, peak, outlier in zip(where, peaks, wild.tolist()):
        out[i] = (prepare_window(windows[i], peak) if outlier else windows[i], peak)
    return out


def _outlier_limit(peak: float) -> float:
    """Magnitudes above this are outliers in a window of robust peak ``peak`` (:data:`OUTLIER_PEAKS`,
    :data:`OUTLIER_ABS`)."""
    return min(OUTLIER_ABS, OUTLIER_PEAKS * peak) if peak > 0 else OUTLIER_ABS


def _drop_outliers(window, peak=None):
    """``window`` with samples far beyond its robust peak as NaN (gaps, interpolated for the HPA)."""
    peak = robust_peak(window) if peak is None else peak
    limit = _outlier_limit(peak)
    with np.errstate(invalid="ignore"):
        wild = np.abs(window) > limit
    if not wild.any():
        return window
    out = np.array(window, dtype=float)
    out[wild] = np.nan
    return out


def _fill_gaps(window):
    """Linear interpolation over NaN for the HPA's spectrum (edges held)."""
    good = ~np.isnan(window)
    if not good.any():
        return np.zeros_like(window)
    idx = np.arange(window.shape[0])
    return np.interp(idx, idx[good], window[good])
