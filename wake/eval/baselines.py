"""Baseline tremor extractors the paper compares WAKE with: BMFLC, E-BMFLC, WFLC.

The defaults are the parameters tuned once on synthetic signal 1 and used
for every signal (grid and result: docs/studies/baselines.md).

Every class has the :class:`wake.WakeFilter` contract: ``run(x)`` takes
``x`` of shape ``(n,)`` or ``(n, channels)`` (channels are independent) and
returns a :class:`BaselineResult` whose ``voluntary[k]`` is a one-step-ahead
prediction made from ``x[:k]`` alone, and ``tremor = x - voluntary``.

Common model
------------
All three fit, sample by sample, a sum of sinusoids to the measurement::

    s_hat(k) = phi(k)' w(k-1)                      (a priori prediction of x[k])
    e(k)     = x[k] - s_hat(k)
    w(k)     = update(w(k-1), phi(k), e(k))

``phi(k)`` is known ahead of time (it depends on the sample index, or for
WFLC on the accumulated phase, never on ``x[k]``), so ``s_hat(k)`` depends
on ``x[:k]`` only.  The prediction splits into a *voluntary* part and a
*tremor* part by regressor; ``voluntary = (voluntary part of s_hat)`` and
``BaselineResult.model_tremor`` is the tremor part.  ``run(x, horizons=(h, ...))``
also extrapolates the tremor part ``h`` samples ahead (``BaselineResult.ahead``): the
weights after sample ``k``, the regressors (or WFLC's phase) at ``k + h``.

* :class:`BMFLC` (Veluvolu et al. 2007, 2010): sine/cosine bank over the
  tremor band plus one constant regressor (the bias), LMS.  Voluntary part =
  the bias weight (the bank models tremor only).
* :class:`EBMFLC` (Atashzar et al. 2016): one bank over ``0..f_max``;
  weights estimated with an exponential memory (forgetting factor
  ``rho = alpha**(1/Delta)``).  Voluntary part = every bin at or below
  ``f_cut`` (sine *and* cosine of each bin, the 0 Hz bin is the bias);
  tremor part = every bin above.
* :class:`WFLC` (Riviere et al. 1998): ``M`` harmonics of one adaptive
  frequency with an accumulated phase, plus a bias.  Voluntary part = bias.

What they share (the result, the checks of their parameters, among them the
LMS step-size bound, and the regressor rows) is in :mod:`wake.eval.baseline_model`.

Speed
-----
Each ``run`` is one C call per channel (``wake/eval/native/wake_eval.c``, built into
the compiled core ``wake._rtp``, host-only) when the core is installed; the
Python loop beside it (``run(..., engine="python")``) is the reference it is
tested against (``tests/eval/test_baselines_c.py``: within 1e-12 of the
largest output; the regressor rows and the recursions of E-BMFLC's
information matrix are the same operations, only the sums and the Cholesky
solve round differently) and what runs without the core.
"""

from __future__ import annotations

import numpy as np

from wake._validation import as_signal, check_positive
from wake.eval.baseline_c import ENGINES, c_loops_for, run_bmflc, run_ebmflc, run_wflc
from wake.eval.baseline_model import (BaselineResult, band_bins, check_band, check_horizons, check_lms_steps,
                                      rows_ahead, shaped)
from wake.eval.ehwflc import EHWFLCKF

__all__ = ["BaselineResult", "BMFLC", "EBMFLC", "WFLC", "BASELINES", "baseline_methods", "ENGINES"]


