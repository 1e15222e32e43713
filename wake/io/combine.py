"""Three axes into one channel: the vector magnitude or the principal axis (``wake run --combine``).

A tremor shakes the hand in three dimensions; a sensor reports three axes.
``--combine`` turns each triple of channels (x, y, z of one sensor, in the
order the file lists them: ``acc_x, acc_y, acc_z, gyro_x, gyro_y, gyro_z``
gives two triples) into one channel, which WAKE then filters:

* ``norm``: the vector magnitude ``sqrt(x^2 + y^2 + z^2)``.  For an
  accelerometer (a unit of acceleration, ``g``, ``m/s^2``, ..., or a name
  starting with ``acc``) gravity is handled as the magnitude's carrier:
  gravity's magnitude does not change when the wrist turns, so the magnitude
  is gravity (1 g) plus the motion along it, and the recording's median
  magnitude (the gravity estimate; a constant) is subtracted.  Subtracting a
  per-axis gravity estimate *before* the norm would not do: the norm of a
  motion about zero is rectified, and a 6 Hz tremor would show at 12 Hz.
  For the same reason the magnitude of a gyroscope (no carrier) is the
  rectified angular speed: a tremor about one axis shows at twice its
  frequency, which WAKE reports as it is; ``pca`` is the choice there, and
  the note says so.
* ``pca``: the projection onto the principal axis of the triple's motion in
  the tremor band.  The axis is the first principal component of the three
  channels after each is high-passed (its 1 s moving mean taken out, which
  removes gravity and the slow voluntary motion); the whole signal, less its
  mean, is projected on it, so frequencies are kept and the sign is the
  axis's (its largest component positive).  The axis is fitted on the whole
  recording: ``pca`` is for recordings, not streams.

The combined channel is named after what the triple's names share
(``acc_x, acc_y, acc_z`` -> ``acc_norm``; ``gx, gy, gz`` -> ``g_pca``), in
the triple's unit.
"""

from __future__ import annotations

import os
from dataclasses import replace

import numpy as np

__all__ = ["COMBINE_CHOICES", "combine_axes", "is_accelerometer"]

#: Accepted values of ``how`` (``--combine``).
COMBINE_CHOICES = ("norm", "pca")

_ACC_UNITS = {"g", "mg", "m/s^2", "m/s2", "m/s²", "m s^-2", "m s-2", "ms^-2", "ms-2", "m/s/s", "g0"}


def is_accelerometer(names, units) -> bool:
    """An accelerometer triple: a unit of acceleration, or names that start with ``acc``."""
    if any(u.strip().lower().replace(" ", "") in {a.replace(" ", "") for a in _ACC_UNITS} for u in units if u):
        return True
    return all(n.lower().startswith("acc") for n in names)


def _triple_name(names, how) -> str:
    stem = os.path.commonprefix([n.lower() for n in names])
    stem = names[0][:len(stem)].rstrip("_-. ")
    return f"{stem or 'xyz'}_{how}"


def _moving_mean(x, width):
    kernel = np.ones(width) / width
    pad = width // 2
    padded = np.pad(x, ((pad, width - 1 - pad), (0, 0)), mode="edge")
    return np.column_stack([np.convolve(padded[:, c], kernel, mode="valid") for c in range(x.shape[1])])


def _norm(x, acc):
    mag = np.sqrt(np.sum(x * x, axis=1))
    if acc:
        finite = mag[np.isfinite(mag)]
        mag = mag - (np.median(finite) if finite.size else 0.0)
    return mag


def _pca(x, fs):
    filled = np.where(np.isfinite(x), x, np.nanmean(x, axis=0))
    width = max(3, int(round(fs)))
    fast = filled - _moving_mean(filled, width)
    _, _, vt = np.linalg.svd(fast - fast.mean(axis=0), full_matrices=False)
    axis = vt[0] * np.sign(vt[0][np.argmax(np.abs(vt[0]))])
    return (x - np.nanmean(x, axis=0)) @ axis, axis


def combine_axes(rec, how: str):
    """``rec`` with each triple of channels combined into one (module docstring).

    Parameters
    ----------
    rec : Recording
        Its channels, taken three at a time, are the x, y, z of one sensor each.
    how : {"norm", "pca"}

    Returns
    -------
    Recording
        One channel per triple; its ``notes`` say how each was made.

    Raises
    ------
    ValueError
        ``how`` is not a choice, or the channel count is not a multiple of 3.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.io import Recording
    >>> from wake.io.combine import combine_axes
    >>> t = np.arange(1000) / 100.0
    >>> acc = np.column_stack([0.1 * np.sin(2 * np.pi * 6 * t), 0 * t, 1.0 + 0 * t])   # gravity on z
    >>> rec = combine_axes(Recording("r", 100.0, ("acc_x", "acc_y", "acc_z"), acc, units=("g",) * 3), "pca")
    >>> rec.channels, rec.units, round(float(np.std(rec.samples[:, 0])), 4)
    (('acc_pca',), ('g',), 0.0707)
    """
    if how not in COMBINE_CHOICES:
        raise ValueError(f"--combine must be one of {', '.join(COMBINE_CHOICES)}, got {how!r}")
    k = len(rec.channels)
    if k % 3:
        raise ValueError(f"--combine {how} takes the channels three at a time (x, y, z of one sensor); "
                         f"{rec.name} has {k} ({', '.join(rec.channels)}): choose them with --column, e.g. "
                         "--column acc_x,acc_y,acc_z")
    cols, names, units, notes = [], [], [], []
    for i in range(0, k, 3):
        triple = rec.channels[i:i + 3]
        unit = [rec.unit(j) for j in range(i, i + 3)]
        x = rec.samples[:, i:i + 3].astype(float)
        name = _triple_name(triple, how)
        if how == "norm":
            acc = is_accelerometer(triple, unit)
            cols.append(_norm(x, acc))
            notes.append(f"{name}: the magnitude of {', '.join(triple)}" +
                         (" less its median (gravity)" if acc else
                          " (not an accelerometer: no carrier, so a tremor about one axis shows at twice its "
                          "frequency; --combine pca keeps it)"))
        else:
            y, axis = _pca(x, rec.fs)
            cols.append(y)
            notes.append(f"{name}: {', '.join(triple)} projected on their principal axis in the tremor band "
                         f"({', '.join(f'{a:.3f}' for a in axis)})")
        names.append(name)
        units.append(unit[0] if len(set(unit)) == 1 else "")
    return replace(rec, channels=tuple(names), samples=np.column_stack(cols),
                   units=tuple(units) if any(units) else (), notes=(*rec.notes, *notes))
