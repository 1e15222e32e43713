"""Whether the compiled core ``wake._rtp`` is installed, and how to get it.

The lowest layer of the package (docs/reference/architecture.md): the configuration
asks it for the default backend, :mod:`wake.rtp` for its messages, and
neither has to import the other.
"""

from __future__ import annotations

__all__ = ["BUILD_HINT", "CoreUnavailable", "CoreMissingWarning", "core_installed", "default_backend",
           "missing_core_hint", "shadowed_install"]

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
    ``pip install .`` also leaves ``wake_tremor.egg-info`` in the checkout, which the metadata lookup finds
    first; so every ``wake-tremor`` distribution on the path is asked, and every ``wake`` folder on
    ``sys.path`` is looked at (an install by ``pip install --target`` has no metadata of its own).
    """
    import importlib.metadata
    import sys
    from pathlib import Path

    here = Path(__file__).resolve().parent  # the wake package directory imported
    if not (here.parent / "pyproject.toml").is_file():
        return None  # not a source tree

    def has_core(folder: Path) -> bool:
        return folder.is_dir() and folder != here and any(
            f.name.startswith("_rtp") and f.suffix in (".so", ".pyd") for f in folder.iterdir())

    for dist in importlib.metadata.distributions(name="wake-tremor"):
        for f in dist.files or ():
            if f.parts[:1] == ("wake",) and f.name.startswith("_rtp") and f.suffix in (".so", ".pyd"):
                installed = Path(dist.locate_file(f)).resolve().parent
                if has_core(installed):
                    return installed
    for entry in sys.path:
        folder = (Path(entry or ".") / "wake").resolve()
        if has_core(folder):
            return folder
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


class CoreMissingWarning(UserWarning):
    """The compiled C core is not installed: the default backend is the float64 reference."""


def default_backend() -> str:
    """``"c"`` when the compiled core imports, else ``"reference"``, warning (once per process) which."""
    if core_installed():
        return "c"
    import warnings

    hint = missing_core_hint()
    hint = hint.split(", or use")[0] if hint == BUILD_HINT else hint
    warnings.warn("the compiled C core (wake._rtp) is not importable, so WAKE runs on the float64 reference "
                  f"backend; to run the fixed-point core that firmware runs, {hint}",
                  CoreMissingWarning, stacklevel=4)
    return "reference"
