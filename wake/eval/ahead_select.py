"""Any tremor-ahead predictor of :mod:`wake.ahead`, run as the filter runs its own, in float, and its limit.

The filter ships one predictor (``"fir8"``, in the C core too).  To choose another by measurement without
touching the filter, :func:`command_with` refits it at each HPA of a filter run from what that HPA knew
(WAKE's estimate over the window with the weights the HPA installed, the window's tremor truth, the cut-off
flag: what :func:`wake.hpa.run.tremor_ahead` reads), gates it by :func:`wake.ahead.held_out_gain` and
:func:`wake.ahead.gate_target` through the 0.3-s ramp, and runs it per sample on the stream's tremor estimate
``x - voluntary``: the filter's own design when ``predictor="fir8"`` (:func:`command_with` reproduces
``WakeResult.command`` of the float reference to rounding; ``tests/eval/test_ahead_select.py``).  A per-sample
adaptive predictor (:data:`wake.ahead_models.ADAPTIVE`) starts from each HPA's ``"fir8"`` and adapts between
HPAs; its gate's gain is the least-squares scale of the predictions it actually made on the samples new since
the previous HPA (:func:`adaptive_run`).

:func:`wiener_limit` is the hindsight limit of the issue: the ``taps``-tap least-squares predictor from
WAKE's own estimate to the true tremor, fitted on the whole recording.
"""

from __future__ import annotations

import numpy as np

from wake.ahead import MIN_HELD_OUT, fit_predictor, gate_target, held_out_gain, lagged, ramp_step, scale_gain
from wake.ahead_models import ADAPTIVE, PREDICTORS, adaptive_predictor, fit_model
from wake.eval.tremor_ahead import aligned, hindsight_predictor
from wake.hpa.run import gate_truth
from wake.hpa.sharp import detrended_highpass
from wake.wavelets import filter_bank_outputs, filter_bank_taps

__all__ = ["window_pairs", "command_with", "adaptive_run", "wiener_limit"]


def window_pairs(x, result, config, channel=0):
    """Per HPA of one channel: ``(index, estimate, truth, flag, gated)`` as :func:`wake.hpa.run.tremor_ahead`
    sees them.

    ``estimate``: WAKE's tremor estimate over the window recomputed with the weights the HPA installed;
    ``truth``: the window's sharp high-pass truth at the HPA's cut-off (the end-point line out); ``gated``:
    the truth the gate's held-out gain is measured against (:func:`wake.hpa.run.gate_truth`,
    ``config.gate_cutoff``; ``truth`` itself by default).
    """
    x = np.asarray(x, dtype=float)
    taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    out = []
    for u in result.hpa[channel]:
        m = min(u.index, config.window_samples)
        w = x[u.index - m:u.index]
        outputs = filter_bank_outputs(w, taps)
        N = w.shape[0] - outputs.shape[0] + 1
        estimate = w[N:] - outputs[:-1] @ np.asarray(u.weights, dtype=float)
        full = detrended_highpass(w, config.fs, u.cutoff)
        gated = gate_truth(w, config.fs, u.cutoff, full, config.gate_cutoff)[N:]
        out.append((u.index, estimate, full[N:], u.cutoff_flag, gated))
    return out


