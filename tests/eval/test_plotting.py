"""The figure of ``wake demo --plot`` / ``wake run --plot``: it draws, and the envelope keeps every extreme."""

import numpy as np
import pytest

from wake import WakeFilter
from wake.eval.plotting import _envelope
from wake.eval.synthetic import make_signal


def test_envelope_keeps_the_extremes_of_every_bin():
    t = np.arange(1000) / 100.0
    y = np.sin(2 * np.pi * 5 * t) * np.linspace(0, 1, 1000)
    te, lo, hi = _envelope(t, y, 100.0, 0.2)
    assert len(te) == 50 and te[1] == pytest.approx(0.2)
    np.testing.assert_allclose(hi, y.reshape(50, 20).max(axis=1))
    np.testing.assert_allclose(lo, y.reshape(50, 20).min(axis=1))


def draw(path, x, res, **kw):
    """plot_result at 100 Hz; the legends, titles and y labels it drew, read before the figure is closed."""
    import matplotlib.pyplot as plt

    from wake.eval import plotting

    seen = {}
    real_close = plt.close

    def keep_legends(fig):
        seen["texts"] = [t.get_text() for a in fig.axes if a.get_legend() for t in a.get_legend().get_texts()]
        seen["titles"] = [a.get_title() for a in fig.axes]
        seen["ylabels"] = [a.get_ylabel() for a in fig.axes]
        real_close(fig)

    plt.close = keep_legends
    try:
        plotting.plot_result(path, x, res, 100.0, **kw)
    finally:
        plt.close = real_close
    return seen


def test_plot_result_writes_a_png_with_the_cutoff_flag(tmp_path):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (pip install matplotlib)")
    s = make_signal(5.0, seed=1, duration=12.0)
    res = WakeFilter(backend="reference").run(s.measurement)
    seen = draw(tmp_path / "f.png", s.measurement, res, voluntary_truth=s.voluntary, tremor_truth=s.noise,
                unit="rad/s")
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"
    last = res.hpa[0][-1]
    assert any(f"f_d = {last.cutoff:.2f} Hz ({last.cutoff_flag})" in t for t in seen["texts"])
    # a cut-off taken from the spectrum (here the default rule's floor_valley) is not a fallback
    assert last.cutoff_flag == "floor_valley"
    fell_back = 100 * np.mean([u.cutoff_flag in ("no_tremor_peak", "no_valley", "silent") for u in res.hpa[0]])
    assert any(f"{fell_back:.0f} % fell back to the default cut-off" in t for t in seen["titles"]), seen["titles"]
    assert fell_back < 50
    assert any(t.startswith("warm-up") for t in seen["texts"])
    assert seen["ylabels"][0] == "signal (rad/s)"


def test_plot_counts_rest_tremor_without_a_valley_as_fallen_back(tmp_path):
    """Rest tremor on slow drift (docs/studies/design.md, "Rest tremor with little voluntary motion"): the figure
    said "0 % fell back" while f_d sat at 0.59 Hz; the windows without a dip now fall back and say so."""
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (pip install matplotlib)")
    from wake.eval.synthetic import make_rest_tremor
    from wake.hpa import FALLBACK_FLAGS

    s = make_rest_tremor(seed=2030, drift_db=-20.0, duration=20.0)
    res = WakeFilter(backend="reference").run(s.measurement)
    seen = draw(tmp_path / "f.png", s.measurement, res, voluntary_truth=s.voluntary, tremor_truth=s.tremor)
    flags = [u.cutoff_flag for u in res.hpa[0]]
    fell_back = 100 * np.mean([f in FALLBACK_FLAGS for f in flags])
    assert fell_back >= 50, flags
    assert any(f"{fell_back:.0f} % fell back to the default cut-off" in t for t in seen["titles"]), seen["titles"]
    # every window that fell back is on the default cut-off, none down at the low edge
    assert all(u.cutoff == 2.0 for u in res.hpa[0] if u.cutoff_flag in FALLBACK_FLAGS)
    assert min(u.cutoff for u in res.hpa[0]) > 0.6
    last = res.hpa[0][-1]
    if last.cutoff_flag in FALLBACK_FLAGS:
        assert any(f"({last.cutoff_flag}: default used)" in t for t in seen["texts"]), seen["texts"]


def test_the_reference_error_curve_is_drawn_above_the_c_core_and_dashed():
    from wake.eval.figures import _error_line_style

    ref, c = _error_line_style("WAKE-ref"), _error_line_style("WAKE")
    assert ref["zorder"] > c["zorder"] and ref["ls"] != "-" and ref["lw"] < c["lw"]
