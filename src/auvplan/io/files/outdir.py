"""The ``--out`` folders of this process: one lock each, and every path written proven inside.

:func:`acquire` takes an exclusive ``flock`` on ``DIR/.auvplan.lock`` (a second auvplan writing
into the same folder is refused at once, naming the holder's process id; the kernel drops the lock
when the holder exits or is killed, so a crashed run never blocks the next; a lock file removed meanwhile by a
refused command is noticed, and the lock taken again on the file now named) and registers ``DIR``
as an output root.  :func:`check_inside` is called by every writer before it writes: the path,
taken as written (no link resolved), must lie below its root; no folder between the root and the
file may be a symbolic link (auvplan never writes through a link at any level below ``--out``);
and the resolved path must still lie inside the resolved root.  :func:`stale_temporaries` finds
the temporary files an interrupted write left (``.NAME.XXXXXXXX.tmp`` of a name auvplan writes).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import re
from collections.abc import Iterable, Iterator
from pathlib import Path

from ...errors import AuvplanError

__all__ = ["LOCK", "OutputError", "acquire", "held", "release", "release_all", "session", "root_of", "check_inside",
           "stale_temporaries"]

LOCK = ".auvplan.lock"
"""Name of the lock file in an output folder (left in place; the lock itself is the ``flock``)."""

_TEMP = re.compile(r"\.(?P<name>.+)\.[A-Za-z0-9_]{8}\.tmp\Z")
"""A temporary file of :func:`auvplan.io.files.safeio.atomic_write` (``tempfile.mkstemp`` names)."""

_HELD: dict[str, int] = {}
"""Output roots of this process (absolute, unresolved) → the descriptor holding their lock."""


class OutputError(AuvplanError, OSError):
    """An output folder or file cannot be written safely (names the path and why): locked by another
    process, outside its ``--out``, through a link, a user's file in the way."""


def _key(folder: Path | str) -> str:
    return os.path.abspath(os.fspath(folder))


def acquire(folder: Path) -> None:
    """Lock the output folder ``folder`` for this process (a no-op when this process holds it).

    Parameters
    ----------
    folder : pathlib.Path
        An existing output folder.

    Raises
    ------
    OutputError
        When another process holds its lock (naming that process), or the lock file is a link.
    """
    key = _key(folder)
    if key in _HELD:
        return
    path = Path(key) / LOCK
    for _ in range(8):  # a refused command removes the lock file it made: locked, it must still be the file named
        fd = _lock(path, folder)
        try:
            now = os.stat(path, follow_symlinks=False)
        except OSError:
            now = None
        mine = os.fstat(fd)
        if now is not None and (now.st_dev, now.st_ino) == (mine.st_dev, mine.st_ino):
            break
        os.close(fd)
    else:
        raise OutputError(f"{path}: the lock file keeps being replaced; is another program removing it?")
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    _HELD[key] = fd


def _lock(path: Path, folder: Path) -> int:
    """Open ``path`` (created) and take its exclusive ``flock``: the descriptor, or the holder named."""
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o644)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise OutputError(f"{path}: is a symbolic link; auvplan does not follow it (remove it)") from exc
        raise OutputError(f"{path}: cannot create the lock file ({exc.strerror or exc})") from exc
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "?"
        os.close(fd)
        raise OutputError(f"{folder}: another auvplan process (pid {holder}) is writing into this folder; "
                          "wait for it to finish, or choose another --out") from exc
    return fd


def held(folder: Path) -> bool:
    """Whether this process holds the lock of the output folder ``folder``.

    Parameters
    ----------
    folder : pathlib.Path
        An output folder.

    Returns
    -------
    bool
        True after :func:`acquire` and before :func:`release`.
    """
    return _key(folder) in _HELD


