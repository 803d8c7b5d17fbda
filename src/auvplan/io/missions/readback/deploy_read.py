"""Reading back what makes a mission file deployable (issue 51) and checking it against the scenario
(``auvplan mission check``): the file's datum, its safety envelope and its payload events
(:mod:`auvplan.io.missions.deploy_formats` says where each format keeps them).

* **Datum** — a local-coordinate file (MOOS, ROS 2 YAML, CSV) whose datum differs from the scenario's
  ``[origin]`` by more than 1 cm is refused (:class:`~auvplan.errors.DataError`, exit 2): its metres would be
  placed elsewhere.  The CSV's datum is the origin its ``lat``/``lon`` columns put at x = y = 0
  (:func:`csv_datum`).  A file without a datum (written before issue 51) is read as before, and said so.
* **Envelope** — it must contain the mission: every leg inside the polygon and outside the exclusions,
  the deepest waypoint within ``max_depth``, the least re-flown altitude at or above ``min_altitude``, the
  predicted duration within ``max_time`` — the energy check's duration (through the current, with a ``.plan``'s
  launch leg and holds): the time-out is judged against what the mission will take.  A file that carries none is
  reported (``envelope: null``).
* **Fence storage** — a ``.plan``'s ``geoFence`` (every polygon and circle, as ArduPilot stores them) must fit its
  fence storage (:func:`auvplan.io.missions.deploy_formats.fence_storage_problem`, the export's own rule: 672
  bytes on a 16 KiB board), else ArduSub refuses the upload; only the export was held to it, and a user's own
  ``.plan`` with a fence of 84 vertices passed.
* **Mission storage** — a ``.plan``'s commands (the home included) and the smallest of AP_Mission's three
  capacities that holds them (:mod:`auvplan.io.missions.readback.mission_storage`): said, and a failure only when
  the operator names the board (``--board-storage``) and it cannot hold them.
* **Altitude legs** — counted as legs, as the terrain-following check counts them: a ``.plan``'s launch leg (home
  to its first item) is never one, even when that item is in the terrain frame.
"""

from __future__ import annotations

import csv
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from ....errors import DataError
from ...data.geo import LocalFrame
from .. import parsed
from ..antimeridian import join_rings
from ..deploy_formats import FENCE_STORAGE_BYTES, fence_bytes, fence_storage_problem
from .mission_storage import BoardStorage, mission_storage
from .qgc_items import plan_items
from .readers import KML_NS, MISSION_SUFFIXES

__all__ = ["FileDeploy", "read_deploy", "csv_datum", "check_deploy", "file_deploy_check", "DATUM_TOLERANCE_M"]

DATUM_TOLERANCE_M = 0.01
"""Largest distance (m) between a file's datum and the scenario's origin that is taken as the same datum."""


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


def check_deploy(path: str | Path, origin: tuple[float, float] | None, waypoints: NDArray[np.float64],
                 min_altitude_m: float, duration_s: float, board: BoardStorage | None = None) -> dict[str, Any]:
    """Check a file's datum against the scenario and its envelope against its mission (module notes).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    origin : tuple of float or None
        The scenario's ``[origin]``.
    waypoints : numpy.ndarray
        ``(N, 3)`` the file's mission in the scenario's local frame (m).
    min_altitude_m : float
        The least altitude of the mission re-flown under the file's semantics (m).
    duration_s : float
        The mission's predicted duration (s): through the current, with a ``.plan``'s launch leg and holds.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold fails.

    Returns
    -------
    dict
        ``datum`` (``lat``, ``lon``, ``offset_m``, or None), ``envelope`` (its limits and ``ok``, ``reasons``,
        or None), ``payload_events``, ``altitude_legs``, a ``.plan``'s ``fence_storage`` (``bytes``,
        ``limit_bytes``, ``ok``, ``reason``) and ``mission_storage``
        (:func:`~auvplan.io.missions.readback.mission_storage.mission_storage`), and ``ok``.

    Raises
    ------
    DataError
        When the file's datum differs from the scenario's origin (or the scenario has none).
    """
    info = read_deploy(path)
    out: dict[str, Any] = {"datum": None, "envelope": None, "altitude_legs": info.altitude_legs,
                           "payload_events": [{"waypoint": i, "sensor": "on" if on else "off"}
                                              for i, on in info.payload_events]}
    if info.datum is not None:
        if origin is None:
            raise DataError(f"{path}: the file's datum is lat {info.datum[0]:.9f}, lon {info.datum[1]:.9f} but the "
                            "scenario has no [origin]: its local coordinates cannot be placed")
        dx, dy = LocalFrame(*origin).forward(np.array([info.datum[1]]), np.array([info.datum[0]]))
        off = float(np.hypot(dx[0], dy[0]))
        if off > DATUM_TOLERANCE_M:
            raise DataError(f"{path}: datum lat {info.datum[0]:.9f}, lon {info.datum[1]:.9f} differs from the "
                            f"scenario's [origin] lat {origin[0]:.9f}, lon {origin[1]:.9f} ({off:.2f} m apart): its "
                            "local coordinates would be placed that far off")
        out["datum"] = {"lat": info.datum[0], "lon": info.datum[1], "offset_m": off}
    if info.polygon is not None:
        out["envelope"] = _envelope(info, origin, waypoints, min_altitude_m, duration_s,
                                    raw=Path(path).suffix.lower() == ".plan")
    elif info.datum is not None and MISSION_SUFFIXES.get(Path(path).suffix.lower()) in ("moos", "ros"):
        # written since issue 51 (it has a datum), in a format that carries an envelope, but without one
        out["envelope"] = {"ok": False, "vertices": 0, "exclusions": 0, "predicted_s": duration_s,
                           "reasons": ["the file has a datum but no envelope (BHV_OpRegion / envelope removed)"]}
    if info.fence_items is not None:  # a .plan's fence must fit ArduPilot's storage, else ArduSub refuses it
        vertices, circles = info.fence_items
        why = fence_storage_problem(vertices, circles)
        out["fence_storage"] = {"bytes": fence_bytes(vertices, circles), "limit_bytes": FENCE_STORAGE_BYTES,
                                "ok": why is None, "reason": why}
    if info.commands is not None:  # the mission storage a .plan needs (failing only on the board named)
        out["mission_storage"] = mission_storage(info.commands, board)
    out["ok"] = ((out["envelope"] is None or out["envelope"]["ok"]) and out.get("fence_storage", {}).get("ok", True)
                 and out.get("mission_storage", {}).get("ok", True))
    return out


