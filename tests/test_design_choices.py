"""Pins for the choices where the paper is vague (docs/studies/design.md has the numbers).

Each test reruns the measurement that decided a default and asserts the
default still wins, so a change that flips the decision fails here.
"""

import numpy as np
import pytest

from wake import WakeFilter
from wake.eval.metrics import nrmse


def mean_nrmse(signals, **kwargs):
    return np.mean([nrmse(s.voluntary, WakeFilter(backend="reference", **kwargs).run(s.measurement).voluntary, 500)
                    for s in signals])


@pytest.fixture(scope="module")
def default_score(paper_signals):
    return mean_nrmse(paper_signals)


@pytest.mark.parametrize("alternative", [
    dict(fit="paper"),            # the paper's full-window fit
    dict(mode="symmetric"),       # PyWavelets' default boundary
    dict(mode="periodization"),
    dict(process_noise_ratio=1e-5),     # a live Kalman correction
    dict(initial_covariance=0.05),
])
def test_default_beats_alternative(alternative, paper_signals, default_score):
    assert default_score < mean_nrmse(paper_signals, **alternative)
