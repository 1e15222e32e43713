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


def test_plot_result_writes_a_png_with_the_cutoff_flag(tmp_path):
    pytest.importorskip("matplotlib", reason="matplotlib is not installed (pip install matplotlib)")
    import matplotlib.pyplot as plt

    from wake.eval import plotting

    s = make_signal(5.0, seed=1, duration=12.0)
    res = WakeFilter(backend="reference").run(s.measurement)
    seen = {}
    real_close = plt.close

    def keep_legends(fig):  # read the legends and titles before the figure is closed
        seen["texts"] = [t.get_text() for a in fig.axes if a.get_legend() for t in a.get_legend().get_texts()]
        seen["titles"] = [a.get_title() for a in fig.axes]
        seen["ylabels"] = [a.get_ylabel() for a in fig.axes]
        real_close(fig)

    plt.close = keep_legends
    try:
        plotting.plot_result(tmp_path / "f.png", s.measurement, res, 100.0, voluntary_truth=s.voluntary,
                             tremor_truth=s.noise, unit="rad/s")
    finally:
        plt.close = real_close
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
