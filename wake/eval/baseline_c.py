"""The baselines' C loops (``wake/eval/native/wake_eval.c``, in the compiled core ``wake._rtp``): how ``run`` calls them.

Each function takes the model (:mod:`wake.eval.baselines`, :mod:`wake.eval.ehwflc`), the ``(ffi, lib)`` of :func:`c_loops_for`, the
signal as ``(n, channels)`` and what its ``run`` prepared, and returns the same :class:`BaselineResult` as the
model's Python loop, within 1e-12 of it (tests/eval/test_baselines_c.py): one C call per channel, every buffer
a numpy array passed without a copy.
"""

from __future__ import annotations

import numpy as np

from wake.eval.baseline_model import BaselineResult, shaped

__all__ = ["ENGINES", "c_loops_for", "run_bmflc", "run_ebmflc", "run_ehwflc", "run_wflc"]

#: How ``run`` computes: ``"auto"`` (the C loop when the compiled core is installed, else Python), ``"c"`` (the
#: C loop, an error without the core) or ``"python"`` (the reference loop).
ENGINES = ("auto", "c", "python")

#: The loops the compiled core must hold (``wake_eval_<name>``): a core built before one of them is not used.
_LOOPS = ("bmflc", "ebmflc", "wflc", "ehwflc")


def c_loops_for(engine):
    """``(ffi, lib)`` of the compiled core's baseline loops for ``engine``, or None for the Python loop."""
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    if engine == "python":
        return None
    try:
        from wake._rtp import ffi, lib
    except ImportError:
        lib = None
    if lib is None or not all(hasattr(lib, f"wake_eval_{loop}") for loop in _LOOPS):
        if engine == "c":
            from wake._core import missing_core_hint

            raise ValueError(f"engine='c' needs the compiled core wake._rtp: {missing_core_hint()}; "
                             "or use engine='python'")
        return None
    return ffi, lib


def _c_doubles(ffi, a):
    """A C ``double *`` onto the C-contiguous float64 array ``a`` (no copy)."""
    return ffi.from_buffer("double[]", a)


def _c_horizons(ffi, hs):
    """The horizons as a C ``long`` array (it holds its buffer) and their count."""
    return ffi.from_buffer("long[]", np.array(hs if hs else [0], dtype=np.dtype("l"))), len(hs)


def run_bmflc(model, c_loops, arr, one_d, hs, phi):
    """:meth:`wake.eval.baselines.BMFLC.run` in C: ``phi`` its bank's rows (with the horizons' extra rows)."""
    ffi, lib = c_loops
    n, channels = arr.shape
    phi = np.ascontiguousarray(phi)
    m = phi.shape[1]
    vol, bank = np.empty((channels, n)), np.empty((channels, n))
    ahead = np.empty((channels, max(len(hs), 1), n))
    c_hs, n_hs = _c_horizons(ffi, hs)
    for ch in range(channels):
        xc, w = np.ascontiguousarray(arr[:, ch]), np.zeros(m)
        lib.wake_eval_bmflc(_c_doubles(ffi, phi), n, m, _c_doubles(ffi, xc), 2 * model.mu, 2 * model.mu_bias,
                            c_hs, n_hs, _c_doubles(ffi, w), _c_doubles(ffi, vol[ch]), _c_doubles(ffi, bank[ch]),
                            _c_doubles(ffi, ahead[ch]))
    s = shaped(one_d)
    return BaselineResult(s(vol.T.copy()), s(arr - vol.T), s(bank.T.copy()), model.name,
                          ahead={h: s(ahead[:, k].T.copy()) for k, h in enumerate(hs)})


