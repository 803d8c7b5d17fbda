"""What a mission file says of its deployment (issue 51), read back format by format: its datum, safety envelope,
payload events, fence and mission storage (:class:`FileDeploy`, :func:`read_deploy`; :func:`csv_datum` the datum a
CSV's ``lat``/``lon`` columns put at x = y = 0).  :mod:`auvplan.io.missions.readback.deploy_read` checks them against
the scenario (``auvplan mission check``)."""

from __future__ import annotations

import csv
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ...data.geo import LocalFrame
from .. import parsed
from ..antimeridian import join_rings
from .qgc_items import plan_items
from .readers import KML_NS, MISSION_SUFFIXES

__all__ = ["FileDeploy", "read_deploy", "csv_datum", "CIRCLE_SIDES"]

@dataclass(frozen=True)
class FileDeploy:
    """What a mission file says beside its waypoints.

    Attributes
    ----------
    datum : tuple of float or None
        ``(lat, lon)`` of the file's local frame.
    polygon : numpy.ndarray or None
        ``(M, 2)`` the envelope's region: local x, y (MOOS, YAML) or lat, lon (QGC, GeoJSON, KML).
    geographic : bool
        Whether ``polygon`` and ``exclusions`` are lat, lon.
    exclusions : list of numpy.ndarray
        Exclusion polygons, in the same coordinates.
    limits : dict
        ``max_depth_m``, ``min_altitude_m``, ``max_time_s`` where the file gives them.
    payload_events : list of (int, bool)
        ``(waypoint, on)`` where the file switches the sensor.
    altitude_legs : int
        Legs the file flies at an altitude above the seabed (terrain following); a ``.plan``'s launch leg never.
    inclusions : list of numpy.ndarray
        A ``.plan`` fence's other inclusion polygons and circles (as polygons), in the same coordinates: ArduPilot
        keeps the vehicle inside every one (``AC_PolyFence_loader::breached``, without ``FENCE_OPTIONS``' union).
    fence_items : tuple of (list of int, int) or None
        A ``.plan`` fence as ArduPilot stores it: each polygon's vertex count (inclusions and exclusions) and the
        number of circles (:func:`auvplan.io.missions.deploy_formats.fence_bytes`); None for other formats.
    commands : int or None
        A ``.plan``'s mission commands as AP_Mission stores them, the home included
        (:func:`auvplan.io.missions.readback.mission_storage.mission_storage`); None for other formats.
    """

    datum: tuple[float, float] | None = None
    polygon: NDArray[np.float64] | None = None
    geographic: bool = False
    exclusions: list[NDArray[np.float64]] = field(default_factory=list)
    limits: dict[str, float] = field(default_factory=dict)
    payload_events: list[tuple[int, bool]] = field(default_factory=list)
    altitude_legs: int = 0
    inclusions: list[NDArray[np.float64]] = field(default_factory=list)
    fence_items: tuple[list[int], int] | None = None
    commands: int | None = None


_NUM = r"([-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"


def _moos(text: str) -> FileDeploy:
    body = re.sub(r"//[^\n]*", "", text)
    lat = re.search(rf"^\s*LatOrigin\s*=\s*{_NUM}", body, re.M)
    lon = re.search(rf"^\s*LongOrigin\s*=\s*{_NUM}", body, re.M)
    datum = (float(lat.group(1)), float(lon.group(1))) if lat and lon else None
    poly, limits = None, {}
    m = re.search(r"Behavior\s*=\s*BHV_OpRegion\s*\{([^}]*)\}", body)
    if m:
        kv = dict((k.strip().lower(), v.strip()) for k, v in (ln.split("=", 1) for ln in m.group(1).splitlines()
                                                               if "=" in ln))
        if "polygon" in kv:
            poly = np.array([[float(c) for c in pt.split(",")[:2]] for pt in kv["polygon"].split(":")])
        limits = {f"{k}_{'m' if k != 'max_time' else 's'}": float(kv[k])
                  for k in ("max_depth", "min_altitude", "max_time") if k in kv}
    events = []
    for blk in re.finditer(r"Behavior\s*=\s*BHV_ConstantDepth\s*\{([^}]*)\}", body):
        idx = re.search(r"WPT_INDEX\s*==?\s*(\d+)", blk.group(1))
        flag = re.search(r"runflag\s*=\s*PAYLOAD\s*=\s*(on|off)", blk.group(1))
        if idx and flag:
            events.append((int(idx.group(1)), flag.group(1) == "on"))
    alt = len(re.findall(r"Behavior\s*=\s*BHV_MinAltitudeX", body))
    return FileDeploy(datum, poly, False, [], limits, sorted(events), alt)