def release(folder: Path) -> None:
    """Release the output folder ``folder`` if this process locked it (the lock file stays, unlocked).

    Parameters
    ----------
    folder : pathlib.Path
        The folder given to :func:`acquire`.
    """
    fd = _HELD.pop(_key(folder), None)
    if fd is not None:
        with contextlib.suppress(OSError):
            os.close(fd)


def release_all() -> None:
    """Release every output folder this process locked (the lock files stay, unlocked)."""
    while _HELD:
        _, fd = _HELD.popitem()
        with contextlib.suppress(OSError):
            os.close(fd)  # closing the only descriptor drops the flock


@contextlib.contextmanager
def session() -> Iterator[None]:
    """Release, on leaving, every output folder locked inside (one command of the command line).

    Yields
    ------
    None
        Nothing: the block runs with the locks it takes.
    """
    before = set(_HELD)
    try:
        yield
    finally:
        for key in set(_HELD) - before:
            with contextlib.suppress(OSError):
                os.close(_HELD.pop(key))


def _as_written(path: Path | str) -> Path:
    """``path`` made absolute without normalising it (its ``..`` parts kept, no link resolved)."""
    return Path(os.getcwd(), path)


def root_of(path: Path) -> Path | None:
    """Find the locked output root that ``path`` (taken as written, ``..`` kept) starts with.

    Parameters
    ----------
    path : pathlib.Path
        A file about to be written.

    Returns
    -------
    pathlib.Path or None
        The innermost such root, or None when the path lies in none.
    """
    parts = _as_written(path).parts
    best = None
    for root in _HELD:
        rp = Path(root).parts
        if parts[:len(rp)] == rp and (best is None or len(root) > len(best)):
            best = root
    return Path(best) if best is not None else None


def check_inside(path: Path, root: Path | None = None) -> None:
    """Prove that writing ``path`` stays inside its output root and goes through no link.

    Parameters
    ----------
    path : pathlib.Path
        The file about to be written.
    root : pathlib.Path, optional
        Its output root; default: the locked root it lies in (none: only its folder is checked).

    Raises
    ------
    OutputError
        Naming the path: outside the root, or a folder on the way is a symbolic link.
    """
    root = root if root is not None else root_of(path)
    if root is None:
        return
    p, r = _as_written(path), Path(_key(root))
    if p.parts[:len(r.parts)] != r.parts:
        raise OutputError(f"{path}: lies outside the output folder {root}; not written")
    rel = Path(*p.parts[len(r.parts):]) if len(p.parts) > len(r.parts) else Path()
    if ".." in rel.parts or not rel.parts:
        raise OutputError(f"{path}: lies outside the output folder {root}; not written")
    here = r
    for part in rel.parts[:-1]:
        here = here / part
        if here.is_symlink():
            raise OutputError(f"{here}: is a symbolic link below the output folder; auvplan does not write "
                              "through links (remove it, or pass --force to replace the link itself)")
    real_root, real_dir = os.path.realpath(r), os.path.realpath(p.parent)
    if not (real_dir == real_root or real_dir.startswith(real_root.rstrip(os.sep) + os.sep)):
        raise OutputError(f"{path}: resolves to {real_dir}, outside the output folder {root}; not written")


def stale_temporaries(folder: Path, names: Iterable[str]) -> list[Path]:
    """The temporary files an interrupted write of one of ``names`` left in ``folder``.

    Parameters
    ----------
    folder : pathlib.Path
        A folder.
    names : iterable of str
        File names auvplan writes there (their temporaries are ``.NAME.XXXXXXXX.tmp``).

    Returns
    -------
    list of pathlib.Path
        Regular files (not links) of that form, oldest name first.
    """
    wanted = set(names)
    try:
        entries = sorted(os.scandir(folder), key=lambda e: e.name)
    except OSError:
        return []
    out = []
    for e in entries:
        m = _TEMP.match(e.name)
        if m and m["name"] in wanted and e.is_file(follow_symlinks=False):
            out.append(Path(e.path))
    return out
