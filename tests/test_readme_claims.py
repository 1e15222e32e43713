"""The README's comparison sentences on the synthetic set, checked against what `wake evaluate` computes."""

import re
from pathlib import Path

import numpy as np
import pytest

from wake.eval.evaluate import evaluate_synthetic

README = Path(__file__).resolve().parents[1] / "README.md"


@pytest.fixture(scope="module")
def synthetic():
    return evaluate_synthetic(["reference"])


def _text():
    return " ".join(README.read_text(encoding="utf-8").split())


def test_best_on_n_of_ten_synthetic_signals(synthetic):
    m = re.search(r"WAKE is best on (\d+) of the 10 synthetic signals: on signal (\d+) \(SNR [-\d.]+ dB\) "
                  r"(\S+) scores (\d+\.\d+) against WAKE's (\d+\.\d+)", _text())
    assert m, "the README's synthetic comparison sentence is missing or reworded"
    n_best, signal, rival, rival_score, wake_score = int(m[1]), int(m[2]), m[3], float(m[4]), float(m[5])
    rows = synthetic["rows"]
    wins = [r["signal"] for r in rows
            if r["methods"]["WAKE-ref"]["nrmse"] < min(v["nrmse"] for k, v in r["methods"].items()
                                                      if not k.startswith("WAKE"))]
    assert len(wins) == n_best
    assert sorted(set(range(1, 11)) - set(wins)) == [signal]
    row = rows[signal - 1]["methods"]
    assert round(row[rival]["nrmse"], 4) == rival_score
    assert round(row["WAKE-ref"]["nrmse"], 4) == wake_score


def test_synthetic_mean_row(synthetic):
    m = re.search(r"\| Synthetic, 10 signals \(voluntary\) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|", _text())
    assert m, "the README's mean NRMSE table is missing its synthetic row"
    means = {name: np.mean([r["methods"][name]["nrmse"] for r in synthetic["rows"]])
             for name in ("BMFLC", "E-BMFLC", "WFLC", "WAKE-ref")}
    assert [float(v) for v in m.groups()] == [round(means[k], 4) for k in ("BMFLC", "E-BMFLC", "WFLC", "WAKE-ref")]
