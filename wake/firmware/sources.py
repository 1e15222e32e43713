"""Where the C sources are: shipped inside the package as ``wake._csrc``.

``csrc/`` of the source tree is the single source of the C code.  The build
maps it onto the package ``wake._csrc`` (``pyproject.toml``,
``[tool.setuptools.package-dir]``), so a wheel or a plain ``pip install .``
carries ``wake_rtp.c``, ``wake_rtp.h``, the profiling harness and the
examples, and ``wake profile`` / ``wake export-c`` work without a checkout.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["HPA_INTERNAL_HEADERS", "HPA_SOURCES", "INTERNAL_HEADERS", "RTP_HEADERS", "RTP_INTERNAL", "RTP_SOURCES",
           "SourcesUnavailable", "csrc_dir"]

#: The RTP's modules (docs/reference/architecture.md, "The C core's files"): the core step first; a module a
#: build does not use compiles to nothing.
RTP_SOURCES = ("wake_rtp.c", "wake_rtp_state.c", "wake_rtp_split.c", "wake_rtp_ahead.c", "wake_rtp_voluntary.c",
               "wake_rtp_block.c", "wake_rtp_fixed.c")
#: The RTP's public headers: the core (wake_rtp.h, which includes the others), its number formats and status
#: codes, and each feature instance's header.
RTP_HEADERS = ("wake_rtp.h", "wake_rtp_types.h", "wake_ahead.h", "wake_voluntary_ahead.h")
#: The RTP's internal headers, which its modules include by their relative path.
RTP_INTERNAL = ("internal/wake_rtp_internal.h", "internal/wake_rtp_sample.h", "internal/wake_bounds.h")

#: Files every use of the sources needs.
_REQUIRED = ("wake_rtp.c", *RTP_HEADERS, "wake_fixed.h")
#: The on-device HPA's sources, a file per concern (csrc/internal/wake_hpa_internal.h describes each), and the
#: internal headers they share (not part of the API; a build compiles them, a user never includes them).
HPA_SOURCES = ("wake_hpa.c", "wake_hpa_spectrum.c", "wake_hpa_dft.c", "wake_hpa_fit.c", "wake_hpa_solve.c",
               "wake_hpa_ahead.c", "wake_hpa_pieces.c", "wake_hpa_slice.c")
HPA_INTERNAL_HEADERS = ("internal/wake_hpa_internal.h", "internal/wake_bounds.h", "internal/wake_hpa_costs.h")
#: Every internal header once (the analyser's bounds, internal/wake_bounds.h, serve the RTP and the HPA).
INTERNAL_HEADERS = tuple(dict.fromkeys(RTP_INTERNAL + HPA_INTERNAL_HEADERS))


class SourcesUnavailable(FileNotFoundError):
    """The C sources are neither installed with the package nor at the given path."""


def _installed() -> Path | None:
    # Imported from a source checkout (``wake/`` beside ``csrc/``): that tree's
    # sources, even when another copy is installed as ``wake._csrc`` (an
    # editable install of a different checkout maps it there).
    checkout = Path(__file__).resolve().parents[2] / "csrc"
    if all((checkout / f).is_file() for f in _REQUIRED):
        return checkout
    try:
        from importlib.resources import files

        root = Path(str(files("wake._csrc")))
    except (ImportError, ModuleNotFoundError, TypeError):
        root = None
    if root is not None and all((root / f).is_file() for f in _REQUIRED):
        return root
    return None


def csrc_dir(path: str | Path | None = None, *, need: tuple[str, ...] = ()) -> Path:
    """The directory holding the C sources.

    Parameters
    ----------
    path : str or Path, optional
        An explicit ``csrc/`` directory (a checkout, or a modified copy).
        Default: the sources installed with the package.
    need : tuple of str
        Further files (relative paths) that must exist there, e.g.
        ``("profile/harness.c",)``.

    Raises
    ------
    SourcesUnavailable
        With the directory looked at and how to point at another one.

    Examples
    --------
    >>> from wake.firmware.sources import csrc_dir
    >>> (csrc_dir() / "wake_rtp.h").is_file()
    True
    """
    cand = Path(path) if path else _installed()
    if cand is None:
        raise SourcesUnavailable(
            "the C sources are not installed with this copy of wake (package wake._csrc is missing); "
            "reinstall it with `pip install .` from a source tree, or pass the csrc/ directory of a checkout")
    missing = [f for f in _REQUIRED + tuple(need) if not (cand / f).is_file()]
    if missing:
        raise SourcesUnavailable(
            f"the C sources in {cand} lack {', '.join(missing)}: point at the csrc/ directory of a wake "
            "source tree")
    return cand
