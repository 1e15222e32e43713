"""``wake evaluate``: the paper's evaluation recomputed with our implementations.

What :func:`cli` writes into ``OUT_DIR`` (docs/evaluation.md explains the
protocol):

* ``report.md``: Markdown tables.
  - Synthetic set (the paper's Table "results2"): PRF, SNR_out and NRMSE of
    the voluntary estimate for BMFLC, E-BMFLC, WFLC and WAKE (every
    available backend), beside the paper's numbers; the first
    ``window_s * fs`` samples (WAKE's warm-up) are left out for every method.
  - Real recordings (PADS, as the paper's Smartphone table): NRMSE of the
    predicted tremor per recording and axis against the offline ground truth
    (sharp high-pass at the mean ``f_d`` of WAKE's HPA runs on that axis;
    the same truth for every method), and the mean per method.
  - The delay (samples) maximising the cross-correlation between estimated
    and true tremor, per method.
  - Ablation: the paper's literal RTP (:mod:`wake.rtp.literal`) against
    WAKE's per-sample RTP: NRMSE, time and operations per sample.
  - Time since start: NRMSE per slice of time since switch-on and over the
    whole recording from 0.5 s (:mod:`wake.eval.warmup`), for WAKE, every
    baseline and the zero estimate; PADS against a truth independent of WAKE.
  - The cut-off's flags: their shares over the HPA windows, and (figure) the
    AR spectrum of sample windows of each flag with the chosen ``f_d``.
* ``results.json``: every number of the report.
* ``fig_tremor_<recording>.png``, ``fig_nrmse_synthetic.png``,
  ``fig_nrmse_real.png``, ``fig_error_vs_time.png`` (error against time since
  start) and ``fig_spectra_by_flag.png`` when matplotlib is installed.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from wake.eval.baselines import BMFLC, EBMFLC, WFLC
from wake.eval.datasets import default_pads_dir, load_pads_folder
from wake.filter import WakeFilter
from wake.rtp import c_backend_available
from wake.rtp.literal import hpa_schedule, literal_rtp_predict, literal_rtp_run, operation_counts
from wake.eval.metrics import best_lag, nrmse, offline_ground_truth, prf, snr_out
from wake.eval.synthetic import PAPER_BMFLC, PAPER_EBMFLC, PAPER_SNR_DB, PAPER_WAKE, paper_dataset
from wake.eval.warmup import SLICES, error_curve, independent_ground_truth, mean_curve, mean_slices, slice_nrmse
from wake.hpa.spectrum import ar_psd, window_order

__all__ = ["cli", "c_backend_available", "baseline_methods", "evaluate_synthetic", "evaluate_real",
           "ablation_literal_rtp"]

#: WAKE as the paper configures it (the WakeFilter defaults; not tuned here).
WAKE_PARAMS = dict(wavelet="sym3", level=5, window_s=5.0, ar_order=17)
PAPER_COLUMNS = {"BMFLC": PAPER_BMFLC, "E-BMFLC": PAPER_EBMFLC, "WAKE": PAPER_WAKE}
METRICS = ("nrmse", "prf", "snr_out")
METRIC_TITLES = {"nrmse": "NRMSE (lower is better)", "prf": "PRF % (lower is better)",
                 "snr_out": "SNR_out dB (higher is better)"}


#: Two trivial estimates: no tremor at all (voluntary = x), and a prediction of 0
#: for the next sample (voluntary = 0, so the tremor estimate is x itself).
ZERO = "zero tremor (voluntary = x)"
ZERO_PREDICTION = "zero prediction (voluntary = 0)"
TRIVIAL = (ZERO, ZERO_PREDICTION)


def baseline_methods(fs):
    """The baselines with the parameters tuned once on synthetic signal 1 (docs/baselines.md)."""
    return {"BMFLC": BMFLC(fs=fs), "E-BMFLC": EBMFLC(fs=fs), "WFLC": WFLC(fs=fs)}


def _wake_name(backend):
    return "WAKE" if backend == "c" else "WAKE-ref"


def _run_all(x, fs, backends):
    """Every method on x (n, channels): {name: voluntary (n, channels)}, plus the WAKE results."""
    out = {}
    for name, m in baseline_methods(fs).items():
        out[name] = m.run(x).voluntary
    wake = {}
    for b in backends:
        res = WakeFilter(fs=fs, backend=b, **WAKE_PARAMS).run(x)
        out[_wake_name(b)] = res.voluntary
        wake[b] = res
    return out, wake


# --------------------------------------------------------------------------- synthetic
def evaluate_synthetic(backends, quick=False):
    data = paper_dataset()
    if quick:
        data = data[:2]
    rows = []
    lags = {}
    slices, curves = {}, {}
    for i, s in enumerate(data):
        start = int(round(WAKE_PARAMS["window_s"] * s.fs))
        vols, _ = _run_all(s.measurement, s.fs, backends)
        for name, v in {**vols, ZERO: s.measurement, ZERO_PREDICTION: np.zeros_like(s.measurement)}.items():
            slices.setdefault(name, []).append(slice_nrmse(s.voluntary, v, s.fs))
            curves.setdefault(name, []).append(error_curve(s.voluntary, v, s.fs))
        row = {"signal": i + 1, "snr_in": s.snr_db, "methods": {}}
        for name, v in vols.items():
            row["methods"][name] = {
                "nrmse": nrmse(s.voluntary, v, start),
                "prf": prf(s.voluntary, v, start),
                "snr_out": snr_out(s.voluntary, v, start),
            }
            # x - v_hat against x - s_v would align trivially (both hold x's own
            # high-frequency content), so the synthetic delay is the voluntary one.
            lags.setdefault(name, []).append(best_lag(s.voluntary[start:], v[start:]))
        rows.append(row)
    return {"rows": rows, "lags": lags, "slices": {n: mean_slices(v) for n, v in slices.items()},
            "curves": {n: mean_curve(v) for n, v in curves.items()}}


# --------------------------------------------------------------------------- real
def evaluate_real(recordings, backends):
    rows = []
    lags = {}
    vlags = {}
    traces = {}
    slices, curves = {}, {}
    windows = {}   # cut-off flag -> HPA windows (for the spectra figure)
    flags = {}
    for rec in recordings:
        x = rec.samples
        start = int(round(WAKE_PARAMS["window_s"] * rec.fs))
        if x.shape[0] <= start + 2 * rec.fs:
            raise ValueError(f"{rec.name}: {x.shape[0]} samples; need more than the {start}-sample warm-up + 2 s")
        vols, wake = _run_all(x, rec.fs, backends)
        ref = wake.get("reference") or next(iter(wake.values()))
        cutoffs = ref.mean_cutoff
        for c, axis in enumerate(rec.channels):
            _, independent, _ = independent_ground_truth(x[:, c], rec.fs)
            for name, v in {**vols, ZERO: x, ZERO_PREDICTION: np.zeros_like(x)}.items():
                slices.setdefault(name, []).append(slice_nrmse(independent, x[:, c] - v[:, c], rec.fs))
                curves.setdefault(name, []).append(error_curve(independent, x[:, c] - v[:, c], rec.fs))
            for u in ref.hpa[c]:
                flags[u.cutoff_flag] = flags.get(u.cutoff_flag, 0) + 1
                lo = max(0, u.index - int(round(WAKE_PARAMS["window_s"] * rec.fs)))
                windows.setdefault(u.cutoff_flag, []).append(
                    {"label": f"{rec.name} {axis} @ {u.index / rec.fs:g} s", "x": x[lo:u.index, c],
                     "fs": rec.fs, "cutoff": u.cutoff})
            _, gt = offline_ground_truth(x[:, c], rec.fs, float(cutoffs[c]))
            row = {"recording": rec.name, "axis": axis, "cutoff": float(cutoffs[c]), "methods": {}}
            for name, v in vols.items():
                est = x[:, c] - v[:, c]
                row["methods"][name] = nrmse(gt, est, start)
                lags.setdefault(name, []).append(best_lag(gt[start:], est[start:]))
                vlags.setdefault(name, []).append(best_lag((x[:, c] - gt)[start:], v[start:, c]))
            rows.append(row)
            traces[(rec.name, axis)] = (gt, {name: x[:, c] - v[:, c] for name, v in vols.items()})
    # three windows per flag, spread over the run (deterministic: every k-th)
    samples = {f: [w[int(k)] for k in np.linspace(0, len(w) - 1, min(3, len(w)))] for f, w in windows.items()}
    return {"rows": rows, "lags": lags, "voluntary_lags": vlags,
            "slices": {n: mean_slices(v) for n, v in slices.items()},
            "curves": {n: mean_curve(v) for n, v in curves.items()},
            "flags": flags, "flag_windows": samples}, traces


# --------------------------------------------------------------------------- ablation
def ablation_literal_rtp(quick=False, p0_scales=(0.01, 1.0, 100.0)):
    """Literal RTP (Alg. 3) vs WAKE's RTP on the synthetic set, same HPA outputs."""
    data = paper_dataset()[: 2 if quick else 10]
    level = WAKE_PARAMS["level"]
    acc = {"WAKE RTP": []}
    for p in p0_scales:
        acc[f"literal, P0={p:g}R"] = []
    for s in data:
        start = int(round(WAKE_PARAMS["window_s"] * s.fs))
        res = WakeFilter(fs=s.fs, backend="reference", **WAKE_PARAMS).run(s.measurement)
        acc["WAKE RTP"].append(nrmse(s.voluntary, res.voluntary, start))
        sched = hpa_schedule(res.hpa[0], level, s.measurement.shape[0])
        for p in p0_scales:
            lit = literal_rtp_run(s.measurement, sched, level, p0_scale=p, wavelet=WAKE_PARAMS["wavelet"])
            acc[f"literal, P0={p:g}R"].append(nrmse(s.voluntary, lit, start))
    timing = _time_per_sample(data[0], 100 if quick else 400)
    return {"nrmse": acc, "timing_us": timing, "ops": operation_counts(level), "level": level}


