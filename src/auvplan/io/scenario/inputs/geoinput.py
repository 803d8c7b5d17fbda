"""Geographic positions in scenario files: ``{ lat, lon, depth }`` or ``{ lat, lon, altitude }``.

Everywhere a scenario takes a position as a metre triple ``[x, y, z]`` (``[mission]`` start, goal
and route points, ``[[vehicles]]`` start, ``[[obstacles]]`` center, ``[[moving]]`` start, center
and points) it also takes an inline table in degrees (WGS 84) with either

* ``depth`` — metres below the sea surface (``z = -depth``), or
* ``altitude`` — metres above the seabed (``z = seabed(x, y) + altitude``, resolved once the
  terrain is read, by :func:`apply_altitudes`).

:func:`resolve_positions` runs on the parsed TOML before the tables are checked.  It projects
every geographic position into the local frame (:class:`~auvplan.io.data.geo.LocalFrame`, azimuthal
equidistant about ``[origin]``) and hands the tables metre triples, so no algorithm ever sees a
latitude.  When ``[origin]`` is absent it is derived: the centre of the latitude/longitude box of
the mission's geographic points (start, goal, route; all geographic points when the mission has
none).  When ``[bounds]`` gives no x/y they are derived too: the box of the mission's points and of the
``[survey]`` area or corridor (its polygon, centre line or file) plus
:func:`bounds_margin` on every side, which :mod:`auvplan.io.scenario.build` then clips to the data and
reports, naming the side, when the data do not cover a mission point.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ....errors import DataError, ScenarioError
from ...data.cache import cached
from ...data.geo import LocalFrame, forward_kept
from ...data.vector.areas import read_area_lonlat, read_line_lonlat
from ..tables import MAX_MAGNITUDE, table_error

__all__ = ["GeoInput", "AltitudeRef", "resolve_positions", "apply_altitudes", "bounds_margin", "clip_to_data",
           "MIN_MARGIN_M", "MARGIN_FRACTION"]

MIN_MARGIN_M = 2000.0
"""Least margin (m) added on every side of the mission's extent when ``[bounds]`` is derived."""
MARGIN_FRACTION = 0.25
"""Margin added on every side of a derived ``[bounds]``, as a fraction of the mission's larger side."""

_GEO_KEYS = ("lat", "lon", "depth", "altitude")


@dataclass(frozen=True)
class AltitudeRef:
    """A position given as an altitude above the seabed, waiting for the terrain.

    Attributes
    ----------
    path : tuple
        Where its z lives in the parsed document (keys and indices).
    where, key : str
        ``file: [table]`` and the key, for messages.
    x, y : float
        Its horizontal position in the local frame (m).
    altitude : float
        Metres above the seabed.
    """

    path: tuple[str | int, ...]
    where: str
    key: str
    x: float
    y: float
    altitude: float


@dataclass(frozen=True)
class GeoInput:
    """What the geographic positions of a scenario left for the build.

    Attributes
    ----------
    origin : tuple of 2 float or None
        ``(lat, lon)`` of the local frame (given or derived).
    origin_derived : bool
        Whether ``[origin]`` was derived from the mission's points.
    bounds_derived : bool
        Whether ``[bounds]`` x/y were derived (the build clips them to the data).
    mission_points : tuple of (str, x, y)
        The mission's points in the local frame (m), each with the key that gave it.
    altitudes : tuple of AltitudeRef
        Positions to place above the seabed once the terrain is read.
    metric : dict
        The document with every position as a metre triple (z = 0 where an altitude waits).
    """

    origin: tuple[float, float] | None
    origin_derived: bool
    bounds_derived: bool
    mission_points: tuple[tuple[str, float, float], ...]
    altitudes: tuple[AltitudeRef, ...]
    metric: dict[str, Any]


def bounds_margin(span_m: float) -> float:
    """The margin (m) added on every side of a mission whose larger side is ``span_m``.

    Parameters
    ----------
    span_m : float
        The larger side of the box of the mission's points (m).

    Returns
    -------
    float
        ``max(MIN_MARGIN_M, MARGIN_FRACTION * span_m)``.
    """
    return max(MIN_MARGIN_M, MARGIN_FRACTION * float(span_m))


