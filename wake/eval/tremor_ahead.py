"""The tremor ahead in ``wake evaluate``: each method's prediction of the tremor ``h`` samples ahead, scored.

What an actuator plays at sample ``m`` is the prediction made at ``m - h``; it is scored against the true
tremor at ``m`` with the paper's NRMSE per slice of time since start (:func:`wake.eval.warmup.slice_nrmse`).
The methods (docs/studies/design.md, "Tremor ahead"):

* WAKE's gated command (``WakeResult.command`` at ``horizon = h``) and its ungated prediction
  (``tremor_ahead``);
* each baseline extrapolating its own sinusoid model (:func:`baselines_ahead`);
* zero: the actuator stays off;
* two limits fitted in hindsight on the whole recording (:func:`hindsight_predictor`): the issue's oracle, an
  8-tap linear predictor of the true tremor fed the true past, and the 8-tap Wiener predictor from WAKE's own
  estimate to the true tremor (the best any 8-tap filter of what the device sees can do).

The truth: the synthetic set's tremor component ``s_t`` (its white noise is unpredictable), a recording's
tremor independent of WAKE (:func:`wake.eval.warmup.independent_ground_truth`).
"""

from __future__ import annotations

import numpy as np

from wake.ahead import TAPS, horizon_from_ms, lagged
from wake.eval.baselines import baseline_methods
from wake.eval.warmup import slice_nrmse
from wake.filter import WakeFilter

__all__ = ["HORIZONS_MS", "GATED", "UNGATED", "ZERO", "ORACLE", "WIENER", "hindsight_predictor", "aligned",
           "ahead_scores", "ahead_commands", "baselines_ahead"]

#: The horizons ``wake evaluate`` reports, in ms (an actuator's delay: 20-100 ms).
HORIZONS_MS = (10, 20, 50, 100)

GATED = "WAKE command (gated)"
UNGATED = "WAKE prediction (ungated)"
ZERO = "zero (the actuator stays off)"
ORACLE = "oracle: hindsight 8-tap LS on the true tremor, fed the true past"
WIENER = "limit: hindsight 8-tap Wiener, WAKE estimate -> true tremor"
#: Ridge of the hindsight fits, relative to the Gram matrix's mean diagonal (as bench/ahead.py::oracle).
HINDSIGHT_RIDGE = 1e-6


def hindsight_predictor(inp, target, horizon: int, taps: int = TAPS, ridge: float = HINDSIGHT_RIDGE):
    """The ``taps``-tap least-squares predictor of ``target[k + horizon]`` from ``inp[k .. k - taps + 1]``,
    fitted on the whole recording (not clipped: a limit, not a device's filter); its predictions ``P[k]``.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.sin(np.arange(400) / 3.0)
    >>> bool(np.abs(hindsight_predictor(s, s, 5)[100:-5] - s[105:]).max() < 1e-3)
    True
    """
    inp, target = np.asarray(inp, dtype=float), np.asarray(target, dtype=float)
    X = lagged(inp, taps)
    A = X[taps - 1:inp.size - horizon]
    G = A.T @ A
    lam = ridge * np.trace(G) / taps + 1e-300
    c = np.linalg.solve(G + lam * np.eye(taps), A.T @ target[taps - 1 + horizon:])
    return X @ c


def aligned(P, horizon: int):
    """What an actuator plays at each sample: ``P[m - horizon]`` (0 before), ``P[k]`` being for ``k + horizon``."""
    out = np.zeros_like(P)
    out[horizon:] = P[:P.shape[0] - horizon]
    return out


