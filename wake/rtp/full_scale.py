"""Which full scale the fixed-point path runs at, and when it changes.

The C core holds samples as int16 Q15 of a full scale FS: a sample beyond
±FS is clipped, and a signal far below FS loses its low bits (with FS a
million times the signal, every sample quantises to 0 and the prediction
is silent).  One maximum of the first window is a poor choice on real wear:
one glitch sets FS far too high for ever, and a quiet start (device at
rest, zeros, a gap) sets it far too low for ever.

The policy here decides FS at every HPA from the window the HPA has just
seen:

* **robust peak**: the 99th percentile of ``|x|`` over the finite samples,
  so a handful of glitches (up to 1 % of the window) cannot set it;
* **power of two**: FS = the power of two at or above ``headroom`` times the
  robust peak, so a change of FS is a pure shift of every stored value;
* **quiet windows decide nothing**: a window whose robust peak is 0 keeps
  the current FS (and before the first decision the float reference runs);
* **up at once**: when :data:`RAISE_AFTER` samples in a row lie beyond ±FS
  (the signal grew, a DC jump), FS rises before the next sample to the
  power of two at or above ``headroom`` times their largest magnitude; at an
  HPA, FS rises when ``headroom`` times the robust peak of the window
  exceeds it;
* **down with hysteresis**: FS falls only after ``lower_after`` windows in
  a row whose target is at most FS / ``lower_ratio``.

The numbers behind these choices (the red-team streams of
``tests/test_faults.py``) are in docs/studies/design.md, "Full scale of the
fixed-point path".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["FullScalePolicy", "robust_peak", "power_of_two_at_least", "first_persistent_overflow", "RAISE_AFTER"]

#: Share of a window that may be glitches without moving the full scale.
GLITCH_SHARE = 0.01
#: Samples in a row beyond ±FS that raise the full scale between two HPAs (a glitch is shorter).
RAISE_AFTER = 4
#: Largest full scale the policy picks (WakeConfig's limit for ``full_scale``).
TOP = 2.0**332  # ≈ 8.7e99, below 1e100


def robust_peak(window) -> float:
    """99th percentile of ``|x|`` over the finite samples of ``window`` (0 when none); of each row of a stack
    of windows of one length (W, n), as an array.

    Examples
    --------
    >>> x = np.ones(500); x[3] = 1e5        # one glitch
    >>> robust_peak(x)
    1.0
    """
    x = np.asarray(window, dtype=float)
    if x.ndim == 2:   # a stack of windows of one length (each row finite): one partition for all, a peak per row
        if not np.isfinite(x).all():
            return np.array([robust_peak(row) for row in x])
        x = np.abs(x)
        k = _peak_rank(x.shape[1])
        x.partition(k, axis=1)
        return x[:, k].copy()
    x = np.abs(x[np.isfinite(x)])
    if x.size == 0:
        return 0.0
    k = _peak_rank(x.size)
    x.partition(k)
    return float(x[k])


def _peak_rank(n: int) -> int:
    """The rank :func:`robust_peak` picks among ``n`` samples: np.quantile(x, 1 - GLITCH_SHARE, method="lower")
    is the element of rank floor((n - 1) q), which one partition picks (np.quantile's wrappers cost more than
    the selection at a window's size)."""
    return math.floor((n - 1) * (1.0 - GLITCH_SHARE))


def power_of_two_at_least(value: float) -> float:
    """Smallest power of two >= ``value`` (``value`` > 0), capped at :data:`TOP`."""
    if not value > 0:
        raise ValueError(f"value must be > 0, got {value!r}")
    if value >= TOP:
        return TOP
    m, e = math.frexp(value)  # value = m 2^e, 0.5 <= m < 1
    return math.ldexp(1.0, e - 1) if m == 0.5 else math.ldexp(1.0, e)


@dataclass
class FullScalePolicy:
    """Per-channel full-scale decisions (see the module docstring).

    Parameters
    ----------
    headroom : float
        FS is at least ``headroom`` times the robust peak of the window.
    lower_ratio : float
        FS falls only when its target is at most ``FS / lower_ratio`` ...
    lower_after : int
        ... in this many windows in a row.

    Examples
    --------
    >>> p = FullScalePolicy(headroom=16.0)
    >>> p.decide(None, np.zeros(500))            # quiet: no decision yet
    (None, None)
    >>> p.decide(None, np.sin(np.arange(500)))   # 16 x 0.9999 -> 16
    (16.0, 'full_scale_set')
    >>> p.decide(16.0, 50 + np.sin(np.arange(500)))
    (1024.0, 'full_scale_raised')
    """

    headroom: float = 16.0
    lower_ratio: float = 16.0
    lower_after: int = 2
    quiet_windows: int = 0  #: windows in a row whose target lay at or below FS / lower_ratio

    def target(self, window, peak: float | None = None) -> float | None:
        """The full scale ``window`` asks for, or None for a quiet window (``peak``: its :func:`robust_peak`,
        when the caller has it)."""
        peak = robust_peak(window) if peak is None else peak
        if not peak > 0:
            return None
        return power_of_two_at_least(self.headroom * peak)

    def decide(self, current: float | None, window, peak: float | None = None) -> tuple[float | None, str | None]:
        """``(full scale, reason)`` after ``window``; reason None when FS stays (``peak`` as for :meth:`target`)."""
        want = self.target(window, peak)
        if want is None:
            return current, None
        if current is None:
            self.quiet_windows = 0
            return want, "full_scale_set"
        if want > current:
            self.quiet_windows = 0
            return want, "full_scale_raised"
        if want * self.lower_ratio <= current:
            self.quiet_windows += 1
            if self.quiet_windows >= self.lower_after:
                self.quiet_windows = 0
                return want, "full_scale_lowered"
        else:
            self.quiet_windows = 0
        return current, None


def first_persistent_overflow(x, full_scale, carried=0, raise_after=RAISE_AFTER):
    """Index in ``x`` of the sample completing ``raise_after`` samples in a row beyond ±``full_scale``.

    ``carried`` samples beyond it ended the previous block.  Returns
    ``(index, run)``: ``index`` is ``len(x)`` when no run completes, and
    ``run`` is then the length of the run that ends the block (to carry on).

    Examples
    --------
    >>> first_persistent_overflow(np.array([0., 9., 9., 0., 9., 9., 9., 9., 0.]), 1.0)
    (7, 4)
    >>> first_persistent_overflow(np.array([9., 9.]), 1.0, carried=1)
    (2, 3)
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    size = np.abs(x)
    if not n or not np.fmax.reduce(size) > full_scale:   # the usual block: nothing beyond (NaN is never beyond)
        return n, 0
    with np.errstate(invalid="ignore"):
        over = size > full_scale          # NaN: not beyond (it breaks a run)
    idx = np.arange(n)
    last_in_range = np.maximum.accumulate(np.where(over, -1 - carried, idx))
    run = idx - last_in_range
    hit = np.flatnonzero(run >= raise_after)
    if hit.size:
        return int(hit[0]), int(run[hit[0]])
    return n, int(run[-1])
