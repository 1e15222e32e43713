"""The fixed-point formats of the C core and the quantisers into them; no compiled core needed.

=====================  ==========================  =====================
quantity               C format                    valid range
=====================  ==========================  =====================
samples, prediction    int16 Q15 of FS             [-1, 1) FS (clipped)
taps                   int16 Q15                   |tap| < 1, row sum of |taps| < 2
weights                int32 Q24                   [-64, 64]
correction d           int32 Q23 of FS             [-256, 256) FS
P, R, q, p0            int32 Q(P_FRAC) of FS**2    see :data:`P_FRAC`
ahead coefficients     int32 Q27                   [-8, 8]
ahead delay line       int16 Q15 of FS             [-1, 1) FS (saturated)
ahead P, command       int32 Q23 of FS             [-256, 256) FS
gate, goal, ramp       int32 Q30                   [0, 1]
=====================  ==========================  =====================

FS is the full scale: the physical value mapped to the int16 full scale.
The numbers here are those of csrc/wake_rtp.h (its defaults, the build
``wake._rtp`` is compiled with); :mod:`wake.rtp.fixed` refuses a compiled
core whose formats differ, and ``tests/rtp/test_qformat.py`` reads the header
to check them, so the header stays their one source.  ``wake export-header``
quantises with this module on a machine without the compiled core.

See ``docs/studies/fixed_point.md`` for the error analysis.
"""

from __future__ import annotations

import numpy as np

from wake.ahead import check_model
from wake.limits import MAX_LEVEL

__all__ = ["P_FRAC", "MAX_LEVEL", "SAMPLE_FRAC", "TAP_FRAC", "STATE_FRAC", "WEIGHT_FRAC", "WEIGHT_MAX",
           "TAP_ROW_ABS_MAX", "FIR_FRAC", "quantize_taps", "quantize_weights", "quantize_variance",
           "representable_noise", "format_mismatches", "AHEAD_TAPS", "AHEAD_COEF_FRAC", "GATE_FRAC",
           "quantize_ahead"]

#: Fraction bits of the covariance format (``WAKE_RTP_P_FRAC``).
P_FRAC = 32
#: Fraction bits of the I/O samples (``WAKE_RTP_SAMPLE_FRAC``: Q15 of FS).
SAMPLE_FRAC = 15
#: Fraction bits of the filter-bank taps (``WAKE_RTP_TAP_FRAC``).
TAP_FRAC = 15
#: Fraction bits of a_j, d_j and the stored last output (``WAKE_RTP_STATE_FRAC``: Q23 of FS).
STATE_FRAC = 23
#: Fraction bits of the HPA weights (``WAKE_RTP_WEIGHT_FRAC``).
WEIGHT_FRAC = 24
#: Largest accepted |weight| (``WAKE_RTP_WEIGHT_MAX`` / 2**WEIGHT_FRAC).
WEIGHT_MAX = 64.0
#: Largest accepted sum of |taps| of one row in Q15 (``WAKE_RTP_TAP_ROW_ABS_MAX``: 2.0 - 2^-15).
TAP_ROW_ABS_MAX = (2 << TAP_FRAC) - 1
#: Fraction bits of the FIR taps h = B'w (``WAKE_RTP_FIR_FRAC``: 22 up to level 6, else 21).
FIR_FRAC = 22 if MAX_LEVEL <= 6 else 21

#: Taps of the tremor-ahead predictor (``WAKE_RTP_AHEAD_TAPS``, :data:`wake.ahead.TAPS`).
AHEAD_TAPS = 8
#: Fraction bits of the predictor's coefficients (``WAKE_RTP_AHEAD_COEF_FRAC``: Q27, holds +-8).
AHEAD_COEF_FRAC = 27
#: Fraction bits of the gate, its goal and its ramp (``WAKE_RTP_GATE_FRAC``: Q30, [0, 1]).
GATE_FRAC = 30

_INT32_MIN, _INT32_MAX = -(2**31), 2**31 - 1


def format_mismatches(lib) -> list:
    """Where a compiled core ``lib`` (``wake._rtp.lib``) has other formats than this module: one line each."""
    want = {"WAKE_RTP_P_FRAC": P_FRAC, "WAKE_RTP_MAX_LEVEL": MAX_LEVEL, "WAKE_RTP_SAMPLE_FRAC": SAMPLE_FRAC,
            "WAKE_RTP_TAP_FRAC": TAP_FRAC, "WAKE_RTP_STATE_FRAC": STATE_FRAC, "WAKE_RTP_WEIGHT_FRAC": WEIGHT_FRAC,
            "WAKE_RTP_WEIGHT_MAX": int(WEIGHT_MAX * 2**WEIGHT_FRAC), "WAKE_RTP_TAP_ROW_ABS_MAX": TAP_ROW_ABS_MAX,
            "WAKE_RTP_AHEAD_TAPS": AHEAD_TAPS, "WAKE_RTP_AHEAD_COEF_FRAC": AHEAD_COEF_FRAC,
            "WAKE_RTP_GATE_FRAC": GATE_FRAC}
    return [f"{name} = {int(getattr(lib, name))} (wake.rtp.qformat: {value})"
            for name, value in want.items() if int(getattr(lib, name)) != value]


