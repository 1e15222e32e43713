"""The tremor ahead: what an actuator is sent for sample ``n + h``, and the gate that says when to send it.

One definition, read by every place that predicts the tremor ahead: the HPA
fits the predictor and scores the previous one (:func:`fit_predictor`,
:func:`held_out_gain`, :func:`gate_target`), the float reference and the C
core run it per sample (:class:`AheadStep`, the twin of the C code), and the
evaluation scores it.  The design and the numbers behind every constant are
in docs/studies/design.md, "Tremor ahead (issue 32)" (``python bench/tremor_ahead.py``).

Per HPA window (``y``: WAKE's own tremor estimate ``x - voluntary`` over the
window; ``T``: the window's sharp high-pass tremor truth, the same samples)::

    c    = argmin sum_k (T(k + h) - c . y(k .. k-p+1))^2 + lam |c|^2      direct h-step Wiener predictor
    lam  = RIDGE * trace(G) / p,  G = Y'Y                                 ridge relative to the Gram diagonal
    gain = <T, P> / <P, P> over the samples new since the previous HPA,   P: the previous model's predictions
           clipped to [0, 1]                                               (held out: it was not fitted on them)
    goal = gain, or 0 when the window has no tremor peak                  (cut-off flag in NO_TREMOR_FLAGS)

Per sample (``y(n)``: the newest tremor estimate)::

    P(n)       = c . y(n .. n-p+1)                                         the tremor predicted for n + h
    g(n)       = g(n-1) + (goal - g(n-1)) / max(1, tau fs)                 the gate, a first-order ramp
    command(n) = g(n) P(n)                                                 what the actuator plays at n + h

Examples
--------
>>> import numbers

import numpy as np
>>> from wake.ahead import fit_predictor, AheadStep
>>> t = np.arange(500) / 100.0
>>> tremor = np.sin(2 * np.pi * 6.0 * t)
>>> c = fit_predictor(tremor, tremor, horizon=5)
>>> step = AheadStep(c, fs=100.0)
>>> step.set_goal(1.0)
>>> for v in tremor[:400]:
...     predicted, confidence, command = step.step(v)
>>> bool(abs(predicted - tremor[404]) < 0.05), round(confidence, 3)
(True, 1.0)
"""

from __future__ import annotations

import functools
import numbers

import numpy as np

__all__ = ["TAPS", "MAX_HORIZON", "RIDGE", "GATE_TAU_S", "NO_TREMOR_FLAGS", "MIN_HELD_OUT", "COEFFICIENT_LIMIT",
           "fit_predictor", "fit_rows", "lagged",
           "predictions", "held_out_gain", "held_out_pairs", "scale_gain", "gate_target", "check_model", "ramp_step", "horizon_from_ms", "check_horizon", "bank_horizon",
           "AheadStep"]

#: Taps of the direct predictor: the knee on the synthetic set, as good as any order on PADS.
TAPS = 8

#: The longest horizon in samples (``WakeConfig.horizon``, the C HPA's ``horizon``): 320 ms at 100 Hz.
MAX_HORIZON = 32

#: Ridge of the least squares, relative to the mean diagonal of the Gram matrix.
RIDGE = 1e-3

#: Time constant of the gate's ramp in seconds: no step an actuator would feel, and the gate still opens
#: within a tremor burst.
GATE_TAU_S = 0.3

#: Cut-off flags of a window without a tremor peak in the tremor band: nothing to predict, the gate shuts.
NO_TREMOR_FLAGS = ("no_tremor_peak", "silent")

#: Fewer held-out samples than this give no evidence: the gate's goal is 0.
MIN_HELD_OUT = 10

#: Each coefficient is clipped to +-this (a fixed-point range for the C core).  On the ten PADS recordings
#: and the paper's synthetic set, every HPA window at h = 1, 2, 5, 10, 20 gives |c| <= 3.5 (99th
#: percentile 2.3) and sum |c| <= 14.1: the clip only bounds a degenerate window.
COEFFICIENT_LIMIT = 8.0


