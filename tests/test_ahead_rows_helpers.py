"""The helpers of bench/ahead_rows.py (issue 32's cost target): its restricted fit is the library's on the rows
it keeps, and the substitution is undone after the block (docs/studies/design.md, "A fit on fewer rows")."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

import wake.ahead as ahead
import wake.hpa.run as hpa_run

ROOT = Path(__file__).resolve().parents[1]


def _rows():
    spec = importlib.util.spec_from_file_location("bench_ahead_rows", ROOT / "bench" / "ahead_rows.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["bench_ahead_rows"] = mod
    spec.loader.exec_module(mod)
    return mod


def _window(n=300, seed=3):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 100.0
    truth = np.sin(2 * np.pi * 6.0 * t) + 0.3 * np.sin(2 * np.pi * 9.0 * t + 1.0)
    return truth + 0.2 * rng.standard_normal(n), truth


def test_kept_rows_are_the_newest_or_every_sth_ending_at_the_newest():
    rows = _rows()
    assert rows.kept_rows("all rows", 5).tolist() == [0, 1, 2, 3, 4]
    assert rows.kept_rows("last 3", 10).tolist() == [7, 8, 9]
    assert rows.kept_rows("every 3", 10).tolist() == [0, 3, 6, 9]


def test_with_every_row_kept_the_fit_and_the_score_are_the_library_s():
    rows = _rows()
    y, truth = _window()
    for h in (1, 5):
        # the same rows, copied by the indexing: equal up to the order BLAS sums in
        assert np.allclose(rows.fit_on("every 1")(y, truth, h), ahead.fit_predictor(y, truth, h), rtol=1e-12, atol=1e-14)
        previous = ahead.fit_predictor(y[:150], truth[:150], h)
        assert rows.held_out_on("every 1")(y, truth, previous, h, 120) == \
            pytest.approx(ahead.held_out_gain(y, truth, previous, h, 120), abs=1e-12)


def test_the_restricted_fit_is_the_library_fit_on_the_kept_rows_alone():
    rows = _rows()
    y, truth = _window()
    h, taps = 2, ahead.TAPS
    # the newest 100 rows are the rows of the window's last 100 + taps - 1 + h samples
    tail = 100 + taps - 1 + h
    assert np.allclose(rows.fit_on("last 100")(y, truth, h), ahead.fit_predictor(y[-tail:], truth[-tail:], h))
    assert not np.allclose(rows.fit_on("last 100")(y, truth, h), ahead.fit_predictor(y, truth, h))


def test_the_substitution_is_undone_after_the_block_even_on_an_error():
    rows = _rows()
    shipped = hpa_run.fit_predictor, hpa_run.held_out_gain
    with pytest.raises(RuntimeError):
        with rows.variant_in_use("last 160"):
            assert hpa_run.fit_predictor is not shipped[0]
            raise RuntimeError("stop")
    assert (hpa_run.fit_predictor, hpa_run.held_out_gain) == shipped
