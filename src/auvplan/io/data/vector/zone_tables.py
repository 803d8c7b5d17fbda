"""The ``[[zones]]`` tables of a scenario (:mod:`.zones`): each table validated into a :class:`ZoneSpec` (nothing read
from disk yet), and the geometry a table writes placed in the local frame (pairs ``[lat, lon]`` within 5° of the
origin, otherwise metres) and checked: a polygon that is one, a zone that reaches the operating area.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from ....errors import ScenarioError
from ..geo import LocalFrame
from .footprints import _SLIVER_M, _made_valid, _mean_width

__all__ = ["ZoneSpec", "parse_zones"]


_KEYS = ("name", "polygon", "line", "buffer_m", "point", "radius_m", "top_m", "bottom_m", "above_seabed_m",
         "file", "layer", "where")
_GEO_REACH_DEG = 5.0
_MAX_M = 4.0e7
"""Largest coordinate, distance or depth a table may give (m): beyond it GEOS's arithmetic overflows."""


@dataclass(frozen=True)
class ZoneSpec:
    """One ``[[zones]]`` table, validated (nothing read from disk yet).

    Attributes
    ----------
    where_ : str
        ``file: [[zones]] #i`` for messages.
    name : str
        Zone name (prefix of the feature names for a file).
    kind : {"polygon", "line", "point", "file"}
        Which geometry key was given.
    coords : tuple of tuple of float
        The pairs of ``polygon``/``line``/``point`` (empty for a file).
    buffer_m, radius_m : float
        Half-width of a line's corridor, radius round a point (m; 0 when not given).
    top_m, bottom_m : float
        Depth band (m, positive down); ``bottom_m = inf`` reaches the seabed.
    above_seabed_m : float or None
        Height of a seabed band (m).
    file, layer, where : str
        Vector file, its layer (an S-57 object class) and an attribute filter.
    """

    where_: str
    name: str
    kind: str
    coords: tuple[tuple[float, float], ...] = ()
    buffer_m: float = 0.0
    radius_m: float = 0.0
    top_m: float = 0.0
    bottom_m: float = math.inf
    above_seabed_m: float | None = None
    file: str = ""
    layer: str = ""
    where: str = ""


def _num(where: str, key: str, value: Any, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0 \
            or (positive and value == 0):
        raise ScenarioError(f"{where} {key} = {value!r}: expected a {'positive' if positive else 'non-negative'} "
                            "number")
    if value > _MAX_M:
        raise ScenarioError(f"{where} {key} = {value!r}: over {_MAX_M:g} m (the Earth's circumference)")
    return float(value)


def _pairs(where: str, key: str, value: Any, n_min: int) -> tuple[tuple[float, float], ...]:
    pts = [value] if key == "point" else value
    ok = isinstance(pts, list) and len(pts) >= n_min and all(
        isinstance(p, list) and len(p) == 2 and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                    and math.isfinite(c) for c in p) for p in pts)
    if not ok:
        shape = "[a, b]" if key == "point" else f"an array of at least {n_min} [a, b] pairs"
        raise ScenarioError(f"{where} {key} = {str(value)[:60]}: expected {shape} ([lat, lon] or metres [x, y])")
    far = next((p for p in pts if max(abs(p[0]), abs(p[1])) > _MAX_M), None)
    if far is not None:
        raise ScenarioError(f"{where} {key}: the pair {far} lies over {_MAX_M:g} m (the Earth's circumference) "
                            "from the origin")
    return tuple((float(p[0]), float(p[1])) for p in pts)


def _one(table: Any, where: str) -> ZoneSpec:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: expected a table, got {type(table).__name__}")
    for key in table:
        if key not in _KEYS:
            raise ScenarioError(f"{where} unknown key {key!r} (allowed: {', '.join(_KEYS)})")
    if "name" not in table:  # said as missing, not as "name = ''"
        raise ScenarioError(f"{where} has no name: every zone needs one (messages, the chart and the exports name it)")
    name = table["name"]
    if not isinstance(name, str) or not name.strip():
        raise ScenarioError(f"{where} name = {name!r}: expected a non-empty string")
    if any(not c.isprintable() for c in name):  # a newline in a name split every message naming the zone
        raise ScenarioError(f"{where} name = {name!r}: a control character in a zone's name (it is printed in "
                            "messages of one line, the report and the exports)")
    given = [k for k in ("polygon", "line", "point", "file") if k in table]
    if len(given) != 1:
        raise ScenarioError(f"{where} {name!r}: give exactly one of polygon, line, point, file (got "
                            f"{', '.join(given) or 'none'})")
    kind = given[0]
    kw: dict[str, Any] = {}
    for key in ("buffer_m", "radius_m"):
        if key in table:
            kw[key] = _num(where, key, table[key], positive=True)
    if kind == "line" and "buffer_m" not in kw:
        raise ScenarioError(f"{where} {name!r}: a line needs buffer_m (the corridor's half-width)")
    if kind == "point" and "radius_m" not in kw:
        raise ScenarioError(f"{where} {name!r}: a point needs radius_m")
    if "above_seabed_m" in table:
        if "top_m" in table or "bottom_m" in table:
            raise ScenarioError(f"{where} {name!r}: above_seabed_m cannot be combined with top_m/bottom_m")
        kw["above_seabed_m"] = _num(where, "above_seabed_m", table["above_seabed_m"], positive=True)
    top = _num(where, "top_m", table["top_m"]) if "top_m" in table else 0.0
    bottom = _num(where, "bottom_m", table["bottom_m"]) if "bottom_m" in table else math.inf
    if not bottom > top:
        raise ScenarioError(f"{where} bottom_m = {bottom:g}: must be deeper than top_m = {top:g}")
    for key in ("file", "layer", "where"):
        if key in table:
            if kind != "file":
                raise ScenarioError(f"{where} {key} = {table[key]!r}: only with file")
            if not isinstance(table[key], str):
                raise ScenarioError(f"{where} {key} = {table[key]!r}: expected a string")
            if not table[key]:  # layer = '' and where = '' were read as absent
                raise ScenarioError(f"{where} {key} = '': an empty string is not a value (omit the key to leave it "
                                    "unset)")
            kw[key] = table[key]
    coords = () if kind == "file" else _pairs(where, kind, table[kind], {"polygon": 3, "line": 2, "point": 1}[kind])
    return ZoneSpec(where, name.strip(), kind, coords, top_m=top, bottom_m=bottom, **kw)


