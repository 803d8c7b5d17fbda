"""The manifest of an output folder (``.auvplan-manifest.json``): the files auvplan wrote there and the job that
wrote them, each update of it written atomically (:func:`_replace`: a temporary file, flushed, renamed into place).

:mod:`.safeio` reads it before it replaces a file (a file not in it is a user's, never overwritten) and records each
file it writes; ``report`` and ``export`` add their files to a folder's list, the job stays the one that made it.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

__all__ = ["MANIFEST", "written", "written_by", "claim", "disown"]

MANIFEST = ".auvplan-manifest.json"
"""Name of the manifest file in an output folder."""


def written(folder: Path) -> set[str]:
    """Return the names of the files auvplan wrote into ``folder`` (its manifest).

    Parameters
    ----------
    folder : pathlib.Path
        An output folder.

    Returns
    -------
    set of str
        File names; empty when there is no manifest or it is unreadable.
    """
    p = Path(folder) / MANIFEST
    if p.is_symlink() or not p.is_file():
        return set()
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
        return {str(n) for n in data.get("files", [])} if isinstance(data, dict) else set()
    except (OSError, ValueError):
        return set()


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _replace(path: Path, data: bytes) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600; results are ordinary files
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)  # replaces a link itself, never its target
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def written_by(folder: Path) -> str:
    """The command whose results a folder holds (its manifest's ``job``; '' when it does not say).

    Parameters
    ----------
    folder : pathlib.Path
        An output folder.

    Returns
    -------
    str
        ``run``, ``survey``, ``plan`` … or ''.
    """
    p = Path(folder) / MANIFEST
    if p.is_symlink() or not p.is_file():
        return ""
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return ""
    job = data.get("job", "") if isinstance(data, dict) else ""
    return job if isinstance(job, str) else ""


def _record(folder: Path, names: Iterable[str], job: str = "") -> None:
    have, was = written(folder), written_by(folder)
    new = have | set(names)
    if new != have or (job and job != was):
        doc: dict[str, object] = {"files": sorted(new)}
        if job or was:
            doc["job"] = job or was
        _replace(folder / MANIFEST, (json.dumps(doc, indent=1) + "\n").encode())


def claim(folder: Path, names: Iterable[str]) -> None:
    """Record files auvplan writes in ``folder`` by other means (append-only logs) in its manifest.

    Parameters
    ----------
    folder : pathlib.Path
        The output folder.
    names : iterable of str
        File names to record.
    """
    _record(Path(folder), names)


def disown(folder: Path, names: Iterable[str]) -> list[str]:
    """Remove the files of ``names`` that auvplan wrote into ``folder`` (its manifest lists them; regular files,
    never a symbolic link) and their names from the manifest: an earlier job's results that the job writing the
    folder now does not write, which would otherwise be taken for its own.  A user's file is left alone.

    Parameters
    ----------
    folder : pathlib.Path
        The output folder.
    names : iterable of str
        File names.

    Returns
    -------
    list of str
        The names removed, in the order given.
    """
    folder = Path(folder)
    have = written(folder)
    gone = [n for n in names if n in have and (folder / n).is_file() and not (folder / n).is_symlink()]
    for n in gone:
        (folder / n).unlink()
    dropped = [n for n in names if n in have and not os.path.lexists(folder / n)]
    if dropped:
        doc: dict[str, object] = {"files": sorted(have - set(dropped))}
        if written_by(folder):
            doc["job"] = written_by(folder)
        _replace(folder / MANIFEST, (json.dumps(doc, indent=1) + "\n").encode())
    return gone