def _qgc(doc: dict[str, Any]) -> FileDeploy:
    fence = doc.get("geoFence") or {}
    inc = [np.asarray(p["polygon"], dtype=float) for p in fence.get("polygons", []) if p.get("inclusion")]
    exc = [np.asarray(p["polygon"], dtype=float) for p in fence.get("polygons", []) if not p.get("inclusion", True)]
    # its circles (QGroundControl draws them too; ArduPilot keeps the vehicle out of an exclusion circle): were
    # ignored, a mission through one passed; as polygons, an exclusion's around its circle, an inclusion's inside
    circles = [(_circle_ring(c["circle"]["center"], c["circle"]["radius"], not c.get("inclusion", True)),
                bool(c.get("inclusion", True))) for c in fence.get("circles", [])]
    exc += [ring for ring, inclusion in circles if not inclusion]
    inc += [ring for ring, inclusion in circles if inclusion]
    events, wp, alt = [], -1, 0
    items = plan_items(doc)
    for it in items:  # the reader's waypoints (the same walk)
        if it.moves:
            wp += 1
            alt += it.frame == 10 and wp > 0  # legs, as terrain_legs: the launch leg (to item 0) is not one
        elif it.command == 181:
            events.append((wp, float(it.params[1]) > 0))
    stored = ([len(p["polygon"]) for p in fence.get("polygons", [])], len(fence.get("circles", [])))
    return FileDeploy(None, inc[0] if inc else None, True, exc, {}, events, alt, inc[1:], stored,
                      len(items) + 1)  # the home is command 0


CIRCLE_SIDES = 64
"""Sides of the polygon a ``.plan``'s fence circle is tested as (:func:`_circle_ring`)."""


def _circle_ring(center: Any, radius: Any, around: bool) -> NDArray[np.float64]:
    """A QGroundControl fence circle as a ``[lat, lon]`` ring of :data:`CIRCLE_SIDES` sides: its vertices on the
    circle (inside the disc: an inclusion) or pushed out by ``1 / cos(pi / sides)`` (around it: an exclusion), the
    circle as ArduPilot measures it (metres north and east at ``LATLON_TO_M`` a 1e-7 degree, east scaled by the
    cosine of the latitude)."""
    lat, lon, r = float(center[0]), float(center[1]), float(radius)
    if not (math.isfinite(lat) and math.isfinite(lon) and math.isfinite(r) and r > 0.0):
        raise DataError(f"QGC plan: geoFence circle at {center!r}, radius {radius!r}: expected a centre and a "
                        "positive radius (m)")
    k = np.arange(CIRCLE_SIDES) * (2.0 * math.pi / CIRCLE_SIDES)
    reach = r / math.cos(math.pi / CIRCLE_SIDES) if around else r
    per_deg = 111318.84502145034  # ArduPilot's LATLON_TO_M x 1e7
    dlat = reach * np.sin(k) / per_deg
    dlon = reach * np.cos(k) / (per_deg * max(math.cos(math.radians(lat)), 1e-9))
    return np.column_stack([lat + dlat, lon + dlon])


def _yaml(text: str) -> FileDeploy:
    import yaml

    doc = yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # libyaml when built with it
    d = doc.get("datum")
    datum = (float(d["lat"]), float(d["lon"])) if isinstance(d, dict) else None
    env = doc.get("envelope") or {}
    poly = np.asarray(env["polygon"], dtype=float) if "polygon" in env else None
    limits = {k: float(env[k]) for k in ("max_depth_m", "min_altitude_m", "max_time_s") if k in env}
    events = [(int(e["waypoint"]), bool(e["sensor"])) for e in doc.get("payload_events") or []]
    return FileDeploy(datum, poly, False, [], limits, events, 0)