def quantize_taps(taps):
    """Taps (J, 2**J) -> int16 Q15, checking the C core's overflow bound."""
    taps = np.array(taps, dtype=float)
    if taps.ndim != 2 or taps.shape[1] != 2 ** taps.shape[0]:
        raise ValueError(f"taps must have shape (J, 2**J), got {taps.shape}")
    if not 1 <= taps.shape[0] <= MAX_LEVEL:
        raise ValueError(f"the C core supports levels 1..{MAX_LEVEL}, got {taps.shape[0]}")
    if not np.isfinite(taps).all():
        raise ValueError("taps must be finite")
    q = np.round(taps * 2.0**TAP_FRAC)
    if np.abs(q).max() > 2**15 - 1:
        raise ValueError(f"taps must lie within ±1 (int16 Q{TAP_FRAC}), got max |tap| {np.abs(taps).max():.6g}")
    row_abs = np.abs(q).sum(axis=1)
    if row_abs.max() > TAP_ROW_ABS_MAX:
        raise ValueError(
            f"each tap row's sum of |taps| must be below 2.0 (at most {TAP_ROW_ABS_MAX} in Q{TAP_FRAC}) so the "
            f"C filter-bank accumulator cannot overflow; got {row_abs.max() / 2.0**TAP_FRAC:.6g}"
        )
    return np.ascontiguousarray(q, dtype=np.int16)


def quantize_weights(weights, level):
    """HPA weights -> int32 Q24 (|w| <= 64)."""
    w = np.array(weights, dtype=float).reshape(-1)
    if w.shape != (level,) or not np.isfinite(w).all():
        raise ValueError(f"weights must be {level} finite numbers, got {weights!r}")
    if np.abs(w).max(initial=0.0) > WEIGHT_MAX:
        raise ValueError(
            f"weights must lie within ±{WEIGHT_MAX:g} in Q{WEIGHT_FRAC} (int32); got max |w| {np.abs(w).max():.6g}"
        )
    return np.ascontiguousarray(np.round(w * 2.0**WEIGHT_FRAC), dtype=np.int32)


def quantize_variance(value, full_scale, name, *, positive):
    """A variance in physical units -> int32 Q(P_FRAC) of full_scale**2."""
    v = float(value)
    lsb = full_scale**2 / 2.0**P_FRAC
    hi = 2.0 ** (31 - P_FRAC) * full_scale**2
    if not np.isfinite(v) or v < 0 or (positive and v <= 0):
        raise ValueError(f"{name} must be finite and {'> 0' if positive else '>= 0'}, got {value!r}")
    q = round(v / lsb)
    if q > _INT32_MAX:
        raise ValueError(
            f"{name} must lie within [0, {hi:.6g}), i.e. below 2**{31 - P_FRAC} full_scale**2 "
                f"(int32 Q{P_FRAC} of full_scale**2, full_scale = {full_scale:g}); got {v:.6g}"
        )
    if v > 0 and q == 0:
        raise ValueError(
            f"{name} = {v:.6g} rounds to zero in Q{P_FRAC} of full_scale**2; it must be 0 or at least "
            f"{lsb / 2:.6g} (half an LSB); raise it or lower full_scale"
        )
    return q




def representable_noise(r, q, full_scale):
    """Clamp R and q into what the C core holds (Q(P_FRAC) of full_scale**2).

    R below one LSB (a window with no tremor, a large full scale) is raised to
    one LSB; R or q above the Q format's range (a full scale set below the
    signal) are lowered to its top.  Returns ``(r, q, clamped)``.
    """
    lsb = full_scale**2 / 2.0**P_FRAC
    top = _INT32_MAX * lsb
    r2 = min(max(r, lsb), top)
    q2 = 0.0 if q == 0 else min(max(q, lsb), top)
    return r2, q2, (r2 != r or q2 != q)


def weight_words(weights, level, measurement_noise, process_noise, full_scale):
    """An HPA's weights, R and q -> what ``wake_rtp_set_weights`` takes: ``(w_q, r_q, q_q)`` (``q_q`` None when
    ``process_noise`` is None: the core keeps its q).  ValueError for what the core cannot hold."""
    w_q = quantize_weights(weights, level)
    r_q = quantize_variance(measurement_noise, full_scale, "measurement_noise R", positive=True)
    if process_noise is None:
        return w_q, r_q, None
    return w_q, r_q, quantize_variance(process_noise, full_scale, "process_noise Q", positive=False)


def clamped_words(weights, level, measurement_noise, process_noise, full_scale):
    """:func:`weight_words` of R and q clamped first (:func:`representable_noise`): ``((w_q, r_q, q_q), clamped)``:
    what an HPA's install hands the C core, one call (``FixedPointRTP.set_weights_clamped``) or a batch of them
    (wake.hpa.c_batch.InstallBatch)."""
    r, q, clamped = representable_noise(measurement_noise, process_noise, full_scale)
    return weight_words(weights, level, r, q, full_scale), clamped


def quantize_ahead(coefficients, goal):
    """A tremor-ahead predictor and gate goal -> (int32 Q27 coefficients, int32 Q30 goal).

    Examples
    --------
    >>> c, g = quantize_ahead([1.0, -0.5, 0, 0, 0, 0, 0, 8.0], 0.5)
    >>> int(c[0]) == 2**27, int(c[7]) == 2**30, g == 2**29
    (True, True, True)
    """
    c, g = check_model(coefficients, goal)
    c_q = np.ascontiguousarray(np.round(c * 2.0**AHEAD_COEF_FRAC), dtype=np.int32)
    return c_q, int(round(g * 2.0**GATE_FRAC))
