"""Motion-BIDS: read a recording of a BIDS dataset, and write wake's results as a BIDS derivative.

Motion-BIDS (the BIDS extension for motion data, in the specification since
version 1.9.0) stores a recording as three files that share their entities
(``sub-01_task-tremor_tracksys-imu_``):

- ``*_motion.tsv``: the samples, one column per channel, tab-separated, no
  header, ``n/a`` for a missing value;
- ``*_channels.tsv``: one row per column of the data (with a header): its
  ``name``, ``component`` (x, y, z, n/a), ``type`` (ACCEL, GYRO, MAGN, ORNT,
  POS, ..., LATENCY), ``tracked_point`` and ``units``;
- ``*_motion.json``: ``SamplingFrequency`` (Hz), ``TaskName``, ...

A sidecar is taken from beside the data file or, by the inheritance principle,
from a folder above it whose file name's entities all belong to the data file.
The channels are named and united as ``*_channels.tsv`` says; a LATENCY
channel (in s or ms) is the time of every row, else row ``i`` is at
``i / SamplingFrequency``; a channel whose ``status`` is ``bad`` is left out.
No extra package is needed: the standard library reads TSV and JSON.

``wake run ... --bids-out DIR`` writes the filtered signals of such a
recording as a derivative dataset (:func:`write_derivative`).

Examples
--------
>>> from wake.io import read_recording
>>> rec = read_recording("ds/sub-01/motion/sub-01_task-rest_tracksys-imu_motion.tsv")   # doctest: +SKIP
>>> rec.channels, rec.units                                                             # doctest: +SKIP
(('gyro_x', 'gyro_y', 'gyro_z'), ('rad/s', 'rad/s', 'rad/s'))
"""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path

import numpy as np

from wake.io.formats._base import Table, normalise_unit

__all__ = ["MOTION_SUFFIX", "derivative_writer", "is_motion_file", "entities", "motion_files", "read_bids",
           "write_derivative"]

MOTION_SUFFIX = "_motion.tsv"
#: The BIDS version of the derivatives written (Motion-BIDS is part of BIDS from 1.9.0).
BIDS_VERSION = "1.9.0"
#: Folders of a dataset that hold no raw recording.
_NOT_RAW = ("derivatives", "sourcedata", "code", "stimuli")
_ENTITY = re.compile(r"^([a-zA-Z]+)-([a-zA-Z0-9]+)$")
#: The time unit of a LATENCY channel -> seconds per unit.
_LATENCY = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9}
_DESC = "wake"


def is_motion_file(path) -> bool:
    """``sub-<label>_..._motion.tsv``: a Motion-BIDS data file by its name."""
    name = Path(path).name
    return name.endswith(MOTION_SUFFIX) and name.startswith("sub-")


def entities(path) -> dict:
    """``sub-01_task-x_tracksys-imu_motion.tsv`` -> ``{"sub": "01", "task": "x", "tracksys": "imu"}``."""
    stem = Path(path).name.split(".", 1)[0]
    parts = stem.split("_")[:-1]  # the last part is the suffix (motion, channels)
    out = {}
    for part in parts:
        m = _ENTITY.match(part)
        if not m:
            raise ValueError(f"{path}: {part!r} is not a BIDS entity (key-label, e.g. sub-01, task-rest)")
        out[m.group(1)] = m.group(2)
    return out


def motion_files(folder: Path) -> list:
    """Every ``*_motion.tsv`` of a dataset's folder (not under derivatives/, sourcedata/), sorted."""
    folder = Path(folder)
    return sorted(p for p in folder.rglob(f"*{MOTION_SUFFIX}") if p.is_file() and is_motion_file(p)
                  and not any(part in _NOT_RAW or part.startswith(".") for part in p.relative_to(folder).parts[:-1]))


def _root(path: Path) -> Path:
    """The dataset's folder: the nearest above ``path`` with a ``dataset_description.json`` (else ``path``'s)."""
    for folder in path.parents:
        if (folder / "dataset_description.json").is_file():
            return folder
    return path.parent


def sidecar(path: Path, suffix: str):
    """The ``*_<suffix>`` file that applies to data file ``path`` (inheritance principle), or None."""
    own = entities(path)
    root = _root(path)
    for folder in [path.parent, *path.parent.parents]:
        best = None
        for cand in folder.glob(f"*_{suffix}"):
            try:
                ents = entities(cand)
            except ValueError:
                continue
            if all(own.get(k) == v for k, v in ents.items()) and (best is None or len(ents) > len(best[0])):
                best = (ents, cand)
        if best:
            return best[1]
        if folder == root:
            break
    return None


