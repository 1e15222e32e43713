"""One filter used the way real programs use it: from two threads, for hours, with odd inputs.

Each test here reproduces a fault a careless or concurrent caller met: HPA
results applied twice or lost when two threads called ``update()``, worker
threads left running, a history that grew without bound, a masked value
used as data, a byte-order mark that cost the first sample, and ``update()``
coercing ``True`` or ``"1.5"`` into a sample.
"""

import threading

import numpy as np
import pytest

from support import NO_CORE, has_c_backend
from wake import WakeConfig, WakeFilter
from wake.eval.datasets import load_csv

BACKENDS = ["reference", pytest.param("c", marks=pytest.mark.skipif(not has_c_backend(), reason=NO_CORE))]


@pytest.mark.parametrize("backend", BACKENDS)
def test_two_threads_on_one_filter_install_every_hpa_once_and_in_order(backend):
    per_thread, trials = 1_500, 4
    x = np.sin(np.arange(per_thread) / 7.0) + 0.3 * np.sin(np.arange(per_thread) * 0.4)
    for _ in range(trials):
        filt = WakeFilter(fs=100.0, backend=backend, hpa_mode="thread")
        filt.update(0.0)  # one channel, so both threads take the hot path
        errors, start = [], threading.Barrier(2)

        def feed():
            try:
                start.wait()
                for v in x:
                    filt.update(float(v))
            except Exception as exc:  # noqa: BLE001 - reported below
                errors.append(exc)

        threads = [threading.Thread(target=feed) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        filt.close()
        assert errors == []
        total = 1 + 2 * per_thread
        history = filt.hpa_history[0]
        # every HPA once, in order (warm-up at 1, 2, 3, 4 s, then every window), installed after it was asked for
        assert [u.index for u in history] == [100, 200, 300, 400] + list(range(500, total + 1, 500))
        applied = [u.applied_at for u in history]
        assert applied == sorted(applied) and len(set(applied)) == len(applied)
        assert all(u.applied_at > u.index for u in history)
        assert filt.rtp_states[0] is not None


def test_context_manager_stops_the_worker_thread():
    x = np.sin(np.arange(700) / 9.0)
    with WakeFilter(fs=100.0, backend="reference", hpa_mode="thread") as filt:
        for v in x:
            filt.update(float(v))
        workers = list(filt._pool._threads)
        assert workers and all(t.is_alive() for t in workers)
    assert not any(t.is_alive() for t in workers)
    assert filt._pool is None
    # nothing in flight was lost: close() installs it first
    assert [u.index for u in filt.hpa_history[0]] == [100, 200, 300, 400, 500]
    # and the filter stays usable
    assert np.isfinite(filt.update(0.1))


def test_hpa_history_keeps_the_newest_updates_only():
    x = np.sin(np.arange(3_000) / 9.0)
    filt = WakeFilter(fs=100.0, backend="reference", hpa_history_limit=3)
    filt.update_block(x)
    assert [u.index for u in filt.hpa_history[0]] == [2_000, 2_500, 3_000]
    # run() returns every update of the recording it was given
    assert [u.index for u in filt.run(x).hpa[0]] == [100, 200, 300, 400, 500, 1_000, 1_500, 2_000, 2_500, 3_000]
    # the bound survives a snapshot
    g = WakeFilter(config=filt.config)
    g.set_state(filt.get_state())
    g.update_block(x[:500])
    assert [u.index for u in g.hpa_history[0]] == [2_500, 3_000, 3_500]


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "10"])
def test_hpa_history_limit_is_validated(bad):
    with pytest.raises(ValueError, match="hpa_history_limit"):
        WakeConfig(hpa_history_limit=bad)


@pytest.mark.parametrize("bad", [True, None, "1.5", b"1", np.bool_(False), [[1.0]], [], 1 + 2j])
def test_update_refuses_what_run_refuses(bad):
    filt = WakeFilter(fs=100.0, backend="reference")
    with pytest.raises(ValueError, match="sample"):
        filt.update(bad)
    assert filt.hpa_history == []  # nothing was started by the refused sample


def test_update_accepts_numpy_and_integer_scalars_like_run():
    a, b = WakeFilter(backend="reference"), WakeFilter(backend="reference")
    x = [1, 2.5, np.float32(0.5), np.int16(-3)]
    assert [a.update(v) for v in x] == [b.update(float(v)) for v in x]


def test_masked_values_are_missing_samples_not_data():
    x = np.sin(np.arange(1_200) / 9.0)
    masked = np.ma.array(x.copy(), mask=np.zeros(x.size, bool))
    masked[[5, 700]] = 1e6
    masked[[5, 700]] = np.ma.masked
    with_nan = x.copy()
    with_nan[[5, 700]] = np.nan
    filt = WakeFilter(fs=100.0, backend="reference")
    np.testing.assert_array_equal(filt.run(masked).prediction, filt.run(with_nan).prediction)
    np.testing.assert_array_equal(filt.update_block(masked), WakeFilter(backend="reference").update_block(with_nan))
    s = WakeFilter(backend="reference")
    assert s.update(np.ma.masked_array([2.0], mask=[True]))[0] == s.update(np.ma.masked_array([2.0], mask=[True]))[0]


def test_csv_with_a_byte_order_mark_keeps_its_first_sample(tmp_path):
    path = tmp_path / "export.csv"
    path.write_bytes("\ufeff0.5\n1.5\n2.5\n".encode("utf-8"))
    np.testing.assert_array_equal(load_csv(path, fs=100.0).samples[:, 0], [0.5, 1.5, 2.5])
    path.write_bytes("\ufeffgyro_x,gyro_y\n1,2\n3,4\n".encode("utf-8"))
    rec = load_csv(path, column="gyro_x", fs=100.0)
    assert rec.channels == ("gyro_x",)
    np.testing.assert_array_equal(rec.samples[:, 0], [1.0, 3.0])


def test_dropped_filters_stop_their_workers_without_garbage_collection():
    import gc

    x = np.sin(np.arange(520) / 10.0)
    ours = lambda: [t for t in threading.enumerate() if t.name.startswith("wake-hpa")]  # noqa: E731
    before = set(ours())
    gc.disable()
    try:
        for _ in range(20):
            filt = WakeFilter(fs=100.0, backend="reference", hpa_mode="thread")
            filt.update_block(x[:499])
            for v in x[499:]:
                filt.update(float(v))  # starts the worker
            del filt
    finally:
        gc.enable()
    left = [t for t in ours() if t not in before]
    for t in left:
        t.join(timeout=5.0)
    assert not [t for t in left if t.is_alive()]
