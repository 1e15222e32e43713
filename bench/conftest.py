"""Host-speed benchmarks: shared data and the summary printed after a run.

    pytest bench/ --benchmark-only

Plain ``pytest`` from the repository root collects ``tests/`` only
(``testpaths`` in pyproject.toml), so these never run by accident.

Each benchmark records in ``benchmark.extra_info`` how many samples (or HPA
runs) one call processes; the summary below turns the medians into
throughputs and the ratios between benchmarks of the same run, and compares
them with the targets (reported, never asserted: shared CI runners are too
noisy for timing assertions).
"""

import numpy as np
import pytest


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """One process for the benchmarks: pyproject.toml's ``-n auto`` (pytest-xdist, for tests/) would spread them
    over workers, and pytest-benchmark then disables itself; a timing is of one process anyway."""
    if getattr(config.option, "numprocesses", None):
        config.option.numprocesses = 0
        config.option.dist = "no"

#: benchmark name -> (target, predicate on its summary row); reported, never asserted. The end-to-end run's target is
#: a ratio, held by bench/speed_gate.py (CI's gate), not a time here
TARGETS = {
    "test_c_block_run": ("C block run >= 5 M samples/s", lambda s: s["per_second"] >= 5e6),
    "test_hpa_long_window": ("one HPA at L = 2e5 (1 kHz, 200 s window) < 0.5 s", lambda s: s["median"] < 0.5),
}


@pytest.fixture(scope="session")
def recording():
    """A 50 s, 100 Hz synthetic recording (the paper's setting)."""
    from wake.eval.synthetic import make_signal

    return make_signal(10.0, seed=3)


@pytest.fixture(scope="session")
def fitted(recording):
    """Taps, fitted weights, R and full scale, as the filter hands them to the RTP."""
    from wake import WakeFilter

    filt = WakeFilter(fs=recording.fs, backend="reference")
    res = filt.run(recording.measurement)
    upd = res.hpa[0][-1]
    full_scale = filt.headroom * float(np.max(np.abs(recording.measurement[: filt.window_samples])))
    return {"taps": filt.taps, "weights": upd.weights, "R": upd.measurement_noise, "full_scale": full_scale,
            "window": recording.measurement[-filt.window_samples:], "fs": recording.fs}


def _rows(config):
    session = getattr(config, "_benchmarksession", None)
    if session is None:
        return {}
    rows = {}
    for bench in session.benchmarks:
        stats = bench.stats
        if stats is None or not getattr(stats, "rounds", 0):
            continue
        items = bench.extra_info.get("items", 1)
        name = bench.name.split("[")[0]
        rows[name] = {
            "median": stats.median, "iqr": stats.iqr, "min": stats.min, "max": stats.max, "rounds": stats.rounds,
            "items": items, "unit": bench.extra_info.get("unit", "call"),
            "per_item": stats.median / items, "per_second": items / stats.median,
        }
    return rows


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    rows = _rows(config)
    if not rows:
        return
    tr = terminalreporter
    tr.section("WAKE host speed (medians of this run)")
    tr.write_line(f"{'benchmark':<28} {'median':>12} {'IQR':>11} {'rounds':>7} {'per item':>12} {'items/s':>13}")
    for name, r in rows.items():
        tr.write_line(f"{name:<28} {_t(r['median']):>12} {_t(r['iqr']):>11} {r['rounds']:>7} "
                      f"{_t(r['per_item']):>12} {r['per_second']:>10,.0f} {r['unit']}/s")
    # (text, numerator, denominator, samples per numerator item): time per sample, numerator / denominator
    ratios = [
        ("float reference (Kalman inert, vectorised) / C block run", "test_reference_block_run", "test_c_block_run", 1),
        ("float reference (Kalman active, Python loop) / C block run", "test_reference_block_run_kalman",
         "test_c_block_run", 1),
        ("C block run / raw wake_rtp_run (quantisation overhead)", "test_c_block_run", "test_c_block_run_raw", 1),
        ("C step() from Python / C block run", "test_c_step_per_sample", "test_c_block_run", 1),
        ("WakeFilter.update() / C block run", "test_filter_update_per_sample", "test_c_block_run", 1),
        ("one HPA run / C block run over its 500-sample window", "test_hpa_per_update", "test_c_block_run", 500),
    ]
    tr.write_line("")
    tr.write_line("ratios of time per sample (same run):")
    for text, num, den, per in ratios:
        if num in rows and den in rows:
            ratio = rows[num]["per_item"] / (per * rows[den]["per_item"])
            tr.write_line(f"  {text}: {ratio:,.3g}")
    tr.write_line("")
    for name, (text, ok) in TARGETS.items():
        if name in rows:
            tr.write_line(f"target {text}: {'met' if ok(rows[name]) else 'MISSED'} "
                          f"({_t(rows[name]['median'])} median, {rows[name]['per_second']:,.0f} "
                          f"{rows[name]['unit']}/s)")


def _t(seconds):
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds / 1e-9:.3g} ns"
