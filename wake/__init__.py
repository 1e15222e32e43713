"""wake: real-time pathological tremor extraction (WAKE).

WAKE splits a motion signal into voluntary motion and tremor one sample
ahead of time: a slow hyper-parameter adjustment (HPA, :mod:`wake.hpa`)
fits, every ``L`` samples, weights that map wavelet approximations to
voluntary motion; a per-sample real-time prediction (RTP, :mod:`wake.rtp`)
applies them through a fixed filter bank and a Kalman update.
:mod:`wake.firmware` carries the C sources and the firmware tooling,
:mod:`wake.eval` the datasets, baselines and metrics.

>>> import numpy as np
>>> from wake import WakeFilter
>>> from wake.eval.synthetic import make_signal
>>> s = make_signal(10.0, seed=0)
>>> result = WakeFilter(fs=100.0, backend="reference").run(s.measurement)
>>> bool(np.isfinite(result.voluntary).all())
True
"""

from wake._validation import SparseChannelWarning
from wake.rtp.adaptive import ClippingWarning
from wake.config import CoreMissingWarning, WakeConfig
from wake.filter import BACKENDS, WakeFilter, WakeResult, WakeState

__version__ = "0.2.0"

__all__ = ["WakeFilter", "WakeResult", "WakeState", "WakeConfig", "BACKENDS", "ClippingWarning",
           "CoreMissingWarning", "SparseChannelWarning", "__version__"]
