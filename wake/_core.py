"""Whether the compiled core ``wake._rtp`` is installed, and how to get it.

The lowest layer of the package (docs/architecture.md): the configuration
asks it for the default backend, :mod:`wake.rtp` for its messages, and
neither has to import the other.
"""

from __future__ import annotations

__all__ = ["BUILD_HINT", "CoreUnavailable", "core_installed"]

#: How to get the compiled core, for every message that needs it.
BUILD_HINT = ("build it with `pip install .` (or `pip install -e .` inside a source tree) on a machine "
              "with a C compiler, or use backend=\"reference\" (the float64 reference, no compiler needed)")


class CoreUnavailable(ImportError):
    """The compiled fixed-point core ``wake._rtp`` cannot be imported."""


def core_installed() -> bool:
    """Whether the compiled extension ``wake._rtp`` imports (:func:`wake.rtp.c_backend_available` also
    loads the wrapper around it and checks its formats)."""
    try:
        import wake._rtp  # noqa: F401
    except Exception:  # ImportError, or a broken build
        return False
    return True
