"""Figures for ``wake demo --plot`` and ``wake run --plot`` (matplotlib is optional)."""

from __future__ import annotations

import numpy as np

from wake.hpa.spectrum import ar_psd


def _pyplot():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - depends on the environment
        raise ValueError("plotting needs matplotlib: pip install 'wake-tremor[plot]'") from None
    return plt


def plot_result(path, x, result, fs, *, voluntary_truth=None, tremor_truth=None, ar_order=17, title=""):
    """Measurement, predicted voluntary motion, tremor estimate and the PSD with the cut-off.

    Only the first channel of ``result`` is drawn.
    """
    plt = _pyplot()
    vol = np.reshape(result.voluntary, (len(x), -1))[:, 0]
    tre = np.reshape(result.tremor, (len(x), -1))[:, 0]
    t = np.arange(len(x)) / fs
    fig, ax = plt.subplots(3, 1, figsize=(10, 9))
    ax[0].plot(t, x, lw=0.6, color="0.6", label="measurement")
    if voluntary_truth is not None:
        ax[0].plot(t, voluntary_truth, lw=1.2, color="k", label="voluntary (truth)")
    ax[0].plot(t, vol, lw=1.0, color="C0", label="voluntary (predicted)")
    ax[0].axvline(result.warmup / fs, color="C3", ls=":", lw=1, label="first HPA")
    ax[0].set_ylabel("signal")
    ax[0].legend(loc="upper right", fontsize=8)
    ax[0].set_title(title)
    ax[1].plot(t, tre, lw=0.7, color="C1", label="tremor (estimate)")
    if tremor_truth is not None:
        ax[1].plot(t, tremor_truth, lw=0.7, color="k", alpha=0.6, label="tremor + noise (truth)")
    ax[1].set_xlabel("time (s)")
    ax[1].legend(loc="upper right", fontsize=8)
    freqs, psd = ar_psd(np.asarray(x, dtype=float)[: result.warmup], fs, ar_order)
    ax[2].semilogy(freqs, psd, color="C2", label=f"Yule-Walker PSD, first window (p={ar_order})")
    cut = result.mean_cutoff[0]
    ax[2].axvline(cut, color="C3", ls="--", label=f"mean cut-off f_d = {cut:.2f} Hz")
    ax[2].set_xlabel("frequency (Hz)")
    ax[2].set_xlim(0, min(20.0, fs / 2))
    ax[2].legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
