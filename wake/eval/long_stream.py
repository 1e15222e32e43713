"""A realistic long synthetic stream for endurance checks (slowly varying tremor)."""

from __future__ import annotations

import numpy as np


def drifting_tremor_stream(hours=24.0, fs=100.0, seed=0, chunk_s=3600.0):
    """Yield ``(voluntary, measurement)`` chunks of a day-long wrist recording.

    Voluntary motion: two slow sinusoids (0.2-0.8 Hz) whose amplitude wanders.
    Tremor: one component whose frequency drifts between 4 and 9 Hz and whose
    amplitude drifts between 0.05 and 0.6 over hours, with a 15-minute
    rest (no tremor) every 4 hours.  White sensor noise at 1 % of full motion.
    The phase is accumulated, so chunks join without a jump.
    """
    rng = np.random.default_rng(seed)
    n_total = int(round(hours * 3600 * fs))
    chunk = int(round(chunk_s * fs))
    phase_t = 0.0
    phase_v = rng.uniform(0, 2 * np.pi, 2)
    fv = np.array([0.23, 0.61])
    for start in range(0, n_total, chunk):
        n = min(chunk, n_total - start)
        t = (start + np.arange(n)) / fs
        hours_t = t / 3600.0
        f_tremor = 6.5 + 2.5 * np.sin(2 * np.pi * hours_t / 7.3)
        a_tremor = 0.325 + 0.275 * np.sin(2 * np.pi * hours_t / 5.1 + 1.0)
        a_tremor = np.where((hours_t % 4.0) < 0.25, 0.0, a_tremor)
        ph = phase_t + np.cumsum(2 * np.pi * f_tremor / fs)
        phase_t = float(ph[-1])
        a_vol = 1.0 + 0.3 * np.sin(2 * np.pi * hours_t / 3.7)
        vol = a_vol * (np.sin(2 * np.pi * fv[0] * t + phase_v[0]) + 0.5 * np.sin(2 * np.pi * fv[1] * t + phase_v[1]))
        noise = 0.01 * rng.normal(size=n)
        yield vol, vol + a_tremor * np.sin(ph) + noise
