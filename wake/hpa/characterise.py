"""Tremor characterisation of one HPA window, for the person who reads the result.

:func:`characterise_window` turns one window (the samples the HPA read, its
cut-off ``f_d`` and flag, the configuration's tremor band) into a
:class:`TremorStats`; :func:`tremor_table` does it for every HPA run of a
channel.  The definitions (docs/studies/characterisation.md has the measurements
behind each choice):

tremor
    The detrended window (the line through its end points taken out, as for
    the HPA's ground truth, :func:`~wake.hpa.sharp.detrended_highpass`)
    with every FFT bin outside ``(f_d, top]`` zeroed, ``top`` the tremor
    band's upper edge.
frequency
    The local maximum in ``(f_d, top]`` of the Hann periodogram of
    the detrended window (zero-padded to 8 times its length, the peak
    refined by a parabola through the log power of its three bins), the
    maximum chosen being the one standing highest above the periodogram's
    trend (a power law fitted in log-log over the tremor band, peaks left
    out: white noise and the decaying tail of voluntary motion alike).  It
    counts as a tremor peak only when it stands :data:`PEAK_RATIO` above
    that trend and the HPA's cut-off flag is not ``"no_tremor_peak"``.
rms, band_power
    The RMS and the mean square of the tremor (input units, input units
    squared); by Parseval ``band_power`` is the periodogram's power in
    ``(f_d, top]``, and ``band_power == rms**2``.
peak_to_peak
    Twice the median envelope of the narrow-band tremor (see below) over the
    samples in tremor, divided by the band-pass's gain at the dominant
    frequency: ``2 A`` for a sinusoid of amplitude ``A``.
time_share
    The share of the window's samples in tremor: those whose narrow-band
    envelope (the magnitude of the analytic signal) exceeds
    :data:`ENVELOPE_K` times the narrow band's noise RMS (the trend's
    density at the peak times the band-pass's equivalent noise bandwidth;
    for Gaussian noise alone the envelope is Rayleigh distributed and
    exceeds that ``exp(-ENVELOPE_K**2 / 2)`` = 1.1 % of the time) and half
    the median envelope of those samples (where a burst's zero-phase
    envelope passes half its height: the burst's edge).
tsi
    The tremor stability index (di Biase et al., Brain 140(7):1977-1986,
    2017): the inter-quartile range of the change of the cycle frequency
    from one tremor cycle to the next.  The narrow-band tremor is the
    detrended window through a zero-phase 2nd-order Butterworth band-pass
    ``f0 +- NARROW_HALF_BAND_HZ``; its upward zero crossings (linearly
    interpolated) delimit the cycles, ``f_n = 1 / T_n``, and only pairs of
    consecutive cycles that both lie in tremor (their mean envelope above
    the threshold) count.

A window without a tremor peak has NaN frequency, peak-to-peak and TSI,
time share 0 and ``reason="no_tremor_peak"``; one with too few tremor cycles
for an inter-quartile range has NaN TSI and ``reason="few_tremor_cycles"``;
a silent window is NaN throughout (:data:`REASONS`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wake._validation import check_positive
from wake.hpa.cutoff import CUTOFF_FLAGS
from wake.hpa.schedule import prepare_window
from wake.hpa.sharp import end_point_line, sharp_highpass

__all__ = ["ENVELOPE_K", "NARROW_HALF_BAND_HZ", "PEAK_RATIO", "REASONS", "TABLE_FIELDS", "TremorStats",
           "characterise_window", "summarise", "summary_lines", "tremor_table"]

#: A periodogram maximum is a tremor peak when it is this many times the band's median power (13 dB).
PEAK_RATIO = 20.0
#: A periodogram bin this many times the trend is left out of the trend's next fit (6 dB).
OUTLIER_RATIO = 4.0
#: Half width in Hz of the narrow band-pass around the dominant frequency (cycles, envelope, TSI).
NARROW_HALF_BAND_HZ = 2.0
#: A sample is in tremor when its narrow-band envelope exceeds this many noise RMS of the narrow band.
ENVELOPE_K = 3.0
#: The fewest cycle-to-cycle changes an inter-quartile range is taken of.
MIN_CHANGES = 4
#: Zero padding of the periodogram: the FFT is this many times the window long.
PAD = 8

#: Why a field is NaN; ``""`` when every field holds a number.
REASONS = {
    "": "every field holds a number",
    "silent": "the window has (near) zero variance: every field NaN",
    "no_tremor_peak": (f"no periodogram maximum in (f_d, top] stands {10 * np.log10(PEAK_RATIO):.0f} dB above the "
                       "band's trend, or the HPA found none: frequency, peak-to-peak and TSI NaN, time share 0"),
    "few_tremor_cycles": f"fewer than {MIN_CHANGES} cycle-to-cycle changes in tremor: TSI NaN",
}


@dataclass(frozen=True)
class TremorStats:
    """The tremor of one window (:func:`characterise_window`); amplitudes in the input's units."""

    frequency: float     #: dominant tremor frequency in Hz
    rms: float           #: RMS of the tremor
    peak_to_peak: float  #: median peak-to-peak of the tremor cycles
    band_power: float    #: mean square of the tremor (power in (f_d, top]), input units squared
    time_share: float    #: share of the window in tremor, 0 .. 1
    tsi: float           #: tremor stability index in Hz
    reason: str = ""     #: a key of :data:`REASONS`


