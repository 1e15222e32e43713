"""WakeFilter on the fixed-point C backend against the float reference."""

import numpy as np
import pytest

from support import NO_PADS, has_c_backend, pads_dir
from wake import WakeFilter
from wake.eval.metrics import nrmse, offline_ground_truth

pytestmark = pytest.mark.skipif(not has_c_backend(), reason="the compiled C core wake._rtp is not built")


def test_c_matches_reference_on_the_synthetic_set(paper_signals):
    for s in paper_signals:
        c = WakeFilter(backend="c").run(s.measurement)
        r = WakeFilter(backend="reference").run(s.measurement)
        nc, nr = nrmse(s.voluntary, c.voluntary, 500), nrmse(s.voluntary, r.voluntary, 500)
        assert abs(nc - nr) <= 0.01 * nr
        assert c.clipped[0] == 0 and c.saturations[0] == 0
        # the float reference runs until the first HPA (a warm-up HPA at 1 s): bit-identical until then
        first = c.hpa[0][0].index
        assert first == 100 == r.hpa[0][0].index
        np.testing.assert_array_equal(c.voluntary[:first], r.voluntary[:first])


@pytest.mark.parametrize("k", [10, 499, 500, 777])
def test_causal_with_automatic_full_scale(k, signal10):
    x = signal10.measurement[:1500].copy()
    base = WakeFilter(backend="c").run(x).voluntary
    x[k:] *= 7.0
    assert np.array_equal(base[: k + 1], WakeFilter(backend="c").run(x).voluntary[: k + 1])


def test_run_equals_update_on_c(signal10):
    x = signal10.measurement[:1300]
    f = WakeFilter(backend="c")
    res = f.run(x)
    stream = [0.0] + [f.update(v) for v in x[:-1]]
    np.testing.assert_array_equal(res.voluntary, stream)


def test_full_scale_too_small_is_counted_not_silent(signal10):
    from wake import ClippingWarning

    with pytest.warns(ClippingWarning, match=r"clipped at the fixed-point full scale ±0\.2") as caught:
        res = WakeFilter(backend="c", full_scale=0.2).run(signal10.measurement[:1500])
    clipping = [w for w in caught if issubclass(w.category, ClippingWarning)]
    # one warning per HPA whose window clipped (warm-up HPAs included), each flagged in the history
    assert len(clipping) == sum("clipping" in u.flags for u in res.hpa[0]) == len(res.hpa[0]) == 7
    assert res.clipped[0] > 0
    assert np.all(np.isfinite(res.voluntary))
    assert any("noise_clamped" in u.flags for u in res.hpa[0])


def test_explicit_full_scale_runs_c_from_the_first_sample(signal10):
    res = WakeFilter(backend="c", full_scale=8.0).run(signal10.measurement[:1000])
    ref = WakeFilter(backend="reference").run(signal10.measurement[:1000])
    assert res.full_scale[0] == 8.0
    assert not np.array_equal(res.voluntary[1:500], ref.voluntary[1:500])  # quantised from the start
    assert np.max(np.abs(res.voluntary - ref.voluntary)) < 1e-3 * 8.0


def test_live_kalman_on_c_matches_reference(signal10):
    kw = dict(process_noise_ratio=1e-4, initial_covariance=0.01)
    c = WakeFilter(backend="c", **kw).run(signal10.measurement)
    r = WakeFilter(backend="reference", **kw).run(signal10.measurement)
    nc = nrmse(signal10.voluntary, c.voluntary, 500)
    nr = nrmse(signal10.voluntary, r.voluntary, 500)
    assert abs(nc - nr) <= 0.01 * nr


@pytest.mark.slow
@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_c_matches_reference_on_real_recordings():
    from wake.eval.datasets import load_pads_folder

    for rec in load_pads_folder(pads_dir()):
        for c in range(rec.samples.shape[1]):
            x = rec.samples[:, c]
            ref = WakeFilter(backend="reference").run(x)
            fix = WakeFilter(backend="c").run(x)
            truth = offline_ground_truth(x, 100.0, ref.mean_cutoff[0])[1]
            nr = nrmse(truth, ref.tremor, 500)
            nc = nrmse(truth, fix.tremor, 500)
            assert abs(nc - nr) <= 0.01 * nr, (rec.name, c, nc, nr)
            assert fix.clipped[0] == 0 and fix.saturations[0] == 0


def test_gap_in_the_first_window_still_sets_a_finite_full_scale(signal10):
    x = signal10.measurement[:1200].copy()
    x[100:130] = np.nan
    f = WakeFilter(backend="c")
    y = f.update_block(x)
    assert np.all(np.isfinite(y))
    # the full-scale policy (wake.rtp.full_scale): a power of two above 16x the window's robust peak
    peak = np.nanquantile(np.abs(x[:500]), 0.99, method="lower")
    assert f.rtp_states[0].full_scale == 2.0 ** np.ceil(np.log2(16 * peak))
