"""The WAKE filter: the HPA every ``L`` samples, the RTP every sample.

This module schedules; it holds no number format and no backend internals. Each channel owns an RTP
object (:mod:`wake.rtp`) and the samples the next HPA (:mod:`wake.hpa`) needs.

Output contract: ``run(x).prediction == update_block(x) == [update(v) for v in x]`` bit for bit (the
prediction of the next sample; NaN marks a missing one); :attr:`WakeResult.voluntary` is it shifted by one.
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import fields

import numpy as np

from wake._validation import as_sample, as_signal, check_finite_channels
from wake.channel import Channel, start_weights_for
from wake.rate import make_channel
from wake._docs import parameters_doc
from wake.config import BACKENDS, TUNED_RATES, RateWarning, WakeConfig, warn_if_far_from_tuned_rate
from wake.hpa.c_port import check_c_hpa_config
from wake.result import WakeResult
from wake.rtp import load_fixed_point
from wake.state import STATE_VERSION, WakeState  # noqa: F401  (STATE_VERSION: the layout get_state writes)
from wake.target import TARGET, PredictionTarget, voluntary_ahead_refusal
from wake.wavelets import filter_bank_taps

__all__ = ["WakeFilter", "WakeResult", "WakeState", "BACKENDS", "RateWarning", "TUNED_RATES"]

_INFS = (float("inf"), float("-inf"))   # the values update() refuses (NaN marks a missing sample)


def _out_dtype(x) -> type:
    return np.float32 if np.asarray(x).dtype == np.float32 else np.float64


class WakeFilter:
    """Real-time tremor extraction with WAKE.

    Parameters
    ----------
    {config_parameters}: every setting of :class:`WakeConfig`, filled in from its docstring below the class
    config : WakeConfig, optional
        Every setting at once (then no other argument may be given).

    Notes
    -----
    Thread safety: one filter may be shared between threads. :meth:`update`,
    :meth:`update_block`, :meth:`reset`, :meth:`flush`, :meth:`get_state`,
    :meth:`set_state` and :meth:`close` hold the filter's lock, so calls from
    two threads are serialised: each sample is processed whole, and every
    HPA result is installed once and in order.  Which thread's sample comes
    first is up to the threads; to keep a stream in time order, feed it from
    one thread.  :meth:`run` builds a fresh state and touches no stream.
    The lock costs ~0.1 µs per ``update()``.

    Resources: ``hpa_mode="thread"`` starts one worker thread, stopped by
    :meth:`close`, by leaving a ``with WakeFilter(...) as f:`` block, or
    when the filter is garbage collected.  :attr:`hpa_history` keeps the
    newest ``hpa_history_limit`` updates per channel.

    Output contract: :meth:`update`, :meth:`update_block` and :attr:`WakeResult.prediction` of :meth:`run`
    all return, per sample, the prediction of the voluntary motion at the next sample, bit for bit alike
    (``tests/test_streaming.py``); NaN marks a missing sample in all three.

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeFilter
    >>> from wake.eval.synthetic import make_signal
    >>> s = make_signal(10.0, seed=3)
    >>> res = WakeFilter(fs=100.0, backend="reference").run(s.measurement)
    >>> res.voluntary.shape, len(res.hpa[0])   # HPAs: warm-up at 1, 2, 3, 4 s, then every 5 s
    ((5000,), 14)
    """

    def __init__(self, fs: float = 100.0, wavelet: str = "sym3", level: int = 5, window_s: float = 5.0,
                 ar_order: int = 17, *, config: WakeConfig | None = None, **settings):
        if config is not None:
            if settings or (fs, wavelet, level, window_s, ar_order) != (100.0, "sym3", 5, 5.0, 17):
                raise TypeError("give either config= or individual settings, not both")
            if not isinstance(config, WakeConfig):
                raise TypeError(f"config must be a WakeConfig, got {type(config).__name__}")
        else:
            valid = {f.name for f in fields(WakeConfig)}
            unknown = sorted(set(settings) - valid)
            if unknown:
                raise TypeError(f"unknown setting(s) {unknown}; valid settings: {', '.join(sorted(valid))}")
            config = WakeConfig(fs=fs, wavelet=wavelet, level=level, window_s=window_s, ar_order=ar_order,
                                **settings)
        if config.backend == "c" or config.hpa_backend == "c":
            load_fixed_point()  # fail here, with how to build the core, not at the first HPA
        bank = config.bank_config()  # the settings at the rate the bank runs at (wake.rate)
        if config.hpa_backend == "c":
            check_c_hpa_config(bank)
        warn_if_far_from_tuned_rate(config)
        self.config = config
        self.taps = filter_bank_taps(config.wavelet, config.level, config.mode)
        self.start_weights = start_weights_for(bank, self.taps)  # 0.5 ms: once per filter, not per channel
        self._pool = None
        self._lock = threading.RLock()
        self._channels: list[Channel] | None = None
        self._n_channels = None

    def __getattr__(self, name):
        # Settings read as attributes (filt.fs, filt.level, ...): one source, the config.
        config = self.__dict__.get("config")
        if config is not None and (name in WakeConfig.__dataclass_fields__ or name == "window_samples"):
            return getattr(config, name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _new_channels(self, n: int, *, streaming: bool = True) -> list:
        limit = self.config.hpa_history_limit if streaming else None
        return [make_channel(self.config, self.taps, self.start_weights, limit) for _ in range(n)]

    # -- whole recordings --------------------------------------------------
    def run(self, x, *, names=None) -> WakeResult:
        """Process a whole recording from a fresh state.

        Parameters
        ----------
        x : array_like, shape (n,) or (n, channels)
            At least one HPA window (``window_s * fs`` samples) long.  NaN marks a missing sample (as in
            :meth:`update`); inf is refused.  Each channel is filtered independently; one without a finite
            sample is refused, one with fewer than a window warned of (``check_finite_channels``).
        names : sequence of str, optional
            The channels' names for those messages (default ``channel 0``, ...).

        Returns
        -------
        WakeResult
            ``prediction`` equals ``reset()`` then ``update_block(x)``; the filter's stream is untouched.
        """
        arr, one_d = as_signal(x, allow_nan=True)
        n = arr.shape[0]
        if n < self.config.window_samples:
            transposed = (f"; x has shape {np.shape(x)}: if its rows are channels, pass x.T (samples run down "
                          "the first axis)") if arr.shape[1] > n else ""
            raise ValueError(
                f"the recording has {n} samples; WAKE needs at least one HPA window of "
                f"{self.config.window_samples} samples (window_s * fs = {self.config.window_s:g} s * "
                f"{self.config.fs:g} Hz){transposed}")
        check_finite_channels(arr, self.config.window_samples, names)
        channels = self._new_channels(arr.shape[1], streaming=False)
        out = np.stack([ch.process(arr[:, c]) for c, ch in enumerate(channels)], axis=-1)  # (5, n, channels)
        return self._result(arr, out, channels, one_d, _out_dtype(x))

    def _result(self, arr, out, channels, one_d, dtype):
        shape = (lambda a: a[:, 0]) if one_d else (lambda a: a)
        pred = out[0]
        vol = TARGET.voluntary_from(pred)  # voluntary[k] comes from x[:k]
        ahead = PredictionTarget(self.config.horizon)  # tremor_ahead[k] comes from x[:k - h + 1]
        cast = lambda a: shape(a).astype(dtype, copy=False)  # noqa: E731
        res = WakeResult(cast(vol), cast(arr - vol), cast(pred), [list(ch.updates) for ch in channels],
                         self.config.window_samples, self.config.backend, rtp=[ch.rtp.core for ch in channels],
                         tremor_ahead=cast(ahead.voluntary_from(out[1])), confidence=cast(ahead.voluntary_from(out[2])),
                         command=cast(ahead.voluntary_from(out[3])), horizon=self.config.horizon,
                         _voluntary_ahead=self._refusal() or cast(ahead.voluntary_from(out[4])))
        if self.config.backend == "c":
            rtps = [ch.rtp for ch in channels]
            res.full_scale = np.array([r.full_scale if r.full_scale is not None else np.nan for r in rtps])
            res.clipped = np.array([getattr(r.core, "clipped", 0) for r in rtps])
            res.saturations = np.array([getattr(r.core, "saturations", 0) for r in rtps])
            res.full_scale_changes = np.array([r.full_scale_changes for r in rtps])
        return res

    # -- streaming ---------------------------------------------------------
    def _ensure_channels(self, n: int, what: str):
        if self._channels is None:
            self._channels = self._new_channels(n)
            self._n_channels = n
            self.start_worker()  # with the stream, off the sample that completes the first HPA window
        elif n != self._n_channels:
            raise ValueError(
                f"this filter streams {self._n_channels} channel(s); got {what} with {n}. "
                "Call reset() to start a stream with another channel count")

    def update(self, sample):
        """Feed one sample (a scalar, or one value per channel); get the next prediction.

        Parameters
        ----------
        sample : float or array_like, shape (channels,)
            NaN marks a missing sample: the RTP predicts through it without
            a measurement update (docs/studies/design.md, "Missing samples").

        Returns
        -------
        float or numpy.ndarray
            The prediction of the voluntary motion at the next sample: a
            float for a scalar sample, an array of shape ``(channels,)``
            for an array.
        """
        with self._lock:
            if type(sample) is float and self._n_channels == 1:  # the hot path: one channel, a float
                if sample in _INFS:
                    raise ValueError(f"sample holds inf ({sample!r}); pass NaN for a missing sample")
                return float(self._channels[0].update(sample, self._executor))
            values = as_sample(sample)  # the same input policy as run() and update_block()
            self._ensure_channels(values.size, "a sample")
            out = np.array([ch.update(v, self._executor) for ch, v in zip(self._channels, values)])
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
            after ``x[i]`` (float32 for float32 input, else float64).
        """
        return self.update_block_ahead(x)[0]

    def update_block_ahead(self, x) -> tuple:
        """:meth:`update_block` with the tremor ahead: ``(prediction, tremor_ahead, confidence, command)``.

        Each is shaped like ``x``; row ``i`` is what :meth:`update` returns for ``x[i]`` and
        :attr:`last_ahead` after it: the tremor predicted for ``h = horizon`` samples after ``x[i]``, the
        gate's confidence and the gated command an actuator plays then (not shifted: :class:`WakeResult`
        aligns them to the sample they are for).
        """
        return self._block(x)[:4]

    def update_block_voluntary_ahead(self, x) -> tuple:
        """``(prediction, voluntary_ahead)``, shaped like ``x``: row ``i`` is :attr:`last_voluntary_ahead` after it.

        Examples
        --------
        >>> f = WakeFilter(backend="reference", horizon=5)
        >>> pred, ahead = f.update_block_voluntary_ahead(np.sin(np.arange(800) / 30.0))
        >>> bool(ahead[-1] == f.last_voluntary_ahead), bool(np.array_equal(ahead[:100], pred[:100]))  # held
        (True, True)
        """
        self._refusal(refuse=True)
        return self._block(x)[::4]

    def _block(self, x) -> tuple:
        arr, one_d = as_signal(x, allow_nan=True)
        with self._lock:
            self._ensure_channels(arr.shape[1], "a block")
            out = np.stack([ch.process(arr[:, c]) for c, ch in enumerate(self._channels)], axis=-1)
        dtype = _out_dtype(x)
        return tuple((o[:, 0] if one_d else o).astype(dtype, copy=False) for o in out)

    def _refusal(self, refuse: bool = False):
        return voluntary_ahead_refusal(self.horizon, self.backend, self.hpa_backend, refuse=refuse)

    @property
    def last_voluntary_ahead(self):
        """After :meth:`update`: the voluntary motion predicted ``horizon`` samples after the last sample (float
        for one channel, else per channel); ValueError on a backend without it (:func:`voluntary_ahead_refusal`)."""
        self._refusal(refuse=True)
        with self._lock:
            values = np.array([ch.rtp.last_voluntary_ahead for ch in (self._channels or [])])
            return float(values[0]) if self._n_channels == 1 else values

    @property
    def last_ahead(self) -> tuple:
        """After :meth:`update`: ``(tremor_ahead, confidence, command)`` for ``horizon`` samples after the
        last sample, floats for a one-channel stream, else arrays of shape ``(channels,)``.

        ``tremor_ahead`` is the tremor predicted there, ``confidence`` the gate in [0, 1] (0 until the
        second HPA, after a gap or a window without a tremor peak), ``command = confidence * tremor_ahead``
        what an actuator plays then (docs/studies/design.md, "How a firmware uses the command and the confidence").
        """
        with self._lock:
            rows = np.array([ch.rtp.last_ahead for ch in (self._channels or [])]).reshape(-1, 3)
            if self._n_channels == 1:
                return tuple(float(v) for v in rows[0])
            return tuple(rows[:, i].copy() for i in range(3))

    @property
    def rtp_states(self) -> list:
        """Per channel, the RTP object of the current stream (covariance, saturations, ...)."""
        with self._lock:
            return [ch.rtp.core for ch in (self._channels or [])]

    @property
    def hpa_history(self) -> list:
        """Per channel, a list of the newest ``hpa_history_limit`` HPA updates of the stream, oldest first."""
        with self._lock:
            return [list(ch.updates) for ch in (self._channels or [])]

    def reset(self) -> None:
        """Forget the stream (weights, history and RTP state)."""
        with self._lock:
            for ch in self._channels or []:
                if ch.pending is not None:
                    ch.pending[0].cancel()
            self._channels = None
            self._n_channels = None

    def flush(self) -> None:
        """Thread mode: wait for an HPA in flight and install its weights now."""
        with self._lock:
            for ch in self._channels or []:
                ch.swap_if_ready(wait=True)

    # -- explicit state ------------------------------------------------------
    def get_state(self) -> WakeState:
        """A copy of the stream's state (after installing any HPA in flight).

        Examples
        --------
        >>> import numpy as np
        >>> from wake import WakeFilter
        >>> x = np.sin(np.arange(1200) / 20.0)
        >>> f = WakeFilter(backend="reference"); _ = f.update_block(x[:700])
        >>> state = f.get_state()
        >>> a = f.update_block(x[700:])
        >>> g = WakeFilter(backend="reference"); g.set_state(state)
        >>> bool(np.array_equal(a, g.update_block(x[700:])))
        True
        """
        with self._lock:
            self.flush()
            return WakeState(self.config, [ch.state() for ch in (self._channels or [])])

    def set_state(self, state: WakeState) -> None:
        """Continue the stream from :meth:`get_state` (the configurations and layout versions must match)."""
        if not isinstance(state, WakeState):
            raise TypeError(f"state must be a WakeState from get_state(), got {type(state).__name__}")
        snapshots = state.channel_states()
        if state.config != self.config:
            raise ValueError("the state was taken from a filter with another configuration; "
                             "build the filter with WakeFilter(config=state.config)")
        with self._lock:
            self.reset()
            if snapshots:
                channels = self._new_channels(len(snapshots))
                for ch, snap in zip(channels, snapshots):
                    ch.load(snap)
                self._channels = channels
                self._n_channels = len(channels)

    def __getstate__(self):
        return {"state": self.get_state()}

    def __setstate__(self, st):
        state = st["state"]
        self.__init__(config=state.config)
        self.set_state(state)

    # -- worker thread -------------------------------------------------------
    def _executor(self):
        if self._pool is None:
            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="wake-hpa")
            # start the worker now (a no-op task), not inside the update() that completes a window:
            # importing concurrent.futures and starting the thread there cost that sample 10 ms
            self._pool.submit(int).result()
        return self._pool

    def start_worker(self) -> None:
        """Start the HPA worker thread now instead of with the first sample (thread mode).

        A live stream calls this before its first sample.  Nothing happens
        inline or when the worker runs already.
        """
        if self.config.hpa_mode == "thread":
            with self._lock:
                self._executor()

    def close(self) -> None:
        """Stop the HPA worker thread (thread mode); the filter stays usable.

        An HPA in flight is finished and installed first (:meth:`flush`), so
        closing loses nothing; a later window starts a new worker.
        """
        with self._lock:
            self.flush()
            if self._pool is not None:
                self._pool.shutdown(wait=True)
                self._pool = None

    def __enter__(self) -> "WakeFilter":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        pool = self.__dict__.get("_pool")
        if pool is not None:
            pool.shutdown(wait=False)


# Every WakeConfig setting is a WakeFilter argument: its docstring shows WakeConfig's parameter texts, the
# one place they are written, so help(WakeFilter) and help(WakeConfig) cannot disagree.
if WakeFilter.__doc__:
    WakeFilter.__doc__ = WakeFilter.__doc__.replace(
        "    {config_parameters}: every setting of :class:`WakeConfig`, filled in from its docstring below the class\n",
        parameters_doc(WakeConfig))
