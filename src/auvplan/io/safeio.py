"""Safe output folders: atomic writes, a manifest of what auvplan wrote, no symlinks followed.

Every result file goes through :func:`atomic_write`: the bytes go to a temporary file in the
same folder, are flushed to disk, and replace the target with one ``os.replace`` — a reader (or
an interrupted run) sees the old file or the new one, never half of one.  The folder's
``.auvplan-manifest.json`` lists the files auvplan wrote there; a file that is not in it (a
user's own ``mission.csv``) is never replaced unless the caller adopted it first
(:func:`prepare_out` with ``force=True``), and a symbolic link is never written through (with
``force`` the link itself is replaced, its target is left alone).
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

from ..errors import AuvplanError

__all__ = ["MANIFEST", "RESULT_NAMES", "OutputError", "atomic_write", "claim", "write_new", "prepare_out", "written"]

MANIFEST = ".auvplan-manifest.json"
"""Name of the manifest file in an output folder."""

RESULT_NAMES = (
    "run.json", "run.npz", "metrics.json", "path.csv", "route.csv", "keys.csv", "sim_metrics.json", "track.csv",
    "scenario.toml", "source.json", "terrain.npz", "report.html", "mission.geojson", "mission.kml", "mission.csv",
    "mission.moos", "mission.plan", "mission.gpx", "mission.yaml", "rows.csv", "histories.jsonl", "summary.csv",
    "summary.md", "bench.html", "bench.png", "legs.csv",
)
"""File names a command may write into ``--out`` (checked before any work starts)."""


class OutputError(AuvplanError, OSError):
    """An output folder or file cannot be written safely (names the path and why)."""


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


def _record(folder: Path, names: Iterable[str]) -> None:
    have = written(folder)
    new = have | set(names)
    if new != have:
        _replace(folder / MANIFEST, (json.dumps({"files": sorted(new)}, indent=1) + "\n").encode())


def write_new(path: Path, data: str, *, force: bool = False) -> Path:
    """Write a file the user will edit (no manifest), atomically.

    Refused when it exists unless ``force``; never through a symbolic link.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    data : str
        Its text.
    force : bool, optional
        Overwrite an existing file.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    if path.is_symlink() and not force:
        raise OutputError(f"{path}: is a symbolic link; not followed (pass --force to replace the link)")
    if path.exists() and not force:
        raise OutputError(f"{path}: exists; not overwritten (pass --force to replace it)")
    if path.is_dir():
        raise OutputError(f"{path}: is a folder")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        _replace(path, data.encode("utf-8"))
    except OSError as exc:
        raise OutputError(f"{path}: cannot write ({exc.strerror or exc})") from exc
    return path


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


def atomic_write(path: Path, data: bytes | str) -> Path:
    """Write ``data`` to ``path`` atomically (temp file + rename) and record it in the folder's manifest.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    data : bytes or str
        Its content (text is written as UTF-8).

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OutputError
        When ``path`` is a symbolic link, a folder, or an existing file auvplan did not write
        (not in the manifest), or when the folder cannot be written.
    """
    path = Path(path)
    folder = path.parent
    if isinstance(data, str):
        data = data.encode("utf-8")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if path.is_symlink():
            raise OutputError(f"{path}: is a symbolic link; auvplan does not write through links "
                              "(remove it, or pass --force to replace the link itself)")
        if path.is_dir():
            raise OutputError(f"{path}: is a folder, cannot write a file there")
        if path.exists() and path.name not in written(folder):
            raise OutputError(f"{path}: exists and was not written by auvplan; not overwritten "
                              "(choose another --out, or pass --force)")
        _replace(path, data)
        _record(folder, [path.name])
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"{path}: cannot write ({exc.strerror or exc})") from exc
    return path


def prepare_out(folder: Path | str, names: Iterable[str] = RESULT_NAMES, *, force: bool = False) -> Path:
    """Check an output folder before any work: creatable, writable, and no user file in the way.

    Parameters
    ----------
    folder : Path or str
        The ``--out`` folder (created when missing).
    names : iterable of str
        The files the command may write.
    force : bool
        Adopt existing files of those names (they will be overwritten) and remove symbolic
        links of those names (the link, not its target).

    Returns
    -------
    pathlib.Path
        The folder, created.

    Raises
    ------
    OutputError
        Naming the folder or the first file in the way, and how to proceed.
    """
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise OutputError(f"{out}: --out names an existing file, not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out}: cannot create the output folder ({exc.strerror or exc})") from exc
    if not os.access(out, os.W_OK | os.X_OK):
        raise OutputError(f"{out}: the output folder is not writable")
    mine = written(out)
    conflicts = [n for n in names if (out / n).is_symlink() or ((out / n).exists() and n not in mine)]
    if conflicts and not force:
        what = "a symbolic link" if (out / conflicts[0]).is_symlink() else "a file auvplan did not write"
        raise OutputError(f"{out / conflicts[0]}: {what} is in the way ({len(conflicts)} such); nothing was "
                          "overwritten — choose another --out, or pass --force")
    try:
        for n in conflicts:
            if (out / n).is_symlink():
                (out / n).unlink()
            elif (out / n).is_dir():
                raise OutputError(f"{out / n}: a folder is in the way; remove it or choose another --out")
        _record(out, [n for n in conflicts if (out / n).exists()])
        probe = tempfile.NamedTemporaryFile(dir=out, prefix=".auvplan-probe.", delete=True)
        probe.close()
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"{out}: the output folder is not writable ({exc.strerror or exc})") from exc
    return out
