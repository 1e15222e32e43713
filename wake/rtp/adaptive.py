"""An RTP that picks and follows its own full scale, moving from the float reference to the C core.

The C core needs a full scale before its first sample; a stream does not
know one until it has seen a window that is not quiet.  :class:`AdaptiveRTP`
runs the float reference (:class:`~wake.rtp.reference.ReferenceRTP`) until
then, hands its state over to the C core (:class:`~wake.rtp.fixed.FixedPointRTP`)
at the first HPA whose window decides a full scale, and from there moves the
full scale with :class:`~wake.rtp.full_scale.FullScalePolicy`: at an HPA
(:meth:`AdaptiveRTP.install`), and between two HPAs when
:data:`~wake.rtp.full_scale.RAISE_AFTER` samples in a row overflow it (the
overflow rule, :meth:`AdaptiveRTP.step` sample by sample and
:meth:`AdaptiveRTP.run` a block at a time, one rule in both).

With ``backend="reference"`` it is the float reference throughout; with a
full scale given in the configuration, the C core from the first sample at
that full scale, never moved.
"""

from __future__ import annotations

import copy
import warnings
from dataclasses import dataclass

import numpy as np

from wake.rtp.full_scale import (
    GLITCH_SHARE,
    RAISE_AFTER,
    FullScalePolicy,
    first_persistent_overflow,
    power_of_two_at_least,
)
from wake.rtp.reference import ReferenceRTP

__all__ = ["AdaptiveRTP", "AdaptiveRTPState", "ClippingWarning"]


class ClippingWarning(RuntimeWarning):
    """More than 1 % of a window was clipped at the fixed-point full scale."""


@dataclass
class AdaptiveRTPState:
    """Plain data of an :class:`AdaptiveRTP` (part of :class:`wake.channel.ChannelState`)."""

    core: object                 #: the ReferenceRTP or FixedPointRTP running (each pickles itself)
    on_c: bool
    full_scale: float | None
    quiet_windows: int           #: :attr:`FullScalePolicy.quiet_windows`
    full_scale_changes: int
    clipped_before: int
    over_run: int
    over_peak: float


