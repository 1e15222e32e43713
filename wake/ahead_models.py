"""Tremor-ahead predictors beside the filter's own, selectable by name (issue 46).

The filter, the float reference and the C core run one predictor, ``"fir8"`` (:func:`wake.ahead.fit_predictor`,
8 taps); it stays the default everywhere.  Issue 46 asked for a predictor that comes closer to its limit
where tremor is strong and does no harm where it is weak; the candidates are here, under one name each
(:data:`PREDICTORS`, :func:`fit_model`), so that an evaluation can run any of them as the filter runs its
own (:func:`wake.eval.ahead_select.command_with`) and a later change can port the chosen one.  The study that
chose among them: docs/studies/design.md, "Tremor ahead where tremor is strong" (``python bench/strong_ahead.py``).

Beside them, predictors that adapt **per sample** (:data:`ADAPTIVE`, :func:`adaptive_predictor`): the HPA installs
its ``"fir8"`` predictor as the starting point, and between two HPAs the coefficients follow WAKE's own tremor
estimate, whose value at ``n`` becomes known ``horizon`` samples after it was predicted (no truth needed):
``"nlms8"``, normalised LMS on 8 taps (:class:`NLMSPredictor`, about 26 multiply-adds and one division a sample);
``"rls16"``, exponentially weighted RLS on 16 taps (:class:`RLSPredictor`, a ceiling of per-sample adaptation:
about 3 x 16^2 multiply-adds a sample, beyond a microcontroller's step).  The evaluation runs them with
:func:`wake.eval.ahead_select.command_with` as it runs the others.

Examples
--------
>>> import numpy as np
>>> from wake.ahead_models import fit_model
>>> s = np.sin(np.arange(500) / 3.0)
>>> [fit_model(s, s, 2, p).shape for p in ("fir8", "fir40", "order-select")]
[(8,), (40,), (40,)]
"""

from __future__ import annotations

import numpy as np

from wake.ahead import COEFFICIENT_LIMIT, RIDGE, fit_pair, fit_predictor, fit_rows, lagged

__all__ = ["ORDERS", "SELECT_HELD_OUT", "PREDICTORS", "ADAPTIVE", "NLMS_STEP", "RLS_FORGET", "fit_selected",
           "fit_model", "NLMSPredictor", "RLSPredictor", "adaptive_predictor"]

#: Orders :func:`fit_selected` chooses from, per window, by the held-out score.
ORDERS = (8, 16, 24, 40)

#: Share of a window's rows (its newest) on which :func:`fit_selected` scores each order.
SELECT_HELD_OUT = 0.3

#: The predictors :func:`fit_model` knows: ``"fir8"``, today's 8-tap direct predictor (:func:`fit_predictor`,
#: the default everywhere and the C core's); ``"fir40"``, the same with 40 taps (the order of the issue's
#: hindsight limit); ``"order-select"``, :func:`fit_selected`.
PREDICTORS = ("fir8", "fir40", "order-select")


def fit_selected(estimate, truth, horizon: int, orders=ORDERS, ridge: float = RIDGE,
                 held_out: float = SELECT_HELD_OUT):
    """The direct ``horizon``-step predictor with its order chosen on the window's newest rows.

    Each order of ``orders`` is fitted (:func:`fit_rows`) on the oldest ``1 - held_out`` of the window's rows
    and scored on the rest (squared error of its predictions of the truth); the order with the lowest score is
    refitted on every row.  Where tremor is strong and steady a long predictor wins the held-out rows; where it
    is weak or changing the short one does, so a longer order is taken only where it carries over.

    Parameters
    ----------
    estimate, truth : array_like, shape (n,)
        As :func:`fit_predictor`.
    horizon : int
        Samples ahead, >= 1.
    orders : sequence of int
        Candidate orders (each >= 1).
    ridge : float
        As :func:`fit_rows`.
    held_out : float
        In (0, 1).

    Returns
    -------
    numpy.ndarray, shape (max(orders),)
        The chosen predictor, newest estimate first, zero-padded to the longest order (a fixed delay line).

    Examples
    --------
    >>> import numpy as np
    >>> from wake.ahead_models import fit_selected
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(500) / 100.0
    >>> s = np.sin(2 * np.pi * 6 * t) * (1 + 0.3 * np.sin(2 * np.pi * 0.2 * t))
    >>> c = fit_selected(s + 0.05 * rng.standard_normal(500), s, horizon=5)
    >>> c.shape, bool(np.abs(c).max() > 0)
    ((40,), True)
    """
    y, t = fit_pair(estimate, truth, horizon)
    orders = sorted({int(p) for p in orders})
    if not orders or orders[0] < 1:
        raise ValueError(f"orders must be positive integers, got {orders!r}")
    if not 0.0 < held_out < 1.0:
        raise ValueError(f"held_out must lie in (0, 1), got {held_out!r}")
    top = orders[-1]
    out = np.zeros(top)
    rows_all = lagged(y, top)
    first = top - 1                    # every order uses the rows with a full history of the longest one
    X, target = rows_all[first:y.size - horizon], t[first + horizon:]
    if X.shape[0] < 4:
        return out
    cut = int(round(X.shape[0] * (1.0 - held_out)))
    best, best_err = orders[0], np.inf
    for p in orders:
        c = fit_rows(X[:cut, :p], target[:cut], ridge)
        err = float(np.sum((X[cut:, :p] @ c - target[cut:]) ** 2))
        if err < best_err:
            best, best_err = p, err
    out[:best] = fit_rows(X[:, :best], target, ridge)
    return out


