"""Real-time prediction (RTP): one channel's per-sample recursion.

Two implementations share one interface, :class:`RTP`:

- :class:`~wake.rtp.reference.ReferenceRTP` (float64, the oracle, written
  line for line as the paper's J-band, J-state recursion);
- :class:`~wake.rtp.fixed.FixedPointRTP` (the fixed-point C core through
  cffi, the code firmware runs), loaded by :func:`load_fixed_point` only
  when asked for, so that the package works without a compiled core.

:mod:`wake.rtp.qformat` holds the C core's number formats and the quantisers
into them (no compiled core needed); :mod:`wake.rtp.adaptive` the RTP that
picks its own full scale and moves from the reference to the C core.
:mod:`wake.rtp.literal` keeps the paper's literal windowed Algorithm 3 for
the ablation in the evaluation.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from wake._core import BUILD_HINT, CoreUnavailable, missing_core_hint
from wake.rtp.reference import ReferenceRTP

__all__ = ["RTP", "ReferenceRTP", "CoreUnavailable", "c_backend_available", "load_fixed_point"]

@runtime_checkable
class RTP(Protocol):
    """What :class:`~wake.WakeFilter` needs from one channel's RTP.

    ``process_noise`` is always the absolute ``q`` of ``Q = q I`` here.
    """

    level: int
    primed: bool

    def step(self, sample: float) -> float: ...
    def step_missing(self) -> float: ...
    def run(self, samples: np.ndarray) -> np.ndarray: ...
    def set_weights(self, weights, measurement_noise: float, process_noise: float | None = None) -> None: ...
    def reset(self) -> None: ...


def c_backend_available() -> bool:
    """Whether the compiled fixed-point core (``wake._rtp``) imports."""
    try:
        load_fixed_point()
    except CoreUnavailable:
        return False
    return True


def load_fixed_point():
    """The :mod:`wake.rtp.fixed` module, or :class:`CoreUnavailable` with how to build it."""
    try:
        from wake.rtp import fixed
    except Exception as exc:  # ImportError, or a broken build
        raise CoreUnavailable(f"the fixed-point C core wake._rtp is not available ({exc}); "
                              f"{missing_core_hint()}") from exc
    return fixed