def _time_per_sample(s, count):
    """Wall time per sample (microseconds) of both RTPs, one sample at a time, same weights."""
    from wake.rtp.reference import ReferenceRTP
    from wake.wavelets import filter_bank_taps

    level, wavelet = WAKE_PARAMS["level"], WAKE_PARAMS["wavelet"]
    x = s.measurement
    res = WakeFilter(fs=s.fs, backend="reference", **WAKE_PARAMS).run(x[:600])
    u = res.hpa[0][0]
    N = 2**level
    seg = x[500 : 500 + count]
    rtp = ReferenceRTP(filter_bank_taps(wavelet, level), u.weights, u.measurement_noise, 0.0, 0.0)
    rtp_kf = ReferenceRTP(filter_bank_taps(wavelet, level), u.weights, u.measurement_noise, 0.0,
                          u.measurement_noise)
    out = {}
    for name, r in (("WAKE RTP (P0=0, default)", rtp), ("WAKE RTP (P0=R, Kalman active)", rtp_kf)):
        for v in x[500 - N : 500]:
            r.step(v)
        t0 = time.perf_counter()
        for v in seg:
            r.step(v)
        out[name] = (time.perf_counter() - t0) / count * 1e6
    t0 = time.perf_counter()
    for i in range(500, 500 + count):
        literal_rtp_predict(x[i - N + 1 : i + 1], u.weights, u.measurement_noise, u.measurement_noise,
                            wavelet=wavelet)
    out["literal RTP (direct, P0=R)"] = (time.perf_counter() - t0) / count * 1e6
    return out


