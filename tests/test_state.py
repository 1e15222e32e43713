"""The saved state of a stream: a versioned layout, earlier states read, other versions refused."""

import dataclasses
import pickle
from pathlib import Path

import numpy as np
import pytest

from support import has_c_backend
from wake import WakeFilter, WakeState
from wake.channel import ChannelState
from wake.eval.synthetic import make_signal
from wake.state import STATE_VERSION

DATA = Path(__file__).parent / "data"
#: tests/data/state_unversioned_*.pkl: get_state() after this many samples of the signal below, pickled by
#: the release before the layout was versioned (a dict of the channel's attributes per channel)
SAVED_AT = 1234


def _signal():
    return make_signal(5.0, seed=1, duration=20.0).measurement


@pytest.mark.parametrize("backend", ["reference", "c"])
def test_a_state_saved_before_versioning_continues_bit_for_bit(backend):
    if backend == "c" and not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    x = _signal()
    state = pickle.loads((DATA / f"state_unversioned_{backend}.pkl").read_bytes())
    assert state.version == 0 and isinstance(state.channels[0], dict)
    g = WakeFilter(config=state.config)
    g.set_state(state)
    f = WakeFilter(config=state.config)
    f.update_block(x[:SAVED_AT])
    np.testing.assert_array_equal(g.update_block(x[SAVED_AT:]), f.update_block(x[SAVED_AT:]))
    assert [u.applied_at for u in g.hpa_history[0]] == [u.applied_at for u in f.hpa_history[0]]


def test_the_state_is_explicit_data_with_a_version():
    f = WakeFilter(backend="reference")
    f.update_block(_signal()[:700])
    state = f.get_state()
    assert state.version == STATE_VERSION
    assert all(isinstance(c, ChannelState) for c in state.channels)
    assert {f.name for f in dataclasses.fields(ChannelState)} == {"weights", "measurement_noise", "updates",
                                                                  "schedule", "rtp", "ahead_coefficients",
                                                                  "ahead_index"}


def test_a_state_of_another_version_is_refused_with_the_version_named():
    f = WakeFilter(backend="reference")
    f.update_block(_signal()[:700])
    state = dataclasses.replace(f.get_state(), version=STATE_VERSION + 1)
    with pytest.raises(ValueError, match=f"layout version {STATE_VERSION + 1}.*reads version {STATE_VERSION}"):
        WakeFilter(backend="reference").set_state(state)
    blob = pickle.dumps(WakeState(state.config, state.channels, version=STATE_VERSION + 1))
    with pytest.raises(ValueError, match="layout version"):
        WakeFilter(backend="reference").set_state(pickle.loads(blob))


def test_a_loaded_state_can_be_loaded_again():
    x = _signal()
    f = WakeFilter(backend="reference")
    f.update_block(x[:900])
    state = f.get_state()
    outs = []
    for _ in range(2):
        g = WakeFilter(backend="reference")
        g.set_state(state)
        outs.append(g.update_block(x[900:]))
    np.testing.assert_array_equal(outs[0], outs[1])


@pytest.mark.parametrize("backend", ["reference", "c"])
def test_a_state_of_layout_1_continues_with_the_gate_shut_until_the_next_hpa(backend):
    """tests/data/state_v1_*.pkl: get_state() after SAVED_AT samples, pickled by the release before the
    tremor ahead (layout version 1)."""
    if backend == "c" and not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    x = _signal()
    state = pickle.loads((DATA / f"state_v1_{backend}.pkl").read_bytes())
    assert state.version == 1
    g = WakeFilter(config=state.config)
    g.set_state(state)
    f = WakeFilter(config=state.config)
    f.update_block(x[:SAVED_AT])
    continued = g.update_block_ahead(x[SAVED_AT:])
    np.testing.assert_array_equal(continued[0], f.update_block(x[SAVED_AT:]))
    next_hpa = 1500 - SAVED_AT     # the first HPA after the state: it fits the first predictor
    assert not continued[2][:next_hpa].any() and not continued[3][:next_hpa].any()
    assert continued[2][-1] > 0     # later HPAs score it and open the gate
