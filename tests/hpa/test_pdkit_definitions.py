"""Our frequency and amplitude against pdkit's TremorProcessor definitions, computed here.

pdkit 1.4.4 (the newest release) installs but does not import with the SciPy this package supports
(``ImportError: cannot import name 'cumtrapz' from 'scipy.integrate'``; its ``fft_signal`` also calls
``scipy.signal.hann``, gone since SciPy 1.13), and its requirements miss ``tsfresh`` and ``future``
(docs/studies/characterisation.md, "pdkit").  So this test writes out what ``TremorProcessor.amplitude(df,
method="fft")`` computes with its defaults, on the same windows, and compares:

- pdkit: 2nd-order Butterworth high-pass at 2 Hz (``lfilter``, causal), the central 256 samples times a
  Hann window, FFT divided by 256, the one-sided half; frequency = the bin of the largest magnitude,
  amplitude = the sum of the magnitudes of the bins strictly between 2 and 10 Hz.
- For a tone of amplitude A that sum is about A / 2 (a Hann window's coherent gain 1/2, one side of the
  spectrum, the main lobe's bins summed), so ``2 * amplitude`` is compared with ``sqrt(2) * rms``.

Tolerances: frequency within 0.2 Hz (half of pdkit's 100 / 256 = 0.39 Hz bin, ours being within 0.01 Hz
on these tones); amplitude within 8 % (the bin sum depends on where the tone falls between bins: 0.956 to
1.060 of A measured over these 40 tones).
"""

import numpy as np
import pytest
from scipy import signal

from wake.hpa.characterise import characterise_window

FS = 100.0


def pdkit_fft_amplitude(x, fs=FS, cutoff=2.0, order=2, window=256, lower=2.0, upper=10.0):
    """``TremorProcessor(sampling_frequency=fs).amplitude(df, method="fft")`` of pdkit 1.4.4, on a uniform grid."""
    b, a = signal.butter(order, 2 * cutoff / fs, "high", analog=False)
    y = signal.lfilter(b, a, x)
    left = int(len(y) / 2 - window / 2)
    spectrum = np.fft.fft(y[left:left + window] * signal.windows.hann(window)) / window
    f = np.arange(window) / (window / fs)
    f, spectrum = f[: window // 2], spectrum[: window // 2]
    amplitude = float(np.sum(np.abs(spectrum[(f > lower) & (f < upper)])))
    return amplitude, float(f[np.argmax(np.abs(spectrum))])


def test_frequency_and_amplitude_agree_with_pdkit_definitions():
    rng = np.random.default_rng(0)
    t = np.arange(500) / FS
    ratios = []
    for f0 in np.linspace(3.0, 9.5, 40):
        a = rng.uniform(0.1, 5.0)
        x = a * (0.5 * np.sin(2 * np.pi * 0.3 * t) + np.sin(2 * np.pi * f0 * t + rng.uniform(0, 6))
                 + 0.01 * rng.normal(size=t.size))
        ours = characterise_window(x, FS, 2.0)
        amplitude, frequency = pdkit_fft_amplitude(x)
        assert abs(frequency - ours.frequency) <= 0.2
        ratios.append(2 * amplitude / (np.sqrt(2) * ours.rms))
    assert np.all(np.abs(np.array(ratios) - 1) <= 0.08)


def test_pdkit_frequency_is_not_limited_to_the_tremor_band():
    """Where the definitions part: pdkit's frequency is the largest bin anywhere above its 2 Hz high-pass's
    roll-off, so a strong 1.5 Hz movement wins over a 6 Hz tremor; ours looks above f_d only."""
    t = np.arange(500) / FS
    x = 4 * np.sin(2 * np.pi * 1.5 * t) + 0.3 * np.sin(2 * np.pi * 6 * t)
    _, frequency = pdkit_fft_amplitude(x)
    assert frequency < 2.0
    assert characterise_window(x, FS, 3.0).frequency == pytest.approx(6.0, abs=0.1)