def _geojson(doc: dict[str, Any]) -> FileDeploy:
    poly, exc, limits, events, alt = None, [], {}, [], 0
    for f in doc.get("features", []):
        props = f.get("properties") or {}
        if props.get("name") in ("envelope", "exclusion"):
            g = f["geometry"]
            parts = g["coordinates"] if g.get("type") == "MultiPolygon" else [g["coordinates"]]  # cut at ±180°
            ring = join_rings([np.asarray(p[0], dtype=float) for p in parts])[:, ::-1]  # lat, lon
            if props["name"] == "envelope":
                poly = ring
                limits = {k: float(props[k]) for k in ("max_depth_m", "min_altitude_m", "max_time_s") if k in props}
            else:
                exc.append(ring)
        elif props.get("name") == "mission":
            events = [(int(e["waypoint"]), e["sensor"] == "on") for e in props.get("payload_events", [])]
            alt = len(props.get("altitude_m", [])) and len(props["altitude_m"]) - 1
    return FileDeploy(None, poly, True, exc, limits, events, alt)


def _kml(text: str) -> FileDeploy:
    ns = {"k": KML_NS}
    poly, exc, events = None, [], []
    limits: dict[str, float] = {}
    for pm in ET.fromstring(text).iter(f"{{{KML_NS}}}Placemark"):
        name = pm.findtext("k:name", namespaces=ns) or ""
        data = {d.get("name"): d.findtext("k:value", namespaces=ns) or "" for d in pm.iter(f"{{{KML_NS}}}Data")}
        if name in ("envelope", "exclusion"):
            outer = "k:Polygon/k:outerBoundaryIs/k:LinearRing/k:coordinates"
            cs = pm.findall(outer, ns) or pm.findall(f"k:MultiGeometry/{outer}", ns)  # cut at ±180°: the pieces
            ring = join_rings([np.array([[float(v) for v in s.split(",")[:2]] for s in (c.text or "").split()])
                               for c in cs] or [np.empty((0, 2))])[:, ::-1]
            if name == "envelope":
                poly = ring
                limits = {k: float(data[k]) for k in ("max_depth_m", "min_altitude_m", "max_time_s") if k in data}
            else:
                exc.append(ring)
        elif name == "mission" and "payload_events" in data:
            events = [(int(a), b == "on") for a, b in (e.split(":") for e in data["payload_events"].split())]
    return FileDeploy(None, poly, True, exc, limits, events, 0)


def csv_datum(lat: NDArray[np.float64], lon: NDArray[np.float64], x: NDArray[np.float64],
              y: NDArray[np.float64]) -> tuple[float, float] | None:
    """The origin whose local frame puts each ``(lat, lon)`` at its ``(x, y)``: a fixed-point iteration
    moving a guess by the mean residual (converges in a few steps; None without lat/lon).

    Parameters
    ----------
    lat, lon, x, y : numpy.ndarray
        The CSV's columns (degrees, m).

    Returns
    -------
    tuple of float or None
        ``(lat, lon)`` of the file's datum.
    """
    ok = np.isfinite(lat) & np.isfinite(lon) & np.isfinite(x) & np.isfinite(y)
    if not ok.any():
        return None
    lat, lon, x, y = lat[ok], lon[ok], x[ok], y[ok]
    frame = LocalFrame(float(lat[0]), float(lon[0]))
    o_lon, o_lat = frame.inverse(np.array([-x[0]]), np.array([-y[0]]))
    guess = (float(o_lat[0]), float(o_lon[0]))
    for _ in range(8):
        fx, fy = LocalFrame(*guess).forward(lon, lat)
        rx, ry = float(np.mean(fx - x)), float(np.mean(fy - y))
        g_lon, g_lat = LocalFrame(*guess).inverse(np.array([rx]), np.array([ry]))
        guess = (float(g_lat[0]), float(g_lon[0]))
        if np.hypot(rx, ry) < 1e-6:
            break
    return guess


