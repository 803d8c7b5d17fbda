"""The data readers' results kept on disk, so that the front door does not regrid the same file twice.

Reading a seabed or a current file into the local frame (decode the NetCDF, project, regrid, model the
seabed never deeper than the data) costs seconds of a command's start while the arrays it yields are a few
kilobytes; ``validate``, ``plan`` and ``run`` of a scenario read the same files every time (issue 56).  Here
a reader's result is kept in ``$AUVPLAN_CACHE_DIR`` (default ``$XDG_CACHE_HOME/auvplan/data``, i.e.
``~/.cache/auvplan/data``) under a key that changes with everything it was made from, so that **a cached
result is never stale**:

* every data file's SHA-256 of its bytes, its size and its modification time (an edited, replaced or
  touched file is a new key; a file is hashed once a process while its inode and times stay the same: the
  members of an ensemble file are one hash, not one a member — but only once its change time is
  :data:`_RACY_NS` older than the hashing: a file's times tick with the kernel's coarse clock (a few ms) or
  the file system's (2 s on FAT), so a file rewritten in place within one tick, its ``mtime`` set back
  (``os.utime``, ``cp -p``, ``rsync``), kept every time and served the old bytes' entry);
* the request: the reader's arguments (``[terrain]``/``[currents]`` table, the frame's origin, the extent,
  the start time, the memory budget in force, which is part of a reader's verdict);
* the code: a SHA-256 of every ``.py`` file of the ``auvplan`` package, and the names (with their
  versions) of every installed distribution, so that an edit of auvplan or an upgrade of numpy, scipy,
  numba, netCDF4, xarray or pyproj makes every entry a miss.
* the machine (:func:`host_stamp`): the compiled kernels a reader runs (the seabed's, with fused
  multiply-adds where the CPU has them) give other bits on another CPU, so a cache folder shared between
  machines (a network home, a copied ``~/.cache``) or a ``NUMBA_CPU_NAME`` set keeps one entry per CPU.

An entry is one ``.npz`` (the arrays and a JSON record), written to a temporary file and renamed into place
(a reader in another process sees the whole entry or none); one that cannot be read back is recomputed and
replaced; a result over 1 GiB of arrays is not kept (not to fill the disk).  Failures are not kept: a
reader's error is raised again on every call.  The log records a reader emitted (a file's gaps filled, land
found) are kept with its result and emitted again on every hit, at the levels the logging of that moment
shows.  ``AUVPLAN_CACHE=0`` turns the cache off; entries are never deleted by auvplan, and
``rm -r ~/.cache/auvplan/data`` is always safe.
"""

from __future__ import annotations

import functools
import hashlib
import json
import logging
import os
import platform
import stat
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from ..files.limits import current

__all__ = ["cache_dir", "cache_enabled", "cached", "code_stamp", "dataset_files", "file_stamp", "host_stamp",
           "request_key"]

T = TypeVar("T")
"""What a reader returns."""

Packed = tuple[dict[str, np.ndarray], dict[str, Any]]
"""A result as arrays and a JSON-able record."""

_VERSION = 1
"""Layout of an entry (bumped when it changes)."""

_MAX_BYTES = 1 << 30
"""A result larger than this (1 GiB of arrays) is not kept (not to fill the disk)."""

_LOGGING = threading.RLock()
"""Held while a reader's log records are taken aside (:func:`_recorded`)."""


def cache_enabled() -> bool:
    """Whether readers use the cache (``AUVPLAN_CACHE`` unset, or not ``0``/``off``/``no``/``false``).

    Returns
    -------
    bool
        True when enabled.
    """
    return os.environ.get("AUVPLAN_CACHE", "1").strip().lower() not in ("0", "off", "no", "false")


