"""Read tidal-current station files (the JSON cut from XTide's harmonics by ``tools/cut_tides.py``)
and build a :class:`~auvplan.world.currents.tides.TidalCurrent` in a scenario's local frame.

Built-in: ``juan-de-fuca`` — 78 NOAA current station depths at 20 sites of the Strait of Juan de Fuca
and the south of the San Juan Islands (Debian ``xtide-data``, public domain; NOT FOR NAVIGATION),
see ``data/PROVENANCE.md``.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ....errors import DataError
from ....world.currents.tides import HarmonicTables, TidalCurrent
from ...files.jsonfile import MAX_JSON_BYTES, read_bounded_text
from ..cache import cached
from ..geo import LocalFrame, forward_kept
from .currents import parse_time
from .tidecheck import check_tide_doc

__all__ = ["BUILTIN_TIDES", "parse_start_time", "utc_iso", "read_tide_file", "load_tidal_current"]

BUILTIN_TIDES = {
    "juan-de-fuca": "tides_salish.json",
}


def parse_start_time(text: str) -> float:
    """Parse an ISO 8601 time into UTC seconds since 1970.

    Parameters
    ----------
    text : str
        ISO 8601 time, with ``Z`` or an offset; a time without one is UTC.

    Returns
    -------
    float
        Seconds since 1970-01-01T00:00:00Z.
    """
    return float(parse_time(str(text)).astype("datetime64[ns]").astype(np.int64)) / 1e9


def utc_iso(unix_seconds: float) -> str:
    """Format seconds since 1970 as ISO 8601 UTC text.

    Parameters
    ----------
    unix_seconds : float
        Seconds since 1970-01-01T00:00:00Z.

    Returns
    -------
    str
        ``YYYY-MM-DDTHH:MM:SSZ`` (whole seconds).
    """
    return f"{np.datetime64(round(float(unix_seconds)), 's')}Z"


def read_tide_file(source: str, base_dir: Path | None = None) -> dict[str, Any]:
    """Read the tidal station document of a built-in name or a JSON file.

    Parameters
    ----------
    source : str
        A built-in name (``BUILTIN_TIDES``) or a JSON file.
    base_dir : pathlib.Path, optional
        Folder that a relative file name resolves against.

    Returns
    -------
    dict
        The document: constituents, their speeds (degrees/hour), equilibrium arguments and node
        factors per year, and the stations' harmonic constants.
    """
    if source in BUILTIN_TIDES:
        text = resources.files("auvplan.data").joinpath(BUILTIN_TIDES[source]).read_text(encoding="utf-8")
        where = f"built-in tides {source!r}"
    else:
        path = Path(source)
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        if path.exists() and not path.is_file():  # a FIFO blocked for ever, /dev/zero filled the memory
            raise DataError(f"tides = {source!r}: not a regular file (a FIFO, a device or a folder)")
        try:
            text = read_bounded_text(path, MAX_JSON_BYTES, "a tidal station file")
        except DataError as exc:
            cause = exc.__cause__
            why = cause.strerror if isinstance(cause, OSError) else str(exc).removeprefix(f"{path}: ")
            raise DataError(f"tides = {source!r}: cannot read ({why}); built-in: {', '.join(BUILTIN_TIDES)}") from exc
        where = str(path)
    try:
        doc = json.loads(text)
        for key in ("constituents", "speed_deg_per_hour", "first_year", "equilibrium_deg", "node_factor", "stations"):
            doc[key]  # noqa: B018 - presence check
    except RecursionError:
        raise DataError(f"{where}: not a tidal station file (nested too deeply)") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise DataError(f"{where}: not a tidal station file ({exc})") from exc
    if not isinstance(doc, dict):
        raise DataError(f"{where}: not a tidal station file (not a JSON object)")
    check_tide_doc(doc, where)
    return doc


def _local_directions(frame: LocalFrame, lon: ArrayLike, lat: ArrayLike, bearing_deg: ArrayLike) -> NDArray[np.float64]:
    """Unit vectors in the local frame of compass bearings at geographic points (1 km along the
    geodesic, so the frame's meridian convergence is accounted for), kept in the readers' cache under the
    origin and the bits of the points and bearings: a station file read before imports no pyproj (issue 56)."""

    def compute() -> NDArray[np.float64]:
        from pyproj import Geod  # where a file is projected (issue 56)

        lon2, lat2, _ = Geod(ellps="WGS84").fwd(lon, lat, bearing_deg, np.full(np.shape(lon), 1000.0))
        x0, y0 = frame.forward(lon, lat)
        x1, y1 = frame.forward(lon2, lat2)
        d = np.column_stack([x1 - x0, y1 - y0])
        unit: NDArray[np.float64] = d / np.linalg.norm(d, axis=1, keepdims=True)
        return unit

    parts = [np.asarray(v, dtype=float) for v in (lon, lat, bearing_deg)]
    request = (float(frame.lat0), float(frame.lon0), *((a.shape, a.tobytes().hex()) for a in parts))
    unit: NDArray[np.float64] = cached("tide-directions", request, (), compute, lambda u: ({"unit": u}, {}),
                                       lambda a, _: a["unit"])
    return unit


def load_tidal_current(source: str, frame: LocalFrame, start_time: float, *, base_dir: Path | None = None,
                       r0: float = 1000.0) -> TidalCurrent:
    """Build the :class:`TidalCurrent` of a station file in ``frame``.

    Parameters
    ----------
    source : str
        A built-in name or a JSON station file.
    frame : LocalFrame
        The scenario's local frame.
    start_time : float
        UTC seconds since 1970 at simulation time ``t = 0``.
    base_dir : pathlib.Path, optional
        Folder that a relative file name resolves against.
    r0 : float, optional
        Interpolation length between stations (m).

    Returns
    -------
    TidalCurrent
        The predicted current in the local frame (m/s).
    """
    doc = read_tide_file(source, base_dir)
    names = tuple(doc["constituents"])
    tables = HarmonicTables(names, doc["speed_deg_per_hour"], int(doc["first_year"]), doc["equilibrium_deg"],
                            doc["node_factor"])
    st = doc["stations"]
    try:
        lat = np.array([s["lat"] for s in st], dtype=float)
        lon = np.array([s["lon"] for s in st], dtype=float)
        amp = np.array([[s["amplitude_m_s"].get(c, 0.0) for c in names] for s in st], dtype=float)
        kappa = np.array([[s["phase_deg"].get(c, 0.0) for c in names] for s in st], dtype=float)
        zone = np.array([s["zone_hours"] for s in st], dtype=float)
        flood_deg = np.array([s["flood_dir_deg"] for s in st], dtype=float)
        ebb_deg = np.array([s["ebb_dir_deg"] for s in st], dtype=float)
        depth = np.array([s["depth_m"] for s in st], dtype=float)
        mean = np.array([s["mean_m_s"] for s in st], dtype=float)
    except (KeyError, TypeError, ValueError) as exc:
        raise DataError(f"tides = {source!r}: station records incomplete ({exc})") from exc
    keys = list(dict.fromkeys(zip(lat.tolist(), lon.tolist())))
    site = np.array([keys.index(k) for k in zip(lat.tolist(), lon.tolist())])
    sx, sy = forward_kept(frame, np.array([k[1] for k in keys]), np.array([k[0] for k in keys]))
    return TidalCurrent(
        tables=tables,
        site_xy=np.column_stack([sx, sy]),
        site=site,
        depth=depth,
        flood=_local_directions(frame, lon, lat, flood_deg),
        ebb=_local_directions(frame, lon, lat, ebb_deg),
        amplitude=amp,
        greenwich_phase=kappa - tables.speed[None, :] * zone[:, None],
        mean=mean,
        epoch=float(start_time),
        r0=r0,
        names=tuple(s["name"] for s in st),
    )