class BMFLC:
    """Band-limited multiple Fourier linear combiner (Veluvolu et al. 2007/2010).

    Model: ``s_hat(k) = b + sum_r [a_r sin(2 pi f_r k/fs) + c_r cos(2 pi f_r k/fs)]``
    with ``f_r = band[0] + r*df`` up to ``band[1]``; LMS on every weight.  The
    bank models the tremor; the bias ``b`` carries the voluntary motion, so
    ``voluntary[k] = b(k-1)`` (= prediction minus bank part).

    Parameters
    ----------
    fs : float
        Sampling rate, Hz.
    band : (float, float)
        Tremor band of the bank, Hz.  Default 6-14 Hz, the band of Veluvolu
        et al. (2010) that the paper's synthetic tremor also uses.
    df : float
        Frequency spacing, Hz (default 0.1).
    mu : float
        LMS step of the bank weights (default 0.005).
    mu_bias : float
        LMS step of the bias weight (default 0.1).  ``M*mu + mu_bias < 1`` is required
        (module docstring), ``M`` the number of bank frequencies.
    """

    name = "BMFLC"

    def __init__(self, fs=100.0, band=(6.0, 14.0), df=0.1, mu=0.005, mu_bias=0.1):
        self.fs = check_positive("fs", fs)
        self.band = check_band("band", band, self.fs)
        self.df = check_positive("df", df)
        self.freqs = band_bins(*self.band, self.df)
        self.mu, self.mu_bias = check_lms_steps(mu, mu_bias, self.freqs.size)

    def __repr__(self):
        return f"BMFLC(fs={self.fs:g}, band={self.band}, df={self.df:g}, mu={self.mu:g}, mu_bias={self.mu_bias:g})"

    def _bank(self, k):
        arg = 2 * np.pi * self.freqs[None, :] * k[:, None] / self.fs
        return np.concatenate((np.sin(arg), np.cos(arg)), axis=1)  # (len(k), 2M)

    def run(self, x, horizons=(), engine="auto"):
        """The baseline over ``x`` (``(n,)`` or ``(n, channels)``); ``horizons``: also the tremor part that
        many samples ahead; ``engine``: a name in :data:`~wake.eval.baseline_c.ENGINES`."""
        arr, one_d = as_signal(x)
        n, channels = arr.shape
        hs = check_horizons(horizons)
        c_loops = c_loops_for(engine)
        phi = rows_ahead(self._bank, n, max(hs, default=0))
        if c_loops is not None:
            return run_bmflc(self, c_loops, arr, one_d, hs, phi)
        ahead = {h: np.empty((n, channels)) for h in hs}
        w = np.zeros((phi.shape[1], channels))
        b = np.zeros(channels)
        vol = np.empty((n, channels))
        bank = np.empty((n, channels))
        two_mu, two_mub = 2 * self.mu, 2 * self.mu_bias
        for i in range(n):
            p = phi[i]
            t = p @ w
            vol[i] = b
            bank[i] = t
            e = arr[i] - t - b
            w += two_mu * np.outer(p, e)
            b = b + two_mub * e
            for h in hs:
                ahead[h][i] = phi[i + h] @ w
        s = shaped(one_d)
        return BaselineResult(s(vol), s(arr - vol), s(bank), self.name, ahead={h: s(a) for h, a in ahead.items()})



