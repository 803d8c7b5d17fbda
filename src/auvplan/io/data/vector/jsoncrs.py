"""The ``crs`` member of a GeoJSON file, read as the file states it.

GDAL's GeoJSON driver reads a ``crs`` member it cannot build (an unknown name, ``"EPSG:99999"``, a ``link`` to
a remote definition, a member of another shape) as WGS 84 longitude/latitude, silently: no error, no warning,
the layer's CRS is EPSG:4326.  A file in a projected CRS whose ``crs`` is misspelt would then put its zones,
land or survey area in the wrong place of the world, or nowhere.  :func:`check_geojson_crs` builds the stated
``crs`` with pyproj (the ``name`` and ``EPSG`` forms of the 2008 GeoJSON specification, as GDAL reads them) and
refuses the file when it cannot be built or is not the CRS GDAL read.  A file without a ``crs`` member (RFC
7946: WGS 84 by definition) is not affected; a file whose bytes never spell ``"crs"`` is not parsed again.
"""

from __future__ import annotations

import json
import mmap
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pyproj where a file is read (issue 56: a plan from the readers' cache needs none)
    from pyproj import CRS

__all__ = ["check_geojson_crs"]

_SUFFIXES = (".geojson", ".json")


def _stated(member: Any) -> str | None:
    """What pyproj is given for a ``crs`` member (``None``: a form GDAL does not build offline)."""
    if not isinstance(member, dict) or not isinstance(member.get("properties"), dict):
        return None
    kind, props = member.get("type"), member["properties"]
    if kind == "name" and isinstance(props.get("name"), str):
        return str(props["name"])
    if kind == "EPSG" and isinstance(props.get("code"), int) and not isinstance(props.get("code"), bool):
        return f"EPSG:{props['code']}"
    return None


def check_geojson_crs(path: Path, src: str, error: type[Exception], read: CRS) -> None:
    """Refuse a GeoJSON file whose ``crs`` member GDAL could not build (module notes).

    Parameters
    ----------
    path : pathlib.Path
        The vector file (checked only when it is a regular ``.geojson`` / ``.json`` file).
    src : str
        Message prefix naming the file and the key that named it.
    error : type of Exception
        Raised with a message starting with ``src``.
    read : pyproj.CRS
        The CRS GDAL gave the layer.

    Raises
    ------
    error
        When the ``crs`` member cannot be built, or is not ``read``: naming the member.
    """
    if path.suffix.lower() not in _SUFFIXES or not path.is_file() or path.stat().st_size == 0:
        return
    with path.open("rb") as fh, mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as data:
        if data.find(b'"crs"') < 0:
            return
        try:
            doc = json.loads(data[:])
        except ValueError:  # GDAL read it (JSON with comments, NaN …): nothing more to say here
            return
    if not isinstance(doc, dict) or doc.get("crs") is None:
        return
    member = doc["crs"]
    shown = json.dumps(member)[:200]
    given = _stated(member)
    from pyproj import CRS

    try:
        stated = CRS.from_user_input(given) if given is not None else None
    except Exception as exc:  # pyproj's CRSError
        reason = str(exc).splitlines()[0]
        raise error(f"{src}: crs {shown} cannot be built ({reason}); GDAL would read the file as WGS 84: "
                    "state an EPSG code (\"EPSG:32633\") or drop the member for WGS 84") from exc
    if stated is None:
        raise error(f"{src}: crs {shown} cannot be built (a 'name' or 'EPSG' member is read, not a link); GDAL "
                    "would read the file as WGS 84: state an EPSG code (\"EPSG:32633\") or drop the member")
    if not stated.equals(read, ignore_axis_order=True):
        raise error(f"{src}: crs {shown} is {stated.to_string()}, but GDAL read the file as {read.to_string()}")
