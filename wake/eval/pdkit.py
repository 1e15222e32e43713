"""pdkit's smartphone tremor-task recordings as an evaluation dataset.

Thirteen recordings of MDS-UPDRS tremor tasks (the test data of the open-source pdkit project, MIT licence;
the folder's README.md says where they come from): plain CSV, no header, 5 columns (a timestamp in ns,
acceleration x/y/z in m/s^2 with gravity, a status field), 100 Hz nominal with jitter.  :func:`load_pdkit`
resamples the three axes onto a uniform grid on the timestamps (:func:`wake.io.read_csv`); gravity and the
start transient (the phone being put in place) stay in the samples: they are what a device sees, and the
truth (:func:`wake.eval.truth.tremor_truth`) is built to survive them.

The file name says the task and the limb: ``T_-_<TASK>_-_<LIMB>_-_<date>_<time>_-_<id>_-_<subject>.csv``.
:data:`TREMOR_TASKS` are the tasks that ask for tremor (rest, postural, kinetic); pronation-supination and
leg agility are voluntary rhythms at 3-4.5 Hz.  :func:`tremor_axes` picks the axes where tremor dominates.

The folder is found through ``$WAKE_PDKIT_DIR``, an explicit path, or ``../shared/data/pdkit`` next to the
current directory (:func:`default_pdkit_dir`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wake.eval.datasets import dataset_files, default_data_dir
from wake.io import Recording, read_csv

__all__ = ["PDKIT_CHANNELS", "PDKIT_UNITS", "TREMOR_TASKS", "PdkitRecording", "load_pdkit", "load_pdkit_folder",
           "default_pdkit_dir", "band_ratio", "tremor_axes"]

PDKIT_CHANNELS = ("acc_x", "acc_y", "acc_z")
PDKIT_UNITS = ("m/s^2", "m/s^2", "m/s^2")
#: Tasks of the MDS-UPDRS that ask for tremor (the others are voluntary rhythms).
TREMOR_TASKS = ("REST_TREMOR_AMPLITUDE", "POSTURAL_TREMOR_OF_THE_HANDS", "KINETIC_TREMOR_OF_HANDS")


@dataclass(frozen=True)
class PdkitRecording:
    """A pdkit recording: the uniform :class:`~wake.io.Recording` and what its file name says."""

    recording: Recording
    task: str  #: e.g. "REST_TREMOR_AMPLITUDE"
    limb: str  #: e.g. "LEFT_HAND"
    subject: str

    @property
    def tremor_task(self) -> bool:
        return self.task in TREMOR_TASKS

    @property
    def label(self) -> str:
        return f"{self.task} {self.limb} {self.subject}"


def _parse_name(path):
    parts = Path(path).stem.split("_-_")
    if len(parts) != 6 or parts[0] != "T":
        raise ValueError(f"{path}: not a pdkit tremor-task file name (T_-_<TASK>_-_<LIMB>_-_<date>_<time>_-_"
                         f"<id>_-_<subject>.csv)")
    return parts[1], parts[2], parts[5]


def load_pdkit(path, fs=100.0) -> PdkitRecording:
    """One pdkit recording on a uniform ``fs`` grid, its three acceleration axes in m/s^2 (gravity included).

    Parameters
    ----------
    path : str or Path
        A ``T_-_..._-_<subject>.csv`` file of the pdkit test data.
    fs : float
        Grid rate, Hz (the phone's nominal 100 Hz by default).

    Returns
    -------
    PdkitRecording

    Examples
    --------
    >>> from wake.eval.pdkit import default_pdkit_dir, load_pdkit
    >>> folder = default_pdkit_dir()
    >>> if folder is not None:                     # doctest: +SKIP
    ...     r = load_pdkit(sorted(folder.glob("*.csv"))[0])
    ...     r.recording.channels
    ('acc_x', 'acc_y', 'acc_z')
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    task, limb, subject = _parse_name(path)
    rec = read_csv(path, fs=fs, time_column=0, columns=[1, 2, 3])
    if rec.samples.shape[1] != 3:
        raise ValueError(f"{path}: a pdkit recording has 5 columns (time in ns, acceleration x/y/z, status); "
                         f"read {rec.samples.shape[1]} acceleration columns")
    from dataclasses import replace
    rec = replace(rec, name=f"{task}_{limb}_{subject}", channels=PDKIT_CHANNELS, units=PDKIT_UNITS)
    return PdkitRecording(rec, task, limb, subject)


#: pdkit's recordings in its folder (README.md and LICENSE beside them are not)
PDKIT_PATTERN = "T_-_*.csv"


def load_pdkit_folder(folder, fs=100.0, tremor_only=False) -> list:
    """Every pdkit recording in ``folder`` (sorted by file name); ``tremor_only``: the :data:`TREMOR_TASKS`.

    Other files (README.md, LICENSE) are ignored.
    """
    files = dataset_files(folder, PDKIT_PATTERN, "pdkit recording")
    out = [load_pdkit(p, fs) for p in files]
    return [r for r in out if r.tremor_task] if tremor_only else out


def default_pdkit_dir(explicit=None, cwd=None):
    """Where the pdkit folder is: ``explicit``, else ``$WAKE_PDKIT_DIR``, else ``../shared/data/pdkit``
    relative to ``cwd`` (the current directory) if it exists; ``None`` when none applies."""
    return default_data_dir("pdkit", "WAKE_PDKIT_DIR", explicit, cwd)


def band_ratio(x, fs, tremor=(3.0, 12.0), slow=(0.2, 2.5)):
    """Welch power in the ``tremor`` band over the power in the ``slow`` band (mean removed, 512 samples).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(3000) / 100.0
    >>> band_ratio(np.sin(2 * np.pi * 6 * t) + 0.1 * np.sin(2 * np.pi * 1 * t), 100.0) > 10
    True
    """
    import scipy.signal  # here, not at import: it parses docstrings for about a second (issue 44)

    x = np.asarray(x, dtype=float)
    f, p = scipy.signal.welch(x - x.mean(), fs=fs, nperseg=min(512, x.size))
    hi = p[(f >= tremor[0]) & (f <= tremor[1])].sum()
    lo = p[(f >= slow[0]) & (f <= slow[1])].sum()
    return float(hi / lo) if lo > 0 else float("inf")


def tremor_axes(recordings, min_ratio=1.0):
    """``[(PdkitRecording, channel index), ...]``: the axes of tremor tasks whose 3-12 Hz power is at least
    ``min_ratio`` times their 0.2-2.5 Hz power (:func:`band_ratio`); on the 13 files, 13 axes.
    """
    return [(r, c) for r in recordings if r.tremor_task for c in range(r.recording.samples.shape[1])
            if band_ratio(r.recording.samples[:, c], r.recording.fs) >= min_ratio]
