"""``[[zones]]``: charted hazards and no-go areas, written in the scenario or read from the files
operators have, made into :class:`~auvplan.world.Zones` in the local frame.

One table is one zone, or — with ``file`` — one zone per feature of a vector file (GeoJSON, KML,
Shapefile, GeoPackage, FileGDB, S-57 …, anything GDAL reads through pyogrio), in any CRS
(reprojected with pyproj).  An S-57 chart is read by object class: ``layer = "CBLSUB"`` (submarine
cables), ``"PIPSOL"`` (pipelines), ``"WRECKS"``, ``"OBSTRN"``, ``"RESARE"`` (restricted areas),
``"CBLARE"``/``"PIPARE"`` (cable and pipeline areas).

Keys (docs/zones.md): ``name``; one of ``polygon = [[a, b], ...]``, ``line = [[a, b], ...]`` with
``buffer_m``, ``point = [a, b]`` with ``radius_m``, or ``file`` with optional ``layer`` and ``where``
(an OGR SQL attribute filter); a depth band ``top_m``/``bottom_m`` (depths, positive down; absent:
from the surface / to the seabed) or ``above_seabed_m``.  Pairs ``[a, b]`` are ``[lat, lon]`` when the
scenario has an ``[origin]`` and every pair lies within 5° of it, otherwise metres ``[x, y]``.  Lines
and points in a file need ``buffer_m`` / ``radius_m``.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from ....errors import DataError, ScenarioError
from ....world import Terrain, Zone, Zones
from ..geo import LocalFrame
from .dense import check_zone_count, check_zone_vertices, lean
from .kept import kept_geometries
from .reader import read_vector

__all__ = ["ZoneSpec", "parse_zones", "read_zones"]

log = logging.getLogger(__name__)

_KEYS = ("name", "polygon", "line", "buffer_m", "point", "radius_m", "top_m", "bottom_m", "above_seabed_m",
         "file", "layer", "where")
_GEO_REACH_DEG = 5.0
_MAX_M = 4.0e7
"""Largest coordinate, distance or depth a table may give (m): beyond it GEOS's arithmetic overflows."""
_NAME_FIELDS = ("OBJNAM", "NOBJNM", "name", "NAME", "Name")
_QUAD_SEGS = 16
_INSCRIBED = math.cos(math.pi / (4 * _QUAD_SEGS))
"""A buffer's arcs are polygons inscribed in them; buffering by ``r / _INSCRIBED`` circumscribes the
true arcs, so the footprint contains every point within ``r`` (never less, at most 0.12 % more)."""


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


_SLIVER_M = 1e-3
"""A footprint whose mean width (twice its area over its perimeter) is under this (m) encloses no area: points on a
line, a ring folded on itself, or such a line projected from degrees (a few micrometres of curvature)."""


def _mean_width(g: Any) -> float:
    """Twice the area over the perimeter (m): a strip's width, half a disc's radius; 0 for a sliver."""
    perimeter = float(shapely.length(shapely.boundary(g))) if not g.is_empty else 0.0
    return 2.0 * float(g.area) / perimeter if perimeter > 0.0 else 0.0


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


def _made_valid(geom: Any, where: str) -> Any:
    """A polygon feature's valid polygonal parts (empty when it has none): an invalid one (a self-crossing ring, a
    chart's self-touching part) made valid with ``shapely.make_valid`` and said so (a warning, when ``where``
    names it and an area is left: the callers refuse one with none, and a warning before that refusal said it
    was kept).  GEOS's other operations do not keep an invalid polygon's area: ``segmentize`` of a bow tie kept
    one of its two lobes."""
    if shapely.is_valid(geom):
        return geom
    parts = [g for g in shapely.get_parts(_repaired(geom)) if shapely.get_type_id(g) in (3, 6)]
    out = shapely.union_all(parts) if parts else shapely.Polygon()
    if where and not out.is_empty:  # one with no area left is refused by the caller, not warned of
        log.warning("%s: not a valid polygon (%s): made valid (shapely.make_valid), its %d polygonal parts kept",
                    where, shapely.is_valid_reason(geom), len(shapely.get_parts(out)))
    return out


def _repaired(geom: Any) -> Any:
    """``shapely.make_valid`` keeping a polygon's area: its rings' structure (shells unioned, holes subtracted),
    not the default rebuild from the linework with the even-odd rule, which made a part lying inside another
    part (GEOS's "Nested shells": a chart's area with a sub-area as a second part) a hole of the zone."""
    if shapely.get_type_id(geom) in (3, 6):
        return shapely.make_valid(geom, method="structure", keep_collapsed=False)
    return shapely.make_valid(geom)


