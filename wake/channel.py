"""One channel of a WAKE filter: when the HPA runs, what the RTP is fed.

A :class:`Channel` keeps the last ``L`` samples for the next HPA, runs it
(inline, or on the filter's worker thread) and installs its result between
two samples; every sample goes through its RTP object (:mod:`wake.rtp`).
It holds no number format: the fixed-point rules live in
:mod:`wake.rtp.fixed`.
"""

from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np

from wake.config import WakeConfig
from wake.hpa import HPAUpdate, default_weights, run_hpa
from wake.rtp import ReferenceRTP, load_fixed_point

__all__ = ["Channel"]


class Channel:
    """HPA bookkeeping and RTP state of one channel."""

    def __init__(self, config: WakeConfig, taps: np.ndarray):
        self.config = config
        self.taps = taps
        self.weights = default_weights(config.level)
        self.measurement_noise = 1.0
        self.rtp = ReferenceRTP(taps, self.weights, self.measurement_noise,
                                self.process_noise(self.measurement_noise), config.initial_covariance)
        self.on_c = False
        self.full_scale = config.full_scale
        self.updates: list[HPAUpdate] = []
        self.history = np.zeros(config.window_samples)
        self.pos = 0
        self.count = 0
        self.pending = None  # thread mode: (future, window) of an HPA still off the sample path
        if config.backend == "c" and config.full_scale is not None:
            self.switch_to_c(config.full_scale)

    def process_noise(self, measurement_noise: float) -> float:
        """Absolute ``q`` pushed to the RTP: ``process_noise_ratio * R`` of the current window."""
        return self.config.process_noise_ratio * measurement_noise

    # -- HPA ---------------------------------------------------------------
    def hpa_job(self, window):
        """The HPA call for ``window``, with everything it reads passed in (it may run off the sample path)."""
        if np.isnan(window).any():  # gaps are interpolated for the spectrum: the one door every window goes through
            window = _fill_gaps(window)
        return (window, self.config), dict(taps=self.taps, previous_weights=self.weights.copy(), index=self.count)

    def hpa(self, window):
        args, kwargs = self.hpa_job(window)
        self.apply(run_hpa(*args, **kwargs), window, first_sample=self.count)

    def apply(self, upd: HPAUpdate, window, first_sample: int):
        """Install an HPA result between two samples.

        ``first_sample`` is the 1-based number of the first sample whose RTP
        step uses it.  The history keeps a copy of ``upd`` that records it
        (``applied_at``) and what installing it took (``noise_clamped``):
        the HPA's own result is never edited.
        """
        self.weights = upd.weights
        self.measurement_noise = upd.measurement_noise
        if self.config.backend == "c" and not self.on_c:
            observed = window[~np.isnan(window)]  # the window may hold gaps
            peak = float(np.max(np.abs(observed))) if observed.size else 0.0
            self.switch_to_c(self.config.headroom * peak if peak > 0 else 1.0)
        q = self.process_noise(self.measurement_noise)
        notes = ()
        if self.on_c:
            if self.rtp.set_weights_clamped(self.weights, self.measurement_noise, q):
                notes = ("noise_clamped",)
            self.measurement_noise = self.rtp.measurement_noise
        else:
            self.rtp.set_weights(self.weights, self.measurement_noise, q)
        self.updates.append(replace(upd, applied_at=first_sample, flags=upd.flags + notes))

    def switch_to_c(self, full_scale: float):
        fixed = load_fixed_point()
        self.rtp, _ = fixed.FixedPointRTP.from_reference(
            self.rtp, full_scale=full_scale, measurement_noise=self.measurement_noise,
            process_noise=self.process_noise(self.measurement_noise),
            initial_covariance=self.config.initial_covariance)
        self.on_c = True
        self.full_scale = full_scale

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
        # After sample number c arrives, an HPA runs when c is a multiple of L,
        # before that sample's RTP step.
        first_hpa = (-(base + 1)) % L  # index in x of the first sample completing a window
        for stop in list(range(first_hpa, n, L)) + [n]:
            if start < stop:
                y[start:stop] = self.rtp.run(x[start:stop])
            if stop < n:
                self.count = base + stop + 1
                self.hpa(seen[stop + 1 : stop + 1 + L])
            start = stop
        self.count = base + n
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
        if self.count % L == 0:
            window = self.ordered_history()
            if self.config.hpa_mode == "inline":
                self.hpa(window)
            else:
                # One HPA in flight at a time: a new window waits for the last
                # one (it had L samples' time to finish).
                self.swap_if_ready(wait=True, first_sample=self.count)
                args, kwargs = self.hpa_job(window)
                self.pending = (executor().submit(run_hpa, *args, **kwargs), window)
        if sample != sample:
            return self.rtp.step_missing()
        return self.rtp.step(sample)

    def ordered_history(self):
        """The last L samples, oldest first (a copy)."""
        return np.concatenate((self.history[self.pos :], self.history[: self.pos]))

    def snapshot(self) -> dict:
        """Plain-data copy of everything but the in-flight HPA (see WakeFilter.get_state)."""
        return {k: copy.deepcopy(v) for k, v in vars(self).items() if k not in ("pending", "config", "taps")}


def _fill_gaps(window):
    """Linear interpolation over NaN for the HPA's spectrum (edges held)."""
    good = ~np.isnan(window)
    if not good.any():
        return np.zeros_like(window)
    idx = np.arange(window.shape[0])
    return np.interp(idx, idx[good], window[good])
