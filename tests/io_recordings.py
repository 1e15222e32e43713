"""Recordings for the reader tests: a gyroscope and an accelerometer with gravity, at any rate, in any layout.

Both carry a 6 Hz tremor over slow voluntary motion.  The gyroscope (deg/s) has no offset; the accelerometer
(m/s^2) carries gravity, 9.81 on z and a slowly turning share of it on x and y, as a wrist does.
"""

import numpy as np

#: Kinds of recording every reader test runs on.
KINDS = ("gyro", "acc")
#: Rates every reader test runs at, Hz.
RATES = (100.0, 1000.0)


def signals(kind, fs, seconds=12.0, seed=0):
    """``(names, units, samples (n, 3))`` of a 3-axis recording of ``kind`` at ``fs``."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds * fs))) / fs
    tremor = np.sin(2 * np.pi * 6.0 * t)[:, None] * np.array([1.0, 0.6, 0.3])
    voluntary = np.column_stack([np.sin(2 * np.pi * f * t + p) for f, p in ((0.3, 0.0), (0.5, 1.0), (0.2, 2.0))])
    noise = 0.01 * rng.standard_normal((t.size, 3))
    if kind == "gyro":
        return ("gx", "gy", "gz"), ("deg/s",) * 3, 40.0 * voluntary + 8.0 * tremor + noise
    tilt = 0.3 * np.sin(2 * np.pi * 0.1 * t)
    gravity = 9.81 * np.column_stack([np.sin(tilt), np.sin(tilt) * 0.5, np.cos(tilt)])
    return ("ax", "ay", "az"), ("m/s^2",) * 3, gravity + 0.5 * voluntary + 0.3 * tremor + noise


def cell(v) -> str:
    return repr(float(v))


def write(path, header, rows, sep=","):
    """Write ``rows`` (lists of cells, str or numbers) under ``header`` (a list of cells, or None)."""
    lines = [] if header is None else [sep.join(header)]
    lines += [sep.join(c if isinstance(c, str) else cell(c) for c in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path
