"""WAKE at any input rate: a decimating front end, one channel at the bank rate, the prediction carried back.

The filter bank and the HPA were designed at 100 Hz (a level-5 bank spans
320 ms).  At a higher input rate ``fs`` a channel runs them at the bank rate
``fs / D``, ``D = WakeConfig.decimation_factor`` (``round(fs / 100)``, so the
bank rate lies within 67-133 Hz), and this module does the rest
(docs/studies/design.md, "Sampling rates other than 100 Hz", has the measurement
behind the choice):

- **front end** (:class:`FrontEnd`): a causal boxcar of ``D`` input samples
  (the mean of the finite ones; NaN when all are missing), one output at the
  last sample of each group.  Group ``m`` holds inputs ``m D .. m D + D - 1``
  and is centred at input time ``m D + (D - 1) / 2``.
- **the channel** (:class:`wake.channel.Channel`) at ``fs / D``: after group
  ``m`` it predicts group ``m + 1``, i.e. the input samples
  ``(m + 1) D .. (m + 2) D - 1``, centred ``D`` later than group ``m``.
- **carry-back**: that prediction ``p_m`` is held as the prediction of
  each input sample of group ``m + 1``: it predicts the group's mean, whose
  centre lies within ``(D - 1) / 2`` samples of each of them, so the
  boxcar's delay and the one-step horizon at the bank rate are accounted
  for by predicting the next group, not the next bank sample.  (Moving it
  along the slope of the last two predictions measured no better: 0.0678
  against 0.0675 at 200 and 500 Hz.)  Before the first group ends the
  prediction is 0.

At ``D = 1`` (50-149 Hz) there is no front end: :func:`make_channel` returns
a plain :class:`~wake.channel.Channel`, so 100 Hz runs exactly as before.

The sample path (:meth:`RateChannel.update`) and the block path
(:meth:`RateChannel.process`) run the same arithmetic in the same order, so
they agree bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wake.channel import Channel, ChannelState
from wake.config import WakeConfig
from wake.hpa.run import recorded

__all__ = ["FrontEnd", "RateChannel", "RateChannelState", "in_input_samples", "make_channel"]


def in_input_samples(update, factor: int):
    """An HPA update with its sample counts in input samples: bank-rate count ``m`` is input count ``m D``.

    The bank-rate channel counts what it has seen in bank samples; group
    ``m`` (1-based) of the front end completes with input sample ``m D``, so
    an HPA run after ``m`` bank samples ran after ``m D`` input samples, and
    weights installed at bank sample ``a`` took effect at input sample
    ``a D``.  Every update that leaves a :class:`RateChannel`
    (``WakeResult.hpa``, ``WakeFilter.hpa_history``, and through them
    :meth:`WakeResult.tremor_stats`, ``wake run``'s tremor summary and
    ``--tremor-out``, the plots and ``wake evaluate``) goes through here, so
    ``index / fs`` is the HPA window's end time in seconds at every rate.

    Parameters
    ----------
    update : wake.hpa.HPAUpdate
        An update of the bank-rate channel.
    factor : int
        ``D``, the decimation factor.

    Returns
    -------
    wake.hpa.HPAUpdate
        A copy with ``index`` and ``applied_at`` (unless -1: not installed)
        multiplied by ``D``; ``update`` itself when ``D`` is 1.

    Examples
    --------
    >>> from wake.hpa import HPAUpdate
    >>> from wake.rate import in_input_samples
    >>> u = HPAUpdate(500, 3.0, "valley", None, 1.0, 0.1, 0.0, applied_at=501)
    >>> v = in_input_samples(u, 10)
    >>> v.index, v.applied_at
    (5000, 5010)
    """
    if factor == 1:
        return update
    applied = update.applied_at * factor if update.applied_at >= 0 else update.applied_at
    return recorded(update, index=update.index * factor, applied_at=applied)   # dataclasses.replace, faster


class FrontEnd:
    """Causal boxcar decimator by ``factor``: the mean of each group of ``factor`` inputs.

    Parameters
    ----------
    factor : int
        ``D`` >= 1, the group length.

    Examples
    --------
    >>> from wake.rate import FrontEnd
    >>> fe = FrontEnd(2)
    >>> [fe.push(v) for v in (1.0, 3.0, float("nan"), 5.0)]
    [None, 2.0, None, 5.0]
    """

    def __init__(self, factor: int):
        if isinstance(factor, bool) or not isinstance(factor, int) or factor < 1:
            raise ValueError(f"factor must be an integer >= 1, got {factor!r}")
        self.factor = factor
        self.total = 0.0    # sum of the finite inputs of the open group
        self.finite = 0     # how many of them are finite
        self.phase = 0      # inputs in the open group

    def push(self, value: float):
        """Add one input; the group's output (float, NaN if all were missing) when it completes, else None."""
        if value == value:  # finite (inf is refused upstream)
            self.total += value
            self.finite += 1
        self.phase += 1
        if self.phase < self.factor:
            return None
        out = self.total / self.finite if self.finite else math.nan
        self.total, self.finite, self.phase = 0.0, 0, 0
        return out

    def block(self, x: np.ndarray):
        """(positions in ``x`` where a group completes, the group outputs), as :meth:`push` gives them, bit for
        bit: the open group's first samples and the last, incomplete group through :meth:`push`, every complete
        group between them at once (each group's finite inputs added to 0.0 in order, one input position of
        every group at a time, then divided by their count: :meth:`push`'s operations in its order)."""
        x = np.asarray(x, dtype=float)
        n, D = x.shape[0], self.factor
        head = min(n, (D - self.phase) % D)   # the samples that complete the open group
        where, values = [], []
        for i, v in enumerate(x[:head].tolist()):
            out = self.push(v)
            if out is not None:
                where.append(i)
                values.append(out)
        groups = (n - head) // D
        if groups:
            rows = x[head:head + groups * D].reshape(groups, D)
            total, finite = np.zeros(groups), np.zeros(groups, dtype=np.intp)
            for k in range(D):   # total += value, for each finite value of the group in turn
                present = rows[:, k] == rows[:, k]
                total = np.where(present, total + np.where(present, rows[:, k], 0.0), total)
                finite += present
            with np.errstate(invalid="ignore", divide="ignore"):
                means = np.where(finite > 0, total / np.maximum(finite, 1), np.nan)
            where.extend(range(head + D - 1, head + groups * D, D))
            values.extend(means.tolist())
        for i, v in enumerate(x[head + groups * D:].tolist(), start=head + groups * D):
            self.push(v)   # the last, incomplete group: it stays open
        return np.array(where, dtype=np.intp), np.array(values, dtype=float)