def _polygonal(geom: Any, where: str) -> Any:
    """A polygon feature as a valid footprint (:func:`_made_valid`); one enclosing no area refused."""
    out = _made_valid(geom, where)
    if _mean_width(out) < _SLIVER_M:
        raise ScenarioError(f"{where}: the polygon encloses no area (mean width {_mean_width(out):.2g} m)")
    return out


def _footprint(geom: Any, buffer_m: float, radius_m: float, where: str) -> Any:
    """A polygon from a polygon, a line buffered by ``buffer_m`` or a point by ``radius_m`` (m)."""
    kind = shapely.get_type_id(geom)
    if kind in (3, 6):
        return lean(_polygonal(geom, where))  # a million vertices: simplified, grown to contain them (.dense)
    if kind in (1, 2, 5):
        if not buffer_m:
            raise ScenarioError(f"{where}: {geom.geom_type} features need buffer_m (a corridor's half-width)")
        return shapely.buffer(geom, buffer_m / _INSCRIBED, quad_segs=_QUAD_SEGS)
    if kind in (0, 4):
        if not radius_m:
            raise ScenarioError(f"{where}: {geom.geom_type} features need radius_m")
        return shapely.buffer(geom, radius_m / _INSCRIBED, quad_segs=_QUAD_SEGS)
    raise DataError(f"{where}: unsupported geometry {geom.geom_type} (a zone is a polygon, a line or a point; "
                    "split the collection into its parts)")


def _read_file(spec: ZoneSpec, frame: LocalFrame | None, base_dir: Path | None,
               box: Any) -> list[tuple[str, Any]]:
    """Named local-frame geometries of the file's features that reach ``box`` (m), kept in the readers'
    cache (:mod:`.kept`: read once per file, table, origin and extent)."""
    path = Path(spec.file)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    request = (spec, str(path), None if frame is None else (frame.lat0, frame.lon0),
               tuple(float(v) for v in shapely.bounds(box)))
    return kept_geometries("zones", request, path, lambda: _read_features(spec, frame, path, box))


def _read_features(spec: ZoneSpec, frame: LocalFrame | None, path: Path, box: Any) -> list[tuple[str, Any]]:
    """:func:`_read_file` without the cache."""
    src = f"{spec.where_} file = {str(path)!r}"
    found = read_vector(path, src, DataError, layer=spec.layer, where=spec.where, fields=True)
    crs = found.crs
    if frame is None and crs.is_geographic:
        raise ScenarioError(f"{src}: geographic features need [origin] lat/lon")
    label = next((found.fields[f] for f in _NAME_FIELDS if f in found.fields), None)
    geoms = found.geometries
    from pyproj import Transformer  # where a file is projected (issue 56)

    to_geo = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)

    def project(xy: np.ndarray) -> np.ndarray:
        if frame is None:
            return xy
        with np.errstate(invalid="ignore", over="ignore"):  # a coordinate with no place: refused below
            lon, lat = to_geo.transform(xy[:, 0], xy[:, 1])
            x, y = frame.forward(lon, lat)
        out = np.column_stack([x, y])
        bad = ~np.isfinite(out).all(axis=1)
        if bad.any():  # projected to inf: GEOS then refused the ring (a traceback, hostile round 22)
            k = int(np.argmax(bad))
            raise DataError(f"{src}: feature {tag!r}: ({xy[k, 0]:.6g}, {xy[k, 1]:.6g}) in its CRS has no place in "
                            "the local frame (it projects to no point on the Earth)")
        return out

    window = _lonlat_window(frame, box, spec.buffer_m + spec.radius_m) if crs.is_geographic and frame else None
    out = []
    named = _feature_names([str(v).strip() if v not in (None, "") else "" for v in label] if label is not None
                           else [""] * len(geoms))
    for i, g in enumerate(geoms):
        if g is None or g.is_empty:
            continue
        tag = named[i]
        g = shapely.force_2d(g)
        _check_coordinates(g, crs.is_geographic, found.crs_stated, f"{src}: feature {tag!r}")
        if window is not None:
            g = _clip_lonlat(g, window)
            if g.is_empty:
                continue
        if shapely.get_type_id(g) in (3, 6):  # made valid here: GEOS's operations below do not keep its area
            g = _made_valid(g, f"{src}: feature {tag!r}")
            if g.is_empty:
                raise DataError(f"{src}: feature {tag!r}: the polygon encloses no area")
        if crs.is_geographic and shapely.get_type_id(g) not in (0, 4):
            g = shapely.segmentize(g, 0.005)  # about 500 m: straight in the local frame, not in degrees
        local = shapely.transform(g, project)
        if not shapely.intersects(local, box):
            continue
        out.append((f"{spec.name}: {tag}", local))
        check_zone_count(len(out), src, DataError)
    if not out:  # a filter that selects nothing is said as such, not as features too far away
        where = f" matches where = {spec.where!r}" if spec.where else f" in layer {spec.layer!r}" if spec.layer else ""
        log.warning("%s: %s", src, f"no feature{where}" if not len(geoms) else "no feature reaches the operating area")
    return out


