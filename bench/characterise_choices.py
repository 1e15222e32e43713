"""The measurements behind two choices of :mod:`wake.hpa.characterise`: the frequency estimator and the peak test.

    python bench/characterise_choices.py

1. Dominant frequency: four estimators of the tremor frequency of a 5 s,
   100 Hz window (voluntary motion of 3 units at 0.1-0.8 Hz plus a drift,
   tremor of RMS 0.71 at 3.5-11 Hz, white noise at the stated in-window
   SNR), searched in (2, 15] Hz: the AR(17) spectrum of the window (the
   HPA's own), the AR(17) spectrum of its sharp high-pass tremor, Welch
   (256-sample Hann segments) and the Hann periodogram of the whole
   detrended window zero-padded 8 times; the last two with a parabola
   through the log power of the peak's three bins.  Tremor kinds: a tone,
   an amplitude-modulated tone (80 % at 0.5 Hz), a frequency-modulated one
   (index 1.67 at 0.3 Hz, whose spectrum peaks on a sideband: no spectral
   peak finds the carrier there).  Printed: median and 90th percentile of the
   absolute error in Hz over 60 windows each.
2. Peak test: how often a window of noise alone shows a "tremor peak"
   (false alarms of 300), and how often a tone of a given in-band SNR is
   found (of 100), for three ratios of the peak to the band's median power.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy import signal

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wake.hpa.characterise as characterise  # noqa: E402
from wake.hpa.sharp import detrended_highpass, end_point_line  # noqa: E402
from wake.hpa.spectrum import ar_psd  # noqa: E402

FS, N, LOW, TOP = 100.0, 500, 2.0, 15.0


def _refined(f, p):
    band = np.flatnonzero((f > LOW) & (f <= TOP))
    k = band[np.argmax(p[band])]
    a, b, c = np.log(p[k - 1:k + 2])
    return f[k] + 0.5 * (a - c) / (a - 2 * b + c) * (f[1] - f[0])


def _ar_peak(x):
    f, p = ar_psd(x, FS, 17, 1024)
    band = (f > LOW) & (f <= TOP)
    return f[band][np.argmax(p[band])]


def estimates(x):
    """The four estimates of the dominant tremor frequency of ``x``."""
    d = x - end_point_line(x)
    welch = _refined(*signal.welch(d, FS, nperseg=256))
    hann = _refined(*signal.periodogram(d, FS, window="hann", nfft=8 * N))
    return _ar_peak(x), _ar_peak(detrended_highpass(x, FS, LOW)), welch, hann


def frequency_table(rng):
    t = np.arange(N) / FS
    print("in-window SNR, tremor kind: median | p90 absolute error (Hz) of "
          "AR(window), AR(tremor), Welch, Hann periodogram")
    for snr in (20, 10, 3, 0):
        for kind in ("tone", "am", "fm"):
            errors = []
            for _ in range(60):
                f0 = rng.uniform(3.5, 11.0)
                vol = 3 * np.sin(2 * np.pi * rng.uniform(0.1, 0.8) * t + rng.uniform(0, 6)) + t
                if kind == "tone":
                    tremor = np.sin(2 * np.pi * f0 * t + rng.uniform(0, 6))
                elif kind == "am":
                    tremor = (1 + 0.8 * np.sin(2 * np.pi * 0.5 * t)) * np.sin(2 * np.pi * f0 * t)
                else:
                    tremor = np.sin(2 * np.pi * f0 * t + 0.5 / 0.3 * np.sin(2 * np.pi * 0.3 * t))
                noise = rng.normal(size=N) * np.sqrt(np.var(tremor) / 10 ** (snr / 10))
                errors.append(np.abs(np.array(estimates(vol + tremor + noise)) - f0))
            e = np.array(errors)
            med = " ".join(f"{v:.3f}" for v in np.median(e, axis=0))
            p90 = " ".join(f"{v:.3f}" for v in np.percentile(e, 90, axis=0))
            print(f"{snr:>3} dB {kind:>4}: {med} | {p90}")


def peak_test_table(rng):
    t = np.arange(N) / FS
    noise_sd = 0.1
    in_band = noise_sd ** 2 * (TOP - LOW) / (FS / 2)
    kept = characterise.PEAK_RATIO
    print("\npeak ratio: false alarms of 300 noise windows; tones found of 100 at in-band SNR -15, -10, -5, 0 dB")
    try:
        for ratio in (10.0, 20.0, 10 ** 1.5):
            characterise.PEAK_RATIO = ratio

            def found(amplitude):
                x = np.sin(2 * np.pi * 0.3 * t) + noise_sd * rng.normal(size=N)
                x = x + amplitude * np.sin(2 * np.pi * rng.uniform(3, 12) * t)
                return characterise.characterise_window(x, FS, LOW).reason != "no_tremor_peak"

            false = sum(found(0.0) for _ in range(300))
            hits = [sum(found(np.sqrt(2 * in_band * 10 ** (snr / 10))) for _ in range(100))
                    for snr in (-15, -10, -5, 0)]
            print(f"{ratio:6.1f} ({10 * np.log10(ratio):4.1f} dB): {false:>3} / 300; {hits}")
    finally:
        characterise.PEAK_RATIO = kept


def main():
    frequency_table(np.random.default_rng(1))
    peak_test_table(np.random.default_rng(2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