# --------------------------------------------------------------------------- report
def _fmt(v, digits=4):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "n/a"
    return f"{v:.{digits}f}"


def _table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def _method_order(names):
    order = ["BMFLC", "E-BMFLC", "WFLC", "WAKE-ref", "WAKE"]
    return [n for n in order if n in names]


def _synthetic_section(syn):
    rows = syn["rows"]
    names = _method_order(rows[0]["methods"])
    parts = ["## Synthetic set (paper Table \"results2\")", "",
             "Voluntary estimate against the true voluntary motion `s_v`; samples before "
             f"{WAKE_PARAMS['window_s']:g} s (WAKE's warm-up) are left out for every method. "
             "*(paper)* columns are the paper's numbers for the same SNR (its signals are not published; "
             "ours are regenerated by `wake.eval.synthetic.paper_dataset()`).", ""]
    digits = {"nrmse": 4, "prf": 2, "snr_out": 2}
    last_wake = [n for n in names if n.startswith("WAKE")][-1]
    cols = []  # (header, getter)
    for n in names:
        cols.append((n, lambda r, m, n=n: r["methods"][n][m]))
        base = "WAKE" if n == last_wake else n
        if base in PAPER_COLUMNS:
            cols.append((f"{base} (paper)", lambda r, m, base=base: PAPER_COLUMNS[base][m][r["signal"] - 1]))
    for metric in METRICS:
        header = ["Signal", "SNR_in dB"] + [h for h, _ in cols]
        body = [[r["signal"], f"{r['snr_in']:.1f}"] + [_fmt(g(r, metric), digits[metric]) for _, g in cols]
                for r in rows]
        body.append(["**Mean**", ""] + [f"**{_fmt(float(np.mean([g(r, metric) for r in rows])), digits[metric])}**"
                                        for _, g in cols])
        parts += [f"### {METRIC_TITLES[metric]}", "", _table(header, body), ""]
    return "\n".join(parts)


