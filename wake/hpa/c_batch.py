"""The C HPA's batch path: many HPA points of one channel's block in one call of the host-only driver.

``WakeFilter(backend="c", hpa_backend="c").run`` spends most of its time in Python glue between the C
calls, once per HPA window (stretching the RTP to the point, running the C HPA, installing its weights,
R, q and tremor-ahead predictor).  The schedule's points and each window's full-scale decision follow from
the input alone, so :class:`Batch` decides them here, point by point, and hands a run of points to
``wake_batch_run`` (``wake/native/wake_batch.c``, compiled into ``wake._rtp``), which does the RTP stretches,
the HPAs and the installs in C through the core's public API.

A point is taken only when today's path would do nothing else at it: the C core runs (:attr:`AdaptiveRTP.on_c`)
without a voluntary motion ahead installed, the stretch before the point is finite and inside the full scale
(no clipping, no overflow rule, no gap), the window is one the C HPA reads, and the full-scale policy keeps the
full scale there.  Anything else, and any point the driver refuses, runs on :meth:`Channel.hpa` as before:
bit for bit the same outputs and HPA history either way (tests/hpa/test_c_batch.py).
"""

from __future__ import annotations

import numpy as np

from wake.ahead import TAPS, installed_goal
from wake.hpa.c_port import _core, _prepared, quantize_window, update_from_result
from wake.hpa.run import finish_hpa, recorded
from wake.rtp.qformat import clamped_words, quantize_ahead

__all__ = ["Batch", "InstallBatch", "covers", "covers_installs"]

_Q15 = 32768.0
#: |x| / full scale * 2^15 below this rounds inside int16 on both sides: no sample of a taken stretch clips
_INSIDE = 32767.5
#: Samples looked at for NaN and the full scale at once (a batch that stops early looks at no more)
CHUNK = 2**12


def covers(channel) -> bool:
    """Whether the driver may take the next points of ``channel``: the C HPA on the C core, no voluntary motion
    ahead installed, nothing wrapping the channel's HPA (the progress bar of ``wake run`` counts its calls)."""
    config, rtp = channel.config, channel.rtp
    return (config.hpa_backend == "c" and config.backend == "c" and rtp.on_c and "hpa" not in channel.__dict__
            and not rtp.core._state.voluntary_ahead.set and rtp.core.clipped == rtp.clipped_before)


def covers_installs(channel) -> bool:
    """Whether :class:`InstallBatch` may take the next points of ``channel``: the Python HPA (its windows analysed
    by :meth:`Channel.points`) on the C core at the default horizon (no voluntary motion ahead to install), nothing
    wrapping the channel's HPA, no clip since the last HPA."""
    config, rtp = channel.config, channel.rtp
    return (config.hpa_backend != "c" and config.backend == "c" and config.horizon == 1 and rtp.on_c
            and "hpa" not in channel.__dict__ and not rtp.core._state.voluntary_ahead.set
            and rtp.core.clipped == rtp.clipped_before)


