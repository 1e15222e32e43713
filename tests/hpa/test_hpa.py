import numpy as np
import pytest

from wake import WakeConfig
from wake.hpa import CUTOFF_FLAGS, find_cutoff, fit_weights, run_hpa
from wake.hpa.sharp import sharp_highpass
from wake.eval.synthetic import make_signal
from wake.wavelets import filter_bank_taps

FS = 100.0
TAPS = filter_bank_taps("sym3", 5)
CONFIG = WakeConfig(fs=FS, backend="reference")


def window_of(kind, rng, n=500):
    t = np.arange(n) / FS
    return {
        "silence": np.zeros(n),
        "constant": np.full(n, 3.0),
        "pure_tremor": 0.5 * np.sin(2 * np.pi * 7 * t),
        "pure_voluntary": np.sin(2 * np.pi * 0.5 * t),
        "white_noise": rng.normal(size=n),
        "step": np.where(t < 2.5, 0.0, 1.0),
        "tiny": 1e-9 * np.sin(2 * np.pi * 0.5 * t) + 1e-10 * np.sin(2 * np.pi * 8 * t),
        "huge": 1e6 * (np.sin(2 * np.pi * 0.5 * t) + 0.2 * np.sin(2 * np.pi * 8 * t)),
    }[kind]


def test_valley_found_between_bands():
    f = np.linspace(0, 50, 513)
    psd = np.exp(-f / 0.4) + 0.1 * np.exp(-((f - 9) ** 2) / 2)
    fd, flag = find_cutoff(f, psd)
    assert flag == "valley"
    assert 2.0 < fd < 6.0


def test_no_tremor_peak_falls_back():
    f = np.linspace(0, 50, 513)
    fd, flag = find_cutoff(f, np.exp(-f), default_cutoff=2.5)
    assert (fd, flag) == (2.5, "no_tremor_peak")


def test_shallow_dip_is_not_a_valley():
    f = np.linspace(0, 50, 513)
    psd = 1.0 + 0.1 * np.exp(-((f - 8) ** 2))  # a 0.4 dB bump on a flat floor
    fd, flag = find_cutoff(f, psd, rule="paper")
    assert flag in ("no_valley", "no_tremor_peak") and fd == 2.0
    # the floor rises from 0.5 Hz into the bump: no dip for the shallow rule either
    assert find_cutoff(f, psd, rule="shallow") == (2.0, "no_valley")
    # with voluntary content falling into the floor, the shallow rule takes the minimum, never above shallow_max
    fd, flag = find_cutoff(f, psd + 0.05 * np.exp(-f / 0.5), rule="shallow")
    assert flag == "shallow_valley" and 0.5 < fd <= 4.0


def test_shallow_rule_takes_the_minimum_below_a_tremor_peak():
    f = np.linspace(0, 50, 513)
    # voluntary content falling into a 1 dB dip before a tremor peak at 6 Hz: no 3 dB valley
    psd = 1.0 + np.exp(-f / 1.0) + 0.3 * np.exp(-((f - 6) ** 2) / 0.5)
    assert find_cutoff(f, psd, rule="paper") == (2.0, "no_valley")
    fd, flag = find_cutoff(f, psd, rule="shallow")
    search = (f >= 0.5) & (f <= min(4.0, f[np.argmax(np.where(f > 2.5, psd, 0))]))
    assert flag == "shallow_valley" and fd == f[search][np.argmin(psd[search])]
    # no tremor peak: the default stays, whatever the rule
    assert find_cutoff(f, np.exp(-f), rule="shallow") == (2.0, "no_tremor_peak")
    with pytest.raises(ValueError, match="valid choices: paper, shallow, floor"):
        find_cutoff(f, psd, rule="deep")


