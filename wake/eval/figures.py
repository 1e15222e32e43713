"""The figures of ``wake evaluate`` (matplotlib, optional), drawn from the stored summaries.

Two figures need samples the store does not keep: the AR spectra of sample
HPA windows reload those windows' recordings, and the predicted-tremor
figure reruns every method on its one recording (a second or so), so a
rebuilt report never recomputes the cohort.
"""

from __future__ import annotations

import numpy as np

from wake.eval.compute import TRIVIAL, WAKE_PARAMS, run_methods
from wake.eval.metrics import offline_ground_truth
from wake.eval.report import method_order
from wake.eval.sources import load_source
from wake.hpa.spectrum import ar_psd, window_order

__all__ = ["write_figures"]


def _bar_chart(plt, path, names, labels, values, ylabel, title, figsize, fontsize=None):
    """Grouped bars: one group per label, one bar per method."""
    fig, ax = plt.subplots(figsize=figsize)
    idx = np.arange(len(labels))
    width = 0.8 / len(names)
    for j, n in enumerate(names):
        ax.bar(idx + j * width, values[n], width, label=n)
    ax.set_xticks(idx + 0.4 - width / 2, labels, fontsize=fontsize)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _pyplot():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    return plt


def write_figures(out_dir, parts, tremor, sources, real_name="PADS"):
    """Draw every figure the summaries allow into ``out_dir``; returns (file names, note).

    ``parts``: {"synthetic", "cohort", "real"} -> summary or None (:mod:`wake.eval.tables`);
    ``tremor``: ``(row, source, settings, backends)`` of the recording axis to draw, or None;
    ``sources``: source key -> :class:`~wake.eval.sources.Source` (to reload the spectra's windows);
    ``real_name``: what the real recordings are (:func:`wake.eval.report.recordings_label`).
    """
    plt = _pyplot()
    if plt is None:
        return [], ("matplotlib is not installed (pip install matplotlib, or pip install \".[plot]\" in a wake "
                    "source tree): no figures written.")
    syn, real, made = parts.get("synthetic"), parts.get("real"), []
    if syn:
        names = method_order(syn["rows"][0]["methods"])
        _bar_chart(plt, out_dir / "fig_nrmse_synthetic.png", names,
                   [f"{r['signal']}\n{r['snr_in']:.1f} dB" for r in syn["rows"]],
                   {n: [r["methods"][n]["nrmse"] for r in syn["rows"]] for n in names},
                   "voluntary NRMSE", "Synthetic set: NRMSE per signal", (9, 3.5))
        made.append("fig_nrmse_synthetic.png")
    if real:
        names = method_order(real["rows"][0]["methods"])
        recs = sorted({r["recording"] for r in real["rows"]})
        _bar_chart(plt, out_dir / "fig_nrmse_real.png", names,
                   ["\n".join(r.split("_")[:2]) for r in recs],
                   {n: [np.mean([r["methods"][n] for r in real["rows"] if r["recording"] == rec]) for rec in recs]
                    for n in names},
                   "tremor NRMSE (mean over axes)", f"{real_name}: NRMSE per recording", (10, 3.8), fontsize=8)
        made.append("fig_nrmse_real.png")
        if tremor is not None:
            made.append(_tremor_figure(plt, out_dir, names, *tremor))
        made.append(_spectra_figure(plt, out_dir / "fig_spectra_by_flag.png", real["flag_windows"], sources))
    if any(parts.values()):
        made.append(_error_time_figure(plt, out_dir / "fig_error_vs_time.png", parts, real_name))
    return made, ""


def tremor_candidate(rows):
    """The axis the tremor figure draws: of recording 040 (the clearest tremor of the PADS subset) when
    present, else of any, the gyroscope axis with the most offline ground-truth tremor power."""
    cand = [r for r in rows if r["recording"].startswith("040")] or rows
    return max(cand, key=lambda r: r["truth_var"] if r["channel"].startswith("gyro") else -1.0) if cand else None


