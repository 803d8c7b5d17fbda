"""Safe output folders: atomic writes, a manifest of what auvplan wrote, no symlinks followed.

Every result file goes through :func:`atomic_write`: the bytes go to a temporary file in the
same folder, are flushed to disk, and replace the target with one ``os.replace`` — a reader (or
an interrupted run) sees the old file or the new one, never half of one.  The folder's
``.auvplan-manifest.json`` (:mod:`.manifest`) lists the files auvplan wrote there; a file that is not in it (a
user's own ``mission.csv``) is never replaced unless the caller adopted it first
(:func:`prepare_out` with ``force=True``), and a symbolic link is never written through (with
``force`` the link itself is replaced, its target is left alone).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import tempfile
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from . import outdir
from .manifest import MANIFEST, _record, _replace, written, written_by
from .outdir import OutputError

__all__ = ["RESULT_NAMES", "OutputError", "atomic_write", "write_new", "prepare_out", "save_figure",
           "discard_on_failure", "session"]

RESULT_NAMES = (
    "run.json", "run.npz", "metrics.json", "path.csv", "route.csv", "keys.csv", "sim_metrics.json", "track.csv",
    "scenario.toml", "source.json", "terrain.npz", "report.html", "mission.geojson", "mission.kml", "mission.csv",
    "mission.moos", "mission.plan", "mission.gpx", "mission.yaml", "rows.csv", "histories.jsonl", "summary.csv",
    "summary.md", "bench.html", "bench.png", "legs.csv", "sweep.csv", "sweep_summary.json", "sweep.png",
    "ensemble.json", "fixes.csv",
)
"""File names a command may write into ``--out`` (checked before any work starts)."""


def _one_job(out: Path, job: str, force: bool, inputs: Iterable[Path | str] = ()) -> None:
    """One results folder = one job: refuse a folder another command wrote (with ``force``, remove its files,
    unless one is a file the command reads: ``inputs``)."""
    was = written_by(out)
    if not job or not was or was == job:
        return
    if not force:
        raise OutputError(f"{out}: holds the results of `auvplan {was}` ({MANIFEST} job = {was!r}); a results folder "
                          f"holds one job, `auvplan {job}` would mix its files with them — choose another --out, or "
                          "pass --force to remove that job's files first")
    doomed = [out / n for n in sorted(written(out)) if (out / n).is_file() and not (out / n).is_symlink()]
    read = {Path(i).resolve() for i in inputs if Path(i).is_file()}
    kept = next((p for p in doomed if p.resolve() in read), None)
    if kept is not None:  # was: the scenario removed, then 'no such scenario file', the folder emptied
        raise OutputError(f"{kept}: the file this `auvplan {job}` reads; --force would remove it with `auvplan "
                          f"{was}`'s files — copy it out of {out}, or choose another --out")
    for p in doomed:
        p.unlink()
    _replace(out / MANIFEST, (json.dumps({"files": [], "job": job}, indent=1) + "\n").encode())


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
        outdir.check_inside(path)  # inside its --out, through no link (before any folder is made)
        folder.mkdir(parents=True, exist_ok=True)
        outdir.check_inside(path)
        if path.is_symlink():
            raise OutputError(f"{path}: is a symbolic link; auvplan does not write through links "
                              "(remove it, or pass --force to replace the link itself)")
        if path.is_dir():
            raise OutputError(f"{path}: is a folder, cannot write a file there")
        if path.exists() and path.name not in written(folder):
            raise OutputError(f"{path}: exists and was not written by auvplan; not overwritten "
                              "(choose another --out, or pass --force)")
        # the manifest names the file before it exists: a kill between the two leaves a name without
        # its file (harmless), never a file of auvplan's that the next run takes for a user's
        _record(folder, [path.name])
        _replace(path, data)
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"{path}: cannot write ({exc.strerror or exc})") from exc
    return path


def _mine(out: Path, name: str) -> bool:
    """Whether auvplan wrote ``out / name`` (the manifest of the folder holding it lists it)."""
    p = out / name
    return p.name in written(p.parent)


def _check_names(out: Path, names: list[str], force: bool) -> None:
    """Every name a relative path below ``out`` through real folders (links replaced with ``force``)."""
    for n in names:
        parts = Path(n).parts
        if Path(n).is_absolute() or not parts or any(p in ("..", ".") for p in parts):
            raise OutputError(f"{out / n}: a result name that leaves the output folder; nothing was written")
        here = out
        for part in parts[:-1]:
            here = here / part
            if here.is_symlink():
                if not force:
                    raise OutputError(f"{here}: a symbolic link is in the way below the output folder; auvplan "
                                      "does not write through links — remove it, or pass --force")
                here.unlink()  # the link itself, never its target
            elif here.exists() and not here.is_dir():
                raise OutputError(f"{here}: a file is in the way of a results folder; remove it or choose another "
                                  "--out")


def _clean_temporaries(out: Path, names: list[str]) -> None:
    """Remove what an interrupted write left: ``.NAME.XXXXXXXX.tmp`` of the names (and manifests) written here."""
    by_folder: dict[Path, set[str]] = {out: {MANIFEST}}
    for n in names:
        p = out / n
        by_folder.setdefault(p.parent, {MANIFEST}).add(p.name)
    for folder, wanted in by_folder.items():
        if folder.is_dir() and not folder.is_symlink():
            for tmp in outdir.stale_temporaries(folder, wanted):
                tmp.unlink()


def prepare_out(folder: Path | str, names: Iterable[str] = RESULT_NAMES, *, force: bool = False,
                job: str = "", inputs: Iterable[Path | str] = ()) -> Path:
    """Check an output folder before any work: creatable, writable, locked, and no user file in the way.

    The folder is locked for this process (:func:`auvplan.io.files.outdir.acquire`; a second auvplan
    writing into it is refused) and the temporary files an interrupted run left are removed.

    Parameters
    ----------
    folder : Path or str
        The ``--out`` folder (created when missing).
    names : iterable of str
        The files the command may write (``vehicle/run.json`` for a file in a sub-folder).
    force : bool
        Adopt existing files of those names (they will be overwritten) and remove symbolic
        links of those names or on the way to them (the link, not its target).
    job : str, optional
        The command writing the folder (``run``, ``survey`` …), recorded in the manifest: a folder
        another command wrote is refused, naming that command (with ``force`` its files are removed
        first). '' for commands that add to a folder (``report``, ``export``).
    inputs : iterable of path, optional
        Files the command reads (its scenario): ``force`` never removes one of them (refused instead).

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
    names = list(names)
    if out.exists() and not out.is_dir():
        raise OutputError(f"{out}: --out names an existing file, not a folder")
    key = os.path.abspath(out)
    if not (outdir.held(out) and key in _MADE):  # prepared again by the command that locked it: what it made first
        _MADE[key] = _made_by_now(Path(key))
    made = _MADE[key]
    try:
        _prepare(out, names, force, job, inputs)
    except BaseException:
        _undo(Path(key), made)  # refused: the disk as it was found (issue: an empty lock was left behind)
        _MADE.pop(key, None)
        raise
    return out