def _envelope(info: FileDeploy, origin: tuple[float, float] | None, w: NDArray[np.float64], min_alt: float,
              duration: float, raw: bool = False) -> dict[str, Any]:
    """Whether the envelope contains the mission: legs in the polygon and off the exclusions, depth, altitude, time
    (``raw``: a ``.plan``'s fence, in ArduPilot's longitudes, :func:`_planar_latlon`)."""
    pts = w[:, :2]
    assert info.polygon is not None
    rings = [info.polygon, *info.inclusions, *info.exclusions]
    if info.geographic:  # [lat, lon] rings: compared in latitude/longitude, as ArduPilot's fence tests them
        if origin is None:
            raise DataError("a geographic envelope needs the scenario's [origin]")
        rings, pts = _planar_latlon(rings, pts, origin, raw)
    track = _track(pts, raw and info.geographic)
    reasons = []
    for k, ring in enumerate(rings[:1 + len(info.inclusions)]):  # inside every one (ArduPilot's default)
        region = shapely.Polygon(ring)
        if not region.covers(track):
            outside = int(np.sum(~shapely.covers(region, shapely.points(pts))))
            which = "the envelope's polygon" if k == 0 else f"the fence's inclusion {k + 1}"
            reasons.append(f"the mission leaves {which} ({outside} waypoints outside)")
    hit = [k for k, e in enumerate(rings[1 + len(info.inclusions):]) if shapely.Polygon(e).intersects(track)]
    if hit:
        reasons.append(f"the mission crosses exclusion polygon{'s' if len(hit) > 1 else ''} {hit}")
    lim = info.limits
    deepest = float(-w[:, 2].min())
    if "max_depth_m" in lim and deepest > lim["max_depth_m"] + 1e-3:
        reasons.append(f"deepest waypoint {deepest:.2f} m > max_depth {lim['max_depth_m']:g} m")
    if lim.get("min_altitude_m", 0) > 0 and min_alt < lim["min_altitude_m"] - 1e-3:
        reasons.append(f"least altitude {min_alt:.2f} m < min_altitude {lim['min_altitude_m']:g} m")
    if "max_time_s" in lim and not duration <= lim["max_time_s"]:  # never arriving (the energy check's nan/inf) too
        reasons.append(f"predicted duration {duration:.0f} s > max_time {lim['max_time_s']:g} s")
    return {**lim, "vertices": len(info.polygon), "exclusions": len(info.exclusions),
            "deepest_m": deepest, "predicted_s": duration, "ok": not reasons, "reasons": reasons}


def _track(pts: NDArray[np.float64], raw: bool) -> Any:
    """The mission's legs as one shapely geometry; in raw longitudes a leg across ±180° (flown the short way, as
    ArduPilot's ``Location::get_distance_NE`` does) is cut there into its two pieces."""
    if len(pts) < 2:
        return shapely.Point(pts[0])
    if not raw:
        return shapely.LineString(pts)
    pieces: list[list[tuple[float, float]]] = [[(float(pts[0, 0]), float(pts[0, 1]))]]
    for (x0, y0), (x1, y1) in zip(pts[:-1], pts[1:]):
        step = (x1 - x0 + 180.0) % 360.0 - 180.0  # the short way
        if abs(x0 + step) > 180.0:  # crosses the antimeridian: end at ±180, go on from ∓180
            edge = math.copysign(180.0, x0 + step)
            y = y0 + (y1 - y0) * (edge - x0) / step
            pieces[-1].append((edge, y))
            pieces.append([(-edge, y)])
        pieces[-1].append((float(x1), float(y1)))
    return shapely.MultiLineString([p for p in pieces if len(p) > 1])