_NAN = float("nan")



def _check_band(fs, cutoff, tremor_band):
    fs = check_positive("fs", fs)
    cutoff = check_positive("cutoff", cutoff, allow_zero=True)
    try:
        low, top = (float(v) for v in tremor_band)
    except (TypeError, ValueError):
        raise ValueError(f"tremor_band must be a pair (low, high) in Hz, got {tremor_band!r}") from None
    if not 0 < low < top <= fs / 2:
        raise ValueError(f"tremor_band must satisfy 0 < low < high <= fs/2 = {fs / 2:g}, got {tremor_band!r}")
    if not cutoff < top:
        raise ValueError(f"cutoff must be below the tremor band's top ({top:g} Hz), got {cutoff:g}")
    return fs, cutoff, low, top


def _trend(f, p):
    """The periodogram's trend over the band, as a mean power: a parabola in log-log, the peaks left out.

    A parabola through ``log p`` against ``log f`` follows white noise (flat), the decaying tail of
    voluntary motion and the bend where that tail meets the noise floor.  Bins more than
    :data:`OUTLIER_RATIO` above the trend (a tremor peak, its lobes) are left out and the fit is
    repeated, twice.  The mean of the log of an exponentially distributed periodogram bin is
    ``log(mean) - EULER_GAMMA``: the fit is raised by ``exp(EULER_GAMMA)`` to a mean power.
    """
    logf, logp = np.log(f), np.log(np.maximum(p, np.finfo(float).tiny))
    keep = np.ones(f.size, dtype=bool)
    for _ in range(3):
        coef = np.polyfit(logf[keep], logp[keep], 1)
        trend = np.exp(np.polyval(coef, logf) + np.euler_gamma)
        keep = p <= OUTLIER_RATIO * trend
        if keep.sum() < 8:
            break
    return trend


def _peak(x, fs, cutoff, low, top):
    """``(frequency, noise power density there in units^2/Hz)``: the tremor peak of the Hann periodogram.

    The frequency is NaN when no local maximum in ``(cutoff, top]`` stands :data:`PEAK_RATIO` above the
    band's trend (:func:`_trend`); the density is then the trend's mean over the band.
    """
    from scipy.signal import periodogram

    f, p = periodogram(x, fs, window="hann", nfft=PAD * x.size, detrend=False)
    # the trend is fitted over the whole tremor band (and down to f_d when that lies lower): a cut-off
    # just below a short burst's broad peak would leave the fit too few bins beside the peak
    fit = np.flatnonzero((f > min(cutoff, low)) & (f <= top) & (f > 0))
    trend = np.zeros_like(p)
    trend[fit] = _trend(f[fit], p[fit])
    band = fit[f[fit] > cutoff]
    if band.size < 3 or fit.size < 3:  # a window too short to resolve the band: no peak can stand out
        return _NAN, float(np.mean(p[band])) if band.size else 0.0
    inner = band[(band > band[0]) & (band < band[-1])]
    local = inner[(p[inner] >= p[inner - 1]) & (p[inner] >= p[inner + 1])]
    if local.size == 0:
        return _NAN, float(np.mean(trend[band]))
    k = local[np.argmax(p[local] / trend[local])]
    if not p[k] >= PEAK_RATIO * trend[k]:
        return _NAN, float(np.mean(trend[band]))
    a, b, c = np.log(np.maximum(p[k - 1:k + 2], np.finfo(float).tiny))
    curve = a - 2 * b + c
    shift = 0.5 * (a - c) / curve if curve < 0 else 0.0
    return float(f[k] + shift * (f[1] - f[0])), float(trend[k])