class Batch:
    """Points of one block collected for the driver (:meth:`take`), then run (:meth:`flush`).

    Parameters
    ----------
    channel : wake.channel.Channel
        :func:`covers` it.
    x : numpy.ndarray, shape (n,)
        The block :meth:`Channel.process` runs.
    start : int
        The first sample of ``x`` the RTP has not stepped yet.
    """

    def __init__(self, channel, x, start: int):
        self.channel, self.x, self.start = channel, x, start
        self.full_scale = channel.rtp.full_scale
        self.follows = channel.rtp.fixed_full_scale is None   # the policy decides at each HPA
        self.level, self.window = channel.config.level, channel.config.window_samples
        self.points, self.quiet = [], []
        self.stop = start
        # samples from start on looked at (a chunk at a time), and the first a stretch may not hold: NaN (a
        # gap), a clip or an overflow
        self.checked, self.first_bad = start, None

    def take(self, point) -> bool:
        """Add ``point`` (as :meth:`Channel.points` yields it) when the driver covers it: its stretch finite
        and inside the full scale, its window one the C HPA reads and the full scale kept there (the policy's
        decision is taken now, as :meth:`AdaptiveRTP.install` would take it)."""
        stop, window, _count, (prepared, peak), _analysis = point
        if window is None or prepared is None:
            return False
        if prepared.ndim != 1 or not 2 * 2**self.level <= prepared.shape[0] <= self.window:   # run_hpa_c's check
            return False
        if not self._inside(stop):
            return False
        policy = self.channel.rtp.policy
        quiet = policy.quiet_windows
        if self.follows:
            _, reason = policy.decide(self.full_scale, window, peak)
            if reason is not None:
                policy.quiet_windows = quiet
                return False
        self.points.append(point)
        self.quiet.append(quiet)
        self.stop = stop
        return True

    def finish(self) -> None:
        """Let the driver run the RTP on to the end of the block after the last point taken (when every sample
        there lies inside the full scale: one C call fewer)."""
        if self.points and self._inside(self.x.shape[0]):
            self.stop = self.x.shape[0]

    def _inside(self, stop: int) -> bool:
        """Whether every sample before ``stop`` lies inside the full scale (checked :data:`CHUNK` at a time)."""
        limit = self.full_scale / _Q15 * _INSIDE
        while self.first_bad is None and self.checked < stop:
            end = min(self.x.shape[0], self.checked + max(CHUNK, stop - self.checked))
            with np.errstate(invalid="ignore"):
                bad = np.flatnonzero(~(np.abs(self.x[self.checked:end]) < limit))
            self.first_bad = self.checked + int(bad[0]) if bad.size else None
            self.checked = end
        return self.first_bad is None or stop <= self.first_bad

    def flush(self, y) -> tuple:
        """Run the points taken through the driver, writing their stretches' outputs into ``y`` (5, n).

        Returns ``(start, rest)``: the first sample the RTP has not stepped and the points the driver did not
        run (from one it refused: :meth:`Channel.process` runs them its own way, the policy's state put back
        to what it was before them)."""
        if not self.points:
            return self.start, []
        ch = self.channel
        ffi, lib = _core()
        config, rtp = ch.config, ch.rtp
        core = rtp.core
        cfg, taps_q = _prepared(config, ch.taps, config.horizon)
        first, fs = self.start, self.full_scale
        windows = np.concatenate([p[3][0] for p in self.points])
        lengths = np.array([p[3][0].shape[0] for p in self.points], dtype=np.uint16)
        offsets = np.zeros(len(self.points), dtype=np.uint32)
        np.cumsum(lengths[:-1], out=offsets[1:])
        if not np.isfinite(windows).all():   # run_hpa_c refuses such a window: the points from it run on
            bad = int(np.searchsorted(offsets, np.flatnonzero(~np.isfinite(windows))[0], side="right")) - 1
            rtp.policy.quiet_windows = self.quiet[bad]
            rest, self.points = self.points[bad:], self.points[:bad]
            if not self.points:
                return first, rest
            self.stop = self.points[-1][0]
            start, others = self.flush(y)
            return start, others + rest
        k = len(self.points)
        stops = np.array([p[0] - first for p in self.points], dtype=np.uint32)
        counts = np.array([p[2] & 0xFFFFFFFF for p in self.points], dtype=np.uint32)
        stacked = quantize_window(windows, fs)   # elementwise: each window as run_hpa_c quantises it
        span = self.stop - first
        x_q = core._quantize_samples(self.x[first:self.stop])   # every sample inside the full scale: none clips
        vol_q = np.empty(span, dtype=np.int16)
        rows = np.empty((3, span), dtype=np.int32)
        carry = ffi.new("wake_batch_carry_t *")
        carry.weights[0:config.level] = np.clip(np.asarray(ch.weights, dtype=np.float32), -lib.WAKE_HPA_WEIGHT_LIMIT,
                                                lib.WAKE_HPA_WEIGHT_LIMIT).tolist()
        if ch.ahead_coefficients is not None:
            carry.ahead[0:len(carry.ahead)] = np.asarray(ch.ahead_coefficients, dtype=np.float32).tolist()
            carry.ahead_index = ch.ahead_index & 0xFFFFFFFF
            carry.has_ahead = 1
        results = ffi.new("wake_hpa_result_t[]", k)
        clamped = np.zeros(k, dtype=np.uint8)
        done, samples = ffi.new("size_t *"), ffi.new("size_t *")
        hpa = ffi.new("wake_hpa_t *")
        buf = ffi.from_buffer
        lib.wake_batch_run(core._state, hpa, cfg, buf("int16_t[]", taps_q), buf("int16_t[]", x_q), span, k,
                           buf("uint32_t[]", stops), buf("uint32_t[]", counts), buf("int16_t[]", stacked),
                           buf("uint32_t[]", offsets), buf("uint16_t[]", lengths), fs, config.process_noise_ratio,
                           carry, buf("int16_t[]", vol_q), buf("int32_t[]", rows[0]), buf("int32_t[]", rows[1]),
                           buf("int32_t[]", rows[2]), results, buf("uint8_t[]", clamped), done, samples)
        done, ran = int(done[0]), int(samples[0])
        if ran:   # the rows as FixedPointRTP._run_block scales them (no w_h: the one-step prediction, held)
            out = core._scale_rows(vol_q[:ran], rows[:, :ran], y[:, first:first + ran], with_ahead=False)
            rtp.last_prediction = float(out[0, -1])
            rtp.over_run, rtp.over_peak = 0, 0.0   # every sample inside the full scale
        for i in range(done):   # what Channel.apply records and keeps, point by point
            count = self.points[i][2]
            upd = update_from_result(results[i], count, fs, config.level, applied_at=count,
                                     flags=("noise_clamped",) if clamped[i] else ())
            ch.weights = upd.weights
            ch.ahead_coefficients, ch.ahead_index = upd.ahead_coefficients, upd.index
            ch.updates.append(upd)
        if done:
            ch.measurement_noise = rtp.measurement_noise
        if done < k:
            rtp.policy.quiet_windows = self.quiet[done]
        return first + ran, self.points[done:]