def ahead_scores(x, fs, truth, *, backend, settings=None, horizons_ms=HORIZONS_MS, baselines=True):
    """Per method and horizon, the slices of the predicted-tremor NRMSE of one recording.

    Parameters
    ----------
    x, truth : array_like, shape (n, channels)
        The recording and its true tremor.
    fs : float
    backend : {"c", "reference"}
    settings : dict, optional
        WakeFilter settings (the paper's by default).
    horizons_ms : sequence of float
        Rounded to samples at ``fs`` (:func:`wake.ahead.horizon_from_ms`).
    baselines : bool
        Also the baselines' own extrapolation (the slow part).

    Returns
    -------
    dict
        ``{ms: {method: [slice dict per channel]}}``.

    Examples
    --------
    >>> from wake.eval.synthetic import make_signal
    >>> s = make_signal(5.0, seed=1, duration=12.0)
    >>> out = ahead_scores(s.measurement[:, None], s.fs, s.tremor[:, None], backend="reference",
    ...                    horizons_ms=(20,), baselines=False)
    >>> out[20][GATED][0]["after 5 s"] < out[20][ZERO][0]["after 5 s"]
    True
    """
    x = np.asarray(x, dtype=float).reshape(len(x), -1)
    truth = np.asarray(truth, dtype=float).reshape(x.shape)
    return {ms: {name: [slice_nrmse(truth[:, c], est[:, c], fs) for c in range(x.shape[1])]
                 for name, est in methods.items()}
            for ms, methods in ahead_commands(x, fs, truth, backend=backend, settings=settings,
                                              horizons_ms=horizons_ms, baselines=baselines).items()}


def ahead_commands(x, fs, truth, *, backend, settings=None, horizons_ms=HORIZONS_MS, baselines=True):
    """Per horizon and method, what an actuator plays at each sample: what :func:`ahead_scores` scores and
    :mod:`wake.eval.suppression` feeds an actuator.

    Parameters are those of :func:`ahead_scores`.  Returns ``{ms: {method: array (n, channels)}}``, each
    aligned to the sample it plays at (:func:`aligned`).
    """
    x = np.asarray(x, dtype=float).reshape(len(x), -1)
    truth = np.asarray(truth, dtype=float).reshape(x.shape)
    settings = dict(settings or {})
    horizons = {ms: horizon_from_ms(ms, fs) for ms in horizons_ms}
    extrapolated = baselines_ahead(x, fs, sorted(set(horizons.values()))) if baselines else {}
    out = {}
    for ms, h in horizons.items():
        res = WakeFilter(fs=fs, backend=backend, horizon=h, **settings).run(x)
        y = x - res.voluntary
        methods = {GATED: res.command, UNGATED: res.tremor_ahead, ZERO: np.zeros_like(x)}
        methods.update({f"{name}, own extrapolation": aligned(P[h], h) for name, P in extrapolated.items()})
        known = np.nan_to_num(truth)          # a gap has no truth (wake.eval.truth): 0 in the hindsight fits
        methods[ORACLE] = np.column_stack([aligned(hindsight_predictor(t, t, h), h) for t in known.T])
        methods[WIENER] = np.column_stack([aligned(hindsight_predictor(e, t, h), h) for e, t in zip(y.T, known.T)])
        out[ms] = methods
    return out


def baselines_ahead(x, fs, horizons):
    """BMFLC, E-BMFLC, WFLC and eHWFLC-KF (:func:`wake.eval.baselines.baseline_methods`) extrapolating their tremor model:
    the weights after sample ``n``, the reference sinusoids at ``n + h`` (``BaselineResult.ahead``).

    Parameters
    ----------
    x : array_like, shape (n, channels)
    fs : float
    horizons : sequence of int

    Returns
    -------
    dict
        ``{name: {h: P}}``, ``P`` of shape (n, channels): ``P[k]`` the tremor predicted at ``k`` for ``k + h``.

    Examples
    --------
    >>> import numpy as np
    >>> P = baselines_ahead(np.sin(np.arange(300) / 2.0)[:, None], 100.0, (1, 5))
    >>> sorted(P), P["WFLC"][5].shape
    (['BMFLC', 'E-BMFLC', 'WFLC', 'eHWFLC-KF'], (300, 1))
    """
    x = np.asarray(x, dtype=float)
    return {name: method.run(x, horizons=horizons).ahead for name, method in baseline_methods(fs).items()}