class AdaptiveRTP:
    """The RTP of one channel with its full-scale policy (see the module docstring).

    Parameters
    ----------
    taps, weights, measurement_noise, process_noise, initial_covariance
        As for :class:`~wake.rtp.reference.ReferenceRTP`.
    backend : {"c", "reference"}
        Where the RTP runs once a full scale is known.
    full_scale : float, optional
        A fixed full scale (C core from the first sample); None follows the signal.
    headroom : float
        :class:`~wake.rtp.full_scale.FullScalePolicy`'s factor.
    fs : float
        Sampling rate in Hz (the tremor-ahead gate's ramp).

    Notes
    -----
    The tremor ahead (:meth:`set_ahead`, :attr:`last_ahead`, :meth:`run_ahead`) runs in the core: the float
    reference's :class:`~wake.ahead.AheadStep`, then the C core's fixed-point twin, which
    ``FixedPointRTP.from_reference`` carries it into at the switch.

    The voluntary motion ahead (:meth:`set_weights_ahead`, :attr:`last_voluntary_ahead`, :meth:`run_outputs`)
    runs in the core too: the float reference's ``w_h' (a + d)``, then the C core's fixed-point twin
    (:mod:`wake.rtp.fixed_voluntary`), which the switch carries ``w_h`` into.  Until an HPA installs a ``w_h``
    it is the one-step prediction held.

    Examples
    --------
    >>> from wake.wavelets import filter_bank_taps
    >>> rtp = AdaptiveRTP(filter_bank_taps("sym3", 5, "periodization"), np.full(5, 0.2), 1.0,
    ...                   backend="reference")
    >>> rtp.on_c, round(float(rtp.run(np.ones(40))[-1]), 6)
    (False, 1.0)
    """

    def __init__(self, taps, weights, measurement_noise, process_noise=0.0, initial_covariance=0.0, *,
                 backend="c", full_scale=None, headroom=16.0, fs=100.0):
        self.core = ReferenceRTP(taps, weights, measurement_noise, process_noise, initial_covariance, fs=fs)
        self.fs = fs
        self.backend = backend
        self.fixed_full_scale = full_scale     # given by the user: never moved
        self.initial_covariance = initial_covariance
        self.on_c = False
        self.full_scale = full_scale
        self.policy = FullScalePolicy(headroom=headroom)
        self.full_scale_changes = 0   # rises and falls after the first choice
        self.clipped_before = 0       # the C core's clip count at the last HPA
        self.over_run = 0             # samples in a row beyond the full scale, up to the last one
        self.over_peak = 0.0          # their largest magnitude
        if backend == "c" and full_scale is not None:
            self._switch_to_c(full_scale, measurement_noise, process_noise)

    # -- the ordinary RTP interface ---------------------------------------------------
    @property
    def level(self) -> int:
        return self.core.level

    @property
    def primed(self) -> bool:
        return self.core.primed

    @property
    def measurement_noise(self) -> float:
        return self.core.measurement_noise

    @property
    def last_ahead(self) -> tuple:
        """``(predicted, confidence, command)`` after the last sample (see :mod:`wake.ahead`)."""
        return self.core.last_ahead

    def set_ahead(self, coefficients, goal) -> None:
        """Install a tremor-ahead predictor and gate goal (the delay line and the gate carry over)."""
        self.core.set_ahead(coefficients, goal)

    @property
    def last_voluntary_ahead(self) -> float:
        """The voluntary motion predicted ``h`` samples ahead after the last sample (the one-step prediction,
        held, until a ``w_h`` is installed)."""
        if not self.on_c or self.core.has_weights_ahead:
            return self.core.last_voluntary_ahead
        return float(getattr(self, "last_prediction", self.core.last_output))   # what step / run returned last

    def set_weights_ahead(self, weights_ahead) -> None:
        """Install ``w_h`` in the core, float or C (None: keep the one it has)."""
        if weights_ahead is not None:
            self.core.set_weights_ahead(weights_ahead)

    def step(self, sample: float) -> float:
        """One sample (NaN: missing) through the overflow rule and the RTP; the prediction of the next."""
        if sample != sample:
            self.over_run = 0
            self.last_prediction = self.core.step_missing()
            return self.last_prediction
        if self.on_c and self.fixed_full_scale is None:   # the full scale follows the signal
            if abs(sample) > self.full_scale:
                self.over_run += 1
                self.over_peak = max(self.over_peak, abs(sample))
                if self.over_run >= RAISE_AFTER:
                    self._raise(self.over_peak)
            else:
                self.over_run, self.over_peak = 0, 0.0
        self.last_prediction = self.core.step(sample)
        return self.last_prediction

    def step_missing(self) -> float:
        """A missing sample: the RTP predicts through it (:meth:`step` of NaN)."""
        return self.step(float("nan"))

    def run(self, x) -> np.ndarray:
        """:meth:`step` over a block, bit for bit (the overflow rule found per block, not per sample)."""
        return self._run(x)[0]

    def run_ahead(self, x) -> tuple:
        """:meth:`run` with the tremor ahead: ``(voluntary, predicted, confidence, command)``, as a loop of
        :meth:`step` and :attr:`last_ahead`."""
        return tuple(self._run(x)[:4])

    def run_outputs(self, x) -> np.ndarray:
        """``(5, n)``: :meth:`run_ahead`'s four rows and :attr:`last_voluntary_ahead` after each sample."""
        return self._run(x)

    def _core_run(self, x) -> np.ndarray:
        """``(5, n)``: the core's voluntary outputs, tremor ahead and voluntary motion ahead over ``x`` (no
        full-scale move)."""
        if self.on_c:
            return self.core._run_block(x, all_outputs=True)   # the C core's rows, already one (5, n) array
        return np.array(self.core.run_outputs(x))

    def _run(self, x) -> np.ndarray:
        y = self._run_block(x)
        if y.shape[1]:
            self.last_prediction = float(y[0, -1])
        return y

    def _run_block(self, x) -> np.ndarray:
        if not (self.on_c and self.fixed_full_scale is None):
            return self._core_run(x)
        n = x.shape[0]
        y = np.empty((5, n))
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
                y[:, start:stop] = self._core_run(x[start:stop])
                self._raise(peak)
                y[:, stop] = self._core_run(x[stop : stop + 1])[:, 0]
                start = stop + 1
            else:
                y[:, start:] = self._core_run(x[start:])
                self.over_run, self.over_peak = run, peak
                start = n
        return y

    def set_weights(self, weights, measurement_noise, process_noise=None) -> None:
        self.core.set_weights(weights, measurement_noise, process_noise)

    def reset(self) -> None:
        self.core.reset()

    # -- at an HPA --------------------------------------------------------------------
    def install(self, weights, measurement_noise: float, process_noise: float, window, peak=None) -> tuple:
        """New weights, R and q between two samples, after the full-scale policy has seen ``window`` (``peak``:
        its robust peak, :func:`~wake.rtp.full_scale.robust_peak`, when the caller has it).

        On the C core R and q are clamped into its formats (:attr:`measurement_noise` then reads what was
        installed).  Returns the notes for the HPA history (``"clipping"``, ``"full_scale_set"``, ...,
        ``"noise_clamped"``).
        """
        notes = self._revise(window, measurement_noise, process_noise, peak) if self.backend == "c" else ()
        if self.on_c:
            if self.core.set_weights_clamped(weights, measurement_noise, process_noise):
                notes += ("noise_clamped",)
        else:
            self.core.set_weights(weights, measurement_noise, process_noise)
        return notes

    def _revise(self, window, measurement_noise, process_noise, peak=None) -> tuple:
        """Apply the full-scale policy (:mod:`wake.rtp.full_scale`) to the window the HPA saw.

        The C path starts at the first window that is not quiet (until then the
        float reference runs); later windows raise or lower the full scale. A
        full scale given in the configuration is kept as it is.
        """
        notes = ()
        if self.on_c:
            clipped = self.core.clipped - self.clipped_before
            self.clipped_before = self.core.clipped
            if clipped > GLITCH_SHARE * len(window):
                notes += ("clipping",)
                warnings.warn(
                    f"{clipped} of the last {len(window)} samples were clipped at the fixed-point full scale "
                    f"±{self.full_scale:g}"
                    + (" (raise full_scale, or leave it None to let it follow the signal)"
                       if self.fixed_full_scale is not None else "; the full scale follows at this HPA"),
                    ClippingWarning, stacklevel=4)
        if self.fixed_full_scale is not None:
            return notes
        full_scale, reason = self.policy.decide(self.full_scale if self.on_c else None, window, peak)
        if reason is None:
            return notes
        if not self.on_c:
            self._switch_to_c(full_scale, measurement_noise, process_noise)
            self.clipped_before = self.core.clipped
        else:
            self._rescale(full_scale)
        return notes + (reason,)

    # -- full-scale moves ---------------------------------------------------------------
    def _switch_to_c(self, full_scale: float, measurement_noise: float, process_noise: float) -> None:
        from wake.rtp import load_fixed_point

        reference = self.core
        self.core, _ = load_fixed_point().FixedPointRTP.from_reference(
            reference, full_scale=full_scale, measurement_noise=measurement_noise,
            process_noise=process_noise, initial_covariance=self.initial_covariance)
        self.on_c = True
        self.full_scale = full_scale

    def _raise(self, peak: float) -> None:
        """Rise to the power of two at or above ``headroom`` x ``peak`` before the next sample."""
        full_scale = power_of_two_at_least(self.policy.headroom * peak)
        if full_scale > self.full_scale:
            self._rescale(full_scale)
            self.policy.quiet_windows = 0
        self.over_run, self.over_peak = 0, 0.0

    def _rescale(self, full_scale: float) -> None:
        """Move the C core to ``full_scale`` between two samples (state carried, counted)."""
        self.core, _ = self.core.rescaled(full_scale)
        self.full_scale = full_scale
        self.full_scale_changes += 1
        self.clipped_before = self.core.clipped

    # -- state ----------------------------------------------------------------------------
    def state(self) -> AdaptiveRTPState:
        return AdaptiveRTPState(copy.deepcopy(self.core), self.on_c, self.full_scale, self.policy.quiet_windows,
                                self.full_scale_changes, self.clipped_before, self.over_run, self.over_peak)

    def load(self, state: AdaptiveRTPState) -> None:
        self.core = copy.deepcopy(state.core)
        self.on_c, self.full_scale = state.on_c, state.full_scale
        self.policy.quiet_windows = state.quiet_windows
        self.full_scale_changes, self.clipped_before = state.full_scale_changes, state.clipped_before
        self.over_run, self.over_peak = state.over_run, state.over_peak
        self.__dict__.pop("last_prediction", None)   # not in the state: the core's last output stands in
        # a state saved before the tremor ahead existed: it starts with no predictor, the gate shut
        if not self.on_c and not hasattr(self.core, "ahead"):
            self.core.start_ahead(self.fs)