def _channels(path: Path, width: int) -> list:
    """The rows of the recording's ``*_channels.tsv`` (dicts), checked against the data's width."""
    found = sidecar(path, "channels.tsv")
    if found is None:
        raise ValueError(f"{path}: no *_channels.tsv for this recording (beside it or above it); Motion-BIDS "
                         "names and units every column there (to read the file as plain text: --format csv)")
    with open(found, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    missing = [c for c in ("name", "type", "units") if rows and c not in rows[0]]
    if not rows or missing:
        raise ValueError(f"{found}: a channels table needs the columns name, component, type, tracked_point, "
                         f"units{'; missing: ' + ', '.join(missing) if missing else ' and a row per channel'}")
    if len(rows) != width:
        raise ValueError(f"{found} lists {len(rows)} channels but {path.name} has {width} columns")
    return rows


def _motion_json(path: Path) -> dict:
    found = sidecar(path, "motion.json")
    if found is None:
        raise ValueError(f"{path}: no *_motion.json for this recording (beside it or above it); Motion-BIDS gives "
                         "the SamplingFrequency there")
    try:
        with open(found, encoding="utf-8") as f:
            meta = json.load(f)
    except ValueError as exc:
        raise ValueError(f"{found}: not valid JSON ({exc})") from None
    return meta


def _samples(path: Path) -> np.ndarray:
    rows = []
    with open(path, encoding="utf-8") as f:
        for lineno, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                cells = line.rstrip("\r\n").split("\t")
                rows.append([math.nan if c.strip() in ("n/a", "") else float(c) for c in cells])
            except ValueError:
                raise ValueError(f"{path}, line {lineno}: not tab-separated numbers ('n/a' for a missing value); "
                                 "a Motion-BIDS data file has no header row") from None
            if len(rows[-1]) != len(rows[0]):
                raise ValueError(f"{path}, line {lineno}: {len(rows[-1])} values where line 1 has {len(rows[0])}")
    if len(rows) < 2:
        raise ValueError(f"{path}: need at least two rows, the file has {len(rows)}")
    return np.asarray(rows, dtype=float)


def read_bids(path: Path) -> Table:
    """A Motion-BIDS recording from its ``*_motion.tsv`` (module docstring)."""
    ents = entities(path)
    data = _samples(path)
    rows = _channels(path, data.shape[1])
    meta = _motion_json(path)
    notes = [f"Motion-BIDS {', '.join(f'{k}-{v}' for k, v in ents.items())}"]
    time = None
    keep = []
    for j, row in enumerate(rows):
        kind = row.get("type", "").strip().upper()
        if kind == "LATENCY" and time is None:
            unit = row.get("units", "s").strip()
            if unit not in _LATENCY:
                raise ValueError(f"{path}: LATENCY channel {row['name']!r} in {unit!r}; expected s or ms")
            time = data[:, j] * _LATENCY[unit]
        elif row.get("status", "").strip().lower() == "bad":
            notes.append(f"channel {row['name']} left out (status bad)")
        else:
            keep.append(j)
    if time is None:
        fs = meta.get("SamplingFrequency")
        if not isinstance(fs, (int, float)) or isinstance(fs, bool) or not fs > 0:
            raise ValueError(f"{path}: the motion.json's SamplingFrequency is {fs!r}; give a rate in Hz, or a "
                             "LATENCY channel with the time of every row")
        time = np.arange(data.shape[0]) / float(fs)
    if not keep:
        raise ValueError(f"{path}: no channel to filter (every one is LATENCY or bad)")
    names = [rows[j]["name"].strip() for j in keep]
    units = [normalise_unit(rows[j]["units"]) if rows[j]["units"].strip() != "n/a" else "" for j in keep]
    return Table(path.name[:-len(MOTION_SUFFIX)], names, units, data[:, keep], time=time - time[0],
                 notes=tuple(notes), meta={"entities": ents, "channels": [rows[j] for j in keep], "json": meta})


def _derivative_name(source: Path) -> str:
    """``sub-01_task-x_tracksys-imu_motion.tsv`` -> ``sub-01_task-x_tracksys-imu_desc-wake``: desc is the last
    entity before the suffix, as the specification orders them."""
    ents = {k: v for k, v in entities(source).items() if k != "desc"}
    return "_".join([*(f"{k}-{v}" for k, v in ents.items()), f"desc-{_DESC}"])


def check_derivative_source(path) -> Path:
    """``path`` if it is a Motion-BIDS data file, else a ValueError that says which inputs ``--bids-out`` takes."""
    path = Path(path)
    if not is_motion_file(path):
        raise ValueError(f"--bids-out writes a BIDS derivative of a Motion-BIDS recording (a sub-*_motion.tsv, "
                         f"or a dataset folder holding one); {path.name} is not one: write --out CSV instead")
    return path


def derivative_writer(out_dir, rec, version: str):
    """For ``wake run --bids-out DIR``: check now, before the work, that ``rec`` was read from a Motion-BIDS file,
    and return ``write(rec, result, filt)``, which writes the derivative of ``rec`` (as filtered: after
    ``--combine``, its channels) (:func:`write_derivative`) and says so."""
    check_derivative_source(rec.source)

    def write(rec, result, filt) -> str:
        settings = {"wavelet": filt.wavelet, "level": filt.level, "window_s": filt.window_s,
                    "ar_order": filt.ar_order, "cutoff_rule": filt.config.cutoff_rule, "backend": filt.backend}
        paths = write_derivative(out_dir, rec, result, settings, version)
        return f"wrote a BIDS derivative to {out_dir}: {', '.join(p.name for p in paths[1:])}"

    return write


def write_derivative(out_dir, rec, result, settings: dict, version: str) -> list:
    """Write ``result`` (of ``rec``, read from a Motion-BIDS file) as a BIDS derivative dataset in ``out_dir``.

    The dataset gets a ``dataset_description.json`` (``DatasetType``
    ``derivative``, ``GeneratedBy`` wake ``version``) and, in the source's
    ``sub-*/[ses-*/]motion/`` folder, the recording's entities with
    ``desc-wake``: ``_motion.tsv`` (per channel its voluntary motion, then its
    tremor; ``n/a`` for a missing value), ``_channels.tsv`` (the source's
    type, component, tracked point and unit of each) and ``_motion.json``
    (the rate, the source's task and tracking system, the WAKE ``settings``
    and the source file).  Returns the paths written.
    """
    source = check_derivative_source(rec.source)
    table = read_bids(source)
    by_name = {row["name"].strip(): row for row in table.meta["channels"]}
    out_dir = Path(out_dir)
    ents = table.meta["entities"]
    folder = out_dir / f"sub-{ents['sub']}"
    if "ses" in ents:
        folder = folder / f"ses-{ents['ses']}"
    folder = folder / "motion"
    folder.mkdir(parents=True, exist_ok=True)
    written = [_description(out_dir, version)]
    stem = folder / _derivative_name(source)
    vol = np.asarray(result.voluntary, dtype=float).reshape(rec.samples.shape[0], -1)
    tre = np.asarray(result.tremor, dtype=float).reshape(rec.samples.shape[0], -1)
    cols = np.column_stack([a for c in range(vol.shape[1]) for a in (vol[:, c], tre[:, c])])
    with open(f"{stem}_motion.tsv", "w", encoding="utf-8", newline="") as f:
        for row in cols:
            f.write("\t".join("n/a" if not math.isfinite(v) else repr(float(v)) for v in row) + "\n")
    with open(f"{stem}_channels.tsv", "w", encoding="utf-8", newline="") as f:
        f.write("name\tcomponent\ttype\ttracked_point\tunits\tdescription\n")
        for c, name in enumerate(rec.channels):
            src = by_name.get(name, {})
            for kind, what in (("voluntary", "voluntary motion"), ("tremor", "tremor")):
                cells = [f"{name}_{kind}", src.get("component", "n/a") or "n/a", src.get("type", "MISC") or "MISC",
                         src.get("tracked_point", "n/a") or "n/a", rec.unit(c) or "n/a",
                         f"the {what} of {name} extracted by WAKE"]
                f.write("\t".join(cells) + "\n")
    sidecar_json = {k: v for k, v in table.meta["json"].items() if not k.endswith("ChannelCount")}
    sidecar_json.update({
        "SamplingFrequency": float(rec.fs),
        "Description": "WAKE (wavelet decomposition + adaptive Kalman filtering): per channel the voluntary motion "
                       "(predicted from the samples before each one) and the tremor (the measurement minus it)",
        "Sources": [f"bids:raw:{_relative(source)}"],
        "WAKEParameters": settings,
    })
    counts = {}
    for name in rec.channels:
        kind = (by_name.get(name, {}).get("type") or "MISC").strip().upper()
        counts[kind] = counts.get(kind, 0) + 2
    for kind, n in counts.items():
        sidecar_json[f"{kind}ChannelCount"] = n
    with open(f"{stem}_motion.json", "w", encoding="utf-8") as f:
        json.dump(sidecar_json, f, indent=2)
        f.write("\n")
    written += [Path(f"{stem}{s}") for s in ("_motion.tsv", "_channels.tsv", "_motion.json")]
    return written


def _relative(source: Path) -> str:
    root = _root(source)
    try:
        return source.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return source.name


def _description(out_dir: Path, version: str) -> Path:
    """``dataset_description.json`` of the derivative dataset: written once, kept when it is wake's."""
    path = out_dir / "dataset_description.json"
    if path.is_file():
        try:
            with open(path, encoding="utf-8") as f:
                old = json.load(f)
        except ValueError:
            old = {}
        if old.get("DatasetType") == "derivative" and any(g.get("Name") == "wake" for g in old.get("GeneratedBy", [])):
            return path
        raise ValueError(f"--bids-out {out_dir}: it holds a dataset_description.json that is not of a wake "
                         "derivative; choose an empty folder (e.g. <dataset>/derivatives/wake)")
    desc = {"Name": "WAKE tremor extraction", "BIDSVersion": BIDS_VERSION, "DatasetType": "derivative",
            "GeneratedBy": [{"Name": "wake", "Version": version,
                             "Description": "real-time pathological tremor extraction (wavelets + adaptive Kalman "
                                            "filtering)"}]}
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(desc, f, indent=2)
        f.write("\n")
    return path