class EBMFLC:
    """Enhanced BMFLC (Atashzar et al. 2016): full-band bank with a memory window.

    Model: ``s_hat(k) = phi(k)' w`` over bins ``f_i = i*df``, ``i = 0..N``
    (``N df <= f_max``); the 0 Hz bin contributes the constant (its sine is
    identically zero and is left out).  The weights follow the exponentially
    weighted least-squares criterion of the paper's "memory window":

        w(k) = argmin sum_{i<=k} rho^(k-i) (x[i] - phi(i)' w)^2 + delta |w|^2,
        rho = alpha ** (1 / Delta),  Delta = memory_s * fs,

    i.e. a sample ``Delta`` samples old weighs ``alpha`` of the newest.  It
    is solved exactly every sample from the running information matrix
    ``G(k) = rho G(k-1) + phi phi' + (1 - rho) delta I`` (``G(0) = delta I``),
    which equals ``delta I + sum rho^(k-i) phi phi'`` and therefore keeps a
    constant ridge ``delta``.  The ridge keeps the nearly collinear
    neighbouring bins of a short memory well posed;
    ``delta = ridge * 0.5/(1 - rho)``, relative to the steady-state
    energy of one regressor, so it shrinks a well-excited sinusoid by about
    ``ridge`` only.

    Why not the leaky LMS ``w <- rho w + 2 mu phi e``: its fixed point for
    a sinusoid on a bin is ``mu / (mu + 1 - rho)`` of the true amplitude
    (0.40 for mu = 0.01, alpha = 0.05, a 2 s memory at 100 Hz), a steady-state
    amplitude bias that the forgetting factor hides.  The least-squares
    memory has none (``tests/test_baselines.py`` measures it).

    ``voluntary[k]`` = the bins at or below ``f_cut`` (sine and cosine of each,
    and the constant) of ``phi(k)' w(k-1)``; ``model_tremor`` = bins above.

    Parameters
    ----------
    fs : float
    f_max : float
        Top of the bank, Hz (default 14).
    df : float
        Bin spacing, Hz (default 0.5).
    f_cut : float
        Voluntary/tremor split, Hz (default 1.5; bins ``<= f_cut`` are voluntary).
    memory_s : float
        ``Tp``: memory window in seconds (``Delta = memory_s * fs`` samples; default 2).
    alpha : float
        Weight of a sample ``Delta`` old, ``0 < alpha < 1`` (default 0.01).
    ridge : float
        Relative ridge (>= 0; default 1e-3).
    """

    name = "E-BMFLC"

    def __init__(self, fs=100.0, f_max=14.0, df=0.5, f_cut=1.5, memory_s=2.0, alpha=0.01, ridge=1e-3):
        self.fs = check_positive("fs", fs)
        self.f_max = check_positive("f_max", f_max)
        if self.f_max >= self.fs / 2:
            raise ValueError(f"f_max must be below fs/2 = {self.fs / 2:g} Hz, got {f_max!r}")
        self.df = check_positive("df", df)
        if self.df > self.f_max:
            raise ValueError(f"df must be at most f_max = {self.f_max:g} Hz, got {df!r}")
        self.f_cut = check_positive("f_cut", f_cut)
        if self.f_cut >= self.f_max:
            raise ValueError(f"f_cut must lie in (0, f_max = {self.f_max:g}) Hz, got {f_cut!r}")
        self.memory_s = check_positive("memory_s", memory_s)
        alpha = check_positive("alpha", alpha)
        if not alpha < 1:
            raise ValueError(f"alpha must lie in (0, 1) (the weight left after the memory window), got {alpha!r}")
        self.alpha = alpha
        self.ridge = check_positive("ridge", ridge, allow_zero=True)
        self.delta_samples = self.memory_s * self.fs
        if self.delta_samples < 1:
            raise ValueError(f"memory_s * fs must be at least one sample, got {self.delta_samples:g}")
        self.rho = self.alpha ** (1.0 / self.delta_samples)
        self.freqs = band_bins(0.0, self.f_max, self.df)[1:]  # bins above 0 Hz; 0 Hz is the constant

    def __repr__(self):
        return (f"EBMFLC(fs={self.fs:g}, f_max={self.f_max:g}, df={self.df:g}, f_cut={self.f_cut:g}, "
                f"memory_s={self.memory_s:g}, alpha={self.alpha:g}, ridge={self.ridge:g})")

    @property
    def n_regressors(self):
        return 1 + 2 * self.freqs.size

    def _split(self):
        """Number of regressors of the voluntary part (they come first)."""
        return 1 + 2 * int(np.count_nonzero(self.freqs <= self.f_cut + 1e-9))

    def _regressors(self, k):
        """At samples ``k``: columns constant, then (sin, cos) of the voluntary bins, then of the tremor bins."""
        n, k = len(k), k[:, None]
        low = self.freqs <= self.f_cut + 1e-9
        cols = [np.ones((n, 1))]
        for sel in (low, ~low):
            arg = 2 * np.pi * self.freqs[sel][None, :] * k / self.fs
            cols += [np.sin(arg), np.cos(arg)]
        return np.concatenate(cols, axis=1)

    def run(self, x, horizons=(), engine="auto"):
        """The baseline over ``x`` (``(n,)`` or ``(n, channels)``); ``horizons``: also the tremor part that
        many samples ahead; ``engine``: a name in :data:`~wake.eval.baseline_c.ENGINES`."""
        arr, one_d = as_signal(x)
        n, channels = arr.shape
        hs = check_horizons(horizons)
        c_loops = c_loops_for(engine)
        phi = rows_ahead(self._regressors, n, max(hs, default=0))
        p = phi.shape[1]
        nv = self._split()
        rho = self.rho
        delta = max(self.ridge * 0.5 / (1 - rho), 1e-12)
        leak = (1 - rho) * delta
        if c_loops is not None:
            return run_ebmflc(self, c_loops, arr, one_d, hs, phi, nv, rho, delta, leak)
        from scipy.linalg import cho_factor, cho_solve

        ahead = {h: np.empty((n, channels)) for h in hs}
        G = delta * np.eye(p)
        r = np.zeros((p, channels))
        w = np.zeros((p, channels))
        vol = np.empty((n, channels))
        pred = np.empty((n, channels))
        for i in range(n):
            f = phi[i]
            pred[i] = f @ w
            vol[i] = f[:nv] @ w[:nv]
            G *= rho
            G += f[:, None] * f[None, :]
            G.flat[:: p + 1] += leak
            r *= rho
            r += f[:, None] * arr[i][None, :]
            w = cho_solve(cho_factor(G, check_finite=False), r, check_finite=False)
            for h in hs:
                ahead[h][i] = phi[i + h][nv:] @ w[nv:]
        s = shaped(one_d)
        return BaselineResult(s(vol), s(arr - vol), s(pred - vol), self.name, ahead={h: s(a) for h, a in ahead.items()})



