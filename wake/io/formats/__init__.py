"""Readers of wearable and research formats, each through the library of its field, behind an optional extra.

:func:`wake.io.read_recording` asks :func:`resolve` whether a path is one of
these formats (by its suffix, and where a suffix is shared, by its content)
and, when it is, reads it with :func:`read_table` and applies the rules every
format shares (channel choice, units, time, the uniform grid, missing
samples) itself, as it does for delimited text.

========== ============================== ======================== ====================
format     files                          library                  extra
========== ============================== ======================== ====================
cwa        Axivity ``.cwa``               actfast                  ``wearables``
gt3x       ActiGraph ``.gt3x``            actfast                  ``wearables``
geneactiv  GENEActiv ``.bin``             actfast                  ``wearables``
edf        ``.edf``, ``.bdf`` (EDF+, BDF)  edfio                    ``edf``
tsdf       ``*_meta.json`` (+ ``.bin``)    tsdf                     ``tsdf``
parquet    ``.parquet``, ``.pq``          pyarrow                  ``parquet``
bids       ``sub-*_motion.tsv``           (the standard library)   ``bids`` (nothing)
========== ============================== ======================== ====================

A folder is read when it holds exactly one recording of these formats (a
BIDS dataset with one ``*_motion.tsv``, a TSDF folder with one metadata
file); :func:`recordings_in` lists them all (``wake evaluate`` takes each).
A missing library raises :class:`MissingExtraError` (an ImportError and a
ValueError) naming the ``pip install "wake-tremor[...]"`` that brings it.

Examples
--------
>>> from pathlib import Path
>>> from wake.io.formats import format_of
>>> format_of(Path("sub-01_task-rest_tracksys-imu_motion.tsv")), format_of(Path("rec.EDF")), format_of(Path("a.csv"))
('bids', 'edf', None)
"""

from __future__ import annotations

from pathlib import Path

from wake.io.formats import bids
from wake.io.formats._base import MissingExtraError, Table, require

__all__ = ["FORMATS", "EXTRAS", "NAMED_COLUMNS", "MissingExtraError", "Table", "format_of", "read_table",
           "recordings_in", "require", "resolve"]

#: Each format of this package -> the pyproject extra that installs its library.
EXTRAS = {"cwa": "wearables", "gt3x": "wearables", "geneactiv": "wearables", "edf": "edf", "tsdf": "tsdf",
          "parquet": "parquet", "bids": "bids"}
#: The formats of this package, as ``read_recording(format=...)`` and ``--format`` name them.
FORMATS = tuple(EXTRAS)
#: Formats of named columns without a clock of their own: the time column is found as in delimited text.
NAMED_COLUMNS = ("parquet",)
_SUFFIXES = {".cwa": "cwa", ".gt3x": "gt3x", ".edf": "edf", ".bdf": "edf", ".rec": "edf", ".parquet": "parquet",
             ".pq": "parquet"}


def format_of(path: Path):
    """The format of file ``path`` by its suffix and, for ``.bin`` and ``.json``, its content; None: not one of
    these (delimited text or MATLAB, read by :mod:`wake.io.readers`)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if bids.is_motion_file(path) or (path.name.endswith("_motion.json") and path.name.startswith("sub-")):
        return "bids"
    if suffix in _SUFFIXES:
        return _SUFFIXES[suffix]
    if suffix == ".json" and path.is_file():
        from wake.io.formats.tsdf_data import is_tsdf_meta

        return "tsdf" if is_tsdf_meta(path) else None
    if suffix == ".bin":
        from wake.io.formats.tsdf_data import tsdf_meta_for

        return "tsdf" if path.is_file() and tsdf_meta_for(path) is not None else "geneactiv"
    return None


def recordings_in(folder: Path) -> list:
    """The recordings of ``folder`` in these formats: a dataset's ``*_motion.tsv`` (at any depth), TSDF metadata
    files and files with these formats' suffixes (in the folder itself), sorted."""
    from wake.io.formats.tsdf_data import is_tsdf_meta

    folder = Path(folder)
    found = bids.motion_files(folder)
    for p in sorted(folder.iterdir()):
        if not p.is_file() or p in found:
            continue
        suffix = p.suffix.lower()
        if suffix in _SUFFIXES or (suffix == ".json" and is_tsdf_meta(p)):
            found.append(p)
        elif suffix == ".bin" and format_of(p) == "geneactiv":
            found.append(p)
    return found


def resolve(path, format="auto"):
    """``(file, format)`` when ``path`` is to be read by this package, else None.

    A folder resolves to its one recording (:func:`recordings_in`); none or
    several raise a ValueError that lists what was found.  A TSDF binary file
    resolves to its metadata file, a Motion-BIDS ``*_motion.json`` to its data.
    """
    path = Path(path)
    if format not in ("auto", *FORMATS):
        return None
    if path.is_dir():
        found = recordings_in(path)
        if format != "auto":
            found = [p for p in found if format_of(p) == format]
        if len(found) != 1:
            listed = "; ".join(str(p.relative_to(path)) for p in found[:6]) + (" ..." if len(found) > 6 else "")
            raise ValueError(f"{path}: a folder is read when it holds exactly one recording (a BIDS *_motion.tsv, a "
                             f"TSDF *_meta.json, a .cwa/.gt3x/.bin/.edf/.bdf/.parquet file); "
                             + (f"it holds {len(found)}: {listed}; give one of them" if found else "it holds none")
                             + " (wake evaluate takes a folder of several)")
        path = found[0]
    fmt = format_of(path) if format == "auto" else format
    if fmt is None:
        return None
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    if fmt == "tsdf" and path.suffix.lower() == ".bin":
        from wake.io.formats.tsdf_data import tsdf_meta_for

        meta = tsdf_meta_for(path)
        if meta is None:
            raise ValueError(f"{path}: no TSDF metadata file (*_meta.json) beside it names this file")
        path = meta
    if fmt == "bids" and path.name.endswith("_motion.json"):
        path = path.with_name(path.name[:-len("_motion.json")] + bids.MOTION_SUFFIX)
    return path, fmt


def read_table(path: Path, fmt: str, columns=None) -> Table:
    """Read ``path`` (resolved by :func:`resolve`) in format ``fmt`` with its library."""
    if fmt in ("cwa", "gt3x", "geneactiv"):
        from wake.io.formats.wearables import read_wearable

        return read_wearable(path, fmt)
    if fmt == "edf":
        from wake.io.formats.edf import read_edf

        return read_edf(path, columns)
    if fmt == "tsdf":
        from wake.io.formats.tsdf_data import read_tsdf

        return read_tsdf(path)
    if fmt == "parquet":
        from wake.io.formats.parquet import read_parquet

        return read_parquet(path)
    if fmt == "bids":
        if not bids.is_motion_file(path):
            raise ValueError(f"{path}: a Motion-BIDS recording is a sub-<label>_..._motion.tsv file")
        return bids.read_bids(path)
    raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {fmt!r}")
