"""What only the C HPA's batch driver has (wake/native/wake_batch.c, wake.hpa.c_batch.Batch); what both batch
paths share is tested in tests/hpa/test_batch_paths.py.

With the driver switched off (``c_batch.covers`` False) every point runs on ``Channel.hpa``: outputs and HPA
history must be the same bit for bit.
"""

import pytest
from batch_paths import PATHS, assert_same_run, stop_after_first_point
from support import motion

from wake.rtp import c_backend_available

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")

PATH = PATHS["driver"]


@pytest.fixture
def taken(monkeypatch):
    """The points the driver was handed, counted."""
    return PATH.count_points(monkeypatch)


@pytest.mark.parametrize("settings", [dict(horizon=5), dict(horizon=20, gate_cutoff=None),
                                      dict(initial_weights="prior"), dict(horizon=2, gate_cutoff=4.0),
                                      dict(horizon=2, ridge_scale="centred", kind="acc")])
def test_tremor_ahead_options(settings, monkeypatch, taken):
    settings = dict(settings)
    x = motion(100.0, settings.pop("kind", "gyro"), seconds=40.0, seed=4)[0]
    assert_same_run(PATH, x, monkeypatch, taken, **settings)
    assert taken[0] > 0


def test_a_point_the_driver_refuses_runs_on_the_channel(monkeypatch, taken):
    """The driver stops after its first point of each call (as after a refusal): the rest run as before."""
    stop_after_first_point(monkeypatch, "wake_batch_run", 5, "WAKE_BATCH_HPA_REFUSED")
    x = motion(100.0, "acc", seconds=40.0, seed=5)[0]
    assert assert_same_run(PATH, x, monkeypatch, taken) >= 3 * 6
