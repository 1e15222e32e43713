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
    :attr:`voluntary_ahead` is the voluntary motion at ``k`` predicted from
    ``x[:k - h + 1]`` by the HPA's second weight vector ``w_h``
    (docs/studies/design.md, "Voluntary motion at n + h").
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
    #: the voluntary motion ahead, or why this filter cannot give it (read :attr:`voluntary_ahead`)
    _voluntary_ahead: np.ndarray | str | None = field(default=None, repr=False)

    @property
    def voluntary_ahead(self) -> np.ndarray:
        """The voluntary motion at ``k`` predicted ``h`` samples before (``w_h' (a + d)`` of the RTP after
        sample ``k - h``; 0 for ``k < h``).

        Until the first HPA fits ``w_h`` it is the one-step prediction held over ``h`` samples, and at
        ``h = 1`` it equals :attr:`voluntary`.  ``ValueError`` on a backend that cannot produce it
        (:func:`wake.target.voluntary_ahead_refusal`: the Python HPA can, on either RTP backend).

        Examples
        --------
        >>> import numpy as np
        >>> from wake import WakeFilter
        >>> t = np.arange(1500) / 100.0
        >>> x = np.sin(2 * np.pi * 0.5 * t) + 0.2 * np.sin(2 * np.pi * 6 * t)
        >>> res = WakeFilter(backend="reference", horizon=5).run(x)
        >>> truth = np.sin(2 * np.pi * 0.5 * t)
        >>> fitted = np.sqrt(np.mean((res.voluntary_ahead - truth)[500:] ** 2))
        >>> held = np.sqrt(np.mean((np.r_[np.zeros(4), res.voluntary[:-4]] - truth)[500:] ** 2))
        >>> bool(fitted < held)   # fitting ahead beats holding the one-step estimate 4 more samples
        True
        """
        if isinstance(self._voluntary_ahead, str):
            raise ValueError(self._voluntary_ahead)
        if self._voluntary_ahead is None:
            raise ValueError("this result holds no voluntary_ahead (it was not made by WakeFilter.run)")
        return self._voluntary_ahead

    def tremor_stats(self, fs: float, tremor_band=(2.5, 15.0), x=None) -> list:
        """Per channel, the tremor of each HPA window (:func:`wake.hpa.characterise.tremor_table`).

        Parameters
        ----------
        fs : float
            The filter's sampling rate in Hz.
        tremor_band : pair of float
            The filter's ``WakeConfig.tremor_band``.
        x : array_like, optional
            The input; by default ``voluntary + tremor`` (the input up to
            rounding, NaN where a sample was missing).

        Returns
        -------
        list of numpy.ndarray
            Per channel, a structured array with one row per HPA run
            (``end_time``, ``frequency``, ``rms``, ``peak_to_peak``,
            ``band_power``, ``time_share``, ``tsi``, ``reason``, ...).

        Examples
        --------
        >>> import numpy as np
        >>> from wake import WakeFilter
        >>> t = np.arange(1000) / 100.0
        >>> x = np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 6 * t)
        >>> table = WakeFilter(backend="reference").run(x).tremor_stats(100.0)[0]
        >>> float(table["end_time"][-1]), round(float(table["frequency"][-1]), 2)
        (10.0, 6.0)
        """
        from wake.hpa.characterise import tremor_table

        data = np.asarray(self.voluntary, dtype=float) + np.asarray(self.tremor, dtype=float) if x is None else x
        data = np.asarray(data, dtype=float).reshape(len(data), -1)
        if data.shape[1] != len(self.hpa):
            raise ValueError(f"x has {data.shape[1]} channel(s), the result {len(self.hpa)}")
        return [tremor_table(data[:, c], fs, self.hpa[c], self.warmup, tremor_band) for c in range(len(self.hpa))]

    @property
    def cutoffs(self) -> list:
        """Per channel, the array of f_d over the HPA runs."""
        return [np.array([u.cutoff for u in ch]) for ch in self.hpa]

    @property
    def mean_cutoff(self) -> np.ndarray:
        """Per channel, the mean f_d over all HPA runs (the paper's offline cut-off)."""
        return np.array([c.mean() if c.size else np.nan for c in self.cutoffs])
