"""What a vector file may be before GDAL opens it, and GDAL kept off the network while it reads one.

A scenario names its vector files (``[[zones]] file``, ``[survey] file``, ``[land]``); they are local data.
GDAL opens far more than data files: a FIFO blocks its open for ever, an OGR VRT or a WFS description
file makes it fetch from a server (a server that accepts and never answers froze ``validate`` for good,
and ``serve`` would fetch on behalf of a page), a VRT reads any other file of the machine.  Here: the
path must be a regular file or a folder (a FileGDB), and so must the files GDAL may open beside it (the
same name with any suffix: a shapefile's ``.dbf``, a GeoPackage's ``-wal``; a FileGDB's own files), a file
that only describes other sources is refused by its first bytes, and while GDAL reads, its HTTP client gives
up within seconds and ``/vsicurl/`` (and the cloud file systems built on it) opens nothing.
"""

from __future__ import annotations

import contextlib
import glob
import stat
import threading
from collections.abc import Iterator
from pathlib import Path

__all__ = ["NETWORK_OFF", "check_source", "offline"]

NETWORK_OFF = {
    "CPL_VSIL_CURL_ALLOWED_EXTENSIONS": ".auvplan-reads-local-files-only",
    "GDAL_HTTP_CONNECTTIMEOUT": "2",
    "GDAL_HTTP_TIMEOUT": "3",
    "GDAL_HTTP_MAX_RETRY": "0",
    "GML_DOWNLOAD_WFS_SCHEMA": "NO",
}
"""GDAL configuration in force while a vector file is read (restored after)."""

_DESCRIPTIONS = {
    b"<ogrvrtdatasource": "an OGR VRT (it names other files or servers to read)",
    b"<ogrwfsdatasource": "a WFS service description (GDAL would fetch the features from a server)",
    b"wfs_capabilities": "a WFS capabilities document (GDAL would fetch the features from a server)",
    b"gdal_streamed_alg": "a GDAL pipeline (.gdalg.json: it runs commands on other sources)",
}
_SNIFF_BYTES = 4096
_LOCK = threading.Lock()


def check_source(path: Path, src: str, error: type[Exception]) -> None:
    """Refuse a path that is not a regular file or folder, or a file that only describes other sources.

    Parameters
    ----------
    path : pathlib.Path
        The vector file (or a FileGDB folder); it exists.
    src : str
        Message prefix naming the file and the key.
    error : type of Exception
        Raised with a message starting with ``src``.
    """
    mode = _mode(path, src, error)
    _refuse_special(mode, src, error)
    # GDAL opens the files beside it too (a shapefile's .dbf/.shx/.prj/.cpg, a GeoPackage's -wal) and every file
    # of a FileGDB folder: a FIFO among them blocked the open for ever just the same (validate killed after 20 s)
    beside = path.iterdir() if stat.S_ISDIR(mode) else path.parent.glob(_siblings(path.name))
    for other in sorted(beside):
        if other == path or not other.exists():  # a link to nowhere: GDAL's open fails, it does not wait
            continue
        _refuse_special(_mode(other, src, error), f"{src}: {other.name!r} beside it", error)
    if stat.S_ISDIR(mode):
        return
    try:
        with path.open("rb") as fh:
            head = fh.read(_SNIFF_BYTES).lower()
    except OSError as exc:
        raise error(f"{src}: cannot read ({exc.strerror or exc})") from exc
    what = next((w for marker, w in _DESCRIPTIONS.items() if marker in head), None)
    if what is not None:
        raise error(f"{src}: is {what}, not the features themselves; auvplan reads local data only: convert it "
                    "(ogr2ogr -f GPKG zones.gpkg SOURCE) and name that file")


def _mode(path: Path, src: str, error: type[Exception]) -> int:
    """``path``'s ``st_mode`` (links followed), or ``error`` naming why it cannot be read."""
    try:
        return path.stat().st_mode
    except OSError as exc:  # a link loop, a link to nowhere, no permission
        raise error(f"{src}: cannot read ({exc.strerror or exc})") from exc


def _refuse_special(mode: int, src: str, error: type[Exception]) -> None:
    """Refuse what is neither a regular file nor a folder: GDAL's open of it would block or never end."""
    if stat.S_ISDIR(mode) or stat.S_ISREG(mode):
        return
    kind = "a FIFO" if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) \
        else "a socket" if stat.S_ISSOCK(mode) else "not a regular file"
    raise error(f"{src}: is {kind}, not a file of features (reading it would block or never end)")


def _siblings(name: str) -> str:
    """A glob of the files GDAL may open beside ``name``: its stem with any suffix, in any case (``z.DBF``)."""
    stem = name.split(".", 1)[0] or name
    return "".join(f"[{c.lower()}{c.upper()}]" if c.isalpha() else glob.escape(c) for c in stem) + ".*"


@contextlib.contextmanager
def offline() -> Iterator[None]:
    """GDAL's configuration :data:`NETWORK_OFF` for the ``with`` block (one vector read at a time).

    Yields
    ------
    None
    """
    import pyogrio

    with _LOCK:
        before = {k: pyogrio.get_gdal_config_option(k) for k in NETWORK_OFF}
        pyogrio.set_gdal_config_options(NETWORK_OFF)
        try:
            yield
        finally:
            pyogrio.set_gdal_config_options({k: (None if v is None else str(v)) for k, v in before.items()})