def _feature_names(tags: list[str]) -> list[str]:
    """Each feature's name: its own (``tags``, ``""`` for none), numbered ``name #k`` by its feature number where
    several share it (a chart repeats a name on the parts of one area), and where a numbered name is another
    feature's own (a feature named ``"A #2"`` beside two named ``"A"``), that one numbered too: every zone's name
    its own.  A feature without a name is ``#k``."""
    out = [t or f"#{i + 1}" for i, t in enumerate(tags)]
    numbered = [not t for t in tags]
    while True:
        seen = {n: out.count(n) for n in set(out)}
        clash = [i for i, n in enumerate(out) if seen[n] > 1 and not numbered[i]]
        if not clash:
            return out
        for i in clash:  # " #k" with k the feature's own number: two numbered names never match
            out[i], numbered[i] = f"{out[i]} #{i + 1}", True


def _check_coordinates(g: Any, geographic: bool, stated: bool, where: str) -> None:
    """Refuse a feature with a coordinate that is not a number, or not a longitude/latitude in a geographic CRS
    (a file without a CRS is read as WGS 84: metres there are the likely cause, said so)."""
    xy = shapely.get_coordinates(g)
    if not np.isfinite(xy).all():
        raise DataError(f"{where}: a coordinate is not a number (NaN or infinite)")
    if geographic and xy.size and (np.abs(xy[:, 1]).max() > 90.0 or np.abs(xy[:, 0]).max() > 540.0):
        k = int(np.argmax(np.maximum(np.abs(xy[:, 1]) - 90.0, np.abs(xy[:, 0]) - 540.0)))
        why = "" if stated else ("; the file states no CRS, so it was read as longitude/latitude (WGS 84): give it "
                                 "its CRS (a .prj beside a shapefile)")
        raise DataError(f"{where}: ({xy[k, 0]:.6g}, {xy[k, 1]:.6g}) is not a longitude/latitude{why}")
    if geographic:
        _check_seam(g, where)


def _check_seam(g: Any, where: str) -> None:
    """Refuse an edge that jumps more than 180° of longitude (but not the 360° of a whole-Earth box): a reef drawn
    across the antimeridian as 179.99 → -179.99 is, read as written, the band round the Earth without it, and
    the zone was the area's complement (10.7 km² kept out, the reef's 1.7 km² open)."""
    for part in shapely.get_parts(shapely.get_rings(g) if shapely.get_type_id(g) in (3, 6) else g):
        xy = shapely.get_coordinates(part)
        jump = np.abs(np.diff(xy[:, 0])) if len(xy) > 1 else np.empty(0)
        bad = np.flatnonzero((jump > 180.0) & (jump < 360.0))
        if bad.size:
            a, b = xy[bad[0]], xy[bad[0] + 1]
            raise DataError(f"{where}: its edge ({a[0]:.6g}, {a[1]:.6g}) → ({b[0]:.6g}, {b[1]:.6g}) spans "
                            f"{jump[bad[0]]:.6g}° of longitude, the long way round the Earth; across the antimeridian "
                            "continue the longitudes past ±180 (180.01) or split the feature there (RFC 7946 §3.1.9)")


def _lonlat_window(frame: LocalFrame, box: Any, reach_m: float) -> tuple[float, float, float, float]:
    """The longitude/latitude box (deg) holding the operating area ``box`` (m) grown by ``reach_m`` and a
    tenth; its longitudes continue past ±180 where the area crosses the antimeridian."""
    x0, y0, x1, y1 = shapely.bounds(box) + np.array([-reach_m, -reach_m, reach_m, reach_m])
    edge = np.linspace(0.0, 1.0, 33)
    x = np.r_[x0 + (x1 - x0) * edge, np.full(33, x1), x1 - (x1 - x0) * edge, np.full(33, x0)]
    y = np.r_[np.full(33, y0), y0 + (y1 - y0) * edge, np.full(33, y1), y1 - (y1 - y0) * edge]
    lon, lat = frame.inverse(x, y)
    lon = frame.lon0 + (np.asarray(lon) - frame.lon0 + 180.0) % 360.0 - 180.0
    dlon, dlat = 0.1 * float(np.ptp(lon)) + 0.01, 0.1 * float(np.ptp(lat)) + 0.01
    return (float(lon.min()) - dlon, max(float(np.min(lat)) - dlat, -90.0), float(lon.max()) + dlon,
            min(float(np.max(lat)) + dlat, 90.0))


