"""The WAKE filter: HPA every ``L`` samples, RTP every sample."""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import numpy as np

from ._validation import as_signal, check_level, check_mode, check_positive, check_wavelet
from .hpa import FITS, HPAUpdate, _default_weights, run_hpa
from .rtp_reference import ReferenceRTP
from .wavelets import DEFAULT_MODE, filter_bank_taps

__all__ = ["WakeFilter", "WakeResult", "BACKENDS"]

BACKENDS = ("c", "reference")
_INF = float("inf")
HPA_MODES = ("inline", "thread")


def c_backend_available() -> bool:
    """Whether the compiled RTP core (``wake._rtp``) imports."""
    try:
        from . import _rtp  # noqa: F401
    except Exception:  # ImportError, or a broken build
        return False
    return True
#: Highest level the fixed-point C core is built for (WAKE_RTP_MAX_LEVEL).
C_MAX_LEVEL = 6


@dataclass
class WakeResult:
    """What :meth:`WakeFilter.run` returns.

    ``voluntary[k]`` is the prediction of the voluntary motion at sample
    ``k`` made from ``x[:k]`` alone; ``tremor = x - voluntary``.
    """

    voluntary: np.ndarray
    tremor: np.ndarray
    hpa: list  #: per channel, the list of :class:`~wake.hpa.HPAUpdate`
    warmup: int  #: samples before the first HPA (left out of the paper's scores)
    backend: str
    rtp: list = field(default=None, repr=False)  #: per channel, the RTP state after the last sample
    full_scale: np.ndarray = field(default=None)  #: per channel (C backend), else None
    clipped: np.ndarray = field(default=None)  #: input samples clipped to full scale, per channel
    saturations: np.ndarray = field(default=None)  #: saturating narrowings inside the C core, per channel

    @property
    def cutoffs(self):
        """Per channel, the array of f_d over the HPA runs."""
        return [np.array([u.cutoff for u in ch]) for ch in self.hpa]

    @property
    def mean_cutoff(self):
        """Per channel, the mean f_d over all HPA runs (the paper's offline cut-off)."""
        return np.array([c.mean() if c.size else np.nan for c in self.cutoffs])