def fit_model(estimate, truth, horizon: int, predictor: str = "fir8"):
    """The tremor-ahead predictor of one window by name (:data:`PREDICTORS`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.sin(np.arange(500) / 3.0)
    >>> fit_model(s, s, 2).shape, fit_model(s, s, 2, "order-select").shape
    ((8,), (40,))
    >>> fit_model(s, s, 2, "ar")
    Traceback (most recent call last):
    ...
    ValueError: predictor must be one of ('fir8', 'fir40', 'order-select'), got 'ar'
    """
    if predictor == "fir8":
        return fit_predictor(estimate, truth, horizon)
    if predictor == "fir40":
        return fit_predictor(estimate, truth, horizon, taps=40)
    if predictor == "order-select":
        return fit_selected(estimate, truth, horizon)
    raise ValueError(f"predictor must be one of {PREDICTORS}, got {predictor!r}")


#: The per-sample adaptive predictors :func:`adaptive_predictor` knows (each starts from the HPA's ``"fir8"``).
ADAPTIVE = ("nlms8", "rls16")

#: Step size of :class:`NLMSPredictor` (``"nlms8"``): of 0.02, 0.05, 0.1 and 0.2 the best on the strong set at 20
#: and 50 ms, within 1 % of the best (0.02) on pdkit's tremor axes (``python bench/strong_ahead.py --sweep-nlms``;
#: docs/studies/design.md, "Tremor ahead where tremor is strong").
NLMS_STEP = 0.05

#: Forgetting factor of :class:`RLSPredictor` (``"rls16"``): a memory of about 1 / (1 - 0.995) = 200 samples.
RLS_FORGET = 0.995


class NLMSPredictor:
    """A direct ``horizon``-step predictor of WAKE's tremor estimate adapted per sample by normalised LMS.

    Per sample ``n`` (``Y(n) = [y(n), ..., y(n-p+1)]``, newest first)::

        e    = y(n) - c . Y(n - h)                     the error of the prediction made h samples ago
        c   <- c + mu e Y(n - h) / (eps + |Y(n - h)|^2)     each clipped to +-COEFFICIENT_LIMIT
        P(n) = c . Y(n)                                the tremor predicted for n + h

    :meth:`install` sets ``c`` to an HPA's predictor (the delay line carries over).  The clip is the HPA
    predictor's (:data:`wake.ahead.COEFFICIENT_LIMIT`): a burst or a step cannot drive ``c`` past what the
    fixed-point core holds.

    Parameters
    ----------
    taps : int
        ``p``, at least 1.
    horizon : int
        ``h``, samples ahead, at least 1.
    mu : float
        Step size in (0, 2) (:data:`NLMS_STEP`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.sin(2 * np.pi * 6.0 * np.arange(2000) / 100.0)
    >>> pred = NLMSPredictor(8, horizon=5)
    >>> P = np.array([pred.step(v) for v in s])
    >>> bool(np.abs(P[1500:-5] - s[1505:]).max() < 0.05)
    True
    >>> NLMSPredictor(8, horizon=5, mu=3.0)
    Traceback (most recent call last):
    ...
    ValueError: mu must lie in (0, 2) (normalised LMS is stable there), got 3.0
    """

    def __init__(self, taps: int, horizon: int, mu: float = NLMS_STEP):
        self.taps, self.horizon = check_taps_horizon(taps, horizon)
        if not 0.0 < float(mu) < 2.0:
            raise ValueError(f"mu must lie in (0, 2) (normalised LMS is stable there), got {mu!r}")
        self.mu = float(mu)
        self.coefficients = np.zeros(self.taps)
        self.line = np.zeros(self.taps + self.horizon)   # y(n), ..., y(n - p - h + 1), newest first

    def install(self, coefficients):
        """Start from an HPA's predictor (``coefficients`` newest first, zero-padded or cut to ``taps``)."""
        self.coefficients = padded(coefficients, self.taps)

    def step(self, estimate: float) -> float:
        """Take ``y(n)``; return ``P(n)``, the tremor predicted for ``n + horizon``."""
        self.line[1:] = self.line[:-1]
        self.line[0] = estimate
        past = self.line[self.horizon:]
        e = estimate - self.coefficients @ past
        self.coefficients = np.clip(self.coefficients + self.mu * e * past / (1e-12 + past @ past),
                                    -COEFFICIENT_LIMIT, COEFFICIENT_LIMIT)
        return float(self.coefficients @ self.line[:self.taps])


