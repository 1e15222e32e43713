"""The saved state of a stream: :class:`WakeState`, versioned (:data:`STATE_VERSION`)."""

from __future__ import annotations

from dataclasses import dataclass

from wake.channel import channel_state_from_unversioned
from wake.config import WakeConfig

__all__ = ["STATE_VERSION", "WakeState"]

#: The layout of :class:`WakeState` (and of :class:`~wake.channel.ChannelState` in it).  Version 0 is the
#: unversioned snapshot of earlier releases (a dict per channel), still read; version 1 is version 2 without
#: the tremor ahead (:mod:`wake.ahead`), read too: its stream continues with no predictor and the gate shut
#: until the next HPA fits one.
STATE_VERSION = 2


@dataclass
class WakeState:
    """A snapshot of a stream, taken by :meth:`WakeFilter.get_state`.

    Plain data (picklable): the configuration and, per channel, a
    :class:`~wake.channel.ChannelState` (HPA schedule, weights and history,
    RTP).  :meth:`WakeFilter.set_state` continues the stream from it, bit for
    bit, like scipy's ``zi`` / ``zf``; a state of another ``version``
    (:data:`STATE_VERSION`) is refused with a message.
    """

    config: WakeConfig
    channels: list
    version: int = STATE_VERSION

    def __setstate__(self, st):
        # a state pickled before the layout was versioned has no "version": it is version 0
        self.__dict__.update({"version": 0, **st})

    def channel_states(self) -> list:
        """The per-channel states in the current layout (version 0 converted), or ``ValueError``."""
        if self.version in (1, STATE_VERSION):
            return list(self.channels)   # version 1: ChannelState's tremor-ahead fields take their defaults
        if self.version == 0 and all(isinstance(c, dict) for c in self.channels):
            return [channel_state_from_unversioned(c) for c in self.channels]
        raise ValueError(f"this state has layout version {self.version!r}; this version of wake reads "
                         f"version {STATE_VERSION} (and version 1 and the unversioned states of earlier releases): "
                         "load it with the wake release that saved it, or start the stream again")
