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


#: The float reference after a saved state agrees with a fresh stream to this share of the signal's peak.
#: Bit identity holds for the C core (integer arithmetic), not for the float reference across library builds:
#: the pickles carry weights fitted by the numpy/scipy that wrote them, and a BLAS summing in another order
#: moves the normal equations of the fit (wake.hpa.fit) by up to about L u relative (L = 500 rows, u = 2^-53).
#: Their ridge bounds the condition number by J / ridge + 1 = 5e6 (J = 5, ridge 1e-6 of the mean diagonal),
#: so the weights, and the prediction w'(a + d), move by at most 5e6 * 2 * 500 * 1.1e-16 = 5.6e-7 of their
#: scale. 1e-6 of the signal's peak holds that with room; the differences seen were 7e-14 (numpy 2.4.6,
#: scipy 1.17.1 against the builds that wrote the files). A cut-off decided otherwise would differ by far more.
FLOAT_REFERENCE_TOLERANCE = 1e-6


def _signal():
    return make_signal(5.0, seed=1, duration=20.0).measurement


class _Unpickler(pickle.Unpickler):
    """Reads the committed states under numpy 1.x too: they were written by numpy 2, whose arrays pickle as
    ``numpy._core``, a module numpy 1.x calls ``numpy.core`` (a file format question, not one of WAKE's)."""

    def find_class(self, module, name):
        if module.startswith("numpy._core") and not hasattr(np, "_core"):
            module = "numpy.core" + module[len("numpy._core"):]
        return super().find_class(module, name)


def _saved_state(name):
    with open(DATA / name, "rb") as f:
        return _Unpickler(f).load()


def assert_continues(backend, continued, fresh, x):
    """Bit for bit on the C core; within :data:`FLOAT_REFERENCE_TOLERANCE` of the peak on the float reference."""
    if backend == "c":
        np.testing.assert_array_equal(continued, fresh)
    else:
        np.testing.assert_allclose(continued, fresh, rtol=0,
                                   atol=FLOAT_REFERENCE_TOLERANCE * float(np.max(np.abs(x))))


@pytest.mark.parametrize("backend", ["reference", "c"])
def test_a_state_saved_before_versioning_continues(backend):
    if backend == "c" and not has_c_backend():
        pytest.skip("the compiled C core wake._rtp is not built")
    x = _signal()
    state = _saved_state(f"state_unversioned_{backend}.pkl")
    assert state.version == 0 and isinstance(state.channels[0], dict)
    g = WakeFilter(config=state.config)
    g.set_state(state)
    f = WakeFilter(config=state.config)
    f.update_block(x[:SAVED_AT])
    assert_continues(backend, g.update_block(x[SAVED_AT:]), f.update_block(x[SAVED_AT:]), x)
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
    state = _saved_state(f"state_v1_{backend}.pkl")
    assert state.version == 1
    g = WakeFilter(config=state.config)
    g.set_state(state)
    f = WakeFilter(config=state.config)
    f.update_block(x[:SAVED_AT])
    continued = g.update_block_ahead(x[SAVED_AT:])
    assert_continues(backend, continued[0], f.update_block(x[SAVED_AT:]), x)
    next_hpa = 1500 - SAVED_AT     # the first HPA after the state: it fits the first predictor
    assert not continued[2][:next_hpa].any() and not continued[3][:next_hpa].any()
    assert continued[2][-1] > 0     # later HPAs score it and open the gate
