"""Figures for ``wake demo --plot`` and ``wake run --plot`` (matplotlib is optional)."""

from __future__ import annotations

import numpy as np

from wake.hpa.cutoff import FALLBACK_FLAGS
from wake.hpa.spectrum import ar_psd


#: What to install for figures, said by every refusal.
MATPLOTLIB_HINT = "plotting needs matplotlib: pip install matplotlib (or pip install \".[plot]\" in a wake source tree)"


def psd_label(unit: str) -> str:
    """The axis label of a power spectral density of a signal in ``unit``.

    Examples
    --------
    >>> from wake.eval.plotting import psd_label
    >>> psd_label("deg/s"), psd_label("g"), psd_label("")
    ('PSD ((deg/s)^2/Hz)', 'PSD (g^2/Hz)', 'PSD ((input unit)^2/Hz)')
    """
    from wake.io.writers import squared_unit

    return f"PSD ({squared_unit(unit) or '(input unit)^2'}/Hz)"


def require_matplotlib() -> None:
    """Raise ValueError naming the install when matplotlib is missing: call it before the work a figure ends."""
    import importlib.util

    if importlib.util.find_spec("matplotlib") is None:
        raise ValueError(MATPLOTLIB_HINT)


def _pyplot():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - depends on the environment
        raise ValueError(MATPLOTLIB_HINT) from None
    return plt


