import os
from pathlib import Path

import numpy as np
import pytest

from wake.synthetic import make_signal, paper_dataset


def pads_dir():
    """The PADS subset next to the checkout (or $WAKE_PADS_DIR), if present."""
    env = os.environ.get("WAKE_PADS_DIR")
    path = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "data" / "pads"
    return path if path.is_dir() and any(path.glob("*.txt")) else None


def has_c_backend():
    from wake.filter import c_backend_available

    return c_backend_available()


@pytest.fixture(scope="session")
def paper_signals():
    return paper_dataset()


@pytest.fixture(scope="session")
def signal10():
    return make_signal(10.0, seed=3)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
