"""The tremor ahead of the fixed-point C core (``WAKE_RTP_AHEAD``): the Python side of :class:`FixedPointRTP`.

The C core runs the per-sample rule of :mod:`wake.ahead` (:class:`wake.ahead.AheadStep`) in fixed
point: each step takes the tremor estimate ``e(n) = m(n) - y(n-1)`` into a delay line of
:data:`~wake.rtp.qformat.AHEAD_TAPS` values (Q15 of the full scale), predicts the tremor ``h``
samples ahead ``P(n) = c . line`` (coefficients Q27; ``P`` and the command in Q23), ramps the gate ``g += (goal - g) alpha``
(Q30) and makes the command ``g P``.  :class:`AheadMixin` is the interface
:class:`wake.rtp.reference.ReferenceRTP` shares (``set_ahead``, ``last_ahead``, ``run_ahead``); it
needs the struct ``_state`` and ``full_scale`` of :class:`~wake.rtp.fixed.FixedPointRTP`.
docs/studies/fixed_point.md, "The tremor ahead", bounds its error.
"""

from __future__ import annotations

import numpy as np

from wake._rtp import ffi, lib
from wake.rtp.fixed_voluntary import LAYOUT_1_SIZES
from wake.rtp.status import check_status as _check
from wake.ahead import ramp_step
from wake.rtp.qformat import AHEAD_COEF_FRAC, AHEAD_TAPS, GATE_FRAC, SAMPLE_FRAC, STATE_FRAC, quantize_ahead

__all__ = ["AheadMixin", "quantize_ramp"]



def quantize_ramp(alpha: float) -> int:
    """The gate's ramp coefficient ``alpha`` in (0, 1] -> Q30 (at least 1 LSB).

    Examples
    --------
    >>> from wake.ahead import ramp_step
    >>> quantize_ramp(ramp_step(100.0))
    35791394
    """
    a = float(alpha)
    if not 0.0 < a <= 1.0:
        raise ValueError(f"the gate's ramp coefficient must lie in (0, 1], got {alpha!r}")
    return max(1, int(round(a * 2.0**GATE_FRAC)))




class AheadMixin:
    """``set_ahead``, ``last_ahead`` and ``run_ahead`` of the C core (the contract of issue 32)."""

    #: Pickled struct sizes of layout 1 this core loads (wake.rtp.fixed_voluntary.LAYOUT_1_SIZES): whole, before
    #: the voluntary motion ahead (w_h) and before the tremor ahead (a state without w_h holds the one-step
    #: prediction until an HPA installs one).
    _STRUCT_SIZES = LAYOUT_1_SIZES

    def _restore_ahead(self, st):
        """After unpickling: ``fs``, and for a state saved before the tremor ahead, none installed at 100 Hz."""
        self.fs = float(st.get("fs", 100.0))
        if len(st["struct"]) <= ffi.offsetof("wake_rtp_t", "ahead"):
            self._state.ahead.ramp = quantize_ramp(ramp_step(self.fs))   # the rest stays 0: shut, no predictor

    def _init_ahead(self, fs):
        f = float(fs)
        if not np.isfinite(f) or f <= 0:
            raise ValueError(f"fs must be a finite sampling rate > 0 in Hz, got {fs!r}")
        self.fs = f
        _check(lib.wake_rtp_set_ahead_ramp(self._state, quantize_ramp(ramp_step(f))), "wake_rtp_set_ahead_ramp")

    def set_ahead(self, coefficients, goal):
        """Install a tremor-ahead predictor (8 floats, newest estimate first) and the gate's goal in [0, 1].

        The delay line and the gate's value carry over.  Raises ValueError for a wrong shape, a
        coefficient beyond +-8 or a goal outside [0, 1].
        """
        c_q, goal_q = quantize_ahead(coefficients, goal)
        _check(lib.wake_rtp_set_ahead(self._state, ffi.from_buffer("int32_t[]", c_q), goal_q), "wake_rtp_set_ahead")

    @property
    def ahead_coefficients(self):
        """The predictor as the C core holds it (Q27, dequantised), newest estimate first."""
        return np.array(list(self._state.ahead.coef), dtype=float) / 2.0**AHEAD_COEF_FRAC

    @property
    def ahead_goal(self):
        """The gate's goal (Q30, dequantised)."""
        return self._state.ahead.goal / 2.0**GATE_FRAC

    @property
    def ahead_ramp(self):
        """The gate's ramp coefficient alpha (Q30, dequantised)."""
        return self._state.ahead.ramp / 2.0**GATE_FRAC

    @property
    def ahead_history(self):
        """The delay line of tremor estimates, newest first, in physical units."""
        line = np.zeros(AHEAD_TAPS, dtype=np.int16)
        _check(lib.wake_rtp_get_ahead_state(self._state, ffi.from_buffer("int16_t[]", line)), "wake_rtp_get_ahead_state")
        return line * (self.full_scale / 2.0**SAMPLE_FRAC)

    @property
    def ahead_saturations(self):
        """Narrowings of the tremor ahead that saturated (apart from :attr:`saturations`)."""
        return int(self._state.ahead.saturations)

    @property
    def last_ahead(self):
        """``(predicted, confidence, command)`` of the last step: the tremor for ``n + h``, the gate, their product."""
        st = self._state
        lsb = self.full_scale / 2.0**STATE_FRAC   # P and the command are Q23 of the full scale
        return st.ahead.predicted * lsb, st.ahead.gate / 2.0**GATE_FRAC, st.ahead.command * lsb

    def run_ahead(self, samples):
        """:meth:`run_outputs` without its last row: ``(voluntary, predicted, confidence, command)`` arrays,
        bit for bit a loop of :meth:`step` (NaN = missing sample) reading :attr:`last_ahead` after each."""
        return self.run_outputs(samples)[:4]

    def load_ahead(self, coefficients, goal, history, gate, alpha):
        """Set the whole tremor-ahead state in physical units (hand-over, another full scale).

        ``history`` (newest first) is quantised to Q15 of the full scale and clipped into it.
        """
        self.set_ahead(coefficients, goal)
        _check(lib.wake_rtp_set_ahead_ramp(self._state, quantize_ramp(alpha)), "wake_rtp_set_ahead_ramp")
        h = np.asarray(history, dtype=float).reshape(-1)
        if h.shape != (AHEAD_TAPS,) or not np.isfinite(h).all():
            raise ValueError(f"the tremor-ahead history must be {AHEAD_TAPS} finite numbers, newest first")
        line = np.clip(np.round(h / self.full_scale * 2.0**SAMPLE_FRAC), -32768, 32767).astype(np.int16)
        g = float(gate)
        if not 0.0 <= g <= 1.0:
            raise ValueError(f"the gate must lie in [0, 1], got {gate!r}")
        _check(lib.wake_rtp_load_ahead_state(self._state, ffi.from_buffer("int16_t[]", line),
                                             int(round(g * 2.0**GATE_FRAC))), "wake_rtp_load_ahead_state")

    def _carry_ahead_from(self, other):
        """Take the tremor-ahead state of ``other``: an AheadMixin, or a ReferenceRTP's ``ahead`` (AheadStep)."""
        if isinstance(other, AheadMixin):
            self.fs = other.fs
            self.load_ahead(other.ahead_coefficients, other.ahead_goal, other.ahead_history,
                            other.last_ahead[1], other.ahead_ramp)
            return
        ahead = getattr(other, "ahead", None)
        self._init_ahead(getattr(other, "fs", self.fs))
        if ahead is not None:
            self.load_ahead(ahead.coefficients, ahead.goal, ahead.history, ahead.gate, ahead.alpha)