def _slots(data: dict[str, Any], src: str) -> list[tuple[tuple[str | int, ...], str, str, Any, bool]]:
    """Every place a position may be: (path, where, key, value, is a mission point)."""
    out: list[tuple[tuple[str | int, ...], str, str, Any, bool]] = []
    m = data.get("mission")
    if isinstance(m, dict):
        for k in ("start", "goal"):
            if k in m:
                out.append((("mission", k), f"{src}: [mission]", k, m[k], True))
        if isinstance(m.get("route"), list):
            out += [(("mission", "route", i), f"{src}: [mission]", f"route[{i}]", p, True)
                    for i, p in enumerate(m["route"])]
    for arr, keys in (("obstacles", ("center",)), ("moving", ("start", "center")), ("vehicles", ("start",))):
        tables = data.get(arr)
        if not isinstance(tables, list):
            continue
        for i, t in enumerate(tables):
            if not isinstance(t, dict):
                continue
            where = f"{src}: [[{arr}]] #{i + 1}"
            out += [((arr, i, k), where, k, t[k], False) for k in keys if k in t]
            if arr == "moving" and isinstance(t.get("points"), list):
                out += [((arr, i, "points", j), where, f"points[{j}]", p, False) for j, p in enumerate(t["points"])]
    return out


def _number(where: str, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise table_error(where, key, value, "expected a number")
    if not math.isfinite(value) or abs(value) > MAX_MAGNITUDE:
        raise table_error(where, key, value, "must be a finite number")
    return float(value)


def _geo_point(where: str, key: str, value: dict[str, Any]) -> tuple[float, float, str, float]:
    """Check ``{lat, lon, depth | altitude}``: (lat, lon, 'depth' or 'altitude', metres)."""
    for k in value:
        if k not in _GEO_KEYS:
            raise table_error(where, f"{key}.{k}", value[k], "unknown key in a geographic position (allowed: lat, "
                              "lon and one of depth, altitude)")
    for k in ("lat", "lon"):
        if k not in value:
            raise table_error(where, key, value, f"a geographic position needs '{k}' (degrees)")
    lat, lon = _number(where, f"{key}.lat", value["lat"]), _number(where, f"{key}.lon", value["lon"])
    if not -90.0 <= lat <= 90.0:
        raise table_error(where, f"{key}.lat", value["lat"], "must lie in [-90, 90] degrees")
    if not -360.0 <= lon <= 360.0:
        raise table_error(where, f"{key}.lon", value["lon"], "must lie in [-360, 360] degrees")
    given = [k for k in ("depth", "altitude") if k in value]
    if len(given) != 1:
        raise table_error(where, key, value, "give exactly one of 'depth' (m below the surface) and 'altitude' "
                          "(m above the seabed)")
    h = _number(where, f"{key}.{given[0]}", value[given[0]])
    if given[0] == "altitude" and h < 0:
        raise table_error(where, f"{key}.altitude", value["altitude"], "must be >= 0 (metres above the seabed)")
    return lat, lon, given[0], h


def _derive_origin(points: list[tuple[float, float]]) -> tuple[float, float]:
    """Centre of the latitude/longitude box of ``points`` (longitudes unwrapped about the first)."""
    lat = np.array([p[0] for p in points])
    lon = np.array([p[1] for p in points])
    lon = lon[0] + (np.mod(lon - lon[0] + 180.0, 360.0) - 180.0)
    lon0 = 0.5 * (float(lon.min()) + float(lon.max()))
    return 0.5 * (float(lat.min()) + float(lat.max())), float(np.mod(lon0 + 180.0, 360.0) - 180.0)


def _set(doc: dict[str, Any], path: tuple[str | int, ...], value: Any) -> None:
    node: Any = doc
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


def _origin(data: dict[str, Any], src: str) -> tuple[float, float] | None:
    o = data.get("origin")
    if not isinstance(o, dict):
        return None
    try:
        lat = _number(f"{src}: [origin]", "lat", o.get("lat"))
        lon = _number(f"{src}: [origin]", "lon", o.get("lon"))
    except ScenarioError:
        return None  # the [origin] table's own check reports it
    return (lat, lon) if -90.0 <= lat <= 90.0 and -360.0 <= lon <= 360.0 else None


def _survey_points(data: dict[str, Any], base_dir: Path | None) -> list[tuple[float, float]]:
    """The ``[survey]`` area's or centre line's (lat, lon) points, when geographic (files read here too)."""
    sv = data.get("survey")
    if not isinstance(sv, dict):
        return []
    for key in ("polygon", "centerline"):
        pts = sv.get(key)
        if isinstance(pts, list) and all(isinstance(p, list) and len(p) == 2 and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in p) for p in pts):
            return [(float(p[0]), float(p[1])) for p in pts]
    for key, read in (("file", read_area_lonlat), ("centerline_file", read_line_lonlat)):
        name = sv.get(key)
        if isinstance(name, str) and name:
            path = Path(name) if Path(name).is_absolute() or base_dir is None else base_dir / name
            layer = sv.get("layer", "")
            try:
                lonlat = read(path, layer if isinstance(layer, str) else "", "[survey]", key)
            except ScenarioError:
                return []  # the survey's own check names the file and the key
            return [(float(lat), float(lon)) for lon, lat in lonlat]
    return []