def _real_section(real, pads_dir):
    rows = real["rows"]
    names = _method_order(rows[0]["methods"])
    parts = ["## Real recordings (PADS; paper \"Smartphone\" table)", "",
             f"Folder: `{pads_dir}`. Tremor NRMSE per recording and axis against the offline ground truth "
             "(sharp FFT high-pass of the whole recording at the mean `f_d` of WAKE's HPA runs on that axis, "
             f"`wake.eval.metrics.offline_ground_truth`); samples before {WAKE_PARAMS['window_s']:g} s left out. "
             "Best per row in bold.", ""]
    header = ["Recording", "Axis", "f_d Hz"] + names
    body = []
    for r in rows:
        vals = [r["methods"][n] for n in names]
        best = int(np.argmin(vals))
        body.append([r["recording"], r["axis"], f"{r['cutoff']:.2f}"]
                    + [f"**{_fmt(v)}**" if i == best else _fmt(v) for i, v in enumerate(vals)])
    parts += [_table(header, body), ""]
    parts += ["### Mean tremor NRMSE per method", "", _real_summary(rows, names), ""]
    return "\n".join(parts)


def _real_summary(rows, names):
    groups = [("all axes", lambda r: True), ("accelerometer", lambda r: r["axis"].startswith("acc")),
              ("gyroscope", lambda r: r["axis"].startswith("gyro"))]
    body = []
    for label, keep in groups:
        sel = [r for r in rows if keep(r)]
        if not sel:
            continue
        body.append([label, len(sel)] + [_fmt(float(np.mean([r["methods"][n] for r in sel]))) for n in names])
    wins = {n: 0 for n in names}
    for r in rows:
        wins[names[int(np.argmin([r["methods"][n] for n in names]))]] += 1
    body.append(["best on (rows)", len(rows)] + [str(wins[n]) for n in names])
    return _table(["Mean over", "rows"] + names, body)


def _lag_section(syn, real):
    parts = ["## Delay", "",
             "Lag in samples (estimate behind truth > 0) that maximises the cross-correlation "
             "(`wake.eval.metrics.best_lag`, +-25 samples), median [min, max] over signals or recording axes. "
             "Real tremor: predicted tremor `x - v_hat` against the offline ground truth. Voluntary: `v_hat` "
             "against `s_v` (synthetic) or against `x` minus the offline tremor (real). On the synthetic set "
             "the tremor lag is not informative (`x - v_hat` and `x - s_v` share all of x's fast content).", ""]
    names = _method_order(syn["lags"])
    sets = [("synthetic, voluntary", syn["lags"])]
    if real:
        sets += [("real, tremor", real["lags"]), ("real, voluntary", real["voluntary_lags"])]
    body = [[label] + [f"{np.median(lags[n]):g} [{min(lags[n])}, {max(lags[n])}]" for n in names]
            for label, lags in sets]
    parts += [_table(["Set"] + names, body), ""]
    return "\n".join(parts)


def _ablation_section(abl):
    J = abl["level"]
    parts = ["## Ablation: the paper's literal RTP vs WAKE's per-sample RTP", "",
             f"Literal (Algorithm 3): at every sample, a fresh Kalman filter over the whole 2^J = {2**J}-sample "
             "window, started from the approximations at the window's first sample (`wake.rtp.literal`). "
             "Ours: one filter-bank dot product per level and one Kalman update per sample. Both use the same "
             "HPA outputs (weights `w`, `R`); float64 reference; synthetic set; NRMSE of the voluntary "
             "estimate after the warm-up.", ""]
    body = [[name, _fmt(float(np.mean(v))), _fmt(float(np.max(v)))] for name, v in abl["nrmse"].items()]
    parts += [_table(["RTP", "mean NRMSE", "worst NRMSE"], body), ""]
    ops = abl["ops"]
    body = [["WAKE RTP, Kalman inert (P=Q=0, the default)", ops["wake_inert"]],
            ["WAKE RTP, Kalman active", ops["wake_general"]],
            ["literal RTP", ops["literal"]]]
    parts += [f"Multiply-accumulates per sample (J = {J}; formulas in `wake.rtp.literal.operation_counts`):", "",
              _table(["RTP", "MAC / sample"], body), ""]
    body = [[k, f"{v:.1f}"] for k, v in abl["timing_us"].items()]
    parts += ["Wall time per sample (Python float reference, one sample at a time; indicative only):", "",
              _table(["RTP", "us / sample"], body), ""]
    return "\n".join(parts)


