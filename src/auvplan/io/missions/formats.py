"""Mission files vehicles and ground stations load, and reading them back.

Every format carries the same executable mission (:func:`auvplan.guidance.mission.waypoints.build_waypoints`,
the ``route`` of a :class:`~auvplan.sim.RunRecord`):

* ``mission.moos`` — MOOS-IvP behaviour file: ``initialize DEPLOY = false``; one ``BHV_Waypoint``
  (local x, y; the start is where the vehicle is deployed and is not a point) and one
  ``BHV_ConstantDepth`` per leg, active while ``DEPLOY = true`` and ``WPT_INDEX`` (posted by the
  waypoint behaviour: the index of the point it is heading to) is that leg.  Depth is **held**
  per leg (semantics ``"held"``).
* ``mission.plan`` — QGroundControl plan for ArduSub: a leading ``MAV_CMD_DO_CHANGE_SPEED`` (178) at
  the planned speed (QGroundControl never uploads ``cruiseSpeed``), then ``MAV_CMD_NAV_WAYPOINT`` (16) items in
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
:func:`check_mission_file` re-flies the file against a World (``auvplan mission check``); both live in
:mod:`auvplan.io.missions.readback.readers`, with the parsers, and are re-exported here.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from ..data.geo import LocalFrame
from . import deploy_formats as dfmt
from .deploy import DeployInfo, leg_speeds, payload_events, planned_times
from .readback.qgc_items import AP_MISSION_MAX_COMMANDS, capacity_note
from .readback.readers import (
    GPX_NS,
    MAX_MISSION_BYTES,
    MISSION_SUFFIXES,
    ZERO_ALT_M,
    ZERO_LATLON_DEG,
    check_mission_file,
    parse_gpx,
    parse_moos,
    parse_qgc_plan,
    parse_ros_path,
    read_mission,
)
from .readback.speeds import MAX_HOLD_S, along_track_factor

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
    "read_mission",
    "check_mission_file",
]


SPEED_DECIMALS = 4
"""Decimals of a ``.plan``'s speed command (0.1 mm/s)."""
SPEED_BAND = 0.0025
"""A ``.plan`` keeps its speed command while the speed it flies along each leg stays within 0.25 % of the
planned one (a new ``MAV_CMD_DO_CHANGE_SPEED`` only beyond it: AP_Mission's capacity,
:data:`auvplan.io.missions.readback.qgc_items.AP_MISSION_CAPACITY`)."""


def _varies(v: NDArray[np.float64]) -> bool:
    return bool(v.size) and bool(np.ptp(v) > 1e-9)


# ---------------------------------------------------------------------- MOOS-IvP
def _dwells(dwell: ArrayLike | None, n: int, what: str = "", limit: float = math.inf) -> NDArray[np.float64]:
    """Each waypoint's wait (s), whole seconds rounded up (the fix gets at least its ``surface_s``); the last
    waypoint's is after the mission: none."""
    d = np.zeros(n) if dwell is None else np.asarray(dwell, dtype=float).reshape(-1)
    if d.shape != (n,) or not np.all(np.isfinite(d)) or np.any(d < 0.0):
        raise ValueError(f"dwell: one finite wait ≥ 0 per waypoint ({n}), got {d.size}")
    if np.any(np.ceil(d[:-1] - 1e-9) > limit):
        k = int(np.flatnonzero(np.ceil(d[:-1] - 1e-9) > limit)[0])
        raise DataError(f"{what}: waypoint {k} waits {d[k]:g} s ([navigation] surface_s): over {limit:.0f} s, the "
                        "longest hold ArduPilot stores (16 bits); not exported")
    out: NDArray[np.float64] = np.ceil(d - 1e-9)
    if n:
        out[-1] = 0.0
    return out


