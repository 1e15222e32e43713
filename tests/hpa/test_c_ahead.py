"""The C HPA's tremor-ahead fit (csrc/wake_hpa.c, WAKE_HPA_AHEAD) against wake.ahead, the definition.

Each window's estimate and truth are recomputed here in float64 from the int16 window the C HPA reads, the
quantised filter bank and the weights the C HPA installed (as wake.hpa.run_hpa), and fed to
``fit_predictor`` / ``held_out_gain`` / ``gate_target``.  Tolerance: the C HPA accumulates the 8 x 8 Gram
of about 460 rows and solves it in single precision (eps 6e-8); with the ridge 1e-3 trace(G)/8 >=
1e-3 lambda_max/8 the system's condition number is at most 1 + 8/1e-3 = 8,001, so a coefficient may move by
about 1e-3 of the largest; measured (bench/hpa_c_ahead_agreement.py, estimate of the installed weights): at
most 4.5e-4 on PADS, 2.9e-6 on the synthetic set, and 2.1e-3 on this module's narrow-band PADS-shaped window
(its tremor estimate is nearly one sinusoid: the Gram's condition number is near the bound), hence 5e-3 here.
The goal is a ratio of two float sums over at least 10 targets: within 2e-3.  What an actuator gets, the
command g P over the window, within 1 % NRMSE.
"""

import numpy as np
import pytest
from support import NO_PADS, pads_dir

from wake import WakeConfig
from wake.ahead import NO_TREMOR_FLAGS, fit_predictor, gate_target, held_out_gain, predictions
from wake.eval.synthetic import paper_dataset
from wake.hpa.sharp import detrended_highpass
from wake.rtp import c_backend_available
from wake.wavelets import filter_bank_outputs, filter_bank_taps

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")

CONFIG = WakeConfig(backend="reference")
TAPS = filter_bank_taps("sym3", 5)
L, N = CONFIG.window_samples, 2**CONFIG.level
COEF_TOL = 5e-3      # of max(1, max |c|)
GOAL_TOL = 2e-3
COMMAND_NRMSE = 0.01


def python_twin(stream, out, horizon, full_scale):
    """wake.ahead on each window's estimate and truth, from what the C HPA read and the weights it installed."""
    from wake.hpa.c_port import quantize_window
    from wake.rtp.qformat import quantize_taps

    x = quantize_window(stream, full_scale).astype(float)       # LSB: the predictor is scale-free
    taps = quantize_taps(TAPS).astype(float) / 32768.0
    twin, previous = [], None
    for k, o in enumerate(out):
        w = x[k * L:(k + 1) * L]
        y = w[N:] - filter_bank_outputs(w, taps)[:L - N] @ o["weights"]
        truth = detrended_highpass(w, CONFIG.fs, o["cutoff"])[N:]
        c = fit_predictor(y, truth, horizon)
        gain = held_out_gain(y, truth, previous, horizon, L)
        twin.append({"y": y, "coefficients": c, "goal": gate_target(gain, o["flag"])})
        previous = o["coefficients"]        # the C HPA scores its own previous predictor
    return twin


def check_agreement(stream, horizon, full_scale):
    from wake.hpa.c_ahead import run_ahead_c

    out = run_ahead_c(stream, CONFIG, taps=TAPS, horizon=horizon, full_scale=full_scale)
    twin = python_twin(stream, out, horizon, full_scale)
    assert out[0]["goal"] == 0.0                                  # the first HPA has nothing to score
    for o, t in zip(out, twin):
        c, ref = o["coefficients"], t["coefficients"]
        assert np.all(np.abs(c) <= 8.0)
        assert np.max(np.abs(c - ref)) <= COEF_TOL * max(1.0, np.max(np.abs(ref)))
        assert o["goal"] == pytest.approx(t["goal"], abs=GOAL_TOL)
        if o["flag"] in NO_TREMOR_FLAGS:
            assert o["goal"] == 0.0
        command, command_ref = o["goal"] * predictions(t["y"], c), t["goal"] * predictions(t["y"], ref)
        scale = np.sqrt(np.mean(command_ref**2))
        if scale > 0:
            assert np.sqrt(np.mean((command - command_ref) ** 2)) <= COMMAND_NRMSE * scale
        else:
            assert np.all(command == 0.0)
    return out


