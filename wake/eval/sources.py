"""Loading for ``wake evaluate``: what to evaluate, as light descriptors a worker loads itself.

A :class:`Source` names one recording without holding its samples: a file
(any format :func:`wake.io.read_recording` reads, or a PADS file), one of the
paper's ten synthetic signals, or one signal of a generated synthetic cohort
(seed and SNR drawn reproducibly).  Tasks carry sources, not arrays, so the
parent process stays small whatever the cohort size, and a worker on another
machine only needs the path.
"""

from __future__ import annotations

import glob
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wake.eval.datasets import dataset_files
from wake.eval.synthetic import PAPER_SNR_DB, make_signal
from wake.io import read_pads, read_recording
from wake.io.formats import recordings_in
from wake.io.formats.bids import is_motion_file

__all__ = ["Source", "Loaded", "READABLE_SUFFIXES", "paper_sources", "cohort_sources", "file_sources",
           "pads_sources", "pdkit_sources", "strong_sources", "load_source"]

#: File suffixes a folder given as input is searched for (what :func:`wake.io.read_recording` reads).
READABLE_SUFFIXES = (".txt", ".csv", ".tsv", ".dat", ".mat")
#: Seed of the paper's synthetic set (:func:`wake.eval.synthetic.paper_dataset`).
PAPER_SEED = 2018
#: Input SNR range (dB) of a generated cohort: the paper's range, -4.9 to 20.9 dB, rounded out.
COHORT_SNR_DB = (-5.0, 21.0)


@dataclass(frozen=True)
class Source:
    """One recording to evaluate, by reference.

    ``kind``: ``"paper"`` (signal ``index`` of the paper's synthetic set),
    ``"cohort"`` (a generated signal: ``seed``, ``snr_db``), ``"pads"`` or
    ``"file"`` (``path``).  ``key`` names it in the result store.

    Examples
    --------
    >>> from wake.eval.sources import cohort_sources
    >>> s = cohort_sources(2)[1]
    >>> s.kind, s.key, s.duration_s
    ('cohort', 'cohort/1', 50.0)
    """

    kind: str
    key: str
    index: int = 0
    path: str = ""
    seed: int = 0
    snr_db: float = float("nan")
    duration_s: float = 50.0
    fs: float = None  #: sampling rate of a file without a time column (``--fs``)

    @property
    def synthetic(self) -> bool:
        return self.kind in ("paper", "cohort", "strong")


@dataclass
class Loaded:
    """A source's samples: ``x`` (n, channels), the channel names and, for synthetic signals, the truth."""

    name: str
    fs: float
    x: np.ndarray
    channels: tuple
    voluntary: np.ndarray = None  #: (n,) known voluntary motion, synthetic only
    snr_db: float = float("nan")
    tremor: np.ndarray = None  #: (n,) the tremor component s_t alone (without the white noise), synthetic only


def paper_sources(count=None):
    """The paper's ten synthetic signals (``count``: the first ones only)."""
    snrs = PAPER_SNR_DB[: len(PAPER_SNR_DB) if count is None else count]
    return [Source("paper", f"paper/{i + 1}", index=i, seed=PAPER_SEED + i, snr_db=snr)
            for i, snr in enumerate(snrs)]


def cohort_sources(count, seed=0, duration_s=50.0):
    """``count`` generated signals: signal ``i`` has seed ``seed * 1_000_000 + i`` and an SNR drawn from it.

    The SNR is uniform over :data:`COHORT_SNR_DB`, drawn from
    ``numpy.random.default_rng([seed, i])``: the same ``(seed, i)`` always
    gives the same signal, whatever the cohort size.
    """
    if int(count) < 0:
        raise ValueError(f"--synthetic needs a count >= 0 (0: no synthetic signal), got {count}")
    out = []
    for i in range(int(count)):
        snr = float(np.random.default_rng([seed, i]).uniform(*COHORT_SNR_DB))
        out.append(Source("cohort", f"cohort/{i}" if seed == 0 else f"cohort{seed}/{i}", index=i,
                          seed=seed * 1_000_000 + i, snr_db=snr, duration_s=float(duration_s)))
    return out


