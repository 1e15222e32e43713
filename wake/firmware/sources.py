"""Where the C sources are: shipped inside the package as ``wake._csrc``.

``csrc/`` of the source tree is the single source of the C code.  The build
maps it onto the package ``wake._csrc`` (``pyproject.toml``,
``[tool.setuptools.package-dir]``), so a wheel or a plain ``pip install .``
carries ``wake_rtp.c``, ``wake_rtp.h``, the profiling harness and the
examples, and ``wake profile`` / ``wake export-c`` work without a checkout.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["FEATURE_DEFAULTS", "FEATURE_ENTRIES", "FEATURES_MAKE", "HPA_INTERNAL_HEADERS", "HPA_SOURCES",
           "INTERNAL_HEADERS", "RTP_HEADERS", "RTP_INTERNAL", "RTP_SOURCES", "SourcesUnavailable", "csrc_dir",
           "features_make_text", "feature_values", "firmware_entries"]

#: The RTP's modules (docs/reference/architecture.md, "The C core's files"): the core step first.  Every
#: module compiles in every configuration; a firmware links the entries of the features it uses
#: (FEATURE_ENTRIES) and ``--gc-sections`` drops the rest.
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


#: The entry points that exist for one feature only, per feature switch (csrc/wake_rtp.h): a firmware built
#: without the feature calls none of them, so its link (``-ffunction-sections``, ``--gc-sections``) keeps none.
#: The one list of them: ``wake profile`` reads it (firmware_entries), and ``make -C csrc cross`` reads
#: FEATURES_MAKE, generated from it (``python -m wake.firmware.sources --write-make``; a test checks they agree).
FEATURE_ENTRIES = {
    "WAKE_RTP_AHEAD": ("wake_rtp_set_ahead", "wake_rtp_set_ahead_ramp", "wake_rtp_ahead_output",
                       "wake_rtp_load_ahead_state", "wake_rtp_get_ahead_state"),
    "WAKE_RTP_SPLIT": ("wake_rtp_prepare", "wake_rtp_finish", "wake_rtp_finish_missing", "wake_rate_step"),
    "WAKE_RTP_VOLUNTARY_AHEAD": ("wake_rtp_set_voluntary_ahead", "wake_rtp_voluntary_ahead_output",
                                 "wake_rtp_run_outputs"),
}
#: Each switch's value when a build does not set it (csrc/wake_rtp.h).
FEATURE_DEFAULTS = {"WAKE_RTP_AHEAD": "1", "WAKE_RTP_SPLIT": "0", "WAKE_RTP_VOLUNTARY_AHEAD": "0"}
#: The make fragment generated from FEATURE_ENTRIES (relative to the sources' directory).
FEATURES_MAKE = "wake_features.mk"


def feature_values(defs=()) -> dict:
    """Each feature switch's value in a build with the ``-D`` options ``defs`` (``-DNAME`` alone is 1).

    Examples
    --------
    >>> feature_values(["-DWAKE_RTP_SPLIT=1", "-mcpu=cortex-m4"])["WAKE_RTP_SPLIT"]
    '1'
    """
    values = dict(FEATURE_DEFAULTS)
    for d in defs:
        name, _, value = str(d).removeprefix("-D").partition("=")
        if name in values:
            values[name] = value or "1"
    return values


def firmware_entries(names, defs=(), prefixes=("wake_rtp_",)) -> list:
    """The public functions among ``names`` (those starting with one of ``prefixes``) that a firmware built
    with ``defs`` links: all but the entries of a feature the build leaves off (FEATURE_ENTRIES).

    Examples
    --------
    >>> firmware_entries(["wake_rtp_step", "wake_rtp_set_ahead", "wake_ahead_step"], ["-DWAKE_RTP_AHEAD=0"])
    ['wake_rtp_step']
    """
    values = feature_values(defs)
    off = {e for switch, entries in FEATURE_ENTRIES.items() if values[switch] == "0" for e in entries}
    return sorted(n for n in names if n.startswith(tuple(prefixes)) and n not in off)


def features_make_text() -> str:
    """csrc/wake_features.mk: FEATURE_ENTRIES for the Makefile's cross link, and ``wake_entries_off``, the
    entries a build with the flags ``$(1)`` leaves off (as firmware_entries)."""
    lines = ["# Generated from wake.firmware.sources.FEATURE_ENTRIES by `python -m wake.firmware.sources --write-make`:",
             "# do not edit (tests/firmware/test_c_layout.py checks that they agree).  The entry points of each",
             "# feature: a firmware built without the feature links none of them.", ""]
    calls = []
    for switch, entries in FEATURE_ENTRIES.items():
        lines.append(f"WAKE_ENTRIES_{switch} := {' '.join(entries)}")
        if FEATURE_DEFAULTS[switch] == "0":     # off unless the flags set it
            calls.append(f"$(if $(filter -D{switch} -D{switch}=1,$(1)),,$(WAKE_ENTRIES_{switch}))")
        else:                                   # on unless the flags set it to 0
            calls.append(f"$(if $(filter -D{switch}=0,$(1)),$(WAKE_ENTRIES_{switch}))")
    lines += ["", "# $(call wake_entries_off,FLAGS): the entries of the features a build with FLAGS leaves off",
              "wake_entries_off = " + " ".join(calls), ""]
    return "\n".join(lines)


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


def main(argv=None) -> int:
    """``python -m wake.firmware.sources --write-make [CSRC]``: write csrc/wake_features.mk from FEATURE_ENTRIES."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m wake.firmware.sources",
                                     description="Write the make fragment of the feature entries (FEATURE_ENTRIES).")
    parser.add_argument("--write-make", action="store_true", required=True,
                        help=f"write {FEATURES_MAKE} into the sources' directory")
    parser.add_argument("csrc", nargs="?", default=None, help="the csrc/ directory (default: this package's)")
    args = parser.parse_args(argv)
    path = csrc_dir(args.csrc) / FEATURES_MAKE
    path.write_text(features_make_text())
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
