"""Computing for ``wake evaluate``: one task (a recording under one WAKE configuration) into result rows.

:func:`compute_task` is what a worker runs: it loads its :class:`~wake.eval.sources.Source`,
runs WAKE (every requested backend) and, unless told not to, the three
baselines and the two trivial estimates, and returns one row per (channel,
method) with every metric and slice (:data:`ROW_COLUMNS`).  A failing
recording gives one row whose ``error`` says why in one line; the others
go on.  The rows depend on the task alone, never on which worker ran it or
when, so a parallel run stores the same numbers as a serial one.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wake.eval.baselines import baseline_methods
from wake.eval.metrics import best_lag, nrmse, offline_ground_truth, prf, snr_out
from wake.eval.sources import Source, load_source
from wake.eval.synthetic import paper_dataset
from wake.eval.suppression import suppression
from wake.eval.tremor_ahead import ahead_commands
from wake.eval.warmup import SLICES, error_curve, independent_ground_truth, slice_nrmse
from wake.filter import WakeFilter
from wake.rtp.literal import hpa_schedule, literal_rtp_predict, literal_rtp_run, operation_counts

__all__ = ["AHEAD_SET", "AHEAD_AT", "WAKE_PARAMS", "ZERO", "ZERO_PREDICTION", "TRIVIAL", "ROW_COLUMNS", "Task",
           "baseline_methods",
           "wake_name", "run_methods", "compute_task", "ablation_literal_rtp"]

#: WAKE as the paper configures it (the WakeFilter defaults; not tuned here).
WAKE_PARAMS = dict(wavelet="sym3", level=5, window_s=5.0, ar_order=17)

#: Two trivial estimates: no tremor at all (voluntary = x), and a prediction of 0
#: for the next sample (voluntary = 0, so the tremor estimate is x itself).
ZERO = "zero tremor (voluntary = x)"
ZERO_PREDICTION = "zero prediction (voluntary = 0)"
TRIVIAL = (ZERO, ZERO_PREDICTION)

#: What one row of the result store holds, with its type.
ROW_COLUMNS = {"task": str, "source": str, "recording": str, "set": str, "config": str, "channel_index": int,
               "channel": str, "method": str, "fs": float, "snr_in": float, "cutoff": float, "truth_var": float,
               "nrmse": float, "prf": float, "snr_out": float, "lag": int, "voluntary_lag": int,
               **{f"slice {name}": float for name in SLICES}, "curve": str, "hpa": str, "error": str,
               "reduction": float, "disturbance": float}


@dataclass(frozen=True)
class Task:
    """A recording under one WAKE configuration: the unit a worker computes and the store records.

    ``config``: WakeFilter settings as sorted ``(name, value)`` pairs;
    ``baselines``: also run BMFLC, E-BMFLC, WFLC and the trivial estimates.
    """

    source: Source
    config: tuple
    backends: tuple
    baselines: bool = True

    @property
    def settings(self) -> dict:
        return dict(self.config)

    @property
    def config_label(self) -> str:
        return config_label(self.settings)

    @property
    def key(self) -> str:
        # "ahead": the task's rows hold the tremor ahead and its suppression too (a store written before lacks them)
        return (f"{self.source.key}|{self.config_label}|{'+'.join(self.backends)}|{int(self.baselines)}"
                + ("|ahead+suppression" if self.ahead else ""))

    @property
    def ahead(self) -> bool:
        """Whether the task scores the tremor ahead (:mod:`wake.eval.tremor_ahead`): with the baselines, on
        the paper's synthetic set and on recordings; not on a generated cohort, where it would more than
        double the time of each task (mostly the baselines' extrapolation)."""
        return self.baselines and self.source.kind != "cohort"


def config_label(settings):
    """``"wavelet=sym3 level=5 ..."``: the paper's parameters first, then the others by name."""
    names = [k for k in WAKE_PARAMS if k in settings] + sorted(k for k in settings if k not in WAKE_PARAMS)
    return " ".join(f"{k}={settings[k]!r}".replace("'", "") for k in names)


def wake_name(backend):
    """The report's column of a WAKE backend: ``WAKE`` (C core) or ``WAKE-ref`` (float reference)."""
    return "WAKE" if backend == "c" else "WAKE-ref"


def run_methods(x, fs, backends, settings=None, baselines=True):
    """Every method on x: ({name: voluntary}, {backend: WakeResult})."""
    out = {}
    if baselines:
        for name, m in baseline_methods(fs).items():
            out[name] = m.run(x).voluntary
    wake = {}
    for b in backends:
        res = WakeFilter(fs=fs, backend=b, **(WAKE_PARAMS if settings is None else settings)).run(x)
        out[wake_name(b)] = res.voluntary
        wake[b] = res
    return out, wake


def _blank(task, loaded, channel_index, method):
    row = {name: (float("nan") if kind is float else 0 if kind is int else "") for name, kind in ROW_COLUMNS.items()}
    fallback = Path(task.source.path).name if task.source.path else task.source.key
    row.update(task=task.key, source=task.source.key, recording=loaded.name if loaded else fallback,
               set="real" if not task.source.synthetic else task.source.kind, config=task.config_label,
               channel_index=channel_index, method=method, snr_in=task.source.snr_db,
               fs=loaded.fs if loaded else float("nan"))
    return row


def _time_columns(row, truth, estimate, fs):
    row.update({f"slice {k}": v for k, v in slice_nrmse(truth, estimate, fs).items()})
    row["curve"] = json.dumps(error_curve(truth, estimate, fs)[1].tolist())


def _synthetic_rows(task, loaded, vols, start):
    s_v, x, rows = loaded.voluntary, loaded.x[:, 0], []
    trivial = {ZERO: x, ZERO_PREDICTION: np.zeros_like(x)} if task.baselines else {}
    for name, v in {**vols, **trivial}.items():
        row = _blank(task, loaded, 0, name)
        row.update(channel="x", snr_in=loaded.snr_db)
        _time_columns(row, s_v, v, loaded.fs)
        if name in vols:
            row.update(nrmse=nrmse(s_v, v, start), prf=prf(s_v, v, start), snr_out=snr_out(s_v, v, start),
                       lag=best_lag(s_v[start:], v[start:]))
        rows.append(row)
    return rows


def _real_rows(task, loaded, vols, wake, start):
    x, rows = loaded.x, []
    ref_backend = "reference" if "reference" in wake else next(iter(wake))
    ref = wake[ref_backend]
    trivial = {ZERO: x, ZERO_PREDICTION: np.zeros_like(x)} if task.baselines else {}
    for c, axis in enumerate(loaded.channels):
        _, independent, _ = independent_ground_truth(x[:, c], loaded.fs)
        cutoff = float(ref.mean_cutoff[c])
        _, gt = offline_ground_truth(x[:, c], loaded.fs, cutoff)
        for name, v in {**vols, **trivial}.items():
            row = _blank(task, loaded, c, name)
            row.update(channel=axis, cutoff=cutoff, truth_var=float(np.var(gt)))
            _time_columns(row, independent, x[:, c] - v[:, c], loaded.fs)
            if name in vols:
                est = x[:, c] - v[:, c]
                row.update(nrmse=nrmse(gt, est, start), lag=best_lag(gt[start:], est[start:]),
                           voluntary_lag=best_lag((x[:, c] - gt)[start:], v[start:, c]))
            if name == wake_name(ref_backend):
                window = int(round(task.settings.get("window_s", WAKE_PARAMS["window_s"]) * loaded.fs))
                row["hpa"] = json.dumps([[int(u.index), float(u.cutoff), str(u.cutoff_flag), max(0, int(u.index) - window)]
                                         for u in ref.hpa[c]])
            rows.append(row)
    return rows


#: Rows of the tremor ahead (:mod:`wake.eval.tremor_ahead`): ``set`` is this prefix and the set's name, ``method``
#: the method's name, this separator and the horizon in ms (``"WAKE command (gated) @ 50 ms"``).
AHEAD_SET, AHEAD_AT = "ahead-", " @ "
#: Sources whose tremor-ahead rows are summarised apart (the others, PADS and files: "real").
AHEAD_SETS_APART = ("paper", "cohort", "strong", "pdkit")


def _ahead_rows(task, loaded, backends):
    """The tremor-ahead rows of a task: per horizon, method and channel, the slices of the predicted-tremor
    NRMSE against the synthetic tremor component, or a recording's tremor independent of WAKE, and the
    closed-loop suppression of an actuator playing it (:func:`wake.eval.suppression.suppression`: ``reduction``
    %, ``disturbance`` RMS)."""
    x = loaded.x
    truths = [independent_ground_truth(x[:, c], loaded.fs) for c in range(x.shape[1])]
    truth = loaded.tremor[:, None] if loaded.tremor is not None else np.column_stack([t[1] for t in truths])
    backend = "c" if "c" in backends else backends[0]
    rows = []
    for ms, methods in ahead_commands(x, loaded.fs, truth, backend=backend, settings=task.settings).items():
        for name, played in methods.items():
            for c in range(x.shape[1]):
                row = _blank(task, loaded, c, f"{name}{AHEAD_AT}{ms:g} ms")
                reduction, disturbance = suppression(truth[:, c], played[:, c], loaded.fs, truths[c][2])
                row.update(set=AHEAD_SET + (task.source.kind if task.source.kind in AHEAD_SETS_APART else "real"),
                           channel=loaded.channels[c], reduction=reduction, disturbance=disturbance,
                           **{f"slice {k}": v for k, v in slice_nrmse(truth[:, c], played[:, c], loaded.fs).items()})
                rows.append(row)
    return rows


def compute_task(task: Task) -> list:
    """The rows of one task (see :data:`ROW_COLUMNS`); a failure gives one row with ``error`` set.

    Examples
    --------
    >>> from wake.eval.compute import Task, compute_task, WAKE_PARAMS
    >>> from wake.eval.sources import cohort_sources
    >>> task = Task(cohort_sources(1, duration_s=12.0)[0], tuple(sorted(WAKE_PARAMS.items())), ("reference",))
    >>> rows = compute_task(task)
    >>> sorted({r["method"] for r in rows if r["set"] == "cohort"})[:3], rows[0]["error"]
    (['BMFLC', 'E-BMFLC', 'WAKE-ref'], '')
    """
    loaded = None
    try:
        loaded = load_source(task.source)
        settings = task.settings
        start = int(round(settings.get("window_s", WAKE_PARAMS["window_s"]) * loaded.fs))
        if loaded.x.shape[0] <= start + 2 * loaded.fs:
            raise ValueError(f"{loaded.x.shape[0]} samples; need more than the {start}-sample warm-up + 2 s "
                             f"({(start + 2 * loaded.fs) / loaded.fs:g} s at {loaded.fs:g} Hz)")
        signal = loaded.x[:, 0] if loaded.voluntary is not None else loaded.x
        vols, wake = run_methods(signal, loaded.fs, task.backends, settings, task.baselines)
        if loaded.voluntary is not None:
            rows = _synthetic_rows(task, loaded, vols, start)
        else:
            rows = _real_rows(task, loaded, {n: v.reshape(loaded.x.shape) for n, v in vols.items()}, wake, start)
        return rows + (_ahead_rows(task, loaded, task.backends) if task.ahead else [])
    except Exception as exc:  # one failing recording must not stop a cohort: record it and go on
        row = _blank(task, loaded, 0, "")
        message = " ".join(str(exc).split()) or type(exc).__name__
        row["error"] = f"{type(exc).__name__}: {message}"
        return [row]


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