def _headline(syn, real):
    names = _method_order(syn["rows"][0]["methods"])
    body = [["Synthetic (voluntary NRMSE)"]
            + [_fmt(float(np.mean([r["methods"][n]["nrmse"] for r in syn["rows"]]))) for n in names]]
    if real:
        body.append(["PADS (tremor NRMSE)"] + [_fmt(float(np.mean([r["methods"][n] for r in real["rows"]])))
                                              for n in names])
    return _table(["Mean NRMSE"] + names, body)


def _verdict(syn, real, backends):
    key = "WAKE" if "c" in backends else "WAKE-ref"
    lines = []
    for label, table, get in (("synthetic", syn["rows"], lambda r, n: r["methods"][n]["nrmse"]),
                              ("real", real["rows"] if real else None, lambda r, n: r["methods"][n])):
        if not table:
            continue
        means = {n: float(np.mean([get(r, n) for r in table])) for n in table[0]["methods"]}
        base = {n: v for n, v in means.items() if not n.startswith("WAKE")}
        best = min(base, key=base.get)
        ok = means[key] < base[best]
        lines.append(f"- {label}: {key} mean NRMSE {means[key]:.4f} vs best baseline {best} {base[best]:.4f}: "
                     + ("**WAKE better**" if ok else "**WAKE NOT better**"))
    return "\n".join(lines)


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


def _figures(out_dir, syn, real, traces, fs):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return [], ("matplotlib is not installed (pip install matplotlib, or pip install \".[plot]\" in a wake "
                    "source tree): no figures written.")
    made = []
    names = _method_order(syn["rows"][0]["methods"])
    # NRMSE per synthetic signal, then per recording
    _bar_chart(plt, out_dir / "fig_nrmse_synthetic.png", names,
               [f"{r['signal']}\n{r['snr_in']:.1f} dB" for r in syn["rows"]],
               {n: [r["methods"][n]["nrmse"] for r in syn["rows"]] for n in names},
               "voluntary NRMSE", "Synthetic set: NRMSE per signal", (9, 3.5))
    made.append("fig_nrmse_synthetic.png")
    if real:
        recs = sorted({r["recording"] for r in real["rows"]})
        _bar_chart(plt, out_dir / "fig_nrmse_real.png", names,
                   [r.split("_")[0] + "\n" + r.split("_")[1] for r in recs],
                   {n: [np.mean([r["methods"][n] for r in real["rows"] if r["recording"] == rec]) for rec in recs]
                    for n in names},
                   "tremor NRMSE (mean of 6 axes)", "PADS recordings: NRMSE per recording", (10, 3.8), fontsize=8)
        made.append("fig_nrmse_real.png")
        # One recording and axis: 040 (the clearest tremor of the subset) when present, its
        # axis with the most ground-truth tremor power.
        cand = [k for k in traces if k[0].startswith("040")] or list(traces)
        key = max(cand, key=lambda k: float(np.var(traces[k][0])) if k[1].startswith("gyro") else -1.0)
        gt, ests = traces[key]
        a, b = int(6 * fs), int(9 * fs)
        b = min(b, gt.shape[0])
        a = min(a, b - int(fs))
        t = np.arange(a, b) / fs
        fig, ax = plt.subplots(figsize=(10, 4))
        ax.plot(t, gt[a:b], "k", lw=2, label="offline ground truth")
        for n in names:
            ax.plot(t, ests[n][a:b], lw=1, label=n)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"tremor, {key[1]}")
        ax.set_title(f"Predicted tremor vs ground truth: {key[0]} {key[1]}")
        ax.legend(fontsize=8, ncol=3)
        fig.tight_layout()
        fname = f"fig_tremor_{key[0]}_{key[1]}.png"
        fig.savefig(out_dir / fname, dpi=120)
        plt.close(fig)
        made.append(fname)
        made.append(_spectra_figure(plt, out_dir / "fig_spectra_by_flag.png", real["flag_windows"]))
    made.append(_error_time_figure(plt, out_dir / "fig_error_vs_time.png", syn, real))
    return made, ""


