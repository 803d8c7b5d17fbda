"""Mission files vehicles and ground stations load, and reading them back.

Every format carries the same executable mission (:func:`auvplan.guidance.mission.build_waypoints`,
the ``route`` of a :class:`~auvplan.sim.RunRecord`):

* ``mission.moos`` — MOOS-IvP behaviour file: ``initialize DEPLOY = false``; one ``BHV_Waypoint``
  (local x, y; the start is where the vehicle is deployed and is not a point) and one
  ``BHV_ConstantDepth`` per leg, active while ``DEPLOY = true`` and ``WPT_INDEX`` (posted by the
  waypoint behaviour: the index of the point it is heading to) is that leg.  Depth is **held**
  per leg (semantics ``"held"``).
* ``mission.plan`` — QGroundControl plan for ArduSub: ``MAV_CMD_NAV_WAYPOINT`` (16) items in
  ``MAV_FRAME_GLOBAL_RELATIVE_ALT`` (3), altitude = −depth relative to a home on the surface above
  the start; ArduSub's WPNav flies the 3D line (semantics ``"ramp"``), starting from home.
* ``mission.gpx`` — GPX 1.1: the mission as a route (``rte``, ``ele`` = z, negative below sea
  level) and the flown track (``trk``).
* ``mission.yaml`` — ROS 2 ``nav_msgs/Path`` as ``ros2 topic pub``/``echo`` write it: header
  ``frame_id`` ``map`` (ENU about the scenario origin: x east, y north, z up), one
  ``PoseStamped`` per waypoint, stamped with the planned arrival time, oriented along the leg.
* ``mission.geojson`` / ``mission.kml`` — the mission (feature / placemark ``mission``), the flown
  track, the plan and the key waypoints; ``mission.csv`` — the waypoints with lat/lon, depth and
  planned time.

:func:`read_mission` parses any of them back to local waypoints and their depth semantics;
:func:`check_mission_file` re-flies the file against a World (``auvplan mission check``).
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from ...guidance.mission import MissionCheck, fly_check
from ...world import World
from ..data.geo import LocalFrame

__all__ = [
    "MAX_MISSION_BYTES",
    "MISSION_SUFFIXES",
    "to_moos",
    "parse_moos",
    "to_qgc_plan",
    "parse_qgc_plan",
    "to_gpx",
    "parse_gpx",
    "to_ros_path",
    "parse_ros_path",
    "mission_csv",
    "planned_times",
    "leg_speeds",
    "read_mission",
    "check_mission_file",
]

MAX_MISSION_BYTES = 256 * 1024 * 1024
"""Largest mission file ``mission check`` reads (a 200 km mission at full resolution is a few MB)."""

MISSION_SUFFIXES = {".moos": "moos", ".bhv": "moos", ".plan": "qgc", ".gpx": "gpx", ".yaml": "ros", ".yml": "ros",
                    ".geojson": "geojson", ".json": "geojson", ".kml": "kml", ".csv": "csv"}
"""File suffix → format read by :func:`read_mission`."""

_GPX = "http://www.topografix.com/GPX/1/1"
_KML = "http://www.opengis.net/kml/2.2"


def planned_times(waypoints: ArrayLike, speed: float | ArrayLike) -> NDArray[np.float64]:
    """Compute the planned arrival time at each waypoint at ``speed`` along the 3D legs.

    Parameters
    ----------
    waypoints : array_like
        ``(N, 3)`` waypoints (m).
    speed : float or array_like
        Planned speed (m/s), one for all legs or ``(N - 1,)`` one per leg.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` times (s), 0 at the first point.
    """
    w = np.asarray(waypoints, dtype=float)
    legs = np.linalg.norm(np.diff(w, axis=0), axis=1)
    times: NDArray[np.float64] = np.r_[0.0, np.cumsum(legs / leg_speeds(speed, legs.size))]
    return times


def leg_speeds(speed: float | ArrayLike, legs: int) -> NDArray[np.float64]:
    """One planned speed per leg: ``speed`` repeated, or the ``(legs,)`` speeds given (issue 38).

    Parameters
    ----------
    speed : float or array_like
        One speed for all legs or one per leg (m/s).
    legs : int
        Number of legs.

    Returns
    -------
    numpy.ndarray
        ``(legs,)`` speeds (m/s).

    Raises
    ------
    ValueError
        When per-leg speeds do not match the legs.
    """
    v = np.asarray(speed, dtype=float)
    if v.ndim and v.size != legs:
        raise ValueError(f"{v.size} leg speeds for {legs} legs")
    return np.broadcast_to(v, (legs,)).astype(float)


def _varies(v: NDArray[np.float64]) -> bool:
    return bool(v.size) and bool(np.ptp(v) > 1e-9)


# ---------------------------------------------------------------------- MOOS-IvP
def to_moos(points: ArrayLike, speed: float | ArrayLike, name: str = "auvplan") -> str:
    """Write the MOOS-IvP behaviour file of the mission ``points (N, 3)`` (the first is the deploy point).

    ``BHV_Waypoint`` posts ``WPT_INDEX`` = index (from 0) of the point it heads to, so leg i, from
    point i to point i + 1, runs while ``WPT_INDEX = i``; its ``BHV_ConstantDepth`` holds the depth
    of point i + 1.  With a speed per leg that varies, each leg's depth behaviour also posts
    ``WPT_UPDATE = speed=v_i`` when it starts running (``runflag``), and the waypoint behaviour takes
    its parameter updates from ``WPT_UPDATE`` (``updates``): leg i is flown at v_i.
    :func:`auvplan.guidance.mission.build_waypoints` chose the depths so that the
    vehicle stays clear of the seabed whatever depth it holds between a leg's two end depths.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    speed : float or array_like
        Planned speed (m/s), or one per leg ``(N - 1,)``.
    name : str, optional
        Mission name, in the file's comments.

    Returns
    -------
    str
        The ``.bhv`` text.
    """
    p = np.asarray(points, dtype=float)
    v = leg_speeds(speed, len(p) - 1)
    per_leg = _varies(v)
    x0, y0, z0 = p[0]
    pts = ":".join(f"{x:.3f},{y:.3f}" for x, y in p[1:, :2])
    lines = [f"// auvplan mission {name}: {len(p)} waypoints in the local frame (x east, y north, m)",
             f"// start: {x0:.3f}, {y0:.3f}, {-z0:.3f}   (deploy point x, y, depth; not a waypoint)",
             "// depth is held per leg: leg i (WPT_INDEX = i) holds the depth of its end point",
             "", "initialize   DEPLOY = false", "initialize   RETURN = false", "",
             "Behavior = BHV_Waypoint", "{", f"  name           = {name}_waypoints", "  pwt            = 100",
             "  condition      = DEPLOY = true", "  condition      = RETURN = false",
             "  endflag        = RETURN = true", f"  speed          = {v[0] if v.size else 0.0:g}",
             "  capture_radius = 5", "  slip_radius    = 15", "  lead           = 8", f"  points         = {pts}"]
    lines += ["  updates        = WPT_UPDATE", "}"] if per_leg else ["}"]
    for i, z in enumerate(p[1:, 2]):
        lines += ["", "Behavior = BHV_ConstantDepth", "{", f"  name      = {name}_depth_{i}", "  pwt       = 100",
                  "  condition = DEPLOY = true", f"  condition = WPT_INDEX = {i}", f"  depth     = {-z:.3f}",
                  "  duration  = no-time-limit"]
        lines += [f"  runflag   = WPT_UPDATE = speed={v[i]:g}", "}"] if per_leg else ["}"]
    return "\n".join(lines) + "\n"


def _moos_blocks(text: str) -> list[tuple[str, list[tuple[str, str]]]]:
    """``(behaviour type, [(key, value), ...])`` of every ``Behavior = X { ... }`` block."""
    text = re.sub(r"//[^\n]*", "", text)
    out = []
    pos = 0
    # linear: each header is found once and its body ends at the next '}' (blocks do not nest); a header
    # without a closing brace ends the scan, as no later header can have one either (one regex
    # ``Behavior ... \{[^}]*\}`` rescanned to the end of the text from every unclosed header: quadratic)
    while (m := _MOOS_HEADER.search(text, pos)) is not None:
        end = text.find("}", m.end())
        if end < 0:
            break
        pairs = []
        for line in text[m.end():end].splitlines():
            if "=" in line:
                k, v = line.split("=", 1)
                pairs.append((k.strip().lower(), v.strip()))
        out.append((m.group(1), pairs))
        pos = end + 1
    return out


_MOOS_HEADER = re.compile(r"Behavior[ \t\r\n\f\v]*=[ \t\r\n\f\v]*(\w+)[ \t\r\n\f\v]*\{")
"""``Behavior = TYPE {`` of a MOOS-IvP behaviour file."""


def parse_moos(text: str) -> NDArray[np.float64]:
    """Read the waypoints of a file written by :func:`to_moos`.

    Parameters
    ----------
    text : str
        The ``.bhv`` text.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` x, y, z (m): the start (from its ``// start:`` line, when present) and every
        point with the depth its leg holds.
    """
    blocks = _moos_blocks(text)
    wpt = [dict(p) for t, p in blocks if t == "BHV_Waypoint"]
    if not wpt or "points" not in wpt[0]:
        raise DataError("no BHV_Waypoint block with 'points =' in the MOOS file")
    try:
        xy = np.array([[float(v) for v in pair.split(",")[:2]] for pair in wpt[0]["points"].split(":")])
    except ValueError as exc:
        raise DataError(f"MOOS points = {wpt[0]['points'][:60]!r}: not x,y pairs") from exc
    depth = {}
    for t, pairs in blocks:
        if t != "BHV_ConstantDepth":
            continue
        d = dict(pairs)
        found = [re.fullmatch(r"WPT_INDEX\s*==?\s*(\d+)", v) for k, v in pairs if k == "condition"]
        idx = [int(m.group(1)) for m in found if m]
        if idx and "depth" in d:
            depth[idx[0]] = float(d["depth"])
    missing = [i for i in range(len(xy)) if i not in depth]
    if missing:
        raise DataError(f"MOOS file: no BHV_ConstantDepth with condition WPT_INDEX = {missing[0]}")
    w = np.column_stack([xy, [-depth[i] for i in range(len(xy))]])
    m = re.search(r"//\s*start:\s*([-\d.eE+]+),\s*([-\d.eE+]+),\s*([-\d.eE+]+)", text)
    if m:
        w = np.vstack([[float(m.group(1)), float(m.group(2)), -float(m.group(3))], w])
    return w


# ---------------------------------------------------------------------- QGroundControl / ArduSub
def to_qgc_plan(points: ArrayLike, origin: tuple[float, float], speed: float | ArrayLike,
                acceptance_radius: float = 5.0) -> dict[str, Any]:
    """Make a QGroundControl ``.plan`` (JSON) for ArduSub.

    Home on the surface above the first point, one ``MAV_CMD_NAV_WAYPOINT`` per point with
    altitude = z (negative: depth) relative to home.  With a speed per leg that varies, a
    ``MAV_CMD_DO_CHANGE_SPEED`` (178; speed type 1, the speed, throttle −1) after waypoint i sets
    the speed of leg i (ArduSub's WPNav horizontal speed).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    origin : tuple of float
        ``(lat, lon)`` of the local frame's origin (degrees).
    speed : float or array_like
        Planned speed (m/s), or one per leg ``(N - 1,)``.
    acceptance_radius : float, optional
        Waypoint acceptance radius (m).

    Returns
    -------
    dict
        The plan document (write it with ``json.dump``).
    """
    p = np.asarray(points, dtype=float)
    frame = LocalFrame(*origin)
    lon, lat = frame.inverse(p[:, 0], p[:, 1])
    v = leg_speeds(speed, len(p) - 1)
    items: list[dict[str, Any]] = []
    for i, (la, lo, z) in enumerate(zip(lat, lon, p[:, 2])):
        items.append({"type": "SimpleItem", "autoContinue": True, "command": 16, "doJumpId": len(items) + 1,
                      "frame": 3, "params": [0, acceptance_radius, 0, None, round(float(la), 9), round(float(lo), 9),
                                             round(float(z), 3)],
                      "Altitude": round(float(z), 3), "AltitudeMode": 1, "AMSLAltAboveTerrain": None})
        if _varies(v) and i < v.size:
            items.append({"type": "SimpleItem", "autoContinue": True, "command": 178, "doJumpId": len(items) + 1,
                          "frame": 2, "params": [1, round(float(v[i]), 4), -1, 0, 0, 0, 0]})
    speed = float(v[0]) if v.size else 0.0
    return {"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
            "geoFence": {"circles": [], "polygons": [], "version": 2},
            "rallyPoints": {"points": [], "version": 2},
            "mission": {"version": 2, "firmwareType": 3, "vehicleType": 12, "cruiseSpeed": speed, "hoverSpeed": speed,
                        "globalPlanAltitudeMode": 1,
                        "plannedHomePosition": [round(float(lat[0]), 9), round(float(lon[0]), 9), 0],
                        "items": items}}


def parse_qgc_plan(doc: dict[str, Any], frame: LocalFrame) -> NDArray[np.float64]:
    """Read the local waypoints of a QGC plan.

    Parameters
    ----------
    doc : dict
        The parsed ``.plan`` JSON.
    frame : LocalFrame
        The local frame.

    Returns
    -------
    numpy.ndarray
        ``(N + 1, 3)`` (m): home (on the surface) then every ``MAV_CMD_NAV_WAYPOINT`` item
        (relative-altitude frames only).
    """
    try:
        mission = doc["mission"]
        home = mission["plannedHomePosition"]
        rows = [(float(home[0]), float(home[1]), 0.0)]
        for i, item in enumerate(mission["items"]):
            if item.get("command") != 16:
                continue
            if item.get("frame") not in (3, 6):  # GLOBAL_RELATIVE_ALT(_INT)
                raise DataError(f"QGC plan: mission.items[{i}].frame = {item.get('frame')}: expected 3 (relative alt)")
            prm = item["params"]
            rows.append((float(prm[4]), float(prm[5]), float(prm[6])))
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        raise DataError(f"QGC plan: missing or malformed key ({exc})") from exc
    a = np.array(rows)
    x, y = frame.forward(a[:, 1], a[:, 0])
    return np.column_stack([x, y, a[:, 2]])


# ---------------------------------------------------------------------- GPX 1.1
def to_gpx(points: ArrayLike, origin: tuple[float, float], track: ArrayLike | None = None,
           name: str = "auvplan") -> str:
    """Write a GPX 1.1 document: the mission as a route, the flown track as a track.

    ``ele`` is the elevation z (m, negative below sea level).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    origin : tuple of float
        ``(lat, lon)`` of the local frame's origin (degrees).
    track : array_like, optional
        ``(M, 3)`` flown track in the local frame (m).
    name : str, optional
        Mission name.

    Returns
    -------
    str
        The GPX XML text.
    """
    frame = LocalFrame(*origin)
    ET.register_namespace("", _GPX)
    root = ET.Element(f"{{{_GPX}}}gpx", {"version": "1.1", "creator": "auvplan"})
    meta = ET.SubElement(root, f"{{{_GPX}}}metadata")
    ET.SubElement(meta, f"{{{_GPX}}}name").text = name
    ET.SubElement(meta, f"{{{_GPX}}}desc").text = "ele is the elevation (m): negative below sea level (depth = -ele)"

    def put(parent: ET.Element, tag: str, p: NDArray[np.float64], label: str | None = None) -> None:
        lon, lat = frame.inverse(p[:, 0], p[:, 1])
        for k, (lo, la, z) in enumerate(zip(lon, lat, p[:, 2])):
            e = ET.SubElement(parent, f"{{{_GPX}}}{tag}", {"lat": f"{la:.9f}", "lon": f"{lo:.9f}"})
            ET.SubElement(e, f"{{{_GPX}}}ele").text = f"{z:.3f}"
            if label:
                ET.SubElement(e, f"{{{_GPX}}}name").text = f"{label}{k}"

    rte = ET.SubElement(root, f"{{{_GPX}}}rte")
    ET.SubElement(rte, f"{{{_GPX}}}name").text = f"{name} mission"
    put(rte, "rtept", np.asarray(points, dtype=float), "WP")
    if track is not None and np.size(track):
        trk = ET.SubElement(root, f"{{{_GPX}}}trk")
        ET.SubElement(trk, f"{{{_GPX}}}name").text = f"{name} flown track"
        put(ET.SubElement(trk, f"{{{_GPX}}}trkseg"), "trkpt", np.asarray(track, dtype=float))
    return ET.tostring(root, encoding="unicode", xml_declaration=True)


def parse_gpx(text: str, frame: LocalFrame) -> NDArray[np.float64]:
    """Read the local waypoints of the first route of a GPX 1.1 document.

    Parameters
    ----------
    text : str
        The GPX XML text.
    frame : LocalFrame
        The local frame.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    root = _xml(text, "GPX")
    pts = root.findall(f"{{{_GPX}}}rte/{{{_GPX}}}rtept")
    if not pts:
        raise DataError("GPX: no rte/rtept route points")
    try:
        a = np.array([(float(p.get("lon")), float(p.get("lat")),  # type: ignore[arg-type]
                       float(p.find(f"{{{_GPX}}}ele").text)) for p in pts])  # type: ignore[union-attr, arg-type]
    except (TypeError, ValueError, AttributeError) as exc:
        raise DataError(f"GPX: a route point lacks lat, lon or ele ({exc})") from exc
    x, y = frame.forward(a[:, 0], a[:, 1])
    return np.column_stack([x, y, a[:, 2]])


def _xml(text: str, what: str) -> ET.Element:
    try:
        return ET.fromstring(text)
    except ET.ParseError as exc:
        raise DataError(f"{what}: not well-formed XML ({exc})") from exc


# ---------------------------------------------------------------------- ROS 2 nav_msgs/Path
def to_ros_path(points: ArrayLike, speed: float | ArrayLike, frame_id: str = "map") -> str:
    """Write a ``nav_msgs/msg/Path`` as YAML (ENU local frame; stamps = planned times).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    speed : float or array_like
        Planned speed (m/s), or one per leg ``(N - 1,)`` (the stamps follow it).
    frame_id : str, optional
        The ROS frame of the poses (ENU, m).

    Returns
    -------
    str
        The YAML text.
    """
    p = np.asarray(points, dtype=float)
    t = planned_times(p, speed)
    d = np.diff(p, axis=0)
    d = np.vstack([d, d[-1:]]) if len(d) else np.zeros((1, 3))
    yaw = np.arctan2(d[:, 1], d[:, 0])  # ENU yaw: counter-clockwise from east
    pitch = -np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1]))  # ROS pitch about y: positive nose down
    lines = ["# nav_msgs/msg/Path written by auvplan: ENU local frame about the scenario origin (x east, y north,",
             "# z up, m); stamps are planned arrival times from the start (s)",
             "header:", "  stamp: {sec: 0, nanosec: 0}", f"  frame_id: {frame_id}", "poses:"]
    for (x, y, z), tt, ya, pi in zip(p, t, yaw, pitch):
        cy, sy, cp, sp = math.cos(ya / 2), math.sin(ya / 2), math.cos(pi / 2), math.sin(pi / 2)
        qx, qy, qz, qw = -sy * sp, cy * sp, sy * cp, cy * cp
        sec = int(tt)
        lines += [f"- header: {{stamp: {{sec: {sec}, nanosec: {int(round((tt - sec) * 1e9)) % 1_000_000_000}}}, "
                  f"frame_id: {frame_id}}}",
                  f"  pose: {{position: {{x: {x:.3f}, y: {y:.3f}, z: {z:.3f}}}, "
                  f"orientation: {{x: {qx:.6f}, y: {qy:.6f}, z: {qz:.6f}, w: {qw:.6f}}}}}"]
    return "\n".join(lines) + "\n"


