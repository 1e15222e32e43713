"""The paper's synthetic dataset (section "Synthetic Dataset").

Each signal is ``s = s_v + s_w + s_t``:

* ``s_v`` voluntary motion: one sinusoid below 1 Hz with the dominant amplitude;
* ``s_w`` white noise: sinusoids at every multiple of ``freq_step`` from
  ``freq_step`` to ``fs/2``, uniform random amplitudes, random phases;
* ``s_t`` tremor: the same construction restricted to 6-14 Hz.

The paper gives the input SNR of its ten signals, ``10 log10(P(s_v) /
(P(s_w) + P(s_t)))``, but not how the noise power splits between white noise
and tremor; :func:`make_signal` takes that split as ``tremor_share`` (the
fraction of the noise power in the tremor band, 0.5 by default) and scales
both so that the SNR is met exactly.

:func:`make_rest_tremor` builds the opposite case, rest tremor with little
voluntary motion: a narrow 4-6 Hz tremor on slow 1/f drift (docs/studies/design.md,
"Rest tremor with little voluntary motion").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wake._validation import check_positive

__all__ = ["RestTremorSignal", "SyntheticSignal", "PAPER_SNR_DB", "PAPER_WAKE", "REST_TREMOR_DRIFT_DB",
           "make_rest_tremor", "make_signal", "paper_dataset", "rest_tremor_dataset"]

#: Input SNR (dB) of the paper's ten synthetic signals (Table "results2").
PAPER_SNR_DB = (7.5, 5.1, 0.3, -4.0, 4.6, 0.3, -4.9, 20.9, 15.1, 10.0)

#: The paper's WAKE columns for those signals: PRF (%), SNR_out (dB), NRMSE.
PAPER_WAKE = {
    "prf": (4.3, 7.42, 22.95, 68.8, 8.13, 45.56, 135.74, 0.32, 0.9, 2.71),
    "snr_out": (13.67, 7.42, 6.39, 1.72, 10.9, 3.32, -1.23, 25.0, 20.46, 15.67),
    "nrmse": (0.0734, 0.0964, 0.1695, 0.2904, 0.1009, 0.2414, 0.4077, 0.02, 0.0335, 0.0583),
}
#: The paper's BMFLC and E-BMFLC columns, same order.
PAPER_BMFLC = {
    "prf": (11.97, 15.94, 31.49, 74.2, 22.23, 57.45, 183.18, 4.83, 5.43, 7.36),
    "snr_out": (9.22, 7.98, 5.02, 1.3, 6.53, 2.41, -2.63, 13.16, 12.65, 11.33),
    "nrmse": (0.12, 0.14, 0.16, 0.3, 0.17, 0.27, 0.48, 0.08, 0.08, 0.1),
}
PAPER_EBMFLC = {
    "prf": (12.84, 16.41, 30.72, 67.89, 26.23, 73.29, 240.61, 4.15, 4.66, 6.25),
    "snr_out": (8.91, 7.85, 5.13, 1.68, 5.81, 1.35, -3.81, 13.82, 13.32, 12.04),
    "nrmse": (0.13, 0.14, 0.2, 0.29, 0.18, 0.3, 0.55, 0.07, 0.08, 0.09),
}


@dataclass(frozen=True)
class SyntheticSignal:
    """One synthetic recording with every component kept apart."""

    measurement: np.ndarray  #: s = voluntary + white + tremor
    voluntary: np.ndarray  #: s_v
    white: np.ndarray  #: s_w
    tremor: np.ndarray  #: s_t
    fs: float
    snr_db: float  #: the input SNR actually reached
    voluntary_freq: float  #: Hz

    @property
    def noise(self) -> np.ndarray:
        """Everything that is not voluntary motion: ``white + tremor``."""
        return self.white + self.tremor


def _sinusoid_bank(rng, t, f_lo, f_hi, step, amp_mean, amp_spread):
    freqs = np.arange(f_lo, f_hi + step / 2, step)
    amps = rng.uniform(amp_mean - amp_spread, amp_mean + amp_spread, freqs.size)
    phases = rng.uniform(0.0, 2 * np.pi, freqs.size)
    out = np.zeros_like(t)
    for f, a, p in zip(freqs, amps, phases):
        out += a * np.sin(2 * np.pi * f * t + p)
    return out


def make_signal(snr_db, *, seed=0, fs=100.0, duration=50.0, tremor_share=0.5,
                voluntary_amplitude=1.0, voluntary_freq=None, tremor_band=(6.0, 14.0),
                freq_step=0.1):
    """Build one synthetic signal with the requested input SNR.

    Parameters
    ----------
    snr_db : float
        Input SNR in dB, ``10 log10(P(s_v) / (P(s_w) + P(s_t)))``.
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same signal.
    fs : float
        Sampling rate in Hz (the paper: 100).
    duration : float
        Length in seconds (the paper: 50).
    tremor_share : float
        Fraction of the noise power that is tremor (0..1); the rest is white noise.
    voluntary_amplitude : float
        Amplitude of ``s_v``.
    voluntary_freq : float, optional
        Frequency of ``s_v`` in Hz; drawn from U(0.2, 0.9) when omitted.
    tremor_band : (float, float)
        Tremor band in Hz.
    freq_step : float
        Frequency resolution of the sinusoid banks.

    Returns
    -------
    SyntheticSignal

    Examples
    --------
    >>> from wake.eval.synthetic import make_signal
    >>> s = make_signal(7.5, seed=1)
    >>> s.measurement.shape
    (5000,)
    >>> round(s.snr_db, 6)
    7.5
    """
    fs = check_positive("fs", fs)
    duration = check_positive("duration", duration)
    if not 0.0 <= tremor_share <= 1.0:
        raise ValueError(f"tremor_share must be within [0, 1], got {tremor_share!r}")
    lo, hi = tremor_band
    if not 0 < lo < hi <= fs / 2:
        raise ValueError(f"tremor_band must satisfy 0 < low < high <= fs/2 = {fs / 2}, got {tremor_band!r}")
    rng = np.random.default_rng(seed)
    n = int(round(duration * fs))
    t = np.arange(n) / fs
    if voluntary_freq is None:
        voluntary_freq = float(rng.uniform(0.2, 0.9))
    voluntary = voluntary_amplitude * np.sin(2 * np.pi * voluntary_freq * t + rng.uniform(0, 2 * np.pi))
    white = _sinusoid_bank(rng, t, freq_step, fs / 2, freq_step, 1.0, 0.5)
    tremor = _sinusoid_bank(rng, t, lo, hi, freq_step, 1.0, 0.5)
    noise_power = np.mean(voluntary**2) / 10 ** (snr_db / 10)
    white *= np.sqrt((1 - tremor_share) * noise_power / np.mean(white**2))
    tremor *= np.sqrt(tremor_share * noise_power / np.mean(tremor**2))
    reached = 10 * np.log10(np.mean(voluntary**2) / np.mean((white + tremor) ** 2))
    # White noise and tremor are not exactly orthogonal over a finite record;
    # one rescale of both makes the stated SNR exact.
    gain = 10 ** ((reached - snr_db) / 20)
    white *= gain
    tremor *= gain
    reached = 10 * np.log10(np.mean(voluntary**2) / np.mean((white + tremor) ** 2))
    return SyntheticSignal(voluntary + white + tremor, voluntary, white, tremor, fs, float(reached),
                           float(voluntary_freq))


def paper_dataset(seed=2018, **kwargs):
    """The ten signals of the paper's synthetic table, seeded and reproducible.

    Signal ``i`` (0-based) uses ``PAPER_SNR_DB[i]`` and seed ``seed + i``.

    Examples
    --------
    >>> from wake.eval.synthetic import paper_dataset
    >>> data = paper_dataset()
    >>> len(data), [round(s.snr_db, 1) for s in data][:3]
    (10, [7.5, 5.1, 0.3])
    """
    return [make_signal(snr, seed=seed + i, **kwargs) for i, snr in enumerate(PAPER_SNR_DB)]


#: Drift-to-tremor power ratios, dB, of :func:`rest_tremor_dataset` (signal ``i`` uses entry ``i % 5``).
REST_TREMOR_DRIFT_DB = (-20.0, -15.0, -10.0, -5.0, 0.0)


@dataclass(frozen=True)
class RestTremorSignal:
    """One rest-tremor recording with every component kept apart (:func:`make_rest_tremor`)."""

    measurement: np.ndarray  #: voluntary + white + tremor
    voluntary: np.ndarray  #: the 1/f drift: slow motion an actuator must not cancel
    white: np.ndarray  #: sensor noise
    tremor: np.ndarray  #: the rest tremor
    fs: float
    tremor_freq: float  #: centre of the tremor band, Hz
    drift_db: float  #: drift-to-tremor power ratio reached, dB


def make_rest_tremor(*, seed=0, fs=100.0, duration=50.0, drift_db=-10.0, white_db=-30.0, tremor_freq=None,
                     tremor_width=1.0, drift_band=(0.02, 3.0)):
    """Rest tremor with little voluntary motion: a 4-6 Hz tremor on 1/f drift.

    The tremor is a bank of sinusoids every 0.02 Hz over ``tremor_width``
    around ``tremor_freq`` (random amplitudes and phases, unit power).  The
    voluntary part is slow drift whose power density falls as 1/f over
    ``drift_band``: sinusoids every 0.02 Hz with amplitudes proportional to
    ``f**-0.5``, scaled to ``drift_db`` relative to the tremor.  The sensor
    noise is white (sinusoids every 0.1 Hz up to ``fs/2``) at ``white_db``.
    A window of it has a spectrum that rises from the drift into the tremor
    peak with no valley between them.

    Parameters
    ----------
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same signal.
    fs, duration : float
        Sampling rate (Hz) and length (s).
    drift_db : float
        Drift power over tremor power, dB.
    white_db : float
        White noise power over tremor power, dB.
    tremor_freq : float, optional
        Centre of the tremor band, Hz; drawn from U(4.5, 5.5) when omitted, so
        the band lies within 4-6 Hz.
    tremor_width : float
        Width of the tremor band, Hz.
    drift_band : (float, float)
        Lowest and highest drift frequency, Hz.

    Returns
    -------
    RestTremorSignal

    Examples
    --------
    >>> from wake.eval.synthetic import make_rest_tremor
    >>> s = make_rest_tremor(seed=1, drift_db=-10.0)
    >>> s.measurement.shape, round(s.drift_db, 6), bool(4.0 <= s.tremor_freq <= 6.0)
    ((5000,), -10.0, True)
    """
    fs = check_positive("fs", fs)
    duration = check_positive("duration", duration)
    check_positive("tremor_width", tremor_width)
    if not 0 < drift_band[0] < drift_band[1] < fs / 2:
        raise ValueError(f"drift_band must satisfy 0 < low < high < fs/2 = {fs / 2}, got {drift_band!r}")
    rng = np.random.default_rng(seed)
    n = int(round(duration * fs))
    t = np.arange(n) / fs
    if tremor_freq is None:
        tremor_freq = float(rng.uniform(4.5, 5.5))
    if not tremor_width / 2 < tremor_freq < fs / 2 - tremor_width / 2:
        raise ValueError(f"the tremor band {tremor_freq!r} +- {tremor_width / 2!r} Hz must lie inside (0, fs/2)")
    step = 0.02
    tremor = _sinusoid_bank(rng, t, tremor_freq - tremor_width / 2, tremor_freq + tremor_width / 2, step, 1.0, 0.5)
    freqs = np.arange(drift_band[0], drift_band[1] + step / 2, step)
    amps = rng.uniform(0.5, 1.5, freqs.size) / np.sqrt(freqs)
    phases = rng.uniform(0.0, 2 * np.pi, freqs.size)
    drift = np.sum(amps[:, None] * np.sin(2 * np.pi * freqs[:, None] * t + phases[:, None]), axis=0)
    white = _sinusoid_bank(rng, t, 0.1, fs / 2, 0.1, 1.0, 0.5)
    tremor /= np.sqrt(np.mean(tremor**2))
    drift *= 10 ** (drift_db / 20) / np.sqrt(np.mean(drift**2))
    white *= 10 ** (white_db / 20) / np.sqrt(np.mean(white**2))
    return RestTremorSignal(drift + white + tremor, drift, white, tremor, fs, float(tremor_freq),
                            float(10 * np.log10(np.mean(drift**2) / np.mean(tremor**2))))


def rest_tremor_dataset(seed=2030, **kwargs):
    """Ten rest-tremor signals: signal ``i`` uses seed ``seed + i`` and ``REST_TREMOR_DRIFT_DB[i % 5]``.

    Examples
    --------
    >>> from wake.eval.synthetic import rest_tremor_dataset
    >>> data = rest_tremor_dataset()
    >>> len(data), [round(s.drift_db) for s in data][:5]
    (10, [-20, -15, -10, -5, 0])
    """
    return [make_rest_tremor(seed=seed + i, drift_db=REST_TREMOR_DRIFT_DB[i % len(REST_TREMOR_DRIFT_DB)], **kwargs)
            for i in range(10)]