def run_ebmflc(model, c_loops, arr, one_d, hs, phi, nv, rho, delta, leak):
    """:meth:`wake.eval.baselines.EBMFLC.run` in C: ``phi`` its regressor rows, the first ``nv`` voluntary; the
    forgetting factor ``rho``, the ridge ``delta`` and the ``leak`` that keeps it constant."""
    ffi, lib = c_loops
    n, channels = arr.shape
    phi = np.ascontiguousarray(phi)
    p = phi.shape[1]
    vol, pred = np.empty((channels, n)), np.empty((channels, n))
    ahead = np.empty((channels, max(len(hs), 1), n))
    g, u, r, w, y = np.empty((p, p)), np.empty((p, p)), np.empty(p), np.empty(p), np.empty(p)
    c_hs, n_hs = _c_horizons(ffi, hs)
    for ch in range(channels):
        xc = np.ascontiguousarray(arr[:, ch])
        lib.wake_eval_ebmflc(_c_doubles(ffi, phi), n, p, nv, _c_doubles(ffi, xc), rho, delta, leak, c_hs, n_hs,
                             *(_c_doubles(ffi, a) for a in (g, u, r, w, y, vol[ch], pred[ch], ahead[ch])))
    s = shaped(one_d)
    vol, pred = vol.T.copy(), pred.T
    return BaselineResult(s(vol), s(arr - vol), s(pred - vol), model.name,
                          ahead={h: s(ahead[:, k].T.copy()) for k, h in enumerate(hs)})


def run_wflc(model, c_loops, arr, one_d, hs):
    """:meth:`wake.eval.baselines.WFLC.run` in C (its phase, hence its regressors, adapt as it runs)."""
    ffi, lib = c_loops
    n, channels = arr.shape
    M = model.n_harmonics
    lo, hi = (2 * np.pi * f / model.fs for f in model.f_range)
    vol, bank, freq = np.empty((channels, n)), np.empty((channels, n)), np.empty((channels, n))
    ahead = np.empty((channels, max(len(hs), 1), n))
    scratch = [np.empty(M) for _ in range(4)]
    c_hs, n_hs = _c_horizons(ffi, hs)
    for ch in range(channels):
        xc = np.ascontiguousarray(arr[:, ch])
        lib.wake_eval_wflc(_c_doubles(ffi, xc), n, M, model.fs, 2 * np.pi * model.f0 / model.fs, lo, hi,
                           2 * model.mu, 2 * model.mu_bias, 2 * model.mu0, model.beta, c_hs, n_hs,
                           *(_c_doubles(ffi, a) for a in (*scratch, vol[ch], bank[ch], freq[ch], ahead[ch])))
    s = shaped(one_d)
    vol = vol.T.copy()
    return BaselineResult(s(vol), s(arr - vol), s(bank.T.copy()), model.name, frequency=s(freq.T.copy()),
                          ahead={h: s(ahead[:, k].T.copy()) for k, h in enumerate(hs)})


def run_ehwflc(model, c_loops, arr, one_d, hs):
    """:meth:`wake.eval.ehwflc.EHWFLCKF.run` in C (its phase and its Kalman state adapt as it runs)."""
    ffi, lib = c_loops
    n, channels = arr.shape
    M = model.n_harmonics
    dim = 1 + 2 * M
    lo, hi = (2 * np.pi * f / model.fs for f in model.f_range)
    vol, bank, freq = np.empty((channels, n)), np.empty((channels, n)), np.empty((channels, n))
    ahead = np.empty((channels, max(len(hs), 1), n))
    scratch = [np.empty(dim), np.empty((dim, dim)), np.empty(dim), np.empty(dim)]  # w, P, phi, P phi
    c_hs, n_hs = _c_horizons(ffi, hs)
    for ch in range(channels):
        xc = np.ascontiguousarray(arr[:, ch])
        lib.wake_eval_ehwflc(_c_doubles(ffi, xc), n, M, model.fs, 2 * np.pi * model.f0 / model.fs, lo, hi,
                             2 * model.mu0, model.beta, model.p0, model.q_bias, model.q_tremor, c_hs, n_hs,
                             *(_c_doubles(ffi, a) for a in (*scratch, vol[ch], bank[ch], freq[ch], ahead[ch])))
    s = shaped(one_d)
    vol = vol.T.copy()
    return BaselineResult(s(vol), s(arr - vol), s(bank.T.copy()), model.name, frequency=s(freq.T.copy()),
                          ahead={h: s(ahead[:, k].T.copy()) for k, h in enumerate(hs)})