def cache_dir() -> Path:
    """The folder of the cached results (``$AUVPLAN_CACHE_DIR``, else ``$XDG_CACHE_HOME/auvplan/data``).

    Returns
    -------
    pathlib.Path
        The folder (created when an entry is written).
    """
    given = os.environ.get("AUVPLAN_CACHE_DIR")
    if given:
        return Path(given)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "auvplan" / "data"


@functools.cache
def code_stamp() -> str:
    """SHA-256 of every ``.py`` file of the auvplan package and of the installed distributions' names.

    Returns
    -------
    str
        Hex digest; computed once per process (~10 ms).
    """
    h = hashlib.sha256(f"{_VERSION}\0{sys.version}\0{host_stamp()}\0".encode())
    root = str(Path(__file__).resolve().parents[2])
    for rel in _py_files(root):
        with open(os.path.join(root, rel), "rb") as fh:
            h.update(rel.encode() + b"\0" + fh.read() + b"\0")
    for entry in sys.path:  # the installed distributions with their versions: numpy-2.4.6.dist-info …
        try:
            names = sorted(n for n in os.listdir(entry or ".") if n.endswith((".dist-info", ".egg-info")))
        except OSError:
            continue
        if names:  # a folder without distributions (a test or source folder on the path) changes nothing
            h.update("\0".join(names).encode() + b"\0")
    return h.hexdigest()


@functools.cache
def host_stamp() -> str:
    """The CPU compiled kernels are built for: numba compiles for the host's (``NUMBA_CPU_NAME`` and
    ``NUMBA_CPU_FEATURES`` override it) and its fast-math kernels fuse multiply-adds where the CPU has them, so
    the bits of a kernel's results (the seabed under an altitude position, a seabed model's nodes) are the CPU's;
    and whether they are compiled at all (``NUMBA_DISABLE_JIT``: plain Python gives other bits).

    Read from ``/proc/cpuinfo`` (the first processor's model and flags; ~1 ms), not from numba or llvmlite,
    whose import the cache is there to spare (issue 56); elsewhere from :mod:`platform`.

    Returns
    -------
    str
        The machine's architecture, the overrides, and the first processor's model and flags.
    """
    # NUMBA_DISABLE_JIT: the kernels run as plain Python, whose seabed differs from the compiled one by ulps at
    # half the points (numba reads any integer: "0" compiles, as unset)
    nojit = os.environ.get("NUMBA_DISABLE_JIT", "").strip()
    parts = [platform.machine(), os.environ.get("NUMBA_CPU_NAME", ""), os.environ.get("NUMBA_CPU_FEATURES", ""),
             "" if nojit in ("", "0") else "plain Python"]
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if not line.strip() and len(parts) > 3:
                    break  # the first processor's block
                if line.split(":", 1)[0].strip() in ("model name", "flags", "Features", "CPU implementer",
                                                      "CPU part"):
                    parts.append(" ".join(line.split()))
    except OSError:
        parts.append(platform.processor())
    return "\0".join(parts)


def _py_files(root: str) -> list[str]:
    """The ``.py`` files under ``root``, as sorted paths relative to it (``os.walk``: a third of ``rglob``'s cost)."""
    out = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        rel = os.path.relpath(folder, root)
        out += [name if rel == "." else os.path.join(rel, name) for name in files if name.endswith(".py")]
    return sorted(out)


def dataset_files(path: Path) -> list[Path]:
    """The files a data set is made of: ``path`` and its siblings named ``stem.*`` in any case (a shapefile's
    ``.dbf``, ``.prj``, ``.shx``; a GeoTIFF's ``.tif.aux.xml``, world file, ``.ovr`` that GDAL reads with it).

    Parameters
    ----------
    path : pathlib.Path
        The file a scenario names.

    Returns
    -------
    list of pathlib.Path
        ``[path]`` first, then the sibling files in name order (none when the folder cannot be listed).
    """
    head = path.stem.lower() + "."
    try:
        names = sorted(n for n in os.listdir(path.parent) if n != path.name and n.lower().startswith(head))
    except OSError:
        names = []
    return [path, *(p for p in (path.parent / n for n in names) if p.is_file())]


