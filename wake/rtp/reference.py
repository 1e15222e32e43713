"""Float reference of the real-time prediction (RTP) scheme.

This module is the oracle the fixed-point C core (``csrc/wake_rtp.c``) is
tested against; the two are written line for line alike.  One
:class:`ReferenceRTP` is one channel's state, the twin of the C struct
``wake_rtp_t``.

The per-sample recursion (docs/studies/design.md maps each line onto the paper)::

    buffer <- newest sample                      m_J(n), a ring of 2**J samples
    e      = m(n) - y(n-1)                       innovation, eq. (r(k))
    u      = P w                                 (P restarts as (w'Pw / w'w) I when w changes)
    S      = w' u + R                            eq. (S(k))
    K      = u / S                               eq. (K(k))
    d      = d + K e                             state update
    P      = P - u u' / S + Q I                  eq. (P(k|k)), then the F = I prediction
    a      = B m_J(n)                            J-level filter bank
    y(n)   = w' (a + d)                          predicted voluntary motion at n + 1
    v_h(n) = w_h' (a + d)                        predicted voluntary motion at n + h (horizon h > 1)

and beside it the tremor ahead (:class:`wake.ahead.AheadStep`, in attribute
``ahead``): the newest tremor estimate ``e(n) = m(n) - y(n-1)`` (0 for the
first sample and for a missing one) enters an 8-long delay line, ``P(n)`` is
the tremor predicted for ``n + h``, the gate ramps towards the goal the HPA
set (:meth:`ReferenceRTP.set_ahead`), and ``last_ahead`` holds
``(P(n), gate, gate * P(n))``.  The voluntary output does not read it.

The voluntary motion ahead reads the state of the one-step prediction through
a second weight vector ``w_h`` (:meth:`ReferenceRTP.set_weights_ahead`, from
the HPA): ``last_voluntary_ahead`` is ``w_h' (a + d)``, and ``y(n)`` itself
until a ``w_h`` is installed (the one-step prediction held).  The Kalman
update reads ``w`` only, so ``y`` is the same with or without ``w_h``.

The Kalman state is ``x = a + d``: the filter-bank approximations ``a`` (the
paper's state, eq. KFState) plus a correction ``d`` that the scalar
measurement ``m`` observes through ``w``.  Storing ``d`` rather than ``x``
keeps the recursion free of the difference ``a(n) - a(n-1)`` and makes the
innovation the plain prediction error ``m(n) - y(n-1)``.
"""

from __future__ import annotations

import numpy as np

from wake.ahead import TAPS, AheadStep, check_model
from wake.wavelets import sliding_rows

__all__ = ["ReferenceRTP"]


# The two sums below run in a fixed order (one tap, one level at a time), the
# same for one sample and for a block, so that run() and a loop of step()
# agree to the bit; a BLAS product would sum in an order that depends on the
# shapes.

_BANK_ROWS = 2048   # windows per multiply-and-reduce of _filter_bank (its products: 1.35 MB at J = 5)


def _filter_bank(windows, taps):
    """a_j = sum_i B[j, i] m(n - N + 1 + i), oldest sample first; one row per window: every tap's product below a
    row of zeros, reduced along that outer axis (numpy adds one row at a time there, ((0 + p_0) + p_1) + ...:
    the order that keeps step() and run() equal to the bit), two numpy calls per _BANK_ROWS windows."""
    n = windows.shape[0]
    acc = np.empty((n, taps.shape[0]))
    prod = np.zeros((taps.shape[1] + 1, min(n, _BANK_ROWS), taps.shape[0]))
    for start in range(0, n, _BANK_ROWS):
        rows = windows[start : start + _BANK_ROWS]
        np.multiply(rows.T[:, :, None], taps.T[:, None, :], out=prod[1:, : rows.shape[0]])
        np.add.reduce(prod[:, : rows.shape[0]], axis=0, out=acc[start : start + rows.shape[0]])
    return acc


def _weighted_sum(w, values):
    """sum_j w_j values_j, along the first axis of ``values``."""
    acc = w[0] * values[0]
    for j in range(1, w.shape[0]):
        acc = acc + w[j] * values[j]
    return acc


