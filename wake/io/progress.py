"""A progress bar for ``wake run`` (``--progress``): tqdm on stderr, optional.

The bar counts the input samples a :class:`~wake.WakeFilter` has taken in, over all channels, and moves at
every HPA window of every channel (the HPA is where the time goes).  Without tqdm there is no bar and no
error.
"""

from __future__ import annotations

import sys

__all__ = ["PROGRESS_SAMPLES", "run_progress"]


#: ``wake run`` shows a progress bar by itself on jobs of at least this many samples (all channels), on a terminal.
PROGRESS_SAMPLES = 2_000_000


class run_progress:
    """A tqdm bar on stderr over the samples ``filt.run`` has taken in, advanced at each HPA window.

    ``mode``: ``"auto"`` (a bar on a terminal for a job of :data:`PROGRESS_SAMPLES` or more), ``"on"`` or
    ``"off"``.  tqdm is optional (``pip install tqdm``, or the ``cohort`` extra): without it there is no
    bar and no error (``"on"`` says so in one line).
    """

    def __init__(self, filt, n, channels, mode="auto"):
        self.filt, self.total, self.bar = filt, n * channels, None
        self.mode = mode

    def __enter__(self):
        wanted = self.mode == "on" or (self.mode == "auto" and self.total >= PROGRESS_SAMPLES
                                       and sys.stderr.isatty())
        if not wanted:
            return self
        try:
            from tqdm import tqdm
        except ImportError:
            if self.mode == "on":
                print("wake run: no progress bar (tqdm is not installed: pip install tqdm)", file=sys.stderr)
            return self
        self.bar = bar = tqdm(total=self.total, unit="sample", unit_scale=True, desc="wake run", file=sys.stderr,
                              leave=False)
        make = self.filt._new_channels

        def new_channels(k, **kw):  # each channel ticks the bar at its HPA windows
            chans = make(k, **kw)
            step = self.filt.config.decimation_factor  # above 100 Hz a channel's HPA counts the bank's samples
            for ch in chans:
                inner = ch.__dict__.get("inner", ch)  # wake.rate.RateChannel wraps the channel at the bank's rate
                inner.hpa = _ticking(inner, inner.hpa, bar, step)
            return chans

        self.filt._new_channels = new_channels
        return self

    def __exit__(self, *exc):
        if self.bar is not None:
            del self.filt._new_channels  # the class's own again
            self.bar.update(self.total - self.bar.n)
            self.bar.close()
        return False


def _ticking(ch, hpa, bar, step):
    done = [0]

    def tick(window, count=None, *args):   # count: the point's, when a batch path gives it (Channel.points)
        hpa(window, count, *args)
        count = (ch.schedule.count if count is None else count) * step
        bar.update(count - done[0])
        done[0] = count

    return tick