def parse_ros_path(text: str) -> NDArray[np.float64]:
    """Read the waypoints of a ``nav_msgs/Path`` YAML document (PyYAML).

    Parameters
    ----------
    text : str
        The YAML text.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    import yaml

    try:
        doc = yaml.safe_load(text)
        return np.array([[float(ps["pose"]["position"][k]) for k in "xyz"] for ps in doc["poses"]])
    except (yaml.YAMLError, KeyError, TypeError, ValueError) as exc:
        raise DataError(f"nav_msgs/Path YAML: missing or malformed poses ({exc})") from exc


# ---------------------------------------------------------------------- CSV, GeoJSON, KML
def mission_csv(points: ArrayLike, origin: tuple[float, float] | None, speed: float | ArrayLike) -> str:
    """Write the mission waypoints as CSV: ``x, y, z, lat, lon, depth, time`` (planned arrival, s) and
    ``speed`` (m/s through the water on the leg that reaches the waypoint; the first leg's on the first row).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    origin : tuple of float or None
        ``(lat, lon)`` of the local frame's origin (degrees); None leaves lat/lon empty.
    speed : float or array_like
        Planned speed (m/s), or one per leg ``(N - 1,)``.

    Returns
    -------
    str
        The CSV text (m, degrees, s, m/s).
    """
    p = np.asarray(points, dtype=float)
    if origin is not None:
        lon, lat = LocalFrame(*origin).inverse(p[:, 0], p[:, 1])
    else:
        lon = lat = np.full(len(p), np.nan)
    v = leg_speeds(speed, len(p) - 1)
    v = np.r_[v[:1], v] if v.size else np.asarray(speed, dtype=float).reshape(-1)[:1].repeat(len(p))
    rows = ["x,y,z,lat,lon,depth,time,speed"]
    for (x, y, z), la, lo, tt, s in zip(p, lat, lon, planned_times(p, speed), v):
        rows.append(",".join([f"{x:.3f}", f"{y:.3f}", f"{z:.3f}", "" if np.isnan(la) else f"{la:.9f}",
                              "" if np.isnan(lo) else f"{lo:.9f}", f"{-z:.3f}", f"{tt:.2f}", f"{s:.4f}"]))
    return "\n".join(rows) + "\n"


def _geojson_mission(doc: dict[str, Any], frame: LocalFrame) -> NDArray[np.float64]:
    for f in doc.get("features", []):
        if (f.get("properties") or {}).get("name") == "mission":
            c = np.asarray(f["geometry"]["coordinates"], dtype=float)
            x, y = frame.forward(c[:, 0], c[:, 1])
            return np.column_stack([x, y, c[:, 2]])
    raise DataError("GeoJSON: no feature with properties.name = 'mission'")


def _kml_mission(text: str, frame: LocalFrame) -> np.ndarray:
    ns = {"k": _KML}
    for pm in _xml(text, "KML").iter(f"{{{_KML}}}Placemark"):
        if (pm.findtext("k:name", namespaces=ns) or "") == "mission":
            c = np.array([[float(v) for v in s.split(",")]
                          for s in pm.find("k:LineString/k:coordinates", ns).text.split()])  # type: ignore[union-attr]
            x, y = frame.forward(c[:, 0], c[:, 1])
            return np.column_stack([x, y, c[:, 2]])
    raise DataError("KML: no Placemark named 'mission'")


# ---------------------------------------------------------------------- reading and checking
def read_mission(path: str | Path, origin: tuple[float, float] | None = None) -> tuple[NDArray[np.float64], str, str]:
    """Read a mission file (format from the suffix).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    origin : tuple of float, optional
        ``(lat, lon)`` of the local frame (degrees); needed by the geographic formats.

    Returns
    -------
    waypoints : numpy.ndarray
        ``(N, 3)`` waypoints in the local frame (m).
    semantics : str
        The format's depth semantics, ``"held"`` or ``"ramp"``.
    format : str
        The format's name.

    Raises
    ------
    DataError
        Naming the file when it cannot be read.
    """
    path = Path(path)
    fmt = MISSION_SUFFIXES.get(path.suffix.lower())
    if fmt is None:
        raise DataError(f"{path}: unknown mission format {path.suffix!r}; "
                        f"expected one of {', '.join(sorted(MISSION_SUFFIXES))}")
    if fmt in ("qgc", "gpx", "geojson", "kml") and origin is None:
        raise DataError(f"{path}: a {fmt} mission is geographic: the scenario needs an [origin]")
    try:
        size = path.stat().st_size
        if size > MAX_MISSION_BYTES:
            raise DataError(f"{path}: {size:,} bytes, over the {MAX_MISSION_BYTES:,} a mission file may have")
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: cannot read ({exc})") from exc
    frame = LocalFrame(*origin) if origin is not None else None
    try:
        if fmt == "moos":
            return parse_moos(text), "held", fmt
        if fmt == "ros":
            return parse_ros_path(text), "ramp", fmt
        if fmt == "csv":
            rows = np.genfromtxt(path, delimiter=",", names=True)
            return np.column_stack([np.atleast_1d(rows[k]) for k in ("x", "y", "z")]), "ramp", fmt
        assert frame is not None  # the geographic formats need an origin (checked above)
        if fmt == "gpx":
            return parse_gpx(text, frame), "ramp", fmt
        if fmt == "kml":
            return _kml_mission(text, frame), "ramp", fmt
        doc = json.loads(text)
        return (parse_qgc_plan(doc, frame) if fmt == "qgc" else _geojson_mission(doc, frame)), "ramp", fmt
    except DataError as exc:
        raise DataError(f"{path}: {exc}") from exc
    except RecursionError:
        raise DataError(f"{path}: nested too deeply for a {fmt} mission") from None
    except (ValueError, KeyError, TypeError, AttributeError, OverflowError) as exc:
        raise DataError(f"{path}: not a readable {fmt} mission ({exc})") from exc


def check_mission_file(path: str | Path, world: World, pitch_deg: float = 15.0) -> tuple[MissionCheck, str]:
    """Re-fly a mission file under its format's depth semantics (:func:`auvplan.guidance.mission.fly_check`).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    world : World
        Seabed, static obstacles and margins (its origin for geographic formats).
    pitch_deg : float, optional
        Pitch at which held depths change (degrees).

    Returns
    -------
    check : MissionCheck
        Least altitudes, obstacle distance and hits.
    format : str
        The file's format.

    Raises
    ------
    DataError
        Naming the file when it cannot be read, has a non-finite waypoint or fewer than 2.
    """
    waypoints, semantics, fmt = read_mission(path, world.origin)
    if not np.isfinite(waypoints).all():
        raise DataError(f"{path}: the mission has a waypoint that is not finite")
    if len(waypoints) < 2:
        raise DataError(f"{path}: the mission has {len(waypoints)} waypoint{'' if len(waypoints) == 1 else 's'}; "
                        "at least 2 are needed (a start and a goal)")
    return fly_check(world, waypoints, semantics, pitch_deg, launch=fmt == "qgc"), fmt