def _narrow(x, fs, f0):
    """The narrow-band tremor and the band-pass's (gain at f0, equivalent noise bandwidth in Hz), zero phase."""
    from scipy.signal import butter, sosfiltfilt, sosfreqz

    low = max(f0 - NARROW_HALF_BAND_HZ, 0.5 * f0)
    high = min(f0 + NARROW_HALF_BAND_HZ, 0.95 * fs / 2)
    sos = butter(2, [low, high], btype="bandpass", fs=fs, output="sos")
    freqs, h = sosfreqz(sos, worN=4096, fs=fs)
    power = np.abs(h) ** 4  # forward and backward: |H|^2 in amplitude, |H|^4 in power
    gain = float(np.abs(sosfreqz(sos, worN=[f0], fs=fs)[1][0]) ** 2)
    enbw = float(np.sum(power) * (freqs[1] - freqs[0]))
    return sosfiltfilt(sos, x), gain, enbw


def _upward_crossings(y):
    """Fractional sample positions of the upward zero crossings of ``y``."""
    k = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    return k + y[k] / (y[k] - y[k + 1])


def _in_tremor(envelope, noise_rms):
    """The samples in tremor: envelope above ``ENVELOPE_K`` noise RMS and above half the typical tremor envelope."""
    on = envelope > ENVELOPE_K * noise_rms
    if on.any():
        # a burst's edge: the zero-phase filter's envelope passes half the burst's height there
        on &= envelope > 0.5 * np.median(envelope[on])
    return on


def _tsi(nb, on, fs):
    """TSI: the inter-quartile range of the cycle-to-cycle change of the cycle frequency, over tremor cycles."""
    edges = _upward_crossings(nb)
    starts, ends = np.ceil(edges[:-1]).astype(int), np.ceil(edges[1:]).astype(int)
    in_tremor = np.array([e > s and on[s:e].mean() > 0.5 for s, e in zip(starts, ends)], dtype=bool)
    pairs = in_tremor[:-1] & in_tremor[1:] if in_tremor.size > 1 else np.zeros(0, dtype=bool)
    change = np.diff(fs / np.diff(edges))[pairs]
    if change.size < MIN_CHANGES:
        return _NAN
    q25, q75 = np.percentile(change, [25, 75])
    return float(q75 - q25)


