"""One channel of a WAKE filter: the wiring of an HPA schedule, the HPA and an RTP.

A :class:`Channel` owns three pieces, each deciding one thing:

- :class:`~wake.hpa.schedule.HPASchedule`: when the HPA runs and on which
  samples (warm-up points, every ``L``, long gaps);
- :class:`~wake.rtp.adaptive.AdaptiveRTP`: the per-sample prediction, its
  full scale, and the move from the float reference to the C core;
- the HPA itself (:func:`wake.hpa.run_hpa` or the C HPA), run inline or on
  the filter's worker thread; this module dispatches it and installs its
  result between two samples.

It holds no number format (:mod:`wake.rtp.qformat`) and no schedule rule.
"""

from __future__ import annotations

import copy
from collections import deque
from dataclasses import dataclass
from functools import partial
from itertools import islice

import numpy as np

from wake.ahead import TAPS, installed_goal
from wake.config import WakeConfig
from wake.hpa import HPAUpdate, default_weights, run_hpa
from wake.hpa.run import analyse_windows, finish_hpa, recorded
from wake.hpa import c_batch
from wake.hpa.c_port import run_hpa_c
from wake.hpa.prior import prior_weights
from wake.hpa.schedule import HPASchedule, ScheduleState, prepare_window, prepare_windows
from wake.rtp.adaptive import AdaptiveRTP, AdaptiveRTPState, ClippingWarning
from wake.rtp.full_scale import robust_peak

__all__ = ["Channel", "ChannelState", "ClippingWarning", "start_weights_for"]

#: The batch path's windows analysed at once (:meth:`Channel.points`): up to this many samples of them (65
#: windows of 5 s at 100 Hz; one window at a time from L = 2**17 on), so its memory stays that of a few windows.
BATCH_SAMPLES = 2**15


@dataclass
class ChannelState:
    """Plain data of one :class:`Channel` (an entry of :attr:`wake.WakeState.channels`)."""

    weights: np.ndarray
    measurement_noise: float
    updates: list              #: the HPA history kept (:class:`~wake.hpa.HPAUpdate`, oldest first)
    schedule: ScheduleState
    rtp: AdaptiveRTPState
    ahead_coefficients: np.ndarray | None = None  #: the last HPA's tremor-ahead predictor (None: no HPA yet)
    ahead_index: int = 0                          #: the sample count of that HPA