@functools.lru_cache(maxsize=None)
def identity(n: int) -> np.ndarray:
    """``np.eye(n)``, read-only and made once per size (a fit adds it per window)."""
    eye = np.eye(n)
    eye.flags.writeable = False
    return eye


def lagged(s, taps: int = TAPS):
    """Rows ``[s[k], ..., s[k-taps+1]]`` for every ``k`` (zeros before the start), newest first; of each row of (W, n)."""
    s = np.asarray(s, dtype=float)
    pad = np.concatenate((np.zeros(s.shape[:-1] + (taps - 1,)), s), axis=-1)
    # sliding_window_view(pad, taps), read-only, built directly (the helper's checks cost 7x the view); a stack (W, n)
    rows = np.ndarray(s.shape + (taps,), pad.dtype, pad, 0, pad.strides[:-1] + (pad.itemsize, pad.itemsize))
    rows.flags.writeable = False
    return rows[..., ::-1]


def fit_pair(estimate, truth, horizon: int):
    """``estimate`` and ``truth`` as float arrays, checked for a fit ``horizon`` samples ahead: both 1-D and of
    one length (or stacks of them, one series per row), ``horizon`` at least 1 (the rule of every predictor's fit)."""
    y = np.asarray(estimate, dtype=float)
    t = np.asarray(truth, dtype=float)
    if y.shape != t.shape or y.ndim not in (1, 2):
        raise ValueError(f"estimate and truth must be 1-D (or stacks, 2-D) and of one length: {y.shape}, {t.shape}")
    if horizon < 1:
        raise ValueError(f"horizon must be at least 1 sample, got {horizon}")
    return y, t


def fit_predictor(estimate, truth, horizon: int, taps: int = TAPS, ridge: float = RIDGE):
    """The direct ``horizon``-step predictor from WAKE's tremor estimate to the tremor truth.

    Parameters
    ----------
    estimate, truth : array_like, shape (n,) or (W, n)
        The tremor estimate and the tremor truth of the same samples, oldest first (a stack: one fit per row).
    horizon : int
        Samples ahead, >= 1.
    taps, ridge : int, float
        Order and relative ridge (:data:`TAPS`, :data:`RIDGE`).

    Returns
    -------
    numpy.ndarray, shape (taps,)
        ``c``, newest estimate first: ``truth[k + horizon] ~ c . estimate[k], ..., estimate[k - taps + 1]``,
        fitted on every ``k`` with a full history inside the window, each clipped to +-:data:`COEFFICIENT_LIMIT`.
        Zeros when the window has fewer than two such rows, or no power.  A stack gives shape (W, taps).
    """
    y, t = fit_pair(estimate, truth, horizon)
    return fit_rows(lagged(y, taps)[..., taps - 1:y.shape[-1] - horizon, :], t[..., taps - 1 + horizon:], ridge)