def _csv(text: str) -> FileDeploy:
    rows = list(csv.DictReader(text.splitlines()))
    if not rows:
        return FileDeploy()

    def col(k: str) -> NDArray[np.float64]:
        return np.array([float(r[k]) if r.get(k) not in (None, "") else np.nan for r in rows])

    datum = None
    if "lat" in rows[0]:
        lat, lon = col("lat"), col("lon")
        far = (np.abs(lat) > 90.0) | (np.abs(lon) > 540.0)  # 1e308 reached the frame: numpy's warnings, then an error
        if far.any():
            k = int(np.argmax(far))
            raise ValueError(f"line {k + 2}: lat = {lat[k]:.6g}, lon = {lon[k]:.12g}: not a latitude/longitude")
        datum = csv_datum(lat, lon, col("x"), col("y"))
    events = []
    if "payload" in rows[0]:
        p = np.array([r["payload"].strip() == "1" for r in rows])
        prev = np.r_[False, p[:-1]]
        events = [(int(i), bool(p[i])) for i in np.flatnonzero(p != prev)]
    alt = len(rows) - 1 if "altitude" in rows[0] else 0
    return FileDeploy(datum, None, False, [], {}, events, alt)


def read_deploy(path: str | Path) -> FileDeploy:
    """What a mission file carries beside its waypoints (module notes).

    Parameters
    ----------
    path : str or pathlib.Path
        A file :func:`auvplan.io.missions.readback.readers.read_mission` reads.

    Returns
    -------
    FileDeploy
        Its datum, envelope, payload events and terrain-following legs (empty where it says nothing).
    """
    path = Path(path)
    fmt = MISSION_SUFFIXES.get(path.suffix.lower())
    text = path.read_text(encoding="utf-8")
    readers = {"moos": lambda: _moos(text), "qgc": lambda: _qgc(parsed.loads(text)), "ros": lambda: _yaml(text),
               "geojson": lambda: _geojson(parsed.loads(text)), "kml": lambda: _kml(text), "csv": lambda: _csv(text)}
    try:
        if fmt in readers:
            return _numbers(readers[fmt](), path)
    except (ValueError, KeyError, TypeError, AttributeError, IndexError, OverflowError, ET.ParseError) as exc:
        raise DataError(f"{path}: the datum, envelope or payload events cannot be read ({exc})") from exc
    return FileDeploy()


def _numbers(info: FileDeploy, path: Path) -> FileDeploy:
    """Refuse a datum, envelope polygon or limit that is not a finite number (hostile round 22: a NaN
    ``max_depth_m`` was 'envelope OK — max_depth_m nan'; a vertex of 1e308 gave numpy's warnings, then a verdict)."""
    if info.datum is not None and not (all(map(math.isfinite, info.datum)) and abs(info.datum[0]) <= 90.0
                                       and abs(info.datum[1]) <= 540.0):
        raise DataError(f"{path}: datum lat {info.datum[0]!r}, lon {info.datum[1]!r}: not a latitude/longitude")
    for key, value in info.limits.items():
        if not (math.isfinite(value) and value >= 0.0):
            raise DataError(f"{path}: envelope {key} = {value!r}: expected a finite number >= 0")
    for what, rings in (("polygon", [] if info.polygon is None else [info.polygon]),
                        ("exclusion", info.exclusions), ("inclusion", info.inclusions)):
        for ring in rings:
            xy = np.asarray(ring, dtype=float).reshape(-1, 2)
            far = ~np.isfinite(xy).all(axis=1) | (np.abs(xy) > (1e8 if not info.geographic else 540.0)).any(axis=1)
            if info.geographic:
                far |= np.abs(xy[:, 0]) > 90.0
            if far.any():
                k = int(np.argmax(far))
                raise DataError(f"{path}: envelope {what}: vertex {k} = ({xy[k, 0]:.6g}, {xy[k, 1]:.6g}): "
                                f"not {'a latitude/longitude' if info.geographic else 'a position in metres'}")
    return info
