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

The tables are validated and their written geometry placed by :mod:`.zone_tables`, each feature made a footprint
by :mod:`.footprints`; here the files are read and the zones made.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from ....errors import DataError, ScenarioError
from ....world import Terrain, Zone, Zones
from ..geo import LocalFrame
from .dense import check_zone_count, check_zone_vertices
from .footprints import _footprint, _made_valid, _repaired
from .kept import kept_geometries
from .reader import read_vector
from .zone_tables import ZoneSpec, _drawn_polygon, _reaches, _to_local, parse_zones

__all__ = ["ZoneSpec", "parse_zones", "read_zones"]

log = logging.getLogger(__name__)

_NAME_FIELDS = ("OBJNAM", "NOBJNM", "name", "NAME", "Name")


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