class RLSPredictor(NLMSPredictor):
    """:class:`NLMSPredictor`'s predictor adapted by exponentially weighted recursive least squares.

    ``k = Q Y(n-h) / (lam + Y(n-h)' Q Y(n-h))``, ``c <- c + k e`` (clipped as :class:`NLMSPredictor`'s),
    ``Q <- (Q - k Y(n-h)' Q) / lam``.  ``Q`` restarts as ``I / delta`` at each :meth:`install` and at the
    first sample whose regressor has power, ``delta`` 1 % of the regressor's mean square: each HPA's
    predictor is a fresh start.  The division by ``lam`` is skipped while the mean diagonal of ``Q`` is above
    its start ``1 / delta``: a narrow-band tremor excites two of the ``p`` directions, and forgetting in the
    others would grow ``Q`` without bound (RLS wind-up).

    Parameters
    ----------
    taps, horizon : int
    forget : float
        ``lam`` in (0, 1] (:data:`RLS_FORGET`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.sin(2 * np.pi * 6.0 * np.arange(1000) / 100.0)
    >>> pred = RLSPredictor(4, horizon=5)
    >>> P = np.array([pred.step(v) for v in s])
    >>> bool(np.abs(P[500:-5] - s[505:]).max() < 1e-3)
    True
    """

    def __init__(self, taps: int, horizon: int, forget: float = RLS_FORGET):
        super().__init__(taps, horizon)
        if not 0.0 < float(forget) <= 1.0:
            raise ValueError(f"forget must lie in (0, 1], got {forget!r}")
        self.forget = float(forget)
        self.q = None

    def install(self, coefficients):
        super().install(coefficients)
        self.q = None

    def step(self, estimate: float) -> float:
        self.line[1:] = self.line[:-1]
        self.line[0] = estimate
        past = self.line[self.horizon:]
        power = float(past @ past) / self.taps
        if self.q is None and power > 0:
            self.q0 = 100.0 / power
            self.q = np.eye(self.taps) * self.q0
        if self.q is not None:
            e = estimate - self.coefficients @ past
            qx = self.q @ past
            k = qx / (self.forget + past @ qx)
            self.coefficients = np.clip(self.coefficients + k * e, -COEFFICIENT_LIMIT, COEFFICIENT_LIMIT)
            self.q = self.q - np.outer(k, qx)
            if np.trace(self.q) <= self.taps * self.q0:
                self.q /= self.forget
        return float(self.coefficients @ self.line[:self.taps])


def check_taps_horizon(taps, horizon):
    """``(taps, horizon)`` as positive integers, or a ValueError naming which is wrong."""
    for name, v in (("taps", taps), ("horizon", horizon)):
        if isinstance(v, bool) or not float(v).is_integer() or int(v) < 1:
            raise ValueError(f"{name} must be a positive integer, got {v!r}")
    return int(taps), int(horizon)


def padded(coefficients, taps: int):
    """``coefficients`` as a float array of ``taps``: zero-padded, or cut to its ``taps`` newest."""
    c = np.asarray(coefficients, dtype=float).reshape(-1)
    out = np.zeros(taps)
    out[:min(taps, c.size)] = c[:taps]
    return out


def adaptive_predictor(name: str, horizon: int):
    """A fresh per-sample predictor by name (:data:`ADAPTIVE`).

    Examples
    --------
    >>> type(adaptive_predictor("nlms8", 2)).__name__, adaptive_predictor("rls16", 2).taps
    ('NLMSPredictor', 16)
    >>> adaptive_predictor("lms", 2)
    Traceback (most recent call last):
    ...
    ValueError: adaptive predictor must be one of ('nlms8', 'rls16'), got 'lms'
    """
    if name == "nlms8":
        return NLMSPredictor(8, horizon, NLMS_STEP)      # the module's values when called (a study may set them)
    if name == "rls16":
        return RLSPredictor(16, horizon, RLS_FORGET)
    raise ValueError(f"adaptive predictor must be one of {ADAPTIVE}, got {name!r}")