class ReferenceRTP:
    """One channel of the RTP in float64.

    Parameters
    ----------
    taps : array_like, shape (J, 2**J)
        Filter bank taps, oldest sample first (:func:`wake.wavelets.filter_bank_taps`).
    weights : array_like, shape (J,)
        Observation vector ``w`` from the HPA.
    measurement_noise : float
        ``R``, the variance of the HPA's tremor ground truth (> 0).
    process_noise : float
        ``Q = q I`` per sample (>= 0).
    initial_covariance : float
        ``P(0) = p0 I`` (>= 0).
    fs : float
        Sampling rate in Hz: the tremor-ahead gate's ramp (:func:`wake.ahead.ramp_step`).

    Examples
    --------
    >>> import numpy as np
    >>> from wake.wavelets import filter_bank_taps
    >>> from wake.rtp.reference import ReferenceRTP
    >>> rtp = ReferenceRTP(filter_bank_taps("sym3", 3), [0, 0, 1], 1.0)
    >>> [round(rtp.step(1.0), 6) for _ in range(3)]   # a constant is predicted exactly
    [1.0, 1.0, 1.0]
    >>> rtp.set_ahead(np.r_[1.0, np.zeros(7)], 1.0)    # the tremor ahead: the newest estimate, gate open
    >>> _ = rtp.step(1.5); [round(v, 3) for v in rtp.last_ahead]   # (predicted, confidence, command)
    [0.5, 0.033, 0.017]
    """

    def __init__(self, taps, weights, measurement_noise, process_noise=0.0, initial_covariance=0.0, *,
                 fs=100.0):
        taps = np.array(taps, dtype=float)
        if taps.ndim != 2 or taps.shape[1] != 2 ** taps.shape[0]:
            raise ValueError(f"taps must have shape (J, 2**J), got {taps.shape}")
        self.level = taps.shape[0]
        self.n_taps = taps.shape[1]
        self.taps = taps
        self.initial_covariance = float(initial_covariance)
        self.weights = np.zeros(self.level)
        self.measurement_noise = 1.0
        self.process_noise = 0.0
        self.set_weights(weights, measurement_noise, process_noise)
        self.weights_ahead = None
        self.start_ahead(fs)
        self.reset()

    # -- configuration -----------------------------------------------------
    def set_weights(self, weights, measurement_noise, process_noise=None):
        """Install new HPA output between two samples.

        The window, ``d`` and the last output are kept.  The covariance
        restarts isotropic at the variance it held along the direction it
        observed: ``P = (w_old' P w_old / |w_old|^2) I`` (the largest ``P_ii``
        when ``w_old = 0``; docs/studies/design.md, "Covariance at a weight change").
        """
        w = np.array(weights, dtype=float).reshape(-1)
        if w.shape != (self.level,) or not np.isfinite(w).all():
            raise ValueError(f"weights must be {self.level} finite numbers, got {weights!r}")
        r = float(measurement_noise)
        if not np.isfinite(r) or r <= 0:
            raise ValueError(f"measurement_noise R must be finite and > 0, got {measurement_noise!r}")
        q = self.process_noise if process_noise is None else float(process_noise)
        if not np.isfinite(q) or q < 0:
            raise ValueError(f"process_noise Q must be finite and >= 0, got {process_noise!r}")
        if hasattr(self, "covariance"):
            self.covariance = self._restarted_covariance()
        self.weights = w
        self.measurement_noise = r
        self.process_noise = q

    def start_ahead(self, fs):
        """A tremor ahead with no predictor and the gate shut (also for a state saved before it existed)."""
        self.ahead = AheadStep(np.zeros(TAPS), fs)
        self._last_ahead = (0.0, 0.0, 0.0)

    def set_ahead(self, coefficients, goal):
        """Install an HPA's tremor-ahead predictor and gate goal between two samples.

        ``coefficients``: 8 finite numbers, newest estimate first; ``goal`` in [0, 1].  The delay line and
        the gate's value carry over.
        """
        self.ahead.set_model(*check_model(coefficients, goal))

    def set_weights_ahead(self, weights_ahead):
        """Install ``w_h``, the weights of the voluntary motion ``h`` samples ahead (None: hold ``y``)."""
        if weights_ahead is None:
            self.weights_ahead = None
            return
        w = np.array(weights_ahead, dtype=float).reshape(-1)
        if w.shape != (self.level,) or not np.isfinite(w).all():
            raise ValueError(f"weights_ahead must be {self.level} finite numbers or None, got {weights_ahead!r}")
        self.weights_ahead = w

    @property
    def last_voluntary_ahead(self) -> float:
        """``w_h' (a + d)`` after the last sample: the voluntary motion predicted ``h`` samples ahead (the
        one-step prediction while no ``w_h`` is installed)."""
        return getattr(self, "_last_voluntary_ahead", self.last_output)

    @property
    def last_ahead(self):
        """``(predicted, confidence, command)`` after the last sample: the tremor predicted for ``n + h``,
        the gate in [0, 1], and their product."""
        return self._last_ahead

    def _restarted_covariance(self):
        """(w' P w / |w|^2) I for the weights in use: P's variance along w, in every direction."""
        P = self.covariance.reshape(self.level, self.level)
        w = self.weights
        omega = float(w @ w)
        variance = float(w @ P @ w) / omega if omega > 0.0 else float(np.diag(P).max())   # as the C core
        return max(variance, 0.0) * np.eye(self.level).reshape(-1)

    def reset(self):
        """Forget every sample; keep taps and weights."""
        self.buffer = np.zeros(self.n_taps)
        self.head = 0                      # index of the oldest sample
        self.primed = False
        self.last_output = 0.0
        self._last_voluntary_ahead = 0.0
        self.correction = np.zeros(self.level)
        self.covariance = self.initial_covariance * np.eye(self.level).reshape(-1)
        self.ahead.history[:] = 0.0
        self.ahead.gate = 0.0
        self.ahead.goal = 0.0
        self._last_ahead = (0.0, 0.0, 0.0)

    # -- per sample ---------------------------------------------------------
    def _push(self, sample):
        if not self.primed:
            # Warm-up: the window starts full of the first sample, so the
            # filter bank output is defined (and finite) from the first call.
            self.buffer[:] = sample
            self.last_output = sample
            self.primed = True
        self.buffer[self.head] = sample
        self.head = (self.head + 1) % self.n_taps

    def _measurement_update(self, sample):
        w = self.weights
        P = self.covariance.reshape(self.level, self.level)
        # e = m(n) - y(n-1)
        e = sample - self.last_output
        # u = P w
        u = P @ w
        # S = w' u + R
        s = self.measurement_noise + w @ u
        # d = d + K e, with K = u / S
        self.correction += u * (e / s)
        # P = P - u u' / S   (symmetric by construction: C fills the upper triangle and mirrors it)
        P -= np.outer(u, u) / s

    def _time_update(self):
        # P = P + Q I   (F = I)
        self.covariance[:: self.level + 1] += self.process_noise

    def _filter_bank(self):
        window = np.concatenate((self.buffer[self.head :], self.buffer[: self.head]))
        return _filter_bank(window[None, :], self.taps)[0]

    def _predict(self):
        # y = w' (a + d)
        state = self._filter_bank() + self.correction
        y = float(_weighted_sum(self.weights, state))
        self.last_output = y
        # v_h = w_h' (a + d)   (y while no w_h is installed)
        w_h = getattr(self, "weights_ahead", None)
        self._last_voluntary_ahead = y if w_h is None else float(_weighted_sum(w_h, state))
        return y

    def step(self, sample):
        """Take sample ``m(n)``; return the predicted voluntary motion at ``n + 1``."""
        first = not self.primed
        # the tremor estimate e(n) = m(n) - y(n-1) (none before the first prediction)
        estimate = 0.0 if first else sample - self.last_output
        self._push(sample)
        if not first:
            # the first sample had no prediction before it: no innovation, no
            # measurement update (docs/studies/design.md, "What the Kalman state observes")
            self._measurement_update(sample)
        self._time_update()
        y = self._predict()
        self._last_ahead = self.ahead.step(estimate)
        return y

    def step_missing(self):
        """No measurement at ``n`` (NaN or a dropped packet).

        Policy: the last prediction stands in for the sample in the filter
        bank window, and the Kalman filter predicts without a measurement
        update (its covariance grows by ``Q``).  The tremor ahead takes
        estimate 0 and its gate's goal drops to 0 (the held-out gain needs a
        window's worth of samples again).
        """
        self.ahead.set_goal(0.0)
        self._last_ahead = self.ahead.step(0.0)
        if not self.primed:
            return 0.0
        self._push(self.last_output)
        self._time_update()
        return self._predict()

    def run(self, samples):
        """Step through a block; NaN marks a missing sample.

        Same result as calling :meth:`step` / :meth:`step_missing` per
        sample (to rounding), but the filter bank is evaluated for the whole
        block at once and the Kalman recursion is skipped while it is inert
        (``P = 0`` and ``Q = 0``, where it provably leaves ``d`` unchanged).
        The tremor ahead steps too (:meth:`run_ahead` returns it).
        """
        return self._run(np.asarray(samples, dtype=float).reshape(-1))[0]

    def run_outputs(self, samples):
        """:meth:`run_ahead` and the voluntary motion ahead: ``(voluntary, predicted, confidence, command,
        voluntary_ahead)``, the last :attr:`last_voluntary_ahead` after each sample (bit for bit a loop of
        :meth:`step` / :meth:`step_missing`)."""
        out, ahead, vol_ahead = self._run(np.asarray(samples, dtype=float).reshape(-1))
        return out, ahead[:, 0].copy(), ahead[:, 1].copy(), ahead[:, 2].copy(), vol_ahead

    def run_ahead(self, samples):
        """:meth:`run` with the tremor ahead: ``(voluntary, predicted, confidence, command)``, four arrays.

        ``voluntary`` is what :meth:`run` returns; the other three are :attr:`last_ahead` after each
        sample, bit for bit what a loop of :meth:`step` / :meth:`step_missing` gives.
        """
        out, ahead, _ = self._run(np.asarray(samples, dtype=float).reshape(-1))
        return out, ahead[:, 0].copy(), ahead[:, 1].copy(), ahead[:, 2].copy()

    def _run(self, x):
        """The voluntary predictions, the ``(n, 3)`` tremor-ahead outputs and the voluntary motion ahead of
        block ``x``."""
        n = x.shape[0]
        out = np.empty(n)
        ahead = np.empty((n, 3))
        vol_ahead = np.empty(n)
        if n == 0:
            return out, ahead, vol_ahead
        if np.isnan(x).any() or not self.primed:
            # Gaps and the priming sample change the window itself: go sample by sample.
            k = 0
            while k < n and (not self.primed or np.isnan(x[k])):
                out[k] = self.step_missing() if np.isnan(x[k]) else self.step(x[k])
                ahead[k] = self._last_ahead
                vol_ahead[k] = self.last_voluntary_ahead
                k += 1
            if k < n:
                nan_at = np.flatnonzero(np.isnan(x[k:]))
                stop = k + (nan_at[0] if nan_at.size else n - k)
                out[k:stop], ahead[k:stop], vol_ahead[k:stop] = self._run(x[k:stop])
                if stop < n:
                    out[stop:], ahead[stop:], vol_ahead[stop:] = self._run(x[stop:])
            return out, ahead, vol_ahead
        before = self.last_output
        N = self.n_taps
        history = np.concatenate((self.buffer[self.head :], self.buffer[: self.head], x))
        approx = _filter_bank(sliding_rows(history[1:], N), self.taps)
        w = self.weights
        w_h = getattr(self, "weights_ahead", None)
        inert = self.process_noise == 0.0 and not self.covariance.any()
        if inert:
            state = (approx + self.correction).T
            out[:] = _weighted_sum(w, state)
            vol_ahead[:] = out if w_h is None else _weighted_sum(w_h, state)
        else:
            P = self.covariance.reshape(self.level, self.level)
            d = self.correction
            r, q = self.measurement_noise, self.process_noise
            diag = np.arange(self.level)
            y_prev = self.last_output
            for k in range(n):
                u = P @ w
                s = r + w @ u
                d += u * ((x[k] - y_prev) / s)
                P -= np.outer(u, u) / s
                P[diag, diag] += q
                state = approx[k] + d
                y_prev = float(_weighted_sum(w, state))
                out[k] = y_prev
                vol_ahead[k] = y_prev if w_h is None else float(_weighted_sum(w_h, state))
        tail = history[-N:]
        self.buffer[:] = tail
        self.head = 0
        self.last_output = float(out[-1])
        self._last_voluntary_ahead = float(vol_ahead[-1])
        # e(n) = m(n) - y(n-1), the same subtraction as step(); the delay line and the gate go sample by
        # sample, through the one step of wake.ahead
        estimates = x - np.concatenate(([before], out[:-1]))
        _ahead_block(self.ahead, estimates, ahead)
        self._last_ahead = tuple(ahead[-1].tolist())
        return out, ahead, vol_ahead