@pytest.mark.parametrize("horizon", [1, 5, 20])
@pytest.mark.parametrize("signal", [0, 4, 8])
def test_c_ahead_agrees_with_wake_ahead_on_synthetic_windows(signal, horizon):
    x = paper_dataset()[signal].measurement[:4 * L]
    full_scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(x)) * 1.01))
    out = check_agreement(x, horizon, full_scale)
    if horizon <= 5:
        assert max(o["goal"] for o in out[1:]) > 0.0                # the gate opens on a tremor


def test_c_ahead_agrees_on_a_pads_shaped_window_and_shuts_without_tremor():
    """A gyroscope-like axis (deg/s): a 5 Hz tremor whose amplitude swells, on a reach-and-return movement
    and sensor noise, then 5 s of the movement alone (no tremor peak: the gate's goal is 0)."""
    rng = np.random.default_rng(7)
    t = np.arange(4 * L) / CONFIG.fs
    tremor = (20 + 15 * np.sin(2 * np.pi * 0.1 * t)) * np.sin(2 * np.pi * 5.0 * t + 0.3 * np.sin(2 * np.pi * 0.2 * t))
    noise = rng.normal(0, 1.5, t.size)
    tremor[3 * L:] = 0.0
    noise[3 * L:] = 0.0
    x = 80 * np.sin(2 * np.pi * 0.25 * t) + 30 * np.sin(2 * np.pi * 0.6 * t) + tremor + noise
    out = check_agreement(x, 10, 256.0)
    assert out[1]["goal"] > 0.5
    assert out[3]["flag"] in NO_TREMOR_FLAGS and out[3]["goal"] == 0.0


@pytest.mark.skipif(pads_dir() is None, reason=NO_PADS)
def test_c_ahead_agrees_with_wake_ahead_on_pads():
    from wake.eval.datasets import load_pads_folder

    recordings = load_pads_folder(pads_dir())
    checked = 0
    for rec in recordings[:4]:
        windows = min(4, rec.samples.shape[0] // L)
        for c in range(0, rec.samples.shape[1], 2):
            if windows < 2:
                continue
            x = np.asarray(rec.samples[:, c], dtype=float)[:windows * L]
            full_scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(x)) * 1.01 + 1e-12))
            check_agreement(x, 5, full_scale)
            checked += 1
    assert checked >= 4


def test_run_ahead_c_refuses_bad_input():
    from wake.hpa.c_ahead import run_ahead_c

    x = np.zeros(L)
    with pytest.raises(ValueError, match="horizon must lie in 1..32"):
        run_ahead_c(x, CONFIG, taps=TAPS, horizon=33, full_scale=1.0)
    with pytest.raises(ValueError, match="whole number of L = 500"):
        run_ahead_c(np.zeros(L + 1), CONFIG, taps=TAPS, full_scale=1.0)
    with pytest.raises(ValueError, match="full_scale must be finite"):
        run_ahead_c(x, CONFIG, taps=TAPS, full_scale=0.0)


