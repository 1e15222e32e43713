"""``wake evaluate`` at cohort scale: the result store, resuming, parallel runs, grids, failing recordings."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from wake.eval import store as store_module
from wake.eval.compute import ROW_COLUMNS, WAKE_PARAMS, Task, compute_task
from wake.eval.evaluate import cli, parse_grid
from wake.eval.runner import require, run_tasks
from wake.eval.sources import cohort_sources, file_sources
from wake.eval.store import ResultStore

ROOT = Path(__file__).resolve().parents[2]
#: Short signals: a warm-up of 5 s plus 2 s is the least a recording needs.
COHORT = ["--duration", "8", "--backend", "reference", "--no-progress"]


def _tasks(count, baselines=True):
    return [Task(s, tuple(WAKE_PARAMS.items()), ("reference",), baselines)
            for s in cohort_sources(count, duration_s=8.0)]


def _body(report):
    """The report without its command line and run time (the lines that name the run, not its results)."""
    lines = Path(report).read_text().splitlines()
    return [ln for ln in lines if not ln.startswith(("Command:", "_Run time"))]


def _stored(out):
    store = ResultStore(Path(out) / "store", ROW_COLUMNS)
    rows = store.rows(sorted(store._by_task()))
    return [tuple((k, repr(v)) for k, v in r.items()) for r in rows]


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_store_round_trip_is_exact_and_a_rerun_skips_what_is_done(tmp_path, fmt):
    if fmt == "parquet":
        pytest.importorskip("pyarrow", reason="the Parquet store needs pyarrow: pip install \".[cohort]\"")
    tasks = _tasks(3, baselines=False)
    direct = {t.key: compute_task(t) for t in tasks}
    store = ResultStore(tmp_path, ROW_COLUMNS, format=fmt)
    assert run_tasks(tasks[:2], store, progress=False) == (2, 0)
    assert run_tasks(tasks, store, progress=False) == (1, 0)          # only the missing one
    store.compact()
    assert not list((tmp_path / "parts").iterdir()) and (tmp_path / f"results.{fmt}").is_file()
    back = store.rows([t.key for t in reversed(tasks)])
    expected = [r for t in reversed(tasks) for r in direct[t.key]]
    assert [r["task"] for r in back] == [r["task"] for r in expected]
    for got, want in zip(back, expected):
        for name in ROW_COLUMNS:
            assert repr(got[name]) == repr(want[name]), name       # bit for bit, NaN included


def test_store_falls_back_to_csv_without_pyarrow(tmp_path, monkeypatch):
    monkeypatch.setattr(store_module, "parquet_available", lambda: False)
    assert ResultStore(tmp_path, ROW_COLUMNS).format == "csv"
    with pytest.raises(ValueError, match=r"wake-tremor\[cohort\]"):
        ResultStore(tmp_path, ROW_COLUMNS, format="parquet")


def test_missing_optional_package_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "joblib", None)       # import joblib now raises ImportError
    with pytest.raises(ValueError, match=r"--jobs needs joblib: pip install \"wake-tremor\[cohort\]\""):
        require("joblib", "--jobs")
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ValueError, match=r"wake-tremor\[dask\]"):
        require("distributed", "--scheduler")


@pytest.mark.slow
def test_parallel_runs_store_and_report_what_a_serial_run_does(tmp_path):
    pytest.importorskip("joblib", reason="--jobs needs joblib: pip install \".[cohort]\"")
    serial, parallel = tmp_path / "serial", tmp_path / "parallel"
    assert cli([serial, "--synthetic", "6", *COHORT]) == 0
    assert cli([parallel, "--synthetic", "6", *COHORT, "--jobs", "2"]) == 0
    assert _stored(serial) == _stored(parallel)
    assert _body(serial / "report.md") == _body(parallel / "report.md")
    assert "## Synthetic cohort" in (serial / "report.md").read_text()


@pytest.mark.slow
def test_dask_local_cluster_matches_serial(tmp_path):
    pytest.importorskip("distributed", reason="--scheduler needs Dask: pip install \".[dask]\"")
    serial, dask = tmp_path / "serial", tmp_path / "dask"
    assert cli([serial, "--synthetic", "4", *COHORT]) == 0
    assert cli([dask, "--synthetic", "4", *COHORT, "--scheduler", "local", "--jobs", "2"]) == 0
    assert _stored(serial) == _stored(dask)
    assert _body(serial / "report.md") == _body(dask / "report.md")


def test_the_local_cluster_workers_run_without_the_dashboards_profiler():
    distributed = pytest.importorskip("distributed", reason="--scheduler needs Dask: pip install \".[dask]\"")
    import dask

    from wake.eval.runner import LOCAL_CLUSTER_CONFIG, _start_dask

    assert LOCAL_CLUSTER_CONFIG == {"distributed.worker.profile.enabled": False}
    cluster, client = _start_dask(distributed, "local", 1)
    try:
        seen = client.run(lambda: dask.config.get("distributed.worker.profile.enabled"))
    finally:
        client.close()
        cluster.close()
    assert list(seen.values()) == [False]
    assert dask.config.get("distributed.worker.profile.enabled") is True    # the parent's setting is left as it was


def _interrupted_run(out, count, sig):
    """Start a run of ``count`` tasks in a subprocess, send ``sig`` once about half are stored."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    cmd = [sys.executable, "-m", "wake", "evaluate", str(out), "--synthetic", str(count), *COHORT]
    proc = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    parts = out / "store" / "parts"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if parts.is_dir() and len([p for p in parts.iterdir() if not p.name.startswith(".")]) >= count // 2:
            break
        time.sleep(0.02)
    assert proc.poll() is None, f"the run ended before it could be interrupted: {proc.communicate()}"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err.decode()


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL], ids=["SIGINT", "SIGKILL"])
def test_killed_run_resumes_to_the_same_table_recomputing_only_what_was_missing(tmp_path, capsys, sig):
    count = 12
    status, err = _interrupted_run(tmp_path / "killed", count, sig)
    if sig == signal.SIGINT:
        assert status == 130 and "rerun the same command" in err
    else:
        assert status == -signal.SIGKILL
    kept = ResultStore(tmp_path / "killed" / "store", ROW_COLUMNS).done()
    assert count // 2 <= len(kept) < count
    capsys.readouterr()
    assert cli([tmp_path / "killed", "--synthetic", str(count), *COHORT]) == 0
    # a serial run has one task in flight: it, and only what was never started, is computed again
    assert f"{count - len(kept)} of {count} tasks computed" in capsys.readouterr().out
    assert cli([tmp_path / "whole", "--synthetic", str(count), *COHORT]) == 0
    assert _body(tmp_path / "killed" / "report.md") == _body(tmp_path / "whole" / "report.md")
    assert _stored(tmp_path / "killed") == _stored(tmp_path / "whole")


