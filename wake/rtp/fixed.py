"""Python wrapper of the fixed-point C core (``csrc/wake_rtp.c``).

:class:`FixedPointRTP` has the interface of
:class:`wake.rtp.reference.ReferenceRTP` but runs the integer recursion of
the C library, the one firmware runs (with the voluntary motion ahead, ``w_h``,
:mod:`wake.rtp.fixed_voluntary`).  Values cross the boundary in physical units and
are quantised with ``full_scale`` (FS) into the formats of :mod:`wake.rtp.qformat`
(which needs no compiled core); importing this module checks that the compiled core
has those formats.  See ``docs/studies/fixed_point.md`` for the error analysis.
"""

from __future__ import annotations

import numpy as np

from wake._rtp import ffi, lib
from wake.rtp.fixed_ahead import AheadMixin
from wake.rtp.fixed_voluntary import STRUCT_LAYOUT, VoluntaryAheadMixin, migrate_struct
from wake.rtp.status import check_status as _check
from wake.rtp.qformat import (  # noqa: F401  (re-exported: the formats of this core)
    _INT32_MAX, _INT32_MIN, FIR_FRAC, GATE_FRAC, MAX_LEVEL, P_FRAC, SAMPLE_FRAC, STATE_FRAC, TAP_FRAC, TAP_ROW_ABS_MAX,
    WEIGHT_FRAC, WEIGHT_MAX, clamped_words, format_mismatches, quantize_taps, quantize_variance, quantize_weights,
    representable_noise, weight_words)

__all__ = ["FixedPointRTP", "P_FRAC", "quantize_taps", "quantize_weights", "quantize_variance", "representable_noise"]


if format_mismatches(lib):
    raise ImportError("the compiled core wake._rtp was built with other fixed-point formats than wake.rtp.qformat "
                      "expects: " + "; ".join(format_mismatches(lib)) + "; rebuild it without -D overrides "
                      "(python build_ffi.py)")
_SAMPLE_SCALE = 2.0**SAMPLE_FRAC
_step_c = lib.wake_rtp_step   # bound once: step() runs per sample