def _moos_dwell(name: str, j: int, wait: float) -> list[str]:
    """The behaviour that waits at waypoint ``j`` (a surface fix): heading on from it (``WPT_INDEX = j``) the
    vehicle keeps station for ``wait`` seconds while ``DWELL`` pauses the waypoint and depth behaviours."""
    return ["", "Behavior = BHV_StationKeep", "{", f"  name                = {name}_dwell_{j}",
            "  pwt                 = 100",
            "  condition           = DEPLOY = true", f"  condition           = WPT_INDEX = {j}",
            "  runflag             = DWELL = true", "  endflag             = DWELL = false",
            f"  duration            = {wait:g}", "  duration_idle_decay = false", "  center_activate     = true",
            "  inner_radius        = 5", "  outer_radius        = 15", "}"]


def _moos_waypoints(p: NDArray[np.float64], v: NDArray[np.float64], name: str, deploy: DeployInfo | None,
                    paused: list[str]) -> list[str]:
    """The ``.bhv``'s head (comments, datum, flags, envelope) and its ``BHV_Waypoint``, up to its ``updates``."""
    x0, y0, z0 = p[0]
    pts = ":".join(f"{x:.3f},{y:.3f}" for x, y in p[1:, :2])
    dep = deploy is not None
    pay = dep and deploy.payload is not None  # type: ignore[union-attr]
    return [f"// auvplan mission {name}: {len(p)} waypoints in the local frame (x east, y north, m)",
            f"// start: {x0:.3f}, {y0:.3f}, {-z0:.3f}   (deploy point x, y, depth; not a waypoint)",
            "// depth is held per leg: leg i (WPT_INDEX = i) holds the depth of its end point", "",
            *dfmt.moos_datum(deploy.origin if deploy is not None else None),
            "initialize   DEPLOY = false", "initialize   RETURN = false",
            *(["initialize   DWELL = false"] if paused else []),
            *(["initialize   ABORT = false"] if dep else []), *(["initialize   PAYLOAD = off"] if pay else []),
            *dfmt.moos_envelope(deploy.envelope if deploy is not None else None, name), "",
            "Behavior = BHV_Waypoint", "{", f"  name           = {name}_waypoints", "  pwt            = 100",
            "  condition      = DEPLOY = true", "  condition      = RETURN = false",
            *(["  condition      = ABORT = false"] if dep else []), *paused,
            "  endflag        = RETURN = true", *(["  endflag        = MISSION_COMPLETE = true"] if dep else []),
            *(["  endflag        = PAYLOAD = off"] if pay else []), f"  speed          = {v[0] if v.size else 0.0:g}",
            "  capture_radius = 5", "  slip_radius    = 15", "  lead           = 8", f"  points         = {pts}"]