def test_shallow_rule_stops_at_shallow_max():
    """A shallow dip above shallow_max (4 Hz) is not taken: the minimum at or below it is."""
    f = np.linspace(0, 50, 1023)
    # voluntary content, a shallow dip at 5 Hz, a tremor peak at 8 Hz
    psd = 1.0 + 2.0 * np.exp(-f / 0.5) - 0.2 * np.exp(-((f - 5) ** 2) / 0.5) + 0.3 * np.exp(-((f - 8) ** 2) / 0.5)
    fd6, flag6 = find_cutoff(f, psd, rule="shallow", shallow_max=6.0)
    assert flag6 == "shallow_valley" and abs(fd6 - 5.0) < 0.1
    fd, flag = find_cutoff(f, psd, rule="shallow")
    low = (f >= 0.5) & (f <= 4.0)
    assert flag == "shallow_valley" and fd == f[low][np.argmin(psd[low])] and fd <= 4.0
    # the deep valley of the paper rule is not capped
    deep = np.exp(-f / 0.4) + 0.1 * np.exp(-((f - 9) ** 2) / 2)
    assert find_cutoff(f, deep, rule="shallow", shallow_max=1.0) == find_cutoff(f, deep, rule="paper")
    # fewer than 3 bins from cutoff_range[0] up to shallow_max: the default, flagged no_valley
    assert find_cutoff(f, psd, rule="shallow", shallow_max=0.5) == (2.0, "no_valley")
    for bad in (0.25, float("nan"), "4", True):
        with pytest.raises(ValueError, match="shallow_max"):
            find_cutoff(f, psd, shallow_max=bad)
    with pytest.raises(ValueError, match="shallow_max must be at least cutoff_range"):
        WakeConfig(shallow_max=0.25)


def test_the_floor_rule_is_the_default():
    """docs/studies/design.md, "Cut-off on real wear": the 'floor' rule lowers the whole-recording error on PADS and on
    the synthetic set against the paper's rule, so it is the default (tests/test_warmup.py pins the scores)."""
    assert (WakeConfig().cutoff_rule, WakeConfig().shallow_max) == ("floor", 4.0)
    assert CUTOFF_FLAGS["floor_valley"].startswith("rule 'floor'")


def floor_spectrum(f, floor_db):
    """Voluntary content below 1.5 Hz, a flat noise floor `floor_db` below it, a tremor peak at 8 Hz."""
    return np.exp(-f / 0.3) + 10 ** (-floor_db / 10) * (1 + 10 * np.exp(-((f - 8) ** 2) / 0.5))


def test_floor_rule_moves_a_valley_at_the_noise_floor_to_its_low_edge():
    """A valley that is the flat noise floor between the bands: its minimum falls anywhere in the gap, so the
    'floor' rule takes the gap's low edge, the lowest frequency from which the PSD stays within 3 dB of it."""
    f = np.linspace(0, 50, 512)
    psd = floor_spectrum(f, 40.0) * (1 + 0.01 * np.cos(2 * np.pi * f / 3.1))   # ripple: the minimum lies at random
    fd_paper, flag_paper = find_cutoff(f, psd, rule="paper")
    fd, flag = find_cutoff(f, psd, rule="floor")
    assert flag_paper == "valley" and flag == "floor_valley"
    db = 10 * np.log10(psd)
    valley = np.argmin(np.abs(f - fd_paper))
    edge = np.argmin(np.abs(f - fd))
    # every bin from the edge to the valley is within 3 dB of the valley, the bin below the edge is not
    assert np.all(db[edge:valley + 1] <= db[valley] + 3.0) and db[edge - 1] > db[valley] + 3.0
    assert 0.5 <= fd < fd_paper and fd < 3.0
    # the same valley well above the floor (15 dB or more) stays where it is
    deep = np.exp(-f / 0.4) + 0.1 * np.exp(-((f - 9) ** 2) / 2)
    assert find_cutoff(f, deep, rule="floor") == find_cutoff(f, deep, rule="paper")
    # the edge never goes below cutoff_range[0]
    assert find_cutoff(f, psd, rule="floor", edge_db=80.0)[0] == f[f >= 0.5][0]


def test_floor_rule_takes_a_shallow_dip_only_well_above_the_noise_floor():
    f = np.linspace(0, 50, 512)
    # a shoulder: the voluntary content runs into a tremor peak at 6 Hz with a 1 dB dip, 30 dB above the floor
    shoulder = 1.0 + np.exp(-f / 1.0) + 0.3 * np.exp(-((f - 6) ** 2) / 0.5) + 1e-3 * (f > 15)
    shoulder[f > 15] = 1e-3
    assert find_cutoff(f, shoulder, rule="floor") == find_cutoff(f, shoulder, rule="shallow")
    assert find_cutoff(f, shoulder, rule="floor")[1] == "shallow_valley"
    # a weak tremor bump on a flat floor: the dip is the floor itself, so the default stays
    flat = 1.0 + 0.1 * np.exp(-((f - 8) ** 2)) + 0.05 * np.exp(-f / 0.5)
    assert find_cutoff(f, flat, rule="shallow")[1] == "shallow_valley"
    assert find_cutoff(f, flat, rule="floor") == (2.0, "no_valley")
    # the margin decides: the shoulder's dip lies 30 dB above its floor
    assert find_cutoff(f, shoulder, rule="floor", floor_margin_db=40.0) == (2.0, "no_valley")
    # no bins above the tremor band: no floor, the rule acts as 'shallow'
    low = f <= 15
    assert find_cutoff(f[low], flat[low], rule="floor") == find_cutoff(f[low], flat[low], rule="shallow")
    for name in ("floor_margin_db", "edge_db"):
        for bad in (0.0, -3.0, float("inf"), "3", True):
            with pytest.raises(ValueError, match=name):
                find_cutoff(f, flat, rule="floor", **{name: bad})