def _planar_latlon(rings: list[Any], pts: NDArray[np.float64], origin: tuple[float, float], raw: bool = False
                   ) -> tuple[list[NDArray[np.float64]], NDArray[np.float64]]:
    """The envelope's ``[lat, lon]`` rings and the local points as ``(longitude, latitude)`` about the origin's
    longitude (unwrapped: a ring across the antimeridian, 179.99 and -179.99, is the small one, not the band round
    the Earth), where each edge is the straight line ArduPilot's fence tests (``Polygon_outside`` on latitude and
    longitude, ``AC_PolyFence_loader::breached``).  In the local frame (azimuthal) an edge is another line: a
    100 km edge at 68° N bows ~400 m from it, so a mission near a hand-drawn fence's side passed and breached.

    ``raw`` (a ``.plan``): ArduPilot tests its fence on the stored longitudes as they are (``Polygon_outside`` on
    the ``int32`` latitude and longitude, no wrap: ``AC_PolyFence_loader::breached``), so a ring with vertices at
    179.99 and -179.99 is the band round the other side of the Earth there, and is judged so; the points are
    wrapped into [-180, 180]."""
    lon0 = 0.0 if raw else float(origin[1])

    def unwrap(lon: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray((lon - lon0 + 180.0) % 360.0 - 180.0, dtype=float)

    lon, lat = LocalFrame(*origin).inverse(pts[:, 0], pts[:, 1])
    ring_lon = (lambda r: np.asarray(r, dtype=float)[:, 1]) if raw else (lambda r: unwrap(np.asarray(r)[:, 1]))
    return ([np.column_stack([ring_lon(r), np.asarray(r)[:, 0]]) for r in rings],
            np.column_stack([unwrap(np.asarray(lon)), np.asarray(lat)]))


def file_deploy_check(path: str | Path, origin: tuple[float, float] | None, points: NDArray[np.float64], fmt: str,
                      min_altitude_m: float, duration_s: float,
                      board: BoardStorage | None = None) -> tuple[dict[str, Any], str]:
    """:func:`check_deploy` of a file read by ``mission check`` and the result in one line.

    The envelope's time-out is judged against what the mission will really take: ``duration_s``, the energy
    check's duration (:func:`~auvplan.io.missions.energy.mission_file_energy`: through the current, a ``.plan``'s
    launch leg and its holds included), the same figure both lines print.

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    origin : tuple of float or None
        The scenario's ``[origin]``.
    points : numpy.ndarray
        ``(N, 3)`` the file's waypoints (a QGC plan's surface home first).
    fmt : str
        Its format (:data:`auvplan.io.missions.readback.readers.MISSION_SUFFIXES`).
    min_altitude_m : float
        Its least re-flown altitude (m).
    duration_s : float
        The mission's duration as the energy check predicts it (s).
    board : BoardStorage, optional
        The operator's board (``--board-storage``), for a ``.plan``'s ``mission_storage``.

    Returns
    -------
    record : dict
        :func:`check_deploy`'s record.
    line : str
        ``datum …; envelope OK|FAIL|none …; payload …`` (a ``.plan``'s mission storage has its own line:
        :func:`~auvplan.io.missions.readback.mission_storage.storage_line`).
    """
    rec = check_deploy(path, origin, points, min_altitude_m, duration_s, board)
    d, e = rec["datum"], rec["envelope"]
    datum = (f"datum lat {d['lat']:.6f}, lon {d['lon']:.6f} = the scenario's ({d['offset_m'] * 1000:.1f} mm)" if d
             else ("geographic coordinates" if fmt in ("qgc", "gpx", "geojson", "kml") else "no datum in the file"))
    if e is None:
        env = "envelope: none in the file (the operator must add one)"
    else:
        env = (f"envelope {'OK' if e['ok'] else 'FAIL'} — polygon of {e['vertices']} vertices"
               + (f", {e['exclusions']} exclusions" if e["exclusions"] else "")
               + "".join(f", {k} {e[k]:g}" for k in ("max_depth_m", "min_altitude_m", "max_time_s") if k in e)
               + f" (predicted {e['predicted_s']:.0f} s)" + "".join(f"; {r}" for r in e["reasons"]))
    n = len(rec["payload_events"])
    pay = f"{n} payload events" if n else "no payload events"
    alt = f"; {rec['altitude_legs']} legs at altitude" if rec["altitude_legs"] else ""
    fence = rec.get("fence_storage")
    store = f"; geofence FAIL — {fence['reason']}" if fence and not fence["ok"] else ""
    return rec, f"{datum}; {env}; {pay}{alt}{store}"