def _made_by_now(out: Path) -> _Made:
    """What :func:`prepare_out` of ``out`` (absolute) will create: the highest folder missing, lock, manifest."""
    top, path = None, out
    while not os.path.lexists(path):
        top, path = path, path.parent
    return _Made(top, not os.path.lexists(out / outdir.LOCK), not os.path.lexists(out / MANIFEST))


def _prepare(out: Path, names: list[str], force: bool, job: str, inputs: Iterable[Path | str]) -> None:
    """:func:`prepare_out`'s checks, which may create the folder, its lock and its manifest."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out}: cannot create the output folder ({exc.strerror or exc})") from exc
    if not os.access(out, os.W_OK | os.X_OK):
        raise OutputError(f"{out}: the output folder is not writable")
    outdir.acquire(out)
    try:
        _one_job(out, job, force, inputs)
        _check_names(out, names, force)
        _clean_temporaries(out, names)
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"{out}: the output folder is not writable ({exc.strerror or exc})") from exc
    conflicts = [n for n in names if (out / n).is_symlink() or ((out / n).exists() and not _mine(out, n))]
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
        for n in conflicts:
            if (out / n).exists():
                _record((out / n).parent, [(out / n).name])
        if job and written_by(out) != job:
            _record(out, [], job)
        # named as a temporary of the manifest: a kill before it closes leaves what the next run cleans up
        probe = tempfile.NamedTemporaryFile(dir=out, prefix=f".{MANIFEST}.", suffix=".tmp", delete=True)
        probe.close()
    except OutputError:
        raise
    except OSError as exc:
        raise OutputError(f"{out}: the output folder is not writable ({exc.strerror or exc})") from exc


@dataclass(frozen=True)
class _Made:
    """What :func:`prepare_out` created for an output folder (removed again when its command fails)."""

    top: Path | None
    """The highest folder it created (None: the folder existed)."""
    lock: bool
    """It created the lock file."""
    manifest: bool
    """It created the manifest."""


_MADE: dict[str, _Made] = {}
"""The output folders :func:`prepare_out` prepared in this process (absolute path → what it created)."""


def _undo(out: Path, made: _Made) -> None:
    """Remove what :func:`prepare_out` created for ``out`` and no result needs: the lock file (while held), a manifest
    that lists no file, and the folders it created, each only if empty."""
    if not out.is_dir() or out.is_symlink():
        return
    if made.manifest and not written(out):
        with contextlib.suppress(OSError):
            (out / MANIFEST).unlink()
    if made.lock and outdir.held(out):  # never a lock another process holds (acquire re-checks the file it locked)
        with contextlib.suppress(OSError):
            (out / outdir.LOCK).unlink()
    outdir.release(out)
    if made.top is not None:
        _remove_empty(out, made.top)


def _remove_empty(out: Path, top: Path) -> None:
    """Remove the empty folders below ``out``, then ``out`` and its parents up to ``top``, each only if empty."""
    for root, dirs, _ in os.walk(out, topdown=False):  # empty folders only (a link or a full one: rmdir refuses)
        for d in dirs:
            with contextlib.suppress(OSError):
                os.rmdir(os.path.join(root, d))
    path = out
    while True:
        try:
            path.rmdir()
        except OSError:
            return
        if path == top:
            return
        path = path.parent


@contextlib.contextmanager
def session() -> Iterator[None]:
    """One command's output folders: locked while it runs and released after (:func:`auvplan.io.files.outdir.session`);
    when it fails, what :func:`prepare_out` created for them and no result needs is removed (a refused command leaves
    the disk as it found it: no lock file, no empty manifest, no folder it made).

    Yields
    ------
    None
        The command runs; its exception is raised again after the clean-up.
    """
    before = set(_MADE)
    with outdir.session():
        try:
            yield
        except BaseException:
            for key in [k for k in _MADE if k not in before]:
                _undo(Path(key), _MADE[key])
            raise
        finally:
            for key in set(_MADE) - before:
                _MADE.pop(key, None)


@contextlib.contextmanager
def discard_on_failure(folder: Path | str | None) -> Iterator[None]:
    """Remove, when the block fails, the output folder it created (:func:`prepare_out`) and wrote no result into.

    Only what auvplan puts there before any result goes: the lock, a manifest that lists no file, and empty
    folders (a checkpoint folder no task reached); then the folder and the parents the block created, each only if
    empty.  A folder that existed before the block is never removed, nor one holding any other file (a finished
    task's checkpoint stays, for the run again to read back).

    Parameters
    ----------
    folder : pathlib.Path or str or None
        The ``--out`` folder (None: nothing to do).

    Yields
    ------
    None
        The block runs; its exception is raised again after the clean-up.
    """
    top = None
    if folder is not None:
        path = Path(os.path.abspath(folder))
        while not os.path.lexists(path):  # the highest folder missing: the block creates it and below
            top, path = path, path.parent
    try:
        yield
    except BaseException:
        if top is not None:
            _discard(Path(os.path.abspath(folder or ".")), top)
        raise


def _discard(out: Path, top: Path) -> None:
    """:func:`discard_on_failure`'s clean-up of ``out``, created with the missing parents up to ``top``."""
    if out.is_symlink() or not out.is_dir() or written(out):
        return
    outdir.release(out)
    for name in (outdir.LOCK, MANIFEST):
        with contextlib.suppress(OSError):
            (out / name).unlink()
    _remove_empty(out, top)


def save_figure(path: Path, fig: Any, dpi: int = 130) -> Path:
    """Write a matplotlib figure atomically (rendered in memory, then :func:`atomic_write`).

    Parameters
    ----------
    path : pathlib.Path
        The image file; its suffix is the format (``.png``, ``.svg``, ``.pdf`` …).
    fig : matplotlib.figure.Figure
        The figure.
    dpi : int, optional
        Resolution of raster formats.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    buf = io.BytesIO()
    fig.savefig(buf, format=Path(path).suffix.lstrip(".") or "png", dpi=dpi)
    return atomic_write(path, buf.getvalue())