def test_run_hpa_c_scoring_the_previous_predictor_equals_one_instance_across_windows():
    """run_hpa_c builds a fresh instance per window; given the previous HPA's predictor and the samples since
    it, it fits and scores exactly as one instance run over consecutive windows (run_ahead_c) does."""
    from dataclasses import replace

    from wake.hpa.c_ahead import run_ahead_c
    from wake.hpa.c_port import run_hpa_c

    x = paper_dataset()[0].measurement[:4 * L]
    full_scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(x)) * 1.01))
    config = replace(CONFIG, horizon=5)
    chain = run_ahead_c(x, config, taps=TAPS, horizon=5, full_scale=full_scale)
    previous = None
    for k, o in enumerate(chain):
        upd = run_hpa_c(x[k * L:(k + 1) * L], config, taps=TAPS, previous_weights=o["weights_in_use"],
                        index=(k + 1) * L, full_scale=full_scale, previous_ahead=previous,
                        new_samples=L if k else 0)
        np.testing.assert_array_equal(upd.ahead_coefficients, o["coefficients"])
        assert upd.ahead_goal == o["goal"]
        assert upd.ahead_gain == (0.0 if upd.cutoff_flag in NO_TREMOR_FLAGS else upd.ahead_goal)
        previous = upd.ahead_coefficients
    assert max(o["goal"] for o in chain[1:]) > 0.5                 # the gate opens: the scoring was exercised
    with pytest.raises(ValueError, match="previous_ahead must be 8 finite coefficients"):
        run_hpa_c(x[:L], config, taps=TAPS, full_scale=full_scale, previous_ahead=np.zeros(7))
    with pytest.raises(ValueError, match="new_samples must be an integer in 0..index"):
        run_hpa_c(x[:L], config, taps=TAPS, index=L, full_scale=full_scale, previous_ahead=np.zeros(8),
                  new_samples=L + 1)


@pytest.mark.parametrize("horizon", [1, 5])
def test_filter_with_the_c_hpa_commands_the_tremor_ahead_as_with_the_python_hpa(horizon):
    """WakeFilter(hpa_backend="c") takes the predictor and goal from the C HPA; its gated command equals the
    Python HPA's within the pipeline tolerance of docs/studies/hpa_c.md (1 % NRMSE, whole and after 5 s)."""
    from wake import WakeFilter

    x = paper_dataset()[0].measurement[:6 * L]
    runs = {hb: WakeFilter(fs=CONFIG.fs, hpa_backend=hb, horizon=horizon).run(x) for hb in ("python", "c")}
    ref, got = runs["python"].command, runs["c"].command
    assert np.max(runs["c"].confidence) > 0.5                      # the gate opens on the C HPA's goal
    for start in (0, L):
        scale = np.sqrt(np.mean(ref[start:] ** 2))
        assert scale > 0
        assert np.sqrt(np.mean((got[start:] - ref[start:]) ** 2)) <= COMMAND_NRMSE * scale


def test_the_c_hpas_clipping_rule_is_glitch_share_of_the_window_as_in_python(monkeypatch):
    """The C HPA shuts the gate when more than GLITCH_SHARE of its int16 window sits at full scale: for full
    scales around that share it notes "clipping" (goal 0) exactly where the fixed-point RTP's own count of
    clipped samples crosses the Python rule (wake.rtp.adaptive), and the same window unclipped opens the gate.
    The threshold is stated once on each side and checked by c_mirror_problems."""
    from wake._rtp import lib
    from wake.ahead import installed_goal
    from wake.hpa.c_port import c_mirror_problems, run_hpa_c, window_full_scale
    from wake.rtp.full_scale import GLITCH_SHARE

    x = paper_dataset()[0].measurement[:2 * L]
    previous = run_hpa_c(x[:L], CONFIG, taps=TAPS, index=L, full_scale=window_full_scale(x)).ahead_coefficients
    window = x[L:]

    def hpa(full_scale):
        return run_hpa_c(window, CONFIG, taps=TAPS, index=2 * L, full_scale=full_scale, previous_ahead=previous,
                         new_samples=L)

    wide = hpa(window_full_scale(x))
    assert "clipping" not in wide.flags and wide.ahead_goal > 0.5
    peaks = np.sort(np.abs(window))[::-1]
    seen = set()
    for k in (1, 3, 4, 5, 6, 7, 12, 60):            # samples beyond the full scale: 5 is 1 % of L = 500
        full_scale = 0.5 * (peaks[k - 1] + peaks[k])
        clipped = int(np.count_nonzero(np.abs(np.rint(window * 32768.0 / full_scale)) > 32767))  # as FixedPointRTP
        upd = hpa(full_scale)
        python_says = installed_goal(wide.ahead_goal, ("clipping",) if clipped > GLITCH_SHARE * L else ())
        seen.add(python_says == 0.0)
        assert ("clipping" in upd.flags) == (python_says == 0.0), (k, clipped)
        assert (upd.ahead_goal == 0.0) if python_says == 0.0 else upd.ahead_goal > 0.5
    assert seen == {True, False}                   # both sides of the threshold were exercised
    monkeypatch.setattr("wake.hpa.c_port.GLITCH_SHARE", 0.02)
    assert any("WAKE_HPA_GLITCH_DIVISOR = 100" in p for p in c_mirror_problems(lib))