def parse_zones(tables: Any, source: str) -> tuple[ZoneSpec, ...]:
    """Validate the ``[[zones]]`` array of a scenario.

    Parameters
    ----------
    tables : list of dict
        The parsed array of tables.
    source : str
        The scenario file, for messages.

    Returns
    -------
    tuple of ZoneSpec
        One per table.

    Raises
    ------
    ScenarioError
        On an unknown key, a missing or doubled geometry, or a bad value (naming file, key and value).
    """
    if not isinstance(tables, list):
        raise ScenarioError(f"{source}: zones = {str(tables)[:60]}: expected an array of tables [[zones]]")
    specs = tuple(_one(t, f"{source}: [[zones]] #{i + 1}") for i, t in enumerate(tables))
    first: dict[str, str] = {}
    for spec in specs:  # every message, drawing and export names a zone: two of one name are one to a reader
        if spec.name in first:
            raise ScenarioError(f"{spec.where_} name = {spec.name!r}: already the name of {first[spec.name]}; "
                                "each zone needs its own name")
        first[spec.name] = spec.where_.rsplit(": ", 1)[-1]
    return specs


def _to_local(spec: ZoneSpec, frame: LocalFrame | None) -> np.ndarray:
    """The spec's pairs in the local frame: [lat, lon] within reach of the origin, else metres."""
    xy = np.asarray(spec.coords, dtype=float)
    if frame is None:
        return xy
    near = _near_origin(xy, frame)
    if near.all():
        x, y = frame.forward(xy[:, 1], xy[:, 0])
        return np.column_stack([x, y])
    if near.any():
        raise ScenarioError(f"{spec.where_} {spec.kind}: some pairs look like [lat, lon] near the origin and some "
                            "do not; give all in degrees or all in metres")
    return xy


def _near_origin(xy: np.ndarray, frame: LocalFrame) -> np.ndarray:
    """Which pairs ``[a, b]`` lie within 5° of the origin as ``[lat, lon]``."""
    return np.asarray((np.abs(xy[:, 0] - frame.lat0) <= _GEO_REACH_DEG)
                      & (np.abs((xy[:, 1] - frame.lon0 + 180.0) % 360.0 - 180.0) <= _GEO_REACH_DEG))


def _reaches(spec: ZoneSpec, geom: Any, box: Any, frame: LocalFrame | None) -> None:
    """Refuse a zone written in the scenario that lies wholly outside the area (``box``, m): [lat, lon] pairs
    beyond 5° of the origin are read as metres, and such a zone was accepted silently, far from anything."""
    reach = shapely.buffer(geom, spec.buffer_m + spec.radius_m) if spec.kind != "polygon" else geom
    if shapely.intersects(reach, box):
        return
    x0, y0, x1, y1 = shapely.bounds(box)
    about = "" if frame is None else f"[origin] lat = {frame.lat0:g}, lon = {frame.lon0:g}"
    why = "" if frame is None else (  # read as degrees: the place is wrong, not the units
        f"; its pairs were read as [lat, lon] about {about}" if _near_origin(np.asarray(spec.coords, dtype=float),
                                                                            frame).all()
        else f"; its pairs were read as metres [x, y], not all being within {_GEO_REACH_DEG:g}° of {about}")
    raise ScenarioError(f"{spec.where_} {spec.kind} = {str([list(c) for c in spec.coords])[:60]}: the zone lies "
                        f"wholly outside the operating area (x {x0:.0f} .. {x1:.0f}, y {y0:.0f} .. {y1:.0f} m){why}")


def _drawn_polygon(spec: ZoneSpec, xy: np.ndarray) -> None:
    """Refuse a ``polygon`` written in the scenario that is not one: fewer than 3 distinct points, no area (its
    points on a line), or edges that cross (vertices out of order: made valid, a rectangle with two corners
    swapped keeps two triangles of half its area, so the operator is asked, not guessed for)."""
    value = f"{spec.where_} polygon = {str([list(c) for c in spec.coords])[:60]}"
    distinct = len(np.unique(xy, axis=0))
    if distinct < 3:
        raise ScenarioError(f"{value}: {distinct} distinct points; a polygon needs at least 3")
    poly = shapely.Polygon(xy)
    if _mean_width(_made_valid(poly, "")) < _SLIVER_M:  # a crossing ring's signed areas cancel: the valid parts
        raise ScenarioError(f"{value}: encloses no area (its points lie on a line)")
    if not shapely.is_valid(poly):
        raise ScenarioError(f"{value}: not a simple polygon ({shapely.is_valid_reason(poly)}, local m): list its "
                            "vertices in order round the zone, its edges meeting only at their ends")