def to_moos(points: ArrayLike, speed: float | ArrayLike, name: str = "auvplan",
            deploy: DeployInfo | None = None, dwell: ArrayLike | None = None) -> str:
    """Write the MOOS-IvP behaviour file of the mission ``points (N, 3)`` (the first is the deploy point).

    ``BHV_Waypoint`` posts ``WPT_INDEX`` = index (from 0) of the point it heads to, so leg i, from
    point i to point i + 1, runs while ``WPT_INDEX = i``; its ``BHV_ConstantDepth`` holds the depth
    of point i + 1.  With a speed per leg that varies, each leg's depth behaviour also posts
    ``WPT_UPDATE = speed=v_i`` when it starts running (``runflag``), and the waypoint behaviour takes
    its parameter updates from ``WPT_UPDATE`` (``updates``): leg i is flown at v_i.
    :func:`auvplan.guidance.mission.waypoints.build_waypoints` chose the depths so that the
    vehicle stays clear of the seabed whatever depth it holds between a leg's two end depths.
    A wait at waypoint j (a surface fix's ``surface_s``) is a ``BHV_StationKeep`` conditioned on
    ``WPT_INDEX = j`` (the waypoint behaviour heading on from it) for ``duration`` seconds: its ``runflag``
    ``DWELL = true`` pauses the waypoint and depth behaviours (``condition = DWELL = false``) and a
    ``BHV_ConstantDepth`` holds the surface (depth 0) until its ``endflag`` (read back by
    :func:`auvplan.io.missions.readback.dwell.moos_dwells`).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    speed : float or array_like
        Planned speed (m/s), or one per leg ``(N - 1,)``.
    name : str, optional
        Mission name, in the file's comments.
    deploy : DeployInfo, optional
        Datum, envelope, payload and terrain-following altitudes (:mod:`auvplan.io.missions.deploy_formats`).
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s; :attr:`auvplan.nav.NavPlan.dwell_s`), rounded up to whole seconds.

    Returns
    -------
    str
        The ``.bhv`` text.
    """
    p = np.asarray(points, dtype=float)
    v = leg_speeds(speed, len(p) - 1)
    waits = _dwells(dwell, len(p))
    paused = ["  condition      = DWELL = false"] if waits.any() else []
    per_leg = _varies(v)
    lines = _moos_waypoints(p, v, name, deploy, paused)
    dep = deploy is not None
    lines += ["  updates        = WPT_UPDATE", "}"] if per_leg else ["}"]
    for i, z in enumerate(p[1:, 2]):
        inside, after = dfmt.moos_leg_extras(deploy, i)
        lines += ["", "Behavior = BHV_ConstantDepth", "{", f"  name      = {name}_depth_{i}", "  pwt       = 100",
                  "  condition = DEPLOY = true", f"  condition = WPT_INDEX = {i}",
                  *(["  condition = RETURN = false", "  condition = ABORT = false"] if dep else []),
                  *(["  condition = DWELL = false"] if paused else []),
                  f"  depth     = {-z:.3f}", "  duration  = no-time-limit", *inside]
        lines += [f"  runflag   = WPT_UPDATE = speed={v[i]:g}", "}"] if per_leg else ["}"]
        lines += after
    for j in np.flatnonzero(waits):
        lines += _moos_dwell(name, int(j), float(waits[j]))
    if paused:  # at the surface while a fix's wait runs
        lines += ["", "Behavior = BHV_ConstantDepth", "{", f"  name      = {name}_surface", "  pwt       = 100",
                  "  condition = DWELL = true", "  depth     = 0", "  duration  = no-time-limit", "}"]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- QGroundControl / ArduSub
def _global_mode(items: list[dict[str, Any]]) -> int:
    """QGroundControl's plan-wide altitude mode: 1 relative, 4 terrain frame, 0 mixed (each item its own)."""
    modes = {item["AltitudeMode"] for item in items if "AltitudeMode" in item}
    return modes.pop() if len(modes) == 1 else 0 if modes else 1


def _change_speed(speed: float, jump_id: int) -> dict[str, Any]:
    """A ``MAV_CMD_DO_CHANGE_SPEED`` item as QGroundControl writes its mission's flight speed (``SpeedSection``):
    param 1 the speed type (1: ground speed), param 2 the speed (m/s; ArduSub's ``do_change_speed`` sets WPNav's
    horizontal speed to it), param 3 the throttle (−1: unchanged), ``MAV_FRAME_MISSION`` (2)."""
    return {"type": "SimpleItem", "autoContinue": True, "command": 178, "doJumpId": jump_id, "frame": 2,
            "params": [1, round(speed, SPEED_DECIMALS), -1, 0, 0, 0, 0]}