def _tremor_figure(plt, out_dir, names, row, source, settings, backends):
    loaded = load_source(source)
    x, fs, c = loaded.x, loaded.fs, row["channel_index"]
    vols, _ = run_methods(x, fs, backends, settings)
    _, gt = offline_ground_truth(x[:, c], fs, row["cutoff"])
    a, b = int(6 * fs), int(9 * fs)
    b = min(b, gt.shape[0])
    a = min(a, b - int(fs))
    t = np.arange(a, b) / fs
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.plot(t, gt[a:b], "k", lw=2, label="offline ground truth")
    for n in names:
        ax.plot(t, (x[:, c] - vols[n][:, c])[a:b], lw=1, label=n)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"tremor, {row['channel']}")
    ax.set_title(f"Predicted tremor vs ground truth: {row['recording']} {row['channel']}")
    ax.legend(fontsize=8, ncol=3)
    fig.tight_layout()
    fname = f"fig_tremor_{row['recording']}_{row['channel']}.png"
    fig.savefig(out_dir / fname, dpi=120)
    plt.close(fig)
    return fname


def _error_line_style(name):
    """How a method's error curve is drawn.  The C core and the float reference agree to a few digits, so the
    reference is drawn dashed and above the C core's solid line: both stay visible where they coincide."""
    if name == "WAKE-ref":
        return dict(lw=1.4, ls=(0, (4, 3)), color="k", zorder=4)
    if name.startswith("WAKE"):
        return dict(lw=2.6, ls="-", color="C0", zorder=3)
    return dict(lw=1, ls="--" if name in TRIVIAL else "-", zorder=2)


def _error_time_figure(plt, path, parts, real_name="PADS"):
    titles = {"synthetic": "Synthetic set: voluntary error", "cohort": "Synthetic cohort: voluntary error",
              "real": f"{real_name}: tremor error (independent truth)"}
    shown = [(titles[k], part) for k, part in parts.items() if part]
    fig, axes = plt.subplots(1, len(shown), figsize=(6 * len(shown), 4), squeeze=False)
    for ax, (title, part) in zip(axes[0], shown):
        for name in method_order(part["curves"]) + [n for n in TRIVIAL if n in part["curves"]]:
            t, e = part["curves"][name]
            ax.plot(t, e, **_error_line_style(name), label=name)
        ax.axvline(WAKE_PARAMS["window_s"], color="0.6", lw=0.8)
        ax.set_xlabel("time since start (s)")
        ax.set_yscale("log")
        ax.set_ylabel("RMS error per 0.5 s / range of truth")
        ax.set_title(title)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path.name


def _spectra_figure(plt, path, samples, sources):
    flags, loaded = sorted(samples), {}
    cols = max(len(v) for v in samples.values())
    fig, axes = plt.subplots(len(flags), cols, figsize=(4 * cols, 2.6 * len(flags)), squeeze=False)
    for r, flag in enumerate(flags):
        for c in range(cols):
            ax = axes[r][c]
            if c >= len(samples[flag]):
                ax.axis("off")
                continue
            w = samples[flag][c]
            if w["source"] not in loaded:
                loaded[w["source"]] = load_source(sources[w["source"]]).x
            x = loaded[w["source"]][w["start"]:w["stop"], w["channel_index"]]
            f, p = ar_psd(x, w["fs"], window_order(x.size, WAKE_PARAMS["ar_order"]))
            ax.plot(f, 10 * np.log10(np.maximum(p, 1e-300)), lw=1)
            ax.axvline(w["cutoff"], color="r", lw=1)
            ax.set_xlim(0, 15)
            ax.set_title(f"{flag}: {w['label']}", fontsize=8)
            ax.tick_params(labelsize=7)
            if c == 0:
                ax.set_ylabel("AR PSD (dB)", fontsize=8)
            if r == len(flags) - 1:
                ax.set_xlabel("Hz (red: f_d)", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path.name