def fit_rows(rows, target, ridge: float = RIDGE):
    """The predictor's ridge least squares on given rows: what :func:`fit_predictor` solves.

    Parameters
    ----------
    rows : array_like, shape (m, taps) or (W, m, taps)
        Lagged estimates, newest first (rows of :func:`lagged`); a stack: one fit per series, shape (W, taps).
    target : array_like, shape (m,) or (W, m)
        The truth each row predicts.
    ridge : float
        Relative to the Gram matrix's mean diagonal (:data:`RIDGE`).

    Returns
    -------
    numpy.ndarray, shape (taps,)
        The coefficients, each clipped to +-:data:`COEFFICIENT_LIMIT`; zeros with fewer than two rows or no power.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.ahead import fit_rows, lagged
    >>> s = np.sin(0.3 * np.arange(200))
    >>> c = fit_rows(lagged(s, 2)[1:-1], s[2:], ridge=1e-9)   # s[k+1] = 2 cos(0.3) s[k] - s[k-1]
    >>> bool(np.allclose(c, [2 * np.cos(0.3), -1.0], atol=1e-4))
    True
    """
    X, target = np.asarray(rows, dtype=float), np.asarray(target, dtype=float)
    if X.ndim == 2:   # one series: a stack of one (the batched calls are BLAS's and LAPACK's per series)
        return fit_rows(X[None], target[None], ridge)[0]
    c = np.zeros(X.shape[::2])
    if X.shape[1] < 2:
        return c
    G = (Xt := np.swapaxes(X, 1, 2)) @ X
    scale = np.trace(G, axis1=1, axis2=2) / X.shape[2]
    ok = scale > 0   # a series without power: zeros
    if ok.any():
        G, rhs = G[ok] + (ridge * scale[ok])[:, None, None] * identity(X.shape[2]), (Xt @ target[:, :, None])[ok]
        c[ok] = np.linalg.solve(G, rhs)[:, :, 0]
    return np.clip(c, -COEFFICIENT_LIMIT, COEFFICIENT_LIMIT)


def predictions(estimate, coefficients):
    """``P[k] = c . estimate[k .. k-p+1]`` for every ``k`` (zeros before the start of ``estimate``)."""
    c = np.asarray(coefficients, dtype=float)
    return lagged(estimate, c.size) @ c


def held_out_gain(estimate, truth, previous, horizon: int, new_samples: int) -> float:
    """The least-squares scale of the previous model's predictions on samples it was not fitted on.

    Parameters
    ----------
    estimate, truth : array_like, shape (n,)
        This window's tremor estimate and truth (the same samples, oldest first).
    previous : array_like or None
        The previous HPA's coefficients; ``None`` for the first HPA (nothing to score: 0).
    horizon : int
        Samples ahead.
    new_samples : int
        Samples this window adds since the previous HPA: the targets scored are the last ``new_samples``
        of the window whose prediction had a full history inside it.

    Returns
    -------
    float
        ``<T, P> / <P, P>`` clipped to [0, 1]: 1 when the predictor carries over, below 1 when it
        over-shoots, 0 when it is uncorrelated or anti-correlated, or with fewer than
        :data:`MIN_HELD_OUT` samples to score.
    """
    pairs = held_out_pairs(estimate, truth, previous, horizon, new_samples)
    return 0.0 if pairs is None else scale_gain(*pairs)


def held_out_pairs(estimate, truth, previous, horizon: int, new_samples: int):
    """What :func:`held_out_gain` scores: the previous model's predictions and the truth they predict.

    Parameters are those of :func:`held_out_gain`.  Returns ``(predictions, targets)``, two arrays of the held-out
    samples, or None when there is no previous model or fewer than :data:`MIN_HELD_OUT` samples to score.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.ahead import held_out_pairs
    >>> p, t = held_out_pairs(np.ones(50), np.ones(50), [0.5, 0.5], horizon=1, new_samples=20)
    >>> p.size, float(p[0]), held_out_pairs(np.ones(50), np.ones(50), None, 1, 20)
    (20, 1.0, None)
    """
    if previous is None:
        return None
    y = np.asarray(estimate, dtype=float)
    t = np.asarray(truth, dtype=float)
    c = np.asarray(previous, dtype=float)
    first_target = max(y.size - int(new_samples), c.size - 1 + horizon)
    if y.size - first_target < MIN_HELD_OUT:
        return None
    return predictions(y, c)[first_target - horizon:y.size - horizon], t[first_target:]


def scale_gain(p, target) -> float:
    """``<target, p> / <p, p>`` clipped to [0, 1]; 0 when ``p`` has no power."""
    pp = float(p @ p)
    g = float(target @ p) / pp if pp > 0 else 0.0   # clipped as np.clip (NaN, -0.0 kept), without its 4 us of wrappers
    return g if g != g or 0.0 <= g <= 1.0 else (0.0 if g < 0.0 else 1.0)