@dataclass
class RateChannelState:
    """Plain data of one :class:`RateChannel`: the bank-rate channel's state and the front end's."""

    inner: ChannelState
    front_end: tuple   #: (total, finite, phase)
    held: float        #: the newest bank-rate prediction (0 before the first group ends)


class RateChannel:
    """One channel at an input rate ``D`` times the bank rate: front end, :class:`Channel`, held prediction.

    The attributes the filter reads of a channel (``rtp``, ``pending``,
    ``swap_if_ready``, ``schedule``) are the bank-rate channel's; its
    :attr:`updates` are the bank-rate channel's with their sample counts in
    input samples (:func:`in_input_samples`).
    """

    def __init__(self, config: WakeConfig, taps: np.ndarray, start_weights: np.ndarray,
                 history_limit: int | None = None):
        self.factor = config.decimation_factor
        self.inner = Channel(config.bank_config(), taps, start_weights, history_limit)
        self.front_end = FrontEnd(self.factor)
        self.held = 0.0  # the carry-back: the newest bank-rate prediction, held over the group it predicts

    def __getattr__(self, name):
        if name in ("rtp", "pending", "swap_if_ready", "schedule", "config", "weights"):
            return getattr(self.__dict__["inner"], name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __setattr__(self, name, value):
        if name == "pending":
            setattr(self.inner, name, value)
        else:
            object.__setattr__(self, name, value)

    @property
    def updates(self) -> list:
        """The HPA updates of the bank-rate channel, oldest first, counted in input samples."""
        return [in_input_samples(u, self.factor) for u in self.inner.updates]

    def update(self, sample: float, executor) -> float:
        """One input sample (NaN: missing): the prediction of the voluntary motion at the next one."""
        group = self.front_end.push(sample)
        if group is not None:
            self.held = float(self.inner.update(group, executor))
        return self.held

    def process(self, x: np.ndarray) -> np.ndarray:
        """A block continuing the stream: ``y[0, i]`` is what :meth:`update` would return for ``x[i]``,
        ``y[1:4, i]`` the bank-rate RTP's ``last_ahead`` then and ``y[4, i]`` its ``last_voluntary_ahead``;
        shape ``(5, n)`` as :meth:`Channel.process`."""
        ends, groups = self.front_end.block(x)
        out = np.empty((5, x.shape[0]))
        out[0] = self.held
        out[1:4] = np.asarray(self.rtp.last_ahead, dtype=float)[:, None]
        out[4] = self.rtp.last_voluntary_ahead
        if groups.size:
            rows = self.inner.process(groups)
            # what the bank-rate step gives at the end of a group holds until the end of the next one
            out[:, ends[0]:] = np.repeat(rows, np.diff(ends, append=x.shape[0]), axis=1)
            self.held = float(rows[0, -1])
        return out

    def state(self) -> RateChannelState:
        fe = self.front_end
        return RateChannelState(self.inner.state(), (fe.total, fe.finite, fe.phase), self.held)

    def load(self, state: RateChannelState) -> None:
        if not isinstance(state, RateChannelState):
            raise ValueError("the state is of a channel without a decimating front end; build the filter with "
                             "WakeFilter(config=state.config)")
        self.inner.load(state.inner)
        fe = self.front_end
        fe.total, fe.finite, fe.phase = state.front_end
        self.held = state.held


def make_channel(config: WakeConfig, taps: np.ndarray, start_weights: np.ndarray,
                 history_limit: int | None = None):
    """A :class:`Channel` when the input runs at the bank rate, else a :class:`RateChannel`.

    ``taps`` and ``start_weights`` are those of ``config.bank_config()``.

    Examples
    --------
    >>> from wake import WakeConfig
    >>> from wake.rate import make_channel
    >>> from wake.wavelets import filter_bank_taps
    >>> from wake.hpa import default_weights
    >>> cfg = WakeConfig(fs=1000.0, backend="reference")
    >>> ch = make_channel(cfg, filter_bank_taps("sym3", 5, "constant"), default_weights(5))
    >>> type(ch).__name__, ch.factor, ch.config.fs
    ('RateChannel', 10, 100.0)
    """
    if config.decimation_factor == 1:
        return Channel(config, taps, start_weights, history_limit)
    return RateChannel(config, taps, start_weights, history_limit)
