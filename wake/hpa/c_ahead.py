"""The C HPA's tremor-ahead fit (``WAKE_HPA_AHEAD``) on consecutive windows, and its agreement with
:mod:`wake.ahead` window by window: what the tests and ``bench/hpa_c_ahead_agreement.py`` compare."""

from __future__ import annotations

import numpy as np

from wake.config import WakeConfig
from wake.hpa.c_port import _core, _instance, check_c_hpa_config, quantize_window
from wake.hpa.cutoff import CUTOFF_FLAGS

__all__ = ["ahead_agreement", "run_ahead_c"]


def run_ahead_c(stream, config: WakeConfig, *, taps, horizon: int = 1, full_scale: float, start_weights=None):
    """The C HPA's tremor-ahead fit (``WAKE_HPA_AHEAD``) on consecutive full windows of one instance.

    Parameters
    ----------
    stream : array_like, shape (k L,)
        Finite samples, oldest first; each L-sample block is one HPA window, run in order on one instance
        (its index: the samples received when it closed), so each window after the first scores the
        previous window's predictor on its new samples.
    config : WakeConfig
    taps : numpy.ndarray, shape (J, 2**J)
        The filter bank (read as int16 Q15).
    horizon : int
        Samples ahead, 1..``WAKE_HPA_MAX_AHEAD_HORIZON``.
    full_scale : float
        The physical value of Q15 1.0 every window is quantised with.
    start_weights : array_like, optional
        The weights in use before the first HPA (default: the deepest approximation alone).

    Returns
    -------
    list of dict
        Per window: ``weights_in_use``, ``weights``, ``cutoff``, ``flag``, ``coefficients`` (8, newest
        estimate first) and ``goal``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeConfig
    >>> from wake.hpa.c_ahead import run_ahead_c
    >>> from wake.wavelets import filter_bank_taps
    >>> t = np.arange(1500) / 100.0
    >>> x = np.sin(2 * np.pi * 0.3 * t) + 0.5 * np.sin(2 * np.pi * 6 * t)
    >>> out = run_ahead_c(x, WakeConfig(), taps=filter_bank_taps("sym3", 5), full_scale=2.0)
    >>> out[0]["goal"], out[2]["goal"] > 0.9
    (0.0, True)
    """
    ffi, lib = _core()
    check_c_hpa_config(config)
    x = np.asarray(stream, dtype=float)
    J, L = config.level, config.window_samples
    if x.ndim != 1 or x.size < L or x.size % L or not np.isfinite(x).all():
        raise ValueError(f"stream must be 1-D, finite, a whole number of L = {L} sample windows; got shape {x.shape}")
    if not 1 <= int(horizon) <= lib.WAKE_HPA_MAX_AHEAD_HORIZON:
        raise ValueError(f"horizon must lie in 1..{lib.WAKE_HPA_MAX_AHEAD_HORIZON} samples, got {horizon!r}")
    if not (np.isfinite(full_scale) and full_scale > 0):
        raise ValueError(f"full_scale must be finite and > 0, got {full_scale!r}")
    h, _taps_q = _instance(config, taps, start_weights, "start_weights", horizon=int(horizon))
    w = np.array([h.weights[j] for j in range(J)], dtype=np.float32)
    q = quantize_window(x, full_scale)
    out, res = [], ffi.new("wake_hpa_result_t *")
    for k in range(x.size // L):
        block = ffi.from_buffer("int16_t[]", q[k * L:(k + 1) * L])
        used = w.astype(float)
        if lib.wake_hpa_start(h, block, L, (k + 1) * L) != 0 or lib.wake_hpa_run(h) != lib.WAKE_HPA_DONE:
            raise RuntimeError("the C HPA did not finish")
        lib.wake_hpa_take(h, res)
        w = np.array([res.weights[j] for j in range(J)], dtype=np.float32)
        out.append({"weights_in_use": used, "weights": w.astype(float), "cutoff": float(res.cutoff),
                    "flag": list(CUTOFF_FLAGS)[res.flag], "coefficients": np.array(list(res.ahead), dtype=float),
                    "goal": float(res.ahead_goal)})
    return out


def ahead_agreement(stream, config: WakeConfig, *, taps, horizon: int = 1, full_scale: float) -> list:
    """Each window's C tremor-ahead fit (:func:`run_ahead_c`) beside :mod:`wake.ahead`'s on the same estimate.

    Each window's estimate and truth are recomputed in float64 from the int16 window the C HPA read and the
    weights it installed; the float fit (:func:`wake.ahead.fit_predictor`) and goal
    (:func:`wake.ahead.held_out_gain`, scored against :func:`wake.hpa.run.gate_truth`, then
    :func:`wake.ahead.gate_target`) use the C fit of the window before as the previous predictor, as the C HPA does.

    Parameters
    ----------
    stream, config, taps, horizon, full_scale
        As :func:`run_ahead_c`.

    Returns
    -------
    list of dict
        Per window: ``flag``, ``coefficients`` and ``goal`` (the C HPA's), ``reference`` and
        ``reference_goal`` (the float fit's), ``command_nrmse`` (the RMS difference of the gated commands
        ``goal * P`` over the window, divided by the float command's RMS; None where that RMS is 0) and
        ``command_zero`` (whether the C command is then 0 as well).

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeConfig
    >>> from wake.hpa.c_ahead import ahead_agreement
    >>> from wake.wavelets import filter_bank_taps
    >>> t = np.arange(1500) / 100.0
    >>> x = np.sin(2 * np.pi * 0.3 * t) + 0.5 * np.sin(2 * np.pi * 6 * t)
    >>> rows = ahead_agreement(x, WakeConfig(), taps=filter_bank_taps("sym3", 5), full_scale=2.0)
    >>> max(abs(r["goal"] - r["reference_goal"]) for r in rows) < 1e-3
    True
    """
    from wake.ahead import fit_predictor, gate_target, held_out_gain, predictions
    from wake.hpa.run import gate_truth
    from wake.hpa.sharp import detrended_highpass
    from wake.rtp.qformat import quantize_taps
    from wake.wavelets import filter_bank_outputs

    out = run_ahead_c(stream, config, taps=taps, horizon=horizon, full_scale=full_scale)
    L, N = config.window_samples, 2 ** config.level
    x = quantize_window(np.asarray(stream, dtype=float), full_scale).astype(float)
    taps_f = quantize_taps(taps).astype(float) / 32768.0
    rows, previous = [], None
    for k, o in enumerate(out):
        w = x[k * L:(k + 1) * L]
        y = w[N:] - filter_bank_outputs(w, taps_f)[:L - N] @ o["weights"]
        truth = detrended_highpass(w, config.fs, o["cutoff"])
        reference = fit_predictor(y, truth[N:], horizon)
        scored = gate_truth(w, config.fs, o["cutoff"], truth, config.gate_cutoff)[N:]
        goal = gate_target(held_out_gain(y, scored, previous, horizon, L), o["flag"])
        c = o["coefficients"]
        command, command_ref = o["goal"] * predictions(y, c), goal * predictions(y, reference)
        scale = float(np.sqrt(np.mean(command_ref**2)))
        rows.append({"flag": o["flag"], "coefficients": c, "goal": o["goal"], "reference": reference,
                     "reference_goal": goal,
                     "command_nrmse": float(np.sqrt(np.mean((command - command_ref) ** 2))) / scale if scale > 0 else None,
                     "command_zero": bool(np.all(command == 0.0))})
        previous = c
    return rows
