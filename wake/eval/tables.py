"""From stored rows to the report's summaries: per set, per method, per configuration.

Every function here takes rows as :meth:`wake.eval.store.ResultStore.rows`
returns them (in task order), so the means are taken in the same order
whichever worker finished first, and a report rebuilt from the store is
the same, digit for digit, as the one written when the rows were computed.
"""

from __future__ import annotations

import json
import sys
import warnings

import numpy as np

from wake.eval.compute import AHEAD_AT, AHEAD_SET, TRIVIAL
from wake.eval.warmup import SLICES, mean_curve, mean_slices

__all__ = ["ahead_summary", "synthetic_summary", "real_summary", "grid_ranking", "curve_of", "compact_row", "WHOLE",
           "AFTER"]

#: The two slices a configuration is ranked by: the whole recording and after the warm-up.
WHOLE, AFTER = "whole (from 0.5 s)", "after 5 s"


def _not_ahead(rows):
    """The rows of the voluntary / tremor estimates (the tremor ahead's have their own summary)."""
    return [r for r in rows if not r["set"].startswith(AHEAD_SET)]


def _slices_of(row):
    return {name: row[f"slice {name}"] for name in SLICES}


def compact_row(row):
    """A stored row made small for holding thousands: repeated names shared, the error curve as an array.

    Examples
    --------
    >>> from wake.eval.tables import compact_row
    >>> compact_row({"task": "a", "curve": "[0.5, 0.25]", "nrmse": 0.1})["curve"].tolist()
    [0.5, 0.25]
    """
    out = {k: sys.intern(v) if isinstance(v, str) and k != "curve" and len(v) < 200 else v for k, v in row.items()}
    out["curve"] = np.asarray(json.loads(row["curve"] or "[]"), dtype=float)
    return out


def curve_of(row, bin_s=0.5):
    """The stored error curve of a row as :func:`wake.eval.warmup.error_curve` returned it: (t, err)."""
    err = row["curve"] if isinstance(row["curve"], np.ndarray) else np.asarray(json.loads(row["curve"]), dtype=float)
    return (np.arange(err.size) + 0.5) * bin_s, err


def _per_method_time(rows):
    slices, curves = {}, {}
    for r in rows:
        slices.setdefault(r["method"], []).append(_slices_of(r))
        curves.setdefault(r["method"], []).append(curve_of(r))
    return ({n: mean_slices(v) for n, v in slices.items()}, {n: mean_curve(v) for n, v in curves.items()})


def synthetic_summary(rows):
    """The synthetic part of the report (one channel per signal), or None without rows.

    Returns ``{"rows": [{"signal", "snr_in", "methods": {name: {nrmse, prf, snr_out}}}], "lags",
    "slices", "curves"}``.
    """
    rows = _not_ahead(rows)
    if not rows:
        return None
    table, lags, by_source = [], {}, {}
    for r in rows:
        by_source.setdefault(r["source"], []).append(r)
    for source, group in by_source.items():
        entry = {"signal": int(source.rsplit("/", 1)[1]),
                 "snr_in": group[0]["snr_in"], "methods": {}}
        for r in group:
            if r["method"] in TRIVIAL:
                continue
            entry["methods"][r["method"]] = {"nrmse": r["nrmse"], "prf": r["prf"], "snr_out": r["snr_out"]}
            lags.setdefault(r["method"], []).append(r["lag"])
        table.append(entry)
    slices, curves = _per_method_time(rows)
    return {"rows": table, "lags": lags, "slices": slices, "curves": curves}


def _flag_windows(rows):
    """Every HPA window of the stored WAKE runs, by cut-off flag, and three of each spread over the run."""
    flags, windows = {}, {}
    for r in rows:
        for index, cutoff, flag, start in json.loads(r["hpa"] or "[]"):
            flags[flag] = flags.get(flag, 0) + 1
            windows.setdefault(flag, []).append(
                {"label": f"{r['recording']} {r['channel']} @ {index / r['fs']:g} s", "fs": r["fs"],
                 "cutoff": cutoff, "source": r["source"], "channel_index": r["channel_index"],
                 "start": start, "stop": index})
    samples = {f: [w[int(k)] for k in np.linspace(0, len(w) - 1, min(3, len(w)))] for f, w in windows.items()}
    return flags, samples


