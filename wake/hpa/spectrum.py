"""Yule-Walker autoregressive power spectrum (HPA step S1)."""

from __future__ import annotations

import functools

import numpy as np

from wake._validation import check_positive

__all__ = ["autocorrelation", "levinson_durbin", "yule_walker", "ar_psd", "ar_psds", "window_order", "row_mean",
           "row_var"]

#: The smallest normal float64: the floor of the spectrum's denominator (read once; np.finfo is not free).
_TINY = float(np.finfo(float).tiny)


def row_mean(x, keepdims=False):
    """``np.mean(x, axis=-1)``, the same reduce and division without its wrappers (a few microseconds per call on
    the per-window path); each row's mean bit for bit numpy's.

    Examples
    --------
    >>> row_mean(np.array([[1.0, 2.0], [3.0, 5.0]])).tolist()
    [1.5, 4.0]
    """
    m = np.add.reduce(x, axis=-1, keepdims=keepdims)
    return np.true_divide(m, x.shape[-1], out=m) if isinstance(m, np.ndarray) else m / x.shape[-1]


def row_var(x):
    """``np.var(x, axis=-1)`` as numpy computes it (the mean, the squared deviations, their mean), without its
    wrappers; ``np.sqrt`` of it is ``np.std``'s, bit for bit.

    Examples
    --------
    >>> row_var(np.array([[1.0, 3.0], [2.0, 2.0]])).tolist()
    [1.0, 0.0]
    """
    d = x - row_mean(x, keepdims=True)
    return row_mean(np.multiply(d, d, out=d))