class FixedPointRTP(AheadMixin, VoluntaryAheadMixin):
    """One channel of the RTP on the fixed-point C core.

    Parameters
    ----------
    taps, weights, measurement_noise, process_noise, initial_covariance
        As :class:`wake.rtp.reference.ReferenceRTP`, in physical units.
    full_scale : float
        Physical value mapped to 1.0 in Q15.  Samples beyond ±full_scale are
        clipped (and counted in :attr:`clipped`); choose it with headroom
        above the largest expected |sample|.
    fs : float
        Sampling rate in Hz: the ramp of the tremor ahead's gate (:class:`~wake.rtp.fixed_ahead.AheadMixin`).

    Attributes
    ----------
    clipped : int
        Input samples clipped to the int16 range since construction / reset.

    Examples
    --------
    >>> from wake.wavelets import filter_bank_taps
    >>> from wake.rtp.fixed import FixedPointRTP
    >>> rtp = FixedPointRTP(filter_bank_taps("sym3", 3), [0, 0, 1], 1e-3, full_scale=4.0)
    >>> [round(rtp.step(1.0), 3) for _ in range(3)]
    [1.0, 1.0, 1.0]
    """

    def __init__(self, taps, weights, measurement_noise, process_noise=0.0, initial_covariance=0.0, *, full_scale,
                 fs=100.0):
        scale = float(full_scale)
        if not np.isfinite(scale) or scale <= 0:
            raise ValueError(f"full_scale must be finite and > 0, got {full_scale!r}")
        self.full_scale = scale
        self._taps_q = quantize_taps(taps)
        self.level, self.n_taps = self._taps_q.shape
        self._p0_q = quantize_variance(initial_covariance, scale, "initial_covariance", positive=False)
        self._state = ffi.new("wake_rtp_t *")
        self._out = ffi.new("int16_t *")  # reused by step(): one allocation per instance, not per sample
        self._taps_c = ffi.from_buffer("int16_t[]", self._taps_q)   # kept alive with self
        w_q = quantize_weights(weights, self.level)
        r_q = quantize_variance(measurement_noise, scale, "measurement_noise R", positive=True)
        q_q = quantize_variance(process_noise, scale, "process_noise Q", positive=False)
        _check(
            lib.wake_rtp_init(self._state, self.level, self._taps_c, ffi.from_buffer("int32_t[]", w_q), r_q, q_q, self._p0_q),
            "wake_rtp_init",
        )
        self.clipped = 0
        self._carried_saturations = 0  # counted at an earlier full scale (rescaled)
        self._init_ahead(fs)

    # -- quantised parameters in physical units (what the C core really uses)
    @property
    def taps(self):
        """Taps as the C core holds them (Q15, dequantised)."""
        return self._taps_q / 2.0**TAP_FRAC

    @property
    def weights(self):
        return np.array([self._state.weights[j] for j in range(self.level)]) / 2.0**WEIGHT_FRAC

    @property
    def measurement_noise(self):
        return self._state.r * self._p_lsb

    @property
    def process_noise(self):
        return self._state.q * self._p_lsb

    @property
    def initial_covariance(self):
        return self._state.p0 * self._p_lsb

    @property
    def _p_lsb(self):
        return self.full_scale**2 / 2.0**P_FRAC

    # -- state, read from the C struct --------------------------------------
    @property
    def saturations(self):
        """Narrowings that saturated inside the C core since construction / reset."""
        return int(self._state.saturations) + self._carried_saturations

    @property
    def primed(self):
        return bool(self._state.primed)

    @property
    def last_output(self):
        return self._state.last_output / 2.0**STATE_FRAC * self.full_scale

    def _kalman_state(self):
        """(d, P) as integers, rebuilt by the C core from its constant-time form (wake_rtp_get_state)."""
        J = self.level
        d = np.zeros(J, dtype=np.int32)
        P = np.zeros(J * J, dtype=np.int32)
        _check(lib.wake_rtp_get_state(self._state, ffi.from_buffer("int32_t[]", d), ffi.from_buffer("int32_t[]", P)),
               "wake_rtp_get_state")
        return d, P

    @property
    def correction(self):
        """Kalman correction d (J values, physical units)."""
        return self._kalman_state()[0] / 2.0**STATE_FRAC * self.full_scale

    @property
    def covariance(self):
        """Covariance P, flat row-major J*J (physical units squared), like ReferenceRTP."""
        return self._kalman_state()[1] * self._p_lsb

    @property
    def window(self):
        """The newest 2**J samples, oldest first (physical units)."""
        head = int(self._state.head)  # each sample is stored twice: ring[head:head + N] is the window
        ring = np.array([self._state.ring[head + k] for k in range(self.n_taps)], dtype=float)
        return ring / 2.0**SAMPLE_FRAC * self.full_scale

    # -- configuration ------------------------------------------------------
    def set_weights(self, weights, measurement_noise, process_noise=None):
        """Install new HPA output between two samples (no state is touched)."""
        self._set_words(*weight_words(weights, self.level, measurement_noise, process_noise, self.full_scale))

    def _set_words(self, w_q, r_q, q_q):
        q_q = int(self._state.q) if q_q is None else q_q   # None: keep the q in use
        _check(lib.wake_rtp_set_weights(self._state, ffi.from_buffer("int32_t[]", w_q), r_q, q_q), "wake_rtp_set_weights")

    def reset(self):
        """Forget every sample; keep taps and weights (counters restart)."""
        _check(lib.wake_rtp_reset(self._state), "wake_rtp_reset")
        self.clipped = 0
        self._carried_saturations = 0

    def load_state(self, window_oldest_first, correction, covariance, last_output):
        """Set ring, correction, covariance and last output (hand-over from a float warm-up).

        Values are quantised like everything else; out-of-range values raise
        ValueError.  The C core keeps of the covariance what the recursion
        uses, its variance along ``w``: ``P`` restarts as ``(w'Pw / w'w) I``
        (docs/studies/design.md, "Covariance at a weight change"); ``d`` is kept whole.
        """
        scale = self.full_scale
        win = np.asarray(window_oldest_first, dtype=float).reshape(-1)
        if win.shape != (self.n_taps,) or not np.isfinite(win).all():
            raise ValueError(f"window must be {self.n_taps} finite samples, oldest first")
        win_q = self._quantize_samples(win)
        d = np.asarray(correction, dtype=float).reshape(-1)
        if d.shape != (self.level,) or not np.isfinite(d).all():
            raise ValueError(f"correction must be {self.level} finite numbers")
        d_q = np.round(d / scale * 2.0**STATE_FRAC)
        if np.abs(d_q).max() > _INT32_MAX:
            raise ValueError(f"correction must lie within ±{2.0 ** (31 - STATE_FRAC) * scale:g} (Q{STATE_FRAC} of full_scale)")
        P = np.asarray(covariance, dtype=float).reshape(-1)
        if P.shape != (self.level**2,) or not np.isfinite(P).all():
            raise ValueError(f"covariance must be {self.level}x{self.level} finite numbers")
        P_q = np.round(P / self._p_lsb)
        if np.abs(P_q).max() > _INT32_MAX:
            raise ValueError(
                f"covariance entries must lie within ±{_INT32_MAX * self._p_lsb:.6g} (Q{P_FRAC} of full_scale**2)"
            )
        if (np.diag(P_q.reshape(self.level, self.level)) < 0).any():
            raise ValueError("covariance diagonal must be >= 0")
        y = float(last_output)
        y_q = round(y / scale * 2.0**STATE_FRAC) if np.isfinite(y) else None
        if y_q is None or not _INT32_MIN <= y_q <= _INT32_MAX:
            raise ValueError(f"last_output must be finite and within ±{2.0 ** (31 - STATE_FRAC) * scale:g}")
        win_q = np.ascontiguousarray(win_q, dtype=np.int16)
        d_q = np.ascontiguousarray(d_q, dtype=np.int32)
        P_q = np.ascontiguousarray(P_q, dtype=np.int32)
        _check(
            lib.wake_rtp_load_state(
                self._state,
                ffi.from_buffer("int16_t[]", win_q),
                ffi.from_buffer("int32_t[]", d_q),
                ffi.from_buffer("int32_t[]", P_q),
                y_q,
            ),
            "wake_rtp_load_state",
        )

    # -- per sample ---------------------------------------------------------
    def _quantize_samples(self, x, nan_positions=False):
        """Samples -> int16 Q15 of full_scale: round half to even, clip (counted in :attr:`clipped`).

        One division, one ``np.rint`` in place, one ``clip`` in place (only
        when the extremes of the rounded values are out of range: clipping is
        then counted) and one cast.  With ``nan_positions`` NaN samples become
        0 and their indices are returned too.
        """
        # x / (FS / 2^15) is exactly x / FS * 2^15 (scaling by a power of two), as in step()
        with np.errstate(over="ignore"):  # a huge sample becomes ±inf here and is clipped and counted below
            q = np.divide(np.asarray(x, dtype=float), self.full_scale / _SAMPLE_SCALE)
        np.rint(q, out=q)
        nan_idx = np.flatnonzero(np.isnan(q)) if nan_positions else None
        if nan_idx is not None and nan_idx.size:
            q[nan_idx] = 0.0
        if q.size and (np.fmax.reduce(q) > 32767.0 or np.fmin.reduce(q) < -32768.0):
            self.clipped += int(np.count_nonzero(q > 32767.0) + np.count_nonzero(q < -32768.0))
            np.clip(q, -32768.0, 32767.0, out=q)
        q_int = q.astype(np.int16)
        return (q_int, nan_idx) if nan_positions else q_int

    def _to_physical(self, y_q, out=None):
        # one multiply: y / 2^15 * FS == y * (FS / 2^15) exactly (power-of-two scaling)
        return np.multiply(y_q, self.full_scale / _SAMPLE_SCALE, out=out, dtype=float)

    def step(self, sample):
        """Take sample ``m(n)``; return the predicted voluntary motion at ``n + 1``."""
        x = float(sample)
        if x != x:
            return self.step_missing()
        # Scalar twin of _quantize_samples (same half-to-even rounding), without numpy's per-call cost.
        # Clip in float first: x / FS may overflow to inf (x = 1e307), which round() refuses;
        # update_block clips and counts the same values (_quantize_samples).
        v = x / self.full_scale * _SAMPLE_SCALE
        if not -32768.5 < v < 32767.5:
            self.clipped += 1
            m = -32768 if v < 0 else 32767
        else:
            m = round(v)
            if not -32768 <= m <= 32767:   # a half-way case rounded to even outside the range
                self.clipped += 1
                m = -32768 if m < 0 else 32767
        out = self._out
        status = _step_c(self._state, m, out)
        if status:
            _check(status, "wake_rtp_step")
        return out[0] / _SAMPLE_SCALE * self.full_scale

    def step_missing(self):
        """No measurement at ``n``: the last prediction stands in (see ReferenceRTP)."""
        out = ffi.new("int16_t *")
        _check(lib.wake_rtp_step_missing(self._state, out), "wake_rtp_step_missing")
        return float(self._to_physical(out[0]))

    def run(self, samples):
        """Step through a block; NaN marks a missing sample (a :meth:`step_missing`).

        One call of the C core (``wake_rtp_run_outputs``) on zero-copy buffers, whatever the block holds.
        """
        return self._run_block(samples, all_outputs=False)

    def _run_block(self, samples, all_outputs):
        """The block through ``wake_rtp_run_outputs``: the predictions, or with ``all_outputs`` the five rows
        of :meth:`run_outputs` as one ``(5, n)`` array (the C core writes integers; :meth:`_scale_rows` scales each
        by one multiply, as :meth:`step`, :attr:`last_ahead` and :attr:`last_voluntary_ahead` do: bit for bit)."""
        x = np.asarray(samples, dtype=float).reshape(-1)
        n = x.shape[0]
        x_q, nan_idx = self._quantize_samples(x, nan_positions=True)   # NaN -> 0, flagged missing
        missing = ffi.NULL
        if nan_idx.size:
            flags = np.zeros(n, dtype=np.uint8)
            flags[nan_idx] = 1
            missing = ffi.from_buffer("uint8_t[]", flags)
        vol_q = np.empty(n, dtype=np.int16)                # every entry is written by the C core
        rows = np.empty((4, n if all_outputs else 0), dtype=np.int32)   # P, gate, command, voluntary ahead
        with_ahead = all_outputs and bool(self._state.voluntary_ahead.set)   # constant within a block (installed between blocks)
        ptrs = [ffi.from_buffer("int32_t[]", rows[i]) if all_outputs and (i < 3 or with_ahead) else ffi.NULL
                for i in range(4)]                        # a NULL row is not computed
        _check(lib.wake_rtp_run_outputs(self._state, ffi.from_buffer("int16_t[]", x_q), missing, n,
                                        ffi.from_buffer("int16_t[]", vol_q), *ptrs), "wake_rtp_run_outputs")
        if not all_outputs:
            return self._to_physical(vol_q)
        return self._scale_rows(vol_q, rows, np.empty((5, n)), with_ahead)

    def _scale_rows(self, vol_q, rows, out, with_ahead):
        """``vol_q`` and the integer ``rows`` (P, gate, command[, v_h]) as :meth:`run_outputs`' rows, into ``out``."""
        self._to_physical(vol_q, out=out[0])
        lsb = self.full_scale / 2.0**STATE_FRAC            # P, the command and v_h: Q23 of the full scale
        np.multiply(rows[0], lsb, out=out[1])
        np.divide(rows[1], 2.0**GATE_FRAC, out=out[2])
        np.multiply(rows[2], lsb, out=out[3])
        if with_ahead:
            np.multiply(rows[3], lsb, out=out[4])
        else:                                              # no w_h yet: the one-step prediction, held
            np.copyto(out[4], out[0])
        return out

    # -- hand-over and representability ---------------------------------------
    @classmethod
    def from_reference(cls, reference, *, full_scale, measurement_noise, process_noise, initial_covariance):
        """A C channel continuing a float warm-up (:class:`~wake.rtp.reference.ReferenceRTP`).

        R, q and p0 are clamped into the C formats first
        (:func:`representable_noise`); the float state (window, correction,
        covariance, last output) is clipped into them, so a huge
        ``initial_covariance`` or a runaway correction cannot fail the hand-over.

        Returns
        -------
        (FixedPointRTP, bool)
            The channel, and whether R or q had to be clamped.
        """
        r, q, clamped = representable_noise(measurement_noise, process_noise, full_scale)
        p0 = representable_noise(1.0, initial_covariance, full_scale)[1]
        rtp = cls(reference.taps, reference.weights, r, q, p0, full_scale=full_scale)
        rtp._carry_from(reference)   # the tremor ahead (reference.ahead), fs and w_h carry over
        if reference.primed:
            window = np.concatenate((reference.buffer[reference.head:], reference.buffer[: reference.head]))
            top_p = _INT32_MAX * full_scale**2 / 2.0**P_FRAC
            top_x = _INT32_MAX * full_scale / 2.0**STATE_FRAC
            rtp.load_state(window, np.clip(reference.correction, -top_x, top_x),
                           np.clip(reference.covariance, -top_p, top_p),
                           float(np.clip(reference.last_output, -top_x, top_x)))
        return rtp, clamped

    def rescaled(self, full_scale):
        """This channel at another full scale: same taps, weights, R, q, p0 and state, requantised.

        The window, correction, covariance and last output are carried in
        physical units and clipped into the new formats (a sample beyond the
        new ±FS is clipped and counted); the counters (clipped, saturations,
        guard events) carry on.  R and q are clamped like in
        :meth:`from_reference`.

        Returns
        -------
        (FixedPointRTP, bool)
            The channel, and whether R or q had to be clamped.
        """
        scale = float(full_scale)
        r, q, clamped = representable_noise(self.measurement_noise, self.process_noise, scale)
        p0 = representable_noise(1.0, self.initial_covariance, scale)[1]
        new = type(self)(self.taps, self.weights, r, q, p0, full_scale=scale, fs=self.fs)
        new._carry_from(self)   # the tremor ahead, fs and w_h
        if self.primed:
            top_p = _INT32_MAX * scale**2 / 2.0**P_FRAC
            top_x = _INT32_MAX * scale / 2.0**STATE_FRAC
            new.load_state(self.window, np.clip(self.correction, -top_x, top_x),
                           np.clip(self.covariance, -top_p, top_p),
                           float(np.clip(self.last_output, -top_x, top_x)))
        new.clipped += self.clipped
        new._carried_saturations = self.saturations
        return new, clamped

    def set_weights_clamped(self, weights, measurement_noise, process_noise):
        """:meth:`set_weights` after clamping R and q into the C formats; returns whether it clamped."""
        words, clamped = clamped_words(weights, self.level, measurement_noise, process_noise, self.full_scale)
        self._set_words(*words)
        return clamped

    # -- pickling: the struct is plain data but for the taps pointer ----------
    def __getstate__(self):
        return {"full_scale": self.full_scale, "taps_q": self._taps_q, "clipped": self.clipped,
                "p0_q": self._p0_q, "struct": bytes(ffi.buffer(self._state)),
                "carried": self._carried_saturations, "fs": self.fs, "layout": STRUCT_LAYOUT}

    def __setstate__(self, st):
        self.full_scale = st["full_scale"]
        self._taps_q = st["taps_q"]
        self.level, self.n_taps = self._taps_q.shape
        self._p0_q = st["p0_q"]
        self.clipped = st["clipped"]
        if not isinstance(st["carried"], int):
            raise ValueError("this state was saved by another version of the C core (its saturation count is "
                             "not an int); re-create the filter and run it again instead of loading the state")
        struct = migrate_struct(st["struct"], st.get("layout", 1))
        self._carried_saturations = st["carried"]
        self._state = ffi.new("wake_rtp_t *")
        self._out = ffi.new("int16_t *")
        self._taps_c = ffi.from_buffer("int16_t[]", self._taps_q)
        ffi.buffer(self._state)[:len(struct)] = struct
        self._state.taps = self._taps_c  # the pickled pointer belonged to the old process
        self._restore_ahead(st)
