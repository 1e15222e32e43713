"""Host speed of WAKE (pytest-benchmark).

    pytest bench/ --benchmark-only                 # all, with a summary of throughputs and ratios
    pytest bench/ --benchmark-only -k block        # one group

What is measured (one core, single thread):

* ``test_c_block_run``: ``FixedPointRTP.run`` on 10^6 samples, zero-copy
  numpy buffers through cffi (quantisation of the input included).
  Target: >= 5 million samples/s.
* ``test_c_block_run_raw``: ``wake_rtp_run`` on ready int16 buffers (the
  C loop alone, no quantisation).
* ``test_c_step_per_sample``: ``FixedPointRTP.step`` from Python, one call
  per sample.
* ``test_filter_update_per_sample``: ``WakeFilter(backend="c").update``,
  one call per sample, HPA every window included.
* ``test_hpa_per_update``: one ``wake.hpa.run_hpa`` on a 5 s window.
* ``test_hpa_long_window``: one ``run_hpa`` on a 200 s window of a 1 kHz
  sensor (L = 2e5).  Target: < 0.5 s (the autocorrelation takes only the
  p + 1 lags it needs; the full correlation took 4 s here).
* ``test_reference_block_run``: the float64 reference ``ReferenceRTP.run``
  with the Kalman correction inert (q = 0, P = 0, the filter's default),
  where it is one vectorised filter-bank product.
* ``test_reference_block_run_kalman``: the same with the Kalman correction
  active (q > 0, p0 > 0): a Python loop per sample.
* ``test_end_to_end_c``: a 50 s, 100 Hz recording through
  ``WakeFilter(backend="c").run``, HPA included.

The summary (bench/conftest.py) prints medians, IQR and ratios of the same
run; the targets are reported there, not asserted. The speed targets CI
holds the code to are ratios measured in one process, in
``bench/speed_gate.py`` (``run`` and ``update`` against fixed units, one
cohort task), which fails when one exceeds its ceiling.
"""

import numpy as np
import pytest

from wake import WakeConfig, WakeFilter
from wake.hpa import run_hpa
from wake.rtp.reference import ReferenceRTP

cb = pytest.importorskip("wake.rtp.fixed", reason="the C extension wake._rtp is not built (pip install -e .)")

N_BLOCK = 1_000_000
N_STEP = 2_000
N_REFERENCE = 5_000


def _rtp(fitted):
    return cb.FixedPointRTP(fitted["taps"], fitted["weights"], fitted["R"], 0.0, 0.0,
                            full_scale=fitted["full_scale"])


def _block_input(fitted, n):
    """n samples: the recording repeated, within full scale."""
    return np.resize(fitted["window"], n)


def test_c_block_run(benchmark, fitted):
    rtp = _rtp(fitted)
    x = _block_input(fitted, N_BLOCK)
    benchmark.extra_info.update(items=N_BLOCK, unit="samples")
    out = benchmark(rtp.run, x)
    assert out.shape == (N_BLOCK,) and np.isfinite(out).all()


def test_c_block_run_raw(benchmark, fitted):
    rtp = _rtp(fitted)
    x_q = rtp._quantize_samples(_block_input(fitted, N_BLOCK))
    out_q = np.empty_like(x_q)
    lib, ffi = cb.lib, cb.ffi
    in_c = ffi.from_buffer("int16_t[]", x_q)
    out_c = ffi.from_buffer("int16_t[]", out_q)
    benchmark.extra_info.update(items=N_BLOCK, unit="samples")
    status = benchmark(lib.wake_rtp_run, rtp._state, in_c, out_c, N_BLOCK)
    assert status == lib.WAKE_RTP_OK


def test_c_step_per_sample(benchmark, fitted):
    rtp = _rtp(fitted)
    x = [float(v) for v in _block_input(fitted, N_STEP)]

    def run():
        step = rtp.step
        for v in x:
            step(v)

    benchmark.extra_info.update(items=N_STEP, unit="samples")
    benchmark(run)


def test_filter_update_per_sample(benchmark, recording):
    x = recording.measurement[:N_STEP]

    def run():
        filt = WakeFilter(fs=recording.fs, backend="c")
        update = filt.update
        for v in x:
            update(v)

    benchmark.extra_info.update(items=N_STEP, unit="samples")
    benchmark(run)


def test_hpa_per_update(benchmark, fitted):
    benchmark.extra_info.update(items=1, unit="HPA runs")
    upd = benchmark(run_hpa, fitted["window"], WakeConfig(fs=fitted["fs"], backend="reference"), taps=fitted["taps"])
    assert np.isfinite(upd.weights).all()


def test_hpa_long_window(benchmark, recording):
    fs, n = 1000.0, 200_000
    window = np.resize(recording.measurement, n)
    config = WakeConfig(fs=fs, backend="reference", window_s=n / fs)
    benchmark.extra_info.update(items=1, unit="HPA runs")
    upd = benchmark.pedantic(run_hpa, args=(window, config), rounds=5, iterations=1)
    assert np.isfinite(upd.weights).all()


def test_reference_block_run(benchmark, fitted):
    rtp = ReferenceRTP(fitted["taps"], fitted["weights"], fitted["R"])
    x = _block_input(fitted, N_REFERENCE)
    benchmark.extra_info.update(items=N_REFERENCE, unit="samples")
    benchmark(rtp.run, x)


def test_reference_block_run_kalman(benchmark, fitted):
    r = fitted["R"]
    rtp = ReferenceRTP(fitted["taps"], fitted["weights"], r, 1e-3 * r, r)
    x = _block_input(fitted, N_REFERENCE)
    benchmark.extra_info.update(items=N_REFERENCE, unit="samples")
    benchmark(rtp.run, x)


def test_end_to_end_c(benchmark, recording):
    filt = WakeFilter(fs=recording.fs, backend="c")
    benchmark.extra_info.update(items=recording.measurement.size, unit="samples")
    res = benchmark(filt.run, recording.measurement)
    assert res.backend == "c" and np.isfinite(res.voluntary).all()