def _envelope(t, y, fs, seconds=0.2):
    """Min and max of ``y`` over bins of ``seconds``: a long trace readable at a glance."""
    k = max(1, int(round(seconds * fs)))
    n = (len(y) // k) * k
    if n == 0:
        return t, y, y
    yb = np.asarray(y[:n], dtype=float).reshape(-1, k)
    return t[:n].reshape(-1, k)[:, 0], np.nanmin(yb, axis=1), np.nanmax(yb, axis=1)


def _legend(ax, **kw):
    """A legend beside the axes, right of the data, so that it never covers a trace."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8, **kw)


def plot_result(path, x, result, fs, *, voluntary_truth=None, tremor_truth=None, ar_order=17, title="",
                unit="", zoom_s=4.0, channel=0, channel_name=""):
    """A four-panel figure of one channel of ``result`` (``channel``, the first by default).

    1. the whole recording: measurement and predicted voluntary motion, the
       warm-up (before the first HPA on a full window) shaded;
    2. ``zoom_s`` seconds after the warm-up, sample by sample;
    3. the tremor estimate over the whole recording as a min-max envelope
       (about 400 bins), so thousands of samples stay readable;
    4. the AR spectrum of the last HPA window with that HPA's cut-off
       ``f_d`` and its flag (``valley``, or the fallback that set it).

    ``x`` is the measurement, shape ``(n,)`` or ``(n, channels)``;
    ``channel_name`` and ``unit`` label the signal axes (for example
    ``"gyro_x"`` and ``"rad/s"``).  Legends stand beside the panels.
    """
    plt = _pyplot()
    x = np.asarray(x, dtype=float).reshape(len(x), -1)
    if not 0 <= channel < x.shape[1]:
        raise ValueError(f"channel {channel} out of range: the result has {x.shape[1]} channel(s)")
    x = x[:, channel]
    vol = np.reshape(result.voluntary, (len(x), -1))[:, channel]
    tre = np.reshape(result.tremor, (len(x), -1))[:, channel]
    t = np.arange(len(x)) / fs
    what = channel_name or "signal"
    ylab = f"{what} ({unit})" if unit else what
    warm = result.warmup / fs
    fig, ax = plt.subplots(4, 1, figsize=(13, 12))

    ax[0].plot(t, x, lw=0.5, color="0.65", label="measurement")
    if voluntary_truth is not None:
        ax[0].plot(t, voluntary_truth, lw=1.2, color="k", label="voluntary (truth)")
    ax[0].plot(t, vol, lw=0.9, color="C0", label="voluntary (predicted)")
    ax[0].axvspan(0, warm, color="C3", alpha=0.08, label=f"warm-up: before the first full HPA window ({warm:g} s)")
    ax[0].set_ylabel(ylab)
    ax[0].set_xlabel("time (s)")
    _legend(ax[0])
    ax[0].set_title(title)

    start = min(warm, max(t[-1] - zoom_s, 0.0))
    z = (t >= start) & (t <= start + zoom_s)
    ax[1].plot(t[z], x[z], lw=0.8, color="0.6", label="measurement")
    if voluntary_truth is not None:
        ax[1].plot(t[z], np.asarray(voluntary_truth)[z], lw=1.4, color="k", label="voluntary (truth)")
    ax[1].plot(t[z], vol[z], lw=1.2, color="C0", label="voluntary (predicted)")
    ax[1].plot(t[z], tre[z], lw=0.9, color="C1", label="tremor (estimate)")
    if tremor_truth is not None:
        ax[1].plot(t[z], np.asarray(tremor_truth)[z], lw=0.8, color="C1", ls=":", label="tremor + noise (truth)")
    ax[1].set_ylabel(ylab)
    ax[1].set_xlabel(f"time (s), {zoom_s:g} s after the warm-up")
    _legend(ax[1])

    bin_s = max(2.0 / fs, len(x) / fs / 400.0)  # about 400 bins whatever the length
    te, lo, hi = _envelope(t, tre, fs, bin_s)
    ax[2].fill_between(te, lo, hi, color="C1", alpha=0.6, lw=0,
                       label=f"tremor (estimate), min-max per {bin_s:.2g} s")
    if tremor_truth is not None:
        te2, lo2, hi2 = _envelope(t, np.asarray(tremor_truth), fs, bin_s)
        ax[2].plot(te2, hi2, color="k", lw=0.6, alpha=0.7, label="tremor + noise (truth), envelope")
        ax[2].plot(te2, lo2, color="k", lw=0.6, alpha=0.7)
    ax[2].axvspan(0, warm, color="C3", alpha=0.08)
    ax[2].set_ylabel(f"{what} tremor ({unit})" if unit else f"{what} tremor")
    ax[2].set_xlabel("time (s)")
    _legend(ax[2])

    updates = result.hpa[channel]
    if updates:
        last = updates[-1]
        L = int(round(result.warmup))
        seg = x[max(0, last.index - L): last.index]
        seg = seg[np.isfinite(seg)]
        freqs, psd = ar_psd(seg, fs, ar_order)
        ax[2 + 1].semilogy(freqs, psd, color="C2", label=f"AR(p={ar_order}) spectrum, last HPA window "
                                                       f"(ending at {last.index / fs:.1f} s)")
        kind = f"{last.cutoff_flag}: default used" if last.cutoff_flag in FALLBACK_FLAGS else last.cutoff_flag
        ax[3].axvline(last.cutoff, color="C3", ls="--", label=f"f_d = {last.cutoff:.2f} Hz ({kind})")
        flags = [u.cutoff_flag for u in updates]
        share = 100.0 * sum(f in FALLBACK_FLAGS for f in flags) / len(flags)
        ax[3].set_title(f"{len(flags)} HPA runs, {share:.0f} % fell back to the default cut-off", fontsize=9)
    ax[3].set_xlabel("frequency (Hz)")
    ax[3].set_ylabel(psd_label(unit))
    ax[3].set_xlim(0, min(20.0, fs / 2))
    _legend(ax[3])
    fig.tight_layout()
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)


def tremor_figure_path(path) -> str:
    """Where ``wake run --plot PATH`` draws the tremor over time: PATH's name with ``-tremor`` before the suffix.

    Examples
    --------
    >>> from wake.eval.plotting import tremor_figure_path
    >>> tremor_figure_path("out/fig.png")
    'out/fig-tremor.png'
    """
    from pathlib import Path

    p = Path(path)
    return str(p.with_name(f"{p.stem}-tremor{p.suffix or '.png'}"))


def plot_tremor(path, table, window_samples, *, unit="", channel_name="", title=""):
    """The tremor of one channel over time: one point per HPA window (``wake.hpa.characterise.tremor_table``).

    1. dominant tremor frequency, with the window's cut-off ``f_d`` beneath;
    2. amplitude: RMS and median peak-to-peak, in the input's units;
    3. the tremor stability index (TSI);
    4. the share of each window in tremor.

    Points sit at the window's end time; warm-up windows (shorter than
    ``window_samples``) are drawn hollow.  A window without a tremor peak
    has no frequency, peak-to-peak or TSI point (its reason is counted in
    the title).  Legends stand beside the panels.
    """
    plt = _pyplot()
    t = table["end_time"]
    warm = table["samples"] < int(window_samples)
    what = channel_name or "signal"
    fig, ax = plt.subplots(4, 1, figsize=(13, 10), sharex=True)

    def points(axis, values, color, label, marker="o"):
        axis.plot(t, values, color=color, lw=0.8, alpha=0.6)
        axis.plot(t[~warm], values[~warm], marker, color=color, ms=5, ls="none", label=label)
        if warm.any():
            axis.plot(t[warm], values[warm], marker, color=color, ms=5, ls="none", mfc="none",
                      label=f"{label}, warm-up window")

    points(ax[0], table["frequency"], "C1", "dominant tremor frequency")
    ax[0].plot(t, table["cutoff"], "_", color="C3", ms=12, label="f_d of the window (the tremor lies above)")
    ax[0].set_ylabel("frequency (Hz)")
    ax[0].set_ylim(bottom=0.0)
    missing = int(np.sum(table["reason"] == "no_tremor_peak"))
    ax[0].set_title(f"{title}: {missing} of {len(table)} windows without a tremor peak" if title
                    else f"{missing} of {len(table)} windows without a tremor peak", fontsize=10)
    points(ax[1], table["rms"], "C0", "RMS")
    points(ax[1], table["peak_to_peak"], "C2", "median peak-to-peak", marker="s")
    ax[1].set_ylabel(f"{what} tremor ({unit})" if unit else f"{what} tremor")
    points(ax[2], table["tsi"], "C4", "TSI: IQR of the cycle-to-cycle frequency change")
    ax[2].set_ylabel("TSI (Hz)")
    points(ax[3], table["time_share"], "C5", "share of the window in tremor")
    ax[3].set_ylim(-0.05, 1.05)
    ax[3].set_ylabel("time share")
    ax[3].set_xlabel("time (s), end of the HPA window")
    for a in ax:
        _legend(a)
    fig.tight_layout()
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
