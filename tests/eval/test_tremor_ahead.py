"""The tremor ahead scored: do no harm in every slice of time since start, the issue's targets, the baselines'
own extrapolation (docs/studies/design.md, "Tremor ahead")."""

import numpy as np
import pytest

from support import NO_PADS, has_c_backend, pads_dir
from wake.eval.baselines import BMFLC, EBMFLC, WFLC
from wake.eval.synthetic import make_signal, paper_dataset
from wake.eval.tremor_ahead import GATED, ORACLE, WIENER, ZERO, ahead_scores, aligned, baselines_ahead
from wake.eval.warmup import SLICES, independent_ground_truth

BACKEND = "c" if has_c_backend() else "reference"
HORIZONS_MS = (10, 20, 50, 100)      # h = 1, 2, 5 and 10 samples at 100 Hz


def _means(cases):
    """{ms: {method: {slice: mean over axes}}} of ahead_scores over (x, fs, truth) cases, without baselines."""
    acc = {}
    for x, fs, truth in cases:
        for ms, methods in ahead_scores(x, fs, truth, backend=BACKEND, baselines=False).items():
            for name, per_axis in methods.items():
                acc.setdefault(ms, {}).setdefault(name, []).extend(per_axis)
    return {ms: {n: {s: float(np.nanmean([r[s] for r in v])) for s in SLICES} for n, v in m.items()}
            for ms, m in acc.items()}


@pytest.fixture(scope="module")
def synthetic():
    return _means([(s.measurement[:, None], s.fs, s.tremor[:, None]) for s in paper_dataset()])


@pytest.fixture(scope="module")
def pads():
    folder = pads_dir()
    if folder is None:
        pytest.skip(NO_PADS)
    from wake.eval.datasets import load_pads_folder

    cases = []
    for rec in load_pads_folder(folder):
        x = rec.samples.astype(float)
        truth = np.column_stack([independent_ground_truth(x[:, c], rec.fs)[1] for c in range(x.shape[1])])
        cases.append((x, rec.fs, truth))
    return _means(cases)


@pytest.mark.slow
@pytest.mark.parametrize("ms", HORIZONS_MS)
def test_the_command_does_no_harm_on_the_synthetic_set_in_any_slice(synthetic, ms):
    m = synthetic[ms]
    for s in SLICES:
        assert m[GATED][s] <= m[ZERO][s] * (1 + 1e-12), (s, m[GATED][s], m[ZERO][s])
    # and the limits are limits: the oracle below the Wiener limit below zero after 5 s
    assert m[ORACLE]["after 5 s"] < m[WIENER]["after 5 s"] < m[ZERO]["after 5 s"]


@pytest.mark.parametrize("ms", [10, 20, 50])
def test_the_command_beats_zero_after_5_s_on_the_synthetic_set(synthetic, ms):
    assert synthetic[ms][GATED]["after 5 s"] < synthetic[ms][ZERO]["after 5 s"]


@pytest.mark.slow
@pytest.mark.parametrize("ms", [10, 20, 50, 100])
def test_the_command_does_no_harm_on_pads_in_any_slice(pads, ms):
    m = pads[ms]
    for s in SLICES:
        assert m[GATED][s] <= m[ZERO][s] * (1 + 1e-12), (s, m[GATED][s], m[ZERO][s])


def test_the_issues_targets_on_pads_after_5_s(pads):
    zero = pads[10][ZERO]["after 5 s"]
    assert pads[10][GATED]["after 5 s"] < zero
    assert pads[20][GATED]["after 5 s"] <= 0.85 * zero
    assert pads[50][GATED]["after 5 s"] <= 0.95 * zero


def test_the_baselines_extrapolation_at_one_sample_is_their_own_model_tremor():
    s = make_signal(5.0, seed=4, duration=8.0)
    x = np.column_stack([s.measurement, 0.5 * s.measurement])
    P = baselines_ahead(x, s.fs, (1, 3))
    for name, method in (("BMFLC", BMFLC(fs=s.fs)), ("E-BMFLC", EBMFLC(fs=s.fs)), ("WFLC", WFLC(fs=s.fs))):
        model = method.run(x).model_tremor
        np.testing.assert_allclose(P[name][1][:-1], model[1:], atol=1e-12 * np.abs(model).max())
        assert not np.allclose(P[name][3], P[name][1])


def test_aligned_plays_each_prediction_h_samples_later():
    np.testing.assert_array_equal(aligned(np.arange(1.0, 6.0), 2), [0, 0, 1, 2, 3])
