"""What only the Python HPA's batch path has (wake.hpa.c_batch.InstallBatch, wake_batch_install in
wake/native/wake_batch.c); what both batch paths share is tested in tests/hpa/test_batch_paths.py.

With the batch switched off (``c_batch.covers_installs`` False) every point runs on ``Channel.hpa``: outputs and
HPA history must be the same bit for bit.
"""

import numpy as np
import pytest
from batch_paths import PATHS, assert_same_run, stop_after_first_point, without_path
from support import assert_same_history, motion

from wake import WakeFilter
from wake.rtp import c_backend_available

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")

PATH = PATHS["install"]


@pytest.fixture
def taken(monkeypatch):
    """The points the batch installed, counted."""
    return PATH.count_points(monkeypatch)


@pytest.mark.parametrize("settings", [dict(horizon=5), dict(gate_cutoff=4.0), dict(initial_weights="prior"),
                                      dict(ridge_scale="centred")])
def test_settings_the_batch_takes_or_leaves(settings, monkeypatch, taken):
    x = motion(100.0, "gyro", seconds=40.0, seed=4)[0]
    assert_same_run(PATH, x, monkeypatch, taken, **settings)
    # a voluntary motion ahead (horizon > 1) is installed point by point; the rest go to the batch
    assert (taken[0] == 0) == (settings.get("horizon", 1) > 1)


def test_a_point_the_driver_refuses_runs_on_the_channel(monkeypatch, taken):
    """The driver stops after its first point of each call (as after a refusal): the rest run as before."""
    stop_after_first_point(monkeypatch, "wake_batch_install", 2, "WAKE_BATCH_RTP_REFUSED")
    x = motion(100.0, "acc", seconds=40.0, seed=5)[0]
    assert assert_same_run(PATH, x, monkeypatch, taken) == 3   # the first point of each channel's batch, the rest after


def test_a_point_whose_finish_raises_runs_on_the_channel(monkeypatch, taken):
    """A point whose words the batch cannot make (the quantisers refuse them) leaves the batch: it and the points
    after it in that batch run on Channel.hpa (which would raise there as before, after the stretch before it)."""
    import wake.hpa.c_batch as module

    calls = [0]
    real = module.clamped_words

    def refuse_third(*args):
        calls[0] += 1
        if calls[0] == 3:
            raise ValueError("refused")
        return real(*args)

    monkeypatch.setattr(module, "clamped_words", refuse_third)
    x = motion(100.0, "gyro", seconds=40.0, seed=6)[0][:, 0]
    res = WakeFilter(backend="c").run(x)
    monkeypatch.setattr(module, "clamped_words", real)
    ref = without_path(PATH, lambda: WakeFilter(backend="c").run(x), monkeypatch)
    assert calls[0] >= 3 and taken[0] > 0
    assert np.array_equal(res.prediction, ref.prediction)
    assert_same_history(res.hpa, ref.hpa)