def file_stamp(path: Path) -> list[Any]:
    """``[absolute path, size, mtime (ns), SHA-256 of the bytes]`` of a data file.

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    list
        Its stamp.

    Raises
    ------
    OSError
        When the file cannot be read, or is not a regular file (a FIFO, a device: hashed, it would block or never
        end), the caller then reads without the cache, for the reader's message.
    """
    st = path.stat()
    if not stat.S_ISREG(st.st_mode):  # a FIFO or a device: hashing it would block or never end; the reader refuses it
        raise OSError(f"{path}: not a regular file")
    seen = (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns)
    digest = _DIGESTS.get(seen)
    if digest is None:
        start = _now_ns()
        digest = _digest(path)
        if max(st.st_ctime_ns, st.st_mtime_ns) < start - _RACY_NS:  # else a rewrite may keep every time (racy)
            _DIGESTS[seen] = digest
    # the path as given (made absolute), not resolved: a reader's names and log lines are the given path's,
    # so two links to one file are two entries (each replays its own file's name)
    return [os.path.abspath(path), st.st_size, st.st_mtime_ns, digest]


_DIGESTS: dict[tuple[int, ...], str] = {}
"""The SHA-256 of the files this process hashed, by their device, inode, size, modification and change times:
a file read again unchanged (each member of an ensemble file, the nominal field and the uncertainty layer of
one file) is hashed once, not once a read; any write or ``touch`` changes the change time (which no program
can set back), so an edited file is hashed again — once the time has ticked: a file changed within
:data:`_RACY_NS` of its hashing is not kept here (two writes in one tick of the clock have one change time)."""


_RACY_NS = 3_000_000_000
"""A file whose change or modification time is this close to the clock (3 s: FAT's 2 s times, a coarse kernel
clock's ticks, a network file system's clock a little off) is hashed again at every read, not remembered in
:data:`_DIGESTS`: another write within the same tick would keep its times (git's "racily clean" entries).  The
hash itself is cheap (the largest shipped file, 409 kB, 0.4-4.5 ms)."""


def _now_ns() -> int:
    """The wall clock (ns since the epoch), as a file's times are."""
    return time.time_ns()


def _digest(path: Path) -> str:
    """SHA-256 of a file's bytes (read in 1 MiB blocks)."""
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def request_key(kind: str, request: Any, files: Sequence[Path]) -> str:
    """The entry's key: the kind, the request's ``repr``, the files' stamps, the budget and :func:`code_stamp`.

    Parameters
    ----------
    kind : str
        What is cached (``"terrain"``, ``"currents"``).
    request : object
        The reader's arguments; its ``repr`` must be exact (dataclasses and tuples of floats are).
    files : sequence of pathlib.Path
        The data files read.

    Returns
    -------
    str
        64 hexadecimal digits.

    Raises
    ------
    OSError
        When a file cannot be read.
    """
    parts = [kind, repr(request), [file_stamp(p) for p in files], repr(current()), code_stamp()]
    return hashlib.sha256(json.dumps(parts).encode()).hexdigest()


class _Tape(logging.Handler):
    """Keeps every record of the ``auvplan`` loggers that the reader's thread emits while it runs; another
    thread's records (``serve`` logs while a reader runs aside) go on to the root's handlers as they would."""

    def __init__(self, threshold: int) -> None:
        super().__init__(logging.DEBUG)
        self.records: list[list[Any]] = []
        self.owner, self.threshold = threading.get_ident(), threshold

    def emit(self, record: logging.LogRecord) -> None:
        if record.thread == self.owner:
            self.records.append([record.name, record.levelno, record.getMessage()])
        elif record.levelno >= self.threshold:
            logging.getLogger().handle(record)