def test_grid_ranks_every_configuration(tmp_path):
    out = tmp_path / "grid"
    assert cli([out, "--synthetic", "3", *COHORT, "--grid", "level=4,5", "window_s=3,5"]) == 0
    text = (out / "report.md").read_text()
    section = text.split("## Configurations")[1].split("\n## ")[0]
    ranked = [ln for ln in section.splitlines() if ln.startswith("| ") and not ln.startswith("| rank")]
    assert len(ranked) == 4
    assert [int(ln.split("|")[1]) for ln in ranked] == [1, 2, 3, 4]
    means = [float(ln.split("|")[4].split("±")[0]) for ln in ranked]
    assert means == sorted(means) and all(0 < m < 1 for m in means)
    configs = {ln.split("|")[2].strip(" `") for ln in ranked}
    assert configs == {f"wavelet=sym3 level={lv} window_s={w:.1f} ar_order=17" for lv in (4, 5) for w in (3, 5)}
    rows = ResultStore(out / "store", ROW_COLUMNS)._by_task()
    methods = {k.split("|")[1]: {r["method"] for r in v} for k, v in rows.items()}
    first = "wavelet=sym3 level=4 window_s=3.0 ar_order=17"
    assert "BMFLC" in methods[first]                             # baselines once, with the first configuration
    assert all(m == {"WAKE-ref"} for c, m in methods.items() if c != first)


def test_grid_errors_name_the_setting():
    with pytest.raises(ValueError, match="unknown WakeFilter setting 'levels'"):
        parse_grid(["levels=4"])
    with pytest.raises(ValueError, match="level=x"):
        parse_grid(["level=x"])
    with pytest.raises(ValueError, match="is not NAME=VALUE"):
        parse_grid(["level"])
    with pytest.raises(ValueError, match="level=99"):
        parse_grid(["level=99"])
    assert len(parse_grid(["level=4,5,6", "wavelet=sym3,db4", "window_s=3,5"])) == 12