def _time_section(syn, real):
    names = list(SLICES)
    out = ["## Time since start", "",
           "What a wearer lives through: mean NRMSE per slice of time since switch-on, and over the whole "
           "recording from 0.5 s (the tables above leave the first 5 s out, as the paper does). Each slice "
           "is normalised by the range of the truth within it. Synthetic: voluntary NRMSE against the known "
           "voluntary motion. PADS: tremor NRMSE against a truth independent of WAKE (sharp high-pass at the "
           "Welch-spectrum valley between 1.5 and 5 Hz of each whole recording, `wake.eval.warmup`). "
           f"Two trivial estimates: \"{ZERO}\" says there is no tremor; \"{ZERO_PREDICTION}\" predicts 0 for "
           "the next sample, so all of the measurement counts as tremor. `fig_error_vs_time.png` draws the error "
           "against time since start.", ""]
    for title, part in (("Synthetic set (voluntary NRMSE)", syn), ("PADS (tremor NRMSE, independent truth)", real)):
        if not part:
            continue
        methods = _method_order(part["slices"]) + list(TRIVIAL)
        best = {n: min(methods, key=lambda m: part["slices"][m][n]) for n in names}
        rows = [[m] + [("**" if best[n] == m else "") + _fmt(part["slices"][m][n], 3) + ("**" if best[n] == m else "")
                       for n in names] for m in methods]
        out += [f"**{title}** (lowest per slice in bold)", "", _table(["method"] + names, rows), ""]
    return "\n".join(out)


def _flag_section(real):
    total = sum(real["flags"].values())
    rows = [[f, str(k), f"{100 * k / total:.0f} %"] for f, k in sorted(real["flags"].items(), key=lambda kv: -kv[1])]
    return "\n".join(["## The cut-off on PADS", "",
                      f"Flags of WAKE's {total} HPA windows on PADS (warm-up windows included; docs/design.md, "
                      "\"Cut-off\"). `fig_spectra_by_flag.png` draws the AR spectrum of three windows of each flag "
                      "with the `f_d` the HPA took.", "", _table(["flag", "windows", "share"], rows)])


def _error_time_figure(plt, path, syn, real):
    parts = [("Synthetic set: voluntary error", syn)] + ([("PADS: tremor error (independent truth)", real)]
                                                          if real else [])
    fig, axes = plt.subplots(1, len(parts), figsize=(6 * len(parts), 4), squeeze=False)
    for ax, (title, part) in zip(axes[0], parts):
        for name in _method_order(part["curves"]) + list(TRIVIAL):
            t, e = part["curves"][name]
            ax.plot(t, e, lw=2 if name.startswith("WAKE") else 1, ls="--" if name in TRIVIAL else "-", label=name)
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


def _spectra_figure(plt, path, samples):
    flags = sorted(samples)
    cols = max(len(v) for v in samples.values())
    fig, axes = plt.subplots(len(flags), cols, figsize=(4 * cols, 2.6 * len(flags)), squeeze=False)
    for r, flag in enumerate(flags):
        for c in range(cols):
            ax = axes[r][c]
            if c >= len(samples[flag]):
                ax.axis("off")
                continue
            w = samples[flag][c]
            f, p = ar_psd(w["x"], w["fs"], window_order(w["x"].size, WAKE_PARAMS["ar_order"]))
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


def _jsonable(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, dict):
        # the sample windows of the spectra figure are kept by their labels only
        return {str(k): _jsonable(v) for k, v in obj.items() if k != "x"}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (np.floating,)):
        return float(obj)
    return obj