def _clip_lonlat(g: Any, window: tuple[float, float, float, float]) -> Any:
    """A feature (lon/lat) cut to ``window`` when it reaches well beyond it: a chart-wide or planet-sized
    polygon made a footprint of thousands of kilometres and hundreds of thousands of vertices (a hemisphere
    took minutes to index; the whole Earth projected into a shape that held nothing).  A feature near the
    area is kept whole."""
    w0, s0, w1, s1 = window
    gx0, gy0, gx1, gy1 = shapely.bounds(g)
    mx, my = 3.0 * (w1 - w0), 3.0 * (s1 - s0)
    if w0 - mx <= gx0 and gx1 <= w1 + mx and s0 - my <= gy0 and gy1 <= s1 + my:
        return g
    parts = [shapely.transform(shapely.clip_by_rect(_repaired(g), w0 + k, s0, w1 + k, s1),
                               lambda xy, k=k: xy - np.array([k, 0.0]))
             for k in (-360.0, 0.0, 360.0)]
    return shapely.union_all([p for p in parts if not p.is_empty]) if any(not p.is_empty for p in parts) \
        else shapely.Polygon()


def read_zones(specs: tuple[ZoneSpec, ...], frame: LocalFrame | None, terrain: Terrain | None,
               extent_m: tuple[float, float, float, float], *, base_dir: Path | None = None,
               margin_m: float = 1000.0, pad_m: float = 1.0) -> Zones:
    """Make the scenario's zones in the local frame (files read, lines and points buffered).

    Parameters
    ----------
    specs : tuple of ZoneSpec
        The ``[[zones]]`` tables.
    frame : LocalFrame or None
        The scenario's local frame (None: every pair is in metres).
    terrain : Terrain or None
        Seabed for ``above_seabed_m`` zones.
    extent_m : tuple of 4 float
        ``(xmin, xmax, ymin, ymax)`` of the operating area (m); file features that do not reach it
        widened by ``margin_m`` are dropped.
    base_dir : pathlib.Path, optional
        Folder that relative file paths resolve against.
    margin_m : float, default 1000.0
        Widening of the area for file features (m).
    pad_m : float, default 1.0
        How far the planners keep off every zone (:attr:`Zones.pad`, m); checks of missions test the
        zones themselves.

    Returns
    -------
    Zones
        The prisms behind their R-tree.

    Raises
    ------
    ScenarioError, DataError
        On a bad table or an unreadable file (one line naming the file, key and value).
    """
    x0, x1, y0, y1 = extent_m
    box = shapely.box(x0 - margin_m, y0 - margin_m, x1 + margin_m, y1 + margin_m)
    zones: list[Zone] = []
    for spec in specs:
        if spec.kind == "file":
            named = _read_file(spec, frame, base_dir, box)
        else:
            xy = _to_local(spec, frame)
            if spec.kind == "polygon":
                _drawn_polygon(spec, xy)
            geom = {"polygon": shapely.Polygon, "line": shapely.LineString}.get(spec.kind, shapely.Point)(
                xy if spec.kind != "point" else xy[0])
            _reaches(spec, geom, box, frame)
            named = [(spec.name, geom)]
        for name, geom in named:
            source = f" file = {spec.file!r}:" if spec.kind == "file" else ""  # which file holds the feature
            footprint = _footprint(geom, spec.buffer_m, spec.radius_m, f"{spec.where_}{source} {name!r}")
            try:
                zones.append(Zone(name, footprint, spec.top_m, spec.bottom_m, spec.above_seabed_m))
            except DataError as exc:
                raise ScenarioError(f"{spec.where_}: {exc}") from exc
    check_zone_count(len(zones), specs[0].where_.split(":")[0] if specs else "", ScenarioError)
    check_zone_vertices([z.footprint for z in zones], specs[0].where_.split(":")[0] if specs else "", ScenarioError)
    try:
        return Zones(tuple(zones), terrain, pad=pad_m)
    except DataError as exc:
        raise ScenarioError(f"{specs[0].where_.split(':')[0]}: {exc}") from exc
