"""Hyper-parameter adjustment (HPA, the paper's Algorithm 1).

One HPA run takes the last ``L`` samples and returns what the RTP needs:

S1. :func:`wake.spectrum.ar_psd`, the Yule-Walker spectrum of the window;
S2. :func:`find_cutoff`, the cut-off ``f_d`` at the valley between the
    voluntary and the tremor band (with a documented fallback);
    :func:`wake.sharp.sharp_highpass` then gives the tremor ground truth and
    ``R``, its variance;
S3. the ``J`` wavelet approximations (:mod:`wake.wavelets`);
S4. :func:`fit_weights`, the weights ``w`` that minimise the paper's error
    ``e_L``.

The paper fits ``w`` on full-window approximations of the same samples, but
the RTP predicts the *next* sample from the *causal* end-of-window
approximations.  ``fit="causal"`` (the default) fits what the RTP actually
sees: the filter-bank output at sample ``k`` against the voluntary ground
truth at ``k + 1``.  ``fit="paper"`` keeps the paper's fit.  The measured
difference is in docs/design.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .sharp import sharp_highpass
from .spectrum import ar_psd
from .wavelets import filter_bank_outputs, wavelet_approximations

__all__ = ["HPAUpdate", "find_cutoff", "fit_weights", "run_hpa", "CUTOFF_FLAGS", "FITS"]

#: How a cut-off was found.  ``"valley"`` is the normal case; the others are fallbacks.
CUTOFF_FLAGS = {
    "valley": "f_d at the PSD minimum between the voluntary content and the tremor peak",
    "no_tremor_peak": "no local PSD maximum inside tremor_band: default_cutoff used",
    "no_valley": "the PSD has no dip of min_depth_db below both sides: default_cutoff used",
    "silent": "the window has (near) zero variance: default_cutoff used, weights kept",
}
FITS = ("causal", "paper")

#: Largest |weight| the HPA hands over; the C core holds weights in Q24 within +-128.
WEIGHT_LIMIT = 32.0


@dataclass
class HPAUpdate:
    """What one HPA run produced (one entry of ``WakeResult.hpa``)."""

    index: int  #: number of samples received when the HPA ran
    cutoff: float  #: f_d in Hz
    cutoff_flag: str  #: a key of :data:`CUTOFF_FLAGS`
    weights: np.ndarray  #: observation vector w, shape (J,)
    measurement_noise: float  #: R, the variance of the tremor ground truth
    fit_error: float  #: the paper's e_L (RMS fit error over the window)
    ridge: float  #: the ridge factor finally used (raised when the fit was ill-conditioned)
    flags: tuple = field(default_factory=tuple)  #: extra notes: "regularised", "weights_kept"
    applied_at: int = -1  #: sample count at which the RTP took these weights (set by WakeFilter)


def find_cutoff(freqs, psd, *, tremor_band=(2.5, 15.0), cutoff_range=(0.5, 6.0),
                default_cutoff=2.0, min_depth_db=3.0):
    """Cut-off ``f_d`` at the valley between voluntary and tremor content.

    The tremor peak is the largest local maximum of the PSD inside
    ``tremor_band``.  The valley is the PSD minimum over ``cutoff_range``
    below that peak; it counts only if it lies at least ``min_depth_db``
    below both the tremor peak and the largest PSD value to its left
    (the voluntary content).  Otherwise ``default_cutoff`` is returned.

    Parameters
    ----------
    freqs, psd : array_like
        A spectrum from :func:`wake.spectrum.ar_psd`.
    tremor_band : (float, float)
        Where the tremor peak is searched, Hz.
    cutoff_range : (float, float)
        Where ``f_d`` may lie, Hz.  Every returned cut-off is inside it.
    default_cutoff : float
        The fallback, Hz; must lie in ``cutoff_range``.
    min_depth_db : float
        How deep a dip must be to count as a valley.

    Returns
    -------
    cutoff : float
    flag : str
        A key of :data:`CUTOFF_FLAGS`.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa import find_cutoff
    >>> f = np.linspace(0, 50, 501)
    >>> psd = np.exp(-f / 0.5) + np.exp(-((f - 8) ** 2) / 2)   # voluntary + tremor at 8 Hz
    >>> fd, flag = find_cutoff(f, psd)
    >>> flag, bool(2.0 < fd < 6.0)
    ('valley', True)
    """
    lo, hi = cutoff_range
    if not 0 < lo <= default_cutoff <= hi:
        raise ValueError(
            f"need 0 < cutoff_range[0] <= default_cutoff <= cutoff_range[1], got "
            f"cutoff_range={cutoff_range!r}, default_cutoff={default_cutoff!r}"
        )
    if not 0 < tremor_band[0] < tremor_band[1]:
        raise ValueError(f"tremor_band must be (low, high) with 0 < low < high, got {tremor_band!r}")
    freqs = np.asarray(freqs, dtype=float)
    psd = np.asarray(psd, dtype=float)
    if not np.isfinite(psd).all() or psd.max() <= 0:
        return float(default_cutoff), "silent"
    db = 10 * np.log10(np.maximum(psd, psd.max() * 1e-30))
    inner = np.flatnonzero((freqs >= tremor_band[0]) & (freqs <= tremor_band[1]))
    inner = inner[(inner > 0) & (inner < freqs.size - 1)]
    local_max = inner[(db[inner] >= db[inner - 1]) & (db[inner] >= db[inner + 1])]
    if local_max.size == 0:
        return float(default_cutoff), "no_tremor_peak"
    peak = local_max[np.argmax(db[local_max])]
    search = np.flatnonzero((freqs >= lo) & (freqs <= min(hi, freqs[peak])))
    if search.size < 3:
        return float(default_cutoff), "no_valley"
    valley = search[np.argmin(db[search])]
    left = db[: valley + 1].max()
    if db[valley] > db[peak] - min_depth_db or db[valley] > left - min_depth_db:
        return float(default_cutoff), "no_valley"
    return float(freqs[valley]), "valley"


def fit_weights(approximations, target, ridge=1e-6, weight_limit=WEIGHT_LIMIT):
    """Least-squares weights ``w`` minimising ``e_L = sqrt(|A w - y|^2 / L)``.

    ``e_L`` is quadratic in ``w``, so its minimum (which the paper reaches
    with a quasi-Newton search) has the closed form of the normal equations.
    A ridge ``lambda = ridge * trace(A'A) / J`` keeps the nearly collinear
    approximations well-posed; it is raised tenfold until every weight lies
    within ``weight_limit``.

    Returns
    -------
    weights : numpy.ndarray, shape (J,)
    fit_error : float
        ``e_L``.
    ridge : float
        The ridge factor used.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa import fit_weights
    >>> A = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> w, e, r = fit_weights(A, A @ [2.0, -1.0], ridge=0.0)
    >>> np.round(w, 6).tolist(), round(e, 9)
    ([2.0, -1.0], 0.0)
    """
    A = np.asarray(approximations, dtype=float)
    y = np.asarray(target, dtype=float)
    if A.ndim != 2 or y.shape != (A.shape[0],):
        raise ValueError(f"approximations must be (L, J) and target (L,), got {A.shape} and {y.shape}")
    if A.shape[0] < A.shape[1]:
        raise ValueError(f"need at least J = {A.shape[1]} rows to fit J weights, got {A.shape[0]}")
    J = A.shape[1]
    G = A.T @ A
    b = A.T @ y
    scale = np.trace(G) / J
    if not np.isfinite(scale) or scale <= 0:
        return np.zeros(J), float(np.sqrt(np.mean(y**2))), float(ridge)
    eye = np.eye(J)
    factor = float(ridge)
    for _ in range(16):
        w = np.linalg.solve(G + factor * scale * eye, b) if factor > 0 else np.linalg.lstsq(A, y, rcond=None)[0]
        if np.all(np.isfinite(w)) and np.max(np.abs(w)) <= weight_limit:
            break
        factor = max(factor * 10.0, 1e-9)
    else:  # pragma: no cover - a ridge of 1e7 * trace makes w tiny
        w = np.clip(w, -weight_limit, weight_limit)
    err = float(np.sqrt(np.mean((A @ w - y) ** 2)))
    return w, err, factor


def run_hpa(window, fs, *, taps, wavelet="sym3", level=5, mode="constant", ar_order=17,
            fit="causal", ridge=1e-6, tremor_band=(2.5, 15.0), cutoff_range=(0.5, 6.0),
            default_cutoff=2.0, previous_weights=None, index=0):
    """One HPA run over a window of the last ``L`` samples.

    Parameters
    ----------
    window : array_like, shape (L,)
    fs : float
    taps : numpy.ndarray, shape (J, 2**J)
        The RTP filter bank (:func:`wake.wavelets.filter_bank_taps`).
    fit : {"causal", "paper"}
        What ``w`` is fitted on (see the module docstring).
    previous_weights : numpy.ndarray, optional
        Kept when the window is silent.

    Returns
    -------
    HPAUpdate
    """
    if fit not in FITS:
        raise ValueError(f"unknown fit {fit!r}; valid choices: {', '.join(FITS)}")
    x = np.asarray(window, dtype=float)
    flags = []
    spread = np.std(x)
    if not spread > 1e-12 * max(1.0, np.max(np.abs(x))):
        w = np.array(previous_weights, dtype=float) if previous_weights is not None else _default_weights(level)
        floor = max(1e-12, (1e-6 * np.max(np.abs(x))) ** 2)
        return HPAUpdate(index, float(default_cutoff), "silent", w, float(floor), 0.0, float(ridge),
                         ("weights_kept",))
    freqs, psd = ar_psd(x, fs, ar_order)
    cutoff, flag = find_cutoff(freqs, psd, tremor_band=tremor_band, cutoff_range=cutoff_range,
                               default_cutoff=default_cutoff)
    tremor_gt = sharp_highpass(x, fs, cutoff)
    voluntary_gt = x - tremor_gt
    # R: variance of the tremor ground truth, floored at 1e-6 of the window's
    # variance so that a window with no tremor still gives S = w'Pw + R > 0.
    measurement_noise = float(max(np.var(tremor_gt), 1e-6 * spread**2))
    if fit == "causal":
        approx = filter_bank_outputs(x, taps)[:-1]  # a(k) for k = N-1 .. L-2
        target = voluntary_gt[taps.shape[1]:]  # v_GT(k + 1)
    else:
        approx = wavelet_approximations(x, wavelet, level, mode)
        target = voluntary_gt
    w, err, used = fit_weights(approx, target, ridge)
    if used > ridge:
        flags.append("regularised")
    return HPAUpdate(index, cutoff, flag, w, measurement_noise, err, used, tuple(flags))


def _default_weights(level):
    """Warm-up weights: the deepest approximation alone, a plain low-pass."""
    w = np.zeros(level)
    w[-1] = 1.0
    return w