def _files_in(pattern):
    path = Path(pattern)
    if path.is_dir():
        files = recordings_in(path)  # wake.io.formats: a BIDS dataset's *_motion.tsv, TSDF, CWA, EDF, Parquet ...
        if not any(is_motion_file(f) for f in files):  # a BIDS dataset's other .tsv are sidecars, not recordings
            files = sorted({*files, *(p for p in path.iterdir() if p.is_file() and p.suffix.lower() in
                                      READABLE_SUFFIXES and not p.name.lower().startswith("readme"))})
        if not files:
            raise ValueError(f"{path}: no recording in this folder (looked for {', '.join(READABLE_SUFFIXES)}, "
                             "a BIDS *_motion.tsv, a TSDF *_meta.json and the wearable formats of docs/guide/formats.md)")
        return files
    if path.is_file():
        return [path]
    matches = sorted(Path(p) for p in glob.glob(str(pattern), recursive=True) if Path(p).is_file())
    if not matches:
        raise ValueError(f"{pattern}: no such file or folder, and no file matches it as a glob pattern")
    return matches


def file_sources(patterns, kind="file", fs=None):
    """Files from folders, files and glob patterns, in the order given (each folder/glob sorted), no repeats.

    Examples
    --------
    >>> from wake.eval.sources import file_sources
    >>> file_sources(["no/such/*.csv"])
    Traceback (most recent call last):
    ...
    ValueError: no/such/*.csv: no such file or folder, and no file matches it as a glob pattern
    """
    seen, out = set(), []
    for pattern in patterns:
        for f in _files_in(pattern):
            key = str(f.resolve())
            if key not in seen:
                seen.add(key)
                out.append(Source(kind, key if fs is None else f"{key}@{fs:g}Hz", index=len(out), path=key, fs=fs))
    return out


def pads_sources(folder):
    """Every PADS recording (``*.txt``) of ``folder``, sorted by name (as ``load_pads_folder``)."""
    return file_sources(dataset_files(folder, "*.txt"), kind="pads")


def pdkit_sources(folder):
    """Every pdkit recording of ``folder`` (:func:`wake.eval.pdkit.load_pdkit_folder`'s files), sorted by name."""
    from wake.eval.pdkit import PDKIT_PATTERN

    return file_sources(dataset_files(folder, PDKIT_PATTERN, "pdkit recording"), kind="pdkit")


def strong_sources(count, duration_s=30.0):
    """``count`` signals of the synthetic strong-tremor set (:func:`wake.eval.strong_tremor.strong_tremor_dataset`)."""
    if int(count) < 0:
        raise ValueError(f"--strong needs a count >= 0, got {count}")
    return [Source("strong", f"strong/{i}", index=i, duration_s=float(duration_s)) for i in range(int(count))]


def load_source(source: Source) -> Loaded:
    """Read or generate ``source``'s samples (in the worker that evaluates it)."""
    if source.kind == "strong":
        from wake.eval.strong_tremor import KINDS, STRONG_SEED, make_strong_tremor

        s = make_strong_tremor(seed=STRONG_SEED + source.index, duration=source.duration_s,
                               kind=KINDS[source.index % 2])
        return Loaded(s.name, s.fs, s.measurement[:, None], ("x",), s.voluntary, float("nan"), s.tremor)
    if source.kind == "pdkit":
        from wake.eval.pdkit import load_pdkit

        rec = load_pdkit(source.path).recording
        return Loaded(rec.name, rec.fs, rec.samples, tuple(rec.channels))
    if source.synthetic:
        s = make_signal(source.snr_db, seed=source.seed, duration=source.duration_s)
        name = f"signal {source.index + 1}" if source.kind == "paper" else f"cohort signal {source.index}"
        return Loaded(name, s.fs, s.measurement[:, None], ("x",), s.voluntary, s.snr_db, s.tremor)
    rec = read_pads(source.path) if source.kind == "pads" else read_recording(source.path, fs=source.fs)
    return Loaded(rec.name, rec.fs, rec.samples, tuple(rec.channels))