def to_qgc_plan(points: ArrayLike, origin: tuple[float, float], speed: float | ArrayLike,
                acceptance_radius: float = 5.0, deploy: DeployInfo | None = None,
                dwell: ArrayLike | None = None) -> dict[str, Any]:
    """Make a QGroundControl ``.plan`` (JSON) for ArduSub.

    Home on the surface above the first point, one ``MAV_CMD_NAV_WAYPOINT`` per point with
    altitude = z (negative: depth) relative to home.  The plan's first item is a
    ``MAV_CMD_DO_CHANGE_SPEED`` (178; speed type 1, the speed, throttle −1: QGroundControl's own
    "Mission Start" flight speed) at the first leg's speed: ArduSub's ``do_change_speed`` sets WPNav's
    horizontal speed from it, so the launch from home and every leg after it fly the planned speed
    (``cruiseSpeed`` and ``hoverSpeed`` are QGroundControl's estimates: never uploaded, the vehicle
    would fly its ``WPNAV_SPEED`` parameter).  A 178 after waypoint i sets the speed of leg i, written only
    where the speed the command in force would fly along leg i leaves :data:`SPEED_BAND` of the planned one (a 178
    after every waypoint made 3 184 items of 1 594 waypoints; AP_Mission holds 655, 1 312 or at most 4 368).
    The speed written is horizontal: WPNav keeps a 178's speed in the horizontal and flies a leg climbing or
    diving at ``γ`` at ``1 / cos γ`` times it (ArduPilot's
    ``kinematic_limit``), so leg i's command is its planned speed times ``cos γ``
    (:func:`~auvplan.io.missions.readback.speeds.along_track_factor`): the vehicle flies the planned speed through
    the water, not up to 6 % more at a 20° pitch.  A wait at a waypoint (a surface fix's ``surface_s``) is its
    ``MAV_CMD_NAV_WAYPOINT`` param 1, the hold in whole seconds (rounded up; at most 65 535, ArduPilot's 16 bits).

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
    deploy : DeployInfo, optional
        Envelope (the geofence), payload (relay items) and terrain-following altitudes (terrain frame items;
        :mod:`auvplan.io.missions.deploy_formats`).
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s; :attr:`auvplan.nav.NavPlan.dwell_s`).

    Returns
    -------
    dict
        The plan document (write it with ``json.dump``).
    """
    p = np.asarray(points, dtype=float)
    frame = LocalFrame(*origin)
    lon, lat = frame.inverse(p[:, 0], p[:, 1])
    v = leg_speeds(speed, len(p) - 1)
    waits = _dwells(dwell, len(p), "mission.plan", MAX_HOLD_S)
    items = _qgc_items(p, lat, lon, v, speed, waits, deploy, acceptance_radius)
    return _qgc_document(items, deploy, frame, (float(lat[0]), float(lon[0])), v)


def _qgc_items(p: NDArray[np.float64], lat: NDArray[np.float64], lon: NDArray[np.float64], v: NDArray[np.float64],
               speed: float | ArrayLike, waits: NDArray[np.float64], deploy: DeployInfo | None,
               acceptance_radius: float) -> list[dict[str, Any]]:
    """The ``.plan``'s mission items: the launch's speed command, each waypoint, a speed command after it where the
    speed flown leaves :data:`SPEED_BAND`, and the payload's relay items."""
    # WPNav's speed is horizontal: a leg at pitch γ is flown at v / cos γ along it, so the command is v cos γ
    factor = along_track_factor(p)
    horizontal = v / factor if v.size else v
    first = float(horizontal[0]) if v.size else float(np.ravel(speed)[0]) if np.size(speed) else 0.0
    items: list[dict[str, Any]] = [] if not first > 0 else [_change_speed(first, 1)]  # the launch's speed
    said = round(first, SPEED_DECIMALS)  # the command in force: a 178 only where it changes (AP_Mission's capacity)
    alt = deploy.altitude if deploy is not None else None
    terrain = None if alt is None or deploy is None else deploy.terrain_items
    events = dict(payload_events(deploy.payload)) if deploy is not None and deploy.payload is not None else {}
    for i, (la, lo, z) in enumerate(zip(lat, lon, p[:, 2])):
        # terrain following (a leg too steep to follow the seabed within the pitch limit: its straight leg, at the
        # planned depth)
        above = alt[i] if alt is not None and (terrain is None or bool(terrain[i])) else None
        items.append(_qgc_waypoint(la, lo, z, above, waits[i], acceptance_radius, len(items) + 1))
        if i < v.size and abs(said * float(factor[i]) - float(v[i])) > SPEED_BAND * float(v[i]):
            said = round(float(horizontal[i]), SPEED_DECIMALS)  # the speed it flies left the band: a new command
            items.append(_change_speed(float(horizontal[i]), len(items) + 1))
        if i in events:
            items.append(dfmt.qgc_relay(events[i], len(items) + 1))
    return items