def _pads_file(path, seconds, rng):
    t = np.cumsum(rng.uniform(0.008, 0.012, int(seconds * 100)))
    t -= t[0]
    vals = np.sin(2 * np.pi * 0.4 * t)[:, None] + 0.2 * np.sin(2 * np.pi * 6 * t[:, None] + rng.uniform(0, 6, 6))
    path.write_text("\n".join(",".join(f"{v:.8f}" for v in r) for r in np.column_stack([t, vals])) + "\n")


@pytest.mark.slow
def test_failing_recordings_are_recorded_in_one_line_and_the_others_evaluated(tmp_path, capsys):
    rng = np.random.default_rng(3)
    folder = tmp_path / "recs"
    folder.mkdir()
    _pads_file(folder / "200_Task_LeftWrist.txt", 10.0, rng)
    _pads_file(folder / "201_Task_LeftWrist.txt", 3.0, rng)          # too short
    (folder / "202_broken.csv").write_text("a,b\n1,zz\n")              # unreadable
    out = tmp_path / "out"
    assert cli([out, folder, "--synthetic", "0", "--backend", "reference", "--no-progress"]) == 1
    err = capsys.readouterr().err
    assert err.count("wake evaluate: 20") == 2
    assert "201_Task_LeftWrist: ValueError:" in err and "warm-up + 2 s" in err
    text = (out / "report.md").read_text()
    failed = text.split("## Recordings that failed")[1].split("\n## ")[0]
    assert failed.count("\n| 20") == 2 and "202_broken.csv" in failed
    assert "| 200_Task_LeftWrist | gyro_z |" in text
    # errors are kept, and a rerun tries those two again (only them)
    assert cli([out, folder, "--synthetic", "0", "--backend", "reference", "--no-progress"]) == 1
    assert "2 of 3 tasks computed" in capsys.readouterr().out
    store = ResultStore(out / "store", ROW_COLUMNS)
    assert not list((out / "store" / "parts").iterdir())            # merged again, each task once
    # 6 axes x 7 methods (WAKE, four baselines, two trivial), and the tremor ahead: 4 horizons x 9 methods x 6 axes
    assert sorted(len(v) for v in store._by_task().values()) == [1, 1, 6 * 7 + 4 * 9 * 6]


def test_inputs_from_folders_files_and_globs(tmp_path):
    rng = np.random.default_rng(4)
    for name in ("a.txt", "b.txt", "c.csv"):
        _pads_file(tmp_path / name, 1.0, rng)
    (tmp_path / "README.md").write_text("not a recording")
    got = file_sources([tmp_path / "b.txt", str(tmp_path / "*.txt"), tmp_path])
    assert [Path(s.path).name for s in got] == ["b.txt", "a.txt", "c.csv"]      # given order, no repeats
    with pytest.raises(ValueError, match="no such file or folder"):
        file_sources([tmp_path / "missing*.txt"])


@pytest.mark.slow
def test_plain_csv_needs_and_takes_its_rate(tmp_path, capsys):
    t = np.arange(1000) / 100.0
    data = np.column_stack([np.sin(2 * np.pi * 0.3 * t) + 0.1 * np.sin(2 * np.pi * 7 * t), np.cos(2 * np.pi * 0.5 * t)])
    path = tmp_path / "plain.csv"
    path.write_text("left,right\n" + "\n".join(f"{a:.6f},{b:.6f}" for a, b in data) + "\n")
    common = ["--synthetic", "0", "--backend", "reference", "--no-progress"]
    assert cli([tmp_path / "no-rate", path, *common]) == 2      # refused before the work (issue 43, item 5)
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "plain.csv has no time column" in err and "--fs HZ" in err
    assert not (tmp_path / "no-rate" / "report.md").exists()
    assert cli([tmp_path / "rate", path, "--fs", "100", *common]) == 0
    text = (tmp_path / "rate" / "report.md").read_text()
    assert "| plain | left |" in text and "| plain | right |" in text


def test_bad_jobs_and_cohort_size_are_clear_errors(tmp_path, capsys):
    assert cli([tmp_path, "--synthetic", "-1", "--no-progress"]) == 2
    assert "--synthetic needs a count >= 0" in capsys.readouterr().err
    assert cli([tmp_path, "--synthetic", "1", "--jobs", "0", *COHORT]) == 2
    assert "--jobs must be a positive number" in capsys.readouterr().err
