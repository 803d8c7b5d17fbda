"""What a vector file may be before GDAL opens it, and GDAL kept off the network while it reads one.

A scenario names its vector files (``[[zones]] file``, ``[survey] file``, ``[land]``); they are local data.
GDAL opens far more than data files: a FIFO blocks its open for ever, an OGR VRT or a WFS description
file makes it fetch from a server (a server that accepts and never answers froze ``validate`` for good,
and ``serve`` would fetch on behalf of a page), a VRT reads any other file of the machine.  Here: the
path must be a regular file or a folder (a FileGDB), a file that only describes other sources is
refused by its first bytes, and while GDAL reads, its HTTP client gives up within seconds and
``/vsicurl/`` (and the cloud file systems built on it) opens nothing.
"""

from __future__ import annotations

import contextlib
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
    try:
        mode = path.stat().st_mode
    except OSError as exc:  # a link loop, a link to nowhere, no permission
        raise error(f"{src}: cannot read ({exc.strerror or exc})") from exc
    if stat.S_ISDIR(mode):
        return
    if not stat.S_ISREG(mode):
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) \
            else "a socket" if stat.S_ISSOCK(mode) else "not a regular file"
        raise error(f"{src}: is {kind}, not a file of features (reading it would block or never end)")
    try:
        with path.open("rb") as fh:
            head = fh.read(_SNIFF_BYTES).lower()
    except OSError as exc:
        raise error(f"{src}: cannot read ({exc.strerror or exc})") from exc
    what = next((w for marker, w in _DESCRIPTIONS.items() if marker in head), None)
    if what is not None:
        raise error(f"{src}: is {what}, not the features themselves; auvplan reads local data only: convert it "
                    "(ogr2ogr -f GPKG zones.gpkg SOURCE) and name that file")


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