def _qgc_waypoint(la: float, lo: float, z: float, above: float | None, wait: float, acceptance_radius: float,
                  jump_id: int) -> dict[str, Any]:
    """A ``MAV_CMD_NAV_WAYPOINT`` (16) item at ``(la, lo)``: ``above`` the seabed in MAV_FRAME_GLOBAL_TERRAIN_ALT
    (10, QGC mode 4) when given, else at ``z`` relative to home (3, mode 1); ``wait`` its hold (param 1)."""
    if above is not None:
        h, frame_id, mode = round(float(above), 3), 10, 4
    else:
        # ArduSub reads an altitude under 1 cm as "keep the current altitude": the surface is 1 cm deep
        h, frame_id, mode = round(float(z), 3), 3, 1
        h = -ZERO_ALT_M if abs(h) < ZERO_ALT_M else h
    if max(abs(la), abs(lo)) < ZERO_LATLON_DEG:  # ArduSub reads (0, 0) as "stay where you are": 1.1 cm north
        la = ZERO_LATLON_DEG
    return {"type": "SimpleItem", "autoContinue": True, "command": 16, "doJumpId": jump_id,
            "frame": frame_id, "params": [int(wait), acceptance_radius, 0, None, round(float(la), 9),
                                          round(float(lo), 9), h],
            "Altitude": h, "AltitudeMode": mode, "AMSLAltAboveTerrain": None}


def _qgc_document(items: list[dict[str, Any]], deploy: DeployInfo | None, frame: LocalFrame,
                  home: tuple[float, float], v: NDArray[np.float64]) -> dict[str, Any]:
    """The ``.plan`` document of the mission's ``items`` (refused past AP_Mission's capacity), its home at ``home``
    (lat, lon) on the surface, the geofence of ``deploy``."""
    if len(items) + 1 > AP_MISSION_MAX_COMMANDS:
        raise DataError(f"QGC plan: {len(items)} items + the home = {len(items) + 1} commands > {capacity_note()}: "
                        "no ArduPilot vehicle can hold it (split the mission)")
    speed = float(v[0]) if v.size else 0.0
    return {"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
            "geoFence": dfmt.qgc_geofence(deploy, frame),
            "rallyPoints": {"points": [], "version": 2},
            "mission": {"version": 2, "firmwareType": 3, "vehicleType": 12, "cruiseSpeed": speed, "hoverSpeed": speed,
                        "globalPlanAltitudeMode": _global_mode(items),
                        "plannedHomePosition": [round(home[0], 9), round(home[1], 9), 0],
                        "items": items}}


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
    ET.register_namespace("", GPX_NS)
    root = ET.Element(f"{{{GPX_NS}}}gpx", {"version": "1.1", "creator": "auvplan"})
    meta = ET.SubElement(root, f"{{{GPX_NS}}}metadata")
    ET.SubElement(meta, f"{{{GPX_NS}}}name").text = name
    ET.SubElement(meta, f"{{{GPX_NS}}}desc").text = "ele is the elevation (m): negative below sea level (depth = -ele)"

    def put(parent: ET.Element, tag: str, p: NDArray[np.float64], label: str | None = None) -> None:
        lon, lat = frame.inverse(p[:, 0], p[:, 1])
        for k, (lo, la, z) in enumerate(zip(lon, lat, p[:, 2])):
            e = ET.SubElement(parent, f"{{{GPX_NS}}}{tag}", {"lat": f"{la:.9f}", "lon": f"{lo:.9f}"})
            ET.SubElement(e, f"{{{GPX_NS}}}ele").text = _mm(z)
            if label:
                ET.SubElement(e, f"{{{GPX_NS}}}name").text = f"{label}{k}"

    rte = ET.SubElement(root, f"{{{GPX_NS}}}rte")
    ET.SubElement(rte, f"{{{GPX_NS}}}name").text = f"{name} mission"
    put(rte, "rtept", np.asarray(points, dtype=float), "WP")
    if track is not None and np.size(track):
        trk = ET.SubElement(root, f"{{{GPX_NS}}}trk")
        ET.SubElement(trk, f"{{{GPX_NS}}}name").text = f"{name} flown track"
        put(ET.SubElement(trk, f"{{{GPX_NS}}}trkseg"), "trkpt", np.asarray(track, dtype=float))
    return ET.tostring(root, encoding="unicode", xml_declaration=True)