def check_model(coefficients, goal):
    """A predictor and a gate goal as an RTP takes them, validated: ``(float64 array (TAPS,), float)``.

    The coefficients are :data:`TAPS` finite numbers within +-:data:`COEFFICIENT_LIMIT` (what
    :func:`fit_predictor` gives; the C core's Q27 holds no more), newest estimate first; the goal a
    number in [0, 1].

    Examples
    --------
    >>> check_model([0.5] * 8, 1)[1]
    1.0
    >>> check_model([0.5] * 8, 2)
    Traceback (most recent call last):
    ...
    ValueError: the gate's goal must be a number in [0, 1], got 2
    """
    c = np.array(coefficients, dtype=float).reshape(-1)
    if c.shape != (TAPS,) or not np.isfinite(c).all():
        raise ValueError(f"the tremor-ahead predictor must be {TAPS} finite coefficients (newest estimate "
                         f"first), got {coefficients!r}")
    if np.abs(c).max() > COEFFICIENT_LIMIT:
        raise ValueError(f"tremor-ahead coefficients must lie within +-{COEFFICIENT_LIMIT:g} "
                         f"(wake.ahead.fit_predictor clips to it), got max |c| {np.abs(c).max():.6g}")
    try:
        g = float(goal)
    except (TypeError, ValueError):
        raise ValueError(f"the gate's goal must be a number in [0, 1], got {goal!r}") from None
    if not 0.0 <= g <= 1.0:
        raise ValueError(f"the gate's goal must be a number in [0, 1], got {goal!r}")
    return c, g


def gate_target(gain: float, cutoff_flag: str) -> float:
    """The gate's goal after an HPA: the held-out gain, or 0 when the window has no tremor peak."""
    return 0.0 if cutoff_flag in NO_TREMOR_FLAGS else float(gain)


#: What installing an HPA's result may find (:meth:`wake.rtp.adaptive.AdaptiveRTP.install`) that shuts the gate
#: until the next HPA: more than ``GLITCH_SHARE`` of the window clipped at the C core's full scale, so the
#: estimate the predictor reads was cut and its held-out gain measured on a cut estimate.
SHUTTING_NOTES = ("clipping",)


def installed_goal(goal: float, notes) -> float:
    """The goal the gate is given at an HPA: the HPA's own (:func:`gate_target`), or 0 when installing it
    noted one of :data:`SHUTTING_NOTES`.

    Examples
    --------
    >>> installed_goal(0.8, ("full_scale_set",)), installed_goal(0.8, ("clipping", "full_scale_raised"))
    (0.8, 0.0)
    """
    return 0.0 if any(note in SHUTTING_NOTES for note in notes) else float(goal)


def ramp_step(fs: float, tau_s: float = GATE_TAU_S) -> float:
    """The gate's ramp coefficient ``1 / max(1, tau fs)``."""
    return 1.0 / max(1.0, tau_s * fs)


def check_horizon(horizon, fs: float, decimation: int = 1) -> int:
    """``horizon`` in input samples, validated: an integer in 1..``MAX_HORIZON * decimation`` (the filter
    bank predicts :func:`bank_horizon` of its own samples, at most :data:`MAX_HORIZON`).

    Examples
    --------
    >>> check_horizon(50, 1000.0, 10)
    50
    >>> check_horizon(33, 100.0)
    Traceback (most recent call last):
    ...
    ValueError: horizon must be an integer number of samples in [1, 32] at 100 Hz (32 samples of the filter bank's rate), got 33
    """
    top = MAX_HORIZON * decimation
    if isinstance(horizon, bool) or not isinstance(horizon, numbers.Real) or not float(horizon).is_integer() \
            or not 1 <= horizon <= top:
        raise ValueError(f"horizon must be an integer number of samples in [1, {top}] at {fs:g} Hz "
                         f"({MAX_HORIZON} samples of the filter bank's rate), got {horizon!r}")
    return int(horizon)


