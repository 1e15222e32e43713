"""What WAKE predicts: the voluntary motion ``horizon`` samples after the newest sample.

One definition, read by every place that pairs a filter-bank output with
the sample it predicts: the HPA's causal fit (:func:`wake.hpa.run_hpa`), the
start-up prior (:func:`wake.hpa.prior.prior_weights`), the filter's output
alignment (:attr:`wake.WakeResult.voluntary`) and the C HPA
(``WAKE_HPA_HORIZON`` in csrc/wake_hpa.h, checked by
:func:`wake.hpa.c_port.c_mirror_problems`).  Today ``horizon = 1``: every
``update()`` answers with the prediction of the *next* sample, and the RTP's
Kalman update compares each prediction with the sample that follows
(csrc/wake_rtp.c, :mod:`wake.rtp.reference`), so a longer horizon needs
that update and the C HPA's normal equations as well.

Examples
--------
>>> import numpy as np
>>> from wake.target import PredictionTarget
>>> outputs, voluntary = np.arange(5.0), np.arange(10.0, 20.0)
>>> PredictionTarget().fit_pairs(outputs, voluntary, n_taps=6)   # a(k) for k = 5..8 against v(k + 1)
(array([0., 1., 2., 3.]), array([16., 17., 18., 19.]))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PredictionTarget", "TARGET"]


@dataclass(frozen=True)
class PredictionTarget:
    """The sample a prediction is for: ``horizon`` samples after the newest one it has read."""

    horizon: int = 1

    def fit_pairs(self, outputs, voluntary, n_taps: int):
        """The rows of the causal fit: filter-bank outputs ``a(k)``, ``k = N-1 .. L-1`` (``N = n_taps``),
        each against the voluntary ground truth ``v(k + horizon)`` of the same window."""
        return outputs[: outputs.shape[0] - self.horizon], voluntary[n_taps - 1 + self.horizon:]

    def phasor(self, freqs, fs: float):
        """``exp(j 2 pi f horizon / fs)``: the target of a sinusoid of frequency ``f`` seen at delay 0."""
        return np.exp(2j * np.pi * (self.horizon * freqs) / fs)

    def voluntary_from(self, prediction):
        """``voluntary[k]``, the prediction of sample ``k``, from ``prediction[k]``, the prediction made
        after sample ``k`` (zero before any prediction reaches ``k``)."""
        out = np.zeros_like(prediction)
        out[self.horizon:] = prediction[: prediction.shape[0] - self.horizon]
        return out


#: The target of every filter today (see the module docstring).
TARGET = PredictionTarget(horizon=1)