def test_cutoff_argument_checks():
    f = np.linspace(0, 50, 10)
    with pytest.raises(ValueError, match="default_cutoff"):
        find_cutoff(f, np.ones(10), default_cutoff=9.0)
    with pytest.raises(ValueError, match="tremor_band"):
        find_cutoff(f, np.ones(10), tremor_band=(9.0, 3.0))


def test_fit_weights_is_least_squares(rng):
    A = rng.normal(size=(200, 4))
    y = rng.normal(size=200)
    w, err, used = fit_weights(A, y, ridge=0.0)
    np.testing.assert_allclose(w, np.linalg.lstsq(A, y, rcond=None)[0], atol=1e-10)
    assert err == pytest.approx(np.sqrt(np.mean((A @ w - y) ** 2)))
    # the minimum: any perturbation raises e_L
    for _ in range(5):
        w2 = w + 0.01 * rng.normal(size=4)
        assert np.sqrt(np.mean((A @ w2 - y) ** 2)) > err


def test_ill_conditioned_fit_is_regularised(rng):
    a = rng.normal(size=300)
    A = np.column_stack([a, a + 1e-12 * rng.normal(size=300), rng.normal(size=300)])
    w, err, used = fit_weights(A, a + 0.1 * rng.normal(size=300), ridge=0.0, weight_limit=5.0)
    assert np.all(np.isfinite(w)) and np.max(np.abs(w)) <= 5.0
    assert used > 0


def test_hpa_on_synthetic_window():
    s = make_signal(7.5, seed=1)
    upd = run_hpa(s.measurement[:500], CONFIG, taps=TAPS)
    # the synthetic set's gap between the bands is the sensor-noise floor: the default rule takes its low edge
    assert upd.cutoff_flag == "floor_valley"
    paper = run_hpa(s.measurement[:500], WakeConfig(fs=FS, backend="reference", cutoff_rule="paper"), taps=TAPS)
    assert paper.cutoff_flag == "valley" and 1.0 < upd.cutoff < paper.cutoff < 6.0
    # the truth is the sharp high-pass of the window minus its end-point line
    x = s.measurement[:500]
    line = x[0] + (x[-1] - x[0]) * np.arange(500) / 499
    tremor_gt = sharp_highpass(x - line, FS, upd.cutoff)
    assert upd.measurement_noise == pytest.approx(np.var(tremor_gt))
    assert upd.measurement_noise != pytest.approx(np.var(sharp_highpass(x, FS, upd.cutoff)), rel=1e-3)
    assert upd.weights.shape == (5,) and np.all(np.isfinite(upd.weights))
    # the causal fit predicts the voluntary ground truth better than no weights at all
    assert upd.fit_error < 0.5 * np.std(s.voluntary[:500])


@pytest.mark.parametrize("kind", ["silence", "constant", "pure_tremor", "pure_voluntary", "white_noise",
                                  "step", "tiny", "huge"])
def test_degenerate_windows_give_finite_output_and_a_flag(kind, rng):
    x = window_of(kind, rng)
    upd = run_hpa(x, CONFIG, taps=TAPS, previous_weights=np.full(5, 0.2))
    assert upd.cutoff_flag in CUTOFF_FLAGS
    assert 0.5 <= upd.cutoff <= 6.0
    assert np.all(np.isfinite(upd.weights)) and np.max(np.abs(upd.weights)) <= 32
    assert np.isfinite(upd.measurement_noise) and upd.measurement_noise > 0
    if kind in ("silence", "constant"):
        assert upd.cutoff_flag == "silent" and "weights_kept" in upd.flags
        np.testing.assert_array_equal(upd.weights, np.full(5, 0.2))


def test_unknown_fit_is_refused():
    with pytest.raises(ValueError, match="valid choices: causal, paper"):
        WakeConfig(fs=FS, fit="quasi-newton")
