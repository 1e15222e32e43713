"""WakeConfig.gate_cutoff: the gate's held-out gain measured above max(f_d, gate_cutoff) (issue 46)."""

import numpy as np
import pytest
from support import NO_PDKIT, has_c_backend, pdkit_dir

from wake import WakeConfig, WakeFilter
from wake.eval.strong_tremor import make_strong_tremor


def voluntary_rhythm(fs, seconds=30.0):
    """A pronation-supination-like voluntary rhythm: 3.1 Hz, not sinusoidal (a second harmonic), a slow drift."""
    t = np.arange(int(seconds * fs)) / fs
    phase = 2 * np.pi * 3.1 * t + 0.3 * np.sin(2 * np.pi * 0.1 * t)
    noise = 0.01 * np.random.default_rng(0).standard_normal(t.size)
    return np.sin(phase) + 0.3 * np.sin(2 * phase + 1.0) + 0.5 * np.sin(2 * np.pi * 0.3 * t) + noise


def test_settings_are_validated_naming_the_fix():
    with pytest.raises(ValueError, match="below fs/2 = 50 Hz"):
        WakeConfig(gate_cutoff=50.0)
    with pytest.raises(ValueError, match="gate_cutoff"):
        WakeConfig(gate_cutoff=0.0)
    assert WakeConfig(gate_cutoff=4.0, hpa_backend="c").gate_cutoff == 4.0   # the C HPA has it too
    assert WakeConfig(gate_cutoff=4).gate_cutoff == 4.0


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_a_gate_cutoff_below_every_hpa_cutoff_is_todays_gate_bit_for_bit(fs):
    # the HPA's cut-off never falls below cutoff_range[0] = 0.5 Hz: a gate cut-off under it changes nothing
    sig = make_strong_tremor(seed=4, fs=fs, duration=14.0, kind="accelerometer")
    h = int(0.05 * fs)
    a = WakeFilter(fs=fs, horizon=h, backend="reference").run(sig.measurement)
    b = WakeFilter(fs=fs, horizon=h, backend="reference", gate_cutoff=0.4).run(sig.measurement)
    assert np.array_equal(a.command, b.command) and np.array_equal(a.voluntary, b.voluntary)


@pytest.mark.parametrize("fs", [100.0, 1000.0])
def test_a_voluntary_3_hz_rhythm_no_longer_opens_the_gate_and_a_6_hz_tremor_still_does(fs):
    lo, h = int(5 * fs), int(0.02 * fs)
    x = voluntary_rhythm(fs)
    today = WakeFilter(fs=fs, horizon=h, backend="reference").run(x).confidence[lo:].mean()
    gated = WakeFilter(fs=fs, horizon=h, backend="reference", gate_cutoff=4.0).run(x).confidence[lo:].mean()
    assert today > 0.9 and gated < 0.3
    sig = make_strong_tremor(seed=3, fs=fs, duration=30.0, f0=6.0)
    runs = [WakeFilter(fs=fs, horizon=h, backend="reference", gate_cutoff=g).run(sig.measurement) for g in (None, 4.0)]
    conf = [r.confidence[lo:].mean() for r in runs]
    err = [np.sqrt(np.mean((r.command[lo:] - sig.tremor[lo:]) ** 2)) for r in runs]
    assert conf[1] > 0.9 and conf[1] == pytest.approx(conf[0], abs=0.02)
    assert err[1] == pytest.approx(err[0], rel=0.02)


def test_pdkit_no_harm_on_all_39_axes_and_below_zero_on_the_13_tremor_axes_at_20_ms():
    """Issue 46's do-no-harm targets with ridge_scale='centred' and gate_cutoff=4 (20 ms; the study has every
    horizon: docs/studies/design.md)."""
    folder = pdkit_dir()
    if folder is None:
        pytest.skip(NO_PDKIT)
    from wake.eval.pdkit import load_pdkit_folder, tremor_axes
    from wake.eval.truth import tremor_truth
    from wake.eval.warmup import SLICES, slice_nrmse

    recs = load_pdkit_folder(folder)
    tremor = {(id(r), c) for r, c in tremor_axes(recs)}
    backend = "c" if has_c_backend() else "reference"
    rows, zero, below = [], [], 0
    for r in recs:
        for c in range(r.recording.samples.shape[1]):
            x, fs = r.recording.samples[:, c].astype(float), r.recording.fs
            truth = tremor_truth(x, fs)[1]
            res = WakeFilter(fs=fs, horizon=2, backend=backend, ridge_scale="centred", gate_cutoff=4.0).run(x)
            rows.append(slice_nrmse(truth, res.command, fs))
            zero.append(slice_nrmse(truth, np.zeros_like(x), fs))
            below += (id(r), c) in tremor and rows[-1]["after 5 s"] < zero[-1]["after 5 s"]
    for s in SLICES:
        assert np.nanmean([q[s] for q in rows]) <= np.nanmean([z[s] for z in zero]) * (1 + 1e-9), s
    assert below == 13