class WFLC:
    """Weighted-frequency Fourier linear combiner (Riviere, Rader & Thakor 1998).

    Model: ``s_hat(k) = b + sum_{r=1..M} [a_r sin(r theta_k) + c_r cos(r theta_k)]``
    with an *accumulated* phase ``theta_{k+1} = theta_k + 2 pi f_k / fs``
    (not ``2 pi f_k k / fs``, which would jump whenever ``f_k`` changes).
    Updates after ``e = x[k] - s_hat(k)``::

        f:  omega <- omega + 2 mu0 e sum_r r (a_r cos(r theta) - c_r sin(r theta)) / p
        w:  a_r, c_r <- + 2 mu e (sin, cos)(r theta);   b <- b + 2 mu_bias e

    ``omega = 2 pi f / fs`` (rad/sample).  Riviere's frequency step is not
    scale-free (it grows with the squared amplitude); here it is divided by
    ``p``, a running mean square of ``x - b`` (time constant ``1/beta``
    samples), so ``mu0`` means the same for a gyroscope in rad/s and an
    accelerometer in g.  ``f`` is clipped to ``f_range``.
    ``voluntary[k] = b(k-1)``; ``frequency[k]`` is the ``f`` used at ``k``.

    Parameters
    ----------
    fs : float
    n_harmonics : int
        ``M`` (default 1).
    mu : float
        Amplitude-weight step (default 0.3); ``M*mu + mu_bias < 1`` required.
    mu0 : float
        Frequency step (normalised, see above; default 1e-4).
    mu_bias : float
        Bias step (default 0.1).
    f0 : float
        Initial frequency, Hz.
    f_range : (float, float)
        Limits of the adapted frequency, Hz.
    beta : float
        Smoothing of the power normaliser, ``0 < beta <= 1``.
    """

    name = "WFLC"

    def __init__(self, fs=100.0, n_harmonics=1, mu=0.3, mu0=1e-4, mu_bias=0.1, f0=8.0,
                 f_range=(3.0, 15.0), beta=0.01):
        self.fs = check_positive("fs", fs)
        self.n_harmonics = check_positive("n_harmonics", n_harmonics, integer=True)
        self.mu, self.mu_bias = check_lms_steps(mu, mu_bias, self.n_harmonics)
        self.mu0 = check_positive("mu0", mu0, allow_zero=True)
        self.f_range = check_band("f_range", f_range, self.fs)
        self.f0 = check_positive("f0", f0)
        if not self.f_range[0] <= self.f0 <= self.f_range[1]:
            raise ValueError(f"f0 must lie in f_range {self.f_range}, got {f0!r}")
        if self.n_harmonics * self.f_range[1] >= self.fs / 2:
            raise ValueError(
                f"the top harmonic n_harmonics * f_range[1] = {self.n_harmonics * self.f_range[1]:g} Hz "
                f"must stay below fs/2 = {self.fs / 2:g} Hz"
            )
        self.beta = check_positive("beta", beta)
        if self.beta > 1:
            raise ValueError(f"beta must lie in (0, 1], got {beta!r}")

    def __repr__(self):
        return (f"WFLC(fs={self.fs:g}, n_harmonics={self.n_harmonics}, mu={self.mu:g}, mu0={self.mu0:g}, "
                f"mu_bias={self.mu_bias:g}, f0={self.f0:g}, f_range={self.f_range}, beta={self.beta:g})")

    def run(self, x, horizons=(), engine="auto"):
        """The baseline over ``x`` (``(n,)`` or ``(n, channels)``); ``horizons``: also the tremor part that
        many samples ahead; ``engine``: a name in :data:`~wake.eval.baseline_c.ENGINES`."""
        arr, one_d = as_signal(x)
        n, channels = arr.shape
        hs = check_horizons(horizons)
        c_loops = c_loops_for(engine)
        if c_loops is not None:
            return run_wflc(self, c_loops, arr, one_d, hs)
        ahead = {h: np.empty((n, channels)) for h in hs}
        M = self.n_harmonics
        r = np.arange(1, M + 1)[:, None]  # (M, 1)
        lo, hi = (2 * np.pi * f / self.fs for f in self.f_range)
        omega = np.full(channels, 2 * np.pi * self.f0 / self.fs)
        theta = np.zeros(channels)
        a = np.zeros((M, channels))
        c = np.zeros((M, channels))
        b = np.zeros(channels)
        power = np.zeros(channels)
        vol = np.empty((n, channels))
        bank = np.empty((n, channels))
        freq = np.empty((n, channels))
        two_mu, two_mub, two_mu0, beta = 2 * self.mu, 2 * self.mu_bias, 2 * self.mu0, self.beta
        for i in range(n):
            sn = np.sin(r * theta)
            cs = np.cos(r * theta)
            t = (a * sn + c * cs).sum(axis=0)
            vol[i] = b
            bank[i] = t
            freq[i] = omega * self.fs / (2 * np.pi)
            e = arr[i] - t - b
            dev = arr[i] - b
            power = dev * dev if i == 0 else power + beta * (dev * dev - power)
            z = (r * (a * cs - c * sn)).sum(axis=0)
            omega = np.clip(omega + two_mu0 * e * z / (power + 1e-300), lo, hi)
            a += two_mu * sn * e
            c += two_mu * cs * e
            b = b + two_mub * e
            theta = np.mod(theta + omega, 2 * np.pi)
            for h in hs:                          # the phase advanced by the frequency now in use
                ph = theta + (h - 1) * omega
                ahead[h][i] = (a * np.sin(r * ph) + c * np.cos(r * ph)).sum(axis=0)
        s = shaped(one_d)
        return BaselineResult(s(vol), s(arr - vol), s(bank), self.name, frequency=s(freq),
                              ahead={h: s(a) for h, a in ahead.items()})



#: The baselines by display name, in the order of the report (eHWFLC-KF: :mod:`wake.eval.ehwflc`, issue 46).
BASELINES = {"BMFLC": BMFLC, "E-BMFLC": EBMFLC, "WFLC": WFLC, "eHWFLC-KF": EHWFLCKF}


def baseline_methods(fs):
    """The baselines with the parameters tuned once on synthetic signal 1 (docs/studies/baselines.md)."""
    return {name: cls(fs=fs) for name, cls in BASELINES.items()}
