"""Whether the compiled core ``wake._rtp`` is installed, and how to get it.

The lowest layer of the package (docs/reference/architecture.md): the configuration
asks it for the default backend, :mod:`wake.rtp` for its messages, and
neither has to import the other.
"""

from __future__ import annotations

__all__ = ["BUILD_HINT", "CoreUnavailable", "core_installed", "missing_core_hint", "shadowed_install"]

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


def shadowed_install():
    """Where an installed ``wake`` with the compiled core lies hidden behind this source tree, or None.

    After ``pip install .`` in a checkout, Python started in the checkout imports the source tree (the current
    directory comes first on ``sys.path``), which has no compiled core, while the installed copy has one.
    """
    import importlib.metadata
    from pathlib import Path

    here = Path(__file__).resolve().parent  # the wake package directory imported
    if not (here.parent / "pyproject.toml").is_file():
        return None  # not a source tree
    try:
        dist = importlib.metadata.distribution("wake-tremor")
    except importlib.metadata.PackageNotFoundError:
        return None
    for f in dist.files or ():
        if f.parts[:1] == ("wake",) and f.name.startswith("_rtp") and f.suffix in (".so", ".pyd"):
            installed = Path(dist.locate_file(f)).resolve().parent
            return installed if installed != here and installed.is_dir() else None
    return None


def missing_core_hint() -> str:
    """How to get the compiled core, or, when the source tree shadows an installed one, what happened."""
    installed = shadowed_install()
    if installed is None:
        return BUILD_HINT
    from pathlib import Path

    tree = Path(__file__).resolve().parents[1]
    return (f"Python imported the source tree {tree} (the current directory comes first on sys.path), which has "
            f"no compiled core, instead of the installed package in {installed}, which has it: run from "
            "another directory, or install the checkout in place with `pip install -e .`")
