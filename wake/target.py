"""What WAKE predicts: the voluntary motion ``horizon`` samples after the newest sample.

One definition, read by every place that pairs a filter-bank output with
the sample it predicts: the HPA's causal fit (:func:`wake.hpa.run_hpa`), the
start-up prior (:func:`wake.hpa.prior.prior_weights`), the filter's output
alignment (:attr:`wake.WakeResult.voluntary`) and the C HPA
(``WAKE_HPA_HORIZON`` in csrc/wake_hpa.h, checked by
:func:`wake.hpa.c_port.c_mirror_problems`).  The one-step target
:data:`TARGET` has ``horizon = 1``: every ``update()`` answers with the
prediction of the *next* sample, and the RTP's Kalman update compares each
prediction with the sample that follows (csrc/wake_rtp.c,
:mod:`wake.rtp.reference`).

The voluntary motion ``h`` samples ahead (``WakeConfig.horizon = h > 1``,
docs/studies/design.md, "Voluntary motion at n + h") reads the same rule at another
horizon: the HPA fits a second weight vector ``w_h`` on
``PredictionTarget(h).fit_pairs`` (:func:`wake.hpa.run_hpa`), the RTP outputs
``w_h' (a + d)`` from the state of its one-step prediction, and
``PredictionTarget(h).voluntary_from`` aligns it to the sample it is for
(:attr:`wake.WakeResult.voluntary_ahead`).  :func:`voluntary_ahead_refusal`
says which backends produce it.

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

__all__ = ["PredictionTarget", "TARGET", "voluntary_ahead_refusal"]


@dataclass(frozen=True)
class PredictionTarget:
    """The sample a prediction is for: ``horizon`` samples after the newest one it has read."""

    horizon: int = 1

    def fit_pairs(self, outputs, voluntary, n_taps: int):
        """The rows of the causal fit: filter-bank outputs ``a(k)``, ``k = N-1 .. L-1`` (``N = n_taps``),
        each against the voluntary ground truth ``v(k + horizon)`` of the same window (or of each window of a
        stack: ``outputs`` (W, m, J), ``voluntary`` (W, n))."""
        if np.ndim(outputs) == 3:
            return outputs[:, : outputs.shape[1] - self.horizon], voluntary[:, n_taps - 1 + self.horizon:]
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


def voluntary_ahead_refusal(horizon: int, backend: str, hpa_backend: str = "python", *, refuse: bool = False):
    """Why a filter cannot give the voluntary motion ``horizon`` samples ahead, or None when it can (with
    ``refuse``, ``ValueError`` with that reason instead of returning it).

    At ``horizon = 1`` it is the one-step ``voluntary`` on every backend.  Beyond, the second weight
    vector ``w_h`` is fitted by the Python HPA only (the C HPA does not fit one) and run by both RTPs,
    the float reference and the C core (built with ``WAKE_RTP_VOLUNTARY_AHEAD``; docs/studies/design.md,
    "Voluntary motion at n + h").

    Examples
    --------
    >>> voluntary_ahead_refusal(5, "reference") is None, voluntary_ahead_refusal(5, "c") is None
    (True, True)
    >>> print(voluntary_ahead_refusal(5, "c", "c").split(" (")[0])
    voluntary_ahead at horizon 5 needs hpa_backend='python'
    """
    why = _why_no_voluntary_ahead(horizon, backend, hpa_backend)
    if why is not None and refuse:
        raise ValueError(why)
    return why


def _why_no_voluntary_ahead(horizon: int, backend: str, hpa_backend: str):
    if horizon == 1:
        return None
    if backend not in ("reference", "c"):
        return (f"voluntary_ahead at horizon {horizon} needs backend='reference' or 'c' (the RTPs that run the "
                f"second weight vector w_h), got backend={backend!r}")
    if hpa_backend != "python":
        return (f"voluntary_ahead at horizon {horizon} needs hpa_backend='python' (the Python HPA fits the "
                f"second weight vector w_h; the C HPA does not), got hpa_backend={hpa_backend!r}")
    return None