def bank_horizon(horizon: int, decimation: int) -> int:
    """The horizon at the bank's rate, for an input ``decimation`` times faster: ``horizon / decimation``
    rounded to the nearest sample (halves up), at least 1.

    Examples
    --------
    >>> bank_horizon(50, 10), bank_horizon(5, 10), bank_horizon(4, 10), bank_horizon(7, 1)
    (5, 1, 1, 7)
    """
    return max(1, (2 * int(horizon) + int(decimation)) // (2 * int(decimation)))


def horizon_from_ms(horizon_ms: float, fs: float, max_samples: int | None = None) -> int:
    """The horizon in samples of ``horizon_ms`` milliseconds at ``fs`` Hz, rounded to the nearest sample
    (halves up); ``ValueError`` outside 1..``max_samples`` samples (by default :data:`MAX_HORIZON` samples
    of the bank rate: ``MAX_HORIZON * D`` at an input rate ``D`` times it), naming the range in ms.

    Examples
    --------
    >>> horizon_from_ms(50, 100.0), horizon_from_ms(25, 100.0), horizon_from_ms(20, 128.0)
    (5, 3, 3)
    >>> horizon_from_ms(50, 1000.0)   # 5 samples of the bank's 100 Hz
    50
    """
    if max_samples is None:
        from wake.sampling import decimation_for

        max_samples = MAX_HORIZON * decimation_for(fs)
    ms = float(horizon_ms)
    samples = int(np.floor(ms * fs / 1000.0 + 0.5)) if np.isfinite(ms) else 0
    if not 1 <= samples <= max_samples:
        raise ValueError(f"a horizon of {ms:g} ms is {ms * fs / 1000.0:g} samples at {fs:g} Hz; it must "
                         f"round to 1..{max_samples} samples: {500.0 / fs:g} to "
                         f"<{(max_samples + 0.5) * 1000.0 / fs:g} ms")
    return samples


class AheadStep:
    """The per-sample half in float64: a delay line of tremor estimates, the FIR and the gate.

    Parameters
    ----------
    coefficients : array_like, shape (taps,)
        The predictor, newest estimate first (:func:`fit_predictor`).
    fs : float
        Sampling rate in Hz (sets the ramp, :func:`ramp_step`).
    tau_s : float
        The ramp's time constant.

    Examples
    --------
    >>> step = AheadStep([0.5, 0.5], fs=100.0)
    >>> step.step(1.0)
    (0.5, 0.0, 0.0)
    """

    def __init__(self, coefficients, fs: float, tau_s: float = GATE_TAU_S):
        self.coefficients = np.asarray(coefficients, dtype=float).copy()
        self.history = np.zeros(self.coefficients.size)
        self.alpha = ramp_step(fs, tau_s)
        self.goal = 0.0
        self.gate = 0.0

    def set_model(self, coefficients, goal: float):
        """Install an HPA's predictor and gate goal (the delay line and the gate's value carry over)."""
        c = np.asarray(coefficients, dtype=float)
        if c.shape != self.coefficients.shape:
            raise ValueError(f"expected {self.coefficients.size} coefficients, got shape {c.shape}")
        self.coefficients = c.copy()
        self.set_goal(goal)

    def set_goal(self, goal: float):
        """Set the gate's goal, clipped to [0, 1] (0 shuts it: after a gap, a reset, or no tremor peak)."""
        self.goal = float(np.clip(goal, 0.0, 1.0))

    def step(self, estimate: float):
        """Take the newest tremor estimate; return ``(predicted, confidence, command)`` for ``n + h``."""
        self.history[1:] = self.history[:-1]
        self.history[0] = estimate
        predicted = float(self.coefficients @ self.history)
        self.gate += self.alpha * (self.goal - self.gate)
        return predicted, self.gate, self.gate * predicted