# --------------------------------------------------------------------------- command line
def _parser():
    p = argparse.ArgumentParser(
        prog="wake evaluate",
        description="Recompute the paper's evaluation (synthetic table, real recordings, delay, literal-RTP "
                    "ablation) with WAKE and the BMFLC/E-BMFLC/WFLC baselines; write report.md and figures.")
    p.add_argument("out_dir", metavar="OUT_DIR", help="folder for report.md, results.json and the figures")
    p.add_argument("--pads", metavar="DIR", default=None,
                   help="PADS recordings folder (default: $WAKE_PADS_DIR, else ../shared/data/pads relative to "
                        "the current directory if present, else synthetic only)")
    p.add_argument("--synthetic-only", action="store_true", help="skip the real recordings")
    p.add_argument("--backend", choices=("c", "reference", "both"), default="both",
                   help="WAKE RTP backend(s) (default: both; 'both' runs the C one only when it is built)")
    p.add_argument("--quick", action="store_true",
                   help="2 synthetic signals, 2 recordings, short timing: a smoke run, not the paper's numbers")
    return p


def cli(argv: list[str] | None = None) -> int:
    """Entry point of ``wake evaluate``; returns the exit status."""
    args = _parser().parse_args(None if argv is None else [str(a) for a in argv])
    out_dir = Path(args.out_dir)
    notes = []
    have_c = c_backend_available()
    if args.backend == "c" and not have_c:
        print("wake evaluate: the C backend is not built (import wake._rtp failed); "
              "use --backend reference", file=sys.stderr)
        return 2
    backends = {"c": ["c"], "reference": ["reference"]}.get(args.backend) or (
        ["reference", "c"] if have_c else ["reference"])
    if args.backend == "both" and not have_c:
        notes.append("The C backend is not built (`import wake._rtp` failed): WAKE ran on the float "
                     "reference only (column WAKE-ref).")
    pads_dir = None if args.synthetic_only else default_pads_dir(args.pads)
    recordings = []
    if pads_dir is not None:
        try:
            recordings = load_pads_folder(pads_dir)
        except ValueError as exc:
            print(f"wake evaluate: {exc}", file=sys.stderr)
            return 2
        if args.quick:
            recordings = recordings[:2]
    elif not args.synthetic_only:
        notes.append("No PADS folder (--pads, $WAKE_PADS_DIR or ../shared/data/pads): synthetic set only.")
    for n in notes:
        print(f"wake evaluate: {n}")
    out_dir.mkdir(parents=True, exist_ok=True)

    t0 = time.perf_counter()
    syn = evaluate_synthetic(backends, args.quick)
    real, traces = (evaluate_real(recordings, backends) if recordings else (None, {}))
    abl = ablation_literal_rtp(args.quick)
    figs, fig_note = _figures(out_dir, syn, real, traces, 100.0)
    if fig_note:
        notes.append(fig_note)
        print(f"wake evaluate: {fig_note}")

    params = "; ".join(repr(m) for m in baseline_methods(100.0).values())
    parts = ["# WAKE evaluation", "",
             f"Command: `wake evaluate {' '.join(str(a) for a in (argv if argv is not None else sys.argv[1:]))}`"
             + ("  (**--quick: a smoke run, not the paper's numbers**)" if args.quick else ""), "",
             f"WAKE: `WakeFilter({', '.join(f'{k}={v!r}' for k, v in WAKE_PARAMS.items())})`, backends: "
             f"{', '.join(backends)} (WAKE = C backend, WAKE-ref = float reference). Baselines (tuned once on "
             f"synthetic signal 1, docs/baselines.md): `{params}`.", ""]
    parts += [f"> {n}" for n in notes] + ([""] if notes else [])
    parts += ["## Headline", "", _headline(syn, real), "", _verdict(syn, real, backends), ""]
    parts += [_synthetic_section(syn), ""]
    if real:
        parts += [_real_section(real, pads_dir), ""]
    parts += [_lag_section(syn, real), _ablation_section(abl)]
    parts += [_time_section(syn, real), ""]
    if real:
        parts += [_flag_section(real), ""]
    if figs:
        parts += ["## Figures", ""] + [f"![{f}]({f})" for f in figs] + [""]
    parts.append(f"_Run time: {time.perf_counter() - t0:.0f} s._")
    (out_dir / "report.md").write_text("\n".join(parts) + "\n")
    (out_dir / "results.json").write_text(json.dumps(_jsonable(
        {"backends": backends, "synthetic": syn, "real": real, "ablation": abl, "notes": notes,
         "wake_params": WAKE_PARAMS, "paper_snr_db": PAPER_SNR_DB}), indent=1))
    print(_headline(syn, real))
    print(_verdict(syn, real, backends))
    print(f"wake evaluate: wrote {out_dir / 'report.md'}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(cli())
