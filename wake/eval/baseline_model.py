"""What the baselines (:mod:`wake.eval.baselines`) share: their result, the checks of their parameters and the
rows of their regressors.

Step-size bound (BMFLC, WFLC)
-----------------------------
With update ``w_i <- w_i + 2 mu_i phi_i e`` the a-posteriori error on the
current sample is ``(1 - 2 sum_i mu_i phi_i^2) e``.  Every sine/cosine pair
has ``sin^2 + cos^2 = 1`` and the bias regressor is 1, so with a step ``mu``
on the ``M`` pairs and ``mu_bias`` on the bias the factor is
``1 - 2 (M mu + mu_bias)`` *at every sample* (the regressors are normalised:
``|phi(k)|^2 = M + 1`` exactly).  It lies in (-1, 1) iff

    0 < M * mu + mu_bias < 1,

the classical LMS bound ``0 < mu < 1/tr(R)`` (``tr R = E|phi|^2 = M + 1``
when ``mu_bias = mu``, i.e. ``mu < 1/(M + 1)``; ``M + 1`` is the number of
regressors counting a sine/cosine pair once).  Beyond it the error grows
without bound; the constructors refuse such steps.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wake._validation import check_positive

__all__ = ["BaselineResult", "band_bins", "check_band", "check_lms_steps", "shaped", "check_horizons", "rows_ahead"]


@dataclass
class BaselineResult:
    """What a baseline's ``run`` returns (same shape as ``x`` throughout)."""

    voluntary: np.ndarray  #: one-step-ahead voluntary prediction, from x[:k]
    tremor: np.ndarray  #: x - voluntary
    model_tremor: np.ndarray  #: the tremor part of the model's own prediction (bank output)
    method: str
    frequency: np.ndarray = field(default=None)  #: WFLC: adapted frequency (Hz) used at each sample
    warmup: int = 0  #: no HPA warm-up; kept for a uniform interface with WakeResult
    #: ``{h: P}`` for ``run(x, horizons)``: ``P[k]`` the tremor model after sample ``k`` extrapolated to ``k + h``
    ahead: dict = field(default_factory=dict)


def band_bins(lo, hi, df):
    """Bin frequencies from ``lo`` to ``hi`` (inclusive, to rounding) every ``df`` Hz."""
    count = int(np.floor((hi - lo) / df + 1e-9)) + 1
    return lo + df * np.arange(count)


def check_band(name, band, fs):
    """``band`` as a pair of floats ``0 < low < high < fs/2``, or a ValueError naming ``name``."""
    try:
        lo, hi = (float(v) for v in band)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (low, high) in Hz, got {band!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi < fs / 2):
        raise ValueError(f"{name} must satisfy 0 < low < high < fs/2 = {fs / 2:g} Hz, got {band!r}")
    return lo, hi


def check_lms_steps(mu, mu_bias, n_pairs):
    """``(mu, mu_bias)`` within the step-size bound above for ``n_pairs`` sine/cosine pairs, or a ValueError."""
    mu = check_positive("mu", mu)
    mu_bias = check_positive("mu_bias", mu_bias)
    if n_pairs * mu + mu_bias >= 1.0:
        hi = (1.0 - mu_bias) / n_pairs
        raise ValueError(
            f"LMS step out of its stability range: need 0 < M*mu + mu_bias < 1 with M = {n_pairs} "
            f"sine/cosine pairs, got M*mu + mu_bias = {n_pairs * mu + mu_bias:.4g}; with "
            f"mu_bias = {mu_bias:g} the valid range is 0 < mu < {max(hi, 0.0):.4g}"
            + ("" if hi > 0 else " (mu_bias itself must be < 1)")
        )
    return mu, mu_bias


def shaped(one_d):
    """Undo :func:`wake._validation.as_signal`'s column for a 1-D input."""
    return (lambda a: a[:, 0]) if one_d else (lambda a: a)


def check_horizons(horizons):
    """``horizons`` (samples beyond the one-step output) as sorted distinct ints >= 1."""
    return sorted({check_positive("horizon", h, integer=True) for h in horizons})


def rows_ahead(rows_of, n, extra):
    """``rows_of`` at samples ``0..n-1``, then ``n..n+extra-1`` computed apart, so the first ``n`` rows (and with
    them every one-step output) do not depend on how far ahead the model is extrapolated."""
    rows = rows_of(np.arange(n))
    return rows if not extra else np.vstack((rows, rows_of(np.arange(n, n + extra))))
