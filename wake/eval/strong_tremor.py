"""A synthetic strong-tremor set: 4-8 Hz tremor with real tremor's slow amplitude and frequency drift.

The paper's synthetic set (:mod:`wake.eval.synthetic`) holds a broadband 6-14 Hz "tremor" of fixed sinusoids
under a dominant voluntary sinusoid; rest and postural tremor of Parkinson's disease (PD) and essential
tremor (ET) is the opposite: one narrow-band oscillation that dominates the motion, whose amplitude and
frequency wander.  Each signal of :func:`make_strong_tremor` is::

    x = voluntary + tremor + noise (+ gravity and a start transient, accelerometer kind)
    tremor(t) = A(t) [sin phi(t) + h2 sin(2 phi(t) + psi)],   phi' = 2 pi f(t)
    f(t) = f0 + frequency wander;  A(t) = a0 exp(amplitude wander)

Parameters and where they come from (the numbers are chosen inside the ranges these sources report; they
are not fitted to any one recording):

* ``f0`` drawn in 4-8 Hz: PD rest tremor 4-6 Hz, ET postural tremor 5-8 Hz at the ages these devices are
  worn (Deuschl, Bain & Brin 1998, Mov Disord 13 S3: the consensus statement's frequency ranges; Elble 2000,
  "Origins of tremor", Lancet 355:1113).  pdkit's clearest rest tremor is 5.9 Hz.
* frequency wander: a first-order low-pass (time constant ``wander_s`` = 2 s) random walk of standard
  deviation ``freq_sd_hz`` = 0.3 Hz: tremor's spectral peak holds a width of a few tenths of a Hz over a
  recording (Timmer, Lauk & Deuschl 1996, Electroencephalogr Clin Neurophysiol 101:461, which models
  tremor as a damped stochastic oscillator with such a peak).
* amplitude wander: log-amplitude of the same low-pass kind, standard deviation ``amp_sd`` = 0.35 (an
  envelope that varies by a factor of about 2 over seconds, as in the waxing and waning of rest tremor;
  the same source and Timmer et al. 1993, Biol Cybern 70:75).
* second harmonic ``h2`` = 0.15 of the fundamental (a weak harmonic is common in recorded tremor spectra).
* voluntary motion: slow movements, a sum of sinusoids in 0.1-1 Hz whose RMS is ``voluntary_ratio`` of the
  tremor's (default 0.5: tremor dominates, the case where a suppression device matters);
* sensor noise: white, ``noise_db`` = -30 dB below the tremor's power (a MEMS gyroscope or accelerometer at
  100 Hz is well below tremor of this size).
* ``kind="accelerometer"``: a constant gravity offset of 9.81 on the channel and a start transient, the
  device being put in place (a ramp of ``start_step`` = 8 m/s^2 over the first ``start_s`` = 2 s with a
  knock of a few periods of 15 Hz at its end, what pdkit's recordings start with).

The tremor component ``tremor`` is the truth (what an actuator should cancel); the noise is not.

Examples
--------
>>> from wake.eval.strong_tremor import make_strong_tremor
>>> s = make_strong_tremor(seed=3)
>>> s.measurement.shape, 4.0 <= s.f0 <= 8.0
((3000,), True)
>>> bool((s.tremor.std() > s.voluntary.std()))
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wake._validation import check_positive

__all__ = ["StrongTremorSignal", "make_strong_tremor", "strong_tremor_dataset", "KINDS", "STRONG_SEED"]

KINDS = ("gyroscope", "accelerometer")
#: Seed of the set's first signal (signal ``i``: ``STRONG_SEED + i``).
STRONG_SEED = 4600


@dataclass(frozen=True)
class StrongTremorSignal:
    """One strong-tremor signal with its parts kept apart."""

    measurement: np.ndarray  #: what the sensor gives
    tremor: np.ndarray  #: the tremor (the truth)
    voluntary: np.ndarray  #: slow motion, plus gravity and the start transient for an accelerometer
    noise: np.ndarray  #: sensor noise
    fs: float
    f0: float  #: centre tremor frequency, Hz
    kind: str
    name: str


def _wander(rng, n, fs, tau_s, sd):
    """A first-order low-pass of white noise with time constant ``tau_s`` and standard deviation ``sd``."""
    a = np.exp(-1.0 / (tau_s * fs))
    w = rng.standard_normal(n) * sd * np.sqrt(1 - a * a)
    out = np.empty(n)
    acc = rng.standard_normal() * sd
    for i in range(n):
        acc = a * acc + w[i]
        out[i] = acc
    return out


def make_strong_tremor(*, seed=0, fs=100.0, duration=30.0, kind="gyroscope", f0=None, amplitude=1.0,
                       freq_sd_hz=0.3, amp_sd=0.35, wander_s=2.0, h2=0.15, voluntary_ratio=0.5,
                       noise_db=-30.0, start_step=8.0, start_s=2.0):
    """One strong-tremor signal (module docstring: the model and the sources of its defaults).

    Parameters
    ----------
    seed : int
        ``numpy.random.default_rng`` seed.
    fs, duration : float
        Hz and s.
    kind : {"gyroscope", "accelerometer"}
        An accelerometer adds gravity and a start transient.
    f0 : float, optional
        Centre tremor frequency in Hz; drawn in U(4, 8) when omitted.
    amplitude : float
        ``a0``, the tremor's median amplitude.
    freq_sd_hz, amp_sd, wander_s : float
        Frequency and log-amplitude wander and their time constant.
    h2 : float
        Second harmonic relative to the fundamental.
    voluntary_ratio : float
        RMS of the slow voluntary motion over the tremor's.
    noise_db : float
        Sensor noise power relative to the tremor's, dB.
    start_step, start_s : float
        The accelerometer's start transient: a ramp of ``start_step`` over ``start_s`` seconds.

    Returns
    -------
    StrongTremorSignal
    """
    fs = check_positive("fs", fs)
    duration = check_positive("duration", duration)
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    for name, value in (("freq_sd_hz", freq_sd_hz), ("amp_sd", amp_sd), ("h2", h2),
                        ("voluntary_ratio", voluntary_ratio), ("start_step", start_step)):
        check_positive(name, value, allow_zero=True)
    check_positive("amplitude", amplitude)
    check_positive("wander_s", wander_s)
    check_positive("start_s", start_s)
    rng = np.random.default_rng(seed)
    n = int(round(duration * fs))
    t = np.arange(n) / fs
    f0 = float(rng.uniform(4.0, 8.0)) if f0 is None else float(f0)
    if not 0 < 2 * (f0 + 4 * freq_sd_hz) < fs / 2:
        raise ValueError(f"the tremor's second harmonic must stay below fs/2 = {fs / 2:g} Hz: lower f0 "
                         f"({f0:g} Hz) or freq_sd_hz, or raise fs")
    freq = np.clip(f0 + _wander(rng, n, fs, wander_s, freq_sd_hz), 0.5 * f0, 1.5 * f0)
    phase = 2 * np.pi * np.cumsum(freq) / fs + rng.uniform(0, 2 * np.pi)
    env = amplitude * np.exp(_wander(rng, n, fs, wander_s, amp_sd))
    tremor = env * (np.sin(phase) + h2 * np.sin(2 * phase + rng.uniform(0, 2 * np.pi)))
    vol_f = rng.uniform(0.1, 1.0, 4)
    voluntary = sum(rng.uniform(0.5, 1.0) * np.sin(2 * np.pi * f * t + rng.uniform(0, 2 * np.pi)) for f in vol_f)
    voluntary *= voluntary_ratio * tremor.std() / max(voluntary.std(), 1e-300)
    noise = rng.standard_normal(n) * tremor.std() * 10 ** (noise_db / 20)
    if kind == "accelerometer":
        ramp = np.clip(t / start_s, 0.0, 1.0)
        knock = np.where((t >= start_s) & (t < start_s + 0.2),
                         0.3 * start_step * np.sin(2 * np.pi * 15.0 * (t - start_s)) *
                         np.exp(-(t - start_s) / 0.05), 0.0)
        voluntary = voluntary + 9.81 - start_step * (1 - ramp) + knock
    return StrongTremorSignal(voluntary + tremor + noise, tremor, voluntary, noise, fs, f0, kind,
                              f"strong-{kind[:4]}-{seed}")


def strong_tremor_dataset(count=10, seed=STRONG_SEED, fs=100.0, duration=30.0):
    """``count`` signals, half gyroscope and half accelerometer, seeds ``seed + i``.

    Examples
    --------
    >>> from wake.eval.strong_tremor import strong_tremor_dataset
    >>> [s.kind for s in strong_tremor_dataset(4, duration=6.0)]
    ['gyroscope', 'accelerometer', 'gyroscope', 'accelerometer']
    """
    return [make_strong_tremor(seed=seed + i, fs=fs, duration=duration, kind=KINDS[i % 2]) for i in range(count)]
