from pathlib import Path

import numpy as np
import pytest

from support import has_c_backend, pads_dir  # noqa: F401  (re-exported for old imports)

from wake.eval.synthetic import make_signal, paper_dataset


@pytest.fixture(scope="session")
def paper_signals():
    return paper_dataset()


@pytest.fixture(scope="session")
def signal10():
    return make_signal(10.0, seed=3)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture
def recording(tmp_path):
    """A 12 s, two-channel CSV (header ``a,b``; ``b = -a``, no time column) and the synthetic signal behind it."""
    s = make_signal(5.0, seed=1, duration=12.0)
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack([s.measurement, -s.measurement]), delimiter=",", header="a,b", comments="")
    return path, s


def pytest_xdist_auto_num_workers(config):
    """``-n auto`` (pyproject.toml's addopts): one worker per core, except for a run of a single test file (or tests
    of one file), which runs in this process: starting workers would cost more than they save."""
    files = {Path(str(arg).split("::")[0]).resolve() for arg in config.args}
    if len(files) == 1 and next(iter(files)).is_file():
        return 0
    return None
