"""Sampling rates: the rate the filter bank runs at, and the input rates WAKE supports.

The lowest layer (docs/reference/architecture.md): :class:`wake.config.WakeConfig` derives its
``decimation_factor`` from :func:`decimation_for` and :mod:`wake.rate` runs the front
end it implies; docs/studies/design.md, "Sampling rates other than 100 Hz", has the measurement.
"""

from __future__ import annotations

import functools
import math

__all__ = ["BANK_RATE", "TUNED_RATES", "RateWarning", "decimation_for", "rate_note", "sample_counts",
           "warn_if_far_from_tuned_rate"]

#: The filter bank's own rate (Hz) that :func:`decimation_for` aims at: the rate level 5,
#: ``ar_order`` 17 and the 5 s window were designed and measured at.
BANK_RATE = 100.0


def decimation_for(fs: float) -> int:
    """``D``, input samples per filter-bank sample at ``fs`` Hz: ``fs / 100`` rounded, halves up, at least 1.

    The bank then runs at ``fs / D``, within 67-150 Hz for every ``fs`` >= 67 Hz
    (docs/studies/design.md, "Sampling rates other than 100 Hz": 250 Hz takes ``D = 3``,
    83 Hz, which measured better than ``D = 2``).

    Examples
    --------
    >>> from wake.sampling import decimation_for
    >>> [decimation_for(fs) for fs in (50.0, 100.0, 200.0, 250.0, 500.0, 1000.0)]
    [1, 1, 2, 3, 5, 10]
    """
    return max(1, int(math.floor(fs / BANK_RATE + 0.5)))


#: Input rates (Hz) WAKE supports: the decimating front end keeps the bank within 67-150 Hz
#: (docs/studies/design.md, "Sampling rates other than 100 Hz").
TUNED_RATES = (50.0, 1000.0)


class RateWarning(UserWarning):
    """The sampling rate lies outside the supported :data:`TUNED_RATES`."""


def warn_if_far_from_tuned_rate(config) -> None:
    """Warn (:class:`RateWarning`) when ``config.fs`` (a :class:`~wake.WakeConfig`) is outside :data:`TUNED_RATES`."""
    low, high = TUNED_RATES
    if low <= config.fs <= high:
        return
    import warnings

    bank = config.fs / config.decimation_factor
    warnings.warn(
        f"fs = {config.fs:g} Hz is outside the supported {low:g}-{high:g} Hz: the filter bank runs at "
        f"{bank:g} Hz here (fs / decimation {config.decimation_factor}), where its accuracy was not measured"
        + (" and its level-{0} bank spans {1:.0f} ms (320 ms at 100 Hz)".format(
            config.level, 1e3 * 2**config.level / bank) if bank < low else "")
        + f". Resample the recording into {low:g}-{high:g} Hz first (e.g. scipy.signal.resample_poly)",
        RateWarning, stacklevel=3)


def _ordinal(n: int) -> str:
    """``2`` -> ``"2nd"``, ``3`` -> ``"3rd"``, ``11`` -> ``"11th"``, ``21`` -> ``"21st"``."""
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def rate_note(fs: float) -> str:
    """One line on what ``fs`` costs per input sample and per second (``wake run``, ``wake stream``).

    Examples
    --------
    >>> from wake.sampling import rate_note
    >>> print(rate_note(1000.0))
    rate 1000 Hz: filter bank, HPA and RTP at 100 Hz (decimation 10): per input sample one front-end add, every 10th also one RTP step; per second 1000 adds and 100 RTP steps (Cortex-M instructions: wake profile --fs 1000)
    >>> print(rate_note(100.0))
    rate 100 Hz: filter bank, HPA and RTP at 100 Hz (no front end): per input sample one RTP step; per second 100 RTP steps (Cortex-M instructions: wake profile --fs 100)
    """
    D = decimation_for(fs)
    bank = fs / D
    if D == 1:
        work = f"per input sample one RTP step; per second {fs:g} RTP steps"
        how = "no front end"
    else:
        work = (f"per input sample one front-end add, every {_ordinal(D)} also one RTP step; "
                f"per second {fs:g} adds and {bank:g} RTP steps")
        how = f"decimation {D}"
    return f"rate {fs:g} Hz: filter bank, HPA and RTP at {bank:g} Hz ({how}): {work} (Cortex-M instructions: wake profile --fs {fs:g})"


@functools.lru_cache(maxsize=64)
def sample_counts(times_s: tuple, fs: float) -> tuple:
    """The sample count ``round(t * fs)`` of each time ``t`` of ``times_s`` (seconds), made once per setting.

    Examples
    --------
    >>> sample_counts((1.0, 2.5), 100.0)
    (100, 250)
    """
    return tuple(int(round(t * fs)) for t in times_s)