def _survey_pad(data: dict[str, Any]) -> float:
    sv = data.get("survey", {})
    w = [sv.get("width_m", 0.0)] + list(sv.get("widths_m", [])) if isinstance(sv, dict) else []
    return 0.5 * max([float(v) for v in w if isinstance(v, (int, float)) and math.isfinite(v)] + [0.0])


def resolve_positions(data: dict[str, Any], source: str, base_dir: Path | None = None) -> GeoInput | None:
    """Project the geographic positions of a parsed scenario into its local frame.

    Parameters
    ----------
    data : dict
        The parsed TOML document (not modified).
    source : str
        The file, for messages.
    base_dir : pathlib.Path, optional
        Folder a ``[survey]`` file resolves against.

    Returns
    -------
    GeoInput or None
        None when the document has no geographic position; else the metric document (origin
        and bounds filled in when derived: the box of the mission's points and of the ``[survey]``
        area) and the altitudes still to resolve.

    Raises
    ------
    ScenarioError
        A malformed geographic position, naming the file, the table, the key and the value.
    """
    found = []
    for path, where, key, value, in_mission in _slots(data, source):
        if isinstance(value, dict):
            found.append((path, where, key, _geo_point(where, key, value), in_mission))
    if not found:
        return None
    doc = copy.deepcopy(data)
    origin = _origin(data, source)
    derived = origin is None
    if derived and "origin" in data:
        return None  # a malformed [origin]: its own check names the key
    if origin is None:
        pts = [(g[0], g[1]) for _, _, _, g, mission in found if mission] or [(g[0], g[1]) for _, _, _, g, _ in found]
        origin = _derive_origin(pts)
        doc["origin"] = {"lat": origin[0], "lon": origin[1]}
    frame = LocalFrame(*origin)
    altitudes = []
    xy = _projected(frame, [(g[1], g[0]) for _, _, _, g, _ in found])
    for (path, where, key, (_, _, kind, h), _), (x, y) in zip(found, xy.tolist(), strict=True):
        _set(doc, path, [x, y, -h if kind == "depth" else 0.0])
        if kind == "altitude":
            altitudes.append(AltitudeRef(path, where, key, x, y, h))
    mission = []
    for path, _, key, _, in_mission in _slots(doc, source):
        p = _get(doc, path)
        if in_mission and isinstance(p, list) and len(p) == 3 and all(isinstance(v, (int, float)) for v in p):
            mission.append((key, float(p[0]), float(p[1])))
    bounds = doc.get("bounds")
    bounds_derived = (bounds is None or (isinstance(bounds, dict) and "x" not in bounds and "y" not in bounds)) \
        and len(mission) >= 2
    if bounds_derived:
        doc["bounds"] = _derived_bounds(data, bounds, frame, mission, base_dir)
    return GeoInput(origin, derived, bounds_derived, tuple(mission), tuple(altitudes), doc)



