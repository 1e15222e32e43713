"""One channel of a WAKE filter: when the HPA runs, what the RTP is fed.

A :class:`Channel` keeps the last ``L`` samples for the next HPA, runs it
(inline, or on the filter's worker thread) and installs its result between
two samples; every sample goes through its RTP object (:mod:`wake.rtp`).
It holds no number format: the fixed-point rules live in
:mod:`wake.rtp.fixed`.
"""

from __future__ import annotations

import copy
import warnings
from collections import deque
from dataclasses import replace
from functools import partial

import numpy as np

from wake.config import WakeConfig
from wake.hpa import HPAUpdate, default_weights, run_hpa
from wake.hpa.run import clean_only_below
from wake.hpa.c_port import run_hpa_c
from wake.hpa.prior import prior_weights
from wake.rtp import ReferenceRTP, load_fixed_point
from wake.rtp.full_scale import (
    GLITCH_SHARE,
    RAISE_AFTER,
    FullScalePolicy,
    first_persistent_overflow,
    power_of_two_at_least,
    robust_peak,
)

#: A sample beyond this many robust peaks of its window is an outlier for the HPA (interpolated over,
#: flagged): it would dominate the spectrum and the fit, and near 1e154 its square overflows.
OUTLIER_PEAKS = 1e6
#: ... and beyond this magnitude always (L x^2 stays finite for any window length WakeConfig accepts).
OUTLIER_ABS = 1e150

#: A run of missing samples at least this share of the HPA window long is a long gap: the HPA schedule
#: starts again at its end, warm-up first, as after ``reset()``, and no window reaches back into it
#: (docs/design.md, "Missing samples").  Shorter runs are interpolated over.
GAP_SHARE = 0.2

__all__ = ["Channel", "ClippingWarning"]


class ClippingWarning(RuntimeWarning):
    """More than 1 % of a window was clipped at the fixed-point full scale."""


