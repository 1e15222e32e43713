"""Weights for the time before the first HPA: a designed one-step-ahead predictor.

Before any HPA has run, the RTP needs weights.  The first release used the
deepest approximation alone (``w = (0, ..., 0, 1)``), a low-pass that lags
the voluntary motion by about ``2**J / 2`` samples.  :func:`prior_weights`
designs ``w`` from the filter bank itself, with no data: the FIR
``h = B'w`` should predict the *next* sample in the voluntary band and
reject the tremor band, in the least-squares sense over a frequency grid::

    minimise  sum_{f in voluntary band} |H(f) - exp(i 2 pi f / fs)|^2
            + tremor_weight * sum_{f in tremor band} |H(f)|^2
            + ridge |w|^2        subject to  sum(w) = 1  (unit gain at DC)

with ``H(f) = sum_j w_j B_j(f)`` the response of the filter bank's output
(the prediction of sample ``n + 1`` made at ``n``).  The voluntary band is
``[0, default_cutoff]`` and the tremor band the configuration's
``tremor_band``: the cut-off the HPA falls back to when it finds none.
docs/studies/design.md ("Warm-up") gives the measured effect.
"""

from __future__ import annotations

import numpy as np

from wake.config import WEIGHT_LIMIT, WakeConfig
from wake.target import TARGET
from wake.wavelets import filter_bank_taps

__all__ = ["prior_weights"]


def prior_weights(config: WakeConfig, taps=None, *, tremor_weight: float = 0.3, ridge: float = 1e-6,
                  n_freqs: int = 256) -> np.ndarray:
    """Start-up weights: the filter bank as a one-step-ahead predictor below the default cut-off.

    Parameters
    ----------
    config : WakeConfig
        ``fs``, ``wavelet``, ``level``, ``mode``, ``default_cutoff`` and
        ``tremor_band`` are used.
    taps : numpy.ndarray, shape (J, 2**J), optional
        The filter bank (computed from ``config`` when not given).
    tremor_weight : float
        Weight of the tremor band's rejection against the voluntary band's
        prediction error (per grid point; both bands get ``n_freqs`` points).
    ridge : float
        Relative ridge on ``|w|^2`` (the approximations are nearly collinear).
    n_freqs : int
        Grid points per band.

    Returns
    -------
    numpy.ndarray, shape (J,)
        Within ``WEIGHT_LIMIT``; ``sum(w) = 1``: unit gain at DC.

    Examples
    --------
    >>> from wake import WakeConfig
    >>> from wake.hpa.prior import prior_weights
    >>> w = prior_weights(WakeConfig())
    >>> w.shape, bool(abs(w.sum() - 1.0) < 1e-9)
    ((5,), True)
    """
    if taps is None:
        taps = filter_bank_taps(config.wavelet, config.level, config.mode)
    taps = np.asarray(taps, dtype=float)
    n_taps = taps.shape[1]
    delays = np.arange(n_taps - 1, -1, -1)          # taps are oldest first: tap i is n_taps-1-i samples old
    f_vol = np.linspace(0.0, config.default_cutoff, n_freqs)
    lo, hi = config.tremor_band
    f_trem = np.linspace(lo, hi, n_freqs)

    def response(f):
        # B_j(f) = sum_i B[j, i] exp(-i 2 pi f d_i / fs): shape (len(f), J)
        return np.exp(-2j * np.pi * np.outer(f, delays) / config.fs) @ taps.T

    a_vol, a_trem = response(f_vol), np.sqrt(tremor_weight) * response(f_trem)
    target = TARGET.phasor(f_vol, config.fs)  # the sample the RTP predicts (wake.target)
    A = np.vstack([a_vol, a_trem])
    y = np.concatenate([target, np.zeros(n_freqs)])
    # real w: stack real and imaginary parts
    A_r = np.vstack([A.real, A.imag])
    y_r = np.concatenate([y.real, y.imag])
    gram = A_r.T @ A_r
    J = gram.shape[0]
    lam = ridge * np.trace(gram) / J
    # unit gain at DC (sum w = 1: every row of B has unit DC gain), so a sensor's offset
    # (gravity on an accelerometer) passes to the voluntary estimate whole: the KKT system
    #   [G + lam I  1] [w ]   [A'y]
    #   [1'         0] [mu] = [ 1 ]
    kkt = np.zeros((J + 1, J + 1))
    kkt[:J, :J] = gram + lam * np.eye(J)
    kkt[:J, J] = kkt[J, :J] = 1.0
    w = np.linalg.solve(kkt, np.concatenate([A_r.T @ y_r, [1.0]]))[:J]
    return np.clip(w, -WEIGHT_LIMIT, WEIGHT_LIMIT)
