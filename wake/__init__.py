"""wake: real-time pathological tremor extraction (WAKE).

WAKE splits a motion signal into voluntary motion and tremor one sample
ahead of time: a slow hyper-parameter adjustment (HPA, :mod:`wake.hpa`)
fits, every ``L`` samples, weights that map wavelet approximations to
voluntary motion; a per-sample real-time prediction (RTP, :mod:`wake.rtp`)
applies them through a fixed filter bank and a Kalman update.
:mod:`wake.firmware` carries the C sources and the firmware tooling,
:mod:`wake.eval` the datasets, baselines and metrics.

>>> import numpy as np
>>> from wake import WakeFilter
>>> from wake.eval.synthetic import make_signal
>>> s = make_signal(10.0, seed=0)
>>> result = WakeFilter(fs=100.0, backend="reference").run(s.measurement)
>>> bool(np.isfinite(result.voluntary).all())
True
"""

from wake._validation import SparseChannelWarning
from wake.rtp.adaptive import ClippingWarning
from wake.config import CoreMissingWarning, WakeConfig
from wake.filter import BACKENDS, WakeFilter, WakeResult, WakeState


def _version() -> str:
    """The version in the package metadata (pyproject.toml's ``[project] version``, the one place it is set).

    Read with :mod:`importlib.metadata` when the package is installed; from a source checkout run without
    installing (``PYTHONPATH`` on the checkout), from the pyproject.toml beside the package.
    """
    import re
    from importlib import metadata
    from pathlib import Path

    try:
        return metadata.version("wake-tremor")
    except metadata.PackageNotFoundError:
        pyproject = Path(__file__).resolve().parent.parent / "pyproject.toml"
        text = pyproject.read_text(encoding="utf-8") if pyproject.is_file() else ""
        found = re.search(r'^\[project\]$[^\[]*?^version = "([^"]+)"$', text, re.M | re.S)
        return found.group(1) if found else "0+unknown"


__version__ = _version()

__all__ = ["WakeFilter", "WakeResult", "WakeState", "WakeConfig", "BACKENDS", "ClippingWarning",
           "CoreMissingWarning", "SparseChannelWarning", "__version__"]