def characterise_window(window, fs, cutoff, cutoff_flag="valley", tremor_band=(2.5, 15.0)) -> TremorStats:
    """Dominant frequency, amplitude, band power, time share and TSI of the tremor of one HPA window.

    Parameters
    ----------
    window : array_like, shape (n,)
        The samples the HPA read, oldest first, finite, at least 8 samples.
    fs : float
        Sampling rate in Hz.
    cutoff : float
        The HPA's ``f_d`` in Hz: the tremor is what lies above it.
    cutoff_flag : str
        The HPA's cut-off flag; ``"silent"`` gives a NaN row without looking
        further.
    tremor_band : pair of float
        ``(low, high)`` in Hz (``WakeConfig.tremor_band``); the tremor is
        ``(cutoff, high]``.

    Returns
    -------
    TremorStats
        NaN fields carry a ``reason`` (a key of :data:`REASONS`).

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa.characterise import characterise_window
    >>> t = np.arange(500) / 100.0
    >>> s = characterise_window(np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 6 * t), 100.0, 2.0)
    >>> round(s.frequency, 2), round(s.rms, 3), round(s.peak_to_peak, 2), s.time_share
    (6.0, 0.142, 0.4, 1.0)
    >>> characterise_window(np.sin(2 * np.pi * 0.3 * t), 100.0, 2.0).reason
    'no_tremor_peak'
    """
    fs, cutoff, low, top = _check_band(fs, cutoff, tremor_band)
    if cutoff_flag not in CUTOFF_FLAGS:
        raise ValueError(f"cutoff_flag must be one of {', '.join(CUTOFF_FLAGS)}, got {cutoff_flag!r}")
    x = np.asarray(window, dtype=float)
    if x.ndim != 1 or x.size < 8 or not np.all(np.isfinite(x)):
        raise ValueError(f"window must be 1-D, finite and at least 8 samples long, got shape {x.shape}"
                         + ("" if np.all(np.isfinite(x)) else " with NaN or inf"))
    scale = max(1.0, float(np.max(np.abs(x))))
    if cutoff_flag == "silent" or not np.std(x) > 1e-12 * scale:
        return TremorStats(_NAN, _NAN, _NAN, _NAN, _NAN, _NAN, "silent")
    d = x - end_point_line(x)
    tremor = sharp_highpass(d, fs, cutoff) - sharp_highpass(d, fs, top)
    power = float(np.mean(tremor ** 2))
    f0, floor = _peak(d, fs, cutoff, low, top)
    if cutoff_flag == "no_tremor_peak" or not np.isfinite(f0):
        return TremorStats(_NAN, float(np.sqrt(power)), _NAN, power, 0.0, _NAN, "no_tremor_peak")
    nb, gain, enbw = _narrow(d, fs, f0)
    noise_rms = np.sqrt(floor * enbw)  # the noise in the narrow band: its density times its bandwidth
    from scipy.signal import hilbert

    envelope = np.abs(hilbert(nb)) / gain
    on = _in_tremor(envelope, noise_rms / gain)
    p2p = 2.0 * float(np.median(envelope[on])) if on.any() else _NAN
    tsi = _tsi(nb, on, fs)
    return TremorStats(f0, float(np.sqrt(power)), p2p, power, float(on.mean()), tsi,
                       "" if np.isfinite(tsi) else "few_tremor_cycles")


#: The fields of a :func:`tremor_table` row, in order.
TABLE_FIELDS = ("index", "end_time", "samples", "cutoff", "frequency", "rms", "peak_to_peak", "band_power",
                "time_share", "tsi", "reason")


def tremor_table(x, fs, updates, window_samples, tremor_band=(2.5, 15.0)) -> np.ndarray:
    """One :class:`TremorStats` row per HPA run of one channel, as a numpy structured array.

    Parameters
    ----------
    x : array_like, shape (n,)
        The channel's samples (NaN marks a missing sample), at least up to
        the last update's ``index``.
    fs : float
        Sampling rate in Hz.
    updates : sequence
        The channel's HPA updates (:class:`~wake.hpa.HPAUpdate`: ``index``,
        ``cutoff``, ``cutoff_flag`` are read), e.g. ``WakeResult.hpa[c]``
        or ``WakeFilter.hpa_history[c]``.
    window_samples : int
        ``L``: each run read the last ``min(index, L)`` samples, outliers
        and gaps interpolated as the HPA reads them.
    tremor_band : pair of float
        ``WakeConfig.tremor_band``.

    Returns
    -------
    numpy.ndarray
        Fields :data:`TABLE_FIELDS`: ``index`` (samples seen), ``end_time``
        (``index / fs``, s), ``samples`` (the window's length; below ``L``
        in the warm-up), ``cutoff`` and the :class:`TremorStats` fields.

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeFilter
    >>> from wake.hpa.characterise import tremor_table
    >>> t = np.arange(1500) / 100.0
    >>> x = np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 6 * t)
    >>> res = WakeFilter(backend="reference").run(x)
    >>> tab = tremor_table(x, 100.0, res.hpa[0], 500)
    >>> tab["end_time"][-3:].tolist(), np.round(tab["frequency"][-3:], 1).tolist()
    ([5.0, 10.0, 15.0], [6.0, 6.0, 6.0])
    """
    x = np.asarray(x, dtype=float).reshape(-1)
    window_samples = check_positive("window_samples", window_samples, integer=True)
    dtype = [(name, "i8") for name in TABLE_FIELDS[:1]] + [("end_time", "f8"), ("samples", "i8")] + \
        [(name, "f8") for name in TABLE_FIELDS[3:-1]] + [("reason", "U20")]
    rows = []
    for u in updates:
        if not 0 < u.index <= x.size:
            raise ValueError(f"an HPA update at sample {u.index} lies outside the {x.size} samples given")
        window = prepare_window(x[max(0, u.index - window_samples):u.index])
        s = characterise_window(window, fs, u.cutoff, u.cutoff_flag, tremor_band)
        rows.append((u.index, u.index / fs, window.size, u.cutoff, s.frequency, s.rms, s.peak_to_peak,
                     s.band_power, s.time_share, s.tsi, s.reason))
    return np.array(rows, dtype=dtype)


