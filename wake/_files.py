"""Writing output files without destroying anything: no output over an input, no half-written file."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

__all__ = ["check_output_path", "refuse_same_file", "atomic_write_text", "silence_stdout"]


def check_output_path(out, *, option="--out"):
    """Raise ValueError, before any work, when ``out`` cannot be written: its folder is missing (or is not
    a folder), ``out`` is a folder, or the folder is not writable.

    Examples
    --------
    >>> from wake._files import check_output_path
    >>> check_output_path("/nonexistent/dir/o.csv")
    Traceback (most recent call last):
    ...
    ValueError: --out /nonexistent/dir/o.csv: the folder /nonexistent/dir does not exist; create it first or \
choose another path
    """
    path = Path(out)
    folder = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise ValueError(f"{option} {out} is a folder; give a file name in it (e.g. {path / 'out.csv'})")
    if not folder.exists():
        raise ValueError(f"{option} {out}: the folder {folder} does not exist; create it first or choose another "
                         "path")
    if not folder.is_dir():
        raise ValueError(f"{option} {out}: {folder} is a file, not a folder; choose another path")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{option} {out}: the folder {folder} is not writable; choose another path")


def refuse_same_file(out, inputs, *, option="--out"):
    """Raise ValueError when ``out`` is (or links to) one of ``inputs``.

    Compares the files themselves (``os.path.samefile``), so a symbolic
    link, a hard link or another spelling of the same path is caught.
    """
    out_path = Path(out)
    if not out_path.exists():
        return
    for inp in inputs:
        if inp is None:
            continue
        try:
            same = os.path.samefile(out_path, inp)
        except OSError:
            continue
        if same:
            raise ValueError(f"{option} {out} is the input file {inp}: writing it would destroy the recording; "
                             "choose another output path")


def _new_file_mode() -> int:
    """The mode ``open(path, "w")`` would give a new file: 0o666 less the process's umask."""
    mask = os.umask(0o022)  # the umask can only be read by setting it: put it straight back
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write_text(path, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder and ``os.replace``.

    A crash or a full disk leaves the old file (or none), never half of the
    new one. A symbolic link at ``path`` is followed: its target is replaced.
    The file gets the mode a plain ``open(path, "w")`` would give it: an
    existing file keeps its mode, a new one follows the umask (the temporary
    file's own 0600 is not passed on).
    """
    target = Path(os.path.realpath(path))
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "w", encoding=encoding, newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, target.stat().st_mode & 0o7777 if target.exists() else _new_file_mode())
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def silence_stdout() -> None:
    """Point standard output at the null device, after its reader has gone (a broken pipe).

    Without this, Python's own flush at exit reports the broken pipe a second time.
    """
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):
        pass