def _recorded(compute: Callable[[], T]) -> tuple[T, list[list[Any]]]:
    """Run ``compute`` with the ``auvplan`` log records taken aside (every level), and return them."""
    with _LOGGING:  # the logger's level and propagation are the process's: one reader's tape at a time
        logger = logging.getLogger("auvplan")
        tape, level, propagate = _Tape(logger.getEffectiveLevel()), logger.level, logger.propagate
        outer = [h for h in logger.handlers if isinstance(h, _Tape)]  # a reader inside a reader: its records
        for h in outer:  # reach the outer tape once, when replayed
            logger.removeHandler(h)
        logger.addHandler(tape)
        logger.setLevel(logging.DEBUG)
        logger.propagate = False
        try:
            value = compute()
        finally:
            logger.removeHandler(tape)
            for h in outer:
                logger.addHandler(h)
            logger.setLevel(level)
            logger.propagate = propagate
            _replay(tape.records)  # also when the reader failed: its warnings came before its error
    return value, tape.records


def _replay(records: list[list[Any]]) -> None:
    """Emit kept records again, each through its own logger at its own level (what logging shows now)."""
    for name, level, message in records:
        logging.getLogger(str(name)).log(int(level), "%s", message)


def _load(path: Path) -> tuple[dict[str, np.ndarray], dict[str, Any]] | None:
    """An entry's arrays and record, or None when it is missing or cannot be read (cut short, bytes flipped:
    the zip's CRC, a damaged header, a record of another layout)."""
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
        record = json.loads(str(arrays.pop("__record__")))
    except Exception:  # zipfile and numpy raise many types for a damaged file (BadZipFile, NotImplementedError …)
        return None
    ok = isinstance(record, dict) and record.get("version") == _VERSION and "value" in record \
        and isinstance(record.get("log"), list) \
        and all(isinstance(r, list) and len(r) == 3 and isinstance(r[1], int) for r in record["log"])
    return (arrays, record) if ok else None


def _store(path: Path, arrays: dict[str, np.ndarray], record: dict[str, Any]) -> None:
    """Write an entry atomically (a temporary file renamed into place); a read-only cache is skipped."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=path.stem, suffix=".tmp", dir=path.parent)
        try:
            with os.fdopen(fd, "wb") as fh:
                entries: dict[str, Any] = {"__record__": np.array(json.dumps(record)), **arrays}
                np.savez(fh, **entries)
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError:
        pass  # no cache (read-only home, full disk): always correct, only slower


def cached(kind: str, request: Any, files: Sequence[Path], compute: Callable[[], T],
           pack: Callable[[T], Packed], unpack: Callable[[dict[str, np.ndarray], dict[str, Any]], T]) -> T:
    """``compute()``, or its result kept from an earlier call with the same files, request and code.

    Parameters
    ----------
    kind : str
        What is cached (a prefix of the entry's file name).
    request : object
        The reader's arguments (see :func:`request_key`).
    files : sequence of pathlib.Path
        The data files ``compute`` reads.
    compute : callable
        The reader.
    pack : callable
        Its result → ``(arrays, JSON-able record)``.
    unpack : callable
        ``(arrays, record)`` → the result.

    Returns
    -------
    object
        What ``compute`` returns (or returned, for the same key).
    """
    if not cache_enabled():
        return compute()
    try:
        key = request_key(kind, request, files)
    except OSError:  # a missing or unreadable file: the reader says what is wrong with it
        return compute()
    path = cache_dir() / f"{kind}-{key}.npz"
    hit = _load(path)
    if hit is not None:
        arrays, record = hit
        try:
            value = unpack(arrays, record["value"])
        except Exception:  # a damaged entry that still unzips (a member's name flipped): recomputed, replaced
            pass
        else:
            _replay(record["log"])
            return value
    value, records = _recorded(compute)
    arrays, meta = pack(value)
    if sum(a.nbytes for a in arrays.values()) <= _MAX_BYTES:
        _store(path, arrays, {"version": _VERSION, "kind": kind, "value": meta, "log": records})
    return value