def _ahead_block(step: AheadStep, estimates, out) -> None:
    """``out[k] = step.step(estimates[k])`` for a block, bit for bit, with less Python per sample: the delay
    line's states as the rows of one strided view (newest first, as :meth:`AheadStep.step` holds them, each
    contiguous: the same dot product, one batched matmul for the block), the gate's recursion on Python floats (the same operations in the same
    order), and the delay line and the gate left as the last step leaves them."""
    c = step.coefficients
    taps, n = c.size, estimates.shape[0]
    newest_first = np.concatenate((estimates[::-1], step.history))   # e[n-1], ..., e[0], then the line
    rows = np.ndarray((n, taps), newest_first.dtype, newest_first, 0,
                      (newest_first.itemsize, newest_first.itemsize))   # rows[j]: the line after e[n-1-j]
    # one (n, 1, taps) @ (taps, 1) matmul: BLAS's dot on each row, np.dot's numbers (a gemv would sum otherwise)
    out[::-1, 0] = (rows[:, None, :] @ c[:, None])[:, 0, 0]
    g, alpha, goal = step.gate, step.alpha, step.goal
    first = g + alpha * (goal - g)
    if first.hex() == g.hex():   # the gate at its goal (shut before an HPA): each step gives it back, bit for bit
        out[:, 1], g = g, first
    else:
        gates = [0.0] * n
        for k in range(n):
            g += alpha * (goal - g)
            gates[k] = g
        out[:, 1] = gates
    np.multiply(out[:, 1], out[:, 0], out=out[:, 2])
    step.history[:] = rows[0]
    step.gate = g