def command_with(x, result, config, horizon, predictor="fir8", channel=0):
    """The gated command of ``predictor`` (:data:`wake.ahead_models.PREDICTORS`) on one channel of a filter run.

    Parameters
    ----------
    x : array_like, shape (n,)
        The channel's samples.
    result : WakeResult
        ``WakeFilter(...).run`` of the recording (its voluntary output and HPA updates are used).
    config : WakeConfig
        The filter's configuration.
    horizon : int
        Samples ahead.
    predictor : str
        One of :data:`wake.ahead_models.PREDICTORS` (refitted at each HPA) or :data:`wake.ahead_models.ADAPTIVE`
        (adapted per sample, :func:`adaptive_run`).
    channel : int
        Which channel of ``result``.

    Returns
    -------
    prediction, gate, command : numpy.ndarray, shape (n,)
        Aligned to the sample they are for (``command[m]`` was sent at ``m - horizon``), as ``WakeResult``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeConfig, WakeFilter
    >>> from wake.eval.synthetic import make_signal
    >>> s = make_signal(5.0, seed=1, duration=12.0)
    >>> cfg = WakeConfig(fs=s.fs, horizon=2, backend="reference")
    >>> res = WakeFilter(config=cfg).run(s.measurement)
    >>> P, g, cmd = command_with(s.measurement, res, cfg, 2)
    >>> bool(np.allclose(cmd, res.command, atol=1e-9))
    True
    """
    if config.decimation_factor != 1:
        raise ValueError(f"command_with runs at the filter bank's rate: fs = {config.fs:g} Hz decimates by "
                         f"{config.decimation_factor}; pass decimation=1 in the WakeConfig, or a rate of at most "
                         f"150 Hz")
    if predictor not in PREDICTORS + ADAPTIVE:
        raise ValueError(f"predictor must be one of {PREDICTORS + ADAPTIVE}, got {predictor!r}")
    x = np.asarray(x, dtype=float).reshape(-1)
    y = x - np.asarray(result.voluntary, dtype=float).reshape(x.size, -1)[:, channel]
    pairs = window_pairs(x, result, config, channel)
    n = x.size
    P = np.zeros(n)
    goal = np.zeros(n)
    previous, last = None, 0
    starts = [applied_at(result, channel, i, idx) for i, (idx, *_rest) in enumerate(pairs)] + [n]
    if predictor in ADAPTIVE:
        P, goal = adaptive_run(y, pairs, starts[:-1], predictor, horizon)
        pairs = []
    for i, (index, estimate, truth, flag, gated) in enumerate(pairs):
        gain = held_out_gain(estimate, gated, previous, horizon, index - last)
        c = fit_model(estimate, truth, horizon, predictor)
        a, b = starts[i], starts[i + 1]
        if b > a:
            P[a:b] = lagged(y[max(0, a - c.size + 1):b], c.size)[min(a, c.size - 1):] @ c
            goal[a:b] = gate_target(gain, flag)
        previous, last = c, index
    alpha = ramp_step(config.fs)
    g = np.empty(n)
    v = 0.0
    for k in range(n):
        v += alpha * (goal[k] - v)
        g[k] = v
    return aligned(P, horizon), aligned(g, horizon), aligned(g * P, horizon)


def adaptive_run(y, pairs, starts, predictor, horizon):
    """The predictions and the gate's goals of a per-sample adaptive predictor over a stream.

    Parameters
    ----------
    y : numpy.ndarray, shape (n,)
        WAKE's tremor estimate ``x - voluntary``, the stream the predictor reads.
    pairs : list
        :func:`window_pairs` of the run.
    starts : list of int
        The sample from which each HPA's result is in use (:func:`applied_at`).
    predictor : str
        One of :data:`wake.ahead_models.ADAPTIVE`.
    horizon : int

    Returns
    -------
    P, goal : numpy.ndarray, shape (n,)
        ``P[k]``, the tremor predicted at ``k`` for ``k + horizon``; ``goal[k]``, the gate's goal in use.

    Each HPA installs its ``"fir8"`` predictor (:func:`wake.ahead.fit_predictor` on the window) as the starting
    point, and sets the goal to the least-squares scale (:func:`wake.ahead.scale_gain`) of the predictions made
    since the previous HPA onto the window's gated truth (0 for the first HPA or with fewer than
    :data:`wake.ahead.MIN_HELD_OUT` of them), or 0 without a tremor peak (:func:`wake.ahead.gate_target`).
    """
    n = y.size
    P, goal = np.zeros(n), np.zeros(n)
    model = adaptive_predictor(predictor, horizon)
    j, last, now = 0, 0, 0.0
    for k in range(n):
        while j < len(pairs) and starts[j] <= k:
            index, estimate, truth, flag, gated = pairs[j]
            first = max(last, index - gated.size, horizon)
            gain = scale_gain(P[first - horizon:index - horizon], gated[gated.size - (index - first):]) \
                if j > 0 and index - first >= MIN_HELD_OUT else 0.0
            model.install(fit_predictor(estimate, truth, horizon))
            now, last, j = gate_target(gain, flag), index, j + 1
        P[k] = model.step(y[k])
        goal[k] = now
    return P, goal


def applied_at(result, channel, i, index):
    """Sample from which the ``i``-th HPA's model predicts: the last sample of its window (0-based
    ``applied_at - 1``; the filter installs the HPA before that sample's step), or ``index - 1``."""
    at = getattr(result.hpa[channel][i], "applied_at", -1)
    return (int(at) if at is not None and at >= 0 else int(index)) - 1


def wiener_limit(estimate, truth, horizon, taps=40):
    """The hindsight ``taps``-tap Wiener predictor from WAKE's estimate to the true tremor, aligned to the sample
    it is for (:func:`wake.eval.tremor_ahead.hindsight_predictor`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.sin(np.arange(600) / 3.0)
    >>> bool(np.abs(wiener_limit(s, s, 5)[100:] - s[100:]).max() < 1e-3)
    True
    """
    return aligned(hindsight_predictor(estimate, truth, horizon, taps=taps), horizon)