def window_order(n, order):
    """The AR order a window of ``n`` samples is fitted with: ``min(order, (n - 1) // 2)``.

    A warm-up window (docs/studies/design.md, "Warm-up") may be shorter than ``L``;
    the cap keeps the Yule-Walker system over-determined (``n > 2 p``, as
    WakeConfig asks of ``L``).

    Examples
    --------
    >>> from wake.hpa.spectrum import window_order
    >>> window_order(500, 17), window_order(20, 17)
    (17, 9)
    """
    return min(int(order), (int(n) - 1) // 2)


def autocorrelation(x, max_lag):
    """Biased autocorrelation ``gamma(k) = (1/L) sum x(n) x(n+k)`` for k = 0..max_lag.

    ``x`` of shape ``(n,)``, or ``(W, n)``: a stack of windows of one length, each row's lags in its row (the
    same dot products, one matmul per lag for every window).
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[-1]
    if max_lag >= n:
        raise ValueError(f"max_lag must be below the number of samples ({n}), got {max_lag}")
    rows = x.reshape(-1, 1, n)
    # Only max_lag + 1 lags are needed: p + 1 dot products, O(p L), where the full correlation
    # (np.correlate mode="full") is O(L^2): 4 s at L = 2e5 and 166 s at L = 5e5.  A (W, 1, m) @ (W, m, 1)
    # matmul runs BLAS's dot on each window: each lag is np.dot's, bit for bit.
    if rows.shape[0] == 1:   # one window: np.dot itself (a matmul's dispatch costs more than the dot)
        s = rows[0, 0]
        r = np.array([[np.dot(s[: n - k], s[k:]) for k in range(max_lag + 1)]])
    else:
        r = np.empty((rows.shape[0], max_lag + 1))
        for k in range(max_lag + 1):
            r[:, k] = (rows[:, :, : n - k] @ rows[:, 0, k:, None])[:, 0, 0]
    return (r / n).reshape(x.shape[:-1] + (max_lag + 1,))


def levinson_durbin(r, order):
    """Solve the Yule-Walker equations by the Levinson-Durbin recursion.

    Parameters
    ----------
    r : array_like
        Autocorrelation ``r[0..order]``.
    order : int
        AR order ``p``.

    Returns
    -------
    a : numpy.ndarray, shape (order + 1,)
        ``[1, a_1, ..., a_p]`` of ``A(z) = 1 + sum a_k z^-k``.
    sigma2 : float
        Prediction error variance, ``r[0] * prod(1 - k_i**2)``.
    reflection : numpy.ndarray, shape (order,)
        Reflection coefficients ``k_i``.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa.spectrum import levinson_durbin
    >>> a, s2, k = levinson_durbin([1.0, 0.5, 0.25], 2)   # AR(1) with a_1 = -0.5
    >>> np.round(a, 6).tolist(), round(s2, 6)
    ([1.0, -0.5, 0.0], 0.75)
    """
    r = np.asarray(r, dtype=float)
    if r.shape[-1] < order + 1:
        raise ValueError(f"need {order + 1} autocorrelation lags for order {order}, got {r.shape[-1]}")
    a, err, refl = _levinson_rows(r.reshape(-1, r.shape[-1]), order)
    if r.ndim == 1:
        return a[0], float(err[0]), refl[0]
    return a, err, refl


def _levinson_rows(r, order):
    """:func:`levinson_durbin` of each row of ``r`` (W, >= order + 1): ``a`` (W, order + 1), ``sigma2`` (W,),
    ``reflection`` (W, order).  The recursion runs once for every row, each row's operations those of the
    one-row recursion (the same dot, multiplies and adds): a row whose error reached 0 stops there."""
    n_rows = r.shape[0]
    if n_rows == 1:
        return _levinson_one(r[0], order)
    a = np.zeros((n_rows, order + 1))
    a[:, 0] = 1.0
    refl = np.zeros((n_rows, order))
    err = r[:, 0].copy()
    back = np.ascontiguousarray(r[:, order - 1 :: -1][:, :order])   # r[order-1], ..., r[0]: r[m-1:0:-1] a tail
    for m in range(1, order + 1):
        done = err <= 0   # a perfectly predictable (or silent) window: higher orders add nothing
        if done.any():
            if done.all():
                break
            live = np.flatnonzero(~done)
            a[live], e, refl[live] = _levinson_step(r[live], back[live], a[live], err[live], refl[live], m, order)
            err[live] = e
        else:
            a, err, refl = _levinson_step(r, back, a, err, refl, m, order)
    return a, np.where(0.0 > err, 0.0, err), refl   # max(err, 0.0)


def _levinson_step(r, back, a, err, refl, m, order):
    """Order ``m`` of the recursion on every row given (in place on ``a``, ``refl``; the new error)."""
    # (W, 1, m-1) @ (W, m-1, 1): BLAS's dot per row, as np.dot of the one-row recursion
    acc = r[:, m] + (a[:, None, 1:m] @ back[:, order - m : order - 1, None])[:, 0, 0]
    k = -acc / err
    a[:, 1 : m + 1] += k[:, None] * a[:, m - 1 :: -1][:, :m]
    refl[:, m - 1] = k
    return a, err * (1.0 - k * k), refl


def _levinson_one(r, order):
    """:func:`_levinson_rows` of one row, its operations on Python floats and np.dot (a batched step's array
    calls cost more than the arithmetic they do on one row): the same numbers (tests/hpa/test_window_stack.py)."""
    a = np.zeros(order + 1)
    a[0] = 1.0
    refl = [0.0] * order
    err = float(r[0])
    r_m = r.tolist()
    back = np.ascontiguousarray(r[order - 1 :: -1][:order])
    dot = np.dot
    for m in range(1, order + 1):
        if err <= 0:
            break
        acc = r_m[m] + float(dot(a[1:m], back[order - m : order - 1]))
        k = -acc / err
        a[1 : m + 1] += k * a[m - 1 :: -1][:m]
        refl[m - 1] = k
        err *= 1.0 - k * k
    return a[None], np.array([max(err, 0.0)]), np.array([refl])


def yule_walker(x, order):
    """AR(p) coefficients and noise variance of ``x`` (mean removed); ``x`` (W, n): of each row."""
    x = np.asarray(x, dtype=float)
    x = x - row_mean(x, keepdims=True)
    r = autocorrelation(x, order)
    a, sigma2, _ = levinson_durbin(r, order)
    return a, sigma2


def ar_psd(x, fs, order=17, n_freqs=512):
    """Yule-Walker power spectral density ``sigma^2 / |1 + sum a_k e^{-j 2 pi f k / fs}|^2``.

    Parameters
    ----------
    x : array_like, shape (L,) or (W, L)
        HPA window, or a stack of windows of one length (a spectrum per row: ``psd`` of shape (W, n_freqs),
        each row bit for bit that window's own).
    fs : float
        Sampling rate in Hz.
    order : int
        AR model order ``p`` (the paper: 17).
    n_freqs : int
        Number of frequencies on ``[0, fs/2]``.

    Returns
    -------
    freqs, psd : numpy.ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa.spectrum import ar_psd
    >>> t = np.arange(500) / 100.0
    >>> rng = np.random.default_rng(0)
    >>> x = np.sin(2 * np.pi * 8 * t) + 0.1 * rng.normal(size=t.size)
    >>> f, p = ar_psd(x, 100.0, order=8)
    >>> bool(abs(f[np.argmax(p)] - 8.0) < 0.3)
    True
    """
    x = np.asarray(x, dtype=float)
    (freqs, psd), = ar_psds([x.reshape(-1, x.shape[-1])], fs, [order], n_freqs)
    return freqs, psd.reshape(x.shape[:-1] + psd.shape[-1:])


def ar_psds(stacks, fs, orders, n_freqs=512) -> list:
    """:func:`ar_psd` of each of a list of stacks of windows, ``(W_i, n_i)`` with the AR order ``orders[i]``: one
    ``(freqs, psd)`` per stack, each row bit for bit :func:`ar_psd` of its window alone.

    The stacks may differ in length (the warm-up windows of a block beside its full ones): each stack's mean
    removal and autocorrelation are its own, the Levinson recursion and the spectrum's FFT run once for every
    row of one order (a row's numbers do not depend on the rows beside it).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> short, full = rng.normal(size=(2, 200)), rng.normal(size=(3, 500))
    >>> (_, p1), (_, p2) = ar_psds([short, full], 100.0, [8, 8])
    >>> p1.shape, p2.shape, bool(np.array_equal(p2[1], ar_psd(full[1], 100.0, 8)[1]))
    ((2, 512), (3, 512), True)
    """
    grids, lags = {}, {}
    for i, (x, order) in enumerate(zip(stacks, orders)):
        try:
            grid = _grid(fs, order, n_freqs)
        except TypeError:   # something unhashable: checked (and refused by name) without the cache
            grid = _grid.__wrapped__(fs, order, n_freqs)
        order = grids.setdefault(grid[0], grid)[0]
        if x.shape[-1] <= order:
            raise ValueError(f"the window has {x.shape[-1]} samples; an AR({order}) fit needs more than {order}")
        lags.setdefault(order, []).append((i, autocorrelation(x - row_mean(x, keepdims=True), order)))
    out = [None] * len(stacks)
    for order, parts in lags.items():
        _, nfft, freqs, pick = grids[order]
        a, sigma2, _ = levinson_durbin(parts[0][1] if len(parts) == 1 else np.concatenate([r for _, r in parts]),
                                       order)
        denom = np.abs(np.fft.rfft(a, nfft, axis=-1)) ** 2
        if pick is not None:
            denom = denom[..., pick]
        psd = sigma2[:, None] / np.maximum(denom, _TINY)
        start = 0
        for i, r in parts:
            out[i] = freqs.copy(), psd[start:start + r.shape[0]]
            start += r.shape[0]
    return out


@functools.lru_cache(maxsize=64, typed=True)   # typed: True is not 1 (check_positive refuses a bool)
def _grid(fs, order, n_freqs):
    """:func:`ar_psd`'s arguments checked, its FFT length, frequencies and (below the AR order) the bins it
    picks: the same for every window of a stream, made once."""
    fs = check_positive("fs", fs)
    order = check_positive("order", order, integer=True)
    n_freqs = check_positive("n_freqs", n_freqs, integer=True)
    if n_freqs < 2:
        raise ValueError(f"n_freqs must be >= 2, got {n_freqs}")
    # A(e^{j 2 pi f / fs}) on n_freqs points of [0, fs/2]: one real FFT of the
    # zero-padded coefficients (nfft = 2 (n_freqs - 1) puts the last bin at fs/2).
    nfft = max(2 * (n_freqs - 1), order + 1)
    nfft += nfft % 2
    freqs = np.fft.rfftfreq(nfft, 1.0 / fs)
    pick = None
    if freqs.size != n_freqs:  # n_freqs below the AR order: sample the fine grid
        pick = np.linspace(0, freqs.size - 1, n_freqs).round().astype(int)
        freqs = freqs[pick]
    freqs.flags.writeable = False
    return order, nfft, freqs, pick