def test_filter_with_the_c_hpa_takes_the_clipping_rule_from_the_c_hpa():
    """WakeFilter(hpa_backend="c") on a stream clipped at its 90th percentile: the C HPA's own goal is 0 at
    every HPA the fixed-point RTP saw clip (the filter no longer re-applies the rule on its result), the gate
    stays shut as with the Python HPA, and a wide full scale opens it."""
    from wake import ClippingWarning, WakeFilter

    x = paper_dataset()[0].measurement[:6 * L]
    peak = float(np.quantile(np.abs(x), 0.9))
    runs = {}
    for hb in ("python", "c"):
        with pytest.warns(ClippingWarning):
            runs[hb] = WakeFilter(fs=CONFIG.fs, full_scale=peak, horizon=4, hpa_backend=hb).run(x)
    c_hpa = runs["c"].hpa[0]
    assert all(u.flags.count("clipping") == 1 for u in c_hpa[1:])
    assert all(u.ahead_goal == 0.0 for u in c_hpa)     # the C HPA's own result, not the installation's
    assert [("clipping" in u.flags) for u in c_hpa] == [("clipping" in u.flags) for u in runs["python"].hpa[0]]
    for r in runs.values():
        assert not r.confidence.any() and not r.command.any()
    wide = WakeFilter(fs=CONFIG.fs, full_scale=4 * np.abs(x).max(), horizon=4, hpa_backend="c").run(x)
    assert not any("clipping" in u.flags for u in wide.hpa[0])
    assert wide.confidence.max() > 0.3


def test_a_silent_window_keeps_the_predictor_and_shuts_the_gate_in_both_hpas():
    """After a constant window both HPAs keep the previous predictor (goal 0), so the next window scores it:
    the gate reopens at the next HPA when the tremor comes back as it was."""
    from wake.hpa import run_hpa
    from wake.hpa.c_ahead import run_ahead_c
    from wake.hpa.c_port import run_hpa_c

    x = paper_dataset()[0].measurement[:3 * L].copy()
    x[L:2 * L] = 0.25
    full_scale = 2.0 ** np.ceil(np.log2(np.max(np.abs(x)) * 1.01))
    previous = np.linspace(-0.5, 0.9, 8)
    for hpa, extra in ((run_hpa, {}), (run_hpa_c, dict(full_scale=full_scale))):
        upd = hpa(x[L:2 * L], CONFIG, taps=TAPS, index=2 * L, previous_ahead=previous, new_samples=L, **extra)
        assert upd.cutoff_flag == "silent" and upd.ahead_goal == 0.0
        np.testing.assert_allclose(upd.ahead_coefficients, previous, rtol=1e-7)
        first = hpa(x[L:2 * L], CONFIG, taps=TAPS, index=2 * L, **extra)     # no predictor yet: zeros
        assert first.cutoff_flag == "silent" and not first.ahead_coefficients.any()
    chain = run_ahead_c(x, CONFIG, taps=TAPS, horizon=1, full_scale=full_scale)
    np.testing.assert_array_equal(chain[1]["coefficients"], chain[0]["coefficients"])
    assert chain[1]["goal"] == 0.0 and chain[2]["goal"] > 0.5
