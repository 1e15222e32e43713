"""The runner's one task model: lazy batches of tasks, stored as they complete, whatever the order."""

import pytest

from wake.eval.compute import ROW_COLUMNS, WAKE_PARAMS, compute_task
from wake.eval.runner import (MAX_BATCH, TaskList, _Progress, _store_results, batch_size, batches, compute_batch,
                              run_tasks)
from wake.eval.sources import cohort_sources
from wake.eval.store import ResultStore


def _tasks(count):
    return TaskList(cohort_sources(count, duration_s=8.0), [WAKE_PARAMS], ["reference"])


def _exact(store, tasks):
    return [tuple((k, repr(v)) for k, v in r.items()) for r in store.rows([t.key for t in tasks])]


def test_batches_are_taken_lazily_from_the_task_stream():
    pulled = []

    def stream():
        for i in range(10):
            pulled.append(i)
            yield i

    groups = batches(stream(), 3)
    assert next(groups) == (0, 1, 2) and pulled == [0, 1, 2]        # nothing read ahead of the first batch
    assert list(groups) == [(3, 4, 5), (6, 7, 8), (9,)]
    with pytest.raises(ValueError, match="at least one task"):
        next(batches([1], 0))


def test_batch_size_gives_every_worker_several_batches_and_stays_small():
    assert batch_size(3, 2) == 1                      # a small cohort: one task per batch, both workers busy
    assert batch_size(10**6, 2) == MAX_BATCH
    for pending in range(0, 200, 7):
        size = batch_size(pending, 2)
        assert 1 <= size <= MAX_BATCH and (size == 1 or pending // size >= 8)


def test_task_list_is_made_as_iterated_in_configuration_order():
    tasks = TaskList(cohort_sources(2, duration_s=8.0), [WAKE_PARAMS, {**WAKE_PARAMS, "level": 4}], ["c"])
    made = list(tasks)
    assert len(tasks) == 4 and [t.source.index for t in made] == [0, 1, 0, 1]
    assert [t.settings["level"] for t in made] == [5, 5, 4, 4] and [t.baselines for t in made] == [1, 1, 0, 0]
    assert [t.key for t in made] == [t.key for t in tasks]         # the same tasks on every pass


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_batches_stored_in_any_completion_order_equal_a_serial_run(tmp_path, fmt):
    if fmt == "parquet":
        pytest.importorskip("pyarrow", reason="the Parquet store needs pyarrow: pip install \".[cohort]\"")
    tasks = _tasks(5)
    serial = ResultStore(tmp_path / "serial", ROW_COLUMNS, format=fmt)
    assert run_tasks(tasks, serial, progress=False) == (5, 0)
    batched = ResultStore(tmp_path / "batched", ROW_COLUMNS, format=fmt)
    done = [compute_batch(b) for b in batches(tasks, 2)]
    assert [len(pairs) for pairs in done] == [2, 2, 1]
    assert _store_results(reversed(done), batched, _Progress(5, 0, False)) == 0     # last batch stored first
    assert len(list((tmp_path / "batched" / "parts").iterdir())) == 3                # one part per batch
    assert _exact(batched, tasks) == _exact(serial, tasks)
    batched.compact()
    serial.compact()
    assert _exact(batched, tasks) == _exact(serial, tasks)


@pytest.mark.slow
@pytest.mark.parametrize("executor", ["joblib", "dask"])
def test_parallel_batches_equal_a_serial_run_bit_for_bit(tmp_path, executor):
    if executor == "joblib":
        pytest.importorskip("joblib", reason="--jobs needs joblib: pip install \".[cohort]\"")
    else:
        pytest.importorskip("distributed", reason="--scheduler needs Dask: pip install \".[dask]\"")
    tasks = _tasks(5)
    serial = ResultStore(tmp_path / "serial", ROW_COLUMNS)
    run_tasks(tasks, serial, progress=False)
    parallel = ResultStore(tmp_path / "parallel", ROW_COLUMNS)
    where = {"scheduler": "local"} if executor == "dask" else {}
    assert run_tasks(tasks, parallel, jobs=2, batch=2, progress=False, **where) == (5, 0)
    assert len(list((tmp_path / "parallel" / "parts").iterdir())) == 3                # batches of 2, 2, 1
    assert _exact(parallel, tasks) == _exact(serial, tasks)


def test_a_task_in_several_parts_reads_as_its_latest_record(tmp_path):
    pytest.importorskip("pyarrow", reason="the Parquet store needs pyarrow: pip install \".[cohort]\"")
    tasks = list(_tasks(2))
    rows = {t.key: compute_task(t) for t in tasks}
    failed = [{**rows[tasks[0].key][0], "error": "OSError: the disk was away"}]
    store = ResultStore(tmp_path, ROW_COLUMNS)
    store.add_many([(tasks[0].key, failed), (tasks[1].key, rows[tasks[1].key])])    # a batch with a failure
    assert store.done() == {tasks[1].key}
    store.add_many([(tasks[0].key, rows[tasks[0].key])])                              # the rerun's batch
    assert store.done() == {t.key for t in tasks}
    want = [tuple((k, repr(v)) for k, v in r.items()) for t in tasks for r in rows[t.key]]
    assert _exact(store, tasks) == want
    store.compact()
    assert _exact(store, tasks) == want                                               # the failure is gone