# ---------------------------------------------------------------------- ROS 2 nav_msgs/Path
def to_ros_path(points: ArrayLike, speed: float | ArrayLike, frame_id: str = "map",
                tail: ArrayLike | None = None, deploy: DeployInfo | None = None,
                dwell: ArrayLike | None = None, times: ArrayLike | None = None) -> str:
    """Write a ``nav_msgs/msg/Path`` as YAML (ENU local frame; stamps = planned times).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission waypoints in the local frame (m).
    speed : float or array_like
        Planned speed (m/s), or one per leg ``(N - 1,)`` (the stamps follow it).
    frame_id : str, optional
        The ROS frame of the poses (ENU, m).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first: the pose that starts one faces against it (yaw + 180°,
        :mod:`auvplan.io.missions.tail`).
    deploy : DeployInfo, optional
        Top-level ``datum: {lat, lon}``, ``envelope`` and ``payload_events``.
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s): the stamps after it are that much later (:func:`planned_times`).
    times : array_like, optional
        ``(N,)`` the planned arrival at each waypoint (s), as the mission is flown (through the current, the waits
        counted: :attr:`auvplan.nav.NavPlan.vertex_times_s`); default :func:`planned_times` (still water).

    Returns
    -------
    str
        The YAML text.
    """
    p = np.asarray(points, dtype=float)
    t = _times(p, speed, dwell, times)
    d = np.diff(p, axis=0)
    d = np.vstack([d, d[-1:]]) if len(d) else np.zeros((1, 3))
    yaw = np.arctan2(d[:, 1], d[:, 0])  # ENU yaw: counter-clockwise from east
    if tail is not None:  # a tail-first leg: the heading held against it
        yaw[:-1] = np.where(np.asarray(tail, dtype=bool), np.angle(-np.exp(1j * yaw[:-1])), yaw[:-1])
    pitch = -np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1]))  # ROS pitch about y: positive nose down
    lines = ["# nav_msgs/msg/Path written by auvplan: ENU local frame about the scenario origin (x east, y north,",
             "# z up, m); stamps are planned arrival times from the start (s)",
             *dfmt.yaml_extras(deploy), "header:", "  stamp: {sec: 0, nanosec: 0}", f"  frame_id: {frame_id}",
             "poses:"]
    for (x, y, z), tt, ya, pi in zip(p, t, yaw, pitch):
        cy, sy, cp, sp = math.cos(ya / 2), math.sin(ya / 2), math.cos(pi / 2), math.sin(pi / 2)
        qx, qy, qz, qw = -sy * sp, cy * sp, sy * cp, cy * cp
        sec = int(tt)
        lines += [f"- header: {{stamp: {{sec: {sec}, nanosec: {int(round((tt - sec) * 1e9)) % 1_000_000_000}}}, "
                  f"frame_id: {frame_id}}}",
                  f"  pose: {{position: {{x: {_mm(x)}, y: {_mm(y)}, z: {_mm(z)}}}, "
                  f"orientation: {{x: {qx:.6f}, y: {qy:.6f}, z: {qz:.6f}, w: {qw:.6f}}}}}"]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- CSV