class Channel:
    """The HPA schedule, the HPA and the RTP of one channel, wired (see the module docstring)."""

    def __init__(self, config: WakeConfig, taps: np.ndarray, start_weights: np.ndarray,
                 history_limit: int | None = None):
        self.config = config
        self.taps = taps
        self.start_weights = start_weights  # before the first HPA (start_weights_for)
        self.weights = start_weights
        self.measurement_noise = 1.0
        self.rtp = AdaptiveRTP(taps, self.weights, self.measurement_noise,
                               self.process_noise(self.measurement_noise), config.initial_covariance,
                               backend=config.backend, full_scale=config.full_scale, headroom=config.headroom,
                               fs=config.fs)
        # the last HPA's tremor-ahead predictor and sample count: the next HPA scores it on the samples since
        self.ahead_coefficients = None
        self.ahead_index = 0
        self.schedule = HPASchedule(config)
        # the newest history_limit HPA updates (None: all of them, for run())
        self.updates: deque[HPAUpdate] = deque(maxlen=history_limit)
        self.pending = None  # thread mode: (future, window) of an HPA still off the sample path

    def process_noise(self, measurement_noise: float) -> float:
        """Absolute ``q`` pushed to the RTP: ``process_noise_ratio * R`` of the current window."""
        return self.config.process_noise_ratio * measurement_noise

    # -- HPA ---------------------------------------------------------------
    def hpa_job(self, window, count=None, prepared=None, analysis=None):
        """The HPA call for ``window`` as a function of no arguments, with everything it reads bound
        (it may run off the sample path).

        ``count`` is the sample count of its point (default: the schedule's now), ``prepared`` the window as
        :func:`~wake.hpa.schedule.prepare_window` gave it and ``analysis`` its window-only steps
        (:func:`~wake.hpa.run.analyse_windows`; Python HPA), when a batch path has them already.
        """
        count = self.schedule.count if count is None else count
        window = prepare_window(window) if prepared is None else prepared
        if self.config.hpa_backend == "c":
            # the C HPA reads the int16 samples the RTP reads (its full scale once on the C path)
            hpa, extra = run_hpa_c, dict(taps=self.taps, full_scale=self.rtp.full_scale if self.rtp.on_c else None)
        elif analysis is None:
            hpa, extra = run_hpa, dict(taps=self.taps, start_weights=self.start_weights)
        else:
            hpa, window, extra = finish_hpa, analysis, dict(start_weights=self.start_weights)
        # both fit the tremor ahead and score the previous HPA's predictor on the samples since it
        previous = None if self.ahead_coefficients is None else self.ahead_coefficients.copy()
        return partial(hpa, window, self.config, previous_weights=self.weights.copy(), index=count,
                       previous_ahead=previous, new_samples=count - self.ahead_index, **extra)

    def hpa(self, window, count=None, prepared=None, analysis=None, peak=None):
        """Run the HPA on ``window`` inline and install its result before the next RTP step.

        ``count``, ``prepared``, ``analysis`` and ``peak``: the point's sample count (default: the schedule's
        now) and what a batch path has already computed for the window (:meth:`points`).
        """
        count = self.schedule.count if count is None else count
        if prepared is None:
            peak = robust_peak(window)   # read by the window's preparation and by the full-scale policy
            prepared = prepare_window(window, peak)
        self.apply(self.hpa_job(window, count, prepared, analysis)(), window, first_sample=count, peak=peak)

    def apply(self, upd: HPAUpdate, window, first_sample: int, peak=None):
        """Install an HPA result between two samples.

        ``first_sample`` is the 1-based number of the first sample whose RTP
        step uses it.  The history keeps a copy of ``upd`` that records it
        (``applied_at``) and what installing it took (``noise_clamped``,
        full-scale moves): the HPA's own result is never edited.
        """
        self.weights = upd.weights
        notes = self.rtp.install(self.weights, upd.measurement_noise, self.process_noise(upd.measurement_noise),
                                 window, peak)
        self.measurement_noise = self.rtp.measurement_noise if self.rtp.on_c else upd.measurement_noise
        # an HPA without a predictor shuts the gate, and so does a window clipped at the C core's full scale:
        # the C HPA applies that rule itself to the int16 window it read (its goal is final, "clipping" among
        # its flags), the Python HPA's goal goes through wake.ahead.installed_goal here
        coefficients = upd.ahead_coefficients
        goal = upd.ahead_goal if self.config.hpa_backend == "c" else installed_goal(upd.ahead_goal, notes)
        self.rtp.set_ahead(np.zeros(TAPS) if coefficients is None else coefficients, goal)
        self.ahead_coefficients, self.ahead_index = coefficients, upd.index
        # w_h, the voluntary motion ahead (horizon > 1); None keeps the one in use
        self.rtp.set_weights_ahead(upd.weights_ahead)
        flags = upd.flags + tuple(note for note in notes if note not in upd.flags)
        self.updates.append(recorded(upd, applied_at=first_sample, flags=flags))

    def swap_if_ready(self, wait=False, first_sample=None):
        """Thread mode: install a finished HPA between two samples."""
        if self.pending is None:
            return
        future, window = self.pending
        if wait or future.done():
            self.pending = None
            self.apply(future.result(), window, self.schedule.count + 1 if first_sample is None else first_sample)

    # -- samples -------------------------------------------------------------
    def process(self, x):
        """A block of samples continuing the stream: ``y[0, i]`` is what ``update(x[i])`` would return (the
        prediction for the next sample), ``y[1:4, i]`` the RTP's ``last_ahead`` then (predicted tremor at
        ``n + h``, confidence, command) and ``y[4, i]`` its ``last_voluntary_ahead`` (the voluntary motion
        predicted for ``n + h``); shape ``(5, n)``."""
        n = x.shape[0]
        y = np.empty((5, n))
        if self.config.hpa_mode == "thread":
            self.swap_if_ready(wait=True, first_sample=self.schedule.count + 1)
        start, batch = 0, None
        for point in self.points(x):
            # on the C core runs of points go to the batch driver in one call (wake.hpa.c_batch): with the C HPA
            # the HPAs too, with the Python HPA the RTP stretches and installs of the windows it finishes
            if batch is None and c_batch.covers(self):
                batch = c_batch.Batch(self, x, start)
            elif batch is None and c_batch.covers_installs(self):
                batch = c_batch.InstallBatch(self, x, start)
            if batch is not None:
                if batch.take(point):
                    continue
                start, rest = batch.flush(y)
                batch = None
                for refused in rest:   # from a point the driver refused: this path, as before
                    start = self._point(x, y, start, refused)
            start = self._point(x, y, start, point)
        if batch is not None:
            batch.finish()
            start, rest = batch.flush(y)
            for refused in rest:
                start = self._point(x, y, start, refused)
        if start < n:
            y[:, start:] = self.rtp.run_outputs(x[start:])
        return y

    def _point(self, x, y, start: int, point) -> int:
        """The RTP up to one HPA point of :meth:`points` (outputs into ``y``), then its HPA; the next start."""
        stop, window, count, (prepared, peak), analysis = point
        # the HPA at this point runs before the RTP step of x[stop]
        if start < stop:
            y[:, start:stop] = self.rtp.run_outputs(x[start:stop])
            start = stop
        if window is not None:
            self.hpa(window, count, prepared, analysis, peak)
        return start

    def points(self, x):
        """The HPA points of block ``x`` (:meth:`HPASchedule.block`) as ``(stop, window, count, (prepared, peak),
        analysis)``: ``count`` the point's sample count, ``prepared`` the window the HPA reads, ``peak`` the
        window's robust peak (read by the preparation and the full-scale policy) and, for the
        Python HPA, ``analysis`` its window-only steps, done for up to :data:`BATCH_SAMPLES` samples of windows
        at once (:func:`~wake.hpa.run.analyse_windows`, the warm-up windows beside the full ones: no window's steps
        read an earlier HPA, so they may run before the RTP reaches the point; bit for bit one at a time)."""
        points = self.schedule.block(x)
        size = max(1, BATCH_SAMPLES // self.schedule.window_samples)
        while chunk := [(stop, window, self.schedule.count) for stop, window in islice(points, size)]:
            prepared, peaks = zip(*[(None, None) if done is None else done
                                    for done in prepare_windows([window for _, window, _ in chunk])])
            analyses = [None] * len(chunk)
            rows = [i for i, win in enumerate(prepared) if win is not None]
            if self.config.hpa_backend != "c" and rows:
                done = analyse_windows([prepared[i] for i in rows], self.config, taps=self.taps,
                                       start_weights=self.start_weights)
                for i, analysis in zip(rows, done):
                    analyses[i] = analysis
            for (stop, window, count), win, peak, analysis in zip(chunk, prepared, peaks, analyses):
                yield stop, window, count, (win, peak), analysis

    def update(self, sample: float, executor) -> float:
        """One sample of the stream (NaN: missing): the prediction of the voluntary motion at the next one.

        The hot path of ``WakeFilter.update``: a thread-mode HPA that has finished is installed first; the
        sample enters the schedule, and when it completes an HPA point the HPA runs (inline) or is handed
        to ``executor()`` (thread mode, installed between two later samples); then the RTP steps.

        Parameters
        ----------
        sample : float
            One value of this channel.
        executor : callable
            Returns the filter's worker pool (started on first use); thread mode only.
        """
        if self.pending is not None:
            self.swap_if_ready()
        if self.schedule.push(sample):
            window = self.schedule.take_window()
            if window is None:
                pass                  # inside a long gap: no HPA, the weights stay
            elif self.config.hpa_mode == "inline":
                self.hpa(window)
            else:
                # One HPA in flight at a time: a new window waits for the last
                # one (it had L samples' time to finish).
                self.swap_if_ready(wait=True, first_sample=self.schedule.count)
                self.pending = (executor().submit(self.hpa_job(window)), window)
        return self.rtp.step(sample)

    # -- state -------------------------------------------------------------------
    def state(self) -> ChannelState:
        """Plain-data copy of everything but the in-flight HPA (see WakeFilter.get_state)."""
        return ChannelState(self.weights.copy(), self.measurement_noise, copy.deepcopy(list(self.updates)),
                            self.schedule.state(), self.rtp.state(), copy.deepcopy(self.ahead_coefficients),
                            self.ahead_index)

    def load(self, state: ChannelState) -> None:
        """Continue from :meth:`state` (copies: the state can be loaded again)."""
        self.weights = np.array(state.weights)
        self.measurement_noise = state.measurement_noise
        self.updates.clear()
        self.updates.extend(copy.deepcopy(state.updates))
        self.schedule.load(state.schedule)
        self.rtp.load(state.rtp)
        self.ahead_coefficients = copy.deepcopy(state.ahead_coefficients)
        self.ahead_index = state.ahead_index


def channel_state_from_unversioned(snapshot: dict) -> ChannelState:
    """A :class:`ChannelState` from the unversioned snapshot (``vars(Channel)``) of wake up to 0.x."""
    history = np.asarray(snapshot["history"], dtype=float)
    pos = snapshot["pos"]
    schedule = ScheduleState(snapshot["count"], snapshot["next_hpa"], snapshot["missing_run"],
                             snapshot["gap_end"], snapshot["gap_skipped"],
                             np.concatenate((history[pos:], history[:pos])))
    rtp = AdaptiveRTPState(snapshot["rtp"], snapshot["on_c"], snapshot["full_scale"],
                           snapshot["full_scale_policy"].quiet_windows, snapshot["full_scale_changes"],
                           snapshot["clipped_before"], snapshot["over_run"], snapshot["over_peak"])
    return ChannelState(snapshot["weights"], snapshot["measurement_noise"], list(snapshot["updates"]),
                        schedule, rtp)


def start_weights_for(config: WakeConfig, taps: np.ndarray) -> np.ndarray:
    """The weights before the first HPA (``config.initial_weights``): one per filter, shared by its channels."""
    return prior_weights(config, taps) if config.initial_weights == "prior" else default_weights(config.level)
