"""Tremor-ahead predictors beside the filter's own, selectable by name (issue 46).

The filter, the float reference and the C core run one predictor, ``"fir8"`` (:func:`wake.ahead.fit_predictor`,
8 taps); it stays the default everywhere.  Issue 46 asked for a predictor that comes closer to its limit
where tremor is strong and does no harm where it is weak; the candidates are here, under one name each
(:data:`PREDICTORS`, :func:`fit_model`), so that an evaluation can run any of them as the filter runs its
own (:func:`wake.eval.ahead_select.command_with`) and a later change can port the chosen one.  The study that
chose among them: docs/studies/design.md, "Tremor ahead where tremor is strong" (``python bench/strong_ahead.py``).

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

from wake.ahead import RIDGE, fit_pair, fit_predictor, fit_rows, lagged

__all__ = ["ORDERS", "SELECT_HELD_OUT", "PREDICTORS", "fit_selected", "fit_model"]

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