class Channel:
    """HPA bookkeeping and RTP state of one channel."""

    def __init__(self, config: WakeConfig, taps: np.ndarray, start_weights: np.ndarray,
                 history_limit: int | None = None):
        self.config = config
        self.taps = taps
        self.start_weights = start_weights  # before the first HPA (start_weights_for)
        self.weights = start_weights
        self.measurement_noise = 1.0
        self.rtp = ReferenceRTP(taps, self.weights, self.measurement_noise,
                                self.process_noise(self.measurement_noise), config.initial_covariance)
        self.on_c = False
        self.full_scale = config.full_scale
        self.full_scale_policy = FullScalePolicy(headroom=config.headroom)
        self.full_scale_changes = 0   # rises and falls after the first choice
        self.clipped_before = 0       # the RTP's clip count at the last HPA
        self.over_run = 0             # samples in a row beyond the full scale, up to the last one
        self.over_peak = 0.0          # their largest magnitude
        # the newest history_limit HPA updates (None: all of them, for run())
        self.updates: deque[HPAUpdate] = deque(maxlen=history_limit)
        self.history = np.zeros(config.window_samples)
        self.pos = 0
        self.count = 0
        self.next_hpa = config.next_hpa(0)  # sample count of the next HPA (progressive, then every L)
        self.pending = None  # thread mode: (future, window) of an HPA still off the sample path
        # long gaps (GAP_SHARE): missing samples in a row up to now, and the count of the last sample of the
        # latest long gap (the HPA schedule runs from there)
        self.missing_run = 0
        self.gap_end = None
        self.gap_skipped = 0          # HPA points skipped: inside a long gap
        self.long_gap = self.gap_length()   # fixed with the config; update() reads it every sample
        if config.backend == "c" and config.full_scale is not None:
            self.switch_to_c(config.full_scale)

    def process_noise(self, measurement_noise: float) -> float:
        """Absolute ``q`` pushed to the RTP: ``process_noise_ratio * R`` of the current window."""
        return self.config.process_noise_ratio * measurement_noise

    # -- HPA ---------------------------------------------------------------
    def hpa_job(self, window):
        """The HPA call for ``window`` as a function of no arguments, with everything it reads bound
        (it may run off the sample path)."""
        window = _drop_outliers(window)
        if np.isnan(window).any():  # gaps are interpolated for the spectrum: the one door every window goes through
            window = _fill_gaps(window)
        if self.config.hpa_backend == "c":
            # the C HPA reads the int16 samples the RTP reads (its full scale once on the C path)
            hpa, extra = run_hpa_c, dict(full_scale=self.full_scale if self.on_c else None)
        else:
            hpa, extra = run_hpa, dict(start_weights=self.start_weights)
        return partial(hpa, window, self.config, taps=self.taps, previous_weights=self.weights.copy(),
                       index=self.count, **extra)

    def hpa(self, window):
        self.apply(self.hpa_job(window)(), window, first_sample=self.count)

    def apply(self, upd: HPAUpdate, window, first_sample: int):
        """Install an HPA result between two samples.

        ``first_sample`` is the 1-based number of the first sample whose RTP
        step uses it.  The history keeps a copy of ``upd`` that records it
        (``applied_at``) and what installing it took (``noise_clamped``):
        the HPA's own result is never edited.
        """
        self.weights = upd.weights
        self.measurement_noise = upd.measurement_noise
        notes = self.revise_full_scale(window) if self.config.backend == "c" else ()
        q = self.process_noise(self.measurement_noise)
        if self.on_c:
            if self.rtp.set_weights_clamped(self.weights, self.measurement_noise, q):
                notes += ("noise_clamped",)
            self.measurement_noise = self.rtp.measurement_noise
        else:
            self.rtp.set_weights(self.weights, self.measurement_noise, q)
        self.updates.append(replace(upd, applied_at=first_sample, flags=upd.flags + notes))

    def revise_full_scale(self, window) -> tuple:
        """Apply the full-scale policy (:mod:`wake.rtp.full_scale`) to the window the HPA saw.

        The C path starts at the first window that is not quiet (until then the
        float reference runs); later windows raise or lower the full scale. A
        full scale given in the configuration is kept as it is. Returns the
        notes for the HPA history.
        """
        notes = ()
        if self.on_c:
            clipped = self.rtp.clipped - self.clipped_before
            self.clipped_before = self.rtp.clipped
            if clipped > GLITCH_SHARE * len(window):
                notes += ("clipping",)
                warnings.warn(
                    f"{clipped} of the last {len(window)} samples were clipped at the fixed-point full scale "
                    f"±{self.full_scale:g}"
                    + (" (raise full_scale, or leave it None to let it follow the signal)"
                       if self.config.full_scale is not None else "; the full scale follows at this HPA"),
                    ClippingWarning, stacklevel=2)
        if self.config.full_scale is not None:
            return notes
        fs, reason = self.full_scale_policy.decide(self.full_scale if self.on_c else None, window)
        if reason is None:
            return notes
        if not self.on_c:
            self.switch_to_c(fs)
            self.clipped_before = self.rtp.clipped
        else:
            self.rescale(fs)
        return notes + (reason,)

    def switch_to_c(self, full_scale: float):
        fixed = load_fixed_point()
        self.rtp, _ = fixed.FixedPointRTP.from_reference(
            self.rtp, full_scale=full_scale, measurement_noise=self.measurement_noise,
            process_noise=self.process_noise(self.measurement_noise),
            initial_covariance=self.config.initial_covariance)
        self.on_c = True
        self.full_scale = full_scale

    # -- long gaps -----------------------------------------------------------
    def gap_length(self) -> int:
        """Missing samples in a row that make a long gap (at least one)."""
        return max(1, int(np.ceil(round(GAP_SHARE * self.config.window_samples, 9))))   # 0.2 * 500 is 100

    def point_after(self, count: int) -> int:
        """The next HPA point after ``count`` samples: the schedule from the stream's start, or from the end
        of the latest long gap, there from its first point of ``CLEAN_ONLY_BELOW_S`` (2 s) or more: the weights
        in use were fitted before the gap, and a shorter fit does not beat them (docs/design.md, "Missing
        samples")."""
        if self.gap_end is None:
            return self.config.next_hpa(count)
        return self.gap_end + self.config.next_hpa(max(count - self.gap_end, clean_only_below(self.config) - 1))

    def gap_ended(self, last_missing: int) -> None:
        """A long gap ended with sample number ``last_missing``: the schedule starts again from there, warm-up
        HPAs first, as after ``reset()``."""
        self.gap_end = last_missing
        self.next_hpa = self.point_after(last_missing)

    def hpa_window(self, window, count: int):
        """The samples the HPA at ``count`` reads: ``window`` (the last min(count, L)) from the latest long
        gap's end on, or None inside a long gap (the HPA is skipped, the weights kept).  The schedule runs
        from the gap's end (:meth:`point_after`), so at least its first point's ``2 * 2**J`` samples follow."""
        if self.missing_run >= self.long_gap:
            self.gap_skipped += 1
            return None
        if self.gap_end is None:
            return window
        return window[max(0, window.shape[0] - (count - self.gap_end)):]

    # -- samples -------------------------------------------------------------
    def process(self, x):
        """A block of samples continuing the stream: ``y[i]`` is what
        ``update(x[i])`` would return (the prediction for the next sample)."""
        L = self.config.window_samples
        n = x.shape[0]
        y = np.empty(n)
        if self.config.hpa_mode == "thread":
            self.swap_if_ready(wait=True, first_sample=self.count + 1)
        seen = np.concatenate((self.ordered_history(), x))  # the last L samples before x, then x
        base = self.count
        start = 0
        # Long gaps (what update() sees sample by sample): valid[j] is the index of a present sample, and
        # the run of missing samples before it (the run carried from the last call before the first).
        valid = np.flatnonzero(~np.isnan(x))
        before = np.diff(valid, prepend=-1) - 1
        if valid.size:
            before[0] += self.missing_run
        ends = list(valid[before >= self.long_gap])  # first sample after each long gap
        carried = self.missing_run

        def run_at(k):
            """Missing samples in a row up to and including x[k]."""
            j = np.searchsorted(valid, k, side="right") - 1
            return int(k - valid[j]) if j >= 0 else int(k + 1 + carried)

        # After sample number c = next_hpa arrives, an HPA runs (on the last
        # min(c, L) samples) before that sample's RTP step.
        while True:
            stop = self.next_hpa - base - 1  # index in x of the sample completing the next HPA point
            if ends and ends[0] <= min(stop, n - 1):
                # a long gap ended before that point (update() reschedules when its first sample comes)
                self.gap_ended(base + int(ends.pop(0)))
                continue
            if stop >= n:
                break
            if start < stop:
                y[start:stop] = self.run_rtp(x[start:stop])
                start = stop
            self.count = base + stop + 1
            self.missing_run = run_at(stop)
            m = min(self.count, L)
            window = self.hpa_window(seen[L + stop + 1 - m : L + stop + 1], self.count)
            self.next_hpa = self.point_after(self.count)
            if window is not None:
                self.hpa(window)
        if start < n:
            y[start:] = self.run_rtp(x[start:])
        self.count = base + n
        self.missing_run = run_at(n - 1) if n else self.missing_run
        self.history = seen[-L:].copy()
        self.pos = 0
        return y

    def swap_if_ready(self, wait=False, first_sample=None):
        """Thread mode: install a finished HPA between two samples."""
        if self.pending is None:
            return
        future, window = self.pending
        if wait or future.done():
            self.pending = None
            self.apply(future.result(), window, self.count + 1 if first_sample is None else first_sample)

    def update(self, sample, executor):
        L = self.config.window_samples
        if self.pending is not None:
            self.swap_if_ready()
        # history is a ring: self.pos is the oldest sample
        self.history[self.pos] = sample
        self.pos = (self.pos + 1) % L
        self.count += 1
        if sample != sample:
            self.missing_run += 1
        else:
            if self.missing_run >= self.long_gap:
                self.gap_ended(self.count - 1)
            self.missing_run = 0
        if self.count == self.next_hpa:
            window = self.hpa_window(self.ordered_history()[-min(self.count, L):], self.count)
            self.next_hpa = self.point_after(self.count)
            if window is None:
                pass                  # inside a long gap: no HPA, the weights stay
            elif self.config.hpa_mode == "inline":
                self.hpa(window)
            else:
                # One HPA in flight at a time: a new window waits for the last
                # one (it had L samples' time to finish).
                self.swap_if_ready(wait=True, first_sample=self.count)
                self.pending = (executor().submit(self.hpa_job(window)), window)
        if sample != sample:
            self.over_run = 0
            return self.rtp.step_missing()
        if self.follows_signal():
            if abs(sample) > self.full_scale:
                self.over_run += 1
                self.over_peak = max(self.over_peak, abs(sample))
                if self.over_run >= RAISE_AFTER:
                    self.raise_full_scale(self.over_peak)
            else:
                self.over_run, self.over_peak = 0, 0.0
        return self.rtp.step(sample)

    # -- full scale between two HPAs ------------------------------------------
    def follows_signal(self) -> bool:
        """Whether the full scale may rise between HPAs (C path, full scale not fixed by the user)."""
        return self.on_c and self.config.full_scale is None

    def run_rtp(self, x):
        """``rtp.run(x)``, raising the full scale where :data:`RAISE_AFTER` samples in a row overflow it.

        Gives what :meth:`update` gives sample by sample.
        """
        if not self.follows_signal():
            return self.rtp.run(x)
        n = x.shape[0]
        y = np.empty(n)
        start = 0
        while start < n:
            k, run = first_persistent_overflow(x[start:], self.full_scale, self.over_run)
            end = start + min(k, n - start - 1)          # the last sample of the run looked at
            peak = 0.0
            if run:
                first = end - run + 1                       # before start: carried from earlier samples
                peak = float(np.max(np.abs(x[max(start, first) : end + 1])))
                if first < start:
                    peak = max(peak, self.over_peak)
            if start + k < n:
                stop = start + k
                y[start:stop] = self.rtp.run(x[start:stop])
                self.raise_full_scale(peak)
                y[stop] = self.rtp.run(x[stop : stop + 1])[0]
                start = stop + 1
            else:
                y[start:] = self.rtp.run(x[start:])
                self.over_run, self.over_peak = run, peak
                start = n
        return y

    def raise_full_scale(self, peak: float):
        """Rise to the power of two at or above ``headroom`` x ``peak`` before the next sample."""
        fs = power_of_two_at_least(self.config.headroom * peak)
        if fs > self.full_scale:
            self.rescale(fs)
            self.full_scale_policy.quiet_windows = 0
        self.over_run, self.over_peak = 0, 0.0

    def rescale(self, fs: float):
        """Move the C path to full scale ``fs`` between two samples (state carried, counted)."""
        self.rtp, _ = self.rtp.rescaled(fs)
        self.full_scale = fs
        self.full_scale_changes += 1
        self.clipped_before = self.rtp.clipped

    def ordered_history(self):
        """The last L samples, oldest first (a copy)."""
        return np.concatenate((self.history[self.pos :], self.history[: self.pos]))

    def snapshot(self) -> dict:
        """Plain-data copy of everything but the in-flight HPA (see WakeFilter.get_state)."""
        return {k: copy.deepcopy(v) for k, v in vars(self).items() if k not in ("pending", "config", "taps")}


def start_weights_for(config: WakeConfig, taps: np.ndarray) -> np.ndarray:
    """The weights before the first HPA (``config.initial_weights``): one per filter, shared by its channels."""
    return prior_weights(config, taps) if config.initial_weights == "prior" else default_weights(config.level)


def _drop_outliers(window):
    """``window`` with samples far beyond its robust peak as NaN (gaps, interpolated for the HPA)."""
    peak = robust_peak(window)
    limit = min(OUTLIER_ABS, OUTLIER_PEAKS * peak) if peak > 0 else OUTLIER_ABS
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