class _Channel:
    """HPA bookkeeping and RTP state of one channel."""

    def __init__(self, owner: "WakeFilter"):
        self.owner = owner
        self.reset()

    def reset(self):
        o = self.owner
        self.weights = _default_weights(o.level)
        self.measurement_noise = 1.0
        self.rtp = ReferenceRTP(o.taps, self.weights, self.measurement_noise,
                                o._process_noise(self.measurement_noise), o.initial_covariance)
        self.on_c = False
        self.full_scale = o.full_scale
        self.updates: list[HPAUpdate] = []
        self.history = np.zeros(o.window_samples)
        self.pos = 0
        self.count = 0
        self.pending = None  # thread mode: (future, window) of an HPA still off the sample path
        if o.backend == "c" and o.full_scale is not None:
            self._switch_to_c(o.full_scale)

    # -- HPA ---------------------------------------------------------------
    def hpa_arguments(self, window, index, previous_weights):
        # Everything the HPA reads is passed in: off the sample path it runs
        # while the channel keeps changing.  Gaps (NaN) are interpolated for
        # the spectrum here, the one door every window goes through.
        o = self.owner
        if np.isnan(window).any():
            window = _fill_gaps(window)
        return (window, o.fs), dict(taps=o.taps, wavelet=o.wavelet, level=o.level, mode=o.mode,
                                    ar_order=o.ar_order, fit=o.fit, ridge=o.ridge, tremor_band=o.tremor_band,
                                    cutoff_range=o.cutoff_range, default_cutoff=o.default_cutoff,
                                    previous_weights=previous_weights, index=index)

    def compute_hpa(self, window, index, previous_weights):
        args, kwargs = self.hpa_arguments(window, index, previous_weights)
        return run_hpa(*args, **kwargs)

    def hpa(self, window):
        upd = self.compute_hpa(window, self.count, self.weights)
        self.apply(upd, window, first_sample=self.count)
        return upd

    def apply(self, upd, window, first_sample):
        """Install an HPA result; ``first_sample`` is the 1-based number of the
        first sample whose RTP step uses it (recorded as ``applied_at``)."""
        o = self.owner
        upd.applied_at = first_sample
        self.updates.append(upd)
        self.weights = upd.weights
        self.measurement_noise = upd.measurement_noise
        if o.backend == "c" and not self.on_c:
            observed = window[~np.isnan(window)]  # the window may hold gaps
            peak = float(np.max(np.abs(observed))) if observed.size else 0.0
            self._switch_to_c(o.headroom * peak if peak > 0 else 1.0)
        q = o._process_noise(self.measurement_noise)
        if self.on_c:
            self.measurement_noise, q, clamped = _representable_noise(self.measurement_noise, q, self.full_scale)
            if clamped:
                upd.flags = upd.flags + ("noise_clamped",)
        self.rtp.set_weights(self.weights, self.measurement_noise, q)

    def _switch_to_c(self, full_scale):
        from ._c_backend import FixedPointRTP

        o = self.owner
        r, q, _ = _representable_noise(self.measurement_noise, o._process_noise(self.measurement_noise),
                                       full_scale)
        p0 = _representable_noise(1.0, o.initial_covariance, full_scale)[1]
        c = FixedPointRTP(o.taps, self.weights, r, q, p0, full_scale=full_scale)
        ref = self.rtp
        if ref.primed:
            window = np.concatenate((ref.buffer[ref.head:], ref.buffer[: ref.head]))
            # The float warm-up state, clipped into the C formats (a huge
            # initial_covariance or a runaway correction cannot be held).
            from ._c_backend import P_FRAC, STATE_FRAC

            top_p = (2.0**31 - 1) * full_scale**2 / 2.0**P_FRAC
            top_x = (2.0**31 - 1) * full_scale / 2.0**STATE_FRAC
            c.load_state(window, np.clip(ref.correction, -top_x, top_x), np.clip(ref.covariance, -top_p, top_p),
                         float(np.clip(ref.last_output, -top_x, top_x)))
        self.rtp = c
        self.on_c = True
        self.full_scale = full_scale

    # -- samples -------------------------------------------------------------
    def process(self, x):
        """A block of samples continuing the stream: ``y[i]`` is what
        ``update(x[i])`` would return (the prediction for the next sample)."""
        o = self.owner
        L = o.window_samples
        n = x.shape[0]
        y = np.empty(n)
        if o.hpa_mode == "thread":
            self.swap_if_ready(wait=True, first_sample=self.count + 1)
        seen = np.concatenate((self.ordered_history(), x))  # the last L samples before x, then x
        base = self.count
        start = 0
        # After sample number c arrives, an HPA runs when c is a multiple of L,
        # before that sample's RTP step.
        first_hpa = (-(base + 1)) % L  # index in x of the first sample completing a window
        for stop in list(range(first_hpa, n, L)) + [n]:
            if start < stop:
                y[start:stop] = self.rtp.run(x[start:stop])
            if stop < n:
                self.count = base + stop + 1
                self.hpa(seen[stop + 1 : stop + 1 + L])
            start = stop
        self.count = base + n
        self.history = seen[-L:].copy()
        self.pos = 0
        return y

    def swap_if_ready(self, wait=False, first_sample=None):
        """Thread mode: install a finished HPA between two samples."""
        if self.pending is None:
            return
        future, window = self.pending
        if wait or future.done():
            self.pending = None
            self.apply(future.result(), window, self.count + 1 if first_sample is None else first_sample)

    def update(self, sample):
        o = self.owner
        if self.pending is not None:
            self.swap_if_ready()
        # history is a ring: self.pos is the oldest sample
        self.history[self.pos] = sample
        self.pos = (self.pos + 1) % o.window_samples
        self.count += 1
        if self.count % o.window_samples == 0:
            window = self.ordered_history()
            if o.hpa_mode == "inline":
                self.hpa(window)
            else:
                # One HPA in flight at a time: a new window waits for the last
                # one (it had L samples' time to finish).
                self.swap_if_ready(wait=True, first_sample=self.count)
                args, kwargs = self.hpa_arguments(window, self.count, self.weights.copy())
                job = o._executor().submit(run_hpa, *args, **kwargs)
                self.pending = (job, window)
        if sample != sample:
            return self.rtp.step_missing()
        return self.rtp.step(sample)

    def ordered_history(self):
        """The last L samples, oldest first (a copy)."""
        return np.concatenate((self.history[self.pos :], self.history[: self.pos]))


