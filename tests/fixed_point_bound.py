"""The C core's error bound against the float reference (docs/studies/fixed_point.md, eqs. (B1), (B2)), shared by the
tests of the one-step output (tests/rtp/test_fixed_point.py) and of ``v_h`` (tests/rtp/test_fixed_voluntary.py).

Values are in full-scale units; ``fixed`` is the ``wake.rtp.fixed`` module (its Q formats), passed in so that
this module imports without the C extension.
"""

import numpy as np


def quantized(x, fs):
    """``x`` rounded to the C core's Q15 input at full scale ``fs``."""
    return np.clip(np.round(np.asarray(x) / fs * 32768), -32768, 32767) / 32768 * fs


def static_bound(n_taps, fixed):
    """Eq. (B1): Q15 output rounding, Q23 rounding of the FIR sum, and the rounding of the N FIR taps
    h = B'w to Q(FIR_FRAC) times |sample| <= 1."""
    return 2.0**-16 + 2.0**-24 + n_taps * 2.0 ** -(fixed.FIR_FRAC + 1)


def kalman_bound_step(ref, m, B, fs, fixed):
    """Eq. (B2), one sample ``m`` before ``ref`` steps on it: ``B <- (1 - g) B + rho`` with ``g = w'Pw / S``
    and ``rho = sum|w| 2^-24 + |e| (sum|w|)^2 4 LSB_P / S``; ``B`` unchanged when the update is idle."""
    w = ref.weights
    P = ref.covariance.reshape(ref.level, ref.level) / fs**2
    wu = float(w @ P @ w)
    if not (wu > 0 or ref.process_noise > 0):
        return B
    sw = np.abs(w).sum()
    S = wu + ref.measurement_noise / fs**2
    e = abs(m - ref.last_output) / fs if ref.primed else 0.0
    return (1 - wu / S) * B + sw * 2.0**-24 + e * sw * sw * 4 * 2.0**-fixed.P_FRAC / S