def real_summary(rows):
    """The recordings' part of the report (tremor against the offline truth), or None without rows."""
    rows = _not_ahead(rows)
    if not rows:
        return None
    table, lags, vlags, current = [], {}, {}, None
    for r in rows:
        if r["method"] in TRIVIAL:
            continue
        if current is None or (current["recording"], current["axis"]) != (r["recording"], r["channel"]):
            current = {"recording": r["recording"], "axis": r["channel"], "cutoff": r["cutoff"], "methods": {}}
            table.append(current)
        current["methods"][r["method"]] = r["nrmse"]
        lags.setdefault(r["method"], []).append(r["lag"])
        vlags.setdefault(r["method"], []).append(r["voluntary_lag"])
    slices, curves = _per_method_time(rows)
    flags, samples = _flag_windows(rows)
    return {"rows": table, "lags": lags, "voluntary_lags": vlags, "slices": slices, "curves": curves,
            "flags": flags, "flag_windows": samples}


def grid_ranking(rows, configs, method):
    """Each configuration's ``method`` NRMSE over the whole recording and after 5 s, best first.

    Returns a list of ``{"config", "count", "whole": (mean, std, worst), "after": (mean, std, worst)}``
    sorted by the whole-recording mean (ties: after-5-s mean, then grid order).
    """
    out = []
    for order, config in enumerate(configs):
        sel = [r for r in rows if r["config"] == config and r["method"] == method]
        if not sel:
            continue
        stats = {}
        for label, name in (("whole", WHOLE), ("after", AFTER)):
            v = np.array([r[f"slice {name}"] for r in sel], dtype=float)
            stats[label] = (float(np.nanmean(v)), float(np.nanstd(v)), float(np.nanmax(v)))
        out.append({"config": config, "count": len(sel), "order": order, **stats})
    return sorted(out, key=lambda e: (e["whole"][0], e["after"][0], e["order"]))


def ahead_summary(rows):
    """The tremor ahead's part of the report (:mod:`wake.eval.tremor_ahead`), or None without its rows.

    Returns ``{set: {"axes": count, "horizons": {ms: {method: mean slices}}}}``, methods in the order stored
    (WAKE's gated command first, zero, the limits, the baselines).

    Examples
    --------
    >>> row = {"set": "ahead-paper", "method": "zero @ 10 ms", "channel_index": 0, "source": "s",
    ...        **{f"slice {k}": 0.5 for k in SLICES}}
    >>> ahead_summary([row])["paper"]["horizons"][10.0]["zero"]["after 5 s"]
    0.5
    """
    acc, axes, sup = {}, {}, {}
    for r in rows:
        if not r["set"].startswith(AHEAD_SET):
            continue
        name, ms = r["method"].rsplit(AHEAD_AT, 1)
        key = r["set"][len(AHEAD_SET):]
        acc.setdefault(key, {}).setdefault(float(ms.split()[0]), {}).setdefault(name, []).append(_slices_of(r))
        sup.setdefault(key, {}).setdefault(float(ms.split()[0]), {}).setdefault(name, []).append(
            (r.get("reduction", np.nan), r.get("disturbance", np.nan)))
        axes.setdefault(key, set()).add((r["source"], r["channel_index"]))
    if not acc:
        return None
    return {key: {"axes": len(axes[key]), "horizons": {ms: {n: mean_slices(v) for n, v in methods.items()}
                                                       for ms, methods in sorted(by_ms.items())},
                  "suppression": {ms: {n: _mean_suppression(v) for n, v in methods.items()}
                                  for ms, methods in sorted(sup[key].items())}}
            for key, by_ms in acc.items()}


def _mean_suppression(pairs):
    """Mean ``{"reduction": %, "disturbance": RMS}`` over axes (NaN left out; rows stored before issue 46 have
    neither)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)       # every row without them: NaN, said as such
        red, dist = np.nanmean(np.asarray(pairs, dtype=float), axis=0)
    return {"reduction": float(red), "disturbance": float(dist)}
