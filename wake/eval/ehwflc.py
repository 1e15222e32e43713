"""eHWFLC-KF: a high-order weighted-frequency Fourier linear combiner whose amplitudes a Kalman filter tracks.

The peer with the best published suppression numbers (Zhou et al., IEEE TNSRE 30:2856, 2022: 89.3 % tremor
power reduction on a bench-top suppression device over 18 Parkinson's recordings), the enhanced form of the
HWFLC-KF of Zhou, Jenkins, Naish and Trejos (IEEE EMBC 2017).  Its structure, as those papers describe it:

* a **high-order** tremor model: the fundamental and its harmonics (Parkinsonian tremor's second and third
  harmonics carry much of its power), ``M`` of them on one adapted fundamental;
* the **fundamental frequency** adapted as in WFLC (Riviere et al. 1998), on the accumulated phase;
* the **amplitudes** (a sine and a cosine weight per harmonic) estimated by a **Kalman filter** with a
  random-walk state instead of WFLC's LMS step, so that their adaptation rate follows their uncertainty;
* a bias (the voluntary motion of this family of methods) in the same state.

Per sample (state ``w = [b, a_1, c_1, ..., a_M, c_M]``, ``phi = [1, sin theta, cos theta, ..., sin M theta,
cos M theta]``)::

    s_hat = phi' w;   e = x[k] - s_hat                                  a priori, from x[:k]
    P <- P + Q;   K = P phi / (phi' P phi + 1);   w <- w + K e;   P <- P - K phi' P
    omega <- clip(omega + 2 mu0 e sum_r r (a_r cos r theta - c_r sin r theta) / p, f_range)
    theta <- theta + omega

``Q = diag(q_bias, q_tremor, ..., q_tremor)`` relative to a unit measurement variance, so the gains and the
estimate are the same for a signal in any unit; ``p`` is WFLC's running mean square of ``x - b`` that makes
``mu0`` scale-free (:class:`wake.eval.baselines.WFLC`).  ``voluntary[k] = b`` before sample ``k``;
``run(x, horizons)`` extrapolates the harmonics at the phase advanced by the frequency in use.

What here is ours, not the papers' (whose full parameter tables were not available to this implementation):
the scale-free noise parametrisation, the defaults below (tuned once on synthetic signal 1 as the other
baselines were; docs/studies/baselines.md, "eHWFLC-KF"), and the frequency range.  The per-sample loop runs in C
(``wake/eval/native/wake_eval.c``, :func:`wake.eval.baseline_c.run_ehwflc`) when the compiled core is built; the numpy loop
here, vectorised over channels, is the reference it matches within 1e-12 (tests/eval/test_baselines_c.py).

Examples
--------
>>> import numpy as np
>>> from wake.eval.ehwflc import EHWFLCKF
>>> t = np.arange(2000) / 100.0
>>> x = 0.5 * t / 20 + 0.2 * np.sin(2 * np.pi * 6 * t)
>>> res = EHWFLCKF(fs=100.0).run(x, horizons=(5,))
>>> bool(np.sqrt(np.mean((res.tremor - 0.2 * np.sin(2 * np.pi * 6 * t))[1000:] ** 2)) < 0.05)
True
"""

from __future__ import annotations

import numpy as np

from wake._validation import as_signal, check_positive
from wake.eval.baseline_c import ENGINES, c_loops_for, run_ehwflc
from wake.eval.baseline_model import BaselineResult, check_band, check_horizons, shaped

__all__ = ["EHWFLCKF"]