def summarise(table, window_samples) -> dict:
    """A channel's tremor in a few numbers: the full windows of a :func:`tremor_table`, summed up.

    Only full windows (``samples == window_samples``) count: the warm-up
    windows overlap the first full one.  ``frequency``, ``peak_to_peak``
    and ``tsi`` are medians over the windows with a tremor peak (NaN when
    there is none); ``rms`` is the median over the non-silent windows;
    ``time_share`` the mean over them (each full window is as long as the
    next, so it is the share of the time they cover).

    Examples
    --------
    >>> import numpy as np
    >>> from wake import WakeFilter
    >>> from wake.hpa.characterise import summarise
    >>> t = np.arange(1500) / 100.0
    >>> x = np.sin(2 * np.pi * 0.3 * t) + 0.2 * np.sin(2 * np.pi * 6 * t)
    >>> s = summarise(WakeFilter(backend="reference").run(x).tremor_stats(100.0)[0], 500)
    >>> s["windows"], s["tremor_windows"], round(s["frequency"], 1), round(s["time_share"], 2)
    (3, 3, 6.0, 1.0)
    """
    full = table[table["samples"] == int(window_samples)]
    heard = full[full["reason"] != "silent"]
    peaked = heard[np.isfinite(heard["frequency"])]

    def median(values):
        values = values[np.isfinite(values)]
        return float(np.median(values)) if values.size else _NAN

    return {"windows": int(full.size), "tremor_windows": int(peaked.size),
            "frequency": median(peaked["frequency"]), "rms": median(heard["rms"]),
            "peak_to_peak": median(peaked["peak_to_peak"]), "tsi": median(peaked["tsi"]),
            "time_share": float(np.mean(heard["time_share"])) if heard.size else _NAN}


def summary_lines(channels, units, tables, config) -> list:
    """The tremor paragraph ``wake run`` prints: a heading and one line per channel (:func:`summarise` of its table).

    ``units`` holds each channel's unit ("" for none); ``config`` is the filter's :class:`~wake.config.WakeConfig`.
    """
    top = config.tremor_band[1]
    lines = [f"tremor per channel, over the full HPA windows ({config.window_s:g} s; the tremor lies between f_d "
             f"and {top:g} Hz; docs/studies/characterisation.md):"]
    for name, unit, table in zip(channels, units, tables):
        s = summarise(table, config.window_samples)
        unit = f" {unit}" if unit else ""
        if not s["windows"]:
            lines.append(f"  {name}: no full HPA window (too few finite samples): not characterised")
            continue
        text = f"  {name}: a tremor peak in {s['tremor_windows']} of {s['windows']} windows"
        if s["tremor_windows"]:
            text += (f"; median frequency {s['frequency']:.2f} Hz, TSI {s['tsi']:.2f} Hz, "
                     f"peak-to-peak {s['peak_to_peak']:.3g}{unit}")
        lines.append(text + f"; RMS {s['rms']:.3g}{unit}; in tremor {100 * s['time_share']:.0f} % of the time")
    return lines