def _derived_bounds(data: dict[str, Any], bounds: Any, frame: LocalFrame, mission: list[tuple[str, float, float]],
                    base_dir: Path | None) -> dict[str, Any]:
    """``[bounds]`` with x and y the box of the mission's points and of the ``[survey]`` area, padded
    (:func:`bounds_margin`); its other keys kept."""
    xs, ys = [p[1] for p in mission], [p[2] for p in mission]
    survey = _survey_points(data, base_dir)
    if survey:  # the survey area is part of the mission: the derived box holds it too
        sx, sy = forward_kept(frame, np.array([p[1] for p in survey]), np.array([p[0] for p in survey]))
        w = _survey_pad(data)
        xs += [float(np.min(sx)) - w, float(np.max(sx)) + w]
        ys += [float(np.min(sy)) - w, float(np.max(sy)) + w]
    pad = bounds_margin(max(max(xs) - min(xs), max(ys) - min(ys)))
    box = dict(bounds) if isinstance(bounds, dict) else {}
    box.update(x=[min(xs) - pad, max(xs) + pad], y=[min(ys) - pad, max(ys) + pad])
    return box


def _projected(frame: LocalFrame, lonlat: list[tuple[float, float]]) -> np.ndarray:
    """``(N, 2)`` east and north (m) of each ``(lon, lat)``: pyproj's, one point at a time, kept in the readers'
    cache under the origin and the positions (:func:`~auvplan.io.data.cache.cached`; pyproj's version is in its
    code stamp), so that a scenario parsed before imports no pyproj (~0.1 s of a command's start, issue 56)."""

    def compute() -> np.ndarray:
        return np.array([[float(v) for v in frame.forward(lon, lat)] for lon, lat in lonlat],
                        dtype=np.float64).reshape(-1, 2)

    request = (float(frame.lat0), float(frame.lon0), tuple((float(lon), float(lat)) for lon, lat in lonlat))
    xy: np.ndarray = cached("positions", request, (), compute, lambda a: ({"xy": a}, {}), lambda arr, _: arr["xy"])
    return xy

def _get(doc: dict[str, Any], path: tuple[str | int, ...]) -> Any:
    node: Any = doc
    for k in path:
        node = node[k]
    return node


def apply_altitudes(geo: GeoInput, seabed: Any) -> dict[str, Any]:
    """The metric document with every altitude-referenced z placed above the seabed.

    Parameters
    ----------
    geo : GeoInput
        From :func:`resolve_positions`.
    seabed : callable
        ``seabed(x, y)`` → seabed elevation (m, up positive; NaN outside the data).

    Returns
    -------
    dict
        A copy of ``geo.metric`` with ``z = seabed(x, y) + altitude`` at each :class:`AltitudeRef`.

    Raises
    ------
    ScenarioError
        When a position lies where there is no seabed (naming the key).
    """
    doc = copy.deepcopy(geo.metric)
    for ref in geo.altitudes:
        zb = float(seabed(ref.x, ref.y))
        if not math.isfinite(zb):
            raise table_error(ref.where, ref.key, {"altitude": ref.altitude}, "no seabed there (outside the terrain "
                              "data): give a depth instead")
        _set(doc, ref.path, [ref.x, ref.y, zb + ref.altitude])
    return doc


def clip_to_data(geo: GeoInput, box: tuple[float, float, float, float], data: tuple[float, float, float, float],
                 what: str) -> tuple[float, float, float, float]:
    """Clip a derived ``[bounds]`` box to the data, after checking the data cover every mission point.

    Parameters
    ----------
    geo : GeoInput
        From :func:`resolve_positions` (its mission points).
    box : tuple of 4 float
        ``(xmin, xmax, ymin, ymax)`` derived: the mission's points plus the margin (m).
    data : tuple of 4 float
        ``(xmin, xmax, ymin, ymax)`` of the data in the local frame (m).
    what : str
        ``file: [terrain]`` and the data's name, for messages.

    Returns
    -------
    tuple of 4 float
        The box clipped to the data.

    Raises
    ------
    DataError
        When a mission point lies beyond the data, naming the point and the side(s).
    """
    x0, x1, y0, y1 = data
    for key, x, y in geo.mission_points:
        sides = [side for side, out in (("west", x < x0), ("east", x > x1), ("south", y < y0), ("north", y > y1))
                 if out]
        if sides:
            raise DataError(f"{what}: the data (x [{x0:.0f}, {x1:.0f}] y [{y0:.0f}, {y1:.0f}] m about the origin) do "
                            f"not cover [mission] {key} (x = {x:.0f}, y = {y:.0f} m): beyond the data's "
                            f"{' and '.join(sides)} side{'s' if len(sides) > 1 else ''}")
    return max(box[0], x0), min(box[1], x1), max(box[2], y0), min(box[3], y1)