def _representable_noise(r, q, full_scale):
    """Clamp R and q into what the C core holds (Q(P_FRAC) of full_scale**2).

    R below one LSB (a window with no tremor, a large full scale) is raised to
    one LSB; R or q above the Q format's range (a full scale set below the
    signal) are lowered to its top.  Returns ``(r, q, clamped)``.
    """
    from ._c_backend import P_FRAC

    lsb = full_scale**2 / 2.0**P_FRAC
    top = (2.0**31 - 1) * lsb
    r2 = min(max(r, lsb), top)
    q2 = 0.0 if q == 0 else min(max(q, lsb), top)
    return r2, q2, (r2 != r or q2 != q)


def _fill_gaps(window):
    """Linear interpolation over NaN for the HPA's spectrum (edges held)."""
    good = ~np.isnan(window)
    if not good.any():
        return np.zeros_like(window)
    idx = np.arange(window.shape[0])
    return np.interp(idx, idx[good], window[good])


class WakeFilter:
    """Real-time tremor extraction with WAKE.

    Parameters
    ----------
    fs : float
        Sampling rate in Hz.
    wavelet : str
        Mother wavelet (a discrete PyWavelets name; the paper: ``"sym3"``).
    level : int
        Decomposition level ``J``; the RTP window is ``2**J`` samples.
        1..8 on the reference backend, 1..6 on the C backend.
    window_s : float
        HPA window ``L`` in seconds; HPA runs every ``L`` samples.
        ``L`` must hold at least ``2 * 2**J`` samples and more than
        ``2 * ar_order``.
    ar_order : int
        Yule-Walker AR order ``p``.
    backend : {"c", "reference"}
        ``"c"`` runs the RTP in the fixed-point C core; ``"reference"`` in
        the float64 reference it is tested against.
    mode : str
        Wavelet boundary mode of the filter bank (see docs/design.md).
    fit : {"causal", "paper"}
        What the HPA fits ``w`` on (see :mod:`wake.hpa`).
    process_noise : float
        ``Q = q R I``: process noise per sample, relative to ``R``.
        0 (the default, see docs/design.md) keeps the pure filter bank.
    initial_covariance : float
        ``P(0) = p0 I`` in squared signal units.
    ridge : float
        Relative ridge of the weight fit.
    tremor_band, cutoff_range, default_cutoff
        Cut-off search, see :func:`wake.hpa.find_cutoff`.
    full_scale : float, optional
        C backend: the physical value mapped to the int16 full scale.
        ``None`` picks ``headroom * max|x|`` over the first HPA window, per
        channel (the float reference runs the warm-up until then).
    headroom : float
        Factor of the automatic full scale (>= 1).  16 (24 dB) because real
        recordings often start quiet: on the PADS recordings 4x clipped, 16x
        did not (docs/fixed_point.md); it costs 4 of the 16 bits.
    hpa_mode : {"inline", "thread"}
        Streaming only (:meth:`update`).  ``"inline"`` runs the HPA inside
        the ``update()`` call that completes a window; ``"thread"`` runs it
        on a worker thread and swaps the new weights in between two later
        samples, so ``update()`` never waits for an HPA.  Each
        :class:`~wake.hpa.HPAUpdate` records the sample count at which its
        weights took effect (``applied_at``).  The worker still shares the
        interpreter lock with ``update()``; docs/design.md ("Non-blocking
        HPA") has the measured latencies.  :meth:`run` is always inline.

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeFilter
    >>> from wake.synthetic import make_signal
    >>> s = make_signal(10.0, seed=3)
    >>> res = WakeFilter(fs=100.0, backend="reference").run(s.measurement)
    >>> res.voluntary.shape, len(res.hpa[0])
    ((5000,), 9)
    """

    def __init__(self, fs=100.0, wavelet="sym3", level=5, window_s=5.0, ar_order=17, *,
                 backend="c", mode=DEFAULT_MODE, fit="causal", process_noise=0.0,
                 initial_covariance=0.0, ridge=1e-6, tremor_band=(2.5, 15.0),
                 cutoff_range=(0.5, 6.0), default_cutoff=2.0, full_scale=None, headroom=16.0,
                 hpa_mode="inline"):
        self.fs = check_positive("fs", fs)
        check_wavelet(wavelet)
        self.wavelet = wavelet
        if backend not in BACKENDS:
            raise ValueError(f"unknown backend {backend!r}; valid choices: {', '.join(BACKENDS)}")
        self.backend = backend
        self.level = check_level(level, C_MAX_LEVEL if backend == "c" else 8)
        self.mode = check_mode(mode)
        self.window_s = check_positive("window_s", window_s)
        self.ar_order = check_positive("ar_order", ar_order, integer=True)
        self.window_samples = int(round(self.window_s * self.fs))
        need = max(2 * 2**self.level, 2 * self.ar_order + 1)
        if self.window_samples < need:
            raise ValueError(
                f"the HPA window holds {self.window_samples} samples (window_s * fs); level {self.level} "
                f"and ar_order {self.ar_order} need at least {need}: lengthen window_s to "
                f">= {need / self.fs:g} s or lower the level"
            )
        if fit not in FITS:
            raise ValueError(f"unknown fit {fit!r}; valid choices: {', '.join(FITS)}")
        self.fit = fit
        self.process_noise_ratio = check_positive("process_noise", process_noise, allow_zero=True)
        self.initial_covariance = check_positive("initial_covariance", initial_covariance, allow_zero=True)
        self.ridge = check_positive("ridge", ridge, allow_zero=True)
        nyquist = self.fs / 2
        lo, hi = _pair("tremor_band", tremor_band)
        if not 0 < lo < hi <= nyquist:
            raise ValueError(f"tremor_band must satisfy 0 < low < high <= fs/2 = {nyquist}, got {tremor_band!r}")
        clo, chi = _pair("cutoff_range", cutoff_range)
        if not 0 < clo < chi < nyquist:
            raise ValueError(f"cutoff_range must satisfy 0 < low < high < fs/2 = {nyquist}, got {cutoff_range!r}")
        self.tremor_band = (lo, hi)
        self.cutoff_range = (clo, chi)
        self.default_cutoff = check_positive("default_cutoff", default_cutoff)
        if not clo <= self.default_cutoff <= chi:
            raise ValueError(f"default_cutoff must lie in cutoff_range {self.cutoff_range}, got {default_cutoff}")
        self.full_scale = None if full_scale is None else check_positive("full_scale", full_scale)
        self.headroom = check_positive("headroom", headroom)
        if self.headroom < 1:
            raise ValueError(f"headroom must be >= 1 (it multiplies the window's peak), got {headroom}")
        if hpa_mode not in HPA_MODES:
            raise ValueError(f"unknown hpa_mode {hpa_mode!r}; valid choices: {', '.join(HPA_MODES)}")
        self.hpa_mode = hpa_mode
        self._pool = None
        self.taps = filter_bank_taps(wavelet, self.level, mode)
        self._channels: list[_Channel] | None = None
        self._n_channels = None

    def _process_noise(self, measurement_noise):
        """Absolute ``q`` pushed to the RTP: ``process_noise * R`` of the current window."""
        return self.process_noise_ratio * measurement_noise

    # -- whole recordings --------------------------------------------------
    def run(self, x):
        """Process a whole recording.

        Parameters
        ----------
        x : array_like, shape (n,) or (n, channels)
            At least one HPA window (``window_s * fs`` samples) long; every
            sample finite.  Each channel is filtered independently.

        Returns
        -------
        WakeResult

        Notes
        -----
        ``run`` starts from a fresh state and leaves the filter's streaming
        state untouched; ``run(x)`` equals ``reset()`` and ``update()`` on
        every sample of ``x``.
        """
        arr, one_d = as_signal(x)
        n = arr.shape[0]
        if n < self.window_samples:
            raise ValueError(
                f"the recording has {n} samples; WAKE needs at least one HPA window of "
                f"{self.window_samples} samples (window_s * fs = {self.window_s:g} s * {self.fs:g} Hz)"
            )
        channels = [_Channel(self) for _ in range(arr.shape[1])]
        out = np.zeros_like(arr)
        for c, ch in enumerate(channels):
            out[1:, c] = ch.process(arr[:, c])[:-1]  # voluntary[k] comes from x[:k]
        return self._result(arr, out, channels, one_d)

    def _result(self, arr, out, channels, one_d):
        shape = (lambda a: a[:, 0]) if one_d else (lambda a: a)
        res = WakeResult(shape(out), shape(arr - out), [ch.updates for ch in channels],
                         self.window_samples, self.backend, rtp=[ch.rtp for ch in channels])
        if self.backend == "c":
            res.full_scale = np.array([ch.full_scale if ch.full_scale is not None else np.nan for ch in channels])
            res.clipped = np.array([getattr(ch.rtp, "clipped", 0) for ch in channels])
            res.saturations = np.array([getattr(ch.rtp, "saturations", 0) for ch in channels])
        return res

    # -- streaming ---------------------------------------------------------
    def update(self, sample):
        """Feed one sample (a scalar, or one value per channel); get the next prediction.

        NaN marks a missing sample: the RTP predicts through it without a
        measurement update (docs/design.md, "Missing samples").
        """
        if type(sample) is float and self._n_channels == 1:  # the hot path: one channel, a float
            if sample in (_INF, -_INF):
                raise ValueError(f"sample holds inf ({sample!r}); pass NaN for a missing sample")
            return float(self._channels[0].update(sample))
        values = np.asarray(sample, dtype=float).reshape(-1)
        if values.size == 0:
            raise ValueError("update() needs one value per channel, got an empty sample")
        if np.isinf(values).any():
            raise ValueError(f"sample holds inf ({sample!r}); pass NaN for a missing sample")
        if self._channels is None:
            self._channels = [_Channel(self) for _ in range(values.size)]
            self._n_channels = values.size
        elif values.size != self._n_channels:
            raise ValueError(
                f"this filter streams {self._n_channels} channel(s); got {values.size} value(s). "
                "Call reset() to start a stream with another channel count"
            )
        out = np.array([ch.update(v) for ch, v in zip(self._channels, values)])
        return float(out[0]) if np.ndim(sample) == 0 else out

    def update_block(self, x):
        """Feed a block of samples to the stream; same outputs as ``update()`` per sample.

        Parameters
        ----------
        x : array_like, shape (n,) or (n, channels)
            NaN marks a missing sample; inf is refused.

        Returns
        -------
        numpy.ndarray, same shape as ``x``
            ``out[i]`` is the prediction of the voluntary motion at the sample
            after ``x[i]``.
        """
        arr, one_d = as_signal(x, allow_nan=True)
        if self._channels is None:
            self._channels = [_Channel(self) for _ in range(arr.shape[1])]
            self._n_channels = arr.shape[1]
        elif arr.shape[1] != self._n_channels:
            raise ValueError(
                f"this filter streams {self._n_channels} channel(s); got a block with {arr.shape[1]}. "
                "Call reset() to start a stream with another channel count"
            )
        out = np.column_stack([ch.process(arr[:, c]) for c, ch in enumerate(self._channels)])
        return out[:, 0] if one_d else out

    @property
    def rtp_states(self):
        """Per channel, the RTP object of the current stream (covariance, saturations, ...)."""
        return [ch.rtp for ch in (self._channels or [])]

    def reset(self):
        """Forget the stream (weights, history and RTP state)."""
        for ch in self._channels or []:
            if ch.pending is not None:
                ch.pending[0].cancel()
        self._channels = None
        self._n_channels = None

    def flush(self):
        """Thread mode: wait for an HPA in flight and install its weights now."""
        for ch in self._channels or []:
            ch.swap_if_ready(wait=True)

    def _executor(self):
        if self._pool is None:
            from concurrent.futures import ThreadPoolExecutor

            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="wake-hpa")
        return self._pool

    def close(self):
        """Stop the HPA worker thread (thread mode); the filter stays usable."""
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None

    def __del__(self):
        pool = getattr(self, "_pool", None)
        if pool is not None:
            pool.shutdown(wait=False)

    @property
    def hpa_history(self):
        """Per channel, the HPA updates of the current stream."""
        return [ch.updates for ch in (self._channels or [])]


def _pair(name, value):
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (low, high) in Hz, got {value!r}") from None
    for v in (lo, hi):
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not np.isfinite(v):
            raise ValueError(f"{name} must hold two finite numbers, got {value!r}")
    return float(lo), float(hi)
