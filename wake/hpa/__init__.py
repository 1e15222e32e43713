"""Hyper-parameter adjustment (HPA, the paper's Algorithm 1).

One module per step: :mod:`~wake.hpa.spectrum` (S1, Yule-Walker),
:mod:`~wake.hpa.cutoff` (S2, the valley ``f_d``), :mod:`~wake.hpa.sharp`
(the sharp high-pass ground truth), :mod:`~wake.hpa.fit` (S4, the weights);
:func:`run_hpa` chains them over one window.
"""

from wake.hpa.cutoff import CUTOFF_FLAGS, FALLBACK_FLAGS, find_cutoff
from wake.hpa.fit import default_weights, fit_weights
from wake.config import FITS
from wake.hpa.run import HPAUpdate, run_hpa
from wake.hpa.sharp import sharp_highpass
from wake.hpa.spectrum import ar_psd, levinson_durbin, yule_walker

__all__ = ["CUTOFF_FLAGS", "FALLBACK_FLAGS", "FITS", "HPAUpdate", "ar_psd", "default_weights",
           "find_cutoff", "fit_weights", "levinson_durbin", "run_hpa", "sharp_highpass", "yule_walker"]