class InstallBatch(Batch):
    """The Python HPA's points of one block, their RTP stretches and installs in one C call (``wake_batch_install``).

    Python finishes each window in order (:func:`~wake.hpa.run.finish_hpa`, from the weights and predictor the
    previous point left, as :meth:`Channel.hpa` does) and quantises what :meth:`Channel.apply` would install with
    the install's own code (:func:`~wake.rtp.qformat.clamped_words`, :func:`~wake.rtp.qformat.quantize_ahead`);
    the driver runs the stretches and installs those words.  The points it takes are those :class:`Batch` takes
    (stretch finite and inside the full scale, the full scale kept), so installing notes nothing but a clamped R
    or q, as there.  A point whose finish or quantisation raises, and every point after it, run on
    :meth:`Channel.hpa` instead (which raises there, after the stretch, as before).
    """

    def take(self, point) -> bool:
        return point[4] is not None and super().take(point)

    def flush(self, y) -> tuple:
        if not self.points:
            return self.start, []
        ch = self.channel
        ffi, lib = _core()
        config, rtp = ch.config, ch.rtp
        core, first, k, level = rtp.core, self.start, len(self.points), config.level
        w_q, c_q = np.empty((k, level), dtype=np.int32), np.empty((k, TAPS), dtype=np.int32)
        r_q, q_q, goal_q = (np.empty(k, dtype=np.int32) for _ in range(3))
        weights, coefficients, index, finished = ch.weights, ch.ahead_coefficients, ch.ahead_index, []
        for i, (_stop, _window, count, _prepared_peak, analysis) in enumerate(self.points):
            try:   # as Channel.hpa_job binds it, then Channel.apply's quantisation
                upd = finish_hpa(analysis, config, previous_weights=weights.copy(), index=count,
                                 start_weights=ch.start_weights, new_samples=count - index,
                                 previous_ahead=None if coefficients is None else coefficients.copy())
                (w_q[i], r_q[i], q_q[i]), clamped = clamped_words(
                    upd.weights, level, upd.measurement_noise, ch.process_noise(upd.measurement_noise), core.full_scale)
                c_q[i], goal_q[i] = quantize_ahead(np.zeros(TAPS) if upd.ahead_coefficients is None
                                                   else upd.ahead_coefficients, installed_goal(upd.ahead_goal, ()))
            except (ValueError, ArithmeticError):
                break
            finished.append((upd, clamped))
            weights, coefficients, index = upd.weights, upd.ahead_coefficients, upd.index
        if len(finished) < k:   # the rest run on Channel.hpa, the policy's state put back to before them
            rtp.policy.quiet_windows = self.quiet[len(finished)]
            rest, self.points = self.points[len(finished):], self.points[:len(finished)]
            self.stop = self.points[-1][0] if self.points else first
        else:
            rest = []
        span = self.stop - first
        x_q = core._quantize_samples(self.x[first:self.stop])   # every sample inside the full scale: none clips
        vol_q = np.empty(span, dtype=np.int16)
        rows = np.empty((3, span), dtype=np.int32)
        stops = np.array([p[0] - first for p in self.points], dtype=np.uint32)
        done, samples = ffi.new("size_t *"), ffi.new("size_t *")
        buf = ffi.from_buffer
        lib.wake_batch_install(core._state, buf("int16_t[]", x_q), span, len(self.points), buf("uint32_t[]", stops),
                               level, buf("int32_t[]", w_q), buf("int32_t[]", r_q), buf("int32_t[]", q_q),
                               buf("int32_t[]", c_q), buf("int32_t[]", goal_q), buf("int16_t[]", vol_q),
                               buf("int32_t[]", rows[0]), buf("int32_t[]", rows[1]), buf("int32_t[]", rows[2]),
                               done, samples)
        done, ran = int(done[0]), int(samples[0])
        if ran:   # the rows as FixedPointRTP._run_block scales them (no w_h: the one-step prediction, held)
            out = core._scale_rows(vol_q[:ran], rows[:, :ran], y[:, first:first + ran], with_ahead=False)
            rtp.last_prediction = float(out[0, -1])
            rtp.over_run, rtp.over_peak = 0, 0.0   # every sample inside the full scale
        for (upd, clamped), point in zip(finished[:done], self.points):   # what Channel.apply records and keeps
            flags = upd.flags + (("noise_clamped",) if clamped and "noise_clamped" not in upd.flags else ())
            ch.weights = upd.weights
            ch.ahead_coefficients, ch.ahead_index = upd.ahead_coefficients, upd.index
            ch.updates.append(recorded(upd, applied_at=point[2], flags=flags))
        if done:
            ch.measurement_noise = rtp.measurement_noise
        if done < len(self.points):
            rtp.policy.quiet_windows = self.quiet[done]
        return first + ran, self.points[done:] + rest
