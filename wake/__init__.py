"""wake: real-time pathological tremor extraction (WAKE).

WAKE splits a motion signal into voluntary motion and tremor one sample
ahead of time: a slow hyper-parameter adjustment (HPA) fits, every ``L``
samples, weights that map wavelet approximations to voluntary motion; a
per-sample real-time prediction (RTP) applies them through a fixed filter
bank and a Kalman update.

>>> import numpy as np
>>> from wake import WakeFilter
>>> from wake.synthetic import make_signal
>>> s = make_signal(10.0, seed=0)
>>> result = WakeFilter(fs=100.0, backend="reference").run(s.measurement)
>>> bool(np.isfinite(result.voluntary).all())
True
"""

from .filter import BACKENDS, WakeFilter, WakeResult
from .hpa import CUTOFF_FLAGS, HPAUpdate, find_cutoff, fit_weights, run_hpa
from .metrics import nrmse, offline_ground_truth, prf, snr_out
from .rtp_reference import ReferenceRTP
from .sharp import sharp_highpass
from .spectrum import ar_psd, levinson_durbin, yule_walker
from .wavelets import filter_bank_outputs, filter_bank_taps, wavelet_approximations

__version__ = "0.1.0"

__all__ = [
    "WakeFilter", "WakeResult", "BACKENDS", "HPAUpdate", "CUTOFF_FLAGS", "run_hpa", "find_cutoff",
    "fit_weights", "ReferenceRTP", "sharp_highpass", "ar_psd", "levinson_durbin", "yule_walker",
    "filter_bank_taps", "filter_bank_outputs", "wavelet_approximations", "nrmse", "prf", "snr_out",
    "offline_ground_truth",
]