def mission_csv(points: ArrayLike, origin: tuple[float, float] | None, speed: float | ArrayLike,
                tail: ArrayLike | None = None, deploy: DeployInfo | None = None,
                nav_error: ArrayLike | None = None, dwell: ArrayLike | None = None,
                times: ArrayLike | None = None) -> str:
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
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first: then a last column ``tail_first`` (1/0, the leg that reaches
        the waypoint; :mod:`auvplan.io.missions.tail`).
    deploy : DeployInfo, optional
        Then the last columns ``altitude`` (terrain following: planned altitude above the seabed, m) and
        ``payload`` (1: the sensor is on from this waypoint to the next), when the mission has them.
    nav_error : array_like, optional
        ``(N,)`` the predicted navigation error at each waypoint, after any fix there (confidence × σ,
        :mod:`auvplan.nav`): then a last column ``nav_error_m``.
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s): the planned times after it are that much later
        (:func:`planned_times`).
    times : array_like, optional
        ``(N,)`` the planned arrival at each waypoint (s), as the mission is flown (through the current, the waits
        counted: :attr:`auvplan.nav.NavPlan.vertex_times_s`); default :func:`planned_times` (still water).

    Returns
    -------
    str
        The CSV text (m, degrees, s, m/s); no ``-0.000`` (a waypoint at the surface is at depth ``0.000``).
    """
    p = np.asarray(points, dtype=float)
    if origin is not None:
        lon, lat = LocalFrame(*origin).inverse(p[:, 0], p[:, 1])
    else:
        lon = lat = np.full(len(p), np.nan)
    v = leg_speeds(speed, len(p) - 1)
    v = np.r_[v[:1], v] if v.size else np.asarray(speed, dtype=float).reshape(-1)[:1].repeat(len(p))
    k = None if tail is None else np.asarray(tail, dtype=bool)
    k = None if k is None or not k.any() else np.r_[k[:1], k].astype(int)
    alt = deploy.altitude if deploy is not None else None
    pay = None if deploy is None or deploy.payload is None else np.r_[deploy.payload, False].astype(int)
    ne = None if nav_error is None else np.asarray(nav_error, dtype=float).reshape(-1)
    rows = ["x,y,z,lat,lon,depth,time,speed" + ("" if k is None else ",tail_first")
            + ("" if alt is None else ",altitude") + ("" if pay is None else ",payload")
            + ("" if ne is None else ",nav_error_m")]
    for i, ((x, y, z), la, lo, tt, s) in enumerate(zip(p, lat, lon, _times(p, speed, dwell, times), v)):
        rows.append(",".join([_mm(x), _mm(y), _mm(z), "" if np.isnan(la) else f"{la:.9f}",
                              "" if np.isnan(lo) else f"{lo:.9f}", _mm(-z), f"{tt:.2f}", f"{s:.4f}"]
                             + ([] if k is None else [str(k[i])]) + ([] if alt is None else [f"{alt[i]:.3f}"])
                             + ([] if pay is None else [str(pay[i])]) + ([] if ne is None else [f"{ne[i]:.2f}"])))
    return "\n".join(rows) + "\n"


def _mm(v: float) -> str:
    """A length to the millimetre, never ``-0.000`` (a value that rounds to zero is written ``0.000``)."""
    return f"{round(float(v), 3) + 0.0:.3f}"


def _times(p: NDArray[np.float64], speed: float | ArrayLike, dwell: ArrayLike | None,
           times: ArrayLike | None) -> NDArray[np.float64]:
    """The arrival at each waypoint: ``times`` as given (one per waypoint) or :func:`planned_times`."""
    if times is None:
        return planned_times(p, speed, dwell)
    t = np.asarray(times, dtype=float).reshape(-1)
    if t.size != p.shape[0]:
        raise ValueError(f"times: one per waypoint ({p.shape[0]}), got {t.size}")
    return t
