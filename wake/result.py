"""What :meth:`wake.WakeFilter.run` returns."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["WakeResult"]


@dataclass
class WakeResult:
    """What :meth:`WakeFilter.run` returns.

    ``prediction[k]`` is the prediction of the voluntary motion at sample
    ``k + 1`` made from ``x[:k + 1]`` (what ``update(x[k])`` returns);
    ``voluntary[k]`` is the prediction of sample ``k`` from ``x[:k]``
    (``voluntary[0] = 0``: nothing is known yet) and
    ``tremor = x - voluntary``.  The tremor ahead (:mod:`wake.ahead`) is
    aligned the same way, to the sample it is for: ``tremor_ahead[k]`` is the
    tremor at ``k`` predicted from ``x[:k - h + 1]`` (``h = horizon``; 0 for
    ``k < h``), ``confidence[k]`` the gate then and ``command[k]`` their
    product, what an actuator commanded ``h`` samples earlier plays at ``k``.
    Arrays are float32 when the input was float32, float64 otherwise.
    """

    voluntary: np.ndarray
    tremor: np.ndarray
    prediction: np.ndarray
    hpa: list  #: per channel, the list of :class:`~wake.hpa.HPAUpdate`
    warmup: int  #: samples before the first HPA (left out of the paper's scores)
    backend: str
    rtp: list = field(default=None, repr=False)  #: per channel, the RTP state after the last sample
    full_scale: np.ndarray = field(default=None)  #: per channel (C backend), else None
    clipped: np.ndarray = field(default=None)  #: input samples clipped to full scale, per channel
    saturations: np.ndarray = field(default=None)  #: saturating narrowings inside the C core, per channel
    full_scale_changes: np.ndarray = field(default=None)  #: rises and falls of the full scale, per channel
    tremor_ahead: np.ndarray = field(default=None)  #: the tremor at k predicted h samples before
    confidence: np.ndarray = field(default=None)  #: the gate in [0, 1] of that prediction
    command: np.ndarray = field(default=None)  #: confidence * tremor_ahead: what the actuator plays at k
    horizon: int = 1  #: h, samples ahead (WakeConfig.horizon)

    @property
    def cutoffs(self) -> list:
        """Per channel, the array of f_d over the HPA runs."""
        return [np.array([u.cutoff for u in ch]) for ch in self.hpa]

    @property
    def mean_cutoff(self) -> np.ndarray:
        """Per channel, the mean f_d over all HPA runs (the paper's offline cut-off)."""
        return np.array([c.mean() if c.size else np.nan for c in self.cutoffs])