class EHWFLCKF:
    """eHWFLC-KF (module docstring: the model, the sources and what is ours).

    Parameters
    ----------
    fs : float
        Sampling rate, Hz.
    n_harmonics : int, optional
        ``M``, the fundamental and ``M - 1`` harmonics; by default 3, or as many as stay below ``fs / 2``
        (2 at 50 Hz).
    q_tremor : float
        Random-walk variance of each harmonic weight per sample, relative to the measurement's (default 1e-3).
    q_bias : float
        The same for the bias (default 0.1).
    mu0 : float
        Frequency step (WFLC's, normalised; default 1e-4).
    f0 : float
        Initial fundamental, Hz (default 6).
    f_range : (float, float)
        Limits of the fundamental, Hz (default 3-12); ``M * f_range[1]`` must stay below ``fs / 2``.
    beta : float
        Smoothing of the power normaliser, ``0 < beta <= 1`` (default 0.01).
    p0 : float
        Initial state variance, relative (default 1).
    """

    name = "eHWFLC-KF"

    def __init__(self, fs=100.0, n_harmonics=None, q_tremor=1e-3, q_bias=0.1, mu0=1e-4, f0=6.0, f_range=(3.0, 12.0),
                 beta=0.01, p0=1.0):
        self.fs = check_positive("fs", fs)
        self.f_range = check_band("f_range", f_range, self.fs)
        if n_harmonics is None:
            n_harmonics = max(1, min(3, int(np.ceil(self.fs / 2 / self.f_range[1])) - 1))
        self.n_harmonics = check_positive("n_harmonics", n_harmonics, integer=True)
        self.q_tremor = check_positive("q_tremor", q_tremor)
        self.q_bias = check_positive("q_bias", q_bias)
        self.mu0 = check_positive("mu0", mu0, allow_zero=True)
        self.f0 = check_positive("f0", f0)
        if not self.f_range[0] <= self.f0 <= self.f_range[1]:
            raise ValueError(f"f0 must lie in f_range {self.f_range}, got {f0!r}")
        if self.n_harmonics * self.f_range[1] >= self.fs / 2:
            raise ValueError(f"the top harmonic n_harmonics * f_range[1] = {self.n_harmonics * self.f_range[1]:g} Hz "
                             f"must stay below fs/2 = {self.fs / 2:g} Hz: lower n_harmonics or f_range[1]")
        self.beta = check_positive("beta", beta)
        if self.beta > 1:
            raise ValueError(f"beta must lie in (0, 1], got {beta!r}")
        self.p0 = check_positive("p0", p0)

    def __repr__(self):
        return (f"EHWFLCKF(fs={self.fs:g}, n_harmonics={self.n_harmonics}, q_tremor={self.q_tremor:g}, "
                f"q_bias={self.q_bias:g}, mu0={self.mu0:g}, f0={self.f0:g}, f_range={self.f_range}, "
                f"beta={self.beta:g}, p0={self.p0:g})")

    #: The engines :meth:`run` takes (:data:`~wake.eval.baseline_c.ENGINES`): the C loop or the numpy reference.
    engines = ENGINES

    def run(self, x, horizons=(), engine="auto"):
        """``x`` of shape (n,) or (n, channels) -> :class:`~wake.eval.baselines.BaselineResult`; ``horizons``:
        also the tremor part that many samples ahead; ``engine``: a name in :attr:`engines`."""
        arr, one_d = as_signal(x)
        n, channels = arr.shape
        hs = check_horizons(horizons)
        c_loops = c_loops_for(engine)
        if c_loops is not None:
            return run_ehwflc(self, c_loops, arr, one_d, hs)
        ahead = {h: np.empty((n, channels)) for h in hs}
        M = self.n_harmonics
        dim = 1 + 2 * M
        r = np.arange(1, M + 1)[None, :]                     # (1, M)
        lo, hi = (2 * np.pi * f / self.fs for f in self.f_range)
        omega = np.full(channels, 2 * np.pi * self.f0 / self.fs)
        theta = np.zeros(channels)
        w = np.zeros((channels, dim))
        P = np.broadcast_to(self.p0 * np.eye(dim), (channels, dim, dim)).copy()
        Q = np.diag(np.r_[self.q_bias, np.full(2 * M, self.q_tremor)])
        power = np.zeros(channels)
        vol = np.empty((n, channels))
        bank = np.empty((n, channels))
        freq = np.empty((n, channels))
        phi = np.empty((channels, dim))
        phi[:, 0] = 1.0
        two_mu0, beta = 2 * self.mu0, self.beta
        for i in range(n):
            sn = np.sin(r * theta[:, None])                  # (channels, M)
            cs = np.cos(r * theta[:, None])
            phi[:, 1::2] = sn
            phi[:, 2::2] = cs
            b = w[:, 0]
            t = (w[:, 1::2] * sn + w[:, 2::2] * cs).sum(axis=1)
            vol[i] = b
            bank[i] = t
            freq[i] = omega * self.fs / (2 * np.pi)
            e = arr[i] - t - b
            dev = arr[i] - b
            power = dev * dev if i == 0 else power + beta * (dev * dev - power)
            z = (r * (w[:, 1::2] * cs - w[:, 2::2] * sn)).sum(axis=1)
            P += Q
            Pphi = np.einsum("cij,cj->ci", P, phi)
            S = np.einsum("ci,ci->c", phi, Pphi) + 1.0
            K = Pphi / S[:, None]
            w += K * e[:, None]
            P -= K[:, :, None] * Pphi[:, None, :]
            omega = np.clip(omega + two_mu0 * e * z / (power + 1e-300), lo, hi)
            theta = np.mod(theta + omega, 2 * np.pi)
            for h in hs:                                     # the phase advanced by the frequency now in use
                ph = (theta + (h - 1) * omega)[:, None] * r
                ahead[h][i] = (w[:, 1::2] * np.sin(ph) + w[:, 2::2] * np.cos(ph)).sum(axis=1)
        s = shaped(one_d)
        return BaselineResult(s(vol), s(arr - vol), s(bank), self.name, frequency=s(freq),
                              ahead={h: s(a) for h, a in ahead.items()})
