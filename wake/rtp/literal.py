"""The paper's RTP as literally written in Algorithms 2 and 3 (ablation only).

At every sample ``n`` the literal RTP takes the last ``N = 2**J`` samples
``m_J(n)``, decomposes them into the ``J`` approximations ``A_J`` (a
``J x N`` matrix; column ``k`` belongs to sample ``k`` of the window) and
runs a fresh Kalman filter over the whole window::

    x(0|0) = A_J[:, 1]                     first column of the window's approximations
    P(0|0) = p0 I
    for k = 1 .. N:                        z(k) = m(k), the k-th sample of the window
        x(k|k-1) = x(k-1|k-1);  P(k|k-1) = P(k-1|k-1) + q I        (F = I)
        r = z(k) - w' x(k|k-1)                                     eq. (Innov)
        S = w' P(k|k-1) w + R                                      eq. (inovCov)
        K = P(k|k-1) w / S                                         eq. (KalGain)
        x(k|k) = x(k|k-1) + K r
        P(k|k) = P(k|k-1) - K w' P(k|k-1)                          eq. (CovUpd)
    prediction of the voluntary motion at n + 1 = w' x(N|N)        (Alg. 2, S3)

``w`` and ``R`` come from the HPA.  The paper's observation model also adds
the HPA window's tremor ground truth as a "known bias"; that signal does
not exist for the samples of the current window in real time, so it is
left out (as in WAKE's own RTP).  Nothing carries over between samples:
the filter restarts from ``A_J[:, 1]`` every time.

WAKE's RTP (:mod:`wake.rtp.reference`) instead runs *one* Kalman filter
along the stream with the filter-bank approximations at the newest sample
as the state: ``O(J N + J^2)`` operations per sample against
``O(J N + N J^2)`` here.  :func:`operation_counts` gives both.
"""

from __future__ import annotations

import numpy as np

from wake.wavelets import DEFAULT_MODE, wavelet_approximations

__all__ = ["literal_rtp_predict", "literal_rtp_run", "first_column_taps", "hpa_schedule", "operation_counts"]


def literal_rtp_predict(window, weights, measurement_noise, p0, q=0.0, wavelet="sym3", mode=DEFAULT_MODE):
    """One literal RTP step on one window (direct: decomposition + ``N`` Kalman iterations).

    Parameters
    ----------
    window : array_like, shape (2**J,)
        ``m_J(n)``, oldest sample first.
    weights : array_like, shape (J,)
        ``w`` from the HPA.
    measurement_noise : float
        ``R`` from the HPA.
    p0 : float
        ``P(0|0) = p0 I``.
    q : float
        ``Q = q I``.

    Returns
    -------
    float
        The predicted voluntary motion at the next sample.
    """
    m = np.asarray(window, dtype=float)
    w = np.asarray(weights, dtype=float)
    J = w.shape[0]
    if m.shape != (2**J,):
        raise ValueError(f"the window must hold 2**J = {2**J} samples for {J} weights, got shape {m.shape}")
    A = wavelet_approximations(m, wavelet, J, mode)  # (N, J): row k = column k of the paper's A_J
    x = A[0].copy()
    P = p0 * np.eye(J)
    for k in range(m.shape[0]):
        P = P + q * np.eye(J)
        r = m[k] - w @ x
        Pw = P @ w
        S = w @ Pw + measurement_noise
        K = Pw / S
        x = x + K * r
        P = P - np.outer(K, Pw)
    return float(w @ x)


def first_column_taps(wavelet, level, mode=DEFAULT_MODE):
    """Taps ``T`` (J, 2**J) with ``T @ window = A_J[:, 1]`` (the approximations at the oldest sample)."""
    n = 2**level
    eye = np.eye(n)
    return np.column_stack([wavelet_approximations(eye[i], wavelet, level, mode)[0] for i in range(n)])


def _windows(x, n_taps):
    """Window ending at each sample; before the first full one, padded with x[0] (as the RTP warm-up)."""
    padded = np.concatenate((np.full(n_taps - 1, x[0]), x))
    return np.lib.stride_tricks.sliding_window_view(padded, n_taps)


def literal_rtp_run(x, schedule, level, p0_scale=1.0, q=0.0, wavelet="sym3", mode=DEFAULT_MODE):
    """Literal RTP over a whole single-channel recording, aligned like :class:`wake.WakeResult`.

    ``out[i + 1]`` is the prediction made after sample ``i`` from the window
    ending at ``i``; ``out[0] = x[0]``.  It equals :func:`literal_rtp_predict`
    on every window (same arithmetic, batched over the samples that share
    one HPA output: the Kalman gains do not depend on the data).

    Parameters
    ----------
    x : array_like, shape (n,)
    schedule : list of (first_sample, weights, R)
        HPA outputs in force from sample index ``first_sample`` on (sorted).
    level : int
    p0_scale : float
        ``P(0|0) = p0_scale * R * I``.
    q : float
        ``Q = q * R * I``.
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    N = 2**level
    T0 = first_column_taps(wavelet, level, mode)
    win = _windows(x, N)  # win[i] ends at sample i
    out = np.empty(n)
    out[0] = x[0]
    bounds = [int(s[0]) for s in schedule] + [n - 1]
    for seg, (start, w, R) in enumerate(schedule):
        stop = bounds[seg + 1]
        if stop <= start:
            continue
        w = np.asarray(w, dtype=float)
        W = win[start:stop]
        X = W @ T0.T
        P = p0_scale * R * np.eye(level)
        Q = q * R * np.eye(level)
        for k in range(N):
            P = P + Q
            Pw = P @ w
            S = w @ Pw + R
            K = Pw / S
            r = W[:, k] - X @ w
            X += np.outer(r, K)
            P = P - np.outer(K, Pw)
        out[start + 1 : stop + 1] = X @ w
    return out


def hpa_schedule(updates, level, n):
    """(first_sample, w, R) triples as WakeFilter applies them: default weights, R = 1 until the first HPA.

    The HPA that ran with ``index`` samples received is in force for the
    step on sample ``index - 1`` and after (see :class:`wake.hpa.schedule.HPASchedule`).
    """
    from wake.wavelets import default_weights

    sched = [(0, default_weights(level), 1.0)]
    for u in updates:
        sched.append((max(int(u.index) - 1, 0), np.asarray(u.weights), float(u.measurement_noise)))
    sched = [s for s in sched if s[0] < n]
    return sched


def operation_counts(level):
    """Multiply-accumulate operations per sample: WAKE's RTP vs the literal RTP.

    WAKE (general case, ``P`` or ``Q`` non-zero): filter bank ``J N``; ``u = P w``
    ``J^2``; ``S`` ``J``; ``d += K e`` ``J``; ``P -= u u'/S`` ``J^2``;
    output ``w'(a + d)`` ``2 J``.  With ``P = Q = 0`` (WAKE's default) the
    Kalman part is inert and only ``J N + 2 J`` remain.
    Literal: approximations at the oldest sample ``J N`` (its cheapest form,
    one tap vector per level; a full decomposition costs more), then per
    window sample ``P w`` ``J^2``, ``S`` ``J``, ``K`` ``J``, innovation ``J``,
    state ``J``, covariance ``J^2``: ``N (2 J^2 + 4 J)``; output ``J``.
    """
    J = int(level)
    N = 2**J
    return {
        "wake_general": J * N + 2 * J * J + 4 * J,
        "wake_inert": J * N + 2 * J,
        "literal": J * N + N * (2 * J * J + 4 * J) + J,
    }
